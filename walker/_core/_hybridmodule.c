/* walker._hybrid: the CPython binding of walker's compiled core.
 *
 * solve(...)          one run of the hybrid integrator (hybrid.c), without the GIL, as a
 *                     SolveResult record (_hybridresult.c), keyword arguments only;
 * PreparedSolve(...)  solve()'s settings bound once, run(...) with the rest;
 * models()            walker's compiled models (wk_model_table) as integer addresses;
 * kernels()           the generated kernels (wk_kernel_table) as (signature, address,
 *                     n_q, n_p, shape); kernel_hashes() the generated modules' hashes;
 * call_state_fn(...)  calls a model's energy / points / start_phase / torques function;
 * basin_points(...)   many starts of a walker's stride map (batch.c), without the GIL;
 * PreparedMap(...)    one start of a walker's stride map per map() call, its settings
 *                     parsed once (_hybridmap.c);
 * search(...)         the gait search on a map in Python, through callbacks; with
 *                     PreparedMap.search, on the compiled map (newton.c, _hybridsearch.c).
 *
 * Plain C API, no numpy: arrays come in through the buffer protocol (C-contiguous float64
 * or int64) and go out as bytearrays that walker/simulation/integrate.py views with numpy.frombuffer.
 * Model functions are passed as integer addresses of C functions with the signatures of
 * wk_system.h.  The argument converters are in _hybridargs.c, the record solve() returns in
 * _hybridresult.c, the section settings and PreparedMap in _hybridmap.c (all declared in
 * _hybridbinding.h).
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <math.h>
#include <stdint.h>
#include <string.h>

#include "_hybridbinding.h"
#include "batch.h"
#include "hybrid.h"
#include "wk_terrain.h"

#ifndef WK_SOURCE_HASH
#define WK_SOURCE_HASH "unknown"
#endif
#ifndef WK_COMPILE_FLAGS
#define WK_COMPILE_FLAGS "unknown"
#endif
#include "wk_common.h"
#include "wk_models.h"
#include "wk_system.h"

/* ------------------------------------------------------------------------------------------
 * solve
 * ------------------------------------------------------------------------------------------ */

/* solve()'s keywords: the system, the start, the solver settings, the output; the
 * optional ones (sample_times, jacobian_seed, n_p; terrain, terrain_solve()'s only) last. */
#define SOLVE_FIELDS(X, P)                                                                   \
    WKPY_SYSTEM_FIELDS(X, P) X(P, x0) X(P, p) X(P, phase0) X(P, t0) X(P, t_max)               \
    X(P, n_strides) WKPY_SOLVER_FIELDS(X, P) X(P, output) X(P, want_jac) X(P, sample_times)   \
    X(P, jacobian_seed) X(P, n_p) X(P, terrain)
enum { SOLVE_FIELDS(WKPY_SLOT_ENUM, S_) SOLVE_N };
static const char *const solve_names[] = {SOLVE_FIELDS(WKPY_SLOT_NAME, S_)};
static PyObject *solve_interned[SOLVE_N];
static wkpy_kwlist solve_kw = {"solve", SOLVE_N - 1, S_sample_times, solve_names,
                               solve_interned};
static wkpy_kwlist terrain_solve_kw = {"terrain_solve", SOLVE_N, S_sample_times, solve_names,
                                       solve_interned};

PyDoc_STRVAR(solve_doc,
             "solve(*, rhs, guards, reset, jac, ctx, directions, n_x, n_guards, n_impulse,\n"
             "      x0, p, phase0, t0, t_max, n_strides, method, adaptive, rtol, atol,\n"
             "      first_step, max_step, max_steps, n_interior, screen_interior, output,\n"
             "      want_jac, sample_times=None, jacobian_seed=None, n_p=None)\n"
             "--\n\n"
             "One run of the hybrid integrator (see walker/simulation/integrate.py, which validates the\n"
             "input and is the way to call this).  Keyword arguments only.  rhs, guards,\n"
             "reset, jac, ctx: int addresses (wk_system.h; jac = 0: none, ctx = 0: NULL).\n"
             "directions: int64 (n_phases, n_guards); x0 (n_x,), p, sample_times: float64\n"
             "1-D (p of length n_p when given, and the compiled model's n_p when the\n"
             "functions are a compiled model's);\n"
             "method and output: the codes of walker.status; n_interior: guard samples inside\n"
             "every step, with screen_interior kept only in a step where a guard may come\n"
             "near zero (guards without explicit t).  jacobian_seed (with want_jac): None or\n"
             "a float64 (n_x, m) array S, 1 <= m <= n_x; the run then propagates\n"
             "(d x / d x0) S, and jac and dt_dx0 hold m columns.  The GIL is released while\n"
             "integrating.\n\n"
             "Returns a SolveResult, a named tuple read by field: status (a walker.status\n"
             "value), t, x (the final time, state, phase); the counters n_steps, n_rejected,\n"
             "n_rhs, n_events, n_strides and the row counts n_logged, n_samples, n_recorded;\n"
             "error_estimate; the event log event_t, event_guard, event_phase_before,\n"
             "event_phase_after, event_x_pre, event_x_post, event_impulse (output events or\n"
             "richer); sample_x, sample_phase (samples); record_t, record_x, record_phase\n"
             "(full); jac (n_x, m), dt_dx0 (m,) and has_dt_dx0 (with want_jac; m = n_x\n"
             "without a seed).  Arrays are bytearrays of native float64 / int64, row-major;\n"
             "help(SolveResult) describes each field.");

