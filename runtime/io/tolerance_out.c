/* The writers of a tolerance study: samples CSV, Markdown summary, JSON
 * (usm_tolerance.h). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "csv_out.h"
#include "study/tolerance_rows.h"
#include "usm_map.h"

/* A field of the CSV dialect (csv_out.h): the shortest text that reads back
 * exactly, empty where the value does not exist. */
static void num(FILE *f, double v) { usm_csv_num(f, 0, v); }

static void yesno(FILE *f, double v)
{
    fputc(',', f);
    if (!isnan(v))
        fputs(v != 0.0 ? "true" : "false", f);
}

int usm_tolerance_write_csv(const usm_tolerance *t, FILE *out)
{
    static const int order[] = {USM_TOL_EXISTS, USM_TOL_STABLE, USM_TOL_STICK_ADMISSIBLE,
                                USM_TOL_THETA, USM_TOL_ROTOR_SPEED, USM_TOL_F_N, USM_TOL_F_T,
                                USM_TOL_MAX_MODULUS, USM_TOL_EFFICIENCY};
    if (!t->have_result)
        return -1;
    fputs("sample", out);
    for (int j = 0; j < t->nvary; ++j)
        fprintf(out, ",%s [%s]", t->vary[j].param->name, t->vary[j].param->unit);
    for (size_t c = 0; c < sizeof order / sizeof order[0]; ++c) {
        const char *unit = usm_tolerance_output_unit(order[c]);
        fprintf(out, ",%s", usm_tolerance_output_name(order[c]));
        if (unit)
            fprintf(out, " [%s]", unit);
    }
    fputs(",good,redraws,operating_point,op_class,valid,invalid_reason\n", out);
    for (uint64_t i = 0; i < t->sum.samples; ++i) {
        const double *row = t->rows + i * (uint64_t)t->width;
        fprintf(out, "%llu", (unsigned long long)i);
        for (int j = 0; j < t->nvary; ++j)
            num(out, row[j]);
        for (size_t c = 0; c < sizeof order / sizeof order[0]; ++c) {
            if (order[c] >= USM_TOL_NNUMERIC)
                yesno(out, row[t->nvary + order[c]]);
            else
                num(out, row[t->nvary + order[c]]);
        }
        yesno(out, row[TOL_ROW_GOOD(t)]);
        fprintf(out, ",%d", (int)row[TOL_ROW_REDRAWS(t)]);
        if (!isnan(row[t->nvary + USM_TOL_OPERATING_POINT]))
            fprintf(out, ",%d", (int)row[t->nvary + USM_TOL_OPERATING_POINT]);
        else
            fputc(',', out);
        fprintf(out, ",%s",
                usm_point_op_class_name((usm_point_op_class)(int)row[t->nvary + USM_TOL_OP_CLASS]));
        /* a row's validity is NaN (no solution) or a usm_validity, checked on load */
        const double v = row[t->nvary + USM_TOL_VALIDITY];
        usm_csv_validity(out, !isnan(v), isnan(v) ? USM_VALID : (usm_validity)(int)v);
        fputc('\n', out);
    }
    return ferror(out) ? -1 : 0;
}

static void dist_text(const usm_tolerance_vary *v, char buf[96])
{
    if (v->kind == USM_DIST_UNIFORM && !v->relative)
        snprintf(buf, 96, "uniform on [%.6g, %.6g]", v->lo, v->hi);
    else
        snprintf(buf, 96, "%s, %s %.6g%s", v->kind == USM_DIST_NORMAL ? "normal" : "uniform",
                 v->kind == USM_DIST_NORMAL ? "sigma" : "half-width",
                 v->relative ? 100.0 * v->width : v->width, v->relative ? " %" : "");
}

static void cell(FILE *f, double v)
{
    if (isfinite(v))
        fprintf(f, " %.6g |", v);
    else
        fputs(" - |", f);
}

