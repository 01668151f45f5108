/* The kneed walker with dry friction at the stance ankle, the hip and the swing knee: C port
 * of the compiled functions of walker/models/kneed_coulomb.py (same operations in the same
 * order).  State (q1, q2, q3, qd1, qd2, qd3); phases 0..26 unlocked with the mode code
 * ankle + 3 hip + 9 knee, 27..35 locked (q3 = q2, qd3 = qd2 kept exactly) with the code
 * ankle + 3 hip (wk_friction.h); guards knee_lock, swing_foot_contact, fall_forward,
 * fall_backward (the kneed walker's, model_kneed.c), then per joint slip_stops and
 * stick_breaks.  The phase functions are wk_friction.c's over the kernels of each base. */
#include <stdbool.h>
#include <stddef.h>
#include "wk_common.h"
#include "wk_friction.h"
#include "wk_friction_models.h"
#include "wk_kneed.h"
#include "kneed.h"

#define I_COULOMB WK_KNEED_COULOMB_P_COULOMB_ANKLE
#define N_UNLOCKED 27
#define UNLOCKED WK_KNEED_PHASE_UNLOCKED
#define LOCKED WK_KNEED_PHASE_LOCKED
#define N_BASE_GUARDS 4

/* Joint rows: ankle w = qd1, hip w = qd2 - qd1, knee w = qd3 - qd2 (unlocked only). */
static const double S_UNLOCKED[3 * 3] = {1.0, 0.0, 0.0, -1.0, 1.0, 0.0, 0.0, -1.0, 1.0};
static const double S_LOCKED[2 * 2] = {1.0, 0.0, -1.0, 1.0};

/* The kernels of each base phase: unlocked (3 coordinates and joints), locked (q1, q2); the
 * rates start at x[3] in both. */
static const wk_friction_kernels KERNELS[2] = {
    {3, 3, 3, S_UNLOCKED, wk_kneed_unlocked_mass_matrix, wk_kneed_unlocked_bias,
     wk_kneed_unlocked_forcing, wk_kneed_unlocked_accel, wk_kneed_unlocked_dmass,
     wk_kneed_unlocked_dbias_dq, wk_kneed_unlocked_dbias_dqd},
    {2, 2, 3, S_LOCKED, wk_kneed_locked_mass_matrix, wk_kneed_locked_bias,
     wk_kneed_locked_forcing, wk_kneed_locked_accel, wk_kneed_locked_dmass,
     wk_kneed_locked_dbias_dq, wk_kneed_locked_dbias_dqd},
};

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

/* wk_friction_phase_rhs over both base phases (K the table of both): in a locked phase the
 * locked walker's, q3 and qd3 copying q2 and qd2. */
static void phase_rhs(const wk_friction_kernels *K, const double *F, int64_t phase,
                      const double *x, const double *p, double *dx)
{
    int64_t modes[3];
    double qdd[2];
    if (split(phase, modes) == UNLOCKED) {
        wk_friction_phase_rhs(&K[UNLOCKED], F, phase, x, p, dx);
        return;
    }
    wk_friction_phase_accelerations(&K[LOCKED], F, modes, x, p, qdd);
    wk_kneed_locked_state(x + 3, qdd, dx);
}

/* wk_friction_phase_jac over both base phases: in a locked phase (q1, q2, qd1, qd2) map to
 * state columns 0, 1, 3, 4 and q3, qd3 copy q2, qd2. */
static void phase_jac(const wk_friction_kernels *K, const double *F, int64_t phase,
                      const double *x, const double *p, double *J)
{
    int64_t modes[3];
    double a[2 * 4];
    if (split(phase, modes) == UNLOCKED) {
        wk_friction_phase_jac(&K[UNLOCKED], F, phase, x, p, J);
        return;
    }
    wk_friction_phase_jacobian(&K[LOCKED], F, modes, x, p, a);
    for (int i = 0; i < 36; i++) J[i] = 0.0;
    wk_kneed_locked_jac(a, 4, J);
}

/* rhs and jac (wk_friction.h). */
WK_FRICTION_PHASE_FUNCTION(rhs, phase_rhs, KERNELS[0], I_COULOMB)
WK_FRICTION_PHASE_FUNCTION(jac, phase_jac, KERNELS[0], I_COULOMB)

/* The guards over the kneed walker's guards walker_guards (its plane or terrain ones). */
static void guards_on(wk_guards_fn walker_guards, int64_t phase, double t, const double *x,
                      const double *p, double *g, void *ctx)
{
    int64_t modes[3];
    int base = split(phase, modes);
    walker_guards(base, t, x, p, g, ctx);
    wk_friction_phase_guards(&KERNELS[base], p + I_COULOMB, modes, x, p, g + N_BASE_GUARDS);
    if (base == LOCKED) {
        g[WK_KNEED_COULOMB_GUARD_KNEE_SLIP_STOPS] = 1.0;
        g[WK_KNEED_COULOMB_GUARD_KNEE_STICK_BREAKS] = 1.0;
    }
}

static void guards(int64_t phase, double t, const double *x, const double *p, double *g,
                   void *ctx)
{
    guards_on(wk_model_kneed_guards, phase, t, x, p, g, ctx);
}

/* Chooses every joint's mode for state x of base phase base (velocities projected in
 * place onto the stuck joints) and returns the phase; -1 if a solve is singular. */
static int64_t start(int64_t base, double *x, const double *p)
{
    int64_t modes[3] = {0, 0, WK_STICK}; /* the locked knee (chosen below while unlocked) */
    int64_t offset = base == LOCKED ? N_UNLOCKED : 0;
    int64_t new_phase = wk_friction_phase_start(&KERNELS[base], p + I_COULOMB, modes, offset, x, p);
    if (base == LOCKED && new_phase >= 0) x[5] = x[4];
    return new_phase;
}

/* The reset over the kneed walker's reset walker_reset (its plane or terrain one). */
static void reset_on(wk_reset_fn walker_reset, int64_t phase, int64_t k, double t,
                     const double *x, const double *p, double *x_new, double *impulse,
                     int64_t *out, void *ctx)
{
    int64_t modes[3];
    int base = split(phase, modes);
    if (k < N_BASE_GUARDS) {
        wk_friction_base_reset(walker_reset, start, base, phase, k, t, x, p, x_new, impulse,
                               out, ctx);
        return;
    }
    int64_t offset = base == LOCKED ? N_UNLOCKED : 0;
    if (wk_friction_phase_reset(&KERNELS[base], p + I_COULOMB, modes, phase, offset,
                                k - N_BASE_GUARDS, x, p, x_new, out) &&
        base == LOCKED)
        x_new[5] = x_new[4];
}

static void reset(int64_t phase, int64_t k, double t, const double *x, const double *p,
                  double *x_new, double *impulse, int64_t *out, void *ctx)
{
    reset_on(wk_model_kneed_reset, phase, k, t, x, p, x_new, impulse, out, ctx);
}

/* start_phase (in the unlocked phase); energy and drawing points are the kneed walker's
 * (model_kneed.c). */
WK_FRICTION_WALKER_ENTRY(kneed_coulomb, kneed, WK_KNEED_COULOMB_N_X)

/* Terrain (wk_terrain.h): the kneed walker's terrain guards, knee lock and heel strike in
 * place of its plane ones; the friction guards and resets unchanged. */
#include "wk_terrain.h"

WK_FRICTION_WALKER_TERRAIN(kneed_coulomb, kneed, WK_KNEED_COULOMB_P_SLOPE,
                           WK_KNEED_COULOMB_P_FOOT_RADIUS, WK_KNEED_COULOMB_N_P)
