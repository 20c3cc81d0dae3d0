/* multipliers.h: monodromy -> Floquet multipliers, the one path of
 * floquet.c (stationary solutions) and periodic.c (periodic orbits).
 * Internal to libusm; not installed.
 *
 * Both compute the monodromy as Psi = S B S^{-1}, in the balanced
 * coordinates S = D^{-1} T of the variational integration (T the generated
 * tangent map).  The multipliers, the eigenvalues of B, are computed from
 * Psi: S is as ill-conditioned as the Euler angles (about 1/theta^2), so B
 * itself carries rounding errors of cond(S) eps relative to Psi, and so
 * would its eigenvalues.  A cyclic coordinate i gives B e_i = e_i, so Psi
 * fixes S e_i: with the orthogonal Qc whose first columns span these
 * vectors (QR of them, usm_multipliers_basis), Qc^T Psi Qc = [I *; 0 R], and
 * the other multipliers are the eigenvalues of R (usm_multipliers_eigen);
 * the cyclic ones are exactly 1 and reported as such.
 */
#ifndef USM_SOLVE_MULTIPLIERS_H
#define USM_SOLVE_MULTIPLIERS_H

#include "usm.h"

/* The workspace of one model: the basis Qc and GSL's eigensolver. */
typedef struct usm_multipliers usm_multipliers;

/* For model m, or NULL when out of memory. */
usm_multipliers *usm_multipliers_alloc(const usm_model *m);
/* Free w; NULL is allowed. */
void usm_multipliers_free(usm_multipliers *w);

/* The basis Qc from S (n x n row-major): the QR factorisation of its
 * columns S e_i, i cyclic (nothing to do for a model without cyclic
 * coordinates).  0, or -1 when GSL's QR fails. */
int usm_multipliers_basis(usm_multipliers *w, const double *S);

/* R, the non-cyclic block of Qc^T Psi Qc (nk x nk row-major, nk the
 * non-cyclic multipliers' count, returned): the monodromy with the cyclic
 * directions deflated, whose eigenvalues the multipliers are. */
int usm_multipliers_reduced(usm_multipliers *w, const double *Psi, double *R);

/* The non-cyclic multipliers: the eigenvalues of R from Psi (n x n
 * row-major) and the basis of the last usm_multipliers_basis.  0, or -1 with
 * msg when the eigensolver does not converge. */
int usm_multipliers_eigen(usm_multipliers *w, const double *Psi, char msg[USM_MSG_LEN]);

/* The non-cyclic multipliers of Psi without the eigensolver, for an error
 * estimate: the roots of the characteristic polynomial of the same reduced
 * matrix (Faddeev-LeVerrier, then Aberth-Ehrlich iterations), into re and
 * im (usm_multipliers_count each); with warm, the iterations start from
 * re and im (the multipliers of a nearby Psi), else from a circle.  Good to about 1e-12 for the moduli of
 * order one Floquet multipliers have, far below the differences an error
 * estimate compares; 0, or -1 when the iterations do not converge (the
 * caller uses usm_multipliers_eigen then). */
int usm_multipliers_roots(usm_multipliers *w, const double *Psi, int warm, double *re,
                          double *im);

/* The number of non-cyclic multipliers, and those of the last
 * usm_multipliers_eigen into re and im (that many each), in the
 * eigensolver's order. */
int usm_multipliers_count(const usm_multipliers *w);
void usm_multipliers_values(const usm_multipliers *w, double *re, double *im);

/* All n multipliers of the last usm_multipliers_eigen into out (n, re, im,
 * cyclic, max_modulus, stable), sorted by decreasing modulus (ties: by
 * decreasing real, then imaginary part); the other fields are left alone. */
void usm_multipliers_result(const usm_multipliers *w, usm_floquet_result *out);

#endif /* USM_SOLVE_MULTIPLIERS_H */
