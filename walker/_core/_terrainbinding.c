/* walker._hybrid's terrain functions (terrain.c, wk_terrain.h): added to the module by
 * wkpy_add_terrain.
 *
 * terrain_model(guards)    the name of the model whose plane guards are at this address if
 *                          it has terrain functions, else None;
 * terrain_walk(...)        one walk of a stride map over per-step terrain, optionally with
 *                          the Jacobians;
 * terrain_ensemble(...)    many walks (Monte Carlo), without the GIL.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <math.h>
#include <stdint.h>
#include <string.h>

#include "_hybridbinding.h"
#include "wk_terrain.h"

static PyObject *py_terrain_model(PyObject *self, PyObject *arg)
{
    (void)self;
    uintptr_t guards;
    if (wkpy_arg_address(arg, "guards", 1, &guards)) return NULL;
    const wk_terrain_entry *te = wk_terrain_find((wk_guards_fn)guards);
    if (te == NULL) Py_RETURN_NONE;
    return PyUnicode_FromString(te->name);
}

static PyObject *py_terrain_lift(PyObject *self, PyObject *arg)
{
    (void)self;
    uintptr_t guards;
    if (wkpy_arg_address(arg, "guards", 1, &guards)) return NULL;
    const wk_terrain_entry *te = wk_terrain_find((wk_guards_fn)guards);
    if (te == NULL || te->lift == NULL || te->lift_jacobian == NULL) Py_RETURN_NONE;
    return Py_BuildValue("(KK)", (unsigned long long)(uintptr_t)te->lift,
                         (unsigned long long)(uintptr_t)te->lift_jacobian);
}

/* The section settings and the model's terrain entry; 0 or -1 with an exception. */
static int parse_head(PyObject *const *args, wkpy_section *s, const wk_terrain_entry **te)
{
    if (wkpy_section_parse(args, s)) return -1;
    *te = wk_terrain_find(s->fn.guards);
    if (*te == NULL) {
        PyErr_SetString(PyExc_ValueError, "terrain is not supported for this system's model");
        wkpy_section_free(s);
        return -1;
    }
    return 0;
}

/* A (rows, 2) or (m, rows, 2) float64 buffer of finite steps; 0 or -1 with an exception. */
static int check_steps(const Py_buffer *v, int ndim)
{
    if (v->shape[ndim - 1] != 2 || v->shape[ndim - 2] < 1) {
        PyErr_SetString(PyExc_ValueError, "`terrain` must have at least one row of 2 values");
        return -1;
    }
    Py_ssize_t n = 1;
    for (int i = 0; i < ndim; i++) n *= v->shape[i];
    if (!wkpy_all_finite((const double *)v->buf, n)) {
        PyErr_SetString(PyExc_ValueError, "All values of `terrain` must be finite.");
        return -1;
    }
    return 0;
}

#define WALK_NARGS (WKPY_SECTION_NARGS + 5)

PyDoc_STRVAR(terrain_walk_doc,
             "terrain_walk(*section, start, terrain, want_jac, from_state, previous)\n--\n\n"
             "One walk from start (a section point (n_z,), or with from_state a full state\n"
             "(n_x,)) over terrain (n_steps, 2) of (slope, drop) rows, n_steps strides\n"
             "(wk_terrain.h); previous: None or the (slope, drop) the start landed on;\n"
             "section: the WKPY_SECTION_NARGS settings of basin_points.  Returns (status,\n"
             "strides, t, x, z, jz, tjac): x, z bytearrays of float64 (n_x,), (n_z,); jz\n"
             "(n_z, n_start) and tjac (n_z, 2 n_steps) bytearrays with want_jac, else None.");

