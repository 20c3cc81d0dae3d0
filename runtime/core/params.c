/* Parameter defaults, lookup by name and validation. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "usm.h"

void usm_params_default(usm_params *p)
{
    /* The paper's Appendix A (Table 5), the values it states in the text
     * (mu0, kappa) and those it leaves out (f, M, the imperfections: chosen,
     * with the reasons in derive/usm_derive/defaults.py, the one place the
     * numbers are written; the equations documents print the same table). */
    for (int k = 0; k < USM_NPARAMS; ++k)
        *usm_params_field(p, &usm_param_table[k]) = usm_param_defaults[k];
}

/* The name of the first imperfection (in table order) that is not 0, NULL when none is. */
static const char *imperfection_set(const usm_params *p)
{
    for (int j = 0; j < USM_NIMPERFECTIONS; ++j) {
        const usm_param_info *info = &usm_param_table[usm_param_imperfections[j]];
        if (usm_params_get(p, info) != 0.0)
            return info->name;
    }
    return NULL;
}

int usm_params_check_ideal(const usm_params *p, char msg[USM_MSG_LEN])
{
    const char *name = imperfection_set(p);
    if (!name)
        return USM_OK;
    snprintf(msg, USM_MSG_LEN,
             "%s: must be 0 here: a stationary solution exists only for the ideal motor "
             "(a real motor has a periodic steady state: usm_periodic_solve)", name);
    return USM_EINPUT;
}

const usm_param_info *usm_params_find(const char *name)
{
    if (!name)
        return NULL;
    for (int i = 0; i < USM_NPARAMS; ++i)
        if (strcmp(usm_param_table[i].name, name) == 0)
            return &usm_param_table[i];
    return NULL;
}

double *usm_params_field(usm_params *p, const usm_param_info *info)
{
    return (double *)((char *)p + info->offset);
}

double usm_params_get(const usm_params *p, const usm_param_info *info)
{
    return *(const double *)((const char *)p + info->offset);
}

int usm_params_set(usm_params *p, const char *name, double value, char msg[USM_MSG_LEN])
{
    const usm_param_info *info = usm_params_find(name);
    if (!info) {
        snprintf(msg, USM_MSG_LEN, "%s: unknown parameter", name ? name : "(null)");
        return USM_EINPUT;
    }
    if (!isfinite(value)) {
        snprintf(msg, USM_MSG_LEN, "%s: value must be a finite number", name);
        return USM_EINPUT;
    }
    *usm_params_field(p, info) = value;
    return USM_OK;
}

int usm_params_check(const usm_params *p, const usm_model *m, char msg[USM_MSG_LEN])
{
    for (int i = 0; i < USM_NPARAMS; ++i) {
        const usm_param_info *info = &usm_param_table[i];
        double v = usm_params_get(p, info);
        if (!isfinite(v)) {
            snprintf(msg, USM_MSG_LEN, "%s: value must be a finite number", info->name);
            return USM_EINPUT;
        }
        if (usm_param_constraints[i] == USM_CONSTRAINT_POSITIVE && !(v > 0.0)) {
            snprintf(msg, USM_MSG_LEN, "%s: must be positive (%s), got %g", info->name,
                     info->description, v);
            return USM_EINPUT;
        }
        if (usm_param_constraints[i] == USM_CONSTRAINT_NONNEGATIVE && !(v >= 0.0)) {
            snprintf(msg, USM_MSG_LEN, "%s: must not be negative (%s), got %g", info->name,
                     info->description, v);
            return USM_EINPUT;
        }
        if (usm_param_constraints[i] == USM_CONSTRAINT_UNIT_INTERVAL && !(v >= 0.0 && v <= 1.0)) {
            snprintf(msg, USM_MSG_LEN, "%s: must lie in [0, 1] (%s), got %g", info->name,
                     info->description, v);
            return USM_EINPUT;
        }
    }
    if (!(fabs(p->amp_imbalance) <= 1.0)) {
        snprintf(msg, USM_MSG_LEN,
                 "amp_imbalance: must lie in [-1, 1] (phase amplitudes m0 (1 +- e) are not "
                 "negative), got %g", p->amp_imbalance);
        return USM_EINPUT;
    }
    if (!(fabs(p->mode_split) < 1.0)) {
        snprintf(msg, USM_MSG_LEN,
                 "mode_split: must lie in (-1, 1) (tilt stiffnesses c_r (1 +- s) positive), got %g",
                 p->mode_split);
        return USM_EINPUT;
    }
    if (m && !m->imperfect && usm_params_check_ideal(p, msg) != USM_OK) {
        snprintf(msg, USM_MSG_LEN,
                 "%s: must be 0 in model %s, an ideal motor (the variant imperfect models it)",
                 imperfection_set(p), m->name);
        return USM_EINPUT;
    }
    for (int i = 0; m && i < USM_NPARAMS; ++i) {
        const usm_param_coupling *c = usm_param_coupled(m, i);
        const usm_param_info *to = c ? &usm_param_table[c->equals] : NULL;
        if (c && usm_params_get(p, &usm_param_table[i]) != usm_params_get(p, to)) {
            snprintf(msg, USM_MSG_LEN, "%s: must equal %s (%g) in model %s, which assumes %s",
                     usm_param_table[i].name, to->name, usm_params_get(p, to), m->name,
                     c->because);
            return USM_EINPUT;
        }
    }
    return USM_OK;
}
