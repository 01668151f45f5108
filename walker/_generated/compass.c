/* generated, do not edit: walker C kernels for `compass`
 * input hash: sha256:ad6c018dc54b381378e570439f1bf50a0c64d859e711bdf1df7716a42de0392a
 * sympy 1.14.0; regenerate with `python scripts/generate_kernels.py`
 * argument order:
 *   q = [q_stance, q_swing]
 *   qd = [q_stance_dot, q_swing_dot]
 *   p = [mass_hip, mass_leg, com_from_foot, com_to_hip, inertia_leg, foot_radius, slope, g, damping_hip, damping_ankle]
 *   q = [q_stance, q_swing, x_hip, y_hip]
 * kernels:
 *   wk_compass_accel(q, qd, p, out)
 *   wk_compass_accel_jac(q, qd, p, out)
 *   wk_compass_mass_matrix(q, p, out)
 *   wk_compass_coriolis(q, qd, p, out)
 *   wk_compass_gravity(q, p, out)
 *   wk_compass_bias(q, qd, p, out)
 *   wk_compass_forcing(q, qd, p, out)
 *   wk_compass_dmass(q, p, out)
 *   wk_compass_dbias_dq(q, qd, p, out)
 *   wk_compass_dbias_dqd(q, qd, p, out)
 *   wk_compass_kinetic(q, qd, p)
 *   wk_compass_potential(q, p)
 *   wk_compass_points(q, p, out)
 *   wk_compass_hip_jac(q, p, out)
 *   wk_compass_ext_mass_matrix(q, p, out)
 *   wk_compass_ext_swing_contact_jac(q, p, out)
 *   wk_compass_ext_stance_contact_jac(q, p, out)
 */
#include <math.h>

#include "compass.h"

/* Accelerations qdd = -D^-1 (h - Q), Q the joint-damping forcing, by unrolled Cholesky, out (>= n,). */
void wk_compass_accel(const double *q, const double *qd, const double *p, double *out)
{
    const double q_stance = q[0];
    const double q_swing = q[1];
    const double q_stance_dot = qd[0];
    const double q_swing_dot = qd[1];
    const double mass_hip = p[0];
    const double mass_leg = p[1];
    const double com_from_foot = p[2];
    const double com_to_hip = p[3];
    const double inertia_leg = p[4];
    const double foot_radius = p[5];
    const double slope = p[6];
    const double g = p[7];
    const double damping_hip = p[8];
    const double damping_ankle = p[9];
    const double x0 = sin(q_stance);
    const double x1 = x0*x0;
    const double x2 = com_from_foot*com_from_foot;
    const double x3 = mass_hip*x2;
    const double x4 = cos(q_stance);
    const double x5 = x4*x4;
    const double x6 = com_to_hip*com_to_hip;
    const double x7 = mass_hip*x6;
    const double x8 = mass_leg*x6;
    const double x9 = foot_radius*foot_radius;
    const double x10 = mass_hip*x9;
    const double x11 = sin(slope);
    const double x12 = x11*x11;
    const double x13 = cos(slope);
    const double x14 = x13*x13;
    const double x15 = 2.0*mass_hip;
    const double x16 = com_from_foot*com_to_hip;
    const double x17 = x15*x16;
    const double x18 = 2.0*mass_leg;
    const double x19 = x16*x18;
    const double x20 = com_from_foot*foot_radius;
    const double x21 = x1*x20;
    const double x22 = x20*x5;
    const double x23 = 4.0*mass_leg;
    const double x24 = com_to_hip*foot_radius;
    const double x25 = x15*x24;
    const double x26 = x18*x24;
    const double x27 = foot_radius*x11;
    const double x28 = com_from_foot*x27;
    const double x29 = x0*x28;
    const double x30 = x13*x4;
    const double x31 = x20*x30;
    const double x32 = com_to_hip*x27;
    const double x33 = x0*x32;
    const double x34 = x18*x2;
    const double x35 = x18*x9;
    const double x36 = x23*x9;
    const double x37 = sin(q_swing);
    const double x38 = com_to_hip*x37;
    const double x39 = mass_leg*x38;
    const double x40 = cos(q_swing);
    const double x41 = mass_leg*x4;
    const double x42 = x13*x24;
    const double x43 = mass_leg*x40;
    const double x44 = x0*x8;
    const double x45 = x4*x8;
    const double x46 = damping_hip*q_stance_dot;
    const double x47 = damping_hip*q_swing_dot;
    const double x48 = com_from_foot - foot_radius;
    const double x49 = g*mass_leg;
    const double x50 = g*(-x0*(com_to_hip + x48) + x27);
    const double x51 = x38*x41;
    const double x52 = com_from_foot*x51;
    const double x53 = x0*x43;
    const double x54 = x24*x53;
    const double x55 = x37*x45;
    const double x56 = x16*x53;
    const double x57 = foot_radius*x51;
    const double x58 = x40*x44;
    const double x59 = q_stance_dot*q_stance_dot;
    const double x60 = x0*x13*x20;
    const double x61 = mass_hip*x4;
    const double x62 = x0*x42;
    const double d00 = inertia_leg + 2.0*x0*x10*x11 + x0*x11*x36 + x1*x10 + x1*x17 + x1*x19 - x1*x25 - x1*x26 + x1*x3 + x1*x34 + x1*x35 + x1*x7 + x1*x8 + x10*x12 - 2.0*x10*x13*x4 + x10*x14 + x10*x5 + x12*x35 + x14*x35 - x15*x21 - x15*x22 - x15*x29 + x15*x31 - x15*x33 + x17*x5 - x18*x33 + x19*x5 - x21*x23 - x22*x23 - x23*x29 + x23*x31 + x25*x30 - x25*x5 + x26*x30 - x26*x5 + x3*x5 - x30*x36 + x34*x5 + x35*x5 + x5*x7 + x5*x8;
    const double d10 = -com_from_foot*x0*x39 + com_to_hip*foot_radius*mass_leg*x0*x37 + com_to_hip*foot_radius*mass_leg*x11*x37 + com_to_hip*foot_radius*mass_leg*x4*x40 - x16*x40*x41 - x37*x44 - x40*x45 - x42*x43;
    const double d11 = inertia_leg + x37*x37*x8 + x40*x40*x8;
    const double h0 = damping_ankle*q_stance_dot + mass_hip*x50 + mass_leg*x50 + q_swing_dot*q_swing_dot*(foot_radius*x13*x39 + x32*x43 + x52 + x54 + x55 - x56 - x57 - x58) + x46 - x47 + x49*(-x0*x48 + x27) + x59*(mass_hip*x0*x13*x9 + mass_hip*x11*x4*x9 - mass_hip*x60 - mass_hip*x62 + 2.0*mass_leg*x0*x13*x9 + 2.0*mass_leg*x11*x4*x9 - mass_leg*x62 - x18*x28*x4 - x18*x60 - x28*x61 - x32*x41 - x32*x61);
    const double h1 = x38*x49 - x46 + x47 + x59*(-x52 - x54 - x55 + x56 + x57 + x58);
    const double l00 = sqrt(d00);
    const double l10 = (d10)/l00;
    const double l11 = sqrt(d11 - l10*l10);
    const double z0_y = (-h0)/l00;
    const double z1_y = (-h1 - l10*z0_y)/l11;
    const double z1 = (z1_y)/l11;
    const double z0 = (z0_y - l10*z1)/l00;
    out[0] = z0;
    out[1] = z1;
}

