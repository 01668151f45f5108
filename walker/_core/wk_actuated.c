/* The phase functions the actuated walkers (model_three_link.c, model_five_link.c) share:
 * C ports of the actuated_* functions, central_difference_jac, slope_frame and impact_status
 * of walker/models/_common.py, with the same operations in the same order (wk_actuated.h). */
#include <math.h>
#include <stddef.h>
#include "wk_common.h"
#include "wk_terrain.h"
#include "wk_control.h"
#include "wk_friction.h"
#include "wk_actuated.h"

#define MAX_Q WK_ACTUATED_MAX_Q
#define MAX_J WK_FRICTION_MAX_JOINTS

int wk_actuated_torque(void *ctx, const double *q, const double *qd, const double *D,
                       const double *h, const double *B, const double *p, int control_offset,
                       double *u, int n)
{
    const wk_controller *ctl = (const wk_controller *)ctx;
    if (ctl != NULL && ctl->torque != NULL)
        return ctl->torque(q, qd, D, h, B, p, u, ctl->user) != 0;
    return wk_control_controller_torque(q, qd, D, h, B, p + control_offset, u, n);
}

/* The mass matrix D, the generalized force without dry friction f and the controller torque
 * u at state x (M->force on the kernels' D and h); returns 1 when the torque saturated. */
static int forces(const wk_actuated_model *M, const double *x, const double *p, double *D,
                  double *f, double *u, void *ctx)
{
    const double *qd = x + M->n_q;
    double h[MAX_Q];
    M->mass_matrix(x, p, D);
    M->bias(x, qd, p, h);
    return M->force(x, qd, D, h, p, f, u, ctx);
}

int wk_actuated_closed_loop(const wk_actuated_model *M, int64_t phase, const double *x,
                            const double *p, double *qdd, double *u, double *lam, void *ctx)
{
    double D[MAX_Q * MAX_Q], f[MAX_Q], F[MAX_J];
    int64_t modes[MAX_J];
    int sat = forces(M, x, p, D, f, u, ctx);
    wk_friction_decode(phase, modes, M->n_joints);
    M->dry(p, F);
    wk_friction_accelerations(D, f, M->S, F, modes, M->n_q, M->n_joints, qdd, lam);
    return sat;
}

void wk_actuated_rhs(const wk_actuated_model *M, int64_t phase, double t, const double *x,
                     const double *p, double *dx, void *ctx)
{
    (void)t;
    int n = M->n_q;
    double qdd[MAX_Q], u[MAX_J], lam[MAX_J];
    int sat = wk_actuated_closed_loop(M, phase, x, p, qdd, u, lam, ctx);
    for (int i = 0; i < n; i++) {
        dx[i] = x[n + i];
        dx[n + i] = qdd[i];
    }
    dx[2 * n] = M->power(u, x);
    dx[2 * n + 1] = sat ? 1.0 : 0.0;
}

void wk_actuated_jac(wk_rhs_fn rhs, int64_t phase, double t, const double *x, const double *p,
                     double *J, void *ctx, int n_x, double rel_step)
{
    double xp[WK_ACTUATED_MAX_X], fp[WK_ACTUATED_MAX_X], fm[WK_ACTUATED_MAX_X];
    for (int i = 0; i < n_x; i++) xp[i] = x[i];
    for (int j = 0; j < n_x; j++) {
        double ax = fabs(x[j]);
        double hstep = rel_step * (ax > 1.0 ? ax : 1.0);
        xp[j] = x[j] + hstep;
        rhs(phase, t, xp, p, fp, ctx);
        xp[j] = x[j] - hstep;
        rhs(phase, t, xp, p, fm, ctx);
        xp[j] = x[j];
        for (int i = 0; i < n_x; i++) J[i * n_x + j] = (fp[i] - fm[i]) / (2.0 * hstep);
    }
}

void wk_slope_frame(const double *v, double slope, double *t, double *n)
{
    *t = v[0] * cos(slope) - v[1] * sin(slope);
    *n = v[0] * sin(slope) + v[1] * cos(slope);
}

