/* A terrain walk with its Jacobians (wk_terrain_walk_jac, see wk_terrain.h): stride by
 * stride, the integrator's variational equations and saltation matrices, and at each
 * touchdown the terrain's terms by Richardson-extrapolated central differences of the guard
 * and the reset.  Round feet: each stride's system is augmented with two constant states,
 * the slope of the plane the stance foot rolls on (the previous step's) and the stance
 * leg's angle at landing, so that their effects on the flow (the rolling), the guard and
 * the impact are carried by the same variational equations and saltation matrices. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "wk_common.h"
#include "wk_terrain.h"


#define TERRAIN_FD_STEP 1e-3

/* One function value of the event's finite differences: the guard k and the reset's state
 * at x, with the ground T->ground as it is set. */
static void event_values(const wk_functions *f, const wk_problem *pb, int64_t phase, int64_t k,
                         const double *x, double *g, double *xn, double *imp, double *gbuf)
{
    int64_t out[3] = {0, 0, 0};
    f->guards(phase, 0.0, x, pb->p, gbuf, f->ctx);
    *g = gbuf[k];
    for (int64_t i = 0; i < pb->n_x; i++) xn[i] = x[i];
    for (int64_t i = 0; i < pb->n_impulse; i++) imp[i] = 0.0;
    f->reset(phase, k, 0.0, x, pb->p, xn, imp, out, f->ctx);
}

/* Richardson-extrapolated central difference (4 D(h/2) - D(h)) / 3 of the guard and the
 * reset along one direction: ``which`` 0 the state along ``dir`` (x + s dir), 1 the step's
 * slope, 2 its drop.  dg receives the guard's derivative, dR (n_x) the reset's. */
static void event_derivative(const wk_functions *f, wk_terrain *T, const wk_problem *pb,
                             int64_t phase, int64_t k, const double *x, int which,
                             const double *dir, double h, double *dg, double *dR, double *work)
{
    const int64_t n_x = pb->n_x;
    double *xp = work, *xn = xp + n_x, *acc = xn + n_x, *acch = acc + n_x;
    double *imp = acch + n_x, *gbuf = imp + pb->n_impulse;
    const wk_ground saved = T->ground;
    double gd[2] = {0.0, 0.0};
    for (int level = 0; level < 2; level++) {
        const double step = level == 0 ? h : 0.5 * h;
        double *col = level == 0 ? acc : acch;
        for (int64_t i = 0; i < n_x; i++) col[i] = 0.0;
        for (int si = 0; si < 2; si++) {
            const double sgn = si == 0 ? 1.0 : -1.0;
            for (int64_t i = 0; i < n_x; i++) xp[i] = x[i];
            T->ground = saved;
            if (which == 0) {
                for (int64_t i = 0; i < n_x; i++) xp[i] = x[i] + sgn * step * dir[i];
            } else {
                if (which == 1)
                    T->ground.slope = saved.slope + sgn * step;
                else
                    T->ground.drop = saved.drop + sgn * step;
                T->ground.plane = 0;
            }
            double g;
            event_values(f, pb, phase, k, xp, &g, xn, imp, gbuf);
            gd[level] += sgn * g / (2.0 * step);
            for (int64_t i = 0; i < n_x; i++) col[i] += sgn * xn[i] / (2.0 * step);
        }
    }
    T->ground = saved;
    *dg = (4.0 * gd[1] - gd[0]) / 3.0;
    for (int64_t i = 0; i < n_x; i++) dR[i] = (4.0 * acch[i] - acc[i]) / 3.0;
}

/* The terrain's two columns c (n_x, 2) row-major of the map to the post-impact state at a
 * touchdown from x (phase, guard k): c_j = dR/dtau_j - (DR f-) (dg/dtau_j) / (grad g . f-),
 * tau = (slope, drop) of the current step (autonomous guards and resets). */
