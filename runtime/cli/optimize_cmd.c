/* usm optimize: best design over parameter bounds, subject to a stationary
 * solution existing, being stable with a margin, sticking (stick model) and
 * user constraints.  NLopt's SLSQP with the analytic sensitivities
 * (usm_design.h) as gradients, from several deterministic starts. */
#define _POSIX_C_SOURCE 200809L /* strtok_r */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <jansson.h>
#include <nlopt.h>

#include "commands.h"
#include "diag.h"
#include "json_out.h"
#include "options.h"
#include "steady_out.h"
#include "usm_design.h"

#define MAX_CONS 32
#define FEAS_TOL 1e-6   /* constraint violation accepted, in the scaled units */
#define ACTIVE_TOL 1e-5 /* a constraint this close to its bound is active */
#define MAX_EVALS 300   /* per start */

typedef struct constraint {
    int output;   /* USM_SENS_* */
    int upper;    /* 1: OUTPUT <= value, 0: OUTPUT >= value */
    double value;
    char text[128];
} constraint;

typedef struct opt_args {
    cli_common common;
    int objective, minimize;
    int nvary, vary[USM_NPARAMS];
    double lo[USM_NPARAMS], hi[USM_NPARAMS];
    int ncons;
    constraint cons[MAX_CONS];
    double margin;
    int allow_slip, starts, help;
} opt_args;

/* One evaluated design point (cached: NLopt asks for the objective and each
 * constraint at the same x separately). */
typedef struct problem {
    const opt_args *a;
    usm_steady *steady;
    usm_sensitivity *sens;
    usm_params p;
    double x[USM_NPARAMS];
    int have;             /* x evaluated */
    int solved;           /* a stationary solution exists at x */
    usm_steady_solution sol;
    usm_sensitivity_result *r;
    int evaluations;
    int failed;           /* a numerical failure (not "no solution") */
    char msg[USM_MSG_LEN];
} problem;

static void usage(FILE *out)
{
    fprintf(out,
            "usage: usm optimize --objective NAME [--minimize] --vary NAME=LO:HI [--vary ...]\n"
            "                    [--constraint OUTPUT>=X | OUTPUT<=X]... [--stability-margin D]\n"
            "                    [--allow-slip] [--starts N] [--model M] [--variant V]\n"
            "                    [--params F] [--set N=V]... [--json]\n"
            "\n"
            "Maximize (default) or minimize an output of the primary stationary solution over\n"
            "the --vary parameters within their bounds, subject to: a stationary solution\n"
            "exists; max_modulus <= 1 - D (--stability-margin, default 0.01); stick is\n"
            "admissible in the stick model (F_t <= mu0 F_n) unless --allow-slip; every\n"
            "--constraint.  NLopt SLSQP with the analytic sensitivities as gradients, from\n"
            "--starts (default 8) deterministic points spread over the box; the best\n"
            "feasible result wins.\n"
            "\n"
            "outputs (objective and constraints): rotor_speed (its magnitude), theta, F_n, F_t,\n"
            "efficiency, stick_margin, max_modulus, power_in, power_out\n"
            "\n"
            "options:\n");
    cli_common_usage(out);
    fprintf(out,
            "  -h, --help          print this help\n"
            "\n"
            "exit status: 0 optimum found, 1 numerical failure, 2 bad specification,\n"
            "             3 no feasible point (the message names the constraint)\n");
}

