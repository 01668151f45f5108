# generated, do not edit: walker kernels for `simplest`
# input hash: sha256:780618c2198beadffb0d97746b9f5afe921c180e70d4079c1175e643c2b74945
# sympy 1.14.0; regenerate with `python scripts/generate_kernels.py`
# argument order:
#   q = [theta, phi]
#   qd = [theta_dot, phi_dot]
#   p = [slope, g, leg_length, damping_ankle]
# kernels:
#   accel(q, qd, p)
#   daccel_dx(q, qd, p)
"""Generated numba kernels for the `simplest` model.

Garcia's simplest walker (limit of the point-mass compass gait).
"""

import math  # noqa: F401

from walker._jit import njit

KERNEL_HASH = "780618c2198beadffb0d97746b9f5afe921c180e70d4079c1175e643c2b74945"
ARGUMENT_ORDER = {'accel': {'q': ('theta', 'phi'), 'qd': ('theta_dot', 'phi_dot'), 'p': ('slope', 'g', 'leg_length', 'damping_ankle')}, 'daccel_dx': {'q': ('theta', 'phi'), 'qd': ('theta_dot', 'phi_dot'), 'p': ('slope', 'g', 'leg_length', 'damping_ankle')}}

@njit(cache=True, error_model="numpy")
def accel(q, qd, p, out):
    """(theta_ddot, phi_ddot), out (2,)."""
    theta = q[0]
    phi = q[1]
    theta_dot = qd[0]
    slope = p[0]
    g = p[1]
    leg_length = p[2]
    damping_ankle = p[3]
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
    x14 = damping_ankle*theta_dot*math.sqrt(g*leg_length)
    x15 = g*x0*x8
    x16 = phi - theta
    x17 = math.sin(x16)
    x18 = x17*x17
    x19 = math.cos(x16)
    x20 = x19*x19
    x21 = 1.0/(x10*x18 + x10*x20 + x11*x18 + x11*x20 + x18*x4 + x18*x7 + x20*x4 + x20*x7)
    x22 = x18*x21
    x23 = x20*x21
    x24 = g*x21
    x25 = g*x13
    x26 = x17*x24
    x27 = x19*x21
    x28 = x27*x5
    x29 = x17*x21
    x30 = x0*x0*x0*x27
    x31 = theta_dot*theta_dot
    x32 = x3*x31
    x33 = x29*x5*x5*x5
    x34 = x31*x9
    x35 = x0*x27*x31
    x36 = x29*x31*x5
    out[0] = g*x0*x12*x8 - g*x12*x13 - x12*x14
    out[1] = -x0*x13*x26 - x0*x14*x29 - x1*x19*x2*x24 + x10*x36 + x11*x35 - x14*x22 - x14*x23 + x14*x28 + x15*x22 + x15*x23 - x15*x28 - x22*x25 - x23*x25 - x26*x6*x8 + x30*x32 + x30*x34 + x32*x33 + x33*x34 + x35*x7 + x36*x4


@njit(cache=True, error_model="numpy")
def daccel_dx(q, qd, p, out):
    """d accel / d x, out (2, 4)."""
    theta = q[0]
    phi = q[1]
    theta_dot = qd[0]
    slope = p[0]
    g = p[1]
    leg_length = p[2]
    damping_ankle = p[3]
    x0 = math.sin(theta)
    x1 = x0*x0
    x2 = math.sin(slope)
    x3 = x2*x2
    x4 = leg_length*x3
    x5 = x1*x4
    x6 = math.cos(theta)
    x7 = x6*x6
    x8 = x4*x7
    x9 = math.cos(slope)
    x10 = x9*x9
    x11 = leg_length*x10
    x12 = x1*x11
    x13 = x11*x7
    x14 = 1.0/(x12 + x13 + x5 + x8)
    x15 = g*x14
    x16 = x0*x2
    x17 = x6*x9
    x18 = damping_ankle*math.sqrt(g*leg_length)
    x19 = phi - theta
    x20 = math.sin(x19)
    x21 = x20*x20
    x22 = math.cos(x19)
    x23 = x22*x22
    x24 = 1.0/(x12*x21 + x12*x23 + x13*x21 + x13*x23 + x21*x5 + x21*x8 + x23*x5 + x23*x8)
    x25 = g*x24
    x26 = x21*x25
    x27 = x23*x25
    x28 = x22*x9
    x29 = x0*x20
    x30 = x25*x7
    x31 = x22*x6
    x32 = x16*x25*x31
    x33 = x18*x24
    x34 = theta_dot*x33
    x35 = x0*x22
    x36 = x20*x6
    x37 = theta_dot*theta_dot
    x38 = x24*x37
    x39 = x0*x0*x0
    x40 = x20*x39
    x41 = x6*x6*x6
    x42 = x29*x38
    x43 = x22*x39
    x44 = 2*theta_dot*x24
    x45 = x4*x44
    x46 = x20*x41
    x47 = x11*x44
    x48 = x35*x44
    x49 = x36*x44
    out[0, 0] = x15*x16 + x15*x17
    out[0, 1] = 0
    out[0, 2] = -x14*x18
    out[0, 3] = 0
    out[1, 0] = x1*x25*x28 + x16*x26 + x16*x27 + x17*x25*x29 + x17*x26 + x17*x27 - x2*x20*x30 - x32
    out[1, 1] = g*x0*x20*x24*x6*x9 + g*x1*x2*x20*x24 + leg_length*x1*x10*x22*x24*x37*x6 + leg_length*x1*x22*x24*x3*x37*x6 + leg_length*x10*x22*x24*x37*x41 + leg_length*x22*x24*x3*x37*x41 - x11*x38*x40 - x13*x42 - x28*x30 - x32 - x34*x35 - x34*x36 - x38*x4*x40 - x42*x8
    out[1, 2] = x12*x49 + x13*x48 - x21*x33 - x23*x33 - x29*x33 + x31*x33 + x43*x45 + x43*x47 + x45*x46 + x46*x47 + x48*x8 + x49*x5
    out[1, 3] = 0
