/* walker._hybrid's stride maps: the settings of a walker's section (batch.h) read once from
 * Python, and walker._hybrid.PreparedMap, one stride-map call in one compiled call.
 *
 * wkpy_section_parse reads the keywords that basin_points and PreparedMap share
 * (WKPY_SECTION_FIELDS: the system, the solver settings, the affine lift, the projection and
 * the start checks) into a wkpy_section that owns copies of the arrays.  PreparedMap keeps one, filled when
 * walker.simulation.stride.StrideMap prepares its run, so a call parses only z, n_strides and
 * jacobian.  Declared in _hybridbinding.h.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "_hybridbinding.h"
#include "batch.h"
#include "hybrid.h"

/* ------------------------------------------------------------------------------------------
 * The section's settings
 * ------------------------------------------------------------------------------------------ */

void wkpy_section_free(wkpy_section *s)
{
    free(s->block);
    s->block = NULL;
}

/* Copies the n items of 8 bytes of a buffer to *cursor and advances it. */
static void *take(char **cursor, const Py_buffer *v, Py_ssize_t n)
{
    void *at = *cursor;
    if (n > 0) memcpy(at, v->buf, (size_t)n * 8);
    *cursor += (size_t)n * 8;
    return at;
}

static const char *const section_names[] = {WKPY_SECTION_FIELDS(WKPY_SLOT_NAME, WKPY_SEC_)};
static PyObject *section_interned[WKPY_SECTION_NARGS];
wkpy_kwlist wkpy_section_kw = {"PreparedMap", WKPY_SECTION_NARGS, WKPY_SECTION_NARGS,
                               section_names, section_interned};

