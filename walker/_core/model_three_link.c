/* Grizzle's three-link walker in closed loop with hip friction (described in
 * walker/models/three_link.py; the operations of walker's former numba phase functions, in
 * the same order).  State
 * (q_stance, q_swing, q_torso, qd_stance, qd_swing, qd_torso, actuator_work,
 * saturated_time); phase = joint-mode code of (hip_stance, hip_swing) (wk_friction.h);
 * guards heel_strike, fall_forward, fall_backward, slip_forward, slip_backward, lift_off,
 * then slip_stops / stick_breaks per joint.  The controller comes from ctx (wk_actuated.h).
 * Also controller mode 3 (the finite-time controller on polynomial outputs,
 * wk_control_finite_time_torque, with its own Jacobian treatment in jac) and step_event = 1
 * (guard 0 is q_stance - theta_minus). */
#include <math.h>
#include <stddef.h>
#include "wk_common.h"
#include "wk_control.h"
#include "wk_friction.h"
#include "wk_actuated.h"
#include "three_link.h"

#define N_X WK_THREE_LINK_N_X
#define N_Q 3
#define N_U WK_THREE_LINK_N_INPUTS
#define N_JOINTS WK_THREE_LINK_N_JOINTS
#define N_BASE_GUARDS 6
#define I_LEG_A WK_THREE_LINK_P_COM_FROM_FOOT
#define I_LEG_B WK_THREE_LINK_P_COM_TO_HIP
#define I_SLOPE WK_THREE_LINK_P_SLOPE
#define I_FRICTION WK_THREE_LINK_P_FRICTION
#define CONTROL_OFFSET WK_THREE_LINK_CONTROL_OFFSET
#define I_STEP_EVENT WK_THREE_LINK_P_STEP_EVENT
#define I_FT WK_THREE_LINK_P_FT_ALPHA /* the finite-time block (wk_control.h): ft_alpha, ft_epsilon, poly_* */
#define I_DAMPING_HIP WK_THREE_LINK_P_DAMPING_HIP
#define I_COULOMB_HIP WK_THREE_LINK_P_COULOMB_HIP
#define I_THETA_MINUS WK_THREE_LINK_P_THETA_MINUS
#define JAC_STEP 1e-6
#define JAC_STEP_FT 1e-4 /* mode 3 (see wk_model_three_link_jac) */

static const double B_MATRIX[N_Q * N_U] = {1.0, 0.0, 0.0, 1.0, -1.0, -1.0};
static const double S_MATRIX[N_JOINTS * N_Q] = {1.0, 0.0, -1.0, 0.0, 1.0, -1.0};

/* The controller's torque: the user's (ctx, wk_actuated.h) or the built-in one (mode 3,
 * the finite-time controller on polynomial outputs, reads the block p + I_FT). */
static int torque(void *ctx, const double *q, const double *qd, const double *D,
                  const double *h, const double *p, double *u)
{
    const wk_controller *ctl = (const wk_controller *)ctx;
    if ((ctl == NULL || ctl->torque == NULL) &&
        (int64_t)p[CONTROL_OFFSET + WK_CONTROL_I_MODE] == WK_CONTROL_MODE_FINITE_TIME)
        return wk_control_finite_time_torque(q, qd, D, h, B_MATRIX, p + CONTROL_OFFSET,
                                             p + I_FT, u, N_Q);
    return wk_actuated_torque(ctx, q, qd, D, h, B_MATRIX, p, CONTROL_OFFSET, u, N_Q);
}

/* Generalized force without dry friction f = B u - h - F_v S^T S qd and controller torque u
 * (wk_actuated_model.force); returns 1 when the torque saturated. */
static int force(const double *q, const double *qd, const double *D, const double *h,
                 const double *p, double *f, double *u, void *ctx)
{
    int sat = torque(ctx, q, qd, D, h, p, u);
    for (int i = 0; i < 3; i++)
        f[i] = B_MATRIX[i * N_U + 0] * u[0] + B_MATRIX[i * N_U + 1] * u[1] - h[i];
    double damping = p[I_DAMPING_HIP];
    if (damping != 0.0) {
        for (int j = 0; j < N_JOINTS; j++) {
            const double *S = S_MATRIX + j * N_Q;
            double w = S[0] * qd[0] + S[1] * qd[1] + S[2] * qd[2];
            for (int i = 0; i < 3; i++) f[i] -= damping * S[i] * w;
        }
    }
    return sat;
}

