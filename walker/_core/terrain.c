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
    {WK_ENTRY_NAME_rimless_wheel, wk_model_rimless_wheel_guards, WK_RIMLESS_WHEEL_P_SLOPE,
     wk_terrain_rimless_wheel_guards, wk_terrain_rimless_wheel_reset, 0, -1, 0},
    {WK_ENTRY_NAME_simplest, wk_model_simplest_guards, WK_SIMPLEST_P_SLOPE,
     wk_terrain_simplest_guards, wk_terrain_simplest_reset, 0, -1, 0},
    {WK_ENTRY_NAME_compass, wk_model_compass_guards, WK_COMPASS_P_SLOPE,
     wk_terrain_compass_guards, wk_terrain_compass_reset, 0, WK_COMPASS_P_FOOT_RADIUS,
     WK_COMPASS_N_P},
    {WK_ENTRY_NAME_compass_plain, wk_model_compass_plain_guards, WK_COMPASS_P_SLOPE,
     wk_terrain_compass_plain_guards, wk_terrain_compass_plain_reset, 0, -1, 0},
#define KNEED_ENTRY(name)                                                                    \
    {WK_ENTRY_NAME_##name, wk_model_##name##_guards, WK_KNEED_P_SLOPE,                      \
     wk_terrain_##name##_guards, wk_terrain_##name##_reset, 0, WK_KNEED_P_FOOT_RADIUS,     \
     WK_KNEED_N_P}
    KNEED_ENTRY(kneed),
    KNEED_ENTRY(kneed_plain),
    KNEED_ENTRY(kneed_ignore_scuff),
    KNEED_ENTRY(kneed_plain_ignore_scuff),
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
    if (T->extend != NULL && index >= T->n_ready && index < T->n_steps)
        T->n_ready = T->extend(T->extend_ctx, index + 1);
    const int64_t prev = index - 1;
    const int has = index >= 0 && index < T->n_steps;
    const int has_prev = prev >= 0 && prev < T->n_steps;
    T->ground.slope = has ? T->steps[2 * index] : T->scene_slope;
    T->ground.drop = has ? T->steps[2 * index + 1] : 0.0;
    T->ground.prev_slope = has_prev ? T->steps[2 * prev] : T->scene_slope;
    T->ground.prev_drop = has_prev ? T->steps[2 * prev + 1] : 0.0;
    if (prev == -1 && T->previous != NULL) {
        T->ground.prev_slope = T->previous[0];
        T->ground.prev_drop = T->previous[1];
    }
    wk_terrain_update_plane(T);
}

void wk_terrain_on_stride(void *ctx, int64_t n_done, const double *x)
{
    wk_terrain *T = (wk_terrain *)ctx;
    wk_terrain_set_step(T, n_done);
    T->land_angle = x[0];
}

const double *wk_terrain_stance_params(wk_terrain *T, const double *p)
{
    if (!T->rolling) return p;
    T->p_buf[T->slope_index] = T->ground.prev_slope; /* the rest copied at the start */
    return T->p_buf;
}

double wk_terrain_round_height(const wk_terrain *T, double centres, double q_stance, double R)
{
    const double d = T->ground.slope - T->ground.prev_slope;
    return centres + R * (T->land_angle - q_stance) * sin(d) + R * (cos(d) - 1.0) +
           T->ground.drop * cos(T->ground.slope);
}

int64_t wk_terrain_heel_strike_round(const wk_floating_base *B, const int *swap, int n_c,
                                     const double *x, const double *p, const wk_terrain *T,
                                     double *x_new, double *impulse)
{
    enum { NF = WK_FLOATING_BASE_MAX };
    double p_n[WK_TERRAIN_MAX_P], p_s[WK_TERRAIN_MAX_P];
    double pts[WK_POINTS_MAX * 2], hip_J[2 * NF], qf[NF], qdf[NF], qdf_plus[NF];
    double M[NF * NF], Jsw[2 * NF], Jst[2 * NF], lam[2];
    const int n = B->n;
    if (n + 2 > NF || B->n_points > WK_POINTS_MAX || T->n_params > WK_TERRAIN_MAX_P)
        return WK_LINEAR_SOLVE_FAILED;
    for (int64_t i = 0; i < T->n_params; i++) p_n[i] = p_s[i] = p[i];
    const double gam = T->ground.slope, gam_s = T->ground.prev_slope;
    p_n[T->slope_index] = gam;
    p_s[T->slope_index] = gam_s;
    /* the hip's velocity from the stance foot rolling on its plane; the swing foot's
     * contact on the step's plane, the trailing foot's on its own */
    B->points(x, p_s, pts);
    B->hip_jac(x, p_s, hip_J);
    wk_floating_base_state(x, x + n_c, pts + 2 * B->hip_row, hip_J, qf, qdf, n);
    B->ext_mass_matrix(qf, p_n, M);
    B->ext_swing_contact_jac(qf, p_n, Jsw);
    B->ext_stance_contact_jac(qf, p_s, Jst);
    if (!wk_impact(M, Jsw, qdf, qdf_plus, lam, n + 2, 2)) return WK_LINEAR_SOLVE_FAILED;
    impulse[0] = lam[0] * cos(gam) - lam[1] * sin(gam);
    impulse[1] = lam[0] * sin(gam) + lam[1] * cos(gam);
    double v0 = 0.0, v1 = 0.0;
    for (int j = 0; j < n + 2; j++) {
        v0 += Jst[0 * (n + 2) + j] * qdf_plus[j];
        v1 += Jst[1 * (n + 2) + j] * qdf_plus[j];
    }
    const double lift = v0 * sin(gam_s) + v1 * cos(gam_s);
    wk_swap_legs(swap, n_c, x, qdf_plus, x_new);
    if (!(impulse[1] > 0.0) || !(lift > 0.0)) return WK_NONPHYSICAL_IMPACT;
    return 0;
}

