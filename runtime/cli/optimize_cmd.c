/* usm optimize: best design over parameter bounds (the optimizer:
 * usm_optimize.h); this file reads the problem and writes the optimum. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "commands.h"
#include "diag.h"
#include "optimize_args.h"
#include "options.h"
#include "progress.h"
#include "usm_io.h"
#include "usm_optimize.h"
#include "usm_robust.h"
#include "usm_run.h"

typedef struct opt_args {
    cli_common common;
    usm_opt_problem pb;
    usm_robust_problem rp;   /* the robust options; rp.nominal = pb at the end */
    int robust;              /* usm_robust_problem_is_robust */
    int quiet;               /* --quiet: no progress line (robust design) */
} opt_args;

static void usage(FILE *out)
{
    fprintf(out,
            "usage: usm optimize --objective NAME [--minimize] --vary NAME=LO:HI [--vary ...]\n"
            "                    [--constraint OUTPUT>=X | OUTPUT<=X]... [--stability-margin D]\n"
            "                    [--allow-slip] [--allow-driven] [--starts N] [--t0 S]\n"
            "                    [--no-flat] [--model M] [--variant V] [--params F]\n"
            "                    [--set N=V]... [--from-rest [--from-rest-periods N]] [--json]\n"
            "       usm optimize --objective yield|mean:NAME|qNN:NAME|NAME --scatter NAME=DIST...\n"
            "                    [--constraint yield>=Y] [--samples N] [--verify-samples N]\n"
            "                    [--seed S] [--threads N] [--max-evals N] [--quiet] (robust design)\n"
            "       usm optimize --objective NAME --over-range P=LO:HI[:N] [--range-stat S]\n"
            "                    [--band-threshold X] ... (ranges, datasheet quantities)\n"
            "\n"
            "Maximize (default) or minimize an output of the primary stationary solution over\n"
            "the --vary parameters within their bounds, subject to: a stationary solution\n"
            "exists; max_modulus <= 1 - D (--stability-margin, default 0.01; multipliers\n"
            "from t0); the motor drives the load, power_out >= 0, unless --allow-driven;\n"
            "stick is admissible in the stick model (F_t <= mu0 F_n) unless --allow-slip;\n"
            "every --constraint.  NLopt SLSQP with the analytic sensitivities as gradients,\n"
            "from --starts (default 8) deterministic points spread over the box; the best\n"
            "feasible result wins.  At the optimum: each active constraint's multiplier\n"
            "(the objective's change per unit of its bound), the KKT residual, and the\n"
            "flat parameters (objective within 1e-4 relative over more than a tenth of\n"
            "their bounds).  A design is judged by its operating point: one root is it\n"
            "when stable; where several roots exist the design is refused (infeasible)\n"
            "unless --from-rest, which simulates the start-up there and judges the root\n"
            "it reaches.\n"
            "\n"
            "outputs (objective and constraints; analytic gradients): speed (= -rotor_speed,\n"
            "positive when the motor drives; rotor_speed is an alias of it), theta, F_n,\n"
            "F_t, efficiency, stick_margin, max_modulus, power_in, power_out,\n"
            "margin (= 1 - max_modulus, analytic); and for constraints only, of the judged\n"
            "root as usm steady writes them: alpha, beta, mu_used, v_c, v_rel, R_star, Z,\n"
            "power_damping, power_slip (central differences in the varied parameters,\n"
            "step 1e-4 of each box).  A constraint may name root R's output (R from 1,\n"
            "as usm steady lists the roots) as rootR.NAME, e.g. root2.theta>=5e-5: every\n"
            "output, by central differences along that root (max_modulus, margin: that\n"
            "root's own multipliers, analytic derivative);\n"
            "violated where root R does not exist.  roots>=N / roots<=N (the number of\n"
            "roots) is a filter: a design not meeting it is refused\n"
            "\n"
            "options:\n");
    cli_common_usage(out);
    fprintf(out,
            "  --allow-driven      drop power_out >= 0 (designs the load drives backwards)\n"
            "  --t0 S              start of the Floquet period [s] (default 0, the paper's)\n"
            "  --no-flat           skip the near-optimal intervals (flat parameters)\n");
    cli_from_rest_usage(out);
    fprintf(out,
            "robust design (a derivative-free search, NLopt COBYLA, from the nominal optimum):\n"
            "  --objective yield   maximize the yield: the fraction of built motors (the\n"
            "                      --scatter samples) whose operating point exists, is stable,\n"
            "                      valid and meets every --constraint\n"
            "  --objective mean:NAME, qNN:NAME  the mean or the NN %% quantile of output NAME\n"
            "                      over the scatter (q05:power_out: 5 %% of the motors give less;\n"
            "                      a sample without an operating point counts as the worst)\n"
            "  --constraint yield>=Y  at least the fraction Y (0 < Y < 1) of the motors good;\n"
            "                      every other constraint holds at the nominal design and is a\n"
            "                      spec of each sample\n"
            "  --scatter NAME=DIST the manufacturing scatter of a parameter, DIST as usm\n"
            "                      tolerance --vary: normal:2%%, normal:SIGMA, uniform:P%%,\n"
            "                      uniform:LO:HI, numbers with units (F0=normal:20mN)\n"
            "                      (repeatable)\n"
            "  --samples N         common-random-number samples per design (default 10000;\n"
            "                      " USM_ROBUST_SAMPLES_TEXT "): the same seed and draws at every\n"
            "                      design\n"
            "  --verify-samples N  the final check: a fresh sample (seed S + 1) at the chosen\n"
            "                      design with its 95 %% Wilson interval (default 100000;\n"
            "                      " USM_ROBUST_SAMPLES_TEXT ")\n"
            "  --seed S            seed of the samples (default 1; 0 to " USM_SEED_MAX_TEXT ")\n"
            "  --threads N         worker threads for the samples (default 2)\n"
            "  --max-evals N       designs per COBYLA run (default 40)\n"
            "operating ranges and datasheet quantities (objective or constraint):\n"
            "  --over-range P=LO:HI[:N]  judge the objective output over parameter P from LO\n"
            "                      to HI (N grid values, default 21) by --range-stat: worst\n"
            "                      (default), mean or integral; the load range of stall_torque\n"
            "                      and max_power (T; default 0 to 0.01 N m), the frequency\n"
            "                      range of band_width (f)\n"
            "  stall_torque        slip models: the load T where the speed reaches 0 (the\n"
            "                      stall event of usm sweep --over T)\n"
            "  no_load_speed       the speed at T = 0;  max_power: the largest power_out over\n"
            "                      the load range;  band_width: the length of the frequency\n"
            "                      range where speed >= --band-threshold X [1/s]\n");
    cli_quiet_usage(out);
    fprintf(out,
            "  -h, --help          print this help\n"
            "\n"
            "exit status: 0 optimum found, 1 numerical failure, 2 bad specification,\n"
            "             3 no feasible point (the message names the constraint; with --json\n"
            "             {\"feasible\": false, ...} on stdout)\n");
}

