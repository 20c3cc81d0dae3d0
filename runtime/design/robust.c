/* The robust optimum (usm_robust.h): NLopt's COBYLA (derivative-free) over
 * the box in normalised variables, the yield and the scatter statistics from
 * one common-random-numbers sample set (yield.c), derived quantities
 * from sweeps (robust_quantity.c); started from the nominal optimum
 * (usm_optimize_run) when there is one; the chosen design verified with a
 * fresh, larger sample. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <nlopt.h>

#include "core/progress.h"
#include "usm_map.h"
#include "usm_robust.h"

#define MAX_RCONS (USM_OPT_MAX_CONSTRAINTS + 3 + 8 + 1)
#define ACTIVE_TOL 1e-3   /* a scaled constraint this close to its bound is active */
#define BOUND_TOL 1e-6    /* box units */
#define RHO_BEGIN 0.1     /* COBYLA's first step, box units */
#define XTOL 1e-4         /* box units */

void usm_robust_problem_init(usm_robust_problem *rp)
{
    memset(rp, 0, sizeof *rp);
    usm_opt_problem_init(&rp->nominal);
    rp->nominal.no_flat = 1;
    rp->objective = -1;
    rp->stat = USM_ROBUST_STAT_NOMINAL;
    rp->quantile = 0.05;
    rp->yield_min = NAN;
    rp->samples = 10000;
    rp->seed = 1;
    rp->verify_samples = 100000;
    rp->threads = 2;
    rp->max_evals = 40;
    rp->qopt.range.param = -1;
    rp->qopt.range.points = 21;
    rp->qopt.band_threshold = NAN;
}

static int needs_scatter(const usm_robust_problem *rp)
{
    return rp->objective == USM_ROBUST_YIELD || rp->stat != USM_ROBUST_STAT_NOMINAL ||
           !isnan(rp->yield_min);
}

int usm_robust_problem_is_robust(const usm_robust_problem *rp)
{
    return needs_scatter(rp) || rp->nscatter > 0 || rp->nderived > 0 ||
           rp->objective >= USM_OPT_OUTPUT_COUNT || rp->qopt.range.param >= 0;
}

