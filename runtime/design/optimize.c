/* The best design over parameter bounds (usm_optimize.h): NLopt SLSQP with
 * the analytic sensitivities as gradients, from several deterministic starts;
 * at the optimum the KKT multipliers (non-negative least squares), and the
 * near-optimal interval of each varied parameter (Brent on its profile). */
#include "usm_optimize.h"

#include <ctype.h>
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <nlopt.h>

#include "core/dense.h"
#include "core/grow.h"
#include "core/root.h"

#define FEAS_TOL 1e-6   /* constraint violation accepted, in the scaled units */
#define ACTIVE_TOL 1e-5 /* a constraint this close to its bound is active */
#define BOUND_TOL 1e-9  /* a variable this close to 0 or 1 (box units) sits at its bound */
#define MAX_EVALS 300   /* per start */
#define PROFILE_EVALS 100 /* per re-optimisation of a profile point */
#define FLAT_XTOL 1e-3  /* the near-optimal interval's ends, in box units */
#define MAX_CONS (USM_OPT_MAX_CONSTRAINTS + 3)

/* The built-in and user constraints. */
enum { C_STABILITY, C_DRIVES, C_STICK, C_USER };

typedef struct cons_ctx cons_ctx;

struct usm_optimize {
    const usm_model *model;
    usm_steady *steady;
    usm_sensitivity *sens;
    usm_floquet *floquet;
    usm_sensitivity_result *r;
    usm_sensitivity_result *r_root; /* a named root's (root_output: its max_modulus) */
    int rr_of, rr_ok;     /* root number whose r_root is computed at x (0: none), success */
    usm_root *root;
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
    int fix;              /* a varied parameter held at fix_z (the profile), or -1: NLopt
                             then sees the other nvary - 1 variables */
    double fix_z;
    /* the operating point (usm_opt_problem.from_rest) */
    int refused;          /* evaluations refused: several roots, no from_rest */
    int no_op;            /* evaluations (from_rest) whose start-up reached no stable root */
    char op_msg[USM_MSG_LEN]; /* the last refusal, in words */
    usm_floquet_result *fl; /* every root's multipliers */
    size_t flcap;
    usm_op_result op;
    int have_op;          /* op and fl describe the last feasible optimum */
    /* finite differences of the outputs without analytic derivatives */
    usm_steady *steady_fd; /* the continued solutions */
    double fd_step;       /* h in box units (USM_OPT_FD_STEP) */
    int fd_have, fd_ok;   /* fd_d computed at x (with step fd_h), and whether it succeeded */
    double fd_h;
    double fd_d[USM_OPT_OUTPUT_COUNT][USM_NPARAMS]; /* d(output)/dz */
    usm_params fd_p;      /* the parameters of the last continued solution */
    double fd_r[USM_OPT_OUTPUT_COUNT][USM_NPARAMS]; /* a named root's (root_output) */
    int fdr_of, fdr_ok;   /* root number whose fd_r is computed at x (0: none), success */
    double fdr_h;         /* with this step */
    char msg[USM_MSG_LEN];
};

struct cons_ctx {
    usm_optimize *o;
    int kind;        /* C_* */
    int index;       /* user constraint index */
    double scale;
};

/* ---- the outputs -------------------------------------------------------------------- */

/* The outputs beyond usm_sensitivity's, in index order from USM_SENS_COUNT:
 * a field of usm_steady_solution, named by the generated contracts where
 * they list it (gen), else by the name `usm steady --json` writes; wrap: a
 * phase in [0, 2 pi), whose differences are taken modulo 2 pi. */
typedef struct extra_output {
    const usm_output_info *gen;
    const char *name, *unit;
    size_t offset;
    int wrap;
} extra_output;

#define NEXTRA (USM_OPT_OUTPUT_COUNT - USM_SENS_COUNT)
#define TWO_PI 6.283185307179586476925286766559
#define FIELD(f) offsetof(usm_steady_solution, f)
static const extra_output extra[NEXTRA] = {
    {NULL, "alpha", "rad", FIELD(alpha), 1},
    {&usm_steady_outputs[USM_STEADY_BETA], NULL, NULL, FIELD(beta), 1},
    {NULL, "mu_used", "1", FIELD(mu_used), 0},
    {&usm_steady_outputs[USM_STEADY_V_C], NULL, NULL, FIELD(v_c), 0},
    {&usm_steady_outputs[USM_STEADY_V_REL], NULL, NULL, FIELD(v_rel), 0},
    {&usm_steady_outputs[USM_STEADY_R_STAR], NULL, NULL, FIELD(R_star), 0},
    {&usm_steady_outputs[USM_STEADY_Z], NULL, NULL, FIELD(Z), 0},
    {&usm_power_outputs[USM_POWER_POWER_DAMPING], NULL, NULL, FIELD(power_damping), 0},
    {&usm_power_outputs[USM_POWER_POWER_SLIP], NULL, NULL, FIELD(power_slip), 0},
    {NULL, "margin", "1", 0, 0}, /* 1 - max_modulus: analytic */
};
#undef FIELD

/* The units of the sensitivity outputs, by USM_SENS_* (speed: 1/s). */
static const char *const sens_unit[USM_SENS_COUNT] = {"rad", "1/s", "N", "N", "1",
                                                      "N",   "1",   "W", "W"};

const char *usm_opt_output_name(int k)
{
    if (k == USM_OPT_SPEED)
        return "speed";
    if (k >= USM_SENS_COUNT && k < USM_OPT_OUTPUT_COUNT) {
        const extra_output *e = &extra[k - USM_SENS_COUNT];
        return e->gen ? e->gen->name : e->name;
    }
    return usm_sensitivity_output_name(k);
}

const char *usm_opt_output_unit(int k)
{
    if (k >= 0 && k < USM_SENS_COUNT)
        return sens_unit[k];
    if (k >= USM_SENS_COUNT && k < USM_OPT_OUTPUT_COUNT) {
        const extra_output *e = &extra[k - USM_SENS_COUNT];
        return e->gen ? e->gen->unit : e->unit;
    }
    return NULL;
}

int usm_opt_output_analytic(int k)
{
    if (k < 0 || k >= USM_OPT_OUTPUT_COUNT)
        return -1;
    return k < USM_SENS_COUNT || k == USM_OPT_MARGIN;
}

void usm_opt_output_list(char *buf, size_t len)
{
    size_t n = 0;
    if (len == 0)
        return;
    buf[0] = '\0';
    for (int k = 0; k < USM_OPT_OUTPUT_COUNT && n < len; ++k) {
        int w = snprintf(buf + n, len - n, "%s%s", k ? ", " : "", usm_opt_output_name(k));
        if (w < 0)
            break;
        n += (size_t)w;
    }
}