/* d qdd / d (q, qd), out (n, 2n), fused with the Cholesky solve. */
void wk_compass_accel_jac(const double *q, const double *qd, const double *p, double *out)
{
    const double q_stance = q[0];
    const double q_swing = q[1];
    const double q_stance_dot = qd[0];
    const double q_swing_dot = qd[1];
    const double mass_hip = p[0];
    const double mass_leg = p[1];
    const double com_from_foot = p[2];
    const double com_to_hip = p[3];
    const double inertia_leg = p[4];
    const double foot_radius = p[5];
    const double slope = p[6];
    const double g = p[7];
    const double damping_hip = p[8];
    const double damping_ankle = p[9];
    const double x0 = sin(q_stance);
    const double x1 = x0*x0;
    const double x2 = com_from_foot*com_from_foot;
    const double x3 = mass_hip*x2;
    const double x4 = cos(q_stance);
    const double x5 = x4*x4;
    const double x6 = com_to_hip*com_to_hip;
    const double x7 = mass_hip*x6;
    const double x8 = mass_leg*x6;
    const double x9 = foot_radius*foot_radius;
    const double x10 = mass_hip*x9;
    const double x11 = sin(slope);
    const double x12 = x11*x11;
    const double x13 = cos(slope);
    const double x14 = x13*x13;
    const double x15 = 2.0*mass_hip;
    const double x16 = com_from_foot*com_to_hip;
    const double x17 = x15*x16;
    const double x18 = 2.0*mass_leg;
    const double x19 = x16*x18;
    const double x20 = com_from_foot*foot_radius;
    const double x21 = x1*x20;
    const double x22 = x20*x5;
    const double x23 = 4.0*mass_leg;
    const double x24 = com_to_hip*foot_radius;
    const double x25 = x15*x24;
    const double x26 = x18*x24;
    const double x27 = foot_radius*x11;
    const double x28 = com_from_foot*x27;
    const double x29 = x0*x28;
    const double x30 = x13*x4;
    const double x31 = x20*x30;
    const double x32 = com_to_hip*x27;
    const double x33 = x0*x32;
    const double x34 = x18*x2;
    const double x35 = x18*x9;
    const double x36 = x0*x10*x11;
    const double x37 = x10*x13*x4;
    const double x38 = x23*x9;
    const double x39 = cos(q_swing);
    const double x40 = mass_leg*x24;
    const double x41 = x13*x40;
    const double x42 = sin(q_swing);
    const double x43 = mass_leg*x16;
    const double x44 = x0*x8;
    const double x45 = x4*x8;
    const double x46 = -com_to_hip*foot_radius*mass_leg*x0*x42 - com_to_hip*foot_radius*mass_leg*x39*x4 + x0*x42*x43 + x39*x4*x43 + x39*x45 + x42*x44;
    const double x47 = -com_to_hip*foot_radius*mass_leg*x11*x42 + x39*x41 + x46;
    const double x48 = damping_hip*q_stance_dot;
    const double x49 = damping_hip*q_swing_dot;
    const double x50 = com_from_foot - foot_radius;
    const double x51 = g*mass_leg;
    const double x52 = com_to_hip + x50;
    const double x53 = g*(-x0*x52 + x27);
    const double x54 = q_swing_dot*q_swing_dot;
    const double x55 = mass_leg*x16*x4*x42;
    const double x56 = x0*x39;
    const double x57 = x40*x56;
    const double x58 = mass_leg*x32;
    const double x59 = x42*x45;
    const double x60 = x43*x56;
    const double x61 = x4*x40*x42;
    const double x62 = x39*x44;
    const double x63 = x39*x58 + x41*x42 + x55 + x57 + x59 - x60 - x61 - x62;
    const double x64 = q_stance_dot*q_stance_dot;
    const double x65 = x0*x13;
    const double x66 = mass_hip*x65;
    const double x67 = mass_hip*x4;
    const double x68 = x20*x65;
    const double x69 = x28*x4;
    const double x70 = mass_hip*x0*x13*x9 + mass_hip*x11*x4*x9 + 2.0*mass_leg*x0*x13*x9 + 2.0*mass_leg*x11*x4*x9 - x0*x41 - x18*x68 - x18*x69 - x20*x66 - x24*x66 - x28*x67 - x32*x67 - x4*x58;
    const double x71 = com_to_hip*x51;
    const double x72 = -x55 - x57 - x59 + x60 + x61 + x62;
    const double x73 = x32*x4;
    const double x74 = x4*x52;
    const double x75 = -x46;
    const double x76 = mass_hip*x0;
    const double x77 = mass_hip*x30;
    const double d00 = inertia_leg + x0*x11*x38 + x1*x10 + x1*x17 + x1*x19 - x1*x25 - x1*x26 + x1*x3 + x1*x34 + x1*x35 + x1*x7 + x1*x8 + x10*x12 + x10*x14 + x10*x5 + x12*x35 + x14*x35 - x15*x21 - x15*x22 - x15*x29 + x15*x31 - x15*x33 + x17*x5 - x18*x33 + x19*x5 - x21*x23 - x22*x23 - x23*x29 + x23*x31 + x25*x30 - x25*x5 + x26*x30 - x26*x5 + x3*x5 - x30*x38 + x34*x5 + x35*x5 + 2.0*x36 - 2.0*x37 + x5*x7 + x5*x8;
    const double d10 = -x47;
    const double d11 = inertia_leg + x39*x39*x8 + x42*x42*x8;
    const double h0 = damping_ankle*q_stance_dot + mass_hip*x53 + mass_leg*x53 + x48 - x49 + x51*(-x0*x50 + x27) + x54*x63 + x64*x70;
    const double h1 = x42*x71 - x48 + x49 + x64*x72;
    const double dD0_00 = 2.0*mass_hip*x0*x13*x9 + 2.0*mass_hip*x11*x4*x9 + 4.0*mass_leg*x0*x13*x9 + 4.0*mass_leg*x11*x4*x9 - x15*x68 - x15*x69 - x15*x73 - x18*x73 - x23*x68 - x23*x69 - x25*x65 - x26*x65;
    const double dD0_10 = x72;
    const double dD0_11 = 0.0;
    const double dD1_00 = 0.0;
    const double dD1_10 = x63;
    const double dD1_11 = 0.0;
    const double hq0_0 = -g*mass_hip*x74 - x4*x50*x51 - x51*x74 + x54*x75 + x64*(-x0*x11*x35 + x0*x58 + x18*x29 - x18*x31 - x20*x77 - x24*x77 + x28*x76 + x30*x35 - x30*x40 + x32*x76 - x36 + x37);
    const double hv0_0 = damping_ankle + damping_hip + 2.0*q_stance_dot*x70;
    const double hq1_0 = x46*x64;
    const double hv1_0 = -damping_hip + 2.0*q_stance_dot*x72;
    const double hq0_1 = x47*x54;
    const double hv0_1 = -damping_hip + 2.0*q_swing_dot*x63;
    const double hq1_1 = x39*x71 + x64*x75;
    const double hv1_1 = damping_hip;
    const double l00 = sqrt(d00);
    const double l10 = (d10)/l00;
    const double l11 = sqrt(d11 - l10*l10);
    const double a0_y = (-h0)/l00;
    const double a1_y = (-h1 - l10*a0_y)/l11;
    const double a1 = (a1_y)/l11;
    const double a0 = (a0_y - l10*a1)/l00;
    const double jq0_0_y = (-(hq0_0 + dD0_00*a0 + dD0_10*a1))/l00;
    const double jq1_0_y = (-(hq1_0 + dD0_10*a0 + dD0_11*a1) - l10*jq0_0_y)/l11;
    const double jq1_0 = (jq1_0_y)/l11;
    const double jq0_0 = (jq0_0_y - l10*jq1_0)/l00;
    const double jv0_0_y = (-hv0_0)/l00;
    const double jv1_0_y = (-hv1_0 - l10*jv0_0_y)/l11;
    const double jv1_0 = (jv1_0_y)/l11;
    const double jv0_0 = (jv0_0_y - l10*jv1_0)/l00;
    const double jq0_1_y = (-(hq0_1 + dD1_00*a0 + dD1_10*a1))/l00;
    const double jq1_1_y = (-(hq1_1 + dD1_10*a0 + dD1_11*a1) - l10*jq0_1_y)/l11;
    const double jq1_1 = (jq1_1_y)/l11;
    const double jq0_1 = (jq0_1_y - l10*jq1_1)/l00;
    const double jv0_1_y = (-hv0_1)/l00;
    const double jv1_1_y = (-hv1_1 - l10*jv0_1_y)/l11;
    const double jv1_1 = (jv1_1_y)/l11;
    const double jv0_1 = (jv0_1_y - l10*jv1_1)/l00;
    out[0] = jq0_0;
    out[2] = jv0_0;
    out[1] = jq0_1;
    out[3] = jv0_1;
    out[4] = jq1_0;
    out[6] = jv1_0;
    out[5] = jq1_1;
    out[7] = jv1_1;
}

