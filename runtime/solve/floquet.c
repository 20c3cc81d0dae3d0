/* Floquet multipliers of a stationary solution (paper, section 4).
 *
 * Math: about the stationary orbit xbar(t) the first approximation (4.9) is
 *     M(xbar) dx' = A(t) dx,   A = df/dx - d(M v)/dx |_{v = xbar'}      (1)
 * with both Jacobians generated from the derivation.  The monodromy matrix
 * B = Phi(t0 + T) with Phi' = G Phi, G = M^{-1} A, Phi(t0) = I, T = 2 pi / Omega,
 * and the multipliers are the eigenvalues of B.
 *
 * Coordinates.  Near theta = 1e-4 the Euler-angle linearisation spans about
 * 17 orders of magnitude.  Every method works on Psi = S Phi S^{-1} with
 * S = D^{-1} T, where T is the generated tangent map (Euler-angle
 * perturbations to the small-rotation vector in frame A, constant on the
 * orbit) and D balances T G(t0) T^{-1}; B = S^{-1} Psi(t0 + T) S.  The
 * multipliers are computed from Psi, not from B: S is as ill-conditioned as
 * the Euler angles (cond ~ 1/theta^2), and the rounding errors of forming B
 * moved them by up to 5e-7 (see multipliers).
 *
 * Three ways to compute Psi:
 *  - variational: CVODES integrates the n x n system with Adams and
 *    fixed-point iteration (over one period |lambda| T < ~20: not stiff, so
 *    no n^2 x n^2 linear algebra is needed).  The independent check.
 *  - exponential: the product of balanced matrix exponentials of S G S^{-1}
 *    over N sub-intervals (exponential midpoint rule, GSL's exponential),
 *    Richardson-extrapolated from N and 2N (second order in 1/N).
 *  - magnus (the default): in frame A the coefficients are constant except
 *    the paper's twist term -c_t psi(t) sin(theta), so G(t) is affine in t
 *    (constant under the integrated twist law).  Constant: Psi = exp(T G), one
 *    exponential.  Affine: psi(t) grows with t (it is not periodic, which is
 *    why the multipliers depend on t0, and why no periodic change of
 *    coordinates makes G constant), and its slope D is one column (theta's)
 *    with D^2 = 0: the exact flow of the constant part, one exponential, with
 *    the slope applied as kicks I + c D at Boole nodes (kick_adaptive), error
 *    control on the multipliers.  An affine G whose slope is not nilpotent:
 *    the sixth-order Magnus integrator (magnus_adaptive).  Constant and affine
 *    are checked at t0 + T/2, not assumed; otherwise G is evaluated at the
 *    Gauss nodes of the Magnus steps.  The exponentials: scaling and squaring
 *    with Pade approximants (dense.c).  Where the Magnus series diverges (a
 *    stiff linearisation, |G| T >> pi) the default falls back to the
 *    exponential method.
 *
 * A cyclic coordinate x_i (appearing in neither M nor f) leaves column i of B
 * equal to e_i; its multiplier is exactly 1 and it is removed from the
 * eigenvalue problem, then reported as such.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_blas.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_linalg.h>
#include <gsl/gsl_matrix.h>

#include <cvodes/cvodes.h>
#include "core/cvode_msg.h"
#include "core/cvodes.h"
#include "core/dense.h"
#include "floquet_floor.h"
#include "multipliers.h"
#include "usm.h"

#define TWO_PI 6.283185307179586476925286766559
#define NN (USM_MAX_NX * USM_MAX_NX)

struct usm_floquet {
    const usm_model *m;
    int n;
    /* the orbit being linearised */
    usm_params p;
    double u[USM_MAX_NU];
    double beta;
    /* CVODES */
    usm_cvodes cv;
    int cvode_ready;
    double t0; /* start of the period being integrated */
    /* work space */
    gsl_matrix *G, *E, *P, *Q, *W;
    gsl_vector *dscale;
    gsl_matrix *S, *Sinv;   /* coordinates of the variational integration */
    /* the monodromy in the integration's coordinates, Psi = S B S^{-1} */
    double Psi[NN];
    /* eigenproblem of B without its cyclic rows and columns, from Psi
     * (solve/multipliers.h) */
    usm_multipliers *mult;
    /* Magnus: S G S^{-1} at t0 and t0 + T, and whether G is affine in t */
    double Ga[USM_MAX_NX * USM_MAX_NX], Gb[USM_MAX_NX * USM_MAX_NX];
    int affine;
    /* affine G = Ga + (t - t0) D / T, D = Gb - Ga: the commutators every
     * Magnus step needs, K = [Ga, D], L0 = [Ga, K], L1 = [D, K] */
    double K[USM_MAX_NX * USM_MAX_NX], L0[USM_MAX_NX * USM_MAX_NX], L1[USM_MAX_NX * USM_MAX_NX];
    int magnus_steps;    /* steps of the last Magnus result (0: one exponential) */
    int eval_valid;      /* mult already holds the eigenvalues of Psi */
    double magnus_error; /* its estimated relative error */
    char msg[USM_MSG_LEN];
};

void usm_floquet_options_default(usm_floquet_options *opt)
{
    opt->method = USM_FLOQUET_AUTO;
    opt->rtol = 1e-8;
    opt->atol = 1e-12;
    opt->steps = 64;
}

