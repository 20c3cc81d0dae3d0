/* The outputs of `usm fit` (usm_io.h): its --json object, its table for
 * people and the CSV of the residuals per measured value. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <jansson.h>

#include "io/csv_out.h"
#include "io/json_out.h"
#include "usm_fit.h"
#include "usm_io.h"

static const char *pname(const usm_fit_result *r, int j)
{
    return usm_param_table[r->fit[j]].name;
}

/* The undetermined combination in words: "mu0^1 kappa^-1" style exponents
 * of the direction in log scale (a linear parameter: its change). */
static json_t *combination_json(const usm_fit_result *r, const usm_fit_unidentified *u)
{
    json_t *c = json_object();
    int ok = c != NULL;
    for (int j = 0; j < r->nfit; ++j)
        if (u->direction[j] != 0)
            usm_json_put(c, pname(r, j), usm_json_real(u->direction[j]), &ok);
    return usm_json_finish(c, ok);
}

static json_t *advice_json(const usm_fit_data *d, const usm_fit_unidentified *u)
{
    if (!u->advice)
        return json_null();
    json_t *a = json_object(), *cond = json_object();
    int ok = a && cond;
    usm_json_put(a, "output", json_string(usm_fit_output_name(u->advice_output)), &ok);
    for (int c = 0; c < d->ncond; ++c)
        usm_json_put(cond, usm_param_table[d->cond[c]].name, usm_json_real(u->advice_cond[c]),
                     &ok);
    usm_json_put(a, "conditions", cond, &ok);
    usm_json_put(a, "score", usm_json_real(u->advice_score), &ok);
    return usm_json_finish(a, ok);
}

int usm_fit_write_json(const usm_model *m, const usm_params *p, const usm_fit_data *d,
                       const usm_fit_result *r, FILE *out)
{
    json_t *obj = json_object(), *est = json_object(), *corr = json_array(),
           *sv = json_array(), *un = json_array(), *pts = json_array(), *names = json_array();
    int ok = obj && est && corr && sv && un && pts && names;
    usm_json_put(obj, "model", json_string(m->name), &ok);
    usm_json_put(obj, "parameters", usm_json_params(p), &ok);
    for (int j = 0; j < r->nfit; ++j) {
        json_t *e = json_object(), *row = json_array();
        ok = ok && e && row;
        if (names && json_array_append_new(names, json_string(pname(r, j))) != 0)
            ok = 0;
        usm_json_put(e, "estimate", usm_json_real(r->estimate[j]), &ok);
        usm_json_put(e, "standard_error", usm_json_real(r->se[j]), &ok);
        usm_json_put(e, "ci95", json_pack("[oo]", usm_json_real(r->lo[j]), usm_json_real(r->hi[j])),
                     &ok);
        usm_json_put(e, "ci95_profile",
                     r->profiled[j] ? json_pack("[oo]", usm_json_real(r->profile_lo[j]),
                                                usm_json_real(r->profile_hi[j]))
                                    : json_null(),
                     &ok);
        usm_json_put(e, "start", usm_json_real(r->start[j]), &ok);
        usm_json_put(e, "scale", json_string(r->log_scale[j] ? "log" : "linear"), &ok);
        usm_json_put(e, "unit", json_string(usm_param_table[r->fit[j]].unit), &ok);
        usm_json_put(est, pname(r, j), e, &ok);
        for (int k = 0; k < r->nfit; ++k)
            if (row && json_array_append_new(row, usm_json_real(r->corr[j * r->nfit + k])) != 0)
                ok = 0;
        if (corr && row && json_array_append_new(corr, row) != 0)
            ok = 0;
        if (sv && json_array_append_new(sv, usm_json_real(r->singular[j])) != 0)
            ok = 0;
    }
    usm_json_put(obj, "fitted", names, &ok);
    usm_json_put(obj, "estimates", est, &ok);
    usm_json_put(obj, "correlation", corr, &ok);
    usm_json_put(obj, "chi2", usm_json_real(r->chi2), &ok);
    usm_json_put(obj, "dof", json_integer(r->dof), &ok);
    usm_json_put(obj, "p_value", usm_json_real(r->p_value), &ok);
    usm_json_put(obj, "sigma_estimated", json_boolean(r->sigma_estimated), &ok);
    usm_json_put(obj, "sigma_scale", usm_json_real(r->sigma_scale), &ok);
    usm_json_put(obj, "interval_quantile", usm_json_real(r->quantile), &ok);
    usm_json_put(obj, "singular_values", sv, &ok);
    usm_json_put(obj, "identifiable", json_boolean(r->identifiable), &ok);
    for (int k = 0; k < r->nunidentified; ++k) {
        json_t *u = json_object();
        ok = ok && u;
        usm_json_put(u, "combination", combination_json(r, &r->unidentified[k]), &ok);
        usm_json_put(u, "singular_value", usm_json_real(r->unidentified[k].singular_value), &ok);
        usm_json_put(u, "advice", advice_json(d, &r->unidentified[k]), &ok);
        if (un && u && json_array_append_new(un, u) != 0)
            ok = 0;
    }
    usm_json_put(obj, "unidentifiable", un, &ok);
    for (int i = 0; i < r->npoints; ++i) {
        const usm_fit_point *pt = &r->points[i];
        json_t *e = json_object(), *cond = json_object();
        ok = ok && e && cond;
        usm_json_put(e, "row", json_integer(pt->row + 1), &ok);
        usm_json_put(e, "line", json_integer(d->line[pt->row]), &ok);
        for (int c = 0; c < d->ncond; ++c)
            usm_json_put(cond, usm_param_table[d->cond[c]].name,
                         usm_json_real(d->x[(size_t)pt->row * (size_t)d->ncond + (size_t)c]), &ok);
        usm_json_put(e, "conditions", cond, &ok);
        usm_json_put(e, "output", json_string(usm_fit_output_name(pt->output)), &ok);
        usm_json_put(e, "measured", usm_json_real(pt->measured), &ok);
        usm_json_put(e, "model", usm_json_real(pt->model), &ok);
        usm_json_put(e, "sigma", usm_json_real(pt->sigma), &ok);
        usm_json_put(e, "residual", usm_json_real(pt->residual), &ok);
        usm_json_put(e, "flagged", json_boolean(pt->flagged), &ok);
        usm_json_put(e, "reason", pt->flagged ? json_string(pt->reason) : json_null(), &ok);
        if (pts && e && json_array_append_new(pts, e) != 0)
            ok = 0;
    }
    usm_json_put(obj, "flagged", json_integer(r->nflagged), &ok);
    usm_json_put(obj, "points", pts, &ok);
    usm_json_put(obj, "starts", json_integer(r->starts), &ok);
    usm_json_put(obj, "best_start", json_integer(r->best_start), &ok);
    usm_json_put(obj, "starts_at_best", json_integer(r->starts_at_best), &ok);
    usm_json_put(obj, "iterations", json_integer(r->iterations), &ok);
    usm_json_put(obj, "evaluations", json_integer(r->evaluations), &ok);
    usm_json_put(obj, "wall", usm_json_real(r->wall), &ok);
    return usm_json_write(usm_json_finish(obj, ok), out);
}

