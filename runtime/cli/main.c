/* usm: command-line front end of the usm library.  Dispatches to one
 * subcommand per file (see commands.h). */
#include <stdio.h>
#include <string.h>

#include <gsl/gsl_errno.h>

#include "commands.h"
#include "diag.h"
#include "usm.h"

#ifndef USM_VERSION
#define USM_VERSION "unknown" /* CMake defines it; a bare `gcc -c` does not */
#endif

typedef struct cli_command {
    const char *name;
    const char *summary;
    int (*run)(int argc, char **argv);
} cli_command;

static const cli_command commands[] = {
    {"steady", "stationary solutions and their Floquet multipliers", cli_steady_main},
    {"periodic", "periodic steady state of a real motor (phase error, imbalance, mode split)", cli_periodic_main},
    {"sweep", "motor characteristics: a parameter sweep by continuation, with events", cli_sweep_main},
    {"variants", "list the modelling variants (--variant NAME selects one)", cli_variants_main},
    {"equations", "the derived equations as Markdown or LaTeX", cli_equations_main},
    {"report", "reproduce the paper: report.md with tables and figures", cli_report_main},
    {"map", "stability map: largest Floquet multiplier over a 2-D parameter grid", cli_map_main},
    {"simulate", "start-up transient of the full model: CSV time history, settling, contact checks", cli_simulate_main},
    {"sensitivity", "derivatives and elasticities of the stationary outputs in every parameter", cli_sensitivity_main},
    {"optimize", "best design over parameter bounds under stability, stick and user constraints", cli_optimize_main},
    {"tolerance", "Monte Carlo yield: stability and specs under parameter scatter", cli_tolerance_main},
    {"pareto", "trade-off front of two outputs (epsilon-constraint), CSV, JSON and figure", cli_pareto_main},
};
#define NCOMMANDS (sizeof commands / sizeof commands[0])

static void usage(FILE *out)
{
    fprintf(out,
            "usage: usm COMMAND [OPTIONS]\n"
            "       usm --help | --version\n"
            "       usm help COMMAND\n"
            "\n"
            "Ultrasonic wobbling-disk motor: stationary solution and Floquet stability.\n"
            "\n"
            "commands:\n");
    int width = 0;
    for (size_t k = 0; k < NCOMMANDS; ++k)
        if ((int)strlen(commands[k].name) > width)
            width = (int)strlen(commands[k].name);
    for (size_t k = 0; k < NCOMMANDS; ++k)
        fprintf(out, "  %-*s %s\n", width, commands[k].name, commands[k].summary);
    fprintf(out,
            "\n"
            "Run \"usm COMMAND --help\" for a command's options.\n"
            "Exit status: 0 solved, 1 numerical failure, 2 bad input, 3 no stationary solution.\n");
}

static const cli_command *find_command(const char *name)
{
    for (size_t k = 0; k < NCOMMANDS; ++k)
        if (strcmp(commands[k].name, name) == 0)
            return &commands[k];
    return NULL;
}

static int finish(int status)
{
    /* A full disk or closed pipe must not look like success to a script. */
    if (fflush(stdout) != 0 || ferror(stdout)) {
        cli_error("stdout: write error");
        return status == USM_OK ? USM_EFAILED : status;
    }
    return status;
}

int main(int argc, char **argv)
{
    const cli_command *cmd;
    /* The library reports GSL failures as status codes; GSL's default
     * handler would abort the process instead (see usm.h). */
    gsl_set_error_handler_off();

    if (argc < 2) {
        usage(stderr);
        return USM_EINPUT;
    }
    if (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0) {
        usage(stdout);
        return finish(USM_OK);
    }
    if (strcmp(argv[1], "--version") == 0) {
        printf("usm %s\n", USM_VERSION);
        printf("usm generator %s (derivation input sha256:%s)\n", USM_GENERATOR_VERSION,
               USM_INPUT_DIGEST);
        return finish(USM_OK);
    }
    if (strcmp(argv[1], "help") == 0) {
        char help[] = "--help";
        char *sub[3] = {NULL, help, NULL};
        if (argc == 2) {
            usage(stdout);
            return finish(USM_OK);
        }
        if (!(cmd = find_command(argv[2]))) {
            cli_error("%s: unknown command (see usm --help)", argv[2]);
            return USM_EINPUT;
        }
        sub[0] = argv[2];
        return finish(cmd->run(2, sub));
    }
    if (argv[1][0] == '-') {
        cli_error("%s: unknown option (see usm --help)", argv[1]);
        return USM_EINPUT;
    }
    if (!(cmd = find_command(argv[1]))) {
        cli_error("%s: unknown command (see usm --help)", argv[1]);
        return USM_EINPUT;
    }
    return finish(cmd->run(argc - 1, argv + 1));
}
