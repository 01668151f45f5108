/* walker._hybrid's registries as Python dicts: models() (each compiled model's function
 * addresses and sizes), kernels() (the generated kernels' addresses, argument lengths and
 * output shapes) and kernel_hashes(); the methods are listed in _hybridmodule.c. */

#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <stdint.h>

#include "_hybridbinding.h"
#include "wk_common.h"
#include "wk_models.h"
#include "wk_system.h"

/* ------------------------------------------------------------------------------------------
 * Registries
 * ------------------------------------------------------------------------------------------ */

/* A function pointer as a Python int (0 for NULL).  Converting a function pointer to an
 * integer is implementation-defined in ISO C and exact on every platform Python runs on. */
#define ADDRESS(f) PyLong_FromUnsignedLongLong((unsigned long long)(uintptr_t)(f))

static int set_item(PyObject *dict, const char *key, PyObject *value)
{
    if (value == NULL) return -1;
    int rc = PyDict_SetItemString(dict, key, value);
    Py_DECREF(value);
    return rc;
}

/* An entry of a registry: the value (a new reference; NULL with an exception set) and its
 * key of item i of the registry's table. */
typedef PyObject *(*entry_fn)(const void *table, int64_t i, const char **key);

/* A registry as a new dict: the entries of the count items of table. */
static PyObject *registry(const void *table, int64_t count, entry_fn entry)
{
    PyObject *out = PyDict_New();
    if (out == NULL) return NULL;
    for (int64_t i = 0; i < count; i++) {
        const char *key = NULL;
        PyObject *value = entry(table, i, &key);
        if (value == NULL || PyDict_SetItemString(out, key, value)) {
            Py_XDECREF(value);
            Py_DECREF(out);
            return NULL;
        }
        Py_DECREF(value);
    }
    return out;
}

/* A model's entry: its name -> the dict of its function addresses. */
static PyObject *model_entry(const void *table, int64_t i, const char **key)
{
    const wk_model_entry *e = ((const wk_model_entry *const *)table)[i];
    *key = e->name;
    PyObject *entry = PyDict_New();
    if (entry == NULL) return NULL;
    if (set_item(entry, "rhs", ADDRESS(e->fn.rhs)) ||
        set_item(entry, "guards", ADDRESS(e->fn.guards)) ||
        set_item(entry, "reset", ADDRESS(e->fn.reset)) ||
        set_item(entry, "jac", ADDRESS(e->fn.jac)) || set_item(entry, "ctx", ADDRESS(e->fn.ctx)) ||
        set_item(entry, "energy", ADDRESS(e->energy)) ||
        set_item(entry, "points", ADDRESS(e->points)) ||
        set_item(entry, "start_phase", ADDRESS(e->start_phase)) ||
        set_item(entry, "lift", ADDRESS(e->lift)) ||
        set_item(entry, "lift_jacobian", ADDRESS(e->lift_jacobian)) ||
        set_item(entry, "torques", ADDRESS(e->torques)) ||
        set_item(entry, "rhs_jac", ADDRESS(e->fn.rhs_jac))) {
        Py_DECREF(entry);
        return NULL;
    }
    const wkpy_model_sizes *z = wkpy_sizes_named(e->name);
    if (z == NULL) {
        Py_DECREF(entry);
        PyErr_Format(PyExc_SystemError, "the compiled model '%s' has no sizes", e->name);
        return NULL;
    }
    if (set_item(entry, "n_x", PyLong_FromLongLong(z->n_x)) ||
        set_item(entry, "n_p", PyLong_FromLongLong(z->n_p)) ||
        set_item(entry, "n_phases", PyLong_FromLongLong(z->n_phases)) ||
        set_item(entry, "n_guards", PyLong_FromLongLong(z->n_guards)) ||
        set_item(entry, "n_impulse", PyLong_FromLongLong(z->n_impulse)) ||
        set_item(entry, "n_points", PyLong_FromLongLong(z->n_points)) ||
        set_item(entry, "n_z", PyLong_FromLongLong(z->n_z)) ||
        set_item(entry, "n_inputs", PyLong_FromLongLong(z->n_inputs))) {
        Py_DECREF(entry);
        return NULL;
    }
    return entry;
}