static PyObject *py_terrain_walk(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    (void)self;
    if (nargs != WALK_NARGS) {
        PyErr_Format(PyExc_TypeError, "terrain_walk() takes %d arguments, got %zd", WALK_NARGS,
                     nargs);
        return NULL;
    }
    wkpy_section s;
    const wk_terrain_entry *te;
    if (parse_head(args, &s, &te)) return NULL;
    Py_buffer v_z, v_steps, v_prev;
    wkpy_held held = {0};
    PyObject *result = NULL;
    double *buf = NULL;
    int want_jac, from_state;
    const double *previous = NULL;
    if (wkpy_arg_bool(args[WKPY_SECTION_NARGS + 2], "want_jac", &want_jac) ||
        wkpy_arg_bool(args[WKPY_SECTION_NARGS + 3], "from_state", &from_state))
        goto out;
    if (want_jac && s.fn.jac == NULL)
        WKPY_FAIL(PyExc_ValueError, "`want_jac` needs a Jacobian (`jac` is 0)");
    const int64_t n_start = from_state ? s.pb.n_x : s.sec.n_z;
    if (wkpy_hold_buffer(&held, args[WKPY_SECTION_NARGS], "start", 'd', 1, &v_z)) goto out;
    if (v_z.shape[0] != n_start)
        WKPY_FAIL(PyExc_ValueError, "`start` must have length %lld", (long long)n_start);
    if (!wkpy_all_finite((const double *)v_z.buf, v_z.shape[0]))
        WKPY_FAIL(PyExc_ValueError, "All components of the start `start` must be finite.");
    if (args[WKPY_SECTION_NARGS + 4] != Py_None) {
        if (wkpy_hold_buffer(&held, args[WKPY_SECTION_NARGS + 4], "previous", 'd', 1, &v_prev))
            goto out;
        if (v_prev.shape[0] != 2 || !wkpy_all_finite((const double *)v_prev.buf, 2))
            WKPY_FAIL(PyExc_ValueError, "`previous` must be 2 finite values (slope, drop)");
        previous = (const double *)v_prev.buf;
    }
    if (wkpy_hold_buffer(&held, args[WKPY_SECTION_NARGS + 1], "terrain", 'd', 2, &v_steps))
        goto out;
    if (check_steps(&v_steps, 2)) goto out;
    const int64_t n_x = s.pb.n_x, n_z = s.sec.n_z, n_steps = v_steps.shape[0];
    const int64_t n_jz = want_jac ? n_z * n_start : 0, n_tj = want_jac ? n_z * 2 * n_steps : 0;
    buf = PyMem_Malloc((size_t)(n_x + n_z + n_jz + n_tj + 1) * sizeof(double));
    if (buf == NULL) {
        PyErr_NoMemory();
        goto out;
    }
    double *x = buf, *z_out = x + n_x, *jz = z_out + n_z, *tjac = jz + n_jz;
    int64_t status = 0, strides = 0;
    double t = 0.0;
    int rc;
    const double *steps = (const double *)v_steps.buf;
    const wk_terrain_start st = {(const double *)v_z.buf, from_state, previous};
    wkpy_signals_begin();
    Py_BEGIN_ALLOW_THREADS
    if (want_jac)
        rc = wk_terrain_walk_jac(&s.fn, te, &s.pb, &s.sec, &st, steps, n_steps, &status,
                                 &strides, &t, x, z_out, jz, tjac);
    else
        rc = wk_terrain_walk(&s.fn, te, &s.pb, &s.sec, &st, steps, n_steps, &status, &strides,
                             &t, x, z_out);
    Py_END_ALLOW_THREADS
    /* a signal: the walk ended with the INTERRUPTED status (its own outcome) unless
     * Python's handler raised */
    if (wkpy_signals_end() && wkpy_interrupted(0)) goto out;
    if (wkpy_run_failed(rc, 0, s.pb.n_phases)) goto out;
    PyObject *o_jz = want_jac ? wkpy_bytes_of(jz, n_jz, sizeof(double)) : Py_NewRef(Py_None);
    PyObject *o_tj = want_jac ? wkpy_bytes_of(tjac, n_tj, sizeof(double)) : Py_NewRef(Py_None);
    if (o_jz != NULL && o_tj != NULL)
        result = Py_BuildValue("(LLdNNNN)", (long long)status, (long long)strides, t,
                               wkpy_bytes_of(x, n_x, sizeof(double)),
                               wkpy_bytes_of(z_out, n_z, sizeof(double)), o_jz, o_tj);
    else {
        Py_XDECREF(o_jz);
        Py_XDECREF(o_tj);
    }

out:
    PyMem_Free(buf);
    wkpy_release_held(&held);
    wkpy_section_free(&s);
    return result;
}

#define ENSEMBLE_NARGS (WKPY_SECTION_NARGS + 2)

