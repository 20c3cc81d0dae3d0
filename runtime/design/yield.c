/* The yield of a design with common random numbers (usm_robust.h): one fixed
 * set of standard variates, scaled to each design's nominal values, each
 * sample's operating point by usm_point_evaluate_op on the worker pool,
 * judged by the rule of `usm tolerance` (yield_rule.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#include <gsl/gsl_sort.h>

#include "core/pool_internal.h"
#include "usm_map.h"
#include "usm_robust.h"
#include "yield_rule.h"

#define MAX_SAMPLES 10000000ULL

struct usm_yield {
    const usm_model *m;
    int nscatter;
    usm_tolerance_vary scatter[USM_ROBUST_MAX_SCATTER];
    uint64_t n;
    double *z;           /* n x nscatter standard variates: the common random numbers */
    int nspec;
    usm_opt_constraint spec[USM_OPT_MAX_CONSTRAINTS];
    int allow_driven;    /* a sample the load drives (power_out < 0) may be good */
    /* the last evaluation */
    usm_params p;
    double t0;
    int track;
    double *value;       /* the tracked output per sample (NaN: no operating point) */
    unsigned char *good;
    unsigned char *driven; /* not good only because the load drives the rotor */
    unsigned char *unphysical;
    double *sorted;      /* work for the quantiles */
    int have;
    char msg[USM_MSG_LEN];
};

usm_yield *usm_yield_alloc(const usm_model *m, const usm_tolerance_vary *scatter, int nscatter,
                           uint64_t samples, uint64_t seed, char msg[USM_MSG_LEN])
{
    if (!m || nscatter < 1 || nscatter > USM_ROBUST_MAX_SCATTER || !scatter) {
        snprintf(msg, USM_MSG_LEN, "scatter: 1 to %d --scatter NAME=DIST needed",
                 USM_ROBUST_MAX_SCATTER);
        return NULL;
    }
    if (samples < 1 || samples > MAX_SAMPLES) {
        snprintf(msg, USM_MSG_LEN, "samples: must be 1 to %llu, got %llu",
                 (unsigned long long)MAX_SAMPLES, (unsigned long long)samples);
        return NULL;
    }
    for (int j = 0; j < nscatter; ++j) {
        if (!scatter[j].param) {
            snprintf(msg, USM_MSG_LEN, "scatter: %d: no parameter", j);
            return NULL;
        }
        for (int k = 0; k < j; ++k)
            if (scatter[k].param == scatter[j].param) {
                snprintf(msg, USM_MSG_LEN, "scatter: %s given twice", scatter[j].param->name);
                return NULL;
            }
        const usm_param_coupling *c = usm_param_coupled(m, usm_param_index(scatter[j].param));
        if (c) {
            snprintf(msg, USM_MSG_LEN, "scatter: %s equals %s in model %s; scatter %s",
                     scatter[j].param->name, usm_param_table[c->equals].name, m->name,
                     usm_param_table[c->equals].name);
            return NULL;
        }
    }
    usm_yield *y = calloc(1, sizeof *y);
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    if (y) {
        y->z = malloc(samples * (size_t)nscatter * sizeof *y->z);
        y->value = malloc(samples * sizeof *y->value);
        y->sorted = malloc(samples * sizeof *y->sorted);
        y->good = malloc(samples);
        y->driven = malloc(samples);
        y->unphysical = malloc(samples);
    }
    if (!y || !r || !y->z || !y->value || !y->sorted || !y->good || !y->driven ||
        !y->unphysical) {
        gsl_rng_free(r);
        usm_yield_free(y);
        snprintf(msg, USM_MSG_LEN, "samples: out of memory for %llu samples",
                 (unsigned long long)samples);
        return NULL;
    }
    y->m = m;
    y->nscatter = nscatter;
    memcpy(y->scatter, scatter, (size_t)nscatter * sizeof *scatter);
    y->n = samples;
    /* the common random numbers: drawn once, serially (independent of threads);
     * mt19937 takes the seed modulo 2^32, 0 meaning its default 4357 */
    gsl_rng_set(r, (unsigned long)(seed ^ (seed >> 32)));
    for (uint64_t i = 0; i < samples; ++i)
        for (int j = 0; j < nscatter; ++j)
            y->z[i * (uint64_t)nscatter + (uint64_t)j] =
                scatter[j].kind == USM_DIST_NORMAL ? gsl_ran_gaussian_ziggurat(r, 1.0)
                                                   : 2.0 * gsl_rng_uniform(r) - 1.0;
    gsl_rng_free(r);
    return y;
}

