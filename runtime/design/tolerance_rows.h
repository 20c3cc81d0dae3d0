/* tolerance_rows.h: the state of a tolerance study and its rows of samples,
 * the floor that the other parts of the study (tolerance.c, write/tolerance_checkpoint.c,
 * tolerance_stats.c, ../mpi/tolerance_mpi.c) stand on.  Not installed; not
 * part of the API.
 *
 * Under MPI (or any tol_comm of several ranks) every rank keeps the rows of
 * its own blocks only: rank r of S owns the contiguous blocks [blo, bhi) =
 * [nblocks r / S, nblocks (r + 1) / S) (tol_owned), so the memory per rank is
 * O(samples / S) and the ranks' rows, concatenated in rank order, are the
 * serial run's.  A serial run is rank 0 of 1.
 *
 * The samples are kept as rows of doubles, one per sample, in sample order:
 *   [0, nvary)            the varied parameters' values
 *   nvary + k             output k (USM_TOL_NOUTPUTS; NaN where it does not exist)
 *   nvary + NOUTPUTS      good: 1 counts for the yield; 0 does not; TOL_GOOD_DRIVEN
 *                         (-1) does not for one reason alone, the load drives the
 *                         rotor backwards (power_out < 0; the summary's `driven`)
 *   nvary + NOUTPUTS + 1  redraws of this sample
 * A row of plain doubles is what the checkpoint and MPI move, bit for bit. */
#ifndef USM_TOLERANCE_ROWS_H
#define USM_TOLERANCE_ROWS_H

#include <stddef.h>
#include <stdint.h>

#include "core/progress.h"
#include "usm_tolerance.h"

#define TOL_MAX_SPECS 64
/* Bins of each histogram of `usm tolerance --out`'s figure */
#define TOL_HIST_BINS 40
/* Draws of one sample before the study gives up; a row's redraws are below. */
#define TOL_MAX_REDRAWS 10000
#define TOL_ROW_GOOD(t) ((t)->nvary + USM_TOL_NOUTPUTS)
#define TOL_ROW_REDRAWS(t) ((t)->nvary + USM_TOL_NOUTPUTS + 1)
/* The `good` of a sample good in every other respect whose load drives its
 * rotor backwards (yield_rule.h: *driven): a row holds no power_out, so it
 * keeps this fact itself, for the count and the checkpoint's check. */
#define TOL_GOOD_DRIVEN (-1.0)

struct usm_tolerance {
    const usm_model *m;
    usm_tolerance_vary vary[USM_NPARAMS];
    int nvary;
    usm_tolerance_spec spec[TOL_MAX_SPECS];
    int nspec;
    /* the run */
    usm_params p;
    usm_tolerance_options opt;
    int width;              /* doubles per row: nvary + USM_TOL_NOUTPUTS + 2 */
    uint64_t nblocks;
    unsigned char *done;    /* per block: computed (or read from the checkpoint); every
                               rank knows its own blocks' */
    int rank, size;         /* this rank of `size` (serial: 0 of 1) */
    uint64_t blo, bhi;      /* the blocks this rank owns: [blo, bhi) */
    double *rows;           /* the owned blocks' samples x width, from sample blo * BLOCK */
    char *config;           /* the study's configuration text (checkpoint header) */
    double last_write;      /* monotonic time of the last checkpoint write [s] */
    double write_seconds;   /* how long that write took */
    int lock_fd;            /* the checkpoint's lock (usm_outfile_lock), or -1 */
    uint64_t fail_block;    /* the block whose failure t->msg names (tol_compute), or
                               UINT64_MAX: under MPI the lowest one is reported */
    /* wall seconds of each phase of the last run (usm_tolerance_timings) */
    usm_tolerance_timings timings;
    progress_meter meter;   /* samples done (serial run only: under MPI it stays silent) */
    /* the result */
    int have_result;
    /* the figure's histograms (tol_finish): TOL_HIST_BINS bins of equal width over
     * [lo, hi], the range of every rank's samples, of rotor_speed (0) and
     * max_modulus (1); the figure reads these counts, not the samples */
    struct {
        double lo, hi;
        uint64_t total;
        uint64_t count[TOL_HIST_BINS];
    } hist[2];
    usm_tolerance_summary sum;
    double influence[USM_TOL_NNUMERIC][USM_NPARAMS];
    char msg[USM_MSG_LEN];
};

/* The blocks [*lo, *hi) that rank r of size owns. */
void tol_owned(uint64_t nblocks, int r, int size, uint64_t *lo, uint64_t *hi);

/* The rows of block b (owned by this rank). */
double *tol_block_rows(const usm_tolerance *t, uint64_t b);

/* Samples this rank owns (the rows in t->rows). */
uint64_t tol_local_samples(const usm_tolerance *t);

/* Samples in block b. */
uint64_t tol_block_size(const usm_tolerance *t, uint64_t b);

/* Doubles that the rows of the n blocks listed take. */
uint64_t tol_pack_size(const usm_tolerance *t, const uint64_t *blocks, size_t n);

/* Copy the packed rows of the n blocks listed into t->rows; mark them done. */
void tol_unpack(usm_tolerance *t, const uint64_t *blocks, size_t n, const double *pack);

/* This rank's blocks not done yet, in increasing order, into list (bhi - blo
 * room); returns how many. */
size_t tol_pending(const usm_tolerance *t, uint64_t *list);

/* Whether the outputs out (USM_TOL_NOUTPUTS) meet every --spec. */
int tol_meets_specs(const usm_tolerance *t, const double *out);

/* Whether a row's outputs allow it to be good: every part of the rule of
 * yield_rule.h (the operating point exists, is stable, valid and meets the
 * specs) but the last, the sign of power_out, which the row does not hold
 * (its `good` says it: TOL_GOOD_DRIVEN). */
int tol_row_allows_good(const usm_tolerance *t, const double *row);

/* Seconds on a monotonic clock. */
double tol_now(void);
/* The process's CPU seconds so far (every thread). */
double tol_cpu(void);

#endif /* USM_TOLERANCE_ROWS_H */
