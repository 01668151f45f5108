# generated, do not edit: walker kernels for `compass`
# input hash: sha256:ad6c018dc54b381378e570439f1bf50a0c64d859e711bdf1df7716a42de0392a
# sympy 1.14.0; regenerate with `python scripts/generate_kernels.py`
# argument order:
#   q = [q_stance, q_swing]
#   qd = [q_stance_dot, q_swing_dot]
#   p = [mass_hip, mass_leg, com_from_foot, com_to_hip, inertia_leg, foot_radius, slope, g, damping_hip, damping_ankle]
#   q = [q_stance, q_swing, x_hip, y_hip]
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
#   hip_jac(q, p)
#   ext_mass_matrix(q, p)
#   ext_swing_contact_jac(q, p)
#   ext_stance_contact_jac(q, p)
"""Generated numba kernels for the `compass` model.

Compass gait: single-support dynamics and the floating-base heel-strike model.
"""

import math  # noqa: F401

from walker._jit import njit

KERNEL_HASH = "ad6c018dc54b381378e570439f1bf50a0c64d859e711bdf1df7716a42de0392a"
ARGUMENT_ORDER = {'accel': {'q': ('q_stance', 'q_swing'), 'qd': ('q_stance_dot', 'q_swing_dot'), 'p': ('mass_hip', 'mass_leg', 'com_from_foot', 'com_to_hip', 'inertia_leg', 'foot_radius', 'slope', 'g', 'damping_hip', 'damping_ankle')}, 'accel_jac': {'q': ('q_stance', 'q_swing'), 'qd': ('q_stance_dot', 'q_swing_dot'), 'p': ('mass_hip', 'mass_leg', 'com_from_foot', 'com_to_hip', 'inertia_leg', 'foot_radius', 'slope', 'g', 'damping_hip', 'damping_ankle')}, 'mass_matrix': {'q': ('q_stance', 'q_swing'), 'p': ('mass_hip', 'mass_leg', 'com_from_foot', 'com_to_hip', 'inertia_leg', 'foot_radius', 'slope', 'g', 'damping_hip', 'damping_ankle')}, 'coriolis': {'q': ('q_stance', 'q_swing'), 'qd': ('q_stance_dot', 'q_swing_dot'), 'p': ('mass_hip', 'mass_leg', 'com_from_foot', 'com_to_hip', 'inertia_leg', 'foot_radius', 'slope', 'g', 'damping_hip', 'damping_ankle')}, 'gravity': {'q': ('q_stance', 'q_swing'), 'p': ('mass_hip', 'mass_leg', 'com_from_foot', 'com_to_hip', 'inertia_leg', 'foot_radius', 'slope', 'g', 'damping_hip', 'damping_ankle')}, 'bias': {'q': ('q_stance', 'q_swing'), 'qd': ('q_stance_dot', 'q_swing_dot'), 'p': ('mass_hip', 'mass_leg', 'com_from_foot', 'com_to_hip', 'inertia_leg', 'foot_radius', 'slope', 'g', 'damping_hip', 'damping_ankle')}, 'forcing': {'q': ('q_stance', 'q_swing'), 'qd': ('q_stance_dot', 'q_swing_dot'), 'p': ('mass_hip', 'mass_leg', 'com_from_foot', 'com_to_hip', 'inertia_leg', 'foot_radius', 'slope', 'g', 'damping_hip', 'damping_ankle')}, 'dmass': {'q': ('q_stance', 'q_swing'), 'p': ('mass_hip', 'mass_leg', 'com_from_foot', 'com_to_hip', 'inertia_leg', 'foot_radius', 'slope', 'g', 'damping_hip', 'damping_ankle')}, 'dbias_dq': {'q': ('q_stance', 'q_swing'), 'qd': ('q_stance_dot', 'q_swing_dot'), 'p': ('mass_hip', 'mass_leg', 'com_from_foot', 'com_to_hip', 'inertia_leg', 'foot_radius', 'slope', 'g', 'damping_hip', 'damping_ankle')}, 'dbias_dqd': {'q': ('q_stance', 'q_swing'), 'qd': ('q_stance_dot', 'q_swing_dot'), 'p': ('mass_hip', 'mass_leg', 'com_from_foot', 'com_to_hip', 'inertia_leg', 'foot_radius', 'slope', 'g', 'damping_hip', 'damping_ankle')}, 'kinetic': {'q': ('q_stance', 'q_swing'), 'qd': ('q_stance_dot', 'q_swing_dot'), 'p': ('mass_hip', 'mass_leg', 'com_from_foot', 'com_to_hip', 'inertia_leg', 'foot_radius', 'slope', 'g', 'damping_hip', 'damping_ankle')}, 'potential': {'q': ('q_stance', 'q_swing'), 'p': ('mass_hip', 'mass_leg', 'com_from_foot', 'com_to_hip', 'inertia_leg', 'foot_radius', 'slope', 'g', 'damping_hip', 'damping_ankle')}, 'points': {'q': ('q_stance', 'q_swing'), 'p': ('mass_hip', 'mass_leg', 'com_from_foot', 'com_to_hip', 'inertia_leg', 'foot_radius', 'slope', 'g', 'damping_hip', 'damping_ankle')}, 'hip_jac': {'q': ('q_stance', 'q_swing'), 'p': ('mass_hip', 'mass_leg', 'com_from_foot', 'com_to_hip', 'inertia_leg', 'foot_radius', 'slope', 'g', 'damping_hip', 'damping_ankle')}, 'ext_mass_matrix': {'q': ('q_stance', 'q_swing', 'x_hip', 'y_hip'), 'p': ('mass_hip', 'mass_leg', 'com_from_foot', 'com_to_hip', 'inertia_leg', 'foot_radius', 'slope', 'g', 'damping_hip', 'damping_ankle')}, 'ext_swing_contact_jac': {'q': ('q_stance', 'q_swing', 'x_hip', 'y_hip'), 'p': ('mass_hip', 'mass_leg', 'com_from_foot', 'com_to_hip', 'inertia_leg', 'foot_radius', 'slope', 'g', 'damping_hip', 'damping_ankle')}, 'ext_stance_contact_jac': {'q': ('q_stance', 'q_swing', 'x_hip', 'y_hip'), 'p': ('mass_hip', 'mass_leg', 'com_from_foot', 'com_to_hip', 'inertia_leg', 'foot_radius', 'slope', 'g', 'damping_hip', 'damping_ankle')}}

