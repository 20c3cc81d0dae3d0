/* usm_periodic_sweep.h: continuation of the periodic orbit of a real motor
 *.
 *
 * The orbit of usm_periodic_solve is followed in one parameter lambda (any
 * field of usm_params) by the continuation engine (usm_cont.h): the branch
 * is the zero set of the shooting's periodicity condition in the state at
 * t0 and lambda, followed by pseudo-arclength continuation (the Jacobian
 * from the monodromy and a difference in lambda); the grid values are
 * landed on by Newton with lambda held, to usm_periodic_solve's tolerance.
 * Events are zeros of test functions located by Brent's method on the
 * branch's arc to event_tol in the scaled arclength (about event_tol times
 * the range in lambda), independent of the grid:
 *   contact_loss       F_n_min = 0: the contact opens (the times a period
 *                      counted on the orbit at the step's open end:
 *                      openings_per_period, twice for a mode split's
 *                      2 Omega wobble)
 *   stick_loss         stick models (3dof): friction_needed_max = mu0, the
 *                      zero of max over the orbit of |F_t| - mu0 F_n
 *   stability_change   the largest non-cyclic multiplier modulus = 1; its kind
 *                      from the critical multiplier there: +1 fold, -1
 *                      period_doubling, a complex pair neimark_sacker
 *                      (|Im| > USM_COMPLEX_PAIR_TOL |lambda|), which carries
 *                      the squeal frequency of the pair (usm.h)
 *   fold               the branch turns back (d lambda/ds = 0, located) and
 *                      ends there; the rows beyond have no orbit (no orbit
 *                      carried by the event)
 *   friction_saturation  slip models: F_t/F_n reaches the friction law's
 *                      supremum over the whole orbit and the rotor speed
 *                      diverges; the branch ends there (no orbit).  Located
 *                      directly as the saturated limit orbit (the stator's
 *                      orbit on which the mean rotor acceleration vanishes,
 *                      the rotor speed held where the slip is 1e15 m/s, as
 *                      the stationary sweep's), to the event tolerance, once
 *                      friction_needed_max passes 0.999 of the supremum or
 *                      the continuation loses the branch.
 * Unilateral models (variant imperfect_unilateral; docs/unilateral.md): the
 * branch is the bilateral orbit's; at every grid point where its contact
 * opens the point also carries the orbit with separation (separating,
 * hybrid).  Those are followed as a branch of their own
 * (study/periodic_sweep_hybrid.c): Newton (usm_hybrid_solve_from) from the
 * secant prediction of the last two; a result whose separation fraction or
 * mean speed jumps (3 times the last step's change, and more than 2e-3 /
 * 1e-3 relative) is checked by paths of 2, 4, 8 substeps, accepted where two
 * successive paths end on the same orbit; the first orbit, and every one
 * after a branch is lost, from usm_hybrid_solve (a simulation from rest).
 * Events:
 *   contact_regained   F_n_min = 0 where the contact closes again (the
 *                      contact_loss crossing in the other direction)
 *   grazing            the mode sequence of the followed orbit changes
 *                      between two grid points (an orbit touches a guard
 *                      tangentially there): located by bisection on the
 *                      parameter (each trial continued from the bracket's
 *                      end of the first sequence) to the event tolerance,
 *                      where the two sequences' orbits meet there (their
 *                      separation fractions and mean speeds agree to 1e-3;
 *                      else the first sequence's branch ended in between:
 *                      branch_switch); its text says when a trial failed
 *                      (then the value is the last bracket's middle)
 *   branch_switch      the sweep leaves the followed orbit for the one the
 *                      motor runs on: either the followed orbit is unstable
 *                      (largest non-cyclic |lambda| >= 1) and
 *                      usm_hybrid_solve (a simulation from rest, then
 *                      Newton: the start-up's attractor) finds a stable
 *                      orbit there, or the branch cannot be followed to the
 *                      point (it ends, or Newton fails; branch_lost) and
 *                      usm_hybrid_solve finds an orbit that does not
 *                      continue it (at this point, or at a later one when
 *                      none is found in between), or a change of mode
 *                      sequence is no grazing (above; branch_lost, the
 *                      other orbit Newton's).  The
 *                      point carries the new orbit (switched) and the sweep
 *                      follows it from there; the event, at the grid point,
 *                      carries both orbits (hybrid: the new one; hybrid_left:
 *                      the unstable one, or the branch's last at
 *                      branch_last; unstable_from: where the followed orbit
 *                      turned unstable, located by Brent's method on
 *                      max |lambda| = 1 along it to 1e-6 of the range).
 *                      Where the simulation's Newton finds no
 *                      stable orbit (it converges to the same unstable one,
 *                      e.g. when that is only weakly unstable, or fails) the
 *                      point keeps the unstable followed orbit.
 *   stability_change   also where the followed orbit with separation
 *                      crosses max |lambda| = 1 between two grid points of
 *                      one branch and mode sequence (continued; not across a
 *                      branch_switch, a lost branch or a grazing), losing
 *                      stability or becoming stable: located by Brent's
 *                      method as unstable_from (the same value where a
 *                      branch_switch follows at the next point; both events
 *                      are reported), its kind, multiplier and squeal
 *                      frequency by the bilateral rule from the located
 *                      orbit's multipliers; has_orbit 0 (the bilateral
 *                      orbit's contact is open there), has_hybrid 1 with the
 *                      located orbit with separation in `hybrid` (JSON:
 *                      `orbit`, as the branch_switch's new orbit).
 * Events within one step are reported in sweep order; stick_loss is found
 * also in a step at whose end the contact is already open.
 * The points are the requested grid values in sweep order.
 *
 * Thread safety: one usm_periodic_sweep per thread; no global state.
 */
