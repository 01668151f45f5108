/* walker._hybrid's argument conversion: Python objects in, C values out, and the C arrays
 * of a result out as bytearrays.
 *
 * Every error names the argument and the rule, as walker/simulation/integrate.py's checks do.  Arrays
 * come in through the buffer protocol (C-contiguous float64 or int64) and go out as
 * bytearrays of native float64 / int64 that walker/simulation/integrate.py views with
 * numpy.frombuffer.  Declared in _hybridbinding.h; used by _hybridmodule.c and
 * _hybridresult.c.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <math.h>
#include <stdint.h>
#include <string.h>

#include "_hybridbinding.h"
#include "indices.h"
#include "wk_models.h"

/* An int (not a bool) that fits in int64. */
int wkpy_arg_int(PyObject *o, const char *name, int64_t *out)
{
    if (PyBool_Check(o) || !PyIndex_Check(o)) {
        PyErr_Format(PyExc_TypeError, "`%s` must be an int, got %.200s", name,
                     Py_TYPE(o)->tp_name);
        return -1;
    }
    PyObject *index = PyNumber_Index(o);
    if (index == NULL) return -1;
    long long v = PyLong_AsLongLong(index);
    Py_DECREF(index);
    if (v == -1 && PyErr_Occurred()) {
        PyErr_Format(PyExc_OverflowError, "`%s` does not fit in a 64-bit integer", name);
        return -1;
    }
    *out = (int64_t)v;
    return 0;
}

/* A real number (int or float, not a bool). */
int wkpy_arg_double(PyObject *o, const char *name, double *out)
{
    if (PyFloat_CheckExact(o)) {
        *out = PyFloat_AS_DOUBLE(o);
        return 0;
    }
    if (PyBool_Check(o) || !(PyFloat_Check(o) || PyIndex_Check(o) ||
                             (Py_TYPE(o)->tp_as_number && Py_TYPE(o)->tp_as_number->nb_float))) {
        PyErr_Format(PyExc_TypeError, "`%s` must be a real number, got %.200s", name,
                     Py_TYPE(o)->tp_name);
        return -1;
    }
    double v = PyFloat_AsDouble(o);
    if (v == -1.0 && PyErr_Occurred()) {
        PyErr_Clear();
        PyErr_Format(PyExc_TypeError, "`%s` must be a real number, got %.200s", name,
                     Py_TYPE(o)->tp_name);
        return -1;
    }
    *out = v;
    return 0;
}

/* A bool (or an int used as one). */
int wkpy_arg_bool(PyObject *o, const char *name, int *out)
{
    if (!PyLong_Check(o)) {
        PyErr_Format(PyExc_TypeError, "`%s` must be a bool, got %.200s", name,
                     Py_TYPE(o)->tp_name);
        return -1;
    }
    int v = PyObject_IsTrue(o);
    if (v < 0) return -1;
    *out = v;
    return 0;
}

/* The address of a C function: a non-negative int (0 = NULL, allowed when ``nullable``). */
int wkpy_arg_address(PyObject *o, const char *name, int nullable, uintptr_t *out)
{
    if (PyBool_Check(o) || !PyLong_Check(o)) {
        PyErr_Format(PyExc_TypeError, "`%s` must be an int address, got %.200s", name,
                     Py_TYPE(o)->tp_name);
        return -1;
    }
    unsigned long long v = PyLong_AsUnsignedLongLong(o);
    if (v == (unsigned long long)-1 && PyErr_Occurred()) {
        PyErr_Clear();
        PyErr_Format(PyExc_ValueError, "`%s` must be a non-negative address below 2**64",
                     name);
        return -1;
    }
    if (v == 0 && !nullable) {
        PyErr_Format(PyExc_ValueError, "`%s` must be a non-zero function address", name);
        return -1;
    }
    if ((unsigned long long)(uintptr_t)v != v) {
        PyErr_Format(PyExc_ValueError, "`%s` does not fit in a pointer", name);
        return -1;
    }
    *out = (uintptr_t)v;
    return 0;
}