@njit(cache=True, error_model="numpy")
def accel(q, qd, p, out):
    """Accelerations qdd = -D^-1 (h - Q), Q the joint-damping forcing, by unrolled Cholesky, out (>= n,)."""
    q_stance = q[0]
    q_swing = q[1]
    q_stance_dot = qd[0]
    q_swing_dot = qd[1]
    mass_hip = p[0]
    mass_leg = p[1]
    com_from_foot = p[2]
    com_to_hip = p[3]
    inertia_leg = p[4]
    foot_radius = p[5]
    slope = p[6]
    g = p[7]
    damping_hip = p[8]
    damping_ankle = p[9]
    x0 = math.sin(q_stance)
    x1 = x0*x0
    x2 = com_from_foot*com_from_foot
    x3 = mass_hip*x2
    x4 = math.cos(q_stance)
    x5 = x4*x4
    x6 = com_to_hip*com_to_hip
    x7 = mass_hip*x6
    x8 = mass_leg*x6
    x9 = foot_radius*foot_radius
    x10 = mass_hip*x9
    x11 = math.sin(slope)
    x12 = x11*x11
    x13 = math.cos(slope)
    x14 = x13*x13
    x15 = 2*mass_hip
    x16 = com_from_foot*com_to_hip
    x17 = x15*x16
    x18 = 2*mass_leg
    x19 = x16*x18
    x20 = com_from_foot*foot_radius
    x21 = x1*x20
    x22 = x20*x5
    x23 = 4*mass_leg
    x24 = com_to_hip*foot_radius
    x25 = x15*x24
    x26 = x18*x24
    x27 = foot_radius*x11
    x28 = com_from_foot*x27
    x29 = x0*x28
    x30 = x13*x4
    x31 = x20*x30
    x32 = com_to_hip*x27
    x33 = x0*x32
    x34 = x18*x2
    x35 = x18*x9
    x36 = x23*x9
    x37 = math.sin(q_swing)
    x38 = com_to_hip*x37
    x39 = mass_leg*x38
    x40 = math.cos(q_swing)
    x41 = mass_leg*x4
    x42 = x13*x24
    x43 = mass_leg*x40
    x44 = x0*x8
    x45 = x4*x8
    x46 = damping_hip*q_stance_dot
    x47 = damping_hip*q_swing_dot
    x48 = com_from_foot - foot_radius
    x49 = g*mass_leg
    x50 = g*(-x0*(com_to_hip + x48) + x27)
    x51 = x38*x41
    x52 = com_from_foot*x51
    x53 = x0*x43
    x54 = x24*x53
    x55 = x37*x45
    x56 = x16*x53
    x57 = foot_radius*x51
    x58 = x40*x44
    x59 = q_stance_dot*q_stance_dot
    x60 = x0*x13*x20
    x61 = mass_hip*x4
    x62 = x0*x42
    d00 = inertia_leg + 2*x0*x10*x11 + x0*x11*x36 + x1*x10 + x1*x17 + x1*x19 - x1*x25 - x1*x26 + x1*x3 + x1*x34 + x1*x35 + x1*x7 + x1*x8 + x10*x12 - 2*x10*x13*x4 + x10*x14 + x10*x5 + x12*x35 + x14*x35 - x15*x21 - x15*x22 - x15*x29 + x15*x31 - x15*x33 + x17*x5 - x18*x33 + x19*x5 - x21*x23 - x22*x23 - x23*x29 + x23*x31 + x25*x30 - x25*x5 + x26*x30 - x26*x5 + x3*x5 - x30*x36 + x34*x5 + x35*x5 + x5*x7 + x5*x8
    d10 = -com_from_foot*x0*x39 + com_to_hip*foot_radius*mass_leg*x0*x37 + com_to_hip*foot_radius*mass_leg*x11*x37 + com_to_hip*foot_radius*mass_leg*x4*x40 - x16*x40*x41 - x37*x44 - x40*x45 - x42*x43
    d11 = inertia_leg + x37*x37*x8 + x40*x40*x8
    h0 = damping_ankle*q_stance_dot + mass_hip*x50 + mass_leg*x50 + q_swing_dot*q_swing_dot*(foot_radius*x13*x39 + x32*x43 + x52 + x54 + x55 - x56 - x57 - x58) + x46 - x47 + x49*(-x0*x48 + x27) + x59*(mass_hip*x0*x13*x9 + mass_hip*x11*x4*x9 - mass_hip*x60 - mass_hip*x62 + 2*mass_leg*x0*x13*x9 + 2*mass_leg*x11*x4*x9 - mass_leg*x62 - x18*x28*x4 - x18*x60 - x28*x61 - x32*x41 - x32*x61)
    h1 = x38*x49 - x46 + x47 + x59*(-x52 - x54 - x55 + x56 + x57 + x58)
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
    q_stance = q[0]
    q_swing = q[1]
    q_stance_dot = qd[0]
    q_swing_dot = qd[1]
    mass_hip = p[0]
    mass_leg = p[1]
    com_from_foot = p[2]
    com_to_hip = p[3]
    inertia_leg = p[4]
    foot_radius = p[5]
    slope = p[6]
    g = p[7]
    damping_hip = p[8]
    damping_ankle = p[9]
    x0 = math.sin(q_stance)
    x1 = x0*x0
    x2 = com_from_foot*com_from_foot
    x3 = mass_hip*x2
    x4 = math.cos(q_stance)
    x5 = x4*x4
    x6 = com_to_hip*com_to_hip
    x7 = mass_hip*x6
    x8 = mass_leg*x6
    x9 = foot_radius*foot_radius
    x10 = mass_hip*x9
    x11 = math.sin(slope)
    x12 = x11*x11
    x13 = math.cos(slope)
    x14 = x13*x13
    x15 = 2*mass_hip
    x16 = com_from_foot*com_to_hip
    x17 = x15*x16
    x18 = 2*mass_leg
    x19 = x16*x18
    x20 = com_from_foot*foot_radius
    x21 = x1*x20
    x22 = x20*x5
    x23 = 4*mass_leg
    x24 = com_to_hip*foot_radius
    x25 = x15*x24
    x26 = x18*x24
    x27 = foot_radius*x11
    x28 = com_from_foot*x27
    x29 = x0*x28
    x30 = x13*x4
    x31 = x20*x30
    x32 = com_to_hip*x27
    x33 = x0*x32
    x34 = x18*x2
    x35 = x18*x9
    x36 = x0*x10*x11
    x37 = x10*x13*x4
    x38 = x23*x9
    x39 = math.cos(q_swing)
    x40 = mass_leg*x24
    x41 = x13*x40
    x42 = math.sin(q_swing)
    x43 = mass_leg*x16
    x44 = x0*x8
    x45 = x4*x8
    x46 = -com_to_hip*foot_radius*mass_leg*x0*x42 - com_to_hip*foot_radius*mass_leg*x39*x4 + x0*x42*x43 + x39*x4*x43 + x39*x45 + x42*x44
    x47 = -com_to_hip*foot_radius*mass_leg*x11*x42 + x39*x41 + x46
    x48 = damping_hip*q_stance_dot
    x49 = damping_hip*q_swing_dot
    x50 = com_from_foot - foot_radius
    x51 = g*mass_leg
    x52 = com_to_hip + x50
    x53 = g*(-x0*x52 + x27)
    x54 = q_swing_dot*q_swing_dot
    x55 = mass_leg*x16*x4*x42
    x56 = x0*x39
    x57 = x40*x56
    x58 = mass_leg*x32
    x59 = x42*x45
    x60 = x43*x56
    x61 = x4*x40*x42
    x62 = x39*x44
    x63 = x39*x58 + x41*x42 + x55 + x57 + x59 - x60 - x61 - x62
    x64 = q_stance_dot*q_stance_dot
    x65 = x0*x13
    x66 = mass_hip*x65
    x67 = mass_hip*x4
    x68 = x20*x65
    x69 = x28*x4
    x70 = mass_hip*x0*x13*x9 + mass_hip*x11*x4*x9 + 2*mass_leg*x0*x13*x9 + 2*mass_leg*x11*x4*x9 - x0*x41 - x18*x68 - x18*x69 - x20*x66 - x24*x66 - x28*x67 - x32*x67 - x4*x58
    x71 = com_to_hip*x51
    x72 = -x55 - x57 - x59 + x60 + x61 + x62
    x73 = x32*x4
    x74 = x4*x52
    x75 = -x46
    x76 = mass_hip*x0
    x77 = mass_hip*x30
    d00 = inertia_leg + x0*x11*x38 + x1*x10 + x1*x17 + x1*x19 - x1*x25 - x1*x26 + x1*x3 + x1*x34 + x1*x35 + x1*x7 + x1*x8 + x10*x12 + x10*x14 + x10*x5 + x12*x35 + x14*x35 - x15*x21 - x15*x22 - x15*x29 + x15*x31 - x15*x33 + x17*x5 - x18*x33 + x19*x5 - x21*x23 - x22*x23 - x23*x29 + x23*x31 + x25*x30 - x25*x5 + x26*x30 - x26*x5 + x3*x5 - x30*x38 + x34*x5 + x35*x5 + 2*x36 - 2*x37 + x5*x7 + x5*x8
    d10 = -x47
    d11 = inertia_leg + x39*x39*x8 + x42*x42*x8
    h0 = damping_ankle*q_stance_dot + mass_hip*x53 + mass_leg*x53 + x48 - x49 + x51*(-x0*x50 + x27) + x54*x63 + x64*x70
    h1 = x42*x71 - x48 + x49 + x64*x72
    dD0_00 = 2*mass_hip*x0*x13*x9 + 2*mass_hip*x11*x4*x9 + 4*mass_leg*x0*x13*x9 + 4*mass_leg*x11*x4*x9 - x15*x68 - x15*x69 - x15*x73 - x18*x73 - x23*x68 - x23*x69 - x25*x65 - x26*x65
    dD0_10 = x72
    dD0_11 = 0
    dD1_00 = 0
    dD1_10 = x63
    dD1_11 = 0
    hq0_0 = -g*mass_hip*x74 - x4*x50*x51 - x51*x74 + x54*x75 + x64*(-x0*x11*x35 + x0*x58 + x18*x29 - x18*x31 - x20*x77 - x24*x77 + x28*x76 + x30*x35 - x30*x40 + x32*x76 - x36 + x37)
    hv0_0 = damping_ankle + damping_hip + 2*q_stance_dot*x70
    hq1_0 = x46*x64
    hv1_0 = -damping_hip + 2*q_stance_dot*x72
    hq0_1 = x47*x54
    hv0_1 = -damping_hip + 2*q_swing_dot*x63
    hq1_1 = x39*x71 + x64*x75
    hv1_1 = damping_hip
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
    q_stance = q[0]
    q_swing = q[1]
    mass_hip = p[0]
    mass_leg = p[1]
    com_from_foot = p[2]
    com_to_hip = p[3]
    inertia_leg = p[4]
    foot_radius = p[5]
    slope = p[6]
    x0 = math.sin(q_stance)
    x1 = x0*x0
    x2 = com_from_foot*com_from_foot
    x3 = mass_hip*x2
    x4 = math.cos(q_stance)
    x5 = x4*x4
    x6 = com_to_hip*com_to_hip
    x7 = mass_hip*x6
    x8 = mass_leg*x6
    x9 = foot_radius*foot_radius
    x10 = mass_hip*x9
    x11 = math.sin(slope)
    x12 = x11*x11
    x13 = math.cos(slope)
    x14 = x13*x13
    x15 = 2*mass_hip
    x16 = com_from_foot*com_to_hip
    x17 = x15*x16
    x18 = 2*mass_leg
    x19 = x16*x18
    x20 = com_from_foot*foot_radius
    x21 = x1*x20
    x22 = x20*x5
    x23 = 4*mass_leg
    x24 = com_to_hip*foot_radius
    x25 = x15*x24
    x26 = x18*x24
    x27 = x0*x11
    x28 = x20*x27
    x29 = x13*x4
    x30 = x20*x29
    x31 = x18*x2
    x32 = x18*x9
    x33 = 2*x10
    x34 = x23*x9
    x35 = math.sin(q_swing)
    x36 = x0*x35
    x37 = mass_leg*x16
    x38 = math.cos(q_swing)
    x39 = x38*x4
    x40 = com_to_hip*foot_radius*mass_leg*x0*x35 + com_to_hip*foot_radius*mass_leg*x11*x35 + com_to_hip*foot_radius*mass_leg*x38*x4 - mass_leg*x13*x24*x38 - x36*x37 - x36*x8 - x37*x39 - x39*x8
    out[0, 0] = inertia_leg + x1*x10 + x1*x17 + x1*x19 - x1*x25 - x1*x26 + x1*x3 + x1*x31 + x1*x32 + x1*x7 + x1*x8 + x10*x12 + x10*x14 + x10*x5 + x12*x32 + x14*x32 - x15*x21 - x15*x22 - x15*x28 + x15*x30 + x17*x5 + x19*x5 - x21*x23 - x22*x23 - x23*x28 + x23*x30 - x25*x27 + x25*x29 - x25*x5 - x26*x27 + x26*x29 - x26*x5 + x27*x33 + x27*x34 - x29*x33 - x29*x34 + x3*x5 + x31*x5 + x32*x5 + x5*x7 + x5*x8
    out[0, 1] = x40
    out[1, 0] = x40
    out[1, 1] = inertia_leg + x35*x35*x8 + x38*x38*x8


