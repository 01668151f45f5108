/* walker's hybrid integrator (see hybrid.h; the algorithm is described in the module
 * docstring of walker/integrate.py).
 *
 * Floating point: every expression keeps the operation order of walker's earlier numba
 * kernel (in the git history of walker/integrate.py): sums accumulate left to right from
 * 0.0, products are grouped as written, and the build disables contraction into fused
 * multiply-adds (setup.py), so results agree with that kernel to the last bit and do not
 * depend on the compiler.  min/max follow Python's rule: ``min(a, b)`` is ``b`` only when
 * ``b < a`` (so ties and NaNs keep the first argument).
 */
#include "hybrid.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "tableaux.h"

/* Step-size controller constants (Hairer, Norsett, Wanner I, Sect. II.4). */
#define SAFETY 0.9
#define MIN_FACTOR 0.2
#define MAX_FACTOR 10.0
#define SEED_COLUMN_FLOOR 0.01 /* see the seeded error scale in wk_hybrid_solve */
/* Relative step of the Richardson-extrapolated central differences at events. */
#define FD_REL_STEP 1e-3
/* Probe step for guard rates along the vector field. */
#define RATE_EPS 1e-9
/* 1 / golden ratio. */
#define INVPHI 0.6180339887498949

/* Internal status: still running (Status values are >= 0). */
#define RUNNING (-1)
#define ST_COMPLETED 0
#define ST_NO_EVENT 5
#define ST_STEP_UNDERFLOW 6
#define ST_NONFINITE 7
#define ST_MAX_STEPS 8
#define ST_CHATTERING 16

/* Chattering (Zeno) test, per guard: the run stops when ZENO_CHAIN or more intervals in a row
 * between applied firings of the same guard shrink strictly and the last is below
 * ZENO_RATIO times the first of that chain.  A bouncing ball's impacts shrink by the
 * restitution per impact; a gait repeats its heel strikes at nearly equal intervals, and
 * distinct events crowding together (a friction switch just before a heel strike) are
 * different guards, so neither builds such a chain. */
#define ZENO_CHAIN 3
#define ZENO_RATIO 1e-2

/* Dense output kinds. */
#define DENSE_HERMITE 0
#define DENSE_RK45 1
#define DENSE_DOP853 2

/* Rows of the stage array K (DOP853: 12 stages, the FSAL stage, 3 dense-output stages) and
 * of the dense-output coefficients Q (DOP853: 3 + 4 rows). */
#define K_ROWS WK_DOP853_A_ROWS
#define Q_ROWS (3 + WK_DOP853_D_ROWS)

/* Initial capacities of the growing event log and record. */
#define EVENTS_CAP0 8
#define RECORD_CAP0 64

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

/* ------------------------------------------------------------------------------------------
 * Building blocks
 * ------------------------------------------------------------------------------------------ */

/* Augmented vector field: dz[:n_x] = f(x) and, with want_jac, dPhi = J(x) Phi, Phi (n_x, n_c)
 * stored row-major in z[n_x:]. */
#define SPARSE_JAC_MAX 32

/* The variational part alone: dz[n_x:] = J(x) Phi (want_jac only). */
static void fun_var(const model_t *m, int64_t phase, double t, const double *z, double *dz)
{
    const int64_t n = m->n_x;
    const int64_t nc = m->n_c;
    const double *Phi = z + n;
    double *J = m->J;
    m->fn.jac(phase, t, z, m->p, J, m->fn.ctx);
    /* dPhi = J Phi: each entry the sum over k in increasing order, from 0.0, of J[i][k]
     * Phi[k][j], two columns at a time (each in its own accumulator: the same sums). */
    for (int64_t i = 0; i < n; i++) {
        const double *Ji = J + i * n;
        double *out = dz + n + i * nc;
        double chk = 0.0; /* 0 while every entry is finite, NaN after one that is not */
        int64_t j = 0;
        for (; j + 2 <= nc; j += 2) {
            double s0 = 0.0, s1 = 0.0;
            for (int64_t k = 0; k < n; k++) {
                s0 += Ji[k] * Phi[k * nc + j];
                s1 += Ji[k] * Phi[k * nc + j + 1];
            }
            out[j] = s0;
            out[j + 1] = s1;
            chk += (s0 - s0) + (s1 - s1);
        }
        if (j < nc) {
            double s0 = 0.0;
            for (int64_t k = 0; k < n; k++) s0 += Ji[k] * Phi[k * nc + j];
            out[j] = s0;
            chk += s0 - s0;
        }
        if (chk == 0.0 || n > SPARSE_JAC_MAX) continue;
        /* A non-finite entry: the row again over the nonzeros of J's row only, the product
         * the kernel has always formed up to SPARSE_JAC_MAX states.  Where every term is
         * finite the two agree bit for bit (an exact zero added to a sum from 0.0 changes
         * nothing), so only a row with an infinite or NaN term can differ: there 0 * inf
         * is NaN in the full sum and absent from this one. */
        for (int64_t jj = 0; jj < nc; jj++) {
            double acc = 0.0;
            for (int64_t k = 0; k < n; k++)
                if (Ji[k] != 0.0) acc += Ji[k] * Phi[k * nc + jj];
            out[jj] = acc;
        }
    }
}

static void fun(const model_t *m, int64_t phase, double t, const double *z, double *dz)
{
    m->fn.rhs(phase, t, z, m->p, dz, m->fn.ctx);
    if (m->want_jac) fun_var(m, phase, t, z, dz);
}

static int all_finite(const double *v, int64_t n)
{
    for (int64_t i = 0; i < n; i++)
        if (!isfinite(v[i])) return 0;
    return 1;
}

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

/* Stages 1..n_stages-1 (stage 0 = K[0] given), then y_new, then the FSAL stage
 * K[n_stages] = f(t + h, y_new).  A is row-major with a_cols columns.  Returns the number
 * of rhs evaluations. */
static int64_t rk_stages(const model_t *m, int64_t phase, double t, const double *y, double h,
                         const double *A, int a_cols, const double *C, const double *B,
                         int n_stages, double *K, double *y_new, double *tmp)
{
    const int64_t n = m->n_z;
    for (int s = 1; s < n_stages; s++) {
        stage_combine(A + s * a_cols, s, K, n, n, y, h, tmp);
        fun(m, phase, t + C[s] * h, tmp, K + s * n);
    }
    stage_combine(B, n_stages, K, n, n, y, h, y_new);
    fun(m, phase, t + h, y_new, K + n_stages * n);
    return n_stages;
}

/* Scaled RMS error estimate of the embedded pair (0 for fixed-step methods).
 *
 * With a seed of n_c < n_x columns (``n_head`` = n_x < n, ``weight`` = n_x / n_c,
 * ``n_norm`` = n_x + n_x * n_x) the squared scaled errors of the sensitivity components
 * count ``weight`` times and the norm divides by ``n_norm``: as if the columns not carried
 * erred like those carried, so the control asks of the carried columns what the full
 * matrix's asks of all.  Without one, ``n_head`` = n and ``n_norm`` = n: the plain norm. */
