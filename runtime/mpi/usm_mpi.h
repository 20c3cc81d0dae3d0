/* usm_mpi.h: tolerance studies and maps over MPI ranks:
 * the API of the usm_mpi library (usm::usm_mpi, libusm_mpi.a), built and
 * installed beside libusm when CMake finds MPI (the usm command then links
 * it: USM_HAVE_MPI); not part of libusm, which has no MPI.  No MPI type is
 * in this header.
 *
 * The command initialises MPI only when an MPI launcher started it (mpirun,
 * srun: usm_mpi_launched), so a plain `usm ...` never touches MPI.  The ranks
 * share the work out in a fixed order; a map's results are gathered on rank
 * 0, a tolerance study's rows stay on the ranks that computed them (statistics by reductions and a sample sort, samples.csv by MPI-IO), and
 * rank 0's output is byte-identical to a serial run's; only rank 0 prints.
 */
#ifndef USM_MPI_H
#define USM_MPI_H

#include "usm_map.h"
#include "usm_tolerance.h"

/* 1 when the environment shows an MPI launcher (OMPI_COMM_WORLD_SIZE,
 * PMI_SIZE, PMIX_RANK), else 0. */
int usm_mpi_launched(void);

/* MPI_Init (once; MPI_Finalize is registered with atexit) and this
 * process's rank and the number of ranks.  USM_OK or USM_EFAILED with msg. */
int usm_mpi_start(int *rank, int *size, char msg[USM_MSG_LEN]);

/* MPI_Finalize, if usm_mpi_start initialised MPI. */
void usm_mpi_stop(void);

/* usm_tolerance_run distributed over MPI_COMM_WORLD: rank r of S owns the
 * contiguous blocks [nblocks r / S, nblocks (r + 1) / S), computes them (with
 * opt->threads threads), keeps their rows (memory O(samples / S)) and
 * writes its own checkpoint file (FILE for rank 0, FILE.r for rank r); the
 * statistics are computed by all ranks together, without gathering rows.
 * Every rank returns the same status and has the summary
 * (usm_tolerance_result, usm_tolerance_influence); rank 0 has the message;
 * usm_tolerance_sample gives this rank's samples only. */
int usm_tolerance_run_mpi(usm_tolerance *t, const usm_params *p, const usm_tolerance_options *opt);

/* samples.csv of a study run by usm_tolerance_run_mpi (collective: every
 * rank calls it): the file `path` (read on rank 0 only: an existing file,
 * rank 0's usm_io_create temporary; NULL on rank 0: give up, every rank
 * returns USM_EFAILED) written by all ranks with MPI-IO, the header by rank
 * 0, each rank's rows at the offset of the rows before them (MPI_Exscan of
 * the text's lengths): byte for byte usm_tolerance_write_csv's file of a
 * serial run.  USM_OK or USM_EFAILED with msg (on every rank). */
int usm_tolerance_write_csv_mpi(const usm_tolerance *t, const char *path, char msg[USM_MSG_LEN]);

/* A map gathered on rank 0: what usm_map's accessors give after a serial
 * usm_map_run, as plain arrays. */
typedef struct usm_map_gathered {
    int nx, ny;
    usm_map_cell *cells;        /* cells[j * nx + i] = (x_i, y_j) */
    usm_map_boundary_point *bnd[USM_MAP_NBOUNDARY]; /* sorted by k, then column */
    size_t nbnd[USM_MAP_NBOUNDARY];
    size_t floquet_failures;
    char msg[USM_MSG_LEN];      /* why the run failed */
} usm_map_gathered;

/* usm_map_run distributed over MPI_COMM_WORLD (runtime/mpi/map_mpi.c: pairs of
 * columns round-robin over the ranks, each rank using opt->threads threads).
 * Every rank returns the same status; on rank 0, g holds the map, identical
 * bit for bit to a serial run's (free it with usm_map_gathered_free); on the
 * other ranks g is empty. */
int usm_map_run_mpi(const usm_model *m, const usm_params *p, const usm_map_options *opt,
                    usm_map_gathered *g);
void usm_map_gathered_free(usm_map_gathered *g);

#endif /* USM_MPI_H */
