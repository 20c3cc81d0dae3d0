/* Tolerance studies over MPI ranks (usm_mpi.h).
 *
 * Every rank knows the whole study (the same command line) and owns a
 * contiguous range of blocks (tol_owned: rank r of S the blocks [nblocks r /
 * S, nblocks (r + 1) / S)), computes them in rounds of 8 x threads blocks
 * with its threads, keeps their rows and writes its own checkpoint file
 * (write/tolerance_checkpoint.c).  No row travels: after every round the ranks agree on
 * the status (MPI_Allreduce) and, on rank 0's clock, whether to checkpoint;
 * the statistics are reductions, exact order statistics and a sample sort
 * (design/tolerance_stats.c over the collectives below), and samples.csv is
 * written by all ranks into one file with MPI-IO, each at the offset of its
 * rows (usm_tolerance_write_csv_mpi).  A sample is a pure function of (seed,
 * i) and every statistic is exact, so the output is the serial run's, byte
 * for byte. */
#include <limits.h>
#include <mpi.h>
#include <stdlib.h>
#include <string.h>

#include "usm_mpi.h"
#include "design/tolerance_internal.h"
#include "write/tolerance_checkpoint.h"
#include "write/tolerance_csv.h"

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

/* ---- the collectives of the statistics (design/tolerance_comm.h) ------------------------ */

static int m_sum(void *ctx, uint64_t *v, size_t n)
{
    if (n > INT_MAX)
        return -1;
    return MPI_Allreduce(MPI_IN_PLACE, v, (int)n, MPI_UINT64_T, MPI_SUM, *(MPI_Comm *)ctx) ==
                   MPI_SUCCESS ? 0 : -1;
}

static int m_allgather(void *ctx, const void *mine, size_t bytes, void *all)
{
    if (bytes > INT_MAX)
        return -1;
    return MPI_Allgather(mine, (int)bytes, MPI_BYTE, all, (int)bytes, MPI_BYTE,
                         *(MPI_Comm *)ctx) == MPI_SUCCESS ? 0 : -1;
}

static int m_alltoallv(void *ctx, const uint64_t *send, const uint64_t *scount, uint64_t *recv,
                       const uint64_t *rcount)
{
    MPI_Comm comm = *(MPI_Comm *)ctx;
    int size, rc = -1, fits = 1;
    MPI_Comm_size(comm, &size);
    int *sc = malloc((size_t)size * sizeof *sc), *sd = malloc((size_t)size * sizeof *sd),
        *rcn = malloc((size_t)size * sizeof *rcn), *rd = malloc((size_t)size * sizeof *rd);
    uint64_t so = 0, ro = 0;
    for (int r = 0; sc && sd && rcn && rd && r < size; ++r) {
        fits &= so + scount[r] <= INT_MAX && ro + rcount[r] <= INT_MAX;
        sc[r] = (int)scount[r];
        sd[r] = (int)so;
        rcn[r] = (int)rcount[r];
        rd[r] = (int)ro;
        so += scount[r];
        ro += rcount[r];
    }
    /* MPI counts are ints: more than 2^31 values per rank need more ranks */
    if (sc && sd && rcn && rd && fits)
        rc = MPI_Alltoallv(send, sc, sd, MPI_UINT64_T, recv, rcn, rd, MPI_UINT64_T, comm) ==
                     MPI_SUCCESS ? 0 : -1;
    free(sc);
    free(sd);
    free(rcn);
    free(rd);
    return rc;
}

/* ---- the run ----------------------------------------------------------------------------- */

