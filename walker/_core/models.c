/* Registry of walker's compiled models (see wk_models.h): the hand-written C ports of the
 * models in walker/models (walker/_core/model_*.c).  "<model>/plain" entries run the
 * kernels printed for point feet, no offsets, no segment inertias and no dampers
 * (those parameters exactly zero); the parameter vector is the model's full one.
 * "kneed/ignore_scuff" and "kneed/plain/ignore_scuff" are the same under the swing-foot
 * scuffing convention "ignore" (walker/models/kneed.py).  The "/plain" entries also have a
 * fused rhs and Jacobian (fn.rhs_jac, one call of the variant's accel_and_jac kernels);
 * every other entry's fn.rhs_jac is NULL. */
#include <stddef.h>
#include "compass_plain.h"
#include "kneed_plain.h"
#include "wk_actuated.h"
#include "wk_common.h"
#include "wk_friction_models.h"
#include "wk_models.h"
#include "wk_rimless.h"

#define WK_ENTRY(label, name)                                                               \
    {                                                                                       \
        label,                                                                              \
            {wk_model_##name##_rhs, wk_model_##name##_guards, wk_model_##name##_reset,      \
             wk_model_##name##_jac, NULL},                                                  \
            wk_model_##name##_energy, wk_model_##name##_points, NULL                        \
    }

/* An entry whose variant has a fused rhs and Jacobian (wk_model_<name>_rhs_jac). */
#define WK_ENTRY_FUSED(label, name)                                                         \
    {                                                                                       \
        label,                                                                              \
            {wk_model_##name##_rhs, wk_model_##name##_guards, wk_model_##name##_reset,      \
             wk_model_##name##_jac, NULL, wk_model_##name##_rhs_jac},                       \
            wk_model_##name##_energy, wk_model_##name##_points, NULL                        \
    }

static const wk_model_entry SIMPLEST = {
    "simplest",
    {wk_model_simplest_rhs, wk_model_simplest_guards, wk_model_simplest_reset,
     wk_model_simplest_jac, NULL},
    wk_model_simplest_energy,
    wk_model_simplest_points,
    NULL,
    wk_model_simplest_lift,
    wk_model_simplest_lift_jacobian,
};
static const wk_model_entry COMPASS = WK_ENTRY("compass", compass);
static const wk_model_entry COMPASS_PLAIN = WK_ENTRY_FUSED("compass/plain", compass_plain);
static const wk_model_entry KNEED = WK_ENTRY("kneed", kneed);
static const wk_model_entry KNEED_PLAIN = WK_ENTRY_FUSED("kneed/plain", kneed_plain);
static const wk_model_entry KNEED_IGNORE_SCUFF =
    WK_ENTRY("kneed/ignore_scuff", kneed_ignore_scuff);
static const wk_model_entry KNEED_PLAIN_IGNORE_SCUFF =
    WK_ENTRY_FUSED("kneed/plain/ignore_scuff", kneed_plain_ignore_scuff);

static const wk_model_entry *const MODELS[] = {
    &SIMPLEST,
    &COMPASS,
    &COMPASS_PLAIN,
    &KNEED,
    &KNEED_PLAIN,
    &KNEED_IGNORE_SCUFF,
    &KNEED_PLAIN_IGNORE_SCUFF,
    &wk_entry_compass_coulomb,
    &wk_entry_double_pendulum,
    &wk_entry_kneed_coulomb,
    &wk_entry_three_link,
    &wk_entry_five_link,
    &wk_entry_rimless_wheel,
};

const wk_model_entry *const *wk_model_table(int64_t *count)
{
    *count = (int64_t)(sizeof MODELS / sizeof MODELS[0]);
    return MODELS;
}

wk_rhs_jac_fn wk_model_rhs_jac(wk_rhs_fn rhs, wk_jac_fn jac)
{
    if (rhs == NULL || jac == NULL) return NULL;
    for (size_t i = 0; i < sizeof MODELS / sizeof MODELS[0]; i++)
        if (MODELS[i]->fn.rhs == rhs && MODELS[i]->fn.jac == jac) return MODELS[i]->fn.rhs_jac;
    return NULL;
}

/* The variants with hoisted kernels: their plain and hoisted phase functions, the module's
 * constants function and where the constants go (after the n_p parameters). */
typedef struct {
    wk_rhs_fn rhs;
    wk_jac_fn jac;
    wk_rhs_jac_fn rhs_jac;
    wk_rhs_fn hoisted_rhs;
    wk_jac_fn hoisted_jac;
    wk_rhs_jac_fn hoisted_rhs_jac;
    void (*constants)(const double *p, double *out);
    int64_t n_p;
    int64_t n_constants;
} hoist_entry;

#define HOIST_ENTRY(name, module, MODULE)                                                   \
    {                                                                                       \
        wk_model_##name##_rhs, wk_model_##name##_jac, wk_model_##name##_rhs_jac,            \
            wk_model_##name##_hoisted_rhs, wk_model_##name##_hoisted_jac,                   \
            wk_model_##name##_hoisted_rhs_jac, wk_##module##_constants,                     \
            WK_##MODULE##_CONSTANTS_AT, WK_##MODULE##_N_CONSTANTS                           \
    }

#if WK_COMPASS_PLAIN_CONSTANTS_AT + WK_COMPASS_PLAIN_N_CONSTANTS > WK_HOIST_MAX || \
    WK_KNEED_PLAIN_CONSTANTS_AT + WK_KNEED_PLAIN_N_CONSTANTS > WK_HOIST_MAX
#error "WK_HOIST_MAX does not hold a hoisting variant's parameters and constants"
#endif

static const hoist_entry HOISTING[] = {
    HOIST_ENTRY(compass_plain, compass_plain, COMPASS_PLAIN),
    HOIST_ENTRY(kneed_plain, kneed_plain, KNEED_PLAIN),
    HOIST_ENTRY(kneed_plain_ignore_scuff, kneed_plain, KNEED_PLAIN),
};

const double *wk_model_hoist(wk_functions *fn, const double *p, double *buf)
{
    for (size_t i = 0; i < sizeof HOISTING / sizeof HOISTING[0]; i++) {
        const hoist_entry *e = &HOISTING[i];
        if (fn->rhs != e->rhs || (fn->jac != NULL && fn->jac != e->jac)) continue;
        if (fn->rhs_jac != NULL && fn->rhs_jac != e->rhs_jac) continue;
        for (int64_t k = 0; k < e->n_p; k++) buf[k] = p[k];
        e->constants(p, buf + e->n_p);
        fn->rhs = e->hoisted_rhs;
        if (fn->jac != NULL) fn->jac = e->hoisted_jac;
        if (fn->rhs_jac != NULL) fn->rhs_jac = e->hoisted_rhs_jac;
        return buf;
    }
    return p;
}
