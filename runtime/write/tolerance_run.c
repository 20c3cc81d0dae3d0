/* The serial run of a tolerance study (usm_tolerance_run, usm_tolerance.h):
 * the study's rounds of blocks (design/tolerance.c) with its checkpoint
 * written between them (tolerance_checkpoint.c).  The study computes and
 * writes no file; this run, like the MPI one (mpi/tolerance_mpi.c), sits
 * above both and calls each. */
#include <stdlib.h>

#include "design/tolerance_internal.h"
#include "tolerance_checkpoint.h"

int usm_tolerance_run(usm_tolerance *t, const usm_params *p, const usm_tolerance_options *opt)
{
    int status = tol_prepare(t, p, opt, 0, 1);
    uint64_t *list = NULL, computed = 0;
    double *pack = NULL;
    if (status == USM_OK)
        status = tol_checkpoint_open(t);
    if (status != USM_OK)
        return status;
    /* rounds of a few blocks per thread: a checkpoint between rounds */
    const size_t round = 8 * (size_t)opt->threads;
    if (!(list = malloc(t->nblocks * sizeof *list)) ||
        !(pack = malloc(round * USM_TOLERANCE_BLOCK * (size_t)t->width * sizeof *pack))) {
        free(list);
        snprintf(t->msg, USM_MSG_LEN, "out of memory");
        return USM_EFAILED;
    }
    const size_t pending = tol_pending(t, list);
    uint64_t left = 0;
    for (size_t k = 0; k < pending; ++k)
        left += tol_block_size(t, list[k]);
    progress_start(&t->meter, &opt->progress, (long)opt->samples, (long)(opt->samples - left),
                   "samples");
    for (size_t at = 0; at < pending && status == USM_OK;) {
        size_t n = pending - at < round ? pending - at : round;
        if (opt->stop_after_blocks && n > opt->stop_after_blocks - computed)
            n = (size_t)(opt->stop_after_blocks - computed);
        double t0 = tol_now(), c0 = tol_cpu();
        status = tol_compute(t, list + at, n, pack);
        t->timings.compute += tol_now() - t0;
        t->timings.compute_cpu += tol_cpu() - c0;
        if (status != USM_OK)
            break;
        tol_unpack(t, list + at, n, pack);
        at += n;
        computed += n;
        const int stop = opt->stop_after_blocks && computed >= opt->stop_after_blocks &&
                         at < pending;
        t0 = tol_now();
        c0 = tol_cpu();
        if (tol_checkpoint_due(t, at == pending, stop))
            status = tol_checkpoint_write(t);
        t->timings.output += tol_now() - t0;
        t->timings.output_cpu += tol_cpu() - c0;
        if (status == USM_OK && stop)
            status = tol_stopped(t, computed);
    }
    free(list);
    free(pack);
    return status == USM_OK ? tol_finish(t, &tol_comm_serial) : status;
}

