/* generated, do not edit: walker C kernels for `double_pendulum`
 * input hash: sha256:8bc88c67611405c10247b2a55fecc1cee0746fdd047d2b9edfb4a31f594b5604
 * sympy 1.14.0; regenerate with `python scripts/generate_kernels.py`
 * argument order:
 *   q = [q1, q2]
 *   qd = [q1_dot, q2_dot]
 *   p = [mass_1, mass_2, inertia_1, inertia_2, length_1, length_2, com_1, com_2, g, damping_1, damping_2, coulomb_1, coulomb_2]
 * kernels:
 *   wk_double_pendulum_accel(q, qd, p, out)
 *   wk_double_pendulum_accel_jac(q, qd, p, out)
 *   wk_double_pendulum_mass_matrix(q, p, out)
 *   wk_double_pendulum_coriolis(q, qd, p, out)
 *   wk_double_pendulum_gravity(q, p, out)
 *   wk_double_pendulum_bias(q, qd, p, out)
 *   wk_double_pendulum_forcing(q, qd, p, out)
 *   wk_double_pendulum_dmass(q, p, out)
 *   wk_double_pendulum_dbias_dq(q, qd, p, out)
 *   wk_double_pendulum_dbias_dqd(q, qd, p, out)
 *   wk_double_pendulum_kinetic(q, qd, p)
 *   wk_double_pendulum_potential(q, p)
 *   wk_double_pendulum_points(q, p, out)
 */
#include <math.h>

#include "double_pendulum.h"

