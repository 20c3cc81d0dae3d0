/* usm_sweep.h: motor characteristics by continuation of the stationary solution.
 *
 * Math: the stationary residual r(u; lambda) = 0, u = (theta, alpha[, phidot_R]),
 * is followed in one parameter lambda (any field of usm_params) by
 * pseudo-arclength continuation with the generated Jacobians dr/du and
 * dr/dp, so the branch is not lost where it turns (a fold, d lambda/ds = 0).
 * Along the branch the sweep reports events, each located to tolerance:
 *   fold                 a turning point: d lambda/ds = 0, the branch turns back
 *                        (only there; the ends below have their own names)
 *   tilt_zero            the tilt vanishes: the branch reaches theta = 0 (located
 *                        there exactly; the stator stops wobbling, the motor
 *                        stops driving); no solution with theta > 0 beyond it
 *   range_end            the branch leaves the searched tilt range
 *                        [steady.theta_min, steady.theta_max] anywhere else
 *   stick_limit          stick models: F_t = mu0 F_n (stick no longer admissible);
 *                        not reported for slip models, where F_t = mu(v) F_n holds
 *                        by construction
 *   stall                slip models: the rotor speed phidot_R passes 0 (the rotor
 *                        stands still under the load)
 *   friction_saturation  slip model: the friction needed, F_t/F_n, reaches the
 *                        supremum of the friction law (no rotor speed balances)
 *   stability_change     the largest non-cyclic Floquet multiplier crosses |lambda| = 1
 *   maximum, minimum     a user monitor (usm_sweep_monitor) is extremal along the
 *                        branch: d y/ds = 0 (central differences along the tangent)
 *   crossing             a user monitor crosses one of its levels
 *   operating_point_jump the operating point (usm_operating_point.h: the stable
 *                        root the motor runs at) moves to another branch, or
 *                        appears or vanishes (the motor does not start from
 *                        rest; no root is stable where the operating point is
 *                        not the sweep's branch, else stability_change says it),
 *                        between two neighbouring grid points where it is known
 *                        (usm_sweep_options.operating_point); not located: the
 *                        event's value is the midpoint of the two grid values,
 *                        named in `what`
 * The points of the result are the requested grid values lambda_i on the
 * branch, in sweep order.
 * An event is found where its quantity changes sign between the two ends of
 * an accepted continuation step (at most 1/20 of the range): a quantity
 * that changes sign twice within one step (a level crossed twice, an
 * extremum pair, stick lost and regained) is not reported.
 *
 * Thread safety: as usm.h.  Distinct sweeps may run in distinct threads at
 * the same time; one usm_sweep must not be shared without a lock.
 * usm_sweep_run may compute the Floquet multipliers in worker threads of its
 * own (usm_sweep_options.threads).
 */
#ifndef USM_SWEEP_H
#define USM_SWEEP_H

#include "usm.h"
#include "usm_map.h" /* usm_point_op */

