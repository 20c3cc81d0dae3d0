/* floquet_floor.h: the cost floor of a Floquet computation, for the
 * benchmark (bench/usm_bench).  Internal; not installed. */
#ifndef USM_FLOQUET_FLOOR_H
#define USM_FLOQUET_FLOOR_H

#include "usm.h"

/* A = T S G(t0) S^{-1} for the stationary solution sol at p (the balanced
 * coefficient matrix the methods start from, times the period), n x n
 * row-major with n = the model's nx; f keeps the basis of its cyclic
 * directions.  0, or -1 when the linearisation is singular. */
int usm_floquet_floor_setup(usm_floquet *f, const usm_params *p, const usm_steady_solution *sol,
                            double t0, double *A);

/* The floor: exp(A) by the scaling and squaring every method uses, and the
 * multipliers' eigenproblem of the result, as a constant coefficient matrix
 * costs.  0, or -1. */
int usm_floquet_floor(usm_floquet *f, const double *A);

#endif /* USM_FLOQUET_FLOOR_H */