#ifndef USM_PERIODIC_SWEEP_H
#define USM_PERIODIC_SWEEP_H

#include <stdio.h>

#include "usm.h"
#include "usm_periodic.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
    USM_PEVENT_CONTACT_LOSS = 0,
    USM_PEVENT_STICK_LOSS = 1,
    USM_PEVENT_FOLD = 2,
    USM_PEVENT_STABILITY_CHANGE = 3, /* also of the followed orbit with separation
                                        (has_hybrid) on unilateral models */
    USM_PEVENT_FRICTION_SATURATION = 4,
    USM_PEVENT_CONTACT_REGAINED = 5, /* unilateral models: F_n_min = 0 closing */
    USM_PEVENT_GRAZING = 6,          /* unilateral models: the mode sequence changes */
    USM_PEVENT_BRANCH_SWITCH = 7     /* unilateral models: the continued orbit with separation
                                        is unstable; the sweep follows the stable one a
                                        simulation from rest settles on */
} usm_pevent_type;

/* How the critical multiplier crosses the unit circle. */
typedef enum {
    USM_CROSSING_NONE = 0,          /* not a stability change */
    USM_CROSSING_FOLD = 1,          /* a real multiplier through +1 */
    USM_CROSSING_PERIOD_DOUBLING = 2, /* a real multiplier through -1 */
    USM_CROSSING_NEIMARK_SACKER = 3 /* a complex pair */
} usm_crossing_kind;

/* "contact_loss", "stick_loss", "fold", "stability_change",
 * "friction_saturation", "contact_regained", "grazing", "branch_switch". */
const char *usm_pevent_name(usm_pevent_type type);
/* "", "fold", "period_doubling", "neimark_sacker". */
const char *usm_crossing_name(usm_crossing_kind kind);

/* How a followed branch of orbits with separation ended (a branch_switch
 * with branch_lost). */
typedef enum {
    USM_BRANCH_END_NONE = 0,        /* not a lost branch */
    USM_BRANCH_END_NEWTON = 1,      /* Newton failed on it (where, not located) */
    USM_BRANCH_END_FOLD = 2,        /* it turns back: a fold, located */
    USM_BRANCH_END_SEQUENCE = 3     /* its mode sequence changes and no orbit continues it */
} usm_branch_end_how;

/* "", "newton_fails", "fold", "mode_sequence". */
const char *usm_branch_end_how_name(usm_branch_end_how how);

/* One event located on the branch. */
typedef struct usm_periodic_event {
    usm_pevent_type type;
    usm_crossing_kind kind;     /* stability_change only, else USM_CROSSING_NONE */
    double value;               /* parameter value of the event */
    int has_orbit;              /* 0 for fold (no orbit at the turning point),
                                   friction_saturation (infinite rotor speed) and the
                                   events of the orbits with separation */
    usm_periodic_result orbit;  /* the orbit at `value` when has_orbit */
    double multiplier_re, multiplier_im; /* stability_change: the critical multiplier */
    double squeal_frequency;    /* neimark_sacker: the emerging vibration's frequency [Hz],
                                   usm_squeal_frequency(1 / orbit.period (hybrid.period
                                   when has_hybrid), multiplier_re, multiplier_im) in
                                   [0, f/2] (usm.h); NaN otherwise */
    char what[USM_MSG_LEN];     /* one sentence */
    /* branch_switch (has_hybrid 1): the orbit with separation the sweep
     * follows from here (hybrid), and the continued one it leaves
     * (hybrid_left): unstable at `value`, or, when branch_lost, the last
     * orbit of the branch, at branch_last.  stability_change of an orbit
     * with separation (has_hybrid 1): hybrid the located orbit; the other
     * fields below unset (hybrid_left zero, branch_last and unstable_from
     * NaN) */
    int has_hybrid;
    usm_hybrid_result hybrid, hybrid_left;
    int branch_lost;
    double branch_last;
    double unstable_from;       /* not branch_lost: where the followed orbit turned unstable
                                   (max |lambda| = 1 on it, located by Brent to the event
                                   tolerance), NaN when not located */
    double branch_end;          /* branch_switch with branch_lost: where the followed branch
                                   ended, located on it by the continuation (a fold, or a
                                   change of its mode sequence that no orbit continues), NaN
                                   when Newton failed on it before either; 0 on other events */
    usm_branch_end_how branch_end_how; /* branch_switch with branch_lost: how it ended */
} usm_periodic_event;