const char *usm_floquet_message(const usm_floquet *f) { return f->msg; }

static const char *const method_names[] = {"variational", "exponential", "magnus", "auto"};
#define NMETHODS (int)(sizeof method_names / sizeof method_names[0])

const char *usm_floquet_method_name(usm_floquet_method method)
{
    return (int)method >= 0 && (int)method < NMETHODS ? method_names[method] : NULL;
}

int usm_floquet_method_from_name(const char *name, usm_floquet_method *method,
                                 char msg[USM_MSG_LEN])
{
    for (int k = 0; k < NMETHODS; ++k)
        if (strcmp(name, method_names[k]) == 0) {
            *method = (usm_floquet_method)k;
            return USM_OK;
        }
    snprintf(msg, USM_MSG_LEN,
             "%.64s: unknown Floquet method (known: variational, exponential, magnus, auto)", name);
    return USM_EINPUT;
}

/* The coordinates the multipliers are computed in (docs/coordinates.md):
 * the tilt vector for the stick model's twist_integrated variant, whose
 * multipliers it gives to 14.1-15.0 correct digits where the Euler angles give
 * 11.3-12.0 (tests/solve/multipliers_reference.h, six points); the Euler angles
 * everywhere else: under the paper's twist law there are no tilt-vector
 * coordinates (its twist angle needs phi), and for the slip model the tilt
 * vector is no better (11.8-12.7 digits against 11.9-14.7). */
const usm_model *usm_floquet_coordinates(const usm_model *m)
{
    const usm_model *r = m->other_coordinates;
    return r && r->coordinates == 1 && !m->slip ? r : m;
}

usm_floquet *usm_floquet_alloc(const usm_model *m)
{
    usm_floquet *f = calloc(1, sizeof *f);
    if (!f)
        return NULL;
    m = usm_floquet_coordinates(m);
    const size_t n = (size_t)m->nx;
    f->m = m;
    f->n = m->nx;
    f->G = gsl_matrix_alloc(n, n);
    f->E = gsl_matrix_alloc(n, n);
    f->P = gsl_matrix_alloc(n, n);
    f->Q = gsl_matrix_alloc(n, n);
    f->W = gsl_matrix_alloc(n, n);
    f->S = gsl_matrix_alloc(n, n);
    f->Sinv = gsl_matrix_alloc(n, n);
    f->dscale = gsl_vector_alloc(n);
    f->mult = usm_multipliers_alloc(m);
    if (!f->G || !f->E || !f->P || !f->Q || !f->W || !f->S || !f->Sinv || !f->dscale ||
        !f->mult) {
        usm_floquet_free(f);
        return NULL;
    }
    return f;
}

void usm_floquet_free(usm_floquet *f)
{
    if (!f)
        return;
    usm_cvodes_free(&f->cv);
    gsl_matrix_free(f->G);
    gsl_matrix_free(f->E);
    gsl_matrix_free(f->P);
    gsl_matrix_free(f->Q);
    gsl_matrix_free(f->W);
    gsl_matrix_free(f->S);
    gsl_matrix_free(f->Sinv);
    gsl_vector_free(f->dscale);
    usm_multipliers_free(f->mult);
    free(f);
}

/* G(t) = M(xbar)^{-1} A(t), the coefficient matrix of the variational system,
 * is formed in the coordinates S only (balanced_coefficient_matrix below).
 *
 * From the three kernels, not the fused `linearisation` kernel [M, df/dx,
 * d(Mv)/dx], measured again: the fused kernel agrees with the three
 * to 7e-16 of a row and takes 16-24 % less time per evaluation (20-28 ns of
 * 83-135 ns with steady_state), but a method makes few evaluations (Magnus 2-3
 * per period, the exponential method 193, CVODES ~350), so it saves under 1 %
 * of any method's time: Magnus per point, min of 8 interleaved runs, three
 * calls -> fused: 3dof 20.75 -> 21.19 us, 4dof 16.47 -> 15.94,
 * 3dof_twist_integrated 5.86 -> 5.71, 4dof_twist_integrated 9.90 -> 9.53
 * (bench/usm_bench, auto: 22.1 -> 23.2, 17.6 -> 17.5, 6.5 -> 6.2, 10.0 ->
 * 10.0 us): noise of the layout and of the eigen-solver, either sign; CVODES
 * changes its step count by +-10 % under the last-bit change.  The change is not
 * free: M(xbar) is ill-conditioned near theta = 1e-4 (2-norm condition 9e11
 * at the paper's point), so the last bits move every method's multipliers
 * together by up to 4.1e-8 (3dof; 4dof 3e-11; the methods still agree with
 * each other to 4e-11; measured while G was formed with M^{-1} alone, before the balanced
 * form: see balanced_coefficient_matrix).  Not faster: not used. */

/* ---- variational equations with CVODES ----------------------------------- */

/* G <- S G(t) S^{-1}, formed as (M S^{-1})^{-1} (A S^{-1}): the same
 * matrix, but M(xbar) is never inverted alone.  Its 2-norm condition number
 * is 9e11 at the paper's point (the Euler angles' phi/psi degeneracy near
 * theta = 0); M S^{-1}, the mass matrix acting on small-rotation-vector
 * rates, is the well-conditioned one.  Measured against a 50-digit reference
 * (tests/derive/coordinates_study.py, docs/coordinates.md): exp(T eig G) of
 * 3dof_twist_integrated at the paper's point has 11.5 correct digits this
 * way and 10.0 from S (M^{-1} A) S^{-1}. */
