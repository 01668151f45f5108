/* The rimless wheel: a point mass at the hub on massless spokes of length l, rolling down a
 * slope from spoke to spoke.  Written in C only; the model's description,
 * conventions and the derivation of the impact map are in walker/models/rimless_wheel.py.
 *
 * State (theta, theta_dot): theta is the stance spoke's angle from the slope normal,
 * counterclockwise positive (walker's convention), so a wheel rolling downhill has
 * theta_dot < 0 and theta runs from +a (just after an impact) to -a (the next impact),
 * a = pi / spokes the half-angle between spokes.  p = (spokes, leg_length, g, slope).
 *
 * Phases: 0 rolling (pivoting on the stance spoke), 1 standing (at rest on two spokes).
 * Guards (rolling; constant 1.0 while standing):
 *   0 impact            theta + a decreasing through 0: the leading spoke strikes;
 *   1 back_impact       theta - a increasing through 0: the wheel rolled back onto its
 *                       trailing spoke, which strikes;
 *   2 impact_late       \ the same boundaries LATE = 2 GUARD_TOL beyond: they catch a run
 *   3 back_impact_late  / that starts on a boundary and never arms guard 0 or 1 (the
 *                       integrator arms a guard only once it has been seen more than
 *                       GUARD_TOL on its pre-fire side); same resets as 0 and 1.
 */
#include <math.h>
#include <stddef.h>
#include "hybrid.h"
#include "wk_common.h"
#include "wk_rimless.h"

#define RW_PI 3.141592653589793 /* the double nearest pi, as math.pi */
#define RW_LATE (2.0 * WK_GUARD_TOL)

enum { RW_ROLLING = WK_RIMLESS_WHEEL_PHASE_ROLLING, RW_STANDING = WK_RIMLESS_WHEEL_PHASE_STANDING };

/* Hub velocity [m/s] in the slope frame (along the slope downhill, along the normal) of a
 * wheel pivoting on a foot whose spoke is at angle phi from the slope normal, at rate w: the
 * hub sits at l (-sin phi, cos phi) from the foot. */
static void hub_velocity(double l, double phi, double w, double *v)
{
    v[0] = -l * w * cos(phi);
    v[1] = -l * w * sin(phi);
}

void wk_model_rimless_wheel_rhs(int64_t phase, double t, const double *x, const double *p,
                                double *dx, void *ctx)
{
    (void)t;
    (void)ctx;
    if (phase == RW_STANDING) {
        dx[0] = 0.0;
        dx[1] = 0.0;
        return;
    }
    dx[0] = x[1];
    dx[1] = p[WK_RIMLESS_WHEEL_P_G] / p[WK_RIMLESS_WHEEL_P_LEG_LENGTH] * sin(x[0] - p[WK_RIMLESS_WHEEL_P_SLOPE]);
}

void wk_model_rimless_wheel_jac(int64_t phase, double t, const double *x, const double *p,
                                double *J, void *ctx)
{
    (void)t;
    (void)ctx;
    J[0] = 0.0;
    J[1] = phase == RW_STANDING ? 0.0 : 1.0;
    J[2] = phase == RW_STANDING ? 0.0 : p[WK_RIMLESS_WHEEL_P_G] / p[WK_RIMLESS_WHEEL_P_LEG_LENGTH] * cos(x[0] - p[WK_RIMLESS_WHEEL_P_SLOPE]);
    J[3] = 0.0;
}

void wk_model_rimless_wheel_guards(int64_t phase, double t, const double *x, const double *p,
                                   double *g, void *ctx)
{
    (void)t;
    (void)ctx;
    if (phase == RW_STANDING) {
        for (int i = 0; i < 4; i++) g[i] = 1.0;
        return;
    }
    double a = RW_PI / p[WK_RIMLESS_WHEEL_P_SPOKES];
    g[WK_RIMLESS_WHEEL_GUARD_IMPACT] = x[0] + a;
    g[WK_RIMLESS_WHEEL_GUARD_BACK_IMPACT] = x[0] - a;
    g[WK_RIMLESS_WHEEL_GUARD_IMPACT_LATE] = (x[0] + a) + RW_LATE;
    g[WK_RIMLESS_WHEEL_GUARD_BACK_IMPACT_LATE] = (x[0] - a) - RW_LATE;
}

