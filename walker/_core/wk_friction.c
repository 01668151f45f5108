/* Dry joint friction: C port of walker/models/friction.py; see wk_friction.h. */
#include <math.h>
#include <string.h>
#include "wk_common.h"
#include "wk_friction.h"

static int sizes_ok(int n, int m)
{
    return n >= 0 && m >= 0 && n <= WK_FRICTION_MAX_N && m <= WK_FRICTION_MAX_JOINTS;
}

int64_t wk_friction_encode(const int64_t *modes, int m)
{
    int64_t code = 0;
    int64_t scale = 1;
    for (int j = 0; j < m; j++) {
        code += modes[j] * scale;
        scale *= WK_N_MODES;
    }
    return code;
}

void wk_friction_decode(int64_t code, int64_t *modes, int m)
{
    for (int j = 0; j < m; j++) {
        int64_t r = code % WK_N_MODES;
        if (r < 0) r += WK_N_MODES;
        modes[j] = r;
        code = (code - r) / WK_N_MODES;
    }
}

double wk_friction_slip_torque(int64_t mode, double F)
{
    if (mode == WK_SLIP_POSITIVE) return -F;
    if (mode == WK_SLIP_NEGATIVE) return F;
    return 0.0;
}

int wk_friction_system(const double *D, const double *S, const int64_t *modes, int n, int m,
                       double *A)
{
    if (!sizes_ok(n, m)) return 0;
    int k = 0;
    for (int j = 0; j < m; j++) {
        if (modes[j] == WK_STICK) k += 1;
    }
    const int N = n + k;
    for (int i = 0; i < N * N; i++) A[i] = 0.0;
    for (int i = 0; i < n; i++) {
        for (int c = 0; c < n; c++) A[i * N + c] = D[i * n + c];
    }
    int r = n;
    for (int j = 0; j < m; j++) {
        if (modes[j] == WK_STICK) {
            for (int i = 0; i < n; i++) {
                A[i * N + r] = -S[j * n + i];
                A[r * N + i] = S[j * n + i];
            }
            r += 1;
        }
    }
    return N;
}

int wk_friction_accelerations(const double *D, const double *f, const double *S,
                              const double *F, const int64_t *modes, int n, int m,
                              double *qdd, double *lam)
{
    double A[WK_FRICTION_MAX_SYSTEM * WK_FRICTION_MAX_SYSTEM];
    double b[WK_FRICTION_MAX_SYSTEM];
    if (!sizes_ok(n, m)) return 0;
    const int N = wk_friction_system(D, S, modes, n, m, A);
    for (int i = 0; i < N; i++) b[i] = 0.0;
    for (int i = 0; i < n; i++) b[i] = f[i];
    for (int j = 0; j < m; j++) {
        double tau = wk_friction_slip_torque(modes[j], F[j]);
        if (tau != 0.0) {
            for (int i = 0; i < n; i++) b[i] += S[j * n + i] * tau;
        }
    }
    int ok = wk_solve_inplace(A, b, N);
    for (int i = 0; i < n; i++) qdd[i] = b[i];
    int r = n;
    for (int j = 0; j < m; j++) {
        if (modes[j] == WK_STICK) {
            lam[j] = b[r];
            r += 1;
        } else {
            lam[j] = wk_friction_slip_torque(modes[j], F[j]);
        }
    }
    return ok;
}

int wk_friction_slip_force(const double *S, const double *F, const int64_t *modes, int n,
                           int m, double *out)
{
    for (int j = 0; j < m; j++) {
        if (modes[j] == WK_STICK) return 0;
    }
    int any_force = 0;
    for (int i = 0; i < n; i++) out[i] = 0.0;
    for (int j = 0; j < m; j++) {
        double tau = wk_friction_slip_torque(modes[j], F[j]);
        if (tau != 0.0) {
            any_force = 1;
            for (int i = 0; i < n; i++) out[i] += S[j * n + i] * tau;
        }
    }
    return any_force ? 1 : -1;
}

