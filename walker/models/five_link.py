"""The five-link walker (torso, femurs, tibias; hip and knee actuators; point feet) in closed
loop, with viscous and dry (Coulomb) friction at the four actuated joints: the Python
description of its compiled model (walker/_core/model_five_link.c).

State ``x`` (12): ``(q_leg, q_knee, q_torso, q_femur_sw, q_tibia_sw, qd_leg, qd_knee,
qd_torso, qd_femur_sw, qd_tibia_sw, actuator_work, saturated_time)``: the coordinates of
:mod:`walker.symbolic.five_link` (mean stance-leg angle, stance-knee flexion, then absolute
angles from the vertical, counterclockwise positive), their rates, and two accumulators that
the dynamics integrate and the impact carries over unchanged: the actuators' work since
``t0``, ``int u . (B^T qd) dt`` [J], and the time during which some torque was clipped to
the limit [s].  The torque ``u`` is computed inside ``rhs`` by
the controller of ``walker/_core/wk_control.c`` (phase variable ``q_leg``, outputs ``q[1:]``) from
the controller block ``p[CONTROL_OFFSET:]`` of :class:`walker.params.FiveLinkParams`.

Dynamics (``D qdd + C qd + g = B u - F_v qd - F_s sgn(qd) + J^T F`` with the
friction acting on the joint rates): the joints are the actuated ones, ``JOINTS =
("hip_stance", "hip_swing", "knee_stance", "knee_swing")`` with rates ``w = S qd``, ``S =
B^T`` (:data:`S_MATRIX`): hips ``femur - torso``, knees ``tibia - femur`` (rates).  The
controller is unchanged and does not know about the friction (a disturbance that its PD on
the outputs rejects): ``u`` is its torque as in the frictionless model, then ``f = B u - h -
S^T F_v w`` (``h = C qd + g``; ``F_v`` is ``damping_hip`` at the hips, ``damping_knee`` at
the knees) and ``qdd`` follows from :func:`walker.models.friction.accelerations` with the dry
friction ``F_s`` (``coulomb_hip``, ``coulomb_knee``) in the modes of the current phase (a
stuck joint is held by whatever torque up to ``F_s`` keeps ``w_j = 0``: an augmented linear
system).

Phases: ``stance`` x the joint modes, phase index = mode code
(:func:`walker.models.friction.encode`: ``hip_stance + 3 hip_swing + 9 knee_stance + 27
knee_swing``, mode 0 slip+, 1 slip-, 2 stick), 81 phases named by
:func:`walker.models.friction.mode_names`.  :func:`start_phase` gives the phase consistent with a
state (:func:`walker.models.friction.choose_modes`); :class:`walker.simulation.stride.StrideMap` and
:func:`walker.simulation.stride.simulate` start there.

Guards, in priority order:

0. ``heel_strike``: height of the swing foot above the slope, firing when it decreases
   through zero.  Accepted when the swing foot is ahead of the stance foot (by more than
   ``MIN_STEP`` leg lengths); a touchdown behind it is a trip (``TRIPPED``).  Reset:
   floating-base impact as an augmented linear system, then the legs swap (femurs and tibias
   trade places; the new stance knee is the old swing knee), then every joint's mode is
   chosen for the post-impact state.  ``NONPHYSICAL_IMPACT`` when the normal impulse is not
   positive, the impulse leaves the friction cone ``|P_t| <= mu P_n``, or the trailing foot
   does not lift off.
1. ``fall_forward`` / 2. ``fall_backward``: the line from the stance foot to the hip passes
   ``FALL_ANGLE`` from the slope normal.
3. ``slip_forward`` (``mu F_n - F_t``), 4. ``slip_backward`` (``mu F_n + F_t``),
   5. ``lift_off`` (``F_n``): the ground reaction on the stance foot (from the closed-loop
   accelerations of the current phase) leaves the friction cone or pulls; each ends the run
   with ``NONPHYSICAL_IMPACT`` (the event log names the guard).
6. ``hip_down``: the hip reaches the slope (ends the run with ``FELL_BACKWARD``).
7..14. ``<joint>_slip_stops``, ``<joint>_stick_breaks`` per joint in ``JOINTS`` order
   (:func:`walker.models.friction.guards`, directions from
   :func:`walker.models.friction.directions`). Resets (:func:`walker.models.friction.switch`) as in
   :mod:`walker.models.kneed_coulomb`: at ``slip_stops`` the joint is locked
   plastically (:func:`walker.models.friction.project_stuck`; its rate is rounding-small there) and
   every joint's mode is chosen again; at ``stick_breaks`` the joint slips against its
   holding torque and the others are chosen again.  A joint without dry friction
   (``F_s = 0``) has its slip_stops guard held at 1 (never fires): it never sticks and its
   slip sign does not change the dynamics, so the frictionless model integrates exactly as
   before (same steps, same events).

Energy: ``dE/dt = u . w - sum_j F_v,j w_j^2 - sum_slip F_s,j |w_j|`` (a stuck joint does no
work), so between events ``E`` changes by the actuator work minus ``F_s,j |delta theta_j|``
per slipping joint minus the viscous losses.

Section (just after heel strike): ``(q_leg, q_knee, q_torso, q_femur_sw, qd_leg, qd_knee,
qd_torso, qd_femur_sw, qd_tibia_sw)``; ``q_tibia_sw`` puts the swing foot on the slope, behind
its knee (``lift``); ``lift`` sets both accumulators to zero.
"""

