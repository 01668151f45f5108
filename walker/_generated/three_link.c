/* generated, do not edit: walker C kernels for `three_link`
 * input hash: sha256:a162faf890df7b6133d08ac36e4a7e368ab8541829f506da26532d7555d1285b
 * sympy 1.14.0; regenerate with `python scripts/generate_kernels.py`
 * argument order:
 *   q = [q_stance, q_swing, q_torso]
 *   qd = [q_stance_dot, q_swing_dot, q_torso_dot]
 *   p = [mass_hip, mass_leg, mass_torso, com_from_foot, com_to_hip, torso_length, inertia_leg, inertia_torso, slope, g, rotor_inertia]
 *   qdd = [q_stance_ddot, q_swing_ddot, q_torso_ddot]
 *   q = [q_stance, q_swing, q_torso, x_hip, y_hip]
 * kernels:
 *   wk_three_link_accel(q, qd, p, out)
 *   wk_three_link_accel_jac(q, qd, p, out)
 *   wk_three_link_mass_matrix(q, p, out)
 *   wk_three_link_coriolis(q, qd, p, out)
 *   wk_three_link_gravity(q, p, out)
 *   wk_three_link_bias(q, qd, p, out)
 *   wk_three_link_dmass(q, p, out)
 *   wk_three_link_dbias_dq(q, qd, p, out)
 *   wk_three_link_dbias_dqd(q, qd, p, out)
 *   wk_three_link_kinetic(q, qd, p)
 *   wk_three_link_potential(q, p)
 *   wk_three_link_points(q, p, out)
 *   wk_three_link_hip_jac(q, p, out)
 *   wk_three_link_ground_reaction(q, qd, qdd, p, out)
 *   wk_three_link_ext_mass_matrix(q, p, out)
 *   wk_three_link_ext_swing_contact_jac(q, p, out)
 *   wk_three_link_ext_stance_contact_jac(q, p, out)
 */
#include <math.h>

#include "three_link.h"

/* Accelerations qdd = -D^-1 h by unrolled Cholesky, out (>= n,). */
void wk_three_link_accel(const double *q, const double *qd, const double *p, double *out)
{
    const double q_stance = q[0];
    const double q_swing = q[1];
    const double q_torso = q[2];
    const double q_stance_dot = qd[0];
    const double q_swing_dot = qd[1];
    const double q_torso_dot = qd[2];
    const double mass_hip = p[0];
    const double mass_leg = p[1];
    const double mass_torso = p[2];
    const double com_from_foot = p[3];
    const double com_to_hip = p[4];
    const double torso_length = p[5];
    const double inertia_leg = p[6];
    const double inertia_torso = p[7];
    const double g = p[9];
    const double rotor_inertia = p[10];
    const double x0 = sin(q_stance);
    const double x1 = x0*x0;
    const double x2 = com_from_foot*com_from_foot;
    const double x3 = mass_hip*x2;
    const double x4 = cos(q_stance);
    const double x5 = x4*x4;
    const double x6 = mass_torso*x2;
    const double x7 = com_to_hip*com_to_hip;
    const double x8 = mass_hip*x7;
    const double x9 = mass_leg*x7;
    const double x10 = mass_torso*x7;
    const double x11 = 2.0*x1;
    const double x12 = com_from_foot*com_to_hip;
    const double x13 = mass_hip*x12;
    const double x14 = 2.0*x5;
    const double x15 = mass_leg*x12;
    const double x16 = mass_torso*x12;
    const double x17 = mass_leg*x2;
    const double x18 = sin(q_swing);
    const double x19 = com_to_hip*x0;
    const double x20 = com_from_foot*mass_leg*x19;
    const double x21 = cos(q_swing);
    const double x22 = x0*x9;
    const double x23 = sin(q_torso);
    const double x24 = mass_torso*torso_length;
    const double x25 = x23*x24;
    const double x26 = com_from_foot*x0;
    const double x27 = cos(q_torso);
    const double x28 = x24*x27;
    const double x29 = com_from_foot*x4;
    const double x30 = com_to_hip*x4;
    const double x31 = mass_torso*torso_length*torso_length;
    const double x32 = x0*(com_from_foot + com_to_hip);
    const double x33 = g*x32;
    const double x34 = g*mass_leg;
    const double x35 = x19*x28 - x25*x29 - x25*x30 + x26*x28;
    const double x36 = -com_from_foot*com_to_hip*mass_leg*x18*x4 - mass_leg*x18*x4*x7 + x20*x21 + x21*x22;
    const double x37 = q_stance_dot*q_stance_dot;
    const double xb0 = inertia_leg + x1*x10 + x1*x3 + x1*x6 + x1*x8 + x1*x9 + x10*x5 + x11*x13 + x11*x15 + x11*x16 + x11*x17 + x13*x14 + x14*x15 + x14*x16 + x14*x17 + x3*x5 + x5*x6 + x5*x8 + x5*x9;
    const double xb2 = inertia_leg + x18*x18*x9 + x21*x21*x9;
    const double xb3 = x19*x25 + x25*x26 + x28*x29 + x28*x30;
    const double xb4 = 0.0;
    const double xb5 = inertia_torso + x23*x23*x31 + x27*x27*x31;
    const double d00 = rotor_inertia + xb0;
    const double d10 = -x15*x21*x4 - x18*x20 - x18*x22 - x21*x4*x9;
    const double d11 = rotor_inertia + xb2;
    const double d20 = -rotor_inertia + xb3;
    const double d21 = -rotor_inertia + xb4;
    const double d22 = 2.0*rotor_inertia + xb5;
    const double h0 = g*mass_leg*(x19 - x32) - mass_hip*x33 - mass_torso*x33 - q_swing_dot*q_swing_dot*x36 + q_torso_dot*q_torso_dot*x35 - x32*x34;
    const double h1 = com_to_hip*x18*x34 + x36*x37;
    const double h2 = -g*x25 - x35*x37;
    const double l00 = sqrt(d00);
    const double l10 = (d10)/l00;
    const double l20 = (d20)/l00;
    const double l11 = sqrt(d11 - l10*l10);
    const double l21 = (d21 - l20*l10)/l11;
    const double l22 = sqrt(d22 - l20*l20 - l21*l21);
    const double z0_y = (-h0)/l00;
    const double z1_y = (-h1 - l10*z0_y)/l11;
    const double z2_y = (-h2 - l20*z0_y - l21*z1_y)/l22;
    const double z2 = (z2_y)/l22;
    const double z1 = (z1_y - l21*z2)/l11;
    const double z0 = (z0_y - l10*z1 - l20*z2)/l00;
    out[0] = z0;
    out[1] = z1;
    out[2] = z2;
}

