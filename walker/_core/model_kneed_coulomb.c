/* The kneed walker with dry friction at the stance ankle, the hip and the swing knee: C port
 * of the compiled functions of walker/models/kneed_coulomb.py (same operations in the same
 * order).  State (q1, q2, q3, qd1, qd2, qd3); phases 0..26 unlocked with the mode code
 * ankle + 3 hip + 9 knee, 27..35 locked (q3 = q2, qd3 = qd2 kept exactly) with the code
 * ankle + 3 hip (wk_friction.h); guards knee_lock, swing_foot_contact, fall_forward,
 * fall_backward (the kneed walker's, model_kneed.c), then per joint slip_stops and
 * stick_breaks. */
#include <stdbool.h>
#include <stddef.h>
#include "wk_common.h"
#include "wk_friction.h"
#include "wk_friction_models.h"
#include "kneed.h"

#define I_COULOMB 17
#define N_UNLOCKED 27
#define UNLOCKED 0
#define LOCKED 1
#define N_BASE_GUARDS 4

/* Joint rows: ankle w = qd1, hip w = qd2 - qd1, knee w = qd3 - qd2 (unlocked only). */
static const double S_UNLOCKED[3 * 3] = {1.0, 0.0, 0.0, -1.0, 1.0, 0.0, 0.0, -1.0, 1.0};
static const double S_LOCKED[2 * 2] = {1.0, 0.0, -1.0, 1.0};

/* Base phase of phase; modes (3,) receives the joint modes (the locked knee reads as
 * WK_STICK). */
static int split(int64_t phase, int64_t *modes)
{
    if (phase < N_UNLOCKED) {
        wk_friction_decode(phase, modes, 3);
        return UNLOCKED;
    }
    wk_friction_decode(phase - N_UNLOCKED, modes, 2);
    modes[2] = WK_STICK;
    return LOCKED;
}

static int64_t join(int base, const int64_t *modes)
{
    if (base == UNLOCKED) return wk_friction_encode(modes, 3);
    return N_UNLOCKED + wk_friction_encode(modes, 2);
}

/* Coordinates n (= joints) of a base phase. */
static int size_of(int base) { return base == UNLOCKED ? 3 : 2; }

static const double *rows_of(int base) { return base == UNLOCKED ? S_UNLOCKED : S_LOCKED; }

/* D (n x n), f = Q_viscous - C qd - g (n,) and qd (n,) of the base phase. */
static void matrices(int base, const double *x, const double *p, double *D, double *f,
                     double *qd)
{
    const double *q = x;
    double h[3];
    if (base == UNLOCKED) {
        for (int i = 0; i < 3; i++) qd[i] = x[3 + i];
        wk_kneed_unlocked_mass_matrix(q, p, D);
        wk_kneed_unlocked_bias(q, qd, p, h);
        wk_kneed_unlocked_forcing(q, qd, p, f);
        for (int i = 0; i < 3; i++) f[i] -= h[i];
        return;
    }
    for (int i = 0; i < 2; i++) qd[i] = x[3 + i];
    wk_kneed_locked_mass_matrix(q, p, D);
    wk_kneed_locked_bias(q, qd, p, h);
    wk_kneed_locked_forcing(q, qd, p, f);
    for (int i = 0; i < 2; i++) f[i] -= h[i];
}

static int solve(int base, const int64_t *modes, const double *x, const double *p,
                 double *qdd, double *lam)
{
    double D[3 * 3], f[3], qd[3];
    matrices(base, x, p, D, f, qd);
    int n = size_of(base);
    return wk_friction_accelerations(D, f, rows_of(base), p + I_COULOMB, modes, n, n, qdd,
                                     lam);
}

/* Accelerations when no joint sticks: the fused generated kernel (viscous dampers
 * included) plus D^-1 of the slip torques; 0 when some joint sticks. */
