/* sweep_sink.h: what the parts of a sweep report, and how they name it.  Not
 * installed; not part of the API.
 *
 * The calls go one way: sweep.c (API, options, grid, results, order of the
 * work) calls sweep_branch.c (pseudo-arclength continuation and the events on
 * the branch) and sweep_stability.c (Floquet multipliers on the worker pool,
 * stability changes); those two know nothing of usm_sweep and report what they
 * find through a sink (a struct of callbacks) that sweep.c provides.
 */
#ifndef USM_SWEEP_SINK_H
#define USM_SWEEP_SINK_H

#include "core/pool_internal.h"
#include "usm_sweep.h"

/* More grid points than this are a typing error, not a request. */
#define SWEEP_MAX_POINTS 1000000

/* More worker threads than this would only contend for the cores. */
#define SWEEP_MAX_THREADS POOL_MAX_THREADS

/* Unknowns of the continuation: u (nu of them) and the parameter. */
#define SWEEP_MAX_N (USM_MAX_NU + 1)

/* Where the parts report what they find. */
typedef struct sweep_sink {
    void *ctx;
    /* Grid point i settled: sol the branch's root there (NULL: none, error
     * says why), roots the number of stationary solutions at its value.  May
     * be called again for the same i with a better result. */
    void (*point)(void *ctx, size_t i, const usm_steady_solution *sol, int roots,
                  const char *error);
    /* One event (copied by the callee).  0, or -1 when out of memory. */
    int (*event)(void *ctx, const usm_sweep_event *e);
    /* Fraction [0, 1] of the Floquet phase done. */
    void (*progress)(void *ctx, double fraction);
} sweep_sink;

/* "T = 0.0076 N m" style text of a parameter value, for messages (into buf,
 * which is returned). */
const char *sweep_value_text(const usm_param_info *info, double value, char buf[64]);

#endif /* USM_SWEEP_SINK_H */
