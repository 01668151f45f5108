"""Grizzle's three-link walker (two legs, torso, two hip actuators) in closed loop, with
viscous and dry (Coulomb) friction at the two hip joints: the Python description of its
compiled model (walker/_core/model_three_link.c).

State ``x`` (8): ``(q_stance, q_swing, q_torso, qd_stance, qd_swing, qd_torso,
actuator_work, saturated_time)``: absolute angles from the vertical, counterclockwise positive
(:mod:`walker.symbolic.actuated`), then two accumulators that the dynamics integrate and the
impact carries over unchanged: the work done by the actuators since ``t0``,
``int u . (B^T qd) dt`` [J], and the time during which some torque was clipped to the limit
[s] (the saturation report; 0 when the limit was never reached).  The torque ``u`` is
computed inside ``rhs`` by the controller of ``walker/_core/wk_control.c`` from the state and the
controller block ``p[CONTROL_OFFSET:]`` of :class:`walker.params.ThreeLinkParams`.

Dynamics (``D qdd + C qd + g = B u - F_v qd - F_s sgn(qd) + J^T F`` with the
friction acting on the joint rates): the joints are the actuated ones, ``JOINTS =
("hip_stance", "hip_swing")`` with rates ``w = S qd``, ``S = B^T`` (:data:`S_MATRIX`):
``w = (qd_stance - qd_torso, qd_swing - qd_torso)``.  The controller is unchanged and does
not know about the friction (a disturbance that its PD on the outputs rejects): ``u`` is its
torque as in the frictionless model, then ``f = B u - h - F_v S^T w`` (``h = C qd + g``,
``F_v = damping_hip`` at both joints) and ``qdd`` follows from
:func:`walker.models.friction.accelerations` with the dry friction ``F_s = coulomb_hip`` of both
joints in the modes of the current phase (a stuck joint is held by whatever torque up to
``F_s`` keeps ``w_j = 0``: an augmented linear system).

Phases: ``stance`` x the joint modes, phase index = mode code
(:func:`walker.models.friction.encode`: ``hip_stance + 3 hip_swing``, mode 0 slip+, 1 slip-,
2 stick), 9 phases named by :func:`walker.models.friction.mode_names`.  :func:`start_phase` gives
the phase consistent with a state (:func:`walker.models.friction.choose_modes`);
:class:`walker.simulation.stride.StrideMap` and :func:`walker.simulation.stride.simulate` start
there.

Guards, in priority order:

0. ``heel_strike``: height of the swing foot above the slope, firing when it decreases
   through zero; accepted only with the swing foot ahead of the stance foot (by more than
   ``MIN_STEP`` leg lengths, which ignores the mid-stance scuff).  Reset:
   floating-base impact as an augmented linear system, then the legs swap (the torso keeps
   its angle), then every joint's mode is chosen for the post-impact state.
   ``NONPHYSICAL_IMPACT`` when the normal impulse is not positive, the impulse leaves the
   friction cone ``|P_t| <= mu P_n``, or the trailing foot does not lift off.
1. ``fall_forward`` / 2. ``fall_backward``: the stance leg passes ``FALL_ANGLE`` from the
   slope normal.
3. ``slip_forward`` (``mu F_n - F_t``), 4. ``slip_backward`` (``mu F_n + F_t``),
   5. ``lift_off`` (``F_n``): the ground reaction on the stance foot (computed from the
   closed-loop accelerations of the current phase) leaves the friction cone or pulls; each
   ends the run with ``NONPHYSICAL_IMPACT`` (the event log names the guard).  ``F_t`` is
   along the slope (forward), ``F_n`` along its normal.
6. ``hip_stance_slip_stops``, 7. ``hip_stance_stick_breaks``, 8. ``hip_swing_slip_stops``,
   9. ``hip_swing_stick_breaks`` (:func:`walker.models.friction.guards`, directions from
   :func:`walker.models.friction.directions`).  Resets (:func:`walker.models.friction.switch`) as in
   :mod:`walker.models.kneed_coulomb`: at ``slip_stops`` the joint is locked plastically
   (:func:`walker.models.friction.project_stuck`; its rate is rounding-small there) and every
   joint's mode is chosen again; at ``stick_breaks`` the joint slips against its holding
   torque and the other one is chosen again.  With ``coulomb_hip = 0`` the slip_stops
   guards are held at 1 (never fire): a joint without dry friction never sticks and its slip
   sign does not change the dynamics, so the frictionless model integrates exactly as before
   (same steps, same events).

Energy: ``dE/dt = u . w - F_v |w|^2 - sum_slip F_s |w_j|`` (a stuck joint does no work), so
between events ``E`` changes by the actuator work minus ``F_s |delta theta_j|`` per slipping
joint minus the viscous losses.

Section (just after heel strike): ``(q_stance, q_torso, qd_stance, qd_swing, qd_torso)``;
``q_swing = -2 slope - q_stance`` there; ``lift`` sets both accumulators to zero.

The book's variant (Westervelt, Grizzle, Chevallereau, Choi, Morris 2007, three-link example;
``ThreeLinkParams.westervelt_book``, ``gaits/three_link_book.toml``): ``step_event = 1`` makes
guard 0 ``q_stance - theta_minus`` (the step ends where the stance angle falls through
``theta_minus``, wherever the swing foot is; same impact map and leg swap), and the section's
``q_swing`` is then ``theta_minus``.  ``controller = 3``, the finite-time controller on
polynomial outputs, is in ``walker/_core/wk_control.c`` as the others are.
"""