int wkpy_section_parse(PyObject *const *a, wkpy_section *s)
{
    memset(s, 0, sizeof *s);
    wk_functions *fn = &s->fn;
    wk_problem *pb = &s->pb;
    wk_section *sec = &s->sec;
    uintptr_t a_energy, a_start, a_lift, a_lift_jac;
    int64_t method;
    Py_buffer v_dir, v_p, v_a, v_b, v_proj;
    wkpy_held held = {0};
    int rc = -1;

    if (wkpy_arg_system(a, fn, pb) ||
        wkpy_arg_solver(a + WKPY_SEC_method, &method, &sec->max_steps, pb) ||
        wkpy_arg_double(a[WKPY_SEC_offset], "offset", &sec->offset) ||
        wkpy_arg_double(a[WKPY_SEC_fall_angle], "fall_angle", &sec->fall_angle) ||
        wkpy_arg_int(a[WKPY_SEC_n_q], "n_q", &sec->n_q) ||
        wkpy_arg_double(a[WKPY_SEC_wound], "wound", &sec->wound) ||
        wkpy_arg_address(a[WKPY_SEC_energy], "energy", 1, &a_energy) ||
        wkpy_arg_double(a[WKPY_SEC_kinetic_limit], "kinetic_limit", &sec->kinetic_limit) ||
        wkpy_arg_address(a[WKPY_SEC_start_phase], "start_phase", 1, &a_start) ||
        wkpy_arg_double(a[WKPY_SEC_t_max], "t_max", &sec->t_max) ||
        wkpy_arg_address(a[WKPY_SEC_lift], "lift", 1, &a_lift) ||
        wkpy_arg_address(a[WKPY_SEC_lift_jacobian], "lift_jacobian", 1, &a_lift_jac))
        return -1;

    if (pb->n_x < 1 || pb->n_x > MAX_N_X)
        WKPY_FAIL(PyExc_ValueError, "`n_x` must be in [1, %d], got %lld", MAX_N_X,
                  (long long)pb->n_x);
    if (pb->n_guards < 1 || pb->n_guards > MAX_COUNT || fn->guards == NULL || fn->reset == NULL)
        WKPY_FAIL(PyExc_ValueError, "a walker needs guards and a reset (`n_guards` >= 1)");
    if (pb->n_impulse < 1 || pb->n_impulse > MAX_COUNT)
        WKPY_FAIL(PyExc_ValueError, "`n_impulse` must be in [1, 2**24]");
    if (method != WK_METHOD_DOP853 && method != WK_METHOD_DP5 && method != WK_METHOD_RK4 &&
        method != WK_METHOD_EULER)
        WKPY_FAIL(PyExc_ValueError, "`method` must be a code in [0, 3], got %lld",
                  (long long)method);
    pb->method = (int)method;
    if (pb->adaptive && pb->method != WK_METHOD_DOP853 && pb->method != WK_METHOD_DP5)
        WKPY_FAIL(PyExc_ValueError, "`adaptive` needs method DOP853 or RK45");
    if (!(pb->rtol > 0.0 && isfinite(pb->rtol)) || !(pb->atol > 0.0 && isfinite(pb->atol)))
        WKPY_FAIL(PyExc_ValueError, "`rtol` and `atol` must be positive and finite");
    if (!(pb->first_step >= 0.0 && isfinite(pb->first_step)) ||
        (!pb->adaptive && !(pb->first_step > 0.0)))
        WKPY_FAIL(PyExc_ValueError, "`first_step` must be finite and positive (0: automatic)");
    if (!(pb->max_step > 0.0)) WKPY_FAIL(PyExc_ValueError, "`max_step` must be positive");
    if (sec->max_steps < 1) WKPY_FAIL(PyExc_ValueError, "`max_steps` must be >= 1");
    if (sec->n_q < 0 || sec->n_q > pb->n_x)
        WKPY_FAIL(PyExc_ValueError, "`n_q` must be in [0, n_x]");
    if (!(sec->t_max > 0.0 && isfinite(sec->t_max)))
        WKPY_FAIL(PyExc_ValueError, "`t_max` must be positive and finite");
    if ((a_lift == 0) != (a_lift_jac == 0))
        WKPY_FAIL(PyExc_ValueError, "`lift` and `lift_jacobian` must be given together");

    if (wkpy_hold_buffer(&held, a[WKPY_SEC_directions], "directions", 'q', 2, &v_dir)) goto out;
    if (v_dir.shape[1] != pb->n_guards || v_dir.shape[0] < 1)
        WKPY_FAIL(PyExc_ValueError, "`directions` must have n_guards columns and at least one row");
    pb->n_phases = v_dir.shape[0];
    for (int64_t i = 0; i < pb->n_phases * pb->n_guards; i++) {
        const int64_t d = ((const int64_t *)v_dir.buf)[i];
        if (d < -1 || d > 1) WKPY_FAIL(PyExc_ValueError, "`directions` values must be -1, 0 or +1");
    }
    if (wkpy_hold_buffer(&held, a[WKPY_SEC_p], "p", 'd', 1, &v_p)) goto out;
    if (!wkpy_all_finite((const double *)v_p.buf, v_p.shape[0]))
        WKPY_FAIL(PyExc_ValueError, "All parameters `p` must be finite.");
    if (wkpy_hold_buffer(&held, a[WKPY_SEC_lift_a], "lift_a", 'd', 2, &v_a)) goto out;
    sec->n_z = v_a.shape[1];
    if (v_a.shape[0] != pb->n_x || sec->n_z < 1 || sec->n_z > pb->n_x)
        WKPY_FAIL(PyExc_ValueError, "`lift_a` must have shape (n_x, n_z) with 1 <= n_z <= n_x");
    if (wkpy_hold_buffer(&held, a[WKPY_SEC_lift_b], "lift_b", 'd', 1, &v_b)) goto out;
    if (v_b.shape[0] != pb->n_x) WKPY_FAIL(PyExc_ValueError, "`lift_b` must have length n_x");
    if (!wkpy_all_finite((const double *)v_a.buf, v_a.shape[0] * v_a.shape[1]) ||
        !wkpy_all_finite((const double *)v_b.buf, v_b.shape[0]))
        WKPY_FAIL(PyExc_ValueError, "`lift_a` and `lift_b` must be finite");
    /* the compiled functions against the sizes they read and write */
    if (wkpy_check_system(fn, pb, v_p.shape[0]) ||
        wkpy_check_state_fn(a_energy, "energy", WKPY_FN_ENERGY, pb->n_x, v_p.shape[0], 0) ||
        wkpy_check_state_fn(a_start, "start_phase", WKPY_FN_START, pb->n_x, v_p.shape[0], 0) ||
        wkpy_check_state_fn(a_lift, "lift", WKPY_FN_LIFT, pb->n_x, v_p.shape[0], sec->n_z) ||
        wkpy_check_state_fn(a_lift_jac, "lift_jacobian", WKPY_FN_LIFT_JAC, pb->n_x,
                            v_p.shape[0], sec->n_z))
        goto out;
    if (wkpy_hold_buffer(&held, a[WKPY_SEC_proj], "proj", 'q', 1, &v_proj)) goto out;
    if (v_proj.shape[0] != sec->n_z) WKPY_FAIL(PyExc_ValueError, "`proj` must have length n_z");
    for (int64_t i = 0; i < sec->n_z; i++) {
        const int64_t k = ((const int64_t *)v_proj.buf)[i];
        if (k < 0 || k >= pb->n_x)
            WKPY_FAIL(PyExc_ValueError, "`proj` indices must be in [0, n_x)");
    }

    /* One block owns the copies: directions, p, lift_a, lift_b, proj (8-byte items). */
    const Py_ssize_t n_dir = pb->n_phases * pb->n_guards, n_p = v_p.shape[0];
    const Py_ssize_t n_a = pb->n_x * sec->n_z;
    s->block = malloc((size_t)(n_dir + n_p + n_a + pb->n_x + sec->n_z + 1) * 8);
    if (s->block == NULL) {
        PyErr_NoMemory();
        goto out;
    }
    char *cursor = s->block;
    pb->directions = take(&cursor, &v_dir, n_dir);
    pb->p = take(&cursor, &v_p, n_p);
    s->n_p = n_p;
    sec->lift_a = take(&cursor, &v_a, n_a);
    sec->lift_b = take(&cursor, &v_b, pb->n_x);
    sec->proj = take(&cursor, &v_proj, sec->n_z);
    sec->energy = (wk_state_fn)a_energy;
    sec->start_phase = (wk_state_fn)a_start;
    sec->lift = (wk_state_fn)a_lift;
    sec->lift_jacobian = (wk_state_fn)a_lift_jac;
    sec->ctx = fn->ctx;
    rc = 0;

out:
    wkpy_release_held(&held);
    return rc;
}