/* The model's rhs and jac with the parameters of the plane the stance foot rolls on. */
static void rolling_rhs(int64_t phase, double t, const double *x, const double *p, double *dx,
                        void *ctx)
{
    wk_terrain *T = (wk_terrain *)ctx;
    T->rhs(phase, t, x, wk_terrain_stance_params(T, p), dx, T->inner);
}

static void rolling_jac(int64_t phase, double t, const double *x, const double *p, double *J,
                        void *ctx)
{
    wk_terrain *T = (wk_terrain *)ctx;
    T->jac(phase, t, x, wk_terrain_stance_params(T, p), J, T->inner);
}

void wk_terrain_init(wk_terrain *T, const wk_terrain_entry *te, const wk_problem *tmpl,
                         const double *steps, int64_t n_steps, const double *previous)
{
    memset(T, 0, sizeof *T);
    T->steps = steps;
    T->n_steps = n_steps;
    T->scene_slope = tmpl->p[te->slope_index];
    T->previous = previous;
    wk_terrain_set_step(T, 0);
}

/* wk_section_start's checks for a start at a full state x0 (its section point x0[proj]). */
static int64_t state_start(const wk_problem *tmpl, const wk_section *sec, const double *x0,
                           int64_t *phase0)
{
    const double psi = x0[sec->proj[0]] + sec->offset;
    if (!(fabs(psi) < sec->fall_angle)) return psi < 0.0 ? WK_FELL_FORWARD : WK_FELL_BACKWARD;
    for (int64_t i = 0; i < sec->n_q; i++)
        if (fabs(x0[i]) > sec->wound) return WK_OUTSIDE_WALKING_REGION;
    double out[4] = {0.0, 0.0, 0.0, 0.0};
    if (sec->energy != NULL) {
        sec->energy(x0, tmpl->p, out, NULL);
        if (!(out[0] <= sec->kinetic_limit)) return 15;
    }
    *phase0 = 0;
    if (sec->start_phase != NULL) {
        out[0] = 0.0;
        sec->start_phase(x0, tmpl->p, out, NULL);
        *phase0 = (int64_t)out[0];
        if (*phase0 < 0) return WK_LINEAR_SOLVE_FAILED;
    }
    return 0;
}

int64_t wk_terrain_walk_start(const wk_problem *tmpl, const wk_section *sec,
                          const wk_terrain_start *st, double *x, int64_t *phase0)
{
    if (!st->from_state) return wk_section_start(tmpl, sec, st->start, x, phase0);
    memcpy(x, st->start, (size_t)tmpl->n_x * sizeof(double));
    return state_start(tmpl, sec, x, phase0);
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
                                  wk_terrain *T, const double *p, const double *x0)
{
    wk_functions f = *fn;
    T->inner = fn->ctx;
    T->rhs = fn->rhs;
    T->jac = fn->jac;
    T->land_angle = x0[0];
    T->slope_index = te->slope_index;
    T->n_params = te->n_params;
    T->rolling = te->radius_index >= 0 && p[te->radius_index] != 0.0 &&
                 te->n_params <= WK_TERRAIN_MAX_P;
    if (T->rolling) {
        for (int64_t i = 0; i < te->n_params; i++) T->p_buf[i] = p[i];
        f.rhs = rolling_rhs;
        f.jac = fn->jac != NULL ? rolling_jac : NULL;
        f.rhs_jac = NULL;
    }
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

void wk_terrain_fill_nan(double *v, int64_t n)
{
    for (int64_t i = 0; i < n; i++) v[i] = NAN;
}

int wk_terrain_walk(const wk_functions *fn, const wk_terrain_entry *te, const wk_problem *tmpl,
                    const wk_section *sec, const wk_terrain_start *st, const double *steps,
                    int64_t n_steps, int64_t *status, int64_t *strides, double *t, double *x,
                    double *z_out)
{
    return wk_terrain_walk_extended(fn, te, tmpl, sec, st, steps, n_steps, NULL, NULL, status,
                                    strides, t, x, z_out);
}

int wk_terrain_walk_extended(const wk_functions *fn, const wk_terrain_entry *te,
                             const wk_problem *tmpl, const wk_section *sec,
                             const wk_terrain_start *st, const double *steps, int64_t n_steps,
                             int64_t (*extend)(void *, int64_t), void *extend_ctx, int64_t *status,
                             int64_t *strides, double *t, double *x, double *z_out)
{
    const int64_t n_x = tmpl->n_x;
    wk_terrain T;
    wk_terrain_init(&T, te, tmpl, steps, n_steps, st->previous);
    if (extend != NULL) {
        T.extend = extend;
        T.extend_ctx = extend_ctx;
        wk_terrain_set_step(&T, 0);
    }
    int64_t phase0 = 0;
    *strides = 0;
    *t = 0.0;
    wk_terrain_fill_nan(z_out, sec->n_z);
    *status = wk_terrain_walk_start(tmpl, sec, st, x, &phase0);
    if (*status != 0) return WK_OK;
    const wk_functions f = wk_terrain_functions(fn, te, &T, tmpl->p, x);
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
        if (wk_interrupt) {
            /* a signal arrived (hybrid.h): the runs not walked yet end here */
            for (int64_t j = i; j < m; j++) {
                status[j] = WK_INTERRUPTED;
                strides[j] = 0;
            }
            break;
        }
        double t;
        const wk_terrain_start st = {z0 + i * n_z, 0, NULL};
        rc = wk_terrain_walk(fn, te, tmpl, sec, &st, steps + i * n_steps * 2, n_steps,
                             status + i, strides + i, &t, buf, buf + n_x);
    }
    free(buf);
    return rc;
}
