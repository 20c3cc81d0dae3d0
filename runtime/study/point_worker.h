/* point_worker.h: the state of a worker that evaluates parameter points (a
 * stationary solver and a Floquet solver of one model), for the worker pool
 * of the map and of the sweep's operating-point pass.  Not installed; not
 * part of the API. */
#ifndef USM_POINT_WORKER_H
#define USM_POINT_WORKER_H

#include "usm.h"

typedef struct point_worker {
    usm_steady *steady;
    usm_floquet *floquet;
} point_worker;

/* A worker for model m, or NULL when out of memory. */
point_worker *point_worker_alloc(const usm_model *m);
/* Free a point_worker (the pool's state_free); NULL is allowed. */
void point_worker_free(void *state);

#endif /* USM_POINT_WORKER_H */
