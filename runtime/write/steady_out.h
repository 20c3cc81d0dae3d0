/* steady_out.h: the `usm steady --json` object as a jansson value, for the
 * writers that nest it (internal; the public writers: usm_io.h). */
#ifndef USM_STEADY_OUT_H
#define USM_STEADY_OUT_H

#include <stdio.h>

#include <jansson.h>

#include "io/csv_out.h" /* usm_shortest */

#include "usm.h"
#include "usm_io.h"


/* The `usm steady --json` object (keys: see docs/cli.md), or NULL when out
 * of memory. */
json_t *usm_steady_json(const usm_steady_report *r);


#endif /* USM_STEADY_OUT_H */
