/* tolerance_io.h: the checkpoint of a tolerance study (tolerance_io.c).  Not
 * installed; not part of the API. */
#ifndef USM_TOLERANCE_IO_H
#define USM_TOLERANCE_IO_H

#include "tolerance_rows.h"

/* Read / write the checkpoint file opt.checkpoint (tolerance_io.c). */
int tol_checkpoint_load(usm_tolerance *t);
int tol_checkpoint_write(usm_tolerance *t);

/* This rank's checkpoint file: FILE for rank 0, FILE.r for rank r. */
const char *tol_checkpoint_path(const usm_tolerance *t, char *buf, size_t len);

#endif /* USM_TOLERANCE_IO_H */
