/* commands.h: the usm subcommands, run the same way by main.c.
 *
 * A command is a row of the table in main.c (its name and the line of `usm
 * --help`) pointing at a cli_command of its <name>_cmd.c.  main.c allocates
 * the command's options (`size` bytes, zeroed), calls init, offers every
 * argument to `option` after --help/-h, calls finish, then prints the usage
 * (for --help) or calls run, and maps a refused argument to its one line and
 * exit 2.  run returns the exit status (USM_OK, USM_EFAILED, USM_EINPUT,
 * USM_ENOSOLUTION).  Every command's options start with a cli_common.
 */
#ifndef USM_CLI_COMMANDS_H
#define USM_CLI_COMMANDS_H

#include <stddef.h>
#include <stdio.h>

#include "diag.h"

typedef struct cli_command {
    size_t size;             /* of the command's options */
    void (*usage)(FILE *out);
    /* defaults, after cli_common_init; NULL: none.  USM_OK or USM_EINPUT with msg. */
    int (*init)(void *a, char msg[CLI_MSG_LEN]);
    /* argv[*i] offered: CLI_OPT_TAKEN, CLI_OPT_ERROR with msg, or
     * CLI_OPT_NOT_MINE ("unknown option"/"unexpected argument") */
    int (*option)(void *a, int argc, char **argv, int *i, char msg[CLI_MSG_LEN]);
    /* after the last argument; NULL: cli_common_finish.  USM_OK or USM_EINPUT. */
    int (*finish)(void *a, char msg[CLI_MSG_LEN]);
    int (*run)(void *a);
    int mpi;                 /* shares its work over MPI ranks under mpirun */
    int units;               /* shows tables or CSV: takes --units (options.h) */
} cli_command;

extern const cli_command cli_steady, cli_periodic, cli_sweep, cli_variants, cli_equations,
    cli_report, cli_map, cli_simulate, cli_sensitivity, cli_optimize, cli_tolerance, cli_pareto,
    cli_squeal, cli_fit, cli_envelope;

#endif /* USM_CLI_COMMANDS_H */