int usm_opt_output_find(const char *name)
{
    if (!name)
        return -1;
    /* rotor_speed, the sensitivity output's own name, is the alias of speed */
    if (strcmp(name, usm_sensitivity_output_name(USM_SENS_ROTOR_SPEED)) == 0)
        return USM_OPT_SPEED;
    for (int k = 0; k < USM_OPT_OUTPUT_COUNT; ++k)
        if (strcmp(name, usm_opt_output_name(k)) == 0)
            return k;
    return -1;
}

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
    int root = 0;
    const char *whole = output;
    if (output && strcmp(output, "roots") == 0) {
        if (pb->ncons == USM_OPT_MAX_CONSTRAINTS) {
            snprintf(msg, USM_MSG_LEN, "constraint: at most %d", USM_OPT_MAX_CONSTRAINTS);
            return USM_EINPUT;
        }
        pb->cons[pb->ncons++] = (usm_opt_constraint){USM_OPT_ROOTS, upper != 0, value, 0};
        return USM_OK;
    }
    if (output && strncmp(output, "root", 4) == 0 && output[4] != 's') {
        /* rootR.NAME: R a decimal 1 .. USM_OPT_MAX_ROOT */
        const char *dot = strchr(output, '.');
        char *end = NULL;
        long r = dot && isdigit((unsigned char)output[4]) ? strtol(output + 4, &end, 10) : -1;
        if (!dot || end != dot || r < 1 || r > USM_OPT_MAX_ROOT) {
            snprintf(msg, USM_MSG_LEN,
                     "constraint: bad root \"%.40s\": expected rootR.NAME with R the root's "
                     "number as usm steady lists them, 1 to %d (e.g. root2.theta)",
                     output, USM_OPT_MAX_ROOT);
            return USM_EINPUT;
        }
        root = (int)r;
        output = dot + 1;
    }
    int k = usm_opt_output_find(output);
    if (k < 0) {
        char list[USM_MSG_LEN];
        usm_opt_output_list(list, sizeof list);
        if (root > 0)
            snprintf(msg, USM_MSG_LEN,
                     "constraint: unknown output \"%.24s\" in \"%.30s\" (one of: %.140s)",
                     output, whole, list);
        else
            snprintf(msg, USM_MSG_LEN, "constraint: unknown output \"%.24s\" (one of: %.190s)",
                     output, list);
        return USM_EINPUT;
    }
    if (pb->ncons == USM_OPT_MAX_CONSTRAINTS) {
        snprintf(msg, USM_MSG_LEN, "constraint: at most %d", USM_OPT_MAX_CONSTRAINTS);
        return USM_EINPUT;
    }
    pb->cons[pb->ncons++] = (usm_opt_constraint){k, upper != 0, value, root};
    return USM_OK;
}