import numpy as np

from walker._generated import indices as ix
from walker.models import friction as fr
from walker.models._common import (
    ground_reaction_at,
)
from walker.params import MODELS

N_X = len(MODELS["three_link"].state_names)
N_Q = 3
N_IMPULSE = 2
JOINTS = ("hip_stance", "hip_swing")
ACTUATED = True
"""The joints in ``JOINTS`` carry actuators (the controller's torques, one a joint)."""
N_JOINTS = 2
N_CODES = 9
"""Number of joint-mode codes, ``3**N_JOINTS`` (a test checks it)."""
PHASE_NAMES = tuple(f"stance {fr.mode_names(c, JOINTS)}" for c in range(N_CODES))
N_BASE_GUARDS = 6
"""Guards of the frictionless model (indices 0..5); the friction guards follow."""
GUARD_NAMES = (
    "heel_strike",
    "fall_forward",
    "fall_backward",
    "slip_forward",
    "slip_backward",
    "lift_off",
) + tuple(f"{j}_{kind}" for j in JOINTS for kind in ("slip_stops", "stick_breaks"))
DIRECTIONS = np.array(
    [[-1, -1, 1, -1, -1, -1] + fr.directions(c, N_JOINTS) for c in range(N_CODES)],
    dtype=np.int64,
)
STATE_NAMES = MODELS["three_link"].state_names  # the model registry (walker.params)
SECTION_NAMES = ("q_stance", "q_torso", "qd_stance", "qd_swing", "qd_torso")