/* solve(), or with a `terrain` slot (terrain_solve(): n_steps rows of (slope, drop)) the
 * model's terrain guards and reset and the step bookkeeping (wk_terrain.h). */
static PyObject *solve_impl(PyObject *const *a)
{
    wk_functions fn;
    wk_terrain T;
    wk_problem pb;
    memset(&pb, 0, sizeof pb);
    Py_buffer v_dir, v_x0, v_p, v_st, v_seed, v_terrain;
    wkpy_held held = {0};
    PyObject *result = NULL;
    int64_t method, output;

    if (wkpy_arg_system(a, &fn, &pb) || wkpy_arg_int(a[S_phase0], "phase0", &pb.phase0) ||
        wkpy_arg_double(a[S_t0], "t0", &pb.t0) ||
        wkpy_arg_double(a[S_t_max], "t_max", &pb.t_max) ||
        wkpy_arg_int(a[S_n_strides], "n_strides", &pb.n_strides) ||
        wkpy_arg_solver(a + S_method, &method, &pb.max_steps, &pb) ||
        wkpy_arg_int(a[S_output], "output", &output) ||
        wkpy_arg_bool(a[S_want_jac], "want_jac", &pb.want_jac))
        return NULL;

    if (pb.n_x < 1 || pb.n_x > MAX_N_X)
        WKPY_FAIL(PyExc_ValueError, "`n_x` must be in [1, %d], got %lld", MAX_N_X,
                  (long long)pb.n_x);
    if (pb.n_guards < 0 || pb.n_guards > MAX_COUNT)
        WKPY_FAIL(PyExc_ValueError, "`n_guards` must be in [0, 2**24], got %lld",
                  (long long)pb.n_guards);
    if (pb.n_impulse < 1 || pb.n_impulse > MAX_COUNT)
        WKPY_FAIL(PyExc_ValueError, "`n_impulse` must be in [1, 2**24], got %lld",
                  (long long)pb.n_impulse);
    if (pb.n_guards > 0 && (fn.guards == NULL || fn.reset == NULL))
        WKPY_FAIL(PyExc_ValueError, "`%s` must be a non-zero function address when n_guards > 0",
                  fn.guards == NULL ? "guards" : "reset");
    if (method < WK_METHOD_EULER || method > WK_METHOD_DOP853)
        WKPY_FAIL(PyExc_ValueError, "`method` must be a code in [0, 3], got %lld",
                  (long long)method);
    pb.method = (int)method;
    if (output < WK_OUTPUT_MAP || output > WK_OUTPUT_FULL)
        WKPY_FAIL(PyExc_ValueError, "`output` must be a code in [0, 3], got %lld",
                  (long long)output);
    pb.output = (int)output;
    if (pb.adaptive && pb.method != WK_METHOD_DOP853 && pb.method != WK_METHOD_DP5)
        WKPY_FAIL(PyExc_ValueError, "`adaptive` needs method DOP853 or RK45");
    if (!(isfinite(pb.t0) && isfinite(pb.t_max) && pb.t_max > pb.t0))
        WKPY_FAIL(PyExc_ValueError, "`t0` and `t_max` must be finite with t_max > t0");
    if (!(pb.rtol > 0.0 && isfinite(pb.rtol)))
        WKPY_FAIL(PyExc_ValueError, "`rtol` must be positive and finite");
    if (!(pb.atol > 0.0 && isfinite(pb.atol)))
        WKPY_FAIL(PyExc_ValueError, "`atol` must be positive and finite");
    if (!(pb.first_step >= 0.0 && isfinite(pb.first_step)) ||
        (!pb.adaptive && !(pb.first_step > 0.0)))
        WKPY_FAIL(PyExc_ValueError, "`first_step` must be finite and positive (0: automatic, "
                                    "adaptive methods only)");
    if (!(pb.max_step > 0.0))
        WKPY_FAIL(PyExc_ValueError, "`max_step` must be positive");
    if (pb.n_strides < 0) WKPY_FAIL(PyExc_ValueError, "`n_strides` must be >= 0");
    if (pb.max_steps < 1) WKPY_FAIL(PyExc_ValueError, "`max_steps` must be >= 1");
    if (pb.want_jac && fn.jac == NULL)
        WKPY_FAIL(PyExc_ValueError, "`want_jac` needs a Jacobian (`jac` is 0)");

    if (wkpy_hold_buffer(&held, a[S_directions], "directions", 'q', 2, &v_dir)) goto out;
    if (v_dir.shape[1] != pb.n_guards)
        WKPY_FAIL(PyExc_ValueError, "`directions` must have n_guards = %lld columns, got %zd",
                  (long long)pb.n_guards, v_dir.shape[1]);
    pb.n_phases = v_dir.shape[0];
    if (pb.n_phases < 1) WKPY_FAIL(PyExc_ValueError, "`directions` must have at least one row");
    pb.directions = (const int64_t *)v_dir.buf;
    for (int64_t i = 0; i < pb.n_phases * pb.n_guards; i++)
        if (pb.directions[i] < -1 || pb.directions[i] > 1)
            WKPY_FAIL(PyExc_ValueError, "`directions` values must be -1, 0 or +1");
    if (pb.phase0 < 0 || pb.phase0 >= pb.n_phases)
        WKPY_FAIL(PyExc_ValueError, "`phase0` must be in [0, n_phases = %lld), got %lld",
                  (long long)pb.n_phases, (long long)pb.phase0);

    if (wkpy_hold_buffer(&held, a[S_x0], "x0", 'd', 1, &v_x0)) goto out;
    if (v_x0.shape[0] != pb.n_x)
        WKPY_FAIL(PyExc_ValueError, "`x0` must have length n_x = %lld, got %zd", (long long)pb.n_x,
                  v_x0.shape[0]);
    pb.x0 = (const double *)v_x0.buf;
    if (!wkpy_all_finite(pb.x0, v_x0.shape[0]))
        WKPY_FAIL(PyExc_ValueError, "All components of the initial state `x0` must be finite.");

    if (wkpy_hold_buffer(&held, a[S_p], "p", 'd', 1, &v_p)) goto out;
    pb.p = (const double *)v_p.buf;
    if (a[S_n_p] != NULL && a[S_n_p] != Py_None) { /* the system's declared count */
        int64_t n_p;
        if (wkpy_arg_int(a[S_n_p], "n_p", &n_p)) goto out;
        if (v_p.shape[0] != n_p)
            WKPY_FAIL(PyExc_ValueError, "`p` must have length n_p = %lld, got %zd",
                      (long long)n_p, v_p.shape[0]);
    }
    if (!wkpy_all_finite(pb.p, v_p.shape[0]))
        WKPY_FAIL(PyExc_ValueError, "All parameters `p` must be finite.");
    if (wkpy_check_system(&fn, &pb, v_p.shape[0])) goto out;

    if (a[S_sample_times] != NULL && a[S_sample_times] != Py_None) {
        if (wkpy_hold_buffer(&held, a[S_sample_times], "sample_times", 'd', 1, &v_st)) goto out;
        pb.sample_times = (const double *)v_st.buf;
        pb.n_samples = v_st.shape[0];
    }
    if (pb.output == WK_OUTPUT_SAMPLES && pb.n_samples > 0) {
        if (!wkpy_all_finite(pb.sample_times, v_st.shape[0]))
            WKPY_FAIL(PyExc_ValueError, "`sample_times` must be finite");
        for (int64_t i = 1; i < pb.n_samples; i++)
            if (pb.sample_times[i] < pb.sample_times[i - 1])
                WKPY_FAIL(PyExc_ValueError, "`sample_times` must be sorted (non-decreasing)");
    }

    if (a[S_jacobian_seed] != NULL && a[S_jacobian_seed] != Py_None) {
        if (!pb.want_jac) WKPY_FAIL(PyExc_ValueError, "`jacobian_seed` needs `want_jac`");
        if (wkpy_hold_buffer(&held, a[S_jacobian_seed], "jacobian_seed", 'd', 2, &v_seed))
            goto out;
        if (v_seed.shape[0] != pb.n_x || v_seed.shape[1] < 1 || v_seed.shape[1] > pb.n_x)
            WKPY_FAIL(PyExc_ValueError,
                      "`jacobian_seed` must have shape (n_x = %lld, m) with 1 <= m <= n_x, got "
                      "(%zd, %zd)",
                      (long long)pb.n_x, v_seed.shape[0], v_seed.shape[1]);
        if (!wkpy_all_finite((const double *)v_seed.buf, v_seed.shape[0] * v_seed.shape[1]))
            WKPY_FAIL(PyExc_ValueError, "`jacobian_seed` must be finite");
        pb.jac_seed = (const double *)v_seed.buf;
        pb.n_seed = v_seed.shape[1];
    }

    if (a[S_terrain] != NULL) {
        if (wkpy_hold_buffer(&held, a[S_terrain], "terrain", 'd', 2, &v_terrain)) goto out;
        if (v_terrain.shape[1] != 2 ||
            !wkpy_all_finite((const double *)v_terrain.buf, v_terrain.shape[0] * 2))
            WKPY_FAIL(PyExc_ValueError, "`terrain` must be (n_steps, 2) finite values");
        const wk_terrain_entry *te = wk_terrain_find(fn.guards);
        if (te == NULL)
            WKPY_FAIL(PyExc_ValueError, "terrain is not supported for this system's model");
        memset(&T, 0, sizeof T);
        T.steps = (const double *)v_terrain.buf;
        T.n_steps = v_terrain.shape[0];
        T.scene_slope = pb.p[te->slope_index];
        wk_terrain_set_step(&T, 0);
        fn = wk_terrain_functions(&fn, te, &T, pb.p, pb.x0);
    }

    wk_result res;
    int rc;
    wkpy_signals_begin();
    Py_BEGIN_ALLOW_THREADS
    rc = wk_hybrid_solve(&fn, &pb, &res);
    Py_END_ALLOW_THREADS
    const int interrupted = wkpy_signals_end();

    if (interrupted && wkpy_interrupted(0)) result = NULL;
    else if (!wkpy_run_failed(rc, res.phase, pb.n_phases))
        result = wkpy_solve_result(&res, &pb);
    wk_result_free(&res);

out:
    wkpy_release_held(&held);
    return result;
}

