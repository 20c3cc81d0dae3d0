/* The best design over parameter bounds (usm_optimize.h): NLopt SLSQP with
 * the analytic sensitivities as gradients, from several deterministic starts. */
#include "usm_optimize.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <nlopt.h>

#define FEAS_TOL 1e-6   /* constraint violation accepted, in the scaled units */
#define ACTIVE_TOL 1e-5 /* a constraint this close to its bound is active */
#define MAX_EVALS 300   /* per start */
#define MAX_CONS (USM_OPT_MAX_CONSTRAINTS + 2)

typedef struct cons_ctx cons_ctx;

struct usm_optimize {
    const usm_model *model;
    usm_steady *steady;
    usm_sensitivity *sens;
    usm_floquet *floquet;
    usm_sensitivity_result *r;
    /* the run */
    const usm_opt_problem *pb;
    usm_params base, p;
    double x[USM_NPARAMS];
    int have;             /* x evaluated (NLopt asks for the objective and
                             each constraint at the same x separately) */
    int solved;           /* a stationary solution exists at x */
    usm_steady_solution sol;
    int evaluations;
    int failed;           /* a numerical failure (not "no solution") */
    double obj_scale;
    char msg[USM_MSG_LEN];
};

struct cons_ctx {
    usm_optimize *o;
    int kind;        /* 0 stability, 1 stick, 2 user */
    int index;       /* user constraint index */
    double scale;
};

/* ---- the problem ------------------------------------------------------------------ */

void usm_opt_problem_init(usm_opt_problem *pb)
{
    memset(pb, 0, sizeof *pb);
    pb->objective = -1;
    pb->margin = 0.01;
    pb->starts = 8;
}

int usm_opt_problem_add_vary(usm_opt_problem *pb, const char *name, double lo, double hi,
                             char msg[USM_MSG_LEN])
{
    const usm_param_info *info = usm_params_find(name);
    if (!info) {
        snprintf(msg, USM_MSG_LEN, "vary: unknown parameter \"%s\"", name);
        return USM_EINPUT;
    }
    int j = (int)(info - usm_param_table);
    for (int k = 0; k < pb->nvary; ++k)
        if (pb->vary[k] == j) {
            snprintf(msg, USM_MSG_LEN, "vary: %s given twice", name);
            return USM_EINPUT;
        }
    if (!(lo < hi)) {
        snprintf(msg, USM_MSG_LEN, "vary: %s: LO (%g) must be less than HI (%g)", name, lo, hi);
        return USM_EINPUT;
    }
    pb->vary[pb->nvary] = j;
    pb->lo[pb->nvary] = lo;
    pb->hi[pb->nvary] = hi;
    pb->nvary++;
    return USM_OK;
}

int usm_opt_problem_add_constraint(usm_opt_problem *pb, const char *output, int upper,
                                   double value, char msg[USM_MSG_LEN])
{
    int k = usm_sensitivity_output_find(output);
    if (k < 0) {
        snprintf(msg, USM_MSG_LEN, "constraint: unknown output \"%s\"", output);
        return USM_EINPUT;
    }
    if (pb->ncons == USM_OPT_MAX_CONSTRAINTS) {
        snprintf(msg, USM_MSG_LEN, "constraint: at most %d", USM_OPT_MAX_CONSTRAINTS);
        return USM_EINPUT;
    }
    pb->cons[pb->ncons++] = (usm_opt_constraint){k, upper != 0, value};
    return USM_OK;
}

