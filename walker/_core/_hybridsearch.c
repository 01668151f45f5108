/* walker._hybrid's gait search (newton.h), the one search of walker/newton.py, reached two
 * ways, both with keyword arguments only:
 *
 *   PreparedMap.search(z0=, scale=, <region>, <settings>)   a walker's stride map in C,
 *       wk_search_compiled without the GIL (wkpy_prepared_search, called by _hybridmap.c);
 *   search(z0=, scale=, evaluate=, jacobian=, outside=, <settings>)   any other map: each
 *       evaluation calls back into Python, with the GIL held (wkpy_search).
 *
 * <settings> are wk_search_settings' fields by name (SETTINGS), <region> wk_region's (REGION
 * and `energy`, an address).  Both return the same tuple (end, status, it, n_evals, refused,
 * why, why_value, why_index, cond, z, history, known); walker/newton.py reads it.
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

typedef struct {
    const char *name;
    char kind; /* 'i' int64_t, 'b' int used as a bool, 'd' double */
    size_t offset;
} field;

#define SETTING(name, kind) {#name, kind, offsetof(wk_search_settings, name)}
static const field SETTINGS[] = {
    SETTING(period, 'i'),        SETTING(tol, 'd'),          SETTING(max_iter, 'i'),
    SETTING(fallback, 'b'),      SETTING(max_evals, 'i'),    SETTING(exact, 'b'),
    SETTING(jac_cost, 'i'),      SETTING(coarse, 'b'),       SETTING(own_rtol, 'd'),
    SETTING(own_atol, 'd'),      SETTING(armijo, 'd'),       SETTING(line_flat, 'd'),
    SETTING(cond_max, 'd'),      SETTING(max_halvings, 'i'), SETTING(lm_start, 'd'),
    SETTING(lm_grow, 'd'),       SETTING(lm_shrink, 'd'),    SETTING(lm_max, 'd'),
    SETTING(lm_tries, 'i'),      SETTING(tr_start, 'd'),     SETTING(tr_max, 'd'),
    SETTING(stall_window, 'i'),  SETTING(stall_ratio, 'd'),  SETTING(stall_alpha, 'd'),
    SETTING(coarsest_rtol, 'd'), SETTING(coarse_rho, 'd'),   SETTING(coarse_keep, 'd'),
};
#define N_SETTINGS ((int)(sizeof SETTINGS / sizeof SETTINGS[0]))

#define REGION(name, kind) {#name, kind, offsetof(wk_region, name)}
static const field REGION[] = {
    REGION(has_stance, 'b'), REGION(stance_offset, 'd'), REGION(fall_angle, 'd'),
    REGION(n_q, 'i'),        REGION(wound_limit, 'd'),   REGION(kinetic_max, 'd'),
};
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
        PyObject *o = keyword(kw, table[i].name);
        char *at = (char *)base + table[i].offset;
        if (o == NULL) return -1;
        if (table[i].kind == 'i' ? wkpy_arg_int(o, table[i].name, (int64_t *)at)
            : table[i].kind == 'b' ? wkpy_arg_bool(o, table[i].name, (int *)at)
                                   : wkpy_arg_double(o, table[i].name, (double *)at))
            return -1;
    }
    return 0;
}

/* No positional arguments. */
static int no_positional(PyObject *args)
{
    if (PyTuple_GET_SIZE(args) == 0) return 0;
    PyErr_SetString(PyExc_TypeError, "search() takes keyword arguments only");
    return -1;
}

static int in_table(const char *name, const field *table, int n)
{
    for (int i = 0; i < n; i++)
        if (strcmp(name, table[i].name) == 0) return 1;
    return 0;
}

/* Every keyword is a setting, one of `names` (NULL-terminated), or a region field when
 * `region`; else a TypeError naming the first other one. */
