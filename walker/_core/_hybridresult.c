/* walker._hybrid.SolveResult: the named record solve() returns.
 *
 * A PyStructSequence (a tuple subclass, like os.stat_result): each field reads by name,
 * ``sol.status``, ``sol.x``, and by position in the order of the table below.  Arrays are
 * bytearrays of native float64 / int64, row-major, that walker/simulation/integrate.py views with
 * numpy.frombuffer; their row counts are the n_* fields.  Declared in _hybridbinding.h.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <stdint.h>

#include "_hybridbinding.h"

/* The fields, in record order (wkpy_solve_result fills them in this order). */
static PyStructSequence_Field fields[] = {
    {"status", "the run's outcome: a walker.status.Status value (int)"},
    {"t", "time at the end of the run [s] (float)"},
    {"x", "final state: float64 (n_x,)"},
    {"phase", "phase at the end (int)"},
    {"n_steps", "accepted steps (int)"},
    {"n_rejected", "rejected steps (int)"},
    {"n_rhs", "vector-field evaluations (int)"},
    {"n_events", "events applied (resets) (int)"},
    {"n_strides", "strides completed (int)"},
    {"n_logged", "rows of the event log, event_* (int)"},
    {"n_samples", "rows of the samples, sample_* (int)"},
    {"n_recorded", "rows of the record, record_* (int)"},
    {"error_estimate", "sum over accepted steps of rtol times the error norm (float)"},
    {"event_t", "event times [s]: float64 (n_logged,)"},
    {"event_guard", "the guard that fired: int64 (n_logged,)"},
    {"event_phase_before", "phase before the reset: int64 (n_logged,)"},
    {"event_phase_after", "phase after the reset: int64 (n_logged,)"},
    {"event_x_pre", "state before the reset: float64 (n_logged, n_x)"},
    {"event_x_post", "state after the reset: float64 (n_logged, n_x)"},
    {"event_impulse", "impulses of the reset: float64 (n_logged, n_impulse)"},
    {"sample_x", "states at sample_times: float64 (n_samples, n_x)"},
    {"sample_phase", "phases at sample_times: int64 (n_samples,)"},
    {"record_t", "time of every accepted step [s]: float64 (n_recorded,)"},
    {"record_x", "state at every accepted step: float64 (n_recorded, n_x)"},
    {"record_phase", "phase at every accepted step: int64 (n_recorded,)"},
    {"jac", "d x / d x0 times the seed: float64 (n_x, m), zeros unless want_jac"},
    {"dt_dx0", "d t / d x0 times the seed: float64 (m,), valid when has_dt_dx0"},
    {"has_dt_dx0", "whether dt_dx0 holds: the run ended on its last stride, with want_jac"},
    {NULL, NULL},
};

#define N_FIELDS ((int)(sizeof fields / sizeof fields[0]) - 1)

PyDoc_STRVAR(solve_result_doc,
             "SolveResult: what walker._hybrid.solve returns, a named tuple of its run.\n\n"
             "Fields by name (or position, in this order): status, t, x, phase; the counters\n"
             "n_steps, n_rejected, n_rhs, n_events, n_strides, n_logged, n_samples,\n"
             "n_recorded; error_estimate; the event log event_t, event_guard,\n"
             "event_phase_before, event_phase_after, event_x_pre, event_x_post,\n"
             "event_impulse; the samples sample_x, sample_phase; the record record_t,\n"
             "record_x, record_phase; the sensitivities jac, dt_dx0, has_dt_dx0.  Arrays are\n"
             "bytearrays of native float64 / int64, row-major (m: the jacobian_seed's\n"
             "columns, else n_x).");

static PyStructSequence_Desc desc = {
    "walker._hybrid.SolveResult",
    solve_result_doc,
    fields,
    N_FIELDS,
};

/* The type, made once by wkpy_add_solve_result (the module has one instance). */
static PyTypeObject *solve_result_type = NULL;

int wkpy_add_solve_result(PyObject *module)
{
    if (solve_result_type == NULL) {
        solve_result_type = PyStructSequence_NewType(&desc);
        if (solve_result_type == NULL) return -1;
    }
    return PyModule_AddObjectRef(module, "SolveResult", (PyObject *)solve_result_type);
}

PyObject *wkpy_solve_result(const wk_result *res, const wk_problem *pb)
{
    const int64_t *c = res->counters;
    const int64_t n_x = pb->n_x, n_imp = pb->n_impulse;
    const int64_t n_c = pb->jac_seed != NULL ? pb->n_seed : n_x;
    const int64_t n_log = c[WK_N_LOG], n_samp = c[WK_N_SAMPLES], n_rec = c[WK_N_RECORD];
    const size_t d = sizeof(double), q = sizeof(int64_t);
    PyObject *items[] = {
        PyLong_FromLongLong((long long)res->status),
        PyFloat_FromDouble(res->t),
        wkpy_bytes_of(res->x, n_x, d),
        PyLong_FromLongLong((long long)res->phase),
        PyLong_FromLongLong((long long)c[WK_N_STEPS]),
        PyLong_FromLongLong((long long)c[WK_N_REJECTED]),
        PyLong_FromLongLong((long long)c[WK_N_RHS]),
        PyLong_FromLongLong((long long)c[WK_N_EVENTS]),
        PyLong_FromLongLong((long long)c[WK_N_STRIDES]),
        PyLong_FromLongLong((long long)n_log),
        PyLong_FromLongLong((long long)n_samp),
        PyLong_FromLongLong((long long)n_rec),
        PyFloat_FromDouble(res->err_sum),
        wkpy_bytes_of(res->ev_t, n_log, d),
        wkpy_bytes_of(res->ev_guard, n_log, q),
        wkpy_bytes_of(res->ev_phase_before, n_log, q),
        wkpy_bytes_of(res->ev_phase_after, n_log, q),
        wkpy_bytes_of(res->ev_x_pre, n_log * n_x, d),
        wkpy_bytes_of(res->ev_x_post, n_log * n_x, d),
        wkpy_bytes_of(res->ev_impulse, n_log * n_imp, d),
        wkpy_bytes_of(res->s_x, n_samp * n_x, d),
        wkpy_bytes_of(res->s_phase, n_samp, q),
        wkpy_bytes_of(res->r_t, n_rec, d),
        wkpy_bytes_of(res->r_x, n_rec * n_x, d),
        wkpy_bytes_of(res->r_phase, n_rec, q),
        wkpy_bytes_of(res->jac, n_x * n_c, d),
        wkpy_bytes_of(res->dt_dx0, n_c, d),
        PyBool_FromLong(res->has_dt),
    };
    enum { N_ITEMS = sizeof items / sizeof items[0] };
    /* the table and the items agree (a mismatch fails to compile) */
    typedef char items_match_fields[N_ITEMS == N_FIELDS ? 1 : -1];
    (void)sizeof(items_match_fields);

    PyObject *record = PyStructSequence_New(solve_result_type);
    int ok = record != NULL;
    for (int i = 0; i < N_ITEMS; i++) ok = ok && items[i] != NULL;
    if (!ok) {
        for (int i = 0; i < N_ITEMS; i++) Py_XDECREF(items[i]);
        Py_XDECREF(record);
        return NULL;
    }
    for (int i = 0; i < N_ITEMS; i++) PyStructSequence_SET_ITEM(record, i, items[i]);
    return record;
}