/* d qdd / d (q, qd), out (n, 2n), fused with the Cholesky solve. */
void wk_three_link_accel_jac(const double *q, const double *qd, const double *p, double *out)
{
    const double q_stance = q[0];
    const double q_swing = q[1];
    const double q_torso = q[2];
    const double q_stance_dot = qd[0];
    const double q_swing_dot = qd[1];
    const double q_torso_dot = qd[2];
    const double mass_hip = p[0];
    const double mass_leg = p[1];
    const double mass_torso = p[2];
    const double com_from_foot = p[3];
    const double com_to_hip = p[4];
    const double torso_length = p[5];
    const double inertia_leg = p[6];
    const double inertia_torso = p[7];
    const double g = p[9];
    const double rotor_inertia = p[10];
    const double x0 = sin(q_stance);
    const double x1 = x0*x0;
    const double x2 = com_from_foot*com_from_foot;
    const double x3 = mass_hip*x2;
    const double x4 = cos(q_stance);
    const double x5 = x4*x4;
    const double x6 = mass_torso*x2;
    const double x7 = com_to_hip*com_to_hip;
    const double x8 = mass_hip*x7;
    const double x9 = mass_leg*x7;
    const double x10 = mass_torso*x7;
    const double x11 = 2.0*x1;
    const double x12 = com_from_foot*com_to_hip;
    const double x13 = mass_hip*x12;
    const double x14 = 2.0*x5;
    const double x15 = mass_leg*x12;
    const double x16 = mass_torso*x12;
    const double x17 = mass_leg*x2;
    const double x18 = sin(q_swing);
    const double x19 = com_to_hip*x0;
    const double x20 = com_from_foot*mass_leg;
    const double x21 = x19*x20;
    const double x22 = cos(q_swing);
    const double x23 = com_to_hip*x4;
    const double x24 = x0*x9;
    const double x25 = x18*x21 + x18*x24 + x20*x22*x23 + x22*x4*x9;
    const double x26 = -x25;
    const double x27 = sin(q_torso);
    const double x28 = mass_torso*torso_length;
    const double x29 = com_from_foot*x28;
    const double x30 = x27*x29;
    const double x31 = cos(q_torso);
    const double x32 = x29*x31;
    const double x33 = x27*x28;
    const double x34 = x28*x31;
    const double x35 = x0*x30 + x19*x33 + x23*x34 + x32*x4;
    const double x36 = mass_torso*torso_length*torso_length;
    const double x37 = com_from_foot + com_to_hip;
    const double x38 = x0*x37;
    const double x39 = g*x38;
    const double x40 = g*mass_leg;
    const double x41 = q_torso_dot*q_torso_dot;
    const double x42 = x0*x32 + x19*x34 - x23*x33 - x30*x4;
    const double x43 = q_swing_dot*q_swing_dot;
    const double x44 = -com_from_foot*com_to_hip*mass_leg*x18*x4 - mass_leg*x18*x4*x7 + x21*x22 + x22*x24;
    const double x45 = -x44;
    const double x46 = com_to_hip*x40;
    const double x47 = q_stance_dot*q_stance_dot;
    const double x48 = g*mass_torso;
    const double x49 = torso_length*x48;
    const double x50 = -x42;
    const double x51 = x37*x4;
    const double x52 = 2.0*q_stance_dot;
    const double x53 = -x35;
    const double xb0 = inertia_leg + x1*x10 + x1*x3 + x1*x6 + x1*x8 + x1*x9 + x10*x5 + x11*x13 + x11*x15 + x11*x16 + x11*x17 + x13*x14 + x14*x15 + x14*x16 + x14*x17 + x3*x5 + x5*x6 + x5*x8 + x5*x9;
    const double xb2 = inertia_leg + x18*x18*x9 + x22*x22*x9;
    const double xb3 = x35;
    const double xb4 = 0.0;
    const double xb5 = inertia_torso + x27*x27*x36 + x31*x31*x36;
    const double d00 = rotor_inertia + xb0;
    const double d10 = x26;
    const double d11 = rotor_inertia + xb2;
    const double d20 = -rotor_inertia + xb3;
    const double d21 = -rotor_inertia + xb4;
    const double d22 = 2.0*rotor_inertia + xb5;
    const double h0 = g*mass_leg*(x19 - x38) - mass_hip*x39 - mass_torso*x39 - x38*x40 + x41*x42 + x43*x45;
    const double h1 = x18*x46 + x44*x47;
    const double h2 = -x27*x49 + x47*x50;
    const double dD0_00 = 0.0;
    const double dD0_10 = x44;
    const double dD0_11 = 0.0;
    const double dD0_20 = x50;
    const double dD0_21 = 0.0;
    const double dD0_22 = 0.0;
    const double dD1_00 = 0.0;
    const double dD1_10 = x45;
    const double dD1_11 = 0.0;
    const double dD1_20 = 0.0;
    const double dD1_21 = 0.0;
    const double dD1_22 = 0.0;
    const double dD2_00 = 0.0;
    const double dD2_10 = 0.0;
    const double dD2_11 = 0.0;
    const double dD2_20 = x42;
    const double dD2_21 = 0.0;
    const double dD2_22 = 0.0;
    const double hq0_0 = -g*mass_hip*x51 + g*mass_leg*(x23 - x51) + x26*x43 + x35*x41 - x40*x51 - x48*x51;
    const double hv0_0 = 0.0;
    const double hq1_0 = x25*x47;
    const double hv1_0 = x44*x52;
    const double hq2_0 = x47*x53;
    const double hv2_0 = x50*x52;
    const double hq0_1 = x25*x43;
    const double hv0_1 = 2.0*q_swing_dot*x45;
    const double hq1_1 = x22*x46 + x26*x47;
    const double hv1_1 = 0.0;
    const double hq2_1 = 0.0;
    const double hv2_1 = 0.0;
    const double hq0_2 = x41*x53;
    const double hv0_2 = 2.0*q_torso_dot*x42;
    const double hq1_2 = 0.0;
    const double hv1_2 = 0.0;
    const double hq2_2 = -x31*x49 + x35*x47;
    const double hv2_2 = 0.0;
    const double l00 = sqrt(d00);
    const double l10 = (d10)/l00;
    const double l20 = (d20)/l00;
    const double l11 = sqrt(d11 - l10*l10);
    const double l21 = (d21 - l20*l10)/l11;
    const double l22 = sqrt(d22 - l20*l20 - l21*l21);
    const double a0_y = (-h0)/l00;
    const double a1_y = (-h1 - l10*a0_y)/l11;
    const double a2_y = (-h2 - l20*a0_y - l21*a1_y)/l22;
    const double a2 = (a2_y)/l22;
    const double a1 = (a1_y - l21*a2)/l11;
    const double a0 = (a0_y - l10*a1 - l20*a2)/l00;
    const double jq0_0_y = (-(hq0_0 + dD0_00*a0 + dD0_10*a1 + dD0_20*a2))/l00;
    const double jq1_0_y = (-(hq1_0 + dD0_10*a0 + dD0_11*a1 + dD0_21*a2) - l10*jq0_0_y)/l11;
    const double jq2_0_y = (-(hq2_0 + dD0_20*a0 + dD0_21*a1 + dD0_22*a2) - l20*jq0_0_y - l21*jq1_0_y)/l22;
    const double jq2_0 = (jq2_0_y)/l22;
    const double jq1_0 = (jq1_0_y - l21*jq2_0)/l11;
    const double jq0_0 = (jq0_0_y - l10*jq1_0 - l20*jq2_0)/l00;
    const double jv0_0_y = (-hv0_0)/l00;
    const double jv1_0_y = (-hv1_0 - l10*jv0_0_y)/l11;
    const double jv2_0_y = (-hv2_0 - l20*jv0_0_y - l21*jv1_0_y)/l22;
    const double jv2_0 = (jv2_0_y)/l22;
    const double jv1_0 = (jv1_0_y - l21*jv2_0)/l11;
    const double jv0_0 = (jv0_0_y - l10*jv1_0 - l20*jv2_0)/l00;
    const double jq0_1_y = (-(hq0_1 + dD1_00*a0 + dD1_10*a1 + dD1_20*a2))/l00;
    const double jq1_1_y = (-(hq1_1 + dD1_10*a0 + dD1_11*a1 + dD1_21*a2) - l10*jq0_1_y)/l11;
    const double jq2_1_y = (-(hq2_1 + dD1_20*a0 + dD1_21*a1 + dD1_22*a2) - l20*jq0_1_y - l21*jq1_1_y)/l22;
    const double jq2_1 = (jq2_1_y)/l22;
    const double jq1_1 = (jq1_1_y - l21*jq2_1)/l11;
    const double jq0_1 = (jq0_1_y - l10*jq1_1 - l20*jq2_1)/l00;
    const double jv0_1_y = (-hv0_1)/l00;
    const double jv1_1_y = (-hv1_1 - l10*jv0_1_y)/l11;
    const double jv2_1_y = (-hv2_1 - l20*jv0_1_y - l21*jv1_1_y)/l22;
    const double jv2_1 = (jv2_1_y)/l22;
    const double jv1_1 = (jv1_1_y - l21*jv2_1)/l11;
    const double jv0_1 = (jv0_1_y - l10*jv1_1 - l20*jv2_1)/l00;
    const double jq0_2_y = (-(hq0_2 + dD2_00*a0 + dD2_10*a1 + dD2_20*a2))/l00;
    const double jq1_2_y = (-(hq1_2 + dD2_10*a0 + dD2_11*a1 + dD2_21*a2) - l10*jq0_2_y)/l11;
    const double jq2_2_y = (-(hq2_2 + dD2_20*a0 + dD2_21*a1 + dD2_22*a2) - l20*jq0_2_y - l21*jq1_2_y)/l22;
    const double jq2_2 = (jq2_2_y)/l22;
    const double jq1_2 = (jq1_2_y - l21*jq2_2)/l11;
    const double jq0_2 = (jq0_2_y - l10*jq1_2 - l20*jq2_2)/l00;
    const double jv0_2_y = (-hv0_2)/l00;
    const double jv1_2_y = (-hv1_2 - l10*jv0_2_y)/l11;
    const double jv2_2_y = (-hv2_2 - l20*jv0_2_y - l21*jv1_2_y)/l22;
    const double jv2_2 = (jv2_2_y)/l22;
    const double jv1_2 = (jv1_2_y - l21*jv2_2)/l11;
    const double jv0_2 = (jv0_2_y - l10*jv1_2 - l20*jv2_2)/l00;
    out[0] = jq0_0;
    out[3] = jv0_0;
    out[1] = jq0_1;
    out[4] = jv0_1;
    out[2] = jq0_2;
    out[5] = jv0_2;
    out[6] = jq1_0;
    out[9] = jv1_0;
    out[7] = jq1_1;
    out[10] = jv1_1;
    out[8] = jq1_2;
    out[11] = jv1_2;
    out[12] = jq2_0;
    out[15] = jv2_0;
    out[13] = jq2_1;
    out[16] = jv2_1;
    out[14] = jq2_2;
    out[17] = jv2_2;
}