@njit(cache=True, error_model="numpy")
def coriolis(q, qd, p, out):
    """Coriolis matrix C(q, qd), out (n, n)."""
    q_stance = q[0]
    q_swing = q[1]
    q_stance_dot = qd[0]
    q_swing_dot = qd[1]
    mass_hip = p[0]
    mass_leg = p[1]
    com_from_foot = p[2]
    com_to_hip = p[3]
    foot_radius = p[5]
    slope = p[6]
    x0 = math.cos(slope)
    x1 = math.sin(q_stance)
    x2 = x0*x1
    x3 = foot_radius*mass_hip
    x4 = com_from_foot*x3
    x5 = math.cos(q_stance)
    x6 = math.sin(slope)
    x7 = x5*x6
    x8 = com_to_hip*x3
    x9 = mass_leg*x2
    x10 = com_to_hip*foot_radius
    x11 = mass_leg*x7
    x12 = 2*com_from_foot*foot_radius
    x13 = foot_radius*foot_radius
    x14 = math.sin(q_swing)
    x15 = x14*x5
    x16 = mass_leg*x15
    x17 = com_from_foot*com_to_hip
    x18 = x16*x17
    x19 = math.cos(q_swing)
    x20 = x1*x19
    x21 = mass_leg*x10
    x22 = x20*x21
    x23 = com_to_hip*com_to_hip*mass_leg
    x24 = x15*x23
    x25 = mass_leg*x17*x20
    x26 = x10*x16
    x27 = x20*x23
    out[0, 0] = q_stance_dot*(mass_hip*x0*x1*x13 + mass_hip*x13*x5*x6 + 2*mass_leg*x0*x1*x13 + 2*mass_leg*x13*x5*x6 - x10*x11 - x10*x9 - x11*x12 - x12*x9 - x2*x4 - x2*x8 - x4*x7 - x7*x8)
    out[0, 1] = q_swing_dot*(x0*x14*x21 + x18 + x19*x21*x6 + x22 + x24 - x25 - x26 - x27)
    out[1, 0] = q_stance_dot*(-x18 - x22 - x24 + x25 + x26 + x27)
    out[1, 1] = 0


