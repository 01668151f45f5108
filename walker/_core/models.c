/* The fused rhs and Jacobian of a registry entry (wk_model_rhs_jac, wk_models.h).  The
 * registry itself, wk_model_table, is printed from the Python declarations into model_table.c
 * (walker/symbolic/codegen_registry.py); each entry wk_entry_<symbol> is defined in its model
 * file.  "<model>/plain" entries run the kernels printed for point feet, no offsets, no
 * segment inertias and no dampers (those parameters exactly zero); the parameter vector is
 * the model's full one.  "kneed/ignore_scuff" and "kneed/plain/ignore_scuff" are the same
 * under the swing-foot scuffing convention "ignore" (walker/models/kneed.py).  The "/plain"
 * entries also have a fused rhs and Jacobian (fn.rhs_jac, one call of the variant's
 * accel_and_jac kernels); every other entry's fn.rhs_jac is NULL. */
#include <stddef.h>
#include "compass_plain.h"
#include "kneed_plain.h"
#include "wk_actuated.h"
#include "wk_common.h"
#include "wk_friction_models.h"
#include "wk_models.h"

wk_rhs_jac_fn wk_model_rhs_jac(wk_rhs_fn rhs, wk_jac_fn jac)
{
    if (rhs == NULL || jac == NULL) return NULL;
    int64_t count = 0;
    const wk_model_entry *const *table = wk_model_table(&count);
    for (int64_t i = 0; i < count; i++)
        if (table[i]->fn.rhs == rhs && table[i]->fn.jac == jac) return table[i]->fn.rhs_jac;
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
