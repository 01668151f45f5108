/* generated, do not edit: walker C kernels for `kneed`
 * input hash: sha256:d61ae4d28bac087b8c18759817447135bbda444186b5f0ce7fab97b551e5dfb8
 * sympy 1.14.0; regenerate with `python scripts/generate_kernels.py`
 * argument order:
 *   q = [q1, q2, q3]
 *   qd = [q1_dot, q2_dot, q3_dot]
 *   p = [mass_hip, mass_thigh, mass_shank, shank_com_from_foot, shank_com_to_knee, thigh_com_from_knee, thigh_com_to_hip, inertia_thigh, inertia_shank, offset_thigh, offset_shank, foot_radius, slope, g, damping_hip, damping_knee, damping_ankle]
 *   q = [q1, q2]
 *   qd = [q1_dot, q2_dot]
 *   q = [q1, q2, x_hip, y_hip]
 * kernels:
 *   wk_kneed_unlocked_accel(q, qd, p, out)
 *   wk_kneed_unlocked_accel_jac(q, qd, p, out)
 *   wk_kneed_unlocked_mass_matrix(q, p, out)
 *   wk_kneed_unlocked_coriolis(q, qd, p, out)
 *   wk_kneed_unlocked_gravity(q, p, out)
 *   wk_kneed_unlocked_bias(q, qd, p, out)
 *   wk_kneed_unlocked_forcing(q, qd, p, out)
 *   wk_kneed_unlocked_dmass(q, p, out)
 *   wk_kneed_unlocked_dbias_dq(q, qd, p, out)
 *   wk_kneed_unlocked_dbias_dqd(q, qd, p, out)
 *   wk_kneed_unlocked_kinetic(q, qd, p)
 *   wk_kneed_unlocked_potential(q, p)
 *   wk_kneed_unlocked_points(q, p, out)
 *   wk_kneed_locked_accel(q, qd, p, out)
 *   wk_kneed_locked_accel_jac(q, qd, p, out)
 *   wk_kneed_locked_mass_matrix(q, p, out)
 *   wk_kneed_locked_coriolis(q, qd, p, out)
 *   wk_kneed_locked_gravity(q, p, out)
 *   wk_kneed_locked_bias(q, qd, p, out)
 *   wk_kneed_locked_forcing(q, qd, p, out)
 *   wk_kneed_locked_dmass(q, p, out)
 *   wk_kneed_locked_dbias_dq(q, qd, p, out)
 *   wk_kneed_locked_dbias_dqd(q, qd, p, out)
 *   wk_kneed_locked_kinetic(q, qd, p)
 *   wk_kneed_locked_potential(q, p)
 *   wk_kneed_locked_points(q, p, out)
 *   wk_kneed_locked_hip_jac(q, p, out)
 *   wk_kneed_ext_mass_matrix(q, p, out)
 *   wk_kneed_ext_swing_contact_jac(q, p, out)
 *   wk_kneed_ext_stance_contact_jac(q, p, out)
 */
#ifndef WK_GENERATED_KNEED_H
#define WK_GENERATED_KNEED_H

/* Kneed walker: knee-free (3-DOF) and knee-locked (2-DOF) swing, floating base. */
#define WK_KNEED_KERNEL_HASH "d61ae4d28bac087b8c18759817447135bbda444186b5f0ce7fab97b551e5dfb8"