/* Mass matrix D(q), out (n, n). */
void wk_compass_mass_matrix(const double *q, const double *p, double *out)
{
    const double q_stance = q[0];
    const double q_swing = q[1];
    const double mass_hip = p[0];
    const double mass_leg = p[1];
    const double com_from_foot = p[2];
    const double com_to_hip = p[3];
    const double inertia_leg = p[4];
    const double foot_radius = p[5];
    const double slope = p[6];
    const double x0 = sin(q_stance);
    const double x1 = x0*x0;
    const double x2 = com_from_foot*com_from_foot;
    const double x3 = mass_hip*x2;
    const double x4 = cos(q_stance);
    const double x5 = x4*x4;
    const double x6 = com_to_hip*com_to_hip;
    const double x7 = mass_hip*x6;
    const double x8 = mass_leg*x6;
    const double x9 = foot_radius*foot_radius;
    const double x10 = mass_hip*x9;
    const double x11 = sin(slope);
    const double x12 = x11*x11;
    const double x13 = cos(slope);
    const double x14 = x13*x13;
    const double x15 = 2.0*mass_hip;
    const double x16 = com_from_foot*com_to_hip;
    const double x17 = x15*x16;
    const double x18 = 2.0*mass_leg;
    const double x19 = x16*x18;
    const double x20 = com_from_foot*foot_radius;
    const double x21 = x1*x20;
    const double x22 = x20*x5;
    const double x23 = 4.0*mass_leg;
    const double x24 = com_to_hip*foot_radius;
    const double x25 = x15*x24;
    const double x26 = x18*x24;
    const double x27 = x0*x11;
    const double x28 = x20*x27;
    const double x29 = x13*x4;
    const double x30 = x20*x29;
    const double x31 = x18*x2;
    const double x32 = x18*x9;
    const double x33 = 2.0*x10;
    const double x34 = x23*x9;
    const double x35 = sin(q_swing);
    const double x36 = x0*x35;
    const double x37 = mass_leg*x16;
    const double x38 = cos(q_swing);
    const double x39 = x38*x4;
    const double x40 = com_to_hip*foot_radius*mass_leg*x0*x35 + com_to_hip*foot_radius*mass_leg*x11*x35 + com_to_hip*foot_radius*mass_leg*x38*x4 - mass_leg*x13*x24*x38 - x36*x37 - x36*x8 - x37*x39 - x39*x8;
    out[0] = inertia_leg + x1*x10 + x1*x17 + x1*x19 - x1*x25 - x1*x26 + x1*x3 + x1*x31 + x1*x32 + x1*x7 + x1*x8 + x10*x12 + x10*x14 + x10*x5 + x12*x32 + x14*x32 - x15*x21 - x15*x22 - x15*x28 + x15*x30 + x17*x5 + x19*x5 - x21*x23 - x22*x23 - x23*x28 + x23*x30 - x25*x27 + x25*x29 - x25*x5 - x26*x27 + x26*x29 - x26*x5 + x27*x33 + x27*x34 - x29*x33 - x29*x34 + x3*x5 + x31*x5 + x32*x5 + x5*x7 + x5*x8;
    out[1] = x40;
    out[2] = x40;
    out[3] = inertia_leg + x35*x35*x8 + x38*x38*x8;
}