/* A kernel's entry: its name -> (signature, address). */
static PyObject *kernel_entry(const void *table, int64_t i, const char **key)
{
    const wk_kernel_entry *k = (const wk_kernel_entry *)table + i;
    *key = k->name;
    PyObject *shape = PyTuple_New(0);
    for (int d = 0; shape != NULL && d < 3 && k->shape[d] > 0; d++) {
        PyObject *dim = PyLong_FromLongLong((long long)k->shape[d]);
        if (dim == NULL || _PyTuple_Resize(&shape, d + 1)) {
            Py_XDECREF(dim);
            Py_CLEAR(shape);
            break;
        }
        PyTuple_SET_ITEM(shape, d, dim);
    }
    if (shape == NULL) return NULL;
    return Py_BuildValue("(sNLLN)", k->sig, ADDRESS(k->address), (long long)k->n_q,
                         (long long)k->n_p, shape);
}

const char wkpy_models_doc[] = PyDoc_STR(
             "models()\n--\n\n"
             "walker's compiled models: dict name -> dict of int addresses {'rhs', 'guards',\n"
             "'reset', 'jac', 'ctx', 'energy', 'points', 'start_phase', 'lift',\n"
             "'lift_jacobian', 'torques', 'rhs_jac'} (0 for NULL; 'lift' and 'lift_jacobian' a\n"
             "section lift that is not affine; 'torques' the actuated walkers' controller\n"
             "torques; 'rhs_jac', the fused rhs and Jacobian the integrator uses by itself for\n"
             "this (rhs, jac) pair, is informational) and its sizes as ints {'n_x', 'n_p',\n"
             "'n_phases', 'n_guards', 'n_impulse', 'n_points', 'n_z', 'n_inputs'} (state,\n"
             "parameters, phases, guards, impulse components, drawing points, section\n"
             "coordinates, actuator torques),\n"
             "which the binding checks every call against.");

PyObject *wkpy_models(PyObject *self, PyObject *unused)
{
    (void)self;
    (void)unused;
    int64_t count = 0;
    const wk_model_entry *const *table = wk_model_table(&count);
    return registry(table, count, model_entry);
}

const char wkpy_kernels_doc[] = PyDoc_STR(
             "kernels()\n--\n\n"
             "walker's generated C kernels: dict '<model>.<kernel>' -> (signature, address,\n"
             "n_q, n_p, shape): signatures as in wk_models.h ('qqdp_v', 'qp_v', 'qqdp_s',\n"
             "'qp_s', 'qqdqddp_v'); n_q the length of q (and qd, qdd), n_p the parameters\n"
             "read, shape that of out (() for a kernel returning a double).");

PyObject *wkpy_kernels(PyObject *self, PyObject *unused)
{
    (void)self;
    (void)unused;
    int64_t count = 0;
    const wk_kernel_entry *table = wk_kernel_table(&count);
    return registry(table, count, kernel_entry);
}

/* A generated module's hash: its name -> the hash string. */
static PyObject *hash_entry(const void *table, int64_t i, const char **key)
{
    const wk_kernel_hash_entry *k = (const wk_kernel_hash_entry *)table + i;
    *key = k->module;
    return PyUnicode_FromString(k->hash);
}

const char wkpy_kernel_hashes_doc[] = PyDoc_STR(
             "kernel_hashes()\n--\n\n"
             "The hash stamped on each generated C module: dict '<model>' (variants\n"
             "'<model>/<variant>') -> hex string (the symbolic model's sha256).");

PyObject *wkpy_kernel_hashes(PyObject *self, PyObject *unused)
{
    (void)self;
    (void)unused;
    int64_t count = 0;
    const wk_kernel_hash_entry *table = wk_kernel_hash_table(&count);
    return registry(table, count, hash_entry);
}