int usm_tolerance_write_summary(const usm_tolerance *t, FILE *out, const char *histograms)
{
    const usm_tolerance_summary *s = &t->sum;
    char buf[96];
    if (!t->have_result)
        return -1;
    fprintf(out, "# Tolerance study\n\nModel %s; %llu samples, seed %llu; every sample is "
            "judged by its operating point (full stationary search, every root's Floquet "
            "multipliers, method %s, t0 = %g s).\n\n", t->m->name, (unsigned long long)s->samples,
            (unsigned long long)s->seed, usm_floquet_method_name(t->opt.floquet.method),
            t->opt.t0);
    fputs("| parameter | nominal | distribution |\n|---|---|---|\n", out);
    for (int j = 0; j < t->nvary; ++j) {
        dist_text(&t->vary[j], buf);
        fprintf(out, "| %s [%s] | %.6g | %s |\n", t->vary[j].param->name,
                t->vary[j].param->unit, usm_params_get(&t->p, t->vary[j].param), buf);
    }
    fprintf(out, "\nDraws outside a parameter's physical range, drawn again: %llu.\n",
            (unsigned long long)s->redrawn);
    fputs("\n## Yield\n\nA sample counts when its operating point exists (the stable root "
          "the motor runs at: the only root and stable, or the one reached from rest with "
          "--from-rest) and is valid (the model describes the motor there: the contact closed "
          "and, for a stick model, |F_t| <= mu0 F_n)", out);
    for (int k = 0; k < t->nspec; ++k)
        fprintf(out, "%s %s %s %.6g", k ? "," : " and", usm_tolerance_output_name(t->spec[k].output),
                t->spec[k].upper ? "<=" : ">=", t->spec[k].bound);
    fprintf(out, ".\n\n**Yield %.4f %%** (%llu of %llu), 95 %% confidence interval [%.4f %%, "
            "%.4f %%] (Wilson score interval).\n\n", 100.0 * s->yield,
            (unsigned long long)s->good, (unsigned long long)s->samples, 100.0 * s->yield_lo,
            100.0 * s->yield_hi);
    fprintf(out, "Samples with a stationary solution: %llu; stable: %llu; with a solution but "
            "failed multipliers: %llu.\n", (unsigned long long)s->exists,
            (unsigned long long)s->stable, (unsigned long long)s->failed);
    fprintf(out, "By the operating point: %llu have one; no stable root: %llu; do not start "
            "from rest: %llu; unknown (several roots, no simulation from rest, or "
            "undecided): %llu -- these do not count.\n",
            (unsigned long long)s->op_exists, (unsigned long long)s->op_no_stable_root,
            (unsigned long long)s->op_does_not_start, (unsigned long long)s->op_unknown);
    fprintf(out, "Outside the model's validity (the model does not describe the motor there, "
            "so they do not count): %llu (contact open: %llu; past the stick limit: %llu).\n",
            (unsigned long long)s->invalid, (unsigned long long)s->invalid_contact_open,
            (unsigned long long)s->invalid_stick);
    fputs("\n## Quantiles\n\n| output | samples | 1 % | 5 % | 50 % | 95 % | 99 % |\n"
          "|---|---|---|---|---|---|---|\n", out);
    for (int k = 0; k < USM_TOL_NNUMERIC; ++k) {
        fprintf(out, "| %s [%s] | %llu |", usm_tolerance_output_name(k),
                usm_tolerance_output_unit(k), (unsigned long long)s->count[k]);
        for (int q = 0; q < 5; ++q)
            cell(out, s->quantile[k][q]);
        fputc('\n', out);
    }
    fputs("\n## Influence\n\nSpearman rank correlation of each output with each varied "
          "parameter (over the samples where the output exists; - where undefined).\n\n"
          "| output |", out);
    for (int j = 0; j < t->nvary; ++j)
        fprintf(out, " %s |", t->vary[j].param->name);
    fputs("\n|---|", out);
    for (int j = 0; j < t->nvary; ++j)
        fputs("---|", out);
    fputc('\n', out);
    for (int k = 0; k < USM_TOL_NNUMERIC; ++k) {
        fprintf(out, "| %s |", usm_tolerance_output_name(k));
        for (int j = 0; j < t->nvary; ++j)
            cell(out, t->influence[k][j]);
        fputc('\n', out);
    }
    if (histograms)
        fprintf(out, "\n## Histograms\n\n![rotor speed and max_modulus](%s.svg)\n\nData: "
                "samples.csv.\n", histograms);
    return ferror(out) ? -1 : 0;
}

