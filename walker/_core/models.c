/* Registry of walker's compiled models (see wk_models.h): the hand-written C ports of the
 * models in walker/models (walker/_core/model_*.c).  "<model>/plain" entries run the
 * kernels printed for point feet, no offsets, no segment inertias and no dampers
 * (those parameters exactly zero); the parameter vector is the model's full one.
 * "kneed/ignore_scuff" and "kneed/plain/ignore_scuff" are the same under the swing-foot
 * scuffing convention "ignore" (walker/models/kneed.py).  The "/plain" entries also have a
 * fused rhs and Jacobian (fn.rhs_jac, one call of the variant's accel_and_jac kernels);
 * every other entry's fn.rhs_jac is NULL. */
#include <stddef.h>
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
