# generated, do not edit: walker kernels for `double_pendulum`
# input hash: sha256:8bc88c67611405c10247b2a55fecc1cee0746fdd047d2b9edfb4a31f594b5604
# sympy 1.14.0; regenerate with `python scripts/generate_kernels.py`
# argument order:
#   q = [q1, q2]
#   qd = [q1_dot, q2_dot]
#   p = [mass_1, mass_2, inertia_1, inertia_2, length_1, length_2, com_1, com_2, g, damping_1, damping_2, coulomb_1, coulomb_2]
# kernels:
#   accel(q, qd, p)
#   accel_jac(q, qd, p)
#   mass_matrix(q, p)
#   coriolis(q, qd, p)
#   gravity(q, p)
#   bias(q, qd, p)
#   forcing(q, qd, p)
#   dmass(q, p)
#   dbias_dq(q, qd, p)
#   dbias_dqd(q, qd, p)
#   kinetic(q, qd, p)
#   potential(q, p)
#   points(q, p)
"""Generated numba kernels for the `double_pendulum` model.

The planar double pendulum (elbow-manipulator coordinates).
"""

import math  # noqa: F401

from walker._jit import njit

KERNEL_HASH = "8bc88c67611405c10247b2a55fecc1cee0746fdd047d2b9edfb4a31f594b5604"
ARGUMENT_ORDER = {'accel': {'q': ('q1', 'q2'), 'qd': ('q1_dot', 'q2_dot'), 'p': ('mass_1', 'mass_2', 'inertia_1', 'inertia_2', 'length_1', 'length_2', 'com_1', 'com_2', 'g', 'damping_1', 'damping_2', 'coulomb_1', 'coulomb_2')}, 'accel_jac': {'q': ('q1', 'q2'), 'qd': ('q1_dot', 'q2_dot'), 'p': ('mass_1', 'mass_2', 'inertia_1', 'inertia_2', 'length_1', 'length_2', 'com_1', 'com_2', 'g', 'damping_1', 'damping_2', 'coulomb_1', 'coulomb_2')}, 'mass_matrix': {'q': ('q1', 'q2'), 'p': ('mass_1', 'mass_2', 'inertia_1', 'inertia_2', 'length_1', 'length_2', 'com_1', 'com_2', 'g', 'damping_1', 'damping_2', 'coulomb_1', 'coulomb_2')}, 'coriolis': {'q': ('q1', 'q2'), 'qd': ('q1_dot', 'q2_dot'), 'p': ('mass_1', 'mass_2', 'inertia_1', 'inertia_2', 'length_1', 'length_2', 'com_1', 'com_2', 'g', 'damping_1', 'damping_2', 'coulomb_1', 'coulomb_2')}, 'gravity': {'q': ('q1', 'q2'), 'p': ('mass_1', 'mass_2', 'inertia_1', 'inertia_2', 'length_1', 'length_2', 'com_1', 'com_2', 'g', 'damping_1', 'damping_2', 'coulomb_1', 'coulomb_2')}, 'bias': {'q': ('q1', 'q2'), 'qd': ('q1_dot', 'q2_dot'), 'p': ('mass_1', 'mass_2', 'inertia_1', 'inertia_2', 'length_1', 'length_2', 'com_1', 'com_2', 'g', 'damping_1', 'damping_2', 'coulomb_1', 'coulomb_2')}, 'forcing': {'q': ('q1', 'q2'), 'qd': ('q1_dot', 'q2_dot'), 'p': ('mass_1', 'mass_2', 'inertia_1', 'inertia_2', 'length_1', 'length_2', 'com_1', 'com_2', 'g', 'damping_1', 'damping_2', 'coulomb_1', 'coulomb_2')}, 'dmass': {'q': ('q1', 'q2'), 'p': ('mass_1', 'mass_2', 'inertia_1', 'inertia_2', 'length_1', 'length_2', 'com_1', 'com_2', 'g', 'damping_1', 'damping_2', 'coulomb_1', 'coulomb_2')}, 'dbias_dq': {'q': ('q1', 'q2'), 'qd': ('q1_dot', 'q2_dot'), 'p': ('mass_1', 'mass_2', 'inertia_1', 'inertia_2', 'length_1', 'length_2', 'com_1', 'com_2', 'g', 'damping_1', 'damping_2', 'coulomb_1', 'coulomb_2')}, 'dbias_dqd': {'q': ('q1', 'q2'), 'qd': ('q1_dot', 'q2_dot'), 'p': ('mass_1', 'mass_2', 'inertia_1', 'inertia_2', 'length_1', 'length_2', 'com_1', 'com_2', 'g', 'damping_1', 'damping_2', 'coulomb_1', 'coulomb_2')}, 'kinetic': {'q': ('q1', 'q2'), 'qd': ('q1_dot', 'q2_dot'), 'p': ('mass_1', 'mass_2', 'inertia_1', 'inertia_2', 'length_1', 'length_2', 'com_1', 'com_2', 'g', 'damping_1', 'damping_2', 'coulomb_1', 'coulomb_2')}, 'potential': {'q': ('q1', 'q2'), 'p': ('mass_1', 'mass_2', 'inertia_1', 'inertia_2', 'length_1', 'length_2', 'com_1', 'com_2', 'g', 'damping_1', 'damping_2', 'coulomb_1', 'coulomb_2')}, 'points': {'q': ('q1', 'q2'), 'p': ('mass_1', 'mass_2', 'inertia_1', 'inertia_2', 'length_1', 'length_2', 'com_1', 'com_2', 'g', 'damping_1', 'damping_2', 'coulomb_1', 'coulomb_2')}}