/* Coriolis matrix C(q, qd), out (n, n). */
void wk_compass_coriolis(const double *q, const double *qd, const double *p, double *out)
{
    const double q_stance = q[0];
    const double q_swing = q[1];
    const double q_stance_dot = qd[0];
    const double q_swing_dot = qd[1];
    const double mass_hip = p[0];
    const double mass_leg = p[1];
    const double com_from_foot = p[2];
    const double com_to_hip = p[3];
    const double foot_radius = p[5];
    const double slope = p[6];
    const double x0 = cos(slope);
    const double x1 = sin(q_stance);
    const double x2 = x0*x1;
    const double x3 = foot_radius*mass_hip;
    const double x4 = com_from_foot*x3;
    const double x5 = cos(q_stance);
    const double x6 = sin(slope);
    const double x7 = x5*x6;
    const double x8 = com_to_hip*x3;
    const double x9 = mass_leg*x2;
    const double x10 = com_to_hip*foot_radius;
    const double x11 = mass_leg*x7;
    const double x12 = 2.0*com_from_foot*foot_radius;
    const double x13 = foot_radius*foot_radius;
    const double x14 = sin(q_swing);
    const double x15 = x14*x5;
    const double x16 = mass_leg*x15;
    const double x17 = com_from_foot*com_to_hip;
    const double x18 = x16*x17;
    const double x19 = cos(q_swing);
    const double x20 = x1*x19;
    const double x21 = mass_leg*x10;
    const double x22 = x20*x21;
    const double x23 = com_to_hip*com_to_hip*mass_leg;
    const double x24 = x15*x23;
    const double x25 = mass_leg*x17*x20;
    const double x26 = x10*x16;
    const double x27 = x20*x23;
    out[0] = q_stance_dot*(mass_hip*x0*x1*x13 + mass_hip*x13*x5*x6 + 2.0*mass_leg*x0*x1*x13 + 2.0*mass_leg*x13*x5*x6 - x10*x11 - x10*x9 - x11*x12 - x12*x9 - x2*x4 - x2*x8 - x4*x7 - x7*x8);
    out[1] = q_swing_dot*(x0*x14*x21 + x18 + x19*x21*x6 + x22 + x24 - x25 - x26 - x27);
    out[2] = q_stance_dot*(-x18 - x22 - x24 + x25 + x26 + x27);
    out[3] = 0.0;
}

