/* usm pareto: the Pareto front of two outputs (usm_robust.h);
 * this file reads the problem and writes the front. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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
    int help;
    int quiet;
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

static int parse(pareto_args *a, int argc, char **argv, char msg[CLI_MSG_LEN])
{
    static const char *const opts[] = {"--objectives", "--vary", "--constraint",
                                       "--stability-margin", "--starts", "--t0", "--points"};
    enum { NOPTS = sizeof opts / sizeof opts[0] };
    int have_obj = 0;
    memset(a, 0, sizeof *a);
    cli_common_init(&a->common);
    usm_opt_problem_init(&a->pb);
    a->points = 30;
    for (int i = 1; i < argc; ++i) {
        const char *value;
        int r, which = -1;
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            a->help = 1;
            return USM_OK;
        }
        if (strcmp(argv[i], "--allow-slip") == 0) {
            a->pb.allow_slip = 1;
            continue;
        }
        if (strcmp(argv[i], "--allow-driven") == 0) {
            a->pb.allow_driven = 1;
            continue;
        }
        if (strcmp(argv[i], "--force") == 0) {
            a->force = 1;
            continue;
        }
        if (cli_quiet_option(&a->quiet, argc, argv, &i) == CLI_OPT_TAKEN)
            continue;
        if ((r = cli_plot_option(argc, argv, &i, &a->plot, msg)) == CLI_OPT_TAKEN)
            continue;
        if (r == CLI_OPT_ERROR)
            return USM_EINPUT;
        if ((r = cli_common_option(&a->common, argc, argv, &i, msg)) == CLI_OPT_TAKEN)
            continue;
        if (r == CLI_OPT_ERROR)
            return USM_EINPUT;
        for (int o = 0; o < NOPTS && which < 0; ++o) {
            if ((r = cli_option_value(argc, argv, &i, opts[o], &value, msg)) == CLI_OPT_ERROR)
                return USM_EINPUT;
            if (r == CLI_OPT_TAKEN)
                which = o;
        }
        if (which == 0) {
            char lib[USM_IO_MSG_LEN];
            if (usm_pareto_objectives_parse(value, a->obj, a->minimize, lib) != USM_OK) {
                cli_msg(msg, "--%.1000s", lib);
                return USM_EINPUT;
            }
            have_obj = 1;
        } else if (which == 1 || which == 2) {
            if ((which == 1 ? cli_opt_parse_vary : cli_opt_parse_constraint)(&a->pb, value, msg) !=
                USM_OK)
                return USM_EINPUT;
        } else if (which == 3) {
            if (cli_parse_double(opts[which], value, &a->pb.margin, msg) != USM_OK)
                return USM_EINPUT;
        } else if (which == 4) {
            if (cli_parse_int(opts[which], value, &a->pb.starts, msg) != USM_OK)
                return USM_EINPUT;
        } else if (which == 5) {
            if (cli_parse_quantity(opts[which], "s", value, &a->pb.t0, msg) != USM_OK)
                return USM_EINPUT;
        } else if (which == 6) {
            if (cli_parse_int(opts[which], value, &a->points, msg) != USM_OK)
                return USM_EINPUT;
            if (a->points < 2 || a->points > USM_PARETO_MAX_POINTS) {
                cli_msg(msg, "--points: must be 2 to %d", USM_PARETO_MAX_POINTS);
                return USM_EINPUT;
            }
        } else {
            cli_msg(msg, "%s: %s (see usm pareto --help)", argv[i],
                    argv[i][0] == '-' ? "unknown option" : "unexpected argument");
            return USM_EINPUT;
        }
    }
    int rc = cli_common_finish(&a->common, msg);
    if (rc != USM_OK)
        return rc;
    if (!have_obj) {
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

typedef struct csv_data {
    const pareto_args *a;
    const usm_pareto_result *res;
} csv_data;

static int write_csv(FILE *out, const void *data)
{
    const csv_data *d = data;
    return usm_pareto_write_csv(&d->a->pb, d->a->obj, d->res, out);
}

static int plot(const pareto_args *a, const usm_pareto_result *res)
{
    char msg[CLI_MSG_LEN], xcol[96], ycol[96];
    const csv_data data = {a, res};
    int rc = usm_plot_csv_write(a->plot, a->force, write_csv, &data, msg);
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
    rc = usm_plot_render("pareto", a->plot, names, values, 2, msg);
    if (rc == USM_ENOSOLUTION) {
        cli_error("warning: %s", msg);
        return USM_OK;
    }
    if (rc != USM_OK) {
        cli_error("%s", msg);
        return rc == USM_EINPUT ? USM_EINPUT : USM_EFAILED;
    }
    return USM_OK;
}

int cli_pareto_main(int argc, char **argv)
{
    pareto_args a;
    char msg[CLI_MSG_LEN];
    if (parse(&a, argc, argv, msg) != USM_OK) {
        cli_error("%s", msg);
        return USM_EINPUT;
    }
    if (a.help) {
        usage(stdout);
        return USM_OK;
    }
    cli_progress bar;
    cli_progress_init(&bar, "usm pareto", a.quiet);
    a.pb.progress = cli_progress_callback(&bar);
    usm_run *r = usm_run_pareto(a.common.model, &a.common.params, &a.pb, a.obj, a.minimize,
                                a.points);
    cli_progress_end(&bar);
    int status = usm_run_status(r);
    const usm_pareto_result *res = usm_run_pareto_result(r);
    if (status != USM_OK) {
        cli_error("%s", usm_run_message(r));
        usm_run_free(r);
        return status;
    }
    int w = a.common.json ? usm_run_write_json(r, stdout)
                          : usm_pareto_write_csv(&a.pb, a.obj, res, stdout);
    if (w != 0 || fflush(stdout) != 0 || ferror(stdout)) {
        clearerr(stdout);
        cli_error("stdout: write error");
        status = USM_EFAILED;
    }
    if (status == USM_OK && a.plot)
        status = plot(&a, res);
    usm_run_free(r);
    return status;
}
