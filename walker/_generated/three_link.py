# generated, do not edit: walker kernels for `three_link`
# input hash: sha256:465e18f0b2825de7b1a416701aa361092e6d3db4a27b327992c27d8b1ae9763a
# sympy 1.14.0; regenerate with `python scripts/generate_kernels.py`
# argument order:
#   q = [q_stance, q_swing, q_torso]
#   qd = [q_stance_dot, q_swing_dot, q_torso_dot]
#   p = [mass_hip, mass_leg, mass_torso, com_from_foot, com_to_hip, torso_length, inertia_leg, inertia_torso, slope, g]
#   qdd = [q_stance_ddot, q_swing_ddot, q_torso_ddot]
#   q = [q_stance, q_swing, q_torso, x_hip, y_hip]
# kernels:
#   accel(q, qd, p)
#   accel_jac(q, qd, p)
#   mass_matrix(q, p)
#   coriolis(q, qd, p)
#   gravity(q, p)
#   bias(q, qd, p)
#   dmass(q, p)
#   dbias_dq(q, qd, p)
#   dbias_dqd(q, qd, p)
#   kinetic(q, qd, p)
#   potential(q, p)
#   points(q, p)
#   hip_jac(q, p)
#   ground_reaction(q, qd, qdd, p)
#   ext_mass_matrix(q, p)
#   ext_swing_contact_jac(q, p)
#   ext_stance_contact_jac(q, p)
"""Generated numba kernels for the `three_link` model.

Grizzle's three-link walker (legs and torso, hip actuators): pinned dynamics, ground reaction, floating-base heel-strike model.
"""

import math  # noqa: F401

from walker._jit import njit

KERNEL_HASH = "465e18f0b2825de7b1a416701aa361092e6d3db4a27b327992c27d8b1ae9763a"
ARGUMENT_ORDER = {'accel': {'q': ('q_stance', 'q_swing', 'q_torso'), 'qd': ('q_stance_dot', 'q_swing_dot', 'q_torso_dot'), 'p': ('mass_hip', 'mass_leg', 'mass_torso', 'com_from_foot', 'com_to_hip', 'torso_length', 'inertia_leg', 'inertia_torso', 'slope', 'g')}, 'accel_jac': {'q': ('q_stance', 'q_swing', 'q_torso'), 'qd': ('q_stance_dot', 'q_swing_dot', 'q_torso_dot'), 'p': ('mass_hip', 'mass_leg', 'mass_torso', 'com_from_foot', 'com_to_hip', 'torso_length', 'inertia_leg', 'inertia_torso', 'slope', 'g')}, 'mass_matrix': {'q': ('q_stance', 'q_swing', 'q_torso'), 'p': ('mass_hip', 'mass_leg', 'mass_torso', 'com_from_foot', 'com_to_hip', 'torso_length', 'inertia_leg', 'inertia_torso', 'slope', 'g')}, 'coriolis': {'q': ('q_stance', 'q_swing', 'q_torso'), 'qd': ('q_stance_dot', 'q_swing_dot', 'q_torso_dot'), 'p': ('mass_hip', 'mass_leg', 'mass_torso', 'com_from_foot', 'com_to_hip', 'torso_length', 'inertia_leg', 'inertia_torso', 'slope', 'g')}, 'gravity': {'q': ('q_stance', 'q_swing', 'q_torso'), 'p': ('mass_hip', 'mass_leg', 'mass_torso', 'com_from_foot', 'com_to_hip', 'torso_length', 'inertia_leg', 'inertia_torso', 'slope', 'g')}, 'bias': {'q': ('q_stance', 'q_swing', 'q_torso'), 'qd': ('q_stance_dot', 'q_swing_dot', 'q_torso_dot'), 'p': ('mass_hip', 'mass_leg', 'mass_torso', 'com_from_foot', 'com_to_hip', 'torso_length', 'inertia_leg', 'inertia_torso', 'slope', 'g')}, 'dmass': {'q': ('q_stance', 'q_swing', 'q_torso'), 'p': ('mass_hip', 'mass_leg', 'mass_torso', 'com_from_foot', 'com_to_hip', 'torso_length', 'inertia_leg', 'inertia_torso', 'slope', 'g')}, 'dbias_dq': {'q': ('q_stance', 'q_swing', 'q_torso'), 'qd': ('q_stance_dot', 'q_swing_dot', 'q_torso_dot'), 'p': ('mass_hip', 'mass_leg', 'mass_torso', 'com_from_foot', 'com_to_hip', 'torso_length', 'inertia_leg', 'inertia_torso', 'slope', 'g')}, 'dbias_dqd': {'q': ('q_stance', 'q_swing', 'q_torso'), 'qd': ('q_stance_dot', 'q_swing_dot', 'q_torso_dot'), 'p': ('mass_hip', 'mass_leg', 'mass_torso', 'com_from_foot', 'com_to_hip', 'torso_length', 'inertia_leg', 'inertia_torso', 'slope', 'g')}, 'kinetic': {'q': ('q_stance', 'q_swing', 'q_torso'), 'qd': ('q_stance_dot', 'q_swing_dot', 'q_torso_dot'), 'p': ('mass_hip', 'mass_leg', 'mass_torso', 'com_from_foot', 'com_to_hip', 'torso_length', 'inertia_leg', 'inertia_torso', 'slope', 'g')}, 'potential': {'q': ('q_stance', 'q_swing', 'q_torso'), 'p': ('mass_hip', 'mass_leg', 'mass_torso', 'com_from_foot', 'com_to_hip', 'torso_length', 'inertia_leg', 'inertia_torso', 'slope', 'g')}, 'points': {'q': ('q_stance', 'q_swing', 'q_torso'), 'p': ('mass_hip', 'mass_leg', 'mass_torso', 'com_from_foot', 'com_to_hip', 'torso_length', 'inertia_leg', 'inertia_torso', 'slope', 'g')}, 'hip_jac': {'q': ('q_stance', 'q_swing', 'q_torso'), 'p': ('mass_hip', 'mass_leg', 'mass_torso', 'com_from_foot', 'com_to_hip', 'torso_length', 'inertia_leg', 'inertia_torso', 'slope', 'g')}, 'ground_reaction': {'q': ('q_stance', 'q_swing', 'q_torso'), 'qd': ('q_stance_dot', 'q_swing_dot', 'q_torso_dot'), 'qdd': ('q_stance_ddot', 'q_swing_ddot', 'q_torso_ddot'), 'p': ('mass_hip', 'mass_leg', 'mass_torso', 'com_from_foot', 'com_to_hip', 'torso_length', 'inertia_leg', 'inertia_torso', 'slope', 'g')}, 'ext_mass_matrix': {'q': ('q_stance', 'q_swing', 'q_torso', 'x_hip', 'y_hip'), 'p': ('mass_hip', 'mass_leg', 'mass_torso', 'com_from_foot', 'com_to_hip', 'torso_length', 'inertia_leg', 'inertia_torso', 'slope', 'g')}, 'ext_swing_contact_jac': {'q': ('q_stance', 'q_swing', 'q_torso', 'x_hip', 'y_hip'), 'p': ('mass_hip', 'mass_leg', 'mass_torso', 'com_from_foot', 'com_to_hip', 'torso_length', 'inertia_leg', 'inertia_torso', 'slope', 'g')}, 'ext_stance_contact_jac': {'q': ('q_stance', 'q_swing', 'q_torso', 'x_hip', 'y_hip'), 'p': ('mass_hip', 'mass_leg', 'mass_torso', 'com_from_foot', 'com_to_hip', 'torso_length', 'inertia_leg', 'inertia_torso', 'slope', 'g')}}

