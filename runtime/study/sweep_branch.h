/* sweep_branch.h: the continuation of a sweep's branch (sweep_branch.c).  Not
 * installed; not part of the API. */
#ifndef USM_SWEEP_BRANCH_H
#define USM_SWEEP_BRANCH_H

#include "core/root.h"
#include "sweep_sink.h"

/* The branch r(u; lambda) = 0 in scaled coordinates z = (u / su, lambda / Lambda):
 * the components differ by ten orders of magnitude (theta ~ 1e-4 rad, f ~ 4e4 Hz),
 * and both the arclength and the Newton tolerances need them comparable. */
typedef struct sweep_branch {
    const usm_model *m;
    const usm_param_info *info; /* the swept parameter */
    int col;                    /* its column of steady_jacobian_params */
    int nu, n;                  /* n = nu + 1 */
    int rotor;                  /* index of phidot_R in u for a slip model, else -1 */
    usm_params p;               /* working copy; the swept field is set per evaluation */
    double scale[SWEEP_MAX_N];
    double theta_min, theta_max;
    int dir;                    /* +1: lambda increases along the trace, -1: decreases */
    double A[SWEEP_MAX_N * SWEEP_MAX_N]; /* the bordered matrix (n x n), then its LU */
    int piv[SWEEP_MAX_N];
    usm_root *root;             /* events located along a step's arclength */
    /* the run */
    usm_steady *steady;         /* full searches and polishing at grid values */
    const usm_sweep_options *opt;
    const double *grid;
    size_t npts;
    const sweep_sink *sink;
    /* what one step found, passed on to the sink once the step is accepted */
    usm_sweep_event *pev;
    size_t npev, pevcap;
    struct sweep_pending_point *ppt;
    size_t nppt, pptcap;
    int oom;                    /* a pending list could not grow */
    usm_steady_solution last;   /* the last grid point passed on with a solution */
    int defer;                  /* 1: grid points are passed on with only the branch's
                                 * u and roots = SWEEP_ROOTS_PENDING; sweep_finish_points
                                 * completes them (the full search there) */
} sweep_branch;

/* `roots` of a grid point passed on before its full search (sweep_branch.defer). */
#define SWEEP_ROOTS_PENDING (-1)

/* sweep_branch.c: follow the branch of the primary root over the grid
 * values grid[0..n-1] of opt->over, reporting points and events to sink.
 * USM_OK, or a status with msg (a full search failing other than with "no
 * solution").  Where the continuation loses the branch it restarts from the
 * full search at the next grid value (the root nearest the branch's last). */
int sweep_branch_alloc(sweep_branch *b, const usm_model *m);
void sweep_branch_free(sweep_branch *b);
int sweep_trace_grid(sweep_branch *b, const usm_params *p, const usm_sweep_options *opt,
                     const double *grid, size_t n, const sweep_sink *sink,
                     char msg[USM_MSG_LEN]);

/* The deferred part of every grid point passed on with SWEEP_ROOTS_PENDING
 * (sol.u the branch's root): the full search at its value, the root that
 * is the branch's (or the polish from u where the search misses it) and the
 * number of roots, on opt->threads workers; the points are independent, so
 * the result is that of the serial finish.  USM_OK or USM_EFAILED with msg. */
int sweep_finish_points(const usm_model *m, const usm_params *p, const usm_sweep_options *opt,
                        usm_sweep_point *pts, size_t n, char msg[USM_MSG_LEN]);

#endif /* USM_SWEEP_BRANCH_H */