static int little_endian(void)
{
    const uint16_t one = 1;
    unsigned char first;
    memcpy(&first, &one, 1);
    return first == 1;
}

/* Does a struct-module format describe one native 8-byte float ('d') or int ('q')? */
static int format_is(const char *format, char kind)
{
    if (format == NULL) return 0;
    if (*format == '@' || *format == '=' || (*format == '<' && little_endian())) format++;
    if (format[1] != '\0') return 0;
    if (kind == 'd') return format[0] == 'd';
    return format[0] == 'q' || (format[0] == 'l' && sizeof(long) == 8);
}

/* A C-contiguous buffer of float64 (kind 'd') or int64 (kind 'q') with ``ndim``
 * dimensions.  On success the caller releases ``view``. */
int wkpy_arg_buffer(PyObject *o, const char *name, char kind, int ndim, Py_buffer *view)
{
    const char *what = kind == 'd' ? "float64" : "int64";
    if (PyObject_GetBuffer(o, view, PyBUF_C_CONTIGUOUS | PyBUF_FORMAT) < 0) {
        PyErr_Clear();
        PyErr_Format(PyExc_TypeError, "`%s` must be a C-contiguous %s array, got %.200s",
                     name, what, Py_TYPE(o)->tp_name);
        return -1;
    }
    if (view->itemsize != 8 || !format_is(view->format, kind)) {
        PyErr_Format(PyExc_TypeError, "`%s` must be a C-contiguous %s array, got format '%s'",
                     name, what, view->format ? view->format : "B");
        PyBuffer_Release(view);
        return -1;
    }
    if (view->ndim != ndim) {
        PyErr_Format(PyExc_ValueError, "`%s` must be %d-D, got %d-D", name, ndim, view->ndim);
        PyBuffer_Release(view);
        return -1;
    }
    return 0;
}

int wkpy_hold_buffer(wkpy_held *h, PyObject *o, const char *name, char kind, int ndim,
                     Py_buffer *view)
{
    if (h->n >= WKPY_MAX_HELD) {
        PyErr_SetString(PyExc_SystemError, "wkpy_hold_buffer: too many buffers held");
        return -1;
    }
    if (wkpy_arg_buffer(o, name, kind, ndim, view)) return -1;
    h->views[h->n++] = view;
    return 0;
}

void wkpy_release_held(wkpy_held *h)
{
    for (int i = 0; i < h->n; i++) PyBuffer_Release(h->views[i]);
    h->n = 0;
}

int wkpy_run_failed(int rc, int64_t res_phase, int64_t n_phases)
{
    if (rc == WK_ERR_NOMEM) {
        PyErr_NoMemory();
        return 1;
    }
    if (rc == WK_ERR_BAD_PHASE) {
        PyErr_Format(PyExc_ValueError,
                     "`reset` returned next phase %lld, outside [0, n_phases = %lld)",
                     (long long)res_phase, (long long)n_phases);
        return 1;
    }
    return 0;
}

/* Are all n values finite? */
int wkpy_all_finite(const double *v, Py_ssize_t n)
{
    for (Py_ssize_t i = 0; i < n; i++)
        if (!isfinite(v[i])) return 0;
    return 1;
}

/* A new bytearray holding ``count`` items of ``item`` bytes from ``data`` (empty when
 * count <= 0). */
PyObject *wkpy_bytes_of(const void *data, int64_t count, size_t item)
{
    if (count <= 0) return PyByteArray_FromStringAndSize(NULL, 0);
    return PyByteArray_FromStringAndSize((const char *)data, (Py_ssize_t)((size_t)count * item));
}

/* ------------------------------------------------------------------------------------------
 * Keyword-only arguments
 * ------------------------------------------------------------------------------------------ */

static int intern_names(wkpy_kwlist *kw)
{
    for (int j = 0; j < kw->n; j++) {
        if (kw->interned[j] != NULL) continue;
        kw->interned[j] = PyUnicode_InternFromString(kw->names[j]);
        if (kw->interned[j] == NULL) return -1;
    }
    return 0;
}

