"""The compass gait with Coulomb friction at the hip: stick and slip as phases and events.

The hip joint carries, besides the viscous damping of :mod:`walker.models.compass`, a dry
(Coulomb) friction of magnitude ``F_s = coulomb_hip`` [N m] acting on the relative rate
``w = qd_swing - qd_stance``.  Dry friction is not smeared (no ``tanh``): while the hip slips
the torque is ``-F_s sgn(w)`` on the swing leg (and its opposite on the stance leg), with the
sign fixed by the phase; while it sticks the hip is locked and the friction torque ``lambda``
is whatever holds it, as long as ``|lambda| < F_s``.

State ``x = (q_stance, q_swing, qd_stance, qd_swing)``, as in the compass gait (absolute leg
angles from the vertical, counterclockwise positive).  Parameters: ``CompassCoulombParams``,
the compass parameters followed by ``coulomb_hip`` (``p[10]``).

Phases
------
0. ``slip_positive`` (``w > 0``): ``D qdd + h = Q_v + Q_c`` with the viscous forcing ``Q_v``
   of the generated kernels and ``Q_c = F_s [+1, -1]`` (torque ``-F_s`` on the swing leg).
1. ``slip_negative`` (``w < 0``): ``Q_c = F_s [-1, +1]``.
2. ``stick`` (``w = 0``): ``[D, -J^T; J, 0] [qdd; lambda] = [-h + Q_v; 0]``, ``J = [-1, 1]``;
   solved in closed form as the one-degree-of-freedom rigid body ``qdd = a [1, 1]``,
   ``a = -1^T h / 1^T D 1`` (``1^T Q_v = 0``), and ``lambda = (D qdd + h - Q_v)[1]``, the hip
   torque on the swing leg that keeps the joint locked.  ``qd_stance == qd_swing`` is kept
   exactly (the two accelerations are the same number).

With the relative acceleration ``a_free`` of the frictionless hip and ``c = J D^-1 J^T > 0``,
``lambda = -a_free / c`` and the slip phases have ``wdot = -c (lambda +- F_s)``: the hip
sticks at ``w = 0`` iff ``|lambda| < F_s``; ``lambda >= F_s`` slips into ``w < 0``
(``slip_negative``) and ``lambda <= -F_s`` into ``w > 0`` (``slip_positive``).  The strict
inequality makes ``F_s = 0`` never stick.

Guards, in priority order (a lower index wins at the same instant):

0. ``heel_strike``: as in the compass gait (swing-foot height decreasing through zero, accepted
   only with the foot ahead; the mid-stance scuff is ignored).  Reset: the compass impact and
   leg swap, then the phase of the post-impact state (:func:`choose_phase`).
1. ``fall_forward`` / 2. ``fall_backward``: as in the compass gait.
3. ``slip_stops`` (slip phases): ``w`` through zero toward zero (decreasing in phase 0,
   increasing in phase 1).  Reset: ``stick`` if ``|lambda| < F_s`` at the velocity-projected
   state (below), else the slip phase that ``lambda`` points to (generically the other one,
   entered with the event state unchanged).
4. ``stick_breaks`` (phase 2): ``|lambda| - F_s`` increasing through zero.  Reset: the slip
   phase opposite to ``sgn(lambda)``, state unchanged (``w = 0``).
5. ``phase_mismatch``: 1.0 while the state agrees with the phase; when it does not (``w <
   -W_TOL`` in phase 0, ``w > W_TOL`` in phase 1, ``|w| > W_TOL`` in phase 2) it is
   ``MISMATCH_DELAY - t`` (``t`` the time since the last event), which fires ``MISMATCH_DELAY``
   [s] after the start of a segment begun in the wrong phase.  In ``stick`` a hip torque
   ``|lambda| > F_s + LAMBDA_TOL`` (1e-9 N m) is a mismatch too.  This is how a run started
   in phase 0 (what :class:`walker.stride.StrideMap` always does) from a state with ``w < 0``
   reaches the right phase; the wrong friction acts for 2e-10 s only.  A run started in a
   slip phase from a state with ``w = 0`` exactly that should stick leaves ``w = 0`` on the
   wrong side, is caught once ``|w| > W_TOL`` and returns through the other slip phase (a
   detour of about 1e-9 s); start such a state in ``stick`` (``phase0=2``, or the phase
   :func:`choose_phase` returns) to avoid it.  (The guard is discontinuous, so it is kept out
   of ordinary runs: a Jacobian across it would be meaningless.)  Reset: as heel strike,
   :func:`choose_phase`.  In a run started in the right phase it never fires.

Entering ``stick`` projects the velocities onto ``w = 0`` keeping ``1^T D qd`` (the plastic
hip "impact" ``[D, -J^T; J, 0] [qd+; Lambda] = [D qd-; 0]``, here in closed form): both rates
become ``1^T D qd- / 1^T D 1``.  At a ``slip_stops`` event ``|w|`` is rounding-small, so this
changes the energy by O(w^2).

"w == 0" tolerance: after heel strike (or a phase mismatch) a post-impact rate ``|w| <= W_TOL
= 1e-12`` rad/s counts as zero: the velocities are projected as above and the phase chosen by
``lambda``; otherwise the sign of ``w`` chooses the slip phase.  No reset leaves a state on the
fired side of its new phase's guards: a slip phase starts with ``w`` on its own side or exactly
zero, and ``stick`` starts with ``w = 0`` exactly and ``|lambda| < F_s``.

Energy: ``dE/dt = qd^T (Q_v + Q_c) = -b w^2 - F_s |w|`` in slip, 0 in stick (the constraint
does no work), so with ``b = 0`` the energy lost over a slip interval is ``F_s |delta (q_swing -
q_stance)|`` exactly.

Jacobian ``jac``: analytic in every phase, from the generated kernels ``accel_jac``,
``dmass``, ``dbias_dq``, ``dbias_dqd`` (no finite differences), so ``StrideMap(...)(z,
jacobian=True)`` works.  The reset Jacobians at events are the integrator's finite
differences (:func:`walker.integrate.hybrid_solve`).

Known limitation: a tangential stick-slip transition (``|lambda|`` touching ``F_s`` exactly
at the instant ``w`` reaches zero, or ``lambda`` turning back within the ``GUARD_TOL`` band
after unsticking) is resolved by the ``phase_mismatch`` guard, i.e. to within ``W_TOL``, and
repeated stick-slip chattering (Zeno behaviour) is not accelerated; each switch is one event.

References
----------
.. [1] A. Goswami, B. Thuilot, B. Espiau, "Compass-like biped robot part I: stability and
   bifurcation of passive gaits", INRIA RR-2996, 1996.
.. [2] F. Pfeiffer, C. Glocker, "Multibody Dynamics with Unilateral Contacts", Wiley, 1996
   (stick-slip transitions of dry joint friction as switching conditions on the constraint
   force).
"""

