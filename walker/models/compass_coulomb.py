"""The compass gait with dry (Coulomb) friction at the stance ankle and the hip: stick and
slip as phases and events (:mod:`walker.friction`).

State ``x = (q_stance, q_swing, qd_stance, qd_swing)``, as in :mod:`walker.models.compass`
(absolute leg angles from the vertical, counterclockwise positive).  Parameters:
:class:`walker.params.CompassCoulombParams`, the compass parameters (viscous dampers
included) followed by ``coulomb_ankle`` and ``coulomb_hip`` [N m] (``p[10]``, ``p[11]``).

Joints and their rates ``w = S qd``:

* ``ankle`` (slope to stance leg): ``w = qd_stance``;
* ``hip``: ``w = qd_swing - qd_stance``.

Phases: the joint-mode code ``ankle + 3 hip`` (mode 0 slip+, 1 slip-, 2 stick), 9 phases
named ``"swing ankle=slip- hip=stick"`` and so on.  While a joint slips its friction torque
is ``-F_s sgn(w)``; while it sticks the joint is held by the constraint torque that the
augmented system ``[D, -S_k^T; S_k, 0] [qdd; lambda] = [f; 0]`` gives, as long as
``|lambda| < F_s``.  :func:`start_phase` gives the phase consistent with a state (a joint at
rest sticks if its friction can hold it), and :class:`walker.stride.StrideMap` and
:func:`walker.stride.simulate` start there.

Guards, in priority order: 0 ``heel_strike``, 1 ``fall_forward``, 2 ``fall_backward``, as in
the compass gait (their resets are the compass gait's; after a heel strike the modes are
chosen afresh for the post-impact state); then per joint ``<joint>_slip_stops`` (its rate
through zero toward zero) and ``<joint>_stick_breaks`` (``|lambda| - F_s`` increasing through
zero), whose resets are :func:`walker.friction.switch`: a joint that stops slipping gets its
rate made exactly zero by the plastic lock (it is rounding-small at the event, so the energy
changes by O(w^2)) and every joint's mode is chosen again; a joint whose stiction is exceeded
slips against its holding torque.

With both frictions zero the stride is the compass gait's, with the same events (a joint
without dry friction has no friction guards).  Energy: ``dE/dt = -b_hip w_hip^2 - b_ankle
w_ankle^2 - sum_slip F_j |w_j|``, so without the viscous dampers the energy lost over an
interval without events is ``sum_j F_j |delta theta_j|`` exactly, and nothing while stuck.

Jacobian ``jac``: exact in every phase (:func:`walker.friction.accelerations_jacobian` with
the generated ``dmass``, ``dbias_dq``, ``dbias_dqd`` and the linear viscous forcing).

Known limitation: repeated stick-slip switching (Zeno behaviour) is not accelerated; each
switch is one event.

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

from walker import friction as fr
from walker._generated import compass as K
from walker._linalg import solve_inplace
from walker.models import compass as _compass
from walker.models.compass import (
    LIFT_AFFINE,
    SECTION_NAMES,
    SEGMENTS,
    STATE_NAMES,
    energy,
    lift,
    lift_jacobian,
    points,
    project,
    swing_foot,
)
from walker.status import EVENT_CONTINUE, EVENT_IGNORE, EVENT_TERMINAL, Status

__all__ = [
    "N_X",
    "N_IMPULSE",
    "STATE_NAMES",
    "SECTION_NAMES",
    "SEGMENTS",
    "KERNEL_HASH",
    "JOINTS",
    "PHASE_NAMES",
    "GUARD_NAMES",
    "DIRECTIONS",
    "I_COULOMB",
    "rhs",
    "jac",
    "guards",
    "reset",
    "joint_torques",
    "phase_of",
    "modes_of",
    "start_phase",
    "energy",
    "LIFT_AFFINE",
    "lift",
    "lift_jacobian",
    "project",
    "points",
    "swing_foot",
]

N_X = 4
N_IMPULSE = 2
JOINTS = ("ankle", "hip")
N_JOINTS = 2
I_COULOMB = 10
"""Index of ``coulomb_ankle`` in the parameter vector (``coulomb_hip`` follows); a literal,
because numba freezes module globals into its disk cache, which it keys on this file alone;
a test checks it against :class:`walker.params.CompassCoulombParams`."""
N_BASE_GUARDS = 3

PHASE_NAMES = tuple(f"swing {fr.mode_names(c, JOINTS)}" for c in range(fr.N_MODES**N_JOINTS))
GUARD_NAMES = ("heel_strike", "fall_forward", "fall_backward") + tuple(
    f"{j}_{kind}" for j in JOINTS for kind in ("slip_stops", "stick_breaks")
)
DIRECTIONS = np.array(
    [list(_compass.DIRECTIONS[0]) + fr.directions(c, N_JOINTS) for c in range(len(PHASE_NAMES))],
    dtype=np.int64,
)

_S = np.array([[1.0, 0.0], [-1.0, 1.0]])
_SINGULAR = int(Status.LINEAR_SOLVE_FAILED)
KERNEL_HASH = K.KERNEL_HASH


@njit(cache=True, error_model="numpy")
def _matrices(x, p):
    """(D, f, F, qd): ``f = Q_viscous - C qd - g``, ``F`` the dry frictions."""
    q = x[0:2]
    qd = x[2:4].copy()
    D = np.empty((2, 2))
    K.mass_matrix(q, p, D)
    h = np.empty(2)
    K.bias(q, qd, p, h)
    f = np.empty(2)
    K.forcing(q, qd, p, f)
    for i in range(2):
        f[i] -= h[i]
    return D, f, p[I_COULOMB : I_COULOMB + N_JOINTS].copy(), qd


@njit(cache=True, error_model="numpy")
def _modes(phase):
    modes = np.empty(N_JOINTS, dtype=np.int64)
    fr.decode(phase, modes)
    return modes


@njit(cache=True, error_model="numpy")
def rhs(phase, t, x, p, dx):
    modes = _modes(phase)
    qdd = np.empty(2)
    Q = np.empty(2)
    kind = fr.slip_force(_S, p[I_COULOMB : I_COULOMB + N_JOINTS], modes, Q)
    if kind == 0:  # a joint sticks: the augmented system
        D, f, F, _ = _matrices(x, p)
        lam = np.empty(N_JOINTS)
        fr.accelerations(D, f, _S, F, modes, qdd, lam)
    else:  # the fused kernel (viscous dampers included) plus D^-1 of the slip torques
        K.accel(x[0:2], x[2:4], p, qdd)
        if kind > 0:
            D = np.empty((2, 2))
            K.mass_matrix(x[0:2], p, D)
            solve_inplace(D, Q)
            qdd[0] += Q[0]
            qdd[1] += Q[1]
    dx[0] = x[2]
    dx[1] = x[3]
    dx[2] = qdd[0]
    dx[3] = qdd[1]


@njit(cache=True, error_model="numpy")
def jac(phase, t, x, p, J):
    D, f, F, qd = _matrices(x, p)
    modes = _modes(phase)
    qdd = np.empty(2)
    lam = np.empty(N_JOINTS)
    fr.accelerations(D, f, _S, F, modes, qdd, lam)
    q = x[0:2]
    dD = np.empty((2, 2, 2))
    K.dmass(q, p, dD)
    df_dq = np.empty((2, 2))
    K.dbias_dq(q, qd, p, df_dq)
    dh_dqd = np.empty((2, 2))
    K.dbias_dqd(q, qd, p, dh_dqd)
    df_dqd = np.empty((2, 2))
    unit = np.zeros(2)
    col = np.empty(2)
    for k in range(2):
        # The viscous forcing is linear in qd and independent of q: probe its columns.
        unit[:] = 0.0
        unit[k] = 1.0
        K.forcing(q, unit, p, col)
        for i in range(2):
            df_dqd[i, k] = col[i] - dh_dqd[i, k]
            df_dq[i, k] = -df_dq[i, k]
    a = np.empty((2, 4))
    fr.accelerations_jacobian(D, dD, df_dq, df_dqd, _S, modes, qdd, a)
    J[:, :] = 0.0
    J[0, 2] = 1.0
    J[1, 3] = 1.0
    for i in range(2):
        for c in range(4):
            J[2 + i, c] = a[i, c]


@njit(cache=True, error_model="numpy")
def guards(phase, t, x, p, g):
    _compass.guards(0, t, x, p, g)
    modes = _modes(phase)
    lam = np.zeros(N_JOINTS)
    if fr.STICK in modes:  # the holding torques; otherwise the guards need the rates only
        D, f, F, _ = _matrices(x, p)
        qdd = np.empty(2)
        fr.accelerations(D, f, _S, F, modes, qdd, lam)
    fr.guards(_S, p[I_COULOMB : I_COULOMB + N_JOINTS], modes, x[2:4], lam, g[N_BASE_GUARDS:])


@njit(cache=True, error_model="numpy")
def _start(x, p):
    """Choose both joints' modes for state ``x`` (velocities projected in place onto the
    stuck joints) and return the phase; -1 if a solve is singular."""
    D, f, F, qd = _matrices(x, p)
    modes = np.zeros(N_JOINTS, dtype=np.int64)
    qd_new = np.empty(2)
    if not fr.settle(D, f, _S, F, qd, np.ones(N_JOINTS, dtype=np.bool_), modes, qd_new):
        return -1
    x[2] = qd_new[0]
    x[3] = qd_new[1]
    return fr.encode(modes)


@njit(cache=True, error_model="numpy")
def reset(phase, k, t, x, p, x_new, impulse):
    if k < N_BASE_GUARDS:
        action, _, status = _compass.reset(0, k, t, x, p, x_new, impulse)
        if action == EVENT_IGNORE or action == EVENT_TERMINAL:
            return action, phase, status
        new_phase = _start(x_new, p)
        if new_phase < 0:
            return EVENT_TERMINAL, phase, _SINGULAR
        return action, new_phase, status
    D, f, F, qd = _matrices(x, p)
    modes = _modes(phase)
    qd_new = np.empty(2)
    j = (k - N_BASE_GUARDS) // 2
    if not fr.switch(D, f, _S, F, qd, j, (k - N_BASE_GUARDS) % 2 == 1, modes, qd_new):
        return EVENT_TERMINAL, phase, _SINGULAR
    x_new[2] = qd_new[0]
    x_new[3] = qd_new[1]
    return EVENT_CONTINUE, fr.encode(modes), 0


@njit(cache=True, error_model="numpy")
def joint_torques(phase, x, p):
    """Friction torque at each joint (ankle, hip) [N m]: ``-+F_s`` while slipping, the
    holding torque while stuck.  The hip's acts on the swing leg (its opposite on the
    stance leg)."""
    D, f, F, _ = _matrices(x, p)
    qdd = np.empty(2)
    lam = np.empty(N_JOINTS)
    fr.accelerations(D, f, _S, F, _modes(phase), qdd, lam)
    return lam


@njit(cache=True, error_model="numpy")
def start_phase(x, p):
    """The phase consistent with state ``x`` (joint modes from the rates, and for the joints
    at rest from the friction; see :func:`walker.friction.choose_modes`)."""
    return _start(x.copy(), p)


def phase_of(**modes: str) -> int:
    """Phase index from joint modes (``"slip+"``, ``"slip-"``, ``"stick"``; default
    ``"slip+"``), e.g. ``phase_of(ankle="slip-", hip="stick")``."""
    return fr.code_of(JOINTS, modes)


def modes_of(phase: int) -> dict[str, str]:
    """{joint: mode} of a phase index: the inverse of :func:`phase_of`."""
    return fr.labels_of(phase, JOINTS)
