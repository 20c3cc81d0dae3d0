/* Monte Carlo tolerance studies (usm_tolerance.h): parsing, sampling, the
 * blocks of samples on the worker pool, the serial run. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <stdarg.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include "core/grow.h"
#include "core/pool_internal.h"
#include "tolerance_internal.h"
#include "usm_map.h"
#include "yield_rule.h"

/* A sample whose draw is refused this often is a distribution that is almost
 * never physical: an input error, not a rare event. */
#define MAX_REDRAWS TOL_MAX_REDRAWS

/* ---- parsing ---------------------------------------------------------------------- */

/* A finite number that uses all of [s, end). */
static int number(const char *s, const char *end, double *v)
{
    char buf[64], *stop;
    const size_t n = (size_t)(end - s);
    if (n == 0 || n >= sizeof buf || s[0] == ' ' || s[0] == '\t')
        return -1;
    memcpy(buf, s, n);
    buf[n] = '\0';
    errno = 0;
    *v = strtod(buf, &stop);
    return *stop == '\0' && errno == 0 && isfinite(*v) ? 0 : -1;
}

int usm_tolerance_vary_parse(const char *text, usm_tolerance_vary *v, char msg[USM_MSG_LEN])
{
    static const char known[] = "normal:P%, normal:SIGMA, uniform:P%, uniform:LO:HI";
    const char *eq = text ? strchr(text, '=') : NULL;
    char name[64];
    memset(v, 0, sizeof *v);
    if (!eq || eq == text || (size_t)(eq - text) >= sizeof name) {
        snprintf(msg, USM_MSG_LEN, "\"%.64s\": expected NAME=DIST (DIST: %s)", text ? text : "",
                 known);
        return USM_EINPUT;
    }
    memcpy(name, text, (size_t)(eq - text));
    name[eq - text] = '\0';
    if (!(v->param = usm_params_find(name))) {
        snprintf(msg, USM_MSG_LEN, "%s: unknown parameter", name);
        return USM_EINPUT;
    }
    const char *d = eq + 1, *arg, *end = d + strlen(d);
    if (strncmp(d, "normal:", 7) == 0) {
        v->kind = USM_DIST_NORMAL;
        arg = d + 7;
    } else if (strncmp(d, "uniform:", 8) == 0) {
        v->kind = USM_DIST_UNIFORM;
        arg = d + 8;
    } else {
        snprintf(msg, USM_MSG_LEN, "%s: unknown distribution \"%.64s\" (known: %s)", name, d,
                 known);
        return USM_EINPUT;
    }
    const char *colon = strchr(arg, ':');
    if (colon) {
        if (v->kind != USM_DIST_UNIFORM || number(arg, colon, &v->lo) != 0 ||
            number(colon + 1, end, &v->hi) != 0) {
            snprintf(msg, USM_MSG_LEN, "%s: \"%.64s\" is not a distribution (known: %s)", name,
                     d, known);
            return USM_EINPUT;
        }
        if (!(v->lo < v->hi)) {
            snprintf(msg, USM_MSG_LEN, "%s: uniform:LO:HI needs LO < HI, got %g and %g", name,
                     v->lo, v->hi);
            return USM_EINPUT;
        }
        if (!isfinite(v->hi - v->lo)) { /* every draw would be infinite */
            snprintf(msg, USM_MSG_LEN, "%s: uniform:LO:HI: the width HI - LO overflows (%g to "
                     "%g)", name, v->lo, v->hi);
            return USM_EINPUT;
        }
        return USM_OK;
    }
    v->relative = end > arg && end[-1] == '%';
    if (number(arg, v->relative ? end - 1 : end, &v->width) != 0) {
        snprintf(msg, USM_MSG_LEN, "%s: \"%.64s\" is not a distribution (known: %s)", name, d,
                 known);
        return USM_EINPUT;
    }
    if (v->kind == USM_DIST_UNIFORM && !v->relative) {
        snprintf(msg, USM_MSG_LEN, "%s: uniform needs a relative half-width P%% or LO:HI, got "
                 "\"%.64s\"", name, d);
        return USM_EINPUT;
    }
    if (!(v->width > 0.0)) {
        snprintf(msg, USM_MSG_LEN, "%s: the %s of %s must be positive, got %g", name,
                 v->kind == USM_DIST_NORMAL ? "standard deviation" : "half-width", d, v->width);
        return USM_EINPUT;
    }
    if (v->relative)
        v->width /= 100.0;
    /* a subnormal width draws every sample at the nominal value, or rounds to 0 */
    if (!isnormal(v->width)) {
        snprintf(msg, USM_MSG_LEN, "%s: the %s of %s is %g, below the smallest normal double; "
                 "a scatter that small is none", name,
                 v->kind == USM_DIST_NORMAL ? "standard deviation" : "half-width", d, v->width);
        return USM_EINPUT;
    }
    return USM_OK;
}