static int fast_accel(int base, const int64_t *modes, const double *x, const double *p,
                      double *qdd)
{
    int n = size_of(base);
    double Q[3];
    int kind = wk_friction_slip_force(rows_of(base), p + I_COULOMB, modes, n, n, Q);
    if (kind == 0) return 0;
    if (base == UNLOCKED) {
        wk_kneed_unlocked_accel(x, x + 3, p, qdd);
        if (kind > 0) {
            double D[3 * 3];
            wk_kneed_unlocked_mass_matrix(x, p, D);
            wk_solve_inplace(D, Q, 3);
        }
    } else {
        wk_kneed_locked_accel(x, x + 3, p, qdd);
        if (kind > 0) {
            double D[2 * 2];
            wk_kneed_locked_mass_matrix(x, p, D);
            wk_solve_inplace(D, Q, 2);
        }
    }
    if (kind > 0) {
        for (int i = 0; i < n; i++) qdd[i] += Q[i];
    }
    return 1;
}

static void rhs(int64_t phase, double t, const double *x, const double *p, double *dx,
                void *ctx)
{
    (void)t;
    (void)ctx;
    int64_t modes[3];
    int base = split(phase, modes);
    double qdd[3];
    if (!fast_accel(base, modes, x, p, qdd)) {
        double lam[3];
        solve(base, modes, x, p, qdd, lam);
    }
    dx[0] = x[3];
    dx[1] = x[4];
    if (base == UNLOCKED) {
        dx[2] = x[5];
        dx[3] = qdd[0];
        dx[4] = qdd[1];
        dx[5] = qdd[2];
    } else {
        dx[2] = x[4];
        dx[3] = qdd[0];
        dx[4] = qdd[1];
        dx[5] = qdd[1];
    }
}

static void jac(int64_t phase, double t, const double *x, const double *p, double *J,
                void *ctx)
{
    (void)t;
    (void)ctx;
    int64_t modes[3];
    int base = split(phase, modes);
    double D[3 * 3], f[3], qd[3];
    matrices(base, x, p, D, f, qd);
    const int n = size_of(base);
    const double *S = rows_of(base);
    double qdd[3], lam[3];
    wk_friction_accelerations(D, f, S, p + I_COULOMB, modes, n, n, qdd, lam);
    const double *q = x;
    double dD[3 * 3 * 3], dh_dq[3 * 3], dh_dqd[3 * 3], df_dqd[3 * 3];
    double unit[3] = {0.0, 0.0, 0.0}, col[3];
    for (int k = 0; k < n; k++) {
        /* The viscous forcing is linear in qd and independent of q: probe its columns. */
        for (int i = 0; i < n; i++) unit[i] = 0.0;
        unit[k] = 1.0;
        if (base == UNLOCKED)
            wk_kneed_unlocked_forcing(q, unit, p, col);
        else
            wk_kneed_locked_forcing(q, unit, p, col);
        for (int i = 0; i < n; i++) df_dqd[i * n + k] = col[i];
    }
    if (base == UNLOCKED) {
        wk_kneed_unlocked_dmass(q, p, dD);
        wk_kneed_unlocked_dbias_dq(q, qd, p, dh_dq);
        wk_kneed_unlocked_dbias_dqd(q, qd, p, dh_dqd);
    } else {
        wk_kneed_locked_dmass(q, p, dD);
        wk_kneed_locked_dbias_dq(q, qd, p, dh_dq);
        wk_kneed_locked_dbias_dqd(q, qd, p, dh_dqd);
    }
    for (int i = 0; i < n; i++) {
        for (int k = 0; k < n; k++) {
            dh_dq[i * n + k] = -dh_dq[i * n + k];
            df_dqd[i * n + k] -= dh_dqd[i * n + k];
        }
    }
    double a[3 * 6];
    wk_friction_accelerations_jacobian(D, dD, dh_dq, df_dqd, S, modes, qdd, n, n, a);
    for (int i = 0; i < 36; i++) J[i] = 0.0;
    J[0 * 6 + 3] = 1.0;
    J[1 * 6 + 4] = 1.0;
    if (base == UNLOCKED) {
        J[2 * 6 + 5] = 1.0;
        for (int i = 0; i < 3; i++) {
            for (int c = 0; c < 6; c++) J[(3 + i) * 6 + c] = a[i * 6 + c];
        }
        return;
    }
    /* Locked: (q1, q2, qd1, qd2) map to state columns 0, 1, 3, 4; q3, qd3 copy q2, qd2. */
    J[2 * 6 + 4] = 1.0;
    static const int cols[4] = {0, 1, 3, 4};
    for (int i = 0; i < 2; i++) {
        for (int c = 0; c < 4; c++) J[(3 + i) * 6 + cols[c]] = a[i * 4 + c];
    }
    for (int c = 0; c < 6; c++) J[5 * 6 + c] = J[4 * 6 + c];
}

