/* The writers of a tolerance study: samples CSV, Markdown summary, JSON
 * (usm_tolerance.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/pool_internal.h"
#include "io/csv_out.h"
#include "tolerance_csv.h"
#include "design/tolerance_rows.h"
#include "usm_map.h"

static const int csv_order[] = {USM_TOL_EXISTS, USM_TOL_STABLE, USM_TOL_STICK_ADMISSIBLE,
                                USM_TOL_THETA, USM_TOL_ROTOR_SPEED, USM_TOL_F_N, USM_TOL_F_T,
                                USM_TOL_MAX_MODULUS, USM_TOL_EFFICIENCY};
#define NORDER ((int)(sizeof csv_order / sizeof csv_order[0]))

size_t tol_csv_row_max(const usm_tolerance *t)
{
    /* numbers <= 24 bytes and a comma; the texts (op_class, invalid_reason) < 64 each */
    return (size_t)(t->nvary + NORDER) * 26 + 256;
}

size_t tol_csv_header(const usm_tolerance *t, char *buf, size_t len)
{
    size_t n = (size_t)snprintf(buf, len, "sample");
    for (int j = 0; j < t->nvary && n < len; ++j)
        n += (size_t)snprintf(buf + n, len - n, ",%s [%s]", t->vary[j].param->name,
                              t->vary[j].param->unit);
    for (int c = 0; c < NORDER && n < len; ++c) {
        const char *unit = usm_tolerance_output_unit(csv_order[c]);
        n += (size_t)snprintf(buf + n, len - n, ",%s%s%s%s", usm_tolerance_output_name(csv_order[c]),
                              unit ? " [" : "", unit ? unit : "", unit ? "]" : "");
    }
    if (n < len)
        n += (size_t)snprintf(buf + n, len - n, ",good,redraws,operating_point,op_class,valid,"
                              "invalid_reason\n");
    return n < len ? n : len - 1;
}

/* A whole number's digits at o; the end. */
static char *whole(char *o, uint64_t v)
{
    char d[24];
    int n = 0;
    do
        d[n++] = (char)('0' + v % 10);
    while ((v /= 10) != 0);
    while (n)
        *o++ = d[--n];
    return o;
}

static char *text(char *o, const char *s)
{
    const size_t n = strlen(s);
    memcpy(o, s, n);
    return o + n;
}

/* A field of the CSV dialect (csv_out.h): the shortest text that reads back
 * exactly, empty where the value does not exist. */
static char *num(char *o, double v)
{
    *o++ = ',';
    if (isfinite(v))
        o += usm_shortest_len(o, v);
    return o;
}

static char *yesno(char *o, double v)
{
    *o++ = ',';
    if (!isnan(v))
        o = text(o, v != 0.0 ? "true" : "false");
    return o;
}

size_t tol_csv_row(const usm_tolerance *t, uint64_t i, const double *row, char *buf)
{
    char *o = whole(buf, i);
    for (int j = 0; j < t->nvary; ++j)
        o = num(o, row[j]);
    for (int c = 0; c < NORDER; ++c)
        o = csv_order[c] >= USM_TOL_NNUMERIC ? yesno(o, row[t->nvary + csv_order[c]])
                                             : num(o, row[t->nvary + csv_order[c]]);
    o = yesno(o, row[TOL_ROW_GOOD(t)] == 1.0); /* TOL_GOOD_DRIVEN: not good */
    *o++ = ',';
    o = whole(o, (uint64_t)row[TOL_ROW_REDRAWS(t)]); /* checked on load: 0 ... 9999 */
    *o++ = ',';
    if (!isnan(row[t->nvary + USM_TOL_OPERATING_POINT]))
        o = whole(o, (uint64_t)row[t->nvary + USM_TOL_OPERATING_POINT]);
    *o++ = ',';
    o = text(o, usm_point_op_class_name(
                    (usm_point_op_class)(int)row[t->nvary + USM_TOL_OP_CLASS]));
    /* a row's validity is NaN (no solution) or a usm_validity, checked on load;
     * the columns valid, invalid_reason as usm_csv_validity writes them */
    const double v = row[t->nvary + USM_TOL_VALIDITY];
    if (isnan(v))
        o = text(o, ",,");
    else {
        o = text(o, v == (double)USM_VALID ? ",true," : ",false,");
        o = text(o, usm_validity_name((usm_validity)(int)v));
    }
    *o++ = '\n';
    return (size_t)(o - buf);
}

/* The rows are formatted on the study's threads, chunk by chunk, and
 * written in order: the shortest round-trip numbers cost about 4 us of CPU a
 * row, as much as a sixth of a cheap study's computation, which runs on the
 * same threads. */
#define CSV_CHUNK_ROWS 4096
#define CSV_CHUNKS_PER_THREAD 4

typedef struct csv_batch {
    const usm_tolerance *t;
    uint64_t first;   /* the sample number of local row 0 */
    uint64_t n;       /* local rows */
    uint64_t base;    /* the batch's first local row */
    size_t max;       /* bytes of the longest row */
    char **buf;       /* one buffer per chunk of the batch */
    size_t *len;
} csv_batch;

static void *csv_state(void *ctx)
{
    return ctx; /* the chunks need no state of their own */
}

static void csv_state_free(void *state)
{
    (void)state;
}

