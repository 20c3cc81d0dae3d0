/* tolerance_io.h: the checkpoint of a tolerance study (tolerance_io.c).  Not
 * installed; not part of the API. */
#ifndef USM_TOLERANCE_IO_H
#define USM_TOLERANCE_IO_H

#include "tolerance_rows.h"

/* Read / write the checkpoint file opt.checkpoint (tolerance_io.c). */
int tol_checkpoint_load(usm_tolerance *t);
int tol_checkpoint_write(usm_tolerance *t);

#endif /* USM_TOLERANCE_IO_H */