static int parse_vary(opt_args *a, const char *text, char msg[CLI_MSG_LEN])
{
    char name[64];
    const char *eq = strchr(text, '='), *colon = eq ? strchr(eq, ':') : NULL;
    if (!eq || !colon || (size_t)(eq - text) >= sizeof name || eq == text) {
        cli_msg(msg, "--vary: expected NAME=LO:HI, got \"%s\"", text);
        return USM_EINPUT;
    }
    memcpy(name, text, (size_t)(eq - text));
    name[eq - text] = '\0';
    const usm_param_info *info = usm_params_find(name);
    if (!info) {
        cli_msg(msg, "--vary: unknown parameter \"%s\"", name);
        return USM_EINPUT;
    }
    int j = (int)(info - usm_param_table);
    for (int k = 0; k < a->nvary; ++k)
        if (a->vary[k] == j) {
            cli_msg(msg, "--vary: %s given twice", name);
            return USM_EINPUT;
        }
    char lo_text[64];
    if ((size_t)(colon - eq - 1) >= sizeof lo_text) {
        cli_msg(msg, "--vary: expected NAME=LO:HI, got \"%s\"", text);
        return USM_EINPUT;
    }
    memcpy(lo_text, eq + 1, (size_t)(colon - eq - 1));
    lo_text[colon - eq - 1] = '\0';
    double lo, hi;
    if (cli_parse_double("--vary", lo_text, &lo, msg) != USM_OK ||
        cli_parse_double("--vary", colon + 1, &hi, msg) != USM_OK)
        return USM_EINPUT;
    if (!(lo < hi)) {
        cli_msg(msg, "--vary: %s: LO (%g) must be less than HI (%g)", name, lo, hi);
        return USM_EINPUT;
    }
    a->vary[a->nvary] = j;
    a->lo[a->nvary] = lo;
    a->hi[a->nvary] = hi;
    a->nvary++;
    return USM_OK;
}

static int parse_constraint(opt_args *a, const char *text, char msg[CLI_MSG_LEN])
{
    const char *op = strstr(text, ">=");
    int upper = 0;
    if (!op) {
        op = strstr(text, "<=");
        upper = 1;
    }
    char name[64];
    if (!op || op == text || (size_t)(op - text) >= sizeof name) {
        cli_msg(msg, "--constraint: expected OUTPUT>=X or OUTPUT<=X, got \"%s\"", text);
        return USM_EINPUT;
    }
    if (a->ncons == MAX_CONS) {
        cli_msg(msg, "--constraint: at most %d", MAX_CONS);
        return USM_EINPUT;
    }
    memcpy(name, text, (size_t)(op - text));
    name[op - text] = '\0';
    int k = usm_sensitivity_output_find(name);
    if (k < 0) {
        cli_msg(msg, "--constraint: unknown output \"%s\"", name);
        return USM_EINPUT;
    }
    constraint *c = &a->cons[a->ncons];
    if (cli_parse_double("--constraint", op + 2, &c->value, msg) != USM_OK)
        return USM_EINPUT;
    c->output = k;
    c->upper = upper;
    snprintf(c->text, sizeof c->text, "%s %s %g", name, upper ? "<=" : ">=", c->value);
    a->ncons++;
    return USM_OK;
}