static double error_norm(int method, const double *K, double h, const double *scale, int64_t n,
                         int64_t n_head, double weight, double n_norm)
{
    if (method == WK_METHOD_DOP853) {
        double e5 = 0.0, e3 = 0.0, s5 = 0.0, s3 = 0.0;
        int64_t i = 0;
        /* four components at a time (each with its own accumulators; the squares are added
         * in increasing i as below) */
        for (; i + 4 <= n; i += 4) {
            double a5[4] = {0.0, 0.0, 0.0, 0.0}, a3[4] = {0.0, 0.0, 0.0, 0.0};
            for (int s = 0; s < WK_DOP853_E5_ROWS; s++) {
                const double c5 = WK_DOP853_E5[s], c3 = WK_DOP853_E3[s];
                const double *Ks = K + s * n + i;
                a5[0] += c5 * Ks[0];
                a3[0] += c3 * Ks[0];
                a5[1] += c5 * Ks[1];
                a3[1] += c3 * Ks[1];
                a5[2] += c5 * Ks[2];
                a3[2] += c3 * Ks[2];
                a5[3] += c5 * Ks[3];
                a3[3] += c3 * Ks[3];
            }
            for (int b = 0; b < 4; b++) {
                const double q5 = a5[b] / scale[i + b];
                const double q3 = a3[b] / scale[i + b];
                if (i + b < n_head) {
                    e5 += q5 * q5;
                    e3 += q3 * q3;
                } else {
                    s5 += q5 * q5;
                    s3 += q3 * q3;
                }
            }
        }
        for (; i < n; i++) {
            double a5 = 0.0, a3 = 0.0;
            for (int s = 0; s < WK_DOP853_E5_ROWS; s++) {
                a5 += WK_DOP853_E5[s] * K[s * n + i];
                a3 += WK_DOP853_E3[s] * K[s * n + i];
            }
            const double q5 = a5 / scale[i];
            const double q3 = a3 / scale[i];
            if (i < n_head) {
                e5 += q5 * q5;
                e3 += q3 * q3;
            } else {
                s5 += q5 * q5;
                s3 += q3 * q3;
            }
        }
        if (n_head < n) {
            e5 += weight * s5;
            e3 += weight * s3;
        }
        if (e5 == 0.0 && e3 == 0.0) return 0.0;
        /* dop853's combination of the 5th- and 3rd-order estimates. */
        return fabs(h) * e5 / sqrt((e5 + 0.01 * e3) * n_norm);
    }
    if (method == WK_METHOD_DP5) {
        double e = 0.0, se = 0.0;
        for (int64_t i = 0; i < n; i++) {
            double a = 0.0;
            for (int s = 0; s < WK_RK45_E_ROWS; s++) a += WK_RK45_E[s] * K[s * n + i];
            const double q = h * a / scale[i];
            if (i < n_head)
                e += q * q;
            else
                se += q * q;
        }
        if (n_head < n) e += weight * se;
        return sqrt(e / n_norm);
    }
    return 0.0;
}

static double rms_scaled(const double *v, const double *scale, int64_t n)
{
    double acc = 0.0;
    for (int64_t i = 0; i < n; i++) {
        const double q = v[i] / scale[i];
        acc += q * q;
    }
    return sqrt(acc / (double)n);
}

/* Hairer's starting step size (Hairer, Norsett, Wanner I, Sect. II.4).  One rhs
 * evaluation; ``scale``, ``tmp``, ``f1`` are scratch of length n_z. */
static double initial_step(const model_t *m, int64_t phase, double t, const double *y,
                           const double *f0, int order, double rtol, double atol,
                           double max_step, double span, double *tmp, double *f1,
                           double *scale)
{
    const int64_t n = m->n_z;
    for (int64_t i = 0; i < n; i++) scale[i] = atol + rtol * fabs(y[i]);
    const double d0 = rms_scaled(y, scale, n);
    const double d1 = rms_scaled(f0, scale, n);
    double h0;
    if (d0 < 1e-5 || d1 < 1e-5)
        h0 = 1e-6;
    else
        h0 = 0.01 * d0 / d1;
    h0 = min2(h0, span);
    for (int64_t i = 0; i < n; i++) tmp[i] = y[i] + h0 * f0[i];
    fun(m, phase, t + h0, tmp, f1);
    for (int64_t i = 0; i < n; i++) tmp[i] = f1[i] - f0[i];
    const double d2 = rms_scaled(tmp, scale, n) / h0;
    double h1;
    if (d1 <= 1e-15 && d2 <= 1e-15)
        h1 = max2(1e-6, h0 * 1e-3);
    else
        h1 = pow(0.01 / max2(d1, d2), 1.0 / (double)(order + 1));
    return min2(min2(min2(100.0 * h0, h1), max_step), span);
}

/* How much of a step's dense output is ready: none, the state's n_x components (all that
 * guards and samples read) or all n_z (the event state with its sensitivities). */
#define DENSE_NONE 0
#define DENSE_STATE 1
#define DENSE_FULL 2

/* Fill the dense-output coefficients Q of the step (t, y_old) -> (t + h, y_new), from what
 * is ready (``have``) up to ``want`` (DENSE_STATE or DENSE_FULL).  K[0] is f at the step
 * start and K[n_stages] f at the step end (Hermite: K[1]).  Returns the number of extra rhs
 * evaluations (3 for DOP853, else 0), once per step.
 *
 * DOP853 with sensitivities: the state's components of the three extra stages depend on
 * the state's alone (the variational equations do not feed back), so DENSE_STATE computes
 * just those (rhs calls, no Jacobians), and DENSE_FULL -- needed only in a step with an
 * event -- adds the sensitivities' (Jacobian calls at the same stage points).  Every number
 * is computed by the same expression as in one pass, so the result is bit-identical. */
static int64_t dense_prepare(int kind, const model_t *m, int64_t phase, double t,
                             const double *y_old, const double *y_new, double h, double *K,
                             double *Q, double *tmp, int have, int want)
{
    const int64_t n = m->n_z;
    if (kind == DENSE_DOP853) {
        const int split = m->want_jac && want == DENSE_STATE;
        /* components [lo, hi) of Q are filled now */
        const int64_t lo = (have == DENSE_STATE) ? m->n_x : 0;
        const int64_t hi = split ? m->n_x : n;
        if (lo >= hi) return 0;
        for (int s = WK_DOP853_N_STAGES + 1; s < K_ROWS; s++) {
            stage_combine(WK_DOP853_A[s], s, K, n, hi, y_old, h, tmp);
            const double ts = t + WK_DOP853_C[s] * h;
            if (split)
                m->fn.rhs(phase, ts, tmp, m->p, K + s * n, m->fn.ctx);
            else if (have == DENSE_STATE)
                fun_var(m, phase, ts, tmp, K + s * n);
            else
                fun(m, phase, ts, tmp, K + s * n);
        }
        for (int64_t i = lo; i < hi; i++) {
            const double dy = y_new[i] - y_old[i];
            Q[0 * n + i] = dy;
            Q[1 * n + i] = h * K[i] - dy;
            Q[2 * n + i] = 2.0 * dy - h * (K[WK_DOP853_N_STAGES * n + i] + K[i]);
        }
        for (int r = 0; r < WK_DOP853_D_ROWS; r++)
            stage_combine(WK_DOP853_D[r], WK_DOP853_D_COLS, K + lo, n, hi - lo, NULL, h,
                          Q + (3 + r) * n + lo);
        return have == DENSE_NONE ? K_ROWS - WK_DOP853_N_STAGES - 1 : 0;
    }
    if (have != DENSE_NONE) return 0;
    if (kind == DENSE_RK45) {
        for (int64_t i = 0; i < n; i++) {
            for (int r = 0; r < WK_RK45_P_COLS; r++) {
                double acc = 0.0;
                for (int s = 0; s < WK_RK45_P_ROWS; s++) acc += WK_RK45_P[s][r] * K[s * n + i];
                Q[r * n + i] = h * acc;
            }
        }
        return 0;
    }
    for (int64_t i = 0; i < n; i++) {
        Q[0 * n + i] = y_new[i] - y_old[i];
        Q[1 * n + i] = h * K[i];
        Q[2 * n + i] = h * K[n + i];
    }
    return 0;
}