/* The slot of keyword ``name`` (tried first at ``hint``, where the keywords come in the
 * list's order), or -1 with a TypeError naming it. */
static int find_name(const wkpy_kwlist *kw, PyObject *name, int hint)
{
    if (hint < kw->n && kw->interned[hint] == name) return hint;
    for (int j = 0; j < kw->n; j++)
        if (kw->interned[j] == name) return j;
    if (PyUnicode_Check(name))
        for (int j = 0; j < kw->n; j++)
            if (PyUnicode_Compare(kw->interned[j], name) == 0) return j;
    PyErr_Format(PyExc_TypeError, "%s() got an unexpected keyword argument %R", kw->fname, name);
    return -1;
}

static int bind_one(const wkpy_kwlist *kw, PyObject *name, PyObject *value, int *hint,
                    PyObject **slots)
{
    const int j = find_name(kw, name, *hint);
    if (j < 0) return -1;
    if (slots[j] != NULL) {
        PyErr_Format(PyExc_TypeError, "%s() got multiple values for argument `%s`", kw->fname,
                     kw->names[j]);
        return -1;
    }
    slots[j] = value;
    *hint = j + 1;
    return 0;
}

static int bind_start(wkpy_kwlist *kw, Py_ssize_t nargs, PyObject **slots)
{
    /* the last name too: lists may share their first names (solve, terrain_solve) */
    if (kw->interned[kw->n - 1] == NULL && intern_names(kw)) return -1;
    if (nargs != 0) {
        PyErr_Format(PyExc_TypeError, "%s() takes keyword arguments only, got %zd positional",
                     kw->fname, nargs);
        return -1;
    }
    for (int j = 0; j < kw->n; j++) slots[j] = NULL;
    return 0;
}

static int bind_end(const wkpy_kwlist *kw, PyObject **slots)
{
    for (int j = 0; j < kw->n_required; j++)
        if (slots[j] == NULL) {
            PyErr_Format(PyExc_TypeError, "%s() missing required keyword argument `%s`",
                         kw->fname, kw->names[j]);
            return -1;
        }
    return 0;
}

int wkpy_bind_keywords(wkpy_kwlist *kw, PyObject *const *args, Py_ssize_t nargs,
                       PyObject *kwnames, PyObject **slots)
{
    if (bind_start(kw, nargs, slots)) return -1;
    return wkpy_bind_more(kw, args, nargs, kwnames, slots);
}

int wkpy_bind_more(wkpy_kwlist *kw, PyObject *const *args, Py_ssize_t nargs, PyObject *kwnames,
                   PyObject **slots)
{
    if (kw->interned[kw->n - 1] == NULL && intern_names(kw)) return -1;
    if (nargs != 0) {
        PyErr_Format(PyExc_TypeError, "%s() takes keyword arguments only, got %zd positional",
                     kw->fname, nargs);
        return -1;
    }
    const Py_ssize_t n_kw = kwnames == NULL ? 0 : PyTuple_GET_SIZE(kwnames);
    int hint = 0;
    for (Py_ssize_t i = 0; i < n_kw; i++)
        if (bind_one(kw, PyTuple_GET_ITEM(kwnames, i), args[nargs + i], &hint, slots))
            return -1;
    return bind_end(kw, slots);
}

int wkpy_bind_dict(wkpy_kwlist *kw, PyObject *args, PyObject *kwargs, PyObject **slots)
{
    if (bind_start(kw, PyTuple_GET_SIZE(args), slots)) return -1;
    Py_ssize_t pos = 0;
    PyObject *name, *value;
    int hint = 0;
    while (kwargs != NULL && PyDict_Next(kwargs, &pos, &name, &value))
        if (bind_one(kw, name, value, &hint, slots)) return -1;
    return bind_end(kw, slots);
}

