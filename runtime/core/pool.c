/* The worker pool shared by the sweep's Floquet pass and the maps. */
#define _POSIX_C_SOURCE 200809L
#include "pool_internal.h"

#include <pthread.h>
#include <stdio.h>

typedef struct pool {
    const pool_job *job;
    pthread_mutex_t lock;
    size_t next;
    int status;
    char msg[USM_MSG_LEN];
} pool;

static void *worker(void *arg)
{
    pool *w = arg;
    const pool_job *job = w->job;
    void *state = job->state_alloc(job->ctx);
    if (!state) {
        pthread_mutex_lock(&w->lock);
        if (w->status == USM_OK) {
            w->status = USM_EFAILED;
            snprintf(w->msg, USM_MSG_LEN, "out of memory for a worker");
        }
        pthread_mutex_unlock(&w->lock);
        return NULL;
    }
    for (;;) {
        pthread_mutex_lock(&w->lock);
        const int go = w->status == USM_OK && w->next < job->n;
        const size_t i = go ? w->next++ : 0;
        pthread_mutex_unlock(&w->lock);
        if (!go)
            break;
        const int rc = job->task(job->ctx, state, i);
        pthread_mutex_lock(&w->lock);
        if (rc != 0 && w->status == USM_OK)
            w->status = rc;
        if (job->done)
            job->done(job->ctx, i);
        pthread_mutex_unlock(&w->lock);
    }
    job->state_free(state);
    return NULL;
}

int pool_run(const pool_job *job, char msg[USM_MSG_LEN])
{
    pool w;
    pthread_t tid[POOL_MAX_THREADS];
    int started = 0;
    if (job->n == 0)
        return USM_OK;
    w.job = job;
    w.next = 0;
    w.status = USM_OK;
    w.msg[0] = '\0';
    if (pthread_mutex_init(&w.lock, NULL) != 0) {
        snprintf(msg, USM_MSG_LEN, "cannot create a mutex");
        return USM_EFAILED;
    }
    int want = job->threads < 1 ? 1 : job->threads > POOL_MAX_THREADS ? POOL_MAX_THREADS
                                                                         : job->threads;
    if ((size_t)want > job->n)
        want = (int)job->n;
    /* a thread that cannot be started only costs speed: the others take its work */
    for (int k = 1; k < want; ++k)
        if (pthread_create(&tid[started], NULL, worker, &w) == 0)
            ++started;
    worker(&w);
    for (int k = 0; k < started; ++k)
        pthread_join(tid[k], NULL);
    pthread_mutex_destroy(&w.lock);
    if (w.status != USM_OK && w.msg[0])
        snprintf(msg, USM_MSG_LEN, "%s", w.msg);
    return w.status;
}
