"""The rimless wheel (McGeer 1990; Coleman, Chatterjee, Ruina 1997): a wheel without a rim,
``n`` spokes of length ``l`` rolling down a slope from spoke to spoke.

The classical planar model: all the mass is a point mass at the hub, the spokes are
massless, a foot that strikes the ground sticks (a plastic impact) and does not slip.
Energies are per unit hub mass [J/kg] and impulses per unit hub mass [m/s]; the motion does
not depend on the mass.  Parameters: :class:`walker.params.RimlessWheelParams`
``(spokes, leg_length, g, slope)``, ``alpha = pi / spokes`` the half-angle between spokes.

This is the first model written in C only: the phase functions, energy, drawing points and
start phase are in ``walker/_core/model_rimless_wheel.c`` ; this module holds
the description and the section maps.

State and convention
--------------------
``x = (theta, theta_dot)``: ``theta`` is the stance spoke's angle from the slope normal,
counterclockwise positive (walker's convention, as Garcia's ``theta`` in
:mod:`walker.models.simplest`), the hub at ``l (-sin theta, cos theta)`` from the stance foot
in the slope frame (downhill, normal).  A wheel rolling downhill turns clockwise: ``theta``
decreases from ``+alpha`` just after an impact to ``-alpha`` at the next, and
``theta_dot < 0``.  The stance dynamics is the inverted pendulum

    theta'' = (g / l) sin(theta - gamma),

whose energy ``E = l^2 theta'^2 / 2 + g l cos(theta - gamma)`` (potential zero at the stance
foot) is conserved between impacts.

Phases
------
0. ``rolling``: pivoting on the stance spoke, ``-alpha <= theta <= alpha``.
1. ``standing``: at rest on two spokes (``theta = alpha``, ``theta_dot = 0``), gravity
   pressing the wheel onto both feet: the vector field is zero, so the standing wheel is an
   equilibrium of the hybrid system and a run from it ends ``NO_EVENT`` at ``t_max``.  It
   exists for ``|gamma| < alpha`` (the hub above the segment between the two feet).
   ``start_phase`` returns it for a state exactly at rest on two spokes
   (``theta_dot == 0``, ``|theta| == alpha``) on such a slope.

Guards (rolling; constant 1.0 while standing)
---------------------------------------------
0. ``impact``: ``theta + alpha`` decreasing through zero -- the leading spoke strikes.  For
   the impact map take angular momentum about the new contact point: the impulse acts
   there (gravity is finite, the trailing foot leaves the ground), so the hub's momentum
   about it is conserved.  Just before, the hub velocity ``l theta_dot-`` is perpendicular
   to the old spoke, which makes the angle ``2 alpha`` with the new one; only its component
   perpendicular to the new spoke, ``l theta_dot- cos(2 alpha)``, has a moment arm ``l``.
   So ``m l^2 theta_dot+ = m l^2 theta_dot- cos(2 alpha)``:

       theta+ = alpha,   theta_dot+ = cos(2 alpha) theta_dot-,

   a loss of kinetic energy ``sin^2(2 alpha)`` times the kinetic energy before.  A stride.
   The old foot leaves the ground only while ``cos(2 alpha) > 0`` (5 spokes or more); with 3
   or 4 spokes it would have to move into the ground, both feet stay down and the wheel
   stops: it then stands (``|gamma| < alpha``), tips forward from rest (``gamma >= alpha``,
   still a stride) or tips back over the trailing spoke (``FELL_BACKWARD``).
1. ``back_impact``: ``theta - alpha`` increasing through zero -- a wheel that could not
   get over the top (``theta = gamma``) rolled back onto its trailing spoke, which strikes
   with the same impact map about that foot.  Then, with ``w = cos(2 alpha) theta_dot-``
   (0 for 3 or 4 spokes):

   * it rolls back over the trailing spoke (``w^2 >= 2 (g/l) (1 - cos(alpha + gamma))``, or
     ``gamma <= -alpha``): ``FELL_BACKWARD``;
   * else it rocks between the two spokes, every impact scaling the rate by
     ``cos(2 alpha)``, and comes to rest (a Zeno sequence: infinitely many impacts in a
     finite time) unless the first swing forward gets it over the leading spoke's top
     (``cos^2(2 alpha) w^2 >= 2 (g/l) (1 - cos(alpha - gamma))``) or it cannot stand
     (``gamma >= alpha``).  The rocking is not integrated: the wheel is put at rest on
     both spokes at once, ``standing`` (the rocking's finite duration is not added to the
     time);
   * otherwise it swings on the trailing spoke, which becomes the stance spoke:
     ``theta+ = -alpha``, ``theta_dot+ = w`` (not a stride).

   A wheel started on the slope's section (just after an impact, rolling forward) that
   comes back has too little energy to pass either top, so below the critical slope it
   ends standing; it can fall backward only uphill (``gamma < 0``).
2. ``impact_late`` / 3. ``back_impact_late``: the same boundaries ``2 GUARD_TOL`` (2e-10
   rad) beyond, with the resets of 0 and 1.  The integrator arms a guard only once it has
   seen it beyond ``GUARD_TOL`` on its pre-fire side, so a run that starts exactly on a
   boundary and never moves away from it (from rest, or moving out of the interval) would
   pass guards 0 and 1 unseen; these catch it.

Impulse: ``v+ - v-``, the hub's velocity change (the ground's impulse per unit hub mass)
[m/s] in the slope frame (along the slope downhill, along the normal); zero for a fall.

Poincare section: just after an impact, ``theta = alpha``; its one coordinate is the rate
``theta_dot`` (1-D section, :data:`SECTION_NAMES`).  The rolling gait is the fixed point
``theta_dot* = -cot(2 alpha) sqrt(4 (g/l) sin(alpha) sin(gamma))`` with the multiplier
``cos^2(2 alpha)`` (derived in tests/test_rimless_wheel.py); it exists above the critical
slope where it gets over the top, ``theta_dot*^2 > 2 (g/l) (1 - cos(alpha - gamma))``.

References
----------
.. [1] T. McGeer, "Passive dynamic walking", Int. J. Robotics Research 9(2):62-82, 1990.
.. [2] M. J. Coleman, A. Chatterjee, A. Ruina, "Motions of a rimless spoked wheel: a simple
   three-dimensional system with impacts", Dynamics and Stability of Systems 12(3):139-159,
   1997 (the planar analysis: rolling and standing solutions, their stability).
"""