/* Dry-friction magnitudes of the joints [N m]. */
static void dry(const double *p, double *F)
{
    F[0] = p[I_COULOMB_HIP];
    F[1] = p[I_COULOMB_HIP];
}

/* Actuator power: u . (B^T qd), B^T qd = relative hip rates. */
static double power(const double *u, const double *x)
{
    return u[0] * (x[3] - x[5]) + u[1] * (x[4] - x[5]);
}

/* The leg swap at heel strike: (q_swing, q_stance, q_torso) and the post-impact rates
 * likewise. */
static void relabel(const double *x, const double *qdf_plus, double *x_new)
{
    static const int swap[N_Q] = {1, 0, 2};
    wk_swap_legs(swap, N_Q, x, qdf_plus, x_new);
}

/* Statuses of the base guards after heel strike: fall_forward, fall_backward, slip_forward,
 * slip_backward, lift_off. */
static const int64_t BASE_STATUS[N_BASE_GUARDS] = {
    0, WK_FELL_FORWARD, WK_FELL_BACKWARD, WK_NONPHYSICAL_IMPACT, WK_NONPHYSICAL_IMPACT,
    WK_NONPHYSICAL_IMPACT,
};

/* The model's table (wk_actuated.h): the hip at row 1 of the 4 points. */
static const wk_actuated_model MODEL = {
    N_Q, N_JOINTS, S_MATRIX, WK_ACTUATED_KERNELS(three_link, N_Q, 4, 1),
    force, dry, power, relabel, I_SLOPE, I_FRICTION, N_BASE_GUARDS, BASE_STATUS,
};

/* Mode 3's linearized controller (wk_control.h), handed to the rhs as a user controller. */
typedef struct {
    double lin[5 * (N_Q - 1)];
} ft_linearized;

static int ft_linearized_torque(const double *q, const double *qd, const double *D,
                                const double *h, const double *B, const double *p, double *u,
                                void *user)
{
    const ft_linearized *L = (const ft_linearized *)user;
    return wk_control_finite_time_torque_linearized(q, qd, D, h, B, p + CONTROL_OFFSET,
                                                    p + I_FT, L->lin, u, N_Q);
}

void wk_model_three_link_jac(int64_t phase, double t, const double *x, const double *p,
                             double *J, void *ctx)
{
    const wk_controller *ctl = (const wk_controller *)ctx;
    ft_linearized L;
    wk_controller lin_ctl;
    double rel_step = JAC_STEP;
    if ((ctl == NULL || ctl->torque == NULL) &&
        (int64_t)p[CONTROL_OFFSET + WK_CONTROL_I_MODE] == WK_CONTROL_MODE_FINITE_TIME) {
        /* differentiate with v linearized about x (wk_control_finite_time_linearization) */
        wk_control_finite_time_linearization(x, x + 3, p + I_FT, L.lin, N_Q);
        lin_ctl.torque = ft_linearized_torque;
        lin_ctl.user = &L;
        ctx = &lin_ctl;
        rel_step = JAC_STEP_FT;
    }
    wk_actuated_jac(wk_model_three_link_rhs, phase, t, x, p, J, ctx, N_X, rel_step);
}

/* (height above the slope, distance ahead of the stance foot along the slope) [m]. */
static void swing_foot(const double *x, const double *p, double *height, double *ahead)
{
    double r = p[I_LEG_A] + p[I_LEG_B];
    double psi1 = x[0] + p[I_SLOPE];
    double psi2 = x[1] + p[I_SLOPE];
    *height = r * (cos(psi1) - cos(psi2));
    *ahead = r * (sin(psi2) - sin(psi1));
}

