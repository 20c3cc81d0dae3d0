/* Parameter sensitivities of a stationary solution (usm_design.h).
 *
 * Stationary outputs: du/dp = -(dr/du)^-1 dr/dp (implicit function theorem on
 * the generated Jacobians), dy/dp = dy/du du/dp + dy/dp|_u.
 *
 * max_modulus: B = S^-1 Bh S with Bh = E_N ... E_1, E_k = exp(X_k),
 * X_k = S G(t_k) S^-1 h, G = M^-1 A the coefficient matrix of the
 * linearisation at the midpoint t_k, S the (fixed) well-conditioned coordinates
 * of floquet.c.  Multipliers do not depend on S, so dlambda = w^T dBh v / (w^T v)
 * with S held at its nominal value.  For C = alpha beta^T (alpha, beta the
 * adjoint and forward products of a, b through the other factors)
 *     sum_ij C_ij dE_k,ij = sum_ij L(X_k^T, C)_ij dX_k,ij
 * (L the Frechet derivative of exp: L(X, E) is the upper right block of
 * exp([[X, E], [0, X]])), so one block exponential per sub-interval (two for a
 * complex multiplier) serves every parameter; each parameter then costs one
 * call of the generated floquet_direction per sub-interval.
 */
#include <complex.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_eigen.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_linalg.h>
#include <gsl/gsl_matrix.h>

#include "core/dense.h"
#include "usm_design.h"

#define NMAX USM_MAX_NX
#define NN (NMAX * NMAX)
#define MAX_STEPS (3 * USM_SENSITIVITY_STEPS) /* N and 2N sub-intervals */
/* relative distance below which two multipliers count as repeated */
#define REPEATED_TOL 1e-6

static const char *const output_names[USM_SENS_COUNT] = {
    "theta", "rotor_speed", "F_n", "F_t", "efficiency", "stick_margin", "max_modulus",
    "power_in", "power_out"};

const char *usm_sensitivity_output_name(int k)
{
    return k >= 0 && k < USM_SENS_COUNT ? output_names[k] : NULL;
}

int usm_sensitivity_output_find(const char *name)
{
    for (int k = 0; k < USM_SENS_COUNT; ++k)
        if (strcmp(name, output_names[k]) == 0)
            return k;
    return -1;
}

void usm_sensitivity_outputs_default(int want[USM_SENS_COUNT])
{
    for (int k = 0; k < USM_SENS_COUNT; ++k)
        want[k] = k <= USM_SENS_MAX_MODULUS;
}

/* One sub-interval of the product. */
typedef struct step {
    double t;                 /* midpoint */
    double Minv[NN];          /* (M T^-1)^-1 */
    double G[NN];             /* Gy = (M T^-1)^-1 A T^-1 */
    double Gh[NN];            /* D^-1 Gy D */
    double E[NN];             /* exp(Gh h) */
} step;

struct usm_sensitivity {
    const usm_model *m;
    int n;
    double t0;                        /* start of the period (usm_sensitivity_set_t0) */
    char msg[USM_MSG_LEN];
    step *steps;                      /* MAX_STEPS */
    double complex (*WA)[NN], (*WM)[NN]; /* weights of dA and dM per step */
    double complex *wh;               /* weight of dh per step */
    double complex *alpha, *beta;     /* MAX_STEPS x n */
    double T[NN], Tinv[NN]; /* tangent map on the orbit and its inverse */
    double d[NMAX];         /* balancing: Gh = D^-1 Gy D */
    gsl_matrix *work;
    gsl_vector *dscale;
    gsl_eigen_nonsymmv_workspace *eig;
    gsl_vector_complex *evalr, *evall;
    gsl_matrix_complex *evecr, *evecl;
};

