/* Sensitivities as numbers a person reads: elasticities (usm_design.h) and
 * the outputs of `usm sensitivity` (usm_io.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <jansson.h>

#include "io/json_out.h"
#include "usm_design.h"
#include "usm_io.h"

double usm_sensitivity_elasticity(const usm_params *p, const usm_sensitivity_result *r, int k,
                                  int j)
{
    const double y = r->value[k], pj = usm_params_get(p, &usm_param_table[j]);
    if (!r->defined[k] || y == 0)
        return NAN;
    if (r->d[k][j] == 0)
        return 0.0; /* not -0 */
    return pj / y * r->d[k][j];
}

static json_t *output_json(const usm_params *p, const usm_sensitivity_result *r, int k)
{
    json_t *obj = json_object(), *d = json_object(), *e = json_object();
    int ok = obj && d && e;
    usm_json_put(obj, "value", usm_json_real(r->value[k]), &ok);
    for (int j = 0; j < USM_NPARAMS; ++j) {
        const char *name = usm_param_table[j].name;
        usm_json_put(d, name, r->defined[k] ? usm_json_real(r->d[k][j]) : json_null(), &ok);
        usm_json_put(e, name, usm_json_real(usm_sensitivity_elasticity(p, r, k, j)), &ok);
    }
    usm_json_put(obj, "d", d, &ok);
    usm_json_put(obj, "elasticity", e, &ok);
    if (!r->defined[k])
        usm_json_put(obj, "undefined", json_string(r->why[k]), &ok);
    return usm_json_finish(obj, ok);
}

int usm_sensitivity_write_json(const usm_model *m, const usm_params *p,
                               const usm_sensitivity_result *r, const int want[USM_SENS_COUNT],
                               FILE *out)
{
    json_t *obj = json_object(), *outs = json_object();
    int ok = obj && outs;
    usm_json_put(obj, "model", json_string(m->name), &ok);
    usm_json_put(obj, "parameters", usm_json_params(p), &ok);
    for (int k = 0; k < USM_SENS_COUNT; ++k)
        if (want[k]) {
            json_t *o = output_json(p, r, k);
            if (!o)
                ok = 0;
            usm_json_put(outs, usm_sensitivity_output_name(k), o, &ok);
        }
    usm_json_put(obj, "outputs", outs, &ok);
    return usm_json_write(usm_json_finish(obj, ok), out);
}

typedef struct ranked {
    int j;
    double e;
} ranked;

static int by_abs_desc(const void *x, const void *y)
{
    const ranked *a = x, *b = y;
    double ea = isnan(a->e) ? -1 : fabs(a->e), eb = isnan(b->e) ? -1 : fabs(b->e);
    if (ea != eb)
        return (ea < eb) - (ea > eb);
    return a->j - b->j;
}

void usm_sensitivity_write_table(const usm_model *m, const usm_params *p,
                                 const usm_sensitivity_result *r, const int want[USM_SENS_COUNT],
                                 FILE *out)
{
    fprintf(out, "model %s: %s\n", m->name, m->description);
    fprintf(out, "sensitivities of the primary stationary solution (elasticity = (p/y) dy/dp)\n");
    for (int k = 0; k < USM_SENS_COUNT; ++k) {
        if (!want[k])
            continue;
        fprintf(out, "\n%s = %.10g\n", usm_sensitivity_output_name(k), r->value[k]);
        if (!r->defined[k]) {
            fprintf(out, "  undefined: %s\n", r->why[k]);
            continue;
        }
        ranked rk[USM_NPARAMS];
        for (int j = 0; j < USM_NPARAMS; ++j)
            rk[j] = (ranked){j, usm_sensitivity_elasticity(p, r, k, j)};
        qsort(rk, USM_NPARAMS, sizeof rk[0], by_abs_desc);
        int width = 5; /* "param", or the longest name: the columns stay aligned */
        for (int j = 0; j < USM_NPARAMS; ++j)
            if ((int)strlen(usm_param_table[j].name) > width)
                width = (int)strlen(usm_param_table[j].name);
        fprintf(out, "  %-*s %-20s %-20s\n", width, "param", "elasticity", "dy/dp");
        for (int j = 0; j < USM_NPARAMS; ++j)
            fprintf(out, "  %-*s %-20.10g %-20.10g\n", width, usm_param_table[rk[j].j].name, rk[j].e,
                    r->d[k][rk[j].j]);
    }
}
