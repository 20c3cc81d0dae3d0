/* The exponential of a small dense matrix (see dense.h). */
#include "dense.h"

#include <math.h>
#include <string.h>

#define NN (USM_EXPM_MAX_N * USM_EXPM_MAX_N)

/* C = A B with the order N known to the compiler (unrolled; dot products,
 * which GCC compiles better at these sizes than row updates). */
#define MATMUL_FIXED(N)                                                                            \
    static void matmul_##N(const double *A, const double *B, double *C)                            \
    {                                                                                              \
        for (int i = 0; i < N; ++i)                                                                \
            for (int j = 0; j < N; ++j) {                                                          \
                double c = 0;                                                                      \
                for (int k = 0; k < N; ++k)                                                        \
                    c += A[i * N + k] * B[k * N + j];                                              \
                C[i * N + j] = c;                                                                  \
            }                                                                                      \
    }
MATMUL_FIXED(6)
MATMUL_FIXED(7)
MATMUL_FIXED(8)
MATMUL_FIXED(9)

void usm_matmul_dense(int n, const double *A, const double *B, double *C)
{
    switch (n) { /* the orders of the generated models */
    case 6:
        matmul_6(A, B, C);
        return;
    case 7:
        matmul_7(A, B, C);
        return;
    case 8:
        matmul_8(A, B, C);
        return;
    case 9:
        matmul_9(A, B, C);
        return;
    default:
        break;
    }
    for (int i = 0; i < n; ++i) {
        double row[USM_EXPM_MAX_N] = {0};
        for (int k = 0; k < n; ++k) {
            const double a = A[i * n + k];
            for (int j = 0; j < n; ++j)
                row[j] += a * B[k * n + j];
        }
        memcpy(C + i * n, row, sizeof(double) * (size_t)n);
    }
}

void usm_balance_dense(int n, double *A, double *d)
{
    int again = 1;
    for (int i = 0; i < n; ++i)
        d[i] = 1.0;
    while (again) {
        again = 0;
        for (int i = 0; i < n; ++i) {
            double row = 0, col = 0;
            for (int j = 0; j < n; ++j)
                if (j != i) {
                    col += fabs(A[j * n + i]);
                    row += fabs(A[i * n + j]);
                }
            if (col == 0.0 || row == 0.0)
                continue;
            const double s = col + row;
            double f = 1.0, g = row / 2.0;
            while (col < g) {
                f *= 2.0;
                col *= 4.0;
            }
            g = row * 2.0;
            while (col > g) {
                f /= 2.0;
                col /= 4.0;
            }
            if (row + col < 0.95 * s * f) {
                again = 1;
                d[i] *= f;
                for (int j = 0; j < n; ++j) {
                    A[i * n + j] /= f;
                    A[j * n + i] *= f;
                }
            }
        }
    }
}

static double norm1(int n, const double *A)
{
    double best = 0;
    for (int j = 0; j < n; ++j) {
        double s = 0;
        for (int i = 0; i < n; ++i)
            s += fabs(A[i * n + j]);
        if (!(s <= best)) /* also propagates NaN */
            best = s;
    }
    return best;
}

int usm_lu_factor_dense(int n, double *A, int *piv)
{
    for (int k = 0; k < n; ++k) {
        int p = k;
        for (int i = k + 1; i < n; ++i)
            if (fabs(A[i * n + k]) > fabs(A[p * n + k]))
                p = i;
        if (!(A[p * n + k] != 0.0) || !isfinite(A[p * n + k]))
            return -1;
        piv[k] = p;
        if (p != k)
            for (int j = 0; j < n; ++j) {
                const double t = A[k * n + j];
                A[k * n + j] = A[p * n + j];
                A[p * n + j] = t;
            }
        for (int i = k + 1; i < n; ++i) {
            const double l = A[i * n + k] /= A[k * n + k];
            if (l == 0.0)
                continue;
            for (int j = k + 1; j < n; ++j)
                A[i * n + j] -= l * A[k * n + j];
        }
    }
    return 0;
}

/* Row by row (the inner loops run along a row of B, vectorised at -O3);
 * every entry of B sees the same operations in the same order as in the
 * column-by-column substitutions. */