@njit(cache=True, error_model="numpy")
def accel(q, qd, p, out):
    """Accelerations qdd = -D^-1 (h - Q), Q the joint-damping forcing, by unrolled Cholesky, out (>= n,)."""
    q1 = q[0]
    q2 = q[1]
    q1_dot = qd[0]
    q2_dot = qd[1]
    mass_1 = p[0]
    mass_2 = p[1]
    inertia_1 = p[2]
    inertia_2 = p[3]
    length_1 = p[4]
    com_1 = p[6]
    com_2 = p[7]
    g = p[8]
    damping_1 = p[9]
    damping_2 = p[10]
    x0 = math.cos(q1)
    x1 = x0*x0
    x2 = com_1*com_1*mass_1
    x3 = math.sin(q1)
    x4 = x3*x3
    x5 = length_1*length_1*mass_2
    x6 = length_1*x0
    x7 = q1 + q2
    x8 = math.cos(x7)
    x9 = com_2*x8
    x10 = mass_2*x9
    x11 = x10*x6
    x12 = length_1*x3
    x13 = math.sin(x7)
    x14 = com_2*mass_2*x13
    x15 = x12*x14
    x16 = com_2*com_2*mass_2
    x17 = inertia_2 + x13*x13*x16 + x16*x8*x8
    x18 = g*mass_2
    x19 = x10*x12 - x14*x6
    x20 = q1_dot*x19
    d00 = inertia_1 + x1*x2 + x1*x5 + 2*x11 + 2*x15 + x17 + x2*x4 + x4*x5
    d10 = x11 + x15 + x17
    d11 = x17
    h0 = com_1*g*mass_1*x0 + damping_1*q1_dot + q2_dot*x20 + q2_dot*(q2_dot*x19 + x20) + x18*(x6 + x9)
    h1 = damping_2*q2_dot - q1_dot*q1_dot*x19 + x18*x9
    l00 = math.sqrt(d00)
    l10 = (d10)/l00
    l11 = math.sqrt(d11 - l10*l10)
    z0_y = (-h0)/l00
    z1_y = (-h1 - l10*z0_y)/l11
    z1 = (z1_y)/l11
    z0 = (z0_y - l10*z1)/l00
    out[0] = z0
    out[1] = z1


