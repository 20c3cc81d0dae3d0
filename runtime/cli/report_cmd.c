/* usm report: the paper reproduced in DIR/report.md, with figures (the
 * library writes it: usm_report.h). */
#include <stdio.h>
#include <string.h>

#include "commands.h"
#include "diag.h"
#include "options.h"
#include "progress.h"
#include "usm.h"
#include "usm_report.h"

static void usage(FILE *out)
{
    fprintf(out,
            "usage: usm report --out DIR [--quick] [--force] [--no-plots] [--threads N]\n"
            "                  [--params FILE.json] [--set NAME=VALUE]... [--quiet]\n"
            "\n"
            "Reproduce the paper: compute the stationary solutions, Floquet multipliers,\n"
            "motor characteristics (speed vs f, T, m0) and stability maps of both models and\n"
            "write DIR/report.md: every published number beside the computed one, the\n"
            "reasons where they differ, and the figures (PNG and SVG, drawn by gnuplot from\n"
            "CSV data and scripts written into DIR as well).\n"
            "\n"
            "options:\n"
            "  --out DIR           output directory (created if missing)\n"
            "  --quick             coarser grids (a few seconds; for tests)\n"
            "  --force             overwrite DIR/report.md and the report's files even if\n"
            "                      they were not written by usm report.  Without it a report\n"
            "                      that usm wrote is replaced, anything else is kept\n"
            "  --no-plots          write data and gnuplot scripts but do not run gnuplot\n"
            "  --threads N         worker threads (default 2)\n"
            "  --params FILE.json  parameter values (default: the paper's)\n"
            "  --set NAME=VALUE    set one parameter (repeatable; applied after --params)\n");
    cli_quiet_usage(out);
    fprintf(out,
            "  -h, --help          print this help\n"
            "\n"
            "gnuplot is taken from $USM_GNUPLOT, else \"gnuplot\" on the PATH.\n"
            "On success prints the path of report.md.\n"
            "exit status: 0 written, 1 numerical failure or figures not rendered (the\n"
            "             report is still written), 2 bad input or DIR not usable,\n"
            "             3 no stationary solution at the chosen parameters\n");
}

typedef struct report_args {
    cli_common common;
    const char *out;
    int quick, force, plots, threads, quiet;
} report_args;

static int init(void *p, char msg[CLI_MSG_LEN])
{
    report_args *a = p;
    (void)msg;
    a->plots = 1;
    a->threads = 2;
    return USM_OK;
}

static int option(void *p, int argc, char **argv, int *i, char msg[CLI_MSG_LEN])
{
    report_args *a = p;
    int no_plots = 0;
    CLI_TRY(cli_flag_option(argv, i, "--quick", &a->quick));
    CLI_TRY(cli_quiet_option(&a->quiet, argc, argv, i));
    CLI_TRY(cli_flag_option(argv, i, "--force", &a->force));
    if (cli_flag_option(argv, i, "--no-plots", &no_plots) == CLI_OPT_TAKEN) {
        a->plots = 0;
        return CLI_OPT_TAKEN;
    }
    /* The report always covers the paper's two models; --json has no
     * meaning for a directory of files. */
    static const char *const not_here[] = {"--json", "--model", "--variant"};
    for (size_t k = 0; k < sizeof not_here / sizeof not_here[0]; ++k) {
        size_t len = strlen(not_here[k]);
        if (strncmp(argv[*i], not_here[k], len) == 0 &&
            (argv[*i][len] == '\0' || argv[*i][len] == '=')) {
            cli_msg(msg, "%s: not an option of usm report (it covers the paper's 3dof "
                         "and 4dof models; see usm report --help)", not_here[k]);
            return CLI_OPT_ERROR;
        }
    }
    CLI_TRY(cli_common_option(&a->common, argc, argv, i, msg));
    CLI_TRY(cli_path_option(argc, argv, i, "--out", "directory name", &a->out, msg));
    return cli_int_option(argc, argv, i, "--threads", &a->threads, msg);
}

static int finish(void *p, char msg[CLI_MSG_LEN])
{
    report_args *a = p;
    if (!a->out) {
        cli_msg(msg, "--out: missing, the output directory is required");
        return USM_EINPUT;
    }
    return cli_common_finish(&a->common, msg);
}

static int run(void *p)
{
    const report_args *a = p;
    usm_report_options opt;
    char msg[CLI_MSG_LEN];
    int status;

    usm_report_options_default(&opt);
    opt.quick = a->quick;
    opt.threads = a->threads;
    opt.plots = a->plots;
    opt.force = a->force;
    if (usm_report_options_check(&opt, msg) != USM_OK) {
        cli_error("--%s", msg);
        return USM_EINPUT;
    }
    if (usm_report_prepare_dir(a->out, &opt, msg) != USM_OK) {
        cli_error("--out %s", msg);
        return USM_EINPUT;
    }
    cli_progress bar;
    cli_progress_init(&bar, "usm report", a->quiet);
    opt.progress = cli_progress_callback(&bar);
    status = usm_report_write(a->out, &a->common.params, &opt, msg);
    cli_progress_end(&bar);
    if (status != USM_OK) {
        cli_error("%s", msg);
        return status;
    }
    printf("%s/report.md\n", a->out);
    return USM_OK;
}

const cli_command cli_report = {sizeof(report_args), usage, init, option, finish, run, 0, 0};