int wk_friction_accelerations_jacobian(const double *D, const double *dD, const double *df_dq,
                                       const double *df_dqd, const double *S,
                                       const int64_t *modes, const double *qdd, int n, int m,
                                       double *out)
{
    double A[WK_FRICTION_MAX_SYSTEM * WK_FRICTION_MAX_SYSTEM];
    double R[WK_FRICTION_MAX_SYSTEM * 2 * WK_FRICTION_MAX_N];
    if (!sizes_ok(n, m)) return 0;
    const int N = wk_friction_system(D, S, modes, n, m, A);
    const int nc = 2 * n;
    for (int i = 0; i < N * nc; i++) R[i] = 0.0;
    for (int k = 0; k < n; k++) {
        for (int i = 0; i < n; i++) {
            double s = df_dq[i * n + k];
            for (int c = 0; c < n; c++) s -= dD[(k * n + i) * n + c] * qdd[c];
            R[i * nc + k] = s;
            R[i * nc + n + k] = df_dqd[i * n + k];
        }
    }
    int ok = wk_solve_columns(A, R, N, nc);
    for (int i = 0; i < n; i++) {
        for (int c = 0; c < nc; c++) out[i * nc + c] = R[i * nc + c];
    }
    return ok;
}

int wk_friction_consistent(const double *D, const double *f, const double *S, const double *F,
                           const int64_t *modes, const bool *rest, bool strict, int n, int m,
                           double *qdd, double *lam)
{
    if (!wk_friction_accelerations(D, f, S, F, modes, n, m, qdd, lam)) return 0;
    for (int j = 0; j < m; j++) {
        if (modes[j] == WK_STICK) {
            if (strict) {
                if (!(fabs(lam[j]) < F[j])) return 0;
            } else if (!(fabs(lam[j]) <= F[j])) {
                return 0;
            }
        } else if (rest[j]) {
            double wd = 0.0;
            for (int i = 0; i < n; i++) wd += S[j * n + i] * qdd[i];
            if (modes[j] == WK_SLIP_NEGATIVE) wd = -wd;
            if (strict) {
                if (!(wd > 0.0)) return 0;
            } else if (!(wd >= 0.0)) {
                return 0;
            }
        }
    }
    return 1;
}

int wk_friction_choose_modes(const double *D, const double *f, const double *S,
                             const double *F, const double *qd, const bool *free_joints,
                             int n, int m, int64_t *modes)
{
    bool rest[WK_FRICTION_MAX_JOINTS];
    int idx[WK_FRICTION_MAX_JOINTS];
    double qdd[WK_FRICTION_MAX_N];
    double lam[WK_FRICTION_MAX_JOINTS];
    if (!sizes_ok(n, m)) return 0;
    int r = 0;
    for (int j = 0; j < m; j++) {
        rest[j] = false;
        if (!free_joints[j]) continue;
        double w = 0.0;
        for (int i = 0; i < n; i++) w += S[j * n + i] * qd[i];
        if (w > WK_FRICTION_W_TOL) {
            modes[j] = WK_SLIP_POSITIVE;
        } else if (w < -WK_FRICTION_W_TOL) {
            modes[j] = WK_SLIP_NEGATIVE;
        } else {
            rest[j] = true;
            idx[r] = j;
            r += 1;
        }
    }
    if (r == 0) return 1;
    int total = 1;
    for (int a = 0; a < r; a++) total *= WK_N_MODES;
    for (int pass = 0; pass < 2; pass++) {
        bool strict = pass == 0;
        /* Stick first (digit 2 -> 0 order), so a tie prefers the joint at rest to stay. */
        for (int c = 0; c < total; c++) {
            int code = c;
            bool skip = false;
            for (int a = 0; a < r; a++) {
                int mode = WK_N_MODES - 1 - code % WK_N_MODES;
                code /= WK_N_MODES;
                int j = idx[a];
                if (mode == WK_STICK && !(F[j] > 0.0)) skip = true;
                modes[j] = mode;
            }
            if (skip) continue;
            if (wk_friction_consistent(D, f, S, F, modes, rest, strict, n, m, qdd, lam))
                return 1;
        }
    }
    for (int a = 0; a < r; a++) modes[idx[a]] = WK_SLIP_POSITIVE;
    return 0;
}

