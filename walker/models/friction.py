"""Dry (Coulomb) joint friction with stick and slip as phases and events: the mechanics, and
the Python side of its phase and guard naming.  The compiled pieces that any model assembles
from its own ``D``, forcing and joint rows are in ``walker/_core/wk_friction.c`` (the
``wk_friction_*`` functions named below).

A joint ``j`` has the rate ``w_j = S_j qd`` with a constant row ``S_j`` (joints are relative
angles, so ``S`` does not depend on ``q``; the stance "ankle" between the slope and the
stance leg has ``S = e_stance``).  A torque ``tau_j`` at joint ``j`` enters the equations of
motion as the generalized force ``S_j^T tau_j``:

    D(q) qdd = f(q, qd) + sum_j S_j^T tau_j,

``f`` being everything else (``-C qd - g``, the viscous dampers, actuator torques ``B u``).
Dry friction of magnitude ``F_j >= 0`` is, per joint, in one of three modes:

* ``SLIP_POSITIVE`` (``w_j > 0``): ``tau_j = -F_j``;
* ``SLIP_NEGATIVE`` (``w_j < 0``): ``tau_j = +F_j``;
* ``STICK`` (``w_j = 0``): ``tau_j = lambda_j``, the constraint torque that keeps
  ``S_j qdd = 0``, admissible while ``|lambda_j| < F_j``.

The stuck joints make an augmented linear system, as the impacts do::

    [D, -S_k^T; S_k, 0] [qdd; lambda_k] = [f + sum_slip S_j^T tau_j; 0]

(``wk_friction_accelerations``).  No ``tanh`` smear: a mode is a discrete state, kept in the phase
index (``wk_friction_encode``), and a mode changes only at an event:

* ``slip_stops`` (slipping joint): ``w_j`` through zero toward zero;
* ``stick_breaks`` (stuck joint): ``|lambda_j| - F_j`` increasing through zero.

At either event the modes of every joint at rest are chosen again (``wk_friction_choose_modes``):
joints that move slip with the sign of their rate; for the joints at rest, the one
combination of stick / slip+ / slip- that is consistent (stuck: ``|lambda| < F``; slipping
from rest with sign ``s``: ``s S_j qdd > 0``).  With a positive definite ``D`` the
accelerations of joint friction minimize a strictly convex function (maximal dissipation,
[1]_), so the consistent combination is unique when one exists with strict inequalities;
on a tie (a tangency) the first combination consistent with non-strict inequalities is
taken.  ``F_j = 0`` never sticks.  A joint that starts to stick has its velocity projected
onto ``w_j = 0`` by the plastic lock ``[D, -S^T; S, 0] [qd+; Lambda] = [D qd-; 0]``
(``wk_friction_project_stuck``); at a ``slip_stops`` event ``|w_j|`` is rounding-small, so this
changes the energy by O(w^2).

Energy: the friction torques do the power ``sum_j tau_j w_j = -sum_slip F_j |w_j|`` and the
stuck joints none, so over a slip interval joint ``j`` dissipates ``F_j |delta theta_j|``
exactly.

The phase index of a model with friction is ``base * 3**n_joints + code`` where ``code =
sum_j mode_j 3**j`` (``wk_friction_encode``, ``wk_friction_decode``); ``base`` is the model's
own phase (the kneed walker's ``unlocked`` / ``locked``).  Guards: two per joint, ``2 j``
slip_stops and ``2 j + 1`` stick_breaks (``wk_friction_guards``), with directions from
:func:`directions`.

A model's phase functions over these pieces and its generated kernels (``rhs``, ``jac``,
mode choice and friction reset, written once for every friction model) are in
``walker/_core/wk_friction.h``.

References
----------
.. [1] F. Pfeiffer, C. Glocker, *Multibody Dynamics with Unilateral Contacts*, Wiley, 1996
   (dry friction in joints as switching conditions on the constraint force).
.. [2] D. E. Stewart, "Rigid-body dynamics with friction and impact", SIAM Review 42(1):3-39,
   2000 (maximal dissipation; uniqueness of the accelerations).
"""

from __future__ import annotations

__all__ = [
    "SLIP_POSITIVE",
    "SLIP_NEGATIVE",
    "STICK",
    "MODE_LABELS",
    "W_TOL",
    "N_MODES",
    "directions",
    "mode_names",
    "code_of",
    "labels_of",
]

SLIP_POSITIVE, SLIP_NEGATIVE, STICK = 0, 1, 2
N_MODES = 3
MODE_LABELS = ("slip+", "slip-", "stick")
W_TOL = 1e-12
"""|w| [rad/s] at or below which a joint rate counts as zero when modes are chosen."""


def directions(code: int, n_joints: int) -> list[int]:
    """Guard directions (2 per joint) in the modes of ``code`` (Python side, for a model's
    ``DIRECTIONS`` table)."""
    out = []
    for _ in range(n_joints):
        mode = code % N_MODES
        code //= N_MODES
        out.append(1 if mode == SLIP_NEGATIVE else -1)  # slip_stops
        out.append(1)  # stick_breaks
    return out


def mode_names(code: int, joints: tuple[str, ...]) -> str:
    """``"hip=slip+ knee=stick"`` for a mode code (Python side, for phase names)."""
    parts = []
    for name in joints:
        parts.append(f"{name}={MODE_LABELS[code % N_MODES]}")
        code //= N_MODES
    return " ".join(parts)


def code_of(joints: tuple[str, ...], modes: dict[str, str]) -> int:
    """Mode code from ``{joint: label}`` (labels ``"slip+"``, ``"slip-"``, ``"stick"``;
    a joint not given is ``"slip+"``), validated (Python side, for a model's ``phase_of``)."""
    unknown = set(modes) - set(joints)
    if unknown:
        raise ValueError(f"joint modes must be given for {joints}, got {sorted(unknown)}")
    code = 0
    for i, name in enumerate(joints):
        label = modes.get(name, "slip+")
        if label not in MODE_LABELS:
            raise ValueError(f"mode of `{name}` must be one of {MODE_LABELS}, got {label!r}")
        code += MODE_LABELS.index(label) * N_MODES**i
    return code


def labels_of(code: int, joints: tuple[str, ...]) -> dict[str, str]:
    """``{joint: label}`` of a mode code: the inverse of :func:`code_of`."""
    if not 0 <= code < N_MODES ** len(joints):
        raise ValueError(f"`phase` must be in [0, {N_MODES ** len(joints)}), got {code}")
    out = {}
    for name in joints:
        out[name] = MODE_LABELS[code % N_MODES]
        code //= N_MODES
    return out