/* impulse = v_plus - v_minus: the ground's impulse per unit hub mass [m/s], slope frame. */
static void set_impulse(double *impulse, const double *v_plus, const double *v_minus)
{
    impulse[0] = v_plus[0] - v_minus[0];
    impulse[1] = v_plus[1] - v_minus[1];
}

void wk_model_rimless_wheel_reset(int64_t phase, int64_t k, double t, const double *x,
                                  const double *p, double *x_new, double *impulse,
                                  int64_t *out, void *ctx)
{
    (void)t;
    (void)ctx;
    x_new[0] = x[0];
    x_new[1] = x[1];
    impulse[0] = 0.0;
    impulse[1] = 0.0;
    if (phase == RW_STANDING) { /* no guard fires while standing */
        wk_reset_out(out, WK_EVENT_IGNORE, phase, 0);
        return;
    }
    double l = p[WK_RIMLESS_WHEEL_P_LEG_LENGTH], gl = p[WK_RIMLESS_WHEEL_P_G] / p[WK_RIMLESS_WHEEL_P_LEG_LENGTH], slope = p[WK_RIMLESS_WHEEL_P_SLOPE];
    double a = RW_PI / p[WK_RIMLESS_WHEEL_P_SPOKES];
    /* cos(2a) > 0 (the trailing foot leaves the ground) from 5 spokes on; exactly 0 for 4
     * spokes, where cos(2 * (pi/4)) would round to 6e-17 */
    double c = p[WK_RIMLESS_WHEEL_P_SPOKES] > 4.0 ? cos(2.0 * a) : 0.0;
    double w = x[1];
    double v_minus[2], v_plus[2] = {0.0, 0.0};
    hub_velocity(l, x[0], w, v_minus);
    int64_t rest_phase = slope < a ? RW_STANDING : RW_ROLLING;

    if (k == 0 || k == 2) { /* the leading spoke strikes */
        if (c > 0.0) {      /* angular momentum about the new foot: w+ = cos(2a) w- */
            x_new[0] = a;
            x_new[1] = c * w;
            hub_velocity(l, a, x_new[1], v_plus);
            set_impulse(impulse, v_plus, v_minus);
            wk_reset_out(out, WK_EVENT_STRIDE, RW_ROLLING, 0);
            return;
        }
        /* 3 or 4 spokes: the trailing foot cannot leave the ground, the wheel stops on both
         * spokes; from rest it stands (|slope| < a), tips forward (slope >= a) or back. */
        if (slope <= -a) {
            wk_reset_out(out, WK_EVENT_TERMINAL, phase, WK_FELL_BACKWARD);
            return;
        }
        x_new[0] = a;
        x_new[1] = 0.0;
        set_impulse(impulse, v_plus, v_minus);
        wk_reset_out(out, WK_EVENT_STRIDE, rest_phase, 0);
        return;
    }

    /* k == 1 or 3: the trailing spoke strikes (w > 0, rolling back). */
    double w1 = c > 0.0 ? c * w : 0.0; /* rate about the trailing foot after the impact */
    if (slope <= -a || w1 * w1 >= 2.0 * gl * (1.0 - cos(a + slope))) {
        /* it rolls back over the trailing spoke: a fall backward */
        wk_reset_out(out, WK_EVENT_TERMINAL, phase, WK_FELL_BACKWARD);
        return;
    }
    if (c <= 0.0 || (slope < a && c * c * w1 * w1 < 2.0 * gl * (1.0 - cos(a - slope)))) {
        /* it rocks between the two spokes, every impact scaling the rate by cos(2a), and
         * comes to rest on both (at once for 3 or 4 spokes): the Zeno sequence of rocking
         * impacts is not integrated, the wheel is put at rest here. */
        x_new[0] = a;
        x_new[1] = 0.0;
        set_impulse(impulse, v_plus, v_minus);
        wk_reset_out(out, WK_EVENT_CONTINUE, rest_phase, 0);
        return;
    }
    /* it swings back on the trailing spoke, which becomes the stance spoke */
    x_new[0] = -a;
    x_new[1] = w1;
    hub_velocity(l, -a, w1, v_plus);
    set_impulse(impulse, v_plus, v_minus);
    wk_reset_out(out, WK_EVENT_CONTINUE, RW_ROLLING, 0);
}

