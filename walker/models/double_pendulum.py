"""The course's double pendulum (planar elbow coordinates): one phase, no events.

State ``x = (q1, q2, qd1, qd2)``: ``q1`` of link 1 from the +x axis, ``q2`` of link 2
relative to link 1.  Used to check the integrator by energy conservation.
"""

import numpy as np
from numba import njit

from walker._generated import double_pendulum as K
from walker.status import EVENT_IGNORE

N_X = 4
N_IMPULSE = 1
PHASE_NAMES = ("free",)
GUARD_NAMES = ("none",)
DIRECTIONS = np.array([[0]], dtype=np.int64)
STATE_NAMES = ("q1", "q2", "qd1", "qd2")
SECTION_NAMES = ()


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
def guards(phase, t, x, p, g):
    g[0] = 1.0


@njit(cache=True, error_model="numpy")
def reset(phase, k, t, x, p, x_new, impulse):
    for i in range(x.shape[0]):
        x_new[i] = x[i]
    return EVENT_IGNORE, phase, 0


@njit(cache=True, error_model="numpy")
def energy(x, p):
    """(kinetic, potential) [J]."""
    return K.kinetic(x[:2], x[2:], p), K.potential(x[:2], p)


def points(x, p):
    """Base, elbow, tip [m]."""
    pts = np.empty((2, 2))
    K.points(np.ascontiguousarray(x[:2], dtype=np.float64), p, pts)
    return np.vstack([np.zeros((1, 2)), pts])


SEGMENTS = ((0, 1), (1, 2))
KERNEL_HASH = K.KERNEL_HASH
