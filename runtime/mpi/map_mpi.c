/* Stability maps over MPI ranks (usm_mpi.h).
 *
 * A map's columns (one x value each: its grid points and its bisections) are
 * independent, so the ranks share them out without touching map.c: the
 * columns are taken in pairs (2k, 2k + 1), pair k on rank k mod size, and
 * each pair is the library's own map over a 2-point x axis from x_2k to
 * x_2k+1 (usm_map_axis_value returns both ends exactly, and the y axis and
 * its bisection tolerance are the full map's), so every cell and boundary
 * point is bit for bit the one a serial run computes.  An odd last column
 * is paired with its left neighbour, whose duplicate is dropped.  Rank 0
 * gathers the cells and boundary points and sorts the boundaries as
 * usm_map_run does (by k, then column). */
#include <mpi.h>
#include <stdlib.h>
#include <string.h>

#include "usm_mpi.h"

static int cmp_boundary(const void *pa, const void *pb)
{
    const usm_map_boundary_point *a = pa, *b = pb;
    if (a->k != b->k)
        return a->k - b->k;
    return a->column - b->column;
}

void usm_map_gathered_free(usm_map_gathered *g)
{
    free(g->cells);
    for (int k = 0; k < USM_MAP_NBOUNDARY; ++k)
        free(g->bnd[k]);
    memset(g, 0, sizeof *g);
}

/* The worst status over the ranks; rank 0 gets the first failing rank's msg. */
static int agree(int status, char msg[USM_MSG_LEN], int rank)
{
    int worst = status, who = status != USM_OK ? rank : 1 << 30, first = 0;
    if (MPI_Allreduce(&status, &worst, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD) != MPI_SUCCESS ||
        MPI_Allreduce(&who, &first, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD) != MPI_SUCCESS) {
        snprintf(msg, USM_MSG_LEN, "MPI_Allreduce failed");
        return USM_EFAILED;
    }
    if (worst != USM_OK && first != 0 &&
        MPI_Bcast(msg, USM_MSG_LEN, MPI_CHAR, first, MPI_COMM_WORLD) != MPI_SUCCESS)
        snprintf(msg, USM_MSG_LEN, "rank %d failed", first);
    return worst;
}