int wk_friction_project_stuck(const double *D, const double *S, const int64_t *modes,
                              const double *qd, int n, int m, double *qd_out)
{
    double A[WK_FRICTION_MAX_SYSTEM * WK_FRICTION_MAX_SYSTEM];
    double b[WK_FRICTION_MAX_SYSTEM];
    if (!sizes_ok(n, m)) return 0;
    const int N = wk_friction_system(D, S, modes, n, m, A);
    for (int i = 0; i < N; i++) b[i] = 0.0;
    for (int i = 0; i < n; i++) {
        double s = 0.0;
        for (int c = 0; c < n; c++) s += D[i * n + c] * qd[c];
        b[i] = s;
    }
    int ok = wk_solve_inplace(A, b, N);
    for (int i = 0; i < n; i++) qd_out[i] = b[i];
    return ok;
}

int wk_friction_settle(const double *D, const double *f, const double *S, const double *F,
                       const double *qd, const bool *free_joints, int n, int m,
                       int64_t *modes, double *qd_out)
{
    if (!sizes_ok(n, m)) return 0;
    wk_friction_choose_modes(D, f, S, F, qd, free_joints, n, m, modes);
    for (int j = 0; j < m; j++) {
        if (modes[j] == WK_STICK) return wk_friction_project_stuck(D, S, modes, qd, n, m, qd_out);
    }
    for (int i = 0; i < n; i++) qd_out[i] = qd[i];
    return 1;
}

int wk_friction_switch(const double *D, const double *f, const double *S, const double *F,
                       const double *qd, int64_t j, bool breaks, int n, int m,
                       int64_t *modes, double *qd_out)
{
    bool free_joints[WK_FRICTION_MAX_JOINTS];
    if (!sizes_ok(n, m) || j < 0 || j >= m) return 0;
    for (int i = 0; i < m; i++) free_joints[i] = true;
    if (!breaks) {
        int64_t only[WK_FRICTION_MAX_JOINTS];
        double locked[WK_FRICTION_MAX_N];
        for (int i = 0; i < m; i++) only[i] = WK_SLIP_POSITIVE;
        only[j] = WK_STICK;
        if (!wk_friction_project_stuck(D, S, only, qd, n, m, locked)) return 0;
        return wk_friction_settle(D, f, S, F, locked, free_joints, n, m, modes, qd_out);
    }
    double qdd[WK_FRICTION_MAX_N];
    double lam[WK_FRICTION_MAX_JOINTS];
    if (!wk_friction_accelerations(D, f, S, F, modes, n, m, qdd, lam)) return 0;
    modes[j] = lam[j] > 0.0 ? WK_SLIP_NEGATIVE : WK_SLIP_POSITIVE;
    free_joints[j] = false;
    return wk_friction_settle(D, f, S, F, qd, free_joints, n, m, modes, qd_out);
}

void wk_friction_guards(const double *S, const double *F, const int64_t *modes,
                        const double *qd, const double *lam, int n, int m, double *g)
{
    for (int j = 0; j < m; j++) {
        if (modes[j] == WK_STICK) {
            g[2 * j] = 1.0;
            g[2 * j + 1] = fabs(lam[j]) - F[j];
        } else if (!(F[j] > 0.0)) {
            g[2 * j] = 1.0;
            g[2 * j + 1] = 1.0;
        } else {
            double w = 0.0;
            for (int i = 0; i < n; i++) w += S[j * n + i] * qd[i];
            g[2 * j] = w;
            g[2 * j + 1] = 1.0;
        }
    }
}

void wk_friction_dynamics(const wk_friction_kernels *K, const double *x, const double *p,
                          double *D, double *f, double *qd)
{
    const int n = K->n;
    double h[WK_FRICTION_MAX_N];
    for (int i = 0; i < n; i++) qd[i] = x[K->v0 + i];
    K->mass_matrix(x, p, D);
    K->bias(x, qd, p, h);
    K->forcing(x, qd, p, f);
    for (int i = 0; i < n; i++) f[i] -= h[i];
}

int wk_friction_phase_solve(const wk_friction_kernels *K, const double *F,
                            const int64_t *modes, const double *x, const double *p,
                            double *qdd, double *lam)
{
    double D[WK_FRICTION_MAX_N * WK_FRICTION_MAX_N], f[WK_FRICTION_MAX_N];
    double qd[WK_FRICTION_MAX_N];
    if (!sizes_ok(K->n, K->m)) return 0;
    wk_friction_dynamics(K, x, p, D, f, qd);
    return wk_friction_accelerations(D, f, K->S, F, modes, K->n, K->m, qdd, lam);
}

