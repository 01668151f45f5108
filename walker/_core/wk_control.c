/* Feedback controllers of the actuated walkers; see wk_control.h. */
#include <math.h>
#include <stddef.h>
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

/* Input-output linearization: u solves (H D^{-1} B) u = v - cterm + H D^{-1} h, for the
 * outputs' Jacobian H ((n - 1) x n) and their acceleration offset cterm (n - 1). */
static void io_linearize(const double *D, const double *h, const double *B, const double *H,
                         const double *v, const double *cterm, double *u, int n)
{
    const int m = n - 1;
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
        double r = v[i] - cterm[i];
        for (int k = 0; k < n; k++) {
            for (int j = 0; j < m; j++) A[i * m + j] += H[i * n + k] * X[j * n + k];
            r += H[i * n + k] * X[m * n + k];
        }
        rhs[i] = r;
    }
    wk_solve_inplace(A, rhs, m);
    for (int i = 0; i < m; i++) u[i] = rhs[i];
}

/* Clips u (m) to [-limit, limit]; returns 1 if some component was clipped. */
static int saturate(double *u, double limit, int m)
{
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
        double v[WK_CONTROL_MAX_N];
        for (int i = 0; i < m; i++) v[i] = -kp * y[i] - kd * yd[i];
        io_linearize(D, h, B, H, v, cterm, u, n);
    }
    return saturate(u, c[WK_CONTROL_I_LIMIT], m);
}

/* sgn(x) |x|^e (0 at x = 0). */
static double sig(double x, double e)
{
    if (x == 0.0) return 0.0;
    return copysign(pow(fabs(x), e), x);
}

/* P(x) = sum_k a[k] x^k (degree WK_CONTROL_POLY_DEGREE) and its first two derivatives, by
 * Horner's rule. */
static void polynomial(const double *a, double x, double *p0, double *p1, double *p2)
{
    double v = 0.0, d1 = 0.0, d2 = 0.0;
    for (int k = WK_CONTROL_POLY_DEGREE; k >= 0; k--) {
        d2 = d2 * x + 2.0 * d1;
        d1 = d1 * x + v;
        v = v * x + a[k];
    }
    *p0 = v;
    *p1 = d1;
    *p2 = d2;
}

/* The outputs of the finite-time controller (y, yd, H, cterm) at (q, qd). */
static void ft_outputs(const double *q, const double *qd, const double *f, double *y,
                       double *yd, double *H, double *cterm, int n)
{
    const int M1 = WK_CONTROL_POLY_DEGREE + 1;
    for (int i = 0; i < n - 1; i++) {
        double P, P1, P2;
        polynomial(f + WK_CONTROL_FT_I_POLY + i * M1, q[0], &P, &P1, &P2);
        y[i] = q[i + 1] - P;
        yd[i] = qd[i + 1] - P1 * qd[0];
        for (int j = 0; j < n; j++) H[i * n + j] = 0.0;
        H[i * n + 0] = -P1;
        H[i * n + i + 1] = 1.0;
        cterm[i] = -P2 * qd[0] * qd[0];
    }
}

/* Bhat-Bernstein on the time scale epsilon: the output acceleration v(y, yd). */
static double ft_v(double y, double yd, double alpha, double eps)
{
    double ey = eps * yd;
    double phi = y + sig(ey, 2.0 - alpha) / (2.0 - alpha);
    double psi = -sig(ey, alpha) - sig(phi, alpha / (2.0 - alpha));
    return psi / (eps * eps);
}

static int ft_torque(const double *q, const double *qd, const double *D, const double *h,
                     const double *B, const double *c, const double *f, const double *lin,
                     double *u, int n)
{
    const int m = n - 1;
    const double alpha = f[WK_CONTROL_FT_I_ALPHA];
    const double eps = f[WK_CONTROL_FT_I_EPSILON];
    double H[WK_CONTROL_MAX_N * WK_CONTROL_MAX_N];
    double y[WK_CONTROL_MAX_N], yd[WK_CONTROL_MAX_N];
    double v[WK_CONTROL_MAX_N] = {0.0}; /* entries [0, m) set below */
    double cterm[WK_CONTROL_MAX_N];
    ft_outputs(q, qd, f, y, yd, H, cterm, n);
    for (int i = 0; i < m; i++) {
        if (lin == NULL) {
            v[i] = ft_v(y[i], yd[i], alpha, eps);
        } else {
            const double *L = lin + 5 * i;
            v[i] = L[0] + L[1] * (y[i] - L[3]) + L[2] * (yd[i] - L[4]);
        }
    }
    io_linearize(D, h, B, H, v, cterm, u, n);
    return saturate(u, c[WK_CONTROL_I_LIMIT], m);
}

int wk_control_finite_time_torque(const double *q, const double *qd, const double *D,
                                  const double *h, const double *B, const double *c,
                                  const double *f, double *u, int n)
{
    return ft_torque(q, qd, D, h, B, c, f, NULL, u, n);
}

int wk_control_finite_time_torque_linearized(const double *q, const double *qd,
                                             const double *D, const double *h,
                                             const double *B, const double *c,
                                             const double *f, const double *lin, double *u,
                                             int n)
{
    return ft_torque(q, qd, D, h, B, c, f, lin, u, n);
}

void wk_control_finite_time_linearization(const double *q, const double *qd, const double *f,
                                          double *lin, int n)
{
    const double alpha = f[WK_CONTROL_FT_I_ALPHA];
    const double eps = f[WK_CONTROL_FT_I_EPSILON];
    const double r = alpha / (2.0 - alpha);
    double H[WK_CONTROL_MAX_N * WK_CONTROL_MAX_N];
    double y[WK_CONTROL_MAX_N], yd[WK_CONTROL_MAX_N], cterm[WK_CONTROL_MAX_N];
    ft_outputs(q, qd, f, y, yd, H, cterm, n);
    for (int i = 0; i < n - 1; i++) {
        double ey = eps * yd[i];
        double phi = y[i] + sig(ey, 2.0 - alpha) / (2.0 - alpha);
        double aey = fmax(fabs(ey), WK_CONTROL_FT_JAC_FLOOR);
        double aphi = fmax(fabs(phi), WK_CONTROL_FT_JAC_FLOOR);
        /* dpsi/dy and dpsi/d(eps yd), the singular powers floored */
        double dpsi_dy = -r * pow(aphi, r - 1.0);
        double dpsi_de = -alpha * pow(aey, alpha - 1.0) + dpsi_dy * pow(aey, 1.0 - alpha);
        double *L = lin + 5 * i;
        L[0] = ft_v(y[i], yd[i], alpha, eps);
        L[1] = dpsi_dy / (eps * eps);
        L[2] = dpsi_de / eps;
        L[3] = y[i];
        L[4] = yd[i];
    }
}
