/* A walker's stride map in C: one call (walker._hybrid.PreparedMap) and many starts in one
 * compiled call (basins of attraction).
 *
 * wk_section_start and wk_section_run are one call of walker.simulation.stride.StrideMap.__call__ (the
 * lift, the start checks, the run); wk_basin_points is the loop of
 * walker.analysis.basin.basin_chunk for one batch of section points on them.  For models whose lift
 * from section coordinates to the full state is affine and whose projection selects state
 * components: the same floating-point operations as the Python path, so the outcomes are
 * identical.
 */
#ifndef WK_BATCH_H
#define WK_BATCH_H

#include <stdint.h>

#include "hybrid.h"
#include "wk_models.h"
#include "wk_system.h"

typedef struct {
    int64_t n_z;
    const double *lift_a;  /* (n_x, n_z) row-major: x = lift_b + lift_a z */
    const double *lift_b;  /* (n_x,) */
    const int64_t *proj;   /* (n_z,): z[i] = x[proj[i]] */
    double offset;         /* stance-leg angle from the slope normal: z[0] + offset */
    double fall_angle;     /* |z[0] + offset| >= fall_angle: a fall, not integrated */
    int64_t n_q;           /* angles x[0 .. n_q) */
    double wound;          /* |angle| > wound: outside the walking region */
    wk_state_fn energy;    /* NULL: no kinetic-energy test */
    double kinetic_limit;  /* kinetic energy (energy out[0]) above it: outside */
    wk_state_fn start_phase; /* NULL: phase 0; out[0] < 0: LINEAR_SOLVE_FAILED */
    double t_max;          /* per stride */
    int64_t max_steps;     /* per stride */
    wk_state_fn lift;      /* NULL: the affine lift above; else x = lift(z, p) */
    wk_state_fn lift_jacobian; /* with lift: its Jacobian (n_x, n_z) at z */
    void *ctx;             /* the system's ctx (wk_functions.ctx), handed to the functions
                            * above as to every other call (wk_system.h) */
} wk_section;

/* x (n_x,): the model's compiled lift of z where it has one (sec->lift), else
 * lift_b + lift_a z with the operations of the models' Python lift: a row's non-zero terms in
 * column order, then the constant added in front (b - z for b + (-1) z). */
void wk_section_lift(const wk_section *sec, int64_t n_x, const double *p, const double *z,
                     double *x);

/* The seed of the variational equations of a call from z: the lift's Jacobian (n_x, n_z),
 * lift_a for the affine lift, else computed into buf (n_x * n_z values). */
const double *wk_section_seed(const wk_section *sec, int64_t n_x, const double *p,
                              const double *z, double *buf);

/* The start of one stride-map call from section point z (n_z,): x0 (n_x,) receives the
 * lift, then the start checks run in StrideMap.__call__'s order.  Returns 0 when the run
 * may start, in *phase0 (the model's start phase, or 0), else the status of a start that is
 * not integrated: FELL_FORWARD / FELL_BACKWARD, OUTSIDE_WALKING_REGION, or
 * LINEAR_SOLVE_FAILED for a start phase that could not be chosen. */
int64_t wk_section_start(const wk_problem *tmpl, const wk_section *sec, const double *z,
                         double *x0, int64_t *phase0);

/* The run of one stride-map call: `period` strides from (t0 = 0, x0, phase0) with the
 * per-stride budgets of `sec`, output map only; with `seed` (not NULL) the sensitivities
 * are seeded with it, the lift's Jacobian (n_x, n_z) from wk_section_seed, and the run
 * carries them.  Returns wk_hybrid_solve's code; the caller frees `res` (wk_result_free) in
 * every case. */
int wk_section_run(const wk_functions *fn, const wk_problem *tmpl, const wk_section *sec,
                   int64_t period, const double *seed, const double *x0, int64_t phase0,
                   wk_result *res);

/* Iterate each of the m section points z0 (m, n_z): converged when max|z - target| <= tol,
 * or (radius > 0) when ||weight (z - target)||_2 <= radius, weight (n_z, n_z) row-major (the
 * ball where the map is a contraction, walker/analysis/basin.py; radius 0: not tested, weight unread)
 * (outcome -1), else up to n_strides strides, `period` per map call (outcome -2 when the
 * limit is reached undecided), or the status of the stride that failed (outcome > 0).
 * `strides` receives the completed strides.  `tmpl` supplies the system sizes, parameters
 * and solver settings (its x0, phase0, t0, t_max, n_strides, max_steps, output and
 * want_jac are set per call).  Returns WK_OK, or a wk_hybrid_solve error code. */
int wk_basin_points(const wk_functions *fn, const wk_problem *tmpl, const wk_section *sec,
                    int64_t m, const double *z0, const double *target, double tol,
                    const double *weight, double radius, int64_t n_strides, int64_t period,
                    int64_t *outcome, int64_t *strides);

#define WK_BASIN_CONVERGED (-1)
#define WK_BASIN_UNDECIDED (-2)

#endif