PyObject *wkpy_kwlist_names(const wkpy_kwlist *kw)
{
    PyObject *t = PyTuple_New(kw->n);
    for (int j = 0; t != NULL && j < kw->n; j++) {
        PyObject *s = PyUnicode_FromString(kw->names[j]);
        if (s == NULL) Py_CLEAR(t);
        else PyTuple_SET_ITEM(t, j, s);
    }
    return t;
}

/* ------------------------------------------------------------------------------------------
 * The system and the solver settings
 * ------------------------------------------------------------------------------------------ */

int wkpy_arg_system(PyObject *const *sys, wk_functions *fn, wk_problem *pb)
{
    uintptr_t rhs, guards, reset, jac, ctx;
    if (wkpy_arg_address(sys[WKPY_SYS_rhs], "rhs", 0, &rhs) ||
        wkpy_arg_address(sys[WKPY_SYS_guards], "guards", 1, &guards) ||
        wkpy_arg_address(sys[WKPY_SYS_reset], "reset", 1, &reset) ||
        wkpy_arg_address(sys[WKPY_SYS_jac], "jac", 1, &jac) ||
        wkpy_arg_address(sys[WKPY_SYS_ctx], "ctx", 1, &ctx) ||
        wkpy_arg_int(sys[WKPY_SYS_n_x], "n_x", &pb->n_x) ||
        wkpy_arg_int(sys[WKPY_SYS_n_guards], "n_guards", &pb->n_guards) ||
        wkpy_arg_int(sys[WKPY_SYS_n_impulse], "n_impulse", &pb->n_impulse))
        return -1;
    fn->rhs = (wk_rhs_fn)rhs;
    fn->guards = (wk_guards_fn)guards;
    fn->reset = (wk_reset_fn)reset;
    fn->jac = (wk_jac_fn)jac;
    fn->ctx = (void *)ctx;
    /* a built-in model's fused rhs and Jacobian (NULL for any other system) */
    fn->rhs_jac = wk_model_rhs_jac(fn->rhs, fn->jac);
    fn->on_stride = NULL; /* terrain runs set it (terrain.c) */
    return 0;
}

int wkpy_arg_solver(PyObject *const *sol, int64_t *method, int64_t *max_steps, wk_problem *pb)
{
    if (wkpy_arg_int(sol[WKPY_SOL_method], "method", method) ||
        wkpy_arg_bool(sol[WKPY_SOL_adaptive], "adaptive", &pb->adaptive) ||
        wkpy_arg_double(sol[WKPY_SOL_rtol], "rtol", &pb->rtol) ||
        wkpy_arg_double(sol[WKPY_SOL_atol], "atol", &pb->atol) ||
        wkpy_arg_double(sol[WKPY_SOL_first_step], "first_step", &pb->first_step) ||
        wkpy_arg_double(sol[WKPY_SOL_max_step], "max_step", &pb->max_step) ||
        wkpy_arg_int(sol[WKPY_SOL_max_steps], "max_steps", max_steps) ||
        wkpy_arg_int(sol[WKPY_SOL_n_interior], "n_interior", &pb->n_interior) ||
        wkpy_arg_bool(sol[WKPY_SOL_screen_interior], "screen_interior", &pb->screen_interior))
        return -1;
    if (pb->n_interior < 0 || pb->n_interior > MAX_COUNT) {
        PyErr_Format(PyExc_ValueError, "`n_interior` must be in [0, 2**24], got %lld",
                     (long long)pb->n_interior);
        return -1;
    }
    return 0;
}

int wkpy_arg_buffer_pair(PyObject *const *args, const char *name0, int ndim0, const char *name1,
                         int ndim1, Py_buffer *view0, Py_buffer *view1)
{
    if (wkpy_arg_buffer(args[0], name0, 'd', ndim0, view0)) return -1;
    if (wkpy_arg_buffer(args[1], name1, 'd', ndim1, view1)) {
        PyBuffer_Release(view0);
        return -1;
    }
    return 0;
}

/* ------------------------------------------------------------------------------------------
 * The compiled models' sizes
 * ------------------------------------------------------------------------------------------ */