@njit(cache=True, error_model="numpy")
def gravity(q, p, out):
    """Gravity vector g(q) = dP/dq, out (n,)."""
    q_stance = q[0]
    q_swing = q[1]
    mass_hip = p[0]
    mass_leg = p[1]
    com_from_foot = p[2]
    com_to_hip = p[3]
    foot_radius = p[5]
    slope = p[6]
    g = p[7]
    x0 = foot_radius*math.sin(slope)
    x1 = math.sin(q_stance)
    x2 = com_from_foot - foot_radius
    x3 = g*mass_leg
    x4 = g*(x0 - x1*(com_to_hip + x2))
    out[0] = mass_hip*x4 + mass_leg*x4 + x3*(x0 - x1*x2)
    out[1] = com_to_hip*x3*math.sin(q_swing)


@njit(cache=True, error_model="numpy")
def bias(q, qd, p, out):
    """h(q, qd) = C(q, qd) qd + g(q), out (n,)."""
    q_stance = q[0]
    q_swing = q[1]
    q_stance_dot = qd[0]
    q_swing_dot = qd[1]
    mass_hip = p[0]
    mass_leg = p[1]
    com_from_foot = p[2]
    com_to_hip = p[3]
    foot_radius = p[5]
    slope = p[6]
    g = p[7]
    x0 = math.sin(slope)
    x1 = foot_radius*x0
    x2 = math.sin(q_stance)
    x3 = com_from_foot - foot_radius
    x4 = g*mass_leg
    x5 = g*(x1 - x2*(com_to_hip + x3))
    x6 = math.cos(q_stance)
    x7 = math.sin(q_swing)
    x8 = x6*x7
    x9 = com_to_hip*mass_leg
    x10 = com_from_foot*x9
    x11 = x10*x8
    x12 = math.cos(q_swing)
    x13 = x12*x2
    x14 = foot_radius*x9
    x15 = x13*x14
    x16 = math.cos(slope)
    x17 = com_to_hip*x7
    x18 = com_to_hip*com_to_hip*mass_leg
    x19 = x18*x8
    x20 = x10*x13
    x21 = x14*x8
    x22 = x13*x18
    x23 = q_stance_dot*q_stance_dot
    x24 = com_from_foot*mass_hip
    x25 = foot_radius*x16*x2
    x26 = x1*x6
    x27 = com_to_hip*mass_hip
    x28 = 2*com_from_foot*mass_leg
    x29 = foot_radius*foot_radius
    out[0] = mass_hip*x5 + mass_leg*x5 + q_swing_dot*q_swing_dot*(foot_radius*mass_leg*x16*x17 + x1*x12*x9 + x11 + x15 + x19 - x20 - x21 - x22) + x23*(mass_hip*x0*x29*x6 + mass_hip*x16*x2*x29 + 2*mass_leg*x0*x29*x6 + 2*mass_leg*x16*x2*x29 - x24*x25 - x24*x26 - x25*x27 - x25*x28 - x25*x9 - x26*x27 - x26*x28 - x26*x9) + x4*(x1 - x2*x3)
    out[1] = x17*x4 + x23*(-x11 - x15 - x19 + x20 + x21 + x22)


