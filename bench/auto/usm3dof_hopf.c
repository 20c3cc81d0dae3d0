/* AUTO-07p user file: the stability boundary of the 3-DOF model, variant
 * twist_integrated, in (f, T): a Hopf point of the stationary solution in
 * the frame turning with the excitation, the reference for usm's envelope
 * stability curve.
 *
 * Under the integrated twist law the linearisation about the stationary
 * orbit is constant (docs/numerics.md), G = M(xbar)^{-1} A with
 * A = df/dx - d(M v)/dx at v = xbar', and the Floquet multipliers are
 * exp(2 pi / Omega eig G): a pair crossing the unit circle is a pair of
 * eigenvalues of G crossing the imaginary axis.  AUTO continues equilibria
 * of an ODE, so the problem is posed as one whose equilibria are the
 * stationary solutions and whose Jacobian there has G's eigenvalues:
 *     u' = -c r_u(u)^{-1} r(u; f, T)  (u = (theta, alpha); the Jacobian
 *                                      there is -c I: no Hopf point of its
 *                                      own, and c = 1e4 1/s keeps it of the
 *                                      size of G's eigenvalues; -r_u' r, tried
 *                                      first, had an eigenvalue of -2e-5
 *                                      and AUTO's Hopf system diverged)
 *     y' = B(u; f, T) y               (y = 0 at every equilibrium)
 * B is G without its cyclic direction (the rotor angle phi appears in
 * neither M nor f: A's column phi vanishes and G has the eigenvalue 0 for
 * ever, which would make every equilibrium singular), in the coordinates of
 * usm's Floquet computation (runtime/solve/floquet.c): G is formed as
 * (M Ti)^{-1} (A Ti), Ti the inverse of the generated tangent map, because
 * M alone is ill-conditioned at small tilts; Gs = Ti^{-1} G Ti has the null
 * vector w = T e_phi, and B = Q2' Gs Q2 with Q2 an orthonormal basis of w's
 * complement (a Householder reflection), so eig B = eig G without the 0.
 * The Jacobian given to AUTO is exact at the equilibria (y = 0, r = 0):
 * [-c I, 0; 0, B]; its parameter columns [-c r_u^{-1} r_p; 0].  Every kernel
 * is generated (generated/usm_3dof_twist_integrated.c); the start is usm's
 * stationary root at f = 37.5 kHz, T = 2.1 mN m.
 *
 * Built and run only by bench/auto/reference.sh: AUTO-07p is not a
 * dependency of usm and none of this is part of the build or of ctest. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <auto_f2c.h>
#include <gsl/gsl_linalg.h>

#include "usm.h"
#include "usm_3dof_twist_integrated.h"
#include "usm_contracts.h"

#define NX USM_3DOF_TWIST_INTEGRATED_NX
#define NB (NX - 1)
#define PHI USM_3DOF_TWIST_INTEGRATED_X_PHI
#define RATE 1.0
/* time in units of 1/OMEGA_UNIT: B's eigenvalues of order one */
#define OMEGA_UNIT 2.5e5
/* AUTO's unknowns and parameters of order one: its difference steps are
 * 1e-7 (1 + |z|), 1 % of a tilt of 5e-5 rad in radians */
#define THETA_UNIT 1e-4 /* z[0] = theta / THETA_UNIT */
#define T_UNIT 1e-3     /* PAR(2) = T / T_UNIT (mN m) */

static usm_params P;
static int ready;

static void setup(void)
{
    if (ready)
        return;
    usm_params_default(&P);
    ready = 1;
}

/* X <- L^{-1} X for the n x n row-major L (LU with partial pivoting). */
static void solve(double *L, double *X)
{
    gsl_matrix_view Lv = gsl_matrix_view_array(L, NX, NX);
    gsl_permutation *perm = gsl_permutation_alloc(NX);
    int sgn;
    gsl_linalg_LU_decomp(&Lv.matrix, perm, &sgn);
    for (int j = 0; j < NX; ++j) {
        double col[NX];
        for (int i = 0; i < NX; ++i)
            col[i] = X[i * NX + j];
        gsl_vector_view c = gsl_vector_view_array(col, NX);
        gsl_linalg_LU_svx(&Lv.matrix, perm, &c.vector);
        for (int i = 0; i < NX; ++i)
            X[i * NX + j] = col[i];
    }
    gsl_permutation_free(perm);
}

static void matmul(const double *A, const double *B, double *C)
{
    for (int i = 0; i < NX; ++i)
        for (int j = 0; j < NX; ++j) {
            double s = 0;
            for (int k = 0; k < NX; ++k)
                s += A[i * NX + k] * B[k * NX + j];
            C[i * NX + j] = s;
        }
}

