/* Many starts of a walker's stride map in one compiled call (basins of attraction).
 *
 * The loop of walker.basin.basin_chunk for one batch of section points, with the start
 * checks of walker.stride.StrideMap.__call__, for models whose lift from section
 * coordinates to the full state is affine and whose projection selects state components:
 * the same floating-point operations as the Python path, so the outcomes are identical.
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
} wk_section;

/* Iterate each of the m section points z0 (m, n_z): converged when max|z - target| <= tol
 * (outcome -1), else up to n_strides strides, `period` per map call (outcome -2 when the
 * limit is reached undecided), or the status of the stride that failed (outcome > 0).
 * `strides` receives the completed strides.  `tmpl` supplies the system sizes, parameters
 * and solver settings (its x0, phase0, t0, t_max, n_strides, max_steps, output and
 * want_jac are set per call).  Returns WK_OK, or a wk_hybrid_solve error code. */
int wk_basin_points(const wk_functions *fn, const wk_problem *tmpl, const wk_section *sec,
                    int64_t m, const double *z0, const double *target, double tol,
                    int64_t n_strides, int64_t period, int64_t *outcome, int64_t *strides);

#define WK_BASIN_CONVERGED (-1)
#define WK_BASIN_UNDECIDED (-2)

#endif