int usm_opt_problem_check(const usm_opt_problem *pb, const usm_model *m, const usm_params *p,
                          char msg[USM_MSG_LEN])
{
    if (pb->objective < 0 || pb->objective >= USM_SENS_COUNT) {
        snprintf(msg, USM_MSG_LEN, "objective: required");
        return USM_EINPUT;
    }
    if (pb->nvary < 1 || pb->nvary > USM_NPARAMS) {
        snprintf(msg, USM_MSG_LEN, "vary: at least one NAME=LO:HI is required");
        return USM_EINPUT;
    }
    if (!(pb->margin >= 0 && pb->margin < 1)) {
        snprintf(msg, USM_MSG_LEN, "stability-margin: must be in [0, 1)");
        return USM_EINPUT;
    }
    if (!(pb->starts >= 1 && pb->starts <= 1000)) {
        snprintf(msg, USM_MSG_LEN, "starts: must be an integer in [1, 1000]");
        return USM_EINPUT;
    }
    if (pb->ncons < 0 || pb->ncons > USM_OPT_MAX_CONSTRAINTS) {
        snprintf(msg, USM_MSG_LEN, "constraint: at most %d", USM_OPT_MAX_CONSTRAINTS);
        return USM_EINPUT;
    }
    for (int i = 0; i < pb->ncons; ++i)
        if (!usm_sensitivity_output_name(pb->cons[i].output) || !isfinite(pb->cons[i].value)) {
            snprintf(msg, USM_MSG_LEN, "constraint: %d: unknown output or bound not finite", i);
            return USM_EINPUT;
        }
    /* every corner of the box must be admissible parameters */
    for (int k = 0; k < pb->nvary; ++k) {
        if (pb->vary[k] < 0 || pb->vary[k] >= USM_NPARAMS || !(pb->lo[k] < pb->hi[k])) {
            snprintf(msg, USM_MSG_LEN, "vary: %d: unknown parameter or LO >= HI", k);
            return USM_EINPUT;
        }
        const usm_param_info *info = &usm_param_table[pb->vary[k]];
        for (int side = 0; side < 2; ++side) {
            usm_params q = *p;
            char m2[USM_MSG_LEN];
            *usm_params_field(&q, info) = side ? pb->hi[k] : pb->lo[k];
            usm_params_couple(m, &q, pb->vary[k]);
            if (usm_params_check(&q, m, m2) != USM_OK) {
                snprintf(msg, USM_MSG_LEN, "vary: %.240s", m2);
                return USM_EINPUT;
            }
        }
        const usm_param_coupling *c = usm_param_coupled(m, pb->vary[k]);
        if (c) {
            snprintf(msg, USM_MSG_LEN, "vary: %s equals %s in model %s (vary %s)", info->name,
                     usm_param_table[c->equals].name, m->name, usm_param_table[c->equals].name);
            return USM_EINPUT;
        }
    }
    return USM_OK;
}

/* ---- evaluation ------------------------------------------------------------------ */

/* Evaluate the design at normalised x (z in [0, 1] per varied parameter). */
static void evaluate(usm_optimize *o, const double *x)
{
    const usm_opt_problem *pb = o->pb;
    if (o->have && memcmp(x, o->x, sizeof(double) * (size_t)pb->nvary) == 0)
        return;
    memcpy(o->x, x, sizeof(double) * (size_t)pb->nvary);
    o->have = 1;
    o->solved = 0;
    o->evaluations++;
    o->p = o->base;
    for (int k = 0; k < pb->nvary; ++k) {
        /* lo + 1 * (hi - lo) can round one step past hi: the bounds are the user's */
        *usm_params_field(&o->p, &usm_param_table[pb->vary[k]]) =
            fmin(pb->hi[k], fmax(pb->lo[k], pb->lo[k] + x[k] * (pb->hi[k] - pb->lo[k])));
        usm_params_couple(o->model, &o->p, pb->vary[k]);
    }
    if (usm_steady_solve(o->steady, &o->p, NULL) != USM_OK)
        return;
    o->sol = *usm_steady_root(o->steady, 0);
    /* the stability constraint is always there, so max_modulus is always needed */
    if (usm_sensitivity_compute(o->sens, &o->p, &o->sol, 1, o->r) != USM_OK) {
        o->failed = 1;
        snprintf(o->msg, USM_MSG_LEN, "%s", usm_sensitivity_message(o->sens));
        return;
    }
    o->solved = 1;
}

/* y and dy/dz of output k at the current point; -1 when not defined there
 * (the value can exist without the derivative: a kink of max_modulus). */
static int output(const usm_optimize *o, int k, double *y, double *grad)
{
    const usm_opt_problem *pb = o->pb;
    const usm_sensitivity_result *r = o->r;
    if (!o->solved || (grad && !r->defined[k]) || !isfinite(r->value[k]))
        return -1;
    /* rotor_speed is optimised in magnitude */
    const double s = k == USM_SENS_ROTOR_SPEED && r->value[k] < 0 ? -1.0 : 1.0;
    *y = s * r->value[k];
    if (grad)
        for (int i = 0; i < pb->nvary; ++i) {
            double d = r->d[k][pb->vary[i]];
            for (int j = 0; j < USM_NPARAMS; ++j) { /* the parameters tied to it move too */
                const usm_param_coupling *c = usm_param_coupled(o->model, j);
                if (c && c->equals == pb->vary[i])
                    d += r->d[k][j];
            }
            grad[i] = s * d * (pb->hi[i] - pb->lo[i]);
        }
    return 0;
}

