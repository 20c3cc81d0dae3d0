/* The `usm optimize --json` object (usm_optimize.h): the optimum, or after
 * USM_ENOSOLUTION the point of least violation; and the optimum's table for
 * people (usm_io.h). */
#include <stdio.h>

#include "io/json_out.h"
#include "optimize_json.h"
#include "steady_out.h"
#include "usm_io.h"
#include "usm_optimize.h"

json_t *usm_opt_json_strings(int n, const char (*text)[USM_OPT_TEXT_LEN], int *ok)
{
    json_t *a = json_array();
    if (!a)
        *ok = 0;
    for (int i = 0; a && i < n; ++i)
        if (json_array_append_new(a, json_string(text[i])) != 0)
            *ok = 0;
    return a;
}

json_t *usm_opt_json_varied(const usm_opt_problem *pb, const usm_params *p, int *ok)
{
    json_t *v = json_object();
    if (!v)
        *ok = 0;
    for (int j = 0; v && j < pb->nvary; ++j) {
        const usm_param_info *info = &usm_param_table[pb->vary[j]];
        usm_json_put(v, info->name, usm_json_real(usm_params_get(p, info)), ok);
    }
    return v;
}

int usm_optimize_write_json(const usm_optimize *o, const usm_model *m, const usm_opt_problem *pb,
                            const usm_opt_result *res, FILE *out)
{
    json_t *obj = json_object();
    int ok = obj != NULL;
    usm_json_put(obj, "feasible", json_boolean(res->feasible), &ok);
    usm_json_put(obj, "objective", json_string(usm_opt_output_name(pb->objective)), &ok);
    usm_json_put(obj, "sense", json_string(pb->minimize ? "min" : "max"), &ok);
    if (!res->feasible) {
        usm_json_put(obj, "least_violation", usm_json_real(res->least_violation), &ok);
        usm_json_put(obj, "violated",
                     usm_opt_json_strings(res->nviolated, res->violated, &ok), &ok);
        usm_json_put(obj, "value", usm_json_real(res->value), &ok);
        usm_json_put(obj, "varied", usm_opt_json_varied(pb, &res->params, &ok), &ok);
        usm_json_put(obj, "parameters", usm_json_params(&res->params), &ok);
        usm_json_put(obj, "evaluations", json_integer(res->evaluations), &ok);
        return usm_json_write(usm_json_finish(obj, ok), out);
    }
    json_t *mult = json_object(), *flat = json_array(), *near = json_object();
    ok = ok && mult && flat && near;
    usm_json_put(obj, "value", usm_json_real(res->value), &ok);
    usm_json_put(obj, "varied", usm_opt_json_varied(pb, &res->params, &ok), &ok);
    usm_json_put(obj, "parameters", usm_json_params(&res->params), &ok);
    usm_json_put(obj, "active_constraints",
                 usm_opt_json_strings(res->nactive, res->active, &ok), &ok);
    for (int i = 0; i < res->nactive; ++i)
        usm_json_put(mult, res->active[i], usm_json_real(res->multiplier[i]), &ok);
    usm_json_put(obj, "multipliers", mult, &ok);
    usm_json_put(obj, "kkt_residual", usm_json_real(res->kkt_residual), &ok);
    for (int j = 0; j < pb->nvary; ++j) {
        const char *name = usm_param_table[pb->vary[j]].name;
        if (res->flat[j] && json_array_append_new(flat, json_string(name)) != 0)
            ok = 0;
        json_t *iv = json_array();
        if (!iv || json_array_append_new(iv, usm_json_real(res->near_lo[j])) != 0 ||
            json_array_append_new(iv, usm_json_real(res->near_hi[j])) != 0)
            ok = 0;
        usm_json_put(near, name, iv, &ok);
    }
    usm_json_put(obj, "flat", flat, &ok);
    usm_json_put(obj, "near_optimal", near, &ok);
    usm_json_put(obj, "evaluations", json_integer(res->evaluations), &ok);
    usm_json_put(obj, "solution", usm_steady_json(&(usm_steady_report){m, &res->params,
                                                    usm_optimize_steady(o), NULL,
                                                    &res->floquet,
                                                    usm_optimize_roots_floquet(o),
                                                    usm_optimize_op(o)}),
                 &ok);
    return usm_json_write(usm_json_finish(obj, ok), out);
}

void usm_optimize_write_table(const usm_model *m, const usm_opt_problem *pb,
                              const usm_opt_result *res, FILE *out)
{
    const usm_steady_solution *s = &res->sol;
    fprintf(out, "model %s: %s\n", m->name, m->description);
    fprintf(out, "%s %s = %.10g%s\n", pb->minimize ? "minimum of" : "maximum of",
            usm_opt_output_name(pb->objective), res->value,
            pb->objective == USM_OPT_SPEED ? " 1/s (-rotor_speed: positive when driving)" : "");
    fprintf(out, "\nvaried parameters (near-optimal interval: objective within 1e-4 relative)\n");
    for (int j = 0; j < pb->nvary; ++j) {
        const usm_param_info *info = &usm_param_table[pb->vary[j]];
        fprintf(out, "  %-6s %-20.10g in [%g, %g] %s", info->name,
                usm_params_get(&res->params, info), pb->lo[j], pb->hi[j], info->unit);
        if (!pb->no_flat)
            fprintf(out, "; near-optimal in [%.6g, %.6g]%s", res->near_lo[j], res->near_hi[j],
                    res->flat[j] ? ": flat" : "");
        fprintf(out, "\n");
    }
    fprintf(out, "\nactive constraints (multiplier: change of the optimum per unit of the "
            "bound)\n");
    if (res->nactive == 0)
        fprintf(out, "  none\n");
    for (int i = 0; i < res->nactive; ++i)
        fprintf(out, "  %-34s %.6g\n", res->active[i], res->multiplier[i]);
    fprintf(out, "\nKKT residual %.3g, %d evaluations, %d starts\n", res->kkt_residual,
            res->evaluations, pb->starts);
    fprintf(out, "\nstationary solution at the optimum\n");
    fprintf(out, "  theta %.10g rad, rotor_speed %.10g 1/s, F_n %.10g N, F_t %.10g N\n",
            s->theta, s->rotor_speed, s->F_n, s->F_t);
    fprintf(out, "  power_out %.6g W, efficiency %.6g, max_modulus %.10g (t0 = %g s)\n",
            s->power_out, s->efficiency, res->floquet.max_modulus, res->floquet.t0);
    fprintf(out, "  valid %s%s%s\n", s->validity == USM_VALID ? "yes" : "no",
            s->validity == USM_VALID ? "" : ": ", usm_validity_name(s->validity));
}