/* Gravity vector g(q) = dP/dq, out (n,). */
void wk_compass_gravity(const double *q, const double *p, double *out)
{
    const double q_stance = q[0];
    const double q_swing = q[1];
    const double mass_hip = p[0];
    const double mass_leg = p[1];
    const double com_from_foot = p[2];
    const double com_to_hip = p[3];
    const double foot_radius = p[5];
    const double slope = p[6];
    const double g = p[7];
    const double x0 = foot_radius*sin(slope);
    const double x1 = sin(q_stance);
    const double x2 = com_from_foot - foot_radius;
    const double x3 = g*mass_leg;
    const double x4 = g*(x0 - x1*(com_to_hip + x2));
    out[0] = mass_hip*x4 + mass_leg*x4 + x3*(x0 - x1*x2);
    out[1] = com_to_hip*x3*sin(q_swing);
}

/* h(q, qd) = C(q, qd) qd + g(q), out (n,). */
void wk_compass_bias(const double *q, const double *qd, const double *p, double *out)
{
    const double q_stance = q[0];
    const double q_swing = q[1];
    const double q_stance_dot = qd[0];
    const double q_swing_dot = qd[1];
    const double mass_hip = p[0];
    const double mass_leg = p[1];
    const double com_from_foot = p[2];
    const double com_to_hip = p[3];
    const double foot_radius = p[5];
    const double slope = p[6];
    const double g = p[7];
    const double x0 = sin(slope);
    const double x1 = foot_radius*x0;
    const double x2 = sin(q_stance);
    const double x3 = com_from_foot - foot_radius;
    const double x4 = g*mass_leg;
    const double x5 = g*(x1 - x2*(com_to_hip + x3));
    const double x6 = cos(q_stance);
    const double x7 = sin(q_swing);
    const double x8 = x6*x7;
    const double x9 = com_to_hip*mass_leg;
    const double x10 = com_from_foot*x9;
    const double x11 = x10*x8;
    const double x12 = cos(q_swing);
    const double x13 = x12*x2;
    const double x14 = foot_radius*x9;
    const double x15 = x13*x14;
    const double x16 = cos(slope);
    const double x17 = com_to_hip*x7;
    const double x18 = com_to_hip*com_to_hip*mass_leg;
    const double x19 = x18*x8;
    const double x20 = x10*x13;
    const double x21 = x14*x8;
    const double x22 = x13*x18;
    const double x23 = q_stance_dot*q_stance_dot;
    const double x24 = com_from_foot*mass_hip;
    const double x25 = foot_radius*x16*x2;
    const double x26 = x1*x6;
    const double x27 = com_to_hip*mass_hip;
    const double x28 = 2.0*com_from_foot*mass_leg;
    const double x29 = foot_radius*foot_radius;
    out[0] = mass_hip*x5 + mass_leg*x5 + q_swing_dot*q_swing_dot*(foot_radius*mass_leg*x16*x17 + x1*x12*x9 + x11 + x15 + x19 - x20 - x21 - x22) + x23*(mass_hip*x0*x29*x6 + mass_hip*x16*x2*x29 + 2.0*mass_leg*x0*x29*x6 + 2.0*mass_leg*x16*x2*x29 - x24*x25 - x24*x26 - x25*x27 - x25*x28 - x25*x9 - x26*x27 - x26*x28 - x26*x9) + x4*(x1 - x2*x3);
    out[1] = x17*x4 + x23*(-x11 - x15 - x19 + x20 + x21 + x22);
}

