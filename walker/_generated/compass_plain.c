/* generated, do not edit: walker C kernels for `compass_plain`
 * input hash: sha256:811c41dfceee04839ad8be75ac78a0c217e42181fceeaf19ad31cc365cbab24b
 * sympy 1.14.0; regenerate with `python scripts/generate_kernels.py`
 * structural variant `plain` of `compass`: these parameters are exactly 0 and
 * never read (the arguments are those of the general kernels):
 *   foot_radius, inertia_leg, damping_hip, damping_ankle;
 * entries simplified (trigsimp; polynomial in sin/cos and qd with factored coefficients);
 * sin and cos of each angle (coordinates, slope) are computed once per call
 * (wk_sincos, walker/_core/wk_sincos.h: within 1 ulp up to pi/4, libm beyond) and
 * sines and cosines of their sums are expanded by the angle-sum identities;
 * accel and accel_jac solve with the mass matrix in closed form, adj(D) / det(D)
 * from its cofactors (one division), not by Cholesky; accel_and_jac is accel_jac
 * with the accelerations its solve computes as one more column.
 * the accel kernels' parameter-only terms are hoisted into <module>_constants,
 * computed once per parameter vector, which the *_hoisted twins read.
 * argument order:
 *   q = [q_stance, q_swing]
 *   qd = [q_stance_dot, q_swing_dot]
 *   p = [mass_hip, mass_leg, com_from_foot, com_to_hip, inertia_leg, foot_radius, slope, g, damping_hip, damping_ankle]
 *   q = [q_stance, q_swing, x_hip, y_hip]
 * kernels:
 *   wk_compass_plain_accel(q, qd, p, out)
 *   wk_compass_plain_accel_jac(q, qd, p, out)
 *   wk_compass_plain_accel_and_jac(q, qd, p, out)
 *   wk_compass_plain_mass_matrix(q, p, out)
 *   wk_compass_plain_points(q, p, out)
 *   wk_compass_plain_hip_jac(q, p, out)
 *   wk_compass_plain_ext_mass_matrix(q, p, out)
 *   wk_compass_plain_ext_swing_contact_jac(q, p, out)
 *   wk_compass_plain_ext_stance_contact_jac(q, p, out)
 */
#include <math.h>

#include "wk_sincos.h"

#include "compass_plain.h"

