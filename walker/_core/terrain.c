/* Terrain defined per step: the registry of the models' terrain functions, the step
 * bookkeeping the integrator calls after each stride, and the terrain runs (one walk, one
 * walk with its Jacobians, many walks).  See wk_terrain.h. */
#include "wk_terrain.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "wk_common.h"
#include "wk_models.h"
#include "wk_rimless.h"

/* ------------------------------------------------------------------------------------------
 * Registry
 * ------------------------------------------------------------------------------------------ */

static const wk_terrain_entry ENTRIES[] = {
    {"rimless_wheel", wk_model_rimless_wheel_guards, WK_RIMLESS_WHEEL_P_SLOPE,
     wk_terrain_rimless_wheel_guards, wk_terrain_rimless_wheel_reset},
    {"simplest", wk_model_simplest_guards, WK_SIMPLEST_P_SLOPE, wk_terrain_simplest_guards,
     wk_terrain_simplest_reset},
    {"compass", wk_model_compass_guards, WK_COMPASS_P_SLOPE, wk_terrain_compass_guards,
     wk_terrain_compass_reset},
    {"compass/plain", wk_model_compass_plain_guards, WK_COMPASS_P_SLOPE,
     wk_terrain_compass_plain_guards, wk_terrain_compass_plain_reset},
#define KNEED_ENTRY(label, name)                                                             \
    {label, wk_model_##name##_guards, WK_KNEED_P_SLOPE, wk_terrain_##name##_guards,           \
     wk_terrain_##name##_reset}
    KNEED_ENTRY("kneed", kneed),
    KNEED_ENTRY("kneed/plain", kneed_plain),
    KNEED_ENTRY("kneed/ignore_scuff", kneed_ignore_scuff),
    KNEED_ENTRY("kneed/plain/ignore_scuff", kneed_plain_ignore_scuff),
#undef KNEED_ENTRY
};

static const wk_terrain_entry *const MORE[] = {
    &wk_terrain_entry_compass_coulomb,
    &wk_terrain_entry_kneed_coulomb,
    &wk_terrain_entry_three_link,
    &wk_terrain_entry_five_link,
};

const wk_terrain_entry *wk_terrain_find(wk_guards_fn guards)
{
    if (guards == NULL) return NULL;
    for (size_t i = 0; i < sizeof ENTRIES / sizeof ENTRIES[0]; i++)
        if (ENTRIES[i].guards == guards) return &ENTRIES[i];
    for (size_t i = 0; i < sizeof MORE / sizeof MORE[0]; i++)
        if (MORE[i]->guards == guards) return MORE[i];
    return NULL;
}

/* ------------------------------------------------------------------------------------------
 * Steps
 * ------------------------------------------------------------------------------------------ */

void wk_terrain_update_plane(wk_terrain *T)
{
    const wk_ground *G = &T->ground;
    T->ground.plane = G->slope == T->scene_slope && G->drop == 0.0 &&
                      G->prev_slope == T->scene_slope;
}

void wk_terrain_set_step(wk_terrain *T, int64_t index)
{
    T->index = index;
    const int64_t prev = index - 1;
    const int has = index >= 0 && index < T->n_steps;
    const int has_prev = prev >= 0 && prev < T->n_steps;
    T->ground.slope = has ? T->steps[2 * index] : T->scene_slope;
    T->ground.drop = has ? T->steps[2 * index + 1] : 0.0;
    T->ground.prev_slope = has_prev ? T->steps[2 * prev] : T->scene_slope;
    T->ground.prev_drop = has_prev ? T->steps[2 * prev + 1] : 0.0;
    wk_terrain_update_plane(T);
}

void wk_terrain_on_stride(void *ctx, int64_t n_done)
{
    wk_terrain_set_step((wk_terrain *)ctx, n_done);
}

static void terrain_init(wk_terrain *T, const wk_terrain_entry *te, const wk_problem *tmpl,
                         const double *steps, int64_t n_steps)
{
    memset(T, 0, sizeof *T);
    T->steps = steps;
    T->n_steps = n_steps;
    T->scene_slope = tmpl->p[te->slope_index];
    wk_terrain_set_step(T, 0);
}

void wk_terrain_rhs(int64_t phase, double t, const double *x, const double *p, double *dx,
                    void *ctx)
{
    const wk_terrain *T = (const wk_terrain *)ctx;
    T->rhs(phase, t, x, p, dx, T->inner);
}

void wk_terrain_jac(int64_t phase, double t, const double *x, const double *p, double *J,
                    void *ctx)
{
    const wk_terrain *T = (const wk_terrain *)ctx;
    T->jac(phase, t, x, p, J, T->inner);
}

wk_functions wk_terrain_functions(const wk_functions *fn, const wk_terrain_entry *te,
                                  wk_terrain *T)
{
    wk_functions f = *fn;
    T->inner = fn->ctx;
    T->rhs = fn->rhs;
    T->jac = fn->jac;
    f.guards = te->terrain_guards;
    f.reset = te->terrain_reset;
    f.ctx = T;
    f.on_stride = wk_terrain_on_stride;
    if (te->own_ctx) {
        f.rhs = wk_terrain_rhs;
        f.jac = fn->jac != NULL ? wk_terrain_jac : NULL;
        f.rhs_jac = NULL;
    }
    return f;
}

void wk_terrain_rotate_impulse(double *impulse, double from, double to)
{
    const double wx = impulse[0] * cos(from) + impulse[1] * sin(from);
    const double wy = -impulse[0] * sin(from) + impulse[1] * cos(from);
    impulse[0] = wx * cos(to) - wy * sin(to);
    impulse[1] = wx * sin(to) + wy * cos(to);
}

/* ------------------------------------------------------------------------------------------
 * Shared model glue
 * ------------------------------------------------------------------------------------------ */

int64_t wk_terrain_heel_strike(const wk_floating_base *B, const int *swap, int n_c,
                               const double *x, const double *p, const wk_ground *G,
                               double *x_new, double *impulse)
{
    double qdf_plus[WK_FLOATING_BASE_MAX], lift;
    /* the lift-off is measured on the trailing foot's plane, and the impulse first too */
    if (!wk_floating_base_heel_strike(B, x, x + n_c, p, G->prev_slope, qdf_plus, impulse, &lift))
        return WK_LINEAR_SOLVE_FAILED;
    wk_swap_legs(swap, n_c, x, qdf_plus, x_new);
    wk_terrain_rotate_impulse(impulse, G->prev_slope, G->slope);
    if (!(impulse[1] > 0.0) || !(lift > 0.0)) return WK_NONPHYSICAL_IMPACT;
    return 0;
}

/* ------------------------------------------------------------------------------------------
 * One walk
 * ------------------------------------------------------------------------------------------ */

static void fill_nan(double *v, int64_t n)
{
    for (int64_t i = 0; i < n; i++) v[i] = NAN;
}

int wk_terrain_walk(const wk_functions *fn, const wk_terrain_entry *te, const wk_problem *tmpl,
                    const wk_section *sec, const double *z, const double *steps, int64_t n_steps,
                    int64_t *status, int64_t *strides, double *t, double *x, double *z_out)
{
    const int64_t n_x = tmpl->n_x;
    wk_terrain T;
    terrain_init(&T, te, tmpl, steps, n_steps);
    const wk_functions f = wk_terrain_functions(fn, te, &T);
    int64_t phase0 = 0;
    *strides = 0;
    *t = 0.0;
    fill_nan(z_out, sec->n_z);
    *status = wk_section_start(tmpl, sec, z, x, &phase0);
    if (*status != 0) return WK_OK;
    double *x0 = malloc((size_t)n_x * sizeof(double));
    if (x0 == NULL) return WK_ERR_NOMEM;
    memcpy(x0, x, (size_t)n_x * sizeof(double));
    wk_result res;
    const int rc = wk_section_run(&f, tmpl, sec, n_steps, NULL, x0, phase0, &res);
    free(x0);
    if (rc == WK_OK) {
        *status = res.status;
        *strides = res.counters[WK_N_STRIDES];
        *t = res.t;
        memcpy(x, res.x, (size_t)n_x * sizeof(double));
        if (res.status == 0)
            for (int64_t i = 0; i < sec->n_z; i++) z_out[i] = res.x[sec->proj[i]];
    }
    wk_result_free(&res);
    return rc;
}

/* ------------------------------------------------------------------------------------------
 * One walk with its Jacobians
 * ------------------------------------------------------------------------------------------ */

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
}

