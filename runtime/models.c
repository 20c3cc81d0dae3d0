/* Lookup of the generated model descriptors by name. */
#include <string.h>

#include "usm.h"

const usm_model *usm_model_find(const char *name)
{
    if (!name)
        return NULL;
    for (int i = 0; i < USM_NMODELS; ++i)
        if (strcmp(usm_models[i]->name, name) == 0)
            return usm_models[i];
    return NULL;
}
