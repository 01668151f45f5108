/* The five-link walker in closed loop with hip and knee friction: C port of the compiled
 * phase functions in walker/models/five_link.py (same operations in the same order).  State
 * (q_leg, q_knee, q_torso, q_femur_sw, q_tibia_sw, their rates, actuator_work,
 * saturated_time); phase = joint-mode code of (hip_stance, hip_swing, knee_stance,
 * knee_swing) (wk_friction.h); guards heel_strike, fall_forward, fall_backward,
 * slip_forward, slip_backward, lift_off, hip_down, then slip_stops / stick_breaks per joint.
 * The controller comes from ctx (wk_actuated.h). */
#include <math.h>
#include <stddef.h>
#include "wk_common.h"
#include "wk_friction.h"
#include "wk_actuated.h"
#include "five_link.h"

#define N_X WK_FIVE_LINK_N_X
#define N_Q 5
#define N_U WK_FIVE_LINK_N_INPUTS
#define N_JOINTS WK_FIVE_LINK_N_JOINTS
#define N_BASE_GUARDS 7
#define I_LENGTH_FEMUR WK_FIVE_LINK_P_LENGTH_FEMUR
#define I_LENGTH_TIBIA WK_FIVE_LINK_P_LENGTH_TIBIA
#define I_SLOPE WK_FIVE_LINK_P_SLOPE
#define I_FRICTION WK_FIVE_LINK_P_FRICTION
#define CONTROL_OFFSET WK_FIVE_LINK_CONTROL_OFFSET
#define I_DAMPING_HIP WK_FIVE_LINK_P_DAMPING_HIP
#define I_DAMPING_KNEE WK_FIVE_LINK_P_DAMPING_KNEE
#define I_COULOMB_HIP WK_FIVE_LINK_P_COULOMB_HIP
#define I_COULOMB_KNEE WK_FIVE_LINK_P_COULOMB_KNEE
#define JAC_STEP 1e-6

static const double B_MATRIX[N_Q * N_U] = {
    1.0, 0.0, 0.0, 0.0,   /* */
    0.5, 0.0, -1.0, 0.0,  /* */
    -1.0, -1.0, 0.0, 0.0, /* */
    0.0, 1.0, 0.0, -1.0,  /* */
    0.0, 0.0, 0.0, 1.0,
};
static const double S_MATRIX[N_JOINTS * N_Q] = {
    1.0, 0.5, -1.0, 0.0, 0.0,  /* */
    0.0, 0.0, -1.0, 1.0, 0.0,  /* */
    0.0, -1.0, 0.0, 0.0, 0.0,  /* */
    0.0, 0.0, 0.0, -1.0, 1.0,
};
/* Leg swap on the coordinates and rates: q+ = RELABEL q-. */
static const double RELABEL[N_Q * N_Q] = {
    0.0, 0.0, 0.0, 0.5, 0.5,  /* */
    0.0, 0.0, 0.0, 1.0, -1.0, /* */
    0.0, 0.0, 1.0, 0.0, 0.0,  /* */
    1.0, 0.5, 0.0, 0.0, 0.0,  /* */
    1.0, -0.5, 0.0, 0.0, 0.0,
};

/* Generalized force without dry friction f = B u - h - S^T F_v S qd and controller torque u
 * (wk_actuated_model.force); returns 1 when the torque saturated. */
static int force(const double *q, const double *qd, const double *D, const double *h,
                 const double *p, double *f, double *u, void *ctx)
{
    int sat = wk_actuated_torque(ctx, q, qd, D, h, B_MATRIX, p, CONTROL_OFFSET, u, N_Q);
    for (int i = 0; i < 5; i++) {
        double s = -h[i];
        for (int j = 0; j < 4; j++) s += B_MATRIX[i * N_U + j] * u[j];
        f[i] = s;
    }
    for (int j = 0; j < N_JOINTS; j++) {
        double damping = j < 2 ? p[I_DAMPING_HIP] : p[I_DAMPING_KNEE];
        if (damping != 0.0) {
            const double *S = S_MATRIX + j * N_Q;
            double w = 0.0;
            for (int i = 0; i < 5; i++) w += S[i] * qd[i];
            for (int i = 0; i < 5; i++) f[i] -= damping * S[i] * w;
        }
    }
    return sat;
}

/* Dry-friction magnitudes of the joints [N m]. */
static void dry(const double *p, double *F)
{
    F[0] = F[1] = p[I_COULOMB_HIP];
    F[2] = F[3] = p[I_COULOMB_KNEE];
}

