/* Runge-Kutta steps of the hybrid integrator (see hybrid_internal.h for the split): the
 * method table, read from the tableaux (tableaux.h); the augmented vector field with the
 * variational equations; the stages of one step; the scaled error norm of the embedded
 * pairs; step-size control; Hairer's starting step.
 */
#include <math.h>
#include <stdlib.h>

#include "hybrid_internal.h"

/* Step-size controller constants (Hairer, Norsett, Wanner I, Sect. II.4). */
#define SAFETY 0.9
#define MIN_FACTOR 0.2
#define MAX_FACTOR 10.0
#define SEED_COLUMN_FLOOR 0.01 /* see wk_error_scale */

/* Rows of the dense matrix-vector product J Phi beyond which a non-finite row is not
 * recomputed over J's nonzeros (see jac_times_phi). */
#define SPARSE_JAC_MAX 32

/* ------------------------------------------------------------------------------------------
 * The method table
 * ------------------------------------------------------------------------------------------ */

/* One entry from the tableaux of NAME (WK_<NAME>_* in tableaux.h). */
#define METHOD_ENTRY(NAME, DENSE)                                                         \
    {                                                                                     \
        &WK_##NAME##_A[0][0], WK_##NAME##_A_COLS, WK_##NAME##_B, WK_##NAME##_C,           \
            WK_##NAME##_N_STAGES, DENSE, WK_##NAME##_ERR_ORDER, WK_##NAME##_ORDER         \
    }

static const wk_method METHODS[] = {
    [WK_METHOD_EULER] = METHOD_ENTRY(EULER, DENSE_HERMITE),
    [WK_METHOD_RK4] = METHOD_ENTRY(RK4, DENSE_HERMITE),
    [WK_METHOD_DP5] = METHOD_ENTRY(RK45, DENSE_RK45),
    [WK_METHOD_DOP853] = METHOD_ENTRY(DOP853, DENSE_DOP853),
};

#undef METHOD_ENTRY

const wk_method *wk_method_of(int method)
{
    if (method < 0 || method >= (int)(sizeof METHODS / sizeof METHODS[0]))
        return &METHODS[WK_METHOD_EULER];
    return &METHODS[method];
}

/* ------------------------------------------------------------------------------------------
 * The vector field
 * ------------------------------------------------------------------------------------------ */

/* dz[n_x:] = J Phi for the Jacobian J = m->J (filled by the caller) and Phi = z[n_x:]. */
static void jac_times_phi(const model_t *m, const double *z, double *dz)
{
    const int64_t n = m->n_x;
    const int64_t nc = m->n_c;
    const double *Phi = z + n;
    const double *J = m->J;
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

void wk_fun_var(const model_t *m, int64_t phase, double t, const double *z, double *dz)
{
    m->fn.jac(phase, t, z, m->p, m->J, m->fn.ctx);
    jac_times_phi(m, z, dz);
}

void wk_fun_unfused(const model_t *m, int64_t phase, double t, const double *z, double *dz)
{
    m->fn.rhs(phase, t, z, m->p, dz, m->fn.ctx);
    if (m->want_jac) wk_fun_var(m, phase, t, z, dz);
}

void wk_fun(const model_t *m, int64_t phase, double t, const double *z, double *dz)
{
    if (m->want_jac && m->fn.rhs_jac != NULL) {
        /* a built-in model's fused rhs and Jacobian: one call, J as jac fills it */
        m->fn.rhs_jac(phase, t, z, m->p, dz, m->J, m->fn.ctx);
        jac_times_phi(m, z, dz);
        return;
    }
    wk_fun_unfused(m, phase, t, z, dz);
}

int wk_all_finite(const double *v, int64_t n)
{
    for (int64_t i = 0; i < n; i++)
        if (!isfinite(v[i])) return 0;
    return 1;
}

/* ------------------------------------------------------------------------------------------
 * One step
 * ------------------------------------------------------------------------------------------ */

/* The stages with the tableau of ``mt``: A is row-major with a_cols columns. */
int64_t wk_rk_stages(const model_t *m, const wk_method *mt, int64_t phase, double t,
                     const double *y, double h, double *K, double *y_new, double *tmp)
{
    const int64_t n = m->n_z;
    const double *A = mt->A, *B = mt->B, *C = mt->C;
    const int a_cols = mt->a_cols, n_stages = mt->n_stages;
    for (int s = 1; s < n_stages; s++) {
        stage_combine(A + s * a_cols, s, K, n, n, y, h, tmp);
        wk_fun(m, phase, t + C[s] * h, tmp, K + s * n);
    }
    stage_combine(B, n_stages, K, n, n, y, h, y_new);
    wk_fun(m, phase, t + h, y_new, K + n_stages * n);
    return n_stages;
}

/* ------------------------------------------------------------------------------------------
 * Error norm and step-size control
 * ------------------------------------------------------------------------------------------ */

void wk_error_scale(const model_t *m, int seeded, double rtol, double atol, const double *z,
                    const double *y_new, double *scale)
{
    const int64_t n_z = m->n_z, n_x = m->n_x, n_c = m->n_c;
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
}

/* Scaled RMS error estimate of the embedded pair (0 for fixed-step methods).
 *
 * With a seed of n_c < n_x columns (``n_head`` = n_x < n, ``weight`` = n_x / n_c,
 * ``n_norm`` = n_x + n_x * n_x) the squared scaled errors of the sensitivity components
 * count ``weight`` times and the norm divides by ``n_norm``: as if the columns not carried
 * erred like those carried, so the control asks of the carried columns what the full
 * matrix's asks of all.  Without one, ``n_head`` = n and ``n_norm`` = n: the plain norm. */
double wk_error_norm(int method, const double *K, double h, const double *scale, int64_t n,
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

double wk_reject_factor(double err, double exponent)
{
    return max2(MIN_FACTOR, SAFETY * pow(err, exponent));
}

double wk_accept_factor(double err, double exponent, int rejected_now)
{
    double factor;
    if (err == 0.0)
        factor = MAX_FACTOR;
    else
        factor = min2(MAX_FACTOR, SAFETY * pow(err, exponent));
    if (rejected_now) factor = min2(1.0, factor);
    return factor;
}

/* ------------------------------------------------------------------------------------------
 * Starting step
 * ------------------------------------------------------------------------------------------ */

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
double wk_initial_step(const model_t *m, int64_t phase, double t, const double *y,
                       const double *f0, int order, double rtol, double atol, double max_step,
                       double span, double *tmp, double *f1, double *scale)
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
    wk_fun(m, phase, t + h0, tmp, f1);
    for (int64_t i = 0; i < n; i++) tmp[i] = f1[i] - f0[i];
    const double d2 = rms_scaled(tmp, scale, n) / h0;
    double h1;
    if (d1 <= 1e-15 && d2 <= 1e-15)
        h1 = max2(1e-6, h0 * 1e-3);
    else
        h1 = pow(0.01 / max2(d1, d2), 1.0 / (double)(order + 1));
    return min2(min2(min2(100.0 * h0, h1), max_step), span);
}