/* out (r, m) = A (r, n) B (n, m), row-major; out must not alias. */
static void matmul(const double *A, const double *B, int64_t r, int64_t n, int64_t m,
                   double *out)
{
    for (int64_t i = 0; i < r; i++)
        for (int64_t j = 0; j < m; j++) {
            double s = 0.0;
            for (int64_t q = 0; q < n; q++) s += A[i * n + q] * B[q * m + j];
            out[i * m + j] = s;
        }
}

int wk_terrain_walk_jac(const wk_functions *fn, const wk_terrain_entry *te,
                        const wk_problem *tmpl, const wk_section *sec, const double *z,
                        const double *steps, int64_t n_steps, int64_t *status, int64_t *strides,
                        double *t, double *x, double *z_out, double *jz, double *tjac)
{
    const int64_t n_x = tmpl->n_x, n_z = sec->n_z, n_t = 2 * n_steps;
    wk_terrain T;
    terrain_init(&T, te, tmpl, steps, n_steps);
    const wk_functions f = wk_terrain_functions(fn, te, &T);
    int64_t phase = 0;
    *strides = 0;
    *t = 0.0;
    fill_nan(z_out, n_z);
    for (int64_t i = 0; i < n_z * n_z; i++) jz[i] = NAN;
    for (int64_t i = 0; i < n_z * n_t; i++) tjac[i] = NAN;
    *status = wk_section_start(tmpl, sec, z, x, &phase);
    if (*status != 0) return WK_OK;

    const size_t n_work = (size_t)(n_x * n_z * 3 + n_x * n_t * 2 + n_x * n_x * 2 + n_x * 3 +
                                   n_x * 2 + 8 * n_x + 2 * tmpl->n_impulse + tmpl->n_guards);
    double *work = malloc(n_work * sizeof(double));
    if (work == NULL) return WK_ERR_NOMEM;
    double *Jx = work, *Jtmp = Jx + n_x * n_z, *seed_buf = Jtmp + n_x * n_z;
    double *Tx = seed_buf + n_x * n_z, *Ttmp = Tx + n_x * n_t;
    double *eye = Ttmp + n_x * n_t, *M = eye + n_x * n_x;
    double *x0 = M + n_x * n_x, *xm = x0 + n_x, *c = xm + n_x;
    double *fd = c + 2 * n_x;
    for (int64_t i = 0; i < n_x * n_t; i++) Tx[i] = 0.0;
    for (int64_t i = 0; i < n_x * n_x; i++) eye[i] = (i / n_x == i % n_x) ? 1.0 : 0.0;
    const double *seed0 = wk_section_seed(sec, n_x, tmpl->p, z, seed_buf);
    memcpy(x0, x, (size_t)n_x * sizeof(double));

    int rc = WK_OK;
    double t_sum = 0.0;
    for (int64_t k = 0; k < n_steps; k++) {
        wk_terrain_set_step(&T, k);
        wk_problem pb = *tmpl;
        pb.x0 = x0;
        pb.phase0 = phase;
        pb.t0 = 0.0;
        pb.t_max = sec->t_max;
        pb.n_strides = 1;
        pb.max_steps = sec->max_steps;
        pb.output = WK_OUTPUT_EVENTS;
        pb.want_jac = 1;
        pb.jac_seed = k == 0 ? seed0 : NULL;
        pb.n_seed = k == 0 ? n_z : 0;
        pb.sample_times = NULL;
        pb.n_samples = 0;
        wk_result res;
        rc = wk_hybrid_solve(&f, &pb, &res);
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
        memcpy(xm, res.ev_x_pre + e * n_x, (size_t)n_x * sizeof(double));
        const int64_t ev_phase = res.ev_phase_before[e], ev_guard = res.ev_guard[e];
        if (k == 0) {
            memcpy(Jx, res.jac, (size_t)(n_x * n_z) * sizeof(double));
        } else {
            memcpy(M, res.jac, (size_t)(n_x * n_x) * sizeof(double));
            matmul(M, Jx, n_x, n_x, n_z, Jtmp);
            memcpy(Jx, Jtmp, (size_t)(n_x * n_z) * sizeof(double));
            matmul(M, Tx, n_x, n_x, n_t, Ttmp);
            memcpy(Tx, Ttmp, (size_t)(n_x * n_t) * sizeof(double));
        }
        phase = res.phase;
        wk_result_free(&res);
        wk_terrain_set_step(&T, k); /* the run's on_stride moved it on */
        terrain_columns(&f, &T, &pb, ev_phase, ev_guard, xm, c, fd);
        for (int64_t i = 0; i < n_x; i++) {
            Tx[i * n_t + 2 * k] = c[2 * i];
            Tx[i * n_t + 2 * k + 1] = c[2 * i + 1];
        }
        *strides = k + 1;
        memcpy(x0, x, (size_t)n_x * sizeof(double));
    }
    (void)eye;
    *t = t_sum;
    if (rc == WK_OK && *status == 0) {
        for (int64_t i = 0; i < n_z; i++) {
            const int64_t r = sec->proj[i];
            z_out[i] = x[r];
            for (int64_t j = 0; j < n_z; j++) jz[i * n_z + j] = Jx[r * n_z + j];
            for (int64_t j = 0; j < n_t; j++) tjac[i * n_t + j] = Tx[r * n_t + j];
        }
    }
    free(work);
    return rc;
}

/* ------------------------------------------------------------------------------------------
 * Many walks
 * ------------------------------------------------------------------------------------------ */

int wk_terrain_ensemble(const wk_functions *fn, const wk_terrain_entry *te,
                        const wk_problem *tmpl, const wk_section *sec, const double *z0,
                        int64_t m, const double *steps, int64_t n_steps, int64_t *status,
                        int64_t *strides)
{
    const int64_t n_x = tmpl->n_x, n_z = sec->n_z;
    double *buf = malloc((size_t)(n_x + n_z) * sizeof(double));
    if (buf == NULL) return WK_ERR_NOMEM;
    int rc = WK_OK;
    for (int64_t i = 0; i < m && rc == WK_OK; i++) {
        double t;
        rc = wk_terrain_walk(fn, te, tmpl, sec, z0 + i * n_z, steps + i * n_steps * 2, n_steps,
                             status + i, strides + i, &t, buf, buf + n_x);
    }
    free(buf);
    return rc;
}