usm_sensitivity *usm_sensitivity_alloc(const usm_model *m)
{
    usm_sensitivity *s = calloc(1, sizeof *s);
    if (!s)
        return NULL;
    const size_t n = (size_t)m->nx;
    s->m = m;
    s->n = m->nx;
    s->steps = malloc(sizeof(step) * MAX_STEPS);
    s->WA = malloc(sizeof *s->WA * MAX_STEPS);
    s->WM = malloc(sizeof *s->WM * MAX_STEPS);
    s->wh = malloc(sizeof *s->wh * MAX_STEPS);
    s->alpha = malloc(sizeof *s->alpha * MAX_STEPS * NMAX);
    s->beta = malloc(sizeof *s->beta * MAX_STEPS * NMAX);
    s->work = gsl_matrix_alloc(n, n);
    s->dscale = gsl_vector_alloc(n);
    s->eig = gsl_eigen_nonsymmv_alloc(n);
    s->evalr = gsl_vector_complex_alloc(n);
    s->evall = gsl_vector_complex_alloc(n);
    s->evecr = gsl_matrix_complex_alloc(n, n);
    s->evecl = gsl_matrix_complex_alloc(n, n);
    if (!s->steps || !s->WA || !s->WM || !s->wh || !s->alpha || !s->beta || !s->work ||
        !s->dscale ||
        !s->eig || !s->evalr || !s->evall || !s->evecr || !s->evecl) {
        usm_sensitivity_free(s);
        return NULL;
    }
    return s;
}

void usm_sensitivity_free(usm_sensitivity *s)
{
    if (!s)
        return;
    free(s->steps);
    free(s->WA);
    free(s->WM);
    free(s->wh);
    free(s->alpha);
    free(s->beta);
    gsl_matrix_free(s->work);
    gsl_vector_free(s->dscale);
    if (s->eig)
        gsl_eigen_nonsymmv_free(s->eig);
    gsl_vector_complex_free(s->evalr);
    gsl_vector_complex_free(s->evall);
    gsl_matrix_complex_free(s->evecr);
    gsl_matrix_complex_free(s->evecl);
    free(s);
}

void usm_sensitivity_set_t0(usm_sensitivity *s, double t0)
{
    s->t0 = t0;
}

const char *usm_sensitivity_message(const usm_sensitivity *s)
{
    return s->msg;
}

/* out = A^-1 (row-major n x n) with core/dense.h's LU. */
static int invert(usm_sensitivity *s, const double *A, double *out)
{
    const int n = s->n;
    double lu[NN];
    int piv[NMAX];
    memcpy(lu, A, sizeof(double) * (size_t)(n * n));
    if (usm_invert_dense(n, lu, piv, out) != 0)
        return -1;
    for (int i = 0; i < n * n; ++i)
        if (!isfinite(out[i]))
            return -1;
    return 0;
}

/* ---- stationary outputs ------------------------------------------------------ */