/* v (SI unit si) as shown, with its unit */
static double shown(const usm_display *dsp, const char *si, double v, const char **unit)
{
    return usm_display_value(dsp, si, v, unit);
}

void usm_fit_write_table(const usm_model *m, const usm_fit_data *d, const usm_fit_result *r,
                         const usm_display *dsp, FILE *out)
{
    const char *u;
    fprintf(out, "model %s: %d parameter%s fitted to %d measured values (%d rows)\n", m->name,
            r->nfit, r->nfit == 1 ? "" : "s", r->npoints, d->nrows);
    fprintf(out, "\n  %-10s %-14s %-12s %-29s %s\n", "param", "estimate", "std. error",
            "95 % interval", "unit");
    /* the parameters in the display units too (a load torque in mN m); the
     * conversions are scales, so the standard error converts as a value */
    for (int j = 0; j < r->nfit; ++j) {
        const char *si = usm_param_table[r->fit[j]].unit;
        double e = shown(dsp, si, r->estimate[j], &u), se = shown(dsp, si, r->se[j], &u),
               lo = shown(dsp, si, r->lo[j], &u), hi = shown(dsp, si, r->hi[j], &u);
        fprintf(out, "  %-10s %-14.7g %-12.3g [%-12.6g, %-12.6g] %s%s\n", pname(r, j), e, se, lo,
                hi, u, r->log_scale[j] ? " (log scale)" : "");
    }
    for (int j = 0; j < r->nfit; ++j)
        if (r->profiled[j]) {
            const char *si = usm_param_table[r->fit[j]].unit;
            double lo = shown(dsp, si, r->profile_lo[j], &u), hi = shown(dsp, si, r->profile_hi[j], &u);
            fprintf(out, "  %-10s profile likelihood's 95 %% interval [%.6g, %.6g] %s (differs "
                    "from the Jacobian's by more than 10 %%)\n", pname(r, j), lo, hi, u);
        }
    if (r->nfit > 1) {
        fprintf(out, "\ncorrelation\n  %-10s", "");
        for (int k = 0; k < r->nfit; ++k)
            fprintf(out, " %9s", pname(r, k));
        fprintf(out, "\n");
        for (int j = 0; j < r->nfit; ++j) {
            fprintf(out, "  %-10s", pname(r, j));
            for (int k = 0; k < r->nfit; ++k) {
                /* undefined where a standard error is infinite (a combination
                 * the data do not determine, named below) */
                const double c = r->corr[j * r->nfit + k];
                if (isfinite(c))
                    fprintf(out, " %9.4f", c);
                else
                    fprintf(out, " %9s", "undefined");
            }
            fprintf(out, "\n");
        }
    }
    if (r->sigma_estimated)
        fprintf(out, "\nchi2 = %.6g, %d degrees of freedom: no sigma given, sigma estimated from "
                "the residuals (%.3g %% of each output's RMS); intervals by Student t\n",
                r->chi2, r->dof, 100 * r->sigma_scale);
    else
        fprintf(out, "\nchi2 = %.6g, %d degrees of freedom, p-value %.4g\n", r->chi2, r->dof,
                r->p_value);
    fprintf(out, "singular values (unit-norm Jacobian columns):");
    for (int j = 0; j < r->nfit; ++j)
        fprintf(out, " %.3g", r->singular[j]);
    fprintf(out, "\n%s\n", r->identifiable ? "identifiable: every parameter is determined by the data"
                                           : "NOT identifiable:");
    for (int k = 0; k < r->nunidentified; ++k) {
        const usm_fit_unidentified *un = &r->unidentified[k];
        fprintf(out, "  the data do not determine the change");
        for (int j = 0; j < r->nfit; ++j)
            if (un->direction[j] != 0)
                fprintf(out, " %+.3g %s%s", un->direction[j], r->log_scale[j] ? "log " : "",
                        pname(r, j));
        fprintf(out, " (singular value %.3g)\n", un->singular_value);
        if (un->advice) {
            fprintf(out, "  to separate them, measure %s at", usm_fit_output_name(un->advice_output));
            for (int c = 0; c < d->ncond; ++c) {
                const usm_param_info *pi = &usm_param_table[d->cond[c]];
                double v = shown(dsp, pi->unit, un->advice_cond[c], &u);
                fprintf(out, "%s %s = %.6g %s", c ? "," : "", pi->name, v, u);
            }
            fprintf(out, "\n");
        }
    }
    fprintf(out, "\nresiduals (model - measured) / sigma; %d flagged\n", r->nflagged);
    fprintf(out, "  %4s %-19s %-14s %-14s %-6s %-9s %s\n", "row", "output", "measured", "model",
            "unit", "residual", "flag");
    for (int i = 0; i < r->npoints; ++i) {
        const usm_fit_point *pt = &r->points[i];
        const char *si = usm_fit_output_unit(pt->output);
        double mv = shown(dsp, si, pt->measured, &u), mo = shown(dsp, si, pt->model, &u);
        fprintf(out, "  %4d %-19s %-14.7g %-14.7g %-6s %-9.3f %s\n", pt->row + 1,
                usm_fit_output_name(pt->output), mv, mo, u, pt->residual,
                pt->flagged ? pt->reason : "");
    }
    fprintf(out, "\n%d start%s (%d reached the best minimum), %d iterations, %d evaluations, "
            "%.3g s\n", r->starts, r->starts == 1 ? "" : "s", r->starts_at_best, r->iterations,
            r->evaluations, r->wall);
}