@njit(cache=True, error_model="numpy")
def accel_jac(q, qd, p, out):
    """d qdd / d (q, qd), out (n, 2n), fused with the Cholesky solve."""
    q1 = q[0]
    q2 = q[1]
    q1_dot = qd[0]
    q2_dot = qd[1]
    mass_1 = p[0]
    mass_2 = p[1]
    inertia_1 = p[2]
    inertia_2 = p[3]
    length_1 = p[4]
    com_1 = p[6]
    com_2 = p[7]
    g = p[8]
    damping_1 = p[9]
    damping_2 = p[10]
    x0 = math.cos(q1)
    x1 = x0*x0
    x2 = com_1*com_1*mass_1
    x3 = math.sin(q1)
    x4 = x3*x3
    x5 = length_1*length_1*mass_2
    x6 = length_1*x0
    x7 = q1 + q2
    x8 = math.cos(x7)
    x9 = com_2*x8
    x10 = mass_2*x9
    x11 = x10*x6
    x12 = length_1*x3
    x13 = math.sin(x7)
    x14 = com_2*x13
    x15 = mass_2*x14
    x16 = x12*x15
    x17 = com_2*com_2*mass_2
    x18 = inertia_2 + x13*x13*x17 + x17*x8*x8
    x19 = x11 + x16
    x20 = com_1*g*mass_1
    x21 = g*mass_2
    x22 = x10*x12
    x23 = x15*x6
    x24 = x22 - x23
    x25 = q1_dot*x24
    x26 = q2_dot*x24
    x27 = q1_dot*q1_dot
    x28 = -x24
    x29 = 2*x26
    x30 = x14*x21
    x31 = -x30
    x32 = -x19
    x33 = q1_dot*x32
    d00 = inertia_1 + x1*x2 + x1*x5 + 2*x11 + 2*x16 + x18 + x2*x4 + x4*x5
    d10 = x18 + x19
    d11 = x18
    h0 = damping_1*q1_dot + q2_dot*x25 + q2_dot*(x25 + x26) + x0*x20 + x21*(x6 + x9)
    h1 = damping_2*q2_dot + x21*x9 + x27*x28
    dD0_00 = 0
    dD0_10 = 0
    dD0_11 = 0
    dD1_00 = 2*x22 - 2*x23
    dD1_10 = x24
    dD1_11 = 0
    hq0_0 = g*mass_2*(-x12 - x14) - x20*x3
    hv0_0 = damping_1 + x29
    hq1_0 = x31
    hv1_0 = 2*q1_dot*x28
    hq0_1 = q2_dot*x33 + q2_dot*(q2_dot*x32 + x33) + x31
    hv0_1 = 2*x25 + x29
    hq1_1 = x19*x27 - x30
    hv1_1 = damping_2
    l00 = math.sqrt(d00)
    l10 = (d10)/l00
    l11 = math.sqrt(d11 - l10*l10)
    a0_y = (-h0)/l00
    a1_y = (-h1 - l10*a0_y)/l11
    a1 = (a1_y)/l11
    a0 = (a0_y - l10*a1)/l00
    jq0_0_y = (-(hq0_0 + dD0_00*a0 + dD0_10*a1))/l00
    jq1_0_y = (-(hq1_0 + dD0_10*a0 + dD0_11*a1) - l10*jq0_0_y)/l11
    jq1_0 = (jq1_0_y)/l11
    jq0_0 = (jq0_0_y - l10*jq1_0)/l00
    jv0_0_y = (-hv0_0)/l00
    jv1_0_y = (-hv1_0 - l10*jv0_0_y)/l11
    jv1_0 = (jv1_0_y)/l11
    jv0_0 = (jv0_0_y - l10*jv1_0)/l00
    jq0_1_y = (-(hq0_1 + dD1_00*a0 + dD1_10*a1))/l00
    jq1_1_y = (-(hq1_1 + dD1_10*a0 + dD1_11*a1) - l10*jq0_1_y)/l11
    jq1_1 = (jq1_1_y)/l11
    jq0_1 = (jq0_1_y - l10*jq1_1)/l00
    jv0_1_y = (-hv0_1)/l00
    jv1_1_y = (-hv1_1 - l10*jv0_1_y)/l11
    jv1_1 = (jv1_1_y)/l11
    jv0_1 = (jv0_1_y - l10*jv1_1)/l00
    out[0, 0] = jq0_0
    out[0, 2] = jv0_0
    out[0, 1] = jq0_1
    out[0, 3] = jv0_1
    out[1, 0] = jq1_0
    out[1, 2] = jv1_0
    out[1, 1] = jq1_1
    out[1, 3] = jv1_1