void wk_model_three_link_guards(int64_t phase, double t, const double *x, const double *p,
                                double *g, void *ctx)
{
    (void)t;
    double psi1 = x[0] + p[I_SLOPE];
    double height, ahead;
    swing_foot(x, p, &height, &ahead);
    /* step_event 1: the step ends where the stance angle falls through theta_minus (the
     * impact surface of Westervelt et al. 2007), wherever the swing foot is */
    g[WK_THREE_LINK_GUARD_HEEL_STRIKE] = p[I_STEP_EVENT] == 1.0 ? x[0] - p[I_THETA_MINUS] : height;
    g[WK_THREE_LINK_GUARD_FALL_FORWARD] = psi1 + WK_FALL_ANGLE;
    g[WK_THREE_LINK_GUARD_FALL_BACKWARD] = psi1 - WK_FALL_ANGLE;
    wk_actuated_force_guards(&MODEL, phase, x, p, p[I_FRICTION], p[I_SLOPE],
                             g + WK_THREE_LINK_GUARD_SLIP_FORWARD, g + N_BASE_GUARDS, ctx);
}

/* The heel strike's reset: none for a step too short (step_event 1 fires the guard wherever
 * the swing foot is). */
static void strike(int64_t phase, const double *x, const double *p, double *x_new,
                   double *impulse, int64_t *out, void *ctx)
{
    double height, ahead;
    swing_foot(x, p, &height, &ahead);
    if (ahead <= WK_MIN_STEP * (p[I_LEG_A] + p[I_LEG_B]))
        wk_reset_out(out, WK_EVENT_IGNORE, phase, 0);
    else
        wk_actuated_heel_strike(&MODEL, phase, x, p, x_new, impulse, out, ctx);
}

WK_ACTUATED_MODEL(three_link, MODEL)

/* ------------------------------------------------------------------------------------------
 * Terrain (wk_terrain.h): the swing foot's signed distance from the step's plane
 * r (cos(q_st + gamma) - cos(q_sw + gamma)) + h cos(gamma) ends the step (step_event 1, a
 * step ending on the controller's surface, is refused by walker/simulation/_terrain_run.py); the
 * stance foot's contact guards in the frame of the plane it stands on (the previous step's);
 * the heel strike's impulse along and
 * normal to the step's plane, the trailing foot's lift-off from the previous one.  The
 * controller is the model's own ctx (wk_terrain.inner).
 * ------------------------------------------------------------------------------------------ */
#include "wk_terrain.h"

static void terrain_guards(int64_t phase, double t, const double *x, const double *p,
                           double *g, void *ctx)
{
    const wk_terrain *T = (const wk_terrain *)ctx;
    if (T->ground.plane) {
        wk_model_three_link_guards(phase, t, x, p, g, T->inner);
        return;
    }
    const double r = p[I_LEG_A] + p[I_LEG_B], gam = T->ground.slope;
    const double psi1 = x[0] + p[I_SLOPE];
    g[WK_THREE_LINK_GUARD_HEEL_STRIKE] =
        r * (cos(x[0] + gam) - cos(x[1] + gam)) + T->ground.drop * cos(gam);
    g[WK_THREE_LINK_GUARD_FALL_FORWARD] = psi1 + WK_FALL_ANGLE;
    g[WK_THREE_LINK_GUARD_FALL_BACKWARD] = psi1 - WK_FALL_ANGLE;
    wk_actuated_force_guards(&MODEL, phase, x, p, p[I_FRICTION], T->ground.prev_slope,
                             g + WK_THREE_LINK_GUARD_SLIP_FORWARD, g + N_BASE_GUARDS, T->inner);
}

static void terrain_reset(int64_t phase, int64_t k, double t, const double *x, const double *p,
                          double *x_new, double *impulse, int64_t *out, void *ctx)
{
    const wk_terrain *T = (const wk_terrain *)ctx;
    if (T->ground.plane || k != WK_THREE_LINK_GUARD_HEEL_STRIKE) {
        wk_model_three_link_reset(phase, k, t, x, p, x_new, impulse, out, T->inner);
        return;
    }
    for (int i = 0; i < N_X; i++) x_new[i] = x[i];
    const double r = p[I_LEG_A] + p[I_LEG_B], gam = T->ground.slope;
    if (r * (sin(x[1] + gam) - sin(x[0] + gam)) <= WK_MIN_STEP * r)
        wk_reset_out(out, WK_EVENT_IGNORE, phase, 0);
    else
        wk_actuated_heel_strike_on(&MODEL, phase, x, p, gam, T->ground.prev_slope, x_new,
                                   impulse, out, T->inner);
}

const wk_terrain_entry wk_terrain_entry_three_link = {
    WK_ENTRY_NAME_three_link, wk_model_three_link_guards, I_SLOPE, terrain_guards, terrain_reset, 1, -1,
    0,
};
