/* The kneed walker with point or round feet: C port of the compiled phase functions in
 * walker/models/kneed.py (same operations in the same order).  State (q1, q2, q3, qd1, qd2,
 * qd3); phases unlocked (0) and locked (1, q3 = q2 and qd3 = qd2 kept exactly); guards
 * knee_lock, swing_foot_contact, fall_forward, fall_backward.
 *
 * The glue is written once over a table of kernels and instantiated four times: "kneed" on
 * the general kernels wk_kneed_* and "kneed/plain" on wk_kneed_plain_* (point feet, no
 * offsets, no segment inertias, no dampers; walker/_generated/kneed_plain.h) where a plain
 * kernel exists, the general one elsewhere (energies); and each again as
 * "kneed/ignore_scuff", "kneed/plain/ignore_scuff" for the swing-foot scuffing convention
 * swing_scuff = "ignore" (a bent-knee swing foot passes through the ground; the table's
 * ignore_scuff flag is read only when that contact guard fires).  The plain instances also
 * have a fused rhs and Jacobian (rhs_jac, the accel_and_jac kernels; WK_MODEL_FUSED). */
#include <math.h>
#include <stddef.h>
#include "wk_common.h"
#include "wk_kneed.h"
#include "kneed.h"
#include "kneed_plain.h"
#include "wk_terrain.h"

#define I_R WK_KNEED_P_FOOT_RADIUS
#define I_SLOPE WK_KNEED_P_SLOPE
/* |q3 - q2| [rad] below which a foot contact with the knee unlocked counts as simultaneous
 * with knee lock rather than as a trip. */
#define KNEE_TOL 1e-6

typedef struct {
    wk_qqdp_v unlocked_accel;
    wk_qqdp_v unlocked_accel_jac;
    wk_qp_v unlocked_mass_matrix;
    wk_qqdp_s unlocked_kinetic;
    wk_qp_s unlocked_potential;
    wk_qp_v unlocked_points;
    wk_qqdp_v locked_accel;
    wk_qqdp_v locked_accel_jac;
    /* the heel strike's kernels: the knee locked, the 2-link model's (the hip at row 1 of the
     * 5 locked points) */
    wk_floating_base locked_base;
    int ignore_scuff; /* swing_scuff = "ignore" (1) or "trip" (0) */
    /* the plain variant's fused accel_and_jac (NULL for the general kernels, which have
     * none): (n, 2n + 1), accel_jac's Jacobian and the accelerations in the last column */
    wk_qqdp_v unlocked_accel_and_jac;
    wk_qqdp_v locked_accel_and_jac;
} kneed_kernels;

static void lengths(const double *p, double *shank, double *thigh)
{
    *shank = p[WK_KNEED_P_SHANK_COM_FROM_FOOT] + p[WK_KNEED_P_SHANK_COM_TO_KNEE];
    *thigh = p[WK_KNEED_P_THIGH_COM_FROM_KNEE] + p[WK_KNEED_P_THIGH_COM_TO_HIP];
}

/* Least step length of a heel strike [m] (WK_MIN_STEP leg lengths). */
static double min_step(const double *p)
{
    double shank, thigh;
    lengths(p, &shank, &thigh);
    return WK_MIN_STEP * (shank + thigh);
}

static void rhs(const kneed_kernels *K, int64_t phase, const double *x, const double *p,
                double *dx)
{
    if (phase == WK_KNEED_PHASE_UNLOCKED) {
        dx[0] = x[3];
        dx[1] = x[4];
        dx[2] = x[5];
        K->unlocked_accel(x, x + 3, p, dx + 3);
    } else {
        /* Locked: (q1, q2) and (qd1, qd2) are contiguous slices of the state. */
        double qdd[2];
        K->locked_accel(x, x + 3, p, qdd);
        wk_kneed_locked_state(x + 3, qdd, dx);
    }
}

