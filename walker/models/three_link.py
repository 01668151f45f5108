"""Grizzle's three-link walker (two legs, torso, two hip actuators) in closed loop: compiled
phase functions for the hybrid integrator.

State ``x`` (8): ``(q_stance, q_swing, q_torso, qd_stance, qd_swing, qd_torso,
actuator_work, saturated_time)``: absolute angles from the vertical, counterclockwise positive
(:mod:`walker.symbolic.actuated`), then two accumulators that the dynamics integrate and the
impact carries over unchanged: the work done by the actuators since ``t0``,
``int tau . (B^T qd) dt`` [J], and the time during which some torque was clipped to the limit
[s] (the saturation report; 0 when the limit was never reached).  The torque is computed
inside ``rhs`` by :func:`walker.control.controller_torque` from the state and the controller
block ``p[CONTROL_OFFSET:]`` of :class:`walker.params.ThreeLinkParams`.

One phase, ``stance`` (stance foot pinned).  Guards, in priority order:

0. ``heel_strike``: height of the swing foot above the slope, firing when it decreases
   through zero; accepted only with the swing foot ahead of the stance foot (by more than
   ``MIN_STEP`` leg lengths, which ignores the mid-stance scuff).  Reset:
   floating-base impact as an augmented linear system, then the legs swap (the torso keeps
   its angle).  ``NONPHYSICAL_IMPACT`` when the normal impulse is not positive, the impulse
   leaves the friction cone ``|P_t| <= mu P_n``, or the trailing foot does not lift off.
1. ``fall_forward`` / 2. ``fall_backward``: the stance leg passes ``FALL_ANGLE`` from the
   slope normal.
3. ``slip_forward`` (``mu F_n - F_t``), 4. ``slip_backward`` (``mu F_n + F_t``),
   5. ``lift_off`` (``F_n``): the ground reaction on the stance foot (computed from the
   closed-loop accelerations) leaves the friction cone or pulls; each ends the run with
   ``NONPHYSICAL_IMPACT`` (the event log names the guard).  ``F_t`` is along the slope
   (forward), ``F_n`` along its normal.

Section (just after heel strike): ``(q_stance, q_torso, qd_stance, qd_swing, qd_torso)``;
``q_swing = -2 slope - q_stance`` there; ``lift`` sets both accumulators to zero.
"""

import math

import numpy as np
from numba import njit

from walker._generated import three_link as K
from walker._linalg import solve_inplace
from walker.control import controller_torque
from walker.models._common import FALL_ANGLE, floating_base_state, heel_strike_impact
from walker.status import EVENT_IGNORE, EVENT_STRIDE, EVENT_TERMINAL, Status

N_X = 8
N_Q = 3
N_IMPULSE = 2
PHASE_NAMES = ("stance",)
GUARD_NAMES = (
    "heel_strike",
    "fall_forward",
    "fall_backward",
    "slip_forward",
    "slip_backward",
    "lift_off",
)
DIRECTIONS = np.array([[-1, -1, 1, -1, -1, -1]], dtype=np.int64)
STATE_NAMES = (
    "q_stance",
    "q_swing",
    "q_torso",
    "qd_stance",
    "qd_swing",
    "qd_torso",
    "actuator_work",
    "saturated_time",
)
SECTION_NAMES = ("q_stance", "q_torso", "qd_stance", "qd_swing", "qd_torso")

I_LEG_A, I_LEG_B, I_SLOPE, I_FRICTION = 3, 4, 8, 10
MIN_STEP = 1e-8
"""A heel strike needs the swing foot ahead by more than ``MIN_STEP`` leg lengths.  With rigid
legs the foot height ``r (cos q_stance - cos q_swing)`` has two zeros: ``q_swing =
-q_stance`` (a step) and ``q_swing = q_stance`` (the swing foot passing through the stance
foot, step length zero up to round-off): the latter is the mid-stance scuff."""
CONTROL_OFFSET = 11
"""Index in ``p`` of the controller block (:mod:`walker.control` layout)."""

B_MATRIX = np.array([[1.0, 0.0], [0.0, 1.0], [-1.0, -1.0]])
JAC_STEP = 1e-6
"""Relative step of the central differences that give the vector field's Jacobian."""

_NONPHYSICAL = int(Status.NONPHYSICAL_IMPACT)
_FELL_FORWARD = int(Status.FELL_FORWARD)
_FELL_BACKWARD = int(Status.FELL_BACKWARD)
_SINGULAR = int(Status.LINEAR_SOLVE_FAILED)


@njit(cache=True, error_model="numpy")
def closed_loop(x, p, qdd, u):
    """Closed-loop accelerations and torques at state ``x``; returns True when saturated.

    Parameters
    ----------
    x : ndarray, shape (>= 6,)
    p : ndarray
        the ``ThreeLinkParams`` vector.
    qdd : ndarray, shape (3,)   (output) [rad/s^2]
    u : ndarray, shape (2,)   (output) hip torques on the stance and swing legs [N m]
    """
    q = x[:3]
    qd = x[3:6]
    D = np.empty((3, 3))
    h = np.empty(3)
    K.mass_matrix(q, p, D)
    K.bias(q, qd, p, h)
    sat = controller_torque(q, qd, D, h, B_MATRIX, p[CONTROL_OFFSET:], u)
    for i in range(3):
        qdd[i] = B_MATRIX[i, 0] * u[0] + B_MATRIX[i, 1] * u[1] - h[i]
    solve_inplace(D, qdd)
    return sat


