/* generated, do not edit: walker C kernels for `kneed_plain`
 * input hash: sha256:727c2ccf320cbd3d3877a2115ab03eb384daa0263175b58d5944697e7620df0f
 * sympy 1.14.0; regenerate with `python scripts/generate_kernels.py`
 * structural variant `plain` of `kneed`: these parameters are exactly 0 and
 * never read (the arguments are those of the general kernels):
 *   inertia_thigh, inertia_shank, offset_thigh, offset_shank, foot_radius, damping_hip, damping_knee, damping_ankle;
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
 *   q = [q1, q2, q3]
 *   qd = [q1_dot, q2_dot, q3_dot]
 *   p = [mass_hip, mass_thigh, mass_shank, shank_com_from_foot, shank_com_to_knee, thigh_com_from_knee, thigh_com_to_hip, inertia_thigh, inertia_shank, offset_thigh, offset_shank, foot_radius, slope, g, damping_hip, damping_knee, damping_ankle]
 *   q = [q1, q2]
 *   qd = [q1_dot, q2_dot]
 *   q = [q1, q2, x_hip, y_hip]
 * kernels:
 *   wk_kneed_plain_unlocked_accel(q, qd, p, out)
 *   wk_kneed_plain_unlocked_accel_jac(q, qd, p, out)
 *   wk_kneed_plain_unlocked_accel_and_jac(q, qd, p, out)
 *   wk_kneed_plain_unlocked_mass_matrix(q, p, out)
 *   wk_kneed_plain_unlocked_points(q, p, out)
 *   wk_kneed_plain_locked_accel(q, qd, p, out)
 *   wk_kneed_plain_locked_accel_jac(q, qd, p, out)
 *   wk_kneed_plain_locked_accel_and_jac(q, qd, p, out)
 *   wk_kneed_plain_locked_mass_matrix(q, p, out)
 *   wk_kneed_plain_locked_points(q, p, out)
 *   wk_kneed_plain_locked_hip_jac(q, p, out)
 *   wk_kneed_plain_ext_mass_matrix(q, p, out)
 *   wk_kneed_plain_ext_swing_contact_jac(q, p, out)
 *   wk_kneed_plain_ext_stance_contact_jac(q, p, out)
 */
#ifndef WK_GENERATED_KNEED_PLAIN_H
#define WK_GENERATED_KNEED_PLAIN_H

/* Kneed walker: knee-free (3-DOF) and knee-locked (2-DOF) swing, floating base. */
#define WK_KNEED_PLAIN_KERNEL_HASH "727c2ccf320cbd3d3877a2115ab03eb384daa0263175b58d5944697e7620df0f"

/* Accelerations qdd = -D^-1 h (h including any forcing) as -adj(D) h / det(D), cofactors and one division, out (>= n,). [out[3]] */
void wk_kneed_plain_unlocked_accel(const double *q, const double *qd, const double *p, double *out);
/* d qdd / d (q, qd), out (n, 2n), fused with the solve: D^-1 = adj(D) / det(D) (one division) applied to every column. [out[3][6] row-major] */
void wk_kneed_plain_unlocked_accel_jac(const double *q, const double *qd, const double *p, double *out);
/* accel_jac and the accelerations in one call, out (n, 2n+1): columns 0..2n-1 d qdd / d (q, qd), bit for bit those of accel_jac (the same lowering), column 2n qdd = -D^-1 h as the Jacobian's solve computes it (accel's to round-off). [out[3][7] row-major] */
void wk_kneed_plain_unlocked_accel_and_jac(const double *q, const double *qd, const double *p, double *out);
/* Mass matrix D(q), out (n, n). [out[3][3] row-major] */
void wk_kneed_plain_unlocked_mass_matrix(const double *q, const double *p, double *out);
/* Named points in the world frame, out (n_points, 2); names in UNLOCKED_POINTS. [out[5][2] row-major] */
void wk_kneed_plain_unlocked_points(const double *q, const double *p, double *out);
/* Accelerations qdd = -D^-1 h (h including any forcing) as -adj(D) h / det(D), cofactors and one division, out (>= n,). [out[2]] */
void wk_kneed_plain_locked_accel(const double *q, const double *qd, const double *p, double *out);
/* d qdd / d (q, qd), out (n, 2n), fused with the solve: D^-1 = adj(D) / det(D) (one division) applied to every column. [out[2][4] row-major] */
void wk_kneed_plain_locked_accel_jac(const double *q, const double *qd, const double *p, double *out);
/* accel_jac and the accelerations in one call, out (n, 2n+1): columns 0..2n-1 d qdd / d (q, qd), bit for bit those of accel_jac (the same lowering), column 2n qdd = -D^-1 h as the Jacobian's solve computes it (accel's to round-off). [out[2][5] row-major] */
void wk_kneed_plain_locked_accel_and_jac(const double *q, const double *qd, const double *p, double *out);
/* Mass matrix D(q), out (n, n). [out[2][2] row-major] */
void wk_kneed_plain_locked_mass_matrix(const double *q, const double *p, double *out);
/* Named points in the world frame, out (n_points, 2); names in LOCKED_POINTS. [out[5][2] row-major] */
void wk_kneed_plain_locked_points(const double *q, const double *p, double *out);
/* Jacobian of the hip position, out (2, n). [out[2][2] row-major] */
void wk_kneed_plain_locked_hip_jac(const double *q, const double *p, double *out);
/* Floating-base mass matrix, out (n_f, n_f). [out[4][4] row-major] */
void wk_kneed_plain_ext_mass_matrix(const double *q, const double *p, double *out);
/* Jacobian of the swing foot's material contact velocity, out (2, n_f). [out[2][4] row-major] */
void wk_kneed_plain_ext_swing_contact_jac(const double *q, const double *p, double *out);
/* Jacobian of the stance foot's material contact velocity, out (2, n_f). [out[2][4] row-major] */
void wk_kneed_plain_ext_stance_contact_jac(const double *q, const double *p, double *out);

/* Hoisted kernels: p is the parameter vector (WK_<CNAME>_CONSTANTS_AT entries)
 * followed by the constants wk_kneed_plain_constants computes from it. */
#define WK_KNEED_PLAIN_CONSTANTS_AT 17
#define WK_KNEED_PLAIN_N_CONSTANTS 43
void wk_kneed_plain_constants(const double *p, double *out);
void wk_kneed_plain_unlocked_accel_hoisted(const double *q, const double *qd, const double *p, double *out);
void wk_kneed_plain_unlocked_accel_jac_hoisted(const double *q, const double *qd, const double *p, double *out);
void wk_kneed_plain_unlocked_accel_and_jac_hoisted(const double *q, const double *qd, const double *p, double *out);
void wk_kneed_plain_locked_accel_hoisted(const double *q, const double *qd, const double *p, double *out);
void wk_kneed_plain_locked_accel_jac_hoisted(const double *q, const double *qd, const double *p, double *out);
void wk_kneed_plain_locked_accel_and_jac_hoisted(const double *q, const double *qd, const double *p, double *out);

#endif
