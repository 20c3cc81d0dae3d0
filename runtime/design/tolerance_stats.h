/* tolerance_stats.h: the statistics of a tolerance study (tolerance_stats.c).
 * Not installed; not part of the API. */
#ifndef USM_TOLERANCE_STATS_H
#define USM_TOLERANCE_STATS_H

#include "tolerance_comm.h"
#include "tolerance_rows.h"

/* Counts, yield, quantiles and influence from the rows of every rank of c
 * (tolerance_stats.c; a collective: every rank calls it and gets the
 * result).  USM_OK or USM_EFAILED with t->msg. */
int tol_finish(usm_tolerance *t, const tol_comm *c);

#endif /* USM_TOLERANCE_STATS_H */
