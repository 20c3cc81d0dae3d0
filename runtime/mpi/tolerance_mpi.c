/* Tolerance studies over MPI ranks (usm_mpi.h).
 *
 * Every rank knows the whole study (the same command line), so the block
 * lists are computed alike everywhere and only the rows travel: round r's
 * pending blocks are dealt round-robin (block k of the round to rank k mod
 * size), each rank computes its share with its threads, and MPI_Gatherv
 * brings the packed rows to rank 0, which unpacks them in the dealing order.
 * A sample is a pure function of (seed, i), so rank 0 ends with the rows a
 * serial run computes, bit for bit, and the same statistics. */
#include <mpi.h>
#include <stdlib.h>
#include <string.h>

#include "usm_mpi.h"
#include "study/tolerance_internal.h"

int usm_mpi_launched(void)
{
    return getenv("OMPI_COMM_WORLD_SIZE") || getenv("PMI_SIZE") || getenv("PMIX_RANK");
}

static int started_here;

int usm_mpi_start(int *rank, int *size, char msg[USM_MSG_LEN])
{
    int init = 0;
    if (MPI_Initialized(&init) != MPI_SUCCESS) {
        snprintf(msg, USM_MSG_LEN, "MPI_Initialized failed");
        return USM_EFAILED;
    }
    if (!init) {
        int provided;
        /* the pool's threads never call MPI: only the main thread does */
        if (MPI_Init_thread(NULL, NULL, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS) {
            snprintf(msg, USM_MSG_LEN, "MPI_Init failed");
            return USM_EFAILED;
        }
        started_here = 1;
        /* every way out of the command (an early error too) finalizes, as
         * mpirun requires of a rank that ends */
        atexit(usm_mpi_stop);
    }
    if (MPI_Comm_rank(MPI_COMM_WORLD, rank) != MPI_SUCCESS ||
        MPI_Comm_size(MPI_COMM_WORLD, size) != MPI_SUCCESS) {
        snprintf(msg, USM_MSG_LEN, "MPI_Comm_rank/size failed");
        return USM_EFAILED;
    }
    return USM_OK;
}

void usm_mpi_stop(void)
{
    int fin = 0;
    if (started_here && MPI_Finalized(&fin) == MPI_SUCCESS && !fin)
        MPI_Finalize();
    started_here = 0;
}

/* The worst status of all ranks; the message of the failing rank with the
 * lowest key goes to rank 0 (t->msg): the key is the failing block after
 * tol_compute (so that the lowest failing sample is named, as by a serial
 * run), else any (the lowest failing rank). */
static int agree_key(usm_tolerance *t, int status, uint64_t key, int rank, MPI_Comm comm)
{
    uint64_t mine = status != USM_OK ? key : UINT64_MAX, low = mine;
    int worst = status, who, first;
    if (MPI_Allreduce(&status, &worst, 1, MPI_INT, MPI_MAX, comm) != MPI_SUCCESS ||
        MPI_Allreduce(&mine, &low, 1, MPI_UINT64_T, MPI_MIN, comm) != MPI_SUCCESS) {
        snprintf(t->msg, USM_MSG_LEN, "MPI_Allreduce failed");
        return USM_EFAILED;
    }
    who = status != USM_OK && mine == low ? rank : 1 << 30;
    if (MPI_Allreduce(&who, &first, 1, MPI_INT, MPI_MIN, comm) != MPI_SUCCESS) {
        snprintf(t->msg, USM_MSG_LEN, "MPI_Allreduce failed");
        return USM_EFAILED;
    }
    if (worst == USM_OK)
        return USM_OK;
    if (first != 0 &&
        MPI_Bcast(t->msg, USM_MSG_LEN, MPI_CHAR, first, comm) != MPI_SUCCESS)
        snprintf(t->msg, USM_MSG_LEN, "rank %d failed (MPI_Bcast of its message failed)", first);
    return worst;
}

static int agree(usm_tolerance *t, int status, int rank, MPI_Comm comm)
{
    return agree_key(t, status, 0, rank, comm);
}

int usm_tolerance_run_mpi(usm_tolerance *t, const usm_params *p, const usm_tolerance_options *opt)
{
    MPI_Comm comm = MPI_COMM_WORLD;
    int rank, size, status;
    uint64_t *list = NULL, *mine = NULL, computed = 0;
    double *pack = NULL, *all = NULL;
    int *counts = NULL, *displs = NULL;
    if (MPI_Comm_rank(comm, &rank) != MPI_SUCCESS || MPI_Comm_size(comm, &size) != MPI_SUCCESS) {
        snprintf(t->msg, USM_MSG_LEN, "MPI_Comm_rank/size failed");
        return USM_EFAILED;
    }
    status = agree(t, tol_prepare(t, p, opt, rank == 0), rank, comm);
    if (status != USM_OK)
        return status;
    /* the blocks the checkpoint held: rank 0 read them */
    if (MPI_Bcast(t->done, (int)t->nblocks, MPI_UNSIGNED_CHAR, 0, comm) != MPI_SUCCESS) {
        snprintf(t->msg, USM_MSG_LEN, "MPI_Bcast failed");
        return USM_EFAILED;
    }
    const size_t round = 8 * (size_t)opt->threads * (size_t)size;
    const size_t per_rank = (round + (size_t)size - 1) / (size_t)size;
    const size_t row_doubles = USM_TOLERANCE_BLOCK * (size_t)t->width;
    int ok = (list = malloc(t->nblocks * sizeof *list)) != NULL &&
             (mine = malloc(per_rank * sizeof *mine)) != NULL &&
             (pack = malloc(per_rank * row_doubles * sizeof *pack)) != NULL &&
             (counts = malloc((size_t)size * sizeof *counts)) != NULL &&
             (displs = malloc((size_t)size * sizeof *displs)) != NULL &&
             (rank != 0 || (all = malloc(round * row_doubles * sizeof *all)) != NULL);
    if (!ok)
        snprintf(t->msg, USM_MSG_LEN, "out of memory on rank %d", rank);
    status = agree(t, ok ? USM_OK : USM_EFAILED, rank, comm);
    const size_t pending = status == USM_OK ? tol_pending(t, list) : 0;
    for (size_t at = 0; at < pending && status == USM_OK;) {
        size_t n = pending - at < round ? pending - at : round, nmine = 0;
        if (opt->stop_after_blocks && n > opt->stop_after_blocks - computed)
            n = (size_t)(opt->stop_after_blocks - computed);
        const uint64_t *blocks = list + at;
        for (size_t k = (size_t)rank; k < n; k += (size_t)size)
            mine[nmine++] = blocks[k];
        const int computed_st = tol_compute(t, mine, nmine, pack);
        status = agree_key(t, computed_st, t->fail_block, rank, comm);
        if (status != USM_OK)
            break;
        /* rank r's share: blocks r, r + size, ... of the round, packed */
        for (int r = 0, off = 0; r < size; ++r) {
            uint64_t d = 0;
            for (size_t k = (size_t)r; k < n; k += (size_t)size)
                d += tol_block_size(t, blocks[k]) * (uint64_t)t->width;
            counts[r] = (int)d;
            displs[r] = off;
            off += (int)d;
        }
        if (MPI_Gatherv(pack, counts[rank], MPI_DOUBLE, all, counts, displs, MPI_DOUBLE, 0,
                        comm) != MPI_SUCCESS) {
            snprintf(t->msg, USM_MSG_LEN, "MPI_Gatherv failed");
            status = USM_EFAILED;
            break;
        }
        if (rank == 0)
            for (int r = 0; r < size; ++r) {
                const double *src = all + displs[r];
                for (size_t k = (size_t)r; k < n; k += (size_t)size) {
                    tol_unpack(t, blocks + k, 1, src);
                    src += tol_block_size(t, blocks[k]) * (uint64_t)t->width;
                }
            }
        at += n;
        computed += n;
        const int stop = opt->stop_after_blocks && computed >= opt->stop_after_blocks &&
                         at < pending;
        int st = USM_OK;
        if (rank == 0 && tol_checkpoint_due(t, at == pending, stop))
            st = tol_checkpoint_write(t);
        status = agree(t, st, rank, comm);
        if (status == USM_OK && stop)
            status = tol_stopped(t, computed);
    }
    free(list);
    free(mine);
    free(pack);
    free(all);
    free(counts);
    free(displs);
    if (status == USM_OK && rank == 0)
        status = tol_finish(t);
    return status;
}