/* Generalized joint-damping forces Q(q, qd), out (n,); power Q.qd <= 0. */
void wk_compass_forcing(const double *q, const double *qd, const double *p, double *out)
{
    (void)q;
    const double q_stance_dot = qd[0];
    const double q_swing_dot = qd[1];
    const double damping_hip = p[8];
    const double damping_ankle = p[9];
    const double x0 = damping_hip*q_stance_dot - damping_hip*q_swing_dot;
    out[0] = -damping_ankle*q_stance_dot - x0;
    out[1] = x0;
}

/* dD/dq_k for every k, out (n, n, n): out[k] = dD/dq_k. */
void wk_compass_dmass(const double *q, const double *p, double *out)
{
    const double q_stance = q[0];
    const double q_swing = q[1];
    const double mass_hip = p[0];
    const double mass_leg = p[1];
    const double com_from_foot = p[2];
    const double com_to_hip = p[3];
    const double foot_radius = p[5];
    const double slope = p[6];
    const double x0 = sin(q_stance);
    const double x1 = cos(slope);
    const double x2 = x0*x1;
    const double x3 = 2.0*mass_hip;
    const double x4 = com_from_foot*foot_radius;
    const double x5 = x3*x4;
    const double x6 = cos(q_stance);
    const double x7 = sin(slope);
    const double x8 = x6*x7;
    const double x9 = 4.0*mass_leg*x4;
    const double x10 = com_to_hip*foot_radius*x3;
    const double x11 = com_to_hip*mass_leg;
    const double x12 = foot_radius*x11;
    const double x13 = 2.0*x12;
    const double x14 = foot_radius*foot_radius;
    const double x15 = cos(q_swing);
    const double x16 = x0*x15;
    const double x17 = com_from_foot*x11;
    const double x18 = x16*x17;
    const double x19 = sin(q_swing);
    const double x20 = x19*x6;
    const double x21 = x12*x20;
    const double x22 = com_to_hip*com_to_hip*mass_leg;
    const double x23 = x16*x22;
    const double x24 = x17*x20;
    const double x25 = x12*x16;
    const double x26 = x20*x22;
    const double x27 = x18 + x21 + x23 - x24 - x25 - x26;
    const double x28 = x1*x12*x19 + x12*x15*x7 - x18 - x21 - x23 + x24 + x25 + x26;
    out[0] = 2.0*mass_hip*x0*x1*x14 + 2.0*mass_hip*x14*x6*x7 + 4.0*mass_leg*x0*x1*x14 + 4.0*mass_leg*x14*x6*x7 - x10*x2 - x10*x8 - x13*x2 - x13*x8 - x2*x5 - x2*x9 - x5*x8 - x8*x9;
    out[1] = x27;
    out[2] = x27;
    out[3] = 0.0;
    out[4] = 0.0;
    out[5] = x28;
    out[6] = x28;
    out[7] = 0.0;
}

/* dh/dq, out (n, n). */
void wk_compass_dbias_dq(const double *q, const double *qd, const double *p, double *out)
{
    const double q_stance = q[0];
    const double q_swing = q[1];
    const double q_stance_dot = qd[0];
    const double q_swing_dot = qd[1];
    const double mass_hip = p[0];
    const double mass_leg = p[1];
    const double com_from_foot = p[2];
    const double com_to_hip = p[3];
    const double foot_radius = p[5];
    const double slope = p[6];
    const double g = p[7];
    const double x0 = com_from_foot - foot_radius;
    const double x1 = cos(q_stance);
    const double x2 = g*x1;
    const double x3 = x2*(com_to_hip + x0);
    const double x4 = q_swing_dot*q_swing_dot;
    const double x5 = sin(q_stance);
    const double x6 = sin(q_swing);
    const double x7 = x5*x6;
    const double x8 = com_to_hip*mass_leg;
    const double x9 = com_from_foot*x8;
    const double x10 = cos(q_swing);
    const double x11 = x1*x10;
    const double x12 = com_to_hip*com_to_hip*mass_leg;
    const double x13 = foot_radius*x8;
    const double x14 = x11*x12 - x11*x13 + x11*x9 + x12*x7 - x13*x7 + x7*x9;
    const double x15 = -x14;
    const double x16 = q_stance_dot*q_stance_dot;
    const double x17 = sin(slope);
    const double x18 = x17*x5;
    const double x19 = foot_radius*x18;
    const double x20 = mass_hip*x19;
    const double x21 = foot_radius*foot_radius;
    const double x22 = mass_hip*x21;
    const double x23 = cos(slope);
    const double x24 = x1*x23;
    const double x25 = foot_radius*x24;
    const double x26 = mass_hip*x25;
    const double x27 = 2.0*mass_leg;
    const double x28 = com_from_foot*x27;
    const double x29 = x21*x27;
    const double x30 = x10*x8;
    out[0] = -mass_hip*x3 - mass_leg*x0*x2 - mass_leg*x3 + x15*x4 + x16*(com_from_foot*x20 - com_from_foot*x26 + com_to_hip*x20 - com_to_hip*x26 - x18*x22 - x18*x29 + x19*x28 + x19*x8 + x22*x24 + x24*x29 - x25*x28 - x25*x8);
    out[1] = x4*(foot_radius*x23*x30 - x13*x17*x6 + x14);
    out[2] = x14*x16;
    out[3] = g*x30 + x15*x16;
}