/* Mass matrix D(q), out (n, n). */
void wk_three_link_mass_matrix(const double *q, const double *p, double *out)
{
    const double q_stance = q[0];
    const double q_swing = q[1];
    const double q_torso = q[2];
    const double mass_hip = p[0];
    const double mass_leg = p[1];
    const double mass_torso = p[2];
    const double com_from_foot = p[3];
    const double com_to_hip = p[4];
    const double torso_length = p[5];
    const double inertia_leg = p[6];
    const double inertia_torso = p[7];
    const double rotor_inertia = p[10];
    const double x0 = sin(q_stance);
    const double x1 = x0*x0;
    const double x2 = com_from_foot*com_from_foot;
    const double x3 = mass_hip*x2;
    const double x4 = cos(q_stance);
    const double x5 = x4*x4;
    const double x6 = mass_torso*x2;
    const double x7 = com_to_hip*com_to_hip;
    const double x8 = mass_hip*x7;
    const double x9 = mass_leg*x7;
    const double x10 = mass_torso*x7;
    const double x11 = 2.0*x1;
    const double x12 = com_from_foot*com_to_hip;
    const double x13 = mass_hip*x12;
    const double x14 = 2.0*x5;
    const double x15 = mass_leg*x12;
    const double x16 = mass_torso*x12;
    const double x17 = mass_leg*x2;
    const double x18 = sin(q_swing);
    const double x19 = x0*x18;
    const double x20 = cos(q_swing);
    const double x21 = x20*x4;
    const double x22 = -x15*x19 - x15*x21 - x19*x9 - x21*x9;
    const double x23 = mass_torso*torso_length;
    const double x24 = com_from_foot*x23;
    const double x25 = sin(q_torso);
    const double x26 = x0*x25;
    const double x27 = cos(q_torso);
    const double x28 = x27*x4;
    const double x29 = com_to_hip*x23;
    const double x30 = x24*x26 + x24*x28 + x26*x29 + x28*x29;
    const double x31 = mass_torso*torso_length*torso_length;
    const double xb0 = inertia_leg + x1*x10 + x1*x3 + x1*x6 + x1*x8 + x1*x9 + x10*x5 + x11*x13 + x11*x15 + x11*x16 + x11*x17 + x13*x14 + x14*x15 + x14*x16 + x14*x17 + x3*x5 + x5*x6 + x5*x8 + x5*x9;
    const double xb2 = x30;
    const double xb4 = inertia_leg + x18*x18*x9 + x20*x20*x9;
    const double xb5 = 0.0;
    const double xb6 = x30;
    const double xb7 = 0.0;
    const double xb8 = inertia_torso + x25*x25*x31 + x27*x27*x31;
    out[0] = rotor_inertia + xb0;
    out[1] = x22;
    out[2] = -rotor_inertia + xb2;
    out[3] = x22;
    out[4] = rotor_inertia + xb4;
    out[5] = -rotor_inertia + xb5;
    out[6] = -rotor_inertia + xb6;
    out[7] = -rotor_inertia + xb7;
    out[8] = 2.0*rotor_inertia + xb8;
}