void wk_friction_phase_accelerations(const wk_friction_kernels *K, const double *F,
                                     const int64_t *modes, const double *x, const double *p,
                                     double *qdd)
{
    const int n = K->n;
    double Q[WK_FRICTION_MAX_N];
    if (!sizes_ok(n, K->m)) return;
    int kind = wk_friction_slip_force(K->S, F, modes, n, K->m, Q);
    if (kind == 0) { /* a joint sticks: the augmented system */
        double lam[WK_FRICTION_MAX_JOINTS];
        wk_friction_phase_solve(K, F, modes, x, p, qdd, lam);
        return;
    }
    /* the fused kernel (viscous dampers included) plus D^-1 of the slip torques */
    K->accel(x, x + K->v0, p, qdd);
    if (kind > 0) {
        double D[WK_FRICTION_MAX_N * WK_FRICTION_MAX_N];
        K->mass_matrix(x, p, D);
        wk_solve_inplace(D, Q, n);
        for (int i = 0; i < n; i++) qdd[i] += Q[i];
    }
}

int wk_friction_phase_jacobian(const wk_friction_kernels *K, const double *F,
                               const int64_t *modes, const double *x, const double *p,
                               double *a)
{
    enum { N = WK_FRICTION_MAX_N };
    const int n = K->n;
    double D[N * N], f[N], qd[N], qdd[N], lam[WK_FRICTION_MAX_JOINTS];
    double dD[N * N * N], df_dq[N * N], dh_dqd[N * N], df_dqd[N * N];
    double unit[N], col[N];
    if (!sizes_ok(n, K->m)) return 0;
    wk_friction_dynamics(K, x, p, D, f, qd);
    wk_friction_accelerations(D, f, K->S, F, modes, n, K->m, qdd, lam);
    K->dmass(x, p, dD);
    K->dbias_dq(x, qd, p, df_dq);
    K->dbias_dqd(x, qd, p, dh_dqd);
    for (int k = 0; k < n; k++) {
        /* The viscous forcing is linear in qd and independent of q: probe its columns. */
        for (int i = 0; i < n; i++) unit[i] = 0.0;
        unit[k] = 1.0;
        K->forcing(x, unit, p, col);
        for (int i = 0; i < n; i++) {
            df_dqd[i * n + k] = col[i] - dh_dqd[i * n + k];
            df_dq[i * n + k] = -df_dq[i * n + k];
        }
    }
    return wk_friction_accelerations_jacobian(D, dD, df_dq, df_dqd, K->S, modes, qdd, n, K->m,
                                              a);
}

void wk_friction_phase_guards(const wk_friction_kernels *K, const double *F,
                              const int64_t *modes, const double *x, const double *p,
                              double *g)
{
    double lam[WK_FRICTION_MAX_JOINTS] = {0.0};
    bool stuck = false;
    if (!sizes_ok(K->n, K->m)) return;
    for (int j = 0; j < K->m; j++) stuck = stuck || modes[j] == WK_STICK;
    if (stuck) { /* the holding torques; otherwise the guards need the rates only */
        double qdd[WK_FRICTION_MAX_N];
        wk_friction_phase_solve(K, F, modes, x, p, qdd, lam);
    }
    wk_friction_guards(K->S, F, modes, x + K->v0, lam, K->n, K->m, g);
}

int wk_friction_phase_settle(const wk_friction_kernels *K, const double *F, int64_t *modes,
                             double *x, const double *p)
{
    enum { N = WK_FRICTION_MAX_N };
    double D[N * N], f[N], qd[N], qd_new[N];
    bool free_joints[WK_FRICTION_MAX_JOINTS];
    if (!sizes_ok(K->n, K->m)) return 0;
    for (int j = 0; j < K->m; j++) free_joints[j] = true;
    wk_friction_dynamics(K, x, p, D, f, qd);
    if (!wk_friction_settle(D, f, K->S, F, qd, free_joints, K->n, K->m, modes, qd_new)) return 0;
    for (int i = 0; i < K->n; i++) x[K->v0 + i] = qd_new[i];
    return 1;
}

