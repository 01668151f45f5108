/* walker's hybrid integrator, the driver (see hybrid.h; the algorithm is described in the
 * module docstring of walker/simulation/integrate.py): one call of wk_hybrid_solve is one whole run --
 * the loop over steps, the guards' check in each accepted step, the event found first
 * applied (reset, sensitivities, record), samples, and the result's growing storage.  The
 * pieces it calls live in hybrid_step.c (steps, error control), hybrid_dense.c (dense
 * output), hybrid_events.c (guards) and hybrid_saltation.c (sensitivities at events); see
 * hybrid_internal.h, also for the floating-point rules every file keeps.
 */
#include "hybrid.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hybrid_internal.h"
#include "wk_models.h"

/* Internal status: still running (Status values are >= 0). */
#define RUNNING (-1)
/* Events that do not advance time: STILL_EVENTS applied events in a row, each within
 * STILL_ULPS units in the last place of the time of the one before it, end the run as
 * chattering (the accumulation point reached: a reset whose state a guard fires on again at
 * once, e.g. a stick-slip switch that the next step's first instant undoes).  A cascade of
 * simultaneous events at one instant (an impact, then a knee lock) is a few events, bounded
 * by the model's guards. */
#define STILL_EVENTS 16
#define STILL_ULPS 4.0

volatile sig_atomic_t wk_interrupt = 0;

/* Initial capacities of the growing event log and record. */
#define EVENTS_CAP0 8
#define RECORD_CAP0 64

/* Make a step's dense output ready for the state's components (a no-op when it is:
 * ``*have`` tracks what is); returns the rhs evaluations spent. */
