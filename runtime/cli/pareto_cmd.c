/* usm pareto: the Pareto front of two outputs (usm_robust.h);
 * this file reads the problem and writes the front. */
#include <stdio.h>

#include "commands.h"
#include "diag.h"
#include "optimize_args.h"
#include "options.h"
#include "progress.h"
#include "usm_io.h"
#include "usm_plot.h"
#include "usm_robust.h"
#include "usm_run.h"

typedef struct pareto_args {
    cli_common common;
    usm_opt_problem pb;
    int obj[2], minimize[2];
    int points;
    const char *plot;
    int force;
    int quiet;
    int have_obj;
} pareto_args;

static void usage(FILE *out)
{
    fprintf(out,
            "usage: usm pareto --objectives A,B --vary NAME=LO:HI [--vary ...]\n"
            "                  [--constraint OUTPUT>=X | OUTPUT<=X]... [--points N]\n"
            "                  [--stability-margin D] [--allow-slip] [--allow-driven]\n"
            "                  [--starts N] [--t0 S] [--model M] [--variant V] [--params F]\n"
            "                  [--set N=V]... [--json] [--plot PREFIX [--force]] [--quiet]\n"
            "\n"
            "The Pareto front of two outputs of the operating point (the trade-off: no\n"
            "design is better in both) over the --vary parameters, under the constraints\n"
            "of usm optimize (stability margin, drives, stick, every --constraint), by the\n"
            "epsilon-constraint method: the two single optima bound the front; then A is\n"
            "optimized (usm optimize's SLSQP) with B >= eps at N - 2 levels between them,\n"
            "each warm-started from its neighbour's design (the lattice's starts when that\n"
            "fails).  Dominated points are dropped.  Both objectives are maximized; write\n"
            "min:NAME to minimize one (--objectives speed,min:F_n).  Objectives: outputs\n"
            "with analytic gradients (speed, theta, F_n, F_t, efficiency, stick_margin,\n"
            "max_modulus, power_in, power_out, margin).\n"
            "\n"
            "Output: CSV on stdout (point, A [unit], B [unit], the varied parameters, active:\n"
            "the active constraints); --json: {objectives, senses, points: [{A, B, design,\n"
            "active_constraints}], computed, seconds}.\n"
            "\n"
            "options:\n");
    cli_common_usage(out);
    fprintf(out,
            "  --objectives A,B    the two outputs (min:NAME minimizes)\n"
            "  --points N          epsilon levels including the two ends (default 30)\n"
            "  --stability-margin D, --starts N, --t0 S, --allow-slip, --allow-driven:\n"
            "                      as usm optimize\n"
            "  --plot PREFIX       also PREFIX.csv and the figure PREFIX.png/svg (gnuplot)\n"
            "  --force             overwrite the --plot files\n");
    cli_quiet_usage(out);
    fprintf(out,
            "  -h, --help          print this help\n"
            "\n"
            "exit status: 0 front found, 1 numerical failure, 2 bad specification,\n"
            "             3 no feasible design\n");
}

static int init(void *p, char msg[CLI_MSG_LEN])
{
    pareto_args *a = p;
    (void)msg;
    usm_opt_problem_init(&a->pb);
    a->points = 30;
    return USM_OK;
}

static int option(void *p, int argc, char **argv, int *i, char msg[CLI_MSG_LEN])
{
    pareto_args *a = p;
    const char *value;
    char lib[USM_IO_MSG_LEN];
    int r;
    CLI_TRY(cli_flag_option(argv, i, "--force", &a->force));
    CLI_TRY(cli_quiet_option(&a->quiet, argc, argv, i));
    CLI_TRY(cli_plot_option(argc, argv, i, &a->plot, msg));
    CLI_TRY(cli_common_option(&a->common, argc, argv, i, msg));
    if ((r = cli_option_value(argc, argv, i, "--objectives", &value, msg)) == CLI_OPT_TAKEN) {
        if (usm_pareto_objectives_parse(value, a->obj, a->minimize, lib) != USM_OK) {
            cli_msg(msg, "--%.1000s", lib);
            return CLI_OPT_ERROR;
        }
        a->have_obj = 1;
    }
    if (r != CLI_OPT_NOT_MINE)
        return r;
    if ((r = cli_int_option(argc, argv, i, "--points", &a->points, msg)) == CLI_OPT_TAKEN &&
        (a->points < 2 || a->points > USM_PARETO_MAX_POINTS)) {
        cli_msg(msg, "--points: must be 2 to %d", USM_PARETO_MAX_POINTS);
        return CLI_OPT_ERROR;
    }
    if (r != CLI_OPT_NOT_MINE)
        return r;
    return cli_opt_problem_option(&a->pb, argc, argv, i, msg);
}

static int finish(void *p, char msg[CLI_MSG_LEN])
{
    pareto_args *a = p;
    int rc = cli_common_finish(&a->common, msg);
    if (rc != USM_OK)
        return rc;
    if (!a->have_obj) {
        cli_msg(msg, "--objectives: required (A,B)");
        return USM_EINPUT;
    }
    if (a->force && !a->plot) {
        cli_msg(msg, "--force: only with --plot (it overwrites the --plot files)");
        return USM_EINPUT;
    }
    char lib[USM_MSG_LEN];
    if (usm_params_check_ideal(&a->common.params, lib) != USM_OK) {
        cli_msg(msg, "%s", lib);
        return USM_EINPUT;
    }
    usm_opt_problem q = a->pb;
    q.objective = a->obj[0];
    if (usm_opt_problem_check(&q, a->common.model, &a->common.params, lib) != USM_OK) {
        cli_msg(msg, "--%s", lib);
        return USM_EINPUT;
    }
    return a->plot ? usm_plot_csv_check(a->plot, a->force, msg) : USM_OK;
}

static int front_csv(const void *p, const usm_run *r, FILE *out)
{
    const pareto_args *a = p;
    return usm_pareto_write_csv(&a->pb, a->obj, usm_run_pareto_result(r), out);
}

static int plot(const pareto_args *a, const usm_run *r)
{
    char msg[CLI_MSG_LEN], xcol[96], ycol[96];
    const cli_csv csv = {front_csv, a, r};
    int rc = usm_plot_csv_write(a->plot, a->force, cli_csv_write, &csv, msg);
    if (rc != USM_OK) {
        cli_error("%s", msg);
        return rc;
    }
    snprintf(ycol, sizeof ycol, "%s [%s]", usm_opt_output_name(a->obj[0]),
             usm_opt_output_unit(a->obj[0]));
    snprintf(xcol, sizeof xcol, "%s [%s]", usm_opt_output_name(a->obj[1]),
             usm_opt_output_unit(a->obj[1]));
    const char *names[] = {"xcol", "ycol"};
    const char *values[] = {xcol, ycol};
    return cli_plot_status(usm_plot_render("pareto", a->plot, names, values, 2, msg), msg);
}

static int run(void *p)
{
    pareto_args *a = p;
    cli_progress bar;
    cli_progress_init(&bar, "usm pareto", a->quiet);
    a->pb.progress = cli_progress_callback(&bar);
    usm_run *r = usm_run_pareto(a->common.model, &a->common.params, &a->pb, a->obj, a->minimize,
                                a->points);
    cli_progress_end(&bar);
    int status = cli_run_output(r, a->common.json, 0, front_csv, a);
    if (status == USM_OK && a->plot)
        status = plot(a, r);
    usm_run_free(r);
    return status;
}

const cli_command cli_pareto = {sizeof(pareto_args), usage, init, option, finish, run, 0, 0};