int usm_tolerance_vary_check(const usm_tolerance_vary *v, const usm_model *m,
                             const usm_params *p, char msg[USM_MSG_LEN])
{
    if (!v || !v->param || !p) {
        snprintf(msg, USM_MSG_LEN, "scatter: %s", !p ? "no parameters" : "no parameter");
        return USM_EINPUT;
    }
    const usm_param_info *info = v->param;
    const int k = usm_param_index(info);
    const double nominal = usm_params_get(p, info);
    const usm_constraint sign = usm_param_constraints[k];
    const usm_param_range *r = &usm_param_ranges[k];
    const char *kind = v->kind == USM_DIST_NORMAL ? "standard deviation" : "half-width";
    char why[USM_MSG_LEN];
    /* a parameter the model does not read: its scatter would change nothing */
    for (int j = 0; m && !m->imperfect && j < USM_NIMPERFECTIONS; ++j)
        if (usm_param_imperfections[j] == k) {
            snprintf(msg, USM_MSG_LEN, "%s: model %s is an ideal motor, without %s (%s); "
                     "its scatter changes nothing (the variant imperfect models it)",
                     info->name, m->name, info->name, info->description);
            return USM_EINPUT;
        }
    const usm_param_coupling *c = m ? usm_param_coupled(m, k) : NULL;
    if (c) {
        snprintf(msg, USM_MSG_LEN, "%s: model %s ties it to %s (%s); scatter %s", info->name,
                 m->name, usm_param_table[c->equals].name, c->because,
                 usm_param_table[c->equals].name);
        return USM_EINPUT;
    }
    if (v->relative && nominal == 0.0) {
        snprintf(msg, USM_MSG_LEN, "%s: a relative (%%) width of a parameter whose "
                 "nominal value is 0; give it in %s", info->name, info->unit);
        return USM_EINPUT;
    }
    if (v->kind == USM_DIST_UNIFORM && !v->relative) {
        /* a range wholly outside the physical one would only redraw forever;
         * one that overlaps it is drawn, the draws outside redrawn */
        if ((sign == USM_CONSTRAINT_POSITIVE && !(v->hi > 0.0)) ||
            (sign == USM_CONSTRAINT_NONNEGATIVE && !(v->hi >= 0.0))) {
            snprintf(msg, USM_MSG_LEN, "%s: uniform:%g:%g lies outside the physical range "
                     "(%s)", info->name, v->lo, v->hi, info->constraint);
            return USM_EINPUT;
        }
        if (v->hi < r->lo || v->lo > r->hi) {
            usm_param_check_value(k, v->hi < r->lo ? v->hi : v->lo, why);
            snprintf(msg, USM_MSG_LEN, "%s: uniform:%g:%g lies outside the parameter's range: "
                     "%.180s", info->name, v->lo, v->hi, why);
            return USM_EINPUT;
        }
        return USM_OK;
    }
    /* a width wider than the whole range, or (a parameter of one sign) than
     * the value itself: a number typed in the wrong unit, most draws redrawn */
    const double width = v->relative ? v->width * fabs(nominal) : v->width;
    if (width > 0.5 * (r->hi - r->lo)) {
        char hint[64] = "";
        if (!v->relative && strcmp(info->unit, "rad") == 0)
            snprintf(hint, sizeof hint, "; did you mean %g deg?", v->width);
        snprintf(msg, USM_MSG_LEN, "%s: the %s %g %s is wider than half the parameter's "
                 "range %g..%g %s%s", info->name, kind, width, info->unit, r->lo, r->hi,
                 info->unit, hint);
        return USM_EINPUT;
    }
    if (sign != USM_CONSTRAINT_ANY && width > fabs(nominal)) {
        char hint[64] = "";
        if (!v->relative)
            snprintf(hint, sizeof hint, "; did you mean %g%%?", v->width);
        snprintf(msg, USM_MSG_LEN, "%s: the %s %g %s exceeds the value %g %s itself (most "
                 "draws would leave the physical range)%s", info->name, kind, width,
                 info->unit, nominal, info->unit, hint);
        return USM_EINPUT;
    }
    return USM_OK;
}

