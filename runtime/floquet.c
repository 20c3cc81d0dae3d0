/* Floquet multipliers of a stationary solution (paper, section 4).
 *
 * Math: about the stationary orbit xbar(t) the first approximation (4.9) is
 *     M(xbar) dx' = A(t) dx,   A = df/dx - d(M v)/dx |_{v = xbar'}      (1)
 * with both Jacobians generated from the derivation.  The monodromy matrix
 * B = Phi(t0 + T) with Phi' = M^{-1} A Phi, Phi(t0) = I, T = 2 pi / Omega, and
 * the multipliers are the eigenvalues of B (GSL, balanced Hessenberg-QR).
 *
 * Two independent ways to compute B:
 *  - variational: CVODES integrates the n x n system (1) with Adams and
 *    fixed-point iteration (over one period |lambda| T < ~20: not stiff, so
 *    no n^2 x n^2 linear algebra is needed) in
 *    well-conditioned coordinates: near theta = 1e-4 the Euler-angle
 *    linearisation spans about 17 orders of magnitude and the error control
 *    of CVODES cannot resolve the physically small combinations of dphi and
 *    dpsi.  With S = D^{-1} T, where T is the generated tangent map (Euler-angle
 *    perturbations to the small-rotation vector in frame A, constant on the
 *    orbit) and D balances T G(t0) T^{-1} (GSL), Psi = S Phi S^{-1} is
 *    integrated, and B = S^{-1} Psi(t0 + T) S;
 *  - exponential: in frame A the coefficients of (1) are constant except the
 *    paper's twist term; B is the product of balanced matrix exponentials of
 *    S G S^{-1} over N sub-intervals (exponential midpoint rule, GSL's
 *    scaling-and-squaring exponential), Richardson-extrapolated from N and 2N
 *    (the rule is of second order in 1/N).
 *
 * A cyclic coordinate x_i (appearing in neither M nor f) leaves column i of B
 * equal to e_i; its multiplier is exactly 1 and it is removed from B before
 * the eigenvalue problem, then reported as such.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_blas.h>
#include <gsl/gsl_eigen.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_linalg.h>
#include <gsl/gsl_matrix.h>

#include <cvodes/cvodes.h>
#include <nvector/nvector_serial.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#include "cvode_msg.h"
#include "usm.h"

#define TWO_PI 6.283185307179586476925286766559

struct usm_floquet {
    const usm_model *m;
    int n;
    /* the orbit being linearised */
    usm_params p;
    double u[USM_MAX_NU];
    double beta;
    /* CVODES */
    SUNContext ctx;
    void *cvode;
    N_Vector y;
    SUNNonlinearSolver NLS;
    int cvode_ready;
    double t0; /* start of the period being integrated */
    /* work space */
    gsl_matrix *G, *Mx, *E, *P, *Q, *W;
    gsl_permutation *perm;
    gsl_vector *dscale;
    gsl_matrix *S, *Sinv;   /* coordinates of the variational integration */
    /* eigenproblem of B without its cyclic rows and columns */
    int nk, keep[USM_MAX_NX];
    gsl_matrix *R;
    gsl_eigen_nonsymm_workspace *eig;
    gsl_vector_complex *eval;
    char cvmsg[USM_MSG_LEN]; /* CVODES' last message (see cv_errors) */
    char msg[USM_MSG_LEN];
};

void usm_floquet_options_default(usm_floquet_options *opt)
{
    opt->method = USM_FLOQUET_VARIATIONAL;
    opt->rtol = 1e-8;
    opt->atol = 1e-12;
    opt->steps = 64;
}

const char *usm_floquet_message(const usm_floquet *f) { return f->msg; }

usm_floquet *usm_floquet_alloc(const usm_model *m)
{
    usm_floquet *f = calloc(1, sizeof *f);
    if (!f)
        return NULL;
    const size_t n = (size_t)m->nx;
    f->m = m;
    f->n = m->nx;
    f->G = gsl_matrix_alloc(n, n);
    f->Mx = gsl_matrix_alloc(n, n);
    f->E = gsl_matrix_alloc(n, n);
    f->P = gsl_matrix_alloc(n, n);
    f->Q = gsl_matrix_alloc(n, n);
    f->W = gsl_matrix_alloc(n, n);
    f->S = gsl_matrix_alloc(n, n);
    f->Sinv = gsl_matrix_alloc(n, n);
    f->perm = gsl_permutation_alloc(n);
    f->dscale = gsl_vector_alloc(n);
    for (int i = 0; i < m->nx; ++i)
        if (!m->cyclic[i])
            f->keep[f->nk++] = i;
    f->R = gsl_matrix_alloc((size_t)f->nk, (size_t)f->nk);
    f->eig = gsl_eigen_nonsymm_alloc((size_t)f->nk);
    f->eval = gsl_vector_complex_alloc((size_t)f->nk);
    if (!f->G || !f->Mx || !f->E || !f->P || !f->Q || !f->W || !f->S || !f->Sinv || !f->perm || !f->dscale ||
        !f->R || !f->eig || !f->eval || SUNContext_Create(NULL, &f->ctx) != 0) {
        usm_floquet_free(f);
        return NULL;
    }
    return f;
}

