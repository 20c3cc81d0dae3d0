/* dense.h: small dense matrix kernels of the Floquet analysis (internal to
 * libusm): product, LU factorisation and solve, balancing and the
 * exponential of row-major n x n matrices, n <= USM_EXPM_MAX_N.  Plain loops
 * on arrays: at these sizes they are several times faster than GSL's general
 * routines.
 *
 * The exponential: scaling and squaring with the diagonal Pade approximant of degree 3, 5, 7,
 * 9 or 13 chosen from the 1-norm (N. J. Higham, "The scaling and squaring
 * method for the matrix exponential revisited", SIAM J. Matrix Anal. Appl. 26
 * (2005) 1179-1193): backward error below the unit roundoff in exact
 * arithmetic.  For the at most 9 x 9 matrices of the Floquet analysis it costs
 * a few microseconds; the caller balances the matrix first.
 */
#ifndef USM_DENSE_H
#define USM_DENSE_H

/* Largest order handled. */
#define USM_EXPM_MAX_N 9

/* E = exp(A), both n x n row-major (E may not alias A), 1 <= n <= USM_EXPM_MAX_N.
 * 0, or -1 when A is not finite or the Pade denominator is singular. */
int usm_expm_dense(int n, const double *A, double *E);

/* E = exp(A) and L = L(A, C), the Frechet derivative of exp at A in the
 * direction C (the upper right block of exp([[A, C], [0, A]])), all n x n
 * row-major, 1 <= n <= USM_EXPM_MAX_N: the scaling and squaring of
 * usm_expm_dense carried out on the block triangular matrix, whose blocks
 * stay in that form (Al-Mohy and Higham, SIAM J. Matrix Anal. Appl. 30 (2009)
 * 1639-1657, use the same structure); the degree and scaling are chosen from
 * the block matrix's 1-norm.  0, or -1 as usm_expm_dense. */
int usm_expm_frechet_dense(int n, const double *A, const double *C, double *E, double *L);

/* C = A B, n x n row-major (C may not alias A or B). */
void usm_matmul_dense(int n, const double *A, const double *B, double *C);

/* The one dense LU of libusm.  A = P^T L U with partial pivoting, in place
 * (n x n row-major, any n): L (unit diagonal) below the
 * diagonal, U on and above it, the row exchanged with row k at step k in
 * piv[k].  0, or -1 when a pivot is zero or not finite. */
int usm_lu_factor_dense(int n, double *A, int *piv);

/* B <- A^{-1} B from the factors of usm_lu_factor_dense; B is n x cols
 * row-major (cols = 1: a vector). */
void usm_lu_solve_dense(int n, const double *LU, const int *piv, double *B, int cols);

/* Ainv = A^{-1}, both n x n row-major (Ainv may not alias A): A is
 * overwritten by its factors and piv (n entries) by its pivots, as
 * usm_lu_factor_dense; the columns of the identity solved for with
 * usm_lu_solve_dense.  0, or -1 as the factorisation. */
int usm_invert_dense(int n, double *A, int *piv, double *Ainv);

/* X <- Q^{-1} X, both n x n row-major: usm_lu_factor_dense (Q is
 * overwritten by its factors) and usm_lu_solve_dense.  0, or -1 as the
 * factorisation. */
int usm_solve_dense(int n, double *Q, double *X);

/* A <- D^{-1} A D with D = diag(d) powers of 2 that make the off-diagonal
 * row and column norms of A nearly equal (Parlett and Reinsch; the
 * algorithm of GSL's gsl_linalg_balance_matrix). */
void usm_balance_dense(int n, double *A, double *d);

#endif /* USM_DENSE_H */