/* Every compiled model's sizes, by the name before the first '/' of its registry entries
 * (its variants share them): SIZES, one row a model, printed from its Python declaration
 * (walker/symbolic/codegen_registry.py); tests/test_declared_once.py checks it is current. */
#include "_hybridsizes.h"

const wkpy_model_sizes *wkpy_sizes_named(const char *entry_name)
{
    const size_t len = strcspn(entry_name, "/");
    for (size_t i = 0; i < sizeof SIZES / sizeof SIZES[0]; i++)
        if (strlen(SIZES[i].name) == len && strncmp(SIZES[i].name, entry_name, len) == 0)
            return &SIZES[i];
    return NULL;
}

/* The registry entry after index *from whose function of ``role`` is ``address`` (role
 * WKPY_FN_NONE: any of its functions, the role found in *found); its sizes, or NULL when no
 * further entry has it.  *from is advanced past the entry returned. */
static const wkpy_model_sizes *next_owner(uintptr_t address, int role, int64_t *from, int *found)
{
    int64_t count = 0;
    const wk_model_entry *const *table = wk_model_table(&count);
    for (; address != 0 && *from < count; (*from)++) {
        const wk_model_entry *e = table[*from];
        const uintptr_t fns[WKPY_FN_NONE] = {
            (uintptr_t)e->fn.rhs,       (uintptr_t)e->fn.guards,     (uintptr_t)e->fn.reset,
            (uintptr_t)e->fn.jac,       (uintptr_t)e->energy,        (uintptr_t)e->points,
            (uintptr_t)e->start_phase,  (uintptr_t)e->lift,          (uintptr_t)e->lift_jacobian,
            (uintptr_t)e->torques,
        };
        for (int k = 0; k < WKPY_FN_NONE; k++)
            if (fns[k] == address && (role == WKPY_FN_NONE || k == role)) {
                *found = k;
                (*from)++;
                return wkpy_sizes_named(e->name);
            }
    }
    return NULL;
}

const wkpy_model_sizes *wkpy_sizes_of(uintptr_t address, int *role)
{
    int64_t from = 0;
    *role = WKPY_FN_NONE;
    return next_owner(address, WKPY_FN_NONE, &from, role);
}

const wkpy_model_sizes *wkpy_sizes_for(uintptr_t address, int role, int64_t n_p)
{
    int64_t from = 0;
    int found;
    const wkpy_model_sizes *s, *first = NULL;
    while ((s = next_owner(address, role, &from, &found)) != NULL) {
        if (first == NULL) first = s;
        if (s->n_p == n_p) return s;
    }
    return first;
}

static const char *const ROLE_NAMES[WKPY_FN_NONE] = {
    "rhs", "guards", "reset", "jac", "energy", "points", "start_phase", "lift", "lift_jacobian",
    "torques",
};

int wkpy_state_fn_lengths(const wkpy_model_sizes *s, int role, int64_t *n_in, int64_t *n_out)
{
    switch (role) {
    case WKPY_FN_ENERGY: *n_in = s->n_x; *n_out = 2; return 0;
    case WKPY_FN_POINTS: *n_in = s->n_x; *n_out = 2 * s->n_points; return 0;
    case WKPY_FN_START: *n_in = s->n_x; *n_out = 1; return 0;
    case WKPY_FN_LIFT: *n_in = s->n_z; *n_out = s->n_x; return 0;
    case WKPY_FN_LIFT_JAC: *n_in = s->n_z; *n_out = s->n_x * s->n_z; return 0;
    case WKPY_FN_TORQUES: *n_in = s->n_x; *n_out = s->n_inputs; return 0;
    default: return -1;
    }
}

/* One function of a system: when ``address`` is a compiled model's, it must be its
 * function for the slot ``role`` and the sizes it reads and writes must be the model's. */
