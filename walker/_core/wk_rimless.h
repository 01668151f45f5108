/* The rimless wheel (walker/models/rimless_wheel.py), written in C only.
 * model_rimless_wheel.c holds its phase functions and helpers, exported as
 * wk_model_rimless_wheel_{rhs, guards, reset, jac, energy, points, start_phase}, and its
 * registry entry wk_entry_rimless_wheel ("rimless_wheel", fn.ctx NULL).
 *
 * Sizes: n_x 2 (theta, theta_dot), 2 phases (rolling, standing), 4 guards, 2 impulses,
 * 4 points.  Parameters p = (spokes, leg_length, g, slope). */
#ifndef WK_RIMLESS_H
#define WK_RIMLESS_H

#include "wk_models.h"
#include "wk_registry.h"

void wk_model_rimless_wheel_rhs(int64_t phase, double t, const double *x, const double *p,
                                double *dx, void *ctx);
void wk_model_rimless_wheel_guards(int64_t phase, double t, const double *x, const double *p,
                                   double *g, void *ctx);
void wk_model_rimless_wheel_reset(int64_t phase, int64_t k, double t, const double *x,
                                  const double *p, double *x_new, double *impulse,
                                  int64_t *out, void *ctx);
void wk_model_rimless_wheel_jac(int64_t phase, double t, const double *x, const double *p,
                                double *J, void *ctx);
void wk_model_rimless_wheel_energy(const double *x, const double *p, double *out, void *ctx);
void wk_model_rimless_wheel_points(const double *x, const double *p, double *out, void *ctx);
void wk_model_rimless_wheel_start_phase(const double *x, const double *p, double *out,
                                        void *ctx);

extern const wk_model_entry wk_entry_rimless_wheel;

#endif