int usm_tolerance_spec_parse(const char *text, usm_tolerance_spec *s, char msg[USM_MSG_LEN])
{
    const char *op = text ? strpbrk(text, "<>") : NULL;
    char name[64];
    memset(s, 0, sizeof *s);
    if (!op || op[1] != '=' || op == text || (size_t)(op - text) >= sizeof name) {
        snprintf(msg, USM_MSG_LEN, "\"%.64s\": expected OUTPUT>=X or OUTPUT<=X", text ? text : "");
        return USM_EINPUT;
    }
    memcpy(name, text, (size_t)(op - text));
    name[op - text] = '\0';
    s->output = usm_tolerance_output_find(name);
    if (s->output < 0 || s->output >= USM_TOL_NNUMERIC) {
        snprintf(msg, USM_MSG_LEN, "%s: %s (outputs with a spec: theta, rotor_speed, F_n, F_t, "
                 "max_modulus, efficiency)", name, s->output < 0 ? "unknown output" :
                 "a yes/no output takes no bound");
        return USM_EINPUT;
    }
    s->upper = op[0] == '<';
    if (number(op + 2, op + strlen(op), &s->bound) != 0) {
        snprintf(msg, USM_MSG_LEN, "%s: bound \"%.64s\" is not a finite number", name, op + 2);
        return USM_EINPUT;
    }
    return USM_OK;
}

/* ---- the study object ------------------------------------------------------------ */

void usm_tolerance_options_default(usm_tolerance_options *opt)
{
    memset(opt, 0, sizeof *opt);
    opt->samples = 1000;
    opt->seed = 1;
    opt->threads = 2;
    usm_floquet_options_default(&opt->floquet);
    opt->checkpoint_interval = 10.0;
    usm_op_options_default(&opt->op);
}

usm_tolerance *usm_tolerance_alloc(const usm_model *m)
{
    usm_tolerance *t = calloc(1, sizeof *t);
    if (t) {
        t->m = m;
        t->lock_fd = -1;
    }
    return t;
}

static void clear(usm_tolerance *t)
{
    free(t->done);
    free(t->rows);
    free(t->config);
    t->done = NULL;
    t->rows = NULL;
    t->config = NULL;
    t->have_result = 0;
    if (t->lock_fd >= 0)
        close(t->lock_fd);
    t->lock_fd = -1;
}

void usm_tolerance_free(usm_tolerance *t)
{
    if (!t)
        return;
    clear(t);
    free(t);
}