@njit(cache=True, error_model="numpy")
def forcing(q, qd, p, out):
    """Generalized joint-damping forces Q(q, qd), out (n,); power Q.qd <= 0."""
    q_stance_dot = qd[0]
    q_swing_dot = qd[1]
    damping_hip = p[8]
    damping_ankle = p[9]
    x0 = damping_hip*q_stance_dot - damping_hip*q_swing_dot
    out[0] = -damping_ankle*q_stance_dot - x0
    out[1] = x0


@njit(cache=True, error_model="numpy")
def dmass(q, p, out):
    """dD/dq_k for every k, out (n, n, n): out[k] = dD/dq_k."""
    q_stance = q[0]
    q_swing = q[1]
    mass_hip = p[0]
    mass_leg = p[1]
    com_from_foot = p[2]
    com_to_hip = p[3]
    foot_radius = p[5]
    slope = p[6]
    x0 = math.sin(q_stance)
    x1 = math.cos(slope)
    x2 = x0*x1
    x3 = 2*mass_hip
    x4 = com_from_foot*foot_radius
    x5 = x3*x4
    x6 = math.cos(q_stance)
    x7 = math.sin(slope)
    x8 = x6*x7
    x9 = 4*mass_leg*x4
    x10 = com_to_hip*foot_radius*x3
    x11 = com_to_hip*mass_leg
    x12 = foot_radius*x11
    x13 = 2*x12
    x14 = foot_radius*foot_radius
    x15 = math.cos(q_swing)
    x16 = x0*x15
    x17 = com_from_foot*x11
    x18 = x16*x17
    x19 = math.sin(q_swing)
    x20 = x19*x6
    x21 = x12*x20
    x22 = com_to_hip*com_to_hip*mass_leg
    x23 = x16*x22
    x24 = x17*x20
    x25 = x12*x16
    x26 = x20*x22
    x27 = x18 + x21 + x23 - x24 - x25 - x26
    x28 = x1*x12*x19 + x12*x15*x7 - x18 - x21 - x23 + x24 + x25 + x26
    out[0, 0, 0] = 2*mass_hip*x0*x1*x14 + 2*mass_hip*x14*x6*x7 + 4*mass_leg*x0*x1*x14 + 4*mass_leg*x14*x6*x7 - x10*x2 - x10*x8 - x13*x2 - x13*x8 - x2*x5 - x2*x9 - x5*x8 - x8*x9
    out[0, 0, 1] = x27
    out[0, 1, 0] = x27
    out[0, 1, 1] = 0
    out[1, 0, 0] = 0
    out[1, 0, 1] = x28
    out[1, 1, 0] = x28
    out[1, 1, 1] = 0


