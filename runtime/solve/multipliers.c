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

int usm_multipliers_eigen(usm_multipliers *w, const double *Psi, char msg[USM_MSG_LEN])
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
    gsl_eigen_nonsymm_params(0, 1, w->eig); /* balance before QR */
    if (gsl_eigen_nonsymm(w->R, w->eval, w->eig) != GSL_SUCCESS) {
        snprintf(msg, USM_MSG_LEN, "eigenvalues of the monodromy matrix did not converge");
        return -1;
    }
    return 0;
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