int usm_robust_problem_check(const usm_robust_problem *rp, const usm_model *m,
                             const usm_params *p, char msg[USM_MSG_LEN])
{
    if (rp->objective < 0 || !usm_robust_quantity_name(rp->objective)) {
        snprintf(msg, USM_MSG_LEN, "objective: required");
        return USM_EINPUT;
    }
    if (needs_scatter(rp) && rp->nscatter < 1) {
        snprintf(msg, USM_MSG_LEN, "scatter: a yield or a statistic over the scatter needs at "
                 "least one --scatter NAME=DIST");
        return USM_EINPUT;
    }
    if (rp->nscatter > 0 && !needs_scatter(rp)) {
        snprintf(msg, USM_MSG_LEN, "scatter: given, but neither the objective (yield, mean:NAME, "
                 "qNN:NAME) nor a yield constraint uses it");
        return USM_EINPUT;
    }
    if (rp->stat != USM_ROBUST_STAT_NOMINAL &&
        (rp->objective >= USM_OPT_OUTPUT_COUNT || rp->qopt.range.param >= 0)) {
        snprintf(msg, USM_MSG_LEN, "objective: mean:/qNN: take an output of the operating "
                 "point, not %s or an --over-range", usm_robust_quantity_name(rp->objective));
        return USM_EINPUT;
    }
    if (rp->stat == USM_ROBUST_STAT_QUANTILE && !(rp->quantile > 0 && rp->quantile < 1)) {
        snprintf(msg, USM_MSG_LEN, "objective: the quantile must lie in (0, 1)");
        return USM_EINPUT;
    }
    if (!isnan(rp->yield_min) && !(rp->yield_min > 0 && rp->yield_min < 1)) {
        snprintf(msg, USM_MSG_LEN, "constraint: yield>=Y needs 0 < Y < 1");
        return USM_EINPUT;
    }
    if (rp->samples < USM_ROBUST_MIN_SAMPLES || rp->samples > USM_ROBUST_MAX_SAMPLES ||
        rp->verify_samples < USM_ROBUST_MIN_SAMPLES || rp->verify_samples > USM_ROBUST_MAX_SAMPLES) {
        const int v = rp->samples >= USM_ROBUST_MIN_SAMPLES && rp->samples <= USM_ROBUST_MAX_SAMPLES;
        snprintf(msg, USM_MSG_LEN, "%s: must be %llu to %llu, got %llu",
                 v ? "verify-samples" : "samples", (unsigned long long)USM_ROBUST_MIN_SAMPLES,
                 (unsigned long long)USM_ROBUST_MAX_SAMPLES,
                 (unsigned long long)(v ? rp->verify_samples : rp->samples));
        return USM_EINPUT;
    }
    if (rp->seed > USM_SEED_MAX) {
        snprintf(msg, USM_MSG_LEN, "seed: must be 0 to %llu, got %llu",
                 (unsigned long long)USM_SEED_MAX, (unsigned long long)rp->seed);
        return USM_EINPUT;
    }
    if (rp->threads < 1 || rp->threads > 64) {
        snprintf(msg, USM_MSG_LEN, "threads: must be 1 to 64, got %d", rp->threads);
        return USM_EINPUT;
    }
    if (rp->max_evals < 4 || rp->max_evals > 100000) {
        snprintf(msg, USM_MSG_LEN, "max-evals: must be 4 to 100000, got %d", rp->max_evals);
        return USM_EINPUT;
    }
    if (rp->objective == USM_ROBUST_YIELD && rp->nominal.minimize) {
        snprintf(msg, USM_MSG_LEN, "minimize: the objective yield is maximized (a design "
                 "of least yield is no design); drop --minimize");
        return USM_EINPUT;
    }
    for (int i = 0; i < rp->nominal.ncons; ++i)
        if (rp->nominal.cons[i].root != 0 || rp->nominal.cons[i].output == USM_OPT_ROOTS) {
            snprintf(msg, USM_MSG_LEN, "constraint: rootR.NAME and roots are not available in a "
                     "robust problem (the operating point is judged)");
            return USM_EINPUT;
        }
    if (rp->nominal.from_rest) {
        snprintf(msg, USM_MSG_LEN, "from-rest: not available in a robust problem");
        return USM_EINPUT;
    }
    /* the derived quantities' own needs, before any computation */
    for (int i = -1; i < rp->nderived; ++i) {
        const int k = i < 0 ? rp->objective : rp->derived[i].quantity;
        const char *field = i < 0 ? "objective" : "constraint";
        const usm_robust_range *r = &rp->qopt.range;
        if (k == USM_ROBUST_STALL_TORQUE && !m->slip) {
            snprintf(msg, USM_MSG_LEN, "%s: stall_torque: model %s keeps stick (its rotor speed "
                     "is kinematic and never stalls); use a slip model (--model 4dof)", field,
                     m->name);
            return USM_EINPUT;
        }
        if ((k == USM_ROBUST_STALL_TORQUE || k == USM_ROBUST_MAX_POWER) && r->param >= 0 &&
            r->param != USM_P_T) {
            snprintf(msg, USM_MSG_LEN, "over-range: %s searches a load range: give T=LO:HI",
                     usm_robust_quantity_name(k));
            return USM_EINPUT;
        }
        if (k == USM_ROBUST_BAND_WIDTH &&
            (r->param != USM_P_f || !isfinite(rp->qopt.band_threshold))) {
            snprintf(msg, USM_MSG_LEN, "%s: band_width needs --over-range f=LO:HI and "
                     "--band-threshold X (the speed [1/s] the band keeps)",
                     r->param != USM_P_f ? "over-range" : "band-threshold");
            return USM_EINPUT;
        }
    }
    if (rp->qopt.range.param >= 0 && rp->objective >= USM_OPT_OUTPUT_COUNT &&
        rp->objective != USM_ROBUST_STALL_TORQUE && rp->objective != USM_ROBUST_MAX_POWER &&
        rp->objective != USM_ROBUST_BAND_WIDTH && rp->nderived == 0) {
        snprintf(msg, USM_MSG_LEN, "over-range: the objective %s takes no range",
                 usm_robust_quantity_name(rp->objective));
        return USM_EINPUT;
    }
    /* the box, margin, t0 as the nominal optimizer checks them */
    usm_opt_problem pb = rp->nominal;
    pb.objective = USM_OPT_SPEED;
    if (usm_opt_problem_check(&pb, m, p, msg) != USM_OK)
        return USM_EINPUT;
    for (int j = 0; j < rp->nscatter; ++j) {
        const usm_tolerance_vary *v = &rp->scatter[j];
        char why[USM_MSG_LEN];
        if (usm_tolerance_vary_check(v, m, p, why) != USM_OK) {
            snprintf(msg, USM_MSG_LEN, "scatter: %.230s", why);
            return USM_EINPUT;
        }
        /* uniform:LO:HI draws the same values at every design: the design of
         * that parameter would be judged by numbers that ignore it */
        for (int i = 0; v->kind == USM_DIST_UNIFORM && !v->relative && i < pb.nvary; ++i)
            if (pb.vary[i] == usm_param_index(v->param)) {
                snprintf(msg, USM_MSG_LEN, "scatter: %s: uniform:%g:%g is absolute, but %s is "
                         "designed (--vary): every design would see the same %s; give its "
                         "scatter about the design (uniform:P%% or normal:SIGMA)",
                         v->param->name, v->lo, v->hi, v->param->name, v->param->name);
                return USM_EINPUT;
            }
    }
    return USM_OK;
}