@njit(cache=True, error_model="numpy")
def mass_matrix(q, p, out):
    """Mass matrix D(q), out (n, n)."""
    q1 = q[0]
    q2 = q[1]
    mass_1 = p[0]
    mass_2 = p[1]
    inertia_1 = p[2]
    inertia_2 = p[3]
    length_1 = p[4]
    com_1 = p[6]
    com_2 = p[7]
    x0 = math.cos(q1)
    x1 = x0*x0
    x2 = com_1*com_1*mass_1
    x3 = math.sin(q1)
    x4 = x3*x3
    x5 = length_1*length_1*mass_2
    x6 = q1 + q2
    x7 = math.cos(x6)
    x8 = com_2*length_1*mass_2
    x9 = x0*x7*x8
    x10 = math.sin(x6)
    x11 = x10*x3*x8
    x12 = com_2*com_2*mass_2
    x13 = inertia_2 + x10*x10*x12 + x12*x7*x7
    x14 = x11 + x13 + x9
    out[0, 0] = inertia_1 + x1*x2 + x1*x5 + 2*x11 + x13 + x2*x4 + x4*x5 + 2*x9
    out[0, 1] = x14
    out[1, 0] = x14
    out[1, 1] = x13


@njit(cache=True, error_model="numpy")
def coriolis(q, qd, p, out):
    """Coriolis matrix C(q, qd), out (n, n)."""
    q1 = q[0]
    q2 = q[1]
    q1_dot = qd[0]
    q2_dot = qd[1]
    mass_2 = p[1]
    length_1 = p[4]
    com_2 = p[7]
    x0 = q1 + q2
    x1 = com_2*length_1*mass_2
    x2 = x1*math.sin(q1)*math.cos(x0) - x1*math.sin(x0)*math.cos(q1)
    x3 = q2_dot*x2
    out[0, 0] = x3
    out[0, 1] = q1_dot*x2 + x3
    out[1, 0] = -q1_dot*x2
    out[1, 1] = 0


@njit(cache=True, error_model="numpy")
def gravity(q, p, out):
    """Gravity vector g(q) = dP/dq, out (n,)."""
    q1 = q[0]
    q2 = q[1]
    mass_1 = p[0]
    mass_2 = p[1]
    length_1 = p[4]
    com_1 = p[6]
    com_2 = p[7]
    g = p[8]
    x0 = math.cos(q1)
    x1 = com_2*math.cos(q1 + q2)
    x2 = g*mass_2
    out[0] = com_1*g*mass_1*x0 + x2*(length_1*x0 + x1)
    out[1] = x1*x2


@njit(cache=True, error_model="numpy")
def bias(q, qd, p, out):
    """h(q, qd) = C(q, qd) qd + g(q), out (n,)."""
    q1 = q[0]
    q2 = q[1]
    q1_dot = qd[0]
    q2_dot = qd[1]
    mass_1 = p[0]
    mass_2 = p[1]
    length_1 = p[4]
    com_1 = p[6]
    com_2 = p[7]
    g = p[8]
    x0 = math.cos(q1)
    x1 = length_1*x0
    x2 = q1 + q2
    x3 = com_2*math.cos(x2)
    x4 = g*mass_2
    x5 = -com_2*mass_2*x1*math.sin(x2) + length_1*mass_2*x3*math.sin(q1)
    x6 = q1_dot*x5
    out[0] = com_1*g*mass_1*x0 + q2_dot*x6 + q2_dot*(q2_dot*x5 + x6) + x4*(x1 + x3)
    out[1] = -q1_dot*q1_dot*x5 + x3*x4


@njit(cache=True, error_model="numpy")
def forcing(q, qd, p, out):
    """Generalized joint-damping forces Q(q, qd), out (n,); power Q.qd <= 0."""
    q1_dot = qd[0]
    q2_dot = qd[1]
    damping_1 = p[9]
    damping_2 = p[10]
    out[0] = -damping_1*q1_dot
    out[1] = -damping_2*q2_dot


@njit(cache=True, error_model="numpy")
def dmass(q, p, out):
    """dD/dq_k for every k, out (n, n, n): out[k] = dD/dq_k."""
    q1 = q[0]
    q2 = q[1]
    mass_2 = p[1]
    length_1 = p[4]
    com_2 = p[7]
    x0 = q1 + q2
    x1 = com_2*length_1*mass_2
    x2 = x1*math.sin(q1)*math.cos(x0)
    x3 = x1*math.sin(x0)*math.cos(q1)
    x4 = x2 - x3
    out[0, 0, 0] = 0
    out[0, 0, 1] = 0
    out[0, 1, 0] = 0
    out[0, 1, 1] = 0
    out[1, 0, 0] = 2*x2 - 2*x3
    out[1, 0, 1] = x4
    out[1, 1, 0] = x4
    out[1, 1, 1] = 0


