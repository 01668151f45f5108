/* walker's actuated walkers compiled in C: three_link (walker/models/three_link.py) and
 * five_link (walker/models/five_link.py), closed loop with the controllers of wk_control.h
 * and the joint friction of wk_friction.h.  model_three_link.c and model_five_link.c port
 * the numba phase functions with the same operations in the same order.
 *
 * Registry entries (wk_models.h): wk_entry_three_link ("three_link") and
 * wk_entry_five_link ("five_link"), whose fn.ctx is NULL (the built-in controller); the same
 * functions are exported as wk_model_<name>_{rhs, guards, reset, jac, energy, points,
 * start_phase}.
 *
 * Sizes: three_link n_x 8, 3 coordinates, 2 inputs, 10 guards, 2 impulses, 4 points,
 * 9 phases; five_link n_x 12, 5 coordinates, 4 inputs, 15 guards, 2 impulses, 6 points,
 * 81 phases.
 *
 * User controllers (extension point)
 * ----------------------------------
 * Every function of both models (rhs, guards, reset, jac, energy, points, start_phase)
 * takes a trailing ``void *ctx``.  NULL selects the built-in controller
 * (wk_control_controller_torque on the controller block of p).  Otherwise ctx must point to
 * a wk_controller that stays alive while the model is used; where the model needs the torque
 * it calls
 *
 *     saturated = ctl->torque(q, qd, D, h, B, p, u, ctl->user)
 *
 * with q, qd the coordinates and rates (n), D the mass matrix (n x n, row-major), h = C qd
 * + g (n), B the input map (n x (n - 1), row-major), p the model's whole parameter vector
 * (the controller block starts at WK_THREE_LINK_CONTROL_OFFSET / WK_FIVE_LINK_CONTROL_OFFSET)
 * and ``user`` passed through unchanged; it writes the n - 1 torques into u and returns
 * nonzero if it clipped them (the state's saturated_time integrates that flag).  It must
 * not modify its inputs and must be deterministic in them (guards, the Jacobian's
 * differences and the resets recompute the torque).  The joint friction and the rest of the
 * model stay as they are: the controller sees neither.  A ctx with torque == NULL also
 * selects the built-in controller.  Anything yielding a C function pointer of that type can
 * be used (a numba cfunc, ctypes, another extension): the extension need not be rebuilt.
 */
#ifndef WK_ACTUATED_H
#define WK_ACTUATED_H

#include "wk_system.h"
#include "wk_models.h"

typedef int (*wk_torque_fn)(const double *q, const double *qd, const double *D,
                            const double *h, const double *B, const double *p, double *u,
                            void *user);

typedef struct {
    wk_torque_fn torque; /* NULL: the built-in controller */
    void *user;
} wk_controller;

/* Index of the controller block in p (walker.models.<model>.CONTROL_OFFSET). */
#define WK_THREE_LINK_CONTROL_OFFSET WK_THREE_LINK_P_CONTROLLER
#define WK_FIVE_LINK_CONTROL_OFFSET WK_FIVE_LINK_P_CONTROLLER

#define WK_DECLARE_ACTUATED(name)                                                           \
    void wk_model_##name##_rhs(int64_t phase, double t, const double *x, const double *p,   \
                               double *dx, void *ctx);                                      \
    void wk_model_##name##_guards(int64_t phase, double t, const double *x, const double *p,\
                                  double *g, void *ctx);                                    \
    void wk_model_##name##_reset(int64_t phase, int64_t k, double t, const double *x,       \
                                 const double *p, double *x_new, double *impulse,           \
                                 int64_t *out, void *ctx);                                  \
    void wk_model_##name##_jac(int64_t phase, double t, const double *x, const double *p,   \
                               double *J, void *ctx);                                       \
    void wk_model_##name##_energy(const double *x, const double *p, double *out, void *ctx);\
    void wk_model_##name##_points(const double *x, const double *p, double *out, void *ctx);\
    void wk_model_##name##_start_phase(const double *x, const double *p, double *out,       \
                                       void *ctx);                                          \
    extern const wk_model_entry wk_entry_##name;

WK_DECLARE_ACTUATED(three_link)
WK_DECLARE_ACTUATED(five_link)

#endif
