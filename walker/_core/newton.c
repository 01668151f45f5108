/* The gait search, written once: see newton.h.  The compiled stride map's evaluations and
 * walking region follow walker.simulation.stride.StrideMap and walker/simulation/region.py. */
#include "newton.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "wk_common.h"


typedef wk_search_eval evaluation;

typedef struct {
    wk_search_map *map;
    const wk_search_settings *set;
    int64_t n_z, n_evals;
} search;

/* A walker's stride map in C (wk_search_compiled). */
typedef struct {
    wk_search_map base;
    const wk_functions *fn;
    const wk_problem *tmpl;
    const wk_section *sec;
    const wk_region *reg;
    const wk_search_settings *set;
    double *x;    /* (n_x,) scratch: a lifted state */
    double *seed; /* (n_x, n_z) scratch: the seed of a lift that is not affine */
} compiled_map;

/* Return codes of the evaluator besides 0 (and WK_EVAL_DECLINED, WK_EVAL_ERROR). */
#define OUT_OF_BUDGET 1

static double max_abs(const double *v, int64_t n)
{
    double m = fabs(v[0]);
    for (int64_t i = 1; i < n; i++)
        if (fabs(v[i]) > m) m = fabs(v[i]);
    return m;
}

/* max |v_i| / scale_i, NaN when any term is (numpy's max). */
static double max_abs_scaled(const double *v, const double *scale, int64_t n)
{
    double m = fabs(v[0]) / scale[0];
    for (int64_t i = 0; i < n; i++) {
        const double a = fabs(v[i]) / scale[i];
        if (isnan(a)) return a;
        if (a > m) m = a;
    }
    return m;
}

static double norm2(const double *v, int64_t n)
{
    double s = 0.0;
    for (int64_t i = 0; i < n; i++) s += v[i] * v[i];
    return sqrt(s);
}

static int all_finite(const double *v, int64_t n)
{
    for (int64_t i = 0; i < n; i++)
        if (!isfinite(v[i])) return 0;
    return 1;
}

/* WalkingRegion.outside: WK_INSIDE, or why z lies outside (value, index for the message). */
static int compiled_outside(wk_search_map *m, const double *z, double *value, int64_t *index)
{
    compiled_map *s = (compiled_map *)m;
    const wk_region *reg = s->reg;
    if (reg->has_stance) {
        const double psi = z[0] + reg->stance_offset;
        if (!(fabs(psi) < reg->fall_angle)) {
            *value = psi;
            return WK_OUT_FALL;
        }
    }
    double *x = s->x;
    wk_section_lift(s->sec, m->n_x, s->tmpl->p, z, x);
    if (!all_finite(x, m->n_x)) return WK_OUT_NONFINITE;
    int64_t at = 0;
    double most = fabs(x[0]);
    for (int64_t i = 1; i < reg->n_q; i++)
        if (fabs(x[i]) > most) {
            most = fabs(x[i]);
            at = i;
        }
    if (most > reg->wound_limit) {
        *value = x[at];
        *index = at;
        return WK_OUT_WOUND;
    }
    double out[4] = {0.0, 0.0, 0.0, 0.0};
    reg->energy(x, s->tmpl->p, out, s->fn->ctx);
    if (!(out[0] <= reg->kinetic_max)) {
        *value = out[0];
        return WK_OUT_ENERGY;
    }
    return WK_INSIDE;
}