/* Coriolis matrix C(q, qd), out (n, n). */
void wk_three_link_coriolis(const double *q, const double *qd, const double *p, double *out)
{
    const double q_stance = q[0];
    const double q_swing = q[1];
    const double q_torso = q[2];
    const double q_stance_dot = qd[0];
    const double q_swing_dot = qd[1];
    const double q_torso_dot = qd[2];
    const double mass_leg = p[1];
    const double mass_torso = p[2];
    const double com_from_foot = p[3];
    const double com_to_hip = p[4];
    const double torso_length = p[5];
    const double x0 = sin(q_stance);
    const double x1 = x0*cos(q_swing);
    const double x2 = com_to_hip*com_to_hip;
    const double x3 = sin(q_swing);
    const double x4 = cos(q_stance);
    const double x5 = com_from_foot*com_to_hip*mass_leg*x1 - com_from_foot*com_to_hip*mass_leg*x3*x4 + mass_leg*x1*x2 - mass_leg*x2*x3*x4;
    const double x6 = mass_torso*torso_length;
    const double x7 = com_from_foot*x6;
    const double x8 = x0*cos(q_torso);
    const double x9 = com_to_hip*x6;
    const double x10 = x4*sin(q_torso);
    const double x11 = -x10*x7 - x10*x9 + x7*x8 + x8*x9;
    out[0] = 0.0;
    out[1] = -q_swing_dot*x5;
    out[2] = q_torso_dot*x11;
    out[3] = q_stance_dot*x5;
    out[4] = 0.0;
    out[5] = 0.0;
    out[6] = -q_stance_dot*x11;
    out[7] = 0.0;
    out[8] = 0.0;
}

