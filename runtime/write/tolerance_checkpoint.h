/* tolerance_checkpoint.h: the checkpoint files of a tolerance study
 * (tolerance_checkpoint.c), read and written by the runs above the study
 * (tolerance_run.c, mpi/tolerance_mpi.c), never by the study itself.  Not
 * installed; not part of the API. */
#ifndef USM_TOLERANCE_CHECKPOINT_H
#define USM_TOLERANCE_CHECKPOINT_H

#include "design/tolerance_rows.h"

/* Read / write the checkpoint file opt.checkpoint (tolerance_checkpoint.c). */
int tol_checkpoint_load(usm_tolerance *t);
int tol_checkpoint_write(usm_tolerance *t);

/* After tol_prepare, before the first round: with opt.checkpoint, read the
 * rows this rank owns from the checkpoint files where they hold them
 * (tol_checkpoint_load) and lock this rank's file.  USM_OK or a status with
 * t->msg. */
int tol_checkpoint_open(usm_tolerance *t);

/* This rank's checkpoint file: FILE for rank 0, FILE.r for rank r. */
const char *tol_checkpoint_path(const usm_tolerance *t, char *buf, size_t len);

#endif /* USM_TOLERANCE_CHECKPOINT_H */