static int steady_part(usm_sensitivity *s, const usm_params *p, const usm_steady_solution *sol,
                       double dudp[USM_MAX_NU][USM_NPARAMS], usm_sensitivity_result *out)
{
    const usm_model *m = s->m;
    const int nu = m->nu;
    double J[USM_MAX_NU * USM_MAX_NU], Jp[USM_MAX_NU * USM_NPARAMS];
    double D[USM_DESIGN_COUNT * (USM_MAX_NU + USM_NPARAMS)];
    m->steady_jacobian(sol->u, p, J);
    m->steady_jacobian_params(sol->u, p, Jp);
    m->steady_design_jacobian(sol->u, p, D);
    int piv[USM_MAX_NU];
    int bad = usm_lu_factor_dense(nu, J, piv) != 0;
    /* a fold: the root does not move smoothly with the parameters */
    if (!bad) {
        double umin = INFINITY, umax = 0;
        for (int i = 0; i < nu; ++i) {
            const double d = fabs(J[i * nu + i]);
            umin = fmin(umin, d);
            umax = fmax(umax, d);
        }
        bad = !(umin > 1e-14 * umax);
    }
    if (!bad) {
        /* every parameter's right-hand side in one solve */
        for (int i = 0; i < nu * USM_NPARAMS; ++i)
            Jp[i] = -Jp[i];
        usm_lu_solve_dense(nu, J, piv, Jp, USM_NPARAMS);
        for (int i = 0; i < nu; ++i)
            for (int k = 0; k < USM_NPARAMS; ++k) {
                dudp[i][k] = Jp[i * USM_NPARAMS + k];
                if (!isfinite(dudp[i][k]))
                    bad = 1;
            }
    }
    if (bad) {
        snprintf(s->msg, USM_MSG_LEN,
                 "the residual Jacobian dr/du is singular at this solution (a fold): "
                 "du/dp does not exist");
        return USM_EFAILED;
    }
    const double *Du = D + m->steady_design_jacobian_out.du;
    const double *Dp = D + m->steady_design_jacobian_out.dp;
    double dy[USM_DESIGN_COUNT][USM_NPARAMS];
    for (int r = 0; r < USM_DESIGN_COUNT; ++r)
        for (int k = 0; k < USM_NPARAMS; ++k) {
            double acc = Dp[r * USM_NPARAMS + k];
            for (int i = 0; i < nu; ++i)
                acc += Du[r * nu + i] * dudp[i][k];
            dy[r][k] = acc;
        }
    const double Pin = sol->power_in, eff = sol->efficiency;
    out->value[USM_SENS_THETA] = sol->theta;
    out->value[USM_SENS_ROTOR_SPEED] = sol->rotor_speed;
    out->value[USM_SENS_F_N] = sol->F_n;
    out->value[USM_SENS_F_T] = sol->F_t;
    out->value[USM_SENS_EFFICIENCY] = eff;
    out->value[USM_SENS_STICK_MARGIN] = p->mu0 * sol->F_n - sol->F_t;
    out->value[USM_SENS_POWER_IN] = sol->power_in;
    out->value[USM_SENS_POWER_OUT] = sol->power_out;
    for (int k = 0; k < USM_NPARAMS; ++k) {
        out->d[USM_SENS_THETA][k] = dudp[m->u_theta][k];
        out->d[USM_SENS_ROTOR_SPEED][k] = dy[USM_DESIGN_ROTOR_SPEED][k];
        out->d[USM_SENS_F_N][k] = dy[USM_DESIGN_F_N][k];
        out->d[USM_SENS_F_T][k] = dy[USM_DESIGN_F_T][k];
        out->d[USM_SENS_POWER_IN][k] = dy[USM_DESIGN_POWER_IN][k];
        out->d[USM_SENS_POWER_OUT][k] = dy[USM_DESIGN_POWER_OUT][k];
        out->d[USM_SENS_EFFICIENCY][k] =
            (dy[USM_DESIGN_POWER_OUT][k] - eff * dy[USM_DESIGN_POWER_IN][k]) / Pin;
        out->d[USM_SENS_STICK_MARGIN][k] = p->mu0 * dy[USM_DESIGN_F_N][k] - dy[USM_DESIGN_F_T][k] +
                                           (k == USM_P_mu0 ? sol->F_n : 0.0);
    }
    for (int k = 0; k < USM_SENS_COUNT; ++k)
        out->defined[k] = k != USM_SENS_MAX_MODULUS;
    if (!(Pin > 0) || !isfinite(eff)) {
        out->defined[USM_SENS_EFFICIENCY] = 0;
        snprintf(out->why[USM_SENS_EFFICIENCY], USM_MSG_LEN,
                 "power_in <= 0: the efficiency is not defined");
    }
    return USM_OK;
}

/* ---- max_modulus ----------------------------------------------------------------- */

/* The coefficient matrix on the orbit at time t in the coordinates y = T x
 * (T the tangent map, constant on the orbit): Gy = (M T^-1)^-1 (A T^-1).  M T^-1
 * is well conditioned (the frame-A rows of Euler's equations are I_A T qddot +
 * ...), unlike M, whose inverse would lose ~8 digits near theta = 1e-4.
 * Gh = D^-1 Gy D with the balancing D of coordinates(). */