@njit(cache=True, error_model="numpy")
def accel(q, qd, p, out):
    """Accelerations qdd = -D^-1 h by unrolled Cholesky, out (>= n,)."""
    q_stance = q[0]
    q_swing = q[1]
    q_torso = q[2]
    q_stance_dot = qd[0]
    q_swing_dot = qd[1]
    q_torso_dot = qd[2]
    mass_hip = p[0]
    mass_leg = p[1]
    mass_torso = p[2]
    com_from_foot = p[3]
    com_to_hip = p[4]
    torso_length = p[5]
    inertia_leg = p[6]
    inertia_torso = p[7]
    g = p[9]
    x0 = math.sin(q_stance)
    x1 = x0*x0
    x2 = com_from_foot*com_from_foot
    x3 = mass_hip*x2
    x4 = math.cos(q_stance)
    x5 = x4*x4
    x6 = mass_torso*x2
    x7 = com_to_hip*com_to_hip
    x8 = mass_hip*x7
    x9 = mass_leg*x7
    x10 = mass_torso*x7
    x11 = 2*x1
    x12 = com_from_foot*com_to_hip
    x13 = mass_hip*x12
    x14 = 2*x5
    x15 = mass_leg*x12
    x16 = mass_torso*x12
    x17 = mass_leg*x2
    x18 = math.sin(q_swing)
    x19 = com_to_hip*x0
    x20 = com_from_foot*mass_leg*x19
    x21 = math.cos(q_swing)
    x22 = x0*x9
    x23 = math.sin(q_torso)
    x24 = mass_torso*torso_length
    x25 = x23*x24
    x26 = com_from_foot*x0
    x27 = math.cos(q_torso)
    x28 = x24*x27
    x29 = com_from_foot*x4
    x30 = com_to_hip*x4
    x31 = mass_torso*torso_length*torso_length
    x32 = x0*(com_from_foot + com_to_hip)
    x33 = g*x32
    x34 = g*mass_leg
    x35 = x19*x28 - x25*x29 - x25*x30 + x26*x28
    x36 = -com_from_foot*com_to_hip*mass_leg*x18*x4 - mass_leg*x18*x4*x7 + x20*x21 + x21*x22
    x37 = q_stance_dot*q_stance_dot
    d00 = inertia_leg + x1*x10 + x1*x3 + x1*x6 + x1*x8 + x1*x9 + x10*x5 + x11*x13 + x11*x15 + x11*x16 + x11*x17 + x13*x14 + x14*x15 + x14*x16 + x14*x17 + x3*x5 + x5*x6 + x5*x8 + x5*x9
    d10 = -x15*x21*x4 - x18*x20 - x18*x22 - x21*x4*x9
    d11 = inertia_leg + x18*x18*x9 + x21*x21*x9
    d20 = x19*x25 + x25*x26 + x28*x29 + x28*x30
    d21 = 0
    d22 = inertia_torso + x23*x23*x31 + x27*x27*x31
    h0 = g*mass_leg*(x19 - x32) - mass_hip*x33 - mass_torso*x33 - q_swing_dot*q_swing_dot*x36 + q_torso_dot*q_torso_dot*x35 - x32*x34
    h1 = com_to_hip*x18*x34 + x36*x37
    h2 = -g*x25 - x35*x37
    l00 = math.sqrt(d00)
    l10 = (d10)/l00
    l20 = (d20)/l00
    l11 = math.sqrt(d11 - l10*l10)
    l21 = (d21 - l20*l10)/l11
    l22 = math.sqrt(d22 - l20*l20 - l21*l21)
    z0_y = (-h0)/l00
    z1_y = (-h1 - l10*z0_y)/l11
    z2_y = (-h2 - l20*z0_y - l21*z1_y)/l22
    z2 = (z2_y)/l22
    z1 = (z1_y - l21*z2)/l11
    z0 = (z0_y - l10*z1 - l20*z2)/l00
    out[0] = z0
    out[1] = z1
    out[2] = z2


