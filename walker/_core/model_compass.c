/* The compass gait with point or round feet: C port of the compiled phase functions in
 * walker/models/compass.py (same operations in the same order).  State (q_stance, q_swing,
 * qd_stance, qd_swing); guards heel_strike, fall_forward, fall_backward.
 *
 * The glue is written once over a table of kernels and instantiated twice: "compass" on the
 * general kernels wk_compass_* and "compass/plain" on wk_compass_plain_* (point feet, no
 * leg inertia, no dampers; walker/_generated/compass_plain.h) where a plain kernel exists,
 * the general one elsewhere (energies).  The plain instance also has a fused rhs and
 * Jacobian (rhs_jac, the accel_and_jac kernel; WK_MODEL_FUSED). */
#include <math.h>
#include <stddef.h>
#include "wk_common.h"
#include "compass.h"
#include "compass_plain.h"

#define I_R WK_COMPASS_P_FOOT_RADIUS
#define I_SLOPE WK_COMPASS_P_SLOPE

typedef struct {
    wk_qqdp_v accel;
    wk_qqdp_v accel_jac;
    wk_qqdp_s kinetic;
    wk_qp_s potential;
    wk_floating_base base; /* the heel strike's kernels (the hip at row 1 of 4 points) */
    /* the plain variant's fused accel_and_jac (NULL for the general kernels): (2, 5),
     * accel_jac's Jacobian and the accelerations in the last column */
    wk_qqdp_v accel_and_jac;
} compass_kernels;

static void rhs(const compass_kernels *K, int64_t phase, const double *x, const double *p,
                double *dx)
{
    (void)phase;
    dx[0] = x[2];
    dx[1] = x[3];
    K->accel(x, x + 2, p, dx + 2);
}

static void jac(const compass_kernels *K, int64_t phase, const double *x, const double *p,
                double *J)
{
    (void)phase;
    for (int i = 0; i < 16; i++) J[i] = 0.0;
    J[0 * 4 + 2] = 1.0;
    J[1 * 4 + 3] = 1.0;
    K->accel_jac(x, x + 2, p, J + 2 * 4); /* rows 2, 3 */
}

/* rhs and jac in one call of the fused kernel (the plain variant): J as jac fills it, bit
 * for bit; the accelerations in dx those the Jacobian's solve computes, rhs's to round-off. */
static void rhs_jac(const compass_kernels *K, int64_t phase, const double *x, const double *p,
                    double *dx, double *J)
{
    (void)phase;
    double a[2 * 5];
    K->accel_and_jac(x, x + 2, p, a);
    for (int i = 0; i < 16; i++) J[i] = 0.0;
    J[0 * 4 + 2] = 1.0;
    J[1 * 4 + 3] = 1.0;
    dx[0] = x[2];
    dx[1] = x[3];
    for (int i = 0; i < 2; i++) {
        for (int j = 0; j < 4; j++) J[(2 + i) * 4 + j] = a[i * 5 + j];
        dx[2 + i] = a[i * 5 + 4];
    }
}

/* (height above the slope, distance ahead of the stance foot along the slope) [m]. */
static void swing_foot(const double *x, const double *p, double *height, double *ahead)
{
    double L = p[WK_COMPASS_P_COM_FROM_FOOT] + p[WK_COMPASS_P_COM_TO_HIP];
    double R = p[I_R];
    double slope = p[I_SLOPE];
    double psi1 = x[0] + slope;
    double psi2 = x[1] + slope;
    *height = (L - R) * (cos(psi1) - cos(psi2));
    *ahead = (L - R) * (sin(psi2) - sin(psi1));
}

static void guards(const compass_kernels *K, int64_t phase, const double *x,
                   const double *p, double *g)
{
    (void)K;
    (void)phase;
    double psi1 = x[0] + p[I_SLOPE];
    double height, ahead;
    swing_foot(x, p, &height, &ahead);
    g[WK_COMPASS_GUARD_HEEL_STRIKE] = height;
    g[WK_COMPASS_GUARD_FALL_FORWARD] = psi1 + WK_FALL_ANGLE;
    g[WK_COMPASS_GUARD_FALL_BACKWARD] = psi1 - WK_FALL_ANGLE;
}

/* Heel strike (floating-base impact and leg swap, wk_plastic_heel_strike; impulse = (along
 * the slope, normal) on the new stance foot [N s]) or a fall. */
static void reset(const compass_kernels *K, int64_t phase, int64_t k, const double *x,
                  const double *p, double *x_new, double *impulse, int64_t *out)
{
    static const int swap[2] = {1, 0}; /* the leg swap at heel strike */
    for (int i = 0; i < 4; i++) x_new[i] = x[i];
    if (k != WK_COMPASS_GUARD_HEEL_STRIKE) {
        wk_fall_out(out, phase, k == WK_COMPASS_GUARD_FALL_FORWARD);
        return;
    }
    double height, ahead;
    swing_foot(x, p, &height, &ahead);
    if (ahead <= WK_MIN_STEP * (p[WK_COMPASS_P_COM_FROM_FOOT] + p[WK_COMPASS_P_COM_TO_HIP]))
        wk_reset_out(out, WK_EVENT_IGNORE, phase, 0);
    else
        wk_stride_out(out, phase,
                      wk_plastic_heel_strike(&K->base, swap, 2, x, p, p[I_SLOPE], x_new, impulse));
}

/* (kinetic, potential) [J]; potential zero with the stance contact at height 0. */
static void energy(const compass_kernels *K, const double *x, const double *p, double *out)
{
    out[0] = K->kinetic(x, x + 2, p);
    out[1] = K->potential(x, p);
}

