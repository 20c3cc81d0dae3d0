/* tolerance_comm.h: the collective operations that the statistics of a
 * tolerance study (tolerance_stats.c) need from the ranks that share it.
 * The serial run is one rank (tol_comm_serial: copies); mpi/tolerance_mpi.c
 * provides the same operations over MPI_COMM_WORLD.  The statistics run one
 * code path on every rank count, and every result is computed from exact
 * integers or exact order statistics, so the output does not depend on the
 * number of ranks.  Not installed; not part of the API. */
#ifndef USM_TOLERANCE_COMM_H
#define USM_TOLERANCE_COMM_H

#include <stddef.h>
#include <stdint.h>

typedef struct tol_comm {
    int rank, size;
    void *ctx;
    /* v[0..n) summed over the ranks, on every rank.  0 or -1. */
    int (*sum_u64)(void *ctx, uint64_t *v, size_t n);
    /* every rank's `bytes` bytes, in rank order, into all (size x bytes).  0 or -1. */
    int (*allgather)(void *ctx, const void *mine, size_t bytes, void *all);
    /* send[scount[0] + ... ] to the ranks in order (scount[r] values to rank
     * r); recv gets rcount[r] values from rank r, in rank order (rcount from
     * an allgather of the counts).  0 or -1. */
    int (*alltoallv)(void *ctx, const uint64_t *send, const uint64_t *scount, uint64_t *recv,
                     const uint64_t *rcount);
} tol_comm;

/* One rank: the serial run's. */
extern const tol_comm tol_comm_serial;

#endif /* USM_TOLERANCE_COMM_H */
