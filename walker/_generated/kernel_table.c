/* generated, do not edit: registry of generated kernels (placeholder until
 * scripts/generate_kernels.py prints the C kernels). */
#include <stddef.h>
#include "wk_models.h"

static const wk_kernel_entry KERNELS[] = {{NULL, NULL, NULL}};

const wk_kernel_entry *wk_kernel_table(int64_t *count)
{
    *count = 0;
    return KERNELS;
}