/* ------------------------------------------------------------------------------------------
 * PreparedMap
 * ------------------------------------------------------------------------------------------ */

typedef struct {
    PyObject_HEAD
    wkpy_section s;
    int64_t max_period; /* n_strides above it: per-stride budget times it would overflow */
} PreparedMap;

/* Up to this many state components the per-call arrays live on the stack. */
#define SMALL_N 64

static PyObject *prepared_map_new(PyTypeObject *type, PyObject *args, PyObject *kwargs)
{
    PyObject *a[WKPY_SECTION_NARGS];
    if (wkpy_bind_dict(&wkpy_section_kw, args, kwargs, a)) return NULL;
    PreparedMap *self = (PreparedMap *)type->tp_alloc(type, 0);
    if (self == NULL) return NULL;
    if (wkpy_section_parse(a, &self->s)) {
        Py_DECREF(self);
        return NULL;
    }
    self->max_period = INT64_MAX / self->s.sec.max_steps;
    return (PyObject *)self;
}

static void prepared_map_dealloc(PreparedMap *self)
{
    wkpy_section_free(&self->s);
    Py_TYPE(self)->tp_free((PyObject *)self);
}

/* 1 when a method `name` got its `want` positional arguments, else 0 with a TypeError. */
static int takes(const char *name, Py_ssize_t want, Py_ssize_t nargs)
{
    if (nargs == want) return 1;
    PyErr_Format(PyExc_TypeError, "%s() takes %zd arguments, got %zd", name, want, nargs);
    return 0;
}

/* z as n finite float64 values copied to out; 0 when z is anything else (no exception). */
static int read_point(PyObject *o, int64_t n, double *out)
{
    Py_buffer v;
    if (PyObject_GetBuffer(o, &v, PyBUF_C_CONTIGUOUS | PyBUF_FORMAT) < 0) {
        PyErr_Clear();
        return 0;
    }
    const char *f = v.format;
    int ok = v.ndim == 1 && v.itemsize == 8 && v.shape[0] == n && f != NULL &&
             (strcmp(f, "d") == 0 || strcmp(f, "<d") == 0 || strcmp(f, "=d") == 0 ||
              strcmp(f, "@d") == 0);
    if (ok && f[0] == '<') {
        const uint16_t one = 1;
        ok = *(const unsigned char *)&one == 1;
    }
    if (ok) {
        memcpy(out, v.buf, (size_t)n * sizeof(double));
        ok = wkpy_all_finite(out, (Py_ssize_t)n);
    }
    PyBuffer_Release(&v);
    return ok;
}

