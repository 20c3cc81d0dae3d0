/* sweep_stability.h: the multipliers along a sweep and its stability changes
 * (sweep_stability.c).  Not installed; not part of the API. */
#ifndef USM_SWEEP_STABILITY_H
#define USM_SWEEP_STABILITY_H

#include "sweep_sink.h"

/* sweep_stability.c: the multipliers of every converged point of pts (into
 * pts[i].floquet / floquet_error, on opt->threads workers), then the
 * stability changes between neighbouring points as events.  USM_OK or
 * USM_EFAILED with msg. */
int sweep_floquet_points(const usm_model *m, const usm_params *p, const usm_sweep_options *opt,
                         usm_sweep_point *pts, size_t n, const sweep_sink *sink,
                         char msg[USM_MSG_LEN]);
int sweep_stability_events(const usm_model *m, const usm_params *p,
                           const usm_sweep_options *opt, const usm_sweep_point *pts, size_t n,
                           const sweep_sink *sink, char msg[USM_MSG_LEN]);

#endif /* USM_SWEEP_STABILITY_H */
