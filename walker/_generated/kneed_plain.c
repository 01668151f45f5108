/* generated, do not edit: walker C kernels for `kneed_plain`
 * input hash: sha256:343aaedeb9f7c172c35d9d71000eb8f94d63c9110e76b54056bb11cb14f90f44
 * sympy 1.14.0; regenerate with `python scripts/generate_kernels.py`
 * structural variant `plain` of `kneed`: these parameters are exactly 0 and
 * never read (the arguments are those of the general kernels):
 *   inertia_thigh, inertia_shank, offset_thigh, offset_shank, foot_radius, damping_hip, damping_knee, damping_ankle;
 * entries simplified (trigsimp; polynomial in sin/cos and qd with factored coefficients);
 * sin and cos of each angle (coordinates, slope) are computed once per call and
 * sines and cosines of their sums are expanded by the angle-sum identities;
 * accel and accel_jac solve with the mass matrix in closed form, adj(D) / det(D)
 * from its cofactors (one division), not by Cholesky.
 * argument order:
 *   q = [q1, q2, q3]
 *   qd = [q1_dot, q2_dot, q3_dot]
 *   p = [mass_hip, mass_thigh, mass_shank, shank_com_from_foot, shank_com_to_knee, thigh_com_from_knee, thigh_com_to_hip, inertia_thigh, inertia_shank, offset_thigh, offset_shank, foot_radius, slope, g, damping_hip, damping_knee, damping_ankle]
 *   q = [q1, q2]
 *   qd = [q1_dot, q2_dot]
 *   q = [q1, q2, x_hip, y_hip]
 * kernels:
 *   wk_kneed_plain_unlocked_accel(q, qd, p, out)
 *   wk_kneed_plain_unlocked_accel_jac(q, qd, p, out)
 *   wk_kneed_plain_unlocked_mass_matrix(q, p, out)
 *   wk_kneed_plain_unlocked_points(q, p, out)
 *   wk_kneed_plain_locked_accel(q, qd, p, out)
 *   wk_kneed_plain_locked_accel_jac(q, qd, p, out)
 *   wk_kneed_plain_locked_mass_matrix(q, p, out)
 *   wk_kneed_plain_locked_points(q, p, out)
 *   wk_kneed_plain_locked_hip_jac(q, p, out)
 *   wk_kneed_plain_ext_mass_matrix(q, p, out)
 *   wk_kneed_plain_ext_swing_contact_jac(q, p, out)
 *   wk_kneed_plain_ext_stance_contact_jac(q, p, out)
 */
#include <math.h>

#include "kneed_plain.h"