static int balanced_coefficient_matrix(usm_floquet *f, double t)
{
    const int n = f->n;
    double orbit[2 * USM_MAX_NX], Mbuf[NN], Jf[NN], Jm[NN];
    f->m->steady_state(f->u, f->beta, t, &f->p, orbit);
    const double *x = orbit + f->m->steady_state_out.x;
    const double *xdot = orbit + f->m->steady_state_out.xdot;
    f->m->mass(x, &f->p, Mbuf);
    f->m->jac_rhs(x, t, &f->p, Jf);
    f->m->jac_mass(x, xdot, &f->p, Jm);
    for (int k = 0; k < n * n; ++k)
        Jf[k] -= Jm[k];
    usm_matmul_dense(n, Mbuf, f->Sinv->data, f->W->data);
    usm_matmul_dense(n, Jf, f->Sinv->data, f->G->data);
    if (usm_solve_dense(n, f->W->data, f->G->data) != 0)
        return -1;
    for (int i = 0; i < n * n; ++i)
        if (!isfinite(f->G->data[i]))
            return -1;
    return 0;
}

/* S = D^{-1} T (see the header comment) and its inverse. */
static int variational_coordinates(usm_floquet *f, double t0)
{
    const int n = f->n;
    double orbit[2 * USM_MAX_NX], T[NN];
    f->m->steady_state(f->u, f->beta, t0, &f->p, orbit);
    f->m->tangent_map(orbit + f->m->steady_state_out.x, &f->p, T);
    memcpy(f->S->data, T, sizeof(double) * (size_t)(n * n));
    gsl_matrix_set_identity(f->Sinv);
    if (usm_solve_dense(n, T, f->Sinv->data) != 0)
        return -1;
    /* balance T G(t0) T^{-1}: D^{-1} (T G T^{-1}) D */
    if (balanced_coefficient_matrix(f, t0) != 0)
        return -1;
    usm_balance_dense(n, f->G->data, f->dscale->data);
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            f->S->data[i * n + j] /= f->dscale->data[i];
            f->Sinv->data[i * n + j] *= f->dscale->data[j];
        }
    /* the orthogonal basis whose first columns span S e_i, i cyclic
     * (solve/multipliers.h) */
    return usm_multipliers_basis(f->mult, f->S->data);
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

static int setup_cvode(usm_floquet *f, double t0, const usm_floquet_options *opt)
{
    usm_cvodes *c = &f->cv;
    int rc;
    if (!f->cvode_ready) {
        const usm_cvodes_spec spec = {.lmm = CV_ADAMS,
                                      .n = (sunindextype)f->n * f->n,
                                      .rhs = variational_rhs,
                                      .data = f,
                                      .max_steps = 200000};
        if ((rc = usm_cvodes_init(c, &spec, f->msg)) != USM_OK)
            return rc;
        f->cvode_ready = 1;
    }
    double *Y = N_VGetArrayPointer(c->y);
    N_VConst(0.0, c->y);
    for (int i = 0; i < f->n; ++i)
        Y[i * f->n + i] = 1.0;
    f->t0 = t0;
    if ((rc = usm_cvodes_check(c, "CVodeReInit", CVodeReInit(c->mem, 0.0, c->y))) != USM_OK)
        return rc;
    return usm_cvodes_check(c, "CVodeSStolerances",
                            CVodeSStolerances(c->mem, opt->rtol, opt->atol));
}

static int monodromy_variational(usm_floquet *f, double t0, double period,
                                 const usm_floquet_options *opt, double *B)
{
    if (variational_coordinates(f, t0) != 0) {
        snprintf(f->msg, USM_MSG_LEN, "linearisation at t0 is singular or not finite");
        return USM_EFAILED;
    }
    usm_cvodes *c = &f->cv;
    int rc = setup_cvode(f, t0, opt), flag;
    if (rc != USM_OK)
        return rc;
    if ((rc = usm_cvodes_check(c, "CVodeSetStopTime", CVodeSetStopTime(c->mem, period))) != USM_OK)
        return rc;
    double s = 0;
    char name[32];
    c->cvmsg[0] = '\0';
    flag = CVode(c->mem, period, c->y, &s, CV_NORMAL);
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
            snprintf(f->msg, USM_MSG_LEN, "%s: %s%s%.100s", where, name, c->cvmsg[0] ? " -- " : "",
                     c->cvmsg);
        return USM_EFAILED;
    }
    /* B = S^{-1} Psi S, with Psi stored column by column */
    const int n = f->n;
    const double *Y = N_VGetArrayPointer(c->y);
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
            gsl_matrix_set(f->P, (size_t)i, (size_t)j, Y[j * n + i]);
    memcpy(f->Psi, f->P->data, sizeof(double) * (size_t)(n * n));
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
    memcpy(f->Psi, f->P->data, sizeof(double) * (size_t)(n * n));
    gsl_blas_dgemm(CblasNoTrans, CblasNoTrans, 1.0, f->Sinv, f->P, 0.0, f->W);
    gsl_blas_dgemm(CblasNoTrans, CblasNoTrans, 1.0, f->W, f->S, 0.0, f->Q);
    memcpy(B, f->Q->data, sizeof(double) * (size_t)(n * n));
    return USM_OK;
}

