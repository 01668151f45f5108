/* Internal to walker._hybrid, the CPython binding: what its translation units share.
 *
 *   _hybridmodule.c  the methods (solve, models, kernels, call_state_fn, basin_points) and
 *                    the module's init;
 *   _hybridargs.c    argument conversion (every error names the argument), result
 *                    arrays out as bytearrays, and the compiled models' sizes the binding
 *                    checks every buffer against;
 *   _hybridresult.c  the named record solve() returns (walker._hybrid.SolveResult);
 *   _hybridmap.c     a walker's section settings (what basin_points and PreparedMap share)
 *                    and walker._hybrid.PreparedMap, one stride-map call.
 *   _hybridsearch.c  the gait search's binding (newton.h): PreparedMap.search and search.
 *   _hybridsignals.c SIGINT and SIGTERM while compiled work runs (wk_interrupt, hybrid.h).
 *
 * Nothing here is part of the extension's interface: the functions are prefixed wkpy_ and
 * called only by these files.  Include after <Python.h>.
 */
#ifndef WK_HYBRID_BINDING_H
#define WK_HYBRID_BINDING_H

#include <stddef.h>
#include <stdint.h>

#include "batch.h"
#include "hybrid.h"
#include "wk_system.h"

/* Largest sizes accepted (far above any walker; they keep the work-array sizes in range). */
#define MAX_N_X 4096
#define MAX_COUNT ((int64_t)1 << 24)
/* Largest iteration or evaluation budget of a search (walker._checks.MAX_BUDGET, checked
 * there first): the search's history holds one value per iteration. */
#define WKPY_MAX_BUDGET ((int64_t)10000000)

/* Each converter returns 0, or -1 with a Python exception set that names ``name``. */

/* An int (not a bool) that fits in int64. */
int wkpy_arg_int(PyObject *o, const char *name, int64_t *out);

/* A real number (int or float, not a bool). */
int wkpy_arg_double(PyObject *o, const char *name, double *out);

/* A bool (or an int used as one). */
int wkpy_arg_bool(PyObject *o, const char *name, int *out);

/* The address of a C function: a non-negative int (0 = NULL, allowed when ``nullable``). */
int wkpy_arg_address(PyObject *o, const char *name, int nullable, uintptr_t *out);

/* A C-contiguous buffer of float64 (kind 'd') or int64 (kind 'q') with ``ndim``
 * dimensions.  On success the caller releases ``view``. */
int wkpy_arg_buffer(PyObject *o, const char *name, char kind, int ndim, Py_buffer *view);

/* Two float64 buffers in a row (as wkpy_arg_buffer, with ``ndim0`` and ``ndim1``
 * dimensions).  On success the caller releases both; on failure neither is held. */
int wkpy_arg_buffer_pair(PyObject *const *args, const char *name0, int ndim0, const char *name1,
                         int ndim1, Py_buffer *view0, Py_buffer *view1);

/* ------------------------------------------------------------------------------------------
 * Keyword-only arguments
 *
 * solve(), terrain_solve(), basin_points() and PreparedMap() take keyword arguments only.
 * Each function's names are an X-macro list (below and in _hybridmodule.c); the names
 * become an enum of slot indices, so the C reads ``slots[WKPY_SOLVE_x0]``, never a bare
 * position.  wkpy_bind_keywords puts each keyword's value in its slot; the required names
 * come first in a list, the optional ones (slot NULL when not given) after them.
 * ------------------------------------------------------------------------------------------ */

typedef struct {
    const char *fname;        /* the function, for the messages: "solve" */
    int n;                    /* names in the list */
    int n_required;           /* the first n_required must be given */
    const char *const *names; /* n names */
    PyObject **interned;      /* n interned str, made on the first call */
} wkpy_kwlist;

/* Binds a vectorcall's keywords (METH_FASTCALL | METH_KEYWORDS: ``nargs`` positional
 * arguments, refused, then the values of ``kwnames``) to ``slots`` (kw->n of them, NULL
 * where not given).  0, or -1 with a TypeError: positional arguments, an unknown or repeated
 * keyword, a required one missing, each named.  The slots borrow the caller's references. */