@njit(cache=True, error_model="numpy")
def dbias_dq(q, qd, p, out):
    """dh/dq, out (n, n)."""
    q_stance = q[0]
    q_swing = q[1]
    q_stance_dot = qd[0]
    q_swing_dot = qd[1]
    mass_hip = p[0]
    mass_leg = p[1]
    com_from_foot = p[2]
    com_to_hip = p[3]
    foot_radius = p[5]
    slope = p[6]
    g = p[7]
    x0 = com_from_foot - foot_radius
    x1 = math.cos(q_stance)
    x2 = g*x1
    x3 = x2*(com_to_hip + x0)
    x4 = q_swing_dot*q_swing_dot
    x5 = math.sin(q_stance)
    x6 = math.sin(q_swing)
    x7 = x5*x6
    x8 = com_to_hip*mass_leg
    x9 = com_from_foot*x8
    x10 = math.cos(q_swing)
    x11 = x1*x10
    x12 = com_to_hip*com_to_hip*mass_leg
    x13 = foot_radius*x8
    x14 = x11*x12 - x11*x13 + x11*x9 + x12*x7 - x13*x7 + x7*x9
    x15 = -x14
    x16 = q_stance_dot*q_stance_dot
    x17 = math.sin(slope)
    x18 = x17*x5
    x19 = foot_radius*x18
    x20 = mass_hip*x19
    x21 = foot_radius*foot_radius
    x22 = mass_hip*x21
    x23 = math.cos(slope)
    x24 = x1*x23
    x25 = foot_radius*x24
    x26 = mass_hip*x25
    x27 = 2*mass_leg
    x28 = com_from_foot*x27
    x29 = x21*x27
    x30 = x10*x8
    out[0, 0] = -mass_hip*x3 - mass_leg*x0*x2 - mass_leg*x3 + x15*x4 + x16*(com_from_foot*x20 - com_from_foot*x26 + com_to_hip*x20 - com_to_hip*x26 - x18*x22 - x18*x29 + x19*x28 + x19*x8 + x22*x24 + x24*x29 - x25*x28 - x25*x8)
    out[0, 1] = x4*(foot_radius*x23*x30 - x13*x17*x6 + x14)
    out[1, 0] = x14*x16
    out[1, 1] = g*x30 + x15*x16