int usm_map_run_mpi(const usm_model *m, const usm_params *p, const usm_map_options *opt,
                    usm_map_gathered *g)
{
    int rank, size, status = USM_OK;
    memset(g, 0, sizeof *g);
    if (MPI_Comm_rank(MPI_COMM_WORLD, &rank) != MPI_SUCCESS ||
        MPI_Comm_size(MPI_COMM_WORLD, &size) != MPI_SUCCESS) {
        snprintf(g->msg, USM_MSG_LEN, "MPI_Comm_rank/size failed");
        return USM_EFAILED;
    }
    if (!opt || opt->x.points < 2 || opt->y.points < 2) {
        /* the serial run names the field */
        usm_map *lib = usm_map_alloc(m);
        status = lib ? usm_map_run(lib, p, opt) : USM_EFAILED;
        snprintf(g->msg, USM_MSG_LEN, "%s", lib ? usm_map_message(lib) : "out of memory");
        usm_map_free(lib);
        return status == USM_OK ? USM_EFAILED : status;
    }
    const int nx = opt->x.points, ny = opt->y.points, npairs = (nx + 1) / 2;
    const size_t pair_bytes = (size_t)2 * (size_t)ny * sizeof(usm_map_cell);
    const int mine = npairs / size + (rank < npairs % size);
    /* per pair: its cells, then up to 2 (ny - 1) points per boundary kind */
    const size_t bnd_room = (size_t)2 * (size_t)(ny - 1);
    usm_map_cell *cells = calloc((size_t)(mine ? mine : 1) * 2 * (size_t)ny, sizeof *cells);
    usm_map_boundary_point *bnd[USM_MAP_NBOUNDARY] = {NULL, NULL, NULL};
    int nb[USM_MAP_NBOUNDARY] = {0, 0, 0};
    long long failures = 0;
    usm_map *lib = usm_map_alloc(m);
    int ok = cells && lib;
    for (int k = 0; k < USM_MAP_NBOUNDARY; ++k)
        ok = ok && (bnd[k] = calloc((size_t)(mine ? mine : 1) * bnd_room, sizeof *bnd[k]));
    if (!ok) {
        snprintf(g->msg, USM_MSG_LEN, "out of memory on rank %d", rank);
        status = USM_EFAILED;
    }
    for (int q = 0, pair = rank; status == USM_OK && pair < npairs; ++q, pair += size) {
        const int left = 2 * pair + 1 < nx ? 2 * pair : nx - 2;
        usm_map_options sub = *opt;
        sub.x.from = usm_map_axis_value(&opt->x, left);
        sub.x.to = usm_map_axis_value(&opt->x, left + 1);
        sub.x.points = 2;
        if ((status = usm_map_run(lib, p, &sub)) != USM_OK) {
            snprintf(g->msg, USM_MSG_LEN, "%s", usm_map_message(lib));
            break;
        }
        for (int j = 0; j < ny; ++j)
            for (int c = 0; c < 2; ++c)
                cells[((size_t)q * (size_t)ny + (size_t)j) * 2 + (size_t)c] =
                    *usm_map_cell_at(lib, c, j);
        for (int k = 0; k < USM_MAP_NBOUNDARY; ++k)
            for (size_t b = 0; b < usm_map_boundary_count(lib, (usm_map_boundary_kind)k); ++b) {
                usm_map_boundary_point pt = *usm_map_boundary_at(lib, (usm_map_boundary_kind)k, b);
                if (left != 2 * pair && pt.column == 0)
                    continue; /* the duplicate of an odd map's last pair */
                pt.column += left;
                bnd[k][nb[k]++] = pt;
            }
        for (int j = 0; j < ny; ++j)
            for (int c = left != 2 * pair; c < 2; ++c) {
                const usm_point *pt = &usm_map_cell_at(lib, c, j)->point;
                failures += pt->exists && !pt->has_floquet;
            }
    }
    usm_map_free(lib);
    status = agree(status, g->msg, rank);
    int *counts = NULL, *displs = NULL;
    unsigned char *all = NULL;
    if (status == USM_OK) {
        counts = calloc((size_t)size, sizeof *counts);
        displs = calloc((size_t)size, sizeof *displs);
        if (rank == 0) {
            all = malloc((size_t)npairs * pair_bytes);
            g->cells = calloc((size_t)nx * (size_t)ny, sizeof *g->cells);
        }
        ok = counts && displs && (rank != 0 || (all && g->cells));
        if (!ok)
            snprintf(g->msg, USM_MSG_LEN, "out of memory on rank %d", rank);
        status = agree(ok ? USM_OK : USM_EFAILED, g->msg, rank);
    }
    /* the cells: rank r's pairs r, r + size, ... one after the other */
    for (int r = 0, off = 0; status == USM_OK && r < size; ++r) {
        counts[r] = (npairs / size + (r < npairs % size)) * (int)pair_bytes;
        displs[r] = off;
        off += counts[r];
    }
    if (status == USM_OK &&
        MPI_Gatherv(cells, counts[rank], MPI_BYTE, all, counts, displs, MPI_BYTE, 0,
                    MPI_COMM_WORLD) != MPI_SUCCESS) {
        snprintf(g->msg, USM_MSG_LEN, "MPI_Gatherv failed");
        status = USM_EFAILED;
    }
    if (status == USM_OK && rank == 0)
        for (int r = 0; r < size; ++r) {
            const usm_map_cell *src = (const usm_map_cell *)(all + displs[r]);
            for (int pair = r; pair < npairs; pair += size, src += 2 * ny) {
                const int left = 2 * pair + 1 < nx ? 2 * pair : nx - 2;
                for (int j = 0; j < ny; ++j)
                    for (int c = 0; c < 2; ++c)
                        g->cells[(size_t)j * (size_t)nx + (size_t)(left + c)] = src[2 * j + c];
            }
        }
    /* the boundaries: counts first, then the points */
    for (int k = 0; status == USM_OK && k < USM_MAP_NBOUNDARY; ++k) {
        const int bytes = nb[k] * (int)sizeof(usm_map_boundary_point);
        int total = 0;
        if (MPI_Gather(&bytes, 1, MPI_INT, counts, 1, MPI_INT, 0, MPI_COMM_WORLD) != MPI_SUCCESS) {
            status = USM_EFAILED;
            break;
        }
        for (int r = 0; rank == 0 && r < size; ++r) {
            displs[r] = total;
            total += counts[r];
        }
        if (rank == 0 && !(g->bnd[k] = malloc(total ? (size_t)total : 1)))
            status = USM_EFAILED; /* the Gatherv below still runs on every rank */
        unsigned char *dst = rank == 0 && g->bnd[k] ? (unsigned char *)g->bnd[k] : NULL;
        if (MPI_Gatherv(bnd[k], bytes, MPI_BYTE, dst, counts, displs, MPI_BYTE, 0,
                        MPI_COMM_WORLD) != MPI_SUCCESS)
            status = USM_EFAILED;
        if (rank == 0 && g->bnd[k]) {
            g->nbnd[k] = (size_t)total / sizeof(usm_map_boundary_point);
            qsort(g->bnd[k], g->nbnd[k], sizeof *g->bnd[k], cmp_boundary);
        }
        status = agree(status, g->msg, rank);
        if (status != USM_OK)
            snprintf(g->msg, USM_MSG_LEN, "gathering the boundaries failed");
    }
    long long total_failures = 0;
    if (status == USM_OK &&
        MPI_Reduce(&failures, &total_failures, 1, MPI_LONG_LONG, MPI_SUM, 0, MPI_COMM_WORLD) !=
            MPI_SUCCESS)
        status = USM_EFAILED;
    g->floquet_failures = (size_t)total_failures;
    g->nx = nx;
    g->ny = ny;
    free(cells);
    free(all);
    free(counts);
    free(displs);
    for (int k = 0; k < USM_MAP_NBOUNDARY; ++k)
        free(bnd[k]);
    if (status != USM_OK || rank != 0) {
        char keep[USM_MSG_LEN];
        memcpy(keep, g->msg, USM_MSG_LEN);
        usm_map_gathered_free(g);
        memcpy(g->msg, keep, USM_MSG_LEN);
    }
    return status;
}
