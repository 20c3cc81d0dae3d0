/* The state of a point-evaluating worker (point_worker.h). */
#include <stdio.h>
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

void point_op_classify(usm_point_op *op, int orc, const usm_op_result *res, const usm_steady *s,
                       const usm_floquet_result *fl, const usm_floquet_result *root_floquet)
{
    op->index = -1;
    op->reason = res->reason;
    op->starts_from_rest = res->starts_from_rest;
    op->simulated = res->simulated;
    snprintf(op->message, USM_MSG_LEN, "%s", res->message);
    if (orc != USM_OK)
        op->cls = USM_POINT_OP_UNKNOWN;
    else if (res->index >= 0) {
        op->cls = USM_POINT_OP_STABLE;
        op->index = res->index;
        op->sol = *usm_steady_root(s, (size_t)res->index);
        op->floquet = fl ? fl[res->index] : *root_floquet;
    } else if (res->reason == USM_OP_NO_STABLE_ROOT)
        op->cls = USM_POINT_OP_NO_STABLE_ROOT;
    else if (res->reason == USM_OP_DOES_NOT_START)
        op->cls = USM_POINT_OP_DOES_NOT_START;
    else
        op->cls = USM_POINT_OP_UNKNOWN;
}