void usm_lu_solve_dense(int n, const double *LU, const int *piv, double *B, int cols)
{
    for (int k = 0; k < n; ++k)
        if (piv[k] != k)
            for (int c = 0; c < cols; ++c) {
                const double t = B[k * cols + c];
                B[k * cols + c] = B[piv[k] * cols + c];
                B[piv[k] * cols + c] = t;
            }
    for (int k = 0; k < n; ++k)
        for (int i = k + 1; i < n; ++i) {
            const double l = LU[i * n + k];
            if (l == 0.0)
                continue;
            for (int c = 0; c < cols; ++c)
                B[i * cols + c] -= l * B[k * cols + c];
        }
    for (int k = n - 1; k >= 0; --k)
        for (int c = 0; c < cols; ++c) {
            double s = B[k * cols + c];
            for (int i = k + 1; i < n; ++i)
                s -= LU[k * n + i] * B[i * cols + c];
            B[k * cols + c] = s / LU[k * n + k];
        }
}

int usm_invert_dense(int n, double *A, int *piv, double *Ainv)
{
    if (usm_lu_factor_dense(n, A, piv) != 0)
        return -1;
    for (int i = 0; i < n * n; ++i)
        Ainv[i] = 0.0;
    for (int i = 0; i < n; ++i)
        Ainv[i * n + i] = 1.0;
    usm_lu_solve_dense(n, A, piv, Ainv, n);
    return 0;
}

int usm_solve_dense(int n, double *Q, double *X)
{
    int piv[USM_EXPM_MAX_N];
    if (usm_lu_factor_dense(n, Q, piv) != 0)
        return -1;
    usm_lu_solve_dense(n, Q, piv, X, n);
    return 0;
}

/* Higham (2005), Table 2.3 and the coefficients of the [m/m] Pade approximants */
static const double theta[] = {1.495585217958292e-2, 2.539398330063230e-1,
                               9.504178996162932e-1, 2.097847961257068e0, 5.371920351148152e0};
static const double b3[] = {120., 60., 12., 1.};
static const double b5[] = {30240., 15120., 3360., 420., 30., 1.};
static const double b7[] = {17297280., 8648640., 1995840., 277200., 25200., 1512., 56., 1.};
static const double b9[] = {17643225600., 8821612800., 2075673600., 302702400., 30270240.,
                            2162160.,     110880.,     3960.,       90.,        1.};
static const double b13[] = {64764752532480000., 32382376266240000., 7771770303897600.,
                             1187353796428800.,  129060195264000.,   10559470521600.,
                             670442572800.,      33522128640.,       1323241920.,
                             40840800.,          960960.,            16380.,
                             182.,               1.};

/* The squarings s and the Pade degree m (with its coefficients b) for a
 * matrix of 1-norm a1: the lowest degree good to double precision unscaled,
 * else degree 13 after s squarings. */
static int pade_squarings(double a1)
{
    return a1 > theta[4] ? (int)ceil(log2(a1 / theta[4])) : 0;
}

static int pade_degree(double a1, int s, const double **b)
{
    static const double *const coef[] = {b3, b5, b7, b9};
    for (int k = 0; s == 0 && k < 4; ++k)
        if (a1 <= theta[k]) {
            *b = coef[k];
            return 2 * k + 3;
        }
    *b = b13;
    return 13;
}

