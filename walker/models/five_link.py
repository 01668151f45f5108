"""The five-link walker (torso, femurs, tibias; hip and knee actuators; point feet) in closed
loop: compiled phase functions for the hybrid integrator.

State ``x`` (12): ``(q_leg, q_knee, q_torso, q_femur_sw, q_tibia_sw, qd_leg, qd_knee,
qd_torso, qd_femur_sw, qd_tibia_sw, actuator_work, saturated_time)``: the coordinates of
:mod:`walker.symbolic.five_link` (mean stance-leg angle, stance-knee flexion, then absolute
angles from the vertical, counterclockwise positive), their rates, and two accumulators that
the dynamics integrate and the impact carries over unchanged: the actuators' work since
``t0``, ``int tau . (B^T qd) dt`` [J], and the time during which some torque was clipped to
the limit [s].  The torque is computed inside ``rhs`` by
:func:`walker.control.controller_torque` (phase variable ``q_leg``, outputs ``q[1:]``) from
the controller block ``p[CONTROL_OFFSET:]`` of :class:`walker.params.FiveLinkParams`.

One phase, ``stance`` (stance foot pinned).  Guards, in priority order:

0. ``heel_strike``: height of the swing foot above the slope, firing when it decreases
   through zero.  Accepted when the swing foot is ahead of the stance foot (by more than
   ``MIN_STEP`` leg lengths); a touchdown behind it is a trip (``TRIPPED``).  Reset:
   floating-base impact as an augmented linear system, then the legs swap (femurs and tibias
   trade places; the new stance knee is the old swing knee).  ``NONPHYSICAL_IMPACT`` when the
   normal impulse is not positive, the impulse leaves the friction cone ``|P_t| <= mu P_n``,
   or the trailing foot does not lift off.
1. ``fall_forward`` / 2. ``fall_backward``: the line from the stance foot to the hip passes
   ``FALL_ANGLE`` from the slope normal.
3. ``slip_forward`` (``mu F_n - F_t``), 4. ``slip_backward`` (``mu F_n + F_t``),
   5. ``lift_off`` (``F_n``): the ground reaction on the stance foot leaves the friction cone
   or pulls; each ends the run with ``NONPHYSICAL_IMPACT`` (the event log names the guard).
6. ``hip_down``: the hip reaches the slope (ends the run with ``FELL_BACKWARD``).

Section (just after heel strike): ``(q_leg, q_knee, q_torso, q_femur_sw, qd_leg, qd_knee,
qd_torso, qd_femur_sw, qd_tibia_sw)``; ``q_tibia_sw`` puts the swing foot on the slope, behind
its knee (``lift``); ``lift`` sets both accumulators to zero.
"""

import math

import numpy as np
from numba import njit

from walker._generated import five_link as K
from walker._linalg import solve_inplace
from walker.control import controller_torque
from walker.models._common import FALL_ANGLE, floating_base_state, heel_strike_impact
from walker.status import EVENT_STRIDE, EVENT_TERMINAL, Status

N_X = 12
N_Q = 5
N_U = 4
N_IMPULSE = 2
PHASE_NAMES = ("stance",)
GUARD_NAMES = (
    "heel_strike",
    "fall_forward",
    "fall_backward",
    "slip_forward",
    "slip_backward",
    "lift_off",
    "hip_down",
)
DIRECTIONS = np.array([[-1, -1, 1, -1, -1, -1, -1]], dtype=np.int64)
STATE_NAMES = (
    "q_leg",
    "q_knee",
    "q_torso",
    "q_femur_sw",
    "q_tibia_sw",
    "qd_leg",
    "qd_knee",
    "qd_torso",
    "qd_femur_sw",
    "qd_tibia_sw",
    "actuator_work",
    "saturated_time",
)
SECTION_NAMES = (
    "q_leg",
    "q_knee",
    "q_torso",
    "q_femur_sw",
    "qd_leg",
    "qd_knee",
    "qd_torso",
    "qd_femur_sw",
    "qd_tibia_sw",
)