static int parse(opt_args *a, int argc, char **argv, char msg[CLI_MSG_LEN])
{
    memset(a, 0, sizeof *a);
    cli_common_init(&a->common);
    a->objective = -1;
    a->margin = 0.01;
    a->starts = 8;
    for (int i = 1; i < argc; ++i) {
        const char *value;
        int r;
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            a->help = 1;
            return USM_OK;
        }
        if (strcmp(argv[i], "--minimize") == 0) {
            a->minimize = 1;
            continue;
        }
        if (strcmp(argv[i], "--allow-slip") == 0) {
            a->allow_slip = 1;
            continue;
        }
        if ((r = cli_common_option(&a->common, argc, argv, &i, msg)) == CLI_OPT_TAKEN)
            continue;
        if (r == CLI_OPT_ERROR)
            return USM_EINPUT;
        static const char *const opts[] = {"--objective", "--vary", "--constraint",
                                           "--stability-margin", "--starts"};
        int which = -1;
        for (int o = 0; o < 5 && which < 0; ++o) {
            if ((r = cli_option_value(argc, argv, &i, opts[o], &value, msg)) == CLI_OPT_ERROR)
                return USM_EINPUT;
            if (r == CLI_OPT_TAKEN)
                which = o;
        }
        if (which == 0) {
            a->objective = usm_sensitivity_output_find(value);
            if (a->objective < 0) {
                cli_msg(msg, "--objective: unknown output \"%s\" (see usm optimize --help)", value);
                return USM_EINPUT;
            }
        } else if (which == 1) {
            if (parse_vary(a, value, msg) != USM_OK)
                return USM_EINPUT;
        } else if (which == 2) {
            if (parse_constraint(a, value, msg) != USM_OK)
                return USM_EINPUT;
        } else if (which == 3) {
            if (cli_parse_double("--stability-margin", value, &a->margin, msg) != USM_OK)
                return USM_EINPUT;
            if (!(a->margin >= 0 && a->margin < 1)) {
                cli_msg(msg, "--stability-margin: must be in [0, 1)");
                return USM_EINPUT;
            }
        } else if (which == 4) {
            double n;
            if (cli_parse_double("--starts", value, &n, msg) != USM_OK)
                return USM_EINPUT;
            if (!(n >= 1 && n <= 1000 && n == floor(n))) {
                cli_msg(msg, "--starts: must be an integer in [1, 1000]");
                return USM_EINPUT;
            }
            a->starts = (int)n;
        } else {
            if (argv[i][0] == '-')
                cli_msg(msg, "%s: unknown option (see usm optimize --help)", argv[i]);
            else
                cli_msg(msg, "%s: unexpected argument (see usm optimize --help)", argv[i]);
            return USM_EINPUT;
        }
    }
    if (a->objective < 0) {
        cli_msg(msg, "--objective: required");
        return USM_EINPUT;
    }
    if (a->nvary == 0) {
        cli_msg(msg, "--vary: at least one NAME=LO:HI is required");
        return USM_EINPUT;
    }
    int rc = cli_common_finish(&a->common, msg);
    if (rc != USM_OK)
        return rc;
    /* every corner of the box must be admissible parameters */
    for (int k = 0; k < a->nvary; ++k) {
        const usm_param_info *info = &usm_param_table[a->vary[k]];
        for (int side = 0; side < 2; ++side) {
            usm_params q = a->common.params;
            char m2[USM_MSG_LEN];
            *usm_params_field(&q, info) = side ? a->hi[k] : a->lo[k];
            if (a->common.model->axisymmetric_stator && strcmp(info->name, "I_xx") == 0)
                q.I_yy = q.I_xx;
            if (usm_params_check(&q, a->common.model, m2) != USM_OK) {
                cli_msg(msg, "--vary: %s", m2);
                return USM_EINPUT;
            }
        }
        if (a->common.model->axisymmetric_stator && strcmp(info->name, "I_yy") == 0) {
            cli_msg(msg, "--vary: I_yy equals I_xx in model %s (vary I_xx)",
                    a->common.model->name);
            return USM_EINPUT;
        }
    }
    return USM_OK;
}

/* ---- evaluation ------------------------------------------------------------------ */

/* The stability constraint is always there, so max_modulus is always needed. */
static int uses_floquet(const opt_args *a)
{
    (void)a;
    return 1;
}

/* Evaluate the design at normalised x (z in [0, 1] per varied parameter). */
static void evaluate(problem *pb, const double *x)
{
    const opt_args *a = pb->a;
    if (pb->have && memcmp(x, pb->x, sizeof(double) * (size_t)a->nvary) == 0)
        return;
    memcpy(pb->x, x, sizeof(double) * (size_t)a->nvary);
    pb->have = 1;
    pb->solved = 0;
    pb->evaluations++;
    pb->p = a->common.params;
    for (int k = 0; k < a->nvary; ++k) {
        const usm_param_info *info = &usm_param_table[a->vary[k]];
        *usm_params_field(&pb->p, info) = a->lo[k] + x[k] * (a->hi[k] - a->lo[k]);
        if (a->common.model->axisymmetric_stator && strcmp(info->name, "I_xx") == 0)
            pb->p.I_yy = pb->p.I_xx;
    }
    int rc = usm_steady_solve(pb->steady, &pb->p, NULL);
    if (rc != USM_OK)
        return;
    pb->sol = *usm_steady_root(pb->steady, 0);
    rc = usm_sensitivity_compute(pb->sens, &pb->p, &pb->sol, uses_floquet(a), pb->r);
    if (rc != USM_OK) {
        pb->failed = 1;
        snprintf(pb->msg, USM_MSG_LEN, "%s", usm_sensitivity_message(pb->sens));
        return;
    }
    pb->solved = 1;
}

