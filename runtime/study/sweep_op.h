/* sweep_op.h: the operating point along a sweep and where it jumps
 * (sweep_op.c).  Not installed; not part of the API. */
#ifndef USM_SWEEP_OP_H
#define USM_SWEEP_OP_H

#include "sweep_sink.h"

/* The operating point of every grid point of pts (into pts[i].op, on
 * opt->threads workers: usm_point_evaluate_op at the grid value), then the
 * operating_point_jump events between neighbouring grid points.  USM_OK, or
 * USM_EINPUT / USM_EFAILED with msg. */
int sweep_operating_points(const usm_model *m, const usm_params *p,
                           const usm_sweep_options *opt, usm_sweep_point *pts, size_t n,
                           const sweep_sink *sink, char msg[USM_MSG_LEN]);

#endif /* USM_SWEEP_OP_H */
