/* The feedback controllers of walker's actuated walkers (the block layout and the Bezier
 * polynomials in walker/models/control.py); the operations are those of walker's former numba
 * controller, in the same order, so that the torques stay bit-identical.
 *
 * The controller block ``c`` is a slice of a model's parameter vector (three_link:
 * p + 11, five_link: p + 14); its layout is the one documented in walker/models/control.py:
 * c[0] mode (0 off, 1 joint-space PD, 2 virtual constraints by computed torque), c[1] kp,
 * c[2] kd, c[3] torque limit, c[4] theta_plus, c[5] theta_minus, c[6:] Bezier coefficients,
 * WK_CONTROL_BEZIER_DEGREE + 1 per output, output after output.
 *
 * Matrices are row-major; ``n`` is the number of coordinates (n - 1 outputs and inputs),
 * at most WK_CONTROL_MAX_N.
 */
#ifndef WK_CONTROL_H
#define WK_CONTROL_H

#define WK_CONTROL_BEZIER_DEGREE 4
#define WK_CONTROL_MODE_OFF 0
#define WK_CONTROL_MODE_PD 1
#define WK_CONTROL_MODE_VIRTUAL_CONSTRAINTS 2
/* Mode 3: the finite-time controller of Bhat and Bernstein
 * on outputs that are plain polynomials in the stance angle, as in the three-link example of
 * Westervelt, Grizzle, Chevallereau, Choi and Morris (2007); see
 * wk_control_finite_time_torque.  Its settings are a second block ``f`` of the model's
 * parameter vector (three_link: p + 28). */
#define WK_CONTROL_MODE_FINITE_TIME 3
#define WK_CONTROL_POLY_DEGREE 5
/* Indices in the finite-time block f. */
#define WK_CONTROL_FT_I_ALPHA 0
#define WK_CONTROL_FT_I_EPSILON 1
#define WK_CONTROL_FT_I_POLY 2
/* Floor on |phi| and |epsilon yd| in the derivatives of v (wk_control_finite_time_linearization):
 * they are singular where the outputs have settled. */
#define WK_CONTROL_FT_JAC_FLOOR 1e-9
/* Indices in the controller block. */
#define WK_CONTROL_I_MODE 0
#define WK_CONTROL_I_KP 1
#define WK_CONTROL_I_KD 2
#define WK_CONTROL_I_LIMIT 3
#define WK_CONTROL_I_THETA_PLUS 4
#define WK_CONTROL_I_THETA_MINUS 5
#define WK_CONTROL_I_BEZIER 6
/* Largest number of coordinates the controller handles (stack buffers). */
#define WK_CONTROL_MAX_N 8

/* walker.models.control.bezier: the degree-4 Bezier polynomial with coefficients a[0..4] and its
 * first two derivatives at s, into *b, *db, *d2b. */
void wk_control_bezier(const double *a, double s, double *b, double *db, double *d2b);

/* walker.models.control.outputs: y, yd (n - 1), H ((n - 1) x n) and cterm (n - 1) of the virtual
 * constraints y = q[1:] - b(s) for the controller block c. */
void wk_control_outputs(const double *q, const double *qd, const double *c, double *y,
                        double *yd, double *H, double *cterm, int n);

/* walker.models.control.controller_torque: the saturated torque u (n - 1) of the controller in
 * block c, for the mass matrix D (n x n), h = C qd + g (n) and the input map B
 * (n x (n - 1)); none of them is modified.  Returns 1 if some component was clipped to the
 * limit, else 0. */
int wk_control_controller_torque(const double *q, const double *qd, const double *D,
                                 const double *h, const double *B, const double *c, double *u,
                                 int n);

/* The finite-time (Bhat-Bernstein) controller on polynomial outputs, by input-output
 * linearization; torque u (n - 1), saturated at c[WK_CONTROL_I_LIMIT], returns 1 if clipped.
 *
 * Outputs y_i = q[i + 1] - P_i(q[0]), P_i(x) = sum_k f[2 + i (D + 1) + k] x^k (D =
 * WK_CONTROL_POLY_DEGREE), output after output.  With alpha = f[0] in (0, 1) and epsilon =
 * f[1] > 0, the output acceleration is set to v_i = psi(y_i, epsilon yd_i) / epsilon^2, where
 * with sig(x, e) = sgn(x) |x|^e:
 *     phi = y + sig(epsilon yd, 2 - alpha) / (2 - alpha),
 *     psi = -sig(epsilon yd, alpha) - sig(phi, alpha / (2 - alpha)),
 * which brings y and yd to zero in finite time (S. P. Bhat, D. S. Bernstein, IEEE TAC 43(5),
 * 1998; Westervelt et al. 2007, the example code control_three_link.m).  The torque solves
 * H D^{-1} (B u - h) - P''(q[0]) qd[0]^2 = v, as in mode 2. */
int wk_control_finite_time_torque(const double *q, const double *qd, const double *D,
                                  const double *h, const double *B, const double *c,
                                  const double *f, double *u, int n);

/* The Jacobian of the closed loop in mode 3: v is not differentiable where an output has
 * settled (the flow kills a transverse perturbation in finite time), so the model's jac
 * differentiates the vector field with v replaced by its linearization about the state,
 * lin[5 i .. 5 i + 4] = (v_i, dv_i/dy_i, dv_i/dyd_i, y_i, yd_i), with |phi| and
 * |epsilon yd| floored at WK_CONTROL_FT_JAC_FLOOR in the singular powers.  After an output
 * settles its perturbations then decay at a finite rate instead of at once; the model's jac
 * also takes a larger difference step in mode 3 (model_three_link.c, JAC_STEP_FT). */
void wk_control_finite_time_linearization(const double *q, const double *qd, const double *f,
                                          double *lin, int n);
int wk_control_finite_time_torque_linearized(const double *q, const double *qd,
                                             const double *D, const double *h,
                                             const double *B, const double *c,
                                             const double *f, const double *lin, double *u,
                                             int n);

#endif
