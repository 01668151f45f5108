/* generated, do not edit: walker C kernels for `simplest`
 * input hash: sha256:780618c2198beadffb0d97746b9f5afe921c180e70d4079c1175e643c2b74945
 * sympy 1.14.0; regenerate with `python scripts/generate_kernels.py`
 * argument order:
 *   q = [theta, phi]
 *   qd = [theta_dot, phi_dot]
 *   p = [slope, g, leg_length, damping_ankle]
 * kernels:
 *   wk_simplest_accel(q, qd, p, out)
 *   wk_simplest_daccel_dx(q, qd, p, out)
 */
#include <math.h>

#include "simplest.h"

/* (theta_ddot, phi_ddot), out (2,). */
void wk_simplest_accel(const double *q, const double *qd, const double *p, double *out)
{
    const double theta = q[0];
    const double phi = q[1];
    const double theta_dot = qd[0];
    const double slope = p[0];
    const double g = p[1];
    const double leg_length = p[2];
    const double damping_ankle = p[3];
    const double x0 = sin(theta);
    const double x1 = x0*x0;
    const double x2 = sin(slope);
    const double x3 = leg_length*x2*x2;
    const double x4 = x1*x3;
    const double x5 = cos(theta);
    const double x6 = x5*x5;
    const double x7 = x3*x6;
    const double x8 = cos(slope);
    const double x9 = leg_length*x8*x8;
    const double x10 = x1*x9;
    const double x11 = x6*x9;
    const double x12 = 1.0/(x10 + x11 + x4 + x7);
    const double x13 = x2*x5;
    const double x14 = damping_ankle*theta_dot*sqrt(g*leg_length);
    const double x15 = g*x0*x8;
    const double x16 = phi - theta;
    const double x17 = sin(x16);
    const double x18 = x17*x17;
    const double x19 = cos(x16);
    const double x20 = x19*x19;
    const double x21 = 1.0/(x10*x18 + x10*x20 + x11*x18 + x11*x20 + x18*x4 + x18*x7 + x20*x4 + x20*x7);
    const double x22 = x18*x21;
    const double x23 = x20*x21;
    const double x24 = g*x21;
    const double x25 = g*x13;
    const double x26 = x17*x24;
    const double x27 = x19*x21;
    const double x28 = x27*x5;
    const double x29 = x17*x21;
    const double x30 = x0*x0*x0*x27;
    const double x31 = theta_dot*theta_dot;
    const double x32 = x3*x31;
    const double x33 = x29*x5*x5*x5;
    const double x34 = x31*x9;
    const double x35 = x0*x27*x31;
    const double x36 = x29*x31*x5;
    out[0] = g*x0*x12*x8 - g*x12*x13 - x12*x14;
    out[1] = -x0*x13*x26 - x0*x14*x29 - x1*x19*x2*x24 + x10*x36 + x11*x35 - x14*x22 - x14*x23 + x14*x28 + x15*x22 + x15*x23 - x15*x28 - x22*x25 - x23*x25 - x26*x6*x8 + x30*x32 + x30*x34 + x32*x33 + x33*x34 + x35*x7 + x36*x4;
}

/* d accel / d x, out (2, 4). */
void wk_simplest_daccel_dx(const double *q, const double *qd, const double *p, double *out)
{
    const double theta = q[0];
    const double phi = q[1];
    const double theta_dot = qd[0];
    const double slope = p[0];
    const double g = p[1];
    const double leg_length = p[2];
    const double damping_ankle = p[3];
    const double x0 = sin(theta);
    const double x1 = x0*x0;
    const double x2 = sin(slope);
    const double x3 = x2*x2;
    const double x4 = leg_length*x3;
    const double x5 = x1*x4;
    const double x6 = cos(theta);
    const double x7 = x6*x6;
    const double x8 = x4*x7;
    const double x9 = cos(slope);
    const double x10 = x9*x9;
    const double x11 = leg_length*x10;
    const double x12 = x1*x11;
    const double x13 = x11*x7;
    const double x14 = 1.0/(x12 + x13 + x5 + x8);
    const double x15 = g*x14;
    const double x16 = x0*x2;
    const double x17 = x6*x9;
    const double x18 = damping_ankle*sqrt(g*leg_length);
    const double x19 = phi - theta;
    const double x20 = sin(x19);
    const double x21 = x20*x20;
    const double x22 = cos(x19);
    const double x23 = x22*x22;
    const double x24 = 1.0/(x12*x21 + x12*x23 + x13*x21 + x13*x23 + x21*x5 + x21*x8 + x23*x5 + x23*x8);
    const double x25 = g*x24;
    const double x26 = x21*x25;
    const double x27 = x23*x25;
    const double x28 = x22*x9;
    const double x29 = x0*x20;
    const double x30 = x25*x7;
    const double x31 = x22*x6;
    const double x32 = x16*x25*x31;
    const double x33 = x18*x24;
    const double x34 = theta_dot*x33;
    const double x35 = x0*x22;
    const double x36 = x20*x6;
    const double x37 = theta_dot*theta_dot;
    const double x38 = x24*x37;
    const double x39 = x0*x0*x0;
    const double x40 = x20*x39;
    const double x41 = x6*x6*x6;
    const double x42 = x29*x38;
    const double x43 = x22*x39;
    const double x44 = 2.0*theta_dot*x24;
    const double x45 = x4*x44;
    const double x46 = x20*x41;
    const double x47 = x11*x44;
    const double x48 = x35*x44;
    const double x49 = x36*x44;
    out[0] = x15*x16 + x15*x17;
    out[1] = 0.0;
    out[2] = -x14*x18;
    out[3] = 0.0;
    out[4] = x1*x25*x28 + x16*x26 + x16*x27 + x17*x25*x29 + x17*x26 + x17*x27 - x2*x20*x30 - x32;
    out[5] = g*x0*x20*x24*x6*x9 + g*x1*x2*x20*x24 + leg_length*x1*x10*x22*x24*x37*x6 + leg_length*x1*x22*x24*x3*x37*x6 + leg_length*x10*x22*x24*x37*x41 + leg_length*x22*x24*x3*x37*x41 - x11*x38*x40 - x13*x42 - x28*x30 - x32 - x34*x35 - x34*x36 - x38*x4*x40 - x42*x8;
    out[6] = x12*x49 + x13*x48 - x21*x33 - x23*x33 - x29*x33 + x31*x33 + x43*x45 + x43*x47 + x45*x46 + x46*x47 + x48*x8 + x49*x5;
    out[7] = 0.0;
}
