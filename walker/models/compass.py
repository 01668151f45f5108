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

import math

import numpy as np

from walker._generated import compass as K
from walker._generated import indices as ix
from walker._jit import njit
from walker.models._common import (
    FALL_ANGLE,
    LINEAR_SOLVE_FAILED,
    fell,
    floating_base_heel_strike,
    passive_impact_status,
    relabel,
    touchdown,
)
from walker.params import MODELS

N_X = 4
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


@njit(cache=True, error_model="numpy")
def rhs(phase, t, x, p, dx):
    dx[0] = x[2]
    dx[1] = x[3]
    K.accel(x[:2], x[2:], p, dx[2:])


@njit(cache=True, error_model="numpy")
def jac(phase, t, x, p, J):
    J[:, :] = 0.0
    J[0, 2] = 1.0
    J[1, 3] = 1.0
    K.accel_jac(x[:2], x[2:], p, J[2:, :])


@njit(cache=True, error_model="numpy")
def swing_foot(x, p):
    """(height above the slope, distance ahead of the stance foot along the slope) [m]."""
    L = p[_I_LEG_A] + p[_I_LEG_B]
    R = p[_I_R]
    slope = p[_I_SLOPE]
    psi1 = x[0] + slope
    psi2 = x[1] + slope
    return (L - R) * (math.cos(psi1) - math.cos(psi2)), (L - R) * (math.sin(psi2) - math.sin(psi1))


@njit(cache=True, error_model="numpy")
def guards(phase, t, x, p, g):
    psi1 = x[0] + p[_I_SLOPE]
    g[ix.COMPASS_GUARD_HEEL_STRIKE] = swing_foot(x, p)[0]
    g[ix.COMPASS_GUARD_FALL_FORWARD] = psi1 + FALL_ANGLE
    g[ix.COMPASS_GUARD_FALL_BACKWARD] = psi1 - FALL_ANGLE


@njit(cache=True, error_model="numpy")
def heel_strike(x, p, x_new, impulse):
    """Floating-base heel-strike impact and leg swap.

    Returns a Status value: COMPLETED for a physical impact.  ``impulse`` receives the
    impulse on the new stance foot (along the slope, normal to it) [N s].
    """
    qdf_plus = np.empty(4)
    ok, lift = floating_base_heel_strike(
        K.points,
        K.hip_jac,
        K.ext_mass_matrix,
        K.ext_swing_contact_jac,
        K.ext_stance_contact_jac,
        x[:2],
        x[2:],
        p,
        4,
        1,
        p[_I_SLOPE],
        qdf_plus,
        impulse,
    )
    if not ok:
        return LINEAR_SOLVE_FAILED
    relabel(x, qdf_plus, (1, 0), x_new)  # the legs swap
    return passive_impact_status(impulse, lift)


@njit(cache=True, error_model="numpy")
def reset(phase, k, t, x, p, x_new, impulse):
    for i in range(x.shape[0]):
        x_new[i] = x[i]
    if k == 0:
        leg_length = p[_I_LEG_A] + p[_I_LEG_B]
        return touchdown(swing_foot, heel_strike, leg_length, phase, x, p, x_new, impulse)
    return fell(phase, k == 1)


@njit(cache=True, error_model="numpy")
def energy(x, p):
    """(kinetic, potential) [J]; potential is zero with the stance contact at height 0."""
    return K.kinetic(x[:2], x[2:], p), K.potential(x[:2], p)


LIFT_AFFINE = True
"""``lift`` is ``lift(0, p) + lift_jacobian(0, p) z``, each row one term (basin batches,
:meth:`walker.stride.StrideMap.basin_batch`, rely on it; tests/test_basin.py checks it)."""


def lift(z, p):
    """Section point ``(q_stance, qd_stance, qd_swing)`` -> full post-impact state."""
    slope = p[_I_SLOPE]
    return np.array([z[0], -2.0 * slope - z[0], z[1], z[2]])


def lift_jacobian(z, p):
    return np.array([[1.0, 0, 0], [-1.0, 0, 0], [0, 1.0, 0], [0, 0, 1.0]])


def project(x, p):
    return np.array([x[0], x[2], x[3]])


def points(x, p):
    """Joint positions for drawing: rows stance contact, hip, swing contact [m]."""
    pts = np.empty((4, 2))
    K.points(np.ascontiguousarray(x[:2], dtype=np.float64), p, pts)
    return pts[[0, 1, 3]]


SEGMENTS = ((0, 1), (1, 2))
KERNEL_HASH = K.KERNEL_HASH