I_LENGTH_FEMUR, I_LENGTH_TIBIA, I_SLOPE, I_FRICTION = 3, 4, 11, 13
CONTROL_OFFSET = 14
"""Index in ``p`` of the controller block (:mod:`walker.control` layout)."""
MIN_STEP = 1e-8
"""A heel strike needs the swing foot ahead of the stance foot by more than ``MIN_STEP`` leg
lengths; a touchdown at or behind the stance foot is a trip."""

B_MATRIX = np.array(
    [
        [1.0, 0.0, 0.0, 0.0],
        [0.5, 0.0, -1.0, 0.0],
        [-1.0, -1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, -1.0],
        [0.0, 0.0, 0.0, 1.0],
    ]
)
"""Input map ``B`` (:data:`walker.symbolic.five_link.B_MATRIX`): inputs ``(hip stance, hip
swing, knee stance, knee swing)``."""
RELABEL = np.array(
    [
        [0.0, 0.0, 0.0, 0.5, 0.5],
        [0.0, 0.0, 0.0, 1.0, -1.0],
        [0.0, 0.0, 1.0, 0.0, 0.0],
        [1.0, 0.5, 0.0, 0.0, 0.0],
        [1.0, -0.5, 0.0, 0.0, 0.0],
    ]
)
"""Leg swap on the coordinates and rates: ``q+ = RELABEL q-`` (the old swing femur and tibia
become the stance ones, and the other way round)."""
JAC_STEP = 1e-6
"""Relative step of the central differences that give the vector field's Jacobian."""

_NONPHYSICAL = int(Status.NONPHYSICAL_IMPACT)
_FELL_FORWARD = int(Status.FELL_FORWARD)
_FELL_BACKWARD = int(Status.FELL_BACKWARD)
_TRIPPED = int(Status.TRIPPED)
_SINGULAR = int(Status.LINEAR_SOLVE_FAILED)


@njit(cache=True, error_model="numpy")
def closed_loop(x, p, qdd, u):
    """Closed-loop accelerations and torques at state ``x``; returns True when saturated.

    Parameters
    ----------
    x : ndarray, shape (>= 10,)
    p : ndarray
        the ``FiveLinkParams`` vector.
    qdd : ndarray, shape (5,)   (output) [rad/s^2]
    u : ndarray, shape (4,)   (output) torques (hip stance, hip swing, knee stance, knee
        swing) [N m]
    """
    q = x[:5]
    qd = x[5:10]
    D = np.empty((5, 5))
    h = np.empty(5)
    K.mass_matrix(q, p, D)
    K.bias(q, qd, p, h)
    sat = controller_torque(q, qd, D, h, B_MATRIX, p[CONTROL_OFFSET:], u)
    for i in range(5):
        s = -h[i]
        for j in range(4):
            s += B_MATRIX[i, j] * u[j]
        qdd[i] = s
    solve_inplace(D, qdd)
    return sat


@njit(cache=True, error_model="numpy")
def rhs(phase, t, x, p, dx):
    qdd = np.empty(5)
    u = np.empty(4)
    sat = closed_loop(x, p, qdd, u)
    power = 0.0
    for i in range(5):
        dx[i] = x[5 + i]
        dx[5 + i] = qdd[i]
        for j in range(4):
            power += u[j] * B_MATRIX[i, j] * x[5 + i]
    dx[10] = power  # tau . (B^T qd)
    dx[11] = 1.0 if sat else 0.0


