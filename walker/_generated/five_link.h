/* generated, do not edit: walker C kernels for `five_link`
 * input hash: sha256:569a037187e79580aabb748214409590fd9cd6303ac0ac752f7c978ea916d9f7
 * sympy 1.14.0; regenerate with `python scripts/generate_kernels.py`
 * argument order:
 *   q = [q_leg, q_knee, q_torso, q_femur_sw, q_tibia_sw]
 *   qd = [q_leg_dot, q_knee_dot, q_torso_dot, q_femur_sw_dot, q_tibia_sw_dot]
 *   p = [mass_torso, mass_femur, mass_tibia, length_femur, length_tibia, com_torso, com_femur, com_tibia, inertia_torso, inertia_femur, inertia_tibia, slope, g, rotor_inertia]
 *   qdd = [q_leg_ddot, q_knee_ddot, q_torso_ddot, q_femur_sw_ddot, q_tibia_sw_ddot]
 *   q = [q_leg, q_knee, q_torso, q_femur_sw, q_tibia_sw, x_hip, y_hip]
 * kernels:
 *   wk_five_link_accel(q, qd, p, out)
 *   wk_five_link_accel_jac(q, qd, p, out)
 *   wk_five_link_mass_matrix(q, p, out)
 *   wk_five_link_coriolis(q, qd, p, out)
 *   wk_five_link_gravity(q, p, out)
 *   wk_five_link_bias(q, qd, p, out)
 *   wk_five_link_dmass(q, p, out)
 *   wk_five_link_dbias_dq(q, qd, p, out)
 *   wk_five_link_dbias_dqd(q, qd, p, out)
 *   wk_five_link_kinetic(q, qd, p)
 *   wk_five_link_potential(q, p)
 *   wk_five_link_points(q, p, out)
 *   wk_five_link_hip_jac(q, p, out)
 *   wk_five_link_ground_reaction(q, qd, qdd, p, out)
 *   wk_five_link_ext_mass_matrix(q, p, out)
 *   wk_five_link_ext_swing_contact_jac(q, p, out)
 *   wk_five_link_ext_stance_contact_jac(q, p, out)
 */
#ifndef WK_GENERATED_FIVE_LINK_H
#define WK_GENERATED_FIVE_LINK_H

/* Five-link walker (torso, femurs, tibias; hip and knee actuators; RABBIT-like): pinned dynamics, ground reaction, floating-base heel-strike model. */
#define WK_FIVE_LINK_KERNEL_HASH "569a037187e79580aabb748214409590fd9cd6303ac0ac752f7c978ea916d9f7"

/* Accelerations qdd = -D^-1 h by unrolled Cholesky, out (>= n,). [out[5]] */
void wk_five_link_accel(const double *q, const double *qd, const double *p, double *out);
/* d qdd / d (q, qd), out (n, 2n), fused with the Cholesky solve. [out[5][10] row-major] */
void wk_five_link_accel_jac(const double *q, const double *qd, const double *p, double *out);
/* Mass matrix D(q), out (n, n). [out[5][5] row-major] */
void wk_five_link_mass_matrix(const double *q, const double *p, double *out);
/* Coriolis matrix C(q, qd), out (n, n). [out[5][5] row-major] */
void wk_five_link_coriolis(const double *q, const double *qd, const double *p, double *out);
/* Gravity vector g(q) = dP/dq, out (n,). [out[5]] */
void wk_five_link_gravity(const double *q, const double *p, double *out);
/* h(q, qd) = C(q, qd) qd + g(q), out (n,). [out[5]] */
void wk_five_link_bias(const double *q, const double *qd, const double *p, double *out);
/* dD/dq_k for every k, out (n, n, n): out[k] = dD/dq_k. [out[5][5][5] row-major] */
void wk_five_link_dmass(const double *q, const double *p, double *out);
/* dh/dq, out (n, n). [out[5][5] row-major] */
void wk_five_link_dbias_dq(const double *q, const double *qd, const double *p, double *out);
/* dh/dqd, out (n, n). [out[5][5] row-major] */
void wk_five_link_dbias_dqd(const double *q, const double *qd, const double *p, double *out);
/* Kinetic energy [J]. [returns a double] */
double wk_five_link_kinetic(const double *q, const double *qd, const double *p);
/* Potential energy [J] (y = 0 at the origin). [returns a double] */
double wk_five_link_potential(const double *q, const double *p);
/* Named points in the world frame, out (n_points, 2); names in POINTS. [out[6][2] row-major] */
void wk_five_link_points(const double *q, const double *p, double *out);
/* Jacobian of the hip position, out (2, n). [out[2][5] row-major] */
void wk_five_link_hip_jac(const double *q, const double *p, double *out);
/* World-frame ground force on the stance foot (F_x, F_y) [N], out (2,). [out[2]] */
void wk_five_link_ground_reaction(const double *q, const double *qd, const double *qdd, const double *p, double *out);
/* Floating-base mass matrix, out (7, 7). [out[7][7] row-major] */
void wk_five_link_ext_mass_matrix(const double *q, const double *p, double *out);
/* Jacobian of the swing foot position, out (2, 7). [out[2][7] row-major] */
void wk_five_link_ext_swing_contact_jac(const double *q, const double *p, double *out);
/* Jacobian of the stance foot position, out (2, 7). [out[2][7] row-major] */
void wk_five_link_ext_stance_contact_jac(const double *q, const double *p, double *out);

#endif
