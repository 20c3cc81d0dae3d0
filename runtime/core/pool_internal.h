/* pool_internal.h: the one worker pool of libusm (sweep multipliers, maps).
 * Not installed; not part of the API.
 *
 * pool_run calls task(ctx, state, i) for every i in [0, n) on up to `threads`
 * threads, the calling thread being one of them; each thread has its own
 * state (from state_alloc; the solver objects are not thread-safe, the
 * generated kernels are pure).  Indices are handed out in increasing order
 * from a shared counter.  A task returning non-zero stops the handing out;
 * done (optional) is called under the pool's lock after each task, so that
 * progress callbacks are never called twice at once.
 */
#ifndef USM_POOL_INTERNAL_H
#define USM_POOL_INTERNAL_H

#include <stddef.h>

#include "usm.h"

/* More worker threads than this would only contend for the cores. */
#define POOL_MAX_THREADS 64

typedef struct pool_job {
    size_t n;
    int threads;                            /* 1 .. POOL_MAX_THREADS */
    void *ctx;
    void *(*state_alloc)(void *ctx);        /* NULL: out of memory */
    void (*state_free)(void *state);
    int (*task)(void *ctx, void *state, size_t i); /* 0, or a status that stops the pool */
    void (*done)(void *ctx, size_t i);      /* NULL allowed */
} pool_job;

/* USM_OK, the first non-zero status of a task, or USM_EFAILED (out of memory,
 * no mutex) with msg. */
int pool_run(const pool_job *job, char msg[USM_MSG_LEN]);

#endif /* USM_POOL_INTERNAL_H */