static PyObject *py_solve(PyObject *self, PyObject *const *args, Py_ssize_t nargs,
                          PyObject *kwnames)
{
    (void)self;
    PyObject *slots[SOLVE_N];
    if (wkpy_bind_keywords(&solve_kw, args, nargs, kwnames, slots)) return NULL;
    slots[S_terrain] = NULL;
    return solve_impl(slots);
}

PyDoc_STRVAR(terrain_solve_doc,
             "terrain_solve(*, terrain, **solve_keywords)\n--\n\n"
             "solve() over per-step terrain (walker/_core/wk_terrain.h): solve()'s keywords\n"
             "and terrain, a float64 (n_steps, 2) array of (slope, drop) rows, the scene's\n"
             "plane past the last; ValueError for a model without terrain functions.");

static PyObject *py_terrain_solve(PyObject *self, PyObject *const *args, Py_ssize_t nargs,
                                  PyObject *kwnames)
{
    (void)self;
    PyObject *slots[SOLVE_N];
    if (wkpy_bind_keywords(&terrain_solve_kw, args, nargs, kwnames, slots)) return NULL;
    if (slots[S_terrain] == NULL) {
        PyErr_SetString(PyExc_TypeError, "terrain_solve() missing required keyword argument "
                                         "`terrain`");
        return NULL;
    }
    return solve_impl(slots);
}