/* Accelerations qdd = -D^-1 h (h including any forcing) as -adj(D) h / det(D), cofactors and one division, out (>= n,). */
void wk_compass_plain_accel(const double *q, const double *qd, const double *p, double *out)
{
    const double q_stance = q[0];
    const double q_swing = q[1];
    const double q_stance_dot = qd[0];
    const double q_swing_dot = qd[1];
    const double mass_hip = p[0];
    const double mass_leg = p[1];
    const double com_from_foot = p[2];
    const double com_to_hip = p[3];
    const double g = p[7];
    double sin_q_stance, cos_q_stance;
    wk_sincos(q_stance, &sin_q_stance, &cos_q_stance);
    double sin_q_swing, cos_q_swing;
    wk_sincos(q_swing, &sin_q_swing, &cos_q_swing);
    const double x0 = com_from_foot*com_from_foot;
    const double x1 = com_to_hip*com_to_hip;
    const double x2 = mass_leg*x1;
    const double x3 = com_from_foot*mass_hip;
    const double x4 = com_to_hip*mass_leg;
    const double x5 = 2.0*mass_leg;
    const double x6 = x4*(com_from_foot + com_to_hip);
    const double x7 = x6*(-cos_q_stance*sin_q_swing + cos_q_swing*sin_q_stance);
    const double d00 = 2.0*com_from_foot*x4 + 2.0*com_to_hip*x3 + mass_hip*x0 + mass_hip*x1 + x0*x5 + x2;
    const double d10 = -x6*(cos_q_stance*cos_q_swing + sin_q_stance*sin_q_swing);
    const double d11 = x2;
    const double h0 = -g*sin_q_stance*(com_from_foot*x5 + com_to_hip*mass_hip + x3 + x4) - q_swing_dot*q_swing_dot*x7;
    const double h1 = g*sin_q_swing*x4 + q_stance_dot*q_stance_dot*x7;
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
void wk_compass_plain_accel_jac(const double *q, const double *qd, const double *p, double *out)
{
    const double q_stance = q[0];
    const double q_swing = q[1];
    const double q_stance_dot = qd[0];
    const double q_swing_dot = qd[1];
    const double mass_hip = p[0];
    const double mass_leg = p[1];
    const double com_from_foot = p[2];
    const double com_to_hip = p[3];
    const double g = p[7];
    double sin_q_stance, cos_q_stance;
    wk_sincos(q_stance, &sin_q_stance, &cos_q_stance);
    double sin_q_swing, cos_q_swing;
    wk_sincos(q_swing, &sin_q_swing, &cos_q_swing);
    const double x0 = com_from_foot*com_from_foot;
    const double x1 = com_to_hip*com_to_hip;
    const double x2 = mass_leg*x1;
    const double x3 = com_from_foot*mass_hip;
    const double x4 = com_to_hip*mass_leg;
    const double x5 = 2.0*x4;
    const double x6 = 2.0*mass_leg;
    const double x7 = com_from_foot + com_to_hip;
    const double x8 = x4*x7;
    const double x9 = x8*(cos_q_stance*cos_q_swing + sin_q_stance*sin_q_swing);
    const double x10 = g*(com_from_foot*x6 + com_to_hip*mass_hip + x3 + x4);
    const double x11 = q_swing_dot*q_swing_dot;
    const double x12 = -cos_q_stance*sin_q_swing + cos_q_swing*sin_q_stance;
    const double x13 = x12*x8;
    const double x14 = g*x4;
    const double x15 = q_stance_dot*q_stance_dot;
    const double x16 = x11*x9;
    const double x17 = x15*x9;
    const double x18 = x12*x5*x7;
    const double d00 = com_from_foot*x5 + 2.0*com_to_hip*x3 + mass_hip*x0 + mass_hip*x1 + x0*x6 + x2;
    const double d10 = -x9;
    const double d11 = x2;
    const double h0 = -sin_q_stance*x10 - x11*x13;
    const double h1 = sin_q_swing*x14 + x13*x15;
    const double dD0_00 = 0.0;
    const double dD0_10 = x13;
    const double dD0_11 = 0.0;
    const double dD1_00 = 0.0;
    const double dD1_10 = -x13;
    const double dD1_11 = 0.0;
    const double hq0_0 = -cos_q_stance*x10 - x16;
    const double hv0_0 = 0.0;
    const double hq1_0 = x17;
    const double hv1_0 = q_stance_dot*x18;
    const double hq0_1 = x16;
    const double hv0_1 = -q_swing_dot*x18;
    const double hq1_1 = cos_q_swing*x14 - x17;
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

/* accel_jac and the accelerations in one call, out (n, 2n+1): columns 0..2n-1 d qdd / d (q, qd), bit for bit those of accel_jac (the same lowering), column 2n qdd = -D^-1 h as the Jacobian's solve computes it (accel's to round-off). */
void wk_compass_plain_accel_and_jac(const double *q, const double *qd, const double *p, double *out)
{
    const double q_stance = q[0];
    const double q_swing = q[1];
    const double q_stance_dot = qd[0];
    const double q_swing_dot = qd[1];
    const double mass_hip = p[0];
    const double mass_leg = p[1];
    const double com_from_foot = p[2];
    const double com_to_hip = p[3];
    const double g = p[7];
    double sin_q_stance, cos_q_stance;
    wk_sincos(q_stance, &sin_q_stance, &cos_q_stance);
    double sin_q_swing, cos_q_swing;
    wk_sincos(q_swing, &sin_q_swing, &cos_q_swing);
    const double x0 = com_from_foot*com_from_foot;
    const double x1 = com_to_hip*com_to_hip;
    const double x2 = mass_leg*x1;
    const double x3 = com_from_foot*mass_hip;
    const double x4 = com_to_hip*mass_leg;
    const double x5 = 2.0*x4;
    const double x6 = 2.0*mass_leg;
    const double x7 = com_from_foot + com_to_hip;
    const double x8 = x4*x7;
    const double x9 = x8*(cos_q_stance*cos_q_swing + sin_q_stance*sin_q_swing);
    const double x10 = g*(com_from_foot*x6 + com_to_hip*mass_hip + x3 + x4);
    const double x11 = q_swing_dot*q_swing_dot;
    const double x12 = -cos_q_stance*sin_q_swing + cos_q_swing*sin_q_stance;
    const double x13 = x12*x8;
    const double x14 = g*x4;
    const double x15 = q_stance_dot*q_stance_dot;
    const double x16 = x11*x9;
    const double x17 = x15*x9;
    const double x18 = x12*x5*x7;
    const double d00 = com_from_foot*x5 + 2.0*com_to_hip*x3 + mass_hip*x0 + mass_hip*x1 + x0*x6 + x2;
    const double d10 = -x9;
    const double d11 = x2;
    const double h0 = -sin_q_stance*x10 - x11*x13;
    const double h1 = sin_q_swing*x14 + x13*x15;
    const double dD0_00 = 0.0;
    const double dD0_10 = x13;
    const double dD0_11 = 0.0;
    const double dD1_00 = 0.0;
    const double dD1_10 = -x13;
    const double dD1_11 = 0.0;
    const double hq0_0 = -cos_q_stance*x10 - x16;
    const double hv0_0 = 0.0;
    const double hq1_0 = x17;
    const double hv1_0 = q_stance_dot*x18;
    const double hq0_1 = x16;
    const double hv0_1 = -q_swing_dot*x18;
    const double hq1_1 = cos_q_swing*x14 - x17;
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
    out[4] = a0;
    out[5] = jq1_0;
    out[7] = jv1_0;
    out[6] = jq1_1;
    out[8] = jv1_1;
    out[9] = a1;
}

/* Mass matrix D(q), out (n, n). */
void wk_compass_plain_mass_matrix(const double *q, const double *p, double *out)
{
    const double q_stance = q[0];
    const double q_swing = q[1];
    const double mass_hip = p[0];
    const double mass_leg = p[1];
    const double com_from_foot = p[2];
    const double com_to_hip = p[3];
    double sin_q_stance, cos_q_stance;
    wk_sincos(q_stance, &sin_q_stance, &cos_q_stance);
    double sin_q_swing, cos_q_swing;
    wk_sincos(q_swing, &sin_q_swing, &cos_q_swing);
    const double x0 = com_from_foot*com_from_foot;
    const double x1 = com_to_hip*com_to_hip;
    const double x2 = mass_leg*x1;
    const double x3 = com_from_foot*com_to_hip;
    const double x4 = 2.0*mass_leg;
    const double x5 = -com_to_hip*mass_leg*(com_from_foot + com_to_hip)*(cos_q_stance*cos_q_swing + sin_q_stance*sin_q_swing);
    out[0] = mass_hip*x0 + mass_hip*x1 + 2.0*mass_hip*x3 + x0*x4 + x2 + x3*x4;
    out[1] = x5;
    out[2] = x5;
    out[3] = x2;
}

/* Named points in the world frame, out (n_points, 2); names in POINTS. */
void wk_compass_plain_points(const double *q, const double *p, double *out)
{
    const double q_stance = q[0];
    const double q_swing = q[1];
    const double com_from_foot = p[2];
    const double com_to_hip = p[3];
    double sin_q_stance, cos_q_stance;
    wk_sincos(q_stance, &sin_q_stance, &cos_q_stance);
    double sin_q_swing, cos_q_swing;
    wk_sincos(q_swing, &sin_q_swing, &cos_q_swing);
    const double x0 = com_from_foot + com_to_hip;
    const double x1 = -x0;
    const double x2 = sin_q_stance*x1;
    const double x3 = cos_q_stance*x0;
    const double x4 = sin_q_swing*x0 + x2;
    const double x5 = cos_q_swing*x1 + x3;
    out[0] = 0.0;
    out[1] = 0.0;
    out[2] = x2;
    out[3] = x3;
    out[4] = x4;
    out[5] = x5;
    out[6] = x4;
    out[7] = x5;
}

/* Jacobian of the hip position, out (2, n). */
void wk_compass_plain_hip_jac(const double *q, const double *p, double *out)
{
    const double q_stance = q[0];
    const double com_from_foot = p[2];
    const double com_to_hip = p[3];
    double sin_q_stance, cos_q_stance;
    wk_sincos(q_stance, &sin_q_stance, &cos_q_stance);
    const double x0 = -com_from_foot - com_to_hip;
    out[0] = cos_q_stance*x0;
    out[1] = 0.0;
    out[2] = sin_q_stance*x0;
    out[3] = 0.0;
}

/* Floating-base mass matrix, out (n_f, n_f). */
void wk_compass_plain_ext_mass_matrix(const double *q, const double *p, double *out)
{
    const double q_stance = q[0];
    const double q_swing = q[1];
    const double mass_hip = p[0];
    const double mass_leg = p[1];
    const double com_to_hip = p[3];
    double sin_q_stance, cos_q_stance;
    wk_sincos(q_stance, &sin_q_stance, &cos_q_stance);
    double sin_q_swing, cos_q_swing;
    wk_sincos(q_swing, &sin_q_swing, &cos_q_swing);
    const double x0 = com_to_hip*com_to_hip*mass_leg;
    const double x1 = com_to_hip*mass_leg;
    const double x2 = cos_q_stance*x1;
    const double x3 = sin_q_stance*x1;
    const double x4 = cos_q_swing*x1;
    const double x5 = sin_q_swing*x1;
    const double x6 = mass_hip + 2.0*mass_leg;
    out[0] = x0;
    out[1] = 0.0;
    out[2] = x2;
    out[3] = x3;
    out[4] = 0.0;
    out[5] = x0;
    out[6] = x4;
    out[7] = x5;
    out[8] = x2;
    out[9] = x4;
    out[10] = x6;
    out[11] = 0.0;
    out[12] = x3;
    out[13] = x5;
    out[14] = 0.0;
    out[15] = x6;
}

/* Jacobian of the swing foot's material contact velocity, out (2, n_f). */
void wk_compass_plain_ext_swing_contact_jac(const double *q, const double *p, double *out)
{
    const double q_swing = q[1];
    const double com_from_foot = p[2];
    const double com_to_hip = p[3];
    double sin_q_swing, cos_q_swing;
    wk_sincos(q_swing, &sin_q_swing, &cos_q_swing);
    const double x0 = com_from_foot + com_to_hip;
    out[0] = 0.0;
    out[1] = cos_q_swing*x0;
    out[2] = 1.0;
    out[3] = 0.0;
    out[4] = 0.0;
    out[5] = sin_q_swing*x0;
    out[6] = 0.0;
    out[7] = 1.0;
}

/* Jacobian of the stance foot's material contact velocity, out (2, n_f). */
void wk_compass_plain_ext_stance_contact_jac(const double *q, const double *p, double *out)
{
    const double q_stance = q[0];
    const double com_from_foot = p[2];
    const double com_to_hip = p[3];
    double sin_q_stance, cos_q_stance;
    wk_sincos(q_stance, &sin_q_stance, &cos_q_stance);
    const double x0 = com_from_foot + com_to_hip;
    out[0] = cos_q_stance*x0;
    out[1] = 0.0;
    out[2] = 1.0;
    out[3] = 0.0;
    out[4] = sin_q_stance*x0;
    out[5] = 0.0;
    out[6] = 0.0;
    out[7] = 1.0;
}

/* The parameter-only terms of the hoisted kernels (wk_compass_plain_*_hoisted), each
 * computed as the kernel computes it: once per parameter vector p, into out. */
void wk_compass_plain_constants(const double *p, double *out)
{
    { /* accel */
        const double mass_hip = p[0];
        const double mass_leg = p[1];
        const double com_from_foot = p[2];
        const double com_to_hip = p[3];
        const double x0 = com_from_foot*com_from_foot;
        out[0] = x0;
        const double x1 = com_to_hip*com_to_hip;
        out[1] = x1;
        const double x2 = mass_leg*x1;
        out[2] = x2;
        const double x3 = com_from_foot*mass_hip;
        out[3] = x3;
        const double x4 = com_to_hip*mass_leg;
        out[4] = x4;
        const double x5 = 2.0*mass_leg;
        out[5] = x5;
        const double x6 = x4*(com_from_foot + com_to_hip);
        out[6] = x6;
        const double d00 = 2.0*com_from_foot*x4 + 2.0*com_to_hip*x3 + mass_hip*x0 + mass_hip*x1 + x0*x5 + x2;
        out[7] = d00;
        const double d11 = x2;
        out[8] = d11;
    }
    { /* accel_jac */
        const double x0 = out[0];
        const double x1 = out[1];
        const double x2 = out[2];
        const double x3 = out[3];
        const double x4 = out[4];
        const double x6 = out[5];
        const double mass_hip = p[0];
        const double com_from_foot = p[2];
        const double com_to_hip = p[3];
        const double g = p[7];
        const double x5 = 2.0*x4;
        out[9] = x5;
        const double x7 = com_from_foot + com_to_hip;
        out[10] = x7;
        const double x8 = x4*x7;
        out[11] = x8;
        const double x10 = g*(com_from_foot*x6 + com_to_hip*mass_hip + x3 + x4);
        out[12] = x10;
        const double x14 = g*x4;
        out[13] = x14;
        const double d00 = com_from_foot*x5 + 2.0*com_to_hip*x3 + mass_hip*x0 + mass_hip*x1 + x0*x6 + x2;
        out[14] = d00;
    }
}

/* Accelerations qdd = -D^-1 h (h including any forcing) as -adj(D) h / det(D), cofactors and one division, out (>= n,). Hoisted: the parameter-only terms read from p's tail (wk_compass_plain_constants). */
void wk_compass_plain_accel_hoisted(const double *q, const double *qd, const double *p, double *out)
{
    const double q_stance = q[0];
    const double q_swing = q[1];
    const double q_stance_dot = qd[0];
    const double q_swing_dot = qd[1];
    const double mass_hip = p[0];
    const double com_from_foot = p[2];
    const double com_to_hip = p[3];
    const double g = p[7];
    double sin_q_stance, cos_q_stance;
    wk_sincos(q_stance, &sin_q_stance, &cos_q_stance);
    double sin_q_swing, cos_q_swing;
    wk_sincos(q_swing, &sin_q_swing, &cos_q_swing);
    const double x3 = p[WK_COMPASS_PLAIN_CONSTANTS_AT + 3];
    const double x4 = p[WK_COMPASS_PLAIN_CONSTANTS_AT + 4];
    const double x5 = p[WK_COMPASS_PLAIN_CONSTANTS_AT + 5];
    const double x6 = p[WK_COMPASS_PLAIN_CONSTANTS_AT + 6];
    const double x7 = x6*(-cos_q_stance*sin_q_swing + cos_q_swing*sin_q_stance);
    const double d00 = p[WK_COMPASS_PLAIN_CONSTANTS_AT + 7];
    const double d10 = -x6*(cos_q_stance*cos_q_swing + sin_q_stance*sin_q_swing);
    const double d11 = p[WK_COMPASS_PLAIN_CONSTANTS_AT + 8];
    const double h0 = -g*sin_q_stance*(com_from_foot*x5 + com_to_hip*mass_hip + x3 + x4) - q_swing_dot*q_swing_dot*x7;
    const double h1 = g*sin_q_swing*x4 + q_stance_dot*q_stance_dot*x7;
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

/* d qdd / d (q, qd), out (n, 2n), fused with the solve: D^-1 = adj(D) / det(D) (one division) applied to every column. Hoisted: the parameter-only terms read from p's tail (wk_compass_plain_constants). */
void wk_compass_plain_accel_jac_hoisted(const double *q, const double *qd, const double *p, double *out)
{
    const double q_stance = q[0];
    const double q_swing = q[1];
    const double q_stance_dot = qd[0];
    const double q_swing_dot = qd[1];
    double sin_q_stance, cos_q_stance;
    wk_sincos(q_stance, &sin_q_stance, &cos_q_stance);
    double sin_q_swing, cos_q_swing;
    wk_sincos(q_swing, &sin_q_swing, &cos_q_swing);
    const double x5 = p[WK_COMPASS_PLAIN_CONSTANTS_AT + 9];
    const double x7 = p[WK_COMPASS_PLAIN_CONSTANTS_AT + 10];
    const double x8 = p[WK_COMPASS_PLAIN_CONSTANTS_AT + 11];
    const double x9 = x8*(cos_q_stance*cos_q_swing + sin_q_stance*sin_q_swing);
    const double x10 = p[WK_COMPASS_PLAIN_CONSTANTS_AT + 12];
    const double x11 = q_swing_dot*q_swing_dot;
    const double x12 = -cos_q_stance*sin_q_swing + cos_q_swing*sin_q_stance;
    const double x13 = x12*x8;
    const double x14 = p[WK_COMPASS_PLAIN_CONSTANTS_AT + 13];
    const double x15 = q_stance_dot*q_stance_dot;
    const double x16 = x11*x9;
    const double x17 = x15*x9;
    const double x18 = x12*x5*x7;
    const double d00 = p[WK_COMPASS_PLAIN_CONSTANTS_AT + 14];
    const double d10 = -x9;
    const double d11 = p[WK_COMPASS_PLAIN_CONSTANTS_AT + 8];
    const double h0 = -sin_q_stance*x10 - x11*x13;
    const double h1 = sin_q_swing*x14 + x13*x15;
    const double dD0_00 = 0.0;
    const double dD0_10 = x13;
    const double dD0_11 = 0.0;
    const double dD1_00 = 0.0;
    const double dD1_10 = -x13;
    const double dD1_11 = 0.0;
    const double hq0_0 = -cos_q_stance*x10 - x16;
    const double hv0_0 = 0.0;
    const double hq1_0 = x17;
    const double hv1_0 = q_stance_dot*x18;
    const double hq0_1 = x16;
    const double hv0_1 = -q_swing_dot*x18;
    const double hq1_1 = cos_q_swing*x14 - x17;
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

/* accel_jac and the accelerations in one call, out (n, 2n+1): columns 0..2n-1 d qdd / d (q, qd), bit for bit those of accel_jac (the same lowering), column 2n qdd = -D^-1 h as the Jacobian's solve computes it (accel's to round-off). Hoisted: the parameter-only terms read from p's tail (wk_compass_plain_constants). */
void wk_compass_plain_accel_and_jac_hoisted(const double *q, const double *qd, const double *p, double *out)
{
    const double q_stance = q[0];
    const double q_swing = q[1];
    const double q_stance_dot = qd[0];
    const double q_swing_dot = qd[1];
    double sin_q_stance, cos_q_stance;
    wk_sincos(q_stance, &sin_q_stance, &cos_q_stance);
    double sin_q_swing, cos_q_swing;
    wk_sincos(q_swing, &sin_q_swing, &cos_q_swing);
    const double x5 = p[WK_COMPASS_PLAIN_CONSTANTS_AT + 9];
    const double x7 = p[WK_COMPASS_PLAIN_CONSTANTS_AT + 10];
    const double x8 = p[WK_COMPASS_PLAIN_CONSTANTS_AT + 11];
    const double x9 = x8*(cos_q_stance*cos_q_swing + sin_q_stance*sin_q_swing);
    const double x10 = p[WK_COMPASS_PLAIN_CONSTANTS_AT + 12];
    const double x11 = q_swing_dot*q_swing_dot;
    const double x12 = -cos_q_stance*sin_q_swing + cos_q_swing*sin_q_stance;
    const double x13 = x12*x8;
    const double x14 = p[WK_COMPASS_PLAIN_CONSTANTS_AT + 13];
    const double x15 = q_stance_dot*q_stance_dot;
    const double x16 = x11*x9;
    const double x17 = x15*x9;
    const double x18 = x12*x5*x7;
    const double d00 = p[WK_COMPASS_PLAIN_CONSTANTS_AT + 14];
    const double d10 = -x9;
    const double d11 = p[WK_COMPASS_PLAIN_CONSTANTS_AT + 8];
    const double h0 = -sin_q_stance*x10 - x11*x13;
    const double h1 = sin_q_swing*x14 + x13*x15;
    const double dD0_00 = 0.0;
    const double dD0_10 = x13;
    const double dD0_11 = 0.0;
    const double dD1_00 = 0.0;
    const double dD1_10 = -x13;
    const double dD1_11 = 0.0;
    const double hq0_0 = -cos_q_stance*x10 - x16;
    const double hv0_0 = 0.0;
    const double hq1_0 = x17;
    const double hv1_0 = q_stance_dot*x18;
    const double hq0_1 = x16;
    const double hv0_1 = -q_swing_dot*x18;
    const double hq1_1 = cos_q_swing*x14 - x17;
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
    out[4] = a0;
    out[5] = jq1_0;
    out[7] = jv1_0;
    out[6] = jq1_1;
    out[8] = jv1_1;
    out[9] = a1;
}
