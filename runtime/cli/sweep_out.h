/* sweep_out.h: output of `usm sweep`, as CSV for plotting or as one JSON
 * object for programs (formats: docs/sweep.md). */
#ifndef USM_CLI_SWEEP_OUT_H
#define USM_CLI_SWEEP_OUT_H

#include <stdio.h>

#include <jansson.h>

#include "usm_sweep.h"

/* The `usm sweep --json` object, or NULL when out of memory.  p: the
 * parameters apart from the swept one. */
json_t *cli_sweep_json(const usm_sweep *s, const usm_model *m, const usm_params *p,
                       const char *over);

/* The CSV table: a header with units, one row per grid point, then the events
 * as comment lines starting with '#'.  0, or -1 on a write error. */
int cli_sweep_csv(const usm_sweep *s, const char *over, int floquet, FILE *out);

#endif /* USM_CLI_SWEEP_OUT_H */
