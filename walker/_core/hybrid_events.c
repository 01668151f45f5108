/* Guards of the hybrid integrator (see hybrid_internal.h for the split; the rules are in
 * the module docstring of walker/simulation/integrate.py, section Events): arming at a segment start,
 * the guards' rates along the vector field, the root of a guard on the dense output
 * (Illinois regula falsi with bisection safeguard), the extremum of a guard inside a step
 * (golden section, the tangency check) and the chattering (Zeno) test of applied events.
 */
#include <math.h>

#include "hybrid_internal.h"

/* Probe step for guard rates along the vector field. */
#define RATE_EPS 1e-9
/* 1 / golden ratio. */
#define INVPHI 0.6180339887498949

/* Chattering (Zeno) test, per guard: the run stops when ZENO_CHAIN or more intervals in a row
 * between applied firings of the same guard shrink strictly and the last is below
 * ZENO_RATIO times the first of that chain.  A bouncing ball's impacts shrink by the
 * restitution per impact; a gait repeats its heel strikes at nearly equal intervals, and
 * distinct events crowding together (a friction switch just before a heel strike) are
 * different guards, so neither builds such a chain. */
#define ZENO_CHAIN 3
#define ZENO_RATIO 1e-2

/* ------------------------------------------------------------------------------------------
 * Root location
 * ------------------------------------------------------------------------------------------ */

static double guard_at(const model_t *m, const step_t *st, double tau, double *xbuf,
                       double *gbuf, int64_t i)
{
    wk_dense_eval(st->kind, st->Q, m->n_z, st->y_old, (tau - st->t_old) / st->h, m->n_x, xbuf);
    m->fn.guards(st->phase, tau, xbuf, m->p, gbuf, m->fn.ctx);
    return gbuf[i];
}

/* Root of guard i in [a, b] on the dense output (Illinois regula falsi with bisection
 * safeguard); returns the fired-side end of the final bracket. */
double wk_locate(const model_t *m, const step_t *st, double *xbuf, double *gbuf, int64_t i,
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

/* ------------------------------------------------------------------------------------------
 * Arming and rates
 * ------------------------------------------------------------------------------------------ */

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

void wk_guard_rates(const model_t *m, int64_t phase, double t, const double *x,
                    const double *f, const double *g, double *rate, double *xbuf)
{
    for (int64_t k = 0; k < m->n_x; k++) xbuf[k] = x[k] + RATE_EPS * f[k];
    m->fn.guards(phase, t, xbuf, m->p, rate, m->fn.ctx);
    for (int64_t i = 0; i < m->n_guards; i++) rate[i] = rate[i] - g[i];
}

void wk_arm_segment(const model_t *m, int64_t phase, double t, const double *x,
                    const double *f, double *g, unsigned char *armed, double *rate,
                    double *xbuf, double *gbuf)
{
    m->fn.guards(phase, t, x, m->p, g, m->fn.ctx);
    init_arming(m, phase, g, armed);
    arm_approaching(m, phase, t, x, f, g, armed, xbuf, gbuf);
    wk_guard_rates(m, phase, t, x, f, g, rate, xbuf);
}

/* The cubic Hermite interpolant of a guard over a step, in the step fraction s, is the
 * chord plus s (1 - s) [(1 - s) (D0 - Delta) - s (D1 - Delta)], with Delta = g_end - ga and
 * D0, D1 the end slopes (h times the rates); its distance from the chord is at most
 * max(|D0 - Delta|, |D1 - Delta|) / 4.  A guard is far when both end values exceed four
 * times that bound in magnitude (a margin for the interpolant's own error and the probed
 * rates' rounding). */
int wk_guards_far(const model_t *m, double h, const double *ga, const double *g_end,
                  const double *rate_a, const double *rate_b)
{
    const double scale = h / RATE_EPS;
    for (int64_t i = 0; i < m->n_guards; i++) {
        const double a = ga[i], b = g_end[i];
        if (!(a > 0.0 && b > 0.0) && !(a < 0.0 && b < 0.0)) return 0;
        const double delta = b - a;
        const double bend =
            max2(fabs(scale * rate_a[i] - delta), fabs(scale * rate_b[i] - delta));
        if (!(min2(fabs(a), fabs(b)) > bend)) return 0;
    }
    return 1;
}

/* ------------------------------------------------------------------------------------------
 * Extremum inside a step (tangency)
 * ------------------------------------------------------------------------------------------ */

static double dip_value(const model_t *m, const step_t *st, double theta, double sign,
                        double *xbuf, double *gbuf, int64_t i)
{
    wk_dense_eval(st->kind, st->Q, m->n_z, st->y_old, theta, m->n_x, xbuf);
    /* at the trial point's own time (an autonomous guard ignores it) */
    m->fn.guards(st->phase, st->t_old + theta * st->h, xbuf, m->p, gbuf, m->fn.ctx);
    return sign * gbuf[i];
}

/* Extremum of guard i over the step on the dense output (golden section); sign = +1 looks
 * for a minimum, -1 for a maximum.  Returns the step fraction in (0, 1) of the extremum
 * found and stores the guard value there in *value. */
double wk_dip(const model_t *m, const step_t *st, double *xbuf, double *gbuf, int64_t i,
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

/* ------------------------------------------------------------------------------------------
 * Chattering
 * ------------------------------------------------------------------------------------------ */

/* ``zeno`` holds four rows of n_guards, per guard: the absolute time of its last applied
 * firing (NAN: none yet), the last interval, the first interval of the current shrinking
 * chain, its length. */
void wk_chattering_init(double *zeno, int64_t n_guards)
{
    for (int64_t i = 0; i < n_guards; i++) zeno[i] = NAN;
}

int wk_chattering(double *zeno, int64_t n_guards, int64_t k, double t_ev)
{
    double *zeno_t = zeno, *zeno_prev = zeno + n_guards;
    double *zeno_first = zeno + 2 * n_guards, *zeno_len = zeno + 3 * n_guards;
    if (!isnan(zeno_t[k])) {
        const double dt_ev = t_ev - zeno_t[k];
        if (zeno_len[k] > 0.0 && dt_ev < zeno_prev[k]) {
            zeno_len[k] += 1.0;
        } else {
            zeno_len[k] = 1.0;
            zeno_first[k] = dt_ev;
        }
        zeno_prev[k] = dt_ev;
        if (zeno_len[k] >= ZENO_CHAIN && dt_ev <= ZENO_RATIO * zeno_first[k]) return 1;
    }
    zeno_t[k] = t_ev;
    return 0;
}