static int coefficients(usm_sensitivity *s, const usm_params *p, const usm_steady_solution *sol,
                        double t, step *st)
{
    const int n = s->n;
    const usm_model *m = s->m;
    double orbit[2 * NMAX], lin[3 * NN], A[NN], Mt[NN], At[NN];
    m->steady_state(sol->u, sol->beta, t, p, orbit);
    m->linearisation(orbit + m->steady_state_out.x, orbit + m->steady_state_out.xdot, t, p, lin);
    const double *M = lin + m->linearisation_out.mass;
    const double *Jf = lin + m->linearisation_out.jac_rhs;
    const double *Jm = lin + m->linearisation_out.jac_mass;
    for (int i = 0; i < n * n; ++i)
        A[i] = Jf[i] - Jm[i];
    usm_matmul_dense(n, M, s->Tinv, Mt);
    usm_matmul_dense(n, A, s->Tinv, At);
    if (invert(s, Mt, st->Minv) != 0)
        return -1;
    usm_matmul_dense(n, st->Minv, At, st->G);
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
            st->Gh[i * n + j] = st->G[i * n + j] * s->d[j] / s->d[i];
    st->t = t;
    return 0;
}

/* T (tangent map) and its inverse, and D balancing Gy(t0) (as floquet.c). */
static int coordinates(usm_sensitivity *s, const usm_params *p, const usm_steady_solution *sol)
{
    const int n = s->n;
    double orbit[2 * NMAX];
    step st;
    s->m->steady_state(sol->u, sol->beta, s->t0, p, orbit);
    s->m->tangent_map(orbit + s->m->steady_state_out.x, p, s->T);
    for (int i = 0; i < n; ++i)
        s->d[i] = 1.0;
    if (invert(s, s->T, s->Tinv) != 0 || coefficients(s, p, sol, s->t0, &st) != 0)
        return -1;
    gsl_matrix_view Gv = gsl_matrix_view_array(st.G, (size_t)n, (size_t)n);
    if (gsl_linalg_balance_matrix(&Gv.matrix, s->dscale) != GSL_SUCCESS)
        return -1;
    for (int i = 0; i < n; ++i)
        s->d[i] = gsl_vector_get(s->dscale, (size_t)i);
    return 0;
}

/* E = exp(X), X = Gh h, balanced as in floquet.c. */
static int expm(usm_sensitivity *s, const double *Gh, double h, double *E)
{
    const int n = s->n;
    double X[NN], Eb[NN], d[NMAX];
    for (int i = 0; i < n * n; ++i)
        X[i] = Gh[i] * h;
    /* dense.c's Pade exponential: several times faster than GSL's at n <= 9 */
    usm_balance_dense(n, X, d);
    if (usm_expm_dense(n, X, Eb) != 0)
        return -1;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
            E[i * n + j] = Eb[i * n + j] * d[i] / d[j];
    return 0;
}

/* K = L(X^T, C) for real C: upper right block of exp([[X^T, C], [0, X^T]]).
 * C is scaled to unit size first (L is linear in C) so that it does not drive
 * the scaling-and-squaring. */
static int frechet_adjoint(usm_sensitivity *s, const double *X, const double *C, double *K)
{
    const int n = s->n;
    double c = 0;
    for (int i = 0; i < n * n; ++i)
        c = fmax(c, fabs(C[i]));
    if (c == 0) {
        memset(K, 0, sizeof(double) * (size_t)(n * n));
        return 0;
    }
    double XT[NN], Cs[NN], E[NN], L[NN];
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            XT[i * n + j] = X[j * n + i];
            Cs[i * n + j] = C[i * n + j] / c;
        }
    /* the block exponential in its block triangular form (dense.c): a third
     * of the work of the 2n x 2n one */
    if (usm_expm_frechet_dense(n, XT, Cs, E, L) != 0)
        return -1;
    for (int i = 0; i < n * n; ++i)
        K[i] = c * L[i];
    return 0;
}

