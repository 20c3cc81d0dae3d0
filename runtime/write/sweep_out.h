/* sweep_out.h: output of `usm sweep`, as CSV for plotting or as one JSON
 * object for programs (formats: docs/sweep.md). */
#ifndef USM_SWEEP_OUT_H
#define USM_SWEEP_OUT_H

#include <stdio.h>

#include <jansson.h>

#include "io/io_msg.h"
#include "usm_io.h"
#include "usm_sweep.h"

/* The `usm sweep --json` object, or NULL when out of memory.  p: the
 * parameters apart from the swept one. */
json_t *usm_sweep_json(const usm_sweep *s, const usm_model *m, const usm_params *p,
                       const char *over);


#endif /* USM_SWEEP_OUT_H */
