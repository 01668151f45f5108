/* Dry (Coulomb) joint friction with stick and slip as phases and events, with the operations
 * of walker's former numba friction layer in the same order (results stay bit-identical).  See walker/models/friction.py for the
 * mechanics (joint rates w = S qd, the augmented system [D, -S_k^T; S_k, 0] of the stuck
 * joints k, the mode code sum_j mode_j 3**j, the guards 2 j slip_stops and 2 j + 1
 * stick_breaks).
 *
 * Conventions: n coordinates (n <= WK_FRICTION_MAX_N), m joints (m <= WK_FRICTION_MAX_JOINTS);
 * matrices row-major: D (n x n), S (m x n), dD (n x n x n, dD[(k n + i) n + c] = dD_ic/dq_k),
 * df_dq and df_dqd (n x n, [i n + k] = df_i/dq_k); modes int64 (m,); the flags free (m,)
 * as bool.  Functions returning int return 1 for success and 0 for a singular system (as
 * the numba functions' bool), and also 0 when n or m exceed the maxima (nothing is written
 * then).  No allocation: work arrays are fixed-size locals.
 */
#ifndef WK_FRICTION_H
#define WK_FRICTION_H

#include <stdbool.h>
#include <stdint.h>
#include "wk_common.h"

/* Joint modes (walker.models.friction.SLIP_POSITIVE, SLIP_NEGATIVE, STICK) and their number. */
#define WK_SLIP_POSITIVE 0
#define WK_SLIP_NEGATIVE 1
#define WK_STICK 2
#define WK_N_MODES 3

/* walker.models.friction.W_TOL: |w| [rad/s] at or below which a joint rate counts as zero when
 * modes are chosen. */
#define WK_FRICTION_W_TOL 1e-12

/* Largest sizes handled (every walker model fits). */
#define WK_FRICTION_MAX_N 6
#define WK_FRICTION_MAX_JOINTS 4
#define WK_FRICTION_MAX_SYSTEM (WK_FRICTION_MAX_N + WK_FRICTION_MAX_JOINTS)

/* encode: the mode code sum_j modes[j] 3**j. */
int64_t wk_friction_encode(const int64_t *modes, int m);

/* decode: fills modes[0..m-1] from a mode code (Python's floor division and modulo). */
void wk_friction_decode(int64_t code, int64_t *modes, int m);

/* _slip_torque: -F slipping positive, +F slipping negative, 0 stuck. */
double wk_friction_slip_torque(int64_t mode, double F);

/* _system: the augmented matrix [D, -S_k^T; S_k, 0] of the stuck joints k into A, row-major
 * of size N x N with N = n + (number stuck) <= n + m, which is returned (0 if n or m exceed
 * the maxima).  A must hold (n + m)^2 doubles. */
int wk_friction_system(const double *D, const double *S, const int64_t *modes, int n, int m,
                       double *A);

/* accelerations: qdd (n,) and lam (m,) (holding torque of each stuck joint, the friction
 * torque -+F of a slipping one) in the given modes.  Returns 0 for a singular system (qdd
 * and the stuck lam then hold what the numba function leaves: the partly solved system). */
int wk_friction_accelerations(const double *D, const double *f, const double *S,
                              const double *F, const int64_t *modes, int n, int m,
                              double *qdd, double *lam);

/* slip_force: sum_j S_j^T tau_j of the slipping joints into out (n,); returns 0 if some
 * joint is stuck (out unset), 1 if the force is nonzero, -1 if it is zero. */
int wk_friction_slip_force(const double *S, const double *F, const int64_t *modes, int n,
                           int m, double *out);

/* accelerations_jacobian: d qdd / d(q, qd) into out (n x 2n), qdd from
 * wk_friction_accelerations at this state. */
int wk_friction_accelerations_jacobian(const double *D, const double *dD, const double *df_dq,
                                       const double *df_dqd, const double *S,
                                       const int64_t *modes, const double *qdd, int n, int m,
                                       double *out);

/* _consistent: the modes are consistent at rest flags ``rest`` (strict or non-strict
 * inequalities); qdd (n,) and lam (m,) are work arrays (outputs of accelerations). */
int wk_friction_consistent(const double *D, const double *f, const double *S, const double *F,
                           const int64_t *modes, const bool *rest, bool strict, int n, int m,
                           double *qdd, double *lam);

/* choose_modes: chooses the modes of the joints marked free_joints (others kept) in place;
 * returns 0 when no combination is consistent or a system is singular (modes then slip by
 * sign, slip+ at rest). */
int wk_friction_choose_modes(const double *D, const double *f, const double *S,
                             const double *F, const double *qd, const bool *free_joints,
                             int n, int m, int64_t *modes);

/* project_stuck: qd projected onto S_k qd = 0 for the stuck joints k (plastic lock) into
 * qd_out (n,).  qd_out must not alias qd. */
int wk_friction_project_stuck(const double *D, const double *S, const int64_t *modes,
                              const double *qd, int n, int m, double *qd_out);