/* NAME=LO:HI */
static int parse_vary(usm_opt_problem *pb, const char *text, char msg[CLI_MSG_LEN])
{
    char name[64], lo_text[64], lib[USM_MSG_LEN];
    const char *eq = strchr(text, '='), *colon = eq ? strchr(eq, ':') : NULL;
    double lo, hi;
    if (!eq || !colon || eq == text || (size_t)(eq - text) >= sizeof name ||
        (size_t)(colon - eq - 1) >= sizeof lo_text) {
        cli_msg(msg, "--vary: expected NAME=LO:HI, got \"%s\"", text);
        return USM_EINPUT;
    }
    snprintf(name, sizeof name, "%.*s", (int)(eq - text), text);
    snprintf(lo_text, sizeof lo_text, "%.*s", (int)(colon - eq - 1), eq + 1);
    const usm_param_info *info = usm_params_find(name);
    if (!info) {
        cli_msg(msg, "--vary: unknown parameter \"%s\"", name);
        return USM_EINPUT;
    }
    if (cli_parse_quantity("--vary", info->unit, lo_text, &lo, msg) != USM_OK ||
        cli_parse_quantity("--vary", info->unit, colon + 1, &hi, msg) != USM_OK)
        return USM_EINPUT;
    if (usm_opt_problem_add_vary(pb, name, lo, hi, lib) != USM_OK) {
        cli_msg(msg, "--%s", lib);
        return USM_EINPUT;
    }
    return USM_OK;
}