/* ------------------------------------------------------------------------------------------
 * PreparedSolve: solve()'s settings bound once
 * ------------------------------------------------------------------------------------------ */

/* solve()'s keywords bound at construction (none required there) and per run (the required
 * ones then, from both). */
static wkpy_kwlist prepared_solve_kw = {"PreparedSolve", SOLVE_N - 1, 0, solve_names,
                                        solve_interned};
static wkpy_kwlist prepared_run_kw = {"PreparedSolve.run", SOLVE_N - 1, S_sample_times,
                                      solve_names, solve_interned};

typedef struct {
    PyObject_HEAD
    PyObject *slots[SOLVE_N]; /* owned references, NULL where not bound */
} PreparedSolve;

static PyObject *prepared_solve_new(PyTypeObject *type, PyObject *args, PyObject *kwargs)
{
    PyObject *slots[SOLVE_N] = {NULL}; /* terrain's too, which the list leaves out */
    if (wkpy_bind_dict(&prepared_solve_kw, args, kwargs, slots)) return NULL;
    PreparedSolve *self = (PreparedSolve *)type->tp_alloc(type, 0);
    if (self == NULL) return NULL;
    for (int j = 0; j < SOLVE_N; j++) self->slots[j] = Py_XNewRef(slots[j]);
    return (PyObject *)self;
}