int usm_expm_dense(int n, const double *A, double *E)
{
    double As[NN], P[5][NN], U[NN], V[NN], W[NN];
    const int nn = n * n;
    if (n < 1 || n > USM_EXPM_MAX_N)
        return -1;
    const double a1 = norm1(n, A);
    if (!isfinite(a1))
        return -1;
    const int s = pade_squarings(a1);
    const double scale = ldexp(1.0, -s);
    for (int k = 0; k < nn; ++k)
        As[k] = A[k] * scale;
    /* P[0] = I, P[1] = A^2, P[2] = A^4, P[3] = A^6, P[4] = A^8 */
    memset(P[0], 0, sizeof(double) * (size_t)nn);
    for (int i = 0; i < n; ++i)
        P[0][i * n + i] = 1.0;
    usm_matmul_dense(n, As, As, P[1]);
    const double *b;
    const int m = pade_degree(a1, s, &b);
    if (m >= 5)
        usm_matmul_dense(n, P[1], P[1], P[2]);
    if (m >= 7)
        usm_matmul_dense(n, P[2], P[1], P[3]);
    if (m == 9)
        usm_matmul_dense(n, P[3], P[1], P[4]);
    if (m < 13) {
        /* U = A sum b[2k+1] A^{2k},  V = sum b[2k] A^{2k} */
        memset(W, 0, sizeof W);
        memset(V, 0, sizeof V);
        for (int k = 0; 2 * k <= m; ++k)
            for (int e = 0; e < nn; ++e) {
                W[e] += b[2 * k + 1] * P[k][e];
                V[e] += b[2 * k] * P[k][e];
            }
        usm_matmul_dense(n, As, W, U);
    } else {
        double X[NN];
        /* U = A [A6 (b13 A6 + b11 A4 + b9 A2) + b7 A6 + b5 A4 + b3 A2 + b1 I]
         * V =    A6 (b12 A6 + b10 A4 + b8 A2) + b6 A6 + b4 A4 + b2 A2 + b0 I */
        for (int e = 0; e < nn; ++e)
            X[e] = b[13] * P[3][e] + b[11] * P[2][e] + b[9] * P[1][e];
        usm_matmul_dense(n, P[3], X, W);
        for (int e = 0; e < nn; ++e)
            W[e] += b[7] * P[3][e] + b[5] * P[2][e] + b[3] * P[1][e] + b[1] * P[0][e];
        usm_matmul_dense(n, As, W, U);
        for (int e = 0; e < nn; ++e)
            X[e] = b[12] * P[3][e] + b[10] * P[2][e] + b[8] * P[1][e];
        usm_matmul_dense(n, P[3], X, V);
        for (int e = 0; e < nn; ++e)
            V[e] += b[6] * P[3][e] + b[4] * P[2][e] + b[2] * P[1][e] + b[0] * P[0][e];
    }
    /* (V - U) E = V + U */
    for (int e = 0; e < nn; ++e) {
        W[e] = V[e] - U[e];
        E[e] = V[e] + U[e];
    }
    if (usm_solve_dense(n, W, E) != 0)
        return -1;
    for (int k = 0; k < s; ++k) {
        usm_matmul_dense(n, E, E, W);
        memcpy(E, W, sizeof(double) * (size_t)nn);
    }
    for (int e = 0; e < nn; ++e)
        if (!isfinite(E[e]))
            return -1;
    return 0;
}

/* ---- the exponential with its Frechet derivative ------------------------------ */

/* A block upper triangular matrix [[a, b], [0, a]]: products, sums and
 * solves of such matrices stay in the form, at three n x n products per
 * product instead of the eight of the 2n x 2n matrix. */
typedef struct block_pair {
    double a[NN], b[NN];
} block_pair;

static void pair_mul(int n, const block_pair *X, const block_pair *Y, block_pair *Z)
{
    double t[NN];
    usm_matmul_dense(n, X->a, Y->a, Z->a);
    usm_matmul_dense(n, X->a, Y->b, Z->b);
    usm_matmul_dense(n, X->b, Y->a, t);
    for (int e = 0; e < n * n; ++e)
        Z->b[e] += t[e];
}