static void jac(const kneed_kernels *K, int64_t phase, const double *x, const double *p,
                double *J)
{
    for (int i = 0; i < 36; i++) J[i] = 0.0;
    if (phase == WK_KNEED_PHASE_UNLOCKED) {
        J[0 * 6 + 3] = 1.0;
        J[1 * 6 + 4] = 1.0;
        J[2 * 6 + 5] = 1.0;
        K->unlocked_accel_jac(x, x + 3, p, J + 3 * 6); /* rows 3..5 */
    } else {
        double a[2 * 4];
        K->locked_accel_jac(x, x + 3, p, a);
        wk_kneed_locked_jac(a, 4, J);
    }
}

/* rhs and jac in one call of the fused kernels (the plain variants): J as jac fills it, bit
 * for bit (the same lowering as accel_jac); the accelerations in dx those the Jacobian's
 * solve computes, rhs's to round-off. */
static void rhs_jac(const kneed_kernels *K, int64_t phase, const double *x, const double *p,
                    double *dx, double *J)
{
    for (int i = 0; i < 36; i++) J[i] = 0.0;
    if (phase == WK_KNEED_PHASE_UNLOCKED) {
        double a[3 * 7];
        K->unlocked_accel_and_jac(x, x + 3, p, a);
        dx[0] = x[3];
        dx[1] = x[4];
        dx[2] = x[5];
        J[0 * 6 + 3] = 1.0;
        J[1 * 6 + 4] = 1.0;
        J[2 * 6 + 5] = 1.0;
        for (int i = 0; i < 3; i++) {
            for (int j = 0; j < 6; j++) J[(3 + i) * 6 + j] = a[i * 7 + j];
            dx[3 + i] = a[i * 7 + 6];
        }
    } else {
        /* Locked, as in rhs and jac: q3, qd3 copy q2, qd2. */
        double a[2 * 5];
        K->locked_accel_and_jac(x, x + 3, p, a);
        const double qdd[2] = {a[0 * 5 + 4], a[1 * 5 + 4]};
        wk_kneed_locked_state(x + 3, qdd, dx);
        wk_kneed_locked_jac(a, 5, J);
    }
}

/* (height above the slope, distance ahead of the stance foot along the slope) [m] of the
 * swing foot's lowest point. */
static void swing_foot(const double *x, const double *p, double *height, double *ahead)
{
    double shank, thigh;
    lengths(p, &shank, &thigh);
    double R = p[I_R];
    double slope = p[I_SLOPE];
    double L = shank + thigh;
    double psi1 = x[0] + slope;
    double psi2 = x[1] + slope;
    double psi3 = x[2] + slope;
    *height = (L - R) * cos(psi1) - thigh * cos(psi2) - (shank - R) * cos(psi3);
    *ahead = -(L - R) * sin(psi1) + thigh * sin(psi2) + (shank - R) * sin(psi3);
}

static double swing_foot_rate(const double *x, const double *p)
{
    double shank, thigh;
    lengths(p, &shank, &thigh);
    double R = p[I_R];
    double slope = p[I_SLOPE];
    double L = shank + thigh;
    return -(L - R) * sin(x[0] + slope) * x[3] + thigh * sin(x[1] + slope) * x[4] +
           (shank - R) * sin(x[2] + slope) * x[5];
}

static void guards(const kneed_kernels *K, int64_t phase, const double *x, const double *p,
                   double *g)
{
    (void)K;
    double psi1 = x[0] + p[I_SLOPE];
    double height, ahead;
    g[WK_KNEED_GUARD_KNEE_LOCK] = phase == WK_KNEED_PHASE_UNLOCKED ? x[2] - x[1] : 1.0;
    swing_foot(x, p, &height, &ahead);
    g[WK_KNEED_GUARD_SWING_FOOT_CONTACT] = height;
    g[WK_KNEED_GUARD_FALL_FORWARD] = psi1 + WK_FALL_ANGLE;
    g[WK_KNEED_GUARD_FALL_BACKWARD] = psi1 - WK_FALL_ANGLE;
}