/* What dense_prepare(..., DENSE_NONE, DENSE_STATE) leaves ready. */
static inline int dense_have_after(int kind, const model_t *m)
{
    return (kind == DENSE_DOP853 && m->want_jac) ? DENSE_STATE : DENSE_FULL;
}

/* Dense output at t_old + theta * h, first ``count`` components into ``out``; Q has rows
 * of length ``n``. */
static void dense_eval(int kind, const double *Q, int64_t n, const double *y_old,
                       double theta, int64_t count, double *out)
{
    if (kind == DENSE_DOP853) {
        const double s = theta;
        const double s1 = 1.0 - theta;
        for (int64_t i = 0; i < count; i++) {
            double v = Q[5 * n + i] + s * Q[6 * n + i];
            v = Q[4 * n + i] + s1 * v;
            v = Q[3 * n + i] + s * v;
            v = Q[2 * n + i] + s1 * v;
            v = Q[1 * n + i] + s * v;
            v = Q[0 * n + i] + s1 * v;
            out[i] = y_old[i] + s * v;
        }
    } else if (kind == DENSE_RK45) {
        for (int64_t i = 0; i < count; i++) {
            double v = Q[3 * n + i];
            v = Q[2 * n + i] + theta * v;
            v = Q[1 * n + i] + theta * v;
            v = Q[0 * n + i] + theta * v;
            out[i] = y_old[i] + theta * v;
        }
    } else {
        /* cubic Hermite: y0 + th*D + th(th-1)[(1-2th)D + (th-1) h f0 + th h f1] */
        for (int64_t i = 0; i < count; i++) {
            const double d = Q[i];
            out[i] = y_old[i] + theta * d +
                     theta * (theta - 1.0) *
                         ((1.0 - 2.0 * theta) * d + (theta - 1.0) * Q[n + i] +
                          theta * Q[2 * n + i]);
        }
    }
}

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

static double guard_at(const model_t *m, const step_t *st, double tau, double *xbuf,
                       double *gbuf, int64_t i)
{
    dense_eval(st->kind, st->Q, m->n_z, st->y_old, (tau - st->t_old) / st->h, m->n_x, xbuf);
    m->fn.guards(st->phase, tau, xbuf, m->p, gbuf, m->fn.ctx);
    return gbuf[i];
}

/* Root of guard i in [a, b] on the dense output (Illinois regula falsi with bisection
 * safeguard); returns the fired-side end of the final bracket. */
static double locate(const model_t *m, const step_t *st, double *xbuf, double *gbuf, int64_t i,
                     double a, double b, double ga, double gb)
{
    const double sgn = ga > 0.0 ? 1.0 : -1.0;
    double ua = sgn * ga; /* > 0 (pre-fire side) */
    double ub = sgn * gb; /* <= 0 (fired side) */
    if (ub == 0.0) return b;
    int side = 0;
    double width_old = b - a;
    int slow = 0;
    for (int it = 0; it < 200; it++) {
        const double width = b - a;
        if (width <= 4.0 * spacing(max2(fabs(a), fabs(b)))) break;
        double c;
        if (slow >= 2) {
            c = 0.5 * (a + b);
            slow = 0;
        } else {
            c = b - ub * (b - a) / (ub - ua);
        }
        if (!(a < c && c < b)) c = 0.5 * (a + b);
        const double uc = sgn * guard_at(m, st, c, xbuf, gbuf, i);
        if (uc <= 0.0) {
            b = c;
            ub = uc;
            if (uc == 0.0) break;
            if (side == -1) ua *= 0.5; /* Illinois modification */
            side = -1;
        } else {
            a = c;
            ua = uc;
            if (side == 1) ub *= 0.5;
            side = 1;
        }
        if (b - a > 0.5 * width_old)
            slow += 1;
        else
            slow = 0;
        width_old = b - a;
    }
    return b;
}

static inline double fd_step(double v) { return FD_REL_STEP * max2(1.0, fabs(v)); }

/* Scratch of event_derivatives. */
typedef struct {
    double *grad; /* (n_x,) gradient of the guard */
    double *DR;   /* (n_x, n_x) Jacobian of the reset */
    double *dRdt; /* (n_x,) */
    double *gbuf; /* (n_guards,) */
    double *xp;   /* (n_x,) */
    double *xn;   /* (n_x,) */
    double *imp;  /* (n_impulse,) */
    double *col;  /* (n_x,) */
    double *colh; /* (n_x,) */
} deriv_t;

/* Gradient of guard k and Jacobian of the reset at (t, x), with their t-partials, by
 * Richardson-extrapolated central differences D = (4 D(h/2) - D(h)) / 3.  Fills d->grad,
 * d->DR, d->dRdt; returns dg/dt. */
static double event_derivatives(const model_t *m, const deriv_t *d, int64_t phase, int64_t k,
                                double t, const double *x)
{
    const int64_t n_x = m->n_x;
    int64_t out[3];
    double dgdt = 0.0;
    for (int64_t j = 0; j < n_x + 1; j++) { /* j == n_x: time */
        const double base = (j == n_x) ? t : x[j];
        const double hh = fd_step(base);
        double gd = 0.0, gdh = 0.0;
        for (int level = 0; level < 2; level++) {
            const double step = (level == 0) ? hh : 0.5 * hh;
            double gsum = 0.0;
            for (int si = 0; si < 2; si++) {
                const double sgn = (si == 0) ? 1.0 : -1.0;
                double tt = t;
                for (int64_t i = 0; i < n_x; i++) d->xp[i] = x[i];
                if (j == n_x)
                    tt = t + sgn * step;
                else
                    d->xp[j] = x[j] + sgn * step;
                m->fn.guards(phase, tt, d->xp, m->p, d->gbuf, m->fn.ctx);
                gsum += sgn * d->gbuf[k];
                for (int64_t i = 0; i < n_x; i++) d->xn[i] = d->xp[i];
                for (int64_t i = 0; i < m->n_impulse; i++) d->imp[i] = 0.0;
                m->fn.reset(phase, k, tt, d->xp, m->p, d->xn, d->imp, out, m->fn.ctx);
                double *col = (level == 0) ? d->col : d->colh;
                for (int64_t i = 0; i < n_x; i++) {
                    if (sgn > 0)
                        col[i] = d->xn[i];
                    else
                        col[i] = (col[i] - d->xn[i]) / (2.0 * step);
                }
            }
            if (level == 0)
                gd = gsum / (2.0 * step);
            else
                gdh = gsum / (2.0 * step);
        }
        const double gval = (4.0 * gdh - gd) / 3.0;
        if (j == n_x) {
            dgdt = gval;
            for (int64_t i = 0; i < n_x; i++) d->dRdt[i] = (4.0 * d->colh[i] - d->col[i]) / 3.0;
        } else {
            d->grad[j] = gval;
            for (int64_t i = 0; i < n_x; i++)
                d->DR[i * n_x + j] = (4.0 * d->colh[i] - d->col[i]) / 3.0;
        }
    }
    return dgdt;
}

