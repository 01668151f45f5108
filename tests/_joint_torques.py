"""The dry-friction torques a compiled model applies at its joints, recovered by Newton's law.

In a phase of a model with joint friction the compiled ``rhs`` gives the accelerations
``qdd``; the equations of motion ``D qdd = f + S^T tau`` (``f`` every generalized force but
joint friction: ``-h``, the viscous dampers, the actuators ``B u``) then fix the joint torques
``tau`` (``S^T`` has full column rank): a slipping joint's is ``-/+ F_j``, a stuck joint's the
holding torque.  ``D``, ``h`` and the viscous forcing come from the generated kernels, the
actuator torques from the compiled controller, each through the checked interface of
:class:`walker.models.WalkerModel`.
"""

import numpy as np

from walker.models import get_model

_S_COMPASS = np.array([[1.0, 0.0], [-1.0, 1.0]])  # ankle = q_stance, hip = q_swing - q_stance
_S_KNEED = np.array([[1.0, 0.0, 0.0], [-1.0, 1.0, 0.0], [0.0, -1.0, 1.0]])


def _passive(model, prefix, n, S, x, p, qdd):
    q, qd = x[:n], x[model.n_x // 2 : model.n_x // 2 + n]
    D = model.kernel(f"{prefix}mass_matrix", p, q)
    f = model.kernel(f"{prefix}forcing", p, q, qd) - model.kernel(f"{prefix}bias", p, q, qd)
    return D, f, S, qdd


def joint_torques(name, phase, x, p) -> np.ndarray:
    """The friction torque at each joint [N m] of model ``name`` in ``phase`` at state ``x``
    (the order of the module's ``JOINTS``; for the kneed walker's locked phases the ankle and
    hip): the dry friction, and for the actuated walkers also the viscous ``-F_v w_j`` (the
    passive models' dampers are in their generated ``forcing``); an actuated joint's total
    torque is ``model.torques(x, p) + joint_torques(...)``."""
    model = get_model(name)
    m = model.module
    x = np.asarray(x, dtype=float)
    p = p.as_array() if hasattr(p, "as_array") else np.asarray(p, dtype=float)
    dx = model.rhs(phase, x, p)
    if name == "double_pendulum":
        D, f, S, qdd = _passive(model, "", 2, np.eye(2), x, p, dx[2:])
    elif name == "compass_coulomb":
        D, f, S, qdd = _passive(model, "", 2, _S_COMPASS, x, p, dx[2:])
    elif name == "kneed_coulomb":
        if phase < m.N_UNLOCKED:
            D, f, S, qdd = _passive(model, "unlocked_", 3, _S_KNEED, x, p, dx[3:])
        else:
            D, f, S, qdd = _passive(model, "locked_", 2, _S_COMPASS, x, p, dx[3:5])
    else:  # the actuated walkers
        n = m.N_Q
        q, qd = x[:n], x[n : 2 * n]
        S, B = m.S_MATRIX, m.B_MATRIX
        D = model.kernel("mass_matrix", p, q)
        f = B @ model.torques(x, p) - model.kernel("bias", p, q, qd)
        qdd = dx[n : 2 * n]
    tau, *_ = np.linalg.lstsq(S.T, D @ qdd - f, rcond=None)
    return tau
