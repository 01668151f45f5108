/* A walker's stride map in C, one call and many starts: see batch.h. */
#include "batch.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void wk_section_lift(const wk_section *sec, int64_t n_x, const double *p, const double *z,
                     double *x)
{
    if (sec->lift != NULL) {
        sec->lift(z, p, x, sec->ctx);
        return;
    }
    const int64_t n_z = sec->n_z;
    for (int64_t r = 0; r < n_x; r++) {
        const double *a = sec->lift_a + r * n_z;
        double acc = 0.0;
        int any = 0;
        for (int64_t c = 0; c < n_z; c++) {
            if (a[c] == 0.0) continue;
            const double term = a[c] == 1.0 ? z[c] : (a[c] == -1.0 ? -z[c] : a[c] * z[c]);
            acc = any ? acc + term : term;
            any = 1;
        }
        const double b = sec->lift_b[r];
        x[r] = any ? (b != 0.0 ? b + acc : acc) : b;
    }
}

/* max |z - target| <= tol, false when anything is NaN (as numpy's max of NaN). */
static int converged(const double *z, const double *target, int64_t n, double tol)
{
    double worst = 0.0;
    for (int64_t i = 0; i < n; i++) {
        const double d = fabs(z[i] - target[i]);
        if (isnan(d)) return 0;
        if (d > worst) worst = d;
    }
    return worst <= tol;
}

/* ||weight (z - target)||_2 <= radius (weight (n, n) row-major), false when anything is NaN:
 * the point is inside the ball where the stride map is a contraction (walker/analysis/basin.py). */
static int in_ball(const double *z, const double *target, const double *weight, int64_t n,
                   double radius)
{
    double sum = 0.0;
    for (int64_t r = 0; r < n; r++) {
        double acc = 0.0;
        for (int64_t c = 0; c < n; c++) acc += weight[r * n + c] * (z[c] - target[c]);
        sum += acc * acc;
    }
    return sum <= radius * radius;
}

int64_t wk_section_start(const wk_problem *tmpl, const wk_section *sec, const double *z,
                         double *x0, int64_t *phase0)
{
    wk_section_lift(sec, tmpl->n_x, tmpl->p, z, x0);
    const double psi = z[0] + sec->offset;
    if (!(fabs(psi) < sec->fall_angle)) return psi < 0.0 ? WK_FELL_FORWARD : WK_FELL_BACKWARD;
    for (int64_t i = 0; i < sec->n_q; i++)
        if (fabs(x0[i]) > sec->wound) return WK_OUTSIDE_WALKING_REGION;
    double out[4] = {0.0, 0.0, 0.0, 0.0};
    if (sec->energy != NULL) {
        sec->energy(x0, tmpl->p, out, sec->ctx);
        if (!(out[0] <= sec->kinetic_limit)) return WK_OUTSIDE_WALKING_REGION;
    }
    *phase0 = 0;
    if (sec->start_phase != NULL) {
        out[0] = 0.0;
        sec->start_phase(x0, tmpl->p, out, sec->ctx);
        *phase0 = (int64_t)out[0];
        if (*phase0 < 0) return WK_LINEAR_SOLVE_FAILED;
    }
    return 0;
}

const double *wk_section_seed(const wk_section *sec, int64_t n_x, const double *p,
                              const double *z, double *buf)
{
    if (sec->lift == NULL) return sec->lift_a;
    for (int64_t i = 0; i < n_x * sec->n_z; i++) buf[i] = 0.0;
    sec->lift_jacobian(z, p, buf, sec->ctx);
    return buf;
}

int wk_section_run(const wk_functions *fn, const wk_problem *tmpl, const wk_section *sec,
                   int64_t period, const double *seed, const double *x0, int64_t phase0,
                   wk_result *res)
{
    wk_problem pb = *tmpl;
    pb.x0 = x0;
    pb.phase0 = phase0;
    pb.t0 = 0.0;
    pb.t_max = sec->t_max * (double)period;
    pb.n_strides = period;
    pb.max_steps = sec->max_steps * period;
    pb.output = WK_OUTPUT_MAP;
    pb.want_jac = seed != NULL;
    pb.jac_seed = seed;
    pb.n_seed = seed != NULL ? sec->n_z : 0;
    pb.sample_times = NULL;
    pb.n_samples = 0;
    return wk_hybrid_solve(fn, &pb, res);
}

/* One call of the stride map from section point z (StrideMap.__call__ with n_strides =
 * period): returns the status (0: completed, z overwritten with the new section point). */
static int64_t map_once(const wk_functions *fn, const wk_problem *tmpl, const wk_section *sec,
                        int64_t period, double *z, double *x0, int *rc)
{
    int64_t phase0 = 0;
    int64_t status = wk_section_start(tmpl, sec, z, x0, &phase0);
    if (status != 0) return status;
    wk_result res;
    *rc = wk_section_run(fn, tmpl, sec, period, NULL, x0, phase0, &res);
    status = res.status;
    if (*rc == WK_OK && status == 0)
        for (int64_t i = 0; i < sec->n_z; i++) z[i] = res.x[sec->proj[i]];
    wk_result_free(&res);
    return status;
}

int wk_basin_points(const wk_functions *fn, const wk_problem *tmpl, const wk_section *sec,
                    int64_t m, const double *z0, const double *target, double tol,
                    const double *weight, double radius, int64_t n_strides, int64_t period,
                    int64_t *outcome, int64_t *strides)
{
    const int64_t n_z = sec->n_z;
    double *z = malloc((size_t)(n_z + tmpl->n_x) * sizeof(double));
    if (z == NULL) return WK_ERR_NOMEM;
    double *x0 = z + n_z;
    int rc = WK_OK;
    for (int64_t k = 0; k < m && rc == WK_OK; k++) {
        memcpy(z, z0 + k * n_z, (size_t)n_z * sizeof(double));
        int64_t done = 0;
        int64_t result = WK_BASIN_UNDECIDED;
        for (;;) {
            if (converged(z, target, n_z, tol) ||
                (radius > 0.0 && in_ball(z, target, weight, n_z, radius))) {
                result = WK_BASIN_CONVERGED;
                break;
            }
            if (done + period > n_strides) break;
            const int64_t status = map_once(fn, tmpl, sec, period, z, x0, &rc);
            if (rc != WK_OK) break;
            if (status != 0) {
                result = status;
                break;
            }
            done += period;
        }
        outcome[k] = result;
        strides[k] = done;
    }
    free(z);
    return rc;
}