/* (kinetic, potential) per unit hub mass [J/kg]; potential zero at the stance foot. */
void wk_model_rimless_wheel_energy(const double *x, const double *p, double *out, void *ctx)
{
    (void)ctx;
    double l = p[WK_RIMLESS_WHEEL_P_LEG_LENGTH];
    out[0] = 0.5 * l * l * x[1] * x[1];
    out[1] = p[WK_RIMLESS_WHEEL_P_G] * l * cos(x[0] - p[WK_RIMLESS_WHEEL_P_SLOPE]);
}

/* Stance foot, hub, leading spoke's foot, trailing spoke's foot in the world frame [m],
 * out (4, 2); the stance foot at the origin, x downhill along the horizontal. */
void wk_model_rimless_wheel_points(const double *x, const double *p, double *out, void *ctx)
{
    (void)ctx;
    double l = p[WK_RIMLESS_WHEEL_P_LEG_LENGTH], slope = p[WK_RIMLESS_WHEEL_P_SLOPE];
    double a = RW_PI / p[WK_RIMLESS_WHEEL_P_SPOKES];
    double s[2] = {cos(slope), -sin(slope)};
    double n[2] = {sin(slope), cos(slope)};
    double phi[2] = {x[0] + 2.0 * a, x[0] - 2.0 * a};
    out[0] = 0.0;
    out[1] = 0.0;
    for (int i = 0; i < 2; i++) {
        double hub = l * (-sin(x[0]) * s[i] + cos(x[0]) * n[i]);
        out[2 + i] = hub;
        for (int j = 0; j < 2; j++)
            out[4 + 2 * j + i] = hub - l * (-sin(phi[j]) * s[i] + cos(phi[j]) * n[i]);
    }
}

/* Standing (1) for a wheel at rest with two spokes on the ground (theta_dot == 0 and
 * |theta| == a exactly) on a slope it can stand on (|slope| < a); else rolling (0). */
void wk_model_rimless_wheel_start_phase(const double *x, const double *p, double *out,
                                        void *ctx)
{
    (void)ctx;
    double a = RW_PI / p[WK_RIMLESS_WHEEL_P_SPOKES], slope = p[WK_RIMLESS_WHEEL_P_SLOPE];
    int standing = x[1] == 0.0 && fabs(x[0]) == a && slope > -a && slope < a;
    out[0] = standing ? (double)RW_STANDING : (double)RW_ROLLING;
}

const wk_model_entry wk_entry_rimless_wheel = {
    WK_ENTRY_NAME_rimless_wheel,
    {wk_model_rimless_wheel_rhs, wk_model_rimless_wheel_guards, wk_model_rimless_wheel_reset,
     wk_model_rimless_wheel_jac, NULL},
    wk_model_rimless_wheel_energy,
    wk_model_rimless_wheel_points,
    wk_model_rimless_wheel_start_phase,
};

/* ------------------------------------------------------------------------------------------
 * Terrain (wk_terrain.h)
 *
 * Step n's plane passes h below the stance foot with slope gamma.  With phi = theta - slope
 * the stance spoke's angle from the vertical, the leading foot's signed distance from that
 * plane is 2 l sin(a) sin(u) + h cos(gamma), u = phi + gamma + a: it lands at
 * u* = -asin(h cos(gamma) / (2 l sin a)) (u* = 0 on the scene's plane, where u = theta + a),
 * the impact guard is u - u* (never, 1.0, for a drop the spoke cannot reach), and the new
 * stance spoke starts at theta+ = u* - (gamma - slope) + a, the angle it landed at: the
 * post-impact state carries the plane it landed on.  The rate maps as on the plane,
 * theta_dot+ = cos(2a) theta_dot-.  A wheel that does not pass over its stance spoke turns
 * back (theta_dot increasing through 0, guards 1 and 3 on terrain): ROLLED_BACK.  The
 * impulse is along and normal to the step's plane.
 * ------------------------------------------------------------------------------------------ */