import math

import numpy as np

from walker._generated import indices as ix
from walker.models import friction as fr
from walker.models._common import (
    ground_reaction_at,
)
from walker.params import MODELS

N_X = len(MODELS["five_link"].state_names)
N_Q = 5
N_U = 4
N_IMPULSE = 2
JOINTS = ("hip_stance", "hip_swing", "knee_stance", "knee_swing")
ACTUATED = True
"""The joints in ``JOINTS`` carry actuators (the controller's torques, one a joint)."""
N_JOINTS = 4
N_CODES = 81
"""Number of joint-mode codes, ``3**N_JOINTS`` (a test checks it)."""
PHASE_NAMES = tuple(f"stance {fr.mode_names(c, JOINTS)}" for c in range(N_CODES))
N_BASE_GUARDS = 7
"""Guards of the frictionless model (indices 0..6); the friction guards follow."""
GUARD_NAMES = (
    "heel_strike",
    "fall_forward",
    "fall_backward",
    "slip_forward",
    "slip_backward",
    "lift_off",
    "hip_down",
) + tuple(f"{j}_{kind}" for j in JOINTS for kind in ("slip_stops", "stick_breaks"))
DIRECTIONS = np.array(
    [[-1, -1, 1, -1, -1, -1, -1] + fr.directions(c, N_JOINTS) for c in range(N_CODES)],
    dtype=np.int64,
)
STATE_NAMES = MODELS["five_link"].state_names  # the model registry (walker.params)
SECTION_NAMES = (
    "q_leg",
    "q_knee",
    "q_torso",
    "q_femur_sw",
    "qd_leg",
    "qd_knee",
    "qd_torso",
    "qd_femur_sw",
    "qd_tibia_sw",
)

I_LENGTH_FEMUR, I_LENGTH_TIBIA = ix.FIVE_LINK_P_LENGTH_FEMUR, ix.FIVE_LINK_P_LENGTH_TIBIA
I_SLOPE, I_FRICTION = ix.FIVE_LINK_P_SLOPE, ix.FIVE_LINK_P_FRICTION
CONTROL_OFFSET = ix.FIVE_LINK_P_CONTROLLER
"""Index in ``p`` of the controller block (:mod:`walker.models.control` layout)."""
I_DAMPING_HIP, I_DAMPING_KNEE = ix.FIVE_LINK_P_DAMPING_HIP, ix.FIVE_LINK_P_DAMPING_KNEE
I_COULOMB_HIP, I_COULOMB_KNEE = ix.FIVE_LINK_P_COULOMB_HIP, ix.FIVE_LINK_P_COULOMB_KNEE
"""Indices in ``p`` of the joint friction (after the controller block; a test checks them
against :class:`walker.params.FiveLinkParams`)."""
MIN_STEP = 1e-8
"""A heel strike needs the swing foot ahead of the stance foot by more than ``MIN_STEP`` leg
lengths; a touchdown at or behind the stance foot is a trip."""

