/* Parameter defaults, lookup by name and validation. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "usm.h"
#include "units.h"

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

/* v in SI unit `si` as people read it: "1 kHz", "3.14159 rad", "0.4 N": in
 * the unit of the table that is the SI one with a metric prefix (kHz, mN, mNm,
 * um) whose scale is the largest not above |v|, else in SI; a pure number
 * without a unit. */
static void show(char *buf, size_t len, double v, const char *si)
{
    const char *plain = NULL; /* the SI unit as the table spells it ("Nm" for "N m") */
    const usm_unit_row *best = NULL;
    double best_scale = 1.0;
    for (int k = 0; k < usm_unit_rows && !plain; ++k)
        if (strcmp(usm_unit_table[k].si, si) == 0)
            plain = usm_unit_table[k].name;
    for (int k = 0; plain && v != 0.0 && k < usm_unit_rows; ++k) {
        const usm_unit_row *u = &usm_unit_table[k];
        const double scale = pow(10.0, u->exp10);
        const size_t n = strlen(u->name), np = strlen(plain);
        if (strcmp(u->si, si) != 0 || u->factor != 1.0 || u->exp10 == 0 || n != np + 1 ||
            strcmp(u->name + 1, plain) != 0 || scale > fabs(v) * (1.0 + 1e-12) ||
            (fabs(v) >= 1.0 && scale < 1.0) || (best && scale <= best_scale))
            continue;
        best = u;
        best_scale = scale;
    }
    if (strcmp(si, "1") == 0)
        snprintf(buf, len, "%g", v);
    else if (best && fabs(v) / best_scale < 1000.0 * (1.0 + 1e-12))
        snprintf(buf, len, "%g %s", v / best_scale, best->name);
    else
        snprintf(buf, len, "%g %s", v, si);
}

/* The unit value v (a number taken in SI unit `si`) was likely typed for: the
 * unit of its dimension that brings it into [lo, hi], nearest (in decades) to
 * the parameter's default (to a tenth of the range's larger end when the
 * default is 0); NULL when none does. */
static const usm_unit_row *meant_unit(double v, const char *si, double lo, double hi, double ref)
{
    const usm_unit_row *best = NULL;
    double best_score = INFINITY;
    if (ref == 0.0)
        ref = fmax(fabs(lo), fabs(hi)) / 10.0;
    for (int k = 0; v != 0.0 && k < usm_unit_rows; ++k) {
        const usm_unit_row *u = &usm_unit_table[k];
        const double w = v * pow(10.0, u->exp10) * u->factor;
        if (strcmp(u->si, si) != 0 || (u->exp10 == 0 && u->factor == 1.0) || !(w >= lo && w <= hi))
            continue;
        const double score = fabs(log10(fabs(w) / fabs(ref)));
        if (score < best_score) {
            best = u;
            best_score = score;
        }
    }
    return best;
}

int usm_param_check_value(int k, double v, char msg[USM_MSG_LEN])
{
    if (k < 0 || k >= USM_NPARAMS) {
        snprintf(msg, USM_MSG_LEN, "parameter index %d: not a parameter", k);
        return USM_EINPUT;
    }
    const usm_param_info *info = &usm_param_table[k];
    const usm_param_range *r = &usm_param_ranges[k];
    char val[64], lo[64], hi[64], hint[96] = "";
    if (!isfinite(v)) {
        snprintf(msg, USM_MSG_LEN, "%s: value must be a finite number", info->name);
        return USM_EINPUT;
    }
    /* a subnormal value is refused as the parsers refuse it (usm_parse_number) */
    if (v != 0.0 && fabs(v) < DBL_MIN) {
        snprintf(msg, USM_MSG_LEN, "%s: %g is out of range for a double (underflow: its "
                 "magnitude is below %.3g, the smallest normal double)", info->name, v, DBL_MIN);
        return USM_EINPUT;
    }
    if (usm_param_constraints[k] == USM_CONSTRAINT_POSITIVE && !(v > 0.0)) {
        snprintf(msg, USM_MSG_LEN, "%s: must be positive (%s), got %g", info->name,
                 info->description, v);
        return USM_EINPUT;
    }
    if (usm_param_constraints[k] == USM_CONSTRAINT_NONNEGATIVE && !(v >= 0.0)) {
        snprintf(msg, USM_MSG_LEN, "%s: must not be negative (%s), got %g", info->name,
                 info->description, v);
        return USM_EINPUT;
    }
    if (usm_param_constraints[k] == USM_CONSTRAINT_UNIT_INTERVAL && !(v >= 0.0 && v <= 1.0)) {
        snprintf(msg, USM_MSG_LEN, "%s: must lie in [0, 1] (%s), got %g", info->name,
                 info->description, v);
        return USM_EINPUT;
    }
    if (v >= r->lo && v <= r->hi)
        return USM_OK;
    /* a value typed in the wrong unit: say which range and which unit it was
     * likely meant in; an angle beyond a turn is one in degrees */
    const usm_unit_row *u = meant_unit(v, info->unit, r->lo, r->hi, usm_param_defaults[k]);
    if (u)
        snprintf(hint, sizeof hint, "; did you mean %g %s?", v, u->name);
    else if (strcmp(info->unit, "rad") == 0)
        snprintf(hint, sizeof hint, "; an angle needs its unit (rad or deg)");
    show(val, sizeof val, v, info->unit);
    show(lo, sizeof lo, r->lo, info->unit);
    show(hi, sizeof hi, r->hi, info->unit);
    /* a hint cut short at the message's length still names the field first */
    if (snprintf(msg, USM_MSG_LEN, "%s = %s is outside %s..%s%s", info->name, val, lo, hi, hint) >=
        USM_MSG_LEN)
        msg[USM_MSG_LEN - 1] = '\0';
    return USM_EINPUT;
}

int usm_params_set(usm_params *p, const char *name, double value, char msg[USM_MSG_LEN])
{
    const usm_param_info *info = usm_params_find(name);
    if (!info) {
        snprintf(msg, USM_MSG_LEN, "%s: unknown parameter", name ? name : "(null)");
        return USM_EINPUT;
    }
    if (usm_param_check_value(usm_param_index(info), value, msg) != USM_OK)
        return USM_EINPUT;
    *usm_params_field(p, info) = value;
    return USM_OK;
}

int usm_params_check(const usm_params *p, const usm_model *m, char msg[USM_MSG_LEN])
{
    /* the imperfections' own bounds first: they say why */
    if (isfinite(p->amp_imbalance) && !(fabs(p->amp_imbalance) <= 1.0)) {
        snprintf(msg, USM_MSG_LEN,
                 "amp_imbalance: must lie in [-1, 1] (phase amplitudes m0 (1 +- e) are not "
                 "negative), got %g", p->amp_imbalance);
        return USM_EINPUT;
    }
    if (isfinite(p->mode_split) && !(fabs(p->mode_split) < 1.0)) {
        snprintf(msg, USM_MSG_LEN,
                 "mode_split: must lie in (-1, 1) (tilt stiffnesses c_r (1 +- s) positive), got %g",
                 p->mode_split);
        return USM_EINPUT;
    }
    for (int i = 0; i < USM_NPARAMS; ++i) {
        if (usm_param_check_value(i, usm_params_get(p, &usm_param_table[i]), msg) != USM_OK)
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
