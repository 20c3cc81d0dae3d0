/* optimize_args.h: the options usm optimize and usm pareto share
 * (optimize_cmd.c). */
#ifndef USM_CLI_OPTIMIZE_ARGS_H
#define USM_CLI_OPTIMIZE_ARGS_H

#include "options.h"
#include "usm_optimize.h"

/* --vary NAME=LO:HI, --constraint OUTPUT>=X|OUTPUT<=X, --stability-margin D,
 * --starts N, --t0 S, --allow-slip, --allow-driven into pb: offer argv[*i]
 * as to cli_common_option. */
int cli_opt_problem_option(usm_opt_problem *pb, int argc, char **argv, int *i,
                           char msg[CLI_MSG_LEN]);

#endif /* USM_CLI_OPTIMIZE_ARGS_H */