import numpy as np
from numba import njit

from walker._generated import compass as K
from walker.models._common import FALL_ANGLE, MIN_STEP
from walker.models.compass import (
    SECTION_NAMES,
    SEGMENTS,
    STATE_NAMES,
    energy,
    heel_strike,
    lift,
    lift_jacobian,
    points,
    project,
    swing_foot,
)
from walker.params import CompassCoulombParams
from walker.status import (
    EVENT_CONTINUE,
    EVENT_IGNORE,
    EVENT_STRIDE,
    EVENT_TERMINAL,
    Status,
)

__all__ = [
    "N_X",
    "N_IMPULSE",
    "STATE_NAMES",
    "SECTION_NAMES",
    "SEGMENTS",
    "KERNEL_HASH",
    "heel_strike",
    "swing_foot",
    "PHASE_NAMES",
    "GUARD_NAMES",
    "DIRECTIONS",
    "W_TOL",
    "LAMBDA_TOL",
    "MISMATCH_DELAY",
    "rhs",
    "jac",
    "guards",
    "reset",
    "hip_torque_to_stick",
    "choose_phase",
    "energy",
    "lift",
    "lift_jacobian",
    "project",
    "points",
]

N_X = 4
N_IMPULSE = 2
PHASE_NAMES = ("slip_positive", "slip_negative", "stick")
GUARD_NAMES = (
    "heel_strike",
    "fall_forward",
    "fall_backward",
    "slip_stops",
    "stick_breaks",
    "phase_mismatch",
)
# Unused guards return 1.0 (never crossing); their direction is then immaterial.
DIRECTIONS = np.array(
    [[-1, -1, 1, -1, -1, -1], [-1, -1, 1, 1, -1, -1], [-1, -1, 1, -1, 1, -1]], dtype=np.int64
)
SLIP_POSITIVE, SLIP_NEGATIVE, STICK = 0, 1, 2

W_TOL = 1e-12
"""|w| [rad/s] at or below which a post-impact relative hip rate counts as zero."""
LAMBDA_TOL = 1e-9
"""|lambda| - F_s [N m] beyond which a state in ``stick`` is in the wrong phase."""
MISMATCH_DELAY = 2e-10
"""Time [s] after which ``phase_mismatch`` fires; > ``walker.integrate.GUARD_TOL`` (1e-10) so
that the guard starts armed."""