/* Plastic knee-lock impact; impulse[0] is the knee impulse [N m s].  Returns a status. */
static int64_t knee_lock(const kneed_kernels *K, const double *x, const double *p,
                         double *x_new, double *impulse)
{
    double M[3 * 3];
    K->unlocked_mass_matrix(x, p, M);
    const double J[3] = {0.0, -1.0, 1.0};
    double qd_plus[3], lam[1];
    if (!wk_impact(M, J, x + 3, qd_plus, lam, 3, 1)) return WK_LINEAR_SOLVE_FAILED;
    wk_kneed_locked_state(x, qd_plus, x_new);
    impulse[0] = lam[0];
    impulse[1] = 0.0;
    return 0;
}

/* Floating-base heel strike (knee locked) and leg swap (wk_plastic_heel_strike); the new
 * swing knee is straight and unlocked.  impulse = (along slope, normal) on the new stance
 * foot [N s]. */
static int64_t heel_strike(const kneed_kernels *K, const double *x, const double *p,
                           double *x_new, double *impulse)
{
    static const int swap[3] = {1, 0, 0};
    return wk_plastic_heel_strike(&K->locked_base, swap, 3, x, p, p[I_SLOPE], x_new, impulse);
}

/* The terrain's swing foot (wk_terrain.h): its signed distance from the step's plane (the
 * plane functions' height and distance ahead with the step's slope, plus h cos(gamma) for the
 * plane h below the stance foot; round feet: wk_terrain_round_height), its distance ahead
 * and its rate of approach [m, m, m/s]. */
static void terrain_swing_foot(const double *x, const double *p, const wk_terrain *T,
                               double *height, double *ahead, double *rate)
{
    double shank, thigh;
    lengths(p, &shank, &thigh);
    const wk_ground *G = &T->ground;
    const double R = p[I_R], L = shank + thigh, gam = G->slope;
    const double psi1 = x[0] + gam, psi2 = x[1] + gam, psi3 = x[2] + gam;
    if (R == 0.0) {
        *height = L * cos(psi1) - thigh * cos(psi2) - shank * cos(psi3) + G->drop * cos(gam);
        *ahead = -L * sin(psi1) + thigh * sin(psi2) + shank * sin(psi3);
        *rate = -L * sin(psi1) * x[3] + thigh * sin(psi2) * x[4] + shank * sin(psi3) * x[5];
        return;
    }
    const double centres = (L - R) * cos(psi1) - thigh * cos(psi2) - (shank - R) * cos(psi3);
    *height = wk_terrain_round_height(T, centres, x[0], R);
    *ahead = -(L - R) * sin(psi1) + thigh * sin(psi2) + (shank - R) * sin(psi3);
    *rate = -(L - R) * sin(psi1) * x[3] + thigh * sin(psi2) * x[4] +
            (shank - R) * sin(psi3) * x[5] - R * x[3] * sin(gam - G->prev_slope);
}

/* The swing foot's (height, ahead, rate) [m, m, m/s] above the slope (T NULL) or above the
 * step's plane of the terrain T. */
static void contact(const double *x, const double *p, const wk_terrain *T, double *height,
                    double *ahead, double *rate)
{
    if (T != NULL) {
        terrain_swing_foot(x, p, T, height, ahead, rate);
        return;
    }
    swing_foot(x, p, height, ahead);
    *rate = swing_foot_rate(x, p);
}

/* The heel strike on terrain (knee locked): point or round feet. */
static int64_t terrain_heel_strike(const kneed_kernels *K, const double *x, const double *p,
                                   double *x_new, double *impulse, const wk_terrain *T)
{
    static const int swap[3] = {1, 0, 0};
    if (p[I_R] == 0.0)
        return wk_terrain_heel_strike(&K->locked_base, swap, 3, x, p, &T->ground, x_new, impulse);
    return wk_terrain_heel_strike_round(&K->locked_base, swap, 3, x, p, T, x_new, impulse);
}