/* n NaNs as a bytearray of float64: the section point of a stride that failed. */
static PyObject *nan_point(int64_t n)
{
    PyObject *out = PyByteArray_FromStringAndSize(NULL, (Py_ssize_t)(n * 8));
    if (out == NULL) return NULL;
    double *v = (double *)PyByteArray_AS_STRING(out);
    for (int64_t i = 0; i < n; i++) v[i] = NAN;
    return out;
}

/* map()'s answer (0, t, z_new, x, jac) after a run res that completed with status 0: the
 * projection selects components, z_new and (want_jac) the rows of the Jacobian; ``rows``
 * holds n_z values of scratch. */
static PyObject *stride_answer(const wkpy_section *s, const wk_result *res, int want_jac,
                               double *rows)
{
    const int64_t n_x = s->pb.n_x, n_z = s->sec.n_z;
    for (int64_t i = 0; i < n_z; i++) rows[i] = res->x[s->sec.proj[i]];
    PyObject *z_new = wkpy_bytes_of(rows, n_z, sizeof(double));
    PyObject *jac = Py_NewRef(Py_None);
    if (want_jac && z_new != NULL) {
        Py_DECREF(jac);
        jac = PyByteArray_FromStringAndSize(NULL, (Py_ssize_t)(n_z * n_z * 8));
        if (jac != NULL) {
            double *out = (double *)PyByteArray_AS_STRING(jac);
            for (int64_t i = 0; i < n_z; i++)
                memcpy(out + i * n_z, res->jac + s->sec.proj[i] * n_z,
                       (size_t)n_z * sizeof(double));
        }
    }
    if (z_new == NULL || jac == NULL) {
        Py_XDECREF(z_new);
        Py_XDECREF(jac);
        return NULL;
    }
    return Py_BuildValue("(LdNNN)", 0LL, res->t, z_new,
                         wkpy_bytes_of(res->x, n_x, sizeof(double)), jac);
}

PyDoc_STRVAR(prepared_map_map_doc,
             "map(z, n_strides, jacobian) -> (status, t, z_new, x, jac) or None\n\n"
             "One call of the stride map from the section point z: the lift, the start\n"
             "checks, n_strides strides without the GIL and the projection (batch.h), with\n"
             "the operations of walker.simulation.stride.StrideMap.__call__.  status: a walker.status\n"
             "value; t: the step time [s] (0.0 for a start that is not integrated); x: the\n"
             "final state (the lifted start when not integrated); z_new (n_z,), NaN unless\n"
             "status is 0; jac (n_z, n_z) row-major with jacobian when status is 0, else\n"
             "None.  The arrays are bytearrays of float64.  None when the call is not one\n"
             "it answers (z not a C-contiguous finite float64 vector of length n_z,\n"
             "n_strides not an int >= 1, jacobian not a bool,\n"
             "jacobian without the model's Jacobian, a start phase out of range, a lifted\n"
             "state that is not finite): the caller then takes its checked path, which says\n"
             "why.");