/* y and dy/dz of output k at the current point; -1 when not defined there
 * (the value can exist without the derivative: a kink of max_modulus). */
static int output(const problem *pb, int k, double *y, double *grad)
{
    const opt_args *a = pb->a;
    const usm_sensitivity_result *r = pb->r;
    if (!pb->solved || (grad && !r->defined[k]) || !isfinite(r->value[k]))
        return -1;
    /* rotor_speed is optimised in magnitude */
    const double s = k == USM_SENS_ROTOR_SPEED && r->value[k] < 0 ? -1.0 : 1.0;
    *y = s * r->value[k];
    if (grad)
        for (int i = 0; i < a->nvary; ++i) {
            double d = r->d[k][a->vary[i]];
            if (a->common.model->axisymmetric_stator &&
                strcmp(usm_param_table[a->vary[i]].name, "I_xx") == 0)
                d += r->d[k][13]; /* I_yy moves with I_xx (0 in these models) */
            grad[i] = s * d * (a->hi[i] - a->lo[i]);
        }
    return 0;
}

typedef struct cons_ctx {
    problem *pb;
    int kind;        /* 0 stability, 1 stick, 2 user */
    int index;       /* user constraint index */
    double scale;
} cons_ctx;

/* Constraint c(x) <= 0 in scaled units. */
static double cons_value(const cons_ctx *c, const double *x, double *grad)
{
    problem *pb = c->pb;
    const opt_args *a = pb->a;
    evaluate(pb, x);
    double y, g[USM_NPARAMS];
    int k = c->kind == 0 ? USM_SENS_MAX_MODULUS
            : c->kind == 1 ? USM_SENS_STICK_MARGIN
                           : a->cons[c->index].output;
    if (output(pb, k, &y, grad ? g : NULL) != 0) {
        /* no solution (or no derivative): infeasible, no direction */
        if (grad)
            memset(grad, 0, sizeof(double) * (size_t)a->nvary);
        return 1.0;
    }
    double sign, bound;
    if (c->kind == 0) {
        sign = 1;
        bound = 1 - a->margin;
    } else if (c->kind == 1) {
        sign = -1;
        bound = 0;
    } else {
        sign = a->cons[c->index].upper ? 1 : -1;
        bound = a->cons[c->index].value;
        if (k == USM_SENS_ROTOR_SPEED) /* the magnitude, like the objective */
            y = fabs(pb->r->value[k]);
    }
    if (grad)
        for (int i = 0; i < a->nvary; ++i)
            grad[i] = sign * g[i] / c->scale;
    return sign * (y - bound) / c->scale;
}

static double nl_constraint(unsigned n, const double *x, double *grad, void *data)
{
    (void)n;
    return cons_value(data, x, grad);
}

typedef struct obj_ctx {
    problem *pb;
    double scale;
} obj_ctx;

/* NLopt minimises: f = -y / scale to maximise. */
static double nl_objective(unsigned n, const double *x, double *grad, void *data)
{
    obj_ctx *o = data;
    problem *pb = o->pb;
    (void)n;
    evaluate(pb, x);
    double y, g[USM_NPARAMS];
    const double s = pb->a->minimize ? 1.0 : -1.0;
    if (output(pb, pb->a->objective, &y, grad ? g : NULL) != 0) {
        if (grad)
            memset(grad, 0, sizeof(double) * (size_t)pb->a->nvary);
        return 1e30; /* no solution here: worse than anything */
    }
    if (grad)
        for (int i = 0; i < pb->a->nvary; ++i)
            grad[i] = s * g[i] / o->scale;
    return s * y / o->scale;
}

/* ---- the optimisation --------------------------------------------------------------- */

typedef struct best {
    int have;
    double x[USM_NPARAMS];
    double value;        /* objective in its own sense */
    double violation;    /* largest scaled violation (<= FEAS_TOL: feasible) */
    char worst[128];     /* the most violated constraint */
} best;