/* Heel strike on the slope (T NULL) or on the step's plane of the terrain T. */
static int64_t strike(const kneed_kernels *K, const double *x, const double *p, double *x_new,
                      double *impulse, const wk_terrain *T)
{
    if (T != NULL) return terrain_heel_strike(K, x, p, x_new, impulse, T);
    return heel_strike(K, x, p, x_new, impulse);
}

/* Knee lock, followed in the same reset by heel strike when the swing foot is on the ground
 * (within the integrator's guard tolerance), ahead and moving down.  Under "trip" a foot
 * below the ground counts as on it; under "ignore" a foot deeper than the tolerance is
 * passing through the ground and heel strike waits for its next descent.  The ground is the
 * slope (T NULL) or the step's plane of the terrain T. */
static void knee_lock_event(const kneed_kernels *K, int64_t phase, const double *x,
                            const double *p, double *x_new, double *impulse, int64_t *out,
                            const wk_terrain *T)
{
    int64_t status = knee_lock(K, x, p, x_new, impulse);
    if (status != 0) {
        wk_reset_out(out, WK_EVENT_TERMINAL, phase, status);
        return;
    }
    double shank, thigh, height, ahead, rate;
    lengths(p, &shank, &thigh);
    contact(x_new, p, T, &height, &ahead, &rate);
    int touching = height <= 1e-9 * (shank + thigh);
    if (K->ignore_scuff) touching = touching && height >= -1e-9 * (shank + thigh);
    if (touching && ahead > WK_MIN_STEP * (shank + thigh) && rate < 0) {
        double locked[6];
        for (int i = 0; i < 6; i++) locked[i] = x_new[i];
        wk_stride_out(out, 1, strike(K, locked, p, x_new, impulse, T));
        return;
    }
    wk_reset_out(out, WK_EVENT_CONTINUE, 1, 0);
}

/* The reset on the slope (T NULL) or on the step's plane of the terrain T. */
static void step_reset(const kneed_kernels *K, int64_t phase, int64_t k, const double *x,
                       const double *p, double *x_new, double *impulse, int64_t *out,
                       const wk_terrain *T)
{
    for (int i = 0; i < 6; i++) x_new[i] = x[i];
    impulse[0] = 0.0;
    impulse[1] = 0.0;
    if (k == 0) {
        knee_lock_event(K, phase, x, p, x_new, impulse, out, T);
        return;
    }
    if (k == 1) {
        double height, ahead, rate;
        contact(x, p, T, &height, &ahead, &rate);
        if (phase == WK_KNEED_PHASE_UNLOCKED) {
            if (fabs(x[2] - x[1]) <= KNEE_TOL && ahead > min_step(p)) {
                /* The knee locks at this same instant (its guard a hair behind): knee lock
                 * first, then heel strike, as when the knee-lock guard fires first. */
                knee_lock_event(K, phase, x, p, x_new, impulse, out, T);
                return;
            }
            if (K->ignore_scuff) {
                /* swing_scuff = "ignore": the bent-knee swing foot passes through the
                 * ground. */
                wk_reset_out(out, WK_EVENT_IGNORE, phase, 0);
                return;
            }
            wk_reset_out(out, WK_EVENT_TERMINAL, phase, WK_TRIPPED);
            return;
        }
        if (ahead <= min_step(p))
            wk_reset_out(out, WK_EVENT_IGNORE, phase, 0);
        else
            wk_stride_out(out, phase, strike(K, x, p, x_new, impulse, T));
        return;
    }
    wk_fall_out(out, phase, k == WK_KNEED_GUARD_FALL_FORWARD);
}

static void reset(const kneed_kernels *K, int64_t phase, int64_t k, const double *x,
                  const double *p, double *x_new, double *impulse, int64_t *out)
{
    step_reset(K, phase, k, x, p, x_new, impulse, out, NULL);
}

