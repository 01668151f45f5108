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
#ifndef WK_GENERATED_DOUBLE_PENDULUM_H
#define WK_GENERATED_DOUBLE_PENDULUM_H

/* The planar double pendulum (elbow-manipulator coordinates). */
#define WK_DOUBLE_PENDULUM_KERNEL_HASH "8bc88c67611405c10247b2a55fecc1cee0746fdd047d2b9edfb4a31f594b5604"

/* Accelerations qdd = -D^-1 (h - Q), Q the joint-damping forcing, by unrolled Cholesky, out (>= n,). [out[2]] */
void wk_double_pendulum_accel(const double *q, const double *qd, const double *p, double *out);
/* d qdd / d (q, qd), out (n, 2n), fused with the Cholesky solve. [out[2][4] row-major] */
void wk_double_pendulum_accel_jac(const double *q, const double *qd, const double *p, double *out);
/* Mass matrix D(q), out (n, n). [out[2][2] row-major] */
void wk_double_pendulum_mass_matrix(const double *q, const double *p, double *out);
/* Coriolis matrix C(q, qd), out (n, n). [out[2][2] row-major] */
void wk_double_pendulum_coriolis(const double *q, const double *qd, const double *p, double *out);
/* Gravity vector g(q) = dP/dq, out (n,). [out[2]] */
void wk_double_pendulum_gravity(const double *q, const double *p, double *out);
/* h(q, qd) = C(q, qd) qd + g(q), out (n,). [out[2]] */
void wk_double_pendulum_bias(const double *q, const double *qd, const double *p, double *out);
/* Generalized joint-damping forces Q(q, qd), out (n,); power Q.qd <= 0. [out[2]] */
void wk_double_pendulum_forcing(const double *q, const double *qd, const double *p, double *out);
/* dD/dq_k for every k, out (n, n, n): out[k] = dD/dq_k. [out[2][2][2] row-major] */
void wk_double_pendulum_dmass(const double *q, const double *p, double *out);
/* dh/dq, out (n, n). [out[2][2] row-major] */
void wk_double_pendulum_dbias_dq(const double *q, const double *qd, const double *p, double *out);
/* dh/dqd, out (n, n). [out[2][2] row-major] */
void wk_double_pendulum_dbias_dqd(const double *q, const double *qd, const double *p, double *out);
/* Kinetic energy [J]. [returns a double] */
double wk_double_pendulum_kinetic(const double *q, const double *qd, const double *p);
/* Potential energy [J] (y = 0 at the origin). [returns a double] */
double wk_double_pendulum_potential(const double *q, const double *p);
/* Named points in the world frame, out (n_points, 2); names in POINTS. [out[2][2] row-major] */
void wk_double_pendulum_points(const double *q, const double *p, double *out);

#endif