/* ---- Magnus integrator ----------------------------------------------------------- */

/* C = X Y - Y X */
static void commutator(int n, const double *X, const double *Y, double *C)
{
    double YX[NN];
    usm_matmul_dense(n, X, Y, C);
    usm_matmul_dense(n, Y, X, YX);
    for (int k = 0; k < n * n; ++k)
        C[k] -= YX[k];
}

static double max_abs(int nn, const double *A)
{
    double m = 0;
    for (int k = 0; k < nn; ++k)
        m = fmax(m, fabs(A[k]));
    return m;
}

/* The balanced coefficient matrix S G(t0 + tau) S^{-1} into A: interpolated
 * between G0 = f->Ga (tau = 0) and G1 = f->Gb (tau = period) when G is affine
 * in t, evaluated otherwise. */
static int magnus_coefficients(usm_floquet *f, double t0, double tau, double period, double *A)
{
    const int nn = f->n * f->n;
    if (f->affine) {
        const double w = tau / period;
        for (int k = 0; k < nn; ++k)
            A[k] = f->Ga[k] + w * (f->Gb[k] - f->Ga[k]);
        return 0;
    }
    if (balanced_coefficient_matrix(f, t0 + tau) != 0)
        return -1;
    memcpy(A, f->G->data, sizeof(double) * (size_t)nn);
    return 0;
}

/* Psi <- exp(Omega) Psi over [t0 + a, t0 + a + h], Omega the sixth-order
 * Magnus approximation from the three Gauss-Legendre nodes (S. Blanes,
 * F. Casas, J. A. Oteo, J. Ros, Phys. Rep. 470 (2009) 151-238, eq. (253)).
 *
 * Affine G (the paper's twist law): with Am = G at the step's middle,
 * w = (a + h/2) / T, the node combinations are a1 = h Am, a2 = h^2 D / T,
 * a3 = 0, and since [D, D] = 0 the commutators reduce to constants of the
 * period: [a1, a2] = h^3 K / T, [a1, [a1, a2]] = h^4 (L0 + w L1) / T.  One
 * commutator per step remains instead of three (a third of the step's cost
 * at 6x6); the same formula, so the multipliers move only by rounding. */
static void magnus_exponent_affine(const usm_floquet *f, double a, double h, double period,
                                   double *Omega)
{
    const int n = f->n, nn = n * n;
    const double w = (a + 0.5 * h) / period, h2 = h * h / period, h3 = h2 * h,
                 h4 = h3 * h;
    double X[NN] = {0}, Y[NN] = {0}, C[NN];
    for (int k = 0; k < nn; ++k) {
        const double a1 = h * (f->Ga[k] + w * (f->Gb[k] - f->Ga[k]));
        Omega[k] = a1;
        X[k] = -20.0 * a1 + h3 * f->K[k];
        Y[k] = h2 * (f->Gb[k] - f->Ga[k]) - h4 * (f->L0[k] + w * f->L1[k]) / 60.0;
    }
    commutator(n, X, Y, C);
    for (int k = 0; k < nn; ++k)
        Omega[k] += C[k] / 240.0;
}

static int magnus_step(usm_floquet *f, double t0, double a, double h, double period, double *Psi)
{
    const int n = f->n, nn = n * n;
    const double r = sqrt(15.0) / 10.0;
    double A1[NN], A2[NN], A3[NN], a1[NN], a2[NN], a3[NN], C1[NN], C2[NN], X[NN], Y[NN];
    if (f->affine) {
        magnus_exponent_affine(f, a, h, period, A1);
    } else {
        if (magnus_coefficients(f, t0, a + (0.5 - r) * h, period, A1) != 0 ||
            magnus_coefficients(f, t0, a + 0.5 * h, period, A2) != 0 ||
            magnus_coefficients(f, t0, a + (0.5 + r) * h, period, A3) != 0)
            return -1;
        for (int k = 0; k < nn; ++k) {
            a1[k] = h * A2[k];
            a2[k] = sqrt(15.0) * h / 3.0 * (A3[k] - A1[k]);
            a3[k] = 10.0 * h / 3.0 * (A3[k] - 2.0 * A2[k] + A1[k]);
        }
        commutator(n, a1, a2, C1);             /* C1 = [a1, a2] */
        for (int k = 0; k < nn; ++k)
            X[k] = 2.0 * a3[k] + C1[k];
        commutator(n, a1, X, C2);              /* C2 = -[a1, 2 a3 + C1] / 60 */
        for (int k = 0; k < nn; ++k) {
            C2[k] /= -60.0;
            X[k] = -20.0 * a1[k] - a3[k] + C1[k];
            Y[k] = a2[k] + C2[k];
        }
        commutator(n, X, Y, A1);               /* Omega = a1 + a3 / 12 + [X, Y] / 240 */
        for (int k = 0; k < nn; ++k)
            A1[k] = a1[k] + a3[k] / 12.0 + A1[k] / 240.0;
    }
    if (usm_expm_dense(n, A1, A2) != 0)
        return -1;
    usm_matmul_dense(n, A2, Psi, A3);
    memcpy(Psi, A3, sizeof(double) * (size_t)nn);
    return 0;
}

/* Largest distance from an eigenvalue in (re1, im1) to the nearest in
 * (re0, im0), both of length k. */