/* Accelerations qdd = -D^-1 (h - Q), Q the joint-damping forcing, by unrolled Cholesky, out (>= n,). [out[3]] */
void wk_kneed_unlocked_accel(const double *q, const double *qd, const double *p, double *out);
/* d qdd / d (q, qd), out (n, 2n), fused with the Cholesky solve. [out[3][6] row-major] */
void wk_kneed_unlocked_accel_jac(const double *q, const double *qd, const double *p, double *out);
/* Mass matrix D(q), out (n, n). [out[3][3] row-major] */
void wk_kneed_unlocked_mass_matrix(const double *q, const double *p, double *out);
/* Coriolis matrix C(q, qd), out (n, n). [out[3][3] row-major] */
void wk_kneed_unlocked_coriolis(const double *q, const double *qd, const double *p, double *out);
/* Gravity vector g(q) = dP/dq, out (n,). [out[3]] */
void wk_kneed_unlocked_gravity(const double *q, const double *p, double *out);
/* h(q, qd) = C(q, qd) qd + g(q), out (n,). [out[3]] */
void wk_kneed_unlocked_bias(const double *q, const double *qd, const double *p, double *out);
/* Generalized joint-damping forces Q(q, qd), out (n,); power Q.qd <= 0. [out[3]] */
void wk_kneed_unlocked_forcing(const double *q, const double *qd, const double *p, double *out);
/* dD/dq_k for every k, out (n, n, n): out[k] = dD/dq_k. [out[3][3][3] row-major] */
void wk_kneed_unlocked_dmass(const double *q, const double *p, double *out);
/* dh/dq, out (n, n). [out[3][3] row-major] */
void wk_kneed_unlocked_dbias_dq(const double *q, const double *qd, const double *p, double *out);
/* dh/dqd, out (n, n). [out[3][3] row-major] */
void wk_kneed_unlocked_dbias_dqd(const double *q, const double *qd, const double *p, double *out);
/* Kinetic energy [J]. [returns a double] */
double wk_kneed_unlocked_kinetic(const double *q, const double *qd, const double *p);
/* Potential energy [J] (y = 0 at the origin). [returns a double] */
double wk_kneed_unlocked_potential(const double *q, const double *p);
/* Named points in the world frame, out (n_points, 2); names in UNLOCKED_POINTS. [out[5][2] row-major] */
void wk_kneed_unlocked_points(const double *q, const double *p, double *out);
/* Accelerations qdd = -D^-1 (h - Q), Q the joint-damping forcing, by unrolled Cholesky, out (>= n,). [out[2]] */
void wk_kneed_locked_accel(const double *q, const double *qd, const double *p, double *out);
/* d qdd / d (q, qd), out (n, 2n), fused with the Cholesky solve. [out[2][4] row-major] */
void wk_kneed_locked_accel_jac(const double *q, const double *qd, const double *p, double *out);
/* Mass matrix D(q), out (n, n). [out[2][2] row-major] */
void wk_kneed_locked_mass_matrix(const double *q, const double *p, double *out);
/* Coriolis matrix C(q, qd), out (n, n). [out[2][2] row-major] */
void wk_kneed_locked_coriolis(const double *q, const double *qd, const double *p, double *out);
/* Gravity vector g(q) = dP/dq, out (n,). [out[2]] */
void wk_kneed_locked_gravity(const double *q, const double *p, double *out);
/* h(q, qd) = C(q, qd) qd + g(q), out (n,). [out[2]] */
void wk_kneed_locked_bias(const double *q, const double *qd, const double *p, double *out);
/* Generalized joint-damping forces Q(q, qd), out (n,); power Q.qd <= 0. [out[2]] */
void wk_kneed_locked_forcing(const double *q, const double *qd, const double *p, double *out);
/* dD/dq_k for every k, out (n, n, n): out[k] = dD/dq_k. [out[2][2][2] row-major] */
void wk_kneed_locked_dmass(const double *q, const double *p, double *out);
/* dh/dq, out (n, n). [out[2][2] row-major] */
void wk_kneed_locked_dbias_dq(const double *q, const double *qd, const double *p, double *out);
/* dh/dqd, out (n, n). [out[2][2] row-major] */
void wk_kneed_locked_dbias_dqd(const double *q, const double *qd, const double *p, double *out);
/* Kinetic energy [J]. [returns a double] */
double wk_kneed_locked_kinetic(const double *q, const double *qd, const double *p);
/* Potential energy [J] (y = 0 at the origin). [returns a double] */
double wk_kneed_locked_potential(const double *q, const double *p);
/* Named points in the world frame, out (n_points, 2); names in LOCKED_POINTS. [out[5][2] row-major] */
void wk_kneed_locked_points(const double *q, const double *p, double *out);
/* Jacobian of the hip position, out (2, n). [out[2][2] row-major] */
void wk_kneed_locked_hip_jac(const double *q, const double *p, double *out);
/* Floating-base mass matrix, out (n_f, n_f). [out[4][4] row-major] */
void wk_kneed_ext_mass_matrix(const double *q, const double *p, double *out);
/* Jacobian of the swing foot's material contact velocity, out (2, n_f). [out[2][4] row-major] */
void wk_kneed_ext_swing_contact_jac(const double *q, const double *p, double *out);
/* Jacobian of the stance foot's material contact velocity, out (2, n_f). [out[2][4] row-major] */
void wk_kneed_ext_stance_contact_jac(const double *q, const double *p, double *out);

#endif