static int check_fn(uintptr_t address, int role, const wk_problem *pb, int64_t n_p)
{
    int found;
    const wkpy_model_sizes *s = wkpy_sizes_of(address, &found);
    const char *name = ROLE_NAMES[role];
    if (s == NULL) return 0; /* a user's function: its sizes are the caller's to keep */
    s = wkpy_sizes_for(address, role, n_p); /* models may share one (compass_coulomb) */
    if (s == NULL) {
        s = wkpy_sizes_of(address, &found);
        PyErr_Format(PyExc_ValueError, "`%s` is the %s function of the compiled model '%s', "
                     "not its %s", name, ROLE_NAMES[found], s->name, name);
        return -1;
    }
    const char *what = NULL;
    int64_t want = 0, got = 0;
    if (pb->n_x != s->n_x) what = "n_x", want = s->n_x, got = pb->n_x;
    else if (n_p != s->n_p) what = "p", want = s->n_p, got = n_p;
    else if (pb->n_phases > s->n_phases) what = "directions` rows (n_phases", want = s->n_phases,
                                         got = pb->n_phases;
    else if (role == WKPY_FN_GUARDS && pb->n_guards != s->n_guards)
        what = "n_guards", want = s->n_guards, got = pb->n_guards;
    else if (role == WKPY_FN_RESET && pb->n_impulse != s->n_impulse)
        what = "n_impulse", want = s->n_impulse, got = pb->n_impulse;
    if (what == NULL) return 0;
    if (what[0] == 'd')
        PyErr_Format(PyExc_ValueError, "`%s) must be at most %lld for the compiled model '%s' "
                     "(its `%s`), got %lld", what, (long long)want, s->name, name, (long long)got);
    else if (what[0] == 'p')
        PyErr_Format(PyExc_ValueError, "`p` must have length n_p = %lld for the compiled model "
                     "'%s' (its `%s`), got %lld", (long long)want, s->name, name,
                     (long long)got);
    else
        PyErr_Format(PyExc_ValueError, "`%s` must be %lld for the compiled model '%s' (its "
                     "`%s`), got %lld", what, (long long)want, s->name, name, (long long)got);
    return -1;
}

int wkpy_check_system(const wk_functions *fn, const wk_problem *pb, int64_t n_p)
{
    if (check_fn((uintptr_t)fn->rhs, WKPY_FN_RHS, pb, n_p) ||
        check_fn((uintptr_t)fn->guards, WKPY_FN_GUARDS, pb, n_p) ||
        check_fn((uintptr_t)fn->reset, WKPY_FN_RESET, pb, n_p) ||
        check_fn((uintptr_t)fn->jac, WKPY_FN_JAC, pb, n_p))
        return -1;
    return 0;
}

int wkpy_check_state_fn(uintptr_t address, const char *name, int role, int64_t n_x,
                        int64_t n_p, int64_t n_z)
{
    int found;
    if (address == 0) return 0;
    const wkpy_model_sizes *s = wkpy_sizes_of(address, &found);
    if (s == NULL) return 0; /* a user's function: its sizes are the caller's to keep */
    s = wkpy_sizes_for(address, role, n_p); /* models may share one (compass_coulomb) */
    if (s == NULL) {
        s = wkpy_sizes_of(address, &found);
        PyErr_Format(PyExc_ValueError, "`%s` is the %s function of the compiled model '%s', "
                     "not its %s", name, ROLE_NAMES[found], s->name, ROLE_NAMES[role]);
        return -1;
    }
    /* A model's state functions may serve a variant with more parameters (the Coulomb
     * walkers take their base walker's energy and points: the base's parameters come first),
     * so only reading past the caller's `p` is refused. */
    if (s->n_x != n_x || s->n_p > n_p ||
        ((role == WKPY_FN_LIFT || role == WKPY_FN_LIFT_JAC) && s->n_z != n_z)) {
        PyErr_Format(PyExc_ValueError, "`%s` belongs to the compiled model '%s' (n_x = %lld, "
                     "n_p = %lld), which does not fit the system's n_x = %lld, n_p = %lld",
                     name, s->name, (long long)s->n_x, (long long)s->n_p, (long long)n_x,
                     (long long)n_p);
        return -1;
    }
    return 0;
}