import hashlib
import math

import numpy as np

from walker._generated import indices as ix
from walker.params import MODELS

__all__ = [
    "N_X",
    "N_Q",
    "N_IMPULSE",
    "PHASE_NAMES",
    "GUARD_NAMES",
    "DIRECTIONS",
    "STATE_NAMES",
    "SECTION_NAMES",
    "SEGMENTS",
    "SWING_FOOT",
    "KERNEL_HASH",
    "half_angle",
    "lift",
    "lift_jacobian",
    "project",
]

N_X = len(MODELS["rimless_wheel"].state_names)
N_Q = 1
N_IMPULSE = 2
PHASE_NAMES = ("rolling", "standing")
GUARD_NAMES = ("impact", "back_impact", "impact_late", "back_impact_late")
DIRECTIONS = np.array([[-1, 1, -1, 1], [-1, 1, -1, 1]], dtype=np.int64)
STATE_NAMES = MODELS["rimless_wheel"].state_names  # the model registry (walker.params)
SECTION_NAMES = ("theta_dot",)

SEGMENTS = ((0, 1), (1, 2), (1, 3))
"""Drawing (``points``: stance foot, hub, leading foot, trailing foot): the stance spoke and
its two neighbours, the spokes that strike next rolling forward or back."""
SWING_FOOT = 2
"""Index of the leading spoke's foot in ``points``: the next stance foot."""

_SPEC = (
    "rimless_wheel 1: x = (theta, theta_dot), p = (spokes, leg_length, g, slope), "
    "a = pi/spokes; rolling theta'' = g/l sin(theta - slope); standing at rest; "
    "impact theta+ = a, theta_dot+ = cos(2a) theta_dot- (stop if cos(2a) <= 0); "
    "back impact: fall, rest or back step; late guards 2e-10 beyond"
)
KERNEL_HASH = hashlib.sha256(_SPEC.encode()).hexdigest()
"""Fingerprint of the model's equations (walker/_core/model_rimless_wheel.c, written by
hand: no generated kernels); bump the version in ``_SPEC`` when they change."""


def half_angle(p) -> float:
    """``alpha = pi / spokes`` [rad], the half-angle between spokes (``p[0]`` is spokes)."""
    return math.pi / float(p[ix.RIMLESS_WHEEL_P_SPOKES])


LIFT_AFFINE = True
"""``lift`` is ``lift(0, p) + lift_jacobian(0, p) z``, each row one term (basin batches,
:meth:`walker.simulation.stride.StrideMap.basin_batch`, rely on it; tests/test_basin.py checks
it)."""


def lift(z, p):
    """Section point ``(theta_dot,)`` -> full state just after an impact ``(alpha,
    theta_dot)``."""
    return np.array([half_angle(p), float(z[0])])


def lift_jacobian(z, p):
    return np.array([[0.0], [1.0]])


def project(x, p):
    return np.array([x[1]])