static inline int64_t dense_state_ready(int *have, int kind, const model_t *m, int64_t phase,
                                        double t, const double *y_old, const double *y_new,
                                        double h, double *K, double *Q, double *tmp)
{
    if (*have != DENSE_NONE) return 0;
    const int64_t n_rhs =
        wk_dense_prepare(kind, m, phase, t, y_old, y_new, h, K, Q, tmp, DENSE_NONE, DENSE_STATE);
    *have = dense_have_after(kind, m);
    return n_rhs;
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

/* Append the record row (t_abs, x, phase), x of n_x entries; 0 on success. */
static int record_row(wk_result *res, int64_t *cap, int64_t *n_rec, double t_abs,
                      const double *x, int64_t phase, int64_t n_x)
{
    const int64_t r = *n_rec;
    *n_rec = r + 1;
    if (grow_record(res, cap, r + 1, n_x)) return -1;
    res->r_t[r] = t_abs;
    memcpy(res->r_x + r * n_x, x, (size_t)n_x * sizeof(double));
    res->r_phase[r] = phase;
    return 0;
}

/* Take the samples not yet taken (from the n_samp-th of n_samp_total) whose times
 * (absolute, t_abs) fall at or before the local time t_limit, on the dense output of the
 * step st (n_z components, of which the n_x of the state are sampled); returns the new count
 * of samples taken. */
static int64_t take_samples(wk_result *res, int64_t n_samp, int64_t n_samp_total,
                            const double *t_abs, double t_off, double t_off_c, double t_limit,
                            const step_t *st, int64_t n_z, int64_t n_x)
{
    while (n_samp < n_samp_total && local_time(t_abs[n_samp], t_off, t_off_c) <= t_limit) {
        wk_dense_eval(st->kind, st->Q, n_z, st->y_old,
                      (local_time(t_abs[n_samp], t_off, t_off_c) - st->t_old) / st->h, n_x,
                      res->s_x + n_samp * n_x);
        res->s_phase[n_samp] = st->phase;
        n_samp += 1;
    }
    return n_samp;
}

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
    const wk_method *mt = wk_method_of(method);
    const int kind = mt->dense, order = mt->order;
    const double exponent = -1.0 / (double)(mt->err_order + 1);

    /* ---- work arrays: one zeroed block ---- */
    const int64_t n_frac_max = n_interior + 2;
    const int64_t n_work = 7 * n_z                /* z y_new tmp f0 f1 scale iscale */
                           + K_ROWS * n_z + Q_ROWS * n_z /* K Q */
                           + n_z                  /* zev */
                           + n_x * n_x            /* J */
                           + 2 * n_x              /* xbuf x_new */
                           + n_impulse            /* impulse */
                           + 6 * n_guards         /* ga gb gbuf rate_a rate_b g_end */
                           + 4 * n_guards         /* chattering test */
                           + n_frac_max
                           + (want_jac ? WK_SALTATION_WORK(n_x, n_c, n_guards, n_impulse) : 0);
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
    double *J = TAKE(n_x * n_x);
    double *xbuf = TAKE(n_x), *x_new = TAKE(n_x);
    double *impulse = TAKE(n_impulse);
    double *ga = TAKE(n_guards), *gb = TAKE(n_guards), *gbuf = TAKE(n_guards);
    double *rate_a = TAKE(n_guards), *rate_b = TAKE(n_guards), *g_end = TAKE(n_guards);
    double *frac = TAKE(n_frac_max);
    double *zeno = TAKE(4 * n_guards); /* chattering test (wk_chattering) */
    wk_chattering_init(zeno, n_guards);
    double *salt = want_jac ? TAKE(WK_SALTATION_WORK(n_x, n_c, n_guards, n_impulse)) : NULL;
#undef TAKE

    /* a built-in variant's parameter-only kernel terms, computed once for the run */
    wk_functions fn_run = *fn;
    double p_hoisted[WK_HOIST_MAX];
    const double *p_run = wk_model_hoist(&fn_run, pb->p, p_hoisted);
    const model_t mdl = {fn_run,   p_run, pb->directions, n_x, n_z, n_guards, n_impulse,
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
    int64_t n_still = 0; /* applied events in a row that did not advance time */

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
    wk_fun(m, phase, t, z, f0);
    n_rhs += 1;
    if (n_guards > 0) wk_arm_segment(m, phase, t, z, f0, ga, armed, rate_a, xbuf, gbuf);
    double h;
    if (adaptive) {
        if (first_step > 0.0) {
            h = min2(min2(first_step, max_step), t_end - t);
        } else {
            h = wk_initial_step(m, phase, t, z, f0, order, rtol, atol, max_step, t_end - t, tmp,
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
            status = n_strides == 0 ? WK_COMPLETED : WK_NO_EVENT;
            break;
        }
        if (n_steps + n_rej >= pb->max_steps) {
            status = WK_MAX_STEPS;
            break;
        }
        if (wk_interrupt) {
            status = WK_INTERRUPTED;
            break;
        }
        h = min2(h, max_step);
        int last = 0;
        if (t + 1.01 * h >= t_end) {
            h = t_end - t;
            last = 1;
        }
        const double min_step = 10.0 * spacing(fabs(t));
        /* !(h >= min_step): a NaN step size (a starting step from a non-finite rate, e.g.
         * parameters near their bounds) ends the run too, instead of being rejected until
         * max_steps (issue 33) */
        if (adaptive && !(h >= min_step)) {
            status = nonfinite_seen || isnan(h) ? WK_NONFINITE : WK_STEP_UNDERFLOW;
            break;
        }
        /* ---- one step ---- */
        memcpy(K, f0, (size_t)n_z * sizeof(double));
        n_rhs += wk_rk_stages(m, mt, phase, t, z, h, K, y_new, tmp);
        double *K_end = K + mt->n_stages * n_z;
        const double t_new = last ? t_end : t + h;
        double err = 0.0;
        if (adaptive) {
            wk_error_scale(m, seeded, rtol, atol, z, y_new, scale);
            err = wk_error_norm(method, K, h, scale, n_z, err_head, err_weight, err_n);
        }
        const int finite = wk_all_finite(y_new, n_z) && wk_all_finite(K_end, n_z) && isfinite(err);
        if (!finite) {
            if (!adaptive) {
                status = WK_NONFINITE;
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
            h *= wk_reject_factor(err, exponent);
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
            wk_guard_rates(m, phase, t_new, y_new, K_end, g_end, rate_b, xbuf);
            /* interior samples only where a guard may come near zero */
            if (pb->screen_interior && n_frac > 1 &&
                wk_guards_far(m, h, ga, g_end, rate_a, rate_b)) {
                frac[0] = 1.0;
                n_frac = 1;
            }
            double theta_dip = 2.0;
            const int64_t *dir = pb->directions + phase * n_guards;
            for (int64_t i = 0; i < n_guards; i++) {
                if (!armed[i]) continue;
                const double sign =
                    tangency_sign(dir[i], ga[i], g_end[i], rate_a[i], rate_b[i]);
                if (sign != 0.0) {
                    n_rhs += dense_state_ready(&dense_have, kind, m, phase, t, z, y_new, h, K,
                                               Q, tmp);
                    double gv;
                    const double th = wk_dip(m, &st, xbuf, gbuf, i, sign, &gv);
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
                n_rhs += dense_state_ready(&dense_have, kind, m, phase, t, z, y_new, h, K, Q, tmp);
                tb = t + frac[j - 1] * h;
                wk_dense_eval(kind, Q, n_z, z, frac[j - 1], n_x, xbuf);
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
                    n_rhs += dense_state_ready(&dense_have, kind, m, phase, t, z, y_new, h, K,
                                               Q, tmp);
                    troot = wk_locate(m, &st, xbuf, gbuf, i, ta, tb, ga[i], gb[i]);
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
                n_rhs += wk_dense_prepare(kind, m, phase, t, z, y_new, h, K, Q, tmp, dense_have,
                                       DENSE_FULL);
                dense_have = DENSE_FULL;
            }
            const double theta = (best_t - t) / h;
            wk_dense_eval(kind, Q, n_z, z, theta, n_z, zev);
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
            n_samp = take_samples(res, n_samp, n_samp_total, sample_times, t_off, t_off_c,
                                  best_t, &st, n_z, n_x);
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
                if (output == WK_OUTPUT_FULL &&
                    record_row(res, &cap_r, &n_rec, t_off + (t + t_off_c), z, phase, n_x)) {
                    rc = WK_ERR_NOMEM;
                    goto done;
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
                n_rhs += wk_saltation(m, phase, nxt, best_i, best_t, zev, x_new, finishing, z,
                                      res->dt_dx0, salt);
                if (finishing) res->has_dt = 1;
            }
            if (action == WK_EVENT_STRIDE && fn->on_stride != NULL)
                fn->on_stride(fn->ctx, n_done, x_new); /* the next step's ground (terrain.c) */
            phase = nxt;
            t = best_t;
            for (int64_t i = 0; i < n_x; i++) z[i] = x_new[i];
            /* the event's two rows: the state before and after the reset */
            if (output == WK_OUTPUT_FULL &&
                (record_row(res, &cap_r, &n_rec, t_off + (t + t_off_c), zev, phase_before, n_x) ||
                 record_row(res, &cap_r, &n_rec, t_off + (t + t_off_c), z, phase, n_x))) {
                rc = WK_ERR_NOMEM;
                goto done;
            }
            event_applied = 1;
            /* local time is the time since the previous event (or the start) */
            n_still = t <= STILL_ULPS * spacing(fabs(t_off)) ? n_still + 1 : 0;
            /* re-base local time at the event */
            two_sum(&t_off, &t_off_c, t);
            t = 0.0;
            t_end = (t_max - t_off) - t_off_c;
            if (finishing) {
                status = WK_COMPLETED;
                break;
            }
            if (wk_chattering(zeno, n_guards, best_i, t_off + t_off_c) ||
                n_still >= STILL_EVENTS) {
                status = WK_CHATTERING;
                break;
            }
            /* ---- restart the method at the event ---- */
            wk_fun(m, phase, t, z, f0);
            n_rhs += 1;
            wk_arm_segment(m, phase, t, z, f0, ga, armed, rate_a, xbuf, gbuf);
            if (adaptive) {
                if (t < t_end) {
                    h = wk_initial_step(m, phase, t, z, f0, order, rtol, atol, max_step, t_end - t,
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
            n_rhs += dense_state_ready(&dense_have, kind, m, phase, t, z, y_new, h, K, Q, tmp);
            n_samp = take_samples(res, n_samp, n_samp_total, sample_times, t_off, t_off_c, t_new,
                                  &st, n_z, n_x);
        }
        t = t_new;
        memcpy(z, y_new, (size_t)n_z * sizeof(double));
        memcpy(f0, K_end, (size_t)n_z * sizeof(double));
        for (int64_t i = 0; i < n_guards; i++) rate_a[i] = rate_b[i];
        if (output == WK_OUTPUT_FULL &&
            record_row(res, &cap_r, &n_rec, t_off + (t + t_off_c), z, phase, n_x)) {
            rc = WK_ERR_NOMEM;
            goto done;
        }
        if (last) {
            status = n_strides == 0 ? WK_COMPLETED : WK_NO_EVENT;
            break;
        }
        if (adaptive) h *= wk_accept_factor(err, exponent, rejected_now);
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
