/* Shared pieces of walker's hand-written C models; see wk_common.h. */
#include <math.h>
#include "wk_common.h"

/* Gaussian elimination for nc right-hand sides, the operations of walker's former
 * _linalg.solve_inplace (declared in wk_friction.h, whose Jacobians use it). */
int wk_solve_columns(double *A, double *B, int n, int nc)
{
    double scale = 0.0;
    for (int i = 0; i < n; i++) {
        for (int j = 0; j < n; j++) {
            double v = fabs(A[i * n + j]);
            if (v > scale) scale = v;
        }
    }
    double tiny = scale > 0 ? scale * 1e-300 : 1e-300;
    for (int k = 0; k < n; k++) {
        int p = k;
        double big = fabs(A[k * n + k]);
        for (int i = k + 1; i < n; i++) {
            double v = fabs(A[i * n + k]);
            if (v > big) {
                big = v;
                p = i;
            }
        }
        if (!(big > tiny)) return 0;
        if (p != k) {
            for (int j = 0; j < n; j++) {
                double tmp = A[k * n + j];
                A[k * n + j] = A[p * n + j];
                A[p * n + j] = tmp;
            }
            for (int j = 0; j < nc; j++) {
                double tmp = B[k * nc + j];
                B[k * nc + j] = B[p * nc + j];
                B[p * nc + j] = tmp;
            }
        }
        double piv = A[k * n + k];
        for (int i = k + 1; i < n; i++) {
            double f = A[i * n + k] / piv;
            if (f != 0.0) {
                for (int j = k + 1; j < n; j++) A[i * n + j] -= f * A[k * n + j];
                for (int j = 0; j < nc; j++) B[i * nc + j] -= f * B[k * nc + j];
            }
        }
    }
    for (int k = n - 1; k >= 0; k--) {
        for (int c = 0; c < nc; c++) {
            double s = B[k * nc + c];
            for (int j = k + 1; j < n; j++) s -= A[k * n + j] * B[j * nc + c];
            B[k * nc + c] = s / A[k * n + k];
        }
    }
    for (int i = 0; i < n * nc; i++) {
        if (!isfinite(B[i])) return 0;
    }
    return 1;
}

/* The one-column case of wk_solve_columns: the same operations. */
int wk_solve_inplace(double *A, double *b, int n)
{
    return wk_solve_columns(A, b, n, 1);
}

int wk_impact(const double *M, const double *J, const double *qd_minus, double *qd_plus,
              double *impulse, int n, int m)
{
    double A[WK_IMPACT_MAX * WK_IMPACT_MAX];
    double b[WK_IMPACT_MAX];
    const int N = n + m;
    if (N > WK_IMPACT_MAX) return 0;
    for (int i = 0; i < N * N; i++) A[i] = 0.0;
    for (int i = 0; i < N; i++) b[i] = 0.0;
    for (int i = 0; i < n; i++) {
        double s = 0.0;
        for (int j = 0; j < n; j++) {
            A[i * N + j] = M[i * n + j];
            s += M[i * n + j] * qd_minus[j];
        }
        b[i] = s;
        for (int c = 0; c < m; c++) {
            A[i * N + n + c] = -J[c * n + i];
            A[(n + c) * N + i] = J[c * n + i];
        }
    }
    int ok = wk_solve_inplace(A, b, N);
    for (int i = 0; i < n; i++) qd_plus[i] = b[i];
    for (int c = 0; c < m; c++) impulse[c] = b[n + c];
    return ok;
}

void wk_floating_base_state(const double *q, const double *qd, const double *hip,
                            const double *hip_J, double *qf, double *qdf, int n)
{
    for (int i = 0; i < n; i++) {
        qf[i] = q[i];
        qdf[i] = qd[i];
    }
    for (int r = 0; r < 2; r++) {
        qf[n + r] = hip[r];
        double s = 0.0;
        for (int j = 0; j < n; j++) s += hip_J[r * n + j] * qd[j];
        qdf[n + r] = s;
    }
}

int wk_heel_strike_impact(const double *M, const double *J_swing, const double *J_stance,
                          const double *qdf, double slope, double *qdf_plus, double *impulse,
                          double *lift, int n_f)
{
    double lam[2];
    if (!wk_impact(M, J_swing, qdf, qdf_plus, lam, n_f, 2)) return 0;
    double s0 = cos(slope), s1 = -sin(slope);
    double n0 = sin(slope), n1 = cos(slope);
    impulse[0] = lam[0] * s0 + lam[1] * s1;
    impulse[1] = lam[0] * n0 + lam[1] * n1;
    double v0 = 0.0;
    double v1 = 0.0;
    for (int j = 0; j < n_f; j++) {
        v0 += J_stance[0 * n_f + j] * qdf_plus[j];
        v1 += J_stance[1 * n_f + j] * qdf_plus[j];
    }
    *lift = v0 * n0 + v1 * n1;
    return 1;
}

int wk_floating_base_heel_strike(const wk_floating_base *B, const double *q, const double *qd,
                                 const double *p, double slope, double *qdf_plus,
                                 double *impulse, double *lift)
{
    enum { NF = WK_FLOATING_BASE_MAX };
    double pts[WK_POINTS_MAX * 2], hip_J[2 * NF], qf[NF], qdf[NF];
    double M[NF * NF], Jsw[2 * NF], Jst[2 * NF];
    const int n = B->n;
    if (n + 2 > NF || B->n_points > WK_POINTS_MAX || B->hip_row < 0 || B->hip_row >= B->n_points)
        return 0;
    B->points(q, p, pts);
    B->hip_jac(q, p, hip_J);
    wk_floating_base_state(q, qd, pts + 2 * B->hip_row, hip_J, qf, qdf, n);
    B->ext_mass_matrix(qf, p, M);
    B->ext_swing_contact_jac(qf, p, Jsw);
    B->ext_stance_contact_jac(qf, p, Jst);
    return wk_heel_strike_impact(M, Jsw, Jst, qdf, slope, qdf_plus, impulse, lift, n + 2);
}

int64_t wk_plastic_heel_strike(const wk_floating_base *B, const int *swap, int n_c,
                               const double *x, const double *p, double slope, double *x_new,
                               double *impulse)
{
    double qdf_plus[WK_FLOATING_BASE_MAX], lift;
    if (!wk_floating_base_heel_strike(B, x, x + n_c, p, slope, qdf_plus, impulse, &lift))
        return WK_LINEAR_SOLVE_FAILED;
    wk_swap_legs(swap, n_c, x, qdf_plus, x_new);
    if (!(impulse[1] > 0.0) || !(lift > 0.0)) return WK_NONPHYSICAL_IMPACT;
    return 0;
}