void usm_floquet_free(usm_floquet *f)
{
    if (!f)
        return;
    if (f->cvode)
        CVodeFree(&f->cvode);
    if (f->NLS)
        SUNNonlinSolFree(f->NLS);
    if (f->y)
        N_VDestroy(f->y);
    if (f->ctx)
        SUNContext_Free(&f->ctx);
    gsl_matrix_free(f->G);
    gsl_matrix_free(f->Mx);
    gsl_matrix_free(f->E);
    gsl_matrix_free(f->P);
    gsl_matrix_free(f->Q);
    gsl_matrix_free(f->W);
    gsl_matrix_free(f->S);
    gsl_matrix_free(f->Sinv);
    gsl_matrix_free(f->R);
    gsl_permutation_free(f->perm);
    gsl_vector_free(f->dscale);
    if (f->eig)
        gsl_eigen_nonsymm_free(f->eig);
    gsl_vector_complex_free(f->eval);
    free(f);
}

/* G(t) = M(xbar)^{-1} A(t), the coefficient matrix of the variational system. */
static int coefficient_matrix(usm_floquet *f, double t, gsl_matrix *G)
{
    const int n = f->n;
    double orbit[2 * USM_MAX_NX], Mbuf[USM_MAX_NX * USM_MAX_NX];
    double Jf[USM_MAX_NX * USM_MAX_NX], Jm[USM_MAX_NX * USM_MAX_NX];
    f->m->steady_state(f->u, f->beta, t, &f->p, orbit);
    const double *x = orbit, *xdot = orbit + n;
    f->m->mass(x, &f->p, Mbuf);
    f->m->jac_rhs(x, t, &f->p, Jf);
    f->m->jac_mass(x, xdot, &f->p, Jm);
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            gsl_matrix_set(f->Mx, (size_t)i, (size_t)j, Mbuf[i * n + j]);
            gsl_matrix_set(G, (size_t)i, (size_t)j, Jf[i * n + j] - Jm[i * n + j]);
        }
    int sign;
    if (gsl_linalg_LU_decomp(f->Mx, f->perm, &sign) != GSL_SUCCESS)
        return -1;
    for (int j = 0; j < n; ++j) {
        gsl_vector_view col = gsl_matrix_column(G, (size_t)j);
        if (gsl_linalg_LU_svx(f->Mx, f->perm, &col.vector) != GSL_SUCCESS)
            return -1;
    }
    for (int i = 0; i < n * n; ++i)
        if (!isfinite(G->data[i]))
            return -1;
    return 0;
}

/* ---- variational equations with CVODES ----------------------------------- */

/* G <- S G(t) S^{-1} */
static int balanced_coefficient_matrix(usm_floquet *f, double t)
{
    if (coefficient_matrix(f, t, f->W) != 0)
        return -1;
    gsl_blas_dgemm(CblasNoTrans, CblasNoTrans, 1.0, f->S, f->W, 0.0, f->E);
    gsl_blas_dgemm(CblasNoTrans, CblasNoTrans, 1.0, f->E, f->Sinv, 0.0, f->G);
    return 0;
}

