/* walker's actuated walkers compiled in C: three_link (walker/models/three_link.py) and
 * five_link (walker/models/five_link.py), closed loop with the controllers of wk_control.h
 * and the joint friction of wk_friction.h.  model_three_link.c and model_five_link.c port
 * the numba phase functions with the same operations in the same order; what the two share
 * is written once in wk_actuated.c (declared at the end of this file).
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

#include <stdbool.h>
#include "wk_system.h"
#include "wk_models.h"
#include "wk_common.h"

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

/* The functions of an actuated model: those of every model (WK_DECLARE_MODEL, wk_common.h),
 * start_phase and the registry entry. */
#define WK_DECLARE_ACTUATED(name)                                                           \
    WK_DECLARE_MODEL(name)                                                                  \
    void wk_model_##name##_start_phase(const double *x, const double *p, double *out,       \
                                       void *ctx);                                          \
    extern const wk_model_entry wk_entry_##name;

WK_DECLARE_ACTUATED(three_link)
WK_DECLARE_ACTUATED(five_link)

/* The phase functions both models share (wk_actuated.c; C ports of the actuated_* functions
 * of walker/models/_common.py, same operations in the same order), written over a table of
 * the model: n coordinates x[0..n), rates x[n..2 n), m joints that are also the inputs
 * (S = B^T, m x n row-major), and
 *   forces(x, p, D, f, u, ctx): the mass matrix D (n x n), the generalized force without dry
 *     friction f (n) and the controller torque u (m); returns 1 when the torque saturated;
 *   dry(p, F): the joints' dry-friction magnitudes F (m);
 *   ground_reaction(q, qd, qdd, p, F): the generated kernel (world frame). */
#define WK_ACTUATED_MAX_Q 5
#define WK_ACTUATED_MAX_X 12

typedef struct {
    int n_q;
    int n_joints;
    const double *S;
    int (*forces)(const double *x, const double *p, double *D, double *f, double *u,
                  void *ctx);
    void (*dry)(const double *p, double *F);
    void (*ground_reaction)(const double *q, const double *qd, const double *qdd,
                            const double *p, double *F);
} wk_actuated_model;

/* The controller's torque u (n - 1) for B (n x (n - 1)): the user's (ctx, above) or the
 * built-in one, wk_control_controller_torque on the block p + control_offset; returns
 * nonzero when it saturated. */
int wk_actuated_torque(void *ctx, const double *q, const double *qd, const double *D,
                       const double *h, const double *B, const double *p, int control_offset,
                       double *u, int n);

/* actuated_closed_loop: closed-loop accelerations qdd (n), torques u (m) and dry-friction
 * torques lam (m) in phase; returns 1 when the controller saturated. */
int wk_actuated_closed_loop(const wk_actuated_model *M, int64_t phase, const double *x,
                            const double *p, double *qdd, double *u, double *lam, void *ctx);

/* central_difference_jac: df/dx (n_x x n_x, row-major) of rhs by central differences, step
 * rel_step * max(1, |x_j|); n_x <= WK_ACTUATED_MAX_X. */
void wk_actuated_jac(wk_rhs_fn rhs, int64_t phase, double t, const double *x, const double *p,
                     double *J, void *ctx, int n_x, double rel_step);

/* slope_frame: (along the slope, normal to it) components of a world vector v (2). */
void wk_slope_frame(const double *v, double slope, double *t, double *n);

/* actuated_force_guards: g_contact[0..2] = (mu F_n - F_t, mu F_n + F_t, F_n) from the
 * ground reaction for the closed-loop accelerations in phase, g_joints (2 m) the joints'
 * friction guards (wk_friction_guards). */
void wk_actuated_force_guards(const wk_actuated_model *M, int64_t phase, const double *x,
                              const double *p, double mu, double slope, double *g_contact,
                              double *g_joints, void *ctx);

/* impact_status: 0 for a physical heel strike (normal impulse positive, inside the friction
 * cone |P_t| <= mu P_n, trailing foot lifting off), WK_NONPHYSICAL_IMPACT otherwise. */
int64_t wk_impact_status(const double *impulse, double lift, double mu);

/* actuated_after_heel_strike: the reset's out after a heel strike that returned status,
 * every joint's mode chosen afresh at x_new (rates projected in place). */
void wk_actuated_after_heel_strike(const wk_actuated_model *M, int64_t phase, int64_t status,
                                   double *x_new, const double *p, int64_t *out, void *ctx);

/* actuated_joint_event: the reset of joint friction event 2 j (slip_stops) or 2 j + 1
 * (stick_breaks) of joint j: rates into x_new, (action, next phase, status) into out. */
void wk_actuated_joint_event(const wk_actuated_model *M, int64_t phase, int64_t event,
                             const double *x, const double *p, double *x_new, int64_t *out,
                             void *ctx);

/* actuated_start_phase: the phase consistent with x (wk_friction_choose_modes). */
int64_t wk_actuated_start_phase(const wk_actuated_model *M, const double *x, const double *p,
                                void *ctx);

#endif