@njit(cache=True, error_model="numpy")
def accel_jac(q, qd, p, out):
    """d qdd / d (q, qd), out (n, 2n), fused with the Cholesky solve."""
    q_stance = q[0]
    q_swing = q[1]
    q_torso = q[2]
    q_stance_dot = qd[0]
    q_swing_dot = qd[1]
    q_torso_dot = qd[2]
    mass_hip = p[0]
    mass_leg = p[1]
    mass_torso = p[2]
    com_from_foot = p[3]
    com_to_hip = p[4]
    torso_length = p[5]
    inertia_leg = p[6]
    inertia_torso = p[7]
    g = p[9]
    x0 = math.sin(q_stance)
    x1 = x0*x0
    x2 = com_from_foot*com_from_foot
    x3 = mass_hip*x2
    x4 = math.cos(q_stance)
    x5 = x4*x4
    x6 = mass_torso*x2
    x7 = com_to_hip*com_to_hip
    x8 = mass_hip*x7
    x9 = mass_leg*x7
    x10 = mass_torso*x7
    x11 = 2*x1
    x12 = com_from_foot*com_to_hip
    x13 = mass_hip*x12
    x14 = 2*x5
    x15 = mass_leg*x12
    x16 = mass_torso*x12
    x17 = mass_leg*x2
    x18 = math.sin(q_swing)
    x19 = com_to_hip*x0
    x20 = com_from_foot*mass_leg
    x21 = x19*x20
    x22 = math.cos(q_swing)
    x23 = com_to_hip*x4
    x24 = x0*x9
    x25 = x18*x21 + x18*x24 + x20*x22*x23 + x22*x4*x9
    x26 = -x25
    x27 = math.sin(q_torso)
    x28 = mass_torso*torso_length
    x29 = com_from_foot*x28
    x30 = x27*x29
    x31 = math.cos(q_torso)
    x32 = x29*x31
    x33 = x27*x28
    x34 = x28*x31
    x35 = x0*x30 + x19*x33 + x23*x34 + x32*x4
    x36 = mass_torso*torso_length*torso_length
    x37 = com_from_foot + com_to_hip
    x38 = x0*x37
    x39 = g*x38
    x40 = g*mass_leg
    x41 = q_torso_dot*q_torso_dot
    x42 = x0*x32 + x19*x34 - x23*x33 - x30*x4
    x43 = q_swing_dot*q_swing_dot
    x44 = -com_from_foot*com_to_hip*mass_leg*x18*x4 - mass_leg*x18*x4*x7 + x21*x22 + x22*x24
    x45 = -x44
    x46 = com_to_hip*x40
    x47 = q_stance_dot*q_stance_dot
    x48 = g*mass_torso
    x49 = torso_length*x48
    x50 = -x42
    x51 = x37*x4
    x52 = 2*q_stance_dot
    x53 = -x35
    d00 = inertia_leg + x1*x10 + x1*x3 + x1*x6 + x1*x8 + x1*x9 + x10*x5 + x11*x13 + x11*x15 + x11*x16 + x11*x17 + x13*x14 + x14*x15 + x14*x16 + x14*x17 + x3*x5 + x5*x6 + x5*x8 + x5*x9
    d10 = x26
    d11 = inertia_leg + x18*x18*x9 + x22*x22*x9
    d20 = x35
    d21 = 0
    d22 = inertia_torso + x27*x27*x36 + x31*x31*x36
    h0 = g*mass_leg*(x19 - x38) - mass_hip*x39 - mass_torso*x39 - x38*x40 + x41*x42 + x43*x45
    h1 = x18*x46 + x44*x47
    h2 = -x27*x49 + x47*x50
    dD0_00 = 0
    dD0_10 = x44
    dD0_11 = 0
    dD0_20 = x50
    dD0_21 = 0
    dD0_22 = 0
    dD1_00 = 0
    dD1_10 = x45
    dD1_11 = 0
    dD1_20 = 0
    dD1_21 = 0
    dD1_22 = 0
    dD2_00 = 0
    dD2_10 = 0
    dD2_11 = 0
    dD2_20 = x42
    dD2_21 = 0
    dD2_22 = 0
    hq0_0 = -g*mass_hip*x51 + g*mass_leg*(x23 - x51) + x26*x43 + x35*x41 - x40*x51 - x48*x51
    hv0_0 = 0
    hq1_0 = x25*x47
    hv1_0 = x44*x52
    hq2_0 = x47*x53
    hv2_0 = x50*x52
    hq0_1 = x25*x43
    hv0_1 = 2*q_swing_dot*x45
    hq1_1 = x22*x46 + x26*x47
    hv1_1 = 0
    hq2_1 = 0
    hv2_1 = 0
    hq0_2 = x41*x53
    hv0_2 = 2*q_torso_dot*x42
    hq1_2 = 0
    hv1_2 = 0
    hq2_2 = -x31*x49 + x35*x47
    hv2_2 = 0
    l00 = math.sqrt(d00)
    l10 = (d10)/l00
    l20 = (d20)/l00
    l11 = math.sqrt(d11 - l10*l10)
    l21 = (d21 - l20*l10)/l11
    l22 = math.sqrt(d22 - l20*l20 - l21*l21)
    a0_y = (-h0)/l00
    a1_y = (-h1 - l10*a0_y)/l11
    a2_y = (-h2 - l20*a0_y - l21*a1_y)/l22
    a2 = (a2_y)/l22
    a1 = (a1_y - l21*a2)/l11
    a0 = (a0_y - l10*a1 - l20*a2)/l00
    jq0_0_y = (-(hq0_0 + dD0_00*a0 + dD0_10*a1 + dD0_20*a2))/l00
    jq1_0_y = (-(hq1_0 + dD0_10*a0 + dD0_11*a1 + dD0_21*a2) - l10*jq0_0_y)/l11
    jq2_0_y = (-(hq2_0 + dD0_20*a0 + dD0_21*a1 + dD0_22*a2) - l20*jq0_0_y - l21*jq1_0_y)/l22
    jq2_0 = (jq2_0_y)/l22
    jq1_0 = (jq1_0_y - l21*jq2_0)/l11
    jq0_0 = (jq0_0_y - l10*jq1_0 - l20*jq2_0)/l00
    jv0_0_y = (-hv0_0)/l00
    jv1_0_y = (-hv1_0 - l10*jv0_0_y)/l11
    jv2_0_y = (-hv2_0 - l20*jv0_0_y - l21*jv1_0_y)/l22
    jv2_0 = (jv2_0_y)/l22
    jv1_0 = (jv1_0_y - l21*jv2_0)/l11
    jv0_0 = (jv0_0_y - l10*jv1_0 - l20*jv2_0)/l00
    jq0_1_y = (-(hq0_1 + dD1_00*a0 + dD1_10*a1 + dD1_20*a2))/l00
    jq1_1_y = (-(hq1_1 + dD1_10*a0 + dD1_11*a1 + dD1_21*a2) - l10*jq0_1_y)/l11
    jq2_1_y = (-(hq2_1 + dD1_20*a0 + dD1_21*a1 + dD1_22*a2) - l20*jq0_1_y - l21*jq1_1_y)/l22
    jq2_1 = (jq2_1_y)/l22
    jq1_1 = (jq1_1_y - l21*jq2_1)/l11
    jq0_1 = (jq0_1_y - l10*jq1_1 - l20*jq2_1)/l00
    jv0_1_y = (-hv0_1)/l00
    jv1_1_y = (-hv1_1 - l10*jv0_1_y)/l11
    jv2_1_y = (-hv2_1 - l20*jv0_1_y - l21*jv1_1_y)/l22
    jv2_1 = (jv2_1_y)/l22
    jv1_1 = (jv1_1_y - l21*jv2_1)/l11
    jv0_1 = (jv0_1_y - l10*jv1_1 - l20*jv2_1)/l00
    jq0_2_y = (-(hq0_2 + dD2_00*a0 + dD2_10*a1 + dD2_20*a2))/l00
    jq1_2_y = (-(hq1_2 + dD2_10*a0 + dD2_11*a1 + dD2_21*a2) - l10*jq0_2_y)/l11
    jq2_2_y = (-(hq2_2 + dD2_20*a0 + dD2_21*a1 + dD2_22*a2) - l20*jq0_2_y - l21*jq1_2_y)/l22
    jq2_2 = (jq2_2_y)/l22
    jq1_2 = (jq1_2_y - l21*jq2_2)/l11
    jq0_2 = (jq0_2_y - l10*jq1_2 - l20*jq2_2)/l00
    jv0_2_y = (-hv0_2)/l00
    jv1_2_y = (-hv1_2 - l10*jv0_2_y)/l11
    jv2_2_y = (-hv2_2 - l20*jv0_2_y - l21*jv1_2_y)/l22
    jv2_2 = (jv2_2_y)/l22
    jv1_2 = (jv1_2_y - l21*jv2_2)/l11
    jv0_2 = (jv0_2_y - l10*jv1_2 - l20*jv2_2)/l00
    out[0, 0] = jq0_0
    out[0, 3] = jv0_0
    out[0, 1] = jq0_1
    out[0, 4] = jv0_1
    out[0, 2] = jq0_2
    out[0, 5] = jv0_2
    out[1, 0] = jq1_0
    out[1, 3] = jv1_0
    out[1, 1] = jq1_1
    out[1, 4] = jv1_1
    out[1, 2] = jq1_2
    out[1, 5] = jv1_2
    out[2, 0] = jq2_0
    out[2, 3] = jv2_0
    out[2, 1] = jq2_1
    out[2, 4] = jv2_1
    out[2, 2] = jq2_2
    out[2, 5] = jv2_2


