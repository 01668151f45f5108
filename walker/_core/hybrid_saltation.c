/* Sensitivities of the hybrid integrator at an applied event (see hybrid_internal.h for the
 * split).  With jacobian=True the variational equations carry Phi = (d x / d x0) S through
 * the flow (hybrid_step.c); at every applied event Phi is multiplied by the event's
 * saltation matrix (Aizerman & Gantmacher 1958), built from the guard's gradient and the
 * reset's Jacobian (Richardson-extrapolated central differences) and the vector fields
 * before and after the event.  At the run's last event (the stride map's end) the matrix is
 * the derivative of the map to the section instead, and d t / d x0 follows.
 */
#include <math.h>

#include "hybrid_internal.h"

/* Relative step of the Richardson-extrapolated central differences at events. */
#define FD_REL_STEP 1e-3

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

/* The sensitivities' update at an applied event (see hybrid_internal.h): with M = DR +
 * w grad^T / den, den = dg/dt + grad . f-, and w = f+ - DR f- - dR/dt (the saltation matrix)
 * or, at the run's last event, w = -(DR f- + dR/dt) (the derivative of the map to the event
 * state of the section), Phi <- M Phi; d t / d x0 = -grad Phi / den. */
int64_t wk_saltation(const model_t *m, int64_t phase, int64_t next_phase, int64_t guard,
                     double t, const double *zev, const double *x_new, int finishing, double *z,
                     double *dt_dx0, double *work)
{
    const int64_t n_x = m->n_x, n_c = m->n_c;
    double *cursor = work;
#define TAKE(count) (cursor += (count), cursor - (count))
    deriv_t dv;
    dv.grad = TAKE(n_x);
    dv.DR = TAKE(n_x * n_x);
    dv.dRdt = TAKE(n_x);
    dv.gbuf = TAKE(m->n_guards);
    dv.xp = TAKE(n_x);
    dv.xn = TAKE(n_x);
    dv.imp = TAKE(m->n_impulse);
    dv.col = TAKE(n_x);
    dv.colh = TAKE(n_x);
    double *fm = TAKE(n_x), *fp = TAKE(n_x), *w = TAKE(n_x);
    double *Phi_m = TAKE(n_x * n_c), *gPhi = TAKE(n_c);
#undef TAKE
    const double dgdt = event_derivatives(m, &dv, phase, guard, t, zev);
    m->fn.rhs(phase, t, zev, m->p, fm, m->fn.ctx);
    m->fn.rhs(next_phase, t, x_new, m->p, fp, m->fn.ctx);
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
        for (int64_t c = 0; c < n_c; c++) dt_dx0[c] = -gPhi[c] / den;
    }
    return 2;
}