/* settle: choose_modes of the free joints, then project_stuck into qd_out (a copy of qd when
 * no joint sticks).  Returns 0 if the projection is singular (choose_modes' result is not
 * returned, as in the numba function).  qd_out must not alias qd. */
int wk_friction_settle(const double *D, const double *f, const double *S, const double *F,
                       const double *qd, const bool *free_joints, int n, int m,
                       int64_t *modes, double *qd_out);

/* switch: the reset of joint j's friction event (breaks false: slip_stops; true:
 * stick_breaks): new modes in place, new velocities into qd_out.  Returns 0 if a system is
 * singular (or j is not a joint).  qd_out must not alias qd. */
int wk_friction_switch(const double *D, const double *f, const double *S, const double *F,
                       const double *qd, int64_t j, bool breaks, int n, int m,
                       int64_t *modes, double *qd_out);

/* guards: g[2 j] = w_j while slipping with F_j > 0, g[2 j + 1] = |lam_j| - F_j while
 * stuck, 1.0 where unused; g has 2 m entries. */
void wk_friction_guards(const double *S, const double *F, const int64_t *modes,
                        const double *qd, const double *lam, int n, int m, double *g);

/* A model's phase functions over its generated kernels: C port of walker.models.friction's
 * dynamics, phase_* and first_order* (same operations in the same order).  A base phase of
 * a model is a table of its kernels: n coordinates q = x[0..n), rates qd = x[v0..v0 + n),
 * m joints with rows S (m x n); mass_matrix(q, p, D), bias(q, qd, p, h) (C qd + g),
 * forcing(q, qd, p, f) (the viscous forcing, linear in qd), accel(q, qd, p, qdd) (the fused
 * frictionless accelerations), dmass(q, p, dD), dbias_dq and dbias_dqd(q, qd, p, out).  F
 * (m,) are the dry frictions, modes (m,) the joint modes. */
typedef struct {
    int n;
    int m;
    int v0;
    const double *S;
    wk_qp_v mass_matrix;
    wk_qqdp_v bias;
    wk_qqdp_v forcing;
    wk_qqdp_v accel;
    wk_qp_v dmass;
    wk_qqdp_v dbias_dq;
    wk_qqdp_v dbias_dqd;
} wk_friction_kernels;

/* dynamics: D (n x n), f = Q_viscous - C qd - g (n,) and qd (n,) at state x. */
void wk_friction_dynamics(const wk_friction_kernels *K, const double *x, const double *p,
                          double *D, double *f, double *qd);

/* phase_solve: wk_friction_accelerations at state x: qdd (n,), lam (m,). */
int wk_friction_phase_solve(const wk_friction_kernels *K, const double *F,
                            const int64_t *modes, const double *x, const double *p,
                            double *qdd, double *lam);

/* phase_accelerations: qdd (n,) for the vector field: with no joint stuck the fused accel
 * kernel plus D^-1 of the slip torques, else the augmented system. */
void wk_friction_phase_accelerations(const wk_friction_kernels *K, const double *F,
                                     const int64_t *modes, const double *x, const double *p,
                                     double *qdd);

/* phase_jacobian: d qdd / d(q, qd) into a (n x 2n), with the forcing Jacobian df/dq =
 * -dh/dq, df/dqd = V - dh/dqd (V the viscous forcing's columns, probed with unit rates). */
int wk_friction_phase_jacobian(const wk_friction_kernels *K, const double *F,
                               const int64_t *modes, const double *x, const double *p,
                               double *a);

/* phase_guards: the friction guards into g[0..2m); the holding torques are solved for only
 * when a joint sticks. */
void wk_friction_phase_guards(const wk_friction_kernels *K, const double *F,
                              const int64_t *modes, const double *x, const double *p,
                              double *g);

/* phase_settle: every joint's mode chosen at state x (modes in place), the projected rates
 * written into x[v0..v0 + n); returns 0 (x unchanged) if a system is singular. */
int wk_friction_phase_settle(const wk_friction_kernels *K, const double *F, int64_t *modes,
                             double *x, const double *p);

/* phase_switch: the reset of friction guard k (2 j slip_stops, 2 j + 1 stick_breaks of
 * joint j) at state x: modes in place, the new rates into x_new[v0..v0 + n); returns 0
 * (x_new unchanged) if a system is singular. */
int wk_friction_phase_switch(const wk_friction_kernels *K, const double *F, int64_t *modes,
                             int64_t k, const double *x, const double *p, double *x_new);

/* first_order: dx = (qd, qdd) for x = (q, qd) of n coordinates; first_order_jacobian: J
 * (2n x 2n) = [0, I; a] from a (n x 2n). */
void wk_friction_first_order(const double *x, const double *qdd, int n, double *dx);
void wk_friction_first_order_jacobian(const double *a, int n, double *J);

/* A model's rhs, jac, mode choice and friction reset over the phase functions above:
 * C port of walker.models.friction's phase_rhs, phase_jac, phase_start and phase_reset.
 * phase_rhs: dx = (qd, qdd) for a state x = (q, qd) of n coordinates (v0 = n) in the joint
 * modes of mode code code (the numba function takes the decoded modes); phase_jac: its
 * Jacobian J (2n x 2n).  Nothing is written if n or m exceed the maxima. */
