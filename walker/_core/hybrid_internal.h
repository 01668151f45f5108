/* Internal to the hybrid integrator: what its translation units share.
 *
 * The integrator (the algorithm is described in the module docstring of
 * walker/simulation/integrate.py) is split by concern:
 *
 *   hybrid.c            the driver: one call of wk_hybrid_solve = one run (the loop over
 *                       steps, event application, samples, record, growing storage);
 *   hybrid_step.c       Runge-Kutta steps, the method table, the error norm, step-size
 *                       control and the initial step;
 *   hybrid_dense.c      dense output (interpolant coefficients and evaluation);
 *   hybrid_events.c     guards: arming, rates, root location, extremum search, chattering;
 *   hybrid_saltation.c  the sensitivities' update at an applied event (saltation matrix).
 *
 * Nothing here is part of the extension's interface (that is hybrid.h): the functions are
 * prefixed wk_ and called only by these files.  Small helpers on the hot path are static
 * inline here so that every file gets its own copy.
 *
 * Floating point: every expression keeps the operation order of walker's earlier numba
 * kernel (in the git history of walker/simulation/integrate.py): sums accumulate left to right from
 * 0.0, products are grouped as written, and the build disables contraction into fused
 * multiply-adds (setup.py), so results agree with that kernel to the last bit and do not
 * depend on the compiler.  min/max follow Python's rule: ``min(a, b)`` is ``b`` only when
 * ``b < a`` (so ties and NaNs keep the first argument).
 */
#ifndef WK_HYBRID_INTERNAL_H
#define WK_HYBRID_INTERNAL_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>

#include "hybrid.h"
#include "tableaux.h"

/* Dense output kinds. */
#define DENSE_HERMITE 0
#define DENSE_RK45 1
#define DENSE_DOP853 2

/* How much of a step's dense output is ready: none, the state's n_x components (all that
 * guards and samples read) or all n_z (the event state with its sensitivities). */
#define DENSE_NONE 0
#define DENSE_STATE 1
#define DENSE_FULL 2

/* Rows of the stage array K (DOP853: 12 stages, the FSAL stage, 3 dense-output stages) and
 * of the dense-output coefficients Q (DOP853: 3 + 4 rows), sized from the tableaux. */
#define K_ROWS WK_DOP853_A_ROWS
#define Q_ROWS (3 + WK_DOP853_D_ROWS)
#if WK_RK45_N_STAGES + 1 > K_ROWS || WK_RK4_N_STAGES + 1 > K_ROWS || \
    WK_EULER_N_STAGES + 1 > K_ROWS || WK_RK45_E_ROWS > K_ROWS ||      \
    WK_DOP853_E5_ROWS > K_ROWS || WK_DOP853_D_COLS > K_ROWS
#error "K_ROWS does not hold every method's stages"
#endif
#if WK_RK45_P_COLS > Q_ROWS || 3 > Q_ROWS
#error "Q_ROWS does not hold every dense output's coefficients"
#endif

static inline double min2(double a, double b) { return (b < a) ? b : a; }

static inline double max2(double a, double b) { return (b > a) ? b : a; }

/* Distance to the next double away from zero (numpy.spacing for finite x >= 0). */
static inline double spacing(double x) { return nextafter(x, copysign(INFINITY, x)) - x; }

/* The model and the sizes every helper needs. */
typedef struct {
    wk_functions fn;
    const double *p;
    const int64_t *directions;
    int64_t n_x;
    int64_t n_z;
    int64_t n_guards;
    int64_t n_impulse;
    int want_jac;
    int64_t n_c; /* columns of the sensitivity matrix Phi (n_x, n_c) */
    double *J;   /* (n_x, n_x) scratch for the Jacobian */
} model_t;

/* out[i] = y[i] + h * acc[i] (y NULL: h * acc[i]) for i < n_comp, acc[i] the sum over
 * j < count of coef[j] * K[j * n + i] from 0.0 in increasing j.  Four components at a time,
 * each in its own accumulator: the same operations in the same order as one component at a
 * time, with each coefficient loaded once per four. */
static inline void stage_combine(const double *coef, int count, const double *K, int64_t n,
                                 int64_t n_comp, const double *y, double h, double *out)
{
    int64_t i = 0;
    for (; i + 4 <= n_comp; i += 4) {
        double a0 = 0.0, a1 = 0.0, a2 = 0.0, a3 = 0.0;
        const double *Ki = K + i;
        for (int j = 0; j < count; j++) {
            const double c = coef[j];
            const double *Kj = Ki + j * n;
            a0 += c * Kj[0];
            a1 += c * Kj[1];
            a2 += c * Kj[2];
            a3 += c * Kj[3];
        }
        if (y != NULL) {
            out[i] = y[i] + h * a0;
            out[i + 1] = y[i + 1] + h * a1;
            out[i + 2] = y[i + 2] + h * a2;
            out[i + 3] = y[i + 3] + h * a3;
        } else {
            out[i] = h * a0;
            out[i + 1] = h * a1;
            out[i + 2] = h * a2;
            out[i + 3] = h * a3;
        }
    }
    for (; i < n_comp; i++) {
        double acc = 0.0;
        for (int j = 0; j < count; j++) acc += coef[j] * K[j * n + i];
        out[i] = (y != NULL) ? y[i] + h * acc : h * acc;
    }
}

