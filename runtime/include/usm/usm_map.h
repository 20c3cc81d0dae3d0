/* usm_map.h: stability maps over two parameters, and the point evaluator.
 *
 * A map solves every point of a grid over two parameters x and y (any fields
 * of usm_params) from scratch: the full search (usm_steady_solve), its primary
 * root, and the Floquet multipliers of that root.  The points are
 * independent, so the result does not depend on the order or on the number of
 * worker threads (the grid's columns are shared out among them; the pool is
 * the one the sweep uses for its multipliers).  A point without a solution,
 * or whose multipliers fail, is marked with the reason and the map goes on.
 *
 * Boundaries: in every column (one x value), where an indicator changes
 * between two neighbouring grid points, the change is located by bisection
 * in y to 1e-7 of the y range:
 *   existence   a stationary solution exists
 *   stability   the largest non-cyclic multiplier is < 1 (solution on both sides)
 *   stick       F_t <= mu0 F_n (the stick condition; solution on both sides)
 *
 * The point evaluator usm_point_evaluate is the one function that computes a
 * stationary solution and its multipliers at a parameter point; the maps, the
 * sweep's Floquet pass and the command's report call it.
 *
 * Life cycle (GSL style): usm_map_alloc, usm_map_run, accessors, usm_map_free.
 * Thread safety: as usm.h; one usm_map must not be shared without a lock.
 */
#ifndef USM_MAP_H
#define USM_MAP_H

#include "usm.h"
#include "usm_operating_point.h"
#include "usm_progress.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- one point ----------------------------------------------------------------- */

/* The class of a point by its operating point (usm_operating_point.h), how
 * the studies judge a design: */
typedef enum {
    USM_POINT_OP_NOT_EVALUATED = 0, /* not asked (usm_point.has_op == 0) */
    USM_POINT_OP_STABLE = 1,        /* an operating point exists (a stable root, op.index) */
    USM_POINT_OP_NO_STABLE_ROOT = 2,/* roots exist, every one unstable */
    USM_POINT_OP_DOES_NOT_START = 3,/* a stable root exists, but from rest the wobble decays */
    USM_POINT_OP_UNKNOWN = 4,       /* several roots, a stable one among them, and no
                                       simulation from rest asked; or the simulation settled
                                       on no root; or a root's multipliers failed (message) */
    USM_POINT_OP_NO_SOLUTION = 5    /* no stationary solution */
} usm_point_op_class;

/* "not_evaluated", "operating_point", "no_stable_root", "does_not_start",
 * "unknown", "no_solution" (NULL for an unknown value). */
const char *usm_point_op_class_name(usm_point_op_class cls);

/* The operating point of a point: the rule of usm_operating_point on the
 * multipliers of every root (usm_floquet_roots), with a simulation from
 * rest where several roots exist and usm_op_options.from_rest asks for it. */
typedef struct usm_point_op {
    usm_point_op_class cls;
    int index;                  /* root index of the operating point, or -1 */
    usm_op_reason reason;       /* usm_operating_point's reason (USM_OP_UNDECIDED for
                                   no_solution and for failed multipliers) */
    int starts_from_rest;       /* 1, 0, -1 as usm_op_result */
    int simulated;              /* 1: a simulation from rest ran */
    int stable_roots;           /* how many roots are stable (0 when the multipliers failed) */
    usm_steady_solution sol;    /* the operating point's root (index >= 0) */
    usm_floquet_result floquet; /* its multipliers (index >= 0) */
    char message[USM_MSG_LEN];  /* the answer in words (usm_op_result.message) */
} usm_point_op;

/* A stationary solution and its multipliers at one parameter point. */
typedef struct usm_point {
    int exists;                 /* a stationary solution exists */
    int roots;                  /* how many the full search found (1 when given, 0 when
                                   not counted: usm_point_evaluate_warm) */
    usm_steady_solution sol;    /* the primary (or the given) root */
    int has_floquet;            /* multipliers computed */
    usm_floquet_result floquet;
    char error[USM_MSG_LEN];    /* why not exists, or why the multipliers failed */
    int has_op;                 /* 1: op filled (usm_point_evaluate_op) */
    usm_point_op op;            /* the operating point */
} usm_point;

/* Evaluate at parameters p: with root == NULL the full search (s, steady_opt;
 * steady_opt may be NULL) and its primary root, else the given root (s may
 * then be NULL); with floquet != 0 the multipliers over [t0, t0 + T] (f)
 * computed with floquet_opt (NULL: usm_floquet_options_default).
 * USM_OK (out filled; exists or has_floquet may be 0, error says why) or
 * USM_EINPUT (bad parameters: out->error holds the library's message). */
int usm_point_evaluate(usm_steady *s, usm_floquet *f, const usm_params *p,
                       const usm_steady_options *steady_opt, const usm_steady_solution *root,
                       int floquet, double t0, const usm_floquet_options *floquet_opt,
                       usm_point *out);

/* As usm_point_evaluate with root == NULL, but the stationary solution by
 * usm_steady_solve_warm from `guess` (the primary root at a neighbouring
 * parameter point, or NULL): the same primary root, bit for bit, found
 * without searching above it, so out->roots is 0 (not counted) when a
 * solution exists.  For samplers that need the primary root only (Monte
 * Carlo studies); usm_steady_warm(s) says whether the guess's branch was
 * the primary's.  Returns as usm_point_evaluate. */