@njit(cache=True, error_model="numpy")
def mass_matrix(q, p, out):
    """Mass matrix D(q), out (n, n)."""
    q_stance = q[0]
    q_swing = q[1]
    q_torso = q[2]
    mass_hip = p[0]
    mass_leg = p[1]
    mass_torso = p[2]
    com_from_foot = p[3]
    com_to_hip = p[4]
    torso_length = p[5]
    inertia_leg = p[6]
    inertia_torso = p[7]
    x0 = math.sin(q_stance)
    x1 = x0*x0
    x2 = com_from_foot*com_from_foot
    x3 = mass_hip*x2
    x4 = math.cos(q_stance)
    x5 = x4*x4
    x6 = mass_torso*x2
    x7 = com_to_hip*com_to_hip
    x8 = mass_hip*x7
    x9 = mass_leg*x7
    x10 = mass_torso*x7
    x11 = 2*x1
    x12 = com_from_foot*com_to_hip
    x13 = mass_hip*x12
    x14 = 2*x5
    x15 = mass_leg*x12
    x16 = mass_torso*x12
    x17 = mass_leg*x2
    x18 = math.sin(q_swing)
    x19 = x0*x18
    x20 = math.cos(q_swing)
    x21 = x20*x4
    x22 = -x15*x19 - x15*x21 - x19*x9 - x21*x9
    x23 = mass_torso*torso_length
    x24 = com_from_foot*x23
    x25 = math.sin(q_torso)
    x26 = x0*x25
    x27 = math.cos(q_torso)
    x28 = x27*x4
    x29 = com_to_hip*x23
    x30 = x24*x26 + x24*x28 + x26*x29 + x28*x29
    x31 = mass_torso*torso_length*torso_length
    out[0, 0] = inertia_leg + x1*x10 + x1*x3 + x1*x6 + x1*x8 + x1*x9 + x10*x5 + x11*x13 + x11*x15 + x11*x16 + x11*x17 + x13*x14 + x14*x15 + x14*x16 + x14*x17 + x3*x5 + x5*x6 + x5*x8 + x5*x9
    out[0, 1] = x22
    out[0, 2] = x30
    out[1, 0] = x22
    out[1, 1] = inertia_leg + x18*x18*x9 + x20*x20*x9
    out[1, 2] = 0
    out[2, 0] = x30
    out[2, 1] = 0
    out[2, 2] = inertia_torso + x25*x25*x31 + x27*x27*x31