/* Product of N exponentials over one period: fills steps[0..N) and Bh. */
static int product(usm_sensitivity *s, const usm_params *p, const usm_steady_solution *sol,
                   int N, step *steps, double *Bh)
{
    const int n = s->n;
    const double h = 1.0 / p->f / N;
    double W[NN];
    memset(Bh, 0, sizeof(double) * (size_t)(n * n));
    for (int i = 0; i < n; ++i)
        Bh[i * n + i] = 1;
    for (int k = 0; k < N; ++k) {
        if (coefficients(s, p, sol, s->t0 + (k + 0.5) * h, &steps[k]) != 0 ||
            expm(s, steps[k].Gh, h, steps[k].E) != 0)
            return -1;
        usm_matmul_dense(n, steps[k].E, Bh, W);
        memcpy(Bh, W, sizeof W[0] * (size_t)(n * n));
    }
    return 0;
}

/* Weights of one product (factor c of the Richardson combination) for the
 * functional a^T dBh b: WA, WM per step and wh (for dh). */
static int weights(usm_sensitivity *s, int N, const step *steps, double h, double c,
                   const double complex *a, const double complex *b, double complex (*WA)[NN],
                   double complex (*WM)[NN], double complex *wh, int complex_case)
{
    const int n = s->n;
    double complex *al = s->alpha, *be = s->beta;
    /* alpha_k = (E_N..E_{k+1})^T a, beta_k = E_{k-1}..E_1 b */
    memcpy(&al[(N - 1) * NMAX], a, sizeof(double complex) * (size_t)n);
    for (int k = N - 1; k > 0; --k)
        for (int j = 0; j < n; ++j) {
            double complex acc = 0;
            for (int i = 0; i < n; ++i)
                acc += steps[k].E[i * n + j] * al[k * NMAX + i];
            al[(k - 1) * NMAX + j] = acc;
        }
    memcpy(&be[0], b, sizeof(double complex) * (size_t)n);
    for (int k = 0; k + 1 < N; ++k)
        for (int i = 0; i < n; ++i) {
            double complex acc = 0;
            for (int j = 0; j < n; ++j)
                acc += steps[k].E[i * n + j] * be[k * NMAX + j];
            be[(k + 1) * NMAX + i] = acc;
        }
    for (int k = 0; k < N; ++k) {
        double X[NN], Cr[NN], Ci[NN], Kr[NN], Ki[NN];
        for (int i = 0; i < n * n; ++i)
            X[i] = steps[k].Gh[i] * h;
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j) {
                double complex cij = al[k * NMAX + i] * be[k * NMAX + j];
                Cr[i * n + j] = creal(cij);
                Ci[i * n + j] = cimag(cij);
            }
        if (frechet_adjoint(s, X, Cr, Kr) != 0)
            return -1;
        if (complex_case) {
            if (frechet_adjoint(s, X, Ci, Ki) != 0)
                return -1;
        } else
            memset(Ki, 0, sizeof Ki);
        /* sum K . dX with dX = D^-1 Minv (dA T^-1 - dM T^-1 Gy) D h + Gh dh:
         * Kt_ij = K_ij d_j / d_i, P = h Minv^T Kt, WA = P T^-T, WM = -P (T^-1 Gy)^T */
        double complex K[NN], P[NN];
        double TG[NN];
        double complex whk = 0;
        for (int i = 0; i < n * n; ++i) {
            K[i] = Kr[i] + I * Ki[i];
            whk += K[i] * steps[k].Gh[i];
        }
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j)
                K[i * n + j] *= s->d[j] / s->d[i];
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j) {
                double complex acc = 0;
                for (int l = 0; l < n; ++l)
                    acc += steps[k].Minv[l * n + i] * K[l * n + j];
                P[i * n + j] = h * acc;
            }
        usm_matmul_dense(n, s->Tinv, steps[k].G, TG);
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j) {
                double complex a1 = 0, a2 = 0;
                for (int l = 0; l < n; ++l) {
                    a1 += P[i * n + l] * s->Tinv[j * n + l];
                    a2 += P[i * n + l] * TG[j * n + l];
                }
                WA[k][i * n + j] = c * a1;
                WM[k][i * n + j] = -c * a2;
            }
        wh[k] = c * whk;
    }
    return 0;
}