PyDoc_STRVAR(terrain_ensemble_doc,
             "terrain_ensemble(*section, z0, terrain)\n--\n\n"
             "Many walks: run i from z0[i] (m, n_z) over terrain[i] (m, n_steps, 2), without\n"
             "the GIL.  Returns (status, strides): bytearrays of m int64, strides the strides\n"
             "completed before the first failure (n_steps and status 0 when none failed).\n"
             "SIGINT or SIGTERM stops the walks within a step and raises (KeyboardInterrupt,\n"
             "or the exception of Python's handler).");

static PyObject *py_terrain_ensemble(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    (void)self;
    if (nargs != ENSEMBLE_NARGS) {
        PyErr_Format(PyExc_TypeError, "terrain_ensemble() takes %d arguments, got %zd",
                     ENSEMBLE_NARGS, nargs);
        return NULL;
    }
    wkpy_section s;
    const wk_terrain_entry *te;
    if (parse_head(args, &s, &te)) return NULL;
    Py_buffer v_z0, v_steps;
    wkpy_held held = {0};
    PyObject *result = NULL;
    if (wkpy_hold_buffer(&held, args[WKPY_SECTION_NARGS], "z0", 'd', 2, &v_z0)) goto out;
    if (v_z0.shape[1] != s.sec.n_z)
        WKPY_FAIL(PyExc_ValueError, "`z0` must have n_z = %lld columns", (long long)s.sec.n_z);
    if (!wkpy_all_finite((const double *)v_z0.buf, v_z0.shape[0] * v_z0.shape[1]))
        WKPY_FAIL(PyExc_ValueError, "All section points `z0` must be finite.");
    if (wkpy_hold_buffer(&held, args[WKPY_SECTION_NARGS + 1], "terrain", 'd', 3, &v_steps))
        goto out;
    if (check_steps(&v_steps, 3)) goto out;
    if (v_steps.shape[0] != v_z0.shape[0])
        WKPY_FAIL(PyExc_ValueError, "`terrain` must have one run per row of `z0`");
    const int64_t m = v_z0.shape[0], n_steps = v_steps.shape[1];
    int64_t *buf = PyMem_Calloc((size_t)(2 * m + 1), sizeof(int64_t));
    if (buf == NULL) {
        PyErr_NoMemory();
        goto out;
    }
    int rc;
    wkpy_signals_begin();
    Py_BEGIN_ALLOW_THREADS
    rc = wk_terrain_ensemble(&s.fn, te, &s.pb, &s.sec, (const double *)v_z0.buf, m,
                             (const double *)v_steps.buf, n_steps, buf, buf + m);
    Py_END_ALLOW_THREADS
    if (wkpy_signals_end() && wkpy_interrupted(1)) {
        /* the runs cut short carry no outcome of their own: never returned */
    } else if (!wkpy_run_failed(rc, 0, s.pb.n_phases))
        result = Py_BuildValue("(NN)", wkpy_bytes_of(buf, m, sizeof(int64_t)),
                               wkpy_bytes_of(buf + m, m, sizeof(int64_t)));
    PyMem_Free(buf);

out:
    wkpy_release_held(&held);
    wkpy_section_free(&s);
    return result;
}

/* The draws' settings args[0..4]: entropy (int64 words < 2**32, 1 to 4 of them), normal
 * (address), slope_mean, slope_std, height_std; entropy's buffer v (the caller's, until h
 * releases it) held by h, its words in words.  0 or -1 with an exception. */
static int parse_draws(PyObject *const *args, wkpy_held *h, Py_buffer *pv, uint32_t *words,
                       wk_terrain_draws *d)
{
    Py_buffer *vp = pv;
    uintptr_t normal;
    if (!wk_terrain_draws_supported()) {
        PyErr_SetString(PyExc_ValueError, "this build cannot draw terrain (no 128-bit integers)");
        return -1;
    }
    if (wkpy_hold_buffer(h, args[0], "entropy", 'q', 1, vp)) return -1;
    const Py_buffer v = *vp;
    if (v.shape[0] < 1 || v.shape[0] > 4) {
        PyErr_SetString(PyExc_ValueError, "`entropy` must have 1 to 4 words");
        return -1;
    }
    for (Py_ssize_t i = 0; i < v.shape[0]; i++) {
        const int64_t w = ((const int64_t *)v.buf)[i];
        if (w < 0 || w > (int64_t)UINT32_MAX) {
            PyErr_SetString(PyExc_ValueError, "`entropy` words must lie in [0, 2**32)");
            return -1;
        }
        words[i] = (uint32_t)w;
    }
    d->entropy = words;
    d->n_entropy = v.shape[0];
    if (wkpy_arg_address(args[1], "normal", 0, &normal) ||
        wkpy_arg_double(args[2], "slope_mean", &d->slope_mean) ||
        wkpy_arg_double(args[3], "slope_std", &d->slope_std) ||
        wkpy_arg_double(args[4], "height_std", &d->height_std))
        return -1;
    if (!isfinite(d->slope_mean) || !(d->slope_std >= 0.0 && isfinite(d->slope_std)) ||
        !(d->height_std >= 0.0 && isfinite(d->height_std))) {
        PyErr_SetString(PyExc_ValueError,
                        "`slope_mean` must be finite, `slope_std` and `height_std` finite >= 0");
        return -1;
    }
    d->normal = (void *)normal;
    return 0;
}