/* ---- evaluation -------------------------------------------------------------------- */

typedef struct ctx {
    const usm_model *m;
    const usm_robust_problem *rp;
    usm_params base;
    usm_yield *crn;
    int larger_better;       /* the objective's sense */
    double yield_target;     /* yield_min plus the CRN's statistical margin */
    int ncons;
    char text[MAX_RCONS][USM_OPT_TEXT_LEN];
    /* the last evaluation */
    int n;
    double x[USM_NPARAMS];
    int have, ok;
    double obj, cons[MAX_RCONS], yield;
    double obj_scale;        /* |objective| at the start (COBYLA is not scale-free) */
    int evaluations;
    /* the best feasible (least violation when none) */
    int best_have;
    double best_x[USM_NPARAMS], best_obj, best_viol;
    char msg[USM_MSG_LEN];
    int failed;
    progress_meter meter;    /* designs evaluated, against the searches' budgets */
} ctx;

static void design(const ctx *c, const double *x, usm_params *p)
{
    const usm_opt_problem *pb = &c->rp->nominal;
    *p = c->base;
    for (int k = 0; k < pb->nvary; ++k) {
        *usm_params_field(p, &usm_param_table[pb->vary[k]]) =
            fmin(pb->hi[k], fmax(pb->lo[k], pb->lo[k] + x[k] * (pb->hi[k] - pb->lo[k])));
        usm_params_couple(c->m, p, pb->vary[k]);
    }
}

static double scaled(double v, double bound, int upper)
{
    const double s = bound != 0 ? fabs(bound) : 1.0;
    return (upper ? v - bound : bound - v) / s;
}

/* The constraints' texts, in the order evaluate fills cons[]. */
static int cons_texts(ctx *c)
{
    const usm_robust_problem *rp = c->rp;
    const usm_opt_problem *pb = &rp->nominal;
    int n = 0;
    snprintf(c->text[n++], USM_OPT_TEXT_LEN, "stability: max_modulus <= %g", 1 - pb->margin);
    if (!pb->allow_driven)
        snprintf(c->text[n++], USM_OPT_TEXT_LEN, "drives: power_out >= 0");
    if (!c->m->slip && !pb->allow_slip)
        snprintf(c->text[n++], USM_OPT_TEXT_LEN, "stick: F_t <= mu0 F_n");
    for (int i = 0; i < pb->ncons; ++i)
        snprintf(c->text[n++], USM_OPT_TEXT_LEN, "%s %s %g",
                 usm_opt_output_name(pb->cons[i].output), pb->cons[i].upper ? "<=" : ">=",
                 pb->cons[i].value);
    for (int i = 0; i < rp->nderived; ++i)
        snprintf(c->text[n++], USM_OPT_TEXT_LEN, "%s %s %g",
                 usm_robust_quantity_name(rp->derived[i].quantity),
                 rp->derived[i].upper ? "<=" : ">=", rp->derived[i].value);
    if (!isnan(rp->yield_min))
        snprintf(c->text[n++], USM_OPT_TEXT_LEN, "yield >= %g", rp->yield_min);
    return n;
}

