/* usm_envelope.h: the operating envelope of the stationary solution in two
 * parameters: every codimension-one boundary continued as a curve, the
 * codimension-two points where curves meet or end, and the regions between
 * the curves named by their operating class.
 *
 * Math.  A boundary is a stationary solution u (r(u; px, py) = 0, the
 * residual of usm_steady) on which one defining function g vanishes; the
 * extended system [r(u; px, py) = 0; g(u, px, py) = 0], nu + 1 equations in
 * nu + 2 unknowns, is a curve, followed by the continuation engine
 * (usm_cont.h) with one of px, py as its last unknown (the one that moves
 * most along the curve at the seed) and across its folds.  The kinds, named
 * as the one-parameter sweep names its events (usm_sweep.h):
 *   tilt_zero   g = theta: the smallest root is born at the axis; in the
 *               3-DOF model this is also the start threshold from rest
 *               (usm_op_start_margin = 0), which depends on m0, F0, T, R, H
 *               only
 *   fold        g the minimally augmented determinant of r_u: the last
 *               component of the solution of [r_u b; c' 0] [v; g] = [0; 1],
 *               with the borders b, c the left and right null vectors of
 *               the previous point (refreshed every step; the zero set does
 *               not depend on them)
 *   stick_limit g = |F_t| - mu0 F_n (stick models)
 *   stall       g = phidot_R (slip models)
 *   stability   g = the largest non-cyclic Floquet multiplier's modulus - 1
 *               (usm_floquet_compute): the stationary solution is an
 *               equilibrium of the frame turning with the excitation, whose
 *               eigenvalue crossing the imaginary axis is this multiplier
 *               crossing the unit circle
 *   friction_saturation  slip models: F_t / F_n at the friction law's
 *               supremum, where the rotor speed diverges.  As the sweep
 *               locates it: the branch point at a rotor speed W so large
 *               that the law equals its supremum to rounding (slip velocity
 *               1e15 m/s at the seed), g = phidot_R - W with W fixed along
 *               the curve.  A seed line whose F_t / F_n comes within 0.1 %
 *               of the supremum ends there, at that point.
 * The rows of r are the generated Jacobians (r_u, r_px, r_py); g's row is
 * analytic for tilt_zero and stall and by central differences for the
 * others.  A curve point is a solution of the extended system to the
 * engine's Newton tolerance (1e-12 in the scaled unknowns).
 *
 * Seeds: along the box's edges and ny (nx) interior lines of constant y (x),
 * every root of the full search (usm_steady_solve) at the lines' nodes is
 * continued in the line's parameter with the defining functions as the
 * engine's test functions; each located zero is a point of a curve.  A seed
 * on a curve already traced is dropped.
 *
 * Ends and codimension-two points: a curve ends at the box, at theta = 0
 * (a point where it meets tilt_zero), at the tilt range's upper end
 * (range_end), or where the continuation is lost.  On each curve the other
 * kinds' defining functions are test functions too: their zeros are the
 * points where two curves meet ("fold/stick_limit", ...); on a fold curve
 * the quadratic coefficient w' r_uu[v, v] (central differences) has its
 * zero at a cusp ("cusp").
 *
 * Regions: the box rastered (raster x raster cells), the cells crossed by a
 * curve removed, the rest split into connected regions; each region's
 * sample point is its cell farthest from the curves, classified by
 * usm_point_evaluate_op (usm_map.h), the function of `usm map`, with the same
 * operating-point rule (usm_op_options).
 *
 * The imperfect motor (variant imperfect): its steady motion is a periodic
 * orbit, and the curves are contact_loss (F_n_min = 0 over the orbit) and,
 * in stick models, stick_loss (the largest |F_t| - mu0 F_n over it = 0):
 * the orbit's periodicity condition in the state at t0 and both parameters
 * plus g = 0, continued by the engine from the events of one-parameter
 * periodic sweeps (usm_periodic_sweep.h) along the box's four edges, each
 * from its edge to where it leaves the box (envelope_periodic.c).  A curve
 * point is a solution to the sweep's corrector tolerance (1e-8 in the scaled
 * unknowns).  With the option stability, also `stability` (a complex pair
 * e^{+-i omega} of the orbit's non-cyclic Floquet multipliers on the unit
 * circle, Neimark-Sacker, or a real one at -1) and `fold` (a real one at
 * +1, where the branch turns): the periodicity plus the bordered test of
 * R - mu I, R the monodromy with the cyclic directions deflated, mu =
 * e^{i omega} with omega an unknown (Re g = Im g = 0) or mu = +-1, from
 * the edge sweeps' stability_change and fold events; codimension-two
 * points where they meet each other ("fold/stability") or contact_loss /
 * stick_loss ("stability/contact_loss", ...).  Where the critical
 * multiplier is a complex pair the curve's `frequency` holds f omega / 2 pi
 * at each point, as the sweep's
 * squeal frequency (envelope_periodic_stability.c).  Its regions are classified by
 * the periodic orbit there (usm_periodic_solve from the nearest curves'
 * orbits, else the ideal motor, else continued from the box's sides):
 * contact_open, stick_lost; else squeal (unstable through a complex pair,
 * its frequency in the message), unstable (through a real multiplier),
 * stick_admissible (contact_closed in slip models); no_orbit.  The
 * options lines, nodes, h_max, steady, floquet and op do not apply to them.
 *
 * Life cycle (GSL style): usm_envelope_alloc, usm_envelope_run, accessors,
 * usm_envelope_free.  Thread safety: as usm.h.
 */