int usm_opt_problem_check(const usm_opt_problem *pb, const usm_model *m, const usm_params *p,
                          char msg[USM_MSG_LEN])
{
    /* the ideal motor only, refused with usm_steady_solve's own reason */
    if (usm_params_check_ideal(p, msg) != USM_OK)
        return USM_EINPUT;
    if (m->imperfect) {
        snprintf(msg, USM_MSG_LEN,
                 "variant: model %s: the optimizer's gradients are the sensitivities of the "
                 "stationary solution, defined for the ideal motor only; use the variant "
                 "twist_integrated", m->name);
        return USM_EINPUT;
    }
    if (pb->objective < 0 || pb->objective >= USM_OPT_OUTPUT_COUNT) {
        snprintf(msg, USM_MSG_LEN, "objective: required");
        return USM_EINPUT;
    }
    if (!usm_opt_output_analytic(pb->objective)) {
        /* the objective's gradient is differentiated once more (the polish) */
        char list[USM_MSG_LEN] = "";
        size_t n = 0;
        for (int k = 0; k < USM_OPT_OUTPUT_COUNT && n < sizeof list; ++k) {
            if (usm_opt_output_analytic(k) != 1)
                continue;
            int w = snprintf(list + n, sizeof list - n, "%s%s", n ? ", " : "",
                             usm_opt_output_name(k));
            n += w > 0 ? (size_t)w : 0;
        }
        snprintf(msg, USM_MSG_LEN,
                 "objective: %.16s: the objective needs an analytic gradient (one of: %.120s); "
                 "%.16s may be a constraint",
                 usm_opt_output_name(pb->objective), list, usm_opt_output_name(pb->objective));
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
    if (pb->from_rest_periods != 0 &&
        !(pb->from_rest_periods >= 1 && pb->from_rest_periods <= 1e7)) {
        snprintf(msg, USM_MSG_LEN, "from-rest-periods: must be in [1, 1e7]");
        return USM_EINPUT;
    }
    if (!isfinite(pb->t0)) {
        snprintf(msg, USM_MSG_LEN, "t0: must be a finite number");
        return USM_EINPUT;
    }
    for (int k = 0; pb->has_start && k < pb->nvary && k < USM_NPARAMS; ++k)
        if (!isfinite(pb->start[k])) {
            snprintf(msg, USM_MSG_LEN, "start: the warm start's value %d is not finite", k);
            return USM_EINPUT;
        }
    if (pb->ncons < 0 || pb->ncons > USM_OPT_MAX_CONSTRAINTS) {
        snprintf(msg, USM_MSG_LEN, "constraint: at most %d", USM_OPT_MAX_CONSTRAINTS);
        return USM_EINPUT;
    }
    for (int i = 0; i < pb->ncons; ++i) {
        const usm_opt_constraint *u = &pb->cons[i];
        const int count = u->output == USM_OPT_ROOTS;
        if ((!count && !usm_opt_output_name(u->output)) || !isfinite(u->value) ||
            u->root < 0 || u->root > USM_OPT_MAX_ROOT || (count && u->root != 0)) {
            snprintf(msg, USM_MSG_LEN,
                     "constraint: %d: unknown output, bad root or bound not finite", i);
            return USM_EINPUT;
        }
        if (count && !u->upper && u->value > 1 && !pb->from_rest) {
            snprintf(msg, USM_MSG_LEN,
                     "constraint: roots >= %g needs --from-rest (without it a design with "
                     "several roots is refused)", u->value);
            return USM_EINPUT;
        }
    }
    /* every corner of the box must be admissible parameters of an ideal motor */
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
            if (usm_params_check(&q, m, m2) != USM_OK || usm_params_check_ideal(&q, m2) != USM_OK) {
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

/* The operating point of the roots of the last solve (o->steady at o->p):
 * every root's multipliers with fo from pb->t0 into o->fl, then
 * usm_operating_point (a simulation from rest when pb->from_rest).  0 and
 * o->op, or -1 with o->failed (a numerical failure) and o->msg. */
static int operating_point(usm_optimize *o, const usm_floquet_options *fo)
{
    const usm_opt_problem *pb = o->pb;
    const size_t n = usm_steady_count(o->steady);
    if (usm_grow((void **)&o->fl, &o->flcap, n, sizeof *o->fl) != 0) {
        o->failed = 1;
        snprintf(o->msg, USM_MSG_LEN, "out of memory");
        return -1;
    }
    if (usm_floquet_roots(o->floquet, &o->p, o->steady, pb->t0, fo, o->fl) != USM_OK) {
        o->failed = 1;
        snprintf(o->msg, USM_MSG_LEN, "floquet: %.240s", usm_floquet_message(o->floquet));
        return -1;
    }
    usm_op_options oo;
    usm_op_options_default(&oo);
    oo.from_rest = pb->from_rest && n > 1; /* one root: the cheap rule */
    if (pb->from_rest_periods > 0)
        oo.periods = pb->from_rest_periods;
    if (usm_operating_point(o->model, &o->p, o->steady, o->fl, &oo, &o->op) != USM_OK) {
        o->failed = 1;
        snprintf(o->msg, USM_MSG_LEN, "operating point: %.200s", o->op.message);
        return -1;
    }
    return 0;
}

/* Evaluate the design at normalised x (z in [0, 1] per varied parameter). */
static void evaluate(usm_optimize *o, const double *x)
{
    const usm_opt_problem *pb = o->pb;
    if (o->have && memcmp(x, o->x, sizeof(double) * (size_t)pb->nvary) == 0)
        return;
    memcpy(o->x, x, sizeof(double) * (size_t)pb->nvary);
    o->have = 1;
    o->solved = 0;
    o->fd_have = 0;
    o->rr_of = o->fdr_of = 0; /* the named roots' caches belong to the last x */
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
    /* judged by the operating point: one root is it when stable (the
     * stability constraint); several roots only a simulation from rest
     * decides (pb->from_rest), else the design is refused */
    size_t pick = 0;
    const size_t nroots = usm_steady_count(o->steady);
    /* the count of roots: a filter (no derivative), usm_opt_constraint */
    for (int i = 0; i < pb->ncons; ++i) {
        const usm_opt_constraint *u = &pb->cons[i];
        if (u->output == USM_OPT_ROOTS &&
            (u->upper ? (double)nroots > u->value : (double)nroots < u->value)) {
            ++o->refused;
            snprintf(o->op_msg, USM_MSG_LEN, "%zu roots: refused by roots %s %g", nroots,
                     u->upper ? "<=" : ">=", u->value);
            return;
        }
    }
    if (nroots > 1 && !pb->from_rest) {
        ++o->refused;
        snprintf(o->op_msg, USM_MSG_LEN,
                 "%zu roots: which one the motor runs at needs a simulation from rest "
                 "(--from-rest)", nroots);
        return;
    }
    if (nroots > 1) {
        usm_floquet_options fo;
        usm_floquet_options_default(&fo);
        if (operating_point(o, &fo) != 0)
            return;
        if (o->op.index < 0) {
            ++o->no_op;
            /* the reason's name: whole within the refusal message's room */
            snprintf(o->op_msg, USM_MSG_LEN, "no operating point: %s",
                     usm_op_reason_name(o->op.reason));
            return;
        }
        pick = (size_t)o->op.index;
    }
    o->sol = *usm_steady_root(o->steady, pick);
    /* the stability constraint is always there, so max_modulus is always needed */
    if (usm_sensitivity_compute(o->sens, &o->p, &o->sol, 1, o->r) != USM_OK) {
        o->failed = 1;
        snprintf(o->msg, USM_MSG_LEN, "%s", usm_sensitivity_message(o->sens));
        return;
    }
    o->solved = 1;
}

/* The value of output k on solution sol at parameters p, from the solution
 * alone: every output but max_modulus and margin (NaN for those). */
static double field_value(const usm_steady_solution *sol, const usm_params *p, int k)
{
    switch (k) {
    case USM_SENS_THETA:
        return sol->theta;
    case USM_OPT_SPEED:
        return -sol->rotor_speed;
    case USM_SENS_F_N:
        return sol->F_n;
    case USM_SENS_F_T:
        return sol->F_t;
    case USM_SENS_EFFICIENCY:
        return sol->efficiency;
    case USM_SENS_STICK_MARGIN:
        return p->mu0 * sol->F_n - sol->F_t;
    case USM_SENS_POWER_IN:
        return sol->power_in;
    case USM_SENS_POWER_OUT:
        return sol->power_out;
    default:
        if (k > USM_SENS_COUNT - 1 && k < USM_OPT_MARGIN)
            return *(const double *)((const char *)sol + extra[k - USM_SENS_COUNT].offset);
        return NAN;
    }
}

double usm_opt_output_value(int k, const usm_steady_solution *sol, const usm_params *p,
                            double max_modulus)
{
    if (k == USM_SENS_MAX_MODULUS)
        return max_modulus;
    if (k == USM_OPT_MARGIN)
        return 1 - max_modulus;
    return field_value(sol, p, k);
}

/* y1 - y0 for output k, modulo 2 pi for a phase. */
static double fd_diff(int k, double y1, double y0)
{
    double d = y1 - y0;
    if (k >= USM_SENS_COUNT && k < USM_OPT_MARGIN && extra[k - USM_SENS_COUNT].wrap)
        d -= TWO_PI * nearbyint(d / TWO_PI);
    return d;
}

/* The judged root continued to box point z_i = x[i] + dz (the others at
 * x): Newton from o->sol (usm_steady_solve_from), into *out.  0 or -1. */
static int fd_solve_at(usm_optimize *o, const usm_steady_solution *from, int i, double dz,
                       usm_steady_solution *out)
{
    const usm_opt_problem *pb = o->pb;
    usm_params q = o->p;
    const double z = o->x[i] + dz;
    *usm_params_field(&q, &usm_param_table[pb->vary[i]]) =
        fmin(pb->hi[i], fmax(pb->lo[i], pb->lo[i] + z * (pb->hi[i] - pb->lo[i])));
    usm_params_couple(o->model, &q, pb->vary[i]);
    if (usm_steady_solve_from(o->steady_fd, &q, from->u) != USM_OK)
        return -1;
    *out = *usm_steady_root(o->steady_fd, 0);
    o->fd_p = q;
    return 0;
}

/* Finite differences of every output but max_modulus and margin of root
 * `from` (at o->p) in each box variable at the current point (into d, per
 * unit of z), with step h: central, or second-order one-sided where z -+ h
 * leaves [0, 1] (USM_OPT_FD_STEP).  0, or -1 when a continued solution fails. */
static int fd_root(usm_optimize *o, const usm_steady_solution *from, double h,
                   double d[USM_OPT_OUTPUT_COUNT][USM_NPARAMS])
{
    const usm_opt_problem *pb = o->pb;
    for (int i = 0; i < pb->nvary; ++i) {
        const double z = o->x[i];
        usm_steady_solution s1, s2;
        usm_params p1, p2;
        /* d = (c0 y0 + c1 y(z + dz1) + c2 y(z + dz2)) / h with c0 = -(c1 + c2):
         * central, or second-order one-sided at a bound */
        double c1, c2, dz1, dz2;
        if (z - h >= 0 && z + h <= 1)
            c1 = 0.5, c2 = -0.5, dz1 = h, dz2 = -h;
        else if (z + 2 * h <= 1)
            c1 = 2, c2 = -0.5, dz1 = h, dz2 = 2 * h;
        else
            c1 = -2, c2 = 0.5, dz1 = -h, dz2 = -2 * h;
        if (fd_solve_at(o, from, i, dz1, &s1) != 0)
            return -1;
        p1 = o->fd_p;
        if (fd_solve_at(o, from, i, dz2, &s2) != 0)
            return -1;
        p2 = o->fd_p;
        for (int k = 0; k < USM_OPT_OUTPUT_COUNT; ++k) {
            const double y0 = field_value(from, &o->p, k);
            /* differences from y0: a phase's wrap cancels, c0 + c1 + c2 = 0 */
            const double d1 = fd_diff(k, field_value(&s1, &p1, k), y0),
                         d2 = fd_diff(k, field_value(&s2, &p2, k), y0);
            d[k][i] = (c1 * d1 + c2 * d2) / h;
        }
    }
    return 0;
}

/* fd_root of the judged root, kept in o->fd_d for the current point. */
static int fd_derivatives(usm_optimize *o, double h)
{
    if (o->fd_have && o->fd_h == h)
        return o->fd_ok;
    o->fd_have = 1;
    o->fd_h = h;
    o->fd_ok = fd_root(o, &o->sol, h, o->fd_d);
    return o->fd_ok;
}

/* grad = s d(output k)/dz from the sensitivities r (per unit of each box
 * variable; the parameters tied to a varied one move with it). */
static void analytic_gradient(const usm_optimize *o, const usm_sensitivity_result *r, int k,
                              double s, double *grad)
{
    const usm_opt_problem *pb = o->pb;
    for (int i = 0; i < pb->nvary; ++i) {
        double d = r->d[k][pb->vary[i]];
        for (int j = 0; j < USM_NPARAMS; ++j) {
            const usm_param_coupling *c = usm_param_coupled(o->model, j);
            if (c && c->equals == pb->vary[i])
                d += r->d[k][j];
        }
        grad[i] = s * d * (pb->hi[i] - pb->lo[i]);
    }
}

/* Output k of root r (from 1, as usm steady numbers them) at the current
 * point and its central differences along that root: -1 where the design
 * has no solution or no root r (the constraint is then violated). */
static int root_output(usm_optimize *o, int r, int k, double *y, double *grad)
{
    if (!o->solved || (size_t)r > usm_steady_count(o->steady))
        return -1;
    const usm_steady_solution *s = usm_steady_root(o->steady, (size_t)r - 1);
    if (k == USM_SENS_MAX_MODULUS || k == USM_OPT_MARGIN) {
        /* that root's multipliers and their analytic derivative (the same
         * computation as the judged root's, on this root) */
        const usm_sensitivity_result *rr = o->r_root;
        if (o->rr_of != r) { /* once per root and point: constraints share it */
            o->rr_of = r;
            o->rr_ok = usm_sensitivity_compute(o->sens, &o->p, s, 1, o->r_root) == USM_OK;
        }
        if (!o->rr_ok || !isfinite(rr->value[USM_SENS_MAX_MODULUS]) ||
            (grad && !rr->defined[USM_SENS_MAX_MODULUS]))
            return -1;
        const double sign = k == USM_OPT_MARGIN ? -1.0 : 1.0;
        *y = (k == USM_OPT_MARGIN ? 1.0 : 0.0) + sign * rr->value[USM_SENS_MAX_MODULUS];
        if (grad)
            analytic_gradient(o, rr, USM_SENS_MAX_MODULUS, sign, grad);
        return 0;
    }
    *y = field_value(s, &o->p, k);
    if (!isfinite(*y))
        return -1;
    if (grad) {
        if (o->fdr_of != r || o->fdr_h != o->fd_step) {
            o->fdr_of = r;
            o->fdr_h = o->fd_step;
            o->fdr_ok = fd_root(o, s, o->fd_step, o->fd_r) == 0;
        }
        if (!o->fdr_ok)
            return -1;
        for (int i = 0; i < o->pb->nvary; ++i)
            grad[i] = o->fd_r[k][i];
    }
    return 0;
}

/* y and dy/dz of output k at the current point; -1 when not defined there
 * (the value can exist without the derivative: a kink of max_modulus).
 * fd: differences for the outputs that have analytic derivatives too. */
static int output_fd(usm_optimize *o, int k, double *y, double *grad, int fd)
{
    const usm_opt_problem *pb = o->pb;
    const usm_sensitivity_result *r = o->r;
    if (!o->solved)
        return -1;
    if (k == USM_OPT_MARGIN) {
        /* 1 - max_modulus, analytic */
        if (output_fd(o, USM_SENS_MAX_MODULUS, y, grad, fd) != 0)
            return -1;
        *y = 1 - *y;
        if (grad)
            for (int i = 0; i < pb->nvary; ++i)
                grad[i] = -grad[i];
        return 0;
    }
    if (k >= USM_SENS_COUNT || (fd && k != USM_SENS_MAX_MODULUS)) {
        *y = field_value(&o->sol, &o->p, k);
        if (!isfinite(*y))
            return -1;
        if (grad) {
            if (fd_derivatives(o, o->fd_step) != 0)
                return -1;
            for (int i = 0; i < pb->nvary; ++i)
                grad[i] = o->fd_d[k][i];
        }
        return 0;
    }
    if ((grad && !r->defined[k]) || !isfinite(r->value[k]))
        return -1;
    /* speed: -rotor_speed, positive in the driving direction */
    const double s = k == USM_OPT_SPEED ? -1.0 : 1.0;
    *y = s * r->value[k];
    if (grad)
        analytic_gradient(o, r, k, s, grad);
    return 0;
}

static int output(usm_optimize *o, int k, double *y, double *grad)
{
    return output_fd(o, k, y, grad, 0);
}

/* The output, sign and bound of constraint c: sign (y - bound) <= 0. */
static void cons_def(const cons_ctx *c, int *k, double *sign, double *bound)
{
    const usm_opt_problem *pb = c->o->pb;
    switch (c->kind) {
    case C_STABILITY:
        *k = USM_SENS_MAX_MODULUS, *sign = 1, *bound = 1 - pb->margin;
        break;
    case C_DRIVES:
        *k = USM_SENS_POWER_OUT, *sign = -1, *bound = 0;
        break;
    case C_STICK:
        *k = USM_SENS_STICK_MARGIN, *sign = -1, *bound = 0;
        break;
    default:
        *k = pb->cons[c->index].output;
        *sign = pb->cons[c->index].upper ? 1 : -1;
        *bound = pb->cons[c->index].value;
    }
}

/* Constraint c(x) = sign (y - bound) <= 0 in the output's own units, and its
 * gradient in z; -1 where not defined (no solution, no derivative). */
static int cons_own(const cons_ctx *c, const double *x, double *value, double *grad)
{
    usm_optimize *o = c->o;
    int k;
    double sign, bound, y, g[USM_NPARAMS];
    evaluate(o, x);
    cons_def(c, &k, &sign, &bound);
    const int root = c->kind == C_USER ? o->pb->cons[c->index].root : 0;
    if ((root > 0 ? root_output(o, root, k, &y, grad ? g : NULL)
                  : output(o, k, &y, grad ? g : NULL)) != 0)
        return -1;
    *value = sign * (y - bound);
    if (grad)
        for (int i = 0; i < o->pb->nvary; ++i)
            grad[i] = sign * g[i];
    return 0;
}

/* Constraint c(x) <= 0 in scaled units: 1 (infeasible, no direction) where not defined. */
static double cons_value(const cons_ctx *c, const double *x, double *grad)
{
    const int n = c->o->pb->nvary;
    double v;
    if (cons_own(c, x, &v, grad) != 0) {
        if (grad)
            memset(grad, 0, sizeof(double) * (size_t)n);
        return 1.0;
    }
    if (grad)
        for (int i = 0; i < n; ++i)
            grad[i] /= c->scale;
    return v / c->scale;
}

/* NLopt's variables: all nvary, or all but the one held (o->fix). */
static void expand(const usm_optimize *o, const double *xr, double *x)
{
    for (int j = 0, k = 0; j < o->pb->nvary; ++j)
        x[j] = j == o->fix ? o->fix_z : xr[k++];
}

static void reduce(const usm_optimize *o, const double *x, double *xr)
{
    for (int j = 0, k = 0; j < o->pb->nvary; ++j)
        if (j != o->fix)
            xr[k++] = x[j];
}

static double nl_constraint(unsigned n, const double *xr, double *grad, void *data)
{
    const cons_ctx *c = data;
    double x[USM_NPARAMS], g[USM_NPARAMS];
    (void)n;
    expand(c->o, xr, x);
    double v = cons_value(c, x, grad ? g : NULL);
    if (grad)
        reduce(c->o, g, grad);
    return v;
}

/* The objective NLopt minimises at full x: sigma y / scale, sigma = -1 to maximise. */
static double objective(usm_optimize *o, const double *x, double *grad)
{
    const usm_opt_problem *pb = o->pb;
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

static double nl_objective(unsigned n, const double *xr, double *grad, void *data)
{
    usm_optimize *o = data;
    double x[USM_NPARAMS], g[USM_NPARAMS];
    (void)n;
    expand(o, xr, x);
    double v = objective(o, x, grad ? g : NULL);
    if (grad)
        reduce(o, g, grad);
    return v;
}

/* ---- the optimisation --------------------------------------------------------------- */

typedef struct best {
    int have;
    double x[USM_NPARAMS];
    int solved;                    /* a stationary solution at x, the objective defined */
    double value;                  /* objective in its own sense */
    double violation;              /* largest scaled violation (<= FEAS_TOL: feasible) */
    char worst[USM_OPT_TEXT_LEN];  /* the most violated constraint */
} best;

static int constraints(usm_optimize *o, cons_ctx *cc)
{
    int n = 0;
    cc[n++] = (cons_ctx){o, C_STABILITY, 0, 1.0};
    if (!o->pb->allow_driven)
        cc[n++] = (cons_ctx){o, C_DRIVES, 0, 1.0};
    if (!o->model->slip && !o->pb->allow_slip)
        cc[n++] = (cons_ctx){o, C_STICK, 0, 1.0};
    for (int i = 0; i < o->pb->ncons; ++i)
        if (o->pb->cons[i].output != USM_OPT_ROOTS) /* a filter in evaluate, not SLSQP's */
            cc[n++] = (cons_ctx){o, C_USER, i, 1.0};
    return n;
}

static void cons_text(const usm_opt_problem *pb, const cons_ctx *c, char buf[USM_OPT_TEXT_LEN])
{
    if (c->kind == C_STABILITY)
        snprintf(buf, USM_OPT_TEXT_LEN, "stability: max_modulus <= %g", 1 - pb->margin);
    else if (c->kind == C_DRIVES)
        snprintf(buf, USM_OPT_TEXT_LEN, "drives: power_out >= 0");
    else if (c->kind == C_STICK)
        snprintf(buf, USM_OPT_TEXT_LEN, "stick: F_t <= mu0 F_n");
    else {
        const usm_opt_constraint *u = &pb->cons[c->index];
        char root[24] = "";
        if (u->root > 0)
            snprintf(root, sizeof root, "root%d.", u->root);
        snprintf(buf, USM_OPT_TEXT_LEN, "%s%s %s %g", root, usm_opt_output_name(u->output),
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

/* Scales: constraint values relative to a typical size (stick: F_n; drives:
 * power_in; user: |X|). */
static void set_scales(usm_optimize *o, cons_ctx *cc, int nc)
{
    for (int i = 0; i < nc; ++i) {
        if (cc[i].kind == C_STICK)
            cc[i].scale = o->solved ? fmax(fabs(o->sol.F_n), 1e-12) : 1.0;
        else if (cc[i].kind == C_DRIVES)
            cc[i].scale = o->solved ? fmax(fmax(fabs(o->sol.power_in), fabs(o->sol.power_out)),
                                           1e-15)
                                    : 1.0;
        else if (cc[i].kind == C_USER) {
            const usm_opt_constraint *u = &o->pb->cons[cc[i].index];
            double v = fabs(u->value), y;
            if ((u->root > 0 ? root_output(o, u->root, u->output, &y, NULL)
                             : output(o, u->output, &y, NULL)) != 0)
                y = 0;
            cc[i].scale = v > 0 ? v : fabs(y) > 0 ? fabs(y) : 1.0;
        }
    }
}

/* SLSQP from x (full, updated in place) over the variables not held. */
static nlopt_result slsqp(usm_optimize *o, cons_ctx *cc, int nc, double *x, int maxeval)
{
    const int n = o->pb->nvary - (o->fix >= 0);
    double lb[USM_NPARAMS], ub[USM_NPARAMS], xr[USM_NPARAMS], f;
    for (int j = 0; j < n; ++j) {
        lb[j] = 0;
        ub[j] = 1;
    }
    nlopt_opt opt = nlopt_create(NLOPT_LD_SLSQP, (unsigned)n);
    if (!opt)
        return NLOPT_OUT_OF_MEMORY;
    int ok = nlopt_set_lower_bounds(opt, lb) > 0 && nlopt_set_upper_bounds(opt, ub) > 0 &&
             nlopt_set_min_objective(opt, nl_objective, o) > 0 &&
             nlopt_set_xtol_rel(opt, 1e-10) > 0 && nlopt_set_ftol_rel(opt, 1e-12) > 0 &&
             nlopt_set_maxeval(opt, maxeval) > 0;
    for (int i = 0; i < nc && ok; ++i)
        ok = nlopt_add_inequality_constraint(opt, nl_constraint, &cc[i], 1e-10) > 0;
    if (!ok) {
        nlopt_destroy(opt);
        return NLOPT_INVALID_ARGS;
    }
    reduce(o, x, xr);
    nlopt_result res = nlopt_optimize(opt, xr, &f);
    nlopt_destroy(opt);
    expand(o, xr, x);
    return res;
}

/* Is candidate (feasible, solved, y, v) better than b? */
static int better(const usm_opt_problem *pb, const best *b, int solved, double y, double v)
{
    if (!b->have)
        return 1;
    if (solved != b->solved)
        return solved;
    if (!solved)
        return 0;
    const int feasible = v <= FEAS_TOL, best_feasible = b->violation <= FEAS_TOL;
    if (feasible != best_feasible)
        return feasible;
    if (feasible)
        return pb->minimize ? y < b->value : y > b->value;
    return v < b->violation;
}

static int run_starts(usm_optimize *o, best *b, cons_ctx *cc, int nc)
{
    const usm_opt_problem *pb = o->pb;
    const int n = pb->nvary;
    for (int s = 0; s < pb->starts; ++s) {
        double x[USM_NPARAMS];
        /* deterministic spread: a rank-1 lattice (golden-ratio offsets) */
        for (int j = 0; j < n; ++j)
            x[j] = fmod((s + 0.5) / pb->starts + j * 0.6180339887498949, 1.0);
        if (s == 0 && pb->has_start) /* the caller's warm start */
            for (int j = 0; j < n; ++j)
                x[j] = fmin(1.0, fmax(0.0, (pb->start[j] - pb->lo[j]) / (pb->hi[j] - pb->lo[j])));
        evaluate(o, x);
        if (o->failed)
            return USM_EFAILED;
        double y;
        o->obj_scale = 1.0;
        if (output(o, pb->objective, &y, NULL) == 0 && y != 0)
            o->obj_scale = fabs(y);
        set_scales(o, cc, nc);
        nlopt_result res = slsqp(o, cc, nc, x, MAX_EVALS);
        if (o->failed)
            return USM_EFAILED;
        if (res == NLOPT_OUT_OF_MEMORY || res == NLOPT_INVALID_ARGS) {
            snprintf(o->msg, USM_MSG_LEN, "NLopt refused the problem setup");
            return USM_EFAILED;
        }
        if (res < 0 && res != NLOPT_ROUNDOFF_LIMITED && res != NLOPT_FAILURE)
            continue; /* this start failed; others may not */
        char worst[USM_OPT_TEXT_LEN];
        double v = violation(o, cc, nc, x, worst);
        const int solved = o->solved && output(o, pb->objective, &y, NULL) == 0;
        if (better(pb, b, solved, y, v)) {
            b->have = 1;
            memcpy(b->x, x, sizeof(double) * (size_t)n);
            b->solved = solved;
            b->value = solved ? y : NAN;
            b->violation = solved ? v : INFINITY;
            snprintf(b->worst, sizeof b->worst, "%s", solved ? worst : "a stationary solution exists");
        }
    }
    return USM_OK;
}

/* ---- polishing an interior optimum ------------------------------------------------------ */

#define POLISH_STEP 1e-5   /* gradient differences for the Hessian, box units */
#define POLISH_NOISE 1e-10 /* the objective's values are this accurate (relative) */

/* SLSQP stops where its function values stop improving, which leaves the
 * gradient of an interior optimum at ~1e-6 of its size.  Newton's method on
 * the gradient over the free variables (no active constraint, not at a
 * bound; the Hessian from central differences of the analytic gradients)
 * takes it to the gradient's own accuracy.  A step is kept only when it is
 * small (1e-3 of the box), stays feasible, lowers the gradient and does not
 * worsen the objective beyond the noise of its values (measured: a step
 * that took the gradient of the 4dof speed over f from 9e-7 to 6e-13 of the
 * speed "lost" 1.1e-11 of it: the stationary solutions' rounding, not a
 * worse point, which SLSQP, deciding by those values, cannot see past). */
static void polish(usm_optimize *o, cons_ctx *cc, int nc, best *b)
{
    const usm_opt_problem *pb = o->pb;
    const int n = pb->nvary;
    const double sigma = pb->minimize ? 1.0 : -1.0;
    int fr[USM_NPARAMS], m = 0;
    for (int j = 0; j < n; ++j)
        if (b->x[j] > BOUND_TOL && b->x[j] < 1 - BOUND_TOL)
            fr[m++] = j;
    if (m == 0 || m > USM_EXPM_MAX_N)
        return;
    for (int it = 0; it < 3; ++it) {
        double g[USM_NPARAMS], y, x[USM_NPARAMS], H[USM_EXPM_MAX_N * USM_EXPM_MAX_N];
        double step[USM_EXPM_MAX_N], gn = 0;
        int piv[USM_EXPM_MAX_N];
        char worst[USM_OPT_TEXT_LEN];
        evaluate(o, b->x);
        if (!o->solved || output(o, pb->objective, &y, g) != 0)
            return;
        for (int i = 0; i < nc; ++i)
            if (fabs(cons_value(&cc[i], b->x, NULL)) <= ACTIVE_TOL)
                return; /* constrained: SLSQP's multipliers balance it */
        for (int a = 0; a < m; ++a)
            gn = fmax(gn, fabs(g[fr[a]]));
        for (int a = 0; a < m; ++a) {
            double gp[USM_NPARAMS], gm[USM_NPARAMS], yy;
            memcpy(x, b->x, sizeof x);
            x[fr[a]] = b->x[fr[a]] + POLISH_STEP;
            evaluate(o, x);
            if (output(o, pb->objective, &yy, gp) != 0)
                return;
            x[fr[a]] = b->x[fr[a]] - POLISH_STEP;
            evaluate(o, x);
            if (output(o, pb->objective, &yy, gm) != 0)
                return;
            for (int c = 0; c < m; ++c)
                H[c * m + a] = (gp[fr[c]] - gm[fr[c]]) / (2 * POLISH_STEP);
        }
        for (int a = 0; a < m; ++a) {
            for (int c = 0; c < a; ++c)
                H[a * m + c] = H[c * m + a] = 0.5 * (H[a * m + c] + H[c * m + a]);
            step[a] = -g[fr[a]];
        }
        if (usm_lu_factor_dense(m, H, piv) != 0)
            return;
        usm_lu_solve_dense(m, H, piv, step, 1);
        memcpy(x, b->x, sizeof x);
        for (int a = 0; a < m; ++a) {
            if (!(fabs(step[a]) <= 1e-3))
                return;
            x[fr[a]] += step[a];
            if (x[fr[a]] <= BOUND_TOL || x[fr[a]] >= 1 - BOUND_TOL)
                return;
        }
        double v = violation(o, cc, nc, x, worst), g2[USM_NPARAMS], y2, gn2 = 0;
        if (v > FEAS_TOL || output(o, pb->objective, &y2, g2) != 0)
            return;
        for (int a = 0; a < m; ++a)
            gn2 = fmax(gn2, fabs(g2[fr[a]]));
        /* a smaller gradient, and not worse beyond the noise of the values */
        if (!(sigma * (y2 - y) <= POLISH_NOISE * fabs(y)) || !(gn2 < gn))
            return;
        memcpy(b->x, x, sizeof x);
        b->value = y2;
        b->violation = v;
        if (gn2 <= 1e-13 * fabs(y2))
            return;
    }
}

/* ---- at the optimum: multipliers and KKT residual ------------------------------------- */

/* Active constraints and bounds at x, their multipliers as d(value)/d(bound)
 * and the KKT residual.  In the box variables z and the outputs' own units,
 * with sigma = +1 (minimize) or -1 (maximize): the Lagrangian's gradient
 *   r = sigma grad y + sum_i lambda_i grad c_i - sum_lo nu_j e_j + sum_hi nu_j e_j,
 * c_i = sign_i (y_i - X_i) the active constraints, lambda, nu >= 0 by
 * non-negative least squares (cyclic coordinate descent, exact on each
 * coordinate; the problem is tiny).  The optimal objective's change per unit
 * of a bound (envelope theorem): X_i: -sigma sign_i lambda_i; LO_j:
 * sigma nu_j / w_j; HI_j: -sigma nu_j / w_j (w_j = HI_j - LO_j).  The residual:
 * max_j |r_j| / |y| (|y| = 0: max_j |r_j|). */
static double kkt(usm_optimize *o, cons_ctx *cc, int nc, const double *x, usm_opt_result *out)
{
    const usm_opt_problem *pb = o->pb;
    const int n = pb->nvary;
    const double sigma = pb->minimize ? 1.0 : -1.0;
    enum { NCOL = MAX_CONS + USM_NPARAMS };
    double g[USM_NPARAMS], A[NCOL][USM_NPARAMS], y, coef[NCOL]; /* coef: -> d(value)/d(bound) */
    int na = 0;
    evaluate(o, x);
    const int gok = output(o, pb->objective, &y, g) == 0;
    for (int j = 0; j < n; ++j)
        g[j] *= sigma;
    out->nactive = 0;
    for (int i = 0; i < nc; ++i) {
        double v, gi[USM_NPARAMS];
        if (fabs(cons_value(&cc[i], x, NULL)) > ACTIVE_TOL)
            continue;
        int k;
        double sign, bound;
        cons_def(&cc[i], &k, &sign, &bound);
        if (cons_own(&cc[i], x, &v, gi) != 0)
            memset(gi, 0, sizeof gi); /* no derivative: no multiplier (NaN below) */
        memcpy(A[na], gi, sizeof gi);
        coef[na] = -sigma * sign;
        cons_text(pb, &cc[i], out->active[out->nactive++]);
        na++;
    }
    for (int j = 0; j < n; ++j) {
        const int lo = x[j] <= BOUND_TOL, hi = x[j] >= 1 - BOUND_TOL;
        if (!lo && !hi)
            continue;
        memset(A[na], 0, sizeof A[na]);
        A[na][j] = lo ? -1.0 : 1.0;
        coef[na] = (lo ? sigma : -sigma) / (pb->hi[j] - pb->lo[j]);
        snprintf(out->active[out->nactive++], USM_OPT_TEXT_LEN, "bound: %s = %s",
                 usm_param_table[pb->vary[j]].name, lo ? "LO" : "HI");
        na++;
    }
    if (!gok) {
        for (int i = 0; i < na; ++i)
            out->multiplier[i] = NAN;
        return NAN;
    }
    double lambda[NCOL] = {0}, r[USM_NPARAMS];
    memcpy(r, g, sizeof r);
    for (int it = 0; it < 100000 && na > 0; ++it) {
        double change = 0, size = 0;
        for (int i = 0; i < na; ++i) {
            double num = 0, den = 0;
            for (int j = 0; j < n; ++j) {
                num -= r[j] * A[i][j];
                den += A[i][j] * A[i][j];
            }
            if (den == 0)
                continue;
            const double li = fmax(0, lambda[i] + num / den), d = li - lambda[i];
            for (int j = 0; j < n; ++j)
                r[j] += d * A[i][j];
            lambda[i] = li;
            change = fmax(change, fabs(d) * sqrt(den));
            size = fmax(size, li * sqrt(den));
        }
        double gn = 0;
        for (int j = 0; j < n; ++j)
            gn = fmax(gn, fabs(g[j]));
        if (change <= 1e-15 * fmax(size, gn))
            break;
    }
    double res = 0;
    for (int j = 0; j < n; ++j)
        res = fmax(res, fabs(r[j]));
    for (int i = 0; i < na; ++i) {
        double den = 0;
        for (int j = 0; j < n; ++j)
            den += A[i][j] * A[i][j];
        out->multiplier[i] = den > 0 ? coef[i] * lambda[i] : NAN;
        if (out->multiplier[i] == 0)
            out->multiplier[i] = 0; /* never -0 */
    }
    return fabs(y) > 0 ? res / fabs(y) : res;
}

/* ---- flat parameters: the near-optimal interval of each --------------------------------- */

#define PROFILE_CACHE 64

typedef struct profile_ctx {
    usm_optimize *o;
    cons_ctx *cc;
    int nc;
    int j;                        /* the varied parameter */
    const double *xstar;          /* the optimum */
    double ystar, tol;            /* its objective; near-optimal: within tol of it */
    /* the profile's points so far (the other parameters' optima), warm starts */
    int ncache;
    double zc[PROFILE_CACHE], xc[PROFILE_CACHE][USM_NPARAMS];
} profile_ctx;

/* Is y (feasible) better than the best so far (NaN: none)? */
static int improves(const usm_opt_problem *pb, double y, double sofar)
{
    return isnan(sofar) || (pb->minimize ? y < sofar : y > sofar);
}

/* The best feasible objective with parameter j at z, the others re-optimised
 * by SLSQP from the nearest profile point found so far (and, when that does
 * not end near-optimal, from the optimum's values), or the slice itself when
 * better; NaN when no feasible point was found. */
static double profile_value(profile_ctx *c, double z)
{
    usm_optimize *o = c->o;
    const usm_opt_problem *pb = o->pb;
    const int n = pb->nvary;
    double x[USM_NPARAMS], xbest[USM_NPARAMS], y = NAN, yc;
    char worst[USM_OPT_TEXT_LEN];
    memcpy(x, c->xstar, sizeof(double) * (size_t)n);
    x[c->j] = z;
    memcpy(xbest, x, sizeof xbest);
    if (violation(o, c->cc, c->nc, x, worst) <= FEAS_TOL && output(o, pb->objective, &yc, NULL) == 0)
        y = yc;
    for (int attempt = 0; n > 1 && attempt < 2 && !o->failed; ++attempt) {
        const double *from = c->xstar;
        if (attempt == 0) {
            int near = -1;
            for (int k = 0; k < c->ncache; ++k)
                if (near < 0 || fabs(c->zc[k] - z) < fabs(c->zc[near] - z))
                    near = k;
            if (near >= 0 && fabs(c->zc[near] - z) < fabs(c->xstar[c->j] - z))
                from = c->xc[near];
            else
                attempt = 1; /* the optimum is the nearest: one attempt */
        } else if (!isnan(y) && fabs(y - c->ystar) <= c->tol)
            break; /* near-optimal already: no second opinion needed */
        memcpy(x, from, sizeof(double) * (size_t)n);
        x[c->j] = z;
        o->fix = c->j;
        o->fix_z = z;
        nlopt_result res = slsqp(o, c->cc, c->nc, x, PROFILE_EVALS);
        o->fix = -1;
        if (!o->failed && (res > 0 || res == NLOPT_ROUNDOFF_LIMITED || res == NLOPT_FAILURE) &&
            violation(o, c->cc, c->nc, x, worst) <= FEAS_TOL &&
            output(o, pb->objective, &yc, NULL) == 0 && improves(pb, yc, y)) {
            y = yc;
            memcpy(xbest, x, sizeof xbest);
        }
    }
    if (o->failed) {
        /* a numerical failure (the sensitivities) off the optimum: not a
         * near-optimal point, and not a reason to lose the optimum found */
        o->failed = 0;
        o->msg[0] = '\0';
        return NAN;
    }
    if (!isnan(y) && c->ncache < PROFILE_CACHE) {
        c->zc[c->ncache] = z;
        memcpy(c->xc[c->ncache++], xbest, sizeof xbest);
    }
    return y;
}

/* > 0 where near-optimal, < 0 where not (infeasible, or a numerical failure). */
static double profile_fn(double z, void *ctx)
{
    profile_ctx *c = ctx;
    double y = profile_value(c, z);
    if (isnan(y))
        return -c->tol;
    return c->o->pb->minimize ? c->ystar + c->tol - y : y - (c->ystar - c->tol);
}

/* The near-optimal interval of each varied parameter: from the optimum
 * towards each bound in steps that double from 1/64 of the box (each point
 * warm-started from the last), until a point is not near-optimal; then
 * Brent between the last two points to FLAT_XTOL.  One interval is assumed:
 * a near-optimal region beyond a worse one is not looked for. */
static int flat_intervals(usm_optimize *o, cons_ctx *cc, int nc, const double *xstar,
                          double ystar, usm_opt_result *out)
{
    const usm_opt_problem *pb = o->pb;
    profile_ctx *c = malloc(sizeof *c);
    if (!c) {
        snprintf(o->msg, USM_MSG_LEN, "out of memory");
        return USM_EFAILED;
    }
    *c = (profile_ctx){.o = o, .cc = cc, .nc = nc, .xstar = xstar, .ystar = ystar,
                       .tol = USM_OPT_FLAT_TOL * (ystar != 0 ? fabs(ystar) : 1.0)};
    const usm_root_stop stop = {FLAT_XTOL, 0, 60};
    o->obj_scale = ystar != 0 ? fabs(ystar) : 1.0;
    for (int j = 0; j < pb->nvary; ++j) {
        double ends[2];
        c->j = j;
        c->ncache = 0;
        for (int side = 0; side < 2; ++side) {
            const double zb = side ? 1.0 : 0.0, dir = side ? 1.0 : -1.0;
            double z0 = xstar[j], f0 = c->tol, h = 1.0 / 64;
            ends[side] = zb;
            while (fabs(zb - z0) > BOUND_TOL) {
                const double z1 = fabs(zb - z0) <= h ? zb : z0 + dir * h;
                const double f1 = profile_fn(z1, c);
                if (f1 >= 0) {
                    z0 = z1;
                    f0 = f1;
                    h *= 2;
                    continue;
                }
                /* the end of Brent's last bracket on the near-optimal side (the
                 * function never fails: a failure reads as not near-optimal) */
                double z, a, b;
                usm_root_brent(o->root, profile_fn, c, z0, z1, f0, f1, &stop, &z);
                usm_root_bracket(o->root, &a, &b);
                ends[side] = fabs(a - xstar[j]) < fabs(b - xstar[j]) ? a : b;
                break;
            }
        }
        const double w = pb->hi[j] - pb->lo[j];
        out->near_lo[j] = fmax(pb->lo[j], pb->lo[j] + ends[0] * w);
        out->near_hi[j] = fmin(pb->hi[j], pb->lo[j] + ends[1] * w);
        out->flat[j] = ends[1] - ends[0] > USM_OPT_FLAT_FRACTION;
    }
    free(c);
    return USM_OK;
}

/* ---- the workspace and the run ---------------------------------------------------------- */

usm_optimize *usm_optimize_alloc(const usm_model *m)
{
    if (!m)
        return NULL;
    usm_optimize *o = calloc(1, sizeof *o);
    if (!o)
        return NULL;
    o->model = m;
    o->fix = -1;
    o->steady = usm_steady_alloc(m);
    o->steady_fd = usm_steady_alloc(m);
    o->fd_step = USM_OPT_FD_STEP;
    o->sens = usm_sensitivity_alloc(m);
    o->floquet = usm_floquet_alloc(m);
    o->root = usm_root_alloc();
    o->r = malloc(sizeof *o->r);
    o->r_root = malloc(sizeof *o->r_root);
    if (!o->steady || !o->steady_fd || !o->sens || !o->floquet || !o->root || !o->r ||
        !o->r_root) {
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
    free(o->r_root);
    free(o->fl);
    usm_root_free(o->root);
    usm_floquet_free(o->floquet);
    usm_sensitivity_free(o->sens);
    usm_steady_free(o->steady_fd);
    usm_steady_free(o->steady);
    free(o);
}

const usm_op_result *usm_optimize_op(const usm_optimize *o)
{
    return o->have_op ? &o->op : NULL;
}

const usm_floquet_result *usm_optimize_roots_floquet(const usm_optimize *o)
{
    return o->have_op ? o->fl : NULL;
}

const usm_steady *usm_optimize_steady(const usm_optimize *o)
{
    return o->steady;
}

const char *usm_optimize_message(const usm_optimize *o)
{
    return o->msg;
}

/* The point of least violation into out (feasible = 0). */
static void least_violation(usm_optimize *o, cons_ctx *cc, int nc, const best *b,
                            usm_opt_result *out)
{
    const usm_opt_problem *pb = o->pb;
    o->have = 0;
    evaluate(o, b->x);
    out->params = o->p;
    out->solved = o->solved;
    out->value = NAN;
    if (o->solved) {
        out->sol = o->sol;
        double y;
        if (output(o, pb->objective, &y, NULL) == 0)
            out->value = y;
    }
    out->least_violation = o->solved ? b->violation : NAN;
    out->nviolated = 0;
    if (!o->solved) {
        snprintf(out->violated[0], USM_OPT_TEXT_LEN, "a stationary solution exists");
        out->violation[0] = NAN;
        out->nviolated = 1;
        return;
    }
    for (int i = 0; i < nc; ++i) {
        double v = cons_value(&cc[i], b->x, NULL);
        if (v > FEAS_TOL) {
            cons_text(pb, &cc[i], out->violated[out->nviolated]);
            out->violation[out->nviolated++] = v;
        }
    }
}

int usm_optimize_run(usm_optimize *o, const usm_params *p, const usm_opt_problem *pb,
                     usm_opt_result *out)
{
    o->msg[0] = '\0';
    memset(out, 0, sizeof *out);
    out->least_violation = NAN;
    for (int j = 0; j < USM_NPARAMS; ++j)
        out->near_lo[j] = out->near_hi[j] = NAN;
    if (usm_opt_problem_check(pb, o->model, p, o->msg) != USM_OK)
        return USM_EINPUT;
    o->pb = pb;
    o->base = *p;
    o->have = o->solved = o->failed = 0;
    o->refused = o->no_op = o->have_op = 0;
    o->op_msg[0] = '\0';
    o->fix = -1;
    o->evaluations = 0;
    o->fd_step = USM_OPT_FD_STEP;
    usm_sensitivity_set_t0(o->sens, pb->t0);
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
    if (!b.have || !b.solved || b.violation > FEAS_TOL) {
        if (!b.have || !b.solved)
            snprintf(o->msg, USM_MSG_LEN,
                     "constraint: no feasible point found: no stationary solution%s at any of "
                     "the %d starts' end points%s%.90s%s",
                     o->refused || o->no_op ? " with an operating point" : "", pb->starts,
                     o->refused || o->no_op ? " (last refusal: " : "",
                     o->refused || o->no_op ? o->op_msg : "", o->refused || o->no_op ? ")" : "");
        else
            snprintf(o->msg, USM_MSG_LEN,
                     "constraint: no feasible point found: %s cannot be met (best violation %.3g)",
                     b.worst, b.violation);
        if (b.have)
            least_violation(o, cc, nc, &b, out);
        else {
            out->params = *p;
            snprintf(out->violated[0], USM_OPT_TEXT_LEN, "a stationary solution exists");
            out->violation[0] = NAN;
            out->nviolated = 1;
        }
        out->evaluations = o->evaluations;
        return USM_ENOSOLUTION;
    }
    polish(o, cc, nc, &b);
    if (o->failed) {
        if (!o->msg[0])
            snprintf(o->msg, USM_MSG_LEN, "numerical failure");
        return USM_EFAILED;
    }
    o->have = 0; /* re-evaluate at the optimum: the state NLopt left is another point's */
    evaluate(o, b.x);
    if (o->failed || !o->solved) {
        snprintf(o->msg, USM_MSG_LEN, "the optimum did not re-solve");
        return USM_EFAILED;
    }
    out->kkt_residual = kkt(o, cc, nc, b.x, out);
    if (!pb->no_flat && flat_intervals(o, cc, nc, b.x, b.value, out) != USM_OK) {
        if (!o->msg[0])
            snprintf(o->msg, USM_MSG_LEN, "numerical failure");
        return USM_EFAILED;
    }
    o->have = 0; /* the profiles moved the point: back to the optimum */
    evaluate(o, b.x);
    if (o->failed || !o->solved) {
        snprintf(o->msg, USM_MSG_LEN, "the optimum did not re-solve");
        return USM_EFAILED;
    }
    /* the multipliers reported: the discretisation the search used (the
     * sensitivities' exponential product), so that a max_modulus objective
     * or constraint reads the same number here */
    usm_floquet_options fo;
    usm_floquet_options_default(&fo);
    fo.method = USM_FLOQUET_EXPONENTIAL;
    fo.steps = USM_SENSITIVITY_STEPS;
    if (usm_floquet_compute(o->floquet, &o->p, &o->sol, pb->t0, &fo, &out->floquet) != USM_OK) {
        snprintf(o->msg, USM_MSG_LEN, "floquet: %.240s", usm_floquet_message(o->floquet));
        return USM_EFAILED;
    }
    /* the operating point at the optimum, every root's multipliers by the
     * same discretisation (the writer's `solution`) */
    if (operating_point(o, &fo) != 0)
        return USM_EFAILED;
    o->have_op = 1;
    out->feasible = 1;
    out->solved = 1;
    out->value = pb->objective == USM_SENS_MAX_MODULUS ? out->floquet.max_modulus
                 : pb->objective == USM_OPT_MARGIN     ? 1 - out->floquet.max_modulus
                                                       : b.value;
    out->params = o->p;
    out->sol = o->sol;
    out->evaluations = o->evaluations;
    return USM_OK;
}

int usm_optimize_output_derivative(usm_optimize *o, const usm_params *p,
                                   const usm_opt_problem *pb, int k, double step, int fd,
                                   double *value, double d[USM_NPARAMS])
{
    double x[USM_NPARAMS], g[USM_NPARAMS];
    o->msg[0] = '\0';
    o->have_op = 0;
    if (usm_opt_problem_check(pb, o->model, p, o->msg) != USM_OK)
        return USM_EINPUT;
    if (k < 0 || k >= USM_OPT_OUTPUT_COUNT) {
        snprintf(o->msg, USM_MSG_LEN, "output: %d out of range", k);
        return USM_EINPUT;
    }
    if (step == 0)
        step = USM_OPT_FD_STEP;
    if (!(step > 0 && step <= 0.25)) {
        snprintf(o->msg, USM_MSG_LEN, "step: must be in (0, 0.25]");
        return USM_EINPUT;
    }
    if (fd && (k == USM_SENS_MAX_MODULUS || k == USM_OPT_MARGIN)) {
        snprintf(o->msg, USM_MSG_LEN, "%s: no finite differences here (analytic only)",
                 usm_opt_output_name(k));
        return USM_EINPUT;
    }
    for (int i = 0; i < pb->nvary; ++i) {
        const double v = usm_params_get(p, &usm_param_table[pb->vary[i]]);
        if (!(v >= pb->lo[i] && v <= pb->hi[i])) {
            snprintf(o->msg, USM_MSG_LEN, "vary: %s = %g lies outside [%g, %g]",
                     usm_param_table[pb->vary[i]].name, v, pb->lo[i], pb->hi[i]);
            return USM_EINPUT;
        }
        x[i] = (v - pb->lo[i]) / (pb->hi[i] - pb->lo[i]);
    }
    o->pb = pb;
    o->base = *p;
    o->have = o->solved = o->failed = 0;
    o->refused = o->no_op = 0;
    o->fix = -1;
    o->fd_step = step;
    usm_sensitivity_set_t0(o->sens, pb->t0);
    evaluate(o, x);
    int rc = USM_OK;
    if (o->failed)
        rc = USM_EFAILED;
    else if (!o->solved) {
        snprintf(o->msg, USM_MSG_LEN, "no judged root here%s%.200s", o->op_msg[0] ? ": " : "",
                 o->op_msg);
        rc = USM_ENOSOLUTION;
    } else if (output_fd(o, k, value, g, fd) != 0) {
        snprintf(o->msg, USM_MSG_LEN, "%s: the derivative is not defined here",
                 usm_opt_output_name(k));
        rc = USM_ENOSOLUTION;
    } else
        for (int i = 0; i < pb->nvary; ++i)
            d[i] = g[i] / (pb->hi[i] - pb->lo[i]);
    o->fd_step = USM_OPT_FD_STEP;
    o->pb = NULL;
    return rc;
}
