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

from walker.params import MODELS

N_X = len(MODELS["simplest"].state_names)
N_IMPULSE = 1
PHASE_NAMES = ("swing",)
GUARD_NAMES = ("heel_strike", "fall_forward", "fall_backward")
DIRECTIONS = np.array([[1, -1, 1]], dtype=np.int64)
STATE_NAMES = MODELS["simplest"].state_names  # the model registry (walker.params)
SECTION_NAMES = ("theta", "theta_dot")


def lift(z, p):
    """Section point ``(theta, theta_dot)`` -> full state just after heel strike."""
    return np.array([z[0], 2.0 * z[0], z[1], (1.0 - math.cos(2.0 * z[0])) * z[1]])


def lift_jacobian(z, p):
    s2 = math.sin(2.0 * z[0])
    return np.array([[1.0, 0], [2.0, 0], [0, 1.0], [2.0 * s2 * z[1], 1.0 - math.cos(2.0 * z[0])]])


def project(x, p):
    return np.array([x[0], x[2]])


SEGMENTS = ((0, 1), (1, 2))