static int no_other_keywords(PyObject *kw, const char *const *names, int region)
{
    PyObject *key, *value;
    Py_ssize_t pos = 0;
    while (PyDict_Next(kw, &pos, &key, &value)) {
        const char *name = PyUnicode_Check(key) ? PyUnicode_AsUTF8(key) : NULL;
        if (name == NULL) {
            PyErr_Clear();
            PyErr_SetString(PyExc_TypeError, "search() keywords must be strings");
            return -1;
        }
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

/* The settings every search checks; 0, or -1 with a ValueError naming the setting. */
static int check_settings(const wk_search_settings *set)
{
    /* the history holds min(max_iter, max_evals) + 1 values: the budgets are bounded */
    const struct {
        const char *name;
        int64_t value;
    } budgets[] = {{"period", set->period},       {"max_iter", set->max_iter},
                   {"max_evals", set->max_evals}, {"jac_cost", set->jac_cost},
                   {"max_halvings", set->max_halvings}, {"lm_tries", set->lm_tries},
                   {"stall_window", set->stall_window}};
    for (size_t i = 0; i < sizeof budgets / sizeof budgets[0]; i++) {
        if (budgets[i].value > WKPY_MAX_BUDGET) {
            PyErr_Format(PyExc_ValueError, "search(): `%s` must be at most %lld, got %lld",
                         budgets[i].name, (long long)WKPY_MAX_BUDGET,
                         (long long)budgets[i].value);
            return -1;
        }
        if (budgets[i].value < (i < 4 ? 1 : 0)) {
            PyErr_Format(PyExc_ValueError, "search(): `%s` must be at least %d, got %lld",
                         budgets[i].name, i < 4 ? 1 : 0, (long long)budgets[i].value);
            return -1;
        }
    }
    if (set->coarse && !(set->own_rtol > 0.0 && set->own_atol > 0.0)) {
        PyErr_SetString(PyExc_ValueError, "search(): `own_rtol` and `own_atol` must be > 0");
        return -1;
    }
    return 0;
}

/* n float64 values of a buffer into out; 0, or -1 with an exception naming `name`. */
static int read_values(PyObject *o, const char *name, int64_t n, double *out)
{
    Py_buffer v;
    if (PyObject_GetBuffer(o, &v, PyBUF_C_CONTIGUOUS | PyBUF_FORMAT) < 0) {
        PyErr_Clear();
        PyErr_Format(PyExc_TypeError, "search(): `%s` must be a C-contiguous float64 array, "
                     "got %.200s", name, Py_TYPE(o)->tp_name);
        return -1;
    }
    const char *f = v.format == NULL ? "" : v.format;
    if (f[0] == '@' || f[0] == '=' || (f[0] == '<' && PY_LITTLE_ENDIAN)) f++;
    const int ok = v.itemsize == 8 && strcmp(f, "d") == 0 && v.len == (Py_ssize_t)(n * 8);
    if (ok) memcpy(out, v.buf, (size_t)n * sizeof(double));
    PyBuffer_Release(&v);
    if (!ok)
        PyErr_Format(PyExc_ValueError, "search(): `%s` must hold %lld float64 values", name,
                     (long long)n);
    return ok ? 0 : -1;
}

/* z0 and scale (n values each: finite, scale > 0) into a new buffer *buf of 2 n + extra
 * values; 0, or -1 with an exception (nothing allocated). */
static int read_start(PyObject *kw, int64_t n, double **buf, int64_t extra)
{
    PyObject *o_z0 = keyword(kw, "z0"), *o_scale = o_z0 ? keyword(kw, "scale") : NULL;
    if (o_scale == NULL) return -1;
    *buf = PyMem_Malloc((size_t)(2 * n + extra) * sizeof(double));
    if (*buf == NULL) {
        PyErr_NoMemory();
        return -1;
    }
    double *z0 = *buf, *scale = *buf + n;
    if (read_values(o_z0, "z0", n, z0) || read_values(o_scale, "scale", n, scale)) goto fail;
    for (int64_t i = 0; i < n; i++)
        if (!isfinite(z0[i]) || !(scale[i] > 0.0) || !isfinite(scale[i])) {
            PyErr_SetString(PyExc_ValueError,
                            "search(): `z0` must be finite and `scale` finite and > 0");
            goto fail;
        }
    return 0;
fail:
    PyMem_Free(*buf);
    *buf = NULL;
    return -1;
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
    const int64_t n_x = s->pb.n_x, n_z = s->sec.n_z;
    wk_region reg;
    wk_search_settings set;
    uintptr_t energy;
    PyObject *o_energy;
    static const char *const names[] = {"z0", "scale", "energy", NULL};
    if (no_positional(args) || read_fields(kw, REGION, N_REGION, &reg) ||
        read_fields(kw, SETTINGS, N_SETTINGS, &set) ||
        (o_energy = keyword(kw, "energy")) == NULL ||
        wkpy_arg_address(o_energy, "energy", 0, &energy) || no_other_keywords(kw, names, 1) ||
        check_settings(&set))
        return NULL;
    reg.energy = (wk_state_fn)energy;
    if (wkpy_check_state_fn(energy, "energy", WKPY_FN_ENERGY, n_x, s->n_p, 0)) return NULL;
    if (reg.n_q < 1 || reg.n_q > n_x)
        return PyErr_Format(PyExc_ValueError, "search(): `n_q` must be in [1, %lld]",
                            (long long)n_x);
    /* cases the callbacks take: a model without its Jacobian, a period past the budget */
    if (s->fn.jac == NULL || !set.exact || set.jac_cost != 1 || set.period > max_period)
        Py_RETURN_NONE;
    double *buf;
    const int64_t n_hist = history_length(&set);
    if (read_start(kw, n_z, &buf, 2 * n_z + n_x + n_z * n_z + n_hist) < 0) return NULL;
    const double *z0 = buf, *scale = buf + n_z;
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
    rc = wk_search_compiled(&s->fn, &s->pb, &s->sec, &reg, &set, scale, z0, &res);
    Py_END_ALLOW_THREADS
    if (wkpy_signals_end() && wkpy_interrupted(1)) /* the search's end is not its own */
        goto out;
    if (rc != WK_OK) {
        PyErr_NoMemory();
        goto out;
    }
    if (res.end == WK_SEARCH_DECLINED) {
        result = Py_NewRef(Py_None);
        goto out;
    }
    PyObject *known = Py_NewRef(Py_None);
    if (res.known) {
        Py_DECREF(known);
        known = Py_BuildValue("(dNNN)", res.known_t, wkpy_bytes_of(res.known_z, n_z, 8),
                              wkpy_bytes_of(res.known_x, n_x, 8),
                              wkpy_bytes_of(res.known_jac, n_z * n_z, 8));
    }
    result = answer(&res, n_z, known);
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

/* A callback's answer (status, z or None, jac or None, result) into e; has_jac for a
 * Jacobian that came (finite only when `finite`).  0, or WK_EVAL_ERROR. */
static int read_answer(PyObject *r, const char *name, int64_t n, int want_jac, int finite,
                       wk_search_eval *e)
{
    if (r == NULL) return WK_EVAL_ERROR;
    int rc = WK_EVAL_ERROR;
    if (!PyTuple_Check(r) || PyTuple_GET_SIZE(r) != 4) {
        PyErr_Format(PyExc_TypeError, "search(): `%s` must return (status, z, jac, result)",
                     name);
        goto out;
    }
    PyObject *o_z = PyTuple_GET_ITEM(r, 1), *o_jac = PyTuple_GET_ITEM(r, 2);
    if (wkpy_arg_int(PyTuple_GET_ITEM(r, 0), "status", &e->status)) goto out;
    e->t = 0.0;
    e->has_jac = 0;
    if (o_z == Py_None) {
        for (int64_t i = 0; i < n; i++) e->z[i] = NAN;
    } else if (read_values(o_z, "z", n, e->z)) {
        goto out;
    }
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
    const callback_map *c = (const callback_map *)m;
    if (PyErr_CheckSignals() < 0) return WK_EVAL_ERROR;
    PyObject *point = wkpy_bytes_of(z, m->n_z, 8);
    if (point == NULL) return WK_EVAL_ERROR;
    PyObject *r = PyObject_CallFunction(c->evaluate, "Ndi", point, level, want_jac);
    return read_answer(r, "evaluate", m->n_z, want_jac, 1, e);
}

static int callback_jacobian(wk_search_map *m, const double *z, wk_search_eval *e)
{
    const callback_map *c = (const callback_map *)m;
    if (PyErr_CheckSignals() < 0) return WK_EVAL_ERROR;
    PyObject *point = wkpy_bytes_of(z, m->n_z, 8);
    if (point == NULL) return WK_EVAL_ERROR;
    PyObject *r = PyObject_CallFunction(c->jacobian, "N", point);
    return read_answer(r, "jacobian", m->n_z, 1, 0, e);
}

/* outside(z) -> 0 (inside) or k >= 1, the map's reason number k (WK_OUT_OTHER). */
static int callback_outside(wk_search_map *m, const double *z, double *value, int64_t *index)
{
    const callback_map *c = (const callback_map *)m;
    PyObject *point = wkpy_bytes_of(z, m->n_z, 8);
    if (point == NULL) return -1;
    PyObject *r = PyObject_CallFunction(c->outside, "N", point);
    if (r == NULL) return -1;
    int64_t k;
    const int bad = wkpy_arg_int(r, "outside", &k);
    Py_DECREF(r);
    if (bad) return -1;
    if (k <= 0) return WK_INSIDE;
    *value = 0.0;
    *index = k;
    return WK_OUT_OTHER;
}

static void callback_release(wk_search_map *m, wk_search_eval *e)
{
    (void)m;
    Py_CLEAR(e->handle);
}

const char wkpy_search_doc[] =
    "search(*, z0, scale, evaluate, jacobian, outside, <settings>) -> tuple\n\n"
    "walker.newton's gait search (newton.h) on a map in Python.  evaluate(z, rtol, jac) and\n"
    "jacobian(z) return (status, z_next or None, jac or None, result) with float64 arrays\n"
    "(rtol 0.0: the map's own; z a bytearray of float64); outside(z) returns 0 inside or\n"
    "k >= 1, the caller's reason number, or outside is None (no region).  An exception in\n"
    "a callback ends the search and propagates.  Returns (end, status, it, n_evals,\n"
    "refused, why, why_value, why_index, cond, z, history, known) with z and history\n"
    "bytearrays of float64 and known the result of the evaluation at a converged z with its\n"
    "Jacobian, or None.";

PyObject *wkpy_search(PyObject *self, PyObject *args, PyObject *kw)
{
    (void)self;
    wk_search_settings set;
    callback_map c = {{0, 0, callback_evaluate, callback_jacobian, callback_outside,
                       callback_release, 0},
                      NULL, NULL, NULL};
    static const char *const names[] = {"z0", "scale", "evaluate", "jacobian", "outside", NULL};
    if (no_positional(args) || read_fields(kw, SETTINGS, N_SETTINGS, &set) ||
        (c.evaluate = keyword(kw, "evaluate")) == NULL ||
        (c.jacobian = keyword(kw, "jacobian")) == NULL ||
        (c.outside = keyword(kw, "outside")) == NULL || no_other_keywords(kw, names, 0) ||
        check_settings(&set))
        return NULL;
    if (!PyCallable_Check(c.evaluate) || !PyCallable_Check(c.jacobian) ||
        (c.outside != Py_None && !PyCallable_Check(c.outside))) {
        PyErr_SetString(PyExc_TypeError, "search(): `evaluate` and `jacobian` must be "
                                         "callable, `outside` callable or None");
        return NULL;
    }
    if (c.outside == Py_None) c.base.outside = NULL;
    double *buf;
    PyObject *o_z0 = keyword(kw, "z0");
    const Py_ssize_t len = o_z0 == NULL ? -1 : PyObject_Length(o_z0);
    if (len < 0) return NULL;
    const int64_t n = len, n_hist = history_length(&set);
    if (n < 1 || n > MAX_N_X)
        return PyErr_Format(PyExc_ValueError, "search(): `z0` must have 1 to %d values",
                            MAX_N_X);
    if (read_start(kw, n, &buf, 2 * n + n * n + n_hist) < 0) return NULL;
    c.base.n_z = n;
    wk_search_out res = {0};
    res.z = buf + 2 * n;
    res.known_z = buf + 3 * n;
    res.known_jac = buf + 4 * n;
    res.history = res.known_jac + n * n;
    PyObject *result = NULL;
    const int rc = wk_search(&c.base, &set, buf + n, buf, &res);
    PyObject *known = res.known_handle;
    if (rc == WK_ERR_NOMEM)
        PyErr_NoMemory();
    else if (rc == WK_OK)
        result = answer(&res, n, known != NULL ? Py_NewRef(known) : Py_NewRef(Py_None));
    Py_XDECREF(known);
    PyMem_Free(buf);
    return result;
}
