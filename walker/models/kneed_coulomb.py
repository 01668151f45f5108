"""The kneed walker with dry (Coulomb) friction at the stance ankle, the hip and the swing
knee: stick and slip as phases and events (:mod:`walker.friction`).

State ``x = (q1, q2, q3, qd1, qd2, qd3)`` as in :mod:`walker.models.kneed` (stance leg, swing
thigh, swing shank; absolute angles from the vertical, counterclockwise positive).
Parameters: :class:`walker.params.KneedCoulombParams`, the kneed walker's (its viscous
dampers included) followed by ``coulomb_ankle``, ``coulomb_hip``, ``coulomb_knee`` [N m].

Joints and their rates ``w = S qd``:

* ``ankle`` (slope to stance leg): ``w = qd1``;
* ``hip`` (stance leg to swing thigh): ``w = qd2 - qd1``;
* ``knee`` (swing thigh to shank): ``w = qd3 - qd2``; only while the knee is unlocked (the
  locked knee is held by the knee cap).

Phases: ``base`` x joint modes.  Phases 0..26 are ``unlocked`` (3-DOF) with the mode code
``ankle + 3 hip + 9 knee`` (mode 0 slip+, 1 slip-, 2 stick); phases 27..35 are ``locked``
(2-DOF, ``q3 = q2``, ``qd3 = qd2`` kept exactly) with the code ``ankle + 3 hip``.  Phase 0 is
"unlocked, every joint slipping forward"; :func:`start_phase` gives the phase consistent
with a state, and :class:`walker.stride.StrideMap` and :func:`walker.stride.simulate` start
there (the new swing knee is straight and at rest just after heel strike, so whether it
sticks depends on the friction).

Guards, in priority order: 0 ``knee_lock``, 1 ``swing_foot_contact``, 2 ``fall_forward``,
3 ``fall_backward``, exactly as in the kneed walker (their resets are the kneed walker's:
knee lock, heel strike with leg swap, trip, falls); then per joint ``<joint>_slip_stops``
and ``<joint>_stick_breaks`` (4..9), whose resets choose the modes again
(:func:`walker.friction.choose_modes`) and project the velocities of joints that start to
stick.  After every impact the modes are chosen afresh for the post-impact state.  A knee
stuck bent cannot lock, and its foot striking the ground is a trip; a knee stuck straight
strikes as a locked leg (the kneed walker's simultaneous knee-lock and heel-strike rule).

With all three frictions zero the stride is the kneed walker's, with the same events (a
joint without dry friction has no friction guards; the accelerations come from the same
matrices by another elimination, so they agree to round-off).  Energy: between events ``E``
decreases by ``sum_j F_j |delta theta_j|`` plus the viscous dampers' work.

Jacobian ``jac``: exact in every phase (:func:`walker.friction.accelerations_jacobian` with
the generated ``dmass``, ``dbias_dq``, ``dbias_dqd`` and the linear viscous forcing).
"""

import numpy as np
from numba import njit