int usm_tolerance_vary_add(usm_tolerance *t, const usm_tolerance_vary *v)
{
    if (!v || !v->param) {
        snprintf(t->msg, USM_MSG_LEN, "vary: no parameter");
        return USM_EINPUT;
    }
    for (int j = 0; j < t->nvary; ++j)
        if (t->vary[j].param == v->param) {
            snprintf(t->msg, USM_MSG_LEN, "%s: varied twice", v->param->name);
            return USM_EINPUT;
        }
    const usm_param_coupling *c = usm_param_coupled(t->m, usm_param_index(v->param));
    if (c) {
        const char *to = usm_param_table[c->equals].name;
        snprintf(t->msg, USM_MSG_LEN, "%s: equals %s in model %s (%s); vary %s, which moves %s "
                 "with it", v->param->name, to, t->m->name, c->because, to, v->param->name);
        return USM_EINPUT;
    }
    t->vary[t->nvary++] = *v;
    return USM_OK;
}

int usm_tolerance_spec_add(usm_tolerance *t, const usm_tolerance_spec *s)
{
    if (t->nspec >= TOL_MAX_SPECS) {
        snprintf(t->msg, USM_MSG_LEN, "spec: at most %d specs", TOL_MAX_SPECS);
        return USM_EINPUT;
    }
    if (!s || s->output < 0 || s->output >= USM_TOL_NNUMERIC || !isfinite(s->bound)) {
        snprintf(t->msg, USM_MSG_LEN, "spec: not a bound on a numeric output");
        return USM_EINPUT;
    }
    t->spec[t->nspec++] = *s;
    return USM_OK;
}

const char *usm_tolerance_message(const usm_tolerance *t) { return t->msg; }

const usm_tolerance_timings *usm_tolerance_timings_get(const usm_tolerance *t)
{
    return t->done ? &t->timings : NULL;
}

void usm_tolerance_output_seconds_add(usm_tolerance *t, double seconds)
{
    t->timings.output += seconds;
}

void usm_tolerance_output_cpu_seconds_add(usm_tolerance *t, double seconds)
{
    t->timings.output_cpu += seconds;
}

int usm_tolerance_vary_count(const usm_tolerance *t) { return t->nvary; }

const usm_tolerance_vary *usm_tolerance_vary_at(const usm_tolerance *t, int j)
{
    return j >= 0 && j < t->nvary ? &t->vary[j] : NULL;
}

const usm_tolerance_summary *usm_tolerance_result(const usm_tolerance *t)
{
    return t->have_result ? &t->sum : NULL;
}

double usm_tolerance_influence(const usm_tolerance *t, int k, int j)
{
    if (!t->have_result || k < 0 || k >= USM_TOL_NNUMERIC || j < 0 || j >= t->nvary)
        return NAN;
    return t->influence[k][j];
}

int usm_tolerance_sample(const usm_tolerance *t, uint64_t i, double *values, double *out,
                         int *good, int *redraws)
{
    /* under MPI a rank holds its own samples only */
    const uint64_t first = t->blo * USM_TOLERANCE_BLOCK;
    if (!t->have_result || i >= t->sum.samples || i < first ||
        i - first >= tol_local_samples(t))
        return USM_EINPUT;
    const double *row = t->rows + (i - first) * (uint64_t)t->width;
    if (values)
        memcpy(values, row, (size_t)t->nvary * sizeof *values);
    if (out)
        memcpy(out, row + t->nvary, USM_TOL_NOUTPUTS * sizeof *out);
    if (good)
        *good = row[TOL_ROW_GOOD(t)] == 1.0; /* TOL_GOOD_DRIVEN: not good */
    if (redraws)
        *redraws = (int)row[TOL_ROW_REDRAWS(t)];
    return USM_OK;
}

/* ---- the random stream of a sample --------------------------------------------------- */

/* splitmix64 (Steele, Lea, Flood 2014): a 64-bit state advanced by a constant
 * and a bijective mix; passes BigCrush.  GSL's own generators take 32-bit
 * seeds, too few for 10^8 distinct sample streams. */
