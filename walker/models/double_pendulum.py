"""The planar double pendulum (elbow-manipulator coordinates) with viscous and dry (Coulomb)
joint friction: stick and slip as phases and events (:mod:`walker.models.friction`).

State ``x = (q1, q2, qd1, qd2)``: ``q1`` of link 1 from the +x axis, ``q2`` of link 2
relative to link 1 (counterclockwise positive).  Parameters:
:class:`walker.params.DoublePendulumParams`, nine physical parameters followed
by ``damping_1``, ``damping_2`` [N m s/rad] and ``coulomb_1``, ``coulomb_2`` [N m]
(``p[9]`` .. ``p[12]``).  With all four zero (the energy-check preset) the pendulum is
conservative and serves to check the integrator by energy conservation.

Joints and their rates ``w = S qd`` (``S`` the identity, since ``q2`` is relative):

* ``joint_1`` (the ground to link 1): ``w1 = qd1``;
* ``joint_2`` (link 1 to link 2): ``w2 = qd2``.

The friction terms of ``D qdd + C qd + g = -F_v qd - F_s sgn(qd)``, joint by joint: the
viscous part ``-b_j w_j`` is the generated forcing (:func:`walker.symbolic.models.double_pendulum`,
Rayleigh dissipation); the dry part is never smoothed.  While joint ``j`` slips its friction
torque is ``-F_j sgn(w_j)``; while it sticks the joint is held by the constraint torque that
the augmented system ``[D, -S_k^T; S_k, 0] [qdd; lambda] = [f; 0]`` gives, as long as
``|lambda| < F_j``.

Phases: the joint-mode code ``joint_1 + 3 joint_2`` (mode 0 slip+, 1 slip-, 2 stick), 9
phases named ``"free joint_1=slip- joint_2=stick"`` and so on.  :func:`start_phase` gives
the phase consistent with a state (a joint at rest sticks if its friction can hold it), and
:func:`walker.simulation.stride.simulate` starts there.

Guards: per joint ``<joint>_slip_stops`` (its rate through zero toward zero) and
``<joint>_stick_breaks`` (``|lambda| - F_j`` increasing through zero); the model has no
other events (and no strides: a run integrates to ``t_max``, ``n_strides = 0``).  Their
resets are :func:`walker.models.friction.switch`: a joint that stops slipping gets its rate made
exactly zero by the plastic lock (it is rounding-small at the event, so the energy changes
by O(w^2)) and every joint's mode is chosen again; a joint whose stiction is exceeded slips
against its holding torque.  A joint without dry friction has no friction guards, so with
``coulomb_1 = coulomb_2 = 0`` no event ever fires.

Energy: ``dE/dt = -sum_j b_j w_j^2 - sum_slip F_j |w_j|``; the stuck joints do no work.

Evaluation: with no joint stuck, ``rhs`` is the fused generated ``accel`` kernel (viscous
dampers included) plus ``D^-1`` of the slip torques (nothing more without dry friction, so
the frictionless pendulum runs on the generated kernel alone); with a joint stuck, the
augmented system.

Jacobian ``jac``: exact in every phase (:func:`walker.models.friction.accelerations_jacobian` with
the generated ``dmass``, ``dbias_dq``, ``dbias_dqd`` and the linear viscous forcing).

Known limitation: repeated stick-slip switching (Zeno behaviour) is not accelerated; each
switch is one event.

References
----------
.. [1] M. W. Spong, S. Hutchinson, M. Vidyasagar, *Robot Modeling and Control*, Wiley, 2006,
   ch. 7 (the two-link planar elbow manipulator; ``D qdd + C qd + g = tau``).
.. [2] F. Pfeiffer, C. Glocker, "Multibody Dynamics with Unilateral Contacts", Wiley, 1996
   (stick-slip transitions of dry joint friction as switching conditions on the constraint
   force).
"""

import numpy as np

from walker._generated import indices as ix
from walker.models import friction as fr
from walker.models._common import JOINT_FRICTION_EXPORTS
from walker.params import MODELS

__all__ = [*JOINT_FRICTION_EXPORTS, "SECTION_NAMES", "SEGMENTS"]

N_X = len(MODELS["double_pendulum"].state_names)
N_IMPULSE = 1
JOINTS = ("joint_1", "joint_2")
N_JOINTS = 2
I_COULOMB = ix.DOUBLE_PENDULUM_P_COULOMB_1
"""Index of ``coulomb_1`` in the parameter vector (``coulomb_2`` follows), from the
generated :mod:`walker._generated.indices`."""

PHASE_NAMES = tuple(f"free {fr.mode_names(c, JOINTS)}" for c in range(fr.N_MODES**N_JOINTS))
GUARD_NAMES = tuple(f"{j}_{kind}" for j in JOINTS for kind in ("slip_stops", "stick_breaks"))
DIRECTIONS = np.array([fr.directions(c, N_JOINTS) for c in range(len(PHASE_NAMES))], dtype=np.int64)
STATE_NAMES = MODELS["double_pendulum"].state_names  # the model registry (walker.params)
SECTION_NAMES = ()

_S = np.array([[1.0, 0.0], [0.0, 1.0]])

# The phase functions are walker.models.friction's, over the pendulum's kernels: the joint rows _S,
# the dry frictions p[I_COULOMB:], the rates x[2:4].


def phase_of(**modes: str) -> int:
    """Phase index from joint modes (``"slip+"``, ``"slip-"``, ``"stick"``; default
    ``"slip+"``), e.g. ``phase_of(joint_1="slip-", joint_2="stick")``."""
    return fr.code_of(JOINTS, modes)


def modes_of(phase: int) -> dict[str, str]:
    """{joint: mode} of a phase index: the inverse of :func:`phase_of`."""
    return fr.labels_of(phase, JOINTS)


SEGMENTS = ((0, 1), (1, 2))