@njit(cache=True, error_model="numpy")
def rhs(phase, t, x, p, dx):
    qdd = np.empty(3)
    u = np.empty(2)
    sat = closed_loop(x, p, qdd, u)
    for i in range(3):
        dx[i] = x[3 + i]
        dx[3 + i] = qdd[i]
    # actuator power: tau . (B^T qd), B^T qd = relative hip rates
    dx[6] = u[0] * (x[3] - x[5]) + u[1] * (x[4] - x[5])
    dx[7] = 1.0 if sat else 0.0


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
    qdd = np.empty(3)
    u = np.empty(2)
    closed_loop(x, p, qdd, u)
    F = np.empty(2)
    K.ground_reaction(x[:3], x[3:6], qdd, p, F)
    slope = p[I_SLOPE]
    return (
        F[0] * math.cos(slope) - F[1] * math.sin(slope),
        F[0] * math.sin(slope) + F[1] * math.cos(slope),
    )


@njit(cache=True, error_model="numpy")
def swing_foot(x, p):
    """(height above the slope, distance ahead of the stance foot along the slope) [m]."""
    r = p[I_LEG_A] + p[I_LEG_B]
    psi1 = x[0] + p[I_SLOPE]
    psi2 = x[1] + p[I_SLOPE]
    return r * (math.cos(psi1) - math.cos(psi2)), r * (math.sin(psi2) - math.sin(psi1))


@njit(cache=True, error_model="numpy")
def guards(phase, t, x, p, g):
    psi1 = x[0] + p[I_SLOPE]
    g[0] = swing_foot(x, p)[0]
    g[1] = psi1 + FALL_ANGLE
    g[2] = psi1 - FALL_ANGLE
    ft, fn = ground_reaction(x, p)
    mu = p[I_FRICTION]
    g[3] = mu * fn - ft
    g[4] = mu * fn + ft
    g[5] = fn


@njit(cache=True, error_model="numpy")
def heel_strike(x, p, x_new, impulse):
    """Floating-base heel-strike impact and leg swap.

    Returns a Status value: 0 (COMPLETED) for a physical impact.  ``impulse`` receives the
    impulse on the new stance foot, ``(along the slope, normal to it)`` [N s].
    """
    q = x[:3]
    pts = np.empty((4, 2))
    K.points(q, p, pts)
    hip_J = np.empty((2, 3))
    K.hip_jac(q, p, hip_J)
    qf = np.empty(5)
    qdf = np.empty(5)
    floating_base_state(q, x[3:6], pts[1], hip_J, qf, qdf)
    M = np.empty((5, 5))
    K.ext_mass_matrix(qf, p, M)
    Jsw = np.empty((2, 5))
    K.ext_swing_contact_jac(qf, p, Jsw)
    Jst = np.empty((2, 5))
    K.ext_stance_contact_jac(qf, p, Jst)
    qdf_plus = np.empty(5)
    ok, lift = heel_strike_impact(M, Jsw, Jst, qdf, p[I_SLOPE], qdf_plus, impulse)
    if not ok:
        return _SINGULAR
    x_new[0] = x[1]
    x_new[1] = x[0]
    x_new[2] = x[2]
    x_new[3] = qdf_plus[1]
    x_new[4] = qdf_plus[0]
    x_new[5] = qdf_plus[2]
    mu = p[I_FRICTION]
    if not (impulse[1] > 0.0) or not (abs(impulse[0]) <= mu * impulse[1]) or not (lift > 0.0):
        return _NONPHYSICAL
    return 0


@njit(cache=True, error_model="numpy")
def reset(phase, k, t, x, p, x_new, impulse):
    for i in range(x.shape[0]):
        x_new[i] = x[i]
    if k == 0:
        if swing_foot(x, p)[1] <= MIN_STEP * (p[I_LEG_A] + p[I_LEG_B]):
            return EVENT_IGNORE, phase, 0
        status = heel_strike(x, p, x_new, impulse)
        if status != 0:
            return EVENT_TERMINAL, phase, status
        return EVENT_STRIDE, 0, 0
    if k == 1:
        return EVENT_TERMINAL, phase, _FELL_FORWARD
    if k == 2:
        return EVENT_TERMINAL, phase, _FELL_BACKWARD
    return EVENT_TERMINAL, phase, _NONPHYSICAL


@njit(cache=True, error_model="numpy")
def energy(x, p):
    """(kinetic, potential) [J]; potential zero at the stance foot's height."""
    return K.kinetic(x[:3], x[3:6], p), K.potential(x[:3], p)


@njit(cache=True, error_model="numpy")
def torques(x, p):
    """Hip torques ``(tau_stance, tau_swing)`` [N m] the controller applies at ``x``."""
    qdd = np.empty(3)
    u = np.empty(2)
    closed_loop(x, p, qdd, u)
    return u


def lift(z, p):
    """Section point ``(q_stance, q_torso, qd_stance, qd_swing, qd_torso)`` -> full state."""
    slope = p[I_SLOPE]
    return np.array([z[0], -2.0 * slope - z[0], z[1], z[2], z[3], z[4], 0.0, 0.0])


def lift_jacobian(z, p):
    J = np.zeros((N_X, 5))
    J[0, 0] = 1.0
    J[1, 0] = -1.0
    J[2, 1] = 1.0
    J[3, 2] = J[4, 3] = J[5, 4] = 1.0
    return J


def project(x, p):
    return np.array([x[0], x[2], x[3], x[4], x[5]])


def points(x, p):
    """Positions for drawing: rows stance foot, hip, swing foot, torso mass [m]."""
    pts = np.empty((4, 2))
    K.points(np.ascontiguousarray(x[:3], dtype=np.float64), np.asarray(p, dtype=float), pts)
    return pts


SEGMENTS = ((0, 1), (1, 2), (1, 3))
SWING_FOOT = 2  # row of the swing foot in points()
KERNEL_HASH = K.KERNEL_HASH
