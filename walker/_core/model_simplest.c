/* Garcia's simplest walking model: C port of the compiled phase functions in
 * walker/models/simplest.py (same operations in the same order), on the generated kernels
 * wk_simplest_* (walker/_generated/simplest.h).  State (theta, phi, theta_dot, phi_dot);
 * guards heel_strike, fall_forward, fall_backward. */
#include <math.h>
#include <stddef.h>
#include "wk_common.h"
#include "simplest.h"

void wk_model_simplest_rhs(int64_t phase, double t, const double *x, const double *p,
                           double *dx, void *ctx)
{
    (void)phase;
    (void)t;
    (void)ctx;
    double a[2];
    wk_simplest_accel(x, x + 2, p, a);
    dx[0] = x[2];
    dx[1] = x[3];
    dx[2] = a[0];
    dx[3] = a[1];
}

void wk_model_simplest_jac(int64_t phase, double t, const double *x, const double *p,
                           double *J, void *ctx)
{
    (void)phase;
    (void)t;
    (void)ctx;
    for (int i = 0; i < 16; i++) J[i] = 0.0;
    J[0 * 4 + 2] = 1.0;
    J[1 * 4 + 3] = 1.0;
    double da[8];
    wk_simplest_daccel_dx(x, x + 2, p, da);
    for (int j = 0; j < 4; j++) {
        J[2 * 4 + j] = da[0 * 4 + j];
        J[3 * 4 + j] = da[1 * 4 + j];
    }
}

void wk_model_simplest_guards(int64_t phase, double t, const double *x, const double *p,
                              double *g, void *ctx)
{
    (void)phase;
    (void)t;
    (void)p;
    (void)ctx;
    g[WK_SIMPLEST_GUARD_HEEL_STRIKE] = x[1] - 2.0 * x[0];
    g[WK_SIMPLEST_GUARD_FALL_FORWARD] = x[0] + WK_FALL_ANGLE;
    g[WK_SIMPLEST_GUARD_FALL_BACKWARD] = x[0] - WK_FALL_ANGLE;
}

void wk_model_simplest_reset(int64_t phase, int64_t k, double t, const double *x,
                             const double *p, double *x_new, double *impulse, int64_t *out,
                             void *ctx)
{
    (void)t;
    (void)p;
    (void)ctx;
    for (int i = 0; i < 4; i++) x_new[i] = x[i];
    impulse[0] = 0.0;
    if (k == 0) {
        if (x[0] >= 0.0) {
            wk_reset_out(out, WK_EVENT_IGNORE, phase, 0);
            return;
        }
        double c = cos(2.0 * x[0]);
        x_new[0] = -x[0];
        x_new[1] = -2.0 * x[0];
        x_new[2] = c * x[2];
        x_new[3] = c * (1.0 - c) * x[2];
        wk_reset_out(out, WK_EVENT_STRIDE, 0, 0);
        return;
    }
    wk_fall_out(out, phase, k == WK_SIMPLEST_GUARD_FALL_FORWARD);
}

/* (kinetic, potential) per unit hip mass [J/kg]; potential zero at the stance foot. */
void wk_model_simplest_energy(const double *x, const double *p, double *out, void *ctx)
{
    (void)ctx;
    double slope = p[WK_SIMPLEST_P_SLOPE], g = p[WK_SIMPLEST_P_G], l = p[WK_SIMPLEST_P_LEG_LENGTH];
    out[0] = 0.5 * l * l * x[2] * x[2];
    out[1] = g * l * cos(x[0] - slope);
}

/* Stance foot, hip, swing foot in the world frame [m], out (3, 2). */
void wk_model_simplest_points(const double *x, const double *p, double *out, void *ctx)
{
    (void)ctx;
    double slope = p[WK_SIMPLEST_P_SLOPE], l = p[WK_SIMPLEST_P_LEG_LENGTH];
    double s[2] = {cos(slope), -sin(slope)};
    double n[2] = {sin(slope), cos(slope)};
    double st = -sin(x[0]), ct = cos(x[0]);
    double a = x[0] - x[1];
    double sa = -sin(a), ca = cos(a);
    out[0] = 0.0;
    out[1] = 0.0;
    for (int i = 0; i < 2; i++) {
        double hip = l * (st * s[i] + ct * n[i]);
        out[2 + i] = hip;
        out[4 + i] = hip - l * (sa * s[i] + ca * n[i]);
    }
}