/* The design at box point x: c->obj (the objective, NaN when undefined),
 * c->cons (scaled, <= 0 when met), c->ok (a design with an operating point). */
static void evaluate_design(ctx *c, const double *x);

/* A design; a new one counts for the progress. */
static void evaluate(ctx *c, const double *x)
{
    const int before = c->evaluations;
    evaluate_design(c, x);
    if (c->evaluations != before)
        progress_add(&c->meter, 1);
}

static void evaluate_design(ctx *c, const double *x)
{
    const usm_robust_problem *rp = c->rp;
    const usm_opt_problem *pb = &rp->nominal;
    if (c->have && memcmp(x, c->x, sizeof(double) * (size_t)c->n) == 0)
        return;
    memcpy(c->x, x, sizeof(double) * (size_t)c->n);
    c->have = 1;
    c->ok = 0;
    c->obj = NAN;
    c->yield = NAN;
    c->evaluations++;
    for (int i = 0; i < c->ncons; ++i)
        c->cons[i] = 1.0; /* undefined: violated */
    usm_params p;
    design(c, x, &p);
    double v;
    char why[USM_MSG_LEN];
    usm_steady *st = usm_steady_alloc(c->m);
    usm_floquet *fl = usm_floquet_alloc(c->m);
    usm_floquet_options fo;
    usm_op_options oo;
    usm_point pt;
    usm_floquet_options_default(&fo);
    usm_op_options_default(&oo);
    int rc = st && fl ? usm_point_evaluate_op(st, fl, c->m, &p, pb->t0, &fo, &oo, &pt)
                      : USM_EFAILED;
    usm_steady_free(st);
    usm_floquet_free(fl);
    if (rc == USM_EFAILED) {
        c->failed = 1;
        snprintf(c->msg, USM_MSG_LEN, "out of memory");
        return;
    }
    if (rc != USM_OK || pt.op.index < 0)
        return;
    const usm_steady_solution *sol = &pt.op.sol;
    const double mm = pt.op.floquet.max_modulus;
    int n = 0;
    c->cons[n++] = mm - (1 - pb->margin);
    if (!pb->allow_driven)
        c->cons[n++] = -sol->power_out / 1e-3; /* in mW */
    if (!c->m->slip && !pb->allow_slip)
        c->cons[n++] = -usm_opt_output_value(USM_SENS_STICK_MARGIN, sol, &p, mm) / 1e-3;
    for (int i = 0; i < pb->ncons; ++i) {
        v = usm_opt_output_value(pb->cons[i].output, sol, &p, mm);
        c->cons[n++] = isnan(v) ? 1.0 : scaled(v, pb->cons[i].value, pb->cons[i].upper);
    }
    for (int i = 0; i < rp->nderived; ++i) {
        const usm_robust_constraint *d = &rp->derived[i];
        if (usm_robust_quantity_eval(c->m, &p, d->quantity, &rp->qopt, !d->upper, &v, why) ==
            USM_OK)
            c->cons[n] = scaled(v, d->value, d->upper);
        n++;
    }
    /* the scatter */
    if (c->crn) {
        usm_yield_result yr;
        const int track = rp->stat != USM_ROBUST_STAT_NOMINAL ? rp->objective : -1;
        if (usm_yield_eval(c->crn, &p, pb->t0, rp->threads, track, &yr) != USM_OK) {
            c->failed = 1;
            snprintf(c->msg, USM_MSG_LEN, "yield: %.200s", usm_yield_message(c->crn));
            return;
        }
        c->yield = yr.yield;
        /* in units of the allowed failure fraction 1 - yield_min */
        if (!isnan(rp->yield_min))
            c->cons[n++] = (c->yield_target - yr.yield) / (1 - rp->yield_min);
        if (rp->stat == USM_ROBUST_STAT_MEAN)
            c->obj = yr.mean;
        else if (rp->stat == USM_ROBUST_STAT_QUANTILE)
            c->obj = usm_yield_quantile(c->crn, rp->quantile, c->larger_better);
    }
    if (rp->objective == USM_ROBUST_YIELD)
        c->obj = c->yield;
    else if (rp->stat == USM_ROBUST_STAT_NOMINAL) {
        if (rp->objective < USM_OPT_OUTPUT_COUNT && rp->qopt.range.param < 0)
            c->obj = usm_opt_output_value(rp->objective, sol, &p, mm);
        else if (usm_robust_quantity_eval(c->m, &p, rp->objective, &rp->qopt, c->larger_better,
                                          &v, why) == USM_OK)
            c->obj = v;
    }
    if (!isfinite(c->obj))
        c->obj = NAN;
    c->ok = 1;
}

