/* point_worker.h: the state of a worker that evaluates parameter points (a
 * stationary solver and a Floquet solver of one model), for the worker pool
 * of the map and of the sweep's operating-point pass.  Not installed; not
 * part of the API. */
#ifndef USM_POINT_WORKER_H
#define USM_POINT_WORKER_H

#include "usm.h"
#include "usm_map.h"

typedef struct point_worker {
    usm_steady *steady;
    usm_floquet *floquet;
} point_worker;

/* A worker for model m, or NULL when out of memory. */
point_worker *point_worker_alloc(const usm_model *m);
/* Free a point_worker (the pool's state_free); NULL is allowed. */
void point_worker_free(void *state);

/* The operating point's class from usm_operating_point's return code orc and
 * result res among the roots of s, whose multipliers are fl (one per root, or
 * NULL when only root_floquet, the multipliers of the root res names, is at
 * hand): the map and the sweep's one-root reuse say the same thing of a point.
 * Fills every field of op but stable_roots. */
void point_op_classify(usm_point_op *op, int orc, const usm_op_result *res, const usm_steady *s,
                       const usm_floquet_result *fl, const usm_floquet_result *root_floquet);

#endif /* USM_POINT_WORKER_H */