static uint64_t mix64(uint64_t z)
{
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

static void sm_set(void *state, unsigned long seed) { *(uint64_t *)state = (uint64_t)seed; }

static uint64_t sm_next(void *state)
{
    uint64_t *s = state;
    *s += 0x9e3779b97f4a7c15ULL;
    return mix64(*s);
}

static unsigned long sm_get(void *state) { return (unsigned long)(sm_next(state) >> 32); }

static double sm_get_double(void *state)
{
    /* 53 random bits; never 1, may be 0 as gsl_rng_uniform allows */
    return (double)(sm_next(state) >> 11) * 0x1.0p-53;
}

static const gsl_rng_type splitmix64_type = {"splitmix64", 0xffffffffUL, 0, sizeof(uint64_t),
                                             sm_set, sm_get, sm_get_double};

/* The start of sample i's stream: distinct (seed, i) give unrelated states. */
static uint64_t sample_seed(uint64_t seed, uint64_t i)
{
    return mix64(mix64(seed ^ 0x5851f42d4c957f2dULL) + i);
}

static double draw(const usm_tolerance_vary *v, double nominal, gsl_rng *r)
{
    if (v->kind == USM_DIST_NORMAL)
        return nominal + gsl_ran_gaussian(r, v->relative ? v->width * fabs(nominal) : v->width);
    if (v->relative)
        return nominal * (1.0 + v->width * (2.0 * gsl_rng_uniform(r) - 1.0));
    return v->lo + (v->hi - v->lo) * gsl_rng_uniform(r);
}

/* ---- one block (a task of the pool) --------------------------------------------------- */

typedef struct worker {
    usm_steady *steady;
    usm_floquet *floquet;
    gsl_rng *rng;
} worker;

typedef struct run_ctx {
    usm_tolerance *t;
    const uint64_t *blocks;
    double *pack;               /* the blocks' rows, one after the other */
    uint64_t *offset;           /* first sample of block k in pack */
    char *msg;                  /* per task: why it stopped */
} run_ctx;

static void worker_free(void *state)
{
    worker *w = state;
    usm_steady_free(w->steady);
    usm_floquet_free(w->floquet);
    gsl_rng_free(w->rng);
    free(w);
}

static void *worker_alloc(void *ctx)
{
    const usm_tolerance *t = ((run_ctx *)ctx)->t;
    worker *w = calloc(1, sizeof *w);
    if (!w)
        return NULL;
    w->steady = usm_steady_alloc(t->m);
    w->floquet = usm_floquet_alloc(t->m);
    w->rng = gsl_rng_alloc(&splitmix64_type);
    if (!w->steady || !w->floquet || !w->rng) {
        worker_free(w);
        return NULL;
    }
    return w;
}

static int sample(usm_tolerance *t, worker *w, uint64_t i, double *row, char msg[USM_MSG_LEN])
{
    usm_params q;
    usm_point pt;
    char why[USM_MSG_LEN];
    double *out = row + t->nvary;
    int redraws = 0;
    gsl_rng_set(w->rng, (unsigned long)sample_seed(t->opt.seed, i));
    for (;;) {
        q = t->p;
        for (int j = 0; j < t->nvary; ++j) {
            const usm_tolerance_vary *v = &t->vary[j];
            row[j] = draw(v, usm_params_get(&t->p, v->param), w->rng);
            *usm_params_field(&q, v->param) = row[j];
            usm_params_couple(t->m, &q, usm_param_index(v->param));
        }
        if (usm_params_check(&q, t->m, why) == USM_OK)
            break;
        if (++redraws >= MAX_REDRAWS) {
            snprintf(msg, USM_MSG_LEN, "sample %llu: %d draws in a row left the physical range "
                     "(last: %.120s); narrow the distributions", (unsigned long long)i, redraws,
                     why);
            return USM_EINPUT;
        }
    }
    if (usm_point_evaluate_op(w->steady, w->floquet, t->m, &q, t->opt.t0, &t->opt.floquet,
                              &t->opt.op, &pt) != USM_OK) {
        snprintf(msg, USM_MSG_LEN, "sample %llu: %.200s", (unsigned long long)i, pt.error);
        return USM_EINPUT;
    }
    for (int k = 0; k < USM_TOL_NOUTPUTS; ++k)
        out[k] = NAN;
    out[USM_TOL_EXISTS] = pt.exists;
    out[USM_TOL_OP_CLASS] = (double)pt.op.cls;
    /* the operating point when there is one, else the smallest-tilt root */
    const int op = pt.op.index >= 0;
    const usm_steady_solution *sol = op ? &pt.op.sol : &pt.sol;
    if (op)
        out[USM_TOL_OPERATING_POINT] = pt.op.index;
    if (pt.exists) {
        out[USM_TOL_THETA] = sol->theta;
        out[USM_TOL_ROTOR_SPEED] = sol->rotor_speed;
        out[USM_TOL_F_N] = sol->F_n;
        out[USM_TOL_F_T] = sol->F_t;
        out[USM_TOL_EFFICIENCY] = sol->efficiency;
        out[USM_TOL_STICK_ADMISSIBLE] = sol->stick_admissible;
        out[USM_TOL_VALIDITY] = (double)sol->validity;
    }
    if (op || pt.has_floquet) {
        const usm_floquet_result *fl = op ? &pt.op.floquet : &pt.floquet;
        out[USM_TOL_MAX_MODULUS] = fl->max_modulus;
        out[USM_TOL_STABLE] = fl->max_modulus < 1.0;
    }
    /* good: the operating point exists (a stable root), meets the specs, the
     * model describes the motor there and the motor drives its load (the
     * rule of yield_rule.h, the robust yield's too) */
    int driven;
    const int good = yield_sample_good(op, op ? pt.op.floquet.max_modulus : NAN,
                                       out[USM_TOL_VALIDITY] == (double)USM_VALID,
                                       tol_meets_specs(t, out), op ? pt.op.sol.power_out : NAN,
                                       t->opt.allow_driven, &driven);
    row[TOL_ROW_GOOD(t)] = good ? 1.0 : driven ? TOL_GOOD_DRIVEN : 0.0;
    row[TOL_ROW_REDRAWS(t)] = redraws;
    return USM_OK;
}

static void block_done(void *ctx, size_t k)
{
    run_ctx *c = ctx;
    progress_add(&c->t->meter, (long)tol_block_size(c->t, c->blocks[k]));
}

static int block_task(void *ctx, void *state, size_t k)
{
    run_ctx *c = ctx;
    usm_tolerance *t = c->t;
    const uint64_t b = c->blocks[k], first = b * USM_TOLERANCE_BLOCK, n = tol_block_size(t, b);
    double *rows = c->pack + c->offset[k] * (uint64_t)t->width;
    for (uint64_t i = 0; i < n; ++i) {
        const int rc = sample(t, state, first + i, rows + i * (uint64_t)t->width,
                              c->msg + k * USM_MSG_LEN);
        if (rc != USM_OK)
            return rc;
    }
    return USM_OK;
}

int tol_compute(usm_tolerance *t, const uint64_t *blocks, size_t n, double *pack)
{
    run_ctx c = {t, blocks, pack, calloc(n ? n : 1, sizeof *c.offset),
                 calloc(n ? n : 1, USM_MSG_LEN)};
    int status;
    if (!c.msg || !c.offset) {
        free(c.msg);
        free(c.offset);
        snprintf(t->msg, USM_MSG_LEN, "out of memory");
        return USM_EFAILED;
    }
    for (size_t k = 1; k < n; ++k)
        c.offset[k] = c.offset[k - 1] + tol_block_size(t, blocks[k - 1]);
    t->fail_block = UINT64_MAX;
    pool_job job = {n, t->opt.threads, &c, worker_alloc, worker_free, block_task, block_done};
    status = pool_run(&job, t->msg);
    /* the first failing block in list order names the sample: independent of threads */
    for (size_t k = 0; status != USM_OK && k < n; ++k)
        if (c.msg[k * USM_MSG_LEN]) {
            snprintf(t->msg, USM_MSG_LEN, "%s", c.msg + k * USM_MSG_LEN);
            t->fail_block = blocks[k];
            break;
        }
    free(c.msg);
    free(c.offset);
    return status;
}

int tol_checkpoint_due(const usm_tolerance *t, int last, int stop)
{
    /* a large study's file takes long to rewrite: at most 1/20 of the time writing */
    const double wait = fmax(t->opt.checkpoint_interval, 20.0 * t->write_seconds);
    return t->opt.checkpoint && (last || stop || tol_now() - t->last_write >= wait);
}

/* ---- checks and the configuration --------------------------------------------------- */

/* Append to a growing text; -1 when out of memory. */
static int append(char **text, size_t *len, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

static int append(char **text, size_t *len, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    const int n = vsnprintf(NULL, 0, fmt, ap);
    va_end(ap);
    if (n < 0)
        return -1;
    /* what is held is at least *len + 1 bytes */
    size_t cap = *text ? *len + 1 : 0;
    if (usm_grow((void **)text, &cap, *len + (size_t)n + 1, 1) != 0)
        return -1;
    va_start(ap, fmt);
    vsnprintf(*text + *len, (size_t)n + 1, fmt, ap);
    va_end(ap);
    *len += (size_t)n;
    return 0;
}

/* The study as text, one "key value" per line, numbers in %a (exact): the
 * checkpoint's header; a resume must match it line for line. */
static int build_config(usm_tolerance *t)
{
    const usm_tolerance_options *o = &t->opt;
    size_t len = 0;
    int bad = append(&t->config, &len, "model %s\nsamples %llu\nseed %llu\nblock %d\nt0 %a\n",
                     t->m->name, (unsigned long long)o->samples, (unsigned long long)o->seed,
                     USM_TOLERANCE_BLOCK, o->t0);
    bad |= append(&t->config, &len, "floquet %s rtol %a atol %a steps %d\n",
                  usm_floquet_method_name(o->floquet.method), o->floquet.rtol, o->floquet.atol,
                  o->floquet.steps);
    bad |= append(&t->config, &len, "operating_point from_rest %d periods %a\n",
                  o->op.from_rest, o->op.periods);
    /* the rule of a good sample: a checkpoint of the other rule holds other `good`s */
    bad |= append(&t->config, &len, "allow_driven %d\n", o->allow_driven != 0);
    /* the row's layout: a file of rows laid out otherwise is another study's */
    bad |= append(&t->config, &len, "outputs");
    for (int k = 0; k < USM_TOL_NOUTPUTS; ++k)
        bad |= append(&t->config, &len, " %s", usm_tolerance_output_name(k));
    bad |= append(&t->config, &len, " good redraws\n");
    for (int k = 0; k < USM_NPARAMS; ++k)
        bad |= append(&t->config, &len, "param %s %a\n", usm_param_table[k].name,
                      usm_params_get(&t->p, &usm_param_table[k]));
    for (int j = 0; j < t->nvary; ++j) {
        const usm_tolerance_vary *v = &t->vary[j];
        bad |= append(&t->config, &len, "vary %s %s %s %a %a %a\n", v->param->name,
                      v->kind == USM_DIST_NORMAL ? "normal" : "uniform",
                      v->relative ? "relative" : "absolute", v->width, v->lo, v->hi);
    }
    for (int s = 0; s < t->nspec; ++s)
        bad |= append(&t->config, &len, "spec %s %s %a\n", usm_tolerance_output_name(t->spec[s].output),
                      t->spec[s].upper ? "<=" : ">=", t->spec[s].bound);
    return bad ? -1 : 0;
}

static int check(usm_tolerance *t, const usm_params *p, const usm_tolerance_options *opt)
{
    char why[USM_MSG_LEN];
    if (!p || !opt) {
        snprintf(t->msg, USM_MSG_LEN, "%s: must not be NULL", p ? "options" : "params");
        return USM_EINPUT;
    }
    if (opt->samples < 1 || opt->samples > USM_TOLERANCE_MAX_SAMPLES) {
        snprintf(t->msg, USM_MSG_LEN, "samples: need 1 ... %llu, got %llu",
                 (unsigned long long)USM_TOLERANCE_MAX_SAMPLES, (unsigned long long)opt->samples);
        return USM_EINPUT;
    }
    if (opt->seed > USM_SEED_MAX) {
        snprintf(t->msg, USM_MSG_LEN, "seed: must be 0 to %llu, got %llu",
                 (unsigned long long)USM_SEED_MAX, (unsigned long long)opt->seed);
        return USM_EINPUT;
    }
    if (opt->threads < 1 || opt->threads > POOL_MAX_THREADS) {
        snprintf(t->msg, USM_MSG_LEN, "threads: must be between 1 and %d, got %d",
                 POOL_MAX_THREADS, opt->threads);
        return USM_EINPUT;
    }
    if (!isfinite(opt->t0) || !(opt->checkpoint_interval >= 0.0)) {
        snprintf(t->msg, USM_MSG_LEN, "%s: must be a finite number%s",
                 isfinite(opt->t0) ? "checkpoint_interval" : "t0",
                 isfinite(opt->t0) ? " >= 0" : "");
        return USM_EINPUT;
    }
    if (opt->op.from_rest && !(opt->op.periods >= 1 && opt->op.periods <= 1e7)) {
        snprintf(t->msg, USM_MSG_LEN, "from-rest-periods: must be in [1, 1e7], got %g",
                 opt->op.periods);
        return USM_EINPUT;
    }
    if (t->nvary == 0) {
        snprintf(t->msg, USM_MSG_LEN, "vary: no parameter is varied");
        return USM_EINPUT;
    }
    if (usm_params_check(p, t->m, why) != USM_OK) {
        snprintf(t->msg, USM_MSG_LEN, "%s", why);
        return USM_EINPUT;
    }
    for (int j = 0; j < t->nvary; ++j)
        if (usm_tolerance_vary_check(&t->vary[j], t->m, p, t->msg) != USM_OK)
            return USM_EINPUT;
    return USM_OK;
}

int tol_prepare(usm_tolerance *t, const usm_params *p, const usm_tolerance_options *opt,
                int rank, int size)
{
    clear(t);
    t->msg[0] = '\0';
    if (check(t, p, opt) != USM_OK)
        return USM_EINPUT;
    t->p = *p;
    t->opt = *opt;
    t->width = t->nvary + USM_TOL_NOUTPUTS + 2;
    t->nblocks = (opt->samples + USM_TOLERANCE_BLOCK - 1) / USM_TOLERANCE_BLOCK;
    memset(&t->sum, 0, sizeof t->sum);
    memset(&t->timings, 0, sizeof t->timings);
    memset(&t->meter, 0, sizeof t->meter);
    t->write_seconds = 0.0;
    t->last_write = tol_now();
    t->rank = rank;
    t->size = size;
    tol_owned(t->nblocks, rank, size, &t->blo, &t->bhi);
    const uint64_t local = (t->bhi - t->blo) * USM_TOLERANCE_BLOCK;
    if ((uint64_t)t->width > SIZE_MAX / sizeof(double) / opt->samples ||
        !(t->done = calloc(t->nblocks, 1)) ||
        !(t->rows = malloc((local ? local : 1) * (uint64_t)t->width * sizeof(double))) ||
        build_config(t) != 0) {
        clear(t);
        snprintf(t->msg, USM_MSG_LEN, "out of memory for %llu samples",
                 (unsigned long long)opt->samples);
        return USM_EFAILED;
    }
    return USM_OK;
}

int tol_stopped(usm_tolerance *t, uint64_t computed)
{
    snprintf(t->msg, USM_MSG_LEN, "stopped after %llu block(s) as asked; the checkpoint "
             "%.120s holds them", (unsigned long long)computed,
             t->opt.checkpoint ? t->opt.checkpoint : "(none)");
    return USM_EFAILED;
}