/* Actuator power: u . (B^T qd). */
static double power(const double *u, const double *x)
{
    double power = 0.0;
    for (int i = 0; i < 5; i++) {
        for (int j = 0; j < 4; j++) power += u[j] * B_MATRIX[i * N_U + j] * x[5 + i];
    }
    return power;
}

/* The leg swap at heel strike: q+ = RELABEL q-, and the post-impact rates likewise. */
static void relabel(const double *x, const double *qdf_plus, double *x_new)
{
    for (int i = 0; i < 5; i++) {
        double sq = 0.0;
        double sv = 0.0;
        for (int j = 0; j < 5; j++) {
            sq += RELABEL[i * N_Q + j] * x[j];
            sv += RELABEL[i * N_Q + j] * qdf_plus[j];
        }
        x_new[i] = sq;
        x_new[5 + i] = sv;
    }
}

/* Statuses of the base guards after heel strike: fall_forward, fall_backward, slip_forward,
 * slip_backward, lift_off, hip_down. */
static const int64_t BASE_STATUS[N_BASE_GUARDS] = {
    0, WK_FELL_FORWARD, WK_FELL_BACKWARD, WK_NONPHYSICAL_IMPACT, WK_NONPHYSICAL_IMPACT,
    WK_NONPHYSICAL_IMPACT, WK_FELL_BACKWARD,
};

/* The model's table (wk_actuated.h): the hip at row 2 of the 6 points. */
static const wk_actuated_model MODEL = {
    N_Q, N_JOINTS, S_MATRIX, WK_ACTUATED_KERNELS(five_link, N_Q, 6, 2),
    force, dry, power, relabel, I_SLOPE, I_FRICTION, N_BASE_GUARDS, BASE_STATUS,
};

void wk_model_five_link_jac(int64_t phase, double t, const double *x, const double *p,
                            double *J, void *ctx)
{
    wk_actuated_jac(wk_model_five_link_rhs, phase, t, x, p, J, ctx, N_X, JAC_STEP);
}

void wk_model_five_link_guards(int64_t phase, double t, const double *x, const double *p,
                               double *g, void *ctx)
{
    (void)t;
    double pts[6 * 2];
    wk_five_link_points(x, p, pts);
    double slope = p[I_SLOPE];
    double ft_, fn_;
    wk_slope_frame(pts + 8, slope, &ft_, &fn_);
    g[WK_FIVE_LINK_GUARD_HEEL_STRIKE] = fn_;
    double ht, hn;
    wk_slope_frame(pts + 4, slope, &ht, &hn);
    double psi = atan2(-ht, hn); /* stance foot -> hip, from the slope normal */
    g[WK_FIVE_LINK_GUARD_FALL_FORWARD] = psi + WK_FALL_ANGLE;
    g[WK_FIVE_LINK_GUARD_FALL_BACKWARD] = psi - WK_FALL_ANGLE;
    g[WK_FIVE_LINK_GUARD_HIP_DOWN] = hn;
    wk_actuated_force_guards(&MODEL, phase, x, p, p[I_FRICTION], p[I_SLOPE],
                             g + WK_FIVE_LINK_GUARD_SLIP_FORWARD, g + N_BASE_GUARDS, ctx);
}

/* The heel strike's reset: the run ends for a step too short (the swing foot not ahead of
 * the stance foot). */
static void strike(int64_t phase, const double *x, const double *p, double *x_new,
                   double *impulse, int64_t *out, void *ctx)
{
    double pts[6 * 2], ahead, height;
    wk_five_link_points(x, p, pts);
    wk_slope_frame(pts + 8, p[I_SLOPE], &ahead, &height);
    if (ahead <= WK_MIN_STEP * (p[I_LENGTH_FEMUR] + p[I_LENGTH_TIBIA]))
        wk_reset_out(out, WK_EVENT_TERMINAL, phase, WK_TRIPPED);
    else
        wk_actuated_heel_strike(&MODEL, phase, x, p, x_new, impulse, out, ctx);
}

WK_ACTUATED_MODEL(five_link, MODEL)

/* ------------------------------------------------------------------------------------------
 * Terrain (wk_terrain.h): the swing foot's signed distance from the step's plane (its
 * coordinates along the step's slope, plus h cos(gamma)); the stance foot's contact guards in
 * the frame of the plane it stands on (the previous step's); the heel strike's impulse along
 * and normal to the step's plane, the trailing foot's lift-off from the previous one.  The
 * controller is the model's own ctx (wk_terrain.inner).
 * ------------------------------------------------------------------------------------------ */
#include "wk_terrain.h"

