/* usm_report_map.h: the stability map of `usm map` and `usm report` as the
 * command keeps and writes it: the library computes it (usm_map.h: every
 * point from scratch, the boundaries by bisection, the worker pool); these
 * functions copy the result into plain arrays (usm_report_map) and write
 * them: CSV in the project's dialect (usm_io.h), the boundaries' CSV for
 * gnuplot, the `usm map --json` object (formats: docs/cli.md).
 *
 * Thread safety: no global mutable state; distinct usm_report_map objects
 * may be used from distinct threads at the same time (usm_report_map_run
 * starts map->threads worker threads of its own).
 */
#ifndef USM_REPORT_MAP_H
#define USM_REPORT_MAP_H

#include <stddef.h>
#include <stdio.h>

#include "usm.h"
#include "usm_io.h" /* USM_IO_MSG_LEN */
#include "usm_map.h"

#ifdef __cplusplus
extern "C" {
#endif

/* One axis of the map: a parameter by name and its grid. */
typedef struct usm_report_axis {
    const char *name;
    const usm_param_info *param; /* set by usm_report_map_run */
    double from, to;
    int points; /* >= 2 */
} usm_report_axis;

/* One grid point: the stationary solution and its largest multiplier. */
typedef struct usm_report_map_cell {
    double x, y;
    int exists;        /* a stationary solution exists */
    int roots;         /* how many */
    int floquet_ok;    /* multipliers computed (exists and no failure) */
    double max_modulus; /* largest non-cyclic |lambda| (NaN unless floquet_ok) */
    int stable;
    double theta, rotor_speed, mu_used; /* primary root (NaN unless exists) */
    int stick_admissible;
    usm_validity validity; /* of the primary root (USM_VALID unless exists) */
    /* power of the primary root [W] and power_out / power_in (NaN unless
     * exists; efficiency NaN also when power_in <= 0) */
    double power_in, power_out, power_damping, power_slip, efficiency;
    char error[USM_MSG_LEN]; /* why no solution, or why the multipliers failed */
    /* the operating point (usm_point_evaluate_op) */
    int op_class;      /* usm_point_op_class */
    int op_index;      /* root index of the operating point, or -1 */
    int op_reason;     /* usm_op_reason */
    int starts_from_rest; /* 1, 0, -1 (not simulated or undecided) */
    double op_theta, op_rotor_speed, op_max_modulus; /* NaN unless op_index >= 0 */
    char op_message[USM_MSG_LEN];
} usm_report_map_cell;

/* The boundaries located along y: a solution starts or stops existing,
 * max |lambda| crosses 1, F_t = mu0 F_n. */
enum {
    USM_REPORT_BOUNDARY_EXISTENCE = 0,
    USM_REPORT_BOUNDARY_STABILITY = 1,
    USM_REPORT_BOUNDARY_STICK = 2,
    USM_REPORT_NBOUNDARY = 3
};

/* "existence", "stability", "stick" */
const char *usm_report_boundary_name(int kind);

/* One point of a boundary. */
typedef struct usm_report_boundary_point {
    double x, y;
    int column; /* x index */
    int k;      /* 0 for the first change in this column (increasing y), 1, ... */
} usm_report_boundary_point;

/* A map: its input (set by the caller), then its result (set by
 * usm_report_map_run or usm_report_map_fill, freed by usm_report_map_free). */
typedef struct usm_report_map {
    /* input */
    const usm_model *model;
    usm_params params;
    usm_report_axis x, y;
    double t0;       /* Floquet start time [s] */
    const usm_floquet_options *floquet; /* NULL: the library's defaults */
    int threads;     /* >= 1 */
    int boundaries;  /* locate the boundaries (1) or not (0) */
    const usm_op_options *op; /* the operating point's rule (NULL: usm_op_options_default,
                                 no simulation from rest) */
    usm_progress progress; /* the map's progress (usm_map_options); {NULL}: silent */
    /* output: cells[j * x.points + i] is (x_i, y_j) */
    usm_report_map_cell *cells;
    usm_report_boundary_point *bnd[USM_REPORT_NBOUNDARY];
    size_t nbnd[USM_REPORT_NBOUNDARY];
    size_t floquet_failures;
} usm_report_map;

/* One cell of a library map (usm_map.h) as the writers keep it (a map
 * computed elsewhere, e.g. gathered from MPI ranks, is copied with it). */
void usm_report_map_cell_copy(const usm_map_cell *in, usm_report_map_cell *c);

/* The usm_map_options of map: its axes by name, t0, Floquet options,
 * threads, boundaries, progress. */
void usm_report_map_options(const usm_report_map *map, usm_map_options *opt);

/* Fill map's cells and boundaries from a map computed elsewhere, as arrays:
 * cells[j * x.points + i], bnd[k][q] for q < nbnd[k] (e.g. gathered from MPI
 * ranks; usm_report_map_run goes through it too).  USM_OK, or USM_EFAILED
 * (out of memory) with msg and nothing kept. */
int usm_report_map_fill(usm_report_map *map, const usm_map_cell *cells,
                        usm_map_boundary_point *const bnd[USM_MAP_NBOUNDARY],
                        const size_t nbnd[USM_MAP_NBOUNDARY], size_t floquet_failures,
                        char msg[USM_IO_MSG_LEN]);

/* Compute the map with usm_map_run (axes by name: x.name, y.name; x.param
 * and y.param are set from them).  USM_OK, USM_EINPUT (bad axis or
 * parameters along the grid: the library's message, its field as the
 * command's option "--x..."), USM_EFAILED (out of memory, threads). */
int usm_report_map_run(usm_report_map *map, char msg[USM_IO_MSG_LEN]);
/* Free the cells and boundaries of map (not map itself); the input fields
 * stay. */
void usm_report_map_free(usm_report_map *map);

/* CSV in the command's dialect (usm_io.h): header "X [UNIT],Y [UNIT],exists,
 * roots,max_modulus [1],stable,theta [rad],rotor_speed [1/s],mu_used [1],
 * stick_admissible,power_in [W],power_out [W],power_damping [W],
 * power_slip [W],efficiency [1],operating_point,op_class,op_reason,
 * starts_from_rest,op_theta [rad],op_rotor_speed [1/s],op_max_modulus [1]"
 * then one row per point, x fastest (operating_point: the root index from 0
 * or empty; op_class: usm_point_op_class_name; op_reason:
 * usm_op_reason_name, empty when undecided; starts_from_rest true/false or
 * empty).  Values
 * that do not exist (no solution, no multipliers) are empty fields.
 * 0, or -1 on a write error. */
int usm_report_map_write_csv(const usm_report_map *map, FILE *out);

/* CSV of boundary `kind` (USM_REPORT_BOUNDARY_*): "X [UNIT],Y [UNIT]";
 * points of the k-th change of each column form a block, blocks separated by
 * two blank lines (gnuplot "index"), a single blank line where a column has
 * no k-th change (breaks the line).  0, or -1 on a write error. */
int usm_report_map_write_boundary_csv(const usm_report_map *map, int kind, FILE *out);

/* The `usm map --json` object (model, parameters, t0, x, y, points[],
 * boundaries) and a newline to out: 0, or -1 on a write error or when out of
 * memory. */
int usm_report_map_write_json(const usm_report_map *map, FILE *out);

#ifdef __cplusplus
}
#endif

#endif /* USM_REPORT_MAP_H */