/* Gravity vector g(q) = dP/dq, out (n,). */
void wk_three_link_gravity(const double *q, const double *p, double *out)
{
    const double q_stance = q[0];
    const double q_swing = q[1];
    const double q_torso = q[2];
    const double mass_hip = p[0];
    const double mass_leg = p[1];
    const double mass_torso = p[2];
    const double com_from_foot = p[3];
    const double com_to_hip = p[4];
    const double torso_length = p[5];
    const double g = p[9];
    const double x0 = sin(q_stance);
    const double x1 = x0*(com_from_foot + com_to_hip);
    const double x2 = g*x1;
    const double x3 = g*mass_leg;
    out[0] = g*mass_leg*(com_to_hip*x0 - x1) - mass_hip*x2 - mass_torso*x2 - x1*x3;
    out[1] = com_to_hip*x3*sin(q_swing);
    out[2] = -g*mass_torso*torso_length*sin(q_torso);
}

/* h(q, qd) = C(q, qd) qd + g(q), out (n,). */
void wk_three_link_bias(const double *q, const double *qd, const double *p, double *out)
{
    const double q_stance = q[0];
    const double q_swing = q[1];
    const double q_torso = q[2];
    const double q_stance_dot = qd[0];
    const double q_swing_dot = qd[1];
    const double q_torso_dot = qd[2];
    const double mass_hip = p[0];
    const double mass_leg = p[1];
    const double mass_torso = p[2];
    const double com_from_foot = p[3];
    const double com_to_hip = p[4];
    const double torso_length = p[5];
    const double g = p[9];
    const double x0 = sin(q_stance);
    const double x1 = x0*(com_from_foot + com_to_hip);
    const double x2 = g*x1;
    const double x3 = g*mass_leg;
    const double x4 = com_to_hip*x0;
    const double x5 = mass_torso*torso_length;
    const double x6 = x5*cos(q_torso);
    const double x7 = cos(q_stance);
    const double x8 = x5*sin(q_torso);
    const double x9 = x7*x8;
    const double x10 = com_from_foot*x0*x6 - com_from_foot*x9 - com_to_hip*x9 + x4*x6;
    const double x11 = cos(q_swing);
    const double x12 = com_to_hip*com_to_hip;
    const double x13 = sin(q_swing);
    const double x14 = -com_from_foot*com_to_hip*mass_leg*x13*x7 + com_from_foot*mass_leg*x11*x4 + mass_leg*x0*x11*x12 - mass_leg*x12*x13*x7;
    const double x15 = q_stance_dot*q_stance_dot;
    out[0] = g*mass_leg*(-x1 + x4) - mass_hip*x2 - mass_torso*x2 - q_swing_dot*q_swing_dot*x14 + q_torso_dot*q_torso_dot*x10 - x1*x3;
    out[1] = com_to_hip*x13*x3 + x14*x15;
    out[2] = -g*x8 - x10*x15;
}

/* dD/dq_k for every k, out (n, n, n): out[k] = dD/dq_k. */
void wk_three_link_dmass(const double *q, const double *p, double *out)
{
    const double q_stance = q[0];
    const double q_swing = q[1];
    const double q_torso = q[2];
    const double mass_leg = p[1];
    const double mass_torso = p[2];
    const double com_from_foot = p[3];
    const double com_to_hip = p[4];
    const double torso_length = p[5];
    const double x0 = sin(q_stance);
    const double x1 = x0*cos(q_swing);
    const double x2 = com_from_foot*com_to_hip*mass_leg;
    const double x3 = com_to_hip*com_to_hip*mass_leg;
    const double x4 = cos(q_stance);
    const double x5 = x4*sin(q_swing);
    const double x6 = x1*x2 + x1*x3 - x2*x5 - x3*x5;
    const double x7 = mass_torso*torso_length;
    const double x8 = x0*cos(q_torso);
    const double x9 = sin(q_torso);
    const double x10 = -com_from_foot*mass_torso*torso_length*x4*x9 + com_from_foot*x7*x8 - com_to_hip*mass_torso*torso_length*x4*x9 + com_to_hip*x7*x8;
    const double x11 = -x10;
    const double x12 = -x6;
    out[0] = 0.0;
    out[1] = x6;
    out[2] = x11;
    out[3] = x6;
    out[4] = 0.0;
    out[5] = 0.0;
    out[6] = x11;
    out[7] = 0.0;
    out[8] = 0.0;
    out[9] = 0.0;
    out[10] = x12;
    out[11] = 0.0;
    out[12] = x12;
    out[13] = 0.0;
    out[14] = 0.0;
    out[15] = 0.0;
    out[16] = 0.0;
    out[17] = 0.0;
    out[18] = 0.0;
    out[19] = 0.0;
    out[20] = x10;
    out[21] = 0.0;
    out[22] = 0.0;
    out[23] = 0.0;
    out[24] = x10;
    out[25] = 0.0;
    out[26] = 0.0;
}