static void terrain_guards(int64_t phase, double t, const double *x, const double *p,
                           double *g, void *ctx)
{
    const wk_terrain *T = (const wk_terrain *)ctx;
    wk_model_five_link_guards(phase, t, x, p, g, T->inner);
    if (T->ground.plane) return;
    double pts[6 * 2], ahead, height;
    wk_five_link_points(x, p, pts);
    wk_slope_frame(pts + 8, T->ground.slope, &ahead, &height);
    g[WK_FIVE_LINK_GUARD_HEEL_STRIKE] = height + T->ground.drop * cos(T->ground.slope);
    wk_actuated_force_guards(&MODEL, phase, x, p, p[I_FRICTION], T->ground.prev_slope,
                             g + WK_FIVE_LINK_GUARD_SLIP_FORWARD, g + N_BASE_GUARDS, T->inner);
}

static void terrain_reset(int64_t phase, int64_t k, double t, const double *x, const double *p,
                          double *x_new, double *impulse, int64_t *out, void *ctx)
{
    const wk_terrain *T = (const wk_terrain *)ctx;
    if (T->ground.plane || k != WK_FIVE_LINK_GUARD_HEEL_STRIKE) {
        wk_model_five_link_reset(phase, k, t, x, p, x_new, impulse, out, T->inner);
        return;
    }
    for (int i = 0; i < N_X; i++) x_new[i] = x[i];
    double pts[6 * 2], ahead, height;
    wk_five_link_points(x, p, pts);
    wk_slope_frame(pts + 8, T->ground.slope, &ahead, &height);
    if (ahead <= WK_MIN_STEP * (p[I_LENGTH_FEMUR] + p[I_LENGTH_TIBIA]))
        wk_reset_out(out, WK_EVENT_TERMINAL, phase, WK_TRIPPED);
    else
        wk_actuated_heel_strike_on(&MODEL, phase, x, p, T->ground.slope, T->ground.prev_slope,
                                   x_new, impulse, out, T->inner);
}

/* walker.models.five_link._tibia_on_ground: the swing tibia's angle that puts the swing foot
 * on the scene's slope behind its knee, and (with dtib non-NULL) its derivatives by z[0..3];
 * the same operations.  NaN (and NaN derivatives) where the foot cannot reach the slope (the
 * Python lift raises; the compiled start checks then refuse the start). */
static double tibia_on_ground(const double *z, const double *p, double *dtib)
{
    const double lf = p[I_LENGTH_FEMUR], lt = p[I_LENGTH_TIBIA], s = p[I_SLOPE];
    const double tst = z[0] - 0.5 * z[1], fst = z[0] + 0.5 * z[1];
    const double c = (lt * cos(tst + s) + lf * cos(fst + s) - lf * cos(z[3] + s)) / lt;
    if (!(-1.0 < c && c < 1.0)) {
        if (dtib != NULL)
            for (int i = 0; i < 4; i++) dtib[i] = NAN;
        return NAN;
    }
    const double psi = -acos(c);
    if (dtib != NULL) {
        const double root = sqrt(1.0 - c * c);
        dtib[0] = (-(lt * sin(tst + s) + lf * sin(fst + s)) / lt) / root;
        dtib[1] = ((0.5 * lt * sin(tst + s) - 0.5 * lf * sin(fst + s)) / lt) / root;
        dtib[2] = 0.0 / root;
        dtib[3] = (lf * sin(z[3] + s) / lt) / root;
    }
    return psi - s;
}

/* walker.models.five_link.lift: the section point z (9) -> the full state (12) just after
 * heel strike; the same operations. */
static void five_link_lift(const double *z, const double *p, double *out, void *ctx)
{
    (void)ctx;
    const double tib = tibia_on_ground(z, p, NULL);
    for (int i = 0; i < 4; i++) out[i] = z[i];
    out[4] = tib;
    for (int i = 0; i < 5; i++) out[5 + i] = z[4 + i];
    out[10] = 0.0;
    out[11] = 0.0;
}

/* walker.models.five_link.lift_jacobian at z, out (12, 9) row-major. */
static void five_link_lift_jacobian(const double *z, const double *p, double *out, void *ctx)
{
    (void)ctx;
    double dtib[4];
    (void)tibia_on_ground(z, p, dtib);
    for (int i = 0; i < N_X * 9; i++) out[i] = 0.0;
    for (int i = 0; i < 4; i++) out[i * 9 + i] = 1.0;
    for (int j = 0; j < 4; j++) out[4 * 9 + j] = dtib[j];
    for (int i = 0; i < 5; i++) out[(5 + i) * 9 + 4 + i] = 1.0;
}

const wk_terrain_entry wk_terrain_entry_five_link = {
    WK_ENTRY_NAME_five_link, wk_model_five_link_guards, I_SLOPE, terrain_guards, terrain_reset, 1, -1, 0,
    five_link_lift, five_link_lift_jacobian,
};