/* ------------------------------------------------------------------------------------------
 * hybrid_step.c: steps, error norm, step-size control, initial step
 * ------------------------------------------------------------------------------------------ */

/* A method's entry in the method table: its tableau (from tableaux.h) and dense output. */
typedef struct {
    const double *A; /* row-major, a_cols columns */
    int a_cols;
    const double *B;
    const double *C;
    int n_stages;
    int dense; /* DENSE_* kind */
    int err_order;
    int order;
} wk_method;

/* The table entry of a WK_METHOD_* code (Euler for any other value). */
const wk_method *wk_method_of(int method);

/* Augmented vector field: dz[:n_x] = f(x) and, with want_jac, dPhi = J(x) Phi, Phi (n_x, n_c)
 * stored row-major in z[n_x:].  With want_jac and fn.rhs_jac set (a built-in model's fused
 * function, see wk_system.h) f and J come from one rhs_jac call: J bit for bit jac's, f
 * rhs's to round-off. */
void wk_fun(const model_t *m, int64_t phase, double t, const double *z, double *dz);

/* wk_fun from rhs, and with want_jac jac, always (never rhs_jac): the dense output's extra
 * stages, so that they are the same numbers computed in one pass or in two (the state
 * first by rhs, then wk_fun_var; see wk_dense_prepare). */
void wk_fun_unfused(const model_t *m, int64_t phase, double t, const double *z, double *dz);

/* The variational part alone: dz[n_x:] = J(x) Phi (want_jac only). */
void wk_fun_var(const model_t *m, int64_t phase, double t, const double *z, double *dz);

int wk_all_finite(const double *v, int64_t n);

/* Stages 1..n_stages-1 (stage 0 = K[0] given), then y_new, then the FSAL stage
 * K[n_stages] = f(t + h, y_new).  Returns the number of rhs evaluations. */
int64_t wk_rk_stages(const model_t *m, const wk_method *mt, int64_t phase, double t,
                     const double *y, double h, double *K, double *y_new, double *tmp);

/* The error scale atol + rtol * max(|y|, |y_new|) of the step y -> y_new, with a seed of
 * fewer than n_x columns (``seeded``) floored per column (see hybrid_step.c). */
void wk_error_scale(const model_t *m, int seeded, double rtol, double atol, const double *y,
                    const double *y_new, double *scale);

/* Scaled RMS error estimate of the embedded pair (0 for fixed-step methods); see
 * hybrid_step.c for the seeded weighting. */
double wk_error_norm(int method, const double *K, double h, const double *scale, int64_t n,
                     int64_t n_head, double weight, double n_norm);

/* The factor on h after a step with error ``err``: rejected (err > 1) or accepted (never
 * growing right after a rejection, ``rejected_now``).  ``exponent`` = -1 / (err_order + 1). */
double wk_reject_factor(double err, double exponent);
double wk_accept_factor(double err, double exponent, int rejected_now);

/* Hairer's starting step size.  One rhs evaluation; ``scale``, ``tmp``, ``f1`` are scratch
 * of length n_z. */
double wk_initial_step(const model_t *m, int64_t phase, double t, const double *y,
                       const double *f0, int order, double rtol, double atol, double max_step,
                       double span, double *tmp, double *f1, double *scale);

/* ------------------------------------------------------------------------------------------
 * hybrid_dense.c: dense output
 * ------------------------------------------------------------------------------------------ */

/* Fill the dense-output coefficients Q of the step (t, y_old) -> (t + h, y_new) from what is
 * ready (``have``) up to ``want``; returns the number of extra rhs evaluations. */
int64_t wk_dense_prepare(int kind, const model_t *m, int64_t phase, double t,
                         const double *y_old, const double *y_new, double h, double *K,
                         double *Q, double *tmp, int have, int want);

/* What wk_dense_prepare(..., DENSE_NONE, DENSE_STATE) leaves ready. */
static inline int dense_have_after(int kind, const model_t *m)
{
    return (kind == DENSE_DOP853 && m->want_jac) ? DENSE_STATE : DENSE_FULL;
}

/* Dense output at t_old + theta * h, first ``count`` components into ``out``; Q has rows
 * of length ``n``. */
void wk_dense_eval(int kind, const double *Q, int64_t n, const double *y_old, double theta,
                   int64_t count, double *out);