/* S = D^{-1} T (see the header comment) and its inverse. */
static int variational_coordinates(usm_floquet *f, double t0)
{
    const int n = f->n;
    double orbit[2 * USM_MAX_NX], T[USM_MAX_NX * USM_MAX_NX];
    int sign;
    f->m->steady_state(f->u, f->beta, t0, &f->p, orbit);
    f->m->tangent_map(orbit, &f->p, T);
    for (int i = 0; i < n * n; ++i)
        f->S->data[i] = T[i];
    gsl_matrix_memcpy(f->Mx, f->S);
    if (gsl_linalg_LU_decomp(f->Mx, f->perm, &sign) != GSL_SUCCESS ||
        gsl_linalg_LU_invert(f->Mx, f->perm, f->Sinv) != GSL_SUCCESS)
        return -1;
    /* balance T G(t0) T^{-1}: D^{-1} (T G T^{-1}) D */
    if (balanced_coefficient_matrix(f, t0) != 0 ||
        gsl_linalg_balance_matrix(f->G, f->dscale) != GSL_SUCCESS)
        return -1;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const double di = gsl_vector_get(f->dscale, (size_t)i);
            const double dj = gsl_vector_get(f->dscale, (size_t)j);
            f->S->data[i * n + j] /= di;
            f->Sinv->data[i * n + j] *= dj;
        }
    return 0;
}

/* y holds Psi column by column: y[j*n + i] = Psi_ij.  CVODES integrates in
 * tau = t - t0 from 0: with t0 = 100 T, steps near 1e-19 s would vanish in t0 + h. */
static int variational_rhs(sunrealtype tau, N_Vector y, N_Vector ydot, void *data)
{
    usm_floquet *f = data;
    const int n = f->n;
    if (balanced_coefficient_matrix(f, f->t0 + tau) != 0)
        return 1; /* recoverable: CVODES retries with a smaller step */
    const double *Y = N_VGetArrayPointer(y);
    double *D = N_VGetArrayPointer(ydot);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            double s = 0;
            for (int k = 0; k < n; ++k)
                s += gsl_matrix_get(f->G, (size_t)i, (size_t)k) * Y[j * n + k];
            D[j * n + i] = s;
        }
    return 0;
}

/* CVODES' error handler: the message goes into f->cvmsg instead of stderr
 * (the library never prints; the command's errors are one line). */
static void cv_errors(int code, const char *module, const char *function, char *text, void *data)
{
    usm_floquet *f = data;
    (void)code;
    (void)module;
    snprintf(f->cvmsg, sizeof f->cvmsg, "%s: %s", function, text);
}

static int cvode_fail(usm_floquet *f, const char *call, int flag)
{
    char name[32];
    snprintf(f->msg, USM_MSG_LEN, "CVODES %s failed: %s%s%.150s", call,
             usm_cvode_flag_name(flag, name, sizeof name), f->cvmsg[0] ? " -- " : "", f->cvmsg);
    return USM_EFAILED;
}

static int setup_cvode(usm_floquet *f, double t0, const usm_floquet_options *opt)
{
    const sunindextype N = (sunindextype)f->n * f->n;
    int flag;
    if (!f->cvode_ready) {
        f->y = N_VNew_Serial(N, f->ctx);
        f->cvode = CVodeCreate(CV_ADAMS, f->ctx);
        if (!f->y || !f->cvode) {
            snprintf(f->msg, USM_MSG_LEN, "CVODES: out of memory");
            return USM_EFAILED;
        }
        N_VConst(0.0, f->y);
        if ((flag = CVodeSetErrHandlerFn(f->cvode, cv_errors, f)) != CV_SUCCESS)
            return cvode_fail(f, "CVodeSetErrHandlerFn", flag);
        if ((flag = CVodeInit(f->cvode, variational_rhs, 0.0, f->y)) != CV_SUCCESS)
            return cvode_fail(f, "CVodeInit", flag);
        f->NLS = SUNNonlinSol_FixedPoint(f->y, 0, f->ctx);
        if (!f->NLS) {
            snprintf(f->msg, USM_MSG_LEN, "CVODES: cannot create the fixed-point solver");
            return USM_EFAILED;
        }
        if ((flag = CVodeSetNonlinearSolver(f->cvode, f->NLS)) != CV_SUCCESS)
            return cvode_fail(f, "CVodeSetNonlinearSolver", flag);
        if ((flag = CVodeSetUserData(f->cvode, f)) != CV_SUCCESS)
            return cvode_fail(f, "CVodeSetUserData", flag);
        if ((flag = CVodeSetMaxNumSteps(f->cvode, 200000)) != CV_SUCCESS)
            return cvode_fail(f, "CVodeSetMaxNumSteps", flag);
        f->cvode_ready = 1;
    }
    double *Y = N_VGetArrayPointer(f->y);
    N_VConst(0.0, f->y);
    for (int i = 0; i < f->n; ++i)
        Y[i * f->n + i] = 1.0;
    f->t0 = t0;
    if ((flag = CVodeReInit(f->cvode, 0.0, f->y)) != CV_SUCCESS)
        return cvode_fail(f, "CVodeReInit", flag);
    if ((flag = CVodeSStolerances(f->cvode, opt->rtol, opt->atol)) != CV_SUCCESS)
        return cvode_fail(f, "CVodeSStolerances", flag);
    return USM_OK;
}

