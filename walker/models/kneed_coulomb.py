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

from walker import friction as fr
from walker import friction_phases as frp
from walker._generated import indices as ix
from walker._generated import kneed as K
from walker._jit import njit
from walker.models import kneed as _kneed
from walker.models._common import after_base_reset, joint_friction_walker, relabel
from walker.params import MODELS
from walker.status import EVENT_CONTINUE

__all__, __getattr__, __dir__ = joint_friction_walker(__name__, _kneed)

N_X = 6
N_IMPULSE = 2
STATE_NAMES = MODELS["kneed_coulomb"].state_names  # the model registry (walker.params)
JOINTS = ("ankle", "hip", "knee")
N_UNLOCKED = fr.N_MODES**3
N_LOCKED = fr.N_MODES**2
UNLOCKED, LOCKED = ix.KNEED_PHASE_UNLOCKED, ix.KNEED_PHASE_LOCKED
I_COULOMB = ix.KNEED_COULOMB_P_COULOMB_ANKLE
"""Index of ``coulomb_ankle`` in the parameter vector (``coulomb_hip``, ``coulomb_knee``
follow), from the generated :mod:`walker._generated.indices`."""

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
KERNEL_HASH = K.KERNEL_HASH

# The phase functions are walker.friction's, over the kneed walker's kernels of each base
# phase: unlocked (3 coordinates and joints, rows _S_UNLOCKED) and locked (2, _S_LOCKED); the
# dry frictions p[I_COULOMB:], the rates x[3:6] (locked: x[3:5], with qd3 = qd2).


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
def _dry(base, p):
    """Dry frictions of the base phase's joints [N m]."""
    return p[I_COULOMB : I_COULOMB + (3 if base == UNLOCKED else 2)]


@njit(cache=True, error_model="numpy")
def _joints(phase, p):
    """``(base, modes, F)`` of ``phase``: its base phase, the joint modes (3,) (:func:`_split`)
    and the dry frictions of the base phase's joints."""
    modes = np.empty(3, dtype=np.int64)
    base = _split(phase, modes)
    return base, modes, _dry(base, p)


@njit(cache=True, error_model="numpy")
def _unlocked(x, p):
    """(D, f, qd) of the unlocked walker (:func:`walker.friction_phases.dynamics`)."""
    return frp.dynamics(K.unlocked_mass_matrix, K.unlocked_bias, K.unlocked_forcing, x, 3, p, 3)


@njit(cache=True, error_model="numpy")
def _locked(x, p):
    """(D, f, qd) of the locked walker (coordinates q1, q2)."""
    return frp.dynamics(K.locked_mass_matrix, K.locked_bias, K.locked_forcing, x, 3, p, 2)


@njit(cache=True, error_model="numpy")
def _matrices(base, x, p):
    """(D, f, S, F, qd) of the base phase: ``f = Q_viscous - C qd - g``."""
    if base == UNLOCKED:
        D, f, qd = _unlocked(x, p)
        return D, f, _S_UNLOCKED, _dry(base, p).copy(), qd
    D, f, qd = _locked(x, p)
    return D, f, _S_LOCKED, _dry(base, p).copy(), qd


@njit(cache=True, error_model="numpy")
def rhs(phase, t, x, p, dx):
    base, modes, F = _joints(phase, p)
    if base == UNLOCKED:
        frp.phase_rhs(
            _unlocked, K.unlocked_mass_matrix, K.unlocked_accel, _S_UNLOCKED, F, modes, x, p, dx
        )
        return
    qdd = np.empty(2)
    frp.phase_accelerations(
        _locked, K.locked_mass_matrix, K.locked_accel, _S_LOCKED, F, modes, x, 3, p, qdd
    )
    relabel(x[3:], qdd, (0, 1, 1), dx)  # qd3 = qd2, qdd3 = qdd2