/* Constraint c(x) <= 0 in scaled units. */
static double cons_value(const cons_ctx *c, const double *x, double *grad)
{
    usm_optimize *o = c->o;
    const usm_opt_problem *pb = o->pb;
    evaluate(o, x);
    double y, g[USM_NPARAMS];
    int k = c->kind == 0 ? USM_SENS_MAX_MODULUS
            : c->kind == 1 ? USM_SENS_STICK_MARGIN
                           : pb->cons[c->index].output;
    if (output(o, k, &y, grad ? g : NULL) != 0) {
        /* no solution (or no derivative): infeasible, no direction */
        if (grad)
            memset(grad, 0, sizeof(double) * (size_t)pb->nvary);
        return 1.0;
    }
    double sign, bound;
    if (c->kind == 0) {
        sign = 1;
        bound = 1 - pb->margin;
    } else if (c->kind == 1) {
        sign = -1;
        bound = 0;
    } else {
        sign = pb->cons[c->index].upper ? 1 : -1;
        bound = pb->cons[c->index].value;
    }
    if (grad)
        for (int i = 0; i < pb->nvary; ++i)
            grad[i] = sign * g[i] / c->scale;
    return sign * (y - bound) / c->scale;
}

static double nl_constraint(unsigned n, const double *x, double *grad, void *data)
{
    (void)n;
    return cons_value(data, x, grad);
}

/* NLopt minimises: f = -y / scale to maximise. */
static double nl_objective(unsigned n, const double *x, double *grad, void *data)
{
    usm_optimize *o = data;
    const usm_opt_problem *pb = o->pb;
    (void)n;
    evaluate(o, x);
    double y, g[USM_NPARAMS];
    const double s = pb->minimize ? 1.0 : -1.0;
    if (output(o, pb->objective, &y, grad ? g : NULL) != 0) {
        if (grad)
            memset(grad, 0, sizeof(double) * (size_t)pb->nvary);
        return 1e30; /* no solution here: worse than anything */
    }
    if (grad)
        for (int i = 0; i < pb->nvary; ++i)
            grad[i] = s * g[i] / o->obj_scale;
    return s * y / o->obj_scale;
}

/* ---- the optimisation --------------------------------------------------------------- */

typedef struct best {
    int have;
    double x[USM_NPARAMS];
    double value;                  /* objective in its own sense */
    double violation;              /* largest scaled violation (<= FEAS_TOL: feasible) */
    char worst[USM_OPT_TEXT_LEN];  /* the most violated constraint */
} best;

static int constraints(usm_optimize *o, cons_ctx *cc)
{
    int n = 0;
    cc[n++] = (cons_ctx){o, 0, 0, 1.0};
    if (!o->model->slip && !o->pb->allow_slip)
        cc[n++] = (cons_ctx){o, 1, 0, 1.0};
    for (int i = 0; i < o->pb->ncons; ++i)
        cc[n++] = (cons_ctx){o, 2, i, 1.0};
    return n;
}

static void cons_text(const usm_opt_problem *pb, const cons_ctx *c, char buf[USM_OPT_TEXT_LEN])
{
    if (c->kind == 0)
        snprintf(buf, USM_OPT_TEXT_LEN, "stability: max_modulus <= %g", 1 - pb->margin);
    else if (c->kind == 1)
        snprintf(buf, USM_OPT_TEXT_LEN, "stick: F_t <= mu0 F_n");
    else {
        const usm_opt_constraint *u = &pb->cons[c->index];
        snprintf(buf, USM_OPT_TEXT_LEN, "%s %s %g", usm_sensitivity_output_name(u->output),
                 u->upper ? "<=" : ">=", u->value);
    }
}

/* Largest scaled violation at x and the constraint it belongs to. */
static double violation(usm_optimize *o, cons_ctx *cc, int nc, const double *x,
                        char worst[USM_OPT_TEXT_LEN])
{
    double v = -INFINITY;
    evaluate(o, x);
    if (!o->solved) {
        snprintf(worst, USM_OPT_TEXT_LEN, "a stationary solution exists");
        return INFINITY;
    }
    for (int i = 0; i < nc; ++i) {
        double ci = cons_value(&cc[i], x, NULL);
        if (ci > v) {
            v = ci;
            cons_text(o->pb, &cc[i], worst);
        }
    }
    return v;
}

/* Scales: constraint values relative to a typical size (stick: F_n; user: |X|). */
static void set_scales(usm_optimize *o, cons_ctx *cc, int nc)
{
    for (int i = 0; i < nc; ++i) {
        if (cc[i].kind == 1)
            cc[i].scale = o->solved ? fmax(fabs(o->sol.F_n), 1e-12) : 1.0;
        else if (cc[i].kind == 2) {
            const usm_opt_constraint *u = &o->pb->cons[cc[i].index];
            double v = fabs(u->value);
            double y = o->solved ? fabs(o->r->value[u->output]) : 0;
            cc[i].scale = v > 0 ? v : y > 0 ? y : 1.0;
        }
    }
}