void wk_actuated_force_guards(const wk_actuated_model *M, int64_t phase, const double *x,
                              const double *p, double mu, double slope, double *g_contact,
                              double *g_joints, void *ctx)
{
    int n = M->n_q;
    double qdd[MAX_Q], u[MAX_J], lam[MAX_J], F[MAX_J], R[2], ft, fn;
    int64_t modes[MAX_J];
    wk_actuated_closed_loop(M, phase, x, p, qdd, u, lam, ctx);
    M->ground_reaction(x, x + n, qdd, p, R);
    wk_slope_frame(R, slope, &ft, &fn);
    g_contact[0] = mu * fn - ft;
    g_contact[1] = mu * fn + ft;
    g_contact[2] = fn;
    wk_friction_decode(phase, modes, M->n_joints);
    M->dry(p, F);
    wk_friction_guards(M->S, F, modes, x + n, lam, n, M->n_joints, g_joints);
}

int64_t wk_impact_status(const double *impulse, double lift, double mu)
{
    if (!(impulse[1] > 0.0) || !(fabs(impulse[0]) <= mu * impulse[1]) || !(lift > 0.0))
        return WK_NONPHYSICAL_IMPACT;
    return 0;
}

/* actuated_settle: chooses the modes of the free joints at state x (in place), projects the
 * velocities of the stuck joints (in x) and returns the phase; -1 if singular. */
static int64_t settle(const wk_actuated_model *M, int64_t *modes, const bool *free_joints,
                      double *x, const double *p, void *ctx)
{
    int n = M->n_q;
    double D[MAX_Q * MAX_Q], f[MAX_Q], u[MAX_J], F[MAX_J], qd[MAX_Q], qd_new[MAX_Q];
    forces(M, x, p, D, f, u, ctx);
    M->dry(p, F);
    for (int i = 0; i < n; i++) qd[i] = x[n + i];
    if (!wk_friction_settle(D, f, M->S, F, qd, free_joints, n, M->n_joints, modes, qd_new))
        return -1;
    for (int i = 0; i < n; i++) x[n + i] = qd_new[i];
    return wk_friction_encode(modes, M->n_joints);
}

/* Floating-base heel-strike impact and leg swap; returns a status (0 for a physical
 * impact). */
static int64_t impact(const wk_actuated_model *M, const double *x, const double *p,
                      double *x_new, double *impulse)
{
    double qdf_plus[WK_FLOATING_BASE_MAX], lift;
    if (!wk_floating_base_heel_strike(&M->base, x, x + M->n_q, p, p[M->i_slope], qdf_plus,
                                      impulse, &lift))
        return WK_LINEAR_SOLVE_FAILED;
    M->relabel(x, qdf_plus, x_new);
    return wk_impact_status(impulse, lift, p[M->i_friction]);
}

static void after_impact(const wk_actuated_model *M, int64_t phase, int64_t status,
                         const double *p, double *x_new, int64_t *out, void *ctx);

void wk_actuated_heel_strike(const wk_actuated_model *M, int64_t phase, const double *x,
                             const double *p, double *x_new, double *impulse, int64_t *out,
                             void *ctx)
{
    after_impact(M, phase, impact(M, x, p, x_new, impulse), p, x_new, out, ctx);
}

void wk_actuated_heel_strike_on(const wk_actuated_model *M, int64_t phase, const double *x,
                                const double *p, double slope, double trailing_slope,
                                double *x_new, double *impulse, int64_t *out, void *ctx)
{
    double qdf_plus[WK_FLOATING_BASE_MAX], lift;
    int64_t status = WK_LINEAR_SOLVE_FAILED;
    if (wk_floating_base_heel_strike(&M->base, x, x + M->n_q, p, trailing_slope, qdf_plus,
                                     impulse, &lift)) {
        M->relabel(x, qdf_plus, x_new);
        wk_terrain_rotate_impulse(impulse, trailing_slope, slope);
        status = wk_impact_status(impulse, lift, p[M->i_friction]);
    }
    after_impact(M, phase, status, p, x_new, out, ctx);
}