/* Accelerations qdd = -D^-1 (h - Q), Q the joint-damping forcing, by unrolled Cholesky, out (>= n,). */
void wk_double_pendulum_accel(const double *q, const double *qd, const double *p, double *out)
{
    const double q1 = q[0];
    const double q2 = q[1];
    const double q1_dot = qd[0];
    const double q2_dot = qd[1];
    const double mass_1 = p[0];
    const double mass_2 = p[1];
    const double inertia_1 = p[2];
    const double inertia_2 = p[3];
    const double length_1 = p[4];
    const double com_1 = p[6];
    const double com_2 = p[7];
    const double g = p[8];
    const double damping_1 = p[9];
    const double damping_2 = p[10];
    const double x0 = cos(q1);
    const double x1 = x0*x0;
    const double x2 = com_1*com_1*mass_1;
    const double x3 = sin(q1);
    const double x4 = x3*x3;
    const double x5 = length_1*length_1*mass_2;
    const double x6 = length_1*x0;
    const double x7 = q1 + q2;
    const double x8 = cos(x7);
    const double x9 = com_2*x8;
    const double x10 = mass_2*x9;
    const double x11 = x10*x6;
    const double x12 = length_1*x3;
    const double x13 = sin(x7);
    const double x14 = com_2*mass_2*x13;
    const double x15 = x12*x14;
    const double x16 = com_2*com_2*mass_2;
    const double x17 = inertia_2 + x13*x13*x16 + x16*x8*x8;
    const double x18 = g*mass_2;
    const double x19 = x10*x12 - x14*x6;
    const double x20 = q1_dot*x19;
    const double d00 = inertia_1 + x1*x2 + x1*x5 + 2.0*x11 + 2.0*x15 + x17 + x2*x4 + x4*x5;
    const double d10 = x11 + x15 + x17;
    const double d11 = x17;
    const double h0 = com_1*g*mass_1*x0 + damping_1*q1_dot + q2_dot*x20 + q2_dot*(q2_dot*x19 + x20) + x18*(x6 + x9);
    const double h1 = damping_2*q2_dot - q1_dot*q1_dot*x19 + x18*x9;
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
void wk_double_pendulum_accel_jac(const double *q, const double *qd, const double *p, double *out)
{
    const double q1 = q[0];
    const double q2 = q[1];
    const double q1_dot = qd[0];
    const double q2_dot = qd[1];
    const double mass_1 = p[0];
    const double mass_2 = p[1];
    const double inertia_1 = p[2];
    const double inertia_2 = p[3];
    const double length_1 = p[4];
    const double com_1 = p[6];
    const double com_2 = p[7];
    const double g = p[8];
    const double damping_1 = p[9];
    const double damping_2 = p[10];
    const double x0 = cos(q1);
    const double x1 = x0*x0;
    const double x2 = com_1*com_1*mass_1;
    const double x3 = sin(q1);
    const double x4 = x3*x3;
    const double x5 = length_1*length_1*mass_2;
    const double x6 = length_1*x0;
    const double x7 = q1 + q2;
    const double x8 = cos(x7);
    const double x9 = com_2*x8;
    const double x10 = mass_2*x9;
    const double x11 = x10*x6;
    const double x12 = length_1*x3;
    const double x13 = sin(x7);
    const double x14 = com_2*x13;
    const double x15 = mass_2*x14;
    const double x16 = x12*x15;
    const double x17 = com_2*com_2*mass_2;
    const double x18 = inertia_2 + x13*x13*x17 + x17*x8*x8;
    const double x19 = x11 + x16;
    const double x20 = com_1*g*mass_1;
    const double x21 = g*mass_2;
    const double x22 = x10*x12;
    const double x23 = x15*x6;
    const double x24 = x22 - x23;
    const double x25 = q1_dot*x24;
    const double x26 = q2_dot*x24;
    const double x27 = q1_dot*q1_dot;
    const double x28 = -x24;
    const double x29 = 2.0*x26;
    const double x30 = x14*x21;
    const double x31 = -x30;
    const double x32 = -x19;
    const double x33 = q1_dot*x32;
    const double d00 = inertia_1 + x1*x2 + x1*x5 + 2.0*x11 + 2.0*x16 + x18 + x2*x4 + x4*x5;
    const double d10 = x18 + x19;
    const double d11 = x18;
    const double h0 = damping_1*q1_dot + q2_dot*x25 + q2_dot*(x25 + x26) + x0*x20 + x21*(x6 + x9);
    const double h1 = damping_2*q2_dot + x21*x9 + x27*x28;
    const double dD0_00 = 0.0;
    const double dD0_10 = 0.0;
    const double dD0_11 = 0.0;
    const double dD1_00 = 2.0*x22 - 2.0*x23;
    const double dD1_10 = x24;
    const double dD1_11 = 0.0;
    const double hq0_0 = g*mass_2*(-x12 - x14) - x20*x3;
    const double hv0_0 = damping_1 + x29;
    const double hq1_0 = x31;
    const double hv1_0 = 2.0*q1_dot*x28;
    const double hq0_1 = q2_dot*x33 + q2_dot*(q2_dot*x32 + x33) + x31;
    const double hv0_1 = 2.0*x25 + x29;
    const double hq1_1 = x19*x27 - x30;
    const double hv1_1 = damping_2;
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
void wk_double_pendulum_mass_matrix(const double *q, const double *p, double *out)
{
    const double q1 = q[0];
    const double q2 = q[1];
    const double mass_1 = p[0];
    const double mass_2 = p[1];
    const double inertia_1 = p[2];
    const double inertia_2 = p[3];
    const double length_1 = p[4];
    const double com_1 = p[6];
    const double com_2 = p[7];
    const double x0 = cos(q1);
    const double x1 = x0*x0;
    const double x2 = com_1*com_1*mass_1;
    const double x3 = sin(q1);
    const double x4 = x3*x3;
    const double x5 = length_1*length_1*mass_2;
    const double x6 = q1 + q2;
    const double x7 = cos(x6);
    const double x8 = com_2*length_1*mass_2;
    const double x9 = x0*x7*x8;
    const double x10 = sin(x6);
    const double x11 = x10*x3*x8;
    const double x12 = com_2*com_2*mass_2;
    const double x13 = inertia_2 + x10*x10*x12 + x12*x7*x7;
    const double x14 = x11 + x13 + x9;
    out[0] = inertia_1 + x1*x2 + x1*x5 + 2.0*x11 + x13 + x2*x4 + x4*x5 + 2.0*x9;
    out[1] = x14;
    out[2] = x14;
    out[3] = x13;
}

/* Coriolis matrix C(q, qd), out (n, n). */
void wk_double_pendulum_coriolis(const double *q, const double *qd, const double *p, double *out)
{
    const double q1 = q[0];
    const double q2 = q[1];
    const double q1_dot = qd[0];
    const double q2_dot = qd[1];
    const double mass_2 = p[1];
    const double length_1 = p[4];
    const double com_2 = p[7];
    const double x0 = q1 + q2;
    const double x1 = com_2*length_1*mass_2;
    const double x2 = x1*sin(q1)*cos(x0) - x1*sin(x0)*cos(q1);
    const double x3 = q2_dot*x2;
    out[0] = x3;
    out[1] = q1_dot*x2 + x3;
    out[2] = -q1_dot*x2;
    out[3] = 0.0;
}

/* Gravity vector g(q) = dP/dq, out (n,). */
void wk_double_pendulum_gravity(const double *q, const double *p, double *out)
{
    const double q1 = q[0];
    const double q2 = q[1];
    const double mass_1 = p[0];
    const double mass_2 = p[1];
    const double length_1 = p[4];
    const double com_1 = p[6];
    const double com_2 = p[7];
    const double g = p[8];
    const double x0 = cos(q1);
    const double x1 = com_2*cos(q1 + q2);
    const double x2 = g*mass_2;
    out[0] = com_1*g*mass_1*x0 + x2*(length_1*x0 + x1);
    out[1] = x1*x2;
}

/* h(q, qd) = C(q, qd) qd + g(q), out (n,). */
void wk_double_pendulum_bias(const double *q, const double *qd, const double *p, double *out)
{
    const double q1 = q[0];
    const double q2 = q[1];
    const double q1_dot = qd[0];
    const double q2_dot = qd[1];
    const double mass_1 = p[0];
    const double mass_2 = p[1];
    const double length_1 = p[4];
    const double com_1 = p[6];
    const double com_2 = p[7];
    const double g = p[8];
    const double x0 = cos(q1);
    const double x1 = length_1*x0;
    const double x2 = q1 + q2;
    const double x3 = com_2*cos(x2);
    const double x4 = g*mass_2;
    const double x5 = -com_2*mass_2*x1*sin(x2) + length_1*mass_2*x3*sin(q1);
    const double x6 = q1_dot*x5;
    out[0] = com_1*g*mass_1*x0 + q2_dot*x6 + q2_dot*(q2_dot*x5 + x6) + x4*(x1 + x3);
    out[1] = -q1_dot*q1_dot*x5 + x3*x4;
}

/* Generalized joint-damping forces Q(q, qd), out (n,); power Q.qd <= 0. */
void wk_double_pendulum_forcing(const double *q, const double *qd, const double *p, double *out)
{
    (void)q;
    const double q1_dot = qd[0];
    const double q2_dot = qd[1];
    const double damping_1 = p[9];
    const double damping_2 = p[10];
    out[0] = -damping_1*q1_dot;
    out[1] = -damping_2*q2_dot;
}

/* dD/dq_k for every k, out (n, n, n): out[k] = dD/dq_k. */
void wk_double_pendulum_dmass(const double *q, const double *p, double *out)
{
    const double q1 = q[0];
    const double q2 = q[1];
    const double mass_2 = p[1];
    const double length_1 = p[4];
    const double com_2 = p[7];
    const double x0 = q1 + q2;
    const double x1 = com_2*length_1*mass_2;
    const double x2 = x1*sin(q1)*cos(x0);
    const double x3 = x1*sin(x0)*cos(q1);
    const double x4 = x2 - x3;
    out[0] = 0.0;
    out[1] = 0.0;
    out[2] = 0.0;
    out[3] = 0.0;
    out[4] = 2.0*x2 - 2.0*x3;
    out[5] = x4;
    out[6] = x4;
    out[7] = 0.0;
}

/* dh/dq, out (n, n). */
void wk_double_pendulum_dbias_dq(const double *q, const double *qd, const double *p, double *out)
{
    const double q1 = q[0];
    const double q2 = q[1];
    const double q1_dot = qd[0];
    const double q2_dot = qd[1];
    const double mass_1 = p[0];
    const double mass_2 = p[1];
    const double length_1 = p[4];
    const double com_1 = p[6];
    const double com_2 = p[7];
    const double g = p[8];
    const double x0 = sin(q1);
    const double x1 = length_1*x0;
    const double x2 = q1 + q2;
    const double x3 = com_2*sin(x2);
    const double x4 = g*mass_2*x3;
    const double x5 = -x4;
    const double x6 = com_2*length_1*mass_2*cos(q1)*cos(x2) + mass_2*x1*x3;
    const double x7 = -x6;
    const double x8 = q1_dot*x7;
    out[0] = -com_1*g*mass_1*x0 + g*mass_2*(-x1 - x3);
    out[1] = q2_dot*x8 + q2_dot*(q2_dot*x7 + x8) + x5;
    out[2] = x5;
    out[3] = q1_dot*q1_dot*x6 - x4;
}

/* dh/dqd, out (n, n). */
void wk_double_pendulum_dbias_dqd(const double *q, const double *qd, const double *p, double *out)
{
    const double q1 = q[0];
    const double q2 = q[1];
    const double q1_dot = qd[0];
    const double q2_dot = qd[1];
    const double mass_2 = p[1];
    const double length_1 = p[4];
    const double com_2 = p[7];
    const double x0 = q1 + q2;
    const double x1 = com_2*length_1*mass_2;
    const double x2 = x1*sin(q1)*cos(x0) - x1*sin(x0)*cos(q1);
    const double x3 = 2.0*x2;
    const double x4 = q2_dot*x3;
    out[0] = x4;
    out[1] = q1_dot*x3 + x4;
    out[2] = -2.0*q1_dot*x2;
    out[3] = 0.0;
}

/* Kinetic energy [J]. */
double wk_double_pendulum_kinetic(const double *q, const double *qd, const double *p)
{
    const double q1 = q[0];
    const double q2 = q[1];
    const double q1_dot = qd[0];
    const double q2_dot = qd[1];
    const double mass_1 = p[0];
    const double mass_2 = p[1];
    const double inertia_1 = p[2];
    const double inertia_2 = p[3];
    const double length_1 = p[4];
    const double com_1 = p[6];
    const double com_2 = p[7];
    const double x0 = q1_dot*q1_dot;
    const double x1 = sin(q1);
    const double x2 = com_1*com_1*x0;
    const double x3 = cos(q1);
    const double x4 = q1 + q2;
    const double x5 = com_2*cos(x4);
    const double x6 = com_2*sin(x4);
    return ((1.0/2.0))*inertia_1*x0 + ((1.0/2.0))*inertia_2*(q1_dot + q2_dot)*(q1_dot + q2_dot) + ((1.0/2.0))*mass_1*(x1*x1*x2 + x2*x3*x3) + ((1.0/2.0))*mass_2*((q1_dot*(-length_1*x1 - x6) - q2_dot*x6)*(q1_dot*(-length_1*x1 - x6) - q2_dot*x6) + (q1_dot*(length_1*x3 + x5) + q2_dot*x5)*(q1_dot*(length_1*x3 + x5) + q2_dot*x5));
}

/* Potential energy [J] (y = 0 at the origin). */
double wk_double_pendulum_potential(const double *q, const double *p)
{
    const double q1 = q[0];
    const double q2 = q[1];
    const double mass_1 = p[0];
    const double mass_2 = p[1];
    const double length_1 = p[4];
    const double com_1 = p[6];
    const double com_2 = p[7];
    const double g = p[8];
    const double x0 = sin(q1);
    return com_1*g*mass_1*x0 + g*mass_2*(com_2*sin(q1 + q2) + length_1*x0);
}

/* Named points in the world frame, out (n_points, 2); names in POINTS. */
void wk_double_pendulum_points(const double *q, const double *p, double *out)
{
    const double q1 = q[0];
    const double q2 = q[1];
    const double length_1 = p[4];
    const double length_2 = p[5];
    const double x0 = length_1*cos(q1);
    const double x1 = length_1*sin(q1);
    const double x2 = q1 + q2;
    out[0] = x0;
    out[1] = x1;
    out[2] = length_2*cos(x2) + x0;
    out[3] = length_2*sin(x2) + x1;
}
