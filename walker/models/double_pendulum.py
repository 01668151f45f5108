"""The course's double pendulum (planar elbow coordinates) with viscous and dry (Coulomb)
joint friction: stick and slip as phases and events (:mod:`walker.friction`).

State ``x = (q1, q2, qd1, qd2)``: ``q1`` of link 1 from the +x axis, ``q2`` of link 2
relative to link 1 (counterclockwise positive).  Parameters:
:class:`walker.params.DoublePendulumParams`, the course's nine physical parameters followed
by ``damping_1``, ``damping_2`` [N m s/rad] and ``coulomb_1``, ``coulomb_2`` [N m]
(``p[9]`` .. ``p[12]``).  With all four zero (the course's preset) the pendulum is
conservative and serves to check the integrator by energy conservation.

Joints and their rates ``w = S qd`` (``S`` the identity, since ``q2`` is relative):

* ``joint_1`` (the ground to link 1): ``w1 = qd1``;
* ``joint_2`` (link 1 to link 2): ``w2 = qd2``.

The course's ``D qdd + C qd + g = -F_v qd - F_s sgn(qd)`` joint by joint: the viscous part
``-b_j w_j`` is the generated forcing (:func:`walker.symbolic.models.double_pendulum`,
Rayleigh dissipation); the dry part is never smoothed.  While joint ``j`` slips its friction
torque is ``-F_j sgn(w_j)``; while it sticks the joint is held by the constraint torque that
the augmented system ``[D, -S_k^T; S_k, 0] [qdd; lambda] = [f; 0]`` gives, as long as
``|lambda| < F_j``.

Phases: the joint-mode code ``joint_1 + 3 joint_2`` (mode 0 slip+, 1 slip-, 2 stick), 9
phases named ``"free joint_1=slip- joint_2=stick"`` and so on.  :func:`start_phase` gives
the phase consistent with a state (a joint at rest sticks if its friction can hold it), and
:func:`walker.stride.simulate` starts there.

Guards: per joint ``<joint>_slip_stops`` (its rate through zero toward zero) and
``<joint>_stick_breaks`` (``|lambda| - F_j`` increasing through zero); the model has no
other events (and no strides: a run integrates to ``t_max``, ``n_strides = 0``).  Their
resets are :func:`walker.friction.switch`: a joint that stops slipping gets its rate made
exactly zero by the plastic lock (it is rounding-small at the event, so the energy changes
by O(w^2)) and every joint's mode is chosen again; a joint whose stiction is exceeded slips
against its holding torque.  A joint without dry friction has no friction guards, so with
``coulomb_1 = coulomb_2 = 0`` no event ever fires.

Energy: ``dE/dt = -sum_j b_j w_j^2 - sum_slip F_j |w_j|``; the stuck joints do no work.

Evaluation: with no joint stuck, ``rhs`` is the fused generated ``accel`` kernel (viscous
dampers included) plus ``D^-1`` of the slip torques (nothing more without dry friction, so
the frictionless pendulum runs on the generated kernel alone); with a joint stuck, the
augmented system.

Jacobian ``jac``: exact in every phase (:func:`walker.friction.accelerations_jacobian` with
the generated ``dmass``, ``dbias_dq``, ``dbias_dqd`` and the linear viscous forcing).

Known limitation: repeated stick-slip switching (Zeno behaviour) is not accelerated; each
switch is one event.

References
----------
.. [1] The course's double-pendulum exercise (the double pendulum and the
   equation ``D qdd + C qd + g = B tau - F_v qd - F_s sgn(qd) + J^T F``).
.. [2] F. Pfeiffer, C. Glocker, "Multibody Dynamics with Unilateral Contacts", Wiley, 1996
   (stick-slip transitions of dry joint friction as switching conditions on the constraint
   force).
"""

import numpy as np
from numba import njit

from walker import friction as fr
from walker._generated import double_pendulum as K
from walker._linalg import solve_inplace
from walker.status import EVENT_CONTINUE, EVENT_TERMINAL, Status

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
    "points",
]

N_X = 4
N_IMPULSE = 1
JOINTS = ("joint_1", "joint_2")
N_JOINTS = 2
I_COULOMB = 11
"""Index of ``coulomb_1`` in the parameter vector (``coulomb_2`` follows); a literal,
because numba freezes module globals into its disk cache, which it keys on this file alone;
a test checks it against :class:`walker.params.DoublePendulumParams`."""

PHASE_NAMES = tuple(f"free {fr.mode_names(c, JOINTS)}" for c in range(fr.N_MODES**N_JOINTS))
GUARD_NAMES = tuple(f"{j}_{kind}" for j in JOINTS for kind in ("slip_stops", "stick_breaks"))
DIRECTIONS = np.array([fr.directions(c, N_JOINTS) for c in range(len(PHASE_NAMES))], dtype=np.int64)
STATE_NAMES = ("q1", "q2", "qd1", "qd2")
SECTION_NAMES = ()

_S = np.array([[1.0, 0.0], [0.0, 1.0]])
_SINGULAR = int(Status.LINEAR_SOLVE_FAILED)


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
    modes = _modes(phase)
    lam = np.zeros(N_JOINTS)
    if fr.STICK in modes:  # the holding torques; otherwise the guards need the rates only
        D, f, F, _ = _matrices(x, p)
        qdd = np.empty(2)
        fr.accelerations(D, f, _S, F, modes, qdd, lam)
    fr.guards(_S, p[I_COULOMB : I_COULOMB + N_JOINTS], modes, x[2:4], lam, g)


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
    for i in range(x.shape[0]):
        x_new[i] = x[i]
    impulse[0] = 0.0
    D, f, F, qd = _matrices(x, p)
    modes = _modes(phase)
    qd_new = np.empty(2)
    if not fr.switch(D, f, _S, F, qd, k // 2, k % 2 == 1, modes, qd_new):
        return EVENT_TERMINAL, phase, _SINGULAR
    x_new[2] = qd_new[0]
    x_new[3] = qd_new[1]
    return EVENT_CONTINUE, fr.encode(modes), 0


@njit(cache=True, error_model="numpy")
def joint_torques(phase, x, p):
    """Dry-friction torque at each joint (joint_1, joint_2) [N m]: ``-+F_s`` while slipping,
    the holding torque while stuck.  Each acts on the distal link (its opposite on the
    proximal one)."""
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
    ``"slip+"``), e.g. ``phase_of(joint_1="slip-", joint_2="stick")``."""
    return fr.code_of(JOINTS, modes)


def modes_of(phase: int) -> dict[str, str]:
    """{joint: mode} of a phase index: the inverse of :func:`phase_of`."""
    return fr.labels_of(phase, JOINTS)


@njit(cache=True, error_model="numpy")
def energy(x, p):
    """(kinetic, potential) [J]."""
    return K.kinetic(x[:2], x[2:], p), K.potential(x[:2], p)


def points(x, p):
    """Base, elbow, tip [m]."""
    pts = np.empty((2, 2))
    K.points(np.ascontiguousarray(x[:2], dtype=np.float64), p, pts)
    return np.vstack([np.zeros((1, 2)), pts])


SEGMENTS = ((0, 1), (1, 2))
KERNEL_HASH = K.KERNEL_HASH
