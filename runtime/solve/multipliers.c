/* Monodromy -> Floquet multipliers (see multipliers.h). */
#include "multipliers.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_eigen.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_linalg.h>
#include <gsl/gsl_matrix.h>

#include "core/dense.h"

#define NN (USM_MAX_NX * USM_MAX_NX)

struct usm_multipliers {
    const usm_model *m;
    int n, nk;                    /* all and the non-cyclic multipliers */
    gsl_matrix *Vc, *Qc, *Rc;     /* the cyclic columns of S and their QR (NULL: none) */
    gsl_vector *qr_tau;
    gsl_matrix *R;                /* the non-cyclic block of Qc^T Psi Qc */
    gsl_eigen_nonsymm_workspace *eig;
    gsl_vector_complex *eval;
};

void usm_multipliers_free(usm_multipliers *w)
{
    if (!w)
        return;
    if (w->Vc)
        gsl_matrix_free(w->Vc);
    if (w->Qc)
        gsl_matrix_free(w->Qc);
    if (w->Rc)
        gsl_matrix_free(w->Rc);
    if (w->qr_tau)
        gsl_vector_free(w->qr_tau);
    if (w->R)
        gsl_matrix_free(w->R);
    if (w->eig)
        gsl_eigen_nonsymm_free(w->eig);
    if (w->eval)
        gsl_vector_complex_free(w->eval);
    free(w);
}

usm_multipliers *usm_multipliers_alloc(const usm_model *m)
{
    usm_multipliers *w = calloc(1, sizeof *w);
    if (!w)
        return NULL;
    w->m = m;
    w->n = m->nx;
    for (int i = 0; i < m->nx; ++i)
        w->nk += !m->cyclic[i];
    const size_t n = (size_t)w->n, nc = (size_t)(w->n - w->nk);
    if (nc > 0) {
        w->Vc = gsl_matrix_alloc(n, nc);
        w->Rc = gsl_matrix_alloc(n, nc);
        w->Qc = gsl_matrix_alloc(n, n);
        w->qr_tau = gsl_vector_alloc(nc);
    }
    w->R = gsl_matrix_alloc((size_t)w->nk, (size_t)w->nk);
    w->eig = gsl_eigen_nonsymm_alloc((size_t)w->nk);
    w->eval = gsl_vector_complex_alloc((size_t)w->nk);
    if ((nc > 0 && (!w->Vc || !w->Rc || !w->Qc || !w->qr_tau)) || !w->R || !w->eig || !w->eval) {
        usm_multipliers_free(w);
        return NULL;
    }
    return w;
}

int usm_multipliers_basis(usm_multipliers *w, const double *S)
{
    const int n = w->n;
    if (!w->Vc)
        return 0;
    for (int k = 0, c = 0; k < n; ++k)
        if (w->m->cyclic[k]) {
            for (int i = 0; i < n; ++i)
                gsl_matrix_set(w->Vc, (size_t)i, (size_t)c, S[i * n + k]);
            ++c;
        }
    if (gsl_linalg_QR_decomp(w->Vc, w->qr_tau) != GSL_SUCCESS ||
        gsl_linalg_QR_unpack(w->Vc, w->qr_tau, w->Qc, w->Rc) != GSL_SUCCESS)
        return -1;
    return 0;
}

/* R, the non-cyclic block of Qc^T Psi Qc, into w->R. */
static void reduce(usm_multipliers *w, const double *Psi)
{
    const int n = w->n, nk = w->nk, nc = n - nk;
    if (nc == 0)
        memcpy(w->R->data, Psi, sizeof(double) * (size_t)(n * n));
    else {
        double Qt[NN], W[NN], E[NN];
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j)
                Qt[i * n + j] = w->Qc->data[j * n + i];
        usm_matmul_dense(n, Qt, Psi, W);
        usm_matmul_dense(n, W, w->Qc->data, E);
        for (int i = 0; i < nk; ++i)
            memcpy(w->R->data + i * nk, E + (nc + i) * n + nc, sizeof(double) * (size_t)nk);
    }
}

int usm_multipliers_reduced(usm_multipliers *w, const double *Psi, double *R)
{
    reduce(w, Psi);
    memcpy(R, w->R->data, sizeof(double) * (size_t)(w->nk * w->nk));
    return w->nk;
}

int usm_multipliers_eigen(usm_multipliers *w, const double *Psi, char msg[USM_MSG_LEN])
{
    reduce(w, Psi);
    gsl_eigen_nonsymm_params(0, 1, w->eig); /* balance before QR */
    if (gsl_eigen_nonsymm(w->R, w->eval, w->eig) != GSL_SUCCESS) {
        snprintf(msg, USM_MSG_LEN, "eigenvalues of the monodromy matrix did not converge");
        return -1;
    }
    return 0;
}