static void init_arming(const model_t *m, int64_t phase, const double *g, unsigned char *armed)
{
    const int64_t *dir = m->directions + phase * m->n_guards;
    for (int64_t i = 0; i < m->n_guards; i++) armed[i] = (unsigned char)pre_side(dir[i], g[i]);
}

/* Arm a guard that starts within GUARD_TOL of zero, strictly on its pre-fire side, and is
 * moving toward firing (its rate along f, probed by one guard evaluation). */
static void arm_approaching(const model_t *m, int64_t phase, double t, const double *x,
                            const double *f, const double *g, unsigned char *armed,
                            double *xbuf, double *gbuf)
{
    int probed = 0;
    const int64_t *dir = m->directions + phase * m->n_guards;
    for (int64_t i = 0; i < m->n_guards; i++) {
        if (armed[i] || fabs(g[i]) > WK_GUARD_TOL || g[i] == 0.0) continue;
        if (!probed) {
            for (int64_t k = 0; k < m->n_x; k++) xbuf[k] = x[k] + RATE_EPS * f[k];
            m->fn.guards(phase, t, xbuf, m->p, gbuf, m->fn.ctx);
            probed = 1;
        }
        const double rate = gbuf[i] - g[i];
        const int64_t d = dir[i];
        if (d <= 0 && g[i] > 0.0 && rate < 0.0)
            armed[i] = 1;
        else if (d >= 0 && g[i] < 0.0 && rate > 0.0)
            armed[i] = 1;
    }
}

/* The guards' rates along f: g(x + eps f) - g(x) (one guard call). */
static void guard_rates(const model_t *m, int64_t phase, double t, const double *x,
                        const double *f, const double *g, double *rate, double *xbuf)
{
    for (int64_t k = 0; k < m->n_x; k++) xbuf[k] = x[k] + RATE_EPS * f[k];
    m->fn.guards(phase, t, xbuf, m->p, rate, m->fn.ctx);
    for (int64_t i = 0; i < m->n_guards; i++) rate[i] = rate[i] - g[i];
}

static double dip_value(const model_t *m, const step_t *st, double theta, double sign,
                        double *xbuf, double *gbuf, int64_t i)
{
    dense_eval(st->kind, st->Q, m->n_z, st->y_old, theta, m->n_x, xbuf);
    m->fn.guards(st->phase, st->t_old, xbuf, m->p, gbuf, m->fn.ctx);
    return sign * gbuf[i];
}

/* Extremum of guard i over the step on the dense output (golden section); sign = +1 looks
 * for a minimum, -1 for a maximum.  Returns the step fraction in (0, 1) of the extremum
 * found and stores the guard value there in *value. */
static double dip(const model_t *m, const step_t *st, double *xbuf, double *gbuf, int64_t i,
                  double sign, double *value)
{
    double a = 0.0, b = 1.0;
    double c = b - INVPHI * (b - a);
    double d = a + INVPHI * (b - a);
    double fc = dip_value(m, st, c, sign, xbuf, gbuf, i);
    double fd = dip_value(m, st, d, sign, xbuf, gbuf, i);
    for (int it = 0; it < 40; it++) {
        if (fc < fd) {
            b = d;
            d = c;
            fd = fc;
            c = b - INVPHI * (b - a);
            fc = dip_value(m, st, c, sign, xbuf, gbuf, i);
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + INVPHI * (b - a);
            fd = dip_value(m, st, d, sign, xbuf, gbuf, i);
        }
        if (fc <= 0.0 || fd <= 0.0) break;
    }
    if (fc < fd) {
        *value = sign * fc;
        return c;
    }
    *value = sign * fd;
    return d;
}

/* Add x to the compensated sum hi + lo (Knuth's two-sum). */
static inline void two_sum(double *hi, double *lo, double x)
{
    const double s = *hi + x;
    const double bp = s - *hi;
    const double err = (*hi - (s - bp)) + (x - bp);
    *hi = s;
    *lo = *lo + err;
}

/* Absolute time -> local time of the current segment. */
static inline double local_time(double t_abs, double t_off, double t_off_c)
{
    return (t_abs - t_off) - t_off_c;
}

/* ------------------------------------------------------------------------------------------
 * Growing storage
 * ------------------------------------------------------------------------------------------ */

static int64_t grown_capacity(int64_t cap, int64_t n)
{
    while (cap < n) cap = 2 * cap + 1;
    return cap;
}

/* Reallocate ``ptr`` for ``rows`` rows of ``bytes`` bytes; returns -1 from the enclosing
 * function when out of memory (``ptr`` then keeps its old block). */
#define RESIZE(ptr, rows, bytes)                                         \
    do {                                                                 \
        void *nb_ = realloc((ptr), (size_t)(rows) * (size_t)(bytes));    \
        if (nb_ == NULL) return -1;                                      \
        (ptr) = nb_;                                                     \
    } while (0)

/* Room for n events; 0 on success. */
static int grow_events(wk_result *res, int64_t *cap, int64_t n, int64_t n_x, int64_t n_impulse)
{
    if (n <= *cap) return 0;
    const int64_t c = grown_capacity(*cap, n);
    RESIZE(res->ev_t, c, sizeof(double));
    RESIZE(res->ev_guard, c, sizeof(int64_t));
    RESIZE(res->ev_phase_before, c, sizeof(int64_t));
    RESIZE(res->ev_phase_after, c, sizeof(int64_t));
    RESIZE(res->ev_x_pre, c, (size_t)n_x * sizeof(double));
    RESIZE(res->ev_x_post, c, (size_t)n_x * sizeof(double));
    RESIZE(res->ev_impulse, c, (size_t)n_impulse * sizeof(double));
    *cap = c;
    return 0;
}

/* Room for n record rows; 0 on success. */
static int grow_record(wk_result *res, int64_t *cap, int64_t n, int64_t n_x)
{
    if (n <= *cap) return 0;
    const int64_t c = grown_capacity(*cap, n);
    RESIZE(res->r_t, c, sizeof(double));
    RESIZE(res->r_x, c, (size_t)n_x * sizeof(double));
    RESIZE(res->r_phase, c, sizeof(int64_t));
    *cap = c;
    return 0;
}

#undef RESIZE

#define FREE(ptr)       \
    do {                \
        free(ptr);      \
        (ptr) = NULL;   \
    } while (0)

void wk_result_free(wk_result *res)
{
    FREE(res->x);
    FREE(res->ev_t);
    FREE(res->ev_guard);
    FREE(res->ev_phase_before);
    FREE(res->ev_phase_after);
    FREE(res->ev_x_pre);
    FREE(res->ev_x_post);
    FREE(res->ev_impulse);
    FREE(res->s_x);
    FREE(res->s_phase);
    FREE(res->r_t);
    FREE(res->r_x);
    FREE(res->r_phase);
    FREE(res->jac);
    FREE(res->dt_dx0);
}