/* Eigenvalues/vectors of Bh; pick the non-cyclic multiplier of largest modulus. */
static int pick_multiplier(usm_sensitivity *s, const double *Bh, double complex *lambda,
                           double complex *a, double complex *b, usm_sensitivity_result *out)
{
    const int n = s->n;
    gsl_matrix_view Bv = gsl_matrix_view_array(s->work->data, (size_t)n, (size_t)n);
    memcpy(s->work->data, Bh, sizeof(double) * (size_t)(n * n));
    gsl_eigen_nonsymmv_params(1, s->eig);
    if (gsl_eigen_nonsymmv(&Bv.matrix, s->evalr, s->evecr, s->eig) != GSL_SUCCESS)
        return -1;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
            s->work->data[i * n + j] = Bh[j * n + i];
    if (gsl_eigen_nonsymmv(&Bv.matrix, s->evall, s->evecl, s->eig) != GSL_SUCCESS)
        return -1;
    double complex ev[NMAX];
    int cyc[NMAX] = {0}, ncyc = 0;
    for (int i = 0; i < n; ++i) {
        gsl_complex z = gsl_vector_complex_get(s->evalr, (size_t)i);
        ev[i] = GSL_REAL(z) + I * GSL_IMAG(z);
        ncyc += s->m->cyclic[i] != 0;
    }
    /* a cyclic coordinate contributes an exact multiplier 1 (floquet.c) */
    for (int c = 0; c < ncyc; ++c) {
        int best = -1;
        for (int i = 0; i < n; ++i)
            if (!cyc[i] && (best < 0 || cabs(ev[i] - 1) < cabs(ev[best] - 1)))
                best = i;
        cyc[best] = 1;
    }
    int r = -1;
    for (int i = 0; i < n; ++i) {
        if (cyc[i])
            continue;
        if (r < 0 || cabs(ev[i]) > cabs(ev[r]) * (1 + 1e-12) ||
            (cabs(ev[i]) >= cabs(ev[r]) * (1 - 1e-12) && cimag(ev[i]) > cimag(ev[r])))
            r = i;
    }
    *lambda = ev[r];
    out->value[USM_SENS_MAX_MODULUS] = cabs(ev[r]);
    out->multiplier_re = creal(ev[r]);
    out->multiplier_im = cimag(ev[r]);
    for (int i = 0; i < n; ++i)
        if (i != r && cabs(ev[i] - ev[r]) <= REPEATED_TOL * fmax(cabs(ev[r]), 1e-3)) {
            snprintf(out->why[USM_SENS_MAX_MODULUS], USM_MSG_LEN,
                     "repeated multiplier pair (%.10g%+.10gi and %.10g%+.10gi): the largest "
                     "modulus is not differentiable here",
                     creal(ev[r]), cimag(ev[r]), creal(ev[i]), cimag(ev[i]));
            return 1;
        }
    /* another multiplier (not the conjugate) of the same modulus: the largest
     * modulus is the maximum of two smooth functions and has a kink here */
    for (int i = 0; i < n; ++i)
        if (i != r && !cyc[i] && cabs(ev[i] - conj(ev[r])) > REPEATED_TOL * cabs(ev[r]) &&
            fabs(cabs(ev[i]) - cabs(ev[r])) <= REPEATED_TOL * cabs(ev[r])) {
            snprintf(out->why[USM_SENS_MAX_MODULUS], USM_MSG_LEN,
                     "two multipliers of equal modulus (%.10g%+.10gi and %.10g%+.10gi): the "
                     "largest modulus has a kink here, no derivative",
                     creal(ev[r]), cimag(ev[r]), creal(ev[i]), cimag(ev[i]));
            return 1;
        }
    /* left eigenvector: eigenvector of Bh^T for the same eigenvalue */
    int l = 0;
    for (int i = 1; i < n; ++i) {
        gsl_complex zi = gsl_vector_complex_get(s->evall, (size_t)i);
        gsl_complex zl = gsl_vector_complex_get(s->evall, (size_t)l);
        if (cabs(GSL_REAL(zi) + I * GSL_IMAG(zi) - ev[r]) <
            cabs(GSL_REAL(zl) + I * GSL_IMAG(zl) - ev[r]))
            l = i;
    }
    for (int i = 0; i < n; ++i) {
        gsl_complex vr = gsl_matrix_complex_get(s->evecr, (size_t)i, (size_t)r);
        gsl_complex vl = gsl_matrix_complex_get(s->evecl, (size_t)i, (size_t)l);
        b[i] = GSL_REAL(vr) + I * GSL_IMAG(vr);
        a[i] = GSL_REAL(vl) + I * GSL_IMAG(vl);
    }
    double complex wv = 0;
    for (int i = 0; i < n; ++i)
        wv += a[i] * b[i];
    /* |w^T v| of unit vectors: 1 / the eigenvalue's condition number */
    if (cabs(wv) < 1e-8) {
        snprintf(out->why[USM_SENS_MAX_MODULUS], USM_MSG_LEN,
                 "the multiplier %.10g%+.10gi is defective (nearly repeated): the largest "
                 "modulus is not differentiable here",
                 creal(ev[r]), cimag(ev[r]));
        return 1;
    }
    for (int i = 0; i < n; ++i)
        a[i] /= wv;
    return 0;
}