/* The run indices (int64, each in [0, 2**32)) and n_steps >= 1; 0 or -1. */
static int parse_runs(PyObject *o_runs, PyObject *o_steps, wkpy_held *h, Py_buffer *v,
                      int64_t *n_steps)
{
    if (wkpy_hold_buffer(h, o_runs, "runs", 'q', 1, v)) return -1;
    for (Py_ssize_t i = 0; i < v->shape[0]; i++) {
        const int64_t r = ((const int64_t *)v->buf)[i];
        if (r < 0 || r > (int64_t)UINT32_MAX) {
            PyErr_SetString(PyExc_ValueError, "`runs` must lie in [0, 2**32)");
            return -1;
        }
    }
    if (wkpy_arg_int(o_steps, "n_steps", n_steps)) return -1;
    if (*n_steps < 1 || *n_steps > ((int64_t)1 << 40)) {
        PyErr_SetString(PyExc_ValueError, "`n_steps` must be >= 1");
        return -1;
    }
    return 0;
}

PyDoc_STRVAR(terrain_draws_doc,
             "terrain_draws(entropy, normal, slope_mean, slope_std, height_std, runs, n_steps)\n"
             "--\n\n"
             "The first n_steps terrain rows (slope, drop) of each run in runs (int64), drawn\n"
             "in C as walker.analysis.mfpt.draw_terrains draws them (wk_terrain.h, terrain_draw.c):\n"
             "entropy the seed's 32-bit words (int64), normal the address of numpy's\n"
             "random_standard_normal.  Returns a bytearray of float64 (len(runs), n_steps, 2).");

static PyObject *py_terrain_draws(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    (void)self;
    if (nargs != 7) {
        PyErr_Format(PyExc_TypeError, "terrain_draws() takes 7 arguments, got %zd", nargs);
        return NULL;
    }
    wkpy_held held = {0};
    uint32_t words[4];
    wk_terrain_draws d;
    Py_buffer v_entropy, v_runs;
    int64_t n_steps;
    PyObject *result = NULL;
    if (parse_draws(args, &held, &v_entropy, words, &d) ||
        parse_runs(args[5], args[6], &held, &v_runs, &n_steps))
        goto out;
    const int64_t m = v_runs.shape[0];
    double *rows = PyMem_Malloc((size_t)(m * n_steps * 2 + 1) * sizeof(double));
    if (rows == NULL) {
        PyErr_NoMemory();
        goto out;
    }
    const int64_t *runs = (const int64_t *)v_runs.buf;
    Py_BEGIN_ALLOW_THREADS
    for (int64_t i = 0; i < m; i++) wk_terrain_draw_rows(&d, runs[i], n_steps, rows + i * n_steps * 2);
    Py_END_ALLOW_THREADS
    result = wkpy_bytes_of(rows, m * n_steps * 2, sizeof(double));
    PyMem_Free(rows);

out:
    wkpy_release_held(&held);
    return result;
}

#define DRAWN_NARGS (WKPY_SECTION_NARGS + 8)

PyDoc_STRVAR(terrain_ensemble_drawn_doc,
             "terrain_ensemble_drawn(*section, z0, entropy, normal, slope_mean, slope_std,\n"
             "    height_std, runs, n_steps)\n--\n\n"
             "terrain_ensemble with each run's rows drawn in C (terrain_draws): run runs[i]\n"
             "from z0 (n_z,) over its first n_steps rows, without the GIL.  Returns (status,\n"
             "strides), bytearrays of len(runs) int64.  SIGINT or SIGTERM stops the walks\n"
             "within a step and raises.");