#include "wk_terrain.h"

/* u* of the current step, or NAN when the leading spoke cannot reach its plane. */
static double landing_u(const wk_terrain *T, double l, double a)
{
    const double s = T->ground.drop * cos(T->ground.slope) / (2.0 * l * sin(a));
    if (!(fabs(s) < 1.0)) return NAN;
    return -asin(s);
}

void wk_terrain_rimless_wheel_guards(int64_t phase, double t, const double *x, const double *p,
                                     double *g, void *ctx)
{
    const wk_terrain *T = (const wk_terrain *)ctx;
    if (phase == RW_STANDING || T->ground.plane) {
        wk_model_rimless_wheel_guards(phase, t, x, p, g, NULL);
    } else {
        const double a = RW_PI / p[WK_RIMLESS_WHEEL_P_SPOKES];
        const double u_land = landing_u(T, p[WK_RIMLESS_WHEEL_P_LEG_LENGTH], a);
        const double u = x[0] - p[WK_RIMLESS_WHEEL_P_SLOPE] + T->ground.slope + a;
        g[WK_RIMLESS_WHEEL_GUARD_IMPACT] = isnan(u_land) ? 1.0 : u - u_land;
        g[WK_RIMLESS_WHEEL_GUARD_IMPACT_LATE] = isnan(u_land) ? 1.0 : (u - u_land) + RW_LATE;
    }
    if (phase != RW_STANDING) { /* turning back: the wheel did not get over its stance spoke */
        g[WK_RIMLESS_WHEEL_GUARD_BACK_IMPACT] = x[1];
        g[WK_RIMLESS_WHEEL_GUARD_BACK_IMPACT_LATE] = x[1] - RW_LATE;
    }
}

void wk_terrain_rimless_wheel_reset(int64_t phase, int64_t k, double t, const double *x,
                                    const double *p, double *x_new, double *impulse,
                                    int64_t *out, void *ctx)
{
    const wk_terrain *T = (const wk_terrain *)ctx;
    if (phase != RW_STANDING &&
        (k == WK_RIMLESS_WHEEL_GUARD_BACK_IMPACT || k == WK_RIMLESS_WHEEL_GUARD_BACK_IMPACT_LATE)) {
        x_new[0] = x[0];
        x_new[1] = x[1];
        impulse[0] = 0.0;
        impulse[1] = 0.0;
        wk_reset_out(out, WK_EVENT_TERMINAL, phase, WK_ROLLED_BACK);
        return;
    }
    if (phase == RW_STANDING || T->ground.plane) {
        wk_model_rimless_wheel_reset(phase, k, t, x, p, x_new, impulse, out, NULL);
        return;
    }
    const double l = p[WK_RIMLESS_WHEEL_P_LEG_LENGTH], slope = p[WK_RIMLESS_WHEEL_P_SLOPE];
    const double a = RW_PI / p[WK_RIMLESS_WHEEL_P_SPOKES];
    const double c = p[WK_RIMLESS_WHEEL_P_SPOKES] > 4.0 ? cos(2.0 * a) : 0.0;
    const double turn = T->ground.slope - slope; /* the step's plane against the scene's */
    const double u_land = landing_u(T, l, a);
    const double w = x[1];
    double v_minus[2], v_plus[2] = {0.0, 0.0};
    hub_velocity(l, x[0] + turn, w, v_minus); /* in the step's plane frame */
    x_new[0] = (isnan(u_land) ? 0.0 : u_land) - turn + a;
    x_new[1] = c > 0.0 ? c * w : 0.0;
    hub_velocity(l, x_new[0] + turn, x_new[1], v_plus);
    set_impulse(impulse, v_plus, v_minus);
    if (c > 0.0 || x_new[0] - slope < 0.0) {
        /* rolling on; 3 or 4 spokes stop on both feet, and tip forward from rest only with
         * the hub ahead of the new stance foot */
        wk_reset_out(out, WK_EVENT_STRIDE, RW_ROLLING, 0);
        return;
    }
    wk_reset_out(out, WK_EVENT_TERMINAL, phase, WK_ROLLED_BACK);
}