/* KKT residual at x in the normalised variables: |grad f + sum lambda_i grad c_i|
 * over the free variables (not at a bound), lambda >= 0 of the active
 * constraints by least squares, relative to |grad f|. */
static double kkt_residual(usm_optimize *o, cons_ctx *cc, int nc, const double *x,
                           usm_opt_result *out)
{
    const usm_opt_problem *pb = o->pb;
    const int n = pb->nvary;
    double g[USM_NPARAMS], A[MAX_CONS][USM_NPARAMS];
    int na = 0;
    nl_objective((unsigned)n, x, g, o);
    out->nactive = 0;
    for (int i = 0; i < nc; ++i) {
        double gi[USM_NPARAMS];
        double ci = cons_value(&cc[i], x, gi);
        if (fabs(ci) <= ACTIVE_TOL) {
            memcpy(A[na++], gi, sizeof gi);
            cons_text(pb, &cc[i], out->active[out->nactive++]);
        }
    }
    int free_var[USM_NPARAMS];
    for (int j = 0; j < n; ++j) {
        free_var[j] = 1;
        if (x[j] <= 1e-9 || x[j] >= 1 - 1e-9) {
            snprintf(out->active[out->nactive++], USM_OPT_TEXT_LEN, "bound: %s = %s",
                     usm_param_table[pb->vary[j]].name, x[j] <= 1e-9 ? "LO" : "HI");
            free_var[j] = 0;
        }
    }
    /* projected gradient descent on lambda >= 0: tiny problem, a few hundred sweeps */
    double lambda[MAX_CONS] = {0};
    for (int it = 0; it < 500 && na > 0; ++it)
        for (int i = 0; i < na; ++i) {
            double num = 0, den = 0;
            for (int j = 0; j < n; ++j) {
                if (!free_var[j])
                    continue;
                double rj = g[j];
                for (int l = 0; l < na; ++l)
                    if (l != i)
                        rj += lambda[l] * A[l][j];
                num -= rj * A[i][j];
                den += A[i][j] * A[i][j];
            }
            lambda[i] = den > 0 ? fmax(0, num / den) : 0;
        }
    double res = 0, gn = 0;
    for (int j = 0; j < n; ++j) {
        if (!free_var[j])
            continue;
        double rj = g[j];
        for (int l = 0; l < na; ++l)
            rj += lambda[l] * A[l][j];
        res = fmax(res, fabs(rj));
        gn = fmax(gn, fabs(g[j]));
    }
    return gn > 0 ? res / gn : res;
}

static int run_starts(usm_optimize *o, best *b, cons_ctx *cc, int nc)
{
    const usm_opt_problem *pb = o->pb;
    const int n = pb->nvary;
    double lb[USM_NPARAMS], ub[USM_NPARAMS];
    for (int j = 0; j < n; ++j) {
        lb[j] = 0;
        ub[j] = 1;
    }
    for (int s = 0; s < pb->starts; ++s) {
        double x[USM_NPARAMS];
        /* deterministic spread: a rank-1 lattice (golden-ratio offsets) */
        for (int j = 0; j < n; ++j)
            x[j] = fmod((s + 0.5) / pb->starts + j * 0.6180339887498949, 1.0);
        evaluate(o, x);
        if (o->failed)
            return USM_EFAILED;
        double y;
        o->obj_scale = 1.0;
        if (output(o, pb->objective, &y, NULL) == 0 && y != 0)
            o->obj_scale = fabs(y);
        set_scales(o, cc, nc);
        nlopt_opt opt = nlopt_create(NLOPT_LD_SLSQP, (unsigned)n);
        if (!opt) {
            snprintf(o->msg, USM_MSG_LEN, "out of memory");
            return USM_EFAILED;
        }
        int ok = nlopt_set_lower_bounds(opt, lb) > 0 && nlopt_set_upper_bounds(opt, ub) > 0 &&
                 nlopt_set_min_objective(opt, nl_objective, o) > 0 &&
                 nlopt_set_xtol_rel(opt, 1e-10) > 0 && nlopt_set_ftol_rel(opt, 1e-12) > 0 &&
                 nlopt_set_maxeval(opt, MAX_EVALS) > 0;
        for (int i = 0; i < nc && ok; ++i)
            ok = nlopt_add_inequality_constraint(opt, nl_constraint, &cc[i], 1e-10) > 0;
        if (!ok) {
            nlopt_destroy(opt);
            snprintf(o->msg, USM_MSG_LEN, "NLopt refused the problem setup");
            return USM_EFAILED;
        }
        double f;
        nlopt_result res = nlopt_optimize(opt, x, &f);
        nlopt_destroy(opt);
        if (o->failed)
            return USM_EFAILED;
        if (res < 0 && res != NLOPT_ROUNDOFF_LIMITED && res != NLOPT_FAILURE)
            continue; /* this start failed; others may not */
        char worst[USM_OPT_TEXT_LEN];
        double v = violation(o, cc, nc, x, worst);
        if (!o->solved || output(o, pb->objective, &y, NULL) != 0)
            continue;
        const int feasible = v <= FEAS_TOL, best_feasible = b->have && b->violation <= FEAS_TOL;
        int better;
        if (!b->have)
            better = 1;
        else if (feasible != best_feasible)
            better = feasible;
        else if (feasible)
            better = pb->minimize ? y < b->value : y > b->value;
        else
            better = v < b->violation;
        if (better) {
            b->have = 1;
            memcpy(b->x, x, sizeof(double) * (size_t)n);
            b->value = y;
            b->violation = v;
            snprintf(b->worst, sizeof b->worst, "%s", worst);
        }
    }
    return USM_OK;
}

