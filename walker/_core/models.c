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
