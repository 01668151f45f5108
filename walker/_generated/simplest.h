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
#ifndef WK_GENERATED_SIMPLEST_H
#define WK_GENERATED_SIMPLEST_H

/* Garcia's simplest walker (limit of the point-mass compass gait). */
#define WK_SIMPLEST_KERNEL_HASH "780618c2198beadffb0d97746b9f5afe921c180e70d4079c1175e643c2b74945"

/* (theta_ddot, phi_ddot), out (2,). [out[2]] */
void wk_simplest_accel(const double *q, const double *qd, const double *p, double *out);
/* d accel / d x, out (2, 4). [out[2][4] row-major] */
void wk_simplest_daccel_dx(const double *q, const double *qd, const double *p, double *out);

#endif