usm_optimize *usm_optimize_alloc(const usm_model *m)
{
    if (!m)
        return NULL;
    usm_optimize *o = calloc(1, sizeof *o);
    if (!o)
        return NULL;
    o->model = m;
    o->steady = usm_steady_alloc(m);
    o->sens = usm_sensitivity_alloc(m);
    o->floquet = usm_floquet_alloc(m);
    o->r = malloc(sizeof *o->r);
    if (!o->steady || !o->sens || !o->floquet || !o->r) {
        usm_optimize_free(o);
        return NULL;
    }
    return o;
}

void usm_optimize_free(usm_optimize *o)
{
    if (!o)
        return;
    free(o->r);
    usm_floquet_free(o->floquet);
    usm_sensitivity_free(o->sens);
    usm_steady_free(o->steady);
    free(o);
}

const usm_steady *usm_optimize_steady(const usm_optimize *o)
{
    return o->steady;
}

const char *usm_optimize_message(const usm_optimize *o)
{
    return o->msg;
}

int usm_optimize_run(usm_optimize *o, const usm_params *p, const usm_opt_problem *pb,
                     usm_opt_result *out)
{
    o->msg[0] = '\0';
    if (usm_opt_problem_check(pb, o->model, p, o->msg) != USM_OK)
        return USM_EINPUT;
    o->pb = pb;
    o->base = *p;
    o->have = o->solved = o->failed = 0;
    o->evaluations = 0;
    best b;
    memset(&b, 0, sizeof b);
    cons_ctx cc[MAX_CONS];
    int nc = constraints(o, cc);
    int status = run_starts(o, &b, cc, nc);
    if (status != USM_OK) {
        if (!o->msg[0])
            snprintf(o->msg, USM_MSG_LEN, "numerical failure");
        return status;
    }
    if (!b.have) {
        snprintf(o->msg, USM_MSG_LEN,
                 "constraint: no feasible point found: no stationary solution at any of the "
                 "%d starts' end points", pb->starts);
        return USM_ENOSOLUTION;
    }
    if (b.violation > FEAS_TOL) {
        snprintf(o->msg, USM_MSG_LEN,
                 "constraint: no feasible point found: %s cannot be met (best violation %.3g)",
                 b.worst, b.violation);
        return USM_ENOSOLUTION;
    }
    o->have = 0; /* re-evaluate at the optimum: the state NLopt left is another point's */
    evaluate(o, b.x);
    if (o->failed || !o->solved) {
        snprintf(o->msg, USM_MSG_LEN, "the optimum did not re-solve");
        return USM_EFAILED;
    }
    out->kkt_residual = kkt_residual(o, cc, nc, b.x, out);
    if (usm_floquet_compute(o->floquet, &o->p, &o->sol, 0.0, NULL, &out->floquet) != USM_OK) {
        snprintf(o->msg, USM_MSG_LEN, "floquet: %.240s", usm_floquet_message(o->floquet));
        return USM_EFAILED;
    }
    out->value = b.value;
    out->params = o->p;
    out->sol = o->sol;
    out->evaluations = o->evaluations;
    return USM_OK;
}
