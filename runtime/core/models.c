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

const usm_model *usm_model_variant(const char *base, const char *variant)
{
    if (!base || !variant)
        return NULL;
    for (int i = 0; i < USM_NMODELS; ++i)
        if (strcmp(usm_models[i]->base, base) == 0 && strcmp(usm_models[i]->variant, variant) == 0)
            return usm_models[i];
    return NULL;
}

const usm_variant_info *usm_variant_find(const char *name)
{
    if (!name)
        return NULL;
    for (int i = 0; i < USM_NVARIANTS; ++i)
        if (strcmp(usm_variants[i].name, name) == 0)
            return &usm_variants[i];
    return NULL;
}
