/* sweep_out.h: output of `usm sweep`, as CSV for plotting or as one JSON
 * object for programs (formats: docs/sweep.md). */
#ifndef USM_CLI_SWEEP_OUT_H
#define USM_CLI_SWEEP_OUT_H

#include <stdio.h>

#include <jansson.h>

#include "diag.h"
#include "usm_sweep.h"

/* The `usm sweep --json` object, or NULL when out of memory.  p: the
 * parameters apart from the swept one. */
json_t *cli_sweep_json(const usm_sweep *s, const usm_model *m, const usm_params *p,
                       const char *over);

/* The CSV table: a header with units, one row per grid point, then the events
 * as comment lines starting with '#'.  0, or -1 on a write error. */
int cli_sweep_csv(const usm_sweep *s, const char *over, int floquet, FILE *out);

/* `--plot PREFIX` of usm sweep and usm map: the data file PREFIX.csv beside
 * the files cli_plot_check guards.  cli_plot_csv_check: USM_OK when none of
 * PREFIX.csv/.gp/.png/.svg exists (or force), else USM_EINPUT with msg;
 * called before the computation.  cli_plot_csv_open: PREFIX.csv opened for
 * writing (never replacing a file that appeared meanwhile unless force), or
 * NULL with msg. */
int cli_plot_csv_check(const char *prefix, int force, char msg[CLI_MSG_LEN]);
FILE *cli_plot_csv_open(const char *prefix, int force, char msg[CLI_MSG_LEN]);

#endif /* USM_CLI_SWEEP_OUT_H */