static double eigen_distance(int k, const double *re0, const double *im0, const double *re1,
                             const double *im1)
{
    double worst = 0;
    for (int i = 0; i < k; ++i) {
        double best = INFINITY;
        for (int j = 0; j < k; ++j)
            best = fmin(best, hypot(re1[i] - re0[j], im1[i] - im0[j]));
        worst = fmax(worst, best);
    }
    return worst;
}

/* Psi over [t0, t0 + period] in `steps` Magnus steps. */
static int magnus_product(usm_floquet *f, double t0, double period, int steps, double *Psi)
{
    const int n = f->n;
    const double h = period / steps;
    memset(Psi, 0, sizeof(double) * (size_t)(n * n));
    for (int i = 0; i < n; ++i)
        Psi[i * n + i] = 1.0;
    for (int k = 0; k < steps; ++k)
        if (magnus_step(f, t0, k * h, h, period, Psi) != 0) {
            snprintf(f->msg, USM_MSG_LEN,
                     "Magnus step %d of %d failed: not finite (a stiff linearisation: the Magnus "
                     "series diverges; the exponential method copes)",
                     k + 1, steps);
            return -1;
        }
    return 0;
}

#define MAGNUS_MAX_STEPS 128

/* Psi by the Magnus integrator with error control on the multipliers.
 * Starting from 1 and 2 steps, the error of the finer of two results is
 * estimated from the distance between their multipliers, as for a method of
 * sixth order: e(N2) = d / ((N2 / N1)^6 - 1) (relative to the largest
 * modulus where it exceeds 1), and the step count for the tolerance is
 * predicted from it, until e <= tol; beyond MAGNUS_MAX_STEPS it fails.
 *
 * Why the multipliers and not Psi: every error term of the Magnus series for
 * A = a + t b is a commutator with the constant part a, to first order a
 * similarity transformation, which leaves the multipliers alone.  They
 * converge much faster than the entries of Psi (3-DOF, paper's point: with 8
 * steps the multipliers to 2e-12, Psi to 1e-6; bench/usm_bench). */
/* The non-cyclic multipliers of Psi for the error estimate: the roots of
 * the characteristic polynomial (a fifth of the eigensolver's time), or the
 * eigensolver where their iteration fails. */
static int estimate_multipliers(usm_floquet *f, const double *Psi, int warm, double *re,
                                double *im)
{
    if (usm_multipliers_roots(f->mult, Psi, warm, re, im) == 0)
        return 0;
    if (usm_multipliers_eigen(f->mult, Psi, f->msg) != 0)
        return -1;
    usm_multipliers_values(f->mult, re, im);
    return 0;
}

static int magnus_adaptive(usm_floquet *f, double t0, double period, double tol, double *Psi)
{
    const int nk = usm_multipliers_count(f->mult);
    double re0[USM_MAX_NX], im0[USM_MAX_NX], re1[USM_MAX_NX], im1[USM_MAX_NX];
    int n1 = 1, n2 = 2;
    if (magnus_product(f, t0, period, n1, Psi) != 0 ||
        estimate_multipliers(f, Psi, 0, re0, im0) != 0)
        return -1;
    for (;;) {
        /* from the coarser result's multipliers: a few iterations */
        memcpy(re1, re0, sizeof re1);
        memcpy(im1, im0, sizeof im1);
        if (magnus_product(f, t0, period, n2, Psi) != 0 ||
            estimate_multipliers(f, Psi, 1, re1, im1) != 0)
            return -1;
        double scale = 1.0; /* relative to the largest multiplier when that exceeds 1 */
        for (int i = 0; i < nk; ++i)
            scale = fmax(scale, hypot(re1[i], im1[i]));
        const double est =
            eigen_distance(nk, re0, im0, re1, im1) / (pow((double)n2 / n1, 6) - 1.0) / scale;
        f->magnus_steps = n2;
        f->magnus_error = est;
        if (est <= tol) {
            /* the multipliers reported: the eigensolver's, once */
            if (usm_multipliers_eigen(f->mult, Psi, f->msg) != 0)
                return -1;
            f->eval_valid = 1;
            return 0;
        }
        if (n2 >= MAGNUS_MAX_STEPS) {
            snprintf(f->msg, USM_MSG_LEN,
                     "Magnus: estimated error %.2g of the multipliers after %d steps, above "
                     "the tolerance %.2g",
                     est, n2, tol);
            return -1;
        }
        /* no margin after the first pair: one step is outside the
         * asymptotic range and its estimate already overshoots (3-DOF paper
         * point: 1.5e-7 predicted for two steps, 4e-8 seen from eight) */
        const double want = ceil(n2 * pow(est / tol, 1.0 / 6.0) * (n1 == 1 ? 1.0 : 1.1));
        const int next = want > MAGNUS_MAX_STEPS ? MAGNUS_MAX_STEPS : (int)want;
        memcpy(re0, re1, sizeof re0);
        memcpy(im0, im1, sizeof im0);
        n1 = n2;
        n2 = next > n2 ? next : n2 + 1;
    }
}

/* ---- exact flows and kicks (affine G with a nilpotent slope) ------------------- */