@njit(cache=True, error_model="numpy")
def dbias_dqd(q, qd, p, out):
    """dh/dqd, out (n, n)."""
    q_stance = q[0]
    q_swing = q[1]
    q_stance_dot = qd[0]
    q_swing_dot = qd[1]
    mass_hip = p[0]
    mass_leg = p[1]
    com_from_foot = p[2]
    com_to_hip = p[3]
    foot_radius = p[5]
    slope = p[6]
    x0 = math.cos(slope)
    x1 = math.sin(q_stance)
    x2 = x0*x1
    x3 = foot_radius*mass_hip
    x4 = com_from_foot*x3
    x5 = math.cos(q_stance)
    x6 = math.sin(slope)
    x7 = x5*x6
    x8 = com_to_hip*x3
    x9 = mass_leg*x2
    x10 = com_to_hip*foot_radius
    x11 = mass_leg*x7
    x12 = 2*com_from_foot*foot_radius
    x13 = foot_radius*foot_radius
    x14 = 2*q_stance_dot
    x15 = math.sin(q_swing)
    x16 = x15*x5
    x17 = mass_leg*x16
    x18 = com_from_foot*com_to_hip
    x19 = x17*x18
    x20 = math.cos(q_swing)
    x21 = x1*x20
    x22 = mass_leg*x10
    x23 = x21*x22
    x24 = com_to_hip*com_to_hip*mass_leg
    x25 = x16*x24
    x26 = mass_leg*x18*x21
    x27 = x10*x17
    x28 = x21*x24
    out[0, 0] = x14*(mass_hip*x0*x1*x13 + mass_hip*x13*x5*x6 + 2*mass_leg*x0*x1*x13 + 2*mass_leg*x13*x5*x6 - x10*x11 - x10*x9 - x11*x12 - x12*x9 - x2*x4 - x2*x8 - x4*x7 - x7*x8)
    out[0, 1] = 2*q_swing_dot*(x0*x15*x22 + x19 + x20*x22*x6 + x23 + x25 - x26 - x27 - x28)
    out[1, 0] = x14*(-x19 - x23 - x25 + x26 + x27 + x28)
    out[1, 1] = 0


@njit(cache=True, error_model="numpy")
def kinetic(q, qd, p):
    """Kinetic energy [J]."""
    q_stance = q[0]
    q_swing = q[1]
    q_stance_dot = qd[0]
    q_swing_dot = qd[1]
    mass_hip = p[0]
    mass_leg = p[1]
    com_from_foot = p[2]
    com_to_hip = p[3]
    inertia_leg = p[4]
    foot_radius = p[5]
    slope = p[6]
    x0 = q_stance_dot*q_stance_dot
    x1 = ((1.0/2.0))*inertia_leg
    x2 = foot_radius*math.sin(slope)
    x3 = math.sin(q_stance)
    x4 = com_from_foot - foot_radius
    x5 = foot_radius*math.cos(slope)
    x6 = math.cos(q_stance)
    x7 = ((1.0/2.0))*mass_leg
    x8 = com_to_hip + x4
    x9 = x2 - x3*x8
    x10 = -x5 - x6*x8
    x11 = com_to_hip*q_swing_dot
    return ((1.0/2.0))*mass_hip*(x0*x10*x10 + x0*x9*x9) + q_swing_dot*q_swing_dot*x1 + x0*x1 + x7*(x0*(x2 - x3*x4)*(x2 - x3*x4) + x0*(-x4*x6 - x5)*(-x4*x6 - x5)) + x7*((q_stance_dot*x10 + x11*math.cos(q_swing))*(q_stance_dot*x10 + x11*math.cos(q_swing)) + (q_stance_dot*x9 + x11*math.sin(q_swing))*(q_stance_dot*x9 + x11*math.sin(q_swing)))


@njit(cache=True, error_model="numpy")
def potential(q, p):
    """Potential energy [J] (y = 0 at the origin)."""
    q_stance = q[0]
    q_swing = q[1]
    mass_hip = p[0]
    mass_leg = p[1]
    com_from_foot = p[2]
    com_to_hip = p[3]
    foot_radius = p[5]
    slope = p[6]
    g = p[7]
    x0 = math.cos(q_stance)
    x1 = com_from_foot - foot_radius
    x2 = foot_radius*(q_stance + slope)*math.sin(slope) + foot_radius*math.cos(slope)
    x3 = g*mass_leg
    x4 = x0*(com_to_hip + x1) + x2
    return g*mass_hip*x4 + x3*(-com_to_hip*math.cos(q_swing) + x4) + x3*(x0*x1 + x2)


