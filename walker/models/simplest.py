"""Garcia's simplest walking model (Garcia, Chatterjee, Ruina, Coleman 1998): compiled phase
functions for the hybrid integrator.

State ``x = (theta, phi, theta_dot, phi_dot)`` in Garcia's coordinates: ``theta`` is the
stance leg's angle from the slope normal (positive just after heel strike), ``phi`` the swing
leg's angle relative to the stance leg.  The equations are the ``m/M -> 0`` limit of the
point-mass compass gait, derived in :func:`walker.symbolic.models.simplest`.  Parameters:
:class:`walker.params.SimplestParams` ``(slope, g, leg_length, damping_ankle)``.

Stance-ankle damper ``b = damping_ankle`` (dimensionless, in units of ``M l^2 sqrt(g/l)``; 0
in Garcia's model): with ``g = l = 1``

    theta'' = sin(theta - gamma) - b theta',
    phi''   = sin(theta - gamma) - b (1 - cos phi) theta'
              + sin(phi) (theta'^2 - cos(theta - gamma)),

the damper reaching the swing equation only through the hip's acceleration (the limit of
the compass gait's ``damping_ankle``).  Energy per unit hip mass, :func:`energy`:
``E = l^2 theta'^2 / 2 + g l cos(theta - gamma)``, ``dE/dt = -b l^2 sqrt(g/l) theta'^2``.
The massless legs admit no hip damper or friction (see :class:`walker.params.SimplestParams`).

Guards, in priority order:

0. ``heel_strike``: ``phi - 2 theta`` increasing through zero with ``theta < 0``.  Just after
   heel strike ``phi = 2 theta`` exactly and ``phi - 2 theta`` grows; the mid-stance scuff
   (``theta`` near 0) crosses zero *downward*, so the guard's direction alone excludes it and
   the crossing after it arms the guard.  Reset: Garcia's transition
   ``theta+ = -theta-``, ``phi+ = -2 theta-``, ``theta_dot+ = cos(2 theta-) theta_dot-``,
   ``phi_dot+ = cos(2 theta-) (1 - cos(2 theta-)) theta_dot-``.
1. ``fall_forward`` / 2. ``fall_backward``: ``|theta|`` reaches ``FALL_ANGLE``.
"""

import math

import numpy as np

from walker._generated import indices as ix
from walker._generated import simplest as K
from walker._jit import njit
from walker.models._common import FALL_ANGLE, fell
from walker.params import MODELS
from walker.status import EVENT_IGNORE, EVENT_STRIDE

N_X = 4
N_IMPULSE = 1
PHASE_NAMES = ("swing",)
GUARD_NAMES = ("heel_strike", "fall_forward", "fall_backward")
DIRECTIONS = np.array([[1, -1, 1]], dtype=np.int64)
STATE_NAMES = MODELS["simplest"].state_names  # the model registry (walker.params)
SECTION_NAMES = ("theta", "theta_dot")


@njit(cache=True, error_model="numpy")
def rhs(phase, t, x, p, dx):
    a = np.empty(2)
    K.accel(x[:2], x[2:], p, a)
    dx[0] = x[2]
    dx[1] = x[3]
    dx[2] = a[0]
    dx[3] = a[1]


@njit(cache=True, error_model="numpy")
def jac(phase, t, x, p, J):
    J[:, :] = 0.0
    J[0, 2] = 1.0
    J[1, 3] = 1.0
    da = np.empty((2, 4))
    K.daccel_dx(x[:2], x[2:], p, da)
    for j in range(4):
        J[2, j] = da[0, j]
        J[3, j] = da[1, j]


@njit(cache=True, error_model="numpy")
def guards(phase, t, x, p, g):
    g[ix.SIMPLEST_GUARD_HEEL_STRIKE] = x[1] - 2.0 * x[0]
    g[ix.SIMPLEST_GUARD_FALL_FORWARD] = x[0] + FALL_ANGLE
    g[ix.SIMPLEST_GUARD_FALL_BACKWARD] = x[0] - FALL_ANGLE


@njit(cache=True, error_model="numpy")
def reset(phase, k, t, x, p, x_new, impulse):
    for i in range(4):
        x_new[i] = x[i]
    impulse[0] = 0.0
    if k == 0:
        if x[0] >= 0.0:
            return EVENT_IGNORE, phase, 0
        c = math.cos(2.0 * x[0])
        x_new[0] = -x[0]
        x_new[1] = -2.0 * x[0]
        x_new[2] = c * x[2]
        x_new[3] = c * (1.0 - c) * x[2]
        return EVENT_STRIDE, 0, 0
    return fell(phase, k == 1)


@njit(cache=True, error_model="numpy")
def energy(x, p):
    """(kinetic, potential) per unit hip mass [J/kg] (the feet carry no energy in the
    limit); potential zero at the stance foot."""
    slope, g, l = p[ix.SIMPLEST_P_SLOPE], p[ix.SIMPLEST_P_G], p[ix.SIMPLEST_P_LEG_LENGTH]
    kinetic = 0.5 * l * l * x[2] * x[2]
    potential = g * l * math.cos(x[0] - slope)
    return kinetic, potential


def lift(z, p):
    """Section point ``(theta, theta_dot)`` -> full state just after heel strike."""
    return np.array([z[0], 2.0 * z[0], z[1], (1.0 - math.cos(2.0 * z[0])) * z[1]])


def lift_jacobian(z, p):
    s2 = math.sin(2.0 * z[0])
    return np.array([[1.0, 0], [2.0, 0], [0, 1.0], [2.0 * s2 * z[1], 1.0 - math.cos(2.0 * z[0])]])


def project(x, p):
    return np.array([x[0], x[2]])


def points(x, p):
    """Stance foot, hip, swing foot in the world frame [m]."""
    slope, l = p[ix.SIMPLEST_P_SLOPE], p[ix.SIMPLEST_P_LEG_LENGTH]
    s = np.array([math.cos(slope), -math.sin(slope)])
    n = np.array([math.sin(slope), math.cos(slope)])
    hip = l * (-math.sin(x[0]) * s + math.cos(x[0]) * n)
    a = x[0] - x[1]
    foot = hip - l * (-math.sin(a) * s + math.cos(a) * n)
    return np.array([[0.0, 0.0], hip, foot])


SEGMENTS = ((0, 1), (1, 2))
KERNEL_HASH = K.KERNEL_HASH