static void prepared_solve_dealloc(PreparedSolve *self)
{
    for (int j = 0; j < SOLVE_N; j++) Py_CLEAR(self->slots[j]);
    Py_TYPE(self)->tp_free((PyObject *)self);
}

PyDoc_STRVAR(prepared_solve_run_doc,
             "run(**keywords) -> SolveResult\n\n"
             "solve() with the keywords bound at construction and these (keyword arguments\n"
             "only; a keyword bound already is refused): every argument is converted and\n"
             "checked as solve() does.");

static PyObject *prepared_solve_run(PreparedSolve *self, PyObject *const *args,
                                    Py_ssize_t nargs, PyObject *kwnames)
{
    PyObject *slots[SOLVE_N];
    memcpy(slots, self->slots, sizeof slots);
    if (wkpy_bind_more(&prepared_run_kw, args, nargs, kwnames, slots)) return NULL;
    for (int j = 0; j < S_sample_times; j++)
        if (slots[j] == NULL) {
            PyErr_Format(PyExc_TypeError, "PreparedSolve.run() missing required keyword "
                         "argument `%s`", solve_names[j]);
            return NULL;
        }
    slots[S_terrain] = NULL;
    return solve_impl(slots); /* the objects stay alive: self and the caller hold them */
}

static PyMethodDef prepared_solve_methods[] = {
    {"run", (PyCFunction)(void (*)(void))prepared_solve_run, METH_FASTCALL | METH_KEYWORDS,
     prepared_solve_run_doc},
    {NULL, NULL, 0, NULL},
};

PyDoc_STRVAR(prepared_solve_doc,
             "PreparedSolve(**keywords)\n\n"
             "solve()'s settings bound once (keyword arguments only, any of solve()'s but\n"
             "terrain; walker.simulation.integrate.PreparedRun binds the system, the solver settings, t0\n"
             "and output): run() takes the rest by keyword.  A call with many keywords makes\n"
             "the interpreter build a dict; bound here, a run passes only the few that change.\n"
             "Process-local (it holds function addresses): not picklable.");

static PyTypeObject prepared_solve_type = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "walker._hybrid.PreparedSolve",
    .tp_basicsize = sizeof(PreparedSolve),
    .tp_dealloc = (destructor)prepared_solve_dealloc,
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_doc = prepared_solve_doc,
    .tp_methods = prepared_solve_methods,
    .tp_new = prepared_solve_new,
};

/* ------------------------------------------------------------------------------------------
 * call_state_fn
 * ------------------------------------------------------------------------------------------ */

PyDoc_STRVAR(call_state_fn_doc,
             "call_state_fn(address, x, p, n_out, ctx=0)\n--\n\n"
             "Calls the wk_state_fn at ``address`` (a compiled model's energy, points, start_phase,\n"
             "lift or lift_jacobian, see wk_models.h) on the float64 arrays x and p; returns\n"
             "its first n_out outputs as a list of floats.  Only a compiled model's function\n"
             "(its lengths are known): x must have the model's n_x (n_z for a lift), p its\n"
             "n_p, and n_out be at most the function's output count.");