/* StrideMap.__call__ at rtol `level` (0: the map's own tolerances) into *e. */
static int compiled_evaluate(wk_search_map *m, const double *z, double level, int want_jac,
                             evaluation *e)
{
    compiled_map *s = (compiled_map *)m;
    const wk_search_settings *set = s->set;
    const int64_t n_x = m->n_x;
    wk_problem pb = *s->tmpl;
    if (level > 0.0) { /* StrideMap.with_tolerance(level, min(atol * level / rtol, level)) */
        pb.rtol = level;
        pb.atol = fmin(set->own_atol * level / set->own_rtol, level);
    }
    e->has_jac = 0;
    e->t = 0.0;
    int64_t phase0 = 0;
    const int64_t start = wk_section_start(&pb, s->sec, z, e->x, &phase0);
    if (start != 0) {
        e->status = start;
        return 0;
    }
    if (phase0 >= pb.n_phases || !all_finite(e->x, n_x)) return WK_EVAL_DECLINED;
    const double *seed = NULL;
    if (want_jac) {
        seed = wk_section_seed(s->sec, n_x, pb.p, z, s->seed);
        if (!all_finite(seed, n_x * m->n_z)) return WK_EVAL_DECLINED;
    }
    wk_result res;
    const int rc = wk_section_run(s->fn, &pb, s->sec, set->period, seed, e->x, phase0, &res);
    if (rc != WK_OK) {
        wk_result_free(&res);
        return WK_EVAL_DECLINED;
    }
    const int64_t n_z = m->n_z;
    e->status = res.status;
    e->t = res.t;
    memcpy(e->x, res.x, (size_t)n_x * sizeof(double));
    if (res.status == WK_COMPLETED) {
        for (int64_t i = 0; i < n_z; i++) e->z[i] = res.x[s->sec->proj[i]];
        if (want_jac) {
            for (int64_t i = 0; i < n_z; i++)
                memcpy(e->jac + i * n_z, res.jac + s->sec->proj[i] * n_z,
                       (size_t)n_z * sizeof(double));
            e->has_jac = all_finite(e->jac, n_z * n_z);
        }
    }
    wk_result_free(&res);
    return 0;
}

/* The Jacobian at the map's own tolerance: an evaluation with it. */
static int compiled_jacobian(wk_search_map *m, const double *z, evaluation *e)
{
    return compiled_evaluate(m, z, 0.0, 1, e);
}

/* F(z) = P^k(z) - z into f; *ok 0 when the stride failed or its point is not finite. */
static int residual_at(search *s, const double *z, double level, int want_jac, evaluation *e,
                       double *f, int *ok)
{
    const int rc = s->map->evaluate(s->map, z, level, want_jac, e);
    if (rc) return rc;
    *ok = e->status == WK_COMPLETED && all_finite(e->z, s->n_z);
    if (*ok)
        for (int64_t i = 0; i < s->n_z; i++) f[i] = e->z[i] - z[i];
    return 0;
}

/* n evaluations from the budget (max_evals); OUT_OF_BUDGET when it cannot pay them. */
static int spend(search *s, int64_t n)
{
    /* an interrupt ends the search here (the binding then raises; hybrid.h) */
    if (s->n_evals + n > s->set->max_evals || (s->map->poll_interrupt && wk_interrupt))
        return OUT_OF_BUDGET;
    s->n_evals += n;
    return 0;
}

/* Coarse early strides (COARSE_RHO in walker/analysis/newton.py): the rtol for a point whose
 * residual is expected to be `expect`
 * (have_expect 0: unknown), 0.0 for the map's own. */
static double coarse_level(const search *s, int have_expect, double expect)
{
    const wk_search_settings *set = s->set;
    if (!set->coarse || !have_expect || !(expect > 0.0)) return 0.0;
    const double want = fmin(set->coarse_rho * expect * expect, set->coarsest_rtol);
    const double level = want > set->own_rtol ? pow(10.0, floor(log10(want))) : 0.0;
    return level > set->own_rtol ? level : 0.0;
}

/* A glance at the guess: max|F| from one stride at coarsest_rtol without the Jacobian,
 * counted, so that the guess's own evaluation can pick its rtol; *have 0 when there is no
 * coarse map, no room in the budget besides the guess's evaluation, or the stride fails;
 * *failed 1 when it fails. */
