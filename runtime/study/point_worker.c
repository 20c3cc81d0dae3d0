/* The state of a point-evaluating worker (point_worker.h). */
#include <stdlib.h>

#include "point_worker.h"

point_worker *point_worker_alloc(const usm_model *m)
{
    point_worker *w = calloc(1, sizeof *w);
    if (!w)
        return NULL;
    w->steady = usm_steady_alloc(m);
    w->floquet = usm_floquet_alloc(m);
    if (!w->steady || !w->floquet) {
        point_worker_free(w);
        return NULL;
    }
    return w;
}

void point_worker_free(void *state)
{
    point_worker *w = state;
    if (!w)
        return;
    usm_steady_free(w->steady);
    usm_floquet_free(w->floquet);
    free(w);
}
