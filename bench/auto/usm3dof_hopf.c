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
 * B is G without its cyclic direction (the angle psi appears in neither M
 * nor f, as the generated model's `cyclic` says: A's column psi vanishes and
 * G has the eigenvalue 0 for ever, which would make every equilibrium
 * singular), in the coordinates of
 * usm's Floquet computation (runtime/solve/floquet.c): G is formed as
 * (M S^{-1})^{-1} (A S^{-1}), S = D^{-1} T with T the generated tangent map
 * and D a balancing, because M alone is ill-conditioned at small tilts
 * (cond ~ 1/theta^2; the tilts here are 2e-5 to 5e-5 rad).  Even so, in
 * double precision this G's eigenvalues were off by 5e-3 1/s (1.5e-7 in the
 * multipliers' modulus, 1.4e-6 relative in the curve's T: usm's multipliers,
 * which it computes in the tilt-vector coordinates regular at theta = 0,
 * and this G in long double agree that usm's T is the boundary, to 3e-15 in
 * the modulus), so G is formed in long double from a long double copy of
 * the generated kernels (reference.sh makes it); Gs = S G S^{-1} has the null
 * vector w = S e_psi, and B = Q2' Gs Q2 with Q2 an orthonormal basis of w's
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
#define RATE 1.0
/* time in units of 1/OMEGA_UNIT: B's eigenvalues of order one */
#define OMEGA_UNIT 2.5e5
/* AUTO's unknowns and parameters of order one: its difference steps are
 * 1e-7 (1 + |z|), 1 % of a tilt of 5e-5 rad in radians */
#define THETA_UNIT 1e-4 /* z[0] = theta / THETA_UNIT */
#define T_UNIT 1e-3     /* PAR(2) = T / T_UNIT (mN m) */

static usm_params P;
static int ready;
static int cyc; /* the cyclic coordinate (generated: x_i in neither M nor f) */

static void setup(void)
{
    if (ready)
        return;
    usm_params_default(&P);
    const usm_model *m = usm_model_variant("3dof", "twist_integrated");
    while (cyc < NX - 1 && !m->cyclic[cyc])
        cyc++;
    ready = 1;
}

typedef long double ld;
/* The linearisation's kernels in long double: generated/usm_3dof_twist_integrated.c
 * with every double a long double and the prefix ld_ (reference.sh makes
 * the copy with sed; <tgmath.h> picks sinl, cosl, sqrtl). */
void ld_steady_state(const ld *u, ld beta, ld t, const usm_params *p, ld *out);
void ld_mass(const ld *x, const usm_params *p, ld *out);
void ld_jac_rhs(const ld *x, ld t, const usm_params *p, ld *out);
void ld_jac_mass(const ld *x, const ld *v, const usm_params *p, ld *out);
void ld_tangent_map(const ld *x, const usm_params *p, ld *out);

/* X <- L^{-1} X (NX x NX, row-major; Gauss with partial pivoting; L is
 * overwritten) */
static void solve(ld *L, ld *X)
{
    for (int k = 0; k < NX; ++k) {
        int pr = k;
        for (int i = k + 1; i < NX; ++i)
            if (fabsl(L[i * NX + k]) > fabsl(L[pr * NX + k]))
                pr = i;
        for (int j = 0; j < NX; ++j) {
            ld t = L[k * NX + j];
            L[k * NX + j] = L[pr * NX + j];
            L[pr * NX + j] = t;
            t = X[k * NX + j];
            X[k * NX + j] = X[pr * NX + j];
            X[pr * NX + j] = t;
        }
        for (int i = k + 1; i < NX; ++i) {
            const ld m = L[i * NX + k] / L[k * NX + k];
            for (int j = 0; j < NX; ++j) {
                L[i * NX + j] -= m * L[k * NX + j];
                X[i * NX + j] -= m * X[k * NX + j];
            }
        }
    }
    for (int k = NX - 1; k >= 0; --k)
        for (int j = 0; j < NX; ++j) {
            ld sum = X[k * NX + j];
            for (int i = k + 1; i < NX; ++i)
                sum -= L[k * NX + i] * X[i * NX + j];
            X[k * NX + j] = sum / L[k * NX + k];
        }
}

