/* optimize_args.h: the options usm optimize and usm pareto share
 * (optimize_cmd.c). */
#ifndef USM_CLI_OPTIMIZE_ARGS_H
#define USM_CLI_OPTIMIZE_ARGS_H

#include "options.h"
#include "usm_optimize.h"

/* --vary NAME=LO:HI into pb.  USM_OK or USM_EINPUT with msg. */
int cli_opt_parse_vary(usm_opt_problem *pb, const char *text, char msg[CLI_MSG_LEN]);
/* --constraint OUTPUT>=X or OUTPUT<=X into pb.  USM_OK or USM_EINPUT with msg. */
int cli_opt_parse_constraint(usm_opt_problem *pb, const char *text, char msg[CLI_MSG_LEN]);

#endif /* USM_CLI_OPTIMIZE_ARGS_H */