int usm_fit_write_csv(const usm_fit_data *d, const usm_fit_result *r, FILE *out)
{
    char b[32];
    fprintf(out, "row,line");
    for (int c = 0; c < d->ncond; ++c)
        fprintf(out, ",%s [%s]", usm_param_table[d->cond[c]].name, usm_param_table[d->cond[c]].unit);
    fprintf(out, ",output,unit,measured,model,sigma,residual,flagged,reason\n");
    for (int i = 0; i < r->npoints; ++i) {
        const usm_fit_point *pt = &r->points[i];
        fprintf(out, "%d,%ld", pt->row + 1, d->line[pt->row]);
        for (int c = 0; c < d->ncond; ++c) {
            usm_format_shortest(b, d->x[(size_t)pt->row * (size_t)d->ncond + (size_t)c]);
            fprintf(out, ",%s", b);
        }
        fprintf(out, ",%s,%s", usm_fit_output_name(pt->output), usm_fit_output_unit(pt->output));
        const double v[4] = {pt->measured, pt->model, pt->sigma, pt->residual};
        for (int k = 0; k < 4; ++k) {
            if (isfinite(v[k]))
                usm_format_shortest(b, v[k]);
            else
                b[0] = '\0';
            fprintf(out, ",%s", b);
        }
        fprintf(out, ",%d,%s\n", pt->flagged, pt->reason);
    }
    return ferror(out) ? -1 : 0;
}