static int modulus_part(usm_sensitivity *s, const usm_params *p, const usm_steady_solution *sol,
                        double dudp[USM_MAX_NU][USM_NPARAMS], usm_sensitivity_result *out)
{
    const int n = s->n;
    const int single = s->m->t0_independent;
    const int N1 = single ? 1 : USM_SENSITIVITY_STEPS, N2 = 2 * N1;
    step *st1 = s->steps, *st2 = s->steps + N1;
    double B1[NN], B2[NN], Bh[NN];
    if (coordinates(s, p, sol) != 0 || product(s, p, sol, N1, st1, B1) != 0 ||
        (!single && product(s, p, sol, N2, st2, B2) != 0)) {
        snprintf(s->msg, USM_MSG_LEN, "matrix exponential of the linearisation failed");
        return USM_EFAILED;
    }
    for (int i = 0; i < n * n; ++i)
        Bh[i] = single ? B1[i] : (4.0 * B2[i] - B1[i]) / 3.0;
    double complex lambda, a[NMAX], b[NMAX];
    int rc = pick_multiplier(s, Bh, &lambda, a, b, out);
    if (rc < 0) {
        snprintf(s->msg, USM_MSG_LEN, "eigenvectors of the monodromy matrix did not converge");
        return USM_EFAILED;
    }
    if (rc > 0)
        return USM_OK; /* defined = 0, why set */
    const int cplx = cimag(lambda) != 0;
    const double T = 1.0 / p->f;
    if (weights(s, N1, st1, T / N1, single ? 1.0 : -1.0 / 3.0, a, b, s->WA, s->WM, s->wh,
                cplx) != 0 ||
        (!single && weights(s, N2, st2, T / N2, 4.0 / 3.0, a, b, s->WA + N1, s->WM + N1,
                            s->wh + N1, cplx) != 0)) {
        snprintf(s->msg, USM_MSG_LEN, "Frechet derivative of the matrix exponential failed");
        return USM_EFAILED;
    }
    const int nsteps = single ? N1 : N1 + N2;
    for (int j = 0; j < USM_NPARAMS; ++j) {
        usm_params dp;
        double du[USM_MAX_NU];
        memset(&dp, 0, sizeof dp);
        *usm_params_field(&dp, &usm_param_table[j]) = 1.0;
        for (int i = 0; i < s->m->nu; ++i)
            du[i] = dudp[i][j];
        const double dT = j == USM_P_f ? -T / p->f : 0.0;
        double complex dl = 0;
        for (int k = 0; k < nsteps; ++k) {
            const int N = k < N1 ? N1 : N2;
            const int kk = k < N1 ? k : k - N1;
            const double dh = dT / N;
            double d[2 * NN];
            s->m->floquet_direction(sol->u, s->steps[k].t, du, (kk + 0.5) * dh, p, &dp, d);
            const double *dM = d + s->m->floquet_direction_out.dM;
            const double *dA = d + s->m->floquet_direction_out.dA;
            double complex acc = s->wh[k] * dh;
            for (int i = 0; i < n * n; ++i)
                acc += s->WM[k][i] * dM[i] + s->WA[k][i] * dA[i];
            dl += acc;
        }
        /* d|lambda| = Re(conj(lambda) dlambda) / |lambda| */
        out->d[USM_SENS_MAX_MODULUS][j] = creal(conj(lambda) * dl) / cabs(lambda);
    }
    out->defined[USM_SENS_MAX_MODULUS] = 1;
    return USM_OK;
}