static void terrain_columns(const wk_functions *f, wk_terrain *T, const wk_problem *pb,
                            int64_t phase, int64_t k, const double *x, double *c, double *work)
{
    const int64_t n_x = pb->n_x;
    double *fm = work, *Rf = fm + n_x, *Rt = Rf + n_x, *scratch = Rt + n_x;
    /* Every difference of the guard below is of the one geometric guard (plane = 0): on a
     * plane row the step's own guard may be the model's plane guard (the simplest walker's
     * phi - 2 theta), whose scale differs from the geometric foot height's, and the ratio
     * dg/dtau over grad g . f- must take both from the same function. */
    const wk_ground entry = T->ground;
    T->ground.plane = 0;
    f->rhs(phase, 0.0, x, pb->p, fm, f->ctx);
    double fmax = 0.0, xmax = 1.0;
    for (int64_t i = 0; i < n_x; i++) {
        fmax = fmax > fabs(fm[i]) ? fmax : fabs(fm[i]);
        xmax = xmax > fabs(x[i]) ? xmax : fabs(x[i]);
    }
    double gf;
    const double hf = fmax > 0.0 ? TERRAIN_FD_STEP * xmax / fmax : TERRAIN_FD_STEP;
    event_derivative(f, T, pb, phase, k, x, 0, fm, hf, &gf, Rf, scratch);
    for (int j = 0; j < 2; j++) {
        const double base = j == 0 ? T->ground.slope : T->ground.drop;
        const double h = TERRAIN_FD_STEP * (fabs(base) > 1.0 ? fabs(base) : 1.0);
        double gt;
        event_derivative(f, T, pb, phase, k, x, 1 + j, NULL, h, &gt, Rt, scratch);
        for (int64_t i = 0; i < n_x; i++) c[i * 2 + j] = Rt[i] - Rf[i] * gt / gf;
    }
    T->ground = entry;
}

/* ------------------------------------------------------------------------------------------
 * Round feet: the augmented stride (x, gamma_s, land_angle), n_x + 2 states
 * ------------------------------------------------------------------------------------------ */

typedef struct {
    wk_terrain *T;
    wk_functions f; /* the terrain functions (ctx T) */
    int64_t n;      /* the model's n_x */
    double *J;      /* (n, n) */
    double *fa, *fb;
} aug_ctx;

/* T's stance plane and landing angle from the augmented state. */
static wk_terrain *aug_set(aug_ctx *A, const double *xa)
{
    wk_terrain *T = A->T;
    T->ground.prev_slope = xa[A->n];
    T->land_angle = xa[A->n + 1];
    wk_terrain_update_plane(T);
    return T;
}

static void aug_rhs(int64_t phase, double t, const double *xa, const double *p, double *dx,
                    void *ctx)
{
    aug_ctx *A = (aug_ctx *)ctx;
    A->f.rhs(phase, t, xa, p, dx, aug_set(A, xa));
    dx[A->n] = 0.0;
    dx[A->n + 1] = 0.0;
}

static void aug_jac(int64_t phase, double t, const double *xa, const double *p, double *J,
                    void *ctx)
{
    aug_ctx *A = (aug_ctx *)ctx;
    const int64_t n = A->n, m = n + 2;
    wk_terrain *T = aug_set(A, xa);
    A->f.jac(phase, t, xa, p, A->J, T);
    for (int64_t i = 0; i < m * m; i++) J[i] = 0.0;
    for (int64_t i = 0; i < n; i++)
        for (int64_t j = 0; j < n; j++) J[i * m + j] = A->J[i * n + j];
    /* d f / d gamma_s: Richardson-extrapolated central differences of the rolling rhs */
    const double base = xa[n], h = TERRAIN_FD_STEP * (fabs(base) > 1.0 ? fabs(base) : 1.0);
    double d[2][64];
    for (int level = 0; level < 2; level++) {
        const double step = level == 0 ? h : 0.5 * h;
        T->ground.prev_slope = base + step;
        A->f.rhs(phase, t, xa, p, A->fa, T);
        T->ground.prev_slope = base - step;
        A->f.rhs(phase, t, xa, p, A->fb, T);
        for (int64_t i = 0; i < n && i < 64; i++)
            d[level][i] = (A->fa[i] - A->fb[i]) / (2.0 * step);
    }
    aug_set(A, xa);
    for (int64_t i = 0; i < n && i < 64; i++) J[i * m + n] = (4.0 * d[1][i] - d[0][i]) / 3.0;
}

static void aug_guards(int64_t phase, double t, const double *xa, const double *p, double *g,
                       void *ctx)
{
    aug_ctx *A = (aug_ctx *)ctx;
    A->f.guards(phase, t, xa, p, g, aug_set(A, xa));
}

