/* walker._hybrid's gait search (newton.h), the one search of walker/analysis/newton.py, reached two
 * ways, both with keyword arguments only:
 *
 *   PreparedMap.search(z0=, scale=, <region>, <settings>)   a walker's stride map in C,
 *       wk_search_compiled without the GIL (wkpy_prepared_search, called by _hybridmap.c);
 *   search(z0=, scale=, evaluate=, jacobian=, outside=, <settings>)   any other map: each
 *       evaluation calls back into Python, with the GIL held (wkpy_search).
 *
 * <settings> are wk_search_settings' fields by name (SETTINGS), <region> wk_region's (REGION
 * and `energy`, an address).  Both return the same tuple (end, status, it, n_evals, refused,
 * why, why_value, why_index, cond, z, history, known); walker/analysis/newton.py reads it.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "_hybridbinding.h"
#include "newton.h"

/* ------------------------------------------------------------------------------------------
 * Keyword arguments
 * ------------------------------------------------------------------------------------------ */

/* kind: 'n' a count in [1, WKPY_MAX_BUDGET] (the history holds min(max_iter, max_evals) + 1
 * values), 'i' an int64_t in [0, WKPY_MAX_BUDGET], 'b' an int used as a bool, 'd' a double */
typedef struct {
    const char *name;
    char kind;
    size_t offset;
} field;

#define SETTING(name, kind) {#name, kind, offsetof(wk_search_settings, name)}
static const field SETTINGS[] = {
    SETTING(period, 'n'),        SETTING(tol, 'd'),          SETTING(max_iter, 'n'),
    SETTING(fallback, 'b'),      SETTING(max_evals, 'n'),    SETTING(exact, 'b'),
    SETTING(jac_cost, 'n'),      SETTING(coarse, 'b'),       SETTING(own_rtol, 'd'),
    SETTING(own_atol, 'd'),      SETTING(armijo, 'd'),       SETTING(line_flat, 'd'),
    SETTING(cond_max, 'd'),      SETTING(max_halvings, 'i'), SETTING(lm_start, 'd'),
    SETTING(lm_grow, 'd'),       SETTING(lm_shrink, 'd'),    SETTING(lm_max, 'd'),
    SETTING(lm_tries, 'i'),      SETTING(tr_start, 'd'),     SETTING(tr_max, 'd'),
    SETTING(stall_window, 'i'),  SETTING(stall_ratio, 'd'),  SETTING(stall_alpha, 'd'),
    SETTING(coarsest_rtol, 'd'), SETTING(coarse_rho, 'd'),   SETTING(coarse_keep, 'd'),
};
#define REGION(name, kind) {#name, kind, offsetof(wk_region, name)}
static const field REGION[] = {
    REGION(has_stance, 'b'), REGION(stance_offset, 'd'), REGION(fall_angle, 'd'),
    REGION(n_q, 'n'),        REGION(wound_limit, 'd'),   REGION(kinetic_max, 'd'),
};
#define N_SETTINGS ((int)(sizeof SETTINGS / sizeof SETTINGS[0]))
#define N_REGION ((int)(sizeof REGION / sizeof REGION[0]))

/* The keyword argument `name` (borrowed), or NULL with a TypeError when it is missing. */
static PyObject *keyword(PyObject *kw, const char *name)
{
    PyObject *o = kw == NULL ? NULL : PyDict_GetItemString(kw, name);
    if (o == NULL)
        PyErr_Format(PyExc_TypeError, "search() missing required keyword argument '%s'", name);
    return o;
}

/* The n fields of `table` from kw into the struct at base; 0, or -1 with an exception. */
static int read_fields(PyObject *kw, const field *table, int n, void *base)
{
    for (int i = 0; i < n; i++) {
        const char *name = table[i].name, kind = table[i].kind;
        PyObject *o = keyword(kw, name);
        char *at = (char *)base + table[i].offset;
        if (o == NULL || (kind == 'b'   ? wkpy_arg_bool(o, name, (int *)at)
                          : kind == 'd' ? wkpy_arg_double(o, name, (double *)at)
                                        : wkpy_arg_int(o, name, (int64_t *)at)))
            return -1;
        const int64_t v = kind == 'n' || kind == 'i' ? *(int64_t *)at : 0, low = kind == 'n';
        if (v < low || v > WKPY_MAX_BUDGET) {
            PyErr_Format(PyExc_ValueError, "search(): `%s` must be in [%d, %lld], got %lld",
                         name, (int)low, (long long)WKPY_MAX_BUDGET, (long long)v);
            return -1;
        }
    }
    return 0;
}