/* (kinetic, potential) [J]; valid in both phases (locked: q3 = q2, qd3 = qd2). */
static void energy(const kneed_kernels *K, const double *x, const double *p, double *out)
{
    out[0] = K->unlocked_kinetic(x, x + 3, p);
    out[1] = K->unlocked_potential(x, p);
}

/* Stance contact, hip, knee, swing contact [m], out (4, 2): rows 0, 1, 2, 4 of the
 * kernel's points. */
static void points(const kneed_kernels *K, const double *x, const double *p, double *out)
{
    double pts[5 * 2];
    K->unlocked_points(x, p, pts);
    for (int i = 0; i < 6; i++) out[i] = pts[i];
    out[6] = pts[8];
    out[7] = pts[9];
}

#define GENERAL_KERNELS                                                                     \
    wk_kneed_unlocked_accel, wk_kneed_unlocked_accel_jac, wk_kneed_unlocked_mass_matrix,       \
        wk_kneed_unlocked_kinetic, wk_kneed_unlocked_potential, wk_kneed_unlocked_points,     \
        wk_kneed_locked_accel, wk_kneed_locked_accel_jac,                                     \
        {wk_kneed_locked_points, wk_kneed_locked_hip_jac, wk_kneed_ext_mass_matrix,           \
         wk_kneed_ext_swing_contact_jac, wk_kneed_ext_stance_contact_jac, 2, 5, 1}

#define PLAIN_KERNELS                                                                       \
    wk_kneed_plain_unlocked_accel, wk_kneed_plain_unlocked_accel_jac,                         \
        wk_kneed_plain_unlocked_mass_matrix, wk_kneed_unlocked_kinetic,                       \
        wk_kneed_unlocked_potential, wk_kneed_plain_unlocked_points,                          \
        wk_kneed_plain_locked_accel, wk_kneed_plain_locked_accel_jac,                         \
        {wk_kneed_plain_locked_points, wk_kneed_plain_locked_hip_jac,                         \
         wk_kneed_plain_ext_mass_matrix, wk_kneed_plain_ext_swing_contact_jac,                \
         wk_kneed_plain_ext_stance_contact_jac, 2, 5, 1}

#define PLAIN_FUSED wk_kneed_plain_unlocked_accel_and_jac, wk_kneed_plain_locked_accel_and_jac

/* The plain kernels with their hoisted twins where they have one (p extended by
 * wk_kneed_plain_constants): the integrator's phase functions of the plain variants
 * (wk_model_hoist, models.c). */
#define PLAIN_HOISTED_KERNELS                                                               \
    wk_kneed_plain_unlocked_accel_hoisted, wk_kneed_plain_unlocked_accel_jac_hoisted,         \
        wk_kneed_plain_unlocked_mass_matrix, wk_kneed_unlocked_kinetic,                       \
        wk_kneed_unlocked_potential, wk_kneed_plain_unlocked_points,                          \
        wk_kneed_plain_locked_accel_hoisted, wk_kneed_plain_locked_accel_jac_hoisted,         \
        {wk_kneed_plain_locked_points, wk_kneed_plain_locked_hip_jac,                         \
         wk_kneed_plain_ext_mass_matrix, wk_kneed_plain_ext_swing_contact_jac,                \
         wk_kneed_plain_ext_stance_contact_jac, 2, 5, 1}

#define PLAIN_HOISTED_FUSED                                                                 \
    wk_kneed_plain_unlocked_accel_and_jac_hoisted, wk_kneed_plain_locked_accel_and_jac_hoisted

static const kneed_kernels GENERAL = {GENERAL_KERNELS, 0, NULL, NULL};
static const kneed_kernels PLAIN = {PLAIN_KERNELS, 0, PLAIN_FUSED};
static const kneed_kernels GENERAL_IGNORE_SCUFF = {GENERAL_KERNELS, 1, NULL, NULL};
static const kneed_kernels PLAIN_IGNORE_SCUFF = {PLAIN_KERNELS, 1, PLAIN_FUSED};
static const kneed_kernels PLAIN_HOISTED = {PLAIN_HOISTED_KERNELS, 0, PLAIN_HOISTED_FUSED};
static const kneed_kernels PLAIN_HOISTED_IGNORE_SCUFF = {PLAIN_HOISTED_KERNELS, 1,
                                                         PLAIN_HOISTED_FUSED};

