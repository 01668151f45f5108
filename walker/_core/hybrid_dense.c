/* Dense output of the hybrid integrator (see hybrid_internal.h for the split): the
 * interpolant of an accepted step -- DOP853's 7th-order one, Shampine's 4th-order one for
 * RK45, cubic Hermite for the fixed-step methods -- prepared lazily (only a step that needs
 * guard values inside it, samples or an event state pays for it) and evaluated at a step
 * fraction.  The driver (hybrid.c) tracks how much of it is ready (DENSE_NONE / STATE /
 * FULL).
 */
#include <stdlib.h>

#include "hybrid_internal.h"

/* Fill the dense-output coefficients Q of the step (t, y_old) -> (t + h, y_new), from what
 * is ready (``have``) up to ``want`` (DENSE_STATE or DENSE_FULL).  K[0] is f at the step
 * start and K[n_stages] f at the step end (Hermite: K[1]).  Returns the number of extra rhs
 * evaluations (3 for DOP853, else 0), once per step.
 *
 * DOP853 with sensitivities: the state's components of the three extra stages depend on
 * the state's alone (the variational equations do not feed back), so DENSE_STATE computes
 * just those (rhs calls, no Jacobians), and DENSE_FULL -- needed only in a step with an
 * event -- adds the sensitivities' (Jacobian calls at the same stage points).  Every number
 * is computed by the same expression as in one pass (which calls rhs and jac too,
 * wk_fun_unfused, never a fused rhs_jac), so the result is bit-identical. */
int64_t wk_dense_prepare(int kind, const model_t *m, int64_t phase, double t,
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
                wk_fun_var(m, phase, ts, tmp, K + s * n);
            else
                wk_fun_unfused(m, phase, ts, tmp, K + s * n);
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

/* Dense output at t_old + theta * h, first ``count`` components into ``out``; Q has rows
 * of length ``n``. */
void wk_dense_eval(int kind, const double *Q, int64_t n, const double *y_old, double theta,
                   int64_t count, double *out)
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