@njit(cache=True, error_model="numpy")
def coriolis(q, qd, p, out):
    """Coriolis matrix C(q, qd), out (n, n)."""
    q_stance = q[0]
    q_swing = q[1]
    q_torso = q[2]
    q_stance_dot = qd[0]
    q_swing_dot = qd[1]
    q_torso_dot = qd[2]
    mass_leg = p[1]
    mass_torso = p[2]
    com_from_foot = p[3]
    com_to_hip = p[4]
    torso_length = p[5]
    x0 = math.sin(q_stance)
    x1 = x0*math.cos(q_swing)
    x2 = com_to_hip*com_to_hip
    x3 = math.sin(q_swing)
    x4 = math.cos(q_stance)
    x5 = com_from_foot*com_to_hip*mass_leg*x1 - com_from_foot*com_to_hip*mass_leg*x3*x4 + mass_leg*x1*x2 - mass_leg*x2*x3*x4
    x6 = mass_torso*torso_length
    x7 = com_from_foot*x6
    x8 = x0*math.cos(q_torso)
    x9 = com_to_hip*x6
    x10 = x4*math.sin(q_torso)
    x11 = -x10*x7 - x10*x9 + x7*x8 + x8*x9
    out[0, 0] = 0
    out[0, 1] = -q_swing_dot*x5
    out[0, 2] = q_torso_dot*x11
    out[1, 0] = q_stance_dot*x5
    out[1, 1] = 0
    out[1, 2] = 0
    out[2, 0] = -q_stance_dot*x11
    out[2, 1] = 0
    out[2, 2] = 0


@njit(cache=True, error_model="numpy")
def gravity(q, p, out):
    """Gravity vector g(q) = dP/dq, out (n,)."""
    q_stance = q[0]
    q_swing = q[1]
    q_torso = q[2]
    mass_hip = p[0]
    mass_leg = p[1]
    mass_torso = p[2]
    com_from_foot = p[3]
    com_to_hip = p[4]
    torso_length = p[5]
    g = p[9]
    x0 = math.sin(q_stance)
    x1 = x0*(com_from_foot + com_to_hip)
    x2 = g*x1
    x3 = g*mass_leg
    out[0] = g*mass_leg*(com_to_hip*x0 - x1) - mass_hip*x2 - mass_torso*x2 - x1*x3
    out[1] = com_to_hip*x3*math.sin(q_swing)
    out[2] = -g*mass_torso*torso_length*math.sin(q_torso)


@njit(cache=True, error_model="numpy")
def bias(q, qd, p, out):
    """h(q, qd) = C(q, qd) qd + g(q), out (n,)."""
    q_stance = q[0]
    q_swing = q[1]
    q_torso = q[2]
    q_stance_dot = qd[0]
    q_swing_dot = qd[1]
    q_torso_dot = qd[2]
    mass_hip = p[0]
    mass_leg = p[1]
    mass_torso = p[2]
    com_from_foot = p[3]
    com_to_hip = p[4]
    torso_length = p[5]
    g = p[9]
    x0 = math.sin(q_stance)
    x1 = x0*(com_from_foot + com_to_hip)
    x2 = g*x1
    x3 = g*mass_leg
    x4 = com_to_hip*x0
    x5 = mass_torso*torso_length
    x6 = x5*math.cos(q_torso)
    x7 = math.cos(q_stance)
    x8 = x5*math.sin(q_torso)
    x9 = x7*x8
    x10 = com_from_foot*x0*x6 - com_from_foot*x9 - com_to_hip*x9 + x4*x6
    x11 = math.cos(q_swing)
    x12 = com_to_hip*com_to_hip
    x13 = math.sin(q_swing)
    x14 = -com_from_foot*com_to_hip*mass_leg*x13*x7 + com_from_foot*mass_leg*x11*x4 + mass_leg*x0*x11*x12 - mass_leg*x12*x13*x7
    x15 = q_stance_dot*q_stance_dot
    out[0] = g*mass_leg*(-x1 + x4) - mass_hip*x2 - mass_torso*x2 - q_swing_dot*q_swing_dot*x14 + q_torso_dot*q_torso_dot*x10 - x1*x3
    out[1] = com_to_hip*x13*x3 + x14*x15
    out[2] = -g*x8 - x10*x15


