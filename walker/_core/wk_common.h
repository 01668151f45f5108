/* Pieces shared by walker's hand-written C models (model_simplest.c, model_compass.c,
 * model_kneed.c): the fall threshold, the least step, impacts as augmented linear systems,
 * the registry entry macros (the status values are status.h's).  Written as ports of
 * walker's former numba functions (in the git history of walker/models/_common.py and
 * walker/_linalg.py), whose order of operations they keep: results stay bit-identical to the
 * ones walker has always produced.
 */
#ifndef WK_COMMON_H
#define WK_COMMON_H

#include "indices.h" /* every model's named parameter, phase and guard indices (generated) */

#include <stdint.h>
#include "wk_system.h"
#include "wk_registry.h" /* each registry entry's name and declaration (generated) */

/* walker.models._common.FALL_ANGLE and MIN_STEP. */
#define WK_FALL_ANGLE 1.2217304763960306
#define WK_MIN_STEP 1e-8

/* walker.status.Status values: WK_<NAME> in status.h (included by wk_system.h). */

/* Largest augmented system wk_impact solves (coordinates + constraints). */
#define WK_IMPACT_MAX 16

/* Kernel signatures of walker/_generated/<model>.h. */
typedef void (*wk_qqdp_v)(const double *q, const double *qd, const double *p, double *out);
typedef void (*wk_qp_v)(const double *q, const double *p, double *out);
typedef double (*wk_qqdp_s)(const double *q, const double *qd, const double *p);
typedef double (*wk_qp_s)(const double *q, const double *p);

/* Writes a reset's (action, next phase, status) into out[0..2]. */
static inline void wk_reset_out(int64_t *out, int64_t action, int64_t next_phase,
                                int64_t status)
{
    out[0] = action;
    out[1] = next_phase;
    out[2] = status;
}

/* One right-hand side (the operations of walker's former _linalg.solve_inplace): solves
 * A x = b (A n x n, row-major, destroyed; b overwritten with x) by Gaussian elimination with
 * partial pivoting.  Returns 0 when a pivot is zero or not finite, or the solution is not
 * finite. */
int wk_solve_inplace(double *A, double *b, int n);

/* nc right-hand sides (the operations of walker's former _linalg.solve_inplace): solves
 * A X = B (A n x n, row-major, destroyed; B n x nc, row-major, overwritten with X) by
 * Gaussian elimination with partial pivoting; returns 0 when a pivot is zero or not finite,
 * or X is not finite.  wk_solve_inplace is its case nc = 1. */
int wk_solve_columns(double *A, double *B, int n, int nc);

/* walker.models._common.impact: solves [M, -J^T; J, 0] [qd_plus; impulse] = [M qd_minus; 0]
 * for M (n x n) and J (m x n), row-major; n + m <= WK_IMPACT_MAX.  Returns 0 for a
 * singular system (qd_plus and impulse then hold garbage). */
int wk_impact(const double *M, const double *J, const double *qd_minus, double *qd_plus,
              double *impulse, int n, int m);

/* walker.models._common.floating_base_state: qf = (q, hip), qdf = (qd, hip_J qd), with
 * hip_J (2 x n) row-major. */
void wk_floating_base_state(const double *q, const double *qd, const double *hip,
                            const double *hip_J, double *qf, double *qdf, int n);

/* walker.models._common.heel_strike_impact on the floating-base model of n_f coordinates
 * (M n_f x n_f, J_swing and J_stance 2 x n_f, row-major).  Writes the impulse on the new
 * stance foot in the slope frame into impulse[0..1] and the trailing foot's normal contact
 * velocity after the impact into *lift; returns 0 (impulse and *lift untouched) for a
 * singular system. */
int wk_heel_strike_impact(const double *M, const double *J_swing, const double *J_stance,
                          const double *qdf, double slope, double *qdf_plus, double *impulse,
                          double *lift, int n_f);

/* Largest floating-base model (coordinates) and number of drawing points
 * wk_floating_base_heel_strike handles. */
#define WK_FLOATING_BASE_MAX 8
#define WK_POINTS_MAX 8

/* A pinned model of n coordinates and its floating-base extension of n + 2, as the heel
 * strike needs them: the generated kernels points(q, p, pts) (n_points rows of 2, the hip at
 * row hip_row) and hip_jac(q, p, J) (2 x n) of the pinned model, and ext_mass_matrix,
 * ext_swing_contact_jac and ext_stance_contact_jac(qf, p, out) of the floating base. */
typedef struct {
    wk_qp_v points;
    wk_qp_v hip_jac;
    wk_qp_v ext_mass_matrix;
    wk_qp_v ext_swing_contact_jac;
    wk_qp_v ext_stance_contact_jac;
    int n;
    int n_points;
    int hip_row;
} wk_floating_base;

/* walker.models._common.floating_base_heel_strike: the plastic heel strike of the pinned
 * model B (q, qd) on its floating-base extension.  Writes qdf_plus (n + 2), impulse[0..1]
 * and *lift as wk_heel_strike_impact; returns 0 for a singular system (or sizes over the
 * maxima).  The caller swaps the legs and judges the impact. */
