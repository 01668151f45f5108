"""The kneed walker with dry (Coulomb) friction at the stance ankle, the hip and the swing
knee: stick and slip as phases and events (:mod:`walker.models.friction`).

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
with a state, and :class:`walker.simulation.stride.StrideMap` and
:func:`walker.simulation.stride.simulate` start there (the new swing knee is straight and at
rest just after heel strike, so whether it sticks depends on the friction).

Guards, in priority order: 0 ``knee_lock``, 1 ``swing_foot_contact``, 2 ``fall_forward``,
3 ``fall_backward``, exactly as in the kneed walker (their resets are the kneed walker's:
knee lock, heel strike with leg swap, trip, falls); then per joint ``<joint>_slip_stops``
and ``<joint>_stick_breaks`` (4..9), whose resets choose the modes again
(:func:`walker.models.friction.choose_modes`) and project the velocities of joints that start to
stick.  After every impact the modes are chosen afresh for the post-impact state.  A knee
stuck bent cannot lock, and its foot striking the ground is a trip; a knee stuck straight
strikes as a locked leg (the kneed walker's simultaneous knee-lock and heel-strike rule).

With all three frictions zero the stride is the kneed walker's, with the same events (a
joint without dry friction has no friction guards; the accelerations come from the same
matrices by another elimination, so they agree to round-off).  Energy: between events ``E``
decreases by ``sum_j F_j |delta theta_j|`` plus the viscous dampers' work.

Jacobian ``jac``: exact in every phase (:func:`walker.models.friction.accelerations_jacobian` with
the generated ``dmass``, ``dbias_dq``, ``dbias_dqd`` and the linear viscous forcing).
"""

import numpy as np

from walker._generated import indices as ix
from walker.models import friction as fr
from walker.models import kneed as _kneed
from walker.models._common import joint_friction_walker
from walker.params import MODELS

__all__, __getattr__, __dir__ = joint_friction_walker(__name__, _kneed)

KERNEL_MODULE = "kneed"
"""The generated kernels are the kneed model's (:meth:`walker.models.WalkerModel.kernel`)."""
N_X = len(MODELS["kneed_coulomb"].state_names)
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