int wk_friction_phase_switch(const wk_friction_kernels *K, const double *F, int64_t *modes,
                             int64_t k, const double *x, const double *p, double *x_new)
{
    enum { N = WK_FRICTION_MAX_N };
    double D[N * N], f[N], qd[N], qd_new[N];
    if (!sizes_ok(K->n, K->m)) return 0;
    wk_friction_dynamics(K, x, p, D, f, qd);
    if (!wk_friction_switch(D, f, K->S, F, qd, k / 2, k % 2 == 1, K->n, K->m, modes, qd_new))
        return 0;
    for (int i = 0; i < K->n; i++) x_new[K->v0 + i] = qd_new[i];
    return 1;
}

void wk_friction_first_order(const double *x, const double *qdd, int n, double *dx)
{
    for (int i = 0; i < n; i++) {
        dx[i] = x[n + i];
        dx[n + i] = qdd[i];
    }
}

void wk_friction_first_order_jacobian(const double *a, int n, double *J)
{
    const int nx = 2 * n;
    for (int i = 0; i < nx * nx; i++) J[i] = 0.0;
    for (int i = 0; i < n; i++) {
        J[i * nx + n + i] = 1.0;
        for (int c = 0; c < nx; c++) J[(n + i) * nx + c] = a[i * nx + c];
    }
}

void wk_friction_phase_rhs(const wk_friction_kernels *K, const double *F, int64_t code,
                           const double *x, const double *p, double *dx)
{
    int64_t modes[WK_FRICTION_MAX_JOINTS];
    double qdd[WK_FRICTION_MAX_N];
    if (!sizes_ok(K->n, K->m)) return;
    wk_friction_decode(code, modes, K->m);
    wk_friction_phase_accelerations(K, F, modes, x, p, qdd);
    wk_friction_first_order(x, qdd, K->n, dx);
}

void wk_friction_phase_jac(const wk_friction_kernels *K, const double *F, int64_t code,
                           const double *x, const double *p, double *J)
{
    int64_t modes[WK_FRICTION_MAX_JOINTS];
    double a[WK_FRICTION_MAX_N * 2 * WK_FRICTION_MAX_N];
    if (!sizes_ok(K->n, K->m)) return;
    wk_friction_decode(code, modes, K->m);
    wk_friction_phase_jacobian(K, F, modes, x, p, a);
    wk_friction_first_order_jacobian(a, K->n, J);
}

int64_t wk_friction_phase_start(const wk_friction_kernels *K, const double *F, int64_t *modes,
                                int64_t offset, double *x, const double *p)
{
    if (!wk_friction_phase_settle(K, F, modes, x, p)) return -1;
    return offset + wk_friction_encode(modes, K->m);
}

int wk_friction_phase_reset(const wk_friction_kernels *K, const double *F, int64_t *modes,
                            int64_t phase, int64_t offset, int64_t k, const double *x,
                            const double *p, double *x_new, int64_t *out)
{
    if (!wk_friction_phase_switch(K, F, modes, k, x, p, x_new)) {
        wk_reset_out(out, WK_EVENT_TERMINAL, phase, WK_LINEAR_SOLVE_FAILED);
        return 0;
    }
    wk_reset_out(out, WK_EVENT_CONTINUE, offset + wk_friction_encode(modes, K->m), 0);
    return 1;
}

void wk_friction_after_base_reset(wk_friction_start_fn start, int64_t phase, double *x_new,
                                  const double *p, int64_t *out)
{
    int64_t action = out[0], new_base = out[1], status = out[2];
    if (action == WK_EVENT_IGNORE || action == WK_EVENT_TERMINAL) {
        wk_reset_out(out, action, phase, status);
        return;
    }
    int64_t new_phase = start(new_base, x_new, p);
    if (new_phase < 0) {
        wk_reset_out(out, WK_EVENT_TERMINAL, phase, WK_LINEAR_SOLVE_FAILED);
        return;
    }
    wk_reset_out(out, action, new_phase, status);
}

void wk_friction_base_reset(wk_reset_fn walker_reset, wk_friction_start_fn start, int64_t base,
                            int64_t phase, int64_t k, double t, const double *x, const double *p,
                            double *x_new, double *impulse, int64_t *out, void *ctx)
{
    walker_reset(base, k, t, x, p, x_new, impulse, out, ctx);
    wk_friction_after_base_reset(start, phase, x_new, p, out);
}
