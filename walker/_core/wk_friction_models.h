/* Registry entries of walker's models with dry joint friction (walker/models/friction.py, ported
 * in wk_friction.c): model_compass_coulomb.c, model_double_pendulum.c,
 * model_kneed_coulomb.c, C ports of walker/models/compass_coulomb.py, double_pendulum.py
 * and kneed_coulomb.py.  Their start_phase writes the phase as a double (-1 if a solve is
 * singular, as the numba start_phase returns). */
#ifndef WK_FRICTION_MODELS_H
#define WK_FRICTION_MODELS_H

#include "wk_models.h"
#include "wk_registry.h"

extern const wk_model_entry wk_entry_compass_coulomb;
extern const wk_model_entry wk_entry_double_pendulum;
extern const wk_model_entry wk_entry_kneed_coulomb;

/* Defines the static start_phase and the registry entry wk_entry_<name> of the friction model
 * ``name`` on the walker ``base`` (its energy and drawing points, wk_model_<base>_energy and
 * wk_model_<base>_points): with the model file's static rhs, guards, reset and jac, and its
 * start (a wk_friction_start_fn, wk_friction.h), start_phase the phase consistent with the
 * state x of n_x entries in base phase 0 (walker.models.<name>.start_phase). */
#define WK_FRICTION_WALKER_ENTRY(name, base, n_x)                                            \
    static void start_phase(const double *x, const double *p, double *out, void *ctx)        \
    {                                                                                        \
        (void)ctx;                                                                           \
        double y[n_x];                                                                       \
        for (int i = 0; i < (n_x); i++) y[i] = x[i];                                         \
        out[0] = (double)start(0, y, p);                                                     \
    }                                                                                        \
    const wk_model_entry wk_entry_##name = {                                                 \
        WK_ENTRY_NAME_##name,                                                                \
        {rhs, guards, reset, jac, NULL},                                                     \
        wk_model_##base##_energy,                                                            \
        wk_model_##base##_points,                                                            \
        start_phase,                                                                         \
    };

#endif
