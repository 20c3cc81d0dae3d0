/* progress.h: the rate limiter behind usm_progress (usm_progress.h).
 * Not installed.  The study calls progress_add from one thread at a time
 * (its own, or under the worker pool's lock). */
#ifndef USM_CORE_PROGRESS_H
#define USM_CORE_PROGRESS_H

#include "usm_progress.h"

typedef struct progress_meter {
    usm_progress cb;
    long done, total;
    const char *what;
    double last;  /* monotonic seconds of the last call */
    long shown;   /* done as last reported */
} progress_meter;

/* Start at done0 of total and report it (when cb is non-NULL and has fn). */
void progress_start(progress_meter *m, const usm_progress *cb, long total, long done0,
                    const char *what);
/* n more units done; a call when 0.1 s passed since the last one, or at total. */
void progress_add(progress_meter *m, long n);
/* n more units planned (a search that starts again); no call. */
void progress_extend(progress_meter *m, long n);
/* The work ended before its planned total: done = total, reported. */
void progress_finish(progress_meter *m);

#endif /* USM_CORE_PROGRESS_H */