int usm_sensitivity_max_modulus(usm_sensitivity *s, const usm_params *p,
                                const usm_steady_solution *sol, double *value)
{
    const int n = s->n;
    const int single = s->m->t0_independent;
    const int N1 = single ? 1 : USM_SENSITIVITY_STEPS, N2 = 2 * N1;
    double B1[NN], B2[NN], Bh[NN];
    usm_sensitivity_result *r = malloc(sizeof *r);
    s->msg[0] = '\0';
    if (!r) {
        snprintf(s->msg, USM_MSG_LEN, "out of memory");
        return USM_EFAILED;
    }
    int rc = USM_OK;
    if (coordinates(s, p, sol) != 0 || product(s, p, sol, N1, s->steps, B1) != 0 ||
        (!single && product(s, p, sol, N2, s->steps + N1, B2) != 0)) {
        snprintf(s->msg, USM_MSG_LEN, "matrix exponential of the linearisation failed");
        rc = USM_EFAILED;
    } else {
        double complex lambda, a[NMAX], b[NMAX];
        for (int i = 0; i < n * n; ++i)
            Bh[i] = single ? B1[i] : (4.0 * B2[i] - B1[i]) / 3.0;
        if (pick_multiplier(s, Bh, &lambda, a, b, r) < 0) {
            snprintf(s->msg, USM_MSG_LEN, "eigenvectors of the monodromy matrix did not converge");
            rc = USM_EFAILED;
        } else
            *value = cabs(lambda);
    }
    free(r);
    return rc;
}

int usm_sensitivity_compute(usm_sensitivity *s, const usm_params *p,
                            const usm_steady_solution *sol, int floquet,
                            usm_sensitivity_result *out)
{
    double dudp[USM_MAX_NU][USM_NPARAMS];
    s->msg[0] = '\0';
    memset(out, 0, sizeof *out);
    if (s->m->imperfect) {
        /* its stationary kernels are the ideal motor's: the derivatives in the
         * imperfections would read 0, yet off 0 no stationary solution exists */
        snprintf(s->msg, USM_MSG_LEN,
                 "model %s: sensitivities of the stationary solution are defined for the ideal "
                 "motor only; use the variant twist_integrated", s->m->name);
        return USM_EINPUT;
    }
    int rc = steady_part(s, p, sol, dudp, out);
    out->value[USM_SENS_MAX_MODULUS] = NAN;
    snprintf(out->why[USM_SENS_MAX_MODULUS], USM_MSG_LEN, "not computed");
    if (rc != USM_OK || !floquet)
        return rc;
    out->why[USM_SENS_MAX_MODULUS][0] = '\0';
    return modulus_part(s, p, sol, dudp, out);
}