/* Under the paper's twist law G(t0 + s T) = Ga + s D (s in [0, 1]), D = Gb - Ga
 * the change over the period, and D is the twist term's column alone (rows of
 * the accelerations, the column of theta): D^2 = 0, so exp(c D) = I + c D
 * exactly, and D is small (|T D|_1 = 0.09 against |T Ga|_1 = 21 at the
 * paper's point).  With E = exp(T Ga / M) the monodromy is approximated by
 *     Psi = K_M E K_{M-1} E ... E K_1 E,   K_j = I + w_j (j / M) T D,
 * the flow of the constant part exact and the time-dependent part applied as
 * kicks at M + 1 equally spaced nodes with the composite Boole weights w_j
 * (sum 1, sixth order): an exponential quadrature of the variational equation
 * in the interaction picture.  One exponential per result, every other factor
 * a product (K_j E = E + c_j (T D) E, formed from E and (T D) E), where the
 * sixth-order Magnus integrator needs one exponential per step (and its
 * steps must resolve |T Ga|, while here the nodes only sample the kicks).
 * Measured on the 3-DOF paper point against 128 Magnus steps: 48 nodes give
 * the multipliers to 9e-13, 24 to 3e-10. */

/* D = Gb - Ga with D^2 = 0 to rounding (the paper's twist law: one column) */
static int kick_nilpotent(const usm_floquet *f)
{
    const int n = f->n, nn = n * n;
    double D[NN], D2[NN];
    for (int k = 0; k < nn; ++k)
        D[k] = f->Gb[k] - f->Ga[k];
    usm_matmul_dense(n, D, D, D2);
    const double d = max_abs(nn, D);
    return max_abs(nn, D2) <= 1e-14 * n * d * d;
}

/* Psi over the period from M equally spaced nodes; M a multiple of 4, E =
 * exp(T Ga / M), DE = T D E. */
static void kick_product(int n, int M, const double *E, const double *DE, double *Psi)
{
    static const double boole[4] = {32.0 / 90.0, 12.0 / 90.0, 32.0 / 90.0, 14.0 / 90.0};
    const int nn = n * n;
    double F[NN], W[NN];
    /* the kick at s = 0 is the identity: Psi = K_1 E */
    for (int j = 1; j <= M; ++j) {
        /* composite Boole: 7, 32, 12, 32, 14, 32, ..., 7 (times 2 / 45 per
         * panel of four intervals), over 4 M intervals of the panel sum */
        const double w = (j == M ? 7.0 / 90.0 : boole[(j - 1) % 4]) * 4.0 / M;
        const double c = w * j / M;
        for (int k = 0; k < nn; ++k)
            F[k] = E[k] + c * DE[k];
        if (j == 1)
            memcpy(Psi, F, sizeof(double) * (size_t)nn);
        else {
            usm_matmul_dense(n, F, Psi, W);
            memcpy(Psi, W, sizeof(double) * (size_t)nn);
        }
    }
}

#define KICK_MAX_NODES 1024

/* Psi from the kicks, with error control on the multipliers: the result
 * from M nodes against the one from M / 2 (every other node: E^2), the
 * distance of their multipliers over 2^5 the estimate of the finer one's
 * error (sixth order, counted as fifth for a margin: at 24 and 48 nodes the
 * measured errors fell by 40 to 330), M doubled until it is below tol.  The
 * first M: a node every |T Ga|_1 / 2 (48 at the paper's point), at least 16,
 * at most 64 (a stiff direction is carried by the exact flow, not resolved
 * by the nodes).  The finer result's multipliers are the eigensolver's (the
 * ones reported); the coarser's the characteristic polynomial's roots, from
 * them. */
static int kick_adaptive(usm_floquet *f, double period, double tol, double *Psi)
{
    const int n = f->n, nn = n * n, nk = usm_multipliers_count(f->mult);
    double A[NN], Dt[NN], E[NN], E2[NN], DE[NN], Pc[NN];
    double re0[USM_MAX_NX], im0[USM_MAX_NX], re1[USM_MAX_NX], im1[USM_MAX_NX];
    for (int k = 0; k < nn; ++k) {
        A[k] = period * f->Ga[k];
        Dt[k] = period * (f->Gb[k] - f->Ga[k]);
    }
    double a1 = 0; /* |T Ga|_1 */
    for (int j = 0; j < n; ++j) {
        double c = 0;
        for (int i = 0; i < n; ++i)
            c += fabs(A[i * n + j]);
        a1 = fmax(a1, c);
    }
    int M = 8 * (int)ceil(fmin(a1, 48.0) / 6.0);
    M = M < 16 ? 16 : M;
    int have_coarse = 0;
    for (;;) {
        const double scale = 1.0 / M;
        for (int k = 0; k < nn; ++k)
            E[k] = A[k] * scale;
        if (usm_expm_dense(n, E, E2) != 0) {
            snprintf(f->msg, USM_MSG_LEN, "matrix exponential of the linearisation failed");
            return -1;
        }
        memcpy(E, E2, sizeof E);
        usm_matmul_dense(n, Dt, E, DE);
        kick_product(n, M, E, DE, Psi);
        if (usm_multipliers_eigen(f->mult, Psi, f->msg) != 0)
            return -1;
        usm_multipliers_values(f->mult, re1, im1);
        if (!have_coarse) {
            /* the coarser result: every other node */
            usm_matmul_dense(n, E, E, E2);
            usm_matmul_dense(n, Dt, E2, DE);
            kick_product(n, M / 2, E2, DE, Pc);
            memcpy(re0, re1, sizeof re0);
            memcpy(im0, im1, sizeof im0);
            /* the roots, from the finer result's multipliers, leave the
             * eigensolver's values (the finer result's) alone; where their
             * iteration fails, the eigensolver, then the finer again */
            if (usm_multipliers_roots(f->mult, Pc, 1, re0, im0) != 0) {
                if (usm_multipliers_eigen(f->mult, Pc, f->msg) != 0)
                    return -1;
                usm_multipliers_values(f->mult, re0, im0);
                if (usm_multipliers_eigen(f->mult, Psi, f->msg) != 0)
                    return -1;
            }
        }
        double sc = 1.0;
        for (int i = 0; i < nk; ++i)
            sc = fmax(sc, hypot(re1[i], im1[i]));
        const double est = eigen_distance(nk, re0, im0, re1, im1) / 63.0 / sc;
        f->magnus_steps = M;
        f->magnus_error = est;
        if (est <= tol) {
            f->eval_valid = 1;
            return 0;
        }
        if (2 * M > KICK_MAX_NODES) {
            snprintf(f->msg, USM_MSG_LEN,
                     "Magnus (exact flows and kicks): estimated error %.2g of the multipliers "
                     "with %d nodes, above the tolerance %.2g (a stiff linearisation: the "
                     "exponential method copes)",
                     est, M, tol);
            return -1;
        }
        memcpy(re0, re1, sizeof re0);
        memcpy(im0, im1, sizeof im0);
        have_coarse = 1;
        M *= 2;
    }
}