void usm_yield_free(usm_yield *y)
{
    if (!y)
        return;
    free(y->z);
    free(y->value);
    free(y->sorted);
    free(y->good);
    free(y->driven);
    free(y->unphysical);
    free(y);
}

int usm_yield_spec_add(usm_yield *y, int k, int upper, double bound)
{
    if (y->nspec >= USM_OPT_MAX_CONSTRAINTS || !usm_opt_output_name(k) || !isfinite(bound)) {
        snprintf(y->msg, USM_MSG_LEN, "spec: unknown output, bound not finite or too many");
        return USM_EINPUT;
    }
    y->spec[y->nspec++] = (usm_opt_constraint){k, upper != 0, bound, 0};
    return USM_OK;
}

void usm_yield_allow_driven(usm_yield *y, int allow) { y->allow_driven = allow != 0; }

const char *usm_yield_message(const usm_yield *y) { return y->msg; }

/* ---- the samples on the pool --------------------------------------------------------- */

typedef struct worker {
    usm_steady *steady;
    usm_floquet *floquet;
} worker;

static void *worker_alloc(void *ctx)
{
    const usm_yield *y = ctx;
    worker *w = calloc(1, sizeof *w);
    if (!w)
        return NULL;
    w->steady = usm_steady_alloc(y->m);
    w->floquet = usm_floquet_alloc(y->m);
    if (!w->steady || !w->floquet) {
        usm_steady_free(w->steady);
        usm_floquet_free(w->floquet);
        free(w);
        return NULL;
    }
    return w;
}

static void worker_free(void *state)
{
    worker *w = state;
    usm_steady_free(w->steady);
    usm_floquet_free(w->floquet);
    free(w);
}

#define TASK 64 /* samples per task */

static int task(void *ctx, void *state, size_t t)
{
    usm_yield *y = ctx;
    worker *w = state;
    usm_floquet_options fo;
    usm_op_options oo;
    usm_floquet_options_default(&fo);
    usm_op_options_default(&oo);
    const uint64_t first = (uint64_t)t * TASK;
    const uint64_t last = first + TASK < y->n ? first + TASK : y->n;
    for (uint64_t i = first; i < last; ++i) {
        usm_params q = y->p;
        char why[USM_MSG_LEN];
        const double *z = y->z + i * (uint64_t)y->nscatter;
        for (int j = 0; j < y->nscatter; ++j) {
            const usm_tolerance_vary *v = &y->scatter[j];
            const double nominal = usm_params_get(&y->p, v->param);
            double x;
            if (v->kind == USM_DIST_NORMAL)
                x = v->relative ? nominal * (1.0 + v->width * z[j]) : nominal + v->width * z[j];
            else if (v->relative)
                x = nominal * (1.0 + v->width * z[j]);
            else
                x = v->lo + (v->hi - v->lo) * 0.5 * (z[j] + 1.0);
            *usm_params_field(&q, v->param) = x;
            usm_params_couple(y->m, &q, usm_param_index(v->param));
        }
        y->value[i] = NAN;
        y->good[i] = y->driven[i] = 0;
        y->unphysical[i] = usm_params_check(&q, y->m, why) != USM_OK;
        if (y->unphysical[i])
            continue;
        usm_point pt;
        if (usm_point_evaluate_op(w->steady, w->floquet, y->m, &q, y->t0, &fo, &oo, &pt) !=
            USM_OK)
            continue; /* bad parameters after all: not good */
        if (pt.op.index < 0 || !(pt.op.floquet.max_modulus < 1.0))
            continue;
        const usm_steady_solution *sol = &pt.op.sol;
        const double mm = pt.op.floquet.max_modulus;
        /* untracked: 0 marks a sample with an operating point */
        y->value[i] = y->track >= 0 ? usm_opt_output_value(y->track, sol, &q, mm) : 0.0;
        int meets = 1, driven;
        for (int s = 0; s < y->nspec && meets; ++s) {
            const double v = usm_opt_output_value(y->spec[s].output, sol, &q, mm);
            meets = y->spec[s].upper ? v <= y->spec[s].value : v >= y->spec[s].value;
        }
        /* the rule of `usm tolerance` (yield_rule.h) */
        y->good[i] = (unsigned char)yield_sample_good(1, mm, sol->validity == USM_VALID, meets,
                                                      sol->power_out, y->allow_driven, &driven);
        y->driven[i] = (unsigned char)driven;
    }
    return USM_OK;
}

