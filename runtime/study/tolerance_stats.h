/* tolerance_stats.h: the statistics of a tolerance study (tolerance_stats.c).
 * Not installed; not part of the API. */
#ifndef USM_TOLERANCE_STATS_H
#define USM_TOLERANCE_STATS_H

#include "tolerance_rows.h"

/* Counts, yield, quantiles and influence from the rows (tolerance_stats.c). */
int tol_finish(usm_tolerance *t);

#endif /* USM_TOLERANCE_STATS_H */