static PyObject *py_call_state_fn(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    (void)self;
    if (nargs < 4 || nargs > 5) {
        PyErr_Format(PyExc_TypeError, "call_state_fn() takes 4 or 5 arguments, got %zd", nargs);
        return NULL;
    }
    uintptr_t address, ctx = 0;
    int64_t n_out, n_in = 0, n_max = 0;
    int role;
    if (wkpy_arg_address(args[0], "address", 0, &address) ||
        wkpy_arg_int(args[3], "n_out", &n_out) ||
        (nargs == 5 && wkpy_arg_address(args[4], "ctx", 1, &ctx)))
        return NULL;
    /* Only a compiled model's state function: its input and output lengths are known. */
    const wkpy_model_sizes *sizes = wkpy_sizes_of(address, &role);
    if (sizes == NULL || wkpy_state_fn_lengths(sizes, role, &n_in, &n_max)) {
        PyErr_SetString(PyExc_ValueError, "`address` must be the energy, points, start_phase, "
                                          "lift, lift_jacobian or torques function of a "
                                          "compiled model "
                                          "(walker._hybrid.models())");
        return NULL;
    }
    if (n_out < 0 || n_out > n_max) {
        PyErr_Format(PyExc_ValueError, "`n_out` must be in [0, %lld] for the %s's function, "
                     "got %lld", (long long)n_max, sizes->name, (long long)n_out);
        return NULL;
    }
    Py_buffer vx, vp;
    if (wkpy_arg_buffer_pair(args + 1, "x", 1, "p", 1, &vx, &vp)) return NULL;
    PyObject *list = NULL;
    double *out = NULL;
    /* the model with this parameter count, where several share the function */
    sizes = wkpy_sizes_for(address, role, vp.shape[0]);
    wkpy_state_fn_lengths(sizes, role, &n_in, &n_max);
    if (n_out > n_max) {
        PyErr_Format(PyExc_ValueError, "`n_out` must be in [0, %lld] for the %s's function, "
                     "got %lld", (long long)n_max, sizes->name, (long long)n_out);
        goto out;
    }
    if (vx.shape[0] != n_in) {
        PyErr_Format(PyExc_ValueError, "`x` must have length %lld for %s, got %zd",
                     (long long)n_in, sizes->name, vx.shape[0]);
        goto out;
    }
    /* At least the function's parameters: the Coulomb walkers call their base walker's
     * energy and points with their longer vector, whose first entries are the base's. */
    if (vp.shape[0] < sizes->n_p) {
        PyErr_Format(PyExc_ValueError, "`p` must have length at least n_p = %lld for %s, "
                     "got %zd", (long long)sizes->n_p, sizes->name, vp.shape[0]);
        goto out;
    }
    out = PyMem_Calloc((size_t)n_max + 1, sizeof(double));
    if (out == NULL) {
        PyErr_NoMemory();
        goto out;
    }
    wk_state_fn f = (wk_state_fn)address;
    f((const double *)vx.buf, (const double *)vp.buf, out, (void *)ctx);
    list = PyList_New((Py_ssize_t)n_out);
    for (int64_t i = 0; list != NULL && i < n_out; i++) {
        PyObject *v = PyFloat_FromDouble(out[i]);
        if (v == NULL) {
            Py_CLEAR(list);
            break;
        }
        PyList_SET_ITEM(list, (Py_ssize_t)i, v);
    }
out:
    PyMem_Free(out);
    PyBuffer_Release(&vx);
    PyBuffer_Release(&vp);
    return list;
}

/* ------------------------------------------------------------------------------------------
 * Batches
 * ------------------------------------------------------------------------------------------ */

/* basin_points()'s keywords: the section's, then the points and the stopping rule. */
#define BASIN_FIELDS(X, P)                                                                   \
    WKPY_SECTION_FIELDS(X, P) X(P, z0) X(P, target) X(P, tol) X(P, n_strides) X(P, period)    \
    X(P, weight) X(P, radius)
enum { BASIN_FIELDS(WKPY_SLOT_ENUM, B_) BASIN_N };
static const char *const basin_names[] = {BASIN_FIELDS(WKPY_SLOT_NAME, B_)};
static PyObject *basin_interned[BASIN_N];
static wkpy_kwlist basin_kw = {"basin_points", BASIN_N, BASIN_N, basin_names, basin_interned};

PyDoc_STRVAR(basin_points_doc,
             "basin_points(*, **section, z0, target, tol, n_strides, period, weight, radius)\n"
             "    -> (outcome, strides)\n\n"
             "Iterate the stride map from each row of z0 (m, n_z) as walker.analysis.basin.basin_chunk\n"
             "does (batch.h), without the GIL.  Keyword arguments only: the section's\n"
             "(SECTION_FIELDS, as PreparedMap takes them) and target (n_z,), tol, n_strides,\n"
             "period; radius > 0 also stops a point inside ||weight (z - target)||_2 <=\n"
             "radius (weight (n_z, n_z)) as converged.  outcome and strides: bytearrays of m\n"
             "int64.");