/* walker.models.simplest.lift: the section point z = (theta, theta_dot) -> the full state
 * just after heel strike, out (4,); the same operations. */
void wk_model_simplest_lift(const double *z, const double *p, double *out, void *ctx)
{
    (void)p;
    (void)ctx;
    out[0] = z[0];
    out[1] = 2.0 * z[0];
    out[2] = z[1];
    out[3] = (1.0 - cos(2.0 * z[0])) * z[1];
}

/* walker.models.simplest.lift_jacobian at z, out (4, 2) row-major; the same operations. */
void wk_model_simplest_lift_jacobian(const double *z, const double *p, double *out, void *ctx)
{
    (void)p;
    (void)ctx;
    const double s2 = sin(2.0 * z[0]);
    out[0] = 1.0;
    out[1] = 0.0;
    out[2] = 2.0;
    out[3] = 0.0;
    out[4] = 0.0;
    out[5] = 1.0;
    out[6] = 2.0 * s2 * z[1];
    out[7] = 1.0 - cos(2.0 * z[0]);
}

const wk_model_entry wk_entry_simplest = {
    WK_ENTRY_NAME_simplest,
    {wk_model_simplest_rhs, wk_model_simplest_guards, wk_model_simplest_reset,
     wk_model_simplest_jac, NULL},
    wk_model_simplest_energy,
    wk_model_simplest_points,
    NULL,
    wk_model_simplest_lift,
    wk_model_simplest_lift_jacobian,
};

/* ------------------------------------------------------------------------------------------
 * Terrain (wk_terrain.h).  theta is the stance leg's angle from the scene slope's normal,
 * a = theta - phi the swing leg's; the swing foot sits l (sin a - sin theta, cos theta -
 * cos a) from the stance foot (along the scene slope, normal), so with d = gamma - slope its
 * signed distance from the step's plane is l (cos(theta + d) - cos(a + d)) + h cos(gamma).
 * The guard is that distance over -l (the sign of phi - 2 theta at heel strike on the plane).
 * The impact is Garcia's with the inter-leg angle phi- in place of 2 theta-: theta+ =
 * theta- - phi-, phi+ = -phi-, theta_dot+ = cos(phi-) theta_dot-, phi_dot+ = cos(phi-)
 * (1 - cos(phi-)) theta_dot- (the new stance leg is the old swing leg; the hip's velocity,
 * perpendicular to the old stance leg, keeps its component perpendicular to the new one).
 * ------------------------------------------------------------------------------------------ */
#include <stddef.h>
#include "wk_terrain.h"

void wk_terrain_simplest_guards(int64_t phase, double t, const double *x, const double *p,
                                double *g, void *ctx)
{
    const wk_terrain *T = (const wk_terrain *)ctx;
    wk_model_simplest_guards(phase, t, x, p, g, NULL);
    if (T->ground.plane) return;
    const double d = T->ground.slope - p[WK_SIMPLEST_P_SLOPE];
    const double a = x[0] - x[1];
    g[WK_SIMPLEST_GUARD_HEEL_STRIKE] = (cos(a + d) - cos(x[0] + d)) -
                                       T->ground.drop * cos(T->ground.slope) /
                                           p[WK_SIMPLEST_P_LEG_LENGTH];
}

void wk_terrain_simplest_reset(int64_t phase, int64_t k, double t, const double *x,
                               const double *p, double *x_new, double *impulse, int64_t *out,
                               void *ctx)
{
    const wk_terrain *T = (const wk_terrain *)ctx;
    if (T->ground.plane || k != WK_SIMPLEST_GUARD_HEEL_STRIKE) {
        wk_model_simplest_reset(phase, k, t, x, p, x_new, impulse, out, NULL);
        return;
    }
    for (int i = 0; i < 4; i++) x_new[i] = x[i];
    impulse[0] = 0.0;
    if (x[0] >= 0.0) { /* the mid-stance scuff, as on the plane */
        wk_reset_out(out, WK_EVENT_IGNORE, phase, 0);
        return;
    }
    const double c = cos(x[1]);
    x_new[0] = x[0] - x[1];
    x_new[1] = -x[1];
    x_new[2] = c * x[2];
    x_new[3] = c * (1.0 - c) * x[2];
    wk_reset_out(out, WK_EVENT_STRIDE, 0, 0);
}
