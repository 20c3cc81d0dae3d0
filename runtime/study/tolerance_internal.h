/* tolerance_internal.h: the parts of a tolerance study shared by its files
 * (tolerance.c: parsing, sampling, the serial run; tolerance_io.c:
 * checkpoint; tolerance_stats.c: statistics; io/tolerance_out.c: the
 * writers; mpi/tolerance_mpi.c: the MPI run).  Not installed; not part of
 * the API.
 *
 * The samples are kept as rows of doubles, one per sample, in sample order:
 *   [0, nvary)            the varied parameters' values
 *   nvary + k             output k (USM_TOL_NOUTPUTS; NaN where it does not exist)
 *   nvary + NOUTPUTS      good (1: counts for the yield)
 *   nvary + NOUTPUTS + 1  redraws of this sample
 * A row of plain doubles is what the checkpoint and MPI move, bit for bit. */
#ifndef USM_TOLERANCE_INTERNAL_H
#define USM_TOLERANCE_INTERNAL_H

#include "usm_tolerance.h"

#define TOL_MAX_SPECS 64
#define TOL_ROW_GOOD(t) ((t)->nvary + USM_TOL_NOUTPUTS)
#define TOL_ROW_REDRAWS(t) ((t)->nvary + USM_TOL_NOUTPUTS + 1)

struct usm_tolerance {
    const usm_model *m;
    usm_tolerance_vary vary[USM_NPARAMS];
    int nvary;
    usm_tolerance_spec spec[TOL_MAX_SPECS];
    int nspec;
    /* the run */
    usm_params p;
    usm_tolerance_options opt;
    int width;              /* doubles per row: nvary + USM_TOL_NOUTPUTS + 2 */
    uint64_t nblocks;
    unsigned char *done;    /* per block: computed (or read from the checkpoint) */
    double *rows;           /* samples x width */
    char *config;           /* the study's configuration text (checkpoint header) */
    double last_write;      /* monotonic time of the last checkpoint write [s] */
    double write_seconds;   /* how long that write took */
    /* the result */
    int have_result;
    usm_tolerance_summary sum;
    double influence[USM_TOL_NNUMERIC][USM_NPARAMS];
    char msg[USM_MSG_LEN];
};

/* Samples in block b. */
uint64_t tol_block_size(const usm_tolerance *t, uint64_t b);

/* Check the options and nominal parameters, build the configuration text;
 * with root != 0 (the process that gathers the samples) allocate the rows
 * and, when the checkpoint file exists, read its blocks.  USM_OK or a status
 * with t->msg. */
int tol_prepare(usm_tolerance *t, const usm_params *p, const usm_tolerance_options *opt, int root);

/* Doubles that the rows of the n blocks listed take. */
uint64_t tol_pack_size(const usm_tolerance *t, const uint64_t *blocks, size_t n);

/* Compute the n blocks listed (threads: opt.threads), their rows one after
 * the other into pack (tol_pack_size doubles).  USM_OK or a status with
 * t->msg. */
int tol_compute(usm_tolerance *t, const uint64_t *blocks, size_t n, double *pack);

/* Copy the packed rows of the n blocks listed into t->rows; mark them done. */
void tol_unpack(usm_tolerance *t, const uint64_t *blocks, size_t n, const double *pack);

/* USM_EFAILED with the message of a run stopped by stop_after_blocks. */
int tol_stopped(usm_tolerance *t, uint64_t computed);

/* The blocks not done yet, in increasing order, into list (nblocks room);
 * returns how many. */
size_t tol_pending(const usm_tolerance *t, uint64_t *list);

/* Read / write the checkpoint file opt.checkpoint (tolerance_io.c). */
int tol_checkpoint_load(usm_tolerance *t);
int tol_checkpoint_write(usm_tolerance *t);

/* Seconds on a monotonic clock. */
double tol_now(void);

/* Whether a checkpoint write is due after this round (interval elapsed, the
 * stop hook reached, or the last round). */
int tol_checkpoint_due(const usm_tolerance *t, int last, int stop);

/* Counts, yield, quantiles and influence from the rows (tolerance_stats.c). */
int tol_finish(usm_tolerance *t);

#endif /* USM_TOLERANCE_INTERNAL_H */
