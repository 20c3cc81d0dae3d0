/* usm_operating_point.h: the point the motor runs at (issue 20).
 *
 * Definition: the operating point is the stable stationary root that the
 * motor reaches when it is started from rest.  When no root is stable, or
 * the start-up from rest reaches none (the wobble decays: the motor does not
 * start), that is the answer -- never a silent pick of another root.
 *
 * The rule (usm_operating_point), cheap where the answer is unambiguous:
 *  1. No root is stable: no operating point, USM_OP_NO_STABLE_ROOT.
 *  2. Exactly one root, and it is stable: root 0, USM_OP_ONLY_STABLE_ROOT,
 *     without a simulation (unless one is asked for: rule 3 then decides).
 *  3. Otherwise (several roots, at least one stable) only a simulation from
 *     rest decides, and it runs only when asked (usm_op_options.from_rest):
 *     the run of usm_sim_run from rest (usm_simulate.h: tilt0, settling and
 *     decay rules) over `periods` excitation periods; it settles on a stable
 *     root k: k, USM_OP_REACHED_FROM_REST; the wobble decays:
 *     USM_OP_DOES_NOT_START; it settles on no root (too short, runaway, step
 *     cap, or on a root the multipliers call unstable): USM_OP_UNDECIDED,
 *     with the reason in message.  Not asked: USM_OP_UNDECIDED.
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
    int from_rest;        /* 1: simulate from rest (rule 3); default 0 */
    double periods;       /* length of that simulation in excitation periods (default 400:
                             10.8 ms at 37 kHz, settle_periods 100 of them to hold) */
    usm_sim_options sim;  /* its options (default usm_sim_options_default; start, t0 and
                             duration are set by usm_operating_point: from rest at t0 = 0) */
} usm_op_options;

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
} usm_op_result;

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