static int glance(search *s, const double *z, evaluation *e, double *f, int *have, double *r,
                  int *failed)
{
    *have = 0;
    *failed = 0;
    const double level = coarse_level(s, 1, 1.0);
    if (level == 0.0 || s->n_evals + 2 > s->set->max_evals) return 0;
    int rc = spend(s, 1), ok = 0;
    if (!rc) rc = residual_at(s, z, level, 0, e, f, &ok);
    if (rc) return rc;
    if (ok) {
        *have = 1;
        *r = max_abs(f, s->n_z);
    }
    *failed = !ok;
    return 0;
}

/* F(z) at the rtol for the residual `expect` (have_expect 0: the map's own).  A coarse
 * result is kept only when its residual r > tol and its rtol <= coarse_keep r^2; else the
 * point is evaluated again (counted) at the rtol for r, or the map's own; a coarse stride
 * that fails is redone at the map's own. */
static int residual(search *s, const double *z, int want_jac, int have_expect, double expect,
                    evaluation *e, double *f, int *ok)
{
    const wk_search_settings *set = s->set;
    int rc = spend(s, 1);
    if (rc) return rc;
    double level = coarse_level(s, have_expect, expect);
    if (level > 0.0) {
        if ((rc = residual_at(s, z, level, want_jac, e, f, ok))) return rc;
        if (*ok) {
            const double r = max_abs(f, s->n_z);
            if (r > set->tol && level <= set->coarse_keep * r * r) return 0;
            if ((rc = spend(s, 1))) return rc;
            level = coarse_level(s, 1, r);
            if (level > 0.0 && r > set->tol) return residual_at(s, z, level, want_jac, e, f, ok);
        } else if ((rc = spend(s, 1))) {
            return rc;
        }
    }
    return residual_at(s, z, 0.0, want_jac, e, f, ok);
}

/* The Newton step: dz (n,) solving a dz = -f for a (n, n) row-major by Gaussian elimination
 * with partial pivoting (wk_solve_columns), and in *cond the Frobenius condition number
 * ||a||_F ||a^-1||_F (>= the 2-norm one, <= n times it; INFINITY when not finite) from the
 * inverse solved with it.  Returns 0 (cond INFINITY, dz undefined) when a pivot is zero or
 * the solution is not finite.  A: (n, n) and B: (n, n + 1) workspace. */
static int newton_step(const double *a, const double *f, int64_t n, double *A, double *B,
                       double *dz, double *cond)
{
    const int64_t nc = n + 1;
    double norm_a = 0.0;
    for (int64_t i = 0; i < n; i++) {
        for (int64_t j = 0; j < n; j++) {
            A[i * n + j] = a[i * n + j];
            norm_a += a[i * n + j] * a[i * n + j];
            B[i * nc + 1 + j] = i == j ? 1.0 : 0.0;
        }
        B[i * nc] = -f[i];
    }
    *cond = INFINITY;
    if (!wk_solve_columns(A, B, (int)n, (int)nc)) return 0;
    double norm_inv = 0.0;
    for (int64_t i = 0; i < n; i++) {
        for (int64_t j = 1; j < nc; j++) norm_inv += B[i * nc + j] * B[i * nc + j];
        dz[i] = B[i * nc];
    }
    const double c = sqrt(norm_a) * sqrt(norm_inv);
    *cond = isfinite(c) ? c : INFINITY;
    return 1;
}

/* WalkingRegion.outside of the map: WK_INSIDE (also for a map without a region), WK_OUT_*,
 * or -1 when the map failed. */
static int outside(search *s, const double *z, double *value, int64_t *index)
{
    return s->map->outside == NULL ? WK_INSIDE : s->map->outside(s->map, z, value, index);
}

/* A trial point outside the walking region: counted in *refused, the first reason of the
 * iteration kept in out (why_refused); 0 when z lies inside, -1 when the map failed. */
