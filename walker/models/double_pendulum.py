"""The course's double pendulum (planar elbow coordinates): one phase, no events.

State ``x = (q1, q2, qd1, qd2)``: ``q1`` of link 1 from the +x axis, ``q2`` of link 2
relative to link 1.  Used to check the integrator by energy conservation.
"""

import numpy as np
from numba import njit

from walker._generated import double_pendulum as K
from walker.models._common import accelerations, lagrange_jacobian
from walker.status import EVENT_IGNORE

N_X = 4
N_IMPULSE = 1
PHASE_NAMES = ("free",)
GUARD_NAMES = ("none",)
DIRECTIONS = np.array([[0]], dtype=np.int64)
STATE_NAMES = ("q1", "q2", "qd1", "qd2")
SECTION_NAMES = ()


@njit(cache=True)
def rhs(phase, t, x, p, dx):
    dx[0] = x[2]
    dx[1] = x[3]
    K.accel(x[:2], x[2:], p, dx[2:])


@njit(cache=True)
def jac(phase, t, x, p, J):
    q = x[:2]
    qd = x[2:]
    D = np.empty((2, 2))
    h = np.empty(2)
    K.mass_matrix(q, p, D)
    K.bias(q, qd, p, h)
    qdd = np.empty(2)
    accelerations(D, h, qdd)
    K.mass_matrix(q, p, D)
    dD = np.empty((2, 2, 2))
    K.dmass(q, p, dD)
    dh_dq = np.empty((2, 2))
    dh_dqd = np.empty((2, 2))
    K.dbias_dq(q, qd, p, dh_dq)
    K.dbias_dqd(q, qd, p, dh_dqd)
    J[:, :] = 0.0
    J[0, 2] = 1.0
    J[1, 3] = 1.0
    lagrange_jacobian(D, dD, dh_dq, dh_dqd, qdd, J, 2, 2, np.array([0, 1]), np.array([2, 3]))


@njit(cache=True)
def guards(phase, t, x, p, g):
    g[0] = 1.0


@njit(cache=True)
def reset(phase, k, t, x, p, x_new, impulse):
    for i in range(x.shape[0]):
        x_new[i] = x[i]
    return EVENT_IGNORE, phase, 0


@njit(cache=True)
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