int usm_yield_eval(usm_yield *y, const usm_params *p, double t0, int threads, int track,
                   usm_yield_result *r)
{
    char why[USM_MSG_LEN];
    y->msg[0] = '\0';
    y->have = 0;
    memset(r, 0, sizeof *r);
    if (threads < 1 || threads > POOL_MAX_THREADS) {
        snprintf(y->msg, USM_MSG_LEN, "threads: must be 1 to %d", POOL_MAX_THREADS);
        return USM_EINPUT;
    }
    if (track >= 0 && !usm_opt_output_name(track)) {
        snprintf(y->msg, USM_MSG_LEN, "output: %d unknown", track);
        return USM_EINPUT;
    }
    if (usm_params_check(p, y->m, why) != USM_OK) {
        snprintf(y->msg, USM_MSG_LEN, "%s", why);
        return USM_EINPUT;
    }
    for (int j = 0; j < y->nscatter; ++j)
        if (y->scatter[j].relative && usm_params_get(p, y->scatter[j].param) == 0) {
            snprintf(y->msg, USM_MSG_LEN, "scatter: %s: a relative width of a parameter whose "
                     "nominal value is 0", y->scatter[j].param->name);
            return USM_EINPUT;
        }
    y->p = *p;
    y->t0 = t0;
    y->track = track;
    pool_job job = {(size_t)((y->n + TASK - 1) / TASK), threads, y, worker_alloc, worker_free,
                    task, NULL};
    int status = pool_run(&job, y->msg);
    if (status != USM_OK)
        return status;
    double sum = 0;
    r->samples = y->n;
    for (uint64_t i = 0; i < y->n; ++i) {
        r->good += y->good[i];
        r->driven += y->driven[i];
        r->unphysical += y->unphysical[i];
        if (!isnan(y->value[i])) {
            r->op++;
            sum += y->value[i];
        }
    }
    r->yield = (double)r->good / (double)y->n;
    usm_tolerance_wilson(r->good, y->n, &r->yield_lo, &r->yield_hi);
    r->mean = track >= 0 && r->op ? sum / (double)r->op : NAN;
    y->have = 1;
    return USM_OK;
}

double usm_yield_quantile(usm_yield *y, double q, int larger_better)
{
    if (!y->have || y->track < 0 || !(q > 0 && q < 1))
        return NAN;
    const double worst = larger_better ? -INFINITY : INFINITY;
    for (uint64_t i = 0; i < y->n; ++i)
        y->sorted[i] = isnan(y->value[i]) ? worst : y->value[i];
    gsl_sort(y->sorted, 1, y->n);
    uint64_t k = (uint64_t)ceil(q * (double)y->n);
    k = k < 1 ? 1 : k > y->n ? y->n : k;
    return y->sorted[k - 1];
}

int usm_yield_sample(const usm_yield *y, uint64_t i, double *value, int *good)
{
    if (!y->have || i >= y->n)
        return USM_EINPUT;
    if (value)
        *value = y->value[i];
    if (good)
        *good = y->good[i];
    return USM_OK;
}