static double violation(const ctx *c)
{
    double v = c->ok ? 0 : INFINITY;
    for (int i = 0; i < c->ncons; ++i)
        v = fmax(v, c->cons[i]);
    return isnan(c->obj) ? INFINITY : v;
}

/* Keep the best: feasible and better, or less violated when nothing is feasible. */
static void consider(ctx *c)
{
    const double v = violation(c);
    const int feas = v <= 0, best_feas = c->best_have && c->best_viol <= 0;
    int better;
    if (!c->best_have)
        better = 1;
    else if (feas != best_feas)
        better = feas;
    else if (feas)
        better = c->larger_better ? c->obj > c->best_obj : c->obj < c->best_obj;
    else
        better = v < c->best_viol;
    if (better) {
        c->best_have = 1;
        memcpy(c->best_x, c->x, sizeof(double) * (size_t)c->n);
        c->best_obj = c->obj;
        c->best_viol = v;
    }
}

static double nl_objective(unsigned n, const double *x, double *grad, void *data)
{
    ctx *c = data;
    (void)n;
    (void)grad;
    evaluate(c, x);
    if (c->failed)
        return HUGE_VAL;
    consider(c);
    if (isnan(c->obj))
        return 1e3;
    /* minimized: larger-better objectives negated; in units of the start's value */
    return (c->larger_better ? -c->obj : c->obj) / c->obj_scale;
}

static void nl_cons(unsigned mcons, double *result, unsigned n, const double *x, double *grad,
                    void *data)
{
    ctx *c = data;
    (void)n;
    (void)grad;
    evaluate(c, x);
    for (unsigned i = 0; i < mcons; ++i)
        result[i] = c->cons[i];
}

static int cobyla(ctx *c, double *x, int maxeval, double rho)
{
    nlopt_opt opt = nlopt_create(NLOPT_LN_COBYLA, (unsigned)c->n);
    if (!opt)
        return -1;
    double lo[USM_NPARAMS], hi[USM_NPARAMS], tol[MAX_RCONS], step[USM_NPARAMS], f;
    for (int i = 0; i < c->n; ++i) {
        lo[i] = 0;
        hi[i] = 1;
        step[i] = rho;
    }
    for (int i = 0; i < c->ncons; ++i)
        tol[i] = 0;
    nlopt_set_lower_bounds(opt, lo);
    nlopt_set_upper_bounds(opt, hi);
    nlopt_set_min_objective(opt, nl_objective, c);
    if (c->ncons > 0)
        nlopt_add_inequality_mconstraint(opt, (unsigned)c->ncons, nl_cons, c, tol);
    nlopt_set_initial_step(opt, step);
    nlopt_set_xtol_abs1(opt, XTOL);
    nlopt_set_maxeval(opt, maxeval);
    nlopt_result r = nlopt_optimize(opt, x, &f);
    nlopt_destroy(opt);
    return r == NLOPT_OUT_OF_MEMORY || r == NLOPT_INVALID_ARGS ? -1 : 0;
}

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The design at box point x described, with a fresh sample's yield when
 * there is scatter (fresh: the verification set, NULL: none). */
/* The fresh verification sample in designs' worth of CRN samples: its cost. */
static long verify_weight(const usm_robust_problem *rp)
{
    return rp->nscatter > 0 ? (long)((rp->verify_samples + rp->samples - 1) / rp->samples) : 0;
}

