/* walker's actuated walkers compiled in C: three_link (walker/models/three_link.py) and
 * five_link (walker/models/five_link.py), closed loop with the controllers of wk_control.h
 * and the joint friction of wk_friction.h.  model_three_link.c and model_five_link.c keep
 * the operations of walker's former numba phase functions in the same order; what the two
 * share is written once in wk_actuated.c (declared at the end of this file).
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
 * the model: n coordinates x[0..n), rates x[n..2 n), actuator work x[2 n] and saturated time
 * x[2 n + 1]; m joints that are also the inputs (S = B^T, m x n row-major), and
 *   mass_matrix(q, p, D), bias(q, qd, p, h), ground_reaction(q, qd, qdd, p, F): the
 *     generated kernels of the mass matrix D (n x n), h = C qd + g (n) and the ground
 *     reaction F (world frame);
 *   base: the heel strike's floating base (wk_common.h), also of the generated kernels
 *     (WK_ACTUATED_KERNELS fills these fields);
 *   force(q, qd, D, h, p, f, u, ctx): the generalized force without dry friction f (n) and
 *     the controller torque u (m) at (q, qd) with D and h; returns 1 when the torque
 *     saturated;
 *   dry(p, F): the joints' dry-friction magnitudes F (m);
 *   power(u, x): the actuator power u . (B^T qd) at state x;
 *   relabel(x, qdf_plus, x_new): the leg swap at heel strike of the coordinates x and the
 *     post-impact rates qdf_plus (n + 2) into x_new (2 n);
 *   i_slope, i_friction: the indices of the slope and the foot's friction coefficient in p;
 *   n_base_guards, base_status: the guards before the joints' friction guards, and the
 *     status that ends the run where base guard k >= 1 fires (guard 0 is heel strike). */
#define WK_ACTUATED_MAX_Q 5
#define WK_ACTUATED_MAX_X 12

typedef struct {
    int n_q;
    int n_joints;
    const double *S;
    wk_qp_v mass_matrix;
    wk_qqdp_v bias;
    void (*ground_reaction)(const double *q, const double *qd, const double *qdd,
                            const double *p, double *F);
    wk_floating_base base;
    int (*force)(const double *q, const double *qd, const double *D, const double *h,
                 const double *p, double *f, double *u, void *ctx);
    void (*dry)(const double *p, double *F);
    double (*power)(const double *u, const double *x);
    void (*relabel)(const double *x, const double *qdf_plus, double *x_new);
    int i_slope;
    int i_friction;
    int n_base_guards;
    const int64_t *base_status;
} wk_actuated_model;

/* The fields mass_matrix .. base of the table of actuated model ``name`` of n coordinates: its
 * generated kernels wk_<name>_*, the floating base's n_points drawing points with the hip at
 * row hip_row. */
#define WK_ACTUATED_KERNELS(name, n, n_points, hip_row)                                      \
    wk_##name##_mass_matrix, wk_##name##_bias, wk_##name##_ground_reaction,                  \
    {                                                                                        \
        wk_##name##_points, wk_##name##_hip_jac, wk_##name##_ext_mass_matrix,                \
            wk_##name##_ext_swing_contact_jac, wk_##name##_ext_stance_contact_jac, n,        \
            n_points, hip_row                                                                \
    }

/* A model's reset of its heel-strike guard (guard 0), with the signature of the rest of the
 * reset (wk_reset_fn without k and t). */
typedef void (*wk_strike_fn)(int64_t phase, const double *x, const double *p, double *x_new,
                             double *impulse, int64_t *out, void *ctx);

/* The controller's torque u (n - 1) for B (n x (n - 1)): the user's (ctx, above) or the
 * built-in one, wk_control_controller_torque on the block p + control_offset; returns
 * nonzero when it saturated. */
int wk_actuated_torque(void *ctx, const double *q, const double *qd, const double *D,
                       const double *h, const double *B, const double *p, int control_offset,
                       double *u, int n);

/* The controller's torques u (m) at x, as the rhs computes them (the controller sees no
 * friction, so they do not depend on the phase). */
void wk_actuated_torques(const wk_actuated_model *M, const double *x, const double *p, double *u,
                         void *ctx);

/* actuated_closed_loop: closed-loop accelerations qdd (n), torques u (m) and dry-friction
 * torques lam (m) in phase; returns 1 when the controller saturated. */
int wk_actuated_closed_loop(const wk_actuated_model *M, int64_t phase, const double *x,
                            const double *p, double *qdd, double *u, double *lam, void *ctx);

/* The model's rhs (wk_rhs_fn, t unused): dx = (qd, qdd, power, saturated) with the
 * closed-loop accelerations qdd (wk_actuated_closed_loop) and saturated 1 or 0. */
