/* tolerance_csv.h: the samples.csv of a tolerance study as text in memory
 * (tolerance_out.c): its header and its rows, for usm_tolerance_write_csv
 * and for the MPI writer (mpi/tolerance_mpi.c), which writes every rank's
 * rows into one file.  Not installed; not part of the API. */
#ifndef USM_TOLERANCE_CSV_H
#define USM_TOLERANCE_CSV_H

#include <stddef.h>
#include <stdint.h>

#include "usm_tolerance.h"

/* Bytes a row of t may take (with its newline; the bound of tol_csv_row). */
size_t tol_csv_row_max(const usm_tolerance *t);

/* The header line into buf (len bytes; 4096 hold any); its length. */
size_t tol_csv_header(const usm_tolerance *t, char *buf, size_t len);

/* The row of sample i (its doubles at row) into buf (tol_csv_row_max bytes);
 * its length. */
size_t tol_csv_row(const usm_tolerance *t, uint64_t i, const double *row, char *buf);

#endif /* USM_TOLERANCE_CSV_H */