I_LEG_A, I_LEG_B = ix.THREE_LINK_P_COM_FROM_FOOT, ix.THREE_LINK_P_COM_TO_HIP
I_SLOPE, I_FRICTION = ix.THREE_LINK_P_SLOPE, ix.THREE_LINK_P_FRICTION
MIN_STEP = 1e-8
"""A heel strike needs the swing foot ahead by more than ``MIN_STEP`` leg lengths.  With rigid
legs the foot height ``r (cos q_stance - cos q_swing)`` has two zeros: ``q_swing =
-q_stance`` (a step) and ``q_swing = q_stance`` (the swing foot passing through the stance
foot, step length zero up to round-off): the latter is the mid-stance scuff."""
CONTROL_OFFSET = ix.THREE_LINK_P_CONTROLLER
"""Index in ``p`` of the controller block (:mod:`walker.models.control` layout)."""
I_THETA_MINUS = ix.THREE_LINK_P_THETA_MINUS
I_STEP_EVENT = ix.THREE_LINK_P_STEP_EVENT
"""Index in ``p`` of ``step_event`` (0: the step ends at heel strike, 1: where the stance
angle falls through ``theta_minus``)."""
I_FT = ix.THREE_LINK_P_FT_ALPHA
"""Index in ``p`` of the finite-time controller's block (controller 3, compiled C only):
``ft_alpha``, ``ft_epsilon``, ``poly_swing_0..5``, ``poly_torso_0..5``
(``walker/_core/wk_control.h``)."""
I_DAMPING_HIP, I_COULOMB_HIP = ix.THREE_LINK_P_DAMPING_HIP, ix.THREE_LINK_P_COULOMB_HIP
"""Indices in ``p`` of ``damping_hip`` and ``coulomb_hip`` (after the controller blocks; a
test checks them against :class:`walker.params.ThreeLinkParams`)."""

B_MATRIX = np.array([[1.0, 0.0], [0.0, 1.0], [-1.0, -1.0]])
S_MATRIX = np.array([[1.0, 0.0, -1.0], [0.0, 1.0, -1.0]])
"""Joint rows ``S = B^T``: ``w = S qd`` are the hip rates (leg relative to the torso)."""
JAC_STEP = 1e-6
"""Relative step of the central differences that give the vector field's Jacobian."""


def ground_reaction(x, p, phase=None):
    """Ground force on the stance foot ``(F_t, F_n)`` along and normal to the slope [N].

    Parameters
    ----------
    x : ndarray, shape (8,)
    p : ndarray
        the ``ThreeLinkParams`` vector.
    phase : int, optional
        joint-mode phase; default the phase consistent with ``x``
        (:meth:`walker.models.WalkerModel.start_phase`).
    """
    return ground_reaction_at("three_link", x, p, phase)


def phase_of(**modes: str) -> int:
    """Phase index from joint modes (``"slip+"``, ``"slip-"``, ``"stick"``; default
    ``"slip+"``), e.g. ``phase_of(hip_swing="stick")``."""
    return fr.code_of(JOINTS, modes)


def modes_of(phase: int) -> dict[str, str]:
    """{joint: mode} of a phase index: the inverse of :func:`phase_of`."""
    return fr.labels_of(phase, JOINTS)


LIFT_AFFINE = True
"""``lift`` is ``lift(0, p) + lift_jacobian(0, p) z``, each row one term (basin batches,
:meth:`walker.simulation.stride.StrideMap.basin_batch`, rely on it; tests/test_basin.py checks
it)."""


def lift(z, p):
    """Section point ``(q_stance, q_torso, qd_stance, qd_swing, qd_torso)`` -> full state.

    With ``step_event = 0`` the swing foot is on the slope, ``q_swing = -2 slope -
    q_stance``; with ``step_event = 1`` the step ended at ``q_stance = theta_minus``, so after
    the legs swap ``q_swing = theta_minus`` whatever ``q_stance`` is."""
    if p[I_STEP_EVENT] == 1.0:
        q_swing = p[I_THETA_MINUS]
    else:
        q_swing = -2.0 * p[I_SLOPE] - z[0]
    return np.array([z[0], q_swing, z[1], z[2], z[3], z[4], 0.0, 0.0])


def lift_jacobian(z, p):
    J = np.zeros((N_X, 5))
    J[0, 0] = 1.0
    J[1, 0] = 0.0 if p[I_STEP_EVENT] == 1.0 else -1.0
    J[2, 1] = 1.0
    J[3, 2] = J[4, 3] = J[5, 4] = 1.0
    return J


def project(x, p):
    return np.array([x[0], x[2], x[3], x[4], x[5]])


SEGMENTS = ((0, 1), (1, 2), (1, 3))
SWING_FOOT = 2  # row of the swing foot in points()