int wk_floating_base_heel_strike(const wk_floating_base *B, const double *q, const double *qd,
                                 const double *p, double slope, double *qdf_plus,
                                 double *impulse, double *lift);

/* The leg swap after a heel strike, for a state of n_c coordinates and their rates:
 * x_new[i] = q[swap[i]], x_new[n_c + i] = qd[swap[i]] for i < n_c (q the coordinates before
 * the impact, qd the rates after it). */
static inline void wk_swap_legs(const int *swap, int n_c, const double *q, const double *qd,
                                double *x_new)
{
    for (int i = 0; i < n_c; i++) {
        x_new[i] = q[swap[i]];
        x_new[n_c + i] = qd[swap[i]];
    }
}

/* The heel strike of a walker without foot friction (the compass gait; the kneed walker with
 * its knee locked, on its 2-link kernels): wk_floating_base_heel_strike of B at the state x
 * of n_c coordinates and their rates (x + n_c), then the leg swap wk_swap_legs(swap, n_c,
 * x, qdf_plus, x_new).  Returns WK_LINEAR_SOLVE_FAILED for a singular system (x_new
 * untouched), WK_NONPHYSICAL_IMPACT when the normal impulse is not positive or the trailing
 * foot does not lift off, else 0. */
int64_t wk_plastic_heel_strike(const wk_floating_base *B, const int *swap, int n_c,
                               const double *x, const double *p, double slope, double *x_new,
                               double *impulse);

/* The reset's out after a heel strike that returned status: a stride into phase 0, or
 * (status nonzero: a singular or nonphysical impact) the end of the run in phase. */
static inline void wk_stride_out(int64_t *out, int64_t phase, int64_t status)
{
    if (status != 0)
        wk_reset_out(out, WK_EVENT_TERMINAL, phase, status);
    else
        wk_reset_out(out, WK_EVENT_STRIDE, 0, 0);
}

/* The reset's out for a fall guard: the end of the run in phase, fallen forward or
 * backward. */
static inline void wk_fall_out(int64_t *out, int64_t phase, int forward)
{
    wk_reset_out(out, WK_EVENT_TERMINAL, phase, forward ? WK_FELL_FORWARD : WK_FELL_BACKWARD);
}

/* The models' functions, registered in model_table.c: wk_model_<name>_{rhs, guards, reset, jac}
 * (wk_system.h) and wk_model_<name>_{energy, points} (wk_models.h). */
#define WK_DECLARE_MODEL(name)                                                              \
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
    void wk_model_##name##_points(const double *x, const double *p, double *out, void *ctx);

/* Defines the exported function fn with the signature rhs, guards and jac share (wk_rhs_fn)
 * as the static call(K, phase, x, p, out) of a model file, K = &KT (WK_MODEL_VARIANT). */
#define WK_PHASE_FUNCTION(fn, call, KT)                                                      \
    void fn(int64_t phase, double t, const double *x, const double *p, double *out,          \
            void *ctx)                                                                       \
    {                                                                                        \
        (void)t;                                                                             \
        (void)ctx;                                                                           \
        call(&KT, phase, x, p, out);                                                         \
    }

/* Defines the exported function fn with the signature of energy and points (wk_state_fn,
 * wk_models.h) as the static call(K, x, p, out) of a model file, K = &KT. */
#define WK_STATE_FUNCTION(fn, call, KT)                                                      \
    void fn(const double *x, const double *p, double *out, void *ctx)                        \
    {                                                                                        \
        (void)ctx;                                                                           \
        call(&KT, x, p, out);                                                                \
    }

/* Defines the exported functions of model variant ``name`` in a model file whose glue is
 * written once over a table of kernels: static functions
 *     rhs(K, phase, x, p, dx), guards(K, phase, x, p, g),
 *     reset(K, phase, k, x, p, x_new, impulse, out), jac(K, phase, x, p, J),
 *     energy(K, x, p, out), points(K, x, p, out)
 * with K the address of the variant's kernel table KT. */
