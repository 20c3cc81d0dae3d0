/* The outputs of robust design (usm_robust.h): the `usm optimize --json`
 * object of a robust run and its table for people (usm_io.h), and the Pareto
 * front as CSV and JSON. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "io/csv_out.h"
#include "io/json_out.h"
#include "optimize_json.h"
#include "usm_io.h"
#include "usm_robust.h"

static json_t *pair(double a, double b, int *ok)
{
    json_t *v = json_array();
    if (!v || json_array_append_new(v, usm_json_real(a)) != 0 ||
        json_array_append_new(v, usm_json_real(b)) != 0)
        *ok = 0;
    return v;
}

/* One design: value, varied, the nominal operating point, the yields. */
static void put_design(json_t *obj, const usm_robust_problem *rp, const usm_robust_design *d,
                       int *ok)
{
    usm_json_put(obj, "value", usm_json_real(d->value), ok);
    usm_json_put(obj, "nominal_value", usm_json_real(d->nominal_value), ok);
    usm_json_put(obj, "varied", usm_opt_json_varied(&rp->nominal, &d->params, ok), ok);
    json_t *op = json_object();
    if (!op)
        *ok = 0;
    usm_json_put(op, "speed", usm_json_real(d->speed), ok);
    usm_json_put(op, "efficiency", usm_json_real(d->efficiency), ok);
    usm_json_put(op, "power_out", usm_json_real(d->power_out), ok);
    usm_json_put(op, "max_modulus", usm_json_real(d->max_modulus), ok);
    usm_json_put(obj, "nominal_operating_point", op, ok);
    if (rp->nscatter > 0) {
        usm_json_put(obj, "yield", usm_json_real(d->yield), ok);
        usm_json_put(obj, "yield_ci", pair(d->yield_lo, d->yield_hi, ok), ok);
        usm_json_put(obj, "samples", json_integer((json_int_t)d->verify_samples), ok);
        usm_json_put(obj, "crn_yield", usm_json_real(d->crn_yield), ok);
    }
}

static const char *stat_name(const usm_robust_problem *rp, char buf[32])
{
    if (rp->stat == USM_ROBUST_STAT_MEAN)
        return "mean";
    if (rp->stat == USM_ROBUST_STAT_QUANTILE) {
        snprintf(buf, 32, "q%02.0f", rp->quantile * 100);
        return buf;
    }
    return "nominal";
}

int usm_robust_write_json(const usm_model *m, const usm_robust_problem *rp,
                          const usm_robust_result *res, FILE *out)
{
    char sbuf[32];
    json_t *obj = json_object();
    int ok = obj != NULL;
    usm_json_put(obj, "model", json_string(m->name), &ok);
    usm_json_put(obj, "feasible", json_boolean(res->robust.feasible), &ok);
    usm_json_put(obj, "objective", json_string(usm_robust_quantity_name(rp->objective)), &ok);
    usm_json_put(obj, "statistic", json_string(stat_name(rp, sbuf)), &ok);
    const int maximize = rp->objective == USM_ROBUST_YIELD || !rp->nominal.minimize;
    usm_json_put(obj, "sense", json_string(maximize ? "max" : "min"), &ok);
    if (rp->qopt.range.param >= 0) {
        json_t *r = json_object();
        if (!r)
            ok = 0;
        usm_json_put(r, "parameter", json_string(usm_param_table[rp->qopt.range.param].name),
                     &ok);
        usm_json_put(r, "from", usm_json_real(rp->qopt.range.lo), &ok);
        usm_json_put(r, "to", usm_json_real(rp->qopt.range.hi), &ok);
        usm_json_put(r, "points", json_integer(rp->qopt.range.points), &ok);
        usm_json_put(r, "statistic", json_string(usm_range_stat_name(rp->qopt.range.stat)), &ok);
        usm_json_put(obj, "over_range", r, &ok);
    }
    put_design(obj, rp, &res->robust, &ok);
    usm_json_put(obj, "parameters", usm_json_params(&res->robust.params), &ok);
    usm_json_put(obj, "active_constraints",
                 usm_opt_json_strings(res->nactive, res->active, &ok), &ok);
    usm_json_put(obj, "evaluations", json_integer(res->evaluations), &ok);
    if (rp->nscatter > 0) {
        usm_json_put(obj, "verified", json_boolean(res->verified), &ok);
        json_t *crn = json_object();
        if (!crn)
            ok = 0;
        usm_json_put(crn, "samples", json_integer((json_int_t)rp->samples), &ok);
        usm_json_put(crn, "seed", json_integer((json_int_t)rp->seed), &ok);
        usm_json_put(crn, "yield", usm_json_real(res->robust.crn_yield), &ok);
        usm_json_put(obj, "crn", crn, &ok);
        usm_json_put(obj, "verify_seed", json_integer((json_int_t)(rp->seed + 1)), &ok);
    }
    if (res->nominal.feasible) {
        json_t *nom = json_object();
        if (!nom)
            ok = 0;
        put_design(nom, rp, &res->nominal, &ok);
        usm_json_put(obj, "nominal_optimum", nom, &ok);
    }
    usm_json_put(obj, "seconds", usm_json_real(res->seconds), &ok);
    return usm_json_write(usm_json_finish(obj, ok), out);
}

/* ---- the Pareto front ------------------------------------------------------------ */