static int in_table(const char *name, const field *table, int n)
{
    for (int i = 0; i < n; i++)
        if (strcmp(name, table[i].name) == 0) return 1;
    return 0;
}

/* No positional argument, and every keyword a setting, one of `names` (NULL-terminated)
 * or, with `region`, a region field; else a TypeError naming the first other one. */
static int only_keywords(PyObject *args, PyObject *kw, const char *const *names, int region)
{
    if (PyTuple_GET_SIZE(args) != 0) {
        PyErr_SetString(PyExc_TypeError, "search() takes keyword arguments only");
        return -1;
    }
    PyObject *key, *value;
    Py_ssize_t pos = 0;
    while (kw != NULL && PyDict_Next(kw, &pos, &key, &value)) {
        const char *name = PyUnicode_AsUTF8(key);
        if (name == NULL) return -1;
        int known = in_table(name, SETTINGS, N_SETTINGS) ||
                    (region && in_table(name, REGION, N_REGION));
        for (int i = 0; !known && names[i] != NULL; i++) known = strcmp(name, names[i]) == 0;
        if (!known) {
            PyErr_Format(PyExc_TypeError, "search() got an unexpected keyword argument '%s'",
                         name);
            return -1;
        }
    }
    return 0;
}

/* n float64 values of a 1-D buffer into out; 0, or -1 with an exception naming `name`. */
static int read_values(PyObject *o, const char *name, int64_t n, double *out)
{
    Py_buffer v;
    if (wkpy_arg_buffer(o, name, 'd', 1, &v)) return -1;
    const int ok = v.shape[0] == n;
    if (ok) memcpy(out, v.buf, (size_t)n * sizeof(double));
    PyBuffer_Release(&v);
    if (!ok) PyErr_Format(PyExc_ValueError, "`%s` must have length %lld", name, (long long)n);
    return ok ? 0 : -1;
}

/* z0 and scale (n values each: finite, scale > 0) into a new buffer *buf of 2 n + extra
 * values; 0, or -1 with an exception (nothing allocated). */
static int read_start(PyObject *kw, int64_t n, double **buf, int64_t extra)
{
    PyObject *o_z0 = keyword(kw, "z0"), *o_scale = o_z0 ? keyword(kw, "scale") : NULL;
    if (o_scale == NULL || (*buf = PyMem_Malloc((size_t)(2 * n + extra) * 8)) == NULL)
        return o_scale == NULL ? -1 : (PyErr_NoMemory(), -1);
    double *z0 = *buf, *scale = *buf + n;
    int bad = read_values(o_z0, "z0", n, z0) || read_values(o_scale, "scale", n, scale);
    for (int64_t i = 0; !bad && i < n; i++)
        if (!isfinite(z0[i]) || !(scale[i] > 0.0) || !isfinite(scale[i])) {
            PyErr_SetString(PyExc_ValueError, "`z0` must be finite, `scale` finite and > 0");
            bad = 1;
        }
    if (bad) PyMem_Free(*buf);
    return bad ? -1 : 0;
}

/* The history's length: min(max_iter, max_evals) + 1. */
static int64_t history_length(const wk_search_settings *set)
{
    return (set->max_iter < set->max_evals ? set->max_iter : set->max_evals) + 1;
}

/* The answer tuple (see the top of the file); `known` is stolen. */
static PyObject *answer(const wk_search_out *res, int64_t n_z, PyObject *known)
{
    if (known == NULL) return NULL;
    return Py_BuildValue("(iLLLLidLdNNN)", res->end, (long long)res->status, (long long)res->it,
                         (long long)res->n_evals, (long long)res->refused, res->why,
                         res->why_value, (long long)res->why_index, res->cond,
                         wkpy_bytes_of(res->z, n_z, 8),
                         wkpy_bytes_of(res->history, res->n_history, 8), known);
}

/* ------------------------------------------------------------------------------------------
 * PreparedMap.search: a walker's stride map in C
 * ------------------------------------------------------------------------------------------ */

