/* walker's compiled model contract: the C ABI between a hybrid system and the integrator.
 *
 * A hybrid system is four plain C functions plus a few sizes.  walker's own models are
 * compiled into the extension module walker._hybrid when the package is installed; a user
 * can supply the same four functions from anywhere that yields a C function pointer (a
 * numba ``cfunc``, ctypes, cffi, another extension) and pass their addresses.
 *
 * Conventions: arrays are contiguous float64, matrices row-major.  ``ctx`` is an opaque
 * pointer handed unchanged to every call (NULL unless the system was built with one); a
 * model may use it for data of its own, e.g. a user-supplied controller.
 *
 * rhs(phase, t, x, p, dx, ctx)
 *     fills dx[n_x] with dx/dt in ``phase``.
 * guards(phase, t, x, p, g, ctx)
 *     fills g[n_guards]; a guard not used in a phase returns the constant 1.0 there.
 * reset(phase, k, t, x, p, x_new, impulse, out, ctx)
 *     called where guard ``k`` fired, with x_new[n_x] pre-filled with a copy of x and
 *     impulse[n_impulse] zeroed; writes out[0] = action (WK_EVENT_*), out[1] = next phase,
 *     out[2] = status (a walker.status.Status value; 0 unless the action is terminal).
 * jac(phase, t, x, p, J, ctx)   (may be NULL)
 *     fills J[n_x * n_x] (row-major) with df/dx; needed for variational equations.
 *
 * wk_functions also has a member rhs_jac(phase, t, x, p, dx, J, ctx), rhs and jac in one
 * call, that is filled internally, never by a user: the binding sets it when (rhs, jac) is
 * the pair of a built-in model with a fused function (wk_model_rhs_jac, models.c), NULL
 * otherwise.  It comes after ctx, so an initializer {rhs, guards, reset, jac, ctx} leaves
 * it NULL.  After it, on_stride (also internal, NULL for a user system): see wk_stride_fn.
 *
 * ``t`` is the local time since the last applied event (see walker/simulation/integrate.py).
 */
#ifndef WK_SYSTEM_H
#define WK_SYSTEM_H

#include <stdint.h>

typedef void (*wk_rhs_fn)(int64_t phase, double t, const double *x, const double *p,
                          double *dx, void *ctx);
typedef void (*wk_guards_fn)(int64_t phase, double t, const double *x, const double *p,
                             double *g, void *ctx);
typedef void (*wk_reset_fn)(int64_t phase, int64_t k, double t, const double *x,
                            const double *p, double *x_new, double *impulse, int64_t *out,
                            void *ctx);
typedef void (*wk_jac_fn)(int64_t phase, double t, const double *x, const double *p,
                          double *J, void *ctx);

/* dx[n_x] = f(x) and J[n_x * n_x] = df/dx, as rhs and jac fill them (J bit for bit; dx to
 * round-off), in one call. */
typedef void (*wk_rhs_jac_fn)(int64_t phase, double t, const double *x, const double *p,
                              double *dx, double *J, void *ctx);

/* Called by the integrator after it applied a stride event (WK_EVENT_STRIDE) and its
 * sensitivities, before it re-arms the guards, with ``ctx``, the strides completed so far
 * and the state after the reset (n_x): a system whose guards and resets change from stride
 * to stride (walker's terrain, walker/_core/wk_terrain.h) advances its stride there.  Never
 * called inside the finite differences of an event. */
typedef void (*wk_stride_fn)(void *ctx, int64_t n_done, const double *x);

typedef struct {
    wk_rhs_fn rhs;
    wk_guards_fn guards;
    wk_reset_fn reset;
    wk_jac_fn jac; /* NULL: no Jacobian */
    void *ctx;
    wk_rhs_jac_fn rhs_jac; /* filled internally (wk_model_rhs_jac), NULL for user systems */
    wk_stride_fn on_stride; /* filled internally (terrain runs, terrain.c), else NULL */
} wk_functions;

/* Event actions returned by reset in out[0] (WK_EVENT_*), output modes, methods and every
 * walker.status.Status value (WK_<NAME>): printed from walker/status.py. */
#include "status.h"

#endif