/* OUTPUT>=X or OUTPUT<=X (optimize_args.h) */
static int parse_constraint(usm_opt_problem *pb, const char *text, char msg[CLI_MSG_LEN])
{
    const char *op = strstr(text, ">=");
    int upper = 0;
    char name[64], lib[USM_MSG_LEN];
    double value;
    if (!op) {
        op = strstr(text, "<=");
        upper = 1;
    }
    if (!op || op == text || (size_t)(op - text) >= sizeof name) {
        cli_msg(msg, "--constraint: expected OUTPUT>=X or OUTPUT<=X, got \"%s\"", text);
        return USM_EINPUT;
    }
    snprintf(name, sizeof name, "%.*s", (int)(op - text), text);
    /* NAME, rootR.NAME (NAME checked here, R by the library) or roots */
    const int per_root = strncmp(name, "root", 4) == 0;
    const char *dot = per_root ? strchr(name, '.') : NULL;
    const char *bare = dot ? dot + 1 : name;
    if ((!per_root || dot) && usm_opt_output_find(bare) < 0) {
        char list[512];
        usm_opt_output_list(list, sizeof list);
        cli_msg(msg, "--constraint: unknown output \"%s\" (one of: %s)", name, list);
        return USM_EINPUT;
    }
    if (cli_parse_double("--constraint", op + 2, &value, msg) != USM_OK)
        return USM_EINPUT;
    if (usm_opt_problem_add_constraint(pb, name, upper, value, lib) != USM_OK) {
        cli_msg(msg, "--%s", lib);
        return USM_EINPUT;
    }
    return USM_OK;
}

/* --objective NAME, yield, mean:NAME or qNN:NAME */
static int parse_objective(opt_args *a, const char *value, char msg[CLI_MSG_LEN])
{
    char lib[USM_IO_MSG_LEN];
    if (usm_robust_objective_parse(&a->rp, value, lib) != USM_OK) {
        cli_msg(msg, "--%.1000s", lib);
        return USM_EINPUT;
    }
    return USM_OK;
}

/* --constraint yield>=Y or on a derived quantity: CLI_OPT_TAKEN (msg set on
 * an error), else CLI_OPT_NOT_MINE (an optimizer output: parse_constraint). */
static int parse_robust_constraint(opt_args *a, const char *text, char msg[CLI_MSG_LEN])
{
    char lib[USM_IO_MSG_LEN];
    msg[0] = '\0';
    const int rc = usm_robust_constraint_parse(&a->rp, text, lib);
    if (rc == 1)
        return CLI_OPT_NOT_MINE;
    if (rc != USM_OK)
        cli_msg(msg, "--%.1000s", lib);
    return CLI_OPT_TAKEN;
}

/* --over-range P=LO:HI[:N] */
static int parse_range(opt_args *a, const char *text, char msg[CLI_MSG_LEN])
{
    char buf[160], *eq, *c1, *c2;
    snprintf(buf, sizeof buf, "%s", text);
    eq = strchr(buf, '=');
    c1 = eq ? strchr(eq + 1, ':') : NULL;
    c2 = c1 ? strchr(c1 + 1, ':') : NULL;
    if (!eq || !c1) {
        cli_msg(msg, "--over-range: expected NAME=LO:HI[:N], got \"%s\"", text);
        return USM_EINPUT;
    }
    *eq = *c1 = '\0';
    if (c2)
        *c2 = '\0';
    const usm_param_info *info = usm_params_find(buf);
    usm_robust_range *r = &a->rp.qopt.range;
    if (!info) {
        cli_msg(msg, "--over-range: unknown parameter \"%s\"", buf);
        return USM_EINPUT;
    }
    if (cli_parse_quantity("--over-range", info->unit, eq + 1, &r->lo, msg) != USM_OK ||
        cli_parse_quantity("--over-range", info->unit, c1 + 1, &r->hi, msg) != USM_OK)
        return USM_EINPUT;
    if (c2 && (cli_parse_int("--over-range", c2 + 1, &r->points, msg) != USM_OK))
        return USM_EINPUT;
    if (!(r->lo < r->hi) || r->points < 2 || r->points > 100000) {
        cli_msg(msg, "--over-range: needs LO < HI and 2 <= N <= 100000");
        return USM_EINPUT;
    }
    r->param = usm_param_index(info);
    return USM_OK;
}

static int parse_count(const char *opt, const char *value, uint64_t *out, char msg[CLI_MSG_LEN])
{
    double v;
    if (cli_parse_double(opt, value, &v, msg) != USM_OK)
        return USM_EINPUT;
    if (!(v >= (double)USM_ROBUST_MIN_SAMPLES && v <= (double)USM_ROBUST_MAX_SAMPLES) ||
        v != floor(v)) {
        cli_msg(msg, "%s: a whole number %llu to %llu, got \"%s\"", opt,
                (unsigned long long)USM_ROBUST_MIN_SAMPLES,
                (unsigned long long)USM_ROBUST_MAX_SAMPLES, value);
        return USM_EINPUT;
    }
    *out = (uint64_t)v;
    return USM_OK;
}

