/* run_internal.h: the usm_run object (usm_run.h) as the run files fill it. */
#ifndef USM_RUN_INTERNAL_H
#define USM_RUN_INTERNAL_H

#include <stdio.h>

#include "usm_io.h"
#include "usm_run.h"

struct usm_run {
    int status;
    int has_json;
    char msg[USM_IO_MSG_LEN];
    const usm_model *model;
    usm_params params;          /* a copy: writers point into it */
    /* the kind's JSON writer and its state (freed by free_data) */
    int (*write_json)(const usm_run *r, FILE *out);
    void (*free_data)(void *data);
    void *data;
    int kind;                   /* RUN_STEADY ...: which accessor may read data */
    double *rows;               /* usm_run_rows (malloc'd) */
    int (*make_rows)(usm_run *r); /* makes rows at the first usm_run_rows, or NULL */
    size_t nrows, ncols;
};

enum {
    RUN_STEADY = 1, RUN_SENSITIVITY, RUN_PERIODIC, RUN_SIMULATE, RUN_SWEEP, RUN_PERIODIC_SWEEP,
    RUN_MAP, RUN_OPTIMIZE, RUN_ROBUST, RUN_PARETO, RUN_TOLERANCE, RUN_SQUEAL, RUN_FIT, RUN_ENVELOPE
};

/* A run of kind `kind` with data (owned from now on: freed by free_data,
 * also here when out of memory), status USM_OK, no JSON yet.  NULL when out
 * of memory. */
usm_run *run_new(int kind, const usm_model *m, const usm_params *p, void *data,
                 void (*free_data)(void *data));
/* Set the status and the message (printf format). */
void run_fail(usm_run *r, int status, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
/* The data of r when it is of kind `kind`, else NULL. */
void *run_data(const usm_run *r, int kind);

#endif /* USM_RUN_INTERNAL_H */