/* dh/dq, out (n, n). */
void wk_three_link_dbias_dq(const double *q, const double *qd, const double *p, double *out)
{
    const double q_stance = q[0];
    const double q_swing = q[1];
    const double q_torso = q[2];
    const double q_stance_dot = qd[0];
    const double q_swing_dot = qd[1];
    const double q_torso_dot = qd[2];
    const double mass_hip = p[0];
    const double mass_leg = p[1];
    const double mass_torso = p[2];
    const double com_from_foot = p[3];
    const double com_to_hip = p[4];
    const double torso_length = p[5];
    const double g = p[9];
    const double x0 = cos(q_stance);
    const double x1 = x0*(com_from_foot + com_to_hip);
    const double x2 = g*x1;
    const double x3 = g*mass_leg;
    const double x4 = com_to_hip*x0;
    const double x5 = q_torso_dot*q_torso_dot;
    const double x6 = sin(q_stance);
    const double x7 = mass_torso*torso_length;
    const double x8 = x6*x7*sin(q_torso);
    const double x9 = x7*cos(q_torso);
    const double x10 = com_from_foot*x0*x9 + com_from_foot*x8 + com_to_hip*x8 + x4*x9;
    const double x11 = q_swing_dot*q_swing_dot;
    const double x12 = x6*sin(q_swing);
    const double x13 = com_from_foot*mass_leg;
    const double x14 = cos(q_swing);
    const double x15 = com_to_hip*com_to_hip*mass_leg;
    const double x16 = com_to_hip*x12*x13 + x0*x14*x15 + x12*x15 + x13*x14*x4;
    const double x17 = -x16;
    const double x18 = -x10;
    const double x19 = q_stance_dot*q_stance_dot;
    out[0] = g*mass_leg*(-x1 + x4) - mass_hip*x2 - mass_torso*x2 - x1*x3 + x10*x5 + x11*x17;
    out[1] = x11*x16;
    out[2] = x18*x5;
    out[3] = x16*x19;
    out[4] = com_to_hip*x14*x3 + x17*x19;
    out[5] = 0.0;
    out[6] = x18*x19;
    out[7] = 0.0;
    out[8] = -g*x9 + x10*x19;
}

/* dh/dqd, out (n, n). */
void wk_three_link_dbias_dqd(const double *q, const double *qd, const double *p, double *out)
{
    const double q_stance = q[0];
    const double q_swing = q[1];
    const double q_torso = q[2];
    const double q_stance_dot = qd[0];
    const double q_swing_dot = qd[1];
    const double q_torso_dot = qd[2];
    const double mass_leg = p[1];
    const double mass_torso = p[2];
    const double com_from_foot = p[3];
    const double com_to_hip = p[4];
    const double torso_length = p[5];
    const double x0 = sin(q_stance);
    const double x1 = x0*cos(q_swing);
    const double x2 = com_to_hip*com_to_hip;
    const double x3 = sin(q_swing);
    const double x4 = cos(q_stance);
    const double x5 = com_from_foot*com_to_hip*mass_leg*x1 - com_from_foot*com_to_hip*mass_leg*x3*x4 + mass_leg*x1*x2 - mass_leg*x2*x3*x4;
    const double x6 = mass_torso*torso_length;
    const double x7 = com_from_foot*x6;
    const double x8 = x0*cos(q_torso);
    const double x9 = com_to_hip*x6;
    const double x10 = x4*sin(q_torso);
    const double x11 = -x10*x7 - x10*x9 + x7*x8 + x8*x9;
    const double x12 = 2.0*q_stance_dot;
    out[0] = 0.0;
    out[1] = -2.0*q_swing_dot*x5;
    out[2] = 2.0*q_torso_dot*x11;
    out[3] = x12*x5;
    out[4] = 0.0;
    out[5] = 0.0;
    out[6] = -x11*x12;
    out[7] = 0.0;
    out[8] = 0.0;
}