static int describe(ctx *c, const double *x, usm_yield *fresh, usm_robust_design *d)
{
    const usm_robust_problem *rp = c->rp;
    c->have = 0;
    evaluate(c, x);
    if (c->failed)
        return USM_EFAILED;
    memset(d, 0, sizeof *d);
    design(c, x, &d->params);
    d->feasible = c->ok && violation(c) <= 0;
    d->value = c->obj;
    d->crn_yield = c->yield;
    d->yield = d->yield_lo = d->yield_hi = NAN;
    d->speed = d->efficiency = d->power_out = d->max_modulus = d->nominal_value = NAN;
    usm_steady *st = usm_steady_alloc(c->m);
    usm_floquet *fl = usm_floquet_alloc(c->m);
    usm_floquet_options fo;
    usm_op_options oo;
    usm_point pt;
    usm_floquet_options_default(&fo);
    usm_op_options_default(&oo);
    if (st && fl &&
        usm_point_evaluate_op(st, fl, c->m, &d->params, rp->nominal.t0, &fo, &oo, &pt) ==
            USM_OK &&
        pt.op.index >= 0) {
        d->speed = -pt.op.sol.rotor_speed;
        d->efficiency = pt.op.sol.efficiency;
        d->power_out = pt.op.sol.power_out;
        d->max_modulus = pt.op.floquet.max_modulus;
        if (rp->objective < USM_OPT_OUTPUT_COUNT)
            d->nominal_value = usm_opt_output_value(rp->objective, &pt.op.sol, &d->params,
                                                    pt.op.floquet.max_modulus);
    }
    usm_steady_free(st);
    usm_floquet_free(fl);
    if (rp->objective >= USM_OPT_OUTPUT_COUNT && rp->objective != USM_ROBUST_YIELD) {
        char why[USM_MSG_LEN];
        double v;
        if (usm_robust_quantity_eval(c->m, &d->params, rp->objective, &rp->qopt,
                                     c->larger_better, &v, why) == USM_OK)
            d->nominal_value = v;
    }
    if (fresh) {
        usm_yield_result yr;
        if (usm_yield_eval(fresh, &d->params, rp->nominal.t0, rp->threads, -1, &yr) != USM_OK) {
            snprintf(c->msg, USM_MSG_LEN, "yield: %.200s", usm_yield_message(fresh));
            return USM_EFAILED;
        }
        d->yield = yr.yield;
        d->yield_lo = yr.yield_lo;
        d->yield_hi = yr.yield_hi;
        d->verify_samples = yr.samples;
        progress_add(&c->meter, verify_weight(rp));
    }
    return USM_OK;
}

