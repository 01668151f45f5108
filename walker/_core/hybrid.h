/* walker's hybrid integrator: one call integrates a hybrid system (wk_system.h) through its
 * phases and events -- Runge-Kutta steps with dense output, event location, resets,
 * samples, variational equations.  The algorithm is described in the module docstring of
 * walker/simulation/integrate.py, which validates the input and calls wk_hybrid_solve through the
 * extension module walker._hybrid (walker/_core/_hybridmodule.c).
 *
 * Re-entrant: no global mutable state; every work array is allocated per call and freed
 * before return, so several threads may run wk_hybrid_solve at once.
 */
#ifndef WK_HYBRID_H
#define WK_HYBRID_H

#include <signal.h>
#include <stdint.h>
#include "wk_system.h"

/* Methods (WK_METHOD_*) and output modes (WK_OUTPUT_*): walker.status's values, in
 * status.h (included by wk_system.h). */

/* Absolute guard tolerance for arming (walker.simulation.integrate.GUARD_TOL). */
#define WK_GUARD_TOL 1e-10

/* A pending interrupt: the number of a signal (SIGINT, SIGTERM) that arrived while compiled
 * work ran, set by the binding's handler (walker/_core/_hybridsignals.c), else 0.  Every
 * loop polls it (the step loop each step, the gait search each evaluation, a batch each
 * point) and ends with WK_INTERRUPTED; reading it changes no arithmetic. */
extern volatile sig_atomic_t wk_interrupt;

/* Return codes of wk_hybrid_solve (the run's outcome is wk_result.status). */
#define WK_OK 0
#define WK_ERR_NOMEM (-1)     /* an allocation failed */
#define WK_ERR_BAD_PHASE (-2) /* reset returned a next phase outside [0, n_phases);
                               * wk_result.phase holds it */

/* Everything a run needs besides the model functions.  The caller checks the values
 * (walker/simulation/integrate.py and the binding do); arrays are contiguous. */
typedef struct {
    const int64_t *directions; /* (n_phases, n_guards) row-major: -1, 0 or +1 */
    int64_t n_phases;
    int64_t n_x;
    int64_t n_guards;
    int64_t n_impulse;
    const double *x0; /* (n_x,) */
    const double *p;  /* parameters, passed unchanged to the model */
    int64_t phase0;
    double t0;
    double t_max;
    int64_t n_strides;
    int method; /* WK_METHOD_* */
    int adaptive;
    double rtol;
    double atol;
    double first_step; /* 0: Hairer's estimate (adaptive methods) */
    double max_step;
    int64_t max_steps;
    int output;                 /* WK_OUTPUT_* */
    const double *sample_times; /* (n_samples,), used with WK_OUTPUT_SAMPLES */
    int64_t n_samples;
    int want_jac;
    int64_t n_interior;
    /* 1: a step keeps its interior guard samples only when a guard may come near zero in
     * it (wk_guards_far); for guards that do not depend on t explicitly.  0: always. */
    int screen_interior;
    /* With want_jac: the seed S (n_x, n_seed) row-major of the sensitivities, so the run
     * propagates Phi = (d x / d x0) S, n_seed columns, through the flow, the saltation
     * matrices and the resets (a stride map needs only (d x / d x0) times its lift's
     * Jacobian).  NULL: the identity, n_seed = n_x (the full d x / d x0). */
    const double *jac_seed;
    int64_t n_seed;
} wk_problem;

/* Counters, in this order in wk_result.counters. */
enum {
    WK_N_STEPS,
    WK_N_REJECTED,
    WK_N_RHS,
    WK_N_EVENTS,
    WK_N_STRIDES,
    WK_N_LOG,
    WK_N_SAMPLES,
    WK_N_RECORD,
    WK_N_COUNTERS
};

/* What a run returns.  Every pointer is malloc'ed by wk_hybrid_solve (NULL when empty)
 * and released by wk_result_free; row counts are in counters. */
typedef struct {
    int64_t status; /* a walker.status.Status value */
    double t;       /* absolute time at the end */
    int64_t phase;
    int64_t counters[WK_N_COUNTERS];
    double err_sum; /* sum of rtol * err over accepted steps */
    double *x;      /* (n_x,) final state */
    /* event log, counters[WK_N_LOG] rows */
    double *ev_t;
    int64_t *ev_guard;
    int64_t *ev_phase_before;
    int64_t *ev_phase_after;
    double *ev_x_pre;   /* (n_log, n_x) */
    double *ev_x_post;  /* (n_log, n_x) */
    double *ev_impulse; /* (n_log, n_impulse) */
    /* samples, counters[WK_N_SAMPLES] rows */
    double *s_x; /* (n_samp, n_x) */
    int64_t *s_phase;
    /* record, counters[WK_N_RECORD] rows */
    double *r_t;
    double *r_x; /* (n_rec, n_x) */
    int64_t *r_phase;
    double *jac;    /* (n_x, n_c) d x_final / d x0 times the seed (zeros unless want_jac);
                     * n_c = n_seed with a seed, else n_x */
    double *dt_dx0; /* (n_c,) d t_final / d x0 times the seed */
    int has_dt;
} wk_result;

/* Runs the integration; returns WK_OK or a WK_ERR_* code.  ``res`` is always left in a
 * state wk_result_free accepts (also on error). */
int wk_hybrid_solve(const wk_functions *fn, const wk_problem *pb, wk_result *res);

/* Frees the arrays of a result (safe on a zeroed or already freed result). */
void wk_result_free(wk_result *res);

#endif
