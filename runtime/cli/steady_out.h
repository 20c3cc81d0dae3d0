/* steady_out.h: output of a stationary solution and its Floquet multipliers,
 * as a table for people or as one JSON object for programs. */
#ifndef USM_CLI_STEADY_OUT_H
#define USM_CLI_STEADY_OUT_H

#include <stdio.h>

#include <jansson.h>

#include "csv_out.h" /* cli_shortest */

#include "usm.h"

typedef struct cli_steady_report {
    const usm_model *model;
    const usm_params *params;
    const usm_steady *steady;         /* its roots; 0 roots when error is set */
    const char *error;                /* NULL when a root was found */
    const usm_floquet_result *floquet; /* of root 0; NULL when error is set */
} cli_steady_report;

/* The `usm steady --json` object (keys: see docs/cli.md), or NULL when out
 * of memory. */
json_t *cli_steady_json(const cli_steady_report *r);

/* The human-readable table (only for a report without error). */
void cli_steady_table(const cli_steady_report *r, FILE *out);

#endif /* USM_CLI_STEADY_OUT_H */
