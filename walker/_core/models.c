/* Registry of walker's compiled models (see wk_models.h).  Placeholder: filled in as the
 * models are written in C. */
#include <stddef.h>
#include "wk_models.h"

static const wk_model_entry MODELS[] = {{NULL, {NULL, NULL, NULL, NULL, NULL}, NULL, NULL, NULL}};

const wk_model_entry *wk_model_table(int64_t *count)
{
    *count = 0;
    return MODELS;
}
