/* sweep_internal.h: pieces of the sweep shared by sweep.c (API, grid,
 * orchestration), sweep_branch.c (pseudo-arclength continuation and the
 * events on the branch) and sweep_stability.c (Floquet multipliers on worker
 * threads, stability changes).  Not installed; not part of the API.
 */
#ifndef USM_SWEEP_INTERNAL_H
#define USM_SWEEP_INTERNAL_H

#include <gsl/gsl_linalg.h>
#include <gsl/gsl_roots.h>

#include "usm_sweep.h"

/* More grid points than this are a typing error, not a request. */
#define SWEEP_MAX_POINTS 1000000

#include "pool_internal.h"

/* More worker threads than this would only contend for the cores. */
#define SWEEP_MAX_THREADS POOL_MAX_THREADS

/* Unknowns of the continuation: u (nu of them) and the parameter. */
#define SWEEP_MAX_N (USM_MAX_NU + 1)

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
    gsl_matrix *A;
    gsl_permutation *perm;
    gsl_vector *b, *x;
    gsl_root_fsolver *brent;    /* events located along a step's arclength */
} sweep_branch;

struct usm_sweep {
    const usm_model *m;
    usm_steady *steady;   /* full searches and polishing at grid values */
    sweep_branch br;
    usm_sweep_point *pts;
    size_t npts, cap;
    usm_sweep_event *ev;
    size_t nev, evcap;
    char msg[USM_MSG_LEN];
    /* progress: the continuation's share of the run, then the Floquet part's */
    const usm_sweep_options *opt;
    double progress_split;
    size_t done;          /* grid points settled by the continuation phase */
    /* the Floquet phase */
    const usm_params *floquet_params;
    size_t floquet_done, floquet_total;
};

/* sweep.c */
int sweep_add_event(usm_sweep *s, usm_event_type type, double value,
                    const usm_steady_solution *sol, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 5, 6)))
#endif
    ;
void sweep_progress(const usm_sweep *s, double fraction);
/* One more grid point settled (solved or found without solution). */
void sweep_point_done(usm_sweep *s);
/* "T = 0.0076 N m" style text of a parameter value, for messages. */
const char *sweep_value_text(const usm_sweep *s, double value, char buf[64]);

/* sweep_branch.c */
int sweep_branch_alloc(sweep_branch *b, const usm_model *m);
void sweep_branch_free(sweep_branch *b);
/* Follow the primary branch over the grid: fills s->pts and the branch events.
 * USM_OK, or USM_EFAILED when the continuation lost the branch (message in s->msg). */
int sweep_trace_grid(usm_sweep *s, const usm_params *p, const usm_sweep_options *opt);
/* Solve at parameter value `value` on the branch between converged grid points
 * a and b (used to locate stability changes).  0 or -1. */
int sweep_solve_between(usm_sweep *s, const usm_params *p, size_t a, size_t b, double value,
                        usm_steady_solution *sol);

/* sweep_stability.c */
int sweep_floquet_points(usm_sweep *s, const usm_params *p, const usm_sweep_options *opt);
int sweep_stability_events(usm_sweep *s, const usm_params *p, const usm_sweep_options *opt);

#endif /* USM_SWEEP_INTERNAL_H */