static int ncons_total(const opt_args *a, cons_ctx *cc, problem *pb)
{
    int n = 0;
    cc[n++] = (cons_ctx){pb, 0, 0, 1.0};
    if (!a->common.model->slip && !a->allow_slip)
        cc[n++] = (cons_ctx){pb, 1, 0, 1.0};
    for (int i = 0; i < a->ncons; ++i)
        cc[n++] = (cons_ctx){pb, 2, i, 1.0};
    return n;
}

static const char *cons_text(const opt_args *a, const cons_ctx *c, char buf[128])
{
    if (c->kind == 0)
        snprintf(buf, 128, "stability: max_modulus <= %g", 1 - a->margin);
    else if (c->kind == 1)
        snprintf(buf, 128, "stick: F_t <= mu0 F_n");
    else
        snprintf(buf, 128, "%s", a->cons[c->index].text);
    return buf;
}

/* Largest scaled violation at x and the constraint it belongs to. */
static double violation(problem *pb, cons_ctx *cc, int nc, const double *x, char worst[128])
{
    double v = -INFINITY;
    char buf[128];
    evaluate(pb, x);
    if (!pb->solved) {
        snprintf(worst, 128, "a stationary solution exists");
        return INFINITY;
    }
    for (int i = 0; i < nc; ++i) {
        double ci = cons_value(&cc[i], x, NULL);
        if (ci > v) {
            v = ci;
            snprintf(worst, 128, "%s", cons_text(pb->a, &cc[i], buf));
        }
    }
    return v;
}

/* Scales: constraint values relative to a typical size (stick: F_n; user: |X|). */
static void set_scales(problem *pb, cons_ctx *cc, int nc)
{
    for (int i = 0; i < nc; ++i) {
        if (cc[i].kind == 1)
            cc[i].scale = pb->solved ? fmax(fabs(pb->sol.F_n), 1e-12) : 1.0;
        else if (cc[i].kind == 2) {
            double v = fabs(pb->a->cons[cc[i].index].value);
            double y = pb->solved ? fabs(pb->r->value[pb->a->cons[cc[i].index].output]) : 0;
            cc[i].scale = v > 0 ? v : y > 0 ? y : 1.0;
        }
    }
}

/* KKT residual at x in the normalised variables: |grad f + sum lambda_i grad c_i|
 * over the free variables (not at a bound), lambda >= 0 of the active
 * constraints by least squares, relative to |grad f|. */
static double kkt_residual(problem *pb, obj_ctx *oc, cons_ctx *cc, int nc, const double *x,
                           char active[][128], int *nactive)
{
    const opt_args *a = pb->a;
    const int n = a->nvary;
    double g[USM_NPARAMS], A[MAX_CONS + 2][USM_NPARAMS];
    int act[MAX_CONS + 2], na = 0;
    nl_objective((unsigned)n, x, g, oc);
    *nactive = 0;
    for (int i = 0; i < nc; ++i) {
        double gi[USM_NPARAMS];
        double ci = cons_value(&cc[i], x, gi);
        if (fabs(ci) <= ACTIVE_TOL) {
            memcpy(A[na], gi, sizeof gi);
            act[na++] = i;
            cons_text(a, &cc[i], active[(*nactive)++]);
        }
    }
    int free_var[USM_NPARAMS];
    for (int j = 0; j < n; ++j) {
        free_var[j] = 1;
        if (x[j] <= 1e-9 || x[j] >= 1 - 1e-9) {
            snprintf(active[(*nactive)++], 128, "bound: %s = %s", usm_param_table[a->vary[j]].name,
                     x[j] <= 1e-9 ? "LO" : "HI");
            free_var[j] = 0;
        }
    }
    /* projected gradient descent on lambda >= 0: tiny problem, a few hundred sweeps */
    double lambda[MAX_CONS + 2] = {0};
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
    (void)act;
    return gn > 0 ? res / gn : res;
}

