/* The planar double pendulum with viscous and dry joint friction: C port of the compiled
 * functions of walker/models/double_pendulum.py (same operations in the same order).  State
 * (q1, q2, qd1, qd2); phase = joint-mode code joint_1 + 3 joint_2 (wk_friction.h); guards
 * per joint slip_stops and stick_breaks, no other events.  The phase functions are
 * wk_friction.c's over the pendulum's kernels. */
#include <stdbool.h>
#include <stddef.h>
#include "wk_common.h"
#include "wk_friction.h"
#include "wk_friction_models.h"
#include "double_pendulum.h"

#define I_COULOMB WK_DOUBLE_PENDULUM_P_COULOMB_1
#define N_JOINTS WK_DOUBLE_PENDULUM_N_JOINTS

/* Joint rows: w1 = qd1, w2 = qd2 (q2 is relative). */
static const double S[2 * 2] = {1.0, 0.0, 0.0, 1.0};

static const wk_friction_kernels KERNELS = {
    2, N_JOINTS, 2, S,
    wk_double_pendulum_mass_matrix, wk_double_pendulum_bias, wk_double_pendulum_forcing,
    wk_double_pendulum_accel, wk_double_pendulum_dmass, wk_double_pendulum_dbias_dq,
    wk_double_pendulum_dbias_dqd,
};

/* rhs and jac (wk_friction.h). */
WK_FRICTION_ONE_BASE_FIELD(KERNELS, I_COULOMB)

static void guards(int64_t phase, double t, const double *x, const double *p, double *g,
                   void *ctx)
{
    (void)t;
    (void)ctx;
    int64_t modes[N_JOINTS];
    wk_friction_decode(phase, modes, N_JOINTS);
    wk_friction_phase_guards(&KERNELS, p + I_COULOMB, modes, x, p, g);
}

static void reset(int64_t phase, int64_t k, double t, const double *x, const double *p,
                  double *x_new, double *impulse, int64_t *out, void *ctx)
{
    (void)t;
    (void)ctx;
    for (int i = 0; i < 4; i++) x_new[i] = x[i];
    impulse[0] = 0.0;
    int64_t modes[N_JOINTS];
    wk_friction_decode(phase, modes, N_JOINTS);
    wk_friction_phase_reset(&KERNELS, p + I_COULOMB, modes, phase, 0, k, x, p, x_new, out);
}

/* The phase consistent with state x (walker.models.double_pendulum.start_phase). */
static void start_phase(const double *x, const double *p, double *out, void *ctx)
{
    (void)ctx;
    double y[4] = {x[0], x[1], x[2], x[3]};
    int64_t modes[N_JOINTS] = {0, 0};
    out[0] = (double)wk_friction_phase_start(&KERNELS, p + I_COULOMB, modes, 0, y, p);
}

/* (kinetic, potential) [J]. */
static void energy(const double *x, const double *p, double *out, void *ctx)
{
    (void)ctx;
    out[0] = wk_double_pendulum_kinetic(x, x + 2, p);
    out[1] = wk_double_pendulum_potential(x, p);
}

/* Base, elbow, tip [m], out (3, 2). */
static void points(const double *x, const double *p, double *out, void *ctx)
{
    (void)ctx;
    out[0] = 0.0;
    out[1] = 0.0;
    wk_double_pendulum_points(x, p, out + 2);
}

const wk_model_entry wk_entry_double_pendulum = {
    WK_ENTRY_NAME_double_pendulum, {rhs, guards, reset, jac, NULL}, energy, points, start_phase,
};