#ifndef USM_ENVELOPE_H
#define USM_ENVELOPE_H

#include <stddef.h>
#include <stdio.h>

#include "usm.h"
#include "usm_map.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
    USM_ENVELOPE_TILT_ZERO = 0,
    USM_ENVELOPE_FOLD = 1,
    USM_ENVELOPE_STICK_LIMIT = 2,
    USM_ENVELOPE_STALL = 3,
    USM_ENVELOPE_STABILITY = 4,
    USM_ENVELOPE_FRICTION_SATURATION = 5,
    USM_ENVELOPE_CONTACT_LOSS = 6,   /* imperfect models: the orbit's F_n_min = 0 */
    USM_ENVELOPE_STICK_LOSS = 7,     /* imperfect stick models: friction_needed_max = mu0 */
    USM_ENVELOPE_SEPARATION_FOLD = 8, /* unilateral models: a multiplier +1 of the orbit with
                                         separation (the periodic sweep's `fold` of it: the
                                         branch turns back, or its symmetry breaks) */
    USM_ENVELOPE_SEPARATION_STABILITY = 9, /* unilateral models: a multiplier -1 of the orbit
                                              with separation (the sweep's stability_change of
                                              kind period_doubling of it) */
    USM_ENVELOPE_SEPARATION_GRAZING = 10 /* unilateral models: the orbit with separation's
                                            closed phases vanish (F_n just after the landing
                                            impact = 0; past it the rotor only touches) */
} usm_envelope_kind;
#define USM_ENVELOPE_NKINDS 11

/* "tilt_zero", "fold", "stick_limit", "stall", "stability",
 * "friction_saturation", "contact_loss", "stick_loss", "separation_fold",
 * "separation_stability", "separation_grazing"; NULL for another value. */
const char *usm_envelope_kind_name(usm_envelope_kind kind);

/* One axis of the box: parameter `name` from lo to hi (lo < hi). */
typedef struct usm_envelope_axis {
    const char *name;
    double lo, hi;
} usm_envelope_axis;

typedef struct usm_envelope_options {
    usm_envelope_axis x, y;  /* no default: both must be set */
    int lines;               /* interior seed lines per direction (default 3) */
    int nodes;               /* full searches per seed line (default 9, >= 2) */
    double h_max;            /* longest continuation step, scaled arclength
                                (the box's sides have length 1; default 0.02) */
    int max_points;          /* per curve and direction (default 4000) */
    int stability;           /* 1: stability curves (default 1); imperfect models:
                                also the orbits' fold curves */
    int raster;              /* cells per side of the region raster (default 120) */
    usm_steady_options steady; /* the seeds' full searches and the tilt range */
    double t0;               /* Floquet start time [s] (default 0) */
    usm_floquet_options floquet;
    usm_op_options op;       /* the regions' operating-point rule (as usm map;
                                default: no simulation from rest) */
} usm_envelope_options;

/* Defaults as listed; x and y zero (name NULL). */
void usm_envelope_options_default(usm_envelope_options *opt);

/* How a curve ends at one side. */
typedef enum {
    USM_ENVELOPE_END_BOX = 0,      /* at the box's boundary */
    USM_ENVELOPE_END_TILT_ZERO = 1,/* at theta = 0 (a codimension-two point) */
    USM_ENVELOPE_END_RANGE = 2,    /* at the tilt range's upper end */
    USM_ENVELOPE_END_CLOSED = 3,   /* the curve closed on itself */
    USM_ENVELOPE_END_LOST = 4,     /* the continuation was lost */
    USM_ENVELOPE_END_LIMIT = 5,    /* max_points reached */
    USM_ENVELOPE_END_CORNER = 6    /* where another extreme takes over: of the orbit's
                                      F_n (stick excess) in imperfect models, or another
                                      pair of multipliers on a stability curve; the next
                                      curve of the kind starts there */
} usm_envelope_end;

/* "box", "tilt_zero", "range_end", "closed", "lost", "max_points", "corner" */
const char *usm_envelope_end_name(usm_envelope_end end);