void wk_actuated_rhs(const wk_actuated_model *M, int64_t phase, double t, const double *x,
                     const double *p, double *dx, void *ctx);

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

/* The heel strike's reset: the floating-base impact and leg swap (M->base, M->relabel) into
 * x_new and impulse (along the slope, normal to it, on the new stance foot), judged by
 * wk_impact_status; then (actuated_after_heel_strike) the end of the run for a singular or
 * nonphysical impact, else a stride with every joint's mode chosen afresh at x_new (rates
 * projected in place). */
void wk_actuated_heel_strike(const wk_actuated_model *M, int64_t phase, const double *x,
                             const double *p, double *x_new, double *impulse, int64_t *out,
                             void *ctx);

/* wk_actuated_heel_strike on terrain (walker/_core/wk_terrain.h): the impulse along and
 * normal to the plane of slope ``slope`` (the swing foot's), the trailing foot's lift-off
 * from the plane of slope ``trailing_slope`` it stands on. */
void wk_actuated_heel_strike_on(const wk_actuated_model *M, int64_t phase, const double *x,
                                const double *p, double slope, double trailing_slope,
                                double *x_new, double *impulse, int64_t *out, void *ctx);

/* The model's reset (wk_reset_fn, t unused): x_new a copy of x, then strike for guard 0, the
 * end of the run with M->base_status[k] for the other base guards, and for the joints'
 * friction guards (actuated_joint_event) the reset of joint friction event 2 j (slip_stops)
 * or 2 j + 1 (stick_breaks) of joint j: rates into x_new, (action, next phase, status) into
 * out. */
void wk_actuated_reset(const wk_actuated_model *M, wk_strike_fn strike, int64_t phase, int64_t k,
                       double t, const double *x, const double *p, double *x_new,
                       double *impulse, int64_t *out, void *ctx);

/* actuated_start_phase: the phase consistent with x (wk_friction_choose_modes). */
int64_t wk_actuated_start_phase(const wk_actuated_model *M, const double *x, const double *p,
                                void *ctx);

/* Defines the functions of actuated model ``name`` that are written once over its table M
 * (a wk_actuated_model) and its static strike (a wk_strike_fn): wk_model_<name>_rhs, reset,
 * start_phase, energy and points (on the generated kernels wk_<name>_kinetic, potential and
 * points), and the registry entry wk_entry_<name>, with the model file's
 * wk_model_<name>_guards and wk_model_<name>_jac. */
#define WK_ACTUATED_MODEL(name, M)                                                          \
    void wk_model_##name##_rhs(int64_t phase, double t, const double *x, const double *p,   \
                               double *dx, void *ctx)                                       \
    {                                                                                       \
        wk_actuated_rhs(&(M), phase, t, x, p, dx, ctx);                                     \
    }                                                                                       \
    void wk_model_##name##_reset(int64_t phase, int64_t k, double t, const double *x,       \
                                 const double *p, double *x_new, double *impulse,           \
                                 int64_t *out, void *ctx)                                   \
    {                                                                                       \
        wk_actuated_reset(&(M), strike, phase, k, t, x, p, x_new, impulse, out, ctx);       \
    }                                                                                       \
    void wk_model_##name##_start_phase(const double *x, const double *p, double *out,       \
                                       void *ctx)                                           \
    {                                                                                       \
        out[0] = (double)wk_actuated_start_phase(&(M), x, p, ctx);                          \
    }                                                                                       \
    void wk_model_##name##_energy(const double *x, const double *p, double *out, void *ctx)\
    {                                                                                       \
        (void)ctx;                                                                          \
        out[0] = wk_##name##_kinetic(x, x + (M).n_q, p);                                    \
        out[1] = wk_##name##_potential(x, p);                                               \
    }                                                                                       \
    void wk_model_##name##_points(const double *x, const double *p, double *out, void *ctx)\
    {                                                                                       \
        (void)ctx;                                                                          \
        wk_##name##_points(x, p, out);                                                      \
    }                                                                                       \
    void wk_model_##name##_torques(const double *x, const double *p, double *out, void *ctx)\
    {                                                                                       \
        wk_actuated_torques(&(M), x, p, out, ctx);                                          \
    }                                                                                       \
    const wk_model_entry wk_entry_##name = {                                                \
        WK_ENTRY_NAME_##name,                                                               \
        {wk_model_##name##_rhs, wk_model_##name##_guards, wk_model_##name##_reset,          \
         wk_model_##name##_jac, NULL},                                                      \
        wk_model_##name##_energy,                                                           \
        wk_model_##name##_points,                                                           \
        wk_model_##name##_start_phase,                                                      \
        NULL,                                                                               \
        NULL,                                                                               \
        wk_model_##name##_torques,                                                          \
    };

#endif
