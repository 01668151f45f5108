/* The compass gait with dry friction at the stance ankle and the hip: C port of the
 * compiled functions of walker/models/compass_coulomb.py (same operations in the same
 * order).  State (q_stance, q_swing, qd_stance, qd_swing); phase = joint-mode code
 * ankle + 3 hip (wk_friction.h); guards heel_strike, fall_forward, fall_backward (the
 * compass gait's, model_compass.c), then per joint slip_stops and stick_breaks.  The phase
 * functions are wk_friction.c's over the compass gait's kernels. */
#include <stdbool.h>
#include <stddef.h>
#include "wk_common.h"
#include "wk_friction.h"
#include "wk_friction_models.h"
#include "compass.h"

#define I_COULOMB WK_COMPASS_COULOMB_P_COULOMB_ANKLE
#define N_JOINTS WK_COMPASS_COULOMB_N_JOINTS
#define N_BASE_GUARDS 3

/* Joint rows: ankle w = qd_stance, hip w = qd_swing - qd_stance. */
static const double S[2 * 2] = {1.0, 0.0, -1.0, 1.0};

static const wk_friction_kernels KERNELS = {
    2, N_JOINTS, 2, S,
    wk_compass_mass_matrix, wk_compass_bias, wk_compass_forcing, wk_compass_accel,
    wk_compass_dmass, wk_compass_dbias_dq, wk_compass_dbias_dqd,
};

/* rhs and jac (wk_friction.h). */
WK_FRICTION_ONE_BASE_FIELD(KERNELS, I_COULOMB)

/* The guards over the compass gait's guards walker_guards (its plane or terrain ones). */
static void guards_on(wk_guards_fn walker_guards, int64_t phase, double t, const double *x,
                      const double *p, double *g, void *ctx)
{
    int64_t modes[N_JOINTS];
    walker_guards(0, t, x, p, g, ctx);
    wk_friction_decode(phase, modes, N_JOINTS);
    wk_friction_phase_guards(&KERNELS, p + I_COULOMB, modes, x, p, g + N_BASE_GUARDS);
}

static void guards(int64_t phase, double t, const double *x, const double *p, double *g,
                   void *ctx)
{
    guards_on(wk_model_compass_guards, phase, t, x, p, g, ctx);
}

/* Chooses both joints' modes for state x (velocities projected in place onto the stuck
 * joints) and returns the phase; -1 if a solve is singular.  (One base phase: base is
 * unused.) */
static int64_t start(int64_t base, double *x, const double *p)
{
    (void)base;
    int64_t modes[N_JOINTS] = {0, 0};
    return wk_friction_phase_start(&KERNELS, p + I_COULOMB, modes, 0, x, p);
}

/* The reset over the compass gait's reset walker_reset (its plane or terrain one). */
static void reset_on(wk_reset_fn walker_reset, int64_t phase, int64_t k, double t,
                     const double *x, const double *p, double *x_new, double *impulse,
                     int64_t *out, void *ctx)
{
    if (k < N_BASE_GUARDS) {
        wk_friction_base_reset(walker_reset, start, 0, phase, k, t, x, p, x_new, impulse, out,
                               ctx);
        return;
    }
    int64_t modes[N_JOINTS];
    wk_friction_decode(phase, modes, N_JOINTS);
    wk_friction_phase_reset(&KERNELS, p + I_COULOMB, modes, phase, 0, k - N_BASE_GUARDS, x, p,
                            x_new, out);
}

static void reset(int64_t phase, int64_t k, double t, const double *x, const double *p,
                  double *x_new, double *impulse, int64_t *out, void *ctx)
{
    reset_on(wk_model_compass_reset, phase, k, t, x, p, x_new, impulse, out, ctx);
}

/* start_phase; energy and drawing points are the compass gait's (model_compass.c). */
WK_FRICTION_WALKER_ENTRY(compass_coulomb, compass, WK_COMPASS_COULOMB_N_X)

/* Terrain (wk_terrain.h): the compass gait's terrain guards and heel strike in place of its
 * plane ones; the friction guards and resets unchanged. */
#include "wk_terrain.h"

WK_FRICTION_WALKER_TERRAIN(compass_coulomb, compass, WK_COMPASS_COULOMB_P_SLOPE,
                           WK_COMPASS_COULOMB_P_FOOT_RADIUS, WK_COMPASS_COULOMB_N_P)