typedef struct usm_envelope_curve {
    usm_envelope_kind kind;
    size_t npoints;
    const double *xy;        /* npoints (x, y) pairs, in order along the curve */
    const double *u;         /* npoints x nu stationary unknowns there (imperfect
                                models: the orbit's state at t0, nu = nx) */
    int nu;
    usm_envelope_end end[2]; /* at the first and at the last point */
    const double *frequency; /* imperfect models' stability curves: per point the
                                critical complex pair's frequency [Hz]
                                (usm_squeal_frequency of the orbit's), NaN where the
                                critical multiplier is real; NULL on other curves */
} usm_envelope_curve;

/* A point where two curves meet, or a fold curve's cusp. */
typedef struct usm_envelope_codim2 {
    char type[40];           /* "cusp", or "KIND/KIND" (two kind names) */
    double x, y;
    size_t curve;            /* the curve it was found on */
    double u[USM_MAX_NU];    /* the stationary unknowns there (imperfect models:
                                zeros; the curves' u hold the orbit) */
} usm_envelope_codim2;

typedef struct usm_envelope_region {
    double x, y;             /* its sample point */
    size_t cells;            /* raster cells */
    usm_point_op_class cls;  /* usm_point_evaluate_op's class there (imperfect
                                models: USM_POINT_OP_NOT_EVALUATED) */
    char class_name[32];     /* usm_point_op_class_name(cls); imperfect models: the
                                periodic orbit's "stick_admissible", "stick_lost",
                                "contact_open", "contact_closed" (slip models),
                                "squeal", "unstable" or "no_orbit"; unilateral
                                models, where the bilateral orbit's contact
                                opens: "separating" or "separating_unstable"
                                (the orbit with separation from rest) */
    int root;                /* the operating point's root index, or -1 */
    int roots;               /* stationary roots at the sample */
    char message[USM_MSG_LEN];
} usm_envelope_region;

typedef struct usm_envelope usm_envelope;

/* An envelope for model m, or NULL when out of memory. */
usm_envelope *usm_envelope_alloc(const usm_model *m);
/* NULL is allowed. */
void usm_envelope_free(usm_envelope *e);

/* Curves, codimension-two points and regions of the box.  USM_OK,
 * USM_EINPUT (an unknown parameter, lo >= hi, the same parameter twice, bad
 * parameters or options: the message names the field), USM_EFAILED. */
int usm_envelope_run(usm_envelope *e, const usm_params *p, const usm_envelope_options *opt);

/* Why the last run failed ("" after success).  Owned by e. */
const char *usm_envelope_message(const usm_envelope *e);
/* Curves of the last run. */
size_t usm_envelope_curve_count(const usm_envelope *e);
/* Curve i, NULL when out of range; valid until the next run or free. */
const usm_envelope_curve *usm_envelope_curve_at(const usm_envelope *e, size_t i);
/* Codimension-two points of the last run. */
size_t usm_envelope_codim2_count(const usm_envelope *e);
/* Codimension-two point i, NULL when out of range. */
const usm_envelope_codim2 *usm_envelope_codim2_at(const usm_envelope *e, size_t i);
/* Regions of the last run. */
size_t usm_envelope_region_count(const usm_envelope *e);
/* Region i, NULL when out of range. */
const usm_envelope_region *usm_envelope_region_at(const usm_envelope *e, size_t i);
/* The region holding (x, y), or -1 outside the box or in a raster cell a
 * curve crosses. */
int usm_envelope_region_of(const usm_envelope *e, double x, double y);
/* Seeds found, and seeds dropped as lying on a curve already traced. */
void usm_envelope_seed_counts(const usm_envelope *e, size_t *found, size_t *dropped);

/* Writers (runtime/write/envelope_out.c): the object of `usm envelope
 * --json` ({"curves": [{"kind", "points": [[x, y], ...], "ends"}], "regions":
 * [{"class", "root", "sample": [x, y], ...}], "codim2": [...], ...}), and
 * the CSV: one row per curve point (curve,kind,x,y), then the codimension-two
 * points and the regions as comment lines.  0, or -1 on a write error. */
int usm_envelope_write_json(const usm_envelope *e, const usm_model *m, FILE *out);
/* The CSV, as above. */
int usm_envelope_write_csv(const usm_envelope *e, FILE *out);
/* The data file of `usm envelope --plot` (data/plots/envelope.gp reads it):
 * the CSV's header; the curves' rows, a blank line after each curve; then
 * rows "-1,KIND,x,y" with KIND region:CLASS (every raster cell off the
 * curves, at its centre), sample:CLASS[ #ROOT] (each region's sample) and
 * codim2:TYPE.  0, or -1 on a write error. */
int usm_envelope_write_plot_csv(const usm_envelope *e, FILE *out);

#ifdef __cplusplus
}
#endif

#endif /* USM_ENVELOPE_H */
