/* cvodes.h: the one set-up of a CVODES integrator in libusm (internal).
 *
 * Every solver that integrates with CVODES (solve/floquet.c, periodic.c,
 * hybrid.c, simulate.c) creates its integrator here: the context, the state
 * vector, the nonlinear solver (fixed-point iteration for Adams, Newton with a
 * dense LU for BDF), the initialisation, tolerances, user data, step limit,
 * quadratures and root functions, each call checked as in SUNDIALS' examples.
 * What differs from solver to solver is a field of usm_cvodes_spec or a
 * follow-up call checked by usm_cvodes_check.  CVODES never prints: its
 * messages are kept in the integrator (see usm_cvodes.cvmsg) and reach the
 * owner's message through usm_cvodes_fail.
 */
#ifndef USM_CVODES_H
#define USM_CVODES_H

#include <cvodes/cvodes.h>
#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#include "usm.h"

typedef struct usm_cvodes {
    SUNContext ctx;       /* created by the first usm_cvodes_init, kept until usm_cvodes_free */
    int ctx_borrowed;     /* ctx belongs to another integrator (usm_cvodes_share) */
    void *mem;            /* CVODES' memory, NULL before usm_cvodes_init */
    N_Vector y;           /* the state */
    N_Vector atol;        /* absolute tolerances, for CVodeSVtolerances */
    N_Vector q;           /* quadratures, NULL without */
    SUNMatrix A;          /* BDF: the Newton matrix */
    SUNLinearSolver LS;   /* BDF: its dense LU */
    SUNNonlinearSolver NLS; /* Adams: fixed-point iteration */
    char *msg;            /* the owner's message (USM_MSG_LEN), written on failure */
    char cvmsg[USM_MSG_LEN]; /* CVODES' last message, "" when none */
} usm_cvodes;

typedef struct usm_cvodes_spec {
    int lmm;              /* CV_ADAMS (fixed-point iteration) or CV_BDF (Newton, dense LU) */
    sunindextype n;       /* state length */
    double t0;
    const double *y0;     /* the start state; NULL: zeros (for a later CVodeReInit) */
    CVRhsFn rhs;
    CVLsJacFn jac;        /* BDF: the Jacobian; NULL: CVODES' difference quotients */
    void *data;           /* user data of every function */
    long max_steps;
    /* tolerances: rtol > 0 sets them now, else they are the caller's (after a
     * CVodeReInit); with ewt the error weights, else atol_v (n values) when
     * not NULL, else the scalar atol */
    double rtol, atol;
    const double *atol_v;
    CVEwtFn ewt;
    double t_stop;        /* > t0: CVodeSetStopTime */
    int nq;               /* quadratures: their number, function and start */
    CVQuadRhsFn quad;
    const double *q0;
    int nroots;           /* root functions: their number, function, directions (NULL: both) */
    CVRootFn roots;
    const int *root_dir;
} usm_cvodes_spec;

/* The context of `from` for c too (before c's first usm_cvodes_init): one
 * context for the integrators of one owner. */
void usm_cvodes_share(usm_cvodes *c, const usm_cvodes *from);

/* A new integrator in c as spec says (an earlier one is freed, the context
 * kept); failures are written to msg (USM_MSG_LEN), which later failures of
 * usm_cvodes_fail use too.  USM_OK or USM_EFAILED. */
int usm_cvodes_init(usm_cvodes *c, const usm_cvodes_spec *spec, char *msg);

/* USM_OK when flag is CV_SUCCESS (CVLS_SUCCESS), else usm_cvodes_fail(c, call, flag). */
int usm_cvodes_check(usm_cvodes *c, const char *call, int flag);

/* "CVODES <call> failed: <flag name> -- <CVODES' message>" into the owner's
 * message; USM_EFAILED. */
int usm_cvodes_fail(usm_cvodes *c, const char *call, int flag);

/* The integrator freed, the context kept (c can be initialised again). */
void usm_cvodes_release(usm_cvodes *c);

/* The integrator and its context freed; c is all zeros again. */
void usm_cvodes_free(usm_cvodes *c);

#endif /* USM_CVODES_H */
