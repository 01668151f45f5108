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
#ifndef WK_GENERATED_THREE_LINK_H
#define WK_GENERATED_THREE_LINK_H

/* Grizzle's three-link walker (legs and torso, hip actuators): pinned dynamics, ground reaction, floating-base heel-strike model. */
#define WK_THREE_LINK_KERNEL_HASH "a162faf890df7b6133d08ac36e4a7e368ab8541829f506da26532d7555d1285b"

/* Accelerations qdd = -D^-1 h by unrolled Cholesky, out (>= n,). [out[3]] */
void wk_three_link_accel(const double *q, const double *qd, const double *p, double *out);
/* d qdd / d (q, qd), out (n, 2n), fused with the Cholesky solve. [out[3][6] row-major] */
void wk_three_link_accel_jac(const double *q, const double *qd, const double *p, double *out);
/* Mass matrix D(q), out (n, n). [out[3][3] row-major] */
void wk_three_link_mass_matrix(const double *q, const double *p, double *out);
/* Coriolis matrix C(q, qd), out (n, n). [out[3][3] row-major] */
void wk_three_link_coriolis(const double *q, const double *qd, const double *p, double *out);
/* Gravity vector g(q) = dP/dq, out (n,). [out[3]] */
void wk_three_link_gravity(const double *q, const double *p, double *out);
/* h(q, qd) = C(q, qd) qd + g(q), out (n,). [out[3]] */
void wk_three_link_bias(const double *q, const double *qd, const double *p, double *out);
/* dD/dq_k for every k, out (n, n, n): out[k] = dD/dq_k. [out[3][3][3] row-major] */
void wk_three_link_dmass(const double *q, const double *p, double *out);
/* dh/dq, out (n, n). [out[3][3] row-major] */
void wk_three_link_dbias_dq(const double *q, const double *qd, const double *p, double *out);
/* dh/dqd, out (n, n). [out[3][3] row-major] */
void wk_three_link_dbias_dqd(const double *q, const double *qd, const double *p, double *out);
/* Kinetic energy [J]. [returns a double] */
double wk_three_link_kinetic(const double *q, const double *qd, const double *p);
/* Potential energy [J] (y = 0 at the origin). [returns a double] */
double wk_three_link_potential(const double *q, const double *p);
/* Named points in the world frame, out (n_points, 2); names in POINTS. [out[4][2] row-major] */
void wk_three_link_points(const double *q, const double *p, double *out);
/* Jacobian of the hip position, out (2, n). [out[2][3] row-major] */
void wk_three_link_hip_jac(const double *q, const double *p, double *out);
/* World-frame ground force on the stance foot (F_x, F_y) [N], out (2,). [out[2]] */
void wk_three_link_ground_reaction(const double *q, const double *qd, const double *qdd, const double *p, double *out);
/* Floating-base mass matrix, out (5, 5). [out[5][5] row-major] */
void wk_three_link_ext_mass_matrix(const double *q, const double *p, double *out);
/* Jacobian of the swing foot position, out (2, 5). [out[2][5] row-major] */
void wk_three_link_ext_swing_contact_jac(const double *q, const double *p, double *out);
/* Jacobian of the stance foot position, out (2, 5). [out[2][5] row-major] */
void wk_three_link_ext_stance_contact_jac(const double *q, const double *p, double *out);

#endif
