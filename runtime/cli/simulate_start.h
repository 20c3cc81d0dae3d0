/* simulate_start.h: the start state of `usm simulate --from FILE`: a CSV time
 * history written by usm simulate (its last row) or a JSON summary of it
 * (its "final_state"). */
#ifndef USM_CLI_SIMULATE_START_H
#define USM_CLI_SIMULATE_START_H

#include "diag.h"
#include "usm.h"
#include "usm_simulate.h"

/* Read the state of model m from the file at path into opt (x0, t0,
 * rotor_angle0).  USM_OK, or USM_EINPUT with "--from PATH: reason" in msg. */
int cli_sim_read_start(const char *path, const usm_model *m, usm_sim_options *opt,
                       char msg[CLI_MSG_LEN]);

#endif /* USM_CLI_SIMULATE_START_H */