/* Rows stance contact, hip, swing contact [m], out (3, 2): rows 0, 1, 3 of the kernel's
 * points. */
static void points(const compass_kernels *K, const double *x, const double *p, double *out)
{
    double pts[4 * 2];
    K->base.points(x, p, pts);
    for (int i = 0; i < 4; i++) out[i] = pts[i];
    out[4] = pts[6];
    out[5] = pts[7];
}

static const compass_kernels GENERAL = {
    wk_compass_accel,
    wk_compass_accel_jac,
    wk_compass_kinetic,
    wk_compass_potential,
    {wk_compass_points, wk_compass_hip_jac, wk_compass_ext_mass_matrix,
     wk_compass_ext_swing_contact_jac, wk_compass_ext_stance_contact_jac, 2, 4, 1},
    NULL,
};

static const compass_kernels PLAIN = {
    wk_compass_plain_accel,
    wk_compass_plain_accel_jac,
    wk_compass_kinetic,
    wk_compass_potential,
    {wk_compass_plain_points, wk_compass_plain_hip_jac, wk_compass_plain_ext_mass_matrix,
     wk_compass_plain_ext_swing_contact_jac, wk_compass_plain_ext_stance_contact_jac, 2, 4, 1},
    wk_compass_plain_accel_and_jac,
};

/* The plain kernels' hoisted twins (p extended by wk_compass_plain_constants): the
 * integrator's phase functions of "compass/plain" (wk_model_hoist, models.c). */
static const compass_kernels PLAIN_HOISTED = {
    wk_compass_plain_accel_hoisted,
    wk_compass_plain_accel_jac_hoisted,
    wk_compass_kinetic,
    wk_compass_potential,
    {wk_compass_plain_points, wk_compass_plain_hip_jac, wk_compass_plain_ext_mass_matrix,
     wk_compass_plain_ext_swing_contact_jac, wk_compass_plain_ext_stance_contact_jac, 2, 4, 1},
    wk_compass_plain_accel_and_jac_hoisted,
};

WK_MODEL_VARIANT(compass, GENERAL)
WK_MODEL_VARIANT(compass_plain, PLAIN)
WK_MODEL_FUSED(compass_plain, PLAIN)
WK_MODEL_ENTRY(compass)
WK_MODEL_ENTRY_FUSED(compass_plain)
WK_MODEL_HOISTED(compass_plain, PLAIN_HOISTED)

/* ------------------------------------------------------------------------------------------
 * Terrain (wk_terrain.h): the swing foot's signed distance from the step's plane
 * L (cos(q_st + gamma) - cos(q_sw + gamma)) + h cos(gamma) (the angles from the vertical,
 * the plane h below the stance foot; round feet: wk_terrain_round_height), its distance
 * ahead along that plane (a touchdown with the foot not ahead is ignored, as on the plane),
 * and the heel strike with the impulse along and normal to it (wk_terrain_heel_strike,
 * wk_terrain_heel_strike_round).  A step on the scene's plane runs the plane functions
 * above; with round feet the phase functions run with the stance plane's slope
 * (terrain.c).
 * ------------------------------------------------------------------------------------------ */
#include "wk_terrain.h"

static void terrain_guards(const compass_kernels *K, int64_t phase, const double *x,
                           const double *p, double *g, const wk_terrain *T)
{
    if (T->ground.plane) {
        guards(K, phase, x, p, g);
        return;
    }
    const double R = p[I_R];
    const double L = p[WK_COMPASS_P_COM_FROM_FOOT] + p[WK_COMPASS_P_COM_TO_HIP] - R;
    const double gam = T->ground.slope, psi1 = x[0] + p[I_SLOPE];
    const double centres = L * (cos(x[0] + gam) - cos(x[1] + gam));
    g[WK_COMPASS_GUARD_HEEL_STRIKE] = R == 0.0 ? centres + T->ground.drop * cos(gam)
                                               : wk_terrain_round_height(T, centres, x[0], R);
    g[WK_COMPASS_GUARD_FALL_FORWARD] = psi1 + WK_FALL_ANGLE;
    g[WK_COMPASS_GUARD_FALL_BACKWARD] = psi1 - WK_FALL_ANGLE;
}

static void terrain_reset(const compass_kernels *K, int64_t phase, int64_t k, const double *x,
                          const double *p, double *x_new, double *impulse, int64_t *out,
                          const wk_terrain *T)
{
    static const int swap[2] = {1, 0};
    if (T->ground.plane || k != WK_COMPASS_GUARD_HEEL_STRIKE) {
        reset(K, phase, k, x, p, x_new, impulse, out);
        return;
    }
    for (int i = 0; i < 4; i++) x_new[i] = x[i];
    const double L = p[WK_COMPASS_P_COM_FROM_FOOT] + p[WK_COMPASS_P_COM_TO_HIP];
    const double gam = T->ground.slope;
    const double ahead = (L - p[I_R]) * (sin(x[1] + gam) - sin(x[0] + gam));
    if (ahead <= WK_MIN_STEP * L)
        wk_reset_out(out, WK_EVENT_IGNORE, phase, 0);
    else if (p[I_R] == 0.0)
        wk_stride_out(out, phase,
                      wk_terrain_heel_strike(&K->base, swap, 2, x, p, &T->ground, x_new, impulse));
    else
        wk_stride_out(out, phase,
                      wk_terrain_heel_strike_round(&K->base, swap, 2, x, p, T, x_new, impulse));
}

WK_DEFINE_TERRAIN(compass, GENERAL)
WK_DEFINE_TERRAIN(compass_plain, PLAIN)