@njit(cache=True, error_model="numpy")
def jac(phase, t, x, p, J):
    base, modes, F = _joints(phase, p)
    if base == UNLOCKED:
        frp.phase_jac(
            _unlocked,
            K.unlocked_forcing,
            K.unlocked_dmass,
            K.unlocked_dbias_dq,
            K.unlocked_dbias_dqd,
            _S_UNLOCKED,
            F,
            modes,
            x,
            p,
            J,
        )
        return
    a = np.empty((2, 4))
    frp.phase_jacobian(
        _locked,
        K.locked_forcing,
        K.locked_dmass,
        K.locked_dbias_dq,
        K.locked_dbias_dqd,
        _S_LOCKED,
        F,
        modes,
        x,
        p,
        a,
    )
    # Locked: (q1, q2, qd1, qd2) map to state columns 0, 1, 3, 4; q3, qd3 copy q2, qd2.
    J[:, :] = 0.0
    J[0, 3] = 1.0
    J[1, 4] = 1.0
    J[2, 4] = 1.0
    cols = (0, 1, 3, 4)
    for i in range(2):
        for c in range(4):
            J[3 + i, cols[c]] = a[i, c]
    for c in range(6):
        J[5, c] = J[4, c]


@njit(cache=True, error_model="numpy")
def guards(phase, t, x, p, g):
    base, modes, F = _joints(phase, p)
    _kneed.guards(base, t, x, p, g)
    if base == UNLOCKED:
        frp.phase_guards(_unlocked, _S_UNLOCKED, F, modes, x, 3, p, g[4:10])
        return
    frp.phase_guards(_locked, _S_LOCKED, F, modes, x, 3, p, g[4:8])
    g[ix.KNEED_COULOMB_GUARD_KNEE_SLIP_STOPS] = 1.0
    g[ix.KNEED_COULOMB_GUARD_KNEE_STICK_BREAKS] = 1.0


@njit(cache=True, error_model="numpy")
def _start(base, x, p):
    """Choose every joint's mode for state ``x`` (velocities projected in place onto the
    stuck joints) and return the phase; -1 if a solve is singular."""
    modes = np.zeros(3, dtype=np.int64)
    modes[2] = fr.STICK  # the locked knee (unused while unlocked: chosen below)
    if base == UNLOCKED:
        return frp.phase_start(_unlocked, _S_UNLOCKED, _dry(base, p), modes, 0, x, 3, p)
    new_phase = frp.phase_start(_locked, _S_LOCKED, _dry(base, p), modes, N_UNLOCKED, x, 3, p)
    if new_phase >= 0:
        x[5] = x[4]
    return new_phase


@njit(cache=True, error_model="numpy")
def reset(phase, k, t, x, p, x_new, impulse):
    base, modes, F = _joints(phase, p)
    if k < 4:
        action, new_base, status = _kneed.reset(base, k, t, x, p, x_new, impulse)
        return after_base_reset(_start, phase, action, new_base, status, x_new, p)
    if base == UNLOCKED:
        return frp.phase_reset(_unlocked, _S_UNLOCKED, F, modes, phase, 0, k - 4, x, 3, p, x_new)
    action, new_phase, status = frp.phase_reset(
        _locked, _S_LOCKED, F, modes, phase, N_UNLOCKED, k - 4, x, 3, p, x_new
    )
    if action == EVENT_CONTINUE:
        x_new[5] = x_new[4]
    return action, new_phase, status


@njit(cache=True, error_model="numpy")
def joint_torques(phase, x, p):
    """Friction torque at each joint (ankle, hip, knee) [N m]: ``-+F`` while slipping, the
    holding torque while stuck (0 for the locked knee)."""
    base, modes, F = _joints(phase, p)
    if base == UNLOCKED:
        return frp.phase_torques(_unlocked, _S_UNLOCKED, F, modes, x, p)
    lam = np.zeros(3)
    lam[:2] = frp.phase_torques(_locked, _S_LOCKED, F, modes, x, p)
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