/* One requested grid value and the orbit there. */
typedef struct usm_periodic_point {
    double value;
    int converged;              /* the branch's orbit exists here */
    usm_periodic_result orbit;
    char error[USM_MSG_LEN];    /* why not converged; unilateral models: also why a converged
                                   point whose contact opens has no orbit with separation */
    /* unilateral models (usm_model.unilateral) where the contact opens on the
     * bilateral orbit: the orbit with separation (followed from the last
     * one, or usm_hybrid_solve: see the header comment) */
    int separating;             /* 1: `hybrid` holds it */
    usm_hybrid_result hybrid;
    int switched;               /* 1: `hybrid` is the new orbit of a branch_switch at this
                                   point */
} usm_periodic_point;

/* What to sweep (usm_periodic_sweep_options_default, then over/from/to/points). */
typedef struct usm_periodic_sweep_options {
    const char *over;           /* a parameter name (usm_params_find) */
    double from, to;            /* from != to; to < from sweeps down */
    int points;                 /* 2 .. 1000000 (default 101) */
    double event_tol;           /* events to event_tol times |to - from| (default 1e-11) */
    usm_periodic_options periodic; /* the shooting's tolerances (usm_periodic_options_default) */
    void (*progress)(double fraction, void *ctx); /* NULL: silent */
    void *progress_ctx;
} usm_periodic_sweep_options;

/* Fill `opt` with the defaults listed above. */
void usm_periodic_sweep_options_default(usm_periodic_sweep_options *opt);

/* Continuation of one model's periodic orbit with the points and events of
 * its last run (opaque). */
typedef struct usm_periodic_sweep usm_periodic_sweep;

/* A sweep for model m (not NULL), or NULL when out of memory. */
usm_periodic_sweep *usm_periodic_sweep_alloc(const usm_model *m);
/* Free s; NULL is allowed. */
void usm_periodic_sweep_free(usm_periodic_sweep *s);

/* Follow the orbit from opt->from (started there from the ideal motor, as
 * usm_periodic_solve with x0 NULL) to opt->to.  USM_OK (grid points past the
 * end of the branch have converged = 0 and an error); USM_EINPUT (bad option
 * or parameter, a model without periodic orbit); USM_EFAILED (no orbit at
 * opt->from, out of memory).  Reason in usm_periodic_sweep_message. */
int usm_periodic_sweep_run(usm_periodic_sweep *s, const usm_params *p,
                           const usm_periodic_sweep_options *opt);

/* Number of grid points of the last run. */
size_t usm_periodic_sweep_count(const usm_periodic_sweep *s);
/* Point i of the last run in sweep order, NULL when out of range. */
const usm_periodic_point *usm_periodic_sweep_point_at(const usm_periodic_sweep *s, size_t i);
/* Number of events of the last run. */
size_t usm_periodic_sweep_event_count(const usm_periodic_sweep *s);
/* Event i of the last run (in sweep order), NULL when out of range. */
const usm_periodic_event *usm_periodic_sweep_event_at(const usm_periodic_sweep *s, size_t i);
/* Why the last run failed, or "".  Owned by s. */
const char *usm_periodic_sweep_message(const usm_periodic_sweep *s);

/* CSV of the last run: a header with units, one row per grid point (empty
 * fields where no orbit), then one comment line per event.  0, or -1 on a
 * write error. */
int usm_periodic_sweep_csv(const usm_periodic_sweep *s, FILE *out);

/* The JSON object {over, model, periodic: true, parameters, points[],
 * events[]} and a newline; p: the parameters apart from the swept one.  0, or
 * -1 on a write error or when out of memory. */
int usm_periodic_sweep_write_json(const usm_periodic_sweep *s, const usm_params *p, FILE *out);

#ifdef __cplusplus
}
#endif

#endif /* USM_PERIODIC_SWEEP_H */