static PyObject *py_terrain_ensemble_drawn(PyObject *self, PyObject *const *args,
                                           Py_ssize_t nargs)
{
    (void)self;
    if (nargs != DRAWN_NARGS) {
        PyErr_Format(PyExc_TypeError, "terrain_ensemble_drawn() takes %d arguments, got %zd",
                     DRAWN_NARGS, nargs);
        return NULL;
    }
    wkpy_section s;
    const wk_terrain_entry *te;
    if (parse_head(args, &s, &te)) return NULL;
    wkpy_held held = {0};
    uint32_t words[4];
    wk_terrain_draws d;
    Py_buffer v_z0, v_entropy, v_runs;
    int64_t n_steps;
    PyObject *result = NULL;
    if (wkpy_hold_buffer(&held, args[WKPY_SECTION_NARGS], "z0", 'd', 1, &v_z0)) goto out;
    if (v_z0.shape[0] != s.sec.n_z)
        WKPY_FAIL(PyExc_ValueError, "`z0` must have length n_z = %lld", (long long)s.sec.n_z);
    if (!wkpy_all_finite((const double *)v_z0.buf, v_z0.shape[0]))
        WKPY_FAIL(PyExc_ValueError, "All components of the section point `z0` must be finite.");
    if (parse_draws(args + WKPY_SECTION_NARGS + 1, &held, &v_entropy, words, &d) ||
        parse_runs(args[WKPY_SECTION_NARGS + 6], args[WKPY_SECTION_NARGS + 7], &held, &v_runs,
                   &n_steps))
        goto out;
    const int64_t m = v_runs.shape[0];
    int64_t *buf = PyMem_Calloc((size_t)(2 * m + 1), sizeof(int64_t));
    if (buf == NULL) {
        PyErr_NoMemory();
        goto out;
    }
    int rc;
    wkpy_signals_begin();
    Py_BEGIN_ALLOW_THREADS
    rc = wk_terrain_ensemble_drawn(&s.fn, te, &s.pb, &s.sec, (const double *)v_z0.buf, &d,
                                   (const int64_t *)v_runs.buf, m, n_steps, buf, buf + m);
    Py_END_ALLOW_THREADS
    if (wkpy_signals_end() && wkpy_interrupted(1)) {
        /* the runs cut short carry no outcome of their own: never returned */
    } else if (!wkpy_run_failed(rc, 0, s.pb.n_phases))
        result = Py_BuildValue("(NN)", wkpy_bytes_of(buf, m, sizeof(int64_t)),
                               wkpy_bytes_of(buf + m, m, sizeof(int64_t)));
    PyMem_Free(buf);

out:
    wkpy_release_held(&held);
    wkpy_section_free(&s);
    return result;
}

static PyMethodDef terrain_methods[] = {
    {"terrain_model", py_terrain_model, METH_O,
     "terrain_model(guards)\n--\n\nThe model whose plane guards are at address `guards` if "
     "it has terrain functions (wk_terrain.h), else None."},
    {"terrain_lift", py_terrain_lift, METH_O,
     "terrain_lift(guards)\n--\n\nThe addresses (lift, lift_jacobian) of the section lift "
     "that terrain runs of the model whose plane guards are at address `guards` take when its "
     "registry entry has none (wk_terrain.h), else None."},
    {"terrain_walk", (PyCFunction)(void (*)(void))py_terrain_walk, METH_FASTCALL,
     terrain_walk_doc},
    {"terrain_ensemble", (PyCFunction)(void (*)(void))py_terrain_ensemble, METH_FASTCALL,
     terrain_ensemble_doc},
    {"terrain_draws", (PyCFunction)(void (*)(void))py_terrain_draws, METH_FASTCALL,
     terrain_draws_doc},
    {"terrain_ensemble_drawn", (PyCFunction)(void (*)(void))py_terrain_ensemble_drawn,
     METH_FASTCALL, terrain_ensemble_drawn_doc},
    {NULL, NULL, 0, NULL},
};

int wkpy_add_terrain(PyObject *module)
{
    return PyModule_AddFunctions(module, terrain_methods);
}