static PyObject *py_basin_points(PyObject *self, PyObject *const *args, Py_ssize_t nargs,
                                 PyObject *kwnames)
{
    (void)self;
    PyObject *a[BASIN_N];
    if (wkpy_bind_keywords(&basin_kw, args, nargs, kwnames, a)) return NULL;
    wkpy_section s;
    if (wkpy_section_parse(a, &s)) return NULL;
    Py_buffer v_z0, v_target, v_weight;
    wkpy_held held = {0};
    PyObject *result = NULL;
    int64_t n_strides, period;
    double tol, radius;
    if (wkpy_arg_double(a[B_tol], "tol", &tol) ||
        wkpy_arg_int(a[B_n_strides], "n_strides", &n_strides) ||
        wkpy_arg_int(a[B_period], "period", &period) ||
        wkpy_arg_double(a[B_radius], "radius", &radius))
        goto out;

    if (!(tol >= 0.0)) WKPY_FAIL(PyExc_ValueError, "`tol` must be >= 0");
    if (!(radius >= 0.0 && isfinite(radius)))
        WKPY_FAIL(PyExc_ValueError, "`radius` must be finite and >= 0");
    if (n_strides < 0) WKPY_FAIL(PyExc_ValueError, "`n_strides` must be >= 0");
    if (period < 1 || period > INT64_MAX / s.sec.max_steps)
        WKPY_FAIL(PyExc_ValueError, "`period` must be in [1, %lld] (its step budget in int64)",
                  (long long)(INT64_MAX / s.sec.max_steps));
    if (n_strides > INT64_MAX / 2)
        WKPY_FAIL(PyExc_ValueError, "`n_strides` must be at most 2**62");
    if (wkpy_hold_buffer(&held, a[B_z0], "z0", 'd', 2, &v_z0)) goto out;
    if (v_z0.shape[1] != s.sec.n_z)
        WKPY_FAIL(PyExc_ValueError, "`z0` must have n_z = %lld columns, got %zd",
                  (long long)s.sec.n_z, v_z0.shape[1]);
    if (!wkpy_all_finite((const double *)v_z0.buf, v_z0.shape[0] * v_z0.shape[1]))
        WKPY_FAIL(PyExc_ValueError, "All section points `z0` must be finite.");
    if (wkpy_hold_buffer(&held, a[B_target], "target", 'd', 1, &v_target)) goto out;
    if (v_target.shape[0] != s.sec.n_z)
        WKPY_FAIL(PyExc_ValueError, "`target` must have length n_z");
    if (wkpy_hold_buffer(&held, a[B_weight], "weight", 'd', 2, &v_weight)) goto out;
    if (v_weight.shape[0] != s.sec.n_z || v_weight.shape[1] != s.sec.n_z)
        WKPY_FAIL(PyExc_ValueError, "`weight` must have shape (n_z, n_z)");
    if (!wkpy_all_finite((const double *)v_weight.buf, v_weight.shape[0] * v_weight.shape[1]))
        WKPY_FAIL(PyExc_ValueError, "`weight` must be finite.");

    const int64_t m = v_z0.shape[0];
    int64_t *buf = PyMem_Calloc((size_t)(2 * m + 1), sizeof(int64_t));
    if (buf == NULL) {
        PyErr_NoMemory();
        goto out;
    }
    int rc;
    wkpy_signals_begin();
    Py_BEGIN_ALLOW_THREADS
    rc = wk_basin_points(&s.fn, &s.pb, &s.sec, m, (const double *)v_z0.buf,
                         (const double *)v_target.buf, tol, (const double *)v_weight.buf, radius,
                         n_strides, period, buf, buf + m);
    Py_END_ALLOW_THREADS
    if (wkpy_signals_end() && wkpy_interrupted(1)) {
        /* the outcomes after the signal are not the points' own: never returned */
    } else if (rc == WK_ERR_NOMEM) {
        PyErr_NoMemory();
    } else if (rc == WK_ERR_BAD_PHASE) {
        PyErr_SetString(PyExc_ValueError, "`reset` returned a next phase outside the phases");
    } else {
        result = Py_BuildValue("(NN)", wkpy_bytes_of(buf, m, sizeof(int64_t)),
                               wkpy_bytes_of(buf + m, m, sizeof(int64_t)));
    }
    PyMem_Free(buf);

out:
    wkpy_release_held(&held);
    wkpy_section_free(&s);
    return result;
}