@njit(cache=True, error_model="numpy")
def points(q, p, out):
    """Named points in the world frame, out (n_points, 2); names in POINTS."""
    q_stance = q[0]
    q_swing = q[1]
    com_from_foot = p[2]
    com_to_hip = p[3]
    foot_radius = p[5]
    slope = p[6]
    x0 = q_stance + slope
    x1 = foot_radius*math.cos(slope)
    x2 = x0*x1
    x3 = math.sin(slope)
    x4 = foot_radius*x0*x3
    x5 = com_from_foot + com_to_hip - foot_radius
    x6 = x2 + x5*math.sin(q_stance)
    x7 = -foot_radius*x3 + x6
    x8 = x4 + x5*math.cos(q_stance)
    x9 = x1 + x8
    x10 = -x5*math.sin(q_swing)
    x11 = -x5*math.cos(q_swing)
    out[0, 0] = -x2
    out[0, 1] = x4
    out[1, 0] = -x7
    out[1, 1] = x9
    out[2, 0] = -x10 - x7
    out[2, 1] = x11 + x9
    out[3, 0] = -x10 - x6
    out[3, 1] = x11 + x8


@njit(cache=True, error_model="numpy")
def hip_jac(q, p, out):
    """Jacobian of the hip position, out (2, n)."""
    q_stance = q[0]
    com_from_foot = p[2]
    com_to_hip = p[3]
    foot_radius = p[5]
    slope = p[6]
    x0 = com_from_foot + com_to_hip - foot_radius
    out[0, 0] = -foot_radius*math.cos(slope) - x0*math.cos(q_stance)
    out[0, 1] = 0
    out[1, 0] = foot_radius*math.sin(slope) - x0*math.sin(q_stance)
    out[1, 1] = 0


@njit(cache=True, error_model="numpy")
def ext_mass_matrix(q, p, out):
    """Floating-base mass matrix, out (n_f, n_f)."""
    q_stance = q[0]
    q_swing = q[1]
    mass_hip = p[0]
    mass_leg = p[1]
    com_to_hip = p[3]
    inertia_leg = p[4]
    x0 = math.sin(q_stance)
    x1 = com_to_hip*com_to_hip*mass_leg
    x2 = math.cos(q_stance)
    x3 = com_to_hip*mass_leg
    x4 = x2*x3
    x5 = x0*x3
    x6 = math.sin(q_swing)
    x7 = math.cos(q_swing)
    x8 = x3*x7
    x9 = x3*x6
    x10 = mass_hip + 2*mass_leg
    out[0, 0] = inertia_leg + x0*x0*x1 + x1*x2*x2
    out[0, 1] = 0
    out[0, 2] = x4
    out[0, 3] = x5
    out[1, 0] = 0
    out[1, 1] = inertia_leg + x1*x6*x6 + x1*x7*x7
    out[1, 2] = x8
    out[1, 3] = x9
    out[2, 0] = x4
    out[2, 1] = x8
    out[2, 2] = x10
    out[2, 3] = 0
    out[3, 0] = x5
    out[3, 1] = x9
    out[3, 2] = 0
    out[3, 3] = x10


@njit(cache=True, error_model="numpy")
def ext_swing_contact_jac(q, p, out):
    """Jacobian of the swing foot's material contact velocity, out (2, n_f)."""
    q_swing = q[1]
    com_from_foot = p[2]
    com_to_hip = p[3]
    foot_radius = p[5]
    slope = p[6]
    x0 = com_from_foot + com_to_hip - foot_radius
    out[0, 0] = 0
    out[0, 1] = foot_radius*math.cos(slope) + x0*math.cos(q_swing)
    out[0, 2] = 1
    out[0, 3] = 0
    out[1, 0] = 0
    out[1, 1] = -foot_radius*math.sin(slope) + x0*math.sin(q_swing)
    out[1, 2] = 0
    out[1, 3] = 1


@njit(cache=True, error_model="numpy")
def ext_stance_contact_jac(q, p, out):
    """Jacobian of the stance foot's material contact velocity, out (2, n_f)."""
    q_stance = q[0]
    com_from_foot = p[2]
    com_to_hip = p[3]
    foot_radius = p[5]
    slope = p[6]
    x0 = com_from_foot + com_to_hip - foot_radius
    out[0, 0] = foot_radius*math.cos(slope) + x0*math.cos(q_stance)
    out[0, 1] = 0
    out[0, 2] = 1
    out[0, 3] = 0
    out[1, 0] = -foot_radius*math.sin(slope) + x0*math.sin(q_stance)
    out[1, 1] = 0
    out[1, 2] = 0
    out[1, 3] = 1

POINTS = ('stance_contact', 'hip', 'swing_center', 'swing_contact')