int usm_tolerance_run_mpi(usm_tolerance *t, const usm_params *p, const usm_tolerance_options *opt)
{
    MPI_Comm comm = MPI_COMM_WORLD;
    int rank, size, status;
    uint64_t *list = NULL, *pend = NULL, *taken = NULL, *take = NULL, computed = 0;
    double *pack = NULL;
    if (MPI_Comm_rank(comm, &rank) != MPI_SUCCESS || MPI_Comm_size(comm, &size) != MPI_SUCCESS) {
        snprintf(t->msg, USM_MSG_LEN, "MPI_Comm_rank/size failed");
        return USM_EFAILED;
    }
    status = tol_prepare(t, p, opt, rank, size);
    if (status == USM_OK)
        status = tol_checkpoint_open(t);
    status = agree(t, status, rank, comm);
    if (status != USM_OK)
        return status;
    const tol_comm c = {rank, size, &comm, m_sum, m_allgather, m_alltoallv};
    const size_t round = 8 * (size_t)opt->threads;
    int ok = (list = malloc((t->bhi - t->blo + 1) * sizeof *list)) != NULL &&
             (pend = calloc((size_t)size, sizeof *pend)) != NULL &&
             (taken = calloc((size_t)size, sizeof *taken)) != NULL &&
             (take = calloc((size_t)size, sizeof *take)) != NULL &&
             (pack = malloc(round * USM_TOLERANCE_BLOCK * (size_t)t->width * sizeof *pack)) != NULL;
    if (!ok)
        snprintf(t->msg, USM_MSG_LEN, "out of memory on rank %d", rank);
    status = agree(t, ok ? USM_OK : USM_EFAILED, rank, comm);
    /* every rank's pending blocks: the rounds (and the stop hook's budget) are
     * known alike everywhere */
    const uint64_t mine = status == USM_OK ? tol_pending(t, list) : 0;
    if (status == USM_OK &&
        MPI_Allgather(&mine, 1, MPI_UINT64_T, pend, 1, MPI_UINT64_T, comm) != MPI_SUCCESS) {
        snprintf(t->msg, USM_MSG_LEN, "MPI_Allgather failed");
        status = USM_EFAILED;
    }
    while (status == USM_OK) {
        uint64_t budget = opt->stop_after_blocks ? opt->stop_after_blocks - computed : UINT64_MAX,
                 n = 0;
        int last = 1;
        for (int r = 0; r < size; ++r) {
            uint64_t want = pend[r] - taken[r];
            want = want < round ? want : round;
            take[r] = want < budget ? want : budget;
            budget -= take[r];
            n += take[r];
        }
        if (n == 0)
            break;
        double t0 = tol_now(), c0 = tol_cpu();
        const int st = tol_compute(t, list + taken[rank], (size_t)take[rank], pack);
        t->timings.compute += tol_now() - t0;
        t->timings.compute_cpu += tol_cpu() - c0;
        t0 = tol_now();
        status = agree_key(t, st, t->fail_block, rank, comm);
        t->timings.reduce += tol_now() - t0;
        if (status != USM_OK)
            break;
        tol_unpack(t, list + taken[rank], (size_t)take[rank], pack);
        computed += n;
        for (int r = 0; r < size; ++r) {
            taken[r] += take[r];
            last &= taken[r] == pend[r];
        }
        const int stop = opt->stop_after_blocks && computed >= opt->stop_after_blocks && !last;
        /* rank 0's clock decides; every rank writes its own file */
        int due = rank == 0 && tol_checkpoint_due(t, last, stop), wst = USM_OK;
        t0 = tol_now();
        c0 = tol_cpu();
        if (MPI_Bcast(&due, 1, MPI_INT, 0, comm) != MPI_SUCCESS) {
            snprintf(t->msg, USM_MSG_LEN, "MPI_Bcast failed");
            wst = USM_EFAILED;
        } else if (due)
            wst = tol_checkpoint_write(t);
        status = agree(t, wst, rank, comm);
        t->timings.output += tol_now() - t0;
        t->timings.output_cpu += tol_cpu() - c0;
        if (status == USM_OK && stop)
            status = tol_stopped(t, computed);
        if (last)
            break;
    }
    free(list);
    free(pend);
    free(taken);
    free(take);
    free(pack);
    if (status == USM_OK)
        status = agree(t, tol_finish(t, &c), rank, comm);
    return status;
}

/* ---- samples.csv: one file, every rank writing its rows ------------------------------------ */

int usm_tolerance_write_csv_mpi(const usm_tolerance *t, const char *path, char msg[USM_MSG_LEN])
{
    MPI_Comm comm = MPI_COMM_WORLD;
    int rank, len = 0, ok = 1, all;
    char name[4096], *buf = NULL;
    uint64_t used = 0, offset = 0;
    MPI_File fh;
    MPI_Comm_rank(comm, &rank);
    msg[0] = '\0';
    /* rank 0 names the file (it has created it), or 0: give up */
    if (rank == 0)
        len = path && strlen(path) < sizeof name ? (int)strlen(path) + 1 : 0;
    if (MPI_Bcast(&len, 1, MPI_INT, 0, comm) != MPI_SUCCESS || len == 0) {
        snprintf(msg, USM_MSG_LEN, "samples.csv: not written (rank 0 gave up)");
        return USM_EFAILED;
    }
    if (rank == 0)
        memcpy(name, path, (size_t)len);
    if (MPI_Bcast(name, len, MPI_CHAR, 0, comm) != MPI_SUCCESS)
        ok = 0;
    /* this rank's rows as text (rank 0's after the header) */
    const uint64_t n = tol_local_samples(t), first = t->blo * USM_TOLERANCE_BLOCK;
    const size_t max = tol_csv_row_max(t);
    if (ok && (buf = malloc(4096 + (n ? n : 1) * max)) == NULL)
        ok = 0;
    if (ok && rank == 0)
        used = tol_csv_header(t, buf, 4096);
    for (uint64_t i = 0; ok && i < n; ++i)
        used += tol_csv_row(t, first + i, t->rows + i * (uint64_t)t->width, buf + used);
    MPI_Allreduce(&ok, &all, 1, MPI_INT, MPI_MIN, comm);
    if (!all) {
        snprintf(msg, USM_MSG_LEN, "samples.csv: out of memory on some rank");
        free(buf);
        return USM_EFAILED;
    }
    MPI_Exscan(&used, &offset, 1, MPI_UINT64_T, MPI_SUM, comm);
    if (rank == 0)
        offset = 0;
    ok = MPI_File_open(comm, name, MPI_MODE_WRONLY, MPI_INFO_NULL, &fh) == MPI_SUCCESS;
    if (ok) {
        for (uint64_t at = 0; ok && at < used;) {
            const int part = used - at > (1u << 30) ? 1 << 30 : (int)(used - at);
            MPI_Status st;
            ok = MPI_File_write_at(fh, (MPI_Offset)(offset + at), buf + at, part, MPI_CHAR, &st) ==
                 MPI_SUCCESS;
            at += (uint64_t)part;
        }
        ok &= MPI_File_close(&fh) == MPI_SUCCESS;
    }
    MPI_Allreduce(&ok, &all, 1, MPI_INT, MPI_MIN, comm);
    if (!all)
        snprintf(msg, USM_MSG_LEN, "%.200s: MPI-IO write error", name);
    free(buf);
    return all ? USM_OK : USM_EFAILED;
}