/* ------------------------------------------------------------------------------------------
 * hybrid_events.c: guards
 * ------------------------------------------------------------------------------------------ */

/* 1 if g lies beyond GUARD_TOL on the pre-fire side of ``direction``, else 0. */
static inline int pre_side(int64_t direction, double g)
{
    if (direction < 0) return g > WK_GUARD_TOL;
    if (direction > 0) return g < -WK_GUARD_TOL;
    return fabs(g) > WK_GUARD_TOL;
}

static inline int crosses(int64_t direction, double ga, double gb)
{
    if (direction <= 0 && ga > 0.0 && gb <= 0.0) return 1;
    if (direction >= 0 && ga < 0.0 && gb >= 0.0) return 1;
    return 0;
}

/* The dense-output context of an accepted step, for guard evaluations inside it. */
typedef struct {
    int kind;
    const double *Q;
    const double *y_old;
    double t_old;
    double h;
    int64_t phase;
} step_t;

/* Root of guard i in [a, b] on the dense output; returns the fired-side end of the final
 * bracket. */
double wk_locate(const model_t *m, const step_t *st, double *xbuf, double *gbuf, int64_t i,
                 double a, double b, double ga, double gb);

/* Extremum of guard i over the step on the dense output; returns its step fraction and
 * stores the guard value there in *value. */
double wk_dip(const model_t *m, const step_t *st, double *xbuf, double *gbuf, int64_t i,
              double sign, double *value);

/* Tangency check of an armed guard over a step: on its pre-fire side at both ends (ga at
 * the start, g_end at the end) with its rate turning from toward firing (rate_a) to away
 * (rate_b), it has an extremum inside.  +1: look for a minimum, -1: a maximum, 0: none. */
static inline double tangency_sign(int64_t d, double ga, double g_end, double rate_a,
                                   double rate_b)
{
    if (d <= 0 && ga > 0.0 && g_end > 0.0 && rate_a < 0.0 && 0.0 < rate_b) return 1.0;
    if (d >= 0 && ga < 0.0 && g_end < 0.0 && rate_a > 0.0 && 0.0 > rate_b) return -1.0;
    return 0.0;
}

/* A segment start at (t, x) with f = f(t, x): the guards into g, arming (every guard beyond
 * GUARD_TOL on its pre-fire side, and those within GUARD_TOL moving toward firing) and the
 * guards' rates along f.  Three guard calls at most. */
void wk_arm_segment(const model_t *m, int64_t phase, double t, const double *x,
                    const double *f, double *g, unsigned char *armed, double *rate,
                    double *xbuf, double *gbuf);

/* The guards' rates along f: g(x + eps f) - g(x) (one guard call). */
void wk_guard_rates(const model_t *m, int64_t phase, double t, const double *x,
                    const double *f, const double *g, double *rate, double *xbuf);

/* 1 when no guard can reach zero inside the step (t, t + h), so the step's interior guard
 * samples can be skipped: every guard has the same strict sign at both ends and its value
 * there exceeds four times the bound on how far the cubic Hermite interpolant of the guard
 * (from its values ga, g_end and rates rate_a, rate_b at the ends) strays from the chord.
 * A step where any guard is near zero, or changes sign, keeps its samples. */
int wk_guards_far(const model_t *m, double h, const double *ga, const double *g_end,
                  const double *rate_a, const double *rate_b);

/* Chattering (Zeno) test of guard k applied at absolute time t_ev; per-guard state in
 * ``zeno`` (4 n_guards doubles, see hybrid_events.c).  Returns 1 when the run must stop. */
int wk_chattering(double *zeno, int64_t n_guards, int64_t k, double t_ev);

/* Initial per-guard state of wk_chattering. */
void wk_chattering_init(double *zeno, int64_t n_guards);

/* ------------------------------------------------------------------------------------------
 * hybrid_saltation.c: sensitivities at an applied event
 * ------------------------------------------------------------------------------------------ */

/* Doubles of scratch wk_saltation needs. */
#define WK_SALTATION_WORK(n_x, n_c, n_guards, n_impulse) \
    (9 * (n_x) + (n_x) * (n_x) + (n_x) * (n_c) + (n_c) + (n_guards) + (n_impulse))

/* Multiply the sensitivities by the event's saltation matrix (or, for the run's last
 * event, the derivative of the map): ``guard`` fired in ``phase`` at local time t in the
 * state zev (n_z: state and Phi); the reset gave x_new in ``next_phase``.  Writes the new Phi
 * into z[n_x:] and, when ``finishing``, d t / d x0 times the seed into dt_dx0.  ``work``:
 * WK_SALTATION_WORK doubles of scratch.  Returns the number of rhs evaluations. */
int64_t wk_saltation(const model_t *m, int64_t phase, int64_t next_phase, int64_t guard,
                     double t, const double *zev, const double *x_new, int finishing, double *z,
                     double *dt_dx0, double *work);

#endif
