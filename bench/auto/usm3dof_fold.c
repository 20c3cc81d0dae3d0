/* AUTO-07p user file: the fold of the 3-DOF paper model's stationary
 * solution in (f, m0), the reference for usm's envelope fold curve.
 *
 * The unknowns u = (theta, alpha); PAR(1) = f [Hz], PAR(2) = m0 [N m]; PAR(3)
 * = theta is set in pvls so that AUTO can stop on it.  func calls the
 * generated kernels (generated/usm_3dof.c): the stationary residual, its
 * Jacobian and the columns f and m0 of the parameter Jacobian, the same
 * equations usm continues.  The start (the "true fold" problem of
 * docs/sweep.md: m0 = 50 N m, below the fold's frequency) is usm's
 * stationary root with the tilt nearest 0.37 rad searched up to 1 rad;
 * everything after it is AUTO's: the branch in f, its limit point, and the
 * limit point continued in (f, m0) with its cusp.
 *
 * Built and run only by bench/auto/reference.sh: AUTO-07p is not a
 * dependency of usm and none of this is part of the build or of ctest. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include <auto_f2c.h>

#include "usm.h"
#include "usm_3dof.h"
#include "usm_contracts.h"

static usm_params P;
static int ready;

static void setup(void)
{
    if (ready)
        return;
    usm_params_default(&P);
    ready = 1;
}

int func(integer ndim, const doublereal *u, const integer *icp, const doublereal *par,
         integer ijac, doublereal *f, doublereal *dfdu, doublereal *dfdp)
{
    double J[4], Jp[2 * USM_NPARAMS];
    (void)icp;
    setup();
    P.f = par[0];
    P.m0 = par[1];
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
    for (int i = 0; i < ndim; ++i) {
        dfdp[i + 0 * ndim] = Jp[i * USM_NPARAMS + USM_P_f];
        dfdp[i + 1 * ndim] = Jp[i * USM_NPARAMS + USM_P_m0];
    }
    return 0;
}

int stpnt(integer ndim, doublereal t, doublereal *u, doublereal *par)
{
    (void)t;
    setup();
    P.m0 = 50.0;
    P.f = 32000.0;
    usm_steady_options o;
    usm_steady_options_default(&o);
    o.theta_max = 1.0;
    usm_steady *s = usm_steady_alloc(usm_model_find("3dof"));
    if (!s || usm_steady_solve(s, &P, &o) != USM_OK) {
        fprintf(stderr, "usm3dof_fold: no stationary solution at the start\n");
        exit(1);
    }
    size_t best = 0;
    for (size_t k = 1; k < usm_steady_count(s); ++k)
        if (fabs(usm_steady_root(s, k)->u[0] - 0.37) < fabs(usm_steady_root(s, best)->u[0] - 0.37))
            best = k;
    for (int i = 0; i < ndim; ++i)
        u[i] = usm_steady_root(s, best)->u[i];
    usm_steady_free(s);
    par[0] = P.f;
    par[1] = P.m0;
    par[2] = u[0];
    return 0;
}

int pvls(integer ndim, const doublereal *u, doublereal *par)
{
    (void)ndim;
    par[2] = u[0];
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