#undef FREE

/* ------------------------------------------------------------------------------------------
 * The kernel: one call = one whole run
 * ------------------------------------------------------------------------------------------ */

int wk_hybrid_solve(const wk_functions *fn, const wk_problem *pb, wk_result *res)
{
    const int64_t n_x = pb->n_x;
    const int64_t n_guards = pb->n_guards;
    const int64_t n_impulse = pb->n_impulse;
    const int want_jac = pb->want_jac != 0;
    /* columns of Phi: the seed's, or n_x for the identity */
    const int64_t n_c = (pb->jac_seed != NULL) ? pb->n_seed : n_x;
    const int64_t n_z = want_jac ? n_x + n_x * n_c : n_x;
    /* the error norm (error_norm): plain, or weighted for a seed of fewer than n_x columns */
    const int seeded = want_jac && n_c < n_x;
    const int64_t err_head = seeded ? n_x : n_z;
    const double err_weight = seeded ? (double)n_x / (double)n_c : 1.0;
    const double err_n = seeded ? (double)n_x + (double)n_x * (double)n_x : (double)n_z;
    const int method = pb->method;
    const int adaptive = pb->adaptive != 0;
    const double rtol = pb->rtol, atol = pb->atol;
    const double first_step = pb->first_step, max_step = pb->max_step;
    const int output = pb->output;
    const int64_t n_strides = pb->n_strides;
    const int64_t n_interior = pb->n_interior;
    int rc = WK_OK;

    memset(res, 0, sizeof *res);

    /* ---- method set-up ---- */
    const double *A, *B, *C;
    int a_cols, n_stages, kind, err_order, order;
    if (method == WK_METHOD_DOP853) {
        A = &WK_DOP853_A[0][0];
        a_cols = WK_DOP853_A_COLS;
        B = WK_DOP853_B;
        C = WK_DOP853_C;
        n_stages = WK_DOP853_N_STAGES;
        kind = DENSE_DOP853;
        err_order = WK_DOP853_ERR_ORDER;
        order = WK_DOP853_ORDER;
    } else if (method == WK_METHOD_DP5) {
        A = &WK_RK45_A[0][0];
        a_cols = WK_RK45_A_COLS;
        B = WK_RK45_B;
        C = WK_RK45_C;
        n_stages = WK_RK45_N_STAGES;
        kind = DENSE_RK45;
        err_order = WK_RK45_ERR_ORDER;
        order = WK_RK45_ORDER;
    } else if (method == WK_METHOD_RK4) {
        A = &WK_RK4_A[0][0];
        a_cols = WK_RK4_A_COLS;
        B = WK_RK4_B;
        C = WK_RK4_C;
        n_stages = WK_RK4_N_STAGES;
        kind = DENSE_HERMITE;
        err_order = WK_RK4_ERR_ORDER;
        order = WK_RK4_ORDER;
    } else {
        A = &WK_EULER_A[0][0];
        a_cols = WK_EULER_A_COLS;
        B = WK_EULER_B;
        C = WK_EULER_C;
        n_stages = WK_EULER_N_STAGES;
        kind = DENSE_HERMITE;
        err_order = WK_EULER_ERR_ORDER;
        order = WK_EULER_ORDER;
    }
    const double exponent = -1.0 / (double)(err_order + 1);

    /* ---- work arrays: one zeroed block ---- */
    const int64_t n_frac_max = n_interior + 2;
    const int64_t n_work = 7 * n_z                /* z y_new tmp f0 f1 scale iscale */
                           + K_ROWS * n_z + Q_ROWS * n_z /* K Q */
                           + n_z                  /* zev */
                           + 2 * n_x * n_x        /* J DR */
                           + n_x * n_c + n_c      /* Phi_m gPhi */
                           + 11 * n_x             /* xbuf x_new fm fp w, derivatives */
                           + 2 * n_impulse        /* impulse imp */
                           + 7 * n_guards         /* ga gb gbuf rate_a rate_b g_end, dgbuf */
                           + 4 * n_guards         /* chattering test */
                           + n_frac_max;
    double *work = calloc((size_t)n_work, sizeof(double));
    unsigned char *armed = calloc((size_t)n_guards + 1, 1);
    double *cursor = work;
#define TAKE(count) (cursor += (count), cursor - (count))
    if (work == NULL || armed == NULL) {
        rc = WK_ERR_NOMEM;
        goto done;
    }
    double *z = TAKE(n_z), *y_new = TAKE(n_z), *tmp = TAKE(n_z), *f0 = TAKE(n_z);
    double *f1 = TAKE(n_z), *scale = TAKE(n_z), *iscale = TAKE(n_z);
    double *K = TAKE(K_ROWS * n_z), *Q = TAKE(Q_ROWS * n_z), *zev = TAKE(n_z);
    double *J = TAKE(n_x * n_x), *Phi_m = TAKE(n_x * n_c);
    double *xbuf = TAKE(n_x), *x_new = TAKE(n_x), *fm = TAKE(n_x), *fp = TAKE(n_x);
    double *w = TAKE(n_x), *gPhi = TAKE(n_c);
    double *impulse = TAKE(n_impulse);
    double *ga = TAKE(n_guards), *gb = TAKE(n_guards), *gbuf = TAKE(n_guards);
    double *rate_a = TAKE(n_guards), *rate_b = TAKE(n_guards), *g_end = TAKE(n_guards);
    double *frac = TAKE(n_frac_max);
    /* chattering test, per guard: absolute time of its last applied firing (NAN: none yet),
     * the last interval, the first interval of the current shrinking chain, its length */
    double *zeno_t = TAKE(n_guards), *zeno_prev = TAKE(n_guards);
    double *zeno_first = TAKE(n_guards), *zeno_len = TAKE(n_guards);
    for (int64_t i = 0; i < n_guards; i++) zeno_t[i] = NAN;
    deriv_t dv;
    dv.grad = TAKE(n_x);
    dv.DR = TAKE(n_x * n_x);
    dv.dRdt = TAKE(n_x);
    dv.gbuf = TAKE(n_guards);
    dv.xp = TAKE(n_x);
    dv.xn = TAKE(n_x);
    dv.imp = TAKE(n_impulse);
    dv.col = TAKE(n_x);
    dv.colh = TAKE(n_x);
#undef TAKE

    const model_t mdl = {*fn,       pb->p, pb->directions, n_x, n_z, n_guards, n_impulse,
                         want_jac, n_c,   J};
    const model_t *m = &mdl;

    /* ---- result arrays ---- */
    const int store_events = output >= WK_OUTPUT_EVENTS;
    const int64_t n_samp_total = (output == WK_OUTPUT_SAMPLES) ? pb->n_samples : 0;
    const double *sample_times = pb->sample_times;
    int64_t cap_e = 0, cap_r = 0;
    res->x = malloc((size_t)n_x * sizeof(double));
    res->jac = calloc((size_t)(n_x * n_c), sizeof(double));
    res->dt_dx0 = calloc((size_t)n_c, sizeof(double));
    if (res->x == NULL || res->jac == NULL || res->dt_dx0 == NULL) {
        rc = WK_ERR_NOMEM;
        goto done;
    }
    if (store_events && grow_events(res, &cap_e, EVENTS_CAP0, n_x, n_impulse)) {
        rc = WK_ERR_NOMEM;
        goto done;
    }
    if (n_samp_total > 0) {
        res->s_x = malloc((size_t)(n_samp_total * n_x) * sizeof(double));
        res->s_phase = malloc((size_t)n_samp_total * sizeof(int64_t));
        if (res->s_x == NULL || res->s_phase == NULL) {
            rc = WK_ERR_NOMEM;
            goto done;
        }
    }
    if (output == WK_OUTPUT_FULL && grow_record(res, &cap_r, RECORD_CAP0, n_x)) {
        rc = WK_ERR_NOMEM;
        goto done;
    }
    int64_t n_log = 0, n_samp = 0, n_rec = 0;

    /* ---- counters ---- */
    int64_t n_steps = 0, n_rej = 0, n_rhs = 0, n_events = 0, n_done = 0;
    double err_sum = 0.0;
    int64_t status = RUNNING;

    for (int64_t i = 0; i < n_x; i++) z[i] = pb->x0[i];
    if (want_jac) {
        if (pb->jac_seed != NULL)
            memcpy(z + n_x, pb->jac_seed, (size_t)(n_x * n_c) * sizeof(double));
        else
            for (int64_t i = 0; i < n_x; i++) z[n_x + i * n_x + i] = 1.0;
    }

    /* Time is a compensated absolute offset (at the start of the current segment) plus a
     * local time from 0. */
    double t_off = pb->t0;
    double t_off_c = 0.0;
    double t = 0.0;
    double t_end = pb->t_max - pb->t0;
    int64_t phase = pb->phase0;
    const double t_max = pb->t_max;
    if (output == WK_OUTPUT_FULL) {
        res->r_t[0] = t_off;
        memcpy(res->r_x, z, (size_t)n_x * sizeof(double));
        res->r_phase[0] = phase;
        n_rec = 1;
    }

    /* ---- segment start ---- */
    fun(m, phase, t, z, f0);
    n_rhs += 1;
    if (n_guards > 0) {
        fn->guards(phase, t, z, pb->p, ga, fn->ctx);
        init_arming(m, phase, ga, armed);
        arm_approaching(m, phase, t, z, f0, ga, armed, xbuf, gbuf);
        guard_rates(m, phase, t, z, f0, ga, rate_a, xbuf);
    }
    double h;
    if (adaptive) {
        if (first_step > 0.0) {
            h = min2(min2(first_step, max_step), t_end - t);
        } else {
            h = initial_step(m, phase, t, z, f0, order, rtol, atol, max_step, t_end - t, tmp,
                             f1, iscale);
            n_rhs += 1;
        }
    } else {
        h = first_step;
    }
    int nonfinite_seen = 0;
    int rejected_now = 0;
    const int64_t m_sub = n_interior + 1;

    while (status == RUNNING) {
        if (t >= t_end) {
            status = n_strides == 0 ? ST_COMPLETED : ST_NO_EVENT;
            break;
        }
        if (n_steps + n_rej >= pb->max_steps) {
            status = ST_MAX_STEPS;
            break;
        }
        h = min2(h, max_step);
        int last = 0;
        if (t + 1.01 * h >= t_end) {
            h = t_end - t;
            last = 1;
        }
        const double min_step = 10.0 * spacing(fabs(t));
        if (adaptive && h < min_step) {
            status = nonfinite_seen ? ST_NONFINITE : ST_STEP_UNDERFLOW;
            break;
        }
        /* ---- one step ---- */
        memcpy(K, f0, (size_t)n_z * sizeof(double));
        n_rhs += rk_stages(m, phase, t, z, h, A, a_cols, C, B, n_stages, K, y_new, tmp);
        double *K_end = K + n_stages * n_z;
        const double t_new = last ? t_end : t + h;
        double err = 0.0;
        if (adaptive) {
            for (int64_t i = 0; i < n_z; i++) scale[i] = atol + rtol * max2(fabs(z[i]), fabs(y_new[i]));
            if (seeded) {
                /* a seeded column's entries: relative to themselves, but to no less than
                 * SEED_COLUMN_FLOOR of the column's largest.  A column of (d x / d x0) S may
                 * nearly cancel in an entry whose terms the full matrix controls one by one
                 * (the five-link walker's lift mixes the stance and swing angles): measured
                 * against that entry alone, the step shrank 30-fold. */
                for (int64_t c = 0; c < n_c; c++) {
                    double cmax = 0.0;
                    for (int64_t r = 0; r < n_x; r++) {
                        const int64_t i = n_x + r * n_c + c;
                        cmax = max2(cmax, max2(fabs(z[i]), fabs(y_new[i])));
                    }
                    for (int64_t r = 0; r < n_x; r++) {
                        const int64_t i = n_x + r * n_c + c;
                        scale[i] = atol + rtol * max2(max2(fabs(z[i]), fabs(y_new[i])),
                                                      SEED_COLUMN_FLOOR * cmax);
                    }
                }
            }
            err = error_norm(method, K, h, scale, n_z, err_head, err_weight, err_n);
        }
        const int finite = all_finite(y_new, n_z) && all_finite(K_end, n_z) && isfinite(err);
        if (!finite) {
            if (!adaptive) {
                status = ST_NONFINITE;
                break;
            }
            nonfinite_seen = 1;
            n_rej += 1;
            rejected_now = 1;
            h *= 0.25;
            continue;
        }
        if (adaptive && err > 1.0) {
            n_rej += 1;
            rejected_now = 1;
            h *= max2(MIN_FACTOR, SAFETY * pow(err, exponent));
            continue;
        }
        /* ---- accepted ---- */
        n_steps += 1;
        nonfinite_seen = 0;
        err_sum += err * rtol;
        if (kind == DENSE_HERMITE) memmove(K + n_z, K_end, (size_t)n_z * sizeof(double));
        int dense_have = DENSE_NONE;
        int event_applied = 0;
        double ta = t;
        int64_t j = 1;
        int64_t n_frac = m_sub;
        for (int64_t q = 0; q < m_sub; q++) frac[q] = ((double)q + 1.0) / (double)m_sub;
        const step_t st = {kind, Q, z, t, h, phase};
        if (n_guards > 0) {
            /* Tangency check: an armed guard on its pre-fire side at both ends of the step
             * whose rate turns from "toward firing" to "away" has an extremum inside; find
             * it on the dense output and, if the guard dips past zero there, sample that
             * instant too. */
            fn->guards(phase, t_new, y_new, pb->p, g_end, fn->ctx);
            guard_rates(m, phase, t_new, y_new, K_end, g_end, rate_b, xbuf);
            double theta_dip = 2.0;
            const int64_t *dir = pb->directions + phase * n_guards;
            for (int64_t i = 0; i < n_guards; i++) {
                if (!armed[i]) continue;
                const int64_t d = dir[i];
                double sign = 0.0;
                if (d <= 0 && ga[i] > 0.0 && g_end[i] > 0.0 && rate_a[i] < 0.0 && 0.0 < rate_b[i])
                    sign = 1.0;
                else if (d >= 0 && ga[i] < 0.0 && g_end[i] < 0.0 && rate_a[i] > 0.0 &&
                         0.0 > rate_b[i])
                    sign = -1.0;
                if (sign != 0.0) {
                    if (dense_have == DENSE_NONE) {
                        n_rhs += dense_prepare(kind, m, phase, t, z, y_new, h, K, Q, tmp, DENSE_NONE,
                                               DENSE_STATE);
                        dense_have = dense_have_after(kind, m);
                    }
                    double gv;
                    const double th = dip(m, &st, xbuf, gbuf, i, sign, &gv);
                    if (sign * gv <= 0.0 && th < theta_dip) theta_dip = th;
                }
            }
            if (theta_dip < 1.0) {
                int64_t q = n_frac;
                while (q > 0 && frac[q - 1] > theta_dip) {
                    frac[q] = frac[q - 1];
                    q -= 1;
                }
                frac[q] = theta_dip;
                n_frac += 1;
            }
        }
        while (n_guards > 0 && j <= n_frac) {
            double tb;
            if (j == n_frac) {
                tb = t_new;
                fn->guards(phase, tb, y_new, pb->p, gb, fn->ctx);
            } else {
                if (dense_have == DENSE_NONE) {
                    n_rhs += dense_prepare(kind, m, phase, t, z, y_new, h, K, Q, tmp, DENSE_NONE,
                                           DENSE_STATE);
                    dense_have = dense_have_after(kind, m);
                }
                tb = t + frac[j - 1] * h;
                dense_eval(kind, Q, n_z, z, frac[j - 1], n_x, xbuf);
                fn->guards(phase, tb, xbuf, pb->p, gb, fn->ctx);
            }
            double best_t = INFINITY;
            int64_t best_i = -1;
            const int64_t *dir = pb->directions + phase * n_guards;
            for (int64_t i = 0; i < n_guards; i++) {
                if (!armed[i]) continue;
                const int64_t d = dir[i];
                double troot = INFINITY;
                if (crosses(d, ga[i], gb[i])) {
                    if (dense_have == DENSE_NONE) {
                        n_rhs += dense_prepare(kind, m, phase, t, z, y_new, h, K, Q, tmp, DENSE_NONE,
                                               DENSE_STATE);
                        dense_have = dense_have_after(kind, m);
                    }
                    troot = locate(m, &st, xbuf, gbuf, i, ta, tb, ga[i], gb[i]);
                } else if (last && j == n_frac) {
                    /* at t_max: an armed guard within GUARD_TOL on its pre-fire side fires */
                    const double u = ga[i] > 0.0 ? gb[i] : -gb[i];
                    if (fabs(ga[i]) > 0.0 && 0.0 < u && u <= WK_GUARD_TOL) troot = tb;
                }
                if (troot < best_t - 4.0 * spacing(fabs(troot))) {
                    best_t = troot;
                    best_i = i;
                }
            }
            if (best_i < 0) {
                for (int64_t i = 0; i < n_guards; i++) {
                    if (!armed[i]) armed[i] = (unsigned char)pre_side(dir[i], gb[i]);
                    ga[i] = gb[i];
                }
                ta = tb;
                j += 1;
                continue;
            }
            /* ---- an event at best_t ---- */
            if (dense_have != DENSE_FULL) {
                n_rhs += dense_prepare(kind, m, phase, t, z, y_new, h, K, Q, tmp, dense_have,
                                       DENSE_FULL);
                dense_have = DENSE_FULL;
            }
            const double theta = (best_t - t) / h;
            dense_eval(kind, Q, n_z, z, theta, n_z, zev);
            for (int64_t i = 0; i < n_x; i++) x_new[i] = zev[i];
            for (int64_t i = 0; i < n_impulse; i++) impulse[i] = 0.0;
            int64_t rout[3] = {0, 0, 0};
            fn->reset(phase, best_i, best_t, zev, pb->p, x_new, impulse, rout, fn->ctx);
            const int64_t action = rout[0], nxt = rout[1], st_code = rout[2];
            if (action == WK_EVENT_IGNORE) {
                armed[best_i] = 0;
                ta = best_t;
                fn->guards(phase, best_t, zev, pb->p, ga, fn->ctx);
                for (int64_t i = 0; i < n_guards; i++)
                    if (i != best_i && !armed[i]) armed[i] = (unsigned char)pre_side(dir[i], ga[i]);
                continue;
            }
            if (action != WK_EVENT_TERMINAL && (nxt < 0 || nxt >= pb->n_phases)) {
                res->phase = nxt;
                rc = WK_ERR_BAD_PHASE;
                goto done;
            }
            /* samples up to and including the event time come from the pre-event segment */
            while (n_samp < n_samp_total &&
                   local_time(sample_times[n_samp], t_off, t_off_c) <= best_t) {
                dense_eval(kind, Q, n_z, z,
                           (local_time(sample_times[n_samp], t_off, t_off_c) - t) / h, n_x,
                           res->s_x + n_samp * n_x);
                res->s_phase[n_samp] = phase;
                n_samp += 1;
            }
            if (store_events) {
                n_log += 1;
                if (grow_events(res, &cap_e, n_log, n_x, n_impulse)) {
                    rc = WK_ERR_NOMEM;
                    goto done;
                }
                const int64_t e = n_log - 1;
                res->ev_t[e] = t_off + (best_t + t_off_c);
                res->ev_guard[e] = best_i;
                res->ev_phase_before[e] = phase;
                memcpy(res->ev_x_pre + e * n_x, zev, (size_t)n_x * sizeof(double));
                if (action == WK_EVENT_TERMINAL) {
                    res->ev_phase_after[e] = phase;
                    memcpy(res->ev_x_post + e * n_x, zev, (size_t)n_x * sizeof(double));
                    for (int64_t i = 0; i < n_impulse; i++) res->ev_impulse[e * n_impulse + i] = 0.0;
                } else {
                    res->ev_phase_after[e] = nxt;
                    memcpy(res->ev_x_post + e * n_x, x_new, (size_t)n_x * sizeof(double));
                    memcpy(res->ev_impulse + e * n_impulse, impulse,
                           (size_t)n_impulse * sizeof(double));
                }
            }
            if (action == WK_EVENT_TERMINAL) {
                status = st_code;
                t = best_t;
                memcpy(z, zev, (size_t)n_z * sizeof(double));
                if (output == WK_OUTPUT_FULL) {
                    n_rec += 1;
                    if (grow_record(res, &cap_r, n_rec, n_x)) {
                        rc = WK_ERR_NOMEM;
                        goto done;
                    }
                    res->r_t[n_rec - 1] = t_off + (t + t_off_c);
                    memcpy(res->r_x + (n_rec - 1) * n_x, z, (size_t)n_x * sizeof(double));
                    res->r_phase[n_rec - 1] = phase;
                }
                event_applied = 1;
                break;
            }
            /* ---- apply the reset ---- */
            const int64_t phase_before = phase;
            n_events += 1;
            int finishing = 0;
            if (action == WK_EVENT_STRIDE) {
                n_done += 1;
                finishing = n_strides > 0 && n_done >= n_strides;
            }
            if (want_jac) {
                const double dgdt = event_derivatives(m, &dv, phase, best_i, best_t, zev);
                fn->rhs(phase, best_t, zev, pb->p, fm, fn->ctx);
                fn->rhs(nxt, best_t, x_new, pb->p, fp, fn->ctx);
                n_rhs += 2;
                double den = dgdt;
                for (int64_t i = 0; i < n_x; i++) den += dv.grad[i] * fm[i];
                /* w = f+ - DR f- - dR/dt (saltation) or -(DR f- + dR/dt) (map) */
                for (int64_t i = 0; i < n_x; i++) {
                    double acc = 0.0;
                    for (int64_t k = 0; k < n_x; k++) acc += dv.DR[i * n_x + k] * fm[k];
                    w[i] = acc + dv.dRdt[i];
                }
                if (finishing) {
                    for (int64_t i = 0; i < n_x; i++) w[i] = -w[i];
                } else {
                    for (int64_t i = 0; i < n_x; i++) w[i] = fp[i] - w[i];
                }
                /* M = DR + w grad^T / den; Phi <- M Phi (the n_c columns of Phi) */
                for (int64_t r = 0; r < n_x; r++)
                    for (int64_t c = 0; c < n_c; c++) Phi_m[r * n_c + c] = zev[n_x + r * n_c + c];
                for (int64_t c = 0; c < n_c; c++) {
                    double acc = 0.0;
                    for (int64_t k = 0; k < n_x; k++) acc += dv.grad[k] * Phi_m[k * n_c + c];
                    gPhi[c] = acc;
                }
                for (int64_t r = 0; r < n_x; r++) {
                    for (int64_t c = 0; c < n_c; c++) {
                        double acc = w[r] * gPhi[c] / den;
                        for (int64_t k = 0; k < n_x; k++)
                            acc += dv.DR[r * n_x + k] * Phi_m[k * n_c + c];
                        z[n_x + r * n_c + c] = acc;
                    }
                }
                if (finishing) {
                    for (int64_t c = 0; c < n_c; c++) res->dt_dx0[c] = -gPhi[c] / den;
                    res->has_dt = 1;
                }
            }
            phase = nxt;
            t = best_t;
            for (int64_t i = 0; i < n_x; i++) z[i] = x_new[i];
            if (output == WK_OUTPUT_FULL) {
                n_rec += 2;
                if (grow_record(res, &cap_r, n_rec, n_x)) {
                    rc = WK_ERR_NOMEM;
                    goto done;
                }
                res->r_t[n_rec - 2] = t_off + (t + t_off_c);
                memcpy(res->r_x + (n_rec - 2) * n_x, zev, (size_t)n_x * sizeof(double));
                res->r_phase[n_rec - 2] = phase_before;
                res->r_t[n_rec - 1] = t_off + (t + t_off_c);
                memcpy(res->r_x + (n_rec - 1) * n_x, z, (size_t)n_x * sizeof(double));
                res->r_phase[n_rec - 1] = phase;
            }
            event_applied = 1;
            /* re-base local time at the event */
            two_sum(&t_off, &t_off_c, t);
            t = 0.0;
            t_end = (t_max - t_off) - t_off_c;
            if (finishing) {
                status = ST_COMPLETED;
                break;
            }
            {
                const double t_ev = t_off + t_off_c;
                if (!isnan(zeno_t[best_i])) {
                    const double dt_ev = t_ev - zeno_t[best_i];
                    if (zeno_len[best_i] > 0.0 && dt_ev < zeno_prev[best_i]) {
                        zeno_len[best_i] += 1.0;
                    } else {
                        zeno_len[best_i] = 1.0;
                        zeno_first[best_i] = dt_ev;
                    }
                    zeno_prev[best_i] = dt_ev;
                    if (zeno_len[best_i] >= ZENO_CHAIN && dt_ev <= ZENO_RATIO * zeno_first[best_i]) {
                        status = ST_CHATTERING;
                        break;
                    }
                }
                zeno_t[best_i] = t_ev;
            }
            /* ---- restart the method at the event ---- */
            fun(m, phase, t, z, f0);
            n_rhs += 1;
            fn->guards(phase, t, z, pb->p, ga, fn->ctx);
            init_arming(m, phase, ga, armed);
            arm_approaching(m, phase, t, z, f0, ga, armed, xbuf, gbuf);
            guard_rates(m, phase, t, z, f0, ga, rate_a, xbuf);
            if (adaptive) {
                if (t < t_end) {
                    h = initial_step(m, phase, t, z, f0, order, rtol, atol, max_step, t_end - t,
                                     tmp, f1, iscale);
                    n_rhs += 1;
                }
            } else {
                h = first_step;
            }
            rejected_now = 0;
            break;
        }
        if (event_applied) continue;
        /* ---- no event in this step: samples, record, advance ---- */
        if (n_samp < n_samp_total && local_time(sample_times[n_samp], t_off, t_off_c) <= t_new) {
            if (dense_have == DENSE_NONE) {
                n_rhs += dense_prepare(kind, m, phase, t, z, y_new, h, K, Q, tmp, DENSE_NONE,
                                       DENSE_STATE);
                dense_have = dense_have_after(kind, m);
            }
            while (n_samp < n_samp_total &&
                   local_time(sample_times[n_samp], t_off, t_off_c) <= t_new) {
                dense_eval(kind, Q, n_z, z,
                           (local_time(sample_times[n_samp], t_off, t_off_c) - t) / h, n_x,
                           res->s_x + n_samp * n_x);
                res->s_phase[n_samp] = phase;
                n_samp += 1;
            }
        }
        t = t_new;
        memcpy(z, y_new, (size_t)n_z * sizeof(double));
        memcpy(f0, K_end, (size_t)n_z * sizeof(double));
        for (int64_t i = 0; i < n_guards; i++) rate_a[i] = rate_b[i];
        if (output == WK_OUTPUT_FULL) {
            n_rec += 1;
            if (grow_record(res, &cap_r, n_rec, n_x)) {
                rc = WK_ERR_NOMEM;
                goto done;
            }
            res->r_t[n_rec - 1] = t_off + (t + t_off_c);
            memcpy(res->r_x + (n_rec - 1) * n_x, z, (size_t)n_x * sizeof(double));
            res->r_phase[n_rec - 1] = phase;
        }
        if (last) {
            status = n_strides == 0 ? ST_COMPLETED : ST_NO_EVENT;
            break;
        }
        if (adaptive) {
            double factor;
            if (err == 0.0)
                factor = MAX_FACTOR;
            else
                factor = min2(MAX_FACTOR, SAFETY * pow(err, exponent));
            if (rejected_now) factor = min2(1.0, factor);
            h *= factor;
        }
        rejected_now = 0;
    }

    if (want_jac) memcpy(res->jac, z + n_x, (size_t)(n_x * n_c) * sizeof(double));
    memcpy(res->x, z, (size_t)n_x * sizeof(double));
    res->status = status;
    res->t = t_off + (t + t_off_c);
    res->phase = phase;
    res->err_sum = err_sum;
    res->counters[WK_N_STEPS] = n_steps;
    res->counters[WK_N_REJECTED] = n_rej;
    res->counters[WK_N_RHS] = n_rhs;
    res->counters[WK_N_EVENTS] = n_events;
    res->counters[WK_N_STRIDES] = n_done;
    res->counters[WK_N_LOG] = n_log;
    res->counters[WK_N_SAMPLES] = n_samp;
    res->counters[WK_N_RECORD] = n_rec;

done:
    free(work);
    free(armed);
    if (rc != WK_OK) {
        const int64_t bad_phase = res->phase;
        wk_result_free(res);
        memset(res, 0, sizeof *res);
        res->phase = bad_phase;
    }
    return rc;
}