static int refused_at(search *s, const double *z, wk_search_out *out, int64_t *refused)
{
    double value = 0.0;
    int64_t index = 0;
    const int why = outside(s, z, &value, &index);
    if (why <= WK_INSIDE) return why;
    ++*refused;
    if (out->why == WK_INSIDE) {
        out->why = why;
        out->why_value = value;
        out->why_index = index;
    }
    return 1;
}

static void swap(evaluation **a, evaluation **b)
{
    evaluation *t = *a;
    *a = *b;
    *b = t;
}

/* The search proper; w is the
 * workspace.  Returns 0, OUT_OF_BUDGET or DECLINED; out says how it ended otherwise. */
static int run(search *s, const double *scale, const double *z0, double *w, evaluation *ev,
               wk_search_out *out)
{
    const wk_search_settings *set = s->set;
    const int64_t n = s->n_z;
    double *z = out->z, *z_try = w, *dz = w + n, *f = w + 2 * n, *f_try = w + 3 * n;
    double *g = w + 4 * n, *a = w + 5 * n, *A = a + n * n, *B = A + n * n;
    double *jtj = B + n * (n + 1);
    evaluation *here = &ev[0], *trial = &ev[1], *spare = &ev[2];
    double *history = out->history;
    int rc, ok = 0;

    memcpy(z, z0, (size_t)n * sizeof(double));
    out->it = 0;
    out->why = outside(s, z, &out->why_value, &out->why_index);
    if (out->why < 0) return WK_EVAL_ERROR;
    if (out->why != WK_INSIDE) {
        out->end = WK_SEARCH_OUTSIDE_GUESS;
        return 0;
    }
    int have_glance = 0, glance_failed = 0;
    double glanced = 0.0;
    if ((rc = glance(s, z, here, f, &have_glance, &glanced, &glance_failed))) return rc;
    if (glance_failed) {
        /* a stride failing at the coarsest tolerance is confirmed at the
         * map's own without the Jacobian first */
        if ((rc = residual(s, z, 0, 0, 0.0, here, f, &ok))) return rc;
        if (!ok) {
            out->end = WK_SEARCH_START_FAILS;
            out->status = here->status;
            return 0;
        }
    }
    if ((rc = residual(s, z, set->exact, have_glance, glanced, here, f, &ok))) return rc;
    if (!ok) {
        out->end = WK_SEARCH_START_FAILS;
        out->status = here->status;
        return 0;
    }
    int jac_here = here->has_jac;
    history[out->n_history++] = max_abs(f, n);
    double lm = set->lm_start, radius = set->tr_start;
    int64_t poor_run = 0; /* trailing accepted steps that gained little */
    for (int64_t it = 0; it <= set->max_iter; it++) {
        out->it = it;
        const double last = history[out->n_history - 1];
        if (last <= set->tol) {
            out->end = WK_SEARCH_CONVERGED;
            if (jac_here) {
                out->known = 1;
                out->known_t = here->t;
                memcpy(out->known_z, here->z, (size_t)n * sizeof(double));
                if (out->known_x != NULL)
                    memcpy(out->known_x, here->x, (size_t)s->map->n_x * sizeof(double));
                memcpy(out->known_jac, here->jac, (size_t)(n * n) * sizeof(double));
                out->known_handle = here->handle;
                here->handle = NULL;
            }
            return 0;
        }
        if (it == set->max_iter) break;
        if (poor_run >= set->stall_window) {
            out->end = WK_SEARCH_STALL;
            return 0;
        }
        const double *jac_map = here->jac;
        if (!jac_here) { /* the Jacobian at the map's own tolerance */
            if ((rc = spend(s, set->jac_cost)) || (rc = s->map->jacobian(s->map, z, spare)))
                return rc;
            if (spare->status != WK_COMPLETED || !spare->has_jac) {
                out->end = WK_SEARCH_JACOBIAN_FAILED;
                out->status = spare->status != WK_COMPLETED ? spare->status : WK_NONFINITE;
                return 0;
            }
            jac_map = spare->jac;
        }
        for (int64_t i = 0; i < n * n; i++) a[i] = jac_map[i] - (i % (n + 1) == 0 ? 1.0 : 0.0);
        const double merit = norm2(f, n);
        int accepted = 0, shortened = 0;
        double alpha = 1.0;
        int64_t refused = 0, walked = 0;
        int64_t full_step_status = WK_COMPLETED;
        out->why = WK_INSIDE;
        /* --- Newton step, cut to the trust region, with backtracking on ||F||_2 --------- */
        double cond;
        newton_step(a, f, n, A, B, dz, &cond);
        if (cond < set->cond_max) {
            const double length = max_abs_scaled(dz, scale, n);
            if (length > radius)
                for (int64_t i = 0; i < n; i++) dz[i] *= radius / length;
            alpha = 1.0;
            for (int64_t h = 0; h < set->max_halvings; h++) {
                for (int64_t i = 0; i < n; i++) z_try[i] = z[i] + alpha * dz[i];
                const int out_here = refused_at(s, z_try, out, &refused);
                if (out_here < 0) return WK_EVAL_ERROR;
                if (out_here) {
                    if (alpha == 1.0) full_step_status = WK_OUTSIDE_WALKING_REGION;
                    alpha *= 0.5;
                    continue;
                }
                /* a full step should square the residual; a shortened one, less */
                const double expect = alpha == 1.0 ? last * last : last;
                const int want_jac = set->exact && alpha == 1.0;
                if ((rc = residual(s, z_try, want_jac, 1, expect, trial, f_try, &ok)))
                    return rc;
                if (!ok) {
                    if (alpha == 1.0) full_step_status = trial->status;
                } else {
                    walked++;
                    const double merit_try = norm2(f_try, n);
                    if (merit_try <= (1 - set->armijo * alpha) * merit) {
                        accepted = 1;
                        shortened = alpha < 1.0;
                        break;
                    }
                    if (merit_try <= (1 + set->line_flat) * merit) break; /* flat: a minimum */
                }
                alpha *= 0.5;
            }
        } else if (!set->fallback) {
            out->end = WK_SEARCH_SINGULAR;
            out->cond = cond;
            return 0;
        }
        /* --- Levenberg-Marquardt fallback when Newton stalls, in the same trust region --- */
        if (!accepted && set->fallback) {
            for (int64_t i = 0; i < n; i++) {
                double gi = 0.0;
                for (int64_t k = 0; k < n; k++) gi += a[k * n + i] * f[k];
                g[i] = gi;
                for (int64_t j = 0; j < n; j++) {
                    double sij = 0.0;
                    for (int64_t k = 0; k < n; k++) sij += a[k * n + i] * a[k * n + j];
                    jtj[i * n + j] = sij;
                }
            }
            int64_t tries = 0;
            while (lm <= set->lm_max && tries < set->lm_tries) {
                tries++;
                for (int64_t i = 0; i < n; i++) {
                    for (int64_t j = 0; j < n; j++) A[i * n + j] = jtj[i * n + j];
                    A[i * n + i] = jtj[i * n + i] + lm * fmax(jtj[i * n + i], 1e-12);
                    dz[i] = -g[i];
                }
                if (!wk_solve_inplace(A, dz, (int)n)) {
                    lm *= set->lm_grow;
                    continue;
                }
                const double length = max_abs_scaled(dz, scale, n);
                if (!isfinite(length)) {
                    lm *= set->lm_grow;
                    continue;
                }
                if (length > radius)
                    for (int64_t i = 0; i < n; i++) dz[i] *= radius / length;
                for (int64_t i = 0; i < n; i++) z_try[i] = z[i] + dz[i];
                const int out_here = refused_at(s, z_try, out, &refused);
                if (out_here < 0) return WK_EVAL_ERROR;
                if (out_here) {
                    lm *= set->lm_grow;
                    continue;
                }
                if ((rc = residual(s, z_try, 0, 0, 0.0, trial, f_try, &ok))) return rc;
                if (ok && norm2(f_try, n) < merit) {
                    accepted = 1;
                    lm = fmax(lm * set->lm_shrink, 1e-12);
                    break;
                }
                if (ok) walked++;
                lm *= set->lm_grow;
            }
            if (!accepted && lm > set->lm_max) lm = set->lm_start;
        }
        if (!accepted) {
            out->refused = refused;
            out->status = full_step_status;
            if (full_step_status != WK_COMPLETED && walked == 0) {
                out->end = WK_SEARCH_DIVERGED;
            } else {
                out->end = WK_SEARCH_NO_DESCENT;
            }
            return 0;
        }
        for (int64_t i = 0; i < n; i++) dz[i] = z_try[i] - z[i];
        const double step = max_abs_scaled(dz, scale, n);
        radius = shortened ? step : fmin(set->tr_max, fmax(radius, 2.0 * step));
        memcpy(z, z_try, (size_t)n * sizeof(double));
        memcpy(f, f_try, (size_t)n * sizeof(double));
        swap(&here, &trial);
        jac_here = here->has_jac;
        history[out->n_history++] = max_abs(f, n);
        const int poor = history[out->n_history - 1] > set->stall_ratio * last ||
                         (shortened && alpha <= set->stall_alpha);
        poor_run = poor ? poor_run + 1 : 0;
    }
    out->end = WK_SEARCH_MAX_ITER;
    out->it = set->max_iter;
    return 0;
}