int usm_pareto_write_csv(const usm_opt_problem *pb, const int obj[2],
                         const usm_pareto_result *res, FILE *out)
{
    usm_csv_column cols[3 + USM_NPARAMS + 1];
    int n = 0;
    cols[n++] = (usm_csv_column){"point", NULL};
    for (int i = 0; i < 2; ++i)
        cols[n++] = (usm_csv_column){usm_opt_output_name(obj[i]), usm_opt_output_unit(obj[i])};
    for (int j = 0; j < pb->nvary; ++j)
        cols[n++] = (usm_csv_column){usm_param_table[pb->vary[j]].name,
                                     usm_param_table[pb->vary[j]].unit};
    cols[n++] = (usm_csv_column){"active", NULL};
    usm_csv_header(out, cols, n);
    for (int k = 0; k < res->npoints; ++k) {
        const usm_pareto_point *pt = &res->points[k];
        char active[USM_OPT_MAX_ACTIVE * 8] = "";
        size_t len = 0;
        fprintf(out, "%d", k);
        usm_csv_num(out, 0, pt->f[0]);
        usm_csv_num(out, 0, pt->f[1]);
        for (int j = 0; j < pb->nvary; ++j)
            usm_csv_num(out, 0, usm_params_get(&pt->params, &usm_param_table[pb->vary[j]]));
        for (int i = 0; i < pt->nactive && len < sizeof active; ++i) {
            int w = snprintf(active + len, sizeof active - len, "%s%s", i ? "; " : "",
                             pt->active[i]);
            len += w > 0 ? (size_t)w : 0;
        }
        usm_csv_text(out, 0, active);
        fputc('\n', out);
    }
    return ferror(out) ? -1 : 0;
}

int usm_pareto_write_json(const usm_opt_problem *pb, const int obj[2], const int minimize[2],
                          const usm_pareto_result *res, FILE *out)
{
    json_t *o = json_object(), *names = json_array(), *senses = json_array(),
           *pts = json_array();
    int ok = o && names && senses && pts;
    for (int i = 0; ok && i < 2; ++i)
        if (json_array_append_new(names, json_string(usm_opt_output_name(obj[i]))) != 0 ||
            json_array_append_new(senses, json_string(minimize[i] ? "min" : "max")) != 0)
            ok = 0;
    for (int k = 0; ok && k < res->npoints; ++k) {
        const usm_pareto_point *pt = &res->points[k];
        json_t *p = json_object();
        if (!p || json_array_append_new(pts, p) != 0) {
            ok = 0;
            break;
        }
        usm_json_put(p, usm_opt_output_name(obj[0]), usm_json_real(pt->f[0]), &ok);
        usm_json_put(p, usm_opt_output_name(obj[1]), usm_json_real(pt->f[1]), &ok);
        usm_json_put(p, "design", usm_opt_json_varied(pb, &pt->params, &ok), &ok);
        usm_json_put(p, "active_constraints",
                     usm_opt_json_strings(pt->nactive, pt->active, &ok), &ok);
    }
    usm_json_put(o, "objectives", names, &ok);
    usm_json_put(o, "senses", senses, &ok);
    usm_json_put(o, "points", pts, &ok);
    usm_json_put(o, "computed", json_integer(res->computed), &ok);
    usm_json_put(o, "seconds", usm_json_real(res->seconds), &ok);
    return usm_json_write(usm_json_finish(o, ok), out);
}

/* One design of the robust table, under its title. */
static void table_design(const usm_robust_problem *rp, const char *title,
                         const usm_robust_design *d, FILE *out)
{
    char stat[32] = "";
    if (rp->stat == USM_ROBUST_STAT_MEAN)
        snprintf(stat, sizeof stat, "mean:");
    else if (rp->stat == USM_ROBUST_STAT_QUANTILE)
        snprintf(stat, sizeof stat, "q%02.0f:", 100 * rp->quantile);
    fprintf(out, "\n%s: %s%s = %.10g", title, stat, usm_robust_quantity_name(rp->objective),
            d->value);
    if (stat[0])
        fprintf(out, " (nominal %s %.10g)", usm_robust_quantity_name(rp->objective),
                d->nominal_value);
    fprintf(out, "\n");
    for (int j = 0; j < rp->nominal.nvary; ++j) {
        const usm_param_info *info = &usm_param_table[rp->nominal.vary[j]];
        fprintf(out, "  %-6s %-20.10g in [%g, %g] %s\n", info->name,
                usm_params_get(&d->params, info), rp->nominal.lo[j], rp->nominal.hi[j],
                info->unit);
    }
    fprintf(out, "  nominal operating point: speed %.6g 1/s, efficiency %.6g, power_out %.6g W, "
            "max_modulus %.6g\n", d->speed, d->efficiency, d->power_out, d->max_modulus);
    if (rp->nscatter > 0)
        fprintf(out, "  yield %.5f (95 %% Wilson [%.5f, %.5f], %llu fresh samples); "
                "common-random-number yield %.5f (%llu samples)\n", d->yield, d->yield_lo,
                d->yield_hi, (unsigned long long)d->verify_samples, d->crn_yield,
                (unsigned long long)rp->samples);
}

void usm_robust_write_table(const usm_model *m, const usm_robust_problem *rp,
                            const usm_robust_result *res, FILE *out)
{
    fprintf(out, "model %s: %s\n", m->name, m->description);
    table_design(rp, "robust optimum", &res->robust, out);
    fprintf(out, "  active:");
    for (int i = 0; i < res->nactive; ++i)
        fprintf(out, "%s %s", i ? ";" : "", res->active[i]);
    fprintf(out, "%s\n", res->nactive ? "" : " none");
    if (rp->nscatter > 0)
        fprintf(out, "  verified: %s\n", res->verified ? "yes" : "no");
    if (res->nominal.feasible)
        table_design(rp, "nominal optimum (no scatter)", &res->nominal, out);
    fprintf(out, "\n%d designs evaluated in %.3g s\n", res->evaluations, res->seconds);
}