# Indices into ``p``, from the parameter names so that they follow the layout.
_I_SLOPE = CompassCoulombParams.names().index("slope")
_I_COULOMB = CompassCoulombParams.names().index("coulomb_hip")
_FELL_FORWARD = int(Status.FELL_FORWARD)
_FELL_BACKWARD = int(Status.FELL_BACKWARD)
KERNEL_HASH = K.KERNEL_HASH


@njit(cache=True, error_model="numpy")
def _slip_sign(phase):
    return 1.0 if phase == SLIP_POSITIVE else -1.0


@njit(cache=True, error_model="numpy")
def _stick_accel(x, p):
    """(a, lambda, 1^T D 1, 1^T h): the common acceleration of the locked hip [rad/s^2] and
    the hip torque on the swing leg that holds it [N m]."""
    q = x[:2]
    qd = x[2:]
    D = np.empty((2, 2))
    K.mass_matrix(q, p, D)
    h = np.empty(2)
    K.bias(q, qd, p, h)
    Qv = np.empty(2)
    K.forcing(q, qd, p, Qv)
    s = D[0, 0] + D[0, 1] + D[1, 0] + D[1, 1]
    n = h[0] + h[1]
    a = -n / s
    lam = (D[1, 0] + D[1, 1]) * a + h[1] - Qv[1]
    return a, lam, s, n


@njit(cache=True, error_model="numpy")
def hip_torque_to_stick(x, p):
    """Hip torque on the swing leg [N m] that would keep the hip locked at state ``x``
    (``lambda`` of the module docstring; the velocities are used as given)."""
    return _stick_accel(x, p)[1]


@njit(cache=True, error_model="numpy")
def _project_stick(x, x_new, p):
    """Velocities of ``x`` projected onto ``w = 0`` keeping ``1^T D qd``, into ``x_new``."""
    D = np.empty((2, 2))
    K.mass_matrix(x[:2], p, D)
    s = D[0, 0] + D[0, 1] + D[1, 0] + D[1, 1]
    v = ((D[0, 0] + D[1, 0]) * x[2] + (D[0, 1] + D[1, 1]) * x[3]) / s
    x_new[0] = x[0]
    x_new[1] = x[1]
    x_new[2] = v
    x_new[3] = v


@njit(cache=True, error_model="numpy")
def _phase_at_rest(x_new, p):
    """Phase for a state with ``w = 0`` exactly, from the hip torque needed to stick."""
    lam = _stick_accel(x_new, p)[1]
    F = p[_I_COULOMB]
    if lam >= F:
        return SLIP_NEGATIVE
    if lam <= -F:
        return SLIP_POSITIVE
    return STICK


@njit(cache=True, error_model="numpy")
def choose_phase(x, p, x_new):
    """Phase for a post-impact state ``x``; ``x_new`` receives the state to start it from.

    ``w > W_TOL``: slip_positive; ``w < -W_TOL``: slip_negative (state unchanged); otherwise
    the velocities are projected onto ``w = 0`` and the phase follows from ``lambda``.
    """
    for i in range(4):
        x_new[i] = x[i]
    w = x[3] - x[2]
    if w > W_TOL:
        return SLIP_POSITIVE
    if w < -W_TOL:
        return SLIP_NEGATIVE
    _project_stick(x, x_new, p)
    ph = _phase_at_rest(x_new, p)
    return ph


@njit(cache=True, error_model="numpy")
def rhs(phase, t, x, p, dx):
    dx[0] = x[2]
    dx[1] = x[3]
    if phase == STICK:
        a = _stick_accel(x, p)[0]
        dx[2] = a
        dx[3] = a
        return
    K.accel(x[:2], x[2:], p, dx[2:])
    D = np.empty((2, 2))
    K.mass_matrix(x[:2], p, D)
    Fq = _slip_sign(phase) * p[_I_COULOMB]
    det = D[0, 0] * D[1, 1] - D[0, 1] * D[1, 0]
    # D^-1 Q_c with Q_c = Fq [1, -1]
    dx[2] += Fq * (D[1, 1] + D[0, 1]) / det
    dx[3] += -Fq * (D[1, 0] + D[0, 0]) / det


