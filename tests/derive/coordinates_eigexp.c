/* A measurement of the coordinates (not a ctest): the multipliers of the constant
   linearisation of 3dof_twist_integrated at the paper's point, in double, as
   eig(exp(T G)) (GSL exponential_ss) and as exp(T eig(G)), G in the generated
   tangent-map coordinates.  Compare with the 50-digit reference of
   tests/derive/coordinates_study.py.  Build and run from the tree's root:
     gcc -O2 -o /tmp/eigexp tests/derive/coordinates_eigexp.c -Igenerated -Iruntime/include \
         -Lbuild -lusm -lgsl -lgslcblas -lm -Wl,-rpath,$PWD/build
     /tmp/eigexp THETA ALPHA BETA     (from usm steady --variant twist_integrated --json) */
#include <stdio.h>
#include <stdlib.h>
#include <math.h>
#include <complex.h>
#include <gsl/gsl_eigen.h>
#include <gsl/gsl_linalg.h>
#include <gsl/gsl_permutation.h>
#include "usm/usm.h"
#include "usm_3dof_twist_integrated.h"
#define N 7
static void inv(double *A, double *Ai) {
    gsl_matrix_view a = gsl_matrix_view_array(A, N, N), ai = gsl_matrix_view_array(Ai, N, N);
    gsl_permutation *p = gsl_permutation_alloc(N); int s;
    gsl_linalg_LU_decomp(&a.matrix, p, &s); gsl_linalg_LU_invert(&a.matrix, p, &ai.matrix);
    gsl_permutation_free(p);
}
static void mul(const double *A, const double *B, double *C) {
    for (int i = 0; i < N; ++i) for (int j = 0; j < N; ++j) { double s = 0; for (int k = 0; k < N; ++k) s += A[i*N+k]*B[k*N+j]; C[i*N+j] = s; }
}
int main(int argc, char **argv) {
    usm_params p; usm_params_default(&p);
    double u[2] = {atof(argv[1]), atof(argv[2])}, beta = atof(argv[3]);
    double orb[2*N], M[N*N], Jf[N*N], Jm[N*N], Mi[N*N], A[N*N], T[N*N], Ti[N*N], W[N*N], G[N*N], E[N*N];
    usm_3dof_twist_integrated_steady_state(u, beta, 0.0, &p, orb);
    usm_3dof_twist_integrated_mass(orb, &p, M);
    usm_3dof_twist_integrated_jac_rhs(orb, 0.0, &p, Jf);
    usm_3dof_twist_integrated_jac_mass(orb, orb + N, &p, Jm);
    for (int k = 0; k < N*N; ++k) Jf[k] -= Jm[k];
    inv(M, Mi); mul(Mi, Jf, A);
    usm_3dof_twist_integrated_tangent_map(orb, &p, T);
    double Tc[N*N]; for (int k = 0; k < N*N; ++k) Tc[k] = T[k];
    inv(Tc, Ti); mul(T, A, W); mul(W, Ti, G);
    double per = 1.0 / p.f;
    gsl_eigen_nonsymm_workspace *ws = gsl_eigen_nonsymm_alloc(N);
    gsl_eigen_nonsymm_params(0, 1, ws);
    gsl_vector_complex *ev = gsl_vector_complex_alloc(N);
    double Gc[N*N]; for (int k = 0; k < N*N; ++k) Gc[k] = G[k];
    gsl_matrix_view gv = gsl_matrix_view_array(Gc, N, N);
    gsl_eigen_nonsymm(&gv.matrix, ev, ws);
    printf("exp(T eig G):\n");
    for (int i = 0; i < N; ++i) { gsl_complex z = gsl_vector_complex_get(ev, i);
        double complex m = cexp(per * (GSL_REAL(z) + I * GSL_IMAG(z)));
        printf("%.17g %.17g\n", creal(m), cimag(m)); }
    for (int k = 0; k < N*N; ++k) W[k] = per * G[k];
    gsl_matrix_view wv = gsl_matrix_view_array(W, N, N), evw = gsl_matrix_view_array(E, N, N);
    gsl_linalg_exponential_ss(&wv.matrix, &evw.matrix, GSL_PREC_DOUBLE);
    gsl_eigen_nonsymm(&evw.matrix, ev, ws);
    printf("eig(exp(T G)) (GSL exponential_ss):\n");
    for (int i = 0; i < N; ++i) { gsl_complex z = gsl_vector_complex_get(ev, i); printf("%.17g %.17g\n", GSL_REAL(z), GSL_IMAG(z)); }
    return 0;
}