/* Accelerations qdd = -D^-1 h (h including any forcing) as -adj(D) h / det(D), cofactors and one division, out (>= n,). */
void wk_kneed_plain_unlocked_accel(const double *q, const double *qd, const double *p, double *out)
{
    const double q1 = q[0];
    const double q2 = q[1];
    const double q3 = q[2];
    const double q1_dot = qd[0];
    const double q2_dot = qd[1];
    const double q3_dot = qd[2];
    const double mass_hip = p[0];
    const double mass_thigh = p[1];
    const double mass_shank = p[2];
    const double shank_com_from_foot = p[3];
    const double shank_com_to_knee = p[4];
    const double thigh_com_from_knee = p[5];
    const double thigh_com_to_hip = p[6];
    const double g = p[13];
    const double sin_q1 = sin(q1);
    const double cos_q1 = cos(q1);
    const double sin_q2 = sin(q2);
    const double cos_q2 = cos(q2);
    const double sin_q3 = sin(q3);
    const double cos_q3 = cos(q3);
    const double x0 = shank_com_from_foot*shank_com_from_foot;
    const double x1 = shank_com_to_knee*shank_com_to_knee;
    const double x2 = thigh_com_from_knee*thigh_com_from_knee;
    const double x3 = thigh_com_to_hip*thigh_com_to_hip;
    const double x4 = mass_shank*x1;
    const double x5 = 2.0*x0;
    const double x6 = 2.0*mass_thigh;
    const double x7 = mass_hip*shank_com_from_foot;
    const double x8 = 2.0*x7;
    const double x9 = mass_hip*shank_com_to_knee;
    const double x10 = 2.0*x9;
    const double x11 = mass_hip*thigh_com_from_knee;
    const double x12 = 2.0*thigh_com_to_hip;
    const double x13 = mass_shank*shank_com_to_knee;
    const double x14 = 2.0*shank_com_from_foot;
    const double x15 = mass_shank*thigh_com_from_knee;
    const double x16 = mass_shank*thigh_com_to_hip;
    const double x17 = 2.0*shank_com_to_knee;
    const double x18 = mass_thigh*thigh_com_to_hip;
    const double x19 = 4.0*mass_thigh*shank_com_from_foot;
    const double x20 = mass_shank*x2 + mass_shank*x3 + mass_thigh*x3 + x12*x15;
    const double x21 = x15 + x16 + x18;
    const double x22 = thigh_com_from_knee + thigh_com_to_hip;
    const double x23 = shank_com_from_foot + shank_com_to_knee + x22;
    const double x24 = x21*x23;
    const double x25 = x13*x23;
    const double x26 = x13*x22;
    const double x27 = q3_dot*q3_dot;
    const double x28 = x25*(-cos_q1*sin_q3 + cos_q3*sin_q1);
    const double x29 = q2_dot*q2_dot;
    const double x30 = x24*(-cos_q1*sin_q2 + cos_q2*sin_q1);
    const double x31 = x26*(-cos_q2*sin_q3 + cos_q3*sin_q2);
    const double x32 = q1_dot*q1_dot;
    const double d00 = mass_hip*x0 + mass_hip*x1 + mass_hip*x2 + mass_hip*x3 + mass_shank*x5 + 4.0*mass_thigh*shank_com_to_knee*thigh_com_from_knee + mass_thigh*x5 + shank_com_to_knee*x19 + shank_com_to_knee*x8 + thigh_com_from_knee*x10 + 2.0*thigh_com_from_knee*x18 + thigh_com_from_knee*x19 + thigh_com_from_knee*x8 + thigh_com_to_hip*x10 + thigh_com_to_hip*x8 + x1*x6 + x11*x12 + x13*x14 + x14*x15 + x14*x16 + x14*x18 + x15*x17 + x16*x17 + x17*x18 + x2*x6 + x20 + x4;
    const double d10 = -x24*(cos_q1*cos_q2 + sin_q1*sin_q2);
    const double d11 = x20;
    const double d20 = -x25*(cos_q1*cos_q3 + sin_q1*sin_q3);
    const double d21 = x26*(cos_q2*cos_q3 + sin_q2*sin_q3);
    const double d22 = x4;
    const double h0 = -g*sin_q1*(mass_hip*thigh_com_to_hip + mass_shank*x14 + shank_com_from_foot*x6 + shank_com_to_knee*x6 + thigh_com_from_knee*x6 + x11 + x13 + x21 + x7 + x9) - x27*x28 - x29*x30;
    const double h1 = g*sin_q2*x21 + x27*x31 + x30*x32;
    const double h2 = g*sin_q3*x13 + x28*x32 - x29*x31;
    const double c00 = d11*d22 - d21*d21;
    const double c10 = d21*d20 - d22*d10;
    const double c11 = d22*d00 - d20*d20;
    const double c20 = d10*d21 - d20*d11;
    const double c21 = d20*d10 - d00*d21;
    const double c22 = d00*d11 - d10*d10;
    const double det = d00*c00 + d10*c10 + d20*c20;
    const double inv_det = 1.0/det;
    const double z0 = -(c00*h0 + c10*h1 + c20*h2)*inv_det;
    const double z1 = -(c10*h0 + c11*h1 + c21*h2)*inv_det;
    const double z2 = -(c20*h0 + c21*h1 + c22*h2)*inv_det;
    out[0] = z0;
    out[1] = z1;
    out[2] = z2;
}