/* B (NB x NB, row-major) at the stationary unknowns u. */
static void reduced_linearisation(const double *u, double *B)
{
    double orbit[2 * NX], M[NX * NX], Jf[NX * NX], Jm[NX * NX], T[NX * NX], Ti[NX * NX];
    double W[NX * NX], Gs[NX * NX];
    usm_3dof_twist_integrated_steady_state(u, 0.0, 0.0, &P, orbit);
    const double *x = orbit + USM_3DOF_TWIST_INTEGRATED_STEADY_STATE_OUT_X;
    const double *xdot = orbit + USM_3DOF_TWIST_INTEGRATED_STEADY_STATE_OUT_XDOT;
    usm_3dof_twist_integrated_mass(x, &P, M);
    usm_3dof_twist_integrated_jac_rhs(x, 0.0, &P, Jf);
    usm_3dof_twist_integrated_jac_mass(x, xdot, &P, Jm);
    for (int k = 0; k < NX * NX; ++k)
        Jf[k] -= Jm[k];
    usm_3dof_twist_integrated_tangent_map(x, &P, T);
    /* Ti = T^{-1} */
    double Tc[NX * NX];
    memcpy(Tc, T, sizeof Tc);
    for (int i = 0; i < NX * NX; ++i)
        Ti[i] = (i / NX == i % NX);
    solve(Tc, Ti);
    matmul(M, Ti, W);
    matmul(Jf, Ti, Gs);
    solve(W, Gs); /* Gs = (M Ti)^{-1} (A Ti) */
    /* w = T e_phi, Gs's null vector; the Householder reflection H = I - 2 v v' /
     * (v' v), v = w + sign(w_0) |w| e_0, maps w to a multiple of e_0, and its
     * columns 1..NX-1 are Q2 */
    double w[NX], v[NX], nw = 0;
    for (int i = 0; i < NX; ++i) {
        w[i] = T[i * NX + PHI];
        nw += w[i] * w[i];
    }
    nw = sqrt(nw);
    for (int i = 0; i < NX; ++i)
        v[i] = w[i];
    v[0] += (w[0] >= 0 ? nw : -nw);
    double vv = 0;
    for (int i = 0; i < NX; ++i)
        vv += v[i] * v[i];
    double H[NX * NX], HG[NX * NX], HGH[NX * NX];
    for (int i = 0; i < NX; ++i)
        for (int j = 0; j < NX; ++j)
            H[i * NX + j] = (i == j) - 2 * v[i] * v[j] / vv;
    matmul(H, Gs, HG);
    matmul(HG, H, HGH);
    for (int i = 0; i < NB; ++i)
        for (int j = 0; j < NB; ++j)
            B[i * NB + j] = HGH[(i + 1) * NX + (j + 1)] / OMEGA_UNIT;
}

int func(integer ndim, const doublereal *z, const integer *icp, const doublereal *par,
         integer ijac, doublereal *f, doublereal *dfdu, doublereal *dfdp)
{
    double r[2], J[4], Jp[2 * USM_NPARAMS], B[NB * NB];
    (void)icp;
    setup();
    P.f = par[0];
    P.T = par[1] * T_UNIT;
    const double u[2] = {z[0] * THETA_UNIT, z[1]}, *y = z + 2;
    usm_3dof_twist_integrated_steady_residual(u, &P, r);
    usm_3dof_twist_integrated_steady_jacobian(u, &P, J);
    J[0 * 2 + 0] *= THETA_UNIT; /* r_z */
    J[1 * 2 + 0] *= THETA_UNIT;
    reduced_linearisation(u, B);
    const double det = J[0] * J[3] - J[1] * J[2];
    /* Ji = r_u^{-1} */
    const double Ji[4] = {J[3] / det, -J[1] / det, -J[2] / det, J[0] / det};
    for (int i = 0; i < 2; ++i)
        f[i] = -RATE * (Ji[i * 2 + 0] * r[0] + Ji[i * 2 + 1] * r[1]);
    for (int i = 0; i < NB; ++i) {
        double s = 0;
        for (int j = 0; j < NB; ++j)
            s += B[i * NB + j] * y[j];
        f[2 + i] = s;
    }
    if (ijac == 0)
        return 0;
    /* AUTO's arrays are column-major: dfdu[i + j * ndim] = df_i / dz_j */
    for (int k = 0; k < ndim * ndim; ++k)
        dfdu[k] = 0;
    for (int i = 0; i < 2; ++i)
        dfdu[i + i * ndim] = -RATE;
    for (int i = 0; i < NB; ++i)
        for (int j = 0; j < NB; ++j)
            dfdu[(2 + i) + (2 + j) * ndim] = B[i * NB + j];
    if (ijac == 1)
        return 0;
    usm_3dof_twist_integrated_steady_jacobian_params(u, &P, Jp);
    const int cols[2] = {USM_P_f, USM_P_T};
    const double unit[2] = {1.0, T_UNIT};
    for (int c = 0; c < 2; ++c) {
        for (int i = 0; i < ndim; ++i)
            dfdp[i + c * ndim] = 0;
        for (int i = 0; i < 2; ++i)
            dfdp[i + c * ndim] = -RATE * unit[c] *
                                 (Ji[i * 2 + 0] * Jp[0 * USM_NPARAMS + cols[c]] +
                                  Ji[i * 2 + 1] * Jp[1 * USM_NPARAMS + cols[c]]);
    }
    return 0;
}

int stpnt(integer ndim, doublereal t, doublereal *z, doublereal *par)
{
    (void)t;
    setup();
    P.f = 37500.0;
    P.T = 2.1e-3;
    usm_steady *s = usm_steady_alloc(usm_model_variant("3dof", "twist_integrated"));
    if (!s || usm_steady_solve(s, &P, NULL) != USM_OK) {
        fprintf(stderr, "usm3dof_hopf: no stationary solution at the start\n");
        exit(1);
    }
    for (int i = 0; i < ndim; ++i)
        z[i] = 0;
    z[0] = usm_steady_root(s, 0)->u[0] / THETA_UNIT;
    z[1] = usm_steady_root(s, 0)->u[1];
    fprintf(stderr, "usm3dof_hopf: start theta = %.6g rad, alpha = %.6g rad (%zu roots)\n",
            z[0] * THETA_UNIT, z[1], usm_steady_count(s));
    usm_steady_free(s);
    par[0] = P.f;
    par[1] = P.T / T_UNIT;
    return 0;
}

int pvls(integer ndim, const doublereal *u, doublereal *par)
{
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
