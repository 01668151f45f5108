/* Registries of what the extension module walker._hybrid compiles in:
 *
 * - models: walker's own hybrid systems (wk_functions, see wk_system.h) and their
 *   Python-side helpers, one entry per model and structural variant ("kneed" is the general
 *   kernel, "kneed/plain" the variant for point feet, no offsets, no segment inertias and no
 *   dampers; see walker/_core/model_table.c);
 * - kernels: every generated kernel (the .c files in walker/_generated), by "<model>.<kernel>" name, for
 *   the tests that check them against the symbolic model.
 *
 * The binding (walker/_core/_hybridmodule.c) exposes both as dicts of integer addresses.
 */
#ifndef WK_MODELS_H
#define WK_MODELS_H

#include "wk_system.h"

/* Extra per-model functions (NULL where a model has none). */
typedef void (*wk_state_fn)(const double *x, const double *p, double *out, void *ctx);

typedef struct {
    const char *name;
    wk_functions fn;
    wk_state_fn energy;      /* out[0] = kinetic, out[1] = potential [J] */
    wk_state_fn points;      /* out: (n_points, 2) row-major, joint positions for drawing */
    wk_state_fn start_phase; /* out[0] = phase as a double (NULL: phase 0) */
    /* The section's lift where it is not affine (NULL: affine, or no compiled lift): called
     * with the section point z (n_z,) as its first argument, out the full state (n_x,);
     * lift_jacobian's out its Jacobian (n_x, n_z) row-major.  The operations of the model's
     * Python lift and lift_jacobian. */
    wk_state_fn lift;
    wk_state_fn lift_jacobian;
    /* The controller's torques u (n_inputs) at x (the actuated walkers; NULL elsewhere):
     * what the integrator's rhs applies, before any joint friction. */
    wk_state_fn torques;
} wk_model_entry;

/* Generated kernel signatures: "qqdp_v" f(q, qd, p, out); "qp_v" f(q, p, out);
 * "qqdp_s" double f(q, qd, p); "qp_s" double f(q, p); "qqdqddp_v" f(q, qd, qdd, p, out)
 * (the actuated walkers' ground_reaction).  All arguments const double *, out double *
 * (row-major); see walker.symbolic.codegen_c.SIGNATURES. */
typedef struct {
    const char *name;  /* "<model>.<kernel>", variants "<model>/plain.<kernel>" */
    const char *sig;
    void *address;
    int64_t n_q;      /* length of q (and of qd, qdd where the kernel takes them) */
    int64_t n_p;      /* the kernel reads p[0 .. n_p) */
    int64_t shape[3]; /* shape of out, 0 past its last dimension (all 0: returns a double) */
} wk_kernel_entry;

/* The registry: an array of pointers to entries, so that each model file can export its own
 * entry (``const wk_model_entry wk_entry_<model>``). */
const wk_model_entry *const *wk_model_table(int64_t *count);
const wk_kernel_entry *wk_kernel_table(int64_t *count);

/* The hash stamped on each generated C module (its WK_<MODULE>_KERNEL_HASH): what a result's
 * provenance records as the model's kernel_hash. */
typedef struct {
    const char *module; /* "compass", variants "compass/plain" */
    const char *hash;
} wk_kernel_hash_entry;
const wk_kernel_hash_entry *wk_kernel_hash_table(int64_t *count);

/* The fused rhs and Jacobian of the registry entry whose fn has this (rhs, jac) pair; NULL
 * when no entry has it (a user system) or the entry has none.  What the binding sets
 * wk_functions.rhs_jac to when a run is set up. */
wk_rhs_jac_fn wk_model_rhs_jac(wk_rhs_fn rhs, wk_jac_fn jac);

/* Length of the buffer wk_model_hoist fills: the longest parameter vector of a hoisting
 * variant plus its constants (checked in models.c). */
#define WK_HOIST_MAX 96

/* Hoisting (walker/symbolic/codegen_c.py): when fn's rhs (and jac, unless NULL) are those of
 * a registry variant with hoisted kernels ("compass/plain", "kneed/plain",
 * "kneed/plain/ignore_scuff"), writes into buf (WK_HOIST_MAX doubles) the parameter vector p
 * followed by the kernels' parameter-only terms computed from it, replaces fn's rhs, jac and
 * rhs_jac (where set) by the variant's hoisted ones, and returns buf; otherwise leaves fn as
 * it is and returns p.  The phase functions then compute the same numbers bit for bit
 * without recomputing those terms at every call; guards and resets read p's first entries
 * and are unchanged.  The integrator calls it once per run (hybrid.c), so a run always
 * computes them from the parameters it was given (a re-targeted map's included). */
const double *wk_model_hoist(wk_functions *fn, const double *p, double *buf);

#endif
