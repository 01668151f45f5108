/* The compass gait with dry friction at the stance ankle and the hip: C port of the
 * compiled functions of walker/models/compass_coulomb.py (same operations in the same
 * order).  State (q_stance, q_swing, qd_stance, qd_swing); phase = joint-mode code
 * ankle + 3 hip (wk_friction.h); guards heel_strike, fall_forward, fall_backward (the
 * compass gait's, model_compass.c), then per joint slip_stops and stick_breaks. */
#include <stdbool.h>
#include <stddef.h>
#include "wk_common.h"
#include "wk_friction.h"
#include "wk_friction_models.h"
#include "compass.h"

#define I_COULOMB 10
#define N_JOINTS 2
#define N_BASE_GUARDS 3

/* Joint rows: ankle w = qd_stance, hip w = qd_swing - qd_stance. */
static const double S[2 * 2] = {1.0, 0.0, -1.0, 1.0};

/* D, f = Q_viscous - C qd - g at state x (the dry frictions are p + I_COULOMB, the
 * velocities x + 2). */
static void matrices(const double *x, const double *p, double *D, double *f)
{
    const double *q = x;
    const double *qd = x + 2;
    double h[2];
    wk_compass_mass_matrix(q, p, D);
    wk_compass_bias(q, qd, p, h);
    wk_compass_forcing(q, qd, p, f);
    for (int i = 0; i < 2; i++) f[i] -= h[i];
}

static void rhs(int64_t phase, double t, const double *x, const double *p, double *dx,
                void *ctx)
{
    (void)t;
    (void)ctx;
    int64_t modes[N_JOINTS];
    double qdd[2], Q[2];
    wk_friction_decode(phase, modes, N_JOINTS);
    int kind = wk_friction_slip_force(S, p + I_COULOMB, modes, 2, N_JOINTS, Q);
    if (kind == 0) { /* a joint sticks: the augmented system */
        double D[2 * 2], f[2], lam[N_JOINTS];
        matrices(x, p, D, f);
        wk_friction_accelerations(D, f, S, p + I_COULOMB, modes, 2, N_JOINTS, qdd, lam);
    } else { /* the fused kernel (viscous dampers included) plus D^-1 of the slip torques */
        wk_compass_accel(x, x + 2, p, qdd);
        if (kind > 0) {
            double D[2 * 2];
            wk_compass_mass_matrix(x, p, D);
            wk_solve_inplace(D, Q, 2);
            qdd[0] += Q[0];
            qdd[1] += Q[1];
        }
    }
    dx[0] = x[2];
    dx[1] = x[3];
    dx[2] = qdd[0];
    dx[3] = qdd[1];
}

static void jac(int64_t phase, double t, const double *x, const double *p, double *J,
                void *ctx)
{
    (void)t;
    (void)ctx;
    const double *q = x;
    const double *qd = x + 2;
    double D[2 * 2], f[2], qdd[2], lam[N_JOINTS];
    int64_t modes[N_JOINTS];
    matrices(x, p, D, f);
    wk_friction_decode(phase, modes, N_JOINTS);
    wk_friction_accelerations(D, f, S, p + I_COULOMB, modes, 2, N_JOINTS, qdd, lam);
    double dD[2 * 2 * 2], df_dq[2 * 2], dh_dqd[2 * 2], df_dqd[2 * 2];
    wk_compass_dmass(q, p, dD);
    wk_compass_dbias_dq(q, qd, p, df_dq);
    wk_compass_dbias_dqd(q, qd, p, dh_dqd);
    double unit[2], col[2];
    for (int k = 0; k < 2; k++) {
        /* The viscous forcing is linear in qd and independent of q: probe its columns. */
        unit[0] = 0.0;
        unit[1] = 0.0;
        unit[k] = 1.0;
        wk_compass_forcing(q, unit, p, col);
        for (int i = 0; i < 2; i++) {
            df_dqd[i * 2 + k] = col[i] - dh_dqd[i * 2 + k];
            df_dq[i * 2 + k] = -df_dq[i * 2 + k];
        }
    }
    double a[2 * 4];
    wk_friction_accelerations_jacobian(D, dD, df_dq, df_dqd, S, modes, qdd, 2, N_JOINTS, a);
    for (int i = 0; i < 16; i++) J[i] = 0.0;
    J[0 * 4 + 2] = 1.0;
    J[1 * 4 + 3] = 1.0;
    for (int i = 0; i < 2; i++) {
        for (int c = 0; c < 4; c++) J[(2 + i) * 4 + c] = a[i * 4 + c];
    }
}

