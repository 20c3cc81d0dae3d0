/* The `usm optimize --json` object (usm_optimize.h). */
#include <stdio.h>

#include "json_out.h"
#include "steady_out.h"
#include "usm_optimize.h"

int usm_optimize_write_json(const usm_optimize *o, const usm_model *m, const usm_opt_problem *pb,
                            const usm_opt_result *res, FILE *out)
{
    json_t *obj = json_object(), *varied = json_object(), *act = json_array();
    int ok = obj && varied && act;
    usm_json_put(obj, "objective", json_string(usm_sensitivity_output_name(pb->objective)), &ok);
    usm_json_put(obj, "sense", json_string(pb->minimize ? "min" : "max"), &ok);
    usm_json_put(obj, "value", usm_json_real(res->value), &ok);
    for (int j = 0; j < pb->nvary; ++j) {
        const usm_param_info *info = &usm_param_table[pb->vary[j]];
        usm_json_put(varied, info->name, usm_json_real(usm_params_get(&res->params, info)), &ok);
    }
    usm_json_put(obj, "varied", varied, &ok);
    usm_json_put(obj, "parameters", usm_json_params(&res->params), &ok);
    for (int i = 0; i < res->nactive; ++i)
        if (json_array_append_new(act, json_string(res->active[i])) != 0)
            ok = 0;
    usm_json_put(obj, "active_constraints", act, &ok);
    usm_json_put(obj, "kkt_residual", usm_json_real(res->kkt_residual), &ok);
    usm_json_put(obj, "evaluations", json_integer(res->evaluations), &ok);
    usm_json_put(obj, "solution", usm_steady_json(&(usm_steady_report){m, &res->params,
                                                    usm_optimize_steady(o), NULL,
                                                    &res->floquet, NULL, NULL}),
                 &ok);
    if (!ok) {
        json_decref(obj);
        obj = NULL;
    }
    return usm_json_write(obj, out);
}
