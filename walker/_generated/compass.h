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
#ifndef WK_GENERATED_COMPASS_H
#define WK_GENERATED_COMPASS_H

/* Compass gait: single-support dynamics and the floating-base heel-strike model. */
#define WK_COMPASS_KERNEL_HASH "ad6c018dc54b381378e570439f1bf50a0c64d859e711bdf1df7716a42de0392a"

/* Accelerations qdd = -D^-1 (h - Q), Q the joint-damping forcing, by unrolled Cholesky, out (>= n,). [out[2]] */
void wk_compass_accel(const double *q, const double *qd, const double *p, double *out);
/* d qdd / d (q, qd), out (n, 2n), fused with the Cholesky solve. [out[2][4] row-major] */
void wk_compass_accel_jac(const double *q, const double *qd, const double *p, double *out);
/* Mass matrix D(q), out (n, n). [out[2][2] row-major] */
void wk_compass_mass_matrix(const double *q, const double *p, double *out);
/* Coriolis matrix C(q, qd), out (n, n). [out[2][2] row-major] */
void wk_compass_coriolis(const double *q, const double *qd, const double *p, double *out);
/* Gravity vector g(q) = dP/dq, out (n,). [out[2]] */
void wk_compass_gravity(const double *q, const double *p, double *out);
/* h(q, qd) = C(q, qd) qd + g(q), out (n,). [out[2]] */
void wk_compass_bias(const double *q, const double *qd, const double *p, double *out);
/* Generalized joint-damping forces Q(q, qd), out (n,); power Q.qd <= 0. [out[2]] */
void wk_compass_forcing(const double *q, const double *qd, const double *p, double *out);
/* dD/dq_k for every k, out (n, n, n): out[k] = dD/dq_k. [out[2][2][2] row-major] */
void wk_compass_dmass(const double *q, const double *p, double *out);
/* dh/dq, out (n, n). [out[2][2] row-major] */
void wk_compass_dbias_dq(const double *q, const double *qd, const double *p, double *out);
/* dh/dqd, out (n, n). [out[2][2] row-major] */
void wk_compass_dbias_dqd(const double *q, const double *qd, const double *p, double *out);
/* Kinetic energy [J]. [returns a double] */
double wk_compass_kinetic(const double *q, const double *qd, const double *p);
/* Potential energy [J] (y = 0 at the origin). [returns a double] */
double wk_compass_potential(const double *q, const double *p);
/* Named points in the world frame, out (n_points, 2); names in POINTS. [out[4][2] row-major] */
void wk_compass_points(const double *q, const double *p, double *out);
/* Jacobian of the hip position, out (2, n). [out[2][2] row-major] */
void wk_compass_hip_jac(const double *q, const double *p, double *out);
/* Floating-base mass matrix, out (n_f, n_f). [out[4][4] row-major] */
void wk_compass_ext_mass_matrix(const double *q, const double *p, double *out);
/* Jacobian of the swing foot's material contact velocity, out (2, n_f). [out[2][4] row-major] */
void wk_compass_ext_swing_contact_jac(const double *q, const double *p, double *out);
/* Jacobian of the stance foot's material contact velocity, out (2, n_f). [out[2][4] row-major] */
void wk_compass_ext_stance_contact_jac(const double *q, const double *p, double *out);

#endif