/* A JSON number with 17 significant digits (reads back bit for bit), null
 * where the value does not exist (JSON has no NaN). */
static void jreal(FILE *f, double v)
{
    char buf[40];
    if (!isfinite(v)) {
        fputs("null", f);
        return;
    }
    snprintf(buf, sizeof buf, "%.17g", v);
    fputs(buf, f);
    if (!strpbrk(buf, ".e"))
        fputs(".0", f);
}

int usm_tolerance_write_json(const usm_tolerance *t, FILE *out)
{
    static const char *const qk[5] = {"p1", "p5", "p50", "p95", "p99"};
    const usm_tolerance_summary *s = &t->sum;
    if (!t->have_result)
        return -1;
    fprintf(out, "{\n  \"samples\": %llu,\n  \"seed\": %llu,\n  \"yield\": ",
            (unsigned long long)s->samples, (unsigned long long)s->seed);
    jreal(out, s->yield);
    fputs(",\n  \"yield_ci\": [\n    ", out);
    jreal(out, s->yield_lo);
    fputs(",\n    ", out);
    jreal(out, s->yield_hi);
    fputs("\n  ],\n  \"quantiles\": {", out);
    for (int k = 0; k < USM_TOL_NNUMERIC; ++k) {
        fprintf(out, "%s\n    \"%s\": {\n      \"count\": %llu", k ? "," : "",
                usm_tolerance_output_name(k), (unsigned long long)s->count[k]);
        for (int q = 0; q < 5; ++q) {
            fprintf(out, ",\n      \"%s\": ", qk[q]);
            jreal(out, s->quantile[k][q]);
        }
        fputs("\n    }", out);
    }
    fputs("\n  },\n  \"influence\": {", out);
    for (int k = 0; k < USM_TOL_NNUMERIC; ++k) {
        fprintf(out, "%s\n    \"%s\": {", k ? "," : "", usm_tolerance_output_name(k));
        for (int j = 0; j < t->nvary; ++j) {
            fprintf(out, "%s\n      \"%s\": ", j ? "," : "", t->vary[j].param->name);
            jreal(out, t->influence[k][j]);
        }
        fputs("\n    }", out);
    }
    fprintf(out, "\n  },\n  \"failed\": %llu,\n  \"redrawn\": %llu,\n  \"exists\": %llu,\n"
            "  \"stable\": %llu,\n  \"good\": %llu,\n  \"operating_point\": {\"exists\": %llu, "
            "\"no_stable_root\": %llu, \"does_not_start\": %llu, \"unknown\": %llu},\n"
            "  \"invalid\": %llu,\n  \"invalid_reasons\": {\"contact_open\": %llu, "
            "\"stick_not_admissible\": %llu}\n}\n",
            (unsigned long long)s->failed, (unsigned long long)s->redrawn,
            (unsigned long long)s->exists, (unsigned long long)s->stable,
            (unsigned long long)s->good, (unsigned long long)s->op_exists,
            (unsigned long long)s->op_no_stable_root, (unsigned long long)s->op_does_not_start,
            (unsigned long long)s->op_unknown, (unsigned long long)s->invalid,
            (unsigned long long)s->invalid_contact_open, (unsigned long long)s->invalid_stick);
    return ferror(out) ? -1 : 0;
}
