/* usm optimize: best design over parameter bounds (the optimizer:
 * usm_optimize.h); this file reads the problem and writes the optimum. */
#include <stdio.h>

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

/* A library parser's status; on an error its message, which names the
 * option without its dashes, as the option's. */
static int lib_status(int rc, const char *lib, char msg[CLI_MSG_LEN])
{
    if (rc != USM_OK)
        cli_msg(msg, "--%.1000s", lib);
    return rc;
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
 * an error), else CLI_OPT_NOT_MINE (an optimizer output: usm_opt_constraint_parse). */
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

/* optimize_args.h */
int cli_opt_problem_option(usm_opt_problem *pb, int argc, char **argv, int *i,
                           char msg[CLI_MSG_LEN])
{
    char lib[USM_IO_MSG_LEN];
    const char *v;
    int r;
    CLI_TRY(cli_flag_option(argv, i, "--allow-slip", &pb->allow_slip));
    CLI_TRY(cli_flag_option(argv, i, "--allow-driven", &pb->allow_driven));
    if ((r = cli_option_value(argc, argv, i, "--vary", &v, msg)) == CLI_OPT_NOT_MINE &&
        (r = cli_option_value(argc, argv, i, "--constraint", &v, msg)) == CLI_OPT_TAKEN)
        return lib_status(usm_opt_constraint_parse(pb, v, lib), lib, msg) == USM_OK
                   ? r
                   : CLI_OPT_ERROR;
    if (r != CLI_OPT_NOT_MINE)
        return r == CLI_OPT_TAKEN && lib_status(usm_opt_vary_parse(pb, v, lib), lib, msg)
                   ? CLI_OPT_ERROR
                   : r;
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
    char lib[USM_IO_MSG_LEN];
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
            return r == CLI_OPT_TAKEN &&
                           lib_status(usm_robust_option_parse(&a->rp, robust_opts[k] + 2, value,
                                                              lib), lib, msg)
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