static int parse_robust_option(opt_args *a, const char *opt, const char *value,
                               char msg[CLI_MSG_LEN])
{
    usm_robust_problem *rp = &a->rp;
    if (strcmp(opt, "--scatter") == 0) {
        if (rp->nscatter >= USM_ROBUST_MAX_SCATTER) {
            cli_msg(msg, "--scatter: at most %d", USM_ROBUST_MAX_SCATTER);
            return USM_EINPUT;
        }
        char vmsg[USM_IO_MSG_LEN];
        if (usm_tolerance_vary_parse_units("--scatter:", value, &rp->scatter[rp->nscatter],
                                           vmsg) != USM_OK) {
            cli_msg(msg, "%.1000s", vmsg);
            return USM_EINPUT;
        }
        rp->nscatter++;
        return USM_OK;
    }
    if (strcmp(opt, "--samples") == 0)
        return parse_count(opt, value, &rp->samples, msg);
    if (strcmp(opt, "--verify-samples") == 0)
        return parse_count(opt, value, &rp->verify_samples, msg);
    if (strcmp(opt, "--seed") == 0) {
        double v;
        if (cli_parse_double(opt, value, &v, msg) != USM_OK)
            return USM_EINPUT;
        if (!(v >= 0 && v <= (double)USM_SEED_MAX) || v != floor(v)) {
            cli_msg(msg, "--seed: a whole number 0 to %llu, got \"%s\"",
                    (unsigned long long)USM_SEED_MAX, value);
            return USM_EINPUT;
        }
        rp->seed = (uint64_t)v;
        return USM_OK;
    }
    if (strcmp(opt, "--threads") == 0)
        return cli_parse_int(opt, value, &rp->threads, msg);
    if (strcmp(opt, "--max-evals") == 0)
        return cli_parse_int(opt, value, &rp->max_evals, msg);
    if (strcmp(opt, "--over-range") == 0)
        return parse_range(a, value, msg);
    if (strcmp(opt, "--range-stat") == 0) {
        const int s = usm_range_stat_find(value);
        if (s < 0) {
            cli_msg(msg, "--range-stat: one of worst, mean, integral, got \"%s\"", value);
            return USM_EINPUT;
        }
        rp->qopt.range.stat = (usm_range_stat)s;
        return USM_OK;
    }
    /* --band-threshold */
    return cli_parse_double(opt, value, &rp->qopt.band_threshold, msg);
}

/* optimize_args.h */
int cli_opt_problem_option(usm_opt_problem *pb, int argc, char **argv, int *i,
                           char msg[CLI_MSG_LEN])
{
    const char *v;
    int r;
    CLI_TRY(cli_flag_option(argv, i, "--allow-slip", &pb->allow_slip));
    CLI_TRY(cli_flag_option(argv, i, "--allow-driven", &pb->allow_driven));
    if ((r = cli_option_value(argc, argv, i, "--vary", &v, msg)) == CLI_OPT_NOT_MINE &&
        (r = cli_option_value(argc, argv, i, "--constraint", &v, msg)) == CLI_OPT_TAKEN)
        return parse_constraint(pb, v, msg) == USM_OK ? r : CLI_OPT_ERROR;
    if (r != CLI_OPT_NOT_MINE)
        return r == CLI_OPT_TAKEN && parse_vary(pb, v, msg) != USM_OK ? CLI_OPT_ERROR : r;
    if ((r = cli_option_value(argc, argv, i, "--stability-margin", &v, msg)) == CLI_OPT_TAKEN)
        return cli_parse_double("--stability-margin", v, &pb->margin, msg) ? CLI_OPT_ERROR : r;
    if (r != CLI_OPT_NOT_MINE)
        return r;
    CLI_TRY(cli_int_option(argc, argv, i, "--starts", &pb->starts, msg));
    return cli_quantity_option(argc, argv, i, "--t0", "s", &pb->t0, msg);
}

static int init(void *p, char msg[CLI_MSG_LEN])
{
    opt_args *a = p;
    (void)msg;
    usm_opt_problem_init(&a->pb);
    usm_robust_problem_init(&a->rp);
    return USM_OK;
}

