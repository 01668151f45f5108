"""The compass gait with dry (Coulomb) friction at the stance ankle and the hip: stick and
slip as phases and events (:mod:`walker.models.friction`).

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
rest sticks if its friction can hold it), and :class:`walker.simulation.stride.StrideMap` and
:func:`walker.simulation.stride.simulate` start there.

Guards, in priority order: 0 ``heel_strike``, 1 ``fall_forward``, 2 ``fall_backward``, as in
the compass gait (their resets are the compass gait's; after a heel strike the modes are
chosen afresh for the post-impact state); then per joint ``<joint>_slip_stops`` (its rate
through zero toward zero) and ``<joint>_stick_breaks`` (``|lambda| - F_s`` increasing through
zero), whose resets are :func:`walker.models.friction.switch`: a joint that stops slipping gets its
rate made exactly zero by the plastic lock (it is rounding-small at the event, so the energy
changes by O(w^2)) and every joint's mode is chosen again; a joint whose stiction is exceeded
slips against its holding torque.

With both frictions zero the stride is the compass gait's, with the same events (a joint
without dry friction has no friction guards).  Energy: ``dE/dt = -b_hip w_hip^2 - b_ankle
w_ankle^2 - sum_slip F_j |w_j|``, so without the viscous dampers the energy lost over an
interval without events is ``sum_j F_j |delta theta_j|`` exactly, and nothing while stuck.

Jacobian ``jac``: exact in every phase (:func:`walker.models.friction.accelerations_jacobian` with
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

from walker._generated import indices as ix
from walker.models import compass as _compass
from walker.models import friction as fr
from walker.models._common import joint_friction_walker
from walker.params import MODELS

__all__, __getattr__, __dir__ = joint_friction_walker(__name__, _compass)

KERNEL_MODULE = "compass"
"""The generated kernels are the compass model's (:meth:`walker.models.WalkerModel.kernel`)."""
N_X = len(MODELS["compass_coulomb"].state_names)
N_IMPULSE = 2
STATE_NAMES = MODELS["compass_coulomb"].state_names  # the model registry (walker.params)
JOINTS = ("ankle", "hip")
N_JOINTS = 2
I_COULOMB = ix.COMPASS_COULOMB_P_COULOMB_ANKLE
"""Index of ``coulomb_ankle`` in the parameter vector (``coulomb_hip`` follows), from the
generated :mod:`walker._generated.indices`."""
N_BASE_GUARDS = 3

PHASE_NAMES = tuple(f"swing {fr.mode_names(c, JOINTS)}" for c in range(fr.N_MODES**N_JOINTS))
GUARD_NAMES = ("heel_strike", "fall_forward", "fall_backward") + tuple(
    f"{j}_{kind}" for j in JOINTS for kind in ("slip_stops", "stick_breaks")
)
DIRECTIONS = np.array(
    [list(_compass.DIRECTIONS[0]) + fr.directions(c, N_JOINTS) for c in range(len(PHASE_NAMES))],
    dtype=np.int64,
)


def phase_of(**modes: str) -> int:
    """Phase index from joint modes (``"slip+"``, ``"slip-"``, ``"stick"``; default
    ``"slip+"``), e.g. ``phase_of(ankle="slip-", hip="stick")``."""
    return fr.code_of(JOINTS, modes)


def modes_of(phase: int) -> dict[str, str]:
    """{joint: mode} of a phase index: the inverse of :func:`phase_of`."""
    return fr.labels_of(phase, JOINTS)