static int csv_chunk(void *ctx, void *state, size_t k)
{
    const csv_batch *b = ctx;
    const uint64_t lo = b->base + (uint64_t)k * CSV_CHUNK_ROWS;
    const uint64_t hi = lo + CSV_CHUNK_ROWS < b->n ? lo + CSV_CHUNK_ROWS : b->n;
    size_t used = 0;
    (void)state;
    for (uint64_t i = lo; i < hi; ++i)
        used += tol_csv_row(b->t, b->first + i, b->t->rows + i * (uint64_t)b->t->width,
                            b->buf[k] + used);
    b->len[k] = used;
    return USM_OK;
}

int usm_tolerance_write_csv(const usm_tolerance *t, FILE *out)
{
    char head[4096], msg[USM_MSG_LEN];
    if (!t->have_result)
        return -1;
    const int threads = t->opt.threads < 1 ? 1 : t->opt.threads;
    const size_t chunks = (size_t)threads * CSV_CHUNKS_PER_THREAD;
    csv_batch b = {t, t->blo * USM_TOLERANCE_BLOCK, tol_local_samples(t), 0, tol_csv_row_max(t),
                   calloc(chunks, sizeof(char *)), calloc(chunks, sizeof(size_t))};
    int rc = b.buf && b.len ? 0 : -1;
    for (size_t k = 0; k < chunks && rc == 0; ++k)
        if (!(b.buf[k] = malloc(CSV_CHUNK_ROWS * b.max)))
            rc = -1;
    if (rc == 0)
        fwrite(head, 1, tol_csv_header(t, head, sizeof head), out);
    for (; rc == 0 && b.base < b.n; b.base += (uint64_t)chunks * CSV_CHUNK_ROWS) {
        const uint64_t left = b.n - b.base;
        const size_t nc = left >= (uint64_t)chunks * CSV_CHUNK_ROWS
                              ? chunks
                              : (size_t)((left + CSV_CHUNK_ROWS - 1) / CSV_CHUNK_ROWS);
        pool_job job = {nc, threads, &b, csv_state, csv_state_free, csv_chunk, NULL};
        if (pool_run(&job, msg) != USM_OK)
            rc = -1;
        for (size_t k = 0; k < nc && rc == 0; ++k)
            if (fwrite(b.buf[k], 1, b.len[k], out) != b.len[k])
                rc = -1;
    }
    for (size_t k = 0; b.buf && k < chunks; ++k)
        free(b.buf[k]);
    free(b.buf);
    free(b.len);
    return rc != 0 || ferror(out) ? -1 : 0;
}

int usm_tolerance_write_histograms(const usm_tolerance *t, FILE *out)
{
    static const int k[2] = {USM_TOL_ROTOR_SPEED, USM_TOL_MAX_MODULUS};
    if (!t->have_result)
        return -1;
    fputs("bin", out);
    for (int h = 0; h < 2; ++h) {
        const char *name = usm_tolerance_output_name(k[h]), *unit = usm_tolerance_output_unit(k[h]);
        fprintf(out, ",%s_lo [%s],%s_hi [%s],%s_count", name, unit, name, unit, name);
    }
    fputc('\n', out);
    for (int b = 0; b < TOL_HIST_BINS; ++b) {
        fprintf(out, "%d", b);
        for (int h = 0; h < 2; ++h) {
            const double lo = t->hist[h].lo, w = (t->hist[h].hi - lo) / TOL_HIST_BINS;
            /* no sample has the output: no range, no bin */
            usm_csv_num(out, 0, t->hist[h].total ? lo + w * b : NAN);
            usm_csv_num(out, 0, t->hist[h].total ? (b + 1 == TOL_HIST_BINS ? t->hist[h].hi
                                                                            : lo + w * (b + 1))
                                                 : NAN);
            fprintf(out, ",%llu", (unsigned long long)t->hist[h].count[b]);
        }
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
          "--from-rest), is valid (the model describes the motor there: the contact closed "
          "and, for a stick model, |F_t| <= mu0 F_n)", out);
    fputs(t->opt.allow_driven ? " (whether or not the motor drives its load: --allow-driven)"
                              : " and drives its load (power_out >= 0: the load does not drive "
                                "the rotor backwards)", out);
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
    if (!t->opt.allow_driven)
        fprintf(out, "Driven backwards by the load (power_out < 0; good in every other "
                "respect, so they do not count only for this): %llu.\n",
                (unsigned long long)s->driven);
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
            "\"stick_not_admissible\": %llu},\n  \"driven\": %llu,\n",
            (unsigned long long)s->failed, (unsigned long long)s->redrawn,
            (unsigned long long)s->exists, (unsigned long long)s->stable,
            (unsigned long long)s->good, (unsigned long long)s->op_exists,
            (unsigned long long)s->op_no_stable_root, (unsigned long long)s->op_does_not_start,
            (unsigned long long)s->op_unknown, (unsigned long long)s->invalid,
            (unsigned long long)s->invalid_contact_open, (unsigned long long)s->invalid_stick,
            (unsigned long long)s->driven);
    /* wall seconds, different in every run: on a line of their own, last */
    fprintf(out, "  \"timings\": {\"compute\": %.6f, \"reduce\": %.6f, \"statistics\": %.6f, "
            "\"output\": %.6f, \"compute_cpu\": %.6f, \"output_cpu\": %.6f}\n}\n",
            t->timings.compute, t->timings.reduce, t->timings.statistics, t->timings.output,
            t->timings.compute_cpu, t->timings.output_cpu);
    return ferror(out) ? -1 : 0;
}