B_MATRIX = np.array(
    [
        [1.0, 0.0, 0.0, 0.0],
        [0.5, 0.0, -1.0, 0.0],
        [-1.0, -1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, -1.0],
        [0.0, 0.0, 0.0, 1.0],
    ]
)
"""Input map ``B`` (:data:`walker.symbolic.five_link.B_MATRIX`): inputs ``(hip stance, hip
swing, knee stance, knee swing)``."""
S_MATRIX = np.array(
    [
        [1.0, 0.5, -1.0, 0.0, 0.0],
        [0.0, 0.0, -1.0, 1.0, 0.0],
        [0.0, -1.0, 0.0, 0.0, 0.0],
        [0.0, 0.0, 0.0, -1.0, 1.0],
    ]
)
"""Joint rows ``S = B^T``: ``w = S qd`` are the joint rates (hip stance, hip swing, knee
stance, knee swing)."""
RELABEL = np.array(
    [
        [0.0, 0.0, 0.0, 0.5, 0.5],
        [0.0, 0.0, 0.0, 1.0, -1.0],
        [0.0, 0.0, 1.0, 0.0, 0.0],
        [1.0, 0.5, 0.0, 0.0, 0.0],
        [1.0, -0.5, 0.0, 0.0, 0.0],
    ]
)
"""Leg swap on the coordinates and rates: ``q+ = RELABEL q-`` (the old swing femur and tibia
become the stance ones, and the other way round)."""
JAC_STEP = 1e-6
"""Relative step of the central differences that give the vector field's Jacobian."""


def ground_reaction(x, p, phase=None):
    """Ground force on the stance foot ``(F_t, F_n)`` along and normal to the slope [N].

    Parameters
    ----------
    x : ndarray, shape (12,)
    p : ndarray
        the ``FiveLinkParams`` vector.
    phase : int, optional
        joint-mode phase; default the phase consistent with ``x``
        (:meth:`walker.models.WalkerModel.start_phase`).
    """
    return ground_reaction_at("five_link", x, p, phase)


def phase_of(**modes: str) -> int:
    """Phase index from joint modes (``"slip+"``, ``"slip-"``, ``"stick"``; default
    ``"slip+"``), e.g. ``phase_of(knee_stance="stick")``."""
    return fr.code_of(JOINTS, modes)


def modes_of(phase: int) -> dict[str, str]:
    """{joint: mode} of a phase index: the inverse of :func:`phase_of`."""
    return fr.labels_of(phase, JOINTS)


def _tibia_on_ground(z, p):
    """``q_tibia_sw`` that puts the swing foot on the slope behind its knee, and d/dz[:4]."""
    lf, lt, s = p[I_LENGTH_FEMUR], p[I_LENGTH_TIBIA], p[I_SLOPE]
    tst, fst = z[0] - 0.5 * z[1], z[0] + 0.5 * z[1]
    c = (lt * math.cos(tst + s) + lf * math.cos(fst + s) - lf * math.cos(z[3] + s)) / lt
    if not -1.0 < c < 1.0:
        raise ValueError(
            f"`z` must leave the swing foot able to reach the slope, got knee height {c * lt!r}"
        )
    psi = -math.acos(c)
    dc = np.array(
        [
            -(lt * math.sin(tst + s) + lf * math.sin(fst + s)) / lt,
            (0.5 * lt * math.sin(tst + s) - 0.5 * lf * math.sin(fst + s)) / lt,
            0.0,
            lf * math.sin(z[3] + s) / lt,
        ]
    )
    return psi - s, dc / math.sqrt(1.0 - c * c)


def lift(z, p):
    """Section point (``SECTION_NAMES``) -> full state just after heel strike."""
    z = np.asarray(z, dtype=float)
    tib, _ = _tibia_on_ground(z, p)
    return np.array([z[0], z[1], z[2], z[3], tib, *z[4:9], 0.0, 0.0])


def lift_jacobian(z, p):
    z = np.asarray(z, dtype=float)
    _, dtib = _tibia_on_ground(z, p)
    J = np.zeros((N_X, 9))
    for i in range(4):
        J[i, i] = 1.0
    J[4, :4] = dtib
    for i in range(5):
        J[5 + i, 4 + i] = 1.0
    return J


def project(x, p):
    return np.array([x[0], x[1], x[2], x[3], x[5], x[6], x[7], x[8], x[9]])


SEGMENTS = ((0, 1), (1, 2), (2, 3), (3, 4), (2, 5))
SWING_FOOT = 4  # row of the swing foot in points()