from walker import friction as fr
from walker._generated import kneed as K
from walker._linalg import solve_inplace
from walker.models import kneed as _kneed
from walker.models.kneed import (
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

N_X = 6
N_IMPULSE = 2
JOINTS = ("ankle", "hip", "knee")
N_UNLOCKED = fr.N_MODES**3
N_LOCKED = fr.N_MODES**2
UNLOCKED, LOCKED = 0, 1
I_COULOMB = 17
"""Index of ``coulomb_ankle`` in the parameter vector (``coulomb_hip``, ``coulomb_knee``
follow); a test checks it against :class:`walker.params.KneedCoulombParams`."""

PHASE_NAMES = tuple(f"unlocked {fr.mode_names(c, JOINTS)}" for c in range(N_UNLOCKED)) + tuple(
    f"locked {fr.mode_names(c, JOINTS[:2])}" for c in range(N_LOCKED)
)
GUARD_NAMES = ("knee_lock", "swing_foot_contact", "fall_forward", "fall_backward") + tuple(
    f"{j}_{kind}" for j in JOINTS for kind in ("slip_stops", "stick_breaks")
)
DIRECTIONS = np.array(
    [list(_kneed.DIRECTIONS[UNLOCKED]) + fr.directions(c, 3) for c in range(N_UNLOCKED)]
    + [list(_kneed.DIRECTIONS[LOCKED]) + fr.directions(c, 2) + [-1, 1] for c in range(N_LOCKED)],
    dtype=np.int64,
)

_S_UNLOCKED = np.array([[1.0, 0.0, 0.0], [-1.0, 1.0, 0.0], [0.0, -1.0, 1.0]])
_S_LOCKED = np.array([[1.0, 0.0], [-1.0, 1.0]])
_SINGULAR = int(Status.LINEAR_SOLVE_FAILED)
KERNEL_HASH = K.KERNEL_HASH


@njit(cache=True, error_model="numpy")
def _split(phase, modes):
    """Base phase of ``phase``; ``modes`` (3,) receives the joint modes (the locked knee
    reads as ``STICK``)."""
    if phase < N_UNLOCKED:
        fr.decode(phase, modes)
        return UNLOCKED
    fr.decode(phase - N_UNLOCKED, modes[:2])
    modes[2] = fr.STICK
    return LOCKED


@njit(cache=True, error_model="numpy")
def _join(base, modes):
    if base == UNLOCKED:
        return fr.encode(modes)
    return N_UNLOCKED + fr.encode(modes[:2])


@njit(cache=True, error_model="numpy")
def _matrices(base, x, p):
    """(D, f, S, F, qd) of the base phase: ``f = Q_viscous - C qd - g``."""
    if base == UNLOCKED:
        q = x[0:3]
        qd = x[3:6].copy()
        D = np.empty((3, 3))
        K.unlocked_mass_matrix(q, p, D)
        h = np.empty(3)
        K.unlocked_bias(q, qd, p, h)
        f = np.empty(3)
        K.unlocked_forcing(q, qd, p, f)
        for i in range(3):
            f[i] -= h[i]
        return D, f, _S_UNLOCKED, p[I_COULOMB : I_COULOMB + 3].copy(), qd
    q = x[0:2]
    qd = x[3:5].copy()
    D = np.empty((2, 2))
    K.locked_mass_matrix(q, p, D)
    h = np.empty(2)
    K.locked_bias(q, qd, p, h)
    f = np.empty(2)
    K.locked_forcing(q, qd, p, f)
    for i in range(2):
        f[i] -= h[i]
    return D, f, _S_LOCKED, p[I_COULOMB : I_COULOMB + 2].copy(), qd


@njit(cache=True, error_model="numpy")
def _solve(base, modes, x, p, qdd, lam):
    D, f, S, F, _ = _matrices(base, x, p)
    n = D.shape[0]
    return fr.accelerations(D, f, S, F, modes[: S.shape[0]], qdd[:n], lam[: S.shape[0]])


@njit(cache=True, error_model="numpy")
def _fast_accel(base, modes, x, p, qdd):
    """Accelerations when no joint sticks: the fused generated kernel (viscous dampers
    included) plus ``D^-1`` of the slip torques; False when some joint sticks."""
    n = 3 if base == UNLOCKED else 2
    m = 3 if base == UNLOCKED else 2
    Q = np.empty(n)
    S = _S_UNLOCKED if base == UNLOCKED else _S_LOCKED
    kind = fr.slip_force(S, p[I_COULOMB : I_COULOMB + m], modes[:m], Q)
    if kind == 0:
        return False
    if base == UNLOCKED:
        K.unlocked_accel(x[0:3], x[3:6], p, qdd[:3])
        if kind > 0:
            D = np.empty((3, 3))
            K.unlocked_mass_matrix(x[0:3], p, D)
            solve_inplace(D, Q)
    else:
        K.locked_accel(x[0:2], x[3:5], p, qdd[:2])
        if kind > 0:
            D = np.empty((2, 2))
            K.locked_mass_matrix(x[0:2], p, D)
            solve_inplace(D, Q)
    if kind > 0:
        for i in range(n):
            qdd[i] += Q[i]
    return True


@njit(cache=True, error_model="numpy")
def rhs(phase, t, x, p, dx):
    modes = np.empty(3, dtype=np.int64)
    base = _split(phase, modes)
    qdd = np.empty(3)
    if not _fast_accel(base, modes, x, p, qdd):
        lam = np.empty(3)
        _solve(base, modes, x, p, qdd, lam)
    dx[0] = x[3]
    dx[1] = x[4]
    if base == UNLOCKED:
        dx[2] = x[5]
        dx[3] = qdd[0]
        dx[4] = qdd[1]
        dx[5] = qdd[2]
    else:
        dx[2] = x[4]
        dx[3] = qdd[0]
        dx[4] = qdd[1]
        dx[5] = qdd[1]


@njit(cache=True, error_model="numpy")
def jac(phase, t, x, p, J):
    modes = np.empty(3, dtype=np.int64)
    base = _split(phase, modes)
    D, f, S, F, qd = _matrices(base, x, p)
    n = D.shape[0]
    m = S.shape[0]
    qdd = np.empty(n)
    lam = np.empty(m)
    fr.accelerations(D, f, S, F, modes[:m], qdd, lam)
    q = x[0:n]
    dD = np.empty((n, n, n))
    dh_dq = np.empty((n, n))
    dh_dqd = np.empty((n, n))
    df_dqd = np.empty((n, n))
    unit = np.zeros(n)
    col = np.empty(n)
    for k in range(n):
        # The viscous forcing is linear in qd and independent of q: probe its columns.
        unit[:] = 0.0
        unit[k] = 1.0
        if base == UNLOCKED:
            K.unlocked_forcing(q, unit, p, col)
        else:
            K.locked_forcing(q, unit, p, col)
        for i in range(n):
            df_dqd[i, k] = col[i]
    if base == UNLOCKED:
        K.unlocked_dmass(q, p, dD)
        K.unlocked_dbias_dq(q, qd, p, dh_dq)
        K.unlocked_dbias_dqd(q, qd, p, dh_dqd)
    else:
        K.locked_dmass(q, p, dD)
        K.locked_dbias_dq(q, qd, p, dh_dq)
        K.locked_dbias_dqd(q, qd, p, dh_dqd)
    for i in range(n):
        for k in range(n):
            dh_dq[i, k] = -dh_dq[i, k]
            df_dqd[i, k] -= dh_dqd[i, k]
    a = np.empty((n, 2 * n))
    fr.accelerations_jacobian(D, dD, dh_dq, df_dqd, S, modes[:m], qdd, a)
    J[:, :] = 0.0
    J[0, 3] = 1.0
    J[1, 4] = 1.0
    if base == UNLOCKED:
        J[2, 5] = 1.0
        for i in range(3):
            for c in range(6):
                J[3 + i, c] = a[i, c]
        return
    # Locked: (q1, q2, qd1, qd2) map to state columns 0, 1, 3, 4; q3, qd3 copy q2, qd2.
    J[2, 4] = 1.0
    cols = (0, 1, 3, 4)
    for i in range(2):
        for c in range(4):
            J[3 + i, cols[c]] = a[i, c]
    for c in range(6):
        J[5, c] = J[4, c]


@njit(cache=True, error_model="numpy")
def guards(phase, t, x, p, g):
    modes = np.empty(3, dtype=np.int64)
    base = _split(phase, modes)
    _kneed.guards(base, t, x, p, g)
    m = 3 if base == UNLOCKED else 2
    lam = np.zeros(3)
    stuck = False
    for j in range(m):
        stuck |= modes[j] == fr.STICK
    if stuck:  # the holding torques; otherwise the guards need the rates only
        qdd = np.empty(3)
        _solve(base, modes, x, p, qdd, lam)
    S = _S_UNLOCKED if base == UNLOCKED else _S_LOCKED
    fr.guards(S, p[I_COULOMB : I_COULOMB + m], modes[:m], x[3 : 3 + m], lam[:m], g[4 : 4 + 2 * m])
    if base == LOCKED:
        g[8] = 1.0
        g[9] = 1.0


@njit(cache=True, error_model="numpy")
def _write_rates(base, qd, x):
    for i in range(qd.shape[0]):
        x[3 + i] = qd[i]
    if base == LOCKED:
        x[5] = x[4]


@njit(cache=True, error_model="numpy")
def _start(base, x, p):
    """Choose every joint's mode for state ``x`` (velocities projected in place onto the
    stuck joints) and return the phase; -1 if a solve is singular."""
    D, f, S, F, qd = _matrices(base, x, p)
    modes = np.zeros(3, dtype=np.int64)
    modes[2] = fr.STICK  # the locked knee (unused while unlocked: chosen below)
    qd_new = np.empty(qd.shape[0])
    free = np.ones(S.shape[0], dtype=np.bool_)
    if not fr.settle(D, f, S, F, qd, free, modes[: S.shape[0]], qd_new):
        return -1
    _write_rates(base, qd_new, x)
    return _join(base, modes)


@njit(cache=True, error_model="numpy")
def reset(phase, k, t, x, p, x_new, impulse):
    modes = np.empty(3, dtype=np.int64)
    base = _split(phase, modes)
    if k < 4:
        action, new_base, status = _kneed.reset(base, k, t, x, p, x_new, impulse)
        if action == EVENT_IGNORE or action == EVENT_TERMINAL:
            return action, phase, status
        new_phase = _start(new_base, x_new, p)
        if new_phase < 0:
            return EVENT_TERMINAL, phase, _SINGULAR
        return action, new_phase, status
    D, f, S, F, qd = _matrices(base, x, p)
    qd_new = np.empty(qd.shape[0])
    j = (k - 4) // 2
    if not fr.switch(D, f, S, F, qd, j, (k - 4) % 2 == 1, modes[: S.shape[0]], qd_new):
        return EVENT_TERMINAL, phase, _SINGULAR
    _write_rates(base, qd_new, x_new)
    return EVENT_CONTINUE, _join(base, modes), 0


@njit(cache=True, error_model="numpy")
def joint_torques(phase, x, p):
    """Friction torque at each joint (ankle, hip, knee) [N m]: ``-+F`` while slipping, the
    holding torque while stuck (0 for the locked knee)."""
    modes = np.empty(3, dtype=np.int64)
    base = _split(phase, modes)
    qdd = np.empty(3)
    lam = np.zeros(3)
    _solve(base, modes, x, p, qdd, lam)
    if base == LOCKED:
        lam[2] = 0.0
    return lam


@njit(cache=True, error_model="numpy")
def start_phase(x, p):
    """The unlocked phase consistent with state ``x`` (joint modes from the rates, and for
    the joints at rest from the friction; see :func:`walker.friction.choose_modes`)."""
    y = x.copy()
    return _start(UNLOCKED, y, p)


def phase_of(base: str, **modes: str) -> int:
    """Phase index from a base (``"unlocked"``/``"locked"``) and joint modes
    (``"slip+"``, ``"slip-"``, ``"stick"``; default ``"slip+"``), e.g.
    ``phase_of("unlocked", knee="stick")``."""
    if base not in ("unlocked", "locked"):
        raise ValueError(f"`base` must be 'unlocked' or 'locked', got {base!r}")
    if base == "unlocked":
        return fr.code_of(JOINTS, modes)
    return N_UNLOCKED + fr.code_of(JOINTS[:2], modes)


def modes_of(phase: int) -> tuple[str, dict[str, str]]:
    """(base, {joint: mode}) of a phase index: the inverse of :func:`phase_of`."""
    if not 0 <= phase < len(PHASE_NAMES):
        raise ValueError(f"`phase` must be in [0, {len(PHASE_NAMES)}), got {phase}")
    if phase < N_UNLOCKED:
        return "unlocked", fr.labels_of(phase, JOINTS)
    return "locked", fr.labels_of(phase - N_UNLOCKED, JOINTS[:2])
