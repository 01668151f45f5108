/* The gait search of walker/analysis/newton.py in one compiled call: damped Newton in a trust region
 * with backtracking, the Levenberg-Marquardt fallback, the walking region's refusals, the
 * evaluation budget and the coarse early strides, on a walker's stride map in C (batch.h).
 *
 * wk_search is walker.analysis.newton._search with the exact Jacobian, for a map whose every
 * evaluation is one wk_section_start + wk_section_run (the compiled call of
 * walker.simulation.stride.StrideMap): the same decisions in the same order, the constants of
 * walker/analysis/newton.py (passed in, so they are written once), the same arithmetic but for the
 * order of a few sums (the merit's 2-norm, the Levenberg-Marquardt normal equations), which
 * only the comparisons of the line search read.  It ends where the Python search ends and
 * says why; walker/analysis/newton.py turns that into the NewtonResult and its message.
 */
#ifndef WK_NEWTON_H
#define WK_NEWTON_H

#include <stdint.h>

#include "batch.h"

/* walker.simulation.region.WalkingRegion: what outside() tests. */
typedef struct {
    int has_stance;       /* section coordinate 0 is the stance-leg angle */
    double stance_offset; /* z[0] + stance_offset: its angle from the slope normal */
    double fall_angle;
    int64_t n_q;          /* angles x[0 .. n_q) of the lifted state, n_q >= 1 */
    double wound_limit;
    wk_state_fn energy;   /* kinetic energy: out[0] */
    double kinetic_max;
    const double *scale;  /* (n_z,): the trust region's unit of each coordinate */
} wk_region;

/* Why a point lies outside the walking region (WalkingRegion.describe). */
enum { WK_INSIDE = 0, WK_OUT_FALL = 1, WK_OUT_NONFINITE = 2, WK_OUT_WOUND = 3, WK_OUT_ENERGY = 4 };

/* The search's settings and walker/analysis/newton.py's constants, in the order of
 * walker.analysis.newton._COMPILED_CONSTANTS. */
typedef struct {
    int64_t period;
    double tol;
    int64_t max_iter;
    int fallback;
    int64_t max_evals;
    int coarse; /* integrate far iterates more coarsely (own_rtol, own_atol the map's) */
    double own_rtol, own_atol;
    double armijo, line_flat, cond_max;
    int64_t max_halvings;
    double lm_start, lm_grow, lm_shrink, lm_max;
    int64_t lm_tries;
    double tr_start, tr_max;
    int64_t stall_window;
    double stall_ratio, stall_alpha;
    double coarsest_rtol, coarse_rho, coarse_keep;
} wk_search_settings;

/* How the search ended. */
enum {
    WK_SEARCH_CONVERGED = 0,
    WK_SEARCH_OUTSIDE_GUESS = 1, /* why: the guess's reason; not integrated */
    WK_SEARCH_START_FAILS = 2,   /* status: the guess's stride */
    WK_SEARCH_BUDGET = 3,
    WK_SEARCH_STALL = 4,         /* each of the last stall_window steps gained little */
    WK_SEARCH_NO_DESCENT = 5,    /* no step in the trust region reduces ||F|| */
    WK_SEARCH_DIVERGED = 6,      /* status: the full step's; why, refused */
    WK_SEARCH_JACOBIAN_FAILED = 7, /* status */
    WK_SEARCH_SINGULAR = 8,      /* cond; without the fallback */
    WK_SEARCH_MAX_ITER = 9,
    WK_SEARCH_DECLINED = 10,     /* a case this search does not take (a start phase out of
                                  * range, a lifted state that is not finite, an integrator
                                  * error): the caller runs the Python search, which says why */
};

typedef struct {
    int end;                /* WK_SEARCH_* */
    int64_t status;         /* a walker.status value, see the end codes */
    int64_t it, n_evals, refused;
    int why;                /* WK_OUT_*: the first refusal of the guess or the last iteration */
    double why_value;
    int64_t why_index;
    double cond;
    double *z;              /* (n_z,): the solution, or the last accepted iterate */
    double *history;        /* (min(max_iter, max_evals) + 1,): max|F| at accepted iterates */
    int64_t n_history;
    int known;              /* the map at z with a finite Jacobian (converged only) */
    double known_t;
    double *known_z;        /* (n_z,) */
    double *known_x;        /* (n_x,) */
    double *known_jac;      /* (n_z, n_z) row-major */
} wk_search_out;

/* The Newton step of walker/analysis/newton.py: dz (n,) solving a dz = -f for a (n, n) row-major by
 * Gaussian elimination with partial pivoting (wk_solve_columns), and in *cond the Frobenius
 * condition number ||a||_F ||a^-1||_F (>= the 2-norm one, <= n times it; INFINITY when not
 * finite) from the inverse solved with it.  Returns 0 (cond INFINITY, dz undefined) when a
 * pivot is zero or the solution is not finite.  A: (n, n) and B: (n, n + 1) workspace. */
int wk_newton_step(const double *a, const double *f, int64_t n, double *A, double *B,
                   double *dz, double *cond);

/* The search from z0 (n_z,) on the map (fn, tmpl, sec); the caller provides out's arrays.
 * Returns WK_OK, or WK_ERR_NOMEM when the workspace could not be allocated. */
int wk_search(const wk_functions *fn, const wk_problem *tmpl, const wk_section *sec,
              const wk_region *reg, const wk_search_settings *set, const double *z0,
              wk_search_out *out);

#endif