PyObject *wkpy_prepared_search(const wkpy_section *s, int64_t max_period, PyObject *args,
                               PyObject *kw)
{
    static const char *const names[] = {"z0", "scale", "energy", NULL};
    const int64_t n_x = s->pb.n_x, n_z = s->sec.n_z;
    wk_region reg;
    wk_search_settings set;
    uintptr_t energy;
    PyObject *o_energy;
    if (only_keywords(args, kw, names, 1) || read_fields(kw, REGION, N_REGION, &reg) ||
        read_fields(kw, SETTINGS, N_SETTINGS, &set) ||
        (o_energy = keyword(kw, "energy")) == NULL ||
        wkpy_arg_address(o_energy, "energy", 0, &energy) ||
        wkpy_check_state_fn(energy, "energy", WKPY_FN_ENERGY, n_x, s->n_p, 0))
        return NULL;
    reg.energy = (wk_state_fn)energy;
    if (reg.n_q > n_x)
        return PyErr_Format(PyExc_ValueError, "`n_q` must be at most n_x = %lld",
                            (long long)n_x);
    /* cases the callbacks take: a model without its Jacobian, a period past the budget */
    if (s->fn.jac == NULL || !set.exact || set.jac_cost != 1 || set.period > max_period)
        Py_RETURN_NONE;
    double *buf;
    if (read_start(kw, n_z, &buf, 2 * n_z + n_x + n_z * n_z + history_length(&set)))
        return NULL;
    PyObject *result = NULL;
    wk_search_out res = {0};
    res.z = buf + 2 * n_z;
    res.known_z = buf + 3 * n_z;
    res.known_x = buf + 4 * n_z;
    res.known_jac = res.known_x + n_x;
    res.history = res.known_jac + n_z * n_z;
    int rc;
    wkpy_signals_begin();
    Py_BEGIN_ALLOW_THREADS
    rc = wk_search_compiled(&s->fn, &s->pb, &s->sec, &reg, &set, buf + n_z, buf, &res);
    Py_END_ALLOW_THREADS
    if (wkpy_signals_end() && wkpy_interrupted(1)) /* the search's end is not its own */
        goto out;
    if (rc != WK_OK) {
        PyErr_NoMemory();
    } else if (res.end == WK_SEARCH_DECLINED) {
        result = Py_NewRef(Py_None);
    } else {
        result = answer(&res, n_z,
                        !res.known ? Py_NewRef(Py_None)
                                   : Py_BuildValue("(dNNN)", res.known_t,
                                                   wkpy_bytes_of(res.known_z, n_z, 8),
                                                   wkpy_bytes_of(res.known_x, n_x, 8),
                                                   wkpy_bytes_of(res.known_jac, n_z * n_z, 8)));
    }
out:
    PyMem_Free(buf);
    return result;
}

/* ------------------------------------------------------------------------------------------
 * search: a map in Python, through callbacks
 * ------------------------------------------------------------------------------------------ */

typedef struct {
    wk_search_map base;
    PyObject *evaluate, *jacobian, *outside; /* borrowed from the call's keywords */
} callback_map;

/* callback(z, *more) with z (n_z,) as a bytearray of float64; NULL with an exception. */
static PyObject *call_at(PyObject *callback, const wk_search_map *m, const double *z,
                         const char *more, double level, int want_jac)
{
    PyObject *point = wkpy_bytes_of(z, m->n_z, 8);
    if (point == NULL || PyErr_CheckSignals() < 0) {
        Py_XDECREF(point);
        return NULL;
    }
    return more == NULL ? PyObject_CallOneArg(callback, point)
                        : PyObject_CallFunction(callback, "Ndi", point, level, want_jac);
}

/* A callback's answer r (status, z or None, jac or None, result) into e, then r released;
 * has_jac for a Jacobian that came (finite only when `finite`).  0, or WK_EVAL_ERROR. */
static int read_answer(PyObject *r, int64_t n, int want_jac, int finite, wk_search_eval *e)
{
    if (r == NULL) return WK_EVAL_ERROR;
    int rc = WK_EVAL_ERROR;
    if (!PyTuple_Check(r) || PyTuple_GET_SIZE(r) != 4) {
        PyErr_SetString(PyExc_TypeError, "search(): a callback must return (status, z, jac, "
                                         "result)");
        goto out;
    }
    PyObject *o_z = PyTuple_GET_ITEM(r, 1), *o_jac = PyTuple_GET_ITEM(r, 2);
    if (wkpy_arg_int(PyTuple_GET_ITEM(r, 0), "status", &e->status)) goto out;
    e->t = 0.0;
    e->has_jac = 0;
    for (int64_t i = 0; o_z == Py_None && i < n; i++) e->z[i] = NAN;
    if (o_z != Py_None && read_values(o_z, "z", n, e->z)) goto out;
    if (want_jac && o_jac != Py_None) {
        if (read_values(o_jac, "jac", n * n, e->jac)) goto out;
        e->has_jac = 1;
        for (int64_t i = 0; finite && i < n * n; i++)
            if (!isfinite(e->jac[i])) e->has_jac = 0;
    }
    Py_XSETREF(e->handle, Py_NewRef(PyTuple_GET_ITEM(r, 3)));
    rc = 0;
out:
    Py_DECREF(r);
    return rc;
}