int usm_multipliers_roots(usm_multipliers *w, const double *Psi, int warm, double *re,
                          double *im)
{
    const int k = w->nk;
    double c[USM_MAX_NX + 1], M[NN], RM[NN];
    reduce(w, Psi);
    const double *R = w->R->data;
    /* Faddeev-LeVerrier: det(z I - R) = sum_j c[j] z^j, c[k] = 1 */
    c[k] = 1.0;
    memset(M, 0, sizeof M);
    for (int m = 1; m <= k; ++m) {
        for (int i = 0; i < k; ++i)
            M[i * k + i] += c[k - m + 1];
        usm_matmul_dense(k, R, M, RM);
        double tr = 0;
        for (int i = 0; i < k; ++i)
            tr += RM[i * k + i];
        c[k - m] = -tr / m;
        memcpy(M, RM, sizeof(double) * (size_t)(k * k));
    }
    /* Aberth-Ehrlich from points on a circle of the Cauchy bound's radius,
     * in real arithmetic: C's complex division (__divdc3) and cabs took more
     * time than the eigensolver this replaces */
    double zr[USM_MAX_NX], zi[USM_MAX_NX];
    double bound = 0;
    for (int j = 0; j < k; ++j)
        bound = fmax(bound, fabs(c[j]));
    const double radius = 0.5 * (1.0 + bound);
    for (int i = 0; i < k; ++i) {
        const double phi = 6.283185307179586 * (i + 0.25) / k;
        zr[i] = warm ? re[i] : radius * cos(phi);
        zi[i] = warm ? im[i] : radius * sin(phi);
    }
    for (int it = 0, last = 0; it < 200; ++it) {
        double moved2 = 0;
        for (int i = 0; i < k; ++i) {
            /* p(z) and p'(z) by Horner */
            double pr = c[k], pi = 0, dr = 0, di = 0;
            for (int j = k - 1; j >= 0; --j) {
                const double ndr = dr * zr[i] - di * zi[i] + pr, ndi = dr * zi[i] + di * zr[i] + pi;
                const double npr = pr * zr[i] - pi * zi[i] + c[j], npi = pr * zi[i] + pi * zr[i];
                dr = ndr;
                di = ndi;
                pr = npr;
                pi = npi;
            }
            if (pr == 0 && pi == 0)
                continue;
            /* ratio = p / p', s = sum 1 / (z_i - z_j) */
            const double d2 = dr * dr + di * di;
            const double rr = (pr * dr + pi * di) / d2, ri = (pi * dr - pr * di) / d2;
            double sr = 0, si = 0;
            for (int j = 0; j < k; ++j)
                if (j != i) {
                    const double xr = zr[i] - zr[j], xi = zi[i] - zi[j], x2 = xr * xr + xi * xi;
                    sr += xr / x2;
                    si -= xi / x2;
                }
            /* step = ratio / (1 - ratio s) */
            const double qr = 1.0 - (rr * sr - ri * si), qi = -(rr * si + ri * sr);
            const double q2 = qr * qr + qi * qi;
            const double str = (rr * qr + ri * qi) / q2, sti = (ri * qr - rr * qi) / q2;
            if (!isfinite(str) || !isfinite(sti))
                return -1;
            zr[i] -= str;
            zi[i] -= sti;
            moved2 = fmax(moved2, (str * str + sti * sti) /
                                      fmax(1.0, zr[i] * zr[i] + zi[i] * zi[i]));
        }
        /* cubic convergence: one sweep after a step of 1e-9 reaches rounding,
         * where the steps stay at a few ulps instead of vanishing */
        if (last) {
            memcpy(re, zr, sizeof(double) * (size_t)k);
            memcpy(im, zi, sizeof(double) * (size_t)k);
            return 0;
        }
        last = moved2 <= 1e-18;
    }
    return -1;
}

int usm_multipliers_count(const usm_multipliers *w) { return w->nk; }

void usm_multipliers_values(const usm_multipliers *w, double *re, double *im)
{
    for (int i = 0; i < w->nk; ++i) {
        const gsl_complex z = gsl_vector_complex_get(w->eval, (size_t)i);
        re[i] = GSL_REAL(z);
        im[i] = GSL_IMAG(z);
    }
}

typedef struct multiplier {
    double re, im, modulus;
    int cyclic;
} multiplier;

static int by_modulus_desc(const void *a, const void *b)
{
    const multiplier *x = a, *y = b;
    if (x->modulus != y->modulus)
        return (x->modulus < y->modulus) - (x->modulus > y->modulus);
    if (x->re != y->re)
        return (x->re < y->re) - (x->re > y->re);
    return (x->im < y->im) - (x->im > y->im);
}

void usm_multipliers_result(const usm_multipliers *w, usm_floquet_result *out)
{
    const int n = w->n;
    multiplier ms[USM_MAX_NX];
    int k = 0;
    for (int i = 0; i < n; ++i)
        if (w->m->cyclic[i])
            ms[k++] = (multiplier){1.0, 0.0, 1.0, 1};
    for (int i = 0; i < w->nk; ++i) {
        const gsl_complex z = gsl_vector_complex_get(w->eval, (size_t)i);
        ms[k++] = (multiplier){GSL_REAL(z), GSL_IMAG(z), hypot(GSL_REAL(z), GSL_IMAG(z)), 0};
    }
    qsort(ms, (size_t)n, sizeof ms[0], by_modulus_desc);
    out->n = n;
    out->max_modulus = 0;
    for (int i = 0; i < n; ++i) {
        out->re[i] = ms[i].re;
        out->im[i] = ms[i].im;
        out->cyclic[i] = ms[i].cyclic;
        if (!ms[i].cyclic)
            out->max_modulus = fmax(out->max_modulus, ms[i].modulus);
    }
    out->stable = out->max_modulus < 1.0;
}