static int monodromy_variational(usm_floquet *f, double t0, double period,
                                 const usm_floquet_options *opt, double *B)
{
    if (variational_coordinates(f, t0) != 0) {
        snprintf(f->msg, USM_MSG_LEN, "linearisation at t0 is singular or not finite");
        return USM_EFAILED;
    }
    int rc = setup_cvode(f, t0, opt), flag;
    if (rc != USM_OK)
        return rc;
    if ((flag = CVodeSetStopTime(f->cvode, period)) != CV_SUCCESS)
        return cvode_fail(f, "CVodeSetStopTime", flag);
    double s = 0;
    char name[32];
    f->cvmsg[0] = '\0';
    flag = CVode(f->cvode, period, f->y, &s, CV_NORMAL);
    if (flag < 0) {
        /* CV_TOO_MUCH_WORK: Adams with fixed-point iteration is meant for a
         * non-stiff linearisation; CVODES' own text adds nothing then */
        char where[96];
        snprintf(where, sizeof where, "CVODES failed at t = %.6g s of [%.6g, %.6g]", t0 + s, t0,
                 t0 + period);
        usm_cvode_flag_name(flag, name, sizeof name);
        if (flag == CV_TOO_MUCH_WORK)
            snprintf(f->msg, USM_MSG_LEN,
                     "%s: %s (stiff linearisation: use an exponential method)",
                     where, name);
        else
            snprintf(f->msg, USM_MSG_LEN, "%s: %s%s%.100s", where, name, f->cvmsg[0] ? " -- " : "",
                     f->cvmsg);
        return USM_EFAILED;
    }
    /* B = S^{-1} Psi S, with Psi stored column by column */
    const int n = f->n;
    const double *Y = N_VGetArrayPointer(f->y);
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
            gsl_matrix_set(f->P, (size_t)i, (size_t)j, Y[j * n + i]);
    gsl_blas_dgemm(CblasNoTrans, CblasNoTrans, 1.0, f->Sinv, f->P, 0.0, f->W);
    gsl_blas_dgemm(CblasNoTrans, CblasNoTrans, 1.0, f->W, f->S, 0.0, f->Q);
    memcpy(B, f->Q->data, sizeof(double) * (size_t)(n * n));
    return USM_OK;
}

/* ---- product of matrix exponentials ----------------------------------------- */

/* E = exp(h G) via balancing: exp(A) = D exp(D^{-1} A D) D^{-1}. */
static int balanced_expm(usm_floquet *f, double h, gsl_matrix *E)
{
    gsl_matrix_scale(f->G, h);
    if (gsl_linalg_balance_matrix(f->G, f->dscale) != GSL_SUCCESS)
        return -1;
    if (gsl_linalg_exponential_ss(f->G, E, GSL_PREC_DOUBLE) != GSL_SUCCESS)
        return -1;
    for (size_t i = 0; i < E->size1; ++i)
        for (size_t j = 0; j < E->size2; ++j)
            gsl_matrix_set(E, i, j, gsl_matrix_get(E, i, j) * gsl_vector_get(f->dscale, i) /
                                        gsl_vector_get(f->dscale, j));
    return 0;
}

static int product_of_exponentials(usm_floquet *f, double t0, double period, int steps,
                                   gsl_matrix *B)
{
    const double h = period / steps;
    gsl_matrix_set_identity(B);
    for (int k = 0; k < steps; ++k) {
        if (balanced_coefficient_matrix(f, t0 + (k + 0.5) * h) != 0 ||
            balanced_expm(f, h, f->E) != 0)
            return -1;
        gsl_blas_dgemm(CblasNoTrans, CblasNoTrans, 1.0, f->E, B, 0.0, f->W);
        gsl_matrix_memcpy(B, f->W);
    }
    return 0;
}