int wkpy_bind_keywords(wkpy_kwlist *kw, PyObject *const *args, Py_ssize_t nargs,
                       PyObject *kwnames, PyObject **slots);

/* wkpy_bind_keywords onto slots that already hold values (not cleared first): a keyword
 * whose slot holds one is refused as given twice. */
int wkpy_bind_more(wkpy_kwlist *kw, PyObject *const *args, Py_ssize_t nargs, PyObject *kwnames,
                   PyObject **slots);

/* The same from a tuple of positional arguments (refused unless empty) and a dict of
 * keywords (NULL: none), as a type's tp_new receives them. */
int wkpy_bind_dict(wkpy_kwlist *kw, PyObject *args, PyObject *kwargs, PyObject **slots);

/* The names as a tuple of str (a module constant: which keywords a function takes). */
PyObject *wkpy_kwlist_names(const wkpy_kwlist *kw);

#define WKPY_SLOT_ENUM(prefix, name) prefix##name,
#define WKPY_SLOT_NAME(prefix, name) #name,

/* A system: its compiled functions' addresses, guard directions and sizes; the first
 * names of solve()'s, basin_points()'s and PreparedMap()'s lists. */
#define WKPY_SYSTEM_FIELDS(X, P)                                                             \
    X(P, rhs) X(P, guards) X(P, reset) X(P, jac) X(P, ctx) X(P, directions) X(P, n_x)         \
    X(P, n_guards) X(P, n_impulse)
enum { WKPY_SYSTEM_FIELDS(WKPY_SLOT_ENUM, WKPY_SYS_) WKPY_SYSTEM_N };

/* The solver settings, in solve()'s and the section's lists: the method's code
 * (walker.simulation.integrate.METHODS), adaptive, rtol, atol, first_step [s], max_step [s],
 * max_steps (the run's, or per stride), n_interior (guard samples inside a step) and
 * screen_interior (keep them only in a step where a guard may come near zero). */
#define WKPY_SOLVER_FIELDS(X, P)                                                             \
    X(P, method) X(P, adaptive) X(P, rtol) X(P, atol) X(P, first_step) X(P, max_step)         \
    X(P, max_steps) X(P, n_interior) X(P, screen_interior)
enum { WKPY_SOLVER_FIELDS(WKPY_SLOT_ENUM, WKPY_SOL_) WKPY_SOLVER_N };

/* The system from its slots (``sys``: the WKPY_SYSTEM_N slots of a list that starts with
 * WKPY_SYSTEM_FIELDS): the function addresses into ``fn`` (rhs non-zero, the others 0 for
 * NULL) and n_x, n_guards, n_impulse into ``pb`` (their ranges are the caller's to check);
 * the directions are the caller's to read. */
int wkpy_arg_system(PyObject *const *sys, wk_functions *fn, wk_problem *pb);

/* The solver settings from their slots (``sol``: WKPY_SOLVER_N slots in the order of
 * WKPY_SOLVER_FIELDS): the method's code into ``method`` and max_steps into ``max_steps``
 * (the caller checks both), the others into ``pb`` (n_interior checked in [0, 2**24]). */
int wkpy_arg_solver(PyObject *const *sol, int64_t *method, int64_t *max_steps, wk_problem *pb);

/* In a function whose cleanup follows the label ``out``: raise ``exc`` with the message
 * format and arguments, and go to out. */
#define WKPY_FAIL(exc, ...)                                                                  \
    do {                                                                                     \
        PyErr_Format(exc, __VA_ARGS__);                                                      \
        goto out;                                                                            \
    } while (0)

/* The buffers a function holds, each acquired by wkpy_hold_buffer, all released by
 * wkpy_release_held (start from wkpy_held h = {0}). */
#define WKPY_MAX_HELD 8
typedef struct {
    Py_buffer *views[WKPY_MAX_HELD];
    int n;
} wkpy_held;

/* wkpy_arg_buffer into ``view``, which h then holds; 0, or -1 with an exception (nothing
 * more held). */