static int callback_evaluate(wk_search_map *m, const double *z, double level, int want_jac,
                             wk_search_eval *e)
{
    PyObject *r = call_at(((callback_map *)m)->evaluate, m, z, "", level, want_jac);
    return read_answer(r, m->n_z, want_jac, 1, e);
}

static int callback_jacobian(wk_search_map *m, const double *z, wk_search_eval *e)
{
    return read_answer(call_at(((callback_map *)m)->jacobian, m, z, NULL, 0.0, 0), m->n_z, 1,
                       0, e);
}

/* outside(z) -> 0 (inside) or k >= 1, the map's reason number k (WK_OUT_OTHER). */
static int callback_outside(wk_search_map *m, const double *z, double *value, int64_t *index)
{
    PyObject *r = call_at(((callback_map *)m)->outside, m, z, NULL, 0.0, 0);
    int64_t k = 0;
    const int bad = r == NULL || wkpy_arg_int(r, "outside", &k);
    Py_XDECREF(r);
    *value = 0.0;
    *index = k;
    return bad ? -1 : k > 0 ? WK_OUT_OTHER : WK_INSIDE;
}

static void callback_release(wk_search_map *m, wk_search_eval *e)
{
    (void)m;
    Py_CLEAR(e->handle);
}

const char wkpy_search_doc[] =
    "search(*, z0, scale, evaluate, jacobian, outside, <settings>) -> tuple\n\n"
    "walker.analysis.newton's gait search (newton.h) on a map in Python.  evaluate(z, rtol, jac) and\n"
    "jacobian(z) return (status, z_next or None, jac or None, result) with 1-D float64\n"
    "arrays (rtol 0.0: the map's own; z a bytearray of float64); outside(z) returns 0 inside\n"
    "or k >= 1, the caller's reason number, or outside is None (no region).  An exception in\n"
    "a callback ends the search and propagates.  Returns (end, status, it, n_evals, refused,\n"
    "why, why_value, why_index, cond, z, history, known) with z and history bytearrays of\n"
    "float64 and known the result of the evaluation at a converged z with its Jacobian, or\n"
    "None.";

PyObject *wkpy_search(PyObject *self, PyObject *args, PyObject *kw)
{
    (void)self;
    static const char *const names[] = {"z0", "scale", "evaluate", "jacobian", "outside", NULL};
    wk_search_settings set;
    callback_map c = {{0, 0, callback_evaluate, callback_jacobian, callback_outside,
                       callback_release, 0},
                      NULL, NULL, NULL};
    PyObject *o_z0;
    if (only_keywords(args, kw, names, 0) || read_fields(kw, SETTINGS, N_SETTINGS, &set) ||
        (c.evaluate = keyword(kw, "evaluate")) == NULL ||
        (c.jacobian = keyword(kw, "jacobian")) == NULL ||
        (c.outside = keyword(kw, "outside")) == NULL || (o_z0 = keyword(kw, "z0")) == NULL)
        return NULL;
    if (!PyCallable_Check(c.evaluate) || !PyCallable_Check(c.jacobian) ||
        (c.outside != Py_None && !PyCallable_Check(c.outside)))
        return PyErr_Format(PyExc_TypeError, "search(): `evaluate` and `jacobian` must be "
                                             "callable, `outside` callable or None");
    if (c.outside == Py_None) c.base.outside = NULL;
    const Py_ssize_t n = PyObject_Length(o_z0);
    if (n < 0) return NULL;
    if (n < 1 || n > MAX_N_X)
        return PyErr_Format(PyExc_ValueError, "`z0` must have 1 to %d values", MAX_N_X);
    double *buf;
    if (read_start(kw, n, &buf, 2 * n + n * n + history_length(&set))) return NULL;
    c.base.n_z = n;
    wk_search_out res = {0};
    res.z = buf + 2 * n;
    res.known_z = buf + 3 * n;
    res.known_jac = buf + 4 * n;
    res.history = res.known_jac + n * n;
    PyObject *result = NULL, *known;
    const int rc = wk_search(&c.base, &set, buf + n, buf, &res);
    known = res.known_handle != NULL ? res.known_handle : Py_NewRef(Py_None);
    if (rc == WK_ERR_NOMEM) PyErr_NoMemory();
    if (rc == WK_OK) result = answer(&res, n, Py_NewRef(known));
    Py_DECREF(known);
    PyMem_Free(buf);
    return result;
}