/* dh/dqd, out (n, n). */
void wk_compass_dbias_dqd(const double *q, const double *qd, const double *p, double *out)
{
    const double q_stance = q[0];
    const double q_swing = q[1];
    const double q_stance_dot = qd[0];
    const double q_swing_dot = qd[1];
    const double mass_hip = p[0];
    const double mass_leg = p[1];
    const double com_from_foot = p[2];
    const double com_to_hip = p[3];
    const double foot_radius = p[5];
    const double slope = p[6];
    const double x0 = cos(slope);
    const double x1 = sin(q_stance);
    const double x2 = x0*x1;
    const double x3 = foot_radius*mass_hip;
    const double x4 = com_from_foot*x3;
    const double x5 = cos(q_stance);
    const double x6 = sin(slope);
    const double x7 = x5*x6;
    const double x8 = com_to_hip*x3;
    const double x9 = mass_leg*x2;
    const double x10 = com_to_hip*foot_radius;
    const double x11 = mass_leg*x7;
    const double x12 = 2.0*com_from_foot*foot_radius;
    const double x13 = foot_radius*foot_radius;
    const double x14 = 2.0*q_stance_dot;
    const double x15 = sin(q_swing);
    const double x16 = x15*x5;
    const double x17 = mass_leg*x16;
    const double x18 = com_from_foot*com_to_hip;
    const double x19 = x17*x18;
    const double x20 = cos(q_swing);
    const double x21 = x1*x20;
    const double x22 = mass_leg*x10;
    const double x23 = x21*x22;
    const double x24 = com_to_hip*com_to_hip*mass_leg;
    const double x25 = x16*x24;
    const double x26 = mass_leg*x18*x21;
    const double x27 = x10*x17;
    const double x28 = x21*x24;
    out[0] = x14*(mass_hip*x0*x1*x13 + mass_hip*x13*x5*x6 + 2.0*mass_leg*x0*x1*x13 + 2.0*mass_leg*x13*x5*x6 - x10*x11 - x10*x9 - x11*x12 - x12*x9 - x2*x4 - x2*x8 - x4*x7 - x7*x8);
    out[1] = 2.0*q_swing_dot*(x0*x15*x22 + x19 + x20*x22*x6 + x23 + x25 - x26 - x27 - x28);
    out[2] = x14*(-x19 - x23 - x25 + x26 + x27 + x28);
    out[3] = 0.0;
}

/* Kinetic energy [J]. */
double wk_compass_kinetic(const double *q, const double *qd, const double *p)
{
    const double q_stance = q[0];
    const double q_swing = q[1];
    const double q_stance_dot = qd[0];
    const double q_swing_dot = qd[1];
    const double mass_hip = p[0];
    const double mass_leg = p[1];
    const double com_from_foot = p[2];
    const double com_to_hip = p[3];
    const double inertia_leg = p[4];
    const double foot_radius = p[5];
    const double slope = p[6];
    const double x0 = q_stance_dot*q_stance_dot;
    const double x1 = ((1.0/2.0))*inertia_leg;
    const double x2 = foot_radius*sin(slope);
    const double x3 = sin(q_stance);
    const double x4 = com_from_foot - foot_radius;
    const double x5 = foot_radius*cos(slope);
    const double x6 = cos(q_stance);
    const double x7 = ((1.0/2.0))*mass_leg;
    const double x8 = com_to_hip + x4;
    const double x9 = x2 - x3*x8;
    const double x10 = -x5 - x6*x8;
    const double x11 = com_to_hip*q_swing_dot;
    return ((1.0/2.0))*mass_hip*(x0*x10*x10 + x0*x9*x9) + q_swing_dot*q_swing_dot*x1 + x0*x1 + x7*(x0*(x2 - x3*x4)*(x2 - x3*x4) + x0*(-x4*x6 - x5)*(-x4*x6 - x5)) + x7*((q_stance_dot*x10 + x11*cos(q_swing))*(q_stance_dot*x10 + x11*cos(q_swing)) + (q_stance_dot*x9 + x11*sin(q_swing))*(q_stance_dot*x9 + x11*sin(q_swing)));
}