static int monodromy_magnus(usm_floquet *f, double t0, double period,
                            const usm_floquet_options *opt, double *B)
{
    const int n = f->n, nn = n * n;
    double Psi[NN], W[NN];
    if (variational_coordinates(f, t0) != 0) {
        snprintf(f->msg, USM_MSG_LEN, "linearisation at t0 is singular or not finite");
        return USM_EFAILED;
    }
    /* after variational_coordinates, f->G = S G(t0) S^{-1} */
    memcpy(f->Ga, f->G->data, sizeof(double) * (size_t)nn);
    /* constant (twist_integrated) or affine in t (the paper's twist law)?
     * Checked at the middle of the period rather than trusted. */
    if (balanced_coefficient_matrix(f, t0 + 0.5 * period) != 0) {
        snprintf(f->msg, USM_MSG_LEN, "linearisation at t0 + T/2 is singular or not finite");
        return USM_EFAILED;
    }
    memcpy(W, f->G->data, sizeof(double) * (size_t)nn);
    int constant = 0;
    f->affine = 0;
    if (f->m->t0_independent) {
        for (int k = 0; k < nn; ++k)
            Psi[k] = W[k] - f->Ga[k];
        constant = max_abs(nn, Psi) <= 1e-12 * max_abs(nn, f->Ga);
    }
    if (!constant) {
        if (balanced_coefficient_matrix(f, t0 + period) != 0) {
            snprintf(f->msg, USM_MSG_LEN, "linearisation at t0 + T is singular or not finite");
            return USM_EFAILED;
        }
        memcpy(f->Gb, f->G->data, sizeof(double) * (size_t)nn);
        for (int k = 0; k < nn; ++k)
            Psi[k] = W[k] - 0.5 * (f->Ga[k] + f->Gb[k]);
        f->affine = max_abs(nn, Psi) <= 1e-12 * fmax(max_abs(nn, f->Ga), max_abs(nn, f->Gb));
        if (f->affine) {
            for (int k = 0; k < nn; ++k)
                W[k] = f->Gb[k] - f->Ga[k];
            commutator(n, f->Ga, W, f->K);
            commutator(n, f->Ga, f->K, f->L0);
            commutator(n, W, f->K, f->L1);
        }
    }
    f->magnus_steps = 0;
    if (constant) {
        for (int k = 0; k < nn; ++k)
            W[k] = period * f->Ga[k];
        if (usm_expm_dense(n, W, Psi) != 0) {
            snprintf(f->msg, USM_MSG_LEN, "matrix exponential of the linearisation failed");
            return USM_EFAILED;
        }
    } else {
        /* multipliers to 1e-2 rtol (1e-10 by default: ten correct digits,
         * bench/usm_bench), not below the rounding errors' 1e-13 */
        const double tol = fmax(1e-2 * opt->rtol, 1e-13);
        if ((f->affine && kick_nilpotent(f) ? kick_adaptive(f, period, tol, Psi)
                                           : magnus_adaptive(f, t0, period, tol, Psi)) != 0)
            return USM_EFAILED;
    }
    /* B = S^{-1} Psi S */
    memcpy(f->Psi, Psi, sizeof(double) * (size_t)nn);
    usm_matmul_dense(n, f->Sinv->data, Psi, W);
    usm_matmul_dense(n, W, f->S->data, B);
    return USM_OK;
}

/* ---- eigenvalues -------------------------------------------------------------- */

/* The multipliers from Psi (solve/multipliers.h: the eigenvalues of B are
 * computed from Psi = S B S^{-1}, the cyclic directions S e_i split off). */