@njit(cache=True, error_model="numpy")
def jac(phase, t, x, p, J):
    J[:, :] = 0.0
    J[0, 2] = 1.0
    J[1, 3] = 1.0
    q = x[:2]
    qd = x[2:]
    dD = np.empty((2, 2, 2))
    K.dmass(q, p, dD)
    D = np.empty((2, 2))
    K.mass_matrix(q, p, D)
    if phase == STICK:
        a, lam, s, n = _stick_accel(x, p)
        dh_dq = np.empty((2, 2))
        K.dbias_dq(q, qd, p, dh_dq)
        dh_dqd = np.empty((2, 2))
        K.dbias_dqd(q, qd, p, dh_dqd)
        for k in range(2):
            ds = dD[k, 0, 0] + dD[k, 0, 1] + dD[k, 1, 0] + dD[k, 1, 1]
            dn = dh_dq[0, k] + dh_dq[1, k]
            da_dq = -dn / s + n * ds / (s * s)
            da_dqd = -(dh_dqd[0, k] + dh_dqd[1, k]) / s
            J[2, k] = da_dq
            J[3, k] = da_dq
            J[2, 2 + k] = da_dqd
            J[3, 2 + k] = da_dqd
        return
    K.accel_jac(q, qd, p, J[2:, :])
    Fq = _slip_sign(phase) * p[_I_COULOMB]
    det = D[0, 0] * D[1, 1] - D[0, 1] * D[1, 0]
    u0 = Fq * (D[1, 1] + D[0, 1]) / det
    u1 = -Fq * (D[1, 0] + D[0, 0]) / det
    for k in range(2):
        # d(D^-1 Q)/dq_k = -D^-1 (dD/dq_k) u
        r0 = dD[k, 0, 0] * u0 + dD[k, 0, 1] * u1
        r1 = dD[k, 1, 0] * u0 + dD[k, 1, 1] * u1
        J[2, k] += -(D[1, 1] * r0 - D[0, 1] * r1) / det
        J[3, k] += -(-D[1, 0] * r0 + D[0, 0] * r1) / det


@njit(cache=True, error_model="numpy")
def _mismatch(phase, x, p):
    w = x[3] - x[2]
    if phase == SLIP_POSITIVE:
        return w < -W_TOL
    if phase == SLIP_NEGATIVE:
        return w > W_TOL
    if abs(w) > W_TOL:
        return True
    return abs(_stick_accel(x, p)[1]) > p[_I_COULOMB] + LAMBDA_TOL


@njit(cache=True, error_model="numpy")
def guards(phase, t, x, p, g):
    psi1 = x[0] + p[_I_SLOPE]
    g[0] = swing_foot(x, p)[0]
    g[1] = psi1 + FALL_ANGLE
    g[2] = psi1 - FALL_ANGLE
    if phase == STICK:
        g[3] = 1.0
        g[4] = abs(_stick_accel(x, p)[1]) - p[_I_COULOMB]
    else:
        g[3] = x[3] - x[2]
        g[4] = 1.0
    g[5] = MISMATCH_DELAY - t if _mismatch(phase, x, p) else 1.0


@njit(cache=True, error_model="numpy")
def reset(phase, k, t, x, p, x_new, impulse):
    for i in range(x.shape[0]):
        x_new[i] = x[i]
    if k == 0:
        if swing_foot(x, p)[1] <= MIN_STEP * (p[2] + p[3]):
            return EVENT_IGNORE, phase, 0
        x_post = np.empty(4)
        status = heel_strike(x, p, x_post, impulse)
        if status != 0:
            for i in range(4):
                x_new[i] = x_post[i]
            return EVENT_TERMINAL, phase, status
        return EVENT_STRIDE, choose_phase(x_post, p, x_new), 0
    if k == 1:
        return EVENT_TERMINAL, phase, _FELL_FORWARD
    if k == 2:
        return EVENT_TERMINAL, phase, _FELL_BACKWARD
    if k == 3:
        # w reached zero in a slip phase: stick if the friction can hold the hip.
        # The event state lies on the fired side (w rounding-small, of the other phase's
        # sign): it starts the other slip phase unchanged; stick (or, at a tangency, the
        # same slip phase) starts from the projected state with w = 0 exactly.
        _project_stick(x, x_new, p)
        nxt = _phase_at_rest(x_new, p)
        if nxt != STICK and nxt != phase:
            for i in range(4):
                x_new[i] = x[i]
        return EVENT_CONTINUE, nxt, 0
    if k == 4:
        lam = _stick_accel(x, p)[1]
        return EVENT_CONTINUE, (SLIP_NEGATIVE if lam > 0.0 else SLIP_POSITIVE), 0
    return EVENT_CONTINUE, choose_phase(x, p, x_new), 0