int wk_search(wk_search_map *m, const wk_search_settings *set, const double *scale,
              const double *z0, wk_search_out *out)
{
    const int64_t n = m->n_z, n_x = m->n_x;
    const int64_t per_eval = n + n_x + n * n;
    const int64_t n_work = 5 * n + 3 * n * n + n * (n + 1) + 3 * per_eval;
    double *w = malloc((size_t)n_work * sizeof(double));
    if (w == NULL) return WK_ERR_NOMEM;
    search s = {m, set, n, 0};
    evaluation ev[3];
    double *at = w + 5 * n + 3 * n * n + n * (n + 1);
    for (int k = 0; k < 3; k++) {
        ev[k].z = at;
        ev[k].x = at + n;
        ev[k].jac = at + n + n_x;
        ev[k].handle = NULL;
        at += per_eval;
    }
    out->end = WK_SEARCH_DECLINED;
    out->status = WK_COMPLETED;
    out->n_history = 0;
    out->refused = 0;
    out->known = 0;
    out->known_handle = NULL;
    out->why = WK_INSIDE;
    out->cond = 0.0;
    const int rc = run(&s, scale, z0, w, ev, out);
    if (rc == OUT_OF_BUDGET) out->end = WK_SEARCH_BUDGET;
    if (rc == WK_EVAL_DECLINED) out->end = WK_SEARCH_DECLINED;
    out->n_evals = s.n_evals;
    if (m->release != NULL)
        for (int k = 0; k < 3; k++) m->release(m, &ev[k]);
    free(w);
    return rc == WK_EVAL_ERROR ? WK_ERR_SEARCH_MAP : WK_OK;
}

int wk_search_compiled(const wk_functions *fn, const wk_problem *tmpl, const wk_section *sec,
                       const wk_region *reg, const wk_search_settings *set, const double *scale,
                       const double *z0, wk_search_out *out)
{
    const int64_t n = sec->n_z, n_x = tmpl->n_x;
    double *x = malloc((size_t)(n_x + n_x * n) * sizeof(double));
    if (x == NULL) return WK_ERR_NOMEM;
    compiled_map map = {{n, n_x, compiled_evaluate, compiled_jacobian, compiled_outside, NULL, 1},
                        fn, tmpl, sec, reg, set, x, x + n_x};
    const int rc = wk_search(&map.base, set, scale, z0, out);
    free(x);
    return rc;
}