static PyObject *prepared_map_map(PreparedMap *self, PyObject *const *args, Py_ssize_t nargs)
{
    if (!takes("map", 3, nargs)) return NULL;
    const wkpy_section *s = &self->s;
    const int64_t n_x = s->pb.n_x, n_z = s->sec.n_z;
    PyObject *jacobian = args[2];
    if (!PyLong_CheckExact(args[1]) || (jacobian != Py_True && jacobian != Py_False))
        Py_RETURN_NONE;
    int overflow = 0;
    const long long period = PyLong_AsLongLongAndOverflow(args[1], &overflow);
    if (overflow || period < 1 || period > self->max_period) {
        PyErr_Clear();
        Py_RETURN_NONE;
    }
    const int want_jac = jacobian == Py_True;
    if (want_jac && s->fn.jac == NULL) Py_RETURN_NONE;

    /* z, x0 and the seed of a lift that is not affine */
    const int64_t need = 2 * n_x + (want_jac && s->sec.lift != NULL ? n_x * n_z : 0);
    double small[4 * SMALL_N];
    double *z = small;
    if (need > 4 * SMALL_N) {
        z = PyMem_Malloc((size_t)need * sizeof(double));
        if (z == NULL) return PyErr_NoMemory();
    }
    double *x0 = z + n_x;
    PyObject *result = NULL;
    if (!read_point(args[0], n_z, z)) {
        result = Py_NewRef(Py_None);
        goto out;
    }
    int64_t phase0 = 0;
    const int64_t start = wk_section_start(&s->pb, &s->sec, z, x0, &phase0);
    if (start != 0) {
        result = Py_BuildValue("(LdNNO)", (long long)start, 0.0, nan_point(n_z),
                               wkpy_bytes_of(x0, n_x, sizeof(double)), Py_None);
        goto out;
    }
    if (phase0 >= s->pb.n_phases || !wkpy_all_finite(x0, (Py_ssize_t)n_x)) {
        result = Py_NewRef(Py_None);
        goto out;
    }
    const double *seed = NULL;
    if (want_jac) {
        seed = wk_section_seed(&s->sec, n_x, s->pb.p, z, x0 + n_x);
        if (!wkpy_all_finite(seed, (Py_ssize_t)(n_x * n_z))) { /* the checked path's case */
            result = Py_NewRef(Py_None);
            goto out;
        }
    }
    wk_result res;
    int rc;
    wkpy_signals_begin();
    Py_BEGIN_ALLOW_THREADS
    rc = wk_section_run(&s->fn, &s->pb, &s->sec, (int64_t)period, seed, x0, phase0, &res);
    Py_END_ALLOW_THREADS
    if (wkpy_signals_end() && wkpy_interrupted(0))
        result = NULL;
    else if (wkpy_run_failed(rc, res.phase, s->pb.n_phases))
        result = NULL;
    else if (res.status != 0)
        result = Py_BuildValue("(LdNNO)", (long long)res.status, res.t, nan_point(n_z),
                               wkpy_bytes_of(res.x, n_x, sizeof(double)), Py_None);
    else
        result = stride_answer(s, &res, want_jac, z); /* z reused: n_z <= n_x values */
    wk_result_free(&res);
out:
    if (z != small) PyMem_Free(z);
    return result;
}

/* ------------------------------------------------------------------------------------------
 * PreparedMap.search (_hybridsearch.c)
 * ------------------------------------------------------------------------------------------ */

PyDoc_STRVAR(prepared_map_search_doc,
             "search(*, z0, scale, has_stance, stance_offset, fall_angle, n_q, wound_limit,\n"
             "    energy, kinetic_max, <settings>) -> tuple or None\n\n"
             "walker.analysis.newton's gait search on this map in one compiled call (newton.h),\n"
             "without the GIL: the walking region (walker.simulation.region.WalkingRegion.compiled) and\n"
             "the settings (walker.analysis.newton._settings) by name.  Returns walker._hybrid.search's\n"
             "tuple with known None or (t, z, x, jac); None when the search declines (a case\n"
             "newton.h leaves to the search through callbacks).");

static PyObject *prepared_map_search(PreparedMap *self, PyObject *args, PyObject *kwargs)
{
    return wkpy_prepared_search(&self->s, self->max_period, args, kwargs);
}

static PyMethodDef prepared_map_methods[] = {
    {"map", (PyCFunction)(void (*)(void))prepared_map_map, METH_FASTCALL,
     prepared_map_map_doc},
    {"search", (PyCFunction)(void (*)(void))prepared_map_search, METH_VARARGS | METH_KEYWORDS,
     prepared_map_search_doc},
    {NULL, NULL, 0, NULL},
};

PyDoc_STRVAR(prepared_map_doc,
             "PreparedMap(*, rhs, guards, reset, jac, ctx, directions, n_x, n_guards,\n"
             "    n_impulse, p, method, adaptive, rtol, atol, first_step, max_step, max_steps,\n"
             "    n_interior, screen_interior, lift_a, lift_b, proj, offset, fall_angle, n_q,\n"
             "    wound, energy, kinetic_limit, start_phase, t_max, lift, lift_jacobian)\n\n"
             "A walker's stride map with its settings parsed and copied once (keyword\n"
             "arguments only, SECTION_FIELDS, as basin_points takes them; max_steps and t_max\n"
             "per stride): map() runs one call.  Process-local (it holds function\n"
             "addresses): not picklable.");

static PyTypeObject prepared_map_type = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "walker._hybrid.PreparedMap",
    .tp_basicsize = sizeof(PreparedMap),
    .tp_dealloc = (destructor)prepared_map_dealloc,
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_doc = prepared_map_doc,
    .tp_methods = prepared_map_methods,
    .tp_new = prepared_map_new,
};

int wkpy_add_prepared_map(PyObject *module)
{
    if (PyType_Ready(&prepared_map_type) < 0) return -1;
    return PyModule_AddObjectRef(module, "PreparedMap", (PyObject *)&prepared_map_type);
}