/* d qdd / d (q, qd), out (n, 2n), fused with the solve: D^-1 = adj(D) / det(D) (one division) applied to every column. */
void wk_kneed_plain_unlocked_accel_jac(const double *q, const double *qd, const double *p, double *out)
{
    const double q1 = q[0];
    const double q2 = q[1];
    const double q3 = q[2];
    const double q1_dot = qd[0];
    const double q2_dot = qd[1];
    const double q3_dot = qd[2];
    const double mass_hip = p[0];
    const double mass_thigh = p[1];
    const double mass_shank = p[2];
    const double shank_com_from_foot = p[3];
    const double shank_com_to_knee = p[4];
    const double thigh_com_from_knee = p[5];
    const double thigh_com_to_hip = p[6];
    const double g = p[13];
    const double sin_q1 = sin(q1);
    const double cos_q1 = cos(q1);
    const double sin_q2 = sin(q2);
    const double cos_q2 = cos(q2);
    const double sin_q3 = sin(q3);
    const double cos_q3 = cos(q3);
    const double x0 = shank_com_from_foot*shank_com_from_foot;
    const double x1 = shank_com_to_knee*shank_com_to_knee;
    const double x2 = thigh_com_from_knee*thigh_com_from_knee;
    const double x3 = thigh_com_to_hip*thigh_com_to_hip;
    const double x4 = mass_shank*x1;
    const double x5 = 2.0*x0;
    const double x6 = 2.0*mass_thigh;
    const double x7 = mass_hip*shank_com_from_foot;
    const double x8 = 2.0*x7;
    const double x9 = mass_hip*shank_com_to_knee;
    const double x10 = 2.0*x9;
    const double x11 = mass_hip*thigh_com_from_knee;
    const double x12 = 2.0*thigh_com_to_hip;
    const double x13 = mass_shank*shank_com_to_knee;
    const double x14 = 2.0*shank_com_from_foot;
    const double x15 = mass_shank*thigh_com_from_knee;
    const double x16 = mass_shank*thigh_com_to_hip;
    const double x17 = 2.0*shank_com_to_knee;
    const double x18 = mass_thigh*thigh_com_to_hip;
    const double x19 = 4.0*mass_thigh*shank_com_from_foot;
    const double x20 = mass_shank*x2 + mass_shank*x3 + mass_thigh*x3 + x12*x15;
    const double x21 = x15 + x16 + x18;
    const double x22 = thigh_com_from_knee + thigh_com_to_hip;
    const double x23 = shank_com_from_foot + shank_com_to_knee + x22;
    const double x24 = x21*x23;
    const double x25 = x24*(cos_q1*cos_q2 + sin_q1*sin_q2);
    const double x26 = x13*x23;
    const double x27 = x26*(cos_q1*cos_q3 + sin_q1*sin_q3);
    const double x28 = x13*x22;
    const double x29 = x28*(cos_q2*cos_q3 + sin_q2*sin_q3);
    const double x30 = q3_dot*q3_dot;
    const double x31 = x26*(-cos_q1*sin_q3 + cos_q3*sin_q1);
    const double x32 = q2_dot*q2_dot;
    const double x33 = x24*(-cos_q1*sin_q2 + cos_q2*sin_q1);
    const double x34 = g*(mass_hip*thigh_com_to_hip + mass_shank*x14 + shank_com_from_foot*x6 + shank_com_to_knee*x6 + thigh_com_from_knee*x6 + x11 + x13 + x21 + x7 + x9);
    const double x35 = g*x21;
    const double x36 = x28*(-cos_q2*sin_q3 + cos_q3*sin_q2);
    const double x37 = q1_dot*q1_dot;
    const double x38 = g*x13;
    const double x39 = x27*x30;
    const double x40 = x25*x32;
    const double x41 = x25*x37;
    const double x42 = 2.0*x33;
    const double x43 = x27*x37;
    const double x44 = 2.0*x31;
    const double x45 = x29*x30;
    const double x46 = x29*x32;
    const double x47 = 2.0*x36;
    const double d00 = mass_hip*x0 + mass_hip*x1 + mass_hip*x2 + mass_hip*x3 + mass_shank*x5 + 4.0*mass_thigh*shank_com_to_knee*thigh_com_from_knee + mass_thigh*x5 + shank_com_to_knee*x19 + shank_com_to_knee*x8 + thigh_com_from_knee*x10 + 2.0*thigh_com_from_knee*x18 + thigh_com_from_knee*x19 + thigh_com_from_knee*x8 + thigh_com_to_hip*x10 + thigh_com_to_hip*x8 + x1*x6 + x11*x12 + x13*x14 + x14*x15 + x14*x16 + x14*x18 + x15*x17 + x16*x17 + x17*x18 + x2*x6 + x20 + x4;
    const double d10 = -x25;
    const double d11 = x20;
    const double d20 = -x27;
    const double d21 = x29;
    const double d22 = x4;
    const double h0 = -sin_q1*x34 - x30*x31 - x32*x33;
    const double h1 = sin_q2*x35 + x30*x36 + x33*x37;
    const double h2 = sin_q3*x38 + x31*x37 - x32*x36;
    const double dD0_00 = 0.0;
    const double dD0_10 = x33;
    const double dD0_11 = 0.0;
    const double dD0_20 = x31;
    const double dD0_21 = 0.0;
    const double dD0_22 = 0.0;
    const double dD1_00 = 0.0;
    const double dD1_10 = -x33;
    const double dD1_11 = 0.0;
    const double dD1_20 = 0.0;
    const double dD1_21 = -x36;
    const double dD1_22 = 0.0;
    const double dD2_00 = 0.0;
    const double dD2_10 = 0.0;
    const double dD2_11 = 0.0;
    const double dD2_20 = -x31;
    const double dD2_21 = x36;
    const double dD2_22 = 0.0;
    const double hq0_0 = -cos_q1*x34 - x39 - x40;
    const double hv0_0 = 0.0;
    const double hq1_0 = x41;
    const double hv1_0 = q1_dot*x42;
    const double hq2_0 = x43;
    const double hv2_0 = q1_dot*x44;
    const double hq0_1 = x40;
    const double hv0_1 = -q2_dot*x42;
    const double hq1_1 = cos_q2*x35 - x41 + x45;
    const double hv1_1 = 0.0;
    const double hq2_1 = -x46;
    const double hv2_1 = -q2_dot*x47;
    const double hq0_2 = x39;
    const double hv0_2 = -q3_dot*x44;
    const double hq1_2 = -x45;
    const double hv1_2 = q3_dot*x47;
    const double hq2_2 = cos_q3*x38 - x43 + x46;
    const double hv2_2 = 0.0;
    const double c00 = d11*d22 - d21*d21;
    const double c10 = d21*d20 - d22*d10;
    const double c11 = d22*d00 - d20*d20;
    const double c20 = d10*d21 - d20*d11;
    const double c21 = d20*d10 - d00*d21;
    const double c22 = d00*d11 - d10*d10;
    const double det = d00*c00 + d10*c10 + d20*c20;
    const double inv_det = 1.0/det;
    const double m00 = c00*inv_det;
    const double m10 = c10*inv_det;
    const double m11 = c11*inv_det;
    const double m20 = c20*inv_det;
    const double m21 = c21*inv_det;
    const double m22 = c22*inv_det;
    const double a0 = -(m00*h0 + m10*h1 + m20*h2);
    const double a1 = -(m10*h0 + m11*h1 + m21*h2);
    const double a2 = -(m20*h0 + m21*h1 + m22*h2);
    const double r0_0 = hq0_0 + dD0_00*a0 + dD0_10*a1 + dD0_20*a2;
    const double r1_0 = hq1_0 + dD0_10*a0 + dD0_11*a1 + dD0_21*a2;
    const double r2_0 = hq2_0 + dD0_20*a0 + dD0_21*a1 + dD0_22*a2;
    const double jq0_0 = -(m00*r0_0 + m10*r1_0 + m20*r2_0);
    const double jq1_0 = -(m10*r0_0 + m11*r1_0 + m21*r2_0);
    const double jq2_0 = -(m20*r0_0 + m21*r1_0 + m22*r2_0);
    const double jv0_0 = -(m00*hv0_0 + m10*hv1_0 + m20*hv2_0);
    const double jv1_0 = -(m10*hv0_0 + m11*hv1_0 + m21*hv2_0);
    const double jv2_0 = -(m20*hv0_0 + m21*hv1_0 + m22*hv2_0);
    const double r0_1 = hq0_1 + dD1_00*a0 + dD1_10*a1 + dD1_20*a2;
    const double r1_1 = hq1_1 + dD1_10*a0 + dD1_11*a1 + dD1_21*a2;
    const double r2_1 = hq2_1 + dD1_20*a0 + dD1_21*a1 + dD1_22*a2;
    const double jq0_1 = -(m00*r0_1 + m10*r1_1 + m20*r2_1);
    const double jq1_1 = -(m10*r0_1 + m11*r1_1 + m21*r2_1);
    const double jq2_1 = -(m20*r0_1 + m21*r1_1 + m22*r2_1);
    const double jv0_1 = -(m00*hv0_1 + m10*hv1_1 + m20*hv2_1);
    const double jv1_1 = -(m10*hv0_1 + m11*hv1_1 + m21*hv2_1);
    const double jv2_1 = -(m20*hv0_1 + m21*hv1_1 + m22*hv2_1);
    const double r0_2 = hq0_2 + dD2_00*a0 + dD2_10*a1 + dD2_20*a2;
    const double r1_2 = hq1_2 + dD2_10*a0 + dD2_11*a1 + dD2_21*a2;
    const double r2_2 = hq2_2 + dD2_20*a0 + dD2_21*a1 + dD2_22*a2;
    const double jq0_2 = -(m00*r0_2 + m10*r1_2 + m20*r2_2);
    const double jq1_2 = -(m10*r0_2 + m11*r1_2 + m21*r2_2);
    const double jq2_2 = -(m20*r0_2 + m21*r1_2 + m22*r2_2);
    const double jv0_2 = -(m00*hv0_2 + m10*hv1_2 + m20*hv2_2);
    const double jv1_2 = -(m10*hv0_2 + m11*hv1_2 + m21*hv2_2);
    const double jv2_2 = -(m20*hv0_2 + m21*hv1_2 + m22*hv2_2);
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
void wk_kneed_plain_unlocked_mass_matrix(const double *q, const double *p, double *out)
{
    const double q1 = q[0];
    const double q2 = q[1];
    const double q3 = q[2];
    const double mass_hip = p[0];
    const double mass_thigh = p[1];
    const double mass_shank = p[2];
    const double shank_com_from_foot = p[3];
    const double shank_com_to_knee = p[4];
    const double thigh_com_from_knee = p[5];
    const double thigh_com_to_hip = p[6];
    const double sin_q1 = sin(q1);
    const double cos_q1 = cos(q1);
    const double sin_q2 = sin(q2);
    const double cos_q2 = cos(q2);
    const double sin_q3 = sin(q3);
    const double cos_q3 = cos(q3);
    const double x0 = shank_com_from_foot*shank_com_from_foot;
    const double x1 = shank_com_to_knee*shank_com_to_knee;
    const double x2 = thigh_com_from_knee*thigh_com_from_knee;
    const double x3 = thigh_com_to_hip*thigh_com_to_hip;
    const double x4 = mass_shank*x1;
    const double x5 = 2.0*x0;
    const double x6 = 2.0*mass_thigh;
    const double x7 = 2.0*mass_hip;
    const double x8 = shank_com_from_foot*shank_com_to_knee;
    const double x9 = shank_com_from_foot*x7;
    const double x10 = shank_com_to_knee*x7;
    const double x11 = mass_shank*thigh_com_from_knee;
    const double x12 = 2.0*shank_com_from_foot;
    const double x13 = mass_shank*thigh_com_to_hip;
    const double x14 = 2.0*shank_com_to_knee;
    const double x15 = mass_thigh*thigh_com_to_hip;
    const double x16 = 4.0*mass_thigh;
    const double x17 = thigh_com_from_knee*x16;
    const double x18 = mass_shank*x2 + mass_shank*x3 + mass_thigh*x3 + 2.0*thigh_com_to_hip*x11;
    const double x19 = thigh_com_from_knee + thigh_com_to_hip;
    const double x20 = shank_com_from_foot + shank_com_to_knee + x19;
    const double x21 = -x20*(cos_q1*cos_q2 + sin_q1*sin_q2)*(x11 + x13 + x15);
    const double x22 = mass_shank*shank_com_to_knee;
    const double x23 = -x20*x22*(cos_q1*cos_q3 + sin_q1*sin_q3);
    const double x24 = x19*x22*(cos_q2*cos_q3 + sin_q2*sin_q3);
    out[0] = mass_hip*x0 + mass_hip*x1 + mass_hip*x2 + mass_hip*x3 + mass_shank*x5 + 2.0*mass_shank*x8 + mass_thigh*x5 + shank_com_from_foot*x17 + shank_com_to_knee*x17 + thigh_com_from_knee*thigh_com_to_hip*x7 + thigh_com_from_knee*x10 + 2.0*thigh_com_from_knee*x15 + thigh_com_from_knee*x9 + thigh_com_to_hip*x10 + thigh_com_to_hip*x9 + x1*x6 + x11*x12 + x11*x14 + x12*x13 + x12*x15 + x13*x14 + x14*x15 + x16*x8 + x18 + x2*x6 + x4 + x7*x8;
    out[1] = x21;
    out[2] = x23;
    out[3] = x21;
    out[4] = x18;
    out[5] = x24;
    out[6] = x23;
    out[7] = x24;
    out[8] = x4;
}

/* Named points in the world frame, out (n_points, 2); names in UNLOCKED_POINTS. */
void wk_kneed_plain_unlocked_points(const double *q, const double *p, double *out)
{
    const double q1 = q[0];
    const double q2 = q[1];
    const double q3 = q[2];
    const double shank_com_from_foot = p[3];
    const double shank_com_to_knee = p[4];
    const double thigh_com_from_knee = p[5];
    const double thigh_com_to_hip = p[6];
    const double sin_q1 = sin(q1);
    const double cos_q1 = cos(q1);
    const double sin_q2 = sin(q2);
    const double cos_q2 = cos(q2);
    const double sin_q3 = sin(q3);
    const double cos_q3 = cos(q3);
    const double x0 = thigh_com_from_knee + thigh_com_to_hip;
    const double x1 = shank_com_from_foot + shank_com_to_knee;
    const double x2 = x0 + x1;
    const double x3 = -sin_q1*x2;
    const double x4 = cos_q1*x2;
    const double x5 = sin_q2*x0 + x3;
    const double x6 = -cos_q2*x0 + x4;
    const double x7 = sin_q3*x1 + x5;
    const double x8 = -cos_q3*x1 + x6;
    out[0] = 0.0;
    out[1] = 0.0;
    out[2] = x3;
    out[3] = x4;
    out[4] = x5;
    out[5] = x6;
    out[6] = x7;
    out[7] = x8;
    out[8] = x7;
    out[9] = x8;
}

/* Accelerations qdd = -D^-1 h (h including any forcing) as -adj(D) h / det(D), cofactors and one division, out (>= n,). */
void wk_kneed_plain_locked_accel(const double *q, const double *qd, const double *p, double *out)
{
    const double q1 = q[0];
    const double q2 = q[1];
    const double q1_dot = qd[0];
    const double q2_dot = qd[1];
    const double mass_hip = p[0];
    const double mass_thigh = p[1];
    const double mass_shank = p[2];
    const double shank_com_from_foot = p[3];
    const double shank_com_to_knee = p[4];
    const double thigh_com_from_knee = p[5];
    const double thigh_com_to_hip = p[6];
    const double g = p[13];
    const double sin_q1 = sin(q1);
    const double cos_q1 = cos(q1);
    const double sin_q2 = sin(q2);
    const double cos_q2 = cos(q2);
    const double x0 = shank_com_from_foot*shank_com_from_foot;
    const double x1 = shank_com_to_knee*shank_com_to_knee;
    const double x2 = thigh_com_from_knee*thigh_com_from_knee;
    const double x3 = thigh_com_to_hip*thigh_com_to_hip;
    const double x4 = 2.0*x0;
    const double x5 = 2.0*mass_thigh;
    const double x6 = mass_hip*shank_com_from_foot;
    const double x7 = 2.0*x6;
    const double x8 = mass_hip*shank_com_to_knee;
    const double x9 = 2.0*x8;
    const double x10 = mass_hip*thigh_com_from_knee;
    const double x11 = 2.0*thigh_com_to_hip;
    const double x12 = mass_shank*shank_com_to_knee;
    const double x13 = 2.0*shank_com_from_foot;
    const double x14 = mass_shank*thigh_com_from_knee;
    const double x15 = mass_shank*thigh_com_to_hip;
    const double x16 = mass_thigh*thigh_com_to_hip;
    const double x17 = 2.0*thigh_com_from_knee;
    const double x18 = 4.0*mass_thigh*shank_com_from_foot;
    const double x19 = mass_shank*x1 + mass_shank*x2 + mass_shank*x3 + mass_thigh*x3 + x11*x12 + x11*x14 + x12*x17;
    const double x20 = x12 + x14 + x15 + x16;
    const double x21 = x20*(shank_com_from_foot + shank_com_to_knee + thigh_com_from_knee + thigh_com_to_hip);
    const double x22 = x21*(-cos_q1*sin_q2 + cos_q2*sin_q1);
    const double d00 = mass_hip*x0 + mass_hip*x1 + mass_hip*x2 + mass_hip*x3 + mass_shank*x4 + 4.0*mass_thigh*shank_com_to_knee*thigh_com_from_knee + mass_thigh*x4 + 2.0*shank_com_to_knee*x16 + shank_com_to_knee*x18 + shank_com_to_knee*x7 + thigh_com_from_knee*x18 + thigh_com_from_knee*x7 + thigh_com_from_knee*x9 + thigh_com_to_hip*x7 + thigh_com_to_hip*x9 + x1*x5 + x10*x11 + x12*x13 + x13*x14 + x13*x15 + x13*x16 + x16*x17 + x19 + x2*x5;
    const double d10 = -x21*(cos_q1*cos_q2 + sin_q1*sin_q2);
    const double d11 = x19;
    const double h0 = -g*sin_q1*(mass_hip*thigh_com_to_hip + mass_shank*x13 + shank_com_from_foot*x5 + shank_com_to_knee*x5 + thigh_com_from_knee*x5 + x10 + x20 + x6 + x8) - q2_dot*q2_dot*x22;
    const double h1 = g*sin_q2*x20 + q1_dot*q1_dot*x22;
    const double c00 = d11;
    const double c10 = -d10;
    const double c11 = d00;
    const double det = d00*c00 + d10*c10;
    const double inv_det = 1.0/det;
    const double z0 = -(c00*h0 + c10*h1)*inv_det;
    const double z1 = -(c10*h0 + c11*h1)*inv_det;
    out[0] = z0;
    out[1] = z1;
}

/* d qdd / d (q, qd), out (n, 2n), fused with the solve: D^-1 = adj(D) / det(D) (one division) applied to every column. */
void wk_kneed_plain_locked_accel_jac(const double *q, const double *qd, const double *p, double *out)
{
    const double q1 = q[0];
    const double q2 = q[1];
    const double q1_dot = qd[0];
    const double q2_dot = qd[1];
    const double mass_hip = p[0];
    const double mass_thigh = p[1];
    const double mass_shank = p[2];
    const double shank_com_from_foot = p[3];
    const double shank_com_to_knee = p[4];
    const double thigh_com_from_knee = p[5];
    const double thigh_com_to_hip = p[6];
    const double g = p[13];
    const double sin_q1 = sin(q1);
    const double cos_q1 = cos(q1);
    const double sin_q2 = sin(q2);
    const double cos_q2 = cos(q2);
    const double x0 = shank_com_from_foot*shank_com_from_foot;
    const double x1 = shank_com_to_knee*shank_com_to_knee;
    const double x2 = thigh_com_from_knee*thigh_com_from_knee;
    const double x3 = thigh_com_to_hip*thigh_com_to_hip;
    const double x4 = 2.0*x0;
    const double x5 = 2.0*mass_thigh;
    const double x6 = mass_hip*shank_com_from_foot;
    const double x7 = 2.0*x6;
    const double x8 = mass_hip*shank_com_to_knee;
    const double x9 = 2.0*x8;
    const double x10 = mass_hip*thigh_com_from_knee;
    const double x11 = 2.0*thigh_com_to_hip;
    const double x12 = mass_shank*shank_com_to_knee;
    const double x13 = 2.0*shank_com_from_foot;
    const double x14 = mass_shank*thigh_com_from_knee;
    const double x15 = mass_shank*thigh_com_to_hip;
    const double x16 = mass_thigh*thigh_com_to_hip;
    const double x17 = 2.0*thigh_com_from_knee;
    const double x18 = 4.0*mass_thigh*shank_com_from_foot;
    const double x19 = mass_shank*x1 + mass_shank*x2 + mass_shank*x3 + mass_thigh*x3 + x11*x12 + x11*x14 + x12*x17;
    const double x20 = x12 + x14 + x15 + x16;
    const double x21 = x20*(shank_com_from_foot + shank_com_to_knee + thigh_com_from_knee + thigh_com_to_hip);
    const double x22 = x21*(cos_q1*cos_q2 + sin_q1*sin_q2);
    const double x23 = q2_dot*q2_dot;
    const double x24 = x21*(-cos_q1*sin_q2 + cos_q2*sin_q1);
    const double x25 = g*(mass_hip*thigh_com_to_hip + mass_shank*x13 + shank_com_from_foot*x5 + shank_com_to_knee*x5 + thigh_com_from_knee*x5 + x10 + x20 + x6 + x8);
    const double x26 = g*x20;
    const double x27 = q1_dot*q1_dot;
    const double x28 = x22*x23;
    const double x29 = x22*x27;
    const double x30 = 2.0*x24;
    const double d00 = mass_hip*x0 + mass_hip*x1 + mass_hip*x2 + mass_hip*x3 + mass_shank*x4 + 4.0*mass_thigh*shank_com_to_knee*thigh_com_from_knee + mass_thigh*x4 + 2.0*shank_com_to_knee*x16 + shank_com_to_knee*x18 + shank_com_to_knee*x7 + thigh_com_from_knee*x18 + thigh_com_from_knee*x7 + thigh_com_from_knee*x9 + thigh_com_to_hip*x7 + thigh_com_to_hip*x9 + x1*x5 + x10*x11 + x12*x13 + x13*x14 + x13*x15 + x13*x16 + x16*x17 + x19 + x2*x5;
    const double d10 = -x22;
    const double d11 = x19;
    const double h0 = -sin_q1*x25 - x23*x24;
    const double h1 = sin_q2*x26 + x24*x27;
    const double dD0_00 = 0.0;
    const double dD0_10 = x24;
    const double dD0_11 = 0.0;
    const double dD1_00 = 0.0;
    const double dD1_10 = -x24;
    const double dD1_11 = 0.0;
    const double hq0_0 = -cos_q1*x25 - x28;
    const double hv0_0 = 0.0;
    const double hq1_0 = x29;
    const double hv1_0 = q1_dot*x30;
    const double hq0_1 = x28;
    const double hv0_1 = -q2_dot*x30;
    const double hq1_1 = cos_q2*x26 - x29;
    const double hv1_1 = 0.0;
    const double c00 = d11;
    const double c10 = -d10;
    const double c11 = d00;
    const double det = d00*c00 + d10*c10;
    const double inv_det = 1.0/det;
    const double m00 = c00*inv_det;
    const double m10 = c10*inv_det;
    const double m11 = c11*inv_det;
    const double a0 = -(m00*h0 + m10*h1);
    const double a1 = -(m10*h0 + m11*h1);
    const double r0_0 = hq0_0 + dD0_00*a0 + dD0_10*a1;
    const double r1_0 = hq1_0 + dD0_10*a0 + dD0_11*a1;
    const double jq0_0 = -(m00*r0_0 + m10*r1_0);
    const double jq1_0 = -(m10*r0_0 + m11*r1_0);
    const double jv0_0 = -(m00*hv0_0 + m10*hv1_0);
    const double jv1_0 = -(m10*hv0_0 + m11*hv1_0);
    const double r0_1 = hq0_1 + dD1_00*a0 + dD1_10*a1;
    const double r1_1 = hq1_1 + dD1_10*a0 + dD1_11*a1;
    const double jq0_1 = -(m00*r0_1 + m10*r1_1);
    const double jq1_1 = -(m10*r0_1 + m11*r1_1);
    const double jv0_1 = -(m00*hv0_1 + m10*hv1_1);
    const double jv1_1 = -(m10*hv0_1 + m11*hv1_1);
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
void wk_kneed_plain_locked_mass_matrix(const double *q, const double *p, double *out)
{
    const double q1 = q[0];
    const double q2 = q[1];
    const double mass_hip = p[0];
    const double mass_thigh = p[1];
    const double mass_shank = p[2];
    const double shank_com_from_foot = p[3];
    const double shank_com_to_knee = p[4];
    const double thigh_com_from_knee = p[5];
    const double thigh_com_to_hip = p[6];
    const double sin_q1 = sin(q1);
    const double cos_q1 = cos(q1);
    const double sin_q2 = sin(q2);
    const double cos_q2 = cos(q2);
    const double x0 = shank_com_from_foot*shank_com_from_foot;
    const double x1 = shank_com_to_knee*shank_com_to_knee;
    const double x2 = thigh_com_from_knee*thigh_com_from_knee;
    const double x3 = thigh_com_to_hip*thigh_com_to_hip;
    const double x4 = 2.0*x0;
    const double x5 = 2.0*mass_thigh;
    const double x6 = 2.0*mass_hip;
    const double x7 = shank_com_from_foot*shank_com_to_knee;
    const double x8 = shank_com_from_foot*x6;
    const double x9 = shank_com_to_knee*x6;
    const double x10 = mass_shank*shank_com_to_knee;
    const double x11 = 2.0*shank_com_from_foot;
    const double x12 = mass_shank*thigh_com_from_knee;
    const double x13 = mass_shank*thigh_com_to_hip;
    const double x14 = mass_thigh*thigh_com_to_hip;
    const double x15 = 2.0*x14;
    const double x16 = 4.0*mass_thigh;
    const double x17 = thigh_com_from_knee*x16;
    const double x18 = 2.0*x10;
    const double x19 = mass_shank*x1 + mass_shank*x2 + mass_shank*x3 + mass_thigh*x3 + thigh_com_from_knee*x18 + 2.0*thigh_com_to_hip*x12 + thigh_com_to_hip*x18;
    const double x20 = -(cos_q1*cos_q2 + sin_q1*sin_q2)*(shank_com_from_foot + shank_com_to_knee + thigh_com_from_knee + thigh_com_to_hip)*(x10 + x12 + x13 + x14);
    out[0] = mass_hip*x0 + mass_hip*x1 + mass_hip*x2 + mass_hip*x3 + mass_shank*x4 + mass_thigh*x4 + shank_com_from_foot*x17 + shank_com_to_knee*x15 + shank_com_to_knee*x17 + thigh_com_from_knee*thigh_com_to_hip*x6 + thigh_com_from_knee*x15 + thigh_com_from_knee*x8 + thigh_com_from_knee*x9 + thigh_com_to_hip*x8 + thigh_com_to_hip*x9 + x1*x5 + x10*x11 + x11*x12 + x11*x13 + x11*x14 + x16*x7 + x19 + x2*x5 + x6*x7;
    out[1] = x20;
    out[2] = x20;
    out[3] = x19;
}

/* Named points in the world frame, out (n_points, 2); names in LOCKED_POINTS. */
void wk_kneed_plain_locked_points(const double *q, const double *p, double *out)
{
    const double q1 = q[0];
    const double q2 = q[1];
    const double shank_com_from_foot = p[3];
    const double shank_com_to_knee = p[4];
    const double thigh_com_from_knee = p[5];
    const double thigh_com_to_hip = p[6];
    const double sin_q1 = sin(q1);
    const double cos_q1 = cos(q1);
    const double sin_q2 = sin(q2);
    const double cos_q2 = cos(q2);
    const double x0 = thigh_com_from_knee + thigh_com_to_hip;
    const double x1 = shank_com_from_foot + shank_com_to_knee + x0;
    const double x2 = -x1;
    const double x3 = sin_q1*x2;
    const double x4 = cos_q1*x1;
    const double x5 = sin_q2*x1 + x3;
    const double x6 = cos_q2*x2 + x4;
    out[0] = 0.0;
    out[1] = 0.0;
    out[2] = x3;
    out[3] = x4;
    out[4] = sin_q2*x0 + x3;
    out[5] = -cos_q2*x0 + x4;
    out[6] = x5;
    out[7] = x6;
    out[8] = x5;
    out[9] = x6;
}

/* Jacobian of the hip position, out (2, n). */
void wk_kneed_plain_locked_hip_jac(const double *q, const double *p, double *out)
{
    const double q1 = q[0];
    const double shank_com_from_foot = p[3];
    const double shank_com_to_knee = p[4];
    const double thigh_com_from_knee = p[5];
    const double thigh_com_to_hip = p[6];
    const double sin_q1 = sin(q1);
    const double cos_q1 = cos(q1);
    const double x0 = -shank_com_from_foot - shank_com_to_knee - thigh_com_from_knee - thigh_com_to_hip;
    out[0] = cos_q1*x0;
    out[1] = 0.0;
    out[2] = sin_q1*x0;
    out[3] = 0.0;
}

/* Floating-base mass matrix, out (n_f, n_f). */
void wk_kneed_plain_ext_mass_matrix(const double *q, const double *p, double *out)
{
    const double q1 = q[0];
    const double q2 = q[1];
    const double mass_hip = p[0];
    const double mass_thigh = p[1];
    const double mass_shank = p[2];
    const double shank_com_to_knee = p[4];
    const double thigh_com_from_knee = p[5];
    const double thigh_com_to_hip = p[6];
    const double sin_q1 = sin(q1);
    const double cos_q1 = cos(q1);
    const double sin_q2 = sin(q2);
    const double cos_q2 = cos(q2);
    const double x0 = thigh_com_to_hip*thigh_com_to_hip;
    const double x1 = mass_shank*shank_com_to_knee;
    const double x2 = 2.0*x1;
    const double x3 = mass_shank*thigh_com_from_knee;
    const double x4 = mass_shank*shank_com_to_knee*shank_com_to_knee + mass_shank*thigh_com_from_knee*thigh_com_from_knee + mass_shank*x0 + mass_thigh*x0 + thigh_com_from_knee*x2 + thigh_com_to_hip*x2 + 2.0*thigh_com_to_hip*x3;
    const double x5 = mass_shank*thigh_com_to_hip + mass_thigh*thigh_com_to_hip + x1 + x3;
    const double x6 = cos_q1*x5;
    const double x7 = sin_q1*x5;
    const double x8 = cos_q2*x5;
    const double x9 = sin_q2*x5;
    const double x10 = mass_hip + 2.0*mass_shank + 2.0*mass_thigh;
    out[0] = x4;
    out[1] = 0.0;
    out[2] = x6;
    out[3] = x7;
    out[4] = 0.0;
    out[5] = x4;
    out[6] = x8;
    out[7] = x9;
    out[8] = x6;
    out[9] = x8;
    out[10] = x10;
    out[11] = 0.0;
    out[12] = x7;
    out[13] = x9;
    out[14] = 0.0;
    out[15] = x10;
}

/* Jacobian of the swing foot's material contact velocity, out (2, n_f). */
void wk_kneed_plain_ext_swing_contact_jac(const double *q, const double *p, double *out)
{
    const double q2 = q[1];
    const double shank_com_from_foot = p[3];
    const double shank_com_to_knee = p[4];
    const double thigh_com_from_knee = p[5];
    const double thigh_com_to_hip = p[6];
    const double sin_q2 = sin(q2);
    const double cos_q2 = cos(q2);
    const double x0 = shank_com_from_foot + shank_com_to_knee + thigh_com_from_knee + thigh_com_to_hip;
    out[0] = 0.0;
    out[1] = cos_q2*x0;
    out[2] = 1.0;
    out[3] = 0.0;
    out[4] = 0.0;
    out[5] = sin_q2*x0;
    out[6] = 0.0;
    out[7] = 1.0;
}

/* Jacobian of the stance foot's material contact velocity, out (2, n_f). */
void wk_kneed_plain_ext_stance_contact_jac(const double *q, const double *p, double *out)
{
    const double q1 = q[0];
    const double shank_com_from_foot = p[3];
    const double shank_com_to_knee = p[4];
    const double thigh_com_from_knee = p[5];
    const double thigh_com_to_hip = p[6];
    const double sin_q1 = sin(q1);
    const double cos_q1 = cos(q1);
    const double x0 = shank_com_from_foot + shank_com_to_knee + thigh_com_from_knee + thigh_com_to_hip;
    out[0] = cos_q1*x0;
    out[1] = 0.0;
    out[2] = 1.0;
    out[3] = 0.0;
    out[4] = sin_q1*x0;
    out[5] = 0.0;
    out[6] = 0.0;
    out[7] = 1.0;
}