@njit(cache=True, error_model="numpy")
def jac(phase, t, x, p, J):
    """df/dx by central differences (step ``JAC_STEP * max(1, |x_j|)``)."""
    n = x.shape[0]
    xp = x.copy()
    fp = np.empty(n)
    fm = np.empty(n)
    for j in range(n):
        hstep = JAC_STEP * max(1.0, abs(x[j]))
        xp[j] = x[j] + hstep
        rhs(phase, t, xp, p, fp)
        xp[j] = x[j] - hstep
        rhs(phase, t, xp, p, fm)
        xp[j] = x[j]
        for i in range(n):
            J[i, j] = (fp[i] - fm[i]) / (2.0 * hstep)


@njit(cache=True, error_model="numpy")
def ground_reaction(x, p):
    """Ground force on the stance foot ``(F_t, F_n)`` along and normal to the slope [N]."""
    qdd = np.empty(5)
    u = np.empty(4)
    closed_loop(x, p, qdd, u)
    F = np.empty(2)
    K.ground_reaction(x[:5], x[5:10], qdd, p, F)
    slope = p[I_SLOPE]
    return (
        F[0] * math.cos(slope) - F[1] * math.sin(slope),
        F[0] * math.sin(slope) + F[1] * math.cos(slope),
    )


@njit(cache=True, error_model="numpy")
def _slope_frame(v, slope):
    """(along the slope, normal to it) components of a world vector."""
    return (
        v[0] * math.cos(slope) - v[1] * math.sin(slope),
        v[0] * math.sin(slope) + v[1] * math.cos(slope),
    )


@njit(cache=True, error_model="numpy")
def swing_foot(x, p):
    """(height above the slope, distance ahead of the stance foot along the slope) [m]."""
    pts = np.empty((6, 2))
    K.points(x[:5], p, pts)
    t, n = _slope_frame(pts[4], p[I_SLOPE])
    return n, t


@njit(cache=True, error_model="numpy")
def guards(phase, t, x, p, g):
    pts = np.empty((6, 2))
    K.points(x[:5], p, pts)
    slope = p[I_SLOPE]
    g[0] = _slope_frame(pts[4], slope)[1]
    ht, hn = _slope_frame(pts[2], slope)
    psi = math.atan2(-ht, hn)  # stance foot -> hip, from the slope normal
    g[1] = psi + FALL_ANGLE
    g[2] = psi - FALL_ANGLE
    ft, fn = ground_reaction(x, p)
    mu = p[I_FRICTION]
    g[3] = mu * fn - ft
    g[4] = mu * fn + ft
    g[5] = fn
    g[6] = hn


@njit(cache=True, error_model="numpy")
def heel_strike(x, p, x_new, impulse):
    """Floating-base heel-strike impact and leg swap.

    Returns a Status value: 0 (COMPLETED) for a physical impact.  ``impulse`` receives the
    impulse on the new stance foot, ``(along the slope, normal to it)`` [N s].
    """
    q = x[:5]
    pts = np.empty((6, 2))
    K.points(q, p, pts)
    hip_J = np.empty((2, 5))
    K.hip_jac(q, p, hip_J)
    qf = np.empty(7)
    qdf = np.empty(7)
    floating_base_state(q, x[5:10], pts[2], hip_J, qf, qdf)
    M = np.empty((7, 7))
    K.ext_mass_matrix(qf, p, M)
    Jsw = np.empty((2, 7))
    K.ext_swing_contact_jac(qf, p, Jsw)
    Jst = np.empty((2, 7))
    K.ext_stance_contact_jac(qf, p, Jst)
    qdf_plus = np.empty(7)
    ok, lift = heel_strike_impact(M, Jsw, Jst, qdf, p[I_SLOPE], qdf_plus, impulse)
    if not ok:
        return _SINGULAR
    for i in range(5):
        sq = 0.0
        sv = 0.0
        for j in range(5):
            sq += RELABEL[i, j] * x[j]
            sv += RELABEL[i, j] * qdf_plus[j]
        x_new[i] = sq
        x_new[5 + i] = sv
    mu = p[I_FRICTION]
    if not (impulse[1] > 0.0) or not (abs(impulse[0]) <= mu * impulse[1]) or not (lift > 0.0):
        return _NONPHYSICAL
    return 0


