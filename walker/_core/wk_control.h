/* The feedback controllers of walker's actuated walkers: C port of the compiled functions in
 * walker/control.py (same operations in the same order, so that the torques agree with the
 * numba functions to the bit).
 *
 * The controller block ``c`` is a slice of a model's parameter vector (three_link:
 * p + 11, five_link: p + 14); its layout is the one documented in walker/control.py:
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

/* walker.control.bezier: the degree-4 Bezier polynomial with coefficients a[0..4] and its
 * first two derivatives at s, into *b, *db, *d2b. */
void wk_control_bezier(const double *a, double s, double *b, double *db, double *d2b);

/* walker.control.outputs: y, yd (n - 1), H ((n - 1) x n) and cterm (n - 1) of the virtual
 * constraints y = q[1:] - b(s) for the controller block c. */
void wk_control_outputs(const double *q, const double *qd, const double *c, double *y,
                        double *yd, double *H, double *cterm, int n);

/* walker.control.controller_torque: the saturated torque u (n - 1) of the controller in
 * block c, for the mass matrix D (n x n), h = C qd + g (n) and the input map B
 * (n x (n - 1)); none of them is modified.  Returns 1 if some component was clipped to the
 * limit, else 0. */
int wk_control_controller_torque(const double *q, const double *qd, const double *D,
                                 const double *h, const double *B, const double *c, double *u,
                                 int n);

#endif