int wkpy_hold_buffer(wkpy_held *h, PyObject *o, const char *name, char kind, int ndim,
                     Py_buffer *view);

/* Releases the buffers h holds, in the order they were acquired. */
void wkpy_release_held(wkpy_held *h);

/* The exception of a run that failed: wk_hybrid_solve's (or wk_section_run's) code rc
 * WK_ERR_NOMEM (out of memory) or WK_ERR_BAD_PHASE (a reset's next phase, the result's
 * phase res_phase, outside [0, n_phases)); returns 1 then, else 0 (no exception). */
int wkpy_run_failed(int rc, int64_t res_phase, int64_t n_phases);

/* 1 when all n values are finite, else 0. */
int wkpy_all_finite(const double *v, Py_ssize_t n);

/* A new bytearray of ``count`` items of ``item`` bytes copied from ``data`` (empty when
 * count <= 0); NULL with an exception set when out of memory. */
PyObject *wkpy_bytes_of(const void *data, int64_t count, size_t item);

/* Makes the SolveResult type (once) and adds it to ``module``; 0, or -1 with an exception. */
int wkpy_add_solve_result(PyObject *module);

/* A new SolveResult holding a run's result ``res`` of the problem ``pb`` (which gives the
 * array sizes); NULL with an exception set when out of memory. */
PyObject *wkpy_solve_result(const wk_result *res, const wk_problem *pb);

/* The settings of a walker's section, the keywords that basin_points and PreparedMap take
 * (and, in this order as positional arguments, terrain_walk and terrain_ensemble): the
 * system, p, the solver settings (max_steps per stride), the affine lift x = lift_a z +
 * lift_b, the projection's indices proj, the start checks (offset, fall_angle, n_q, wound,
 * the energy function's address, kinetic_limit), the start_phase function's address, t_max
 * (per stride) and the addresses lift, lift_jacobian of a compiled lift that is not affine
 * (0 for the affine one).  walker._hybrid.SECTION_FIELDS lists the names. */
#define WKPY_SECTION_FIELDS(X, P)                                                            \
    WKPY_SYSTEM_FIELDS(X, P) X(P, p) WKPY_SOLVER_FIELDS(X, P) X(P, lift_a) X(P, lift_b)       \
    X(P, proj) X(P, offset) X(P, fall_angle) X(P, n_q) X(P, wound) X(P, energy)               \
    X(P, kinetic_limit) X(P, start_phase) X(P, t_max) X(P, lift) X(P, lift_jacobian)
enum { WKPY_SECTION_FIELDS(WKPY_SLOT_ENUM, WKPY_SEC_) WKPY_SECTION_NARGS };
extern wkpy_kwlist wkpy_section_kw;

typedef struct {
    wk_functions fn;
    wk_problem pb; /* the template: sizes, p, solver settings */
    wk_section sec;
    int64_t n_p; /* the length of pb.p */
    void *block; /* owns directions, p, lift_a, lift_b, proj */
} wkpy_section;

/* Reads the WKPY_SECTION_NARGS slots (in the order of WKPY_SECTION_FIELDS) into ``s``; 0, or
 * -1 with an exception naming the argument (``s`` then owns nothing).  wkpy_section_free
 * releases it. */
int wkpy_section_parse(PyObject *const *slots, wkpy_section *s);
void wkpy_section_free(wkpy_section *s);

/* A compiled model's sizes (walker._hybrid.models() reports them): state, parameters,
 * phases, guards, impulse components, drawing points, section coordinates. */
typedef struct {
    const char *name;
    int64_t n_x, n_p, n_phases, n_guards, n_impulse, n_points, n_z, n_inputs;
} wkpy_model_sizes;

/* The functions of a registry entry, as the slots they fill. */
enum {
    WKPY_FN_RHS, WKPY_FN_GUARDS, WKPY_FN_RESET, WKPY_FN_JAC, WKPY_FN_ENERGY, WKPY_FN_POINTS,
    WKPY_FN_START, WKPY_FN_LIFT, WKPY_FN_LIFT_JAC, WKPY_FN_TORQUES, WKPY_FN_NONE
};

