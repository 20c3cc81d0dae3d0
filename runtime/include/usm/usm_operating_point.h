/* usm_operating_point.h: the point the motor runs at.
 *
 * Definition: the operating point is the stable stationary root that the
 * motor reaches when it is started from rest.  When no root is stable, or
 * the start-up from rest reaches none (the wobble decays: the motor does not
 * start), that is the answer -- never a silent pick of another root.
 *
 * At rest the stator has no tilt.  At theta = 0 the preload's contact
 * moment, of size sqrt((R F0)^2 + (H T / R)^2) in the paper's models, holds
 * the stator against the excitation torque m0 when it is the larger: the
 * wobble cannot grow and the motor does not start, whatever roots exist
 * above.  The boundary is the tilt_zero condition, where the smallest root
 * is born at theta = 0 (F0 = sqrt(m0^2 - (H T / R)^2) / R = 0.99997 N at the
 * paper's other parameters).  usm_op_result.start_margin measures it from
 * the model's own stationary equations at theta = 0: m0 over the excitation
 * amplitude m0_0 that keeps a stationary solution there, minus 1 (> 0: the
 * excitation overcomes the preload's moment at rest; <= 0: rest holds).
 *
 * The rule (usm_operating_point), cheap where the answer is unambiguous:
 *  1. No root is stable: no operating point, USM_OP_NO_STABLE_ROOT.
 *  2. Exactly one root, it is stable and its start is not in doubt
 *     (start_margin > 0): root 0, USM_OP_ONLY_STABLE_ROOT, no simulation.
 *  3. Otherwise (several roots, at least one stable; or one stable root
 *     while rest holds or start_margin could not be computed) the point is
 *     ambiguous, and a simulation from rest decides where usm_op_options.
 *     from_rest asks for it: the run of usm_sim_run from rest (usm_simulate.h:
 *     the start at rest below every unstable root, the settling and decay
 *     rules) over `periods` excitation periods; it settles on a stable
 *     root k: k, USM_OP_REACHED_FROM_REST; the wobble decays:
 *     USM_OP_DOES_NOT_START; it settles on no root (too short, runaway, step
 *     cap, or on a root the multipliers call unstable): USM_OP_UNDECIDED,
 *     with the reason in message.  Not asked: USM_OP_UNDECIDED.
 *     The model simulated: the model itself, except that a paper-variant
 *     model in the z-x-z Euler angles (singular at theta = 0, where a start
 *     below a small unstable root lies: 1e-9 rad at F0 = 1.001 N, f = 38 kHz)
 *     is simulated as its twist_integrated variant in the tilt vector when
 *     that variant has the same roots (the two twist laws differ by
 *     c_t psi (1 - cos theta), O(theta^2 Omega t), and share the stationary
 *     solutions); sim_model says which.
 * starts_from_rest says what the simulation showed (1: settled on a root,
 * 0: the wobble decayed, -1: not simulated or neither).
 *
 * Thread safety: no global state; distinct calls may run at the same time.
 */
#ifndef USM_OPERATING_POINT_H
#define USM_OPERATING_POINT_H

#include "usm.h"
#include "usm_simulate.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Why the operating point is what it is. */
typedef enum {
    USM_OP_UNDECIDED = 0,        /* several roots and no simulation from rest asked, or the
                                    simulation settled on no root (see message) */
    USM_OP_ONLY_STABLE_ROOT = 1, /* exactly one root, and it is stable */
    USM_OP_REACHED_FROM_REST = 2,/* the simulation from rest settled on this stable root */
    USM_OP_NO_STABLE_ROOT = 3,   /* every root is unstable */
    USM_OP_DOES_NOT_START = 4    /* from rest the wobble decays */
} usm_op_reason;

/* "undecided", "only_stable_root", "reached_from_rest", "no_stable_root",
 * "does_not_start" (NULL for an unknown value). */
const char *usm_op_reason_name(usm_op_reason reason);

/* How usm_operating_point decides (usm_op_options_default). */
typedef struct usm_op_options {
    int from_rest;        /* 0: never simulate (default); 1: simulate the ambiguous points
                             (rule 3); USM_OP_FROM_REST_ALWAYS: every point with a stable root */
    double periods;       /* length of that simulation in excitation periods (default 400:
                             10.8 ms at 37 kHz, settle_periods 100 of them to hold) */
    usm_sim_options sim;  /* its options (default usm_sim_options_default; start, t0 and
                             duration are set by usm_operating_point: from rest at t0 = 0) */
} usm_op_options;

/* usm_op_options.from_rest: simulate every point that has a stable root, also
 * those rule 2 decides without (to measure the start threshold). */
#define USM_OP_FROM_REST_ALWAYS 2

/* Fill `opt` with the defaults listed above. */
void usm_op_options_default(usm_op_options *opt);

/* The operating point of one parameter point. */
typedef struct usm_op_result {
    int index;               /* the root index (into usm_steady_root), or -1: none */
    usm_op_reason reason;
    int starts_from_rest;    /* 1 yes, 0 no (the wobble decays), -1 not simulated or undecided */
    int simulated;           /* 1: a simulation from rest ran; sim is its summary */
    usm_sim_summary sim;
    double wall;             /* seconds the decision took (the simulation's, mostly) */
    char message[USM_MSG_LEN]; /* the answer in words, with the reason when undecided */
    double start_margin;     /* m0 / m0_0 - 1 (header comment); NaN when not computed */
    int ambiguous;           /* 1: rule 3 applies (a simulation decides) */
    const usm_model *sim_model; /* the model simulated (NULL: none) */
} usm_op_result;

/* The rule a study applies to its points under options o (NULL: the
 * defaults), in words, for its output: which points a start-up from rest
 * decides and what the others get.  A static string. */
const char *usm_op_rule_text(const usm_op_options *o);

/* The start margin of parameters p under model m (header comment): m0 over
 * the excitation amplitude that keeps a stationary solution at theta = 0,
 * minus 1, by Newton on the model's stationary residuals with theta fixed at
 * 0 and m0 free.  USM_OK (*margin set), or USM_ENOSOLUTION when Newton does
 * not converge from any of its seeds. */
int usm_op_start_margin(const usm_model *m, const usm_params *p, double *margin);

/* The operating point of the roots of the last usm_steady_solve of s (solved
 * with the default options at parameters p, model m) whose multipliers are
 * fl (usm_floquet_roots: one per root), by the rule of this header.  opt may
 * be NULL (the defaults: no simulation).  USM_OK (out filled, whatever the
 * answer), USM_EINPUT for bad options (message in out->message), USM_EFAILED
 * when out of memory.  A simulation that stops early is an answer
 * (USM_OP_UNDECIDED), not a failure. */
int usm_operating_point(const usm_model *m, const usm_params *p, const usm_steady *s,
                        const usm_floquet_result *fl, const usm_op_options *opt,
                        usm_op_result *out);

#ifdef __cplusplus
}
#endif

#endif /* USM_OPERATING_POINT_H */