static void guards(int64_t phase, double t, const double *x, const double *p, double *g,
                   void *ctx)
{
    int64_t modes[3];
    int base = split(phase, modes);
    wk_model_kneed_guards(base, t, x, p, g, ctx);
    const int m = size_of(base);
    double lam[3] = {0.0, 0.0, 0.0};
    bool stuck = false;
    for (int j = 0; j < m; j++) stuck = stuck || modes[j] == WK_STICK;
    if (stuck) { /* the holding torques; otherwise the guards need the rates only */
        double qdd[3];
        solve(base, modes, x, p, qdd, lam);
    }
    wk_friction_guards(rows_of(base), p + I_COULOMB, modes, x + 3, lam, m, m,
                       g + N_BASE_GUARDS);
    if (base == LOCKED) {
        g[8] = 1.0;
        g[9] = 1.0;
    }
}

static void write_rates(int base, const double *qd, double *x)
{
    for (int i = 0; i < size_of(base); i++) x[3 + i] = qd[i];
    if (base == LOCKED) x[5] = x[4];
}

/* Chooses every joint's mode for state x of base phase base (velocities projected in
 * place onto the stuck joints) and returns the phase; -1 if a solve is singular. */
static int64_t start(int base, double *x, const double *p)
{
    double D[3 * 3], f[3], qd[3], qd_new[3];
    matrices(base, x, p, D, f, qd);
    int64_t modes[3] = {0, 0, WK_STICK}; /* the locked knee (chosen below while unlocked) */
    const bool free_joints[3] = {true, true, true};
    const int n = size_of(base);
    if (!wk_friction_settle(D, f, rows_of(base), p + I_COULOMB, qd, free_joints, n, n, modes,
                            qd_new))
        return -1;
    write_rates(base, qd_new, x);
    return join(base, modes);
}

static void reset(int64_t phase, int64_t k, double t, const double *x, const double *p,
                  double *x_new, double *impulse, int64_t *out, void *ctx)
{
    int64_t modes[3];
    int base = split(phase, modes);
    if (k < N_BASE_GUARDS) {
        wk_model_kneed_reset(base, k, t, x, p, x_new, impulse, out, ctx);
        int64_t action = out[0], new_base = out[1], status = out[2];
        if (action == WK_EVENT_IGNORE || action == WK_EVENT_TERMINAL) {
            wk_reset_out(out, action, phase, status);
            return;
        }
        int64_t new_phase = start((int)new_base, x_new, p);
        if (new_phase < 0) {
            wk_reset_out(out, WK_EVENT_TERMINAL, phase, WK_LINEAR_SOLVE_FAILED);
            return;
        }
        wk_reset_out(out, action, new_phase, status);
        return;
    }
    double D[3 * 3], f[3], qd[3], qd_new[3];
    matrices(base, x, p, D, f, qd);
    const int n = size_of(base);
    int64_t j = (k - N_BASE_GUARDS) / 2;
    bool breaks = (k - N_BASE_GUARDS) % 2 == 1;
    if (!wk_friction_switch(D, f, rows_of(base), p + I_COULOMB, qd, j, breaks, n, n, modes,
                            qd_new)) {
        wk_reset_out(out, WK_EVENT_TERMINAL, phase, WK_LINEAR_SOLVE_FAILED);
        return;
    }
    write_rates(base, qd_new, x_new);
    wk_reset_out(out, WK_EVENT_CONTINUE, join(base, modes), 0);
}

/* The unlocked phase consistent with state x (walker.models.kneed_coulomb.start_phase). */
static void start_phase(const double *x, const double *p, double *out, void *ctx)
{
    (void)ctx;
    double y[6];
    for (int i = 0; i < 6; i++) y[i] = x[i];
    out[0] = (double)start(UNLOCKED, y, p);
}

/* Energy and drawing points are the kneed walker's (model_kneed.c). */
const wk_model_entry wk_entry_kneed_coulomb = {
    "kneed_coulomb",
    {rhs, guards, reset, jac, NULL},
    wk_model_kneed_energy,
    wk_model_kneed_points,
    start_phase,
};