static int option(void *p, int argc, char **argv, int *i, char msg[CLI_MSG_LEN])
{
    static const char *const robust_opts[] = {"--scatter", "--samples", "--verify-samples",
                                              "--seed", "--threads", "--max-evals",
                                              "--over-range", "--range-stat", "--band-threshold"};
    opt_args *a = p;
    const char *value;
    int r, j = *i;
    CLI_TRY(cli_flag_option(argv, i, "--minimize", &a->pb.minimize));
    CLI_TRY(cli_flag_option(argv, i, "--no-flat", &a->pb.no_flat));
    CLI_TRY(cli_quiet_option(&a->quiet, argc, argv, i));
    CLI_TRY(cli_common_option(&a->common, argc, argv, i, msg));
    usm_op_options op;
    usm_op_options_default(&op);
    op.periods = a->pb.from_rest_periods > 0 ? a->pb.from_rest_periods : op.periods;
    op.from_rest = a->pb.from_rest;
    if ((r = cli_from_rest_option(&op, argc, argv, i, msg)) == CLI_OPT_TAKEN) {
        a->pb.from_rest = op.from_rest;
        a->pb.from_rest_periods = op.periods;
    }
    if (r != CLI_OPT_NOT_MINE)
        return r;
    if ((r = cli_option_value(argc, argv, i, "--objective", &value, msg)) != CLI_OPT_NOT_MINE)
        return r == CLI_OPT_TAKEN && parse_objective(a, value, msg) != USM_OK ? CLI_OPT_ERROR : r;
    /* a robust constraint (yield, a derived quantity) before an optimizer output's */
    if (cli_option_value(argc, argv, &j, "--constraint", &value, msg) == CLI_OPT_TAKEN &&
        parse_robust_constraint(a, value, msg) == CLI_OPT_TAKEN) {
        *i = j;
        return msg[0] ? CLI_OPT_ERROR : CLI_OPT_TAKEN;
    }
    for (size_t k = 0; k < sizeof robust_opts / sizeof robust_opts[0]; ++k)
        if ((r = cli_option_value(argc, argv, i, robust_opts[k], &value, msg)) != CLI_OPT_NOT_MINE)
            return r == CLI_OPT_TAKEN && parse_robust_option(a, robust_opts[k], value, msg)
                       ? CLI_OPT_ERROR
                       : r;
    return cli_opt_problem_option(&a->pb, argc, argv, i, msg);
}

static int finish(void *p, char msg[CLI_MSG_LEN])
{
    opt_args *a = p;
    int rc = cli_common_finish(&a->common, msg);
    if (rc != USM_OK)
        return rc;
    char lib[USM_MSG_LEN];
    /* an imperfect motor: usm steady's reason, word for word */
    if (usm_params_check_ideal(&a->common.params, lib) != USM_OK) {
        cli_msg(msg, "%s", lib);
        return USM_EINPUT;
    }
    a->robust = usm_robust_problem_is_robust(&a->rp);
    if (a->robust) {
        a->rp.nominal = a->pb;
        if (usm_robust_problem_check(&a->rp, a->common.model, &a->common.params, lib) !=
            USM_OK) {
            cli_msg(msg, "--%s", lib);
            return USM_EINPUT;
        }
        return USM_OK;
    }
    if (a->rp.objective >= 0)
        a->pb.objective = a->rp.objective;
    if (usm_opt_problem_check(&a->pb, a->common.model, &a->common.params, lib) != USM_OK) {
        cli_msg(msg, "--%s", lib);
        return USM_EINPUT;
    }
    return USM_OK;
}

static int write_result(const void *p, const usm_run *r, FILE *out)
{
    const opt_args *a = p;
    if (a->robust)
        usm_robust_write_table(a->common.model, &a->rp, usm_run_robust_result(r), out);
    else
        usm_optimize_write_table(a->common.model, &a->pb, usm_run_optimize_result(r), out);
    return 0;
}

static int run(void *p)
{
    opt_args *a = p;
    const usm_model *m = a->common.model;
    cli_progress bar; /* the robust search only: the nominal one takes seconds */
    cli_progress_init(&bar, "usm optimize", a->quiet || !a->robust);
    a->rp.nominal.progress = cli_progress_callback(&bar);
    usm_run *r = a->robust ? usm_run_robust(m, &a->common.params, &a->rp)
                           : usm_run_optimize(m, &a->common.params, &a->pb);
    cli_progress_end(&bar);
    /* no feasible point: the message, and --json's {"feasible": false, ...} */
    int status = cli_run_output(r, a->common.json, CLI_JSON_ON_FAILURE | CLI_MESSAGE_ALWAYS,
                                write_result, a);
    usm_run_free(r);
    return status;
}

const cli_command cli_optimize = {sizeof(opt_args), usage, init, option, finish, run, 0, 0};
