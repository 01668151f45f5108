/* Registry of walker's compiled models (see wk_models.h): the hand-written C ports of the
 * numba models in walker/models (walker/_core/model_*.c).  "<model>/plain" entries run the
 * kernels printed for point feet, no offsets, no segment inertias and no dampers
 * (those parameters exactly zero); the parameter vector is the model's full one. */
#include <stddef.h>
#include "wk_common.h"
#include "wk_models.h"

#define WK_ENTRY(label, name)                                                               \
    {                                                                                       \
        label,                                                                              \
            {wk_model_##name##_rhs, wk_model_##name##_guards, wk_model_##name##_reset,      \
             wk_model_##name##_jac, NULL},                                                  \
            wk_model_##name##_energy, wk_model_##name##_points, NULL                        \
    }

static const wk_model_entry MODELS[] = {
    WK_ENTRY("simplest", simplest),
    WK_ENTRY("compass", compass),
    WK_ENTRY("compass/plain", compass_plain),
    WK_ENTRY("kneed", kneed),
    WK_ENTRY("kneed/plain", kneed_plain),
};

const wk_model_entry *wk_model_table(int64_t *count)
{
    *count = (int64_t)(sizeof MODELS / sizeof MODELS[0]);
    return MODELS;
}