@njit(cache=True, error_model="numpy")
def reset(phase, k, t, x, p, x_new, impulse):
    for i in range(x.shape[0]):
        x_new[i] = x[i]
    if k == 0:
        if swing_foot(x, p)[1] <= MIN_STEP * (p[I_LENGTH_FEMUR] + p[I_LENGTH_TIBIA]):
            return EVENT_TERMINAL, phase, _TRIPPED
        status = heel_strike(x, p, x_new, impulse)
        if status != 0:
            return EVENT_TERMINAL, phase, status
        return EVENT_STRIDE, 0, 0
    if k == 1:
        return EVENT_TERMINAL, phase, _FELL_FORWARD
    if k == 2 or k == 6:
        return EVENT_TERMINAL, phase, _FELL_BACKWARD
    return EVENT_TERMINAL, phase, _NONPHYSICAL


@njit(cache=True, error_model="numpy")
def energy(x, p):
    """(kinetic, potential) [J]; potential zero at the stance foot's height."""
    return K.kinetic(x[:5], x[5:10], p), K.potential(x[:5], p)


@njit(cache=True, error_model="numpy")
def torques(x, p):
    """Torques ``(hip stance, hip swing, knee stance, knee swing)`` [N m] at ``x``."""
    qdd = np.empty(5)
    u = np.empty(4)
    closed_loop(x, p, qdd, u)
    return u


def _tibia_on_ground(z, p):
    """``q_tibia_sw`` that puts the swing foot on the slope behind its knee, and d/dz[:4]."""
    lf, lt, s = p[I_LENGTH_FEMUR], p[I_LENGTH_TIBIA], p[I_SLOPE]
    tst, fst = z[0] - 0.5 * z[1], z[0] + 0.5 * z[1]
    c = (lt * math.cos(tst + s) + lf * math.cos(fst + s) - lf * math.cos(z[3] + s)) / lt
    if not -1.0 < c < 1.0:
        raise ValueError(
            f"`z` must leave the swing foot able to reach the slope, got knee height {c * lt!r}"
        )
    psi = -math.acos(c)
    dc = np.array(
        [
            -(lt * math.sin(tst + s) + lf * math.sin(fst + s)) / lt,
            (0.5 * lt * math.sin(tst + s) - 0.5 * lf * math.sin(fst + s)) / lt,
            0.0,
            lf * math.sin(z[3] + s) / lt,
        ]
    )
    return psi - s, dc / math.sqrt(1.0 - c * c)


def lift(z, p):
    """Section point (``SECTION_NAMES``) -> full state just after heel strike."""
    z = np.asarray(z, dtype=float)
    tib, _ = _tibia_on_ground(z, p)
    return np.array([z[0], z[1], z[2], z[3], tib, *z[4:9], 0.0, 0.0])


def lift_jacobian(z, p):
    z = np.asarray(z, dtype=float)
    _, dtib = _tibia_on_ground(z, p)
    J = np.zeros((N_X, 9))
    for i in range(4):
        J[i, i] = 1.0
    J[4, :4] = dtib
    for i in range(5):
        J[5 + i, 4 + i] = 1.0
    return J


def project(x, p):
    return np.array([x[0], x[1], x[2], x[3], x[5], x[6], x[7], x[8], x[9]])


def points(x, p):
    """Positions for drawing: rows stance foot, stance knee, hip, swing knee, swing foot,
    torso centre of mass [m]."""
    pts = np.empty((6, 2))
    K.points(np.ascontiguousarray(x[:5], dtype=np.float64), np.asarray(p, dtype=float), pts)
    return pts


SEGMENTS = ((0, 1), (1, 2), (2, 3), (3, 4), (2, 5))
SWING_FOOT = 4  # row of the swing foot in points()
KERNEL_HASH = K.KERNEL_HASH