static void matmul(const ld *A, const ld *B, ld *C)
{
    for (int i = 0; i < NX; ++i)
        for (int j = 0; j < NX; ++j) {
            ld sum = 0;
            for (int k = 0; k < NX; ++k)
                sum += A[i * NX + k] * B[k * NX + j];
            C[i * NX + j] = sum;
        }
}

/* B (NB x NB, row-major) at the stationary unknowns u. */
static void reduced_linearisation(const double *ud, double *B)
{
    ld u[2] = {ud[0], ud[1]}, orbit[2 * NX], M[NX * NX], Jf[NX * NX], Jm[NX * NX];
    ld T[NX * NX], Ti[NX * NX], Tc[NX * NX], W[NX * NX], Gs[NX * NX];
    ld_steady_state(u, 0.0L, 0.0L, &P, orbit);
    const ld *x = orbit + USM_3DOF_TWIST_INTEGRATED_STEADY_STATE_OUT_X;
    const ld *xdot = orbit + USM_3DOF_TWIST_INTEGRATED_STEADY_STATE_OUT_XDOT;
    ld_mass(x, &P, M);
    ld_jac_rhs(x, 0.0L, &P, Jf);
    ld_jac_mass(x, xdot, &P, Jm);
    for (int k = 0; k < NX * NX; ++k)
        Jf[k] -= Jm[k];
    ld_tangent_map(x, &P, T);
    for (int i = 0; i < NX * NX; ++i) {
        Tc[i] = T[i];
        Ti[i] = (i / NX == i % NX);
    }
    solve(Tc, Ti); /* T^{-1} */
    /* S = D^{-1} T as in usm: D balances T G T^{-1}, computed once at the
     * first point and kept (a D that changed with the point, by powers of
     * two, would make B jump under AUTO's continuation) */
    static double D[NX];
    static int have_d;
    if (!have_d) {
        double Gd[NX * NX];
        matmul(M, Ti, W);
        matmul(Jf, Ti, Gs);
        solve(W, Gs);
        for (int i = 0; i < NX * NX; ++i)
            Gd[i] = (double)Gs[i];
        gsl_matrix_view g = gsl_matrix_view_array(Gd, NX, NX);
        gsl_vector_view d = gsl_vector_view_array(D, NX);
        gsl_linalg_balance_matrix(&g.matrix, &d.vector);
        have_d = 1;
    }
    for (int i = 0; i < NX; ++i)
        for (int j = 0; j < NX; ++j)
            Ti[i * NX + j] *= D[j]; /* S^{-1} = T^{-1} D */
    matmul(M, Ti, W);
    matmul(Jf, Ti, Gs);
    solve(W, Gs); /* Gs = (M S^{-1})^{-1} (A S^{-1}) */
    /* w = S e_cyc, Gs's null vector; the Householder reflection H = I - 2 v v' /
     * (v' v), v = w + sign(w_0) |w| e_0, maps w to a multiple of e_0, and its
     * columns 1..NX-1 are Q2 */
    ld w[NX], v[NX], nw = 0, vv = 0;
    for (int i = 0; i < NX; ++i) {
        w[i] = T[i * NX + cyc] / D[i];
        nw += w[i] * w[i];
    }
    nw = sqrtl(nw);
    for (int i = 0; i < NX; ++i)
        v[i] = w[i];
    v[0] += (w[0] >= 0 ? nw : -nw);
    for (int i = 0; i < NX; ++i)
        vv += v[i] * v[i];
    ld H[NX * NX], HG[NX * NX], HGH[NX * NX];
    for (int i = 0; i < NX; ++i)
        for (int j = 0; j < NX; ++j)
            H[i * NX + j] = (i == j) - 2 * v[i] * v[j] / vv;
    matmul(H, Gs, HG);
    matmul(HG, H, HGH);
    for (int i = 0; i < NB; ++i)
        for (int j = 0; j < NB; ++j)
            B[i * NB + j] = (double)(HGH[(i + 1) * NX + (j + 1)] / OMEGA_UNIT);
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