/* ------------------------------------------------------------------------------------------
 * Module
 * ------------------------------------------------------------------------------------------ */

static PyMethodDef methods[] = {
    {"solve", (PyCFunction)(void (*)(void))py_solve, METH_FASTCALL | METH_KEYWORDS, solve_doc},
    {"terrain_solve", (PyCFunction)(void (*)(void))py_terrain_solve,
     METH_FASTCALL | METH_KEYWORDS, terrain_solve_doc},
    {"models", wkpy_models, METH_NOARGS, wkpy_models_doc},
    {"kernels", wkpy_kernels, METH_NOARGS, wkpy_kernels_doc},
    {"kernel_hashes", wkpy_kernel_hashes, METH_NOARGS, wkpy_kernel_hashes_doc},
    {"basin_points", (PyCFunction)(void (*)(void))py_basin_points,
     METH_FASTCALL | METH_KEYWORDS, basin_points_doc},
    {"call_state_fn", (PyCFunction)(void (*)(void))py_call_state_fn, METH_FASTCALL,
     call_state_fn_doc},
    {"search", (PyCFunction)(void (*)(void))wkpy_search, METH_VARARGS | METH_KEYWORDS,
     wkpy_search_doc},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {
    PyModuleDef_HEAD_INIT,
    "walker._hybrid",
    "walker's compiled core: the hybrid integrator and the compiled models (see\n"
    "walker/_core/wk_system.h for the model ABI and walker/simulation/integrate.py for the Python API).",
    -1,
    methods,
    NULL,
    NULL,
    NULL,
    NULL,
};

/* Adds the tuple of kw's names to ``m`` as ``name``; 0, or -1 with an exception. */
static int add_names(PyObject *m, const char *name, const wkpy_kwlist *kw)
{
    PyObject *t = wkpy_kwlist_names(kw);
    if (t == NULL) return -1;
    const int rc = PyModule_AddObjectRef(m, name, t);
    Py_DECREF(t);
    return rc;
}

PyMODINIT_FUNC PyInit__hybrid(void)
{
    PyObject *m = PyModule_Create(&module);
    if (m == NULL) return NULL;
    wkpy_signals_init();
    /* The arming tolerance compiled into the kernel (walker.simulation.integrate.GUARD_TOL). */
    PyObject *tol = PyFloat_FromDouble(WK_GUARD_TOL);
    if (tol == NULL || PyModule_AddObjectRef(m, "GUARD_TOL", tol) < 0) {
        Py_XDECREF(tol);
        Py_DECREF(m);
        return NULL;
    }
    Py_DECREF(tol);
    /* The record solve() returns. */
    if (wkpy_add_solve_result(m) < 0) {
        Py_DECREF(m);
        return NULL;
    }
    /* solve()'s settings bound once. */
    if (PyType_Ready(&prepared_solve_type) < 0 ||
        PyModule_AddObjectRef(m, "PreparedSolve", (PyObject *)&prepared_solve_type) < 0) {
        Py_DECREF(m);
        return NULL;
    }
    /* The compiled stride-map call (_hybridmap.c). */
    if (wkpy_add_prepared_map(m) < 0) {
        Py_DECREF(m);
        return NULL;
    }
    /* The keywords each call takes, by name (walker/simulation/_section.py reads SECTION_FIELDS). */
    if (add_names(m, "SOLVE_FIELDS", &terrain_solve_kw) < 0 ||
        add_names(m, "SECTION_FIELDS", &wkpy_section_kw) < 0 ||
        add_names(m, "BASIN_FIELDS", &basin_kw) < 0) {
        Py_DECREF(m);
        return NULL;
    }
    /* The terrain runs (_terrainbinding.c). */
    if (wkpy_add_terrain(m) < 0) {
        Py_DECREF(m);
        return NULL;
    }
    /* Fingerprint of the sources this was built from (setup.py, walker/_build.py). */
    if (PyModule_AddStringConstant(m, "SOURCE_HASH", WK_SOURCE_HASH) < 0) {
        Py_DECREF(m);
        return NULL;
    }
    /* The compiler command and flags it was built with (setup.py), for provenance. */
    if (PyModule_AddStringConstant(m, "COMPILE_FLAGS", WK_COMPILE_FLAGS) < 0) {
        Py_DECREF(m);
        return NULL;
    }
    return m;
}