static int run_starts(problem *pb, best *b, cons_ctx *cc, int nc, obj_ctx *oc)
{
    const opt_args *a = pb->a;
    const int n = a->nvary;
    double lb[USM_NPARAMS], ub[USM_NPARAMS];
    for (int j = 0; j < n; ++j) {
        lb[j] = 0;
        ub[j] = 1;
    }
    for (int s = 0; s < a->starts; ++s) {
        double x[USM_NPARAMS];
        /* deterministic spread: a rank-1 lattice (golden-ratio offsets) */
        for (int j = 0; j < n; ++j)
            x[j] = fmod((s + 0.5) / a->starts + j * 0.6180339887498949, 1.0);
        evaluate(pb, x);
        if (pb->failed)
            return USM_EFAILED;
        double y;
        oc->scale = 1.0;
        if (output(pb, a->objective, &y, NULL) == 0 && y != 0)
            oc->scale = fabs(y);
        set_scales(pb, cc, nc);
        nlopt_opt opt = nlopt_create(NLOPT_LD_SLSQP, (unsigned)n);
        if (!opt)
            return USM_EFAILED;
        int ok = nlopt_set_lower_bounds(opt, lb) > 0 && nlopt_set_upper_bounds(opt, ub) > 0 &&
                 nlopt_set_min_objective(opt, nl_objective, oc) > 0 &&
                 nlopt_set_xtol_rel(opt, 1e-10) > 0 && nlopt_set_ftol_rel(opt, 1e-12) > 0 &&
                 nlopt_set_maxeval(opt, MAX_EVALS) > 0;
        for (int i = 0; i < nc && ok; ++i)
            ok = nlopt_add_inequality_constraint(opt, nl_constraint, &cc[i], 1e-10) > 0;
        if (!ok) {
            nlopt_destroy(opt);
            snprintf(pb->msg, USM_MSG_LEN, "NLopt refused the problem setup");
            return USM_EFAILED;
        }
        double f;
        nlopt_result res = nlopt_optimize(opt, x, &f);
        nlopt_destroy(opt);
        if (pb->failed)
            return USM_EFAILED;
        if (res < 0 && res != NLOPT_ROUNDOFF_LIMITED && res != NLOPT_FAILURE)
            continue; /* this start failed; others may not */
        char worst[128];
        double v = violation(pb, cc, nc, x, worst);
        if (!pb->solved)
            continue;
        if (output(pb, a->objective, &y, NULL) != 0)
            continue;
        const int feasible = v <= FEAS_TOL, best_feasible = b->have && b->violation <= FEAS_TOL;
        int better;
        if (!b->have)
            better = 1;
        else if (feasible != best_feasible)
            better = feasible;
        else if (feasible)
            better = a->minimize ? y < b->value : y > b->value;
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

static int report(problem *pb, const best *b, cons_ctx *cc, int nc, obj_ctx *oc)
{
    const opt_args *a = pb->a;
    const cli_common *c = &a->common;
    char active[MAX_CONS + USM_NPARAMS + 2][128];
    int nactive;
    pb->have = 0;
    evaluate(pb, b->x);
    double kkt = kkt_residual(pb, oc, cc, nc, b->x, active, &nactive);
    usm_floquet *fl = usm_floquet_alloc(c->model);
    usm_floquet_result fr;
    if (!fl || usm_floquet_compute(fl, &pb->p, &pb->sol, 0.0, NULL, &fr) != USM_OK) {
        cli_error("floquet: %s", fl ? usm_floquet_message(fl) : "out of memory");
        usm_floquet_free(fl);
        return USM_EFAILED;
    }
    const char *oname = usm_sensitivity_output_name(a->objective);
    if (c->json) {
        json_t *obj = json_object(), *varied = json_object(), *act = json_array();
        int ok = obj && varied && act;
        cli_json_put(obj, "objective", json_string(oname), &ok);
        cli_json_put(obj, "sense", json_string(a->minimize ? "min" : "max"), &ok);
        cli_json_put(obj, "value", cli_json_real(b->value), &ok);
        for (int j = 0; j < a->nvary; ++j) {
            const usm_param_info *info = &usm_param_table[a->vary[j]];
            cli_json_put(varied, info->name, cli_json_real(usm_params_get(&pb->p, info)), &ok);
        }
        cli_json_put(obj, "varied", varied, &ok);
        cli_json_put(obj, "parameters", cli_json_params(&pb->p), &ok);
        for (int i = 0; i < nactive; ++i)
            if (json_array_append_new(act, json_string(active[i])) != 0)
                ok = 0;
        cli_json_put(obj, "active_constraints", act, &ok);
        cli_json_put(obj, "kkt_residual", cli_json_real(kkt), &ok);
        cli_json_put(obj, "evaluations", json_integer(pb->evaluations), &ok);
        cli_steady_report rep = {c->model, &pb->p, pb->steady, NULL, &fr};
        cli_json_put(obj, "solution", cli_steady_json(&rep), &ok);
        int rc = ok ? cli_json_print(obj, stdout) : -1;
        json_decref(obj);
        usm_floquet_free(fl);
        if (rc != 0 || fflush(stdout) != 0 || ferror(stdout)) {
            clearerr(stdout);
            cli_error("stdout: write error");
            return USM_EFAILED;
        }
        return USM_OK;
    }
    printf("model %s: %s\n", c->model->name, c->model->description);
    printf("%s %s = %.10g%s\n", a->minimize ? "minimum of" : "maximum of", oname, b->value,
           a->objective == USM_SENS_ROTOR_SPEED ? " (magnitude)" : "");
    printf("\nvaried parameters\n");
    for (int j = 0; j < a->nvary; ++j) {
        const usm_param_info *info = &usm_param_table[a->vary[j]];
        printf("  %-6s %-20.10g in [%g, %g] %s\n", info->name, usm_params_get(&pb->p, info),
               a->lo[j], a->hi[j], info->unit);
    }
    printf("\nactive constraints\n");
    if (nactive == 0)
        printf("  none\n");
    for (int i = 0; i < nactive; ++i)
        printf("  %s\n", active[i]);
    printf("\nKKT residual %.3g, %d evaluations, %d starts\n", kkt, pb->evaluations, a->starts);
    printf("\nstationary solution at the optimum\n");
    printf("  theta %.10g rad, rotor_speed %.10g 1/s, F_n %.10g N, F_t %.10g N\n", pb->sol.theta,
           pb->sol.rotor_speed, pb->sol.F_n, pb->sol.F_t);
    printf("  power_out %.6g W, efficiency %.6g, max_modulus %.10g\n", pb->sol.power_out,
           pb->sol.efficiency, fr.max_modulus);
    usm_floquet_free(fl);
    return USM_OK;
}

static int run(const opt_args *a)
{
    problem pb;
    memset(&pb, 0, sizeof pb);
    pb.a = a;
    pb.steady = usm_steady_alloc(a->common.model);
    pb.sens = usm_sensitivity_alloc(a->common.model);
    pb.r = malloc(sizeof *pb.r);
    best b;
    memset(&b, 0, sizeof b);
    cons_ctx cc[MAX_CONS + 2];
    obj_ctx oc = {&pb, 1.0};
    int status;
    if (!pb.steady || !pb.sens || !pb.r) {
        cli_error("out of memory");
        status = USM_EFAILED;
        goto done;
    }
    int nc = ncons_total(a, cc, &pb);
    status = run_starts(&pb, &b, cc, nc, &oc);
    if (status != USM_OK) {
        cli_error("optimize: %s", pb.msg[0] ? pb.msg : "numerical failure");
        goto done;
    }
    if (!b.have) {
        cli_error("constraint: no feasible point found: no stationary solution at any of the "
                  "%d starts' end points", a->starts);
        status = USM_ENOSOLUTION;
        goto done;
    }
    if (b.violation > FEAS_TOL) {
        cli_error("constraint: no feasible point found: %s cannot be met (best violation %.3g)",
                  b.worst, b.violation);
        status = USM_ENOSOLUTION;
        goto done;
    }
    status = report(&pb, &b, cc, nc, &oc);
done:
    free(pb.r);
    usm_sensitivity_free(pb.sens);
    usm_steady_free(pb.steady);
    return status;
}

int cli_optimize_main(int argc, char **argv)
{
    opt_args a;
    char msg[CLI_MSG_LEN];
    if (parse(&a, argc, argv, msg) != USM_OK) {
        cli_error("%s", msg);
        return USM_EINPUT;
    }
    if (a.help) {
        usage(stdout);
        return USM_OK;
    }
    return run(&a);
}