/* Potential energy [J] (y = 0 at the origin). */
double wk_compass_potential(const double *q, const double *p)
{
    const double q_stance = q[0];
    const double q_swing = q[1];
    const double mass_hip = p[0];
    const double mass_leg = p[1];
    const double com_from_foot = p[2];
    const double com_to_hip = p[3];
    const double foot_radius = p[5];
    const double slope = p[6];
    const double g = p[7];
    const double x0 = cos(q_stance);
    const double x1 = com_from_foot - foot_radius;
    const double x2 = foot_radius*(q_stance + slope)*sin(slope) + foot_radius*cos(slope);
    const double x3 = g*mass_leg;
    const double x4 = x0*(com_to_hip + x1) + x2;
    return g*mass_hip*x4 + x3*(-com_to_hip*cos(q_swing) + x4) + x3*(x0*x1 + x2);
}

/* Named points in the world frame, out (n_points, 2); names in POINTS. */
void wk_compass_points(const double *q, const double *p, double *out)
{
    const double q_stance = q[0];
    const double q_swing = q[1];
    const double com_from_foot = p[2];
    const double com_to_hip = p[3];
    const double foot_radius = p[5];
    const double slope = p[6];
    const double x0 = q_stance + slope;
    const double x1 = foot_radius*cos(slope);
    const double x2 = x0*x1;
    const double x3 = sin(slope);
    const double x4 = foot_radius*x0*x3;
    const double x5 = com_from_foot + com_to_hip - foot_radius;
    const double x6 = x2 + x5*sin(q_stance);
    const double x7 = -foot_radius*x3 + x6;
    const double x8 = x4 + x5*cos(q_stance);
    const double x9 = x1 + x8;
    const double x10 = -x5*sin(q_swing);
    const double x11 = -x5*cos(q_swing);
    out[0] = -x2;
    out[1] = x4;
    out[2] = -x7;
    out[3] = x9;
    out[4] = -x10 - x7;
    out[5] = x11 + x9;
    out[6] = -x10 - x6;
    out[7] = x11 + x8;
}

/* Jacobian of the hip position, out (2, n). */
void wk_compass_hip_jac(const double *q, const double *p, double *out)
{
    const double q_stance = q[0];
    const double com_from_foot = p[2];
    const double com_to_hip = p[3];
    const double foot_radius = p[5];
    const double slope = p[6];
    const double x0 = com_from_foot + com_to_hip - foot_radius;
    out[0] = -foot_radius*cos(slope) - x0*cos(q_stance);
    out[1] = 0.0;
    out[2] = foot_radius*sin(slope) - x0*sin(q_stance);
    out[3] = 0.0;
}

/* Floating-base mass matrix, out (n_f, n_f). */
void wk_compass_ext_mass_matrix(const double *q, const double *p, double *out)
{
    const double q_stance = q[0];
    const double q_swing = q[1];
    const double mass_hip = p[0];
    const double mass_leg = p[1];
    const double com_to_hip = p[3];
    const double inertia_leg = p[4];
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
    const double x10 = mass_hip + 2.0*mass_leg;
    out[0] = inertia_leg + x0*x0*x1 + x1*x2*x2;
    out[1] = 0.0;
    out[2] = x4;
    out[3] = x5;
    out[4] = 0.0;
    out[5] = inertia_leg + x1*x6*x6 + x1*x7*x7;
    out[6] = x8;
    out[7] = x9;
    out[8] = x4;
    out[9] = x8;
    out[10] = x10;
    out[11] = 0.0;
    out[12] = x5;
    out[13] = x9;
    out[14] = 0.0;
    out[15] = x10;
}

/* Jacobian of the swing foot's material contact velocity, out (2, n_f). */
void wk_compass_ext_swing_contact_jac(const double *q, const double *p, double *out)
{
    const double q_swing = q[1];
    const double com_from_foot = p[2];
    const double com_to_hip = p[3];
    const double foot_radius = p[5];
    const double slope = p[6];
    const double x0 = com_from_foot + com_to_hip - foot_radius;
    out[0] = 0.0;
    out[1] = foot_radius*cos(slope) + x0*cos(q_swing);
    out[2] = 1.0;
    out[3] = 0.0;
    out[4] = 0.0;
    out[5] = -foot_radius*sin(slope) + x0*sin(q_swing);
    out[6] = 0.0;
    out[7] = 1.0;
}

/* Jacobian of the stance foot's material contact velocity, out (2, n_f). */
void wk_compass_ext_stance_contact_jac(const double *q, const double *p, double *out)
{
    const double q_stance = q[0];
    const double com_from_foot = p[2];
    const double com_to_hip = p[3];
    const double foot_radius = p[5];
    const double slope = p[6];
    const double x0 = com_from_foot + com_to_hip - foot_radius;
    out[0] = foot_radius*cos(slope) + x0*cos(q_stance);
    out[1] = 0.0;
    out[2] = 1.0;
    out[3] = 0.0;
    out[4] = -foot_radius*sin(slope) + x0*sin(q_stance);
    out[5] = 0.0;
    out[6] = 0.0;
    out[7] = 1.0;
}