int usm_robust_run(const usm_model *m, const usm_params *p, const usm_robust_problem *rp,
                   usm_robust_result *res, char msg[USM_MSG_LEN])
{
    const double t_start = now();
    memset(res, 0, sizeof *res);
    msg[0] = '\0';
    if (usm_robust_problem_check(rp, m, p, msg) != USM_OK)
        return USM_EINPUT;
    ctx *c = calloc(1, sizeof *c);
    usm_yield *fresh = NULL;
    if (!c) {
        snprintf(msg, USM_MSG_LEN, "out of memory");
        return USM_EFAILED;
    }
    c->m = m;
    c->rp = rp;
    c->base = *p;
    c->n = rp->nominal.nvary;
    c->larger_better = rp->objective == USM_ROBUST_YIELD || !rp->nominal.minimize;
    c->ncons = cons_texts(c);
    c->obj_scale = 1.0;
    int status = USM_OK;
    if (rp->nscatter > 0) {
        c->crn = usm_yield_alloc(m, rp->scatter, rp->nscatter, rp->samples, rp->seed, msg);
        fresh = c->crn ? usm_yield_alloc(m, rp->scatter, rp->nscatter, rp->verify_samples,
                                         rp->seed + 1, msg)
                       : NULL;
        if (!c->crn || !fresh) {
            usm_yield_free(c->crn);
            usm_yield_free(fresh);
            free(c);
            return USM_EINPUT;
        }
        usm_yield_allow_driven(c->crn, rp->nominal.allow_driven);
        usm_yield_allow_driven(fresh, rp->nominal.allow_driven);
        for (int i = 0; i < rp->nominal.ncons; ++i) {
            usm_yield_spec_add(c->crn, rp->nominal.cons[i].output, rp->nominal.cons[i].upper,
                               rp->nominal.cons[i].value);
            usm_yield_spec_add(fresh, rp->nominal.cons[i].output, rp->nominal.cons[i].upper,
                               rp->nominal.cons[i].value);
        }
        /* the CRN sample estimates the yield with its own error: the search
         * asks two of its standard errors more, so that the fresh sample
         * confirms the constraint */
        if (!isnan(rp->yield_min))
            c->yield_target = fmin(1.0, rp->yield_min + 2.0 * sqrt(rp->yield_min *
                                   (1 - rp->yield_min) / (double)rp->samples));
    }
    /* the nominal optimum: the same problem without the scatter */
    double x0[USM_NPARAMS];
    int have_nominal = 0;
    for (int j = 0; j < c->n; ++j)
        x0[j] = 0.5;
    const int try_nominal = rp->objective < USM_OPT_OUTPUT_COUNT && rp->qopt.range.param < 0 &&
                            usm_opt_output_analytic(rp->objective) == 1 && rp->nderived == 0;
    {
        /* the planned designs: each phase's start and budget, and the
         * described designs with their verification samples; a search that
         * starts again adds its budget */
        const int coarse = rp->samples >= 4000 && c->crn;
        const long describe_cost = 1 + verify_weight(rp);
        long total = 1 + rp->max_evals + describe_cost * (try_nominal ? 2 : 1);
        if (coarse)
            total += 1 + (rp->max_evals + 1) / 2;
        progress_start(&c->meter, &rp->nominal.progress, total, 0, "designs");
    }
    if (try_nominal) {
        usm_optimize *o = usm_optimize_alloc(m);
        usm_opt_result *r = malloc(sizeof *r);
        usm_opt_problem pb = rp->nominal;
        pb.objective = rp->objective;
        pb.no_flat = 1;
        if (o && r && usm_optimize_run(o, p, &pb, r) == USM_OK) {
            have_nominal = 1;
            for (int j = 0; j < c->n; ++j)
                x0[j] = (usm_params_get(&r->params, &usm_param_table[pb.vary[j]]) - pb.lo[j]) /
                        (pb.hi[j] - pb.lo[j]);
        }
        free(r);
        usm_optimize_free(o);
    }
    if (have_nominal) {
        if ((status = describe(c, x0, fresh, &res->nominal)) != USM_OK)
            goto done;
        res->nominal.feasible = 1; /* feasible as a nominal design; value: the
                                      robust objective (the statistic) there */
    }
    /* Two fidelities: COBYLA on the first eighth of the common random
     * numbers (the same draws: the set is drawn sequentially) from the
     * nominal optimum (else the box's centre; a second run from the centre
     * when the first ends infeasible) finds the region cheaply; then on the
     * whole set from the best point found, with a smaller first step and
     * half the designs.  Each phase's yield target carries its own sample's
     * margin.  Sets under 4000 samples skip the first phase (it takes at
     * least 1000: a yield near 0.99 needs them). */
    double x[USM_NPARAMS];
    memcpy(x, x0, sizeof x);
    const int coarse = rp->samples >= 4000 && c->crn;
    usm_yield *full = c->crn;
    for (int phase = coarse ? 0 : 1; phase < 2; ++phase) {
        const uint64_t ns = phase == 0 ? (rp->samples / 8 > 1000 ? rp->samples / 8 : 1000)
                                       : rp->samples;
        usm_yield *set = full;
        if (phase == 0) {
            set = usm_yield_alloc(m, rp->scatter, rp->nscatter, ns, rp->seed, msg);
            if (!set) {
                status = USM_EFAILED;
                goto done;
            }
            usm_yield_allow_driven(set, rp->nominal.allow_driven);
            for (int i = 0; i < rp->nominal.ncons; ++i)
                usm_yield_spec_add(set, rp->nominal.cons[i].output, rp->nominal.cons[i].upper,
                                   rp->nominal.cons[i].value);
        }
        c->crn = set;
        if (!isnan(rp->yield_min) && set)
            c->yield_target = fmin(1.0, rp->yield_min + 2.0 * sqrt(rp->yield_min *
                                   (1 - rp->yield_min) / (double)ns));
        c->have = 0;
        c->best_have = 0;
        evaluate(c, x); /* the start's objective: COBYLA's scale */
        c->obj_scale = isfinite(c->obj) && c->obj != 0 ? fabs(c->obj) : 1.0;
        const int budget = phase == 0 || !coarse ? rp->max_evals : (rp->max_evals + 1) / 2;
        const double rho = phase == 0 || !coarse ? RHO_BEGIN : RHO_BEGIN / 4;
        int bad = cobyla(c, x, budget, rho) != 0 || c->failed;
        if (!bad && !(c->best_have && c->best_viol <= 0) && phase == 1 && coarse) {
            /* the whole set disagrees with the first phase's region: a full
             * search from its best point */
            if (c->best_have)
                memcpy(x, c->best_x, sizeof x);
            progress_extend(&c->meter, rp->max_evals);
            bad = cobyla(c, x, rp->max_evals, RHO_BEGIN) != 0 || c->failed;
        }
        if (!bad && !(c->best_have && c->best_viol <= 0) && have_nominal &&
            (phase == 0 || !coarse)) {
            for (int j = 0; j < c->n; ++j)
                x[j] = 0.5;
            progress_extend(&c->meter, budget);
            bad = cobyla(c, x, budget, RHO_BEGIN) != 0 || c->failed;
        }
        if (phase == 0)
            usm_yield_free(set);
        c->crn = full;
        if (bad) {
            snprintf(msg, USM_MSG_LEN, "%s", c->failed ? c->msg : "NLopt refused the problem");
            status = USM_EFAILED;
            goto done;
        }
        if (c->best_have)
            memcpy(x, c->best_x, sizeof x);
    }
    double xb[USM_NPARAMS];
    memcpy(xb, c->best_x, sizeof xb);
    if ((status = describe(c, xb, fresh, &res->robust)) != USM_OK)
        goto done;
    /* active constraints and bounds at the chosen design */
    for (int i = 0; i < c->ncons && res->nactive < USM_OPT_MAX_ACTIVE; ++i) {
        const int is_yield = !isnan(rp->yield_min) && i == c->ncons - 1;
        const double tol = is_yield ? 3.0 / (double)rp->samples / (1 - rp->yield_min) : ACTIVE_TOL;
        if (fabs(c->cons[i]) <= tol)
            snprintf(res->active[res->nactive++], USM_OPT_TEXT_LEN, "%s", c->text[i]);
    }
    for (int j = 0; j < c->n && res->nactive < USM_OPT_MAX_ACTIVE; ++j)
        if (xb[j] <= BOUND_TOL || xb[j] >= 1 - BOUND_TOL)
            snprintf(res->active[res->nactive++], USM_OPT_TEXT_LEN, "bound: %s = %s",
                     usm_param_table[rp->nominal.vary[j]].name, xb[j] <= BOUND_TOL ? "LO" : "HI");
    if (fresh) {
        const double n1 = (double)rp->samples, n2 = (double)rp->verify_samples;
        const double y1 = res->robust.crn_yield, y2 = res->robust.yield;
        const double se = sqrt(y1 * (1 - y1) / n1 + y2 * (1 - y2) / n2 + 1.0 / (n1 * n2));
        res->verified = !isnan(rp->yield_min) ? y2 >= rp->yield_min : fabs(y1 - y2) <= 3 * se;
    } else
        res->verified = 1;
    res->evaluations = c->evaluations;
    if (!res->robust.feasible) {
        char worst[USM_OPT_TEXT_LEN] = "";
        double wv = -INFINITY;
        for (int i = 0; i < c->ncons && c->ok; ++i)
            if (c->cons[i] > wv) {
                wv = c->cons[i];
                snprintf(worst, sizeof worst, "%s", c->text[i]);
            }
        /* each reason a sentence of its own: a constraint, a missing objective, no point */
        if (c->ok && isnan(c->obj))
            snprintf(msg, USM_MSG_LEN, "constraint: no feasible design found: the objective %s "
                     "has no value (no operating point) at the best design",
                     usm_robust_quantity_name(rp->objective));
        else if (worst[0])
            snprintf(msg, USM_MSG_LEN, "constraint: no feasible design found: %s cannot be met",
                     worst);
        else
            snprintf(msg, USM_MSG_LEN, "constraint: no feasible design found: no design tried "
                     "has a stationary solution with an operating point");
        status = USM_ENOSOLUTION;
    }
    progress_finish(&c->meter); /* the searches converged within their budgets */
done:
    res->seconds = now() - t_start;
    usm_yield_free(c->crn);
    usm_yield_free(fresh);
    free(c);
    return status;
}