static void guards(int64_t phase, double t, const double *x, const double *p, double *g,
                   void *ctx)
{
    wk_model_compass_guards(0, t, x, p, g, ctx);
    int64_t modes[N_JOINTS];
    double lam[N_JOINTS] = {0.0, 0.0};
    wk_friction_decode(phase, modes, N_JOINTS);
    bool stuck = false;
    for (int j = 0; j < N_JOINTS; j++) stuck = stuck || modes[j] == WK_STICK;
    if (stuck) { /* the holding torques; otherwise the guards need the rates only */
        double D[2 * 2], f[2], qdd[2];
        matrices(x, p, D, f);
        wk_friction_accelerations(D, f, S, p + I_COULOMB, modes, 2, N_JOINTS, qdd, lam);
    }
    wk_friction_guards(S, p + I_COULOMB, modes, x + 2, lam, 2, N_JOINTS, g + N_BASE_GUARDS);
}

/* Chooses both joints' modes for state x (velocities projected in place onto the stuck
 * joints) and returns the phase; -1 if a solve is singular. */
static int64_t start(double *x, const double *p)
{
    double D[2 * 2], f[2], qd[2], qd_new[2];
    int64_t modes[N_JOINTS] = {0, 0};
    const bool free_joints[N_JOINTS] = {true, true};
    matrices(x, p, D, f);
    qd[0] = x[2];
    qd[1] = x[3];
    if (!wk_friction_settle(D, f, S, p + I_COULOMB, qd, free_joints, 2, N_JOINTS, modes,
                            qd_new))
        return -1;
    x[2] = qd_new[0];
    x[3] = qd_new[1];
    return wk_friction_encode(modes, N_JOINTS);
}

static void reset(int64_t phase, int64_t k, double t, const double *x, const double *p,
                  double *x_new, double *impulse, int64_t *out, void *ctx)
{
    if (k < N_BASE_GUARDS) {
        wk_model_compass_reset(0, k, t, x, p, x_new, impulse, out, ctx);
        int64_t action = out[0], status = out[2];
        if (action == WK_EVENT_IGNORE || action == WK_EVENT_TERMINAL) {
            wk_reset_out(out, action, phase, status);
            return;
        }
        int64_t new_phase = start(x_new, p);
        if (new_phase < 0) {
            wk_reset_out(out, WK_EVENT_TERMINAL, phase, WK_LINEAR_SOLVE_FAILED);
            return;
        }
        wk_reset_out(out, action, new_phase, status);
        return;
    }
    double D[2 * 2], f[2], qd[2], qd_new[2];
    int64_t modes[N_JOINTS];
    matrices(x, p, D, f);
    qd[0] = x[2];
    qd[1] = x[3];
    wk_friction_decode(phase, modes, N_JOINTS);
    int64_t j = (k - N_BASE_GUARDS) / 2;
    bool breaks = (k - N_BASE_GUARDS) % 2 == 1;
    if (!wk_friction_switch(D, f, S, p + I_COULOMB, qd, j, breaks, 2, N_JOINTS, modes,
                            qd_new)) {
        wk_reset_out(out, WK_EVENT_TERMINAL, phase, WK_LINEAR_SOLVE_FAILED);
        return;
    }
    x_new[2] = qd_new[0];
    x_new[3] = qd_new[1];
    wk_reset_out(out, WK_EVENT_CONTINUE, wk_friction_encode(modes, N_JOINTS), 0);
}

/* The phase consistent with state x (walker.models.compass_coulomb.start_phase). */
static void start_phase(const double *x, const double *p, double *out, void *ctx)
{
    (void)ctx;
    double y[4] = {x[0], x[1], x[2], x[3]};
    out[0] = (double)start(y, p);
}

/* Energy and drawing points are the compass gait's (model_compass.c). */
const wk_model_entry wk_entry_compass_coulomb = {
    "compass_coulomb",
    {rhs, guards, reset, jac, NULL},
    wk_model_compass_energy,
    wk_model_compass_points,
    start_phase,
};
