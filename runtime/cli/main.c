/* usm: command-line front end of the usm library.  One table of the
 * subcommands, each run the same way (commands.h). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>

#include "commands.h"
#include "diag.h"
#include "options.h"
#include "usm.h"
#ifdef USM_HAVE_MPI
#include "usm_mpi.h"
#endif

#ifndef USM_VERSION
#define USM_VERSION "unknown" /* CMake defines it; a bare `gcc -c` does not */
#endif

typedef struct cli_entry {
    const char *name;
    const char *summary;
    const cli_command *cmd;
} cli_entry;

static const cli_entry commands[] = {
    {"steady", "stationary solutions and their Floquet multipliers", &cli_steady},
    {"periodic", "periodic steady state of a real motor (phase error, imbalance, mode split)", &cli_periodic},
    {"sweep", "motor characteristics: a parameter sweep by continuation, with events", &cli_sweep},
    {"squeal", "beyond the last periodic orbit: kind of motion, Lyapunov exponent, audible lines", &cli_squeal},
    {"variants", "list the modelling variants (--variant NAME selects one)", &cli_variants},
    {"equations", "the derived equations as Markdown or LaTeX", &cli_equations},
    {"report", "reproduce the paper: report.md with tables and figures", &cli_report},
    {"map", "stability map: largest Floquet multiplier over a 2-D parameter grid", &cli_map},
    {"envelope", "operating envelope: every boundary continued in two parameters, regions named", &cli_envelope},
    {"simulate", "start-up transient of the full model: CSV time history, settling, contact checks", &cli_simulate},
    {"sensitivity", "derivatives and elasticities of the stationary outputs in every parameter", &cli_sensitivity},
    {"optimize", "best design over parameter bounds under stability, stick and user constraints", &cli_optimize},
    {"tolerance", "Monte Carlo yield: stability and specs under parameter scatter", &cli_tolerance},
    {"pareto", "trade-off front of two outputs (epsilon-constraint), CSV, JSON and figure", &cli_pareto},
    {"fit", "parameters identified from measured characteristics, with intervals and identifiability", &cli_fit},
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

static const cli_entry *find_command(const char *name)
{
    for (size_t k = 0; k < NCOMMANDS; ++k)
        if (strcmp(commands[k].name, name) == 0)
            return &commands[k];
    return NULL;
}

/* Under mpirun: MPI started, the rank and size in c; the ranks but 0 print
 * nothing (rank 0 reports and writes). */
static int mpi_start(cli_common *c)
{
#ifdef USM_HAVE_MPI
    char msg[USM_MSG_LEN];
    if (usm_mpi_launched() && usm_mpi_start(&c->rank, &c->size, msg) != USM_OK) {
        cli_error("mpi: %s", msg);
        return USM_EFAILED;
    }
    if (c->rank != 0 && (!freopen("/dev/null", "w", stdout) || !freopen("/dev/null", "w", stderr)))
        return USM_EFAILED;
#else
    (void)c;
#endif
    return USM_OK;
}

/* The arguments into the command's options: USM_OK, USM_EINPUT with msg, or
 * -1 for --help. */
static int parse(const cli_entry *e, void *a, int argc, char **argv, char msg[CLI_MSG_LEN])
{
    for (int i = 1; i < argc; ++i) {
        int r;
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0)
            return -1;
        if ((r = e->cmd->option(a, argc, argv, &i, msg)) == CLI_OPT_TAKEN)
            continue;
        if (r == CLI_OPT_NOT_MINE)
            cli_msg(msg, "%s: %s (see usm %s --help)", argv[i],
                    argv[i][0] == '-' ? "unknown option" : "unexpected argument", e->name);
        return USM_EINPUT;
    }
    return e->cmd->finish ? e->cmd->finish(a, msg) : cli_common_finish(a, msg);
}

static int run(const cli_entry *e, int argc, char **argv)
{
    char msg[CLI_MSG_LEN];
    void *a = calloc(1, e->cmd->size);
    int status;
    if (!a) {
        cli_error("out of memory");
        return USM_EFAILED;
    }
    cli_common_init(a);
    ((cli_common *)a)->units_ok = e->cmd->units;
    status = e->cmd->init ? e->cmd->init(a, msg) : USM_OK;
    if (e->cmd->mpi && mpi_start(a) != USM_OK) {
        free(a);
        return USM_EFAILED;
    }
    if (status == USM_OK)
        status = parse(e, a, argc, argv, msg);
    if (status == -1) {
        e->cmd->usage(stdout);
        status = USM_OK;
    } else if (status != USM_OK) {
        cli_error("%s", msg);
        status = USM_EINPUT;
    } else
        status = e->cmd->run(a);
    free(a);
    return status;
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
    const cli_entry *cmd;
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
        return finish(run(cmd, 2, sub));
    }
    if (argv[1][0] == '-') {
        cli_error("%s: unknown option (see usm --help)", argv[1]);
        return USM_EINPUT;
    }
    if (!(cmd = find_command(argv[1]))) {
        cli_error("%s: unknown command (see usm --help)", argv[1]);
        return USM_EINPUT;
    }
    return finish(run(cmd, argc - 1, argv + 1));
}