int usm_point_evaluate_warm(usm_steady *s, usm_floquet *f, const usm_params *p,
                            const usm_steady_options *steady_opt,
                            const usm_steady_solution *guess, int floquet, double t0,
                            const usm_floquet_options *floquet_opt, usm_point *out);

/* As usm_point_evaluate with root == NULL and floquet == 1 (s is solved by
 * the full search with the default options, which the simulation from rest
 * compares with), and the operating point: the multipliers of every root
 * (root 0's are out->floquet), then usm_operating_point with op_opt (NULL:
 * the defaults, no simulation).  out->sol and out->floquet stay the primary
 * root's; out->op is the operating point (has_op = 1).  Cost: one monodromy
 * per root, plus the simulation from rest (0.2 .. 1.2 s) where several roots
 * exist and op_opt->from_rest is set.  Returns as usm_point_evaluate, or
 * USM_EINPUT for bad op_opt (out->error). */
int usm_point_evaluate_op(usm_steady *s, usm_floquet *f, const usm_model *m,
                          const usm_params *p, double t0, const usm_floquet_options *floquet_opt,
                          const usm_op_options *op_opt, usm_point *out);

/* ---- maps ---------------------------------------------------------------------- */

/* One axis of a map: parameter `name` at `points` equally spaced values from
 * `from` to `to` (both included exactly). */
typedef struct usm_map_axis {
    const char *name;
    double from, to;
    int points;            /* 2 .. 100000 */
} usm_map_axis;

/* Value i of an axis. */
double usm_map_axis_value(const usm_map_axis *a, int i);

/* What to map and how (usm_map_options_default). */
typedef struct usm_map_options {
    usm_map_axis x, y;     /* default f 30000 .. 46000 Hz x T 0 .. 0.008 N m, 33 x 33 */
    double t0;             /* Floquet start time [s] (default 0) */
    usm_floquet_options floquet; /* method and tolerances (usm_floquet_options_default) */
    int threads;           /* worker threads (default 2; 1 .. 64) */
    int boundaries;        /* locate the boundaries (default 1) */
    int warm_start;        /* 1: each grid point's primary root by usm_steady_solve_warm
                              from the previous point of its column (the same roots;
                              the cells' `roots` are then 0, not counted); default 0 */
    int operating_point;   /* 1: each cell's operating point (usm_point_evaluate_op; the
                              full search, warm_start ignored for the cells); default 1 */
    usm_op_options op;     /* how (usm_op_options_default: no simulation from rest, so
                              cells with several roots are USM_POINT_OP_UNKNOWN) */
    usm_progress progress; /* the grid's points as their columns finish ("points"; the
                              boundaries' bisections are not counted); default silent */
} usm_map_options;

/* Fill `opt` with the defaults listed above. */
void usm_map_options_default(usm_map_options *opt);

/* One grid point: (x, y) and its evaluation. */
typedef struct usm_map_cell {
    double x, y;
    usm_point point;
} usm_map_cell;

typedef enum {
    USM_MAP_BOUNDARY_EXISTENCE = 0,
    USM_MAP_BOUNDARY_STABILITY = 1,
    USM_MAP_BOUNDARY_STICK = 2
} usm_map_boundary_kind;
#define USM_MAP_NBOUNDARY 3

/* "existence", "stability", "stick" */
const char *usm_map_boundary_name(usm_map_boundary_kind kind);

/* Indicator of boundary `kind` at a point: 1 or 0, or -1 where undefined. */
int usm_map_indicator(usm_map_boundary_kind kind, const usm_point *pt);

/* A located change of an indicator in column `column` (x index); k = 0 for
 * the first change in increasing y of that column, 1 for the second, ... */
typedef struct usm_map_boundary_point {
    double x, y;
    int column;
    int k;
} usm_map_boundary_point;

/* A map of one model with the cells and boundaries of the last run (opaque). */
typedef struct usm_map usm_map;

/* A map for model m (not NULL), or NULL when out of memory. */
usm_map *usm_map_alloc(const usm_model *m);
/* Free map; NULL is allowed. */
void usm_map_free(usm_map *map);

/* USM_OK (cells may be unsolved or without multipliers: their error says
 * why), USM_EINPUT (bad option or parameters somewhere on the grid; message
 * names the field), USM_EFAILED (out of memory, threads). */
int usm_map_run(usm_map *map, const usm_params *p, const usm_map_options *opt);

/* Cell (i, j) = (x_i, y_j) of the last run, NULL when out of range. */
const usm_map_cell *usm_map_cell_at(const usm_map *map, int i, int j);
/* Number of points of boundary `kind` found by the last run. */
size_t usm_map_boundary_count(const usm_map *map, usm_map_boundary_kind kind);
/* Point q of boundary `kind` (sorted by k, then column), NULL when out of range. */
const usm_map_boundary_point *usm_map_boundary_at(const usm_map *map,
                                                  usm_map_boundary_kind kind, size_t q);
/* Solved cells whose multipliers failed. */
size_t usm_map_floquet_failures(const usm_map *map);
/* Why the last run failed.  Owned by map; valid until the next run or free. */
const char *usm_map_message(const usm_map *map);

#ifdef __cplusplus
}
#endif

#endif /* USM_MAP_H */
