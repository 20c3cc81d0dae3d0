/* tolerance_internal.h: the parts of a tolerance study shared by its files
 * (tolerance.c: parsing, sampling, the rounds of blocks; tolerance_stats.c:
 * statistics) and by the layers above it (write/tolerance_run.c: the serial
 * run; write/tolerance_checkpoint.c: the checkpoint; write/tolerance_out.c:
 * the writers; mpi/tolerance_mpi.c: the MPI run).  Not installed; not part
 * of the API.
 */
#ifndef USM_TOLERANCE_INTERNAL_H
#define USM_TOLERANCE_INTERNAL_H

#include "tolerance_rows.h"
#include "tolerance_stats.h"

/* Check the options and nominal parameters, build the configuration text;
 * as rank `rank` of `size`, allocate the rows of the blocks this rank owns
 * (tol_owned); a checkpoint is read above the study, by the run that
 * keeps one (write/tolerance_checkpoint.c: tol_checkpoint_open).  USM_OK or
 * a status with t->msg. */
int tol_prepare(usm_tolerance *t, const usm_params *p, const usm_tolerance_options *opt,
                int rank, int size);

/* Compute the n blocks listed (threads: opt.threads), their rows one after
 * the other into pack (tol_pack_size doubles).  USM_OK or a status with
 * t->msg. */
int tol_compute(usm_tolerance *t, const uint64_t *blocks, size_t n, double *pack);

/* USM_EFAILED with the message of a run stopped by stop_after_blocks. */
int tol_stopped(usm_tolerance *t, uint64_t computed);

/* Whether a checkpoint write is due after this round (interval elapsed, the
 * stop hook reached, or the last round). */
int tol_checkpoint_due(const usm_tolerance *t, int last, int stop);

#endif /* USM_TOLERANCE_INTERNAL_H */