int usm_expm_frechet_dense(int n, const double *A, const double *C, double *E, double *L)
{
    block_pair As, P[5], U, V, W, X;
    const int nn = n * n;
    if (n < 1 || n > USM_EXPM_MAX_N)
        return -1;
    /* the 1-norm of [[A, C], [0, A]], as the 2n x 2n exponential would take it */
    double a1 = 0;
    for (int j = 0; j < n; ++j) {
        double left = 0, right = 0;
        for (int i = 0; i < n; ++i) {
            left += fabs(A[i * n + j]);
            right += fabs(A[i * n + j]) + fabs(C[i * n + j]);
        }
        if (!(left <= a1))
            a1 = left;
        if (!(right <= a1))
            a1 = right;
    }
    if (!isfinite(a1))
        return -1;
    const int s = pade_squarings(a1);
    const double scale = ldexp(1.0, -s);
    for (int k = 0; k < nn; ++k) {
        As.a[k] = A[k] * scale;
        As.b[k] = C[k] * scale;
    }
    memset(&P[0], 0, sizeof P[0]);
    for (int i = 0; i < n; ++i)
        P[0].a[i * n + i] = 1.0;
    pair_mul(n, &As, &As, &P[1]);
    const double *b;
    const int m = pade_degree(a1, s, &b);
    if (m >= 5)
        pair_mul(n, &P[1], &P[1], &P[2]);
    if (m >= 7)
        pair_mul(n, &P[2], &P[1], &P[3]);
    if (m == 9)
        pair_mul(n, &P[3], &P[1], &P[4]);
    if (m < 13) {
        memset(&W, 0, sizeof W);
        memset(&V, 0, sizeof V);
        for (int k = 0; 2 * k <= m; ++k)
            for (int e = 0; e < nn; ++e) {
                W.a[e] += b[2 * k + 1] * P[k].a[e];
                W.b[e] += b[2 * k + 1] * P[k].b[e];
                V.a[e] += b[2 * k] * P[k].a[e];
                V.b[e] += b[2 * k] * P[k].b[e];
            }
        pair_mul(n, &As, &W, &U);
    } else {
        for (int e = 0; e < nn; ++e) {
            X.a[e] = b[13] * P[3].a[e] + b[11] * P[2].a[e] + b[9] * P[1].a[e];
            X.b[e] = b[13] * P[3].b[e] + b[11] * P[2].b[e] + b[9] * P[1].b[e];
        }
        pair_mul(n, &P[3], &X, &W);
        for (int e = 0; e < nn; ++e) {
            W.a[e] += b[7] * P[3].a[e] + b[5] * P[2].a[e] + b[3] * P[1].a[e] + b[1] * P[0].a[e];
            W.b[e] += b[7] * P[3].b[e] + b[5] * P[2].b[e] + b[3] * P[1].b[e];
        }
        pair_mul(n, &As, &W, &U);
        for (int e = 0; e < nn; ++e) {
            X.a[e] = b[12] * P[3].a[e] + b[10] * P[2].a[e] + b[8] * P[1].a[e];
            X.b[e] = b[12] * P[3].b[e] + b[10] * P[2].b[e] + b[8] * P[1].b[e];
        }
        pair_mul(n, &P[3], &X, &V);
        for (int e = 0; e < nn; ++e) {
            V.a[e] += b[6] * P[3].a[e] + b[4] * P[2].a[e] + b[2] * P[1].a[e] + b[0] * P[0].a[e];
            V.b[e] += b[6] * P[3].b[e] + b[4] * P[2].b[e] + b[2] * P[1].b[e];
        }
    }
    /* (V - U) R = V + U, block by block: Qa Ra = Pa, Qa Rb = Pb - Qb Ra
     * (one factorisation of Qa for both) */
    double Q[NN], R[2][NN];
    int piv[USM_EXPM_MAX_N];
    for (int e = 0; e < nn; ++e) {
        Q[e] = V.a[e] - U.a[e];
        R[0][e] = V.a[e] + U.a[e];
    }
    if (usm_lu_factor_dense(n, Q, piv) != 0)
        return -1;
    usm_lu_solve_dense(n, Q, piv, R[0], n);
    usm_matmul_dense(n, V.b, R[0], X.a);
    usm_matmul_dense(n, U.b, R[0], X.b);
    for (int e = 0; e < nn; ++e)
        R[1][e] = V.b[e] + U.b[e] - (X.a[e] - X.b[e]);
    usm_lu_solve_dense(n, Q, piv, R[1], n);
    memcpy(W.a, R[0], sizeof(double) * (size_t)nn);
    memcpy(W.b, R[1], sizeof(double) * (size_t)nn);
    for (int k = 0; k < s; ++k) {
        pair_mul(n, &W, &W, &X);
        memcpy(W.a, X.a, sizeof(double) * (size_t)nn);
        memcpy(W.b, X.b, sizeof(double) * (size_t)nn);
    }
    for (int e = 0; e < nn; ++e) {
        if (!isfinite(W.a[e]) || !isfinite(W.b[e]))
            return -1;
        E[e] = W.a[e];
        L[e] = W.b[e];
    }
    return 0;
}
