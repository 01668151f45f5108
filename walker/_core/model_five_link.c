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
#include "wk_control.h"
#include "wk_friction.h"
#include "wk_actuated.h"
#include "five_link.h"

#define N_X 12
#define N_Q 5
#define N_U 4
#define N_JOINTS 4
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

/* The controller's torque: the user's (ctx, wk_actuated.h) or the built-in one. */
static int torque(void *ctx, const double *q, const double *qd, const double *D,
                  const double *h, const double *p, double *u)
{
    const wk_controller *ctl = (const wk_controller *)ctx;
    if (ctl != NULL && ctl->torque != NULL)
        return ctl->torque(q, qd, D, h, B_MATRIX, p, u, ctl->user) != 0;
    return wk_control_controller_torque(q, qd, D, h, B_MATRIX, p + CONTROL_OFFSET, u, N_Q);
}

/* Mass matrix D, generalized force without dry friction f = B u - h - S^T F_v S qd and
 * controller torque u; returns 1 when the torque saturated. */
static int forces(const double *x, const double *p, double *D, double *f, double *u,
                  void *ctx)
{
    const double *q = x;
    const double *qd = x + 5;
    double h[N_Q];
    wk_five_link_mass_matrix(q, p, D);
    wk_five_link_bias(q, qd, p, h);
    int sat = torque(ctx, q, qd, D, h, p, u);
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

/* Closed-loop accelerations, torques and dry-friction torques in ``phase``; returns 1 when
 * the controller saturated. */
static int closed_loop(int64_t phase, const double *x, const double *p, double *qdd,
                       double *u, double *lam, void *ctx)
{
    double D[N_Q * N_Q], f[N_Q], F[N_JOINTS];
    int64_t modes[N_JOINTS];
    int sat = forces(x, p, D, f, u, ctx);
    wk_friction_decode(phase, modes, N_JOINTS);
    dry(p, F);
    wk_friction_accelerations(D, f, S_MATRIX, F, modes, N_Q, N_JOINTS, qdd, lam);
    return sat;
}

void wk_model_five_link_rhs(int64_t phase, double t, const double *x, const double *p,
                            double *dx, void *ctx)
{
    (void)t;
    double qdd[N_Q], u[N_U], lam[N_JOINTS];
    int sat = closed_loop(phase, x, p, qdd, u, lam, ctx);
    double power = 0.0;
    for (int i = 0; i < 5; i++) {
        dx[i] = x[5 + i];
        dx[5 + i] = qdd[i];
        for (int j = 0; j < 4; j++) power += u[j] * B_MATRIX[i * N_U + j] * x[5 + i];
    }
    dx[10] = power; /* u . (B^T qd) */
    dx[11] = sat ? 1.0 : 0.0;
}

void wk_model_five_link_jac(int64_t phase, double t, const double *x, const double *p,
                            double *J, void *ctx)
{
    double xp[N_X], fp[N_X], fm[N_X];
    for (int i = 0; i < N_X; i++) xp[i] = x[i];
    for (int j = 0; j < N_X; j++) {
        double ax = fabs(x[j]);
        double hstep = JAC_STEP * (ax > 1.0 ? ax : 1.0);
        xp[j] = x[j] + hstep;
        wk_model_five_link_rhs(phase, t, xp, p, fp, ctx);
        xp[j] = x[j] - hstep;
        wk_model_five_link_rhs(phase, t, xp, p, fm, ctx);
        xp[j] = x[j];
        for (int i = 0; i < N_X; i++) J[i * N_X + j] = (fp[i] - fm[i]) / (2.0 * hstep);
    }
}

/* Ground force on the stance foot (F_t, F_n) for the accelerations qdd [N]. */
static void slope_frame_force(const double *x, const double *p, const double *qdd,
                              double *ft, double *fn)
{
    double F[2];
    wk_five_link_ground_reaction(x, x + 5, qdd, p, F);
    double slope = p[I_SLOPE];
    *ft = F[0] * cos(slope) - F[1] * sin(slope);
    *fn = F[0] * sin(slope) + F[1] * cos(slope);
}

/* (along the slope, normal to it) components of a world vector. */
static void slope_frame(const double *v, double slope, double *t, double *n)
{
    *t = v[0] * cos(slope) - v[1] * sin(slope);
    *n = v[0] * sin(slope) + v[1] * cos(slope);
}

void wk_model_five_link_guards(int64_t phase, double t, const double *x, const double *p,
                               double *g, void *ctx)
{
    (void)t;
    double pts[6 * 2];
    wk_five_link_points(x, p, pts);
    double slope = p[I_SLOPE];
    double ft_, fn_;
    slope_frame(pts + 8, slope, &ft_, &fn_);
    g[WK_FIVE_LINK_GUARD_HEEL_STRIKE] = fn_;
    double ht, hn;
    slope_frame(pts + 4, slope, &ht, &hn);
    double psi = atan2(-ht, hn); /* stance foot -> hip, from the slope normal */
    g[WK_FIVE_LINK_GUARD_FALL_FORWARD] = psi + WK_FALL_ANGLE;
    g[WK_FIVE_LINK_GUARD_FALL_BACKWARD] = psi - WK_FALL_ANGLE;
    double qdd[N_Q], u[N_U], lam[N_JOINTS];
    closed_loop(phase, x, p, qdd, u, lam, ctx);
    double ft, fn;
    slope_frame_force(x, p, qdd, &ft, &fn);
    double mu = p[I_FRICTION];
    g[WK_FIVE_LINK_GUARD_SLIP_FORWARD] = mu * fn - ft;
    g[WK_FIVE_LINK_GUARD_SLIP_BACKWARD] = mu * fn + ft;
    g[WK_FIVE_LINK_GUARD_LIFT_OFF] = fn;
    g[WK_FIVE_LINK_GUARD_HIP_DOWN] = hn;
    int64_t modes[N_JOINTS];
    double F[N_JOINTS];
    wk_friction_decode(phase, modes, N_JOINTS);
    dry(p, F);
    wk_friction_guards(S_MATRIX, F, modes, x + 5, lam, N_Q, N_JOINTS, g + N_BASE_GUARDS);
}

/* Floating-base heel-strike impact and leg swap; returns a status (0 for a physical
 * impact) and the impulse on the new stance foot (along the slope, normal to it). */
static int64_t heel_strike(const double *x, const double *p, double *x_new, double *impulse)
{
    /* the hip at row 2 of the 6 points */
    double qdf_plus[7], lift;
    if (!wk_floating_base_heel_strike(wk_five_link_points, wk_five_link_hip_jac,
                                      wk_five_link_ext_mass_matrix,
                                      wk_five_link_ext_swing_contact_jac,
                                      wk_five_link_ext_stance_contact_jac, x, x + 5, p, 5, 6, 2,
                                      p[I_SLOPE], qdf_plus, impulse, &lift))
        return WK_LINEAR_SOLVE_FAILED;
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
    double mu = p[I_FRICTION];
    if (!(impulse[1] > 0.0) || !(fabs(impulse[0]) <= mu * impulse[1]) || !(lift > 0.0))
        return WK_NONPHYSICAL_IMPACT;
    return 0;
}

/* Chooses the modes of the free joints at state x (in place), projects the velocities of
 * the stuck joints (in x) and returns the phase; -1 if singular. */
static int64_t settle(int64_t *modes, const bool *free_joints, double *x, const double *p,
                      void *ctx)
{
    double D[N_Q * N_Q], f[N_Q], u[N_U], F[N_JOINTS], qd[N_Q], qd_new[N_Q];
    forces(x, p, D, f, u, ctx);
    dry(p, F);
    for (int i = 0; i < N_Q; i++) qd[i] = x[5 + i];
    if (!wk_friction_settle(D, f, S_MATRIX, F, qd, free_joints, N_Q, N_JOINTS, modes, qd_new))
        return -1;
    for (int i = 0; i < 5; i++) x[5 + i] = qd_new[i];
    return wk_friction_encode(modes, N_JOINTS);
}

void wk_model_five_link_reset(int64_t phase, int64_t k, double t, const double *x,
                              const double *p, double *x_new, double *impulse, int64_t *out,
                              void *ctx)
{
    (void)t;
    for (int i = 0; i < N_X; i++) x_new[i] = x[i];
    if (k == 0) {
        double pts[6 * 2], ahead, height;
        wk_five_link_points(x, p, pts);
        slope_frame(pts + 8, p[I_SLOPE], &ahead, &height);
        if (ahead <= WK_MIN_STEP * (p[I_LENGTH_FEMUR] + p[I_LENGTH_TIBIA])) {
            wk_reset_out(out, WK_EVENT_TERMINAL, phase, WK_TRIPPED);
            return;
        }
        int64_t status = heel_strike(x, p, x_new, impulse);
        if (status != 0) {
            wk_reset_out(out, WK_EVENT_TERMINAL, phase, status);
            return;
        }
        /* every joint's mode afresh for the post-impact state */
        int64_t modes[N_JOINTS] = {0, 0, 0, 0};
        const bool free_joints[N_JOINTS] = {true, true, true, true};
        int64_t new_phase = settle(modes, free_joints, x_new, p, ctx);
        if (new_phase < 0) {
            wk_reset_out(out, WK_EVENT_TERMINAL, phase, WK_LINEAR_SOLVE_FAILED);
            return;
        }
        wk_reset_out(out, WK_EVENT_STRIDE, new_phase, 0);
        return;
    }
    if (k == 1) {
        wk_reset_out(out, WK_EVENT_TERMINAL, phase, WK_FELL_FORWARD);
        return;
    }
    if (k == 2 || k == 6) {
        wk_reset_out(out, WK_EVENT_TERMINAL, phase, WK_FELL_BACKWARD);
        return;
    }
    if (k < N_BASE_GUARDS) {
        wk_reset_out(out, WK_EVENT_TERMINAL, phase, WK_NONPHYSICAL_IMPACT);
        return;
    }
    /* joint j's slip_stops (plastic lock, then every joint's mode chosen again) or
     * stick_breaks (it slips against its holding torque, the others chosen again) */
    int64_t modes[N_JOINTS];
    double D[N_Q * N_Q], f[N_Q], u[N_U], F[N_JOINTS], qd[N_Q], qd_new[N_Q];
    wk_friction_decode(phase, modes, N_JOINTS);
    forces(x, p, D, f, u, ctx);
    dry(p, F);
    for (int i = 0; i < N_Q; i++) qd[i] = x[5 + i];
    int64_t j = (k - N_BASE_GUARDS) / 2;
    bool breaks = (k - N_BASE_GUARDS) % 2 == 1;
    if (!wk_friction_switch(D, f, S_MATRIX, F, qd, j, breaks, N_Q, N_JOINTS, modes,
                            qd_new)) {
        wk_reset_out(out, WK_EVENT_TERMINAL, phase, WK_LINEAR_SOLVE_FAILED);
        return;
    }
    for (int i = 0; i < 5; i++) x_new[5 + i] = qd_new[i];
    wk_reset_out(out, WK_EVENT_CONTINUE, wk_friction_encode(modes, N_JOINTS), 0);
}

void wk_model_five_link_start_phase(const double *x, const double *p, double *out, void *ctx)
{
    double D[N_Q * N_Q], f[N_Q], u[N_U], F[N_JOINTS], qd[N_Q];
    int64_t modes[N_JOINTS] = {0, 0, 0, 0};
    const bool free_joints[N_JOINTS] = {true, true, true, true};
    forces(x, p, D, f, u, ctx);
    dry(p, F);
    for (int i = 0; i < N_Q; i++) qd[i] = x[5 + i];
    wk_friction_choose_modes(D, f, S_MATRIX, F, qd, free_joints, N_Q, N_JOINTS, modes);
    out[0] = (double)wk_friction_encode(modes, N_JOINTS);
}

void wk_model_five_link_energy(const double *x, const double *p, double *out, void *ctx)
{
    (void)ctx;
    out[0] = wk_five_link_kinetic(x, x + 5, p);
    out[1] = wk_five_link_potential(x, p);
}

void wk_model_five_link_points(const double *x, const double *p, double *out, void *ctx)
{
    (void)ctx;
    wk_five_link_points(x, p, out);
}

const wk_model_entry wk_entry_five_link = {
    "five_link",
    {wk_model_five_link_rhs, wk_model_five_link_guards, wk_model_five_link_reset,
     wk_model_five_link_jac, NULL},
    wk_model_five_link_energy,
    wk_model_five_link_points,
    wk_model_five_link_start_phase,
};