#define WK_MODEL_VARIANT(name, KT)                                                          \
    WK_PHASE_FUNCTION(wk_model_##name##_rhs, rhs, KT)                                       \
    WK_PHASE_FUNCTION(wk_model_##name##_guards, guards, KT)                                 \
    WK_PHASE_FUNCTION(wk_model_##name##_jac, jac, KT)                                       \
    void wk_model_##name##_reset(int64_t phase, int64_t k, double t, const double *x,       \
                                 const double *p, double *x_new, double *impulse,           \
                                 int64_t *out, void *ctx)                                   \
    {                                                                                       \
        (void)t;                                                                            \
        (void)ctx;                                                                          \
        reset(&KT, phase, k, x, p, x_new, impulse, out);                                    \
    }                                                                                       \
    WK_STATE_FUNCTION(wk_model_##name##_energy, energy, KT)                                 \
    WK_STATE_FUNCTION(wk_model_##name##_points, points, KT)

/* Defines the registry entry wk_entry_<name> of model variant ``name`` over its functions
 * wk_model_<name>_{rhs, guards, reset, jac, energy, points} (WK_MODEL_VARIANT); its name,
 * WK_ENTRY_NAME_<name>, is printed from the Python declaration (wk_registry.h). */
#define WK_MODEL_ENTRY(name)                                                                \
    const wk_model_entry wk_entry_##name = {                                                \
        WK_ENTRY_NAME_##name,                                                               \
        {wk_model_##name##_rhs, wk_model_##name##_guards, wk_model_##name##_reset,          \
         wk_model_##name##_jac, NULL},                                                      \
        wk_model_##name##_energy,                                                           \
        wk_model_##name##_points,                                                           \
        NULL,                                                                               \
    };

/* WK_MODEL_ENTRY of a variant with a fused rhs and Jacobian (wk_model_<name>_rhs_jac,
 * WK_MODEL_FUSED). */
#define WK_MODEL_ENTRY_FUSED(name)                                                          \
    const wk_model_entry wk_entry_##name = {                                                \
        WK_ENTRY_NAME_##name,                                                               \
        {wk_model_##name##_rhs, wk_model_##name##_guards, wk_model_##name##_reset,          \
         wk_model_##name##_jac, NULL, wk_model_##name##_rhs_jac},                           \
        wk_model_##name##_energy,                                                           \
        wk_model_##name##_points,                                                           \
        NULL,                                                                               \
    };

/* A model variant's fused rhs and Jacobian, wk_model_<name>_rhs_jac (wk_rhs_jac_fn, see
 * wk_system.h): declared for the variants whose registry entry has one (WK_MODEL_ENTRY_FUSED). */
#define WK_DECLARE_FUSED(name)                                                              \
    void wk_model_##name##_rhs_jac(int64_t phase, double t, const double *x,                \
                                   const double *p, double *dx, double *J, void *ctx);

/* Defines wk_model_<name>_rhs_jac of model variant ``name`` over the static
 * rhs_jac(K, phase, x, p, dx, J) of a model file (see WK_MODEL_VARIANT), K = &KT. */
#define WK_MODEL_FUSED(name, KT)                                                            \
    void wk_model_##name##_rhs_jac(int64_t phase, double t, const double *x,                \
                                   const double *p, double *dx, double *J, void *ctx)       \
    {                                                                                       \
        (void)t;                                                                            \
        (void)ctx;                                                                          \
        rhs_jac(&KT, phase, x, p, dx, J);                                                   \
    }

/* A model variant's hoisted phase functions, wk_model_<name>_hoisted_{rhs, jac, rhs_jac}:
 * those of variant <name> over its kernels' hoisted twins (walker/_generated/<module>_hoisted
 * kernels, which read the parameter-only terms from p's tail instead of computing them), so
 * they take the extended parameter vector that wk_model_hoist (models.c) builds.  The same
 * numbers bit for bit.  Declared for the variants models.c's hoisting table lists. */
#define WK_DECLARE_HOISTED(name)                                                            \
    void wk_model_##name##_hoisted_rhs(int64_t phase, double t, const double *x,            \
                                       const double *p, double *dx, void *ctx);             \
    void wk_model_##name##_hoisted_jac(int64_t phase, double t, const double *x,            \
                                       const double *p, double *J, void *ctx);              \
    void wk_model_##name##_hoisted_rhs_jac(int64_t phase, double t, const double *x,        \
                                           const double *p, double *dx, double *J,          \
                                           void *ctx);

/* Defines them over the static rhs, jac and rhs_jac of a model file with K = &KT, KT the
 * variant's table of hoisted kernels. */
#define WK_MODEL_HOISTED(name, KT)                                                          \
    WK_PHASE_FUNCTION(wk_model_##name##_hoisted_rhs, rhs, KT)                               \
    WK_PHASE_FUNCTION(wk_model_##name##_hoisted_jac, jac, KT)                               \
    WK_MODEL_FUSED(name##_hoisted, KT)

WK_DECLARE_MODEL(simplest)
WK_DECLARE_MODEL(compass)
WK_DECLARE_MODEL(compass_plain)
WK_DECLARE_MODEL(kneed)
WK_DECLARE_MODEL(kneed_plain)
WK_DECLARE_MODEL(kneed_ignore_scuff)
WK_DECLARE_MODEL(kneed_plain_ignore_scuff)
WK_DECLARE_FUSED(compass_plain)
WK_DECLARE_FUSED(kneed_plain)
WK_DECLARE_FUSED(kneed_plain_ignore_scuff)
WK_DECLARE_HOISTED(compass_plain)
WK_DECLARE_HOISTED(kneed_plain)
WK_DECLARE_HOISTED(kneed_plain_ignore_scuff)

/* The simplest walker's section lift and its Jacobian (wk_model_entry.lift, lift_jacobian):
 * the only shipped lift with a compiled C version that is not affine. */
void wk_model_simplest_lift(const double *z, const double *p, double *out, void *ctx);
void wk_model_simplest_lift_jacobian(const double *z, const double *p, double *out, void *ctx);

#endif