@njit(cache=True, error_model="numpy")
def dbias_dq(q, qd, p, out):
    """dh/dq, out (n, n)."""
    q1 = q[0]
    q2 = q[1]
    q1_dot = qd[0]
    q2_dot = qd[1]
    mass_1 = p[0]
    mass_2 = p[1]
    length_1 = p[4]
    com_1 = p[6]
    com_2 = p[7]
    g = p[8]
    x0 = math.sin(q1)
    x1 = length_1*x0
    x2 = q1 + q2
    x3 = com_2*math.sin(x2)
    x4 = g*mass_2*x3
    x5 = -x4
    x6 = com_2*length_1*mass_2*math.cos(q1)*math.cos(x2) + mass_2*x1*x3
    x7 = -x6
    x8 = q1_dot*x7
    out[0, 0] = -com_1*g*mass_1*x0 + g*mass_2*(-x1 - x3)
    out[0, 1] = q2_dot*x8 + q2_dot*(q2_dot*x7 + x8) + x5
    out[1, 0] = x5
    out[1, 1] = q1_dot*q1_dot*x6 - x4


@njit(cache=True, error_model="numpy")
def dbias_dqd(q, qd, p, out):
    """dh/dqd, out (n, n)."""
    q1 = q[0]
    q2 = q[1]
    q1_dot = qd[0]
    q2_dot = qd[1]
    mass_2 = p[1]
    length_1 = p[4]
    com_2 = p[7]
    x0 = q1 + q2
    x1 = com_2*length_1*mass_2
    x2 = x1*math.sin(q1)*math.cos(x0) - x1*math.sin(x0)*math.cos(q1)
    x3 = 2*x2
    x4 = q2_dot*x3
    out[0, 0] = x4
    out[0, 1] = q1_dot*x3 + x4
    out[1, 0] = -2*q1_dot*x2
    out[1, 1] = 0


@njit(cache=True, error_model="numpy")
def kinetic(q, qd, p):
    """Kinetic energy [J]."""
    q1 = q[0]
    q2 = q[1]
    q1_dot = qd[0]
    q2_dot = qd[1]
    mass_1 = p[0]
    mass_2 = p[1]
    inertia_1 = p[2]
    inertia_2 = p[3]
    length_1 = p[4]
    com_1 = p[6]
    com_2 = p[7]
    x0 = q1_dot*q1_dot
    x1 = math.sin(q1)
    x2 = com_1*com_1*x0
    x3 = math.cos(q1)
    x4 = q1 + q2
    x5 = com_2*math.cos(x4)
    x6 = com_2*math.sin(x4)
    return ((1.0/2.0))*inertia_1*x0 + ((1.0/2.0))*inertia_2*(q1_dot + q2_dot)*(q1_dot + q2_dot) + ((1.0/2.0))*mass_1*(x1*x1*x2 + x2*x3*x3) + ((1.0/2.0))*mass_2*((q1_dot*(-length_1*x1 - x6) - q2_dot*x6)*(q1_dot*(-length_1*x1 - x6) - q2_dot*x6) + (q1_dot*(length_1*x3 + x5) + q2_dot*x5)*(q1_dot*(length_1*x3 + x5) + q2_dot*x5))


@njit(cache=True, error_model="numpy")
def potential(q, p):
    """Potential energy [J] (y = 0 at the origin)."""
    q1 = q[0]
    q2 = q[1]
    mass_1 = p[0]
    mass_2 = p[1]
    length_1 = p[4]
    com_1 = p[6]
    com_2 = p[7]
    g = p[8]
    x0 = math.sin(q1)
    return com_1*g*mass_1*x0 + g*mass_2*(com_2*math.sin(q1 + q2) + length_1*x0)


@njit(cache=True, error_model="numpy")
def points(q, p, out):
    """Named points in the world frame, out (n_points, 2); names in POINTS."""
    q1 = q[0]
    q2 = q[1]
    length_1 = p[4]
    length_2 = p[5]
    x0 = length_1*math.cos(q1)
    x1 = length_1*math.sin(q1)
    x2 = q1 + q2
    out[0, 0] = x0
    out[0, 1] = x1
    out[1, 0] = length_2*math.cos(x2) + x0
    out[1, 1] = length_2*math.sin(x2) + x1

POINTS = ('elbow', 'tip')