@njit(cache=True, error_model="numpy")
def dmass(q, p, out):
    """dD/dq_k for every k, out (n, n, n): out[k] = dD/dq_k."""
    q_stance = q[0]
    q_swing = q[1]
    q_torso = q[2]
    mass_leg = p[1]
    mass_torso = p[2]
    com_from_foot = p[3]
    com_to_hip = p[4]
    torso_length = p[5]
    x0 = math.sin(q_stance)
    x1 = x0*math.cos(q_swing)
    x2 = com_from_foot*com_to_hip*mass_leg
    x3 = com_to_hip*com_to_hip*mass_leg
    x4 = math.cos(q_stance)
    x5 = x4*math.sin(q_swing)
    x6 = x1*x2 + x1*x3 - x2*x5 - x3*x5
    x7 = mass_torso*torso_length
    x8 = x0*math.cos(q_torso)
    x9 = math.sin(q_torso)
    x10 = -com_from_foot*mass_torso*torso_length*x4*x9 + com_from_foot*x7*x8 - com_to_hip*mass_torso*torso_length*x4*x9 + com_to_hip*x7*x8
    x11 = -x10
    x12 = -x6
    out[0, 0, 0] = 0
    out[0, 0, 1] = x6
    out[0, 0, 2] = x11
    out[0, 1, 0] = x6
    out[0, 1, 1] = 0
    out[0, 1, 2] = 0
    out[0, 2, 0] = x11
    out[0, 2, 1] = 0
    out[0, 2, 2] = 0
    out[1, 0, 0] = 0
    out[1, 0, 1] = x12
    out[1, 0, 2] = 0
    out[1, 1, 0] = x12
    out[1, 1, 1] = 0
    out[1, 1, 2] = 0
    out[1, 2, 0] = 0
    out[1, 2, 1] = 0
    out[1, 2, 2] = 0
    out[2, 0, 0] = 0
    out[2, 0, 1] = 0
    out[2, 0, 2] = x10
    out[2, 1, 0] = 0
    out[2, 1, 1] = 0
    out[2, 1, 2] = 0
    out[2, 2, 0] = x10
    out[2, 2, 1] = 0
    out[2, 2, 2] = 0


@njit(cache=True, error_model="numpy")
def dbias_dq(q, qd, p, out):
    """dh/dq, out (n, n)."""
    q_stance = q[0]
    q_swing = q[1]
    q_torso = q[2]
    q_stance_dot = qd[0]
    q_swing_dot = qd[1]
    q_torso_dot = qd[2]
    mass_hip = p[0]
    mass_leg = p[1]
    mass_torso = p[2]
    com_from_foot = p[3]
    com_to_hip = p[4]
    torso_length = p[5]
    g = p[9]
    x0 = math.cos(q_stance)
    x1 = x0*(com_from_foot + com_to_hip)
    x2 = g*x1
    x3 = g*mass_leg
    x4 = com_to_hip*x0
    x5 = q_torso_dot*q_torso_dot
    x6 = math.sin(q_stance)
    x7 = mass_torso*torso_length
    x8 = x6*x7*math.sin(q_torso)
    x9 = x7*math.cos(q_torso)
    x10 = com_from_foot*x0*x9 + com_from_foot*x8 + com_to_hip*x8 + x4*x9
    x11 = q_swing_dot*q_swing_dot
    x12 = x6*math.sin(q_swing)
    x13 = com_from_foot*mass_leg
    x14 = math.cos(q_swing)
    x15 = com_to_hip*com_to_hip*mass_leg
    x16 = com_to_hip*x12*x13 + x0*x14*x15 + x12*x15 + x13*x14*x4
    x17 = -x16
    x18 = -x10
    x19 = q_stance_dot*q_stance_dot
    out[0, 0] = g*mass_leg*(-x1 + x4) - mass_hip*x2 - mass_torso*x2 - x1*x3 + x10*x5 + x11*x17
    out[0, 1] = x11*x16
    out[0, 2] = x18*x5
    out[1, 0] = x16*x19
    out[1, 1] = com_to_hip*x14*x3 + x17*x19
    out[1, 2] = 0
    out[2, 0] = x18*x19
    out[2, 1] = 0
    out[2, 2] = -g*x9 + x10*x19