static int multipliers(usm_floquet *f, usm_floquet_result *out)
{
    if (!f->eval_valid && usm_multipliers_eigen(f->mult, f->Psi, f->msg) != 0)
        return USM_EFAILED;
    usm_multipliers_result(f->mult, out);
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
    if (!(opt->rtol >= 1e-14 && opt->rtol <= 1e-3)) {
        snprintf(f->msg, USM_MSG_LEN, "rtol: must be in [1e-14, 1e-3], got %g", opt->rtol);
        return USM_EINPUT;
    }
    if (opt->steps < 1 || opt->steps > USM_FLOQUET_MAX_STEPS) {
        snprintf(f->msg, USM_MSG_LEN, "steps: must be 1 to %d, got %d", USM_FLOQUET_MAX_STEPS,
                 opt->steps);
        return USM_EINPUT;
    }
    if (!(opt->atol >= 0 && opt->atol < 1)) {
        snprintf(f->msg, USM_MSG_LEN, "atol: must be in [0, 1), got %g", opt->atol);
        return USM_EINPUT;
    }
    /* the linearisation about the stationary orbit: the ideal motor only */
    if (usm_params_check_ideal(p, f->msg) != USM_OK)
        return USM_EINPUT;
    f->p = *p;
    f->eval_valid = 0;
    memcpy(f->u, sol->u, sizeof f->u);
    f->beta = sol->beta;
    const double period = 1.0 / p->f;
    memset(out, 0, sizeof *out);
    out->t0 = t0;
    out->t0_dependent = !f->m->t0_independent;
    const usm_floquet_method method = opt->method == USM_FLOQUET_AUTO ? USM_FLOQUET_MAGNUS
                                                                        : opt->method;
    int rc;
    out->method = method;
    switch (method) {
    case USM_FLOQUET_VARIATIONAL:
        rc = monodromy_variational(f, t0, period, opt, out->monodromy);
        break;
    case USM_FLOQUET_EXPONENTIAL:
        rc = monodromy_exponential(f, t0, period, opt->steps, out->monodromy);
        break;
    case USM_FLOQUET_MAGNUS:
        rc = monodromy_magnus(f, t0, period, opt, out->monodromy);
        /* AUTO: where the Magnus series diverges (a stiff linearisation,
         * |A| T far above pi: d_R = 1e10 N s/m), the product of exponentials
         * copes; it is slower, not less safe */
        if (rc != USM_OK && opt->method == USM_FLOQUET_AUTO) {
            out->method = USM_FLOQUET_EXPONENTIAL;
            f->msg[0] = '\0';
            rc = monodromy_exponential(f, t0, period, opt->steps, out->monodromy);
        }
        break;
    default:
        snprintf(f->msg, USM_MSG_LEN, "method: unknown Floquet method %d", (int)opt->method);
        return USM_EINPUT;
    }
    if (rc != USM_OK)
        return rc;
    for (int i = 0; i < f->n * f->n; ++i)
        if (!isfinite(out->monodromy[i])) {
            snprintf(f->msg, USM_MSG_LEN, "monodromy matrix is not finite");
            return USM_EFAILED;
        }
    return multipliers(f, out);
}

/* Every root of the last solve in turn, with the same method and t0 as one
 * root alone: out[k] is bit for bit usm_floquet_compute of root k. */
int usm_floquet_roots(usm_floquet *f, const usm_params *p, const usm_steady *s, double t0,
                      const usm_floquet_options *opt, usm_floquet_result *out)
{
    const size_t n = usm_steady_count(s);
    f->msg[0] = '\0';
    for (size_t k = 0; k < n; ++k) {
        const usm_steady_solution *root = usm_steady_root(s, k);
        int rc = usm_floquet_compute(f, p, root, t0, opt, &out[k]);
        if (rc != USM_OK) {
            char why[USM_MSG_LEN];
            snprintf(why, sizeof why, "%s", f->msg);
            snprintf(f->msg, USM_MSG_LEN, "root #%zu (theta = %.6g rad): %.200s", k + 1, root->theta,
                     why);
            return rc;
        }
    }
    return USM_OK;
}

const char *usm_steady_nonfinite(const usm_steady_solution *s, const usm_floquet_result *f)
{
    const double v[] = {s->theta, s->alpha, s->beta, s->rotor_speed, s->F_n, s->F_t,
                        s->v_c, s->v_rel, s->R_star, s->Z, s->mu_used};
    for (size_t k = 0; k < sizeof v / sizeof v[0]; ++k)
        if (!isfinite(v[k]))
            return "steady: the stationary solution has a non-finite value";
    for (int k = 0; k < f->n; ++k)
        if (!isfinite(f->re[k]) || !isfinite(f->im[k]))
            return "floquet: a multiplier is not finite";
    if (!isfinite(f->max_modulus))
        return "floquet: the largest modulus is not finite";
    return NULL;
}

/* ---- the cost floor (solve/floquet_floor.h) ------------------------------------ */

int usm_floquet_floor_setup(usm_floquet *f, const usm_params *p, const usm_steady_solution *sol,
                            double t0, double *A)
{
    f->p = *p;
    memcpy(f->u, sol->u, sizeof f->u);
    f->beta = sol->beta;
    if (variational_coordinates(f, t0) != 0)
        return -1;
    for (int k = 0; k < f->n * f->n; ++k)
        A[k] = f->G->data[k] / p->f;
    return 0;
}

int usm_floquet_floor(usm_floquet *f, const double *A)
{
    double E[NN];
    if (usm_expm_dense(f->n, A, E) != 0)
        return -1;
    return usm_multipliers_eigen(f->mult, E, f->msg);
}