/* The heel strike after its impact: the run ends for a status, else the joints' modes are
 * chosen for the new stance. */
static void after_impact(const wk_actuated_model *M, int64_t phase, int64_t status,
                         const double *p, double *x_new, int64_t *out, void *ctx)
{
    if (status != 0) {
        wk_reset_out(out, WK_EVENT_TERMINAL, phase, status);
        return;
    }
    int64_t modes[MAX_J];
    bool free_joints[MAX_J];
    for (int j = 0; j < M->n_joints; j++) {
        modes[j] = 0;
        free_joints[j] = true;
    }
    int64_t new_phase = settle(M, modes, free_joints, x_new, p, ctx);
    if (new_phase < 0) {
        wk_reset_out(out, WK_EVENT_TERMINAL, phase, WK_LINEAR_SOLVE_FAILED);
        return;
    }
    wk_reset_out(out, WK_EVENT_STRIDE, new_phase, 0);
}

/* actuated_joint_event: the reset of joint friction event 2 j (slip_stops) or 2 j + 1
 * (stick_breaks) of joint j. */
static void joint_event(const wk_actuated_model *M, int64_t phase, int64_t event,
                        const double *x, const double *p, double *x_new, int64_t *out,
                        void *ctx)
{
    int n = M->n_q;
    int64_t modes[MAX_J];
    double D[MAX_Q * MAX_Q], f[MAX_Q], u[MAX_J], F[MAX_J], qd[MAX_Q], qd_new[MAX_Q];
    wk_friction_decode(phase, modes, M->n_joints);
    forces(M, x, p, D, f, u, ctx);
    M->dry(p, F);
    for (int i = 0; i < n; i++) qd[i] = x[n + i];
    int64_t j = event / 2;
    bool breaks = event % 2 == 1;
    if (!wk_friction_switch(D, f, M->S, F, qd, j, breaks, n, M->n_joints, modes, qd_new)) {
        wk_reset_out(out, WK_EVENT_TERMINAL, phase, WK_LINEAR_SOLVE_FAILED);
        return;
    }
    for (int i = 0; i < n; i++) x_new[n + i] = qd_new[i];
    wk_reset_out(out, WK_EVENT_CONTINUE, wk_friction_encode(modes, M->n_joints), 0);
}

void wk_actuated_reset(const wk_actuated_model *M, wk_strike_fn strike, int64_t phase, int64_t k,
                       double t, const double *x, const double *p, double *x_new,
                       double *impulse, int64_t *out, void *ctx)
{
    (void)t;
    for (int i = 0; i < 2 * M->n_q + 2; i++) x_new[i] = x[i];
    if (k == 0)
        strike(phase, x, p, x_new, impulse, out, ctx);
    else if (k < M->n_base_guards)
        wk_reset_out(out, WK_EVENT_TERMINAL, phase, M->base_status[k]);
    else
        joint_event(M, phase, k - M->n_base_guards, x, p, x_new, out, ctx);
}

int64_t wk_actuated_start_phase(const wk_actuated_model *M, const double *x, const double *p,
                                void *ctx)
{
    int n = M->n_q;
    double D[MAX_Q * MAX_Q], f[MAX_Q], u[MAX_J], F[MAX_J], qd[MAX_Q];
    int64_t modes[MAX_J];
    bool free_joints[MAX_J];
    for (int j = 0; j < M->n_joints; j++) {
        modes[j] = 0;
        free_joints[j] = true;
    }
    forces(M, x, p, D, f, u, ctx);
    M->dry(p, F);
    for (int i = 0; i < n; i++) qd[i] = x[n + i];
    wk_friction_choose_modes(D, f, M->S, F, qd, free_joints, n, M->n_joints, modes);
    return wk_friction_encode(modes, M->n_joints);
}
