"""The compass gait (Goswami, Thuilot, Espiau 1996) with point or round feet: compiled
phase functions for the hybrid integrator.

State ``x = (q_stance, q_swing, qd_stance, qd_swing)``: absolute leg angles from the vertical,
counterclockwise positive.  One phase, ``swing``.  Guards, in
priority order:

0. ``heel_strike``: height of the swing foot's lowest point above the slope, firing when it
   decreases through zero.  Accepted only with the swing foot ahead of the stance foot (by
   more than ``MIN_STEP`` leg lengths, :mod:`walker.models._common`); the
   mid-stance scuff of the rigid swing leg (foot behind) is therefore ignored by the guard's
   construction.  Reset: floating-base impact as an augmented linear system, then the legs
   swap.  A non-positive normal impulse, or a trailing foot that does not lift off, is
   ``NONPHYSICAL_IMPACT``.
1. ``fall_forward``: the stance leg passes ``FALL_ANGLE`` ahead of the slope normal.
2. ``fall_backward``: the stance leg passes ``FALL_ANGLE`` behind it.
"""

import numpy as np

from walker._generated import indices as ix
from walker.params import MODELS

N_X = len(MODELS["compass"].state_names)
N_IMPULSE = 2
PHASE_NAMES = ("swing",)
GUARD_NAMES = ("heel_strike", "fall_forward", "fall_backward")
DIRECTIONS = np.array([[-1, -1, 1]], dtype=np.int64)
STATE_NAMES = MODELS["compass"].state_names  # the model registry (walker.params)
SECTION_NAMES = ("q_stance", "qd_stance", "qd_swing")
VARIANTS = {
    "plain": (
        "foot_radius",
        "inertia_leg",
        "damping_hip",
        "damping_ankle",
    )
}
"""Compiled structural variants (:mod:`walker.models`, item 7): ``plain`` is the compass gait
of point masses with point feet and no dampers."""

_I_R, _I_SLOPE = ix.COMPASS_P_FOOT_RADIUS, ix.COMPASS_P_SLOPE
_I_LEG_A, _I_LEG_B = ix.COMPASS_P_COM_FROM_FOOT, ix.COMPASS_P_COM_TO_HIP


LIFT_AFFINE = True
"""``lift`` is ``lift(0, p) + lift_jacobian(0, p) z``, each row one term (basin batches,
:meth:`walker.simulation.stride.StrideMap.basin_batch`, rely on it; tests/test_basin.py checks
it)."""


def lift(z, p):
    """Section point ``(q_stance, qd_stance, qd_swing)`` -> full post-impact state."""
    slope = p[_I_SLOPE]
    return np.array([z[0], -2.0 * slope - z[0], z[1], z[2]])


def lift_jacobian(z, p):
    return np.array([[1.0, 0, 0], [-1.0, 0, 0], [0, 1.0, 0], [0, 0, 1.0]])


def project(x, p):
    return np.array([x[0], x[2], x[3]])


SEGMENTS = ((0, 1), (1, 2))