/* Kinetic energy [J]. */
double wk_three_link_kinetic(const double *q, const double *qd, const double *p)
{
    const double q_stance = q[0];
    const double q_swing = q[1];
    const double q_torso = q[2];
    const double q_stance_dot = qd[0];
    const double q_swing_dot = qd[1];
    const double q_torso_dot = qd[2];
    const double mass_hip = p[0];
    const double mass_leg = p[1];
    const double mass_torso = p[2];
    const double com_from_foot = p[3];
    const double com_to_hip = p[4];
    const double torso_length = p[5];
    const double inertia_leg = p[6];
    const double inertia_torso = p[7];
    const double rotor_inertia = p[10];
    const double x0 = q_stance_dot*q_stance_dot;
    const double x1 = ((1.0/2.0))*inertia_leg;
    const double x2 = sin(q_stance);
    const double x3 = com_from_foot + com_to_hip;
    const double x4 = x0*x3*x3;
    const double x5 = cos(q_stance);
    const double x6 = com_to_hip*q_swing_dot;
    const double x7 = x2*x3;
    const double x8 = q_stance_dot*x7;
    const double x9 = x3*x5;
    const double x10 = q_stance_dot*x9;
    const double x11 = ((1.0/2.0))*mass_leg;
    const double x12 = q_torso_dot*torso_length;
    const double xa0 = -q_torso_dot;
    const double xb0 = ((1.0/2.0))*inertia_torso*q_torso_dot*q_torso_dot + ((1.0/2.0))*mass_hip*(x2*x2*x4 + x4*x5*x5) + ((1.0/2.0))*mass_torso*((-x10 - x12*cos(q_torso))*(-x10 - x12*cos(q_torso)) + (-x12*sin(q_torso) - x8)*(-x12*sin(q_torso) - x8)) + q_swing_dot*q_swing_dot*x1 + x0*x1 + x11*(x0*(com_to_hip*x2 - x7)*(com_to_hip*x2 - x7) + x0*(com_to_hip*x5 - x9)*(com_to_hip*x5 - x9)) + x11*((-x10 + x6*cos(q_swing))*(-x10 + x6*cos(q_swing)) + (x6*sin(q_swing) - x8)*(x6*sin(q_swing) - x8));
    return rotor_inertia*(((1.0/2.0))*(q_stance_dot + xa0)*(q_stance_dot + xa0) + ((1.0/2.0))*(q_swing_dot + xa0)*(q_swing_dot + xa0)) + xb0;
}

/* Potential energy [J] (y = 0 at the origin). */
double wk_three_link_potential(const double *q, const double *p)
{
    const double q_stance = q[0];
    const double q_swing = q[1];
    const double q_torso = q[2];
    const double mass_hip = p[0];
    const double mass_leg = p[1];
    const double mass_torso = p[2];
    const double com_from_foot = p[3];
    const double com_to_hip = p[4];
    const double torso_length = p[5];
    const double g = p[9];
    const double x0 = cos(q_stance);
    const double x1 = com_from_foot + com_to_hip;
    const double x2 = x0*x1;
    const double x3 = -x0*x1;
    const double x4 = g*mass_leg;
    return g*mass_hip*x2 + g*mass_torso*(torso_length*cos(q_torso) + x2) + x4*(-com_to_hip*x0 - x3) + x4*(-com_to_hip*cos(q_swing) - x3);
}

/* Named points in the world frame, out (n_points, 2); names in POINTS. */
void wk_three_link_points(const double *q, const double *p, double *out)
{
    const double q_stance = q[0];
    const double q_swing = q[1];
    const double q_torso = q[2];
    const double com_from_foot = p[3];
    const double com_to_hip = p[4];
    const double torso_length = p[5];
    const double x0 = com_from_foot + com_to_hip;
    const double x1 = x0*sin(q_stance);
    const double x2 = x0*cos(q_stance);
    out[0] = 0.0;
    out[1] = 0.0;
    out[2] = -x1;
    out[3] = x2;
    out[4] = x0*sin(q_swing) - x1;
    out[5] = -x0*cos(q_swing) + x2;
    out[6] = -torso_length*sin(q_torso) - x1;
    out[7] = torso_length*cos(q_torso) + x2;
}

/* Jacobian of the hip position, out (2, n). */
void wk_three_link_hip_jac(const double *q, const double *p, double *out)
{
    const double q_stance = q[0];
    const double com_from_foot = p[3];
    const double com_to_hip = p[4];
    const double x0 = com_from_foot + com_to_hip;
    out[0] = -x0*cos(q_stance);
    out[1] = 0.0;
    out[2] = 0.0;
    out[3] = -x0*sin(q_stance);
    out[4] = 0.0;
    out[5] = 0.0;
}

