/* usm_mpi.h: tolerance studies and maps over MPI ranks (issue 12, part 3):
 * the API of the usm_mpi library, which the usm command links when CMake
 * finds MPI (USM_HAVE_MPI); not part of libusm (which has no MPI) and not
 * installed.
 *
 * The command initialises MPI only when an MPI launcher started it (mpirun,
 * srun: usm_mpi_launched), so a plain `usm ...` never touches MPI.  The ranks
 * share the work out in a fixed order and rank 0 gathers every result, so
 * rank 0's output is byte-identical to a serial run's; only rank 0 prints
 * and writes files.
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

/* usm_tolerance_run distributed over MPI_COMM_WORLD: blocks of samples dealt
 * round-robin to the ranks (each uses opt->threads threads), the rows
 * gathered on rank 0 after every round, which writes the checkpoint and
 * computes the result.  Every rank returns the same status; rank 0 has the
 * message and the result. */
int usm_tolerance_run_mpi(usm_tolerance *t, const usm_params *p, const usm_tolerance_options *opt);

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
