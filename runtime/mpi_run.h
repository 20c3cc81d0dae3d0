/* mpi_run.h: tolerance studies and maps over MPI ranks (issue 12, part 3).
 * Built into the usm command when CMake finds MPI (USM_HAVE_MPI); not part of
 * libusm and not installed.
 *
 * The command initialises MPI only when an MPI launcher started it (mpirun,
 * srun: usm_mpi_launched), so a plain `usm ...` never touches MPI.  The ranks
 * share the work out in a fixed order and rank 0 gathers every result, so
 * rank 0's output is byte-identical to a serial run's; only rank 0 prints
 * and writes files.
 */
#ifndef USM_MPI_RUN_H
#define USM_MPI_RUN_H

#include "usm_map.h"
#include "usm_tolerance.h"

/* 1 when the environment shows an MPI launcher (OMPI_COMM_WORLD_SIZE,
 * PMI_SIZE, PMIX_RANK), else 0. */
int usm_mpi_launched(void);

/* MPI_Init (once) and this process's rank and the number of ranks.  USM_OK
 * or USM_EFAILED with msg. */
int usm_mpi_start(int *rank, int *size, char msg[USM_MSG_LEN]);

/* MPI_Finalize, if usm_mpi_start initialised MPI. */
void usm_mpi_stop(void);

/* usm_tolerance_run distributed over MPI_COMM_WORLD: blocks of samples dealt
 * round-robin to the ranks (each uses opt->threads threads), the rows
 * gathered on rank 0 after every round, which writes the checkpoint and
 * computes the result.  Every rank returns the same status; rank 0 has the
 * message and the result. */
int usm_tolerance_run_mpi(usm_tolerance *t, const usm_params *p, const usm_tolerance_options *opt);

#endif /* USM_MPI_RUN_H */