void wk_friction_phase_rhs(const wk_friction_kernels *K, const double *F, int64_t code,
                           const double *x, const double *p, double *dx);
void wk_friction_phase_jac(const wk_friction_kernels *K, const double *F, int64_t code,
                           const double *x, const double *p, double *J);

/* Defines the static phase function fn (wk_functions' rhs or jac signature) of a friction
 * model as call(K, F, phase, x, p, out) (the signature of wk_friction_phase_rhs and
 * wk_friction_phase_jac) with K = &KT, its kernel table, and the dry frictions F at
 * p + I_COULOMB. */
#define WK_FRICTION_PHASE_FUNCTION(fn, call, KT, I_COULOMB)                                   \
    static void fn(int64_t phase, double t, const double *x, const double *p, double *out,    \
                   void *ctx)                                                                 \
    {                                                                                         \
        (void)t;                                                                              \
        (void)ctx;                                                                            \
        call(&(KT), p + (I_COULOMB), phase, x, p, out);                                       \
    }

/* Defines the static rhs and jac of a friction model with one base phase, whose phase is the
 * joint-mode code (model_compass_coulomb.c, model_double_pendulum.c): wk_friction_phase_rhs
 * and wk_friction_phase_jac over its kernel table KT. */
#define WK_FRICTION_ONE_BASE_FIELD(KT, I_COULOMB)                                              \
    WK_FRICTION_PHASE_FUNCTION(rhs, wk_friction_phase_rhs, KT, I_COULOMB)                     \
    WK_FRICTION_PHASE_FUNCTION(jac, wk_friction_phase_jac, KT, I_COULOMB)

/* phase_start: every joint's mode chosen at state x (modes in place, the rates projected in
 * place, wk_friction_phase_settle); returns the phase offset + encode(modes) (offset the
 * first phase of the model's base phase), -1 if a system is singular. */
int64_t wk_friction_phase_start(const wk_friction_kernels *K, const double *F, int64_t *modes,
                                int64_t offset, double *x, const double *p);

/* phase_reset: the reset of friction guard k in phase (modes the phase's, changed in place;
 * wk_friction_phase_switch) into out: continue in offset + encode(modes), or end the run
 * with WK_LINEAR_SOLVE_FAILED if a system is singular (then 0 is returned, else 1). */
int wk_friction_phase_reset(const wk_friction_kernels *K, const double *F, int64_t *modes,
                            int64_t phase, int64_t offset, int64_t k, const double *x,
                            const double *p, double *x_new, int64_t *out);

/* walker.models._common.after_base_reset: out holds a base model's reset (action, new base,
 * status) at x_new; after a real event every joint's mode is chosen afresh by
 * start(new_base, x_new, p) (the new phase, rates projected in place; -1 if singular).
 * Rewrites out as the friction model's reset in phase. */
typedef int64_t (*wk_friction_start_fn)(int64_t base, double *x, const double *p);
void wk_friction_after_base_reset(wk_friction_start_fn start, int64_t phase, double *x_new,
                                  const double *p, int64_t *out);

/* A friction walker's reset at guard k of its base walker (k below the base walker's guard
 * count): walker_reset, the base walker's reset (its plane or terrain one, with ctx), in
 * base phase ``base``, then wk_friction_after_base_reset. */
void wk_friction_base_reset(wk_reset_fn walker_reset, wk_friction_start_fn start, int64_t base,
                            int64_t phase, int64_t k, double t, const double *x, const double *p,
                            double *x_new, double *impulse, int64_t *out, void *ctx);

/* Defines the terrain entry wk_terrain_entry_<name> (wk_terrain.h, included before) of the
 * friction walker ``name`` on the walker ``base``: its terrain guards and reset are the model
 * file's static guards_on(walker_guards, phase, t, x, p, g, ctx) and
 * reset_on(walker_reset, phase, k, t, x, p, x_new, impulse, out, ctx) over
 * wk_terrain_<base>_guards and wk_terrain_<base>_reset; its plane guards (the key) the file's
 * static guards; slope_index, radius_index and n_params as in wk_terrain_entry. */
#define WK_FRICTION_WALKER_TERRAIN(name, base, slope_index, radius_index, n_params)           \
    static void terrain_guards(int64_t phase, double t, const double *x, const double *p,    \
                               double *g, void *ctx)                                         \
    {                                                                                        \
        guards_on(wk_terrain_##base##_guards, phase, t, x, p, g, ctx);                       \
    }                                                                                        \
    static void terrain_reset(int64_t phase, int64_t k, double t, const double *x,           \
                              const double *p, double *x_new, double *impulse, int64_t *out, \
                              void *ctx)                                                     \
    {                                                                                        \
        reset_on(wk_terrain_##base##_reset, phase, k, t, x, p, x_new, impulse, out, ctx);    \
    }                                                                                        \
    const wk_terrain_entry wk_terrain_entry_##name = {                                       \
        WK_ENTRY_NAME_##name, guards, slope_index, terrain_guards, terrain_reset, 0,          \
        radius_index, n_params,                                                              \
    };

#endif
