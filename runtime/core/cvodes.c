/* cvodes.c: the one set-up of a CVODES integrator (core/cvodes.h). */
#include "core/cvodes.h"

#include <stdio.h>
#include <string.h>

#include "core/cvode_msg.h"

/* The library never prints: CVODES' message is kept for the owner's. */
static void keep_message(int code, const char *module, const char *function, char *text,
                         void *data)
{
    usm_cvodes *c = data;
    (void)code;
    (void)module;
    snprintf(c->cvmsg, sizeof c->cvmsg, "%s: %s", function, text);
}

int usm_cvodes_fail(usm_cvodes *c, const char *call, int flag)
{
    char name[32];
    if (c->msg)
        snprintf(c->msg, USM_MSG_LEN, "CVODES %s failed: %s%s%.150s", call,
                 usm_cvode_flag_name(flag, name, sizeof name), c->cvmsg[0] ? " -- " : "",
                 c->cvmsg);
    return USM_EFAILED;
}

int usm_cvodes_check(usm_cvodes *c, const char *call, int flag)
{
    /* CV_SUCCESS and CVLS_SUCCESS are both 0 */
    return flag == CV_SUCCESS ? USM_OK : usm_cvodes_fail(c, call, flag);
}

static int out_of_memory(usm_cvodes *c, const char *what)
{
    if (c->msg)
        snprintf(c->msg, USM_MSG_LEN, "CVODES: cannot create %s (out of memory)", what);
    return USM_EFAILED;
}

void usm_cvodes_share(usm_cvodes *c, const usm_cvodes *from)
{
    c->ctx = from->ctx;
    c->ctx_borrowed = 1;
}

void usm_cvodes_release(usm_cvodes *c)
{
    if (c->mem)
        CVodeFree(&c->mem);
    if (c->NLS)
        SUNNonlinSolFree(c->NLS);
    if (c->LS)
        SUNLinSolFree(c->LS);
    if (c->A)
        SUNMatDestroy(c->A);
    if (c->y)
        N_VDestroy(c->y);
    if (c->atol)
        N_VDestroy(c->atol);
    if (c->q)
        N_VDestroy(c->q);
    c->mem = NULL;
    c->NLS = NULL;
    c->LS = NULL;
    c->A = NULL;
    c->y = c->atol = c->q = NULL;
}

void usm_cvodes_free(usm_cvodes *c)
{
    usm_cvodes_release(c);
    if (c->ctx && !c->ctx_borrowed)
        SUNContext_Free(&c->ctx);
    memset(c, 0, sizeof *c);
}

int usm_cvodes_init(usm_cvodes *c, const usm_cvodes_spec *s, char *msg)
{
    const sunindextype n = s->n;
    int rc;
    usm_cvodes_release(c);
    c->msg = msg;
    c->cvmsg[0] = '\0';
    if (!c->ctx && SUNContext_Create(NULL, &c->ctx) != 0) {
        c->ctx = NULL;
        return out_of_memory(c, "the context");
    }
    if (!(c->y = N_VNew_Serial(n, c->ctx)) || !(c->atol = N_VNew_Serial(n, c->ctx)))
        return out_of_memory(c, "the state vector");
    if (s->y0)
        memcpy(N_VGetArrayPointer(c->y), s->y0, sizeof(double) * (size_t)n);
    else
        N_VConst(0.0, c->y);
    if (s->atol_v)
        memcpy(N_VGetArrayPointer(c->atol), s->atol_v, sizeof(double) * (size_t)n);
    else
        N_VConst(0.0, c->atol);
    if (!(c->mem = CVodeCreate(s->lmm, c->ctx)))
        return out_of_memory(c, "the integrator");
    if ((rc = usm_cvodes_check(c, "CVodeSetErrHandlerFn",
                               CVodeSetErrHandlerFn(c->mem, keep_message, c))) != USM_OK)
        return rc;
    if ((rc = usm_cvodes_check(c, "CVodeInit", CVodeInit(c->mem, s->rhs, s->t0, c->y))) != USM_OK)
        return rc;
    if ((rc = usm_cvodes_check(c, "CVodeSetUserData", CVodeSetUserData(c->mem, s->data))) !=
        USM_OK)
        return rc;
    if (s->rtol > 0) {
        if (s->ewt)
            rc = usm_cvodes_check(c, "CVodeWFtolerances", CVodeWFtolerances(c->mem, s->ewt));
        else if (s->atol_v)
            rc = usm_cvodes_check(c, "CVodeSVtolerances",
                                  CVodeSVtolerances(c->mem, s->rtol, c->atol));
        else
            rc = usm_cvodes_check(c, "CVodeSStolerances",
                                  CVodeSStolerances(c->mem, s->rtol, s->atol));
        if (rc != USM_OK)
            return rc;
    }
    if (s->lmm == CV_BDF) {
        if (!(c->A = SUNDenseMatrix(n, n, c->ctx)) || !(c->LS = SUNLinSol_Dense(c->y, c->A, c->ctx)))
            return out_of_memory(c, "the dense linear solver");
        if ((rc = usm_cvodes_check(c, "CVodeSetLinearSolver",
                                   CVodeSetLinearSolver(c->mem, c->LS, c->A))) != USM_OK)
            return rc;
        if (s->jac && (rc = usm_cvodes_check(c, "CVodeSetJacFn", CVodeSetJacFn(c->mem, s->jac))) !=
                          USM_OK)
            return rc;
    } else {
        /* Adams on these non-stiff problems: fixed-point iteration, no Jacobian */
        if (!(c->NLS = SUNNonlinSol_FixedPoint(c->y, 0, c->ctx)))
            return out_of_memory(c, "the fixed-point solver");
        if ((rc = usm_cvodes_check(c, "CVodeSetNonlinearSolver",
                                   CVodeSetNonlinearSolver(c->mem, c->NLS))) != USM_OK)
            return rc;
    }
    if ((rc = usm_cvodes_check(c, "CVodeSetMaxNumSteps",
                               CVodeSetMaxNumSteps(c->mem, s->max_steps))) != USM_OK)
        return rc;
    if (s->t_stop > s->t0 &&
        (rc = usm_cvodes_check(c, "CVodeSetStopTime", CVodeSetStopTime(c->mem, s->t_stop))) !=
            USM_OK)
        return rc;
    if (s->nq > 0) {
        if (!(c->q = N_VNew_Serial(s->nq, c->ctx)))
            return out_of_memory(c, "the quadratures");
        memcpy(N_VGetArrayPointer(c->q), s->q0, sizeof(double) * (size_t)s->nq);
        if ((rc = usm_cvodes_check(c, "CVodeQuadInit", CVodeQuadInit(c->mem, s->quad, c->q))) !=
            USM_OK)
            return rc;
    }
    if (s->nroots > 0) {
        if ((rc = usm_cvodes_check(c, "CVodeRootInit",
                                   CVodeRootInit(c->mem, s->nroots, s->roots))) != USM_OK)
            return rc;
        if (s->root_dir && (rc = usm_cvodes_check(c, "CVodeSetRootDirection",
                                                  CVodeSetRootDirection(c->mem, (int *)s->root_dir))) !=
                               USM_OK)
            return rc;
        if ((rc = usm_cvodes_check(c, "CVodeSetNoInactiveRootWarn",
                                   CVodeSetNoInactiveRootWarn(c->mem))) != USM_OK)
            return rc;
    }
    return USM_OK;
}
