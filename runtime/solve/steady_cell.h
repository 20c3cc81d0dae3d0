/* steady_cell.h: one cell of the stationary search (solve/steady.c), for a
 * continuation that knows where a root is but wants it as the full search
 * gives it.  Internal; not installed. */
#ifndef USM_STEADY_CELL_H
#define USM_STEADY_CELL_H

#include "usm.h"

/* The roots the full search (usm_steady_solve at p, opt) finds by the sign
 * change of its tilt function in the grid cell holding the tilt u[0], bit for
 * bit, in s (usm_steady_count, usm_steady_root).  USM_OK; USM_ENOSOLUTION
 * where that cell shows no sign change (a root near a fold, found by the
 * search's other rule) or nothing converged; USM_EINPUT as usm_steady_solve. */
int usm_steady_solve_cell(usm_steady *s, const usm_params *p, const usm_steady_options *opt,
                          const double *u);

#endif /* USM_STEADY_CELL_H */
