/* AUTO-07p user file: the 3-DOF paper model's stationary load branch, the
 * problem bench/bench_cont follows (T = 0 to the tilt's zero).
 *
 * The unknowns u = (theta, alpha), PAR(1) = T [N m]; func calls the generated
 * kernels (generated/usm_3dof.c): the stationary residual, its Jacobian and
 * its column of the parameter Jacobian, so AUTO and usm evaluate the same
 * equations at the same cost.  The start at T = 0 is usm's stationary root
 * (usm_steady_solve, once, outside the timed points).
 *
 * pvls runs once per continuation point; it records the process CPU time at
 * the first and the last point, and the line printed at exit gives the CPU
 * per point between them (AUTO's start-up and output files excluded).
 *
 * Built and run only by bench/auto/run.sh: AUTO-07p is not a dependency of
 * usm and none of this is part of the build or of ctest. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include <auto_f2c.h>

#include "usm.h"
#include "usm_3dof.h"
#include "usm_contracts.h"

static usm_params P;
static int ready;
static long npoints;
static double cpu_first, cpu_last;

static double cpu_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void report(void)
{
    if (npoints > 1)
        fprintf(stderr, "auto-07p: %ld points, %.3f ms CPU from the first to the last, "
                        "%.2f us per point\n",
                npoints, (cpu_last - cpu_first) * 1e3,
                (cpu_last - cpu_first) / (double)(npoints - 1) * 1e6);
}

static void setup(void)
{
    if (ready)
        return;
    usm_params_default(&P);
    P.T = 0.0;
    ready = 1;
    atexit(report);
}

int func(integer ndim, const doublereal *u, const integer *icp, const doublereal *par,
         integer ijac, doublereal *f, doublereal *dfdu, doublereal *dfdp)
{
    double J[4], Jp[2 * USM_NPARAMS];
    (void)icp;
    setup();
    P.T = par[0];
    usm_3dof_steady_residual(u, &P, f);
    if (ijac == 0)
        return 0;
    usm_3dof_steady_jacobian(u, &P, J);
    for (int i = 0; i < ndim; ++i)
        for (int j = 0; j < ndim; ++j)
            dfdu[i + j * ndim] = J[i * ndim + j]; /* AUTO's arrays are column-major */
    if (ijac == 1)
        return 0;
    usm_3dof_steady_jacobian_params(u, &P, Jp);
    for (int i = 0; i < ndim; ++i)
        dfdp[i + 0 * ndim] = Jp[i * USM_NPARAMS + USM_P_T];
    return 0;
}

int stpnt(integer ndim, doublereal t, doublereal *u, doublereal *par)
{
    (void)t;
    setup();
    usm_steady *s = usm_steady_alloc(usm_model_find("3dof"));
    if (!s || usm_steady_solve(s, &P, NULL) != USM_OK) {
        fprintf(stderr, "usm3dof: no stationary solution at T = 0\n");
        exit(1);
    }
    for (int i = 0; i < ndim; ++i)
        u[i] = usm_steady_root(s, 0)->u[i];
    usm_steady_free(s);
    par[0] = 0.0;
    return 0;
}

int pvls(integer ndim, const doublereal *u, doublereal *par)
{
    (void)ndim;
    /* PAR(2) = theta: AUTO stops where it vanishes (UZSTOP) */
    par[1] = u[0];
    const double now = cpu_s();
    if (npoints++ == 0)
        cpu_first = now;
    cpu_last = now;
    return 0;
}

int bcnd(integer ndim, const doublereal *par, const integer *icp, integer nbc,
         const doublereal *u0, const doublereal *u1, integer ijac, doublereal *fb,
         doublereal *dbc)
{
    return 0;
}

int icnd(integer ndim, const doublereal *par, const integer *icp, integer nint,
         const doublereal *u, const doublereal *uold, const doublereal *udot,
         const doublereal *upold, integer ijac, doublereal *fi, doublereal *dint)
{
    return 0;
}

int fopt(integer ndim, const doublereal *u, const integer *icp, const doublereal *par,
         integer ijac, doublereal *fs, doublereal *dfdu, doublereal *dfdp)
{
    return 0;
}