@njit(cache=True, error_model="numpy")
def dbias_dqd(q, qd, p, out):
    """dh/dqd, out (n, n)."""
    q_stance = q[0]
    q_swing = q[1]
    q_torso = q[2]
    q_stance_dot = qd[0]
    q_swing_dot = qd[1]
    q_torso_dot = qd[2]
    mass_leg = p[1]
    mass_torso = p[2]
    com_from_foot = p[3]
    com_to_hip = p[4]
    torso_length = p[5]
    x0 = math.sin(q_stance)
    x1 = x0*math.cos(q_swing)
    x2 = com_to_hip*com_to_hip
    x3 = math.sin(q_swing)
    x4 = math.cos(q_stance)
    x5 = com_from_foot*com_to_hip*mass_leg*x1 - com_from_foot*com_to_hip*mass_leg*x3*x4 + mass_leg*x1*x2 - mass_leg*x2*x3*x4
    x6 = mass_torso*torso_length
    x7 = com_from_foot*x6
    x8 = x0*math.cos(q_torso)
    x9 = com_to_hip*x6
    x10 = x4*math.sin(q_torso)
    x11 = -x10*x7 - x10*x9 + x7*x8 + x8*x9
    x12 = 2*q_stance_dot
    out[0, 0] = 0
    out[0, 1] = -2*q_swing_dot*x5
    out[0, 2] = 2*q_torso_dot*x11
    out[1, 0] = x12*x5
    out[1, 1] = 0
    out[1, 2] = 0
    out[2, 0] = -x11*x12
    out[2, 1] = 0
    out[2, 2] = 0


@njit(cache=True, error_model="numpy")
def kinetic(q, qd, p):
    """Kinetic energy [J]."""
    q_stance = q[0]
    q_swing = q[1]
    q_torso = q[2]
    q_stance_dot = qd[0]
    q_swing_dot = qd[1]
    q_torso_dot = qd[2]
    mass_hip = p[0]
    mass_leg = p[1]
    mass_torso = p[2]
    com_from_foot = p[3]
    com_to_hip = p[4]
    torso_length = p[5]
    inertia_leg = p[6]
    inertia_torso = p[7]
    x0 = q_stance_dot*q_stance_dot
    x1 = ((1.0/2.0))*inertia_leg
    x2 = math.sin(q_stance)
    x3 = com_from_foot + com_to_hip
    x4 = x0*x3*x3
    x5 = math.cos(q_stance)
    x6 = com_to_hip*q_swing_dot
    x7 = x2*x3
    x8 = q_stance_dot*x7
    x9 = x3*x5
    x10 = q_stance_dot*x9
    x11 = ((1.0/2.0))*mass_leg
    x12 = q_torso_dot*torso_length
    return ((1.0/2.0))*inertia_torso*q_torso_dot*q_torso_dot + ((1.0/2.0))*mass_hip*(x2*x2*x4 + x4*x5*x5) + ((1.0/2.0))*mass_torso*((-x10 - x12*math.cos(q_torso))*(-x10 - x12*math.cos(q_torso)) + (-x12*math.sin(q_torso) - x8)*(-x12*math.sin(q_torso) - x8)) + q_swing_dot*q_swing_dot*x1 + x0*x1 + x11*(x0*(com_to_hip*x2 - x7)*(com_to_hip*x2 - x7) + x0*(com_to_hip*x5 - x9)*(com_to_hip*x5 - x9)) + x11*((-x10 + x6*math.cos(q_swing))*(-x10 + x6*math.cos(q_swing)) + (x6*math.sin(q_swing) - x8)*(x6*math.sin(q_swing) - x8))


@njit(cache=True, error_model="numpy")
def potential(q, p):
    """Potential energy [J] (y = 0 at the origin)."""
    q_stance = q[0]
    q_swing = q[1]
    q_torso = q[2]
    mass_hip = p[0]
    mass_leg = p[1]
    mass_torso = p[2]
    com_from_foot = p[3]
    com_to_hip = p[4]
    torso_length = p[5]
    g = p[9]
    x0 = math.cos(q_stance)
    x1 = com_from_foot + com_to_hip
    x2 = x0*x1
    x3 = -x0*x1
    x4 = g*mass_leg
    return g*mass_hip*x2 + g*mass_torso*(torso_length*math.cos(q_torso) + x2) + x4*(-com_to_hip*x0 - x3) + x4*(-com_to_hip*math.cos(q_swing) - x3)


@njit(cache=True, error_model="numpy")
def points(q, p, out):
    """Named points in the world frame, out (n_points, 2); names in POINTS."""
    q_stance = q[0]
    q_swing = q[1]
    q_torso = q[2]
    com_from_foot = p[3]
    com_to_hip = p[4]
    torso_length = p[5]
    x0 = com_from_foot + com_to_hip
    x1 = x0*math.sin(q_stance)
    x2 = x0*math.cos(q_stance)
    out[0, 0] = 0
    out[0, 1] = 0
    out[1, 0] = -x1
    out[1, 1] = x2
    out[2, 0] = x0*math.sin(q_swing) - x1
    out[2, 1] = -x0*math.cos(q_swing) + x2
    out[3, 0] = -torso_length*math.sin(q_torso) - x1
    out[3, 1] = torso_length*math.cos(q_torso) + x2


@njit(cache=True, error_model="numpy")
def hip_jac(q, p, out):
    """Jacobian of the hip position, out (2, n)."""
    q_stance = q[0]
    com_from_foot = p[3]
    com_to_hip = p[4]
    x0 = com_from_foot + com_to_hip
    out[0, 0] = -x0*math.cos(q_stance)
    out[0, 1] = 0
    out[0, 2] = 0
    out[1, 0] = -x0*math.sin(q_stance)
    out[1, 1] = 0
    out[1, 2] = 0