#ifdef __cplusplus
extern "C" {
#endif

/* What happens at an event of the sweep (see the top of this file). */
typedef enum {
    USM_EVENT_FOLD = 0,
    USM_EVENT_STICK_LIMIT = 1,
    USM_EVENT_FRICTION_SATURATION = 2,
    USM_EVENT_STABILITY_CHANGE = 3,
    USM_EVENT_TILT_ZERO = 4,
    USM_EVENT_RANGE_END = 5,
    USM_EVENT_STALL = 6,
    USM_EVENT_MAXIMUM = 7,
    USM_EVENT_MINIMUM = 8,
    USM_EVENT_CROSSING = 9,
    USM_EVENT_OPERATING_POINT_JUMP = 10
} usm_event_type;

/* "fold", "stick_limit", "friction_saturation", "stability_change",
 * "tilt_zero", "range_end", "stall", "maximum", "minimum", "crossing",
 * "operating_point_jump" */
const char *usm_event_name(usm_event_type type);

/* One event located along the branch. */
typedef struct usm_sweep_event {
    usm_event_type type;
    double value;           /* parameter value where the event happens */
    usm_steady_solution sol; /* the stationary solution there (when it exists) */
    int has_sol;             /* 0 when no stationary solution exists at `value`
                              * (friction_saturation: the rotor speed diverges) */
    char what[USM_MSG_LEN];  /* what changes there, one sentence */
    char monitor[32];        /* maximum, minimum, crossing: the monitor's name */
    double monitor_value;    /* and its value there */
} usm_sweep_event;

/* A user monitor function (as AUTO's user points, COCO's monitor functions):
 * a named scalar y of the stationary solution `sol` at parameters p (p holds
 * the swept value).  Called from the thread that runs the sweep; must be
 * smooth along the branch for extremum events. */
typedef double (*usm_monitor_fn)(const usm_steady_solution *sol, const usm_params *p, void *ctx);

#define USM_SWEEP_MAX_LEVELS 4
#define USM_SWEEP_MAX_MONITORS 8

/* The quantities of a stationary solution a monitor can watch by name (the
 * command's --extremum and --crossing, the Python package's sweep). */
#define USM_SWEEP_QUANTITIES "theta, alpha, rotor_speed, speed, F_n, F_t, mu_used, v_rel"

/* The monitor function of the quantity named by the `len` characters at
 * `name`: theta, alpha [rad], rotor_speed [1/s], speed (= -rotor_speed),
 * F_n, F_t [N], mu_used, v_rel [m/s] of the solution.  Returns the
 * quantity's name as a static string (for usm_sweep_monitor.name) with its
 * function in *fn, or NULL for another name. */
const char *usm_sweep_quantity(const char *name, size_t len, usm_monitor_fn *fn);

/* What to watch: maxima and minima of y along the branch, and the values of
 * the swept parameter where y crosses given levels. */
typedef struct usm_sweep_monitor {
    const char *name;            /* short, no spaces (<= 31 characters) */
    usm_monitor_fn fn;
    void *ctx;
    int extrema;                 /* 1: report maxima and minima */
    int nlevels;                 /* 0 .. USM_SWEEP_MAX_LEVELS */
    double levels[USM_SWEEP_MAX_LEVELS];
} usm_sweep_monitor;

/* One requested grid value of the swept parameter and the solution there. */
typedef struct usm_sweep_point {
    double value;                 /* swept parameter value */
    int converged;                /* a stationary solution exists here */
    usm_steady_solution sol;      /* the branch's root (the sweep never jumps to another) */
    int roots;                    /* stationary solutions at this value (the full
                                   * search's count, with the branch's root);
                                   * > 1: the others lie on other branches */
    int has_floquet;
    usm_floquet_result floquet;
    char error[USM_MSG_LEN];      /* why not converged */
    char floquet_error[USM_MSG_LEN]; /* why the multipliers failed here ("" when
                                   * has_floquet or not asked for); the sweep
                                   * goes on at the other points */
    int has_op;                   /* 1: op filled (usm_sweep_options.operating_point) */
    usm_point_op op;              /* the operating point at this value: every root's
                                   * multipliers and the rule of usm_operating_point
                                   * (usm_point_evaluate_op); op.index counts the
                                   * full search's roots, smallest tilt first */
} usm_sweep_point;

/* What to sweep and how (usm_sweep_options_default). */
typedef struct usm_sweep_options {
    const char *over;   /* parameter name */
    double from, to;
    int points;         /* >= 2 */
    int floquet;        /* compute multipliers at every point (1, default) */
    double t0;          /* Floquet start time [s] (default 0) */
    usm_floquet_options floquet_options; /* method and tolerances of the multipliers
                        * (usm_floquet_options_default) */
    int threads;        /* worker threads for the Floquet part (default 2; 1 = serial) */
    void (*progress)(double fraction, void *ctx); /* NULL: silent.  Called with
                        * fractions in [0, 1], from the calling thread or a
                        * worker, never two calls at once. */
    void *progress_ctx;
    usm_steady_options steady; /* tilt range of the full searches; the branch
                        * ends (event range_end) where theta leaves this range */
    const usm_sweep_monitor *monitors; /* NULL or nmonitors of them (default none) */
    int nmonitors;      /* 0 .. USM_SWEEP_MAX_MONITORS */
    int operating_point; /* 1: the operating point at every grid point and the
                        * operating_point_jump events (needs floquet); default 1 */
    usm_op_options op;  /* its rule (usm_op_options_default: no simulation from
                        * rest; points with several roots then have an unknown
                        * operating point and no jump is reported next to them) */
} usm_sweep_options;

/* Fill `opt` with the defaults (those listed above); the caller then sets
 * over, from, to and points. */
void usm_sweep_options_default(usm_sweep_options *opt);

/* Continuation of one model's stationary solution, with the points and
 * events of the last run (opaque). */
typedef struct usm_sweep usm_sweep;

/* A sweep for model m (not NULL), or NULL when out of memory. */
usm_sweep *usm_sweep_alloc(const usm_model *m);
/* Free s with its points and events; NULL is allowed. */
void usm_sweep_free(usm_sweep *s);

/* USM_OK (points may still be unconverged where no solution exists),
 * USM_EINPUT (bad option or parameter; message names it), USM_EFAILED. */
int usm_sweep_run(usm_sweep *s, const usm_params *p, const usm_sweep_options *opt);

/* Number of points of the last run (the requested grid). */
size_t usm_sweep_count(const usm_sweep *s);
/* Point i of the last run in sweep order, NULL when out of range. */
const usm_sweep_point *usm_sweep_point_at(const usm_sweep *s, size_t i);
/* Number of events located by the last run. */
size_t usm_sweep_event_count(const usm_sweep *s);
/* Event i of the last run, NULL when out of range. */
const usm_sweep_event *usm_sweep_event_at(const usm_sweep *s, size_t i);
/* Why the last run failed (see usm_sweep_run).  Owned by s; valid until the
 * next run or usm_sweep_free. */
const char *usm_sweep_message(const usm_sweep *s);

/* The operating point's rule of the last run (usm_op_rule_text of its
 * options), or NULL when the run judged no operating point. */
const char *usm_sweep_op_rule(const usm_sweep *s);

#ifdef __cplusplus
}
#endif

#endif /* USM_SWEEP_H */