static void aug_reset(int64_t phase, int64_t k, double t, const double *xa, const double *p,
                      double *xa_new, double *impulse, int64_t *out, void *ctx)
{
    aug_ctx *A = (aug_ctx *)ctx;
    A->f.reset(phase, k, t, xa, p, xa_new, impulse, out, aug_set(A, xa));
    xa_new[A->n] = xa[A->n];
    xa_new[A->n + 1] = xa[A->n + 1];
}

static wk_functions aug_functions(aug_ctx *A)
{
    wk_functions g = A->f;
    g.rhs = aug_rhs;
    g.jac = aug_jac;
    g.guards = aug_guards;
    g.reset = aug_reset;
    g.ctx = A;
    g.rhs_jac = NULL;
    g.on_stride = NULL;
    return g;
}

int wk_terrain_walk_jac(const wk_functions *fn, const wk_terrain_entry *te,
                        const wk_problem *tmpl, const wk_section *sec, const wk_terrain_start *st,
                        const double *steps, int64_t n_steps, int64_t *status, int64_t *strides,
                        double *t, double *x, double *z_out, double *jz, double *tjac)
{
    const int64_t n_x = tmpl->n_x, n_z = sec->n_z, n_t = 2 * n_steps;
    const int64_t n_0 = st->from_state ? n_x : n_z; /* the start's coordinates */
    wk_terrain T;
    wk_terrain_init(&T, te, tmpl, steps, n_steps, st->previous);
    int64_t phase = 0;
    *strides = 0;
    *t = 0.0;
    wk_terrain_fill_nan(z_out, n_z);
    for (int64_t i = 0; i < n_z * n_0; i++) jz[i] = NAN;
    for (int64_t i = 0; i < n_z * n_t; i++) tjac[i] = NAN;
    *status = wk_terrain_walk_start(tmpl, sec, st, x, &phase);
    if (*status != 0) return WK_OK;
    const wk_functions f = wk_terrain_functions(fn, te, &T, tmpl->p, x);
    /* round feet: the augmented stride (n_a = n_x + 2 states, n_x + 1 seed columns) */
    const int rolling = T.rolling && n_x <= 64;
    const int64_t n_a = rolling ? n_x + 2 : n_x;

    const size_t n_work =
        (size_t)(n_x * n_0 * 3 + n_x * n_t * 2 + n_a * n_a * 2 + n_a * 3 + n_a * 2 + 8 * n_a +
                 2 * tmpl->n_impulse + tmpl->n_guards + n_x * n_x + 2 * n_x);
    double *work = malloc(n_work * sizeof(double));
    if (work == NULL) return WK_ERR_NOMEM;
    double *Jx = work, *Jtmp = Jx + n_x * n_0, *seed_buf = Jtmp + n_x * n_0;
    double *Tx = seed_buf + n_x * n_0, *Ttmp = Tx + n_x * n_t;
    double *S = Ttmp + n_x * n_t, *M = S + n_a * n_a;
    double *x0 = M + n_a * n_a, *xm = x0 + n_a, *c = xm + n_a;
    double *fd = c + 2 * n_a;
    double *aug_J = fd + 8 * n_a + 2 * tmpl->n_impulse + tmpl->n_guards;
    aug_ctx A = {&T, f, n_x, aug_J, aug_J + n_x * n_x, aug_J + n_x * n_x + n_x};
    const wk_functions fa = rolling ? aug_functions(&A) : f;
    for (int64_t i = 0; i < n_x * n_t; i++) Tx[i] = 0.0;
    /* the first stride's seed: the lift's Jacobian from a section point, else the identity */
    const double *seed0 =
        st->from_state ? NULL : wk_section_seed(sec, n_x, tmpl->p, st->start, seed_buf);
    memcpy(x0, x, (size_t)n_x * sizeof(double));

    int rc = WK_OK;
    double t_sum = 0.0;
    for (int64_t k = 0; k < n_steps; k++) {
        wk_terrain_set_step(&T, k);
        T.land_angle = x0[0];
        /* the seed: (n_a, m); with round feet the stance plane's slope (column n_x) and the
         * landing angle (row n_x + 1: the start's stance angle x0[0]) */
        int64_t m;
        const double *seed;
        if (k == 0 && seed0 != NULL) {
            m = n_z;
            seed = seed0;
        } else {
            m = n_x;
            seed = NULL;
        }
        if (rolling) {
            const int64_t m0 = m;
            m = m0 + 1;
            for (int64_t i = 0; i < n_a * m; i++) S[i] = 0.0;
            for (int64_t r = 0; r < n_x; r++)
                for (int64_t j = 0; j < m0; j++)
                    S[r * m + j] = seed != NULL ? seed[r * m0 + j] : (r == j ? 1.0 : 0.0);
            S[n_x * m + m0] = 1.0;
            for (int64_t j = 0; j < m0; j++) S[(n_x + 1) * m + j] = S[0 * m + j];
            seed = S;
            x0[n_x] = T.ground.prev_slope;
            x0[n_x + 1] = x0[0];
        }
        wk_problem pb = *tmpl;
        pb.n_x = n_a;
        pb.x0 = x0;
        pb.phase0 = phase;
        pb.t0 = 0.0;
        pb.t_max = sec->t_max;
        pb.n_strides = 1;
        pb.max_steps = sec->max_steps;
        pb.output = WK_OUTPUT_EVENTS;
        pb.want_jac = 1;
        pb.jac_seed = seed;
        pb.n_seed = seed != NULL ? m : 0;
        pb.sample_times = NULL;
        pb.n_samples = 0;
        wk_result res;
        rc = wk_hybrid_solve(&fa, &pb, &res);
        if (rc != WK_OK) {
            wk_result_free(&res);
            break;
        }
        t_sum += res.t;
        memcpy(x, res.x, (size_t)n_x * sizeof(double));
        *status = res.status;
        if (res.status != 0 || res.counters[WK_N_LOG] < 1) {
            if (res.status == 0) *status = WK_NO_EVENT; /* cannot happen: a stride logs */
            wk_result_free(&res);
            break;
        }
        const int64_t e = res.counters[WK_N_LOG] - 1;
        memcpy(xm, res.ev_x_pre + e * n_a, (size_t)n_a * sizeof(double));
        const int64_t ev_phase = res.ev_phase_before[e], ev_guard = res.ev_guard[e];
        /* M (n_x, m) from the first n_x rows of the run's (n_a, m) sensitivities */
        for (int64_t r = 0; r < n_x; r++)
            for (int64_t j = 0; j < m; j++) M[r * m + j] = res.jac[r * m + j];
        if (k == 0) {
            for (int64_t r = 0; r < n_x; r++)
                for (int64_t j = 0; j < n_0; j++) Jx[r * n_0 + j] = M[r * m + j];
        } else {
            /* rows of M: its first n_x columns the state, column n_x (round feet) the
             * previous step's slope */
            for (int64_t r = 0; r < n_x; r++) {
                for (int64_t j = 0; j < n_0; j++) {
                    double acc = 0.0;
                    for (int64_t q = 0; q < n_x; q++) acc += M[r * m + q] * Jx[q * n_0 + j];
                    Jtmp[r * n_0 + j] = acc;
                }
                for (int64_t j = 0; j < n_t; j++) {
                    double acc = 0.0;
                    for (int64_t q = 0; q < n_x; q++) acc += M[r * m + q] * Tx[q * n_t + j];
                    Ttmp[r * n_t + j] = acc;
                }
                if (rolling) Ttmp[r * n_t + 2 * (k - 1)] += M[r * m + n_x];
            }
            memcpy(Jx, Jtmp, (size_t)(n_x * n_0) * sizeof(double));
            memcpy(Tx, Ttmp, (size_t)(n_x * n_t) * sizeof(double));
        }
        phase = res.phase;
        wk_result_free(&res);
        wk_terrain_set_step(&T, k); /* the run's on_stride moved it on */
        T.land_angle = x0[0];
        terrain_columns(&fa, &T, &pb, ev_phase, ev_guard, xm, c, fd);
        for (int64_t i = 0; i < n_x; i++) {
            Tx[i * n_t + 2 * k] = c[2 * i];
            Tx[i * n_t + 2 * k + 1] = c[2 * i + 1];
        }
        *strides = k + 1;
        memcpy(x0, x, (size_t)n_x * sizeof(double));
    }
    *t = t_sum;
    if (rc == WK_OK && *status == 0) {
        for (int64_t i = 0; i < n_z; i++) {
            const int64_t r = sec->proj[i];
            z_out[i] = x[r];
            for (int64_t j = 0; j < n_0; j++) jz[i * n_0 + j] = Jx[r * n_0 + j];
            for (int64_t j = 0; j < n_t; j++) tjac[i * n_t + j] = Tx[r * n_t + j];
        }
    }
    free(work);
    return rc;
}