@njit(cache=True, error_model="numpy")
def ground_reaction(q, qd, qdd, p, out):
    """World-frame ground force on the stance foot (F_x, F_y) [N], out (2,)."""
    q_stance = q[0]
    q_swing = q[1]
    q_torso = q[2]
    q_stance_dot = qd[0]
    q_swing_dot = qd[1]
    q_torso_dot = qd[2]
    q_stance_ddot = qdd[0]
    q_swing_ddot = qdd[1]
    q_torso_ddot = qdd[2]
    mass_hip = p[0]
    mass_leg = p[1]
    mass_torso = p[2]
    com_from_foot = p[3]
    com_to_hip = p[4]
    torso_length = p[5]
    g = p[9]
    x0 = com_from_foot*mass_hip
    x1 = math.cos(q_stance)
    x2 = q_stance_ddot*x1
    x3 = mass_torso*x2
    x4 = com_to_hip*mass_hip
    x5 = com_to_hip*mass_leg
    x6 = mass_torso*torso_length
    x7 = x6*math.cos(q_torso)
    x8 = 2*com_from_foot*mass_leg
    x9 = math.cos(q_swing)
    x10 = math.sin(q_swing)
    x11 = q_swing_dot*q_swing_dot
    x12 = math.sin(q_stance)
    x13 = q_stance_dot*q_stance_dot
    x14 = math.sin(q_torso)
    x15 = q_torso_dot*q_torso_dot
    x16 = q_stance_ddot*x12
    x17 = com_from_foot*mass_torso
    x18 = com_to_hip*mass_torso
    x19 = x1*x13
    out[0] = com_from_foot*mass_hip*x12*x13 + 2*com_from_foot*mass_leg*x12*x13 + com_from_foot*mass_torso*x12*x13 - com_from_foot*x3 + com_to_hip*mass_hip*x12*x13 + com_to_hip*mass_leg*q_swing_ddot*x9 + com_to_hip*mass_leg*x12*x13 + com_to_hip*mass_torso*x12*x13 - com_to_hip*x3 + mass_torso*torso_length*x14*x15 - q_torso_ddot*x7 - x0*x2 - x10*x11*x5 - x2*x4 - x2*x5 - x2*x8
    out[1] = com_to_hip*mass_leg*q_swing_ddot*x10 + com_to_hip*mass_leg*x11*x9 + g*mass_hip + 2*g*mass_leg + g*mass_torso - q_torso_ddot*x14*x6 - x0*x16 - x0*x19 - x15*x7 - x16*x17 - x16*x18 - x16*x4 - x16*x5 - x16*x8 - x17*x19 - x18*x19 - x19*x4 - x19*x5 - x19*x8


@njit(cache=True, error_model="numpy")
def ext_mass_matrix(q, p, out):
    """Floating-base mass matrix, out (5, 5)."""
    q_stance = q[0]
    q_swing = q[1]
    q_torso = q[2]
    mass_hip = p[0]
    mass_leg = p[1]
    mass_torso = p[2]
    com_to_hip = p[4]
    torso_length = p[5]
    inertia_leg = p[6]
    inertia_torso = p[7]
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
    x10 = math.sin(q_torso)
    x11 = mass_torso*torso_length*torso_length
    x12 = math.cos(q_torso)
    x13 = mass_torso*torso_length
    x14 = -x12*x13
    x15 = -x10*x13
    x16 = mass_hip + 2*mass_leg + mass_torso
    out[0, 0] = inertia_leg + x0*x0*x1 + x1*x2*x2
    out[0, 1] = 0
    out[0, 2] = 0
    out[0, 3] = x4
    out[0, 4] = x5
    out[1, 0] = 0
    out[1, 1] = inertia_leg + x1*x6*x6 + x1*x7*x7
    out[1, 2] = 0
    out[1, 3] = x8
    out[1, 4] = x9
    out[2, 0] = 0
    out[2, 1] = 0
    out[2, 2] = inertia_torso + x10*x10*x11 + x11*x12*x12
    out[2, 3] = x14
    out[2, 4] = x15
    out[3, 0] = x4
    out[3, 1] = x8
    out[3, 2] = x14
    out[3, 3] = x16
    out[3, 4] = 0
    out[4, 0] = x5
    out[4, 1] = x9
    out[4, 2] = x15
    out[4, 3] = 0
    out[4, 4] = x16


@njit(cache=True, error_model="numpy")
def ext_swing_contact_jac(q, p, out):
    """Jacobian of the swing foot position, out (2, 5)."""
    q_swing = q[1]
    com_from_foot = p[3]
    com_to_hip = p[4]
    x0 = com_from_foot + com_to_hip
    out[0, 0] = 0
    out[0, 1] = x0*math.cos(q_swing)
    out[0, 2] = 0
    out[0, 3] = 1
    out[0, 4] = 0
    out[1, 0] = 0
    out[1, 1] = x0*math.sin(q_swing)
    out[1, 2] = 0
    out[1, 3] = 0
    out[1, 4] = 1


@njit(cache=True, error_model="numpy")
def ext_stance_contact_jac(q, p, out):
    """Jacobian of the stance foot position, out (2, 5)."""
    q_stance = q[0]
    com_from_foot = p[3]
    com_to_hip = p[4]
    x0 = com_from_foot + com_to_hip
    out[0, 0] = x0*math.cos(q_stance)
    out[0, 1] = 0
    out[0, 2] = 0
    out[0, 3] = 1
    out[0, 4] = 0
    out[1, 0] = x0*math.sin(q_stance)
    out[1, 1] = 0
    out[1, 2] = 0
    out[1, 3] = 0
    out[1, 4] = 1

POINTS = ('stance_contact', 'hip', 'swing_contact', 'torso')