/* World-frame ground force on the stance foot (F_x, F_y) [N], out (2,). */
void wk_three_link_ground_reaction(const double *q, const double *qd, const double *qdd, const double *p, double *out)
{
    const double q_stance = q[0];
    const double q_swing = q[1];
    const double q_torso = q[2];
    const double q_stance_dot = qd[0];
    const double q_swing_dot = qd[1];
    const double q_torso_dot = qd[2];
    const double q_stance_ddot = qdd[0];
    const double q_swing_ddot = qdd[1];
    const double q_torso_ddot = qdd[2];
    const double mass_hip = p[0];
    const double mass_leg = p[1];
    const double mass_torso = p[2];
    const double com_from_foot = p[3];
    const double com_to_hip = p[4];
    const double torso_length = p[5];
    const double g = p[9];
    const double x0 = com_from_foot*mass_hip;
    const double x1 = cos(q_stance);
    const double x2 = q_stance_ddot*x1;
    const double x3 = mass_torso*x2;
    const double x4 = com_to_hip*mass_hip;
    const double x5 = com_to_hip*mass_leg;
    const double x6 = mass_torso*torso_length;
    const double x7 = x6*cos(q_torso);
    const double x8 = 2.0*com_from_foot*mass_leg;
    const double x9 = cos(q_swing);
    const double x10 = sin(q_swing);
    const double x11 = q_swing_dot*q_swing_dot;
    const double x12 = sin(q_stance);
    const double x13 = q_stance_dot*q_stance_dot;
    const double x14 = sin(q_torso);
    const double x15 = q_torso_dot*q_torso_dot;
    const double x16 = q_stance_ddot*x12;
    const double x17 = com_from_foot*mass_torso;
    const double x18 = com_to_hip*mass_torso;
    const double x19 = x1*x13;
    out[0] = com_from_foot*mass_hip*x12*x13 + 2.0*com_from_foot*mass_leg*x12*x13 + com_from_foot*mass_torso*x12*x13 - com_from_foot*x3 + com_to_hip*mass_hip*x12*x13 + com_to_hip*mass_leg*q_swing_ddot*x9 + com_to_hip*mass_leg*x12*x13 + com_to_hip*mass_torso*x12*x13 - com_to_hip*x3 + mass_torso*torso_length*x14*x15 - q_torso_ddot*x7 - x0*x2 - x10*x11*x5 - x2*x4 - x2*x5 - x2*x8;
    out[1] = com_to_hip*mass_leg*q_swing_ddot*x10 + com_to_hip*mass_leg*x11*x9 + g*mass_hip + 2.0*g*mass_leg + g*mass_torso - q_torso_ddot*x14*x6 - x0*x16 - x0*x19 - x15*x7 - x16*x17 - x16*x18 - x16*x4 - x16*x5 - x16*x8 - x17*x19 - x18*x19 - x19*x4 - x19*x5 - x19*x8;
}

/* Floating-base mass matrix, out (5, 5). */
void wk_three_link_ext_mass_matrix(const double *q, const double *p, double *out)
{
    const double q_stance = q[0];
    const double q_swing = q[1];
    const double q_torso = q[2];
    const double mass_hip = p[0];
    const double mass_leg = p[1];
    const double mass_torso = p[2];
    const double com_to_hip = p[4];
    const double torso_length = p[5];
    const double inertia_leg = p[6];
    const double inertia_torso = p[7];
    const double rotor_inertia = p[10];
    const double x0 = sin(q_stance);
    const double x1 = com_to_hip*com_to_hip*mass_leg;
    const double x2 = cos(q_stance);
    const double x3 = com_to_hip*mass_leg;
    const double x4 = x2*x3;
    const double x5 = x0*x3;
    const double x6 = sin(q_swing);
    const double x7 = cos(q_swing);
    const double x8 = x3*x7;
    const double x9 = x3*x6;
    const double x10 = sin(q_torso);
    const double x11 = mass_torso*torso_length*torso_length;
    const double x12 = cos(q_torso);
    const double x13 = mass_torso*torso_length;
    const double x14 = -x12*x13;
    const double x15 = -x10*x13;
    const double x16 = mass_hip + 2.0*mass_leg + mass_torso;
    const double xb0 = inertia_leg + x0*x0*x1 + x1*x2*x2;
    const double xb2 = 0.0;
    const double xb6 = inertia_leg + x1*x6*x6 + x1*x7*x7;
    const double xb7 = 0.0;
    const double xb10 = 0.0;
    const double xb11 = 0.0;
    const double xb12 = inertia_torso + x10*x10*x11 + x11*x12*x12;
    out[0] = rotor_inertia + xb0;
    out[1] = 0.0;
    out[2] = -rotor_inertia + xb2;
    out[3] = x4;
    out[4] = x5;
    out[5] = 0.0;
    out[6] = rotor_inertia + xb6;
    out[7] = -rotor_inertia + xb7;
    out[8] = x8;
    out[9] = x9;
    out[10] = -rotor_inertia + xb10;
    out[11] = -rotor_inertia + xb11;
    out[12] = 2.0*rotor_inertia + xb12;
    out[13] = x14;
    out[14] = x15;
    out[15] = x4;
    out[16] = x8;
    out[17] = x14;
    out[18] = x16;
    out[19] = 0.0;
    out[20] = x5;
    out[21] = x9;
    out[22] = x15;
    out[23] = 0.0;
    out[24] = x16;
}

/* Jacobian of the swing foot position, out (2, 5). */
void wk_three_link_ext_swing_contact_jac(const double *q, const double *p, double *out)
{
    const double q_swing = q[1];
    const double com_from_foot = p[3];
    const double com_to_hip = p[4];
    const double x0 = com_from_foot + com_to_hip;
    out[0] = 0.0;
    out[1] = x0*cos(q_swing);
    out[2] = 0.0;
    out[3] = 1.0;
    out[4] = 0.0;
    out[5] = 0.0;
    out[6] = x0*sin(q_swing);
    out[7] = 0.0;
    out[8] = 0.0;
    out[9] = 1.0;
}

/* Jacobian of the stance foot position, out (2, 5). */
void wk_three_link_ext_stance_contact_jac(const double *q, const double *p, double *out)
{
    const double q_stance = q[0];
    const double com_from_foot = p[3];
    const double com_to_hip = p[4];
    const double x0 = com_from_foot + com_to_hip;
    out[0] = x0*cos(q_stance);
    out[1] = 0.0;
    out[2] = 0.0;
    out[3] = 1.0;
    out[4] = 0.0;
    out[5] = x0*sin(q_stance);
    out[6] = 0.0;
    out[7] = 0.0;
    out[8] = 0.0;
    out[9] = 1.0;
}