WK_MODEL_VARIANT(kneed, GENERAL)
WK_MODEL_VARIANT(kneed_plain, PLAIN)
WK_MODEL_VARIANT(kneed_ignore_scuff, GENERAL_IGNORE_SCUFF)
WK_MODEL_VARIANT(kneed_plain_ignore_scuff, PLAIN_IGNORE_SCUFF)
WK_MODEL_FUSED(kneed_plain, PLAIN)
WK_MODEL_FUSED(kneed_plain_ignore_scuff, PLAIN_IGNORE_SCUFF)
WK_MODEL_ENTRY(kneed)
WK_MODEL_ENTRY_FUSED(kneed_plain)
WK_MODEL_ENTRY(kneed_ignore_scuff)
WK_MODEL_ENTRY_FUSED(kneed_plain_ignore_scuff)
WK_MODEL_HOISTED(kneed_plain, PLAIN_HOISTED)
WK_MODEL_HOISTED(kneed_plain_ignore_scuff, PLAIN_HOISTED_IGNORE_SCUFF)

/* ------------------------------------------------------------------------------------------
 * Terrain (wk_terrain.h): the guards with the swing foot's signed distance from the step's
 * plane (terrain_swing_foot), the reset step_reset's on that plane: knee lock then heel
 * strike as on the slope, the heel strike's impulse along and normal to the step's plane
 * (wk_terrain_heel_strike, wk_terrain_heel_strike_round).
 * ------------------------------------------------------------------------------------------ */
static void terrain_guards(const kneed_kernels *K, int64_t phase, const double *x,
                           const double *p, double *g, const wk_terrain *T)
{
    if (T->ground.plane) {
        guards(K, phase, x, p, g);
        return;
    }
    double shank, thigh;
    lengths(p, &shank, &thigh);
    const double gam = T->ground.slope, psi1 = x[0] + p[I_SLOPE];
    g[WK_KNEED_GUARD_KNEE_LOCK] = phase == WK_KNEED_PHASE_UNLOCKED ? x[2] - x[1] : 1.0;
    if (p[I_R] == 0.0) {
        g[WK_KNEED_GUARD_SWING_FOOT_CONTACT] = (shank + thigh) * cos(x[0] + gam) -
                                               thigh * cos(x[1] + gam) -
                                               shank * cos(x[2] + gam) + T->ground.drop * cos(gam);
    } else {
        double height, ahead, rate;
        terrain_swing_foot(x, p, T, &height, &ahead, &rate);
        g[WK_KNEED_GUARD_SWING_FOOT_CONTACT] = height;
    }
    g[WK_KNEED_GUARD_FALL_FORWARD] = psi1 + WK_FALL_ANGLE;
    g[WK_KNEED_GUARD_FALL_BACKWARD] = psi1 - WK_FALL_ANGLE;
}

static void terrain_reset(const kneed_kernels *K, int64_t phase, int64_t k, const double *x,
                          const double *p, double *x_new, double *impulse, int64_t *out,
                          const wk_terrain *T)
{
    step_reset(K, phase, k, x, p, x_new, impulse, out, T->ground.plane ? NULL : T);
}

WK_DEFINE_TERRAIN(kneed, GENERAL)
WK_DEFINE_TERRAIN(kneed_plain, PLAIN)
WK_DEFINE_TERRAIN(kneed_ignore_scuff, GENERAL_IGNORE_SCUFF)
WK_DEFINE_TERRAIN(kneed_plain_ignore_scuff, PLAIN_IGNORE_SCUFF)
