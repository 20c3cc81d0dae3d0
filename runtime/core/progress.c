/* The rate limiter behind usm_progress. */
#define _POSIX_C_SOURCE 200809L
#include "progress.h"

#include <string.h>
#include <time.h>

/* A terminal line redrawn faster than this only costs time. */
#define PROGRESS_INTERVAL 0.1

static double mono(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void report(progress_meter *m)
{
    m->last = mono();
    m->shown = m->done;
    m->cb.fn(m->cb.ctx, m->done, m->total, m->what);
}

void progress_start(progress_meter *m, const usm_progress *cb, long total, long done0,
                    const char *what)
{
    memset(m, 0, sizeof *m);
    if (cb)
        m->cb = *cb;
    m->total = total;
    m->done = done0 < total ? done0 : total;
    m->what = what;
    m->shown = -1;
    if (m->cb.fn)
        report(m);
}

void progress_add(progress_meter *m, long n)
{
    m->done += n;
    if (m->done > m->total)
        m->done = m->total;
    if (!m->cb.fn || m->done == m->shown)
        return;
    if (m->done == m->total || mono() - m->last >= PROGRESS_INTERVAL)
        report(m);
}

void progress_extend(progress_meter *m, long n)
{
    m->total += n;
}

void progress_finish(progress_meter *m)
{
    m->done = m->total;
    if (m->cb.fn && m->done != m->shown)
        report(m);
}