static int monodromy_exponential(usm_floquet *f, double t0, double period, int steps, double *B)
{
    const int n = f->n;
    if (steps < 1 || variational_coordinates(f, t0) != 0 ||
        product_of_exponentials(f, t0, period, steps, f->P) != 0 ||
        product_of_exponentials(f, t0, period, 2 * steps, f->Q) != 0) {
        snprintf(f->msg, USM_MSG_LEN, "matrix exponential of the linearisation failed");
        return USM_EFAILED;
    }
    /* Richardson: the midpoint rule's error is O(h^2) */
    gsl_matrix_scale(f->Q, 4.0 / 3.0);
    gsl_matrix_scale(f->P, -1.0 / 3.0);
    gsl_matrix_add(f->P, f->Q);
    gsl_blas_dgemm(CblasNoTrans, CblasNoTrans, 1.0, f->Sinv, f->P, 0.0, f->W);
    gsl_blas_dgemm(CblasNoTrans, CblasNoTrans, 1.0, f->W, f->S, 0.0, f->Q);
    memcpy(B, f->Q->data, sizeof(double) * (size_t)(n * n));
    return USM_OK;
}

/* ---- eigenvalues -------------------------------------------------------------- */

typedef struct {
    double re, im;
    int cyclic;
} multiplier;

static int by_modulus_desc(const void *a, const void *b)
{
    const multiplier *x = a, *y = b;
    double mx = hypot(x->re, x->im), my = hypot(y->re, y->im);
    if (mx != my)
        return (mx < my) - (mx > my);
    if (x->re != y->re)
        return (x->re < y->re) - (x->re > y->re);
    return (x->im < y->im) - (x->im > y->im);
}

static int multipliers(usm_floquet *f, const double *B, usm_floquet_result *out)
{
    const int n = f->n, nk = f->nk;
    multiplier mult[USM_MAX_NX];
    int nm = 0;
    for (int i = 0; i < n; ++i)
        if (f->m->cyclic[i])
            mult[nm++] = (multiplier){1.0, 0.0, 1};
    for (int i = 0; i < nk; ++i)
        for (int j = 0; j < nk; ++j)
            gsl_matrix_set(f->R, (size_t)i, (size_t)j, B[f->keep[i] * n + f->keep[j]]);
    gsl_eigen_nonsymm_params(0, 1, f->eig); /* balance before QR */
    if (gsl_eigen_nonsymm(f->R, f->eval, f->eig) != GSL_SUCCESS) {
        snprintf(f->msg, USM_MSG_LEN, "eigenvalues of the monodromy matrix did not converge");
        return USM_EFAILED;
    }
    for (int i = 0; i < nk; ++i) {
        gsl_complex z = gsl_vector_complex_get(f->eval, (size_t)i);
        mult[nm++] = (multiplier){GSL_REAL(z), GSL_IMAG(z), 0};
    }
    qsort(mult, (size_t)n, sizeof mult[0], by_modulus_desc);
    out->n = n;
    out->max_modulus = 0;
    for (int i = 0; i < n; ++i) {
        out->re[i] = mult[i].re;
        out->im[i] = mult[i].im;
        out->cyclic[i] = mult[i].cyclic;
        if (!mult[i].cyclic)
            out->max_modulus = fmax(out->max_modulus, hypot(mult[i].re, mult[i].im));
    }
    out->stable = out->max_modulus < 1.0;
    return USM_OK;
}

int usm_floquet_compute(usm_floquet *f, const usm_params *p, const usm_steady_solution *sol,
                        double t0, const usm_floquet_options *opt, usm_floquet_result *out)
{
    usm_floquet_options def;
    if (!opt) {
        usm_floquet_options_default(&def);
        opt = &def;
    }
    f->msg[0] = '\0';
    if (!isfinite(t0)) {
        snprintf(f->msg, USM_MSG_LEN, "t0: must be a finite number");
        return USM_EINPUT;
    }
    f->p = *p;
    memcpy(f->u, sol->u, sizeof f->u);
    f->beta = sol->beta;
    const double period = 1.0 / p->f;
    memset(out, 0, sizeof *out);
    out->t0 = t0;
    out->t0_dependent = !f->m->t0_independent;
    int rc = opt->method == USM_FLOQUET_EXPONENTIAL
                 ? monodromy_exponential(f, t0, period, opt->steps, out->monodromy)
                 : monodromy_variational(f, t0, period, opt, out->monodromy);
    if (rc != USM_OK)
        return rc;
    for (int i = 0; i < f->n * f->n; ++i)
        if (!isfinite(out->monodromy[i])) {
            snprintf(f->msg, USM_MSG_LEN, "monodromy matrix is not finite");
            return USM_EFAILED;
        }
    return multipliers(f, out->monodromy, out);
}