/* The sizes of the registry entry named ``entry_name`` ("kneed/plain": kneed's); NULL when
 * the model has no row (a test keeps every entry covered). */
const wkpy_model_sizes *wkpy_sizes_named(const char *entry_name);

/* The sizes of the compiled model that function ``address`` belongs to, and in *role which
 * of its functions it is; NULL (role WKPY_FN_NONE) for an address outside the registry. */
const wkpy_model_sizes *wkpy_sizes_of(uintptr_t address, int *role);

/* The sizes of a compiled model whose function of ``role`` is ``address`` and whose
 * parameter count is n_p, else of the first whose function it is (models may share one:
 * compass_coulomb uses compass's energy and points); NULL when none has it in this role. */
const wkpy_model_sizes *wkpy_sizes_for(uintptr_t address, int role, int64_t n_p);

/* A state function's input length (n_x, or n_z for a lift) and output count; -1 for a
 * role that is not a state function. */
int wkpy_state_fn_lengths(const wkpy_model_sizes *s, int role, int64_t *n_in, int64_t *n_out);

/* The system's compiled functions against its sizes (pb: n_x, n_phases, n_guards,
 * n_impulse; n_p the parameter count): each of fn's functions that is a compiled model's
 * must fill its slot and find the model's sizes.  0, or -1 with a ValueError naming the
 * argument.  A user's functions are not checked (their sizes are the caller's). */
int wkpy_check_system(const wk_functions *fn, const wk_problem *pb, int64_t n_p);

/* A state function handed to a section or search (energy, start_phase, lift,
 * lift_jacobian: ``role``): when it is a compiled model's, it must be that model's function
 * of this role, with the system's n_x and n_p (and n_z for a lift); a user's function (any
 * other address) is the caller's to size.  0, or -1 with a ValueError naming ``name``. */
int wkpy_check_state_fn(uintptr_t address, const char *name, int role, int64_t n_x,
                        int64_t n_p, int64_t n_z);

/* Interrupts (_hybridsignals.c): wkpy_signals_begin before a compiled call releases the
 * GIL, wkpy_signals_end after it took it back (both with the GIL held); end returns 1 when
 * SIGINT or SIGTERM arrived meanwhile (the call then ended early, WK_INTERRUPTED).
 * wkpy_interrupted then runs Python's signal handlers: -1 with their exception set when
 * one raised; else, with must_raise, -1 with a KeyboardInterrupt (a result cut short that
 * carries no status of its own, or a thread other than the main one), else 0 (the caller
 * returns its result with the INTERRUPTED status). */
void wkpy_signals_init(void); /* at import: notes the main thread */
void wkpy_signals_begin(void);
int wkpy_signals_end(void);
int wkpy_interrupted(int must_raise);

/* Makes the PreparedMap type ready and adds it to ``module``; 0, or -1 with an exception. */
int wkpy_add_prepared_map(PyObject *module);

/* The gait search (_hybridsearch.c): PreparedMap.search on the section s (n_strides at
 * most max_period), and walker._hybrid.search through Python callbacks. */
PyObject *wkpy_prepared_search(const wkpy_section *s, int64_t max_period, PyObject *args,
                               PyObject *kw);
PyObject *wkpy_search(PyObject *self, PyObject *args, PyObject *kw);
extern const char wkpy_search_doc[];

/* Adds the terrain functions (_terrainbinding.c) to ``module``; 0, or -1 with an exception. */
int wkpy_add_terrain(PyObject *module);


/* The registries as dicts (_hybridregistry.c): models(), kernels(), kernel_hashes(). */
extern const char wkpy_models_doc[], wkpy_kernels_doc[], wkpy_kernel_hashes_doc[];
PyObject *wkpy_models(PyObject *self, PyObject *unused);
PyObject *wkpy_kernels(PyObject *self, PyObject *unused);
PyObject *wkpy_kernel_hashes(PyObject *self, PyObject *unused);

#endif
