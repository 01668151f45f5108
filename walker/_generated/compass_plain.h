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
#ifndef WK_GENERATED_COMPASS_PLAIN_H
#define WK_GENERATED_COMPASS_PLAIN_H

/* Compass gait: single-support dynamics and the floating-base heel-strike model. */
#define WK_COMPASS_PLAIN_KERNEL_HASH "811c41dfceee04839ad8be75ac78a0c217e42181fceeaf19ad31cc365cbab24b"

/* Accelerations qdd = -D^-1 h (h including any forcing) as -adj(D) h / det(D), cofactors and one division, out (>= n,). [out[2]] */
void wk_compass_plain_accel(const double *q, const double *qd, const double *p, double *out);
/* d qdd / d (q, qd), out (n, 2n), fused with the solve: D^-1 = adj(D) / det(D) (one division) applied to every column. [out[2][4] row-major] */
void wk_compass_plain_accel_jac(const double *q, const double *qd, const double *p, double *out);
/* accel_jac and the accelerations in one call, out (n, 2n+1): columns 0..2n-1 d qdd / d (q, qd), bit for bit those of accel_jac (the same lowering), column 2n qdd = -D^-1 h as the Jacobian's solve computes it (accel's to round-off). [out[2][5] row-major] */
void wk_compass_plain_accel_and_jac(const double *q, const double *qd, const double *p, double *out);
/* Mass matrix D(q), out (n, n). [out[2][2] row-major] */
void wk_compass_plain_mass_matrix(const double *q, const double *p, double *out);
/* Named points in the world frame, out (n_points, 2); names in POINTS. [out[4][2] row-major] */
void wk_compass_plain_points(const double *q, const double *p, double *out);
/* Jacobian of the hip position, out (2, n). [out[2][2] row-major] */
void wk_compass_plain_hip_jac(const double *q, const double *p, double *out);
/* Floating-base mass matrix, out (n_f, n_f). [out[4][4] row-major] */
void wk_compass_plain_ext_mass_matrix(const double *q, const double *p, double *out);
/* Jacobian of the swing foot's material contact velocity, out (2, n_f). [out[2][4] row-major] */
void wk_compass_plain_ext_swing_contact_jac(const double *q, const double *p, double *out);
/* Jacobian of the stance foot's material contact velocity, out (2, n_f). [out[2][4] row-major] */
void wk_compass_plain_ext_stance_contact_jac(const double *q, const double *p, double *out);

/* Hoisted kernels: p is the parameter vector (WK_<CNAME>_CONSTANTS_AT entries)
 * followed by the constants wk_compass_plain_constants computes from it. */
#define WK_COMPASS_PLAIN_CONSTANTS_AT 10
#define WK_COMPASS_PLAIN_N_CONSTANTS 15
void wk_compass_plain_constants(const double *p, double *out);
void wk_compass_plain_accel_hoisted(const double *q, const double *qd, const double *p, double *out);
void wk_compass_plain_accel_jac_hoisted(const double *q, const double *qd, const double *p, double *out);
void wk_compass_plain_accel_and_jac_hoisted(const double *q, const double *qd, const double *p, double *out);

#endif
