/* The gait search, written once: damped Newton in a trust region with backtracking, the
 * Levenberg-Marquardt fallback, the walking region's refusals, the evaluation budget and the
 * coarse early strides.  walker/analysis/newton.py builds its result and messages; the search runs
 * here for every map:
 *
 *   - a walker's stride map with a compiled call (walker.simulation.stride.StrideMap): wk_search_compiled,
 *     each evaluation one wk_section_start + wk_section_run (batch.h), without the GIL;
 *   - any other map (walker.SystemMap, a user's Python map, finite-difference Jacobians): the
 *     binding's wk_search_map whose evaluations call back into Python (_hybridsearch.c).
 *
 * The constants live in walker/analysis/newton.py and are passed in (wk_search_settings).
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
} wk_region;

/* Why a point lies outside the walking region (WalkingRegion.describe). */
/* WK_OUT_OTHER: a map's own reason (a callback's), numbered in why_index. */
enum {
    WK_INSIDE = 0,
    WK_OUT_FALL = 1,
    WK_OUT_NONFINITE = 2,
    WK_OUT_WOUND = 3,
    WK_OUT_ENERGY = 4,
    WK_OUT_OTHER = 5
};

/* The search's settings and walker/analysis/newton.py's constants (keyword arguments of the
 * binding, walker.analysis.newton._Search.settings). */
typedef struct {
    int64_t period;
    double tol;
    int64_t max_iter;
    int fallback;
    int64_t max_evals;
    int exact;        /* the map's own Jacobian: trial points bring theirs along */
    int64_t jac_cost; /* evaluations one wk_search_map.jacobian call counts */
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
    WK_SEARCH_NO_DESCENT = 5,    /* no step in the trust region reduces ||F||; status: the
                                  * full step's */
    WK_SEARCH_DIVERGED = 6,      /* status: the full step's; why, refused */
    WK_SEARCH_JACOBIAN_FAILED = 7, /* status */
    WK_SEARCH_SINGULAR = 8,      /* cond; without the fallback */
    WK_SEARCH_MAX_ITER = 9,
    WK_SEARCH_DECLINED = 10,     /* a case the compiled map does not take (a start phase out
                                  * of range, a lifted state that is not finite, an
                                  * integrator error): the caller searches again through
                                  * callbacks, whose map says why */
};

/* What wk_search_map's functions return besides 0 (wk_search then stops). */
#define WK_EVAL_DECLINED 2 /* the map does not take this point (WK_SEARCH_DECLINED) */
#define WK_EVAL_ERROR 3    /* the map failed (a Python exception is set): wk_search
                            * returns WK_ERR_SEARCH_MAP */
#define WK_ERR_SEARCH_MAP (-10)

/* One evaluation of the map: status, step time, new section point, final state, Jacobian. */
typedef struct {
    int64_t status;
    double t;
    double *z;    /* (n_z,) */
    double *x;    /* (n_x,) */
    double *jac;  /* (n_z, n_z) row-major */
    int has_jac;  /* a finite Jacobian came with it */
    void *handle; /* the map's own record of it (a callback map's result), or NULL */
} wk_search_eval;

/* The map a search evaluates.  evaluate: P^period at z at rtol `level` (0: the map's own),
 * with its Jacobian when want_jac; jacobian: the Jacobian at z at the map's own tolerance
 * (jac_cost evaluations); outside: WK_INSIDE, why z lies outside the walking region
 * (WK_OUT_*; value, index for the message), or -1 (error); NULL: no region.  release
 * drops an evaluation's handle (NULL: none are kept).  With poll_interrupt the search
 * ends at wk_interrupt (hybrid.h) as at its budget (the binding then raises). */
typedef struct wk_search_map wk_search_map;
struct wk_search_map {
    int64_t n_z, n_x;
    int (*evaluate)(wk_search_map *m, const double *z, double level, int want_jac,
                    wk_search_eval *e);
    int (*jacobian)(wk_search_map *m, const double *z, wk_search_eval *e);
    int (*outside)(wk_search_map *m, const double *z, double *value, int64_t *index);
    void (*release)(wk_search_map *m, wk_search_eval *e);
    int poll_interrupt;
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
    double *known_x;        /* (n_x,), or NULL */
    double *known_jac;      /* (n_z, n_z) row-major */
    void *known_handle;     /* its handle, now the caller's */
} wk_search_out;

/* The search from z0 (n_z,) on the map m, with the trust region's unit of each coordinate
 * in scale (n_z,); the caller provides out's arrays.  Returns WK_OK, WK_ERR_NOMEM when the
 * workspace could not be allocated, or WK_ERR_SEARCH_MAP when the map failed. */
int wk_search(wk_search_map *m, const wk_search_settings *set, const double *scale,
              const double *z0, wk_search_out *out);

/* wk_search on a walker's stride map (fn, tmpl, sec) in its walking region reg. */
int wk_search_compiled(const wk_functions *fn, const wk_problem *tmpl, const wk_section *sec,
                       const wk_region *reg, const wk_search_settings *set, const double *scale,
                       const double *z0, wk_search_out *out);

#endif
