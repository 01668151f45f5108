/* Feedback controllers of the actuated walkers; see wk_control.h. */
#include "wk_control.h"
#include "wk_common.h"

static const double BINOM4[5] = {1.0, 4.0, 6.0, 4.0, 1.0};
static const double BINOM3[4] = {1.0, 3.0, 3.0, 1.0};
static const double BINOM2[3] = {1.0, 2.0, 1.0};

/* a ** k for a float a and an integer k >= 0 as numba computes it: binary exponentiation
 * starting from 1.0 (not libm's pow). */
static double ipow(double a, int k)
{
    double r = 1.0;
    while (k != 0) {
        if (k & 1) r *= a;
        k >>= 1;
        a *= a;
    }
    return r;
}

void wk_control_bezier(const double *a, double s, double *b, double *db, double *d2b)
{
    double v = 0.0;
    for (int k = 0; k < 5; k++) v += a[k] * BINOM4[k] * ipow(s, k) * ipow(1.0 - s, 4 - k);
    double d1 = 0.0;
    for (int k = 0; k < 4; k++)
        d1 += 4.0 * (a[k + 1] - a[k]) * BINOM3[k] * ipow(s, k) * ipow(1.0 - s, 3 - k);
    double d2 = 0.0;
    for (int k = 0; k < 3; k++)
        d2 += 12.0 * (a[k + 2] - 2.0 * a[k + 1] + a[k]) * BINOM2[k] * ipow(s, k) *
              ipow(1.0 - s, 2 - k);
    *b = v;
    *db = d1;
    *d2b = d2;
}

void wk_control_outputs(const double *q, const double *qd, const double *c, double *y,
                        double *yd, double *H, double *cterm, int n)
{
    const int M1 = WK_CONTROL_BEZIER_DEGREE + 1;
    double ds = 1.0 / (c[WK_CONTROL_I_THETA_MINUS] - c[WK_CONTROL_I_THETA_PLUS]);
    double s = (q[0] - c[WK_CONTROL_I_THETA_PLUS]) * ds;
    for (int i = 0; i < n - 1; i++) {
        double b, b1, b2;
        wk_control_bezier(c + WK_CONTROL_I_BEZIER + i * M1, s, &b, &b1, &b2);
        y[i] = q[i + 1] - b;
        yd[i] = qd[i + 1] - b1 * ds * qd[0];
        for (int j = 0; j < n; j++) H[i * n + j] = 0.0;
        H[i * n + 0] = -b1 * ds;
        H[i * n + i + 1] = 1.0;
        cterm[i] = -b2 * ds * ds * qd[0] * qd[0];
    }
}

int wk_control_controller_torque(const double *q, const double *qd, const double *D,
                                 const double *h, const double *B, const double *c, double *u,
                                 int n)
{
    const int m = n - 1;
    const int64_t mode = (int64_t)c[WK_CONTROL_I_MODE];
    if (mode == WK_CONTROL_MODE_OFF) {
        for (int i = 0; i < m; i++) u[i] = 0.0;
        return 0;
    }
    double y[WK_CONTROL_MAX_N], yd[WK_CONTROL_MAX_N], cterm[WK_CONTROL_MAX_N];
    double H[WK_CONTROL_MAX_N * WK_CONTROL_MAX_N];
    wk_control_outputs(q, qd, c, y, yd, H, cterm, n);
    double kp = c[WK_CONTROL_I_KP], kd = c[WK_CONTROL_I_KD];
    if (mode == WK_CONTROL_MODE_PD) {
        /* generalized PD forces on the controlled coordinates q[1:], realized by the
         * actuators: B[1:, :] u = -kp y - kd yd */
        double Ba[WK_CONTROL_MAX_N * WK_CONTROL_MAX_N];
        for (int i = 0; i < m; i++) {
            u[i] = -kp * y[i] - kd * yd[i];
            for (int j = 0; j < m; j++) Ba[i * m + j] = B[(i + 1) * m + j];
        }
        wk_solve_inplace(Ba, u, m);
    } else {
        /* X = D^{-1} [B | h], column by column: wk_solve_inplace on a fresh copy of D per
         * column does, column for column, the operations of numba's solve with a matrix
         * right-hand side (the pivots depend on D alone). */
        double X[WK_CONTROL_MAX_N * WK_CONTROL_MAX_N]; /* column-major, (m + 1) columns */
        double Dc[WK_CONTROL_MAX_N * WK_CONTROL_MAX_N];
        for (int j = 0; j <= m; j++) {
            double *col = X + j * n;
            for (int i = 0; i < n; i++) col[i] = j < m ? B[i * m + j] : h[i];
            for (int i = 0; i < n * n; i++) Dc[i] = D[i];
            wk_solve_inplace(Dc, col, n);
        }
        double A[WK_CONTROL_MAX_N * WK_CONTROL_MAX_N];
        double rhs[WK_CONTROL_MAX_N];
        for (int i = 0; i < m * m; i++) A[i] = 0.0;
        for (int i = 0; i < m; i++) {
            double r = -kp * y[i] - kd * yd[i] - cterm[i];
            for (int k = 0; k < n; k++) {
                for (int j = 0; j < m; j++) A[i * m + j] += H[i * n + k] * X[j * n + k];
                r += H[i * n + k] * X[m * n + k];
            }
            rhs[i] = r;
        }
        wk_solve_inplace(A, rhs, m);
        for (int i = 0; i < m; i++) u[i] = rhs[i];
    }
    double limit = c[WK_CONTROL_I_LIMIT];
    int saturated = 0;
    for (int i = 0; i < m; i++) {
        if (u[i] > limit) {
            u[i] = limit;
            saturated = 1;
        } else if (u[i] < -limit) {
            u[i] = -limit;
            saturated = 1;
        }
    }
    return saturated;
}
