# generated, do not edit: walker kernels for `simplest`
# input hash: sha256:6ee81a4da4603dc8a6610c3e1f29ec80050d70766c34b88c188bb63c8dd6ee2e
# sympy 1.14.0; regenerate with `python scripts/generate_kernels.py`
# argument order:
#   q = [theta, phi]
#   qd = [theta_dot, phi_dot]
#   p = [slope, g, leg_length]
# kernels:
#   accel(q, qd, p)
#   daccel_dx(q, qd, p)
"""Generated numba kernels for the `simplest` model.

Garcia's simplest walker (limit of the point-mass compass gait).
"""

import math  # noqa: F401

from numba import njit

KERNEL_HASH = "6ee81a4da4603dc8a6610c3e1f29ec80050d70766c34b88c188bb63c8dd6ee2e"
ARGUMENT_ORDER = {'accel': {'q': ('theta', 'phi'), 'qd': ('theta_dot', 'phi_dot'), 'p': ('slope', 'g', 'leg_length')}, 'daccel_dx': {'q': ('theta', 'phi'), 'qd': ('theta_dot', 'phi_dot'), 'p': ('slope', 'g', 'leg_length')}}

@njit(cache=True, error_model="numpy")
def accel(q, qd, p, out):
    """(theta_ddot, phi_ddot), out (2,)."""
    theta = q[0]
    phi = q[1]
    theta_dot = qd[0]
    slope = p[0]
    g = p[1]
    leg_length = p[2]
    x0 = math.sin(theta)
    x1 = x0*x0
    x2 = math.sin(slope)
    x3 = leg_length*x2*x2
    x4 = x1*x3
    x5 = math.cos(theta)
    x6 = x5*x5
    x7 = x3*x6
    x8 = math.cos(slope)
    x9 = leg_length*x8*x8
    x10 = x1*x9
    x11 = x6*x9
    x12 = 1.0/(x10 + x11 + x4 + x7)
    x13 = x2*x5
    x14 = phi - theta
    x15 = math.sin(x14)
    x16 = x15*x15
    x17 = math.cos(x14)
    x18 = x17*x17
    x19 = 1.0/(x10*x16 + x10*x18 + x11*x16 + x11*x18 + x16*x4 + x16*x7 + x18*x4 + x18*x7)
    x20 = g*x19
    x21 = x0*x20*x8
    x22 = x13*x20
    x23 = x15*x20
    x24 = x0*x0*x0*x17
    x25 = theta_dot*theta_dot*x19
    x26 = x25*x3
    x27 = x15*x5*x5*x5
    x28 = x25*x9
    x29 = x0*x17*x25
    x30 = x15*x25*x5
    out[0] = g*x0*x12*x8 - g*x12*x13
    out[1] = -x0*x13*x23 - x1*x17*x2*x20 + x10*x30 + x11*x29 + x16*x21 - x16*x22 - x17*x21*x5 + x18*x21 - x18*x22 - x23*x6*x8 + x24*x26 + x24*x28 + x26*x27 + x27*x28 + x29*x7 + x30*x4


@njit(cache=True, error_model="numpy")
def daccel_dx(q, qd, p, out):
    """d accel / d x, out (2, 4)."""
    theta = q[0]
    phi = q[1]
    theta_dot = qd[0]
    slope = p[0]
    g = p[1]
    leg_length = p[2]
    x0 = math.sin(theta)
    x1 = x0*x0
    x2 = math.sin(slope)
    x3 = leg_length*x2*x2
    x4 = x1*x3
    x5 = math.cos(theta)
    x6 = x5*x5
    x7 = x3*x6
    x8 = math.cos(slope)
    x9 = leg_length*x8*x8
    x10 = x1*x9
    x11 = x6*x9
    x12 = g/(x10 + x11 + x4 + x7)
    x13 = x0*x2
    x14 = x5*x8
    x15 = phi - theta
    x16 = math.cos(x15)
    x17 = x16*x16
    x18 = math.sin(x15)
    x19 = x18*x18
    x20 = 1.0/(x10*x17 + x10*x19 + x11*x17 + x11*x19 + x17*x4 + x17*x7 + x19*x4 + x19*x7)
    x21 = g*x20
    x22 = x17*x21
    x23 = x1*x21
    x24 = x16*x8
    x25 = x19*x21
    x26 = x18*x2
    x27 = x21*x6
    x28 = x0*x18
    x29 = x16*x5
    x30 = -x13*x21*x29 + x14*x21*x28
    x31 = theta_dot*theta_dot*x20
    x32 = x31*x9
    x33 = x5*x5*x5
    x34 = x16*x33
    x35 = x3*x31
    x36 = x0*x0*x0
    x37 = x18*x36
    x38 = x29*x31
    x39 = x28*x31
    x40 = x16*x36
    x41 = 2*theta_dot*x20
    x42 = x3*x41
    x43 = x18*x33
    x44 = x41*x9
    x45 = x0*x16*x41
    x46 = x18*x41*x5
    out[0, 0] = x12*x13 + x12*x14
    out[0, 1] = 0
    out[0, 2] = 0
    out[0, 3] = 0
    out[1, 0] = x13*x22 + x13*x25 + x14*x22 + x14*x25 + x23*x24 - x26*x27 + x30
    out[1, 1] = x10*x38 - x11*x39 + x23*x26 - x24*x27 + x30 + x32*x34 - x32*x37 + x34*x35 - x35*x37 + x38*x4 - x39*x7
    out[1, 2] = x10*x46 + x11*x45 + x4*x46 + x40*x42 + x40*x44 + x42*x43 + x43*x44 + x45*x7
    out[1, 3] = 0
