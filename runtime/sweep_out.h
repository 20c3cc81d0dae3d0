/* sweep_out.h: output of `usm sweep`, as CSV for plotting or as one JSON
 * object for programs (formats: docs/sweep.md). */
#ifndef USM_SWEEP_OUT_H
#define USM_SWEEP_OUT_H

#include <stdio.h>

#include <jansson.h>

#include "io_msg.h"
#include "usm_io.h"
#include "usm_sweep.h"

/* The `usm sweep --json` object, or NULL when out of memory.  p: the
 * parameters apart from the swept one. */
json_t *usm_sweep_json(const usm_sweep *s, const usm_model *m, const usm_params *p,
                       const char *over);


/* `--plot PREFIX` of usm sweep and usm map: the data file PREFIX.csv beside
 * the files usm_plot_check guards.  usm_plot_csv_check: USM_OK when none of
 * PREFIX.csv/.gp/.png/.svg exists (or force), else USM_EINPUT with msg;
 * called before the computation.  usm_plot_csv_open: PREFIX.csv opened for
 * writing (never replacing a file that appeared meanwhile unless force), or
 * NULL with msg. */
int usm_plot_csv_check(const char *prefix, int force, char msg[USM_IO_MSG_LEN]);
FILE *usm_plot_csv_open(const char *prefix, int force, char msg[USM_IO_MSG_LEN]);

#endif /* USM_SWEEP_OUT_H */
