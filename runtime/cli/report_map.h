/* report_map.h: stability map, the largest Floquet multiplier over a 2-D grid
 * of two parameters (used by `usm map` and `usm report`).
 *
 * Every grid point is solved from scratch (usm_steady_solve, then
 * usm_floquet_compute on the primary root), so the points are independent and
 * the result does not depend on the order or on the number of threads.  The
 * grid's columns (one x value, every y value) are shared out among worker
 * threads; each thread owns its solver objects.
 *
 * Boundaries: in every column, where an indicator changes between two
 * neighbouring grid points, the change is located by bisection in y:
 *   existence   a stationary solution exists
 *   stability   the largest non-cyclic multiplier is < 1 (solution exists on
 *               both sides)
 *   stick       F_t <= mu0 F_n (the stick condition of section 2; solution
 *               exists on both sides)
 */
#ifndef USM_CLI_REPORT_MAP_H
#define USM_CLI_REPORT_MAP_H

#include <stdio.h>

#include <jansson.h>

#include "diag.h"
#include "usm.h"

typedef struct report_axis {
    const usm_param_info *param;
    double from, to;
    int points; /* >= 2 */
} report_axis;

typedef struct report_map_cell {
    double x, y;
    int exists;        /* a stationary solution exists */
    int roots;         /* how many */
    int floquet_ok;    /* multipliers computed (exists and no failure) */
    double max_modulus; /* largest non-cyclic |lambda| (NaN unless floquet_ok) */
    int stable;
    double theta, rotor_speed, mu_used; /* primary root (NaN unless exists) */
    int stick_admissible;
} report_map_cell;

enum {
    REPORT_BOUNDARY_EXISTENCE = 0,
    REPORT_BOUNDARY_STABILITY = 1,
    REPORT_BOUNDARY_STICK = 2,
    REPORT_NBOUNDARY = 3
};

/* "existence", "stability", "stick" */
const char *report_boundary_name(int kind);

typedef struct report_boundary_point {
    double x, y;
    int column; /* x index */
    int k;      /* 0 for the first change in this column (increasing y), 1, ... */
} report_boundary_point;

typedef struct report_map {
    /* input */
    const usm_model *model;
    usm_params params;
    report_axis x, y;
    double t0;       /* Floquet start time [s] */
    const usm_floquet_options *floquet; /* Floquet method and tolerances; NULL: defaults */
    int threads;     /* >= 1 */
    int boundaries;  /* locate the boundaries (1) or not (0) */
    /* output: cells[j * x.points + i] is (x_i, y_j) */
    report_map_cell *cells;
    report_boundary_point *bnd[REPORT_NBOUNDARY];
    size_t nbnd[REPORT_NBOUNDARY];
    size_t floquet_failures;
} report_map;

/* Solve at parameters p: the primary root and, with want_floquet, its
 * multipliers over [t0, t0 + T].  Fills c (not c->x, c->y); c->exists = 0
 * when there is no solution.  USM_OK, or USM_EINPUT with the library's
 * message in msg (bad parameters). */
int report_map_eval(usm_steady *s, usm_floquet *f, const usm_params *p, double t0,
                    int want_floquet, report_map_cell *c, char msg[USM_MSG_LEN]);

/* report_map_eval with the Floquet options fopt (NULL: the defaults). */
int report_map_eval_opt(usm_steady *s, usm_floquet *f, const usm_params *p, double t0,
                        const usm_floquet_options *fopt, int want_floquet, report_map_cell *c,
                        char msg[USM_MSG_LEN]);

/* Indicator of boundary `kind` at a cell: 1 or 0, or -1 where undefined. */
int report_map_indicator(int kind, const report_map_cell *c);

/* Value i of an axis (exact end points). */
double report_axis_value(const report_axis *a, int i);

/* Check an axis: "FIELD: reason" in msg and USM_EINPUT when bad (field is the
 * option's name, e.g. "--x"). */
int report_axis_check(const report_axis *a, const char *field, char msg[CLI_MSG_LEN]);

/* Compute the map.  USM_OK, USM_EINPUT (bad axis or parameters along the
 * grid: msg), USM_EFAILED (out of memory, thread failure: msg). */
int report_map_run(report_map *map, char msg[CLI_MSG_LEN]);
void report_map_free(report_map *map);

/* CSV: header "x_NAME,y_NAME,exists,roots,max_modulus,stable,theta,rotor_speed,
 * mu_used,stick_admissible" then one row per point, x fastest.  Values that
 * do not exist (no solution, no multipliers) are written "nan".
 * 0, or -1 on a write error. */
int report_map_write_csv(const report_map *map, FILE *out);

/* CSV of one boundary: "x,y"; points of the k-th change of each column form
 * a block, blocks separated by two blank lines (gnuplot "index"), a single
 * blank line where a column has no k-th change (breaks the line). */
int report_map_write_boundary_csv(const report_map *map, int kind, FILE *out);

/* The `usm map --json` object, or NULL when out of memory. */
json_t *report_map_json(const report_map *map);

#endif /* USM_CLI_REPORT_MAP_H */
