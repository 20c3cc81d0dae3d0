/* usm_optimize.h: the best design over parameter bounds (issue 13).
 *
 * Maximize (or minimize) one output of the primary stationary solution
 * (usm_design.h's USM_SENS_* outputs; rotor_speed in magnitude) over chosen
 * parameters within bounds, subject to: a stationary solution exists; its
 * largest non-cyclic Floquet modulus is at most 1 - margin; stick is
 * admissible (F_t <= mu0 F_n) in a stick model unless allow_slip; and each
 * user constraint OUTPUT <= X or OUTPUT >= X.  NLopt's SLSQP with the analytic
 * sensitivities (usm_sensitivity_compute) as gradients, in variables
 * normalised to [0, 1], from `starts` deterministic points of a rank-1
 * lattice over the box; the best feasible end point wins.  At the optimum the
 * result carries the active constraints and bounds and the KKT residual
 * |grad f + sum lambda_i grad c_i| / |grad f| over the free variables
 * (lambda >= 0 by least squares): a check that the gradients agree with the
 * point found.
 *
 * Thread safety: no global mutable state; distinct usm_optimize objects may
 * be used from distinct threads at the same time, one object must not be
 * shared without a lock.
 */
#ifndef USM_OPTIMIZE_H
#define USM_OPTIMIZE_H

#include <stdio.h>

#include "usm.h"
#include "usm_design.h"

#ifdef __cplusplus
extern "C" {
#endif

#define USM_OPT_MAX_CONSTRAINTS 32
/* Room for every active constraint's text: the user ones, stability, stick
 * and one bound per varied parameter. */
#define USM_OPT_MAX_ACTIVE (USM_OPT_MAX_CONSTRAINTS + 2 + USM_NPARAMS)
#define USM_OPT_TEXT_LEN 128

/* A user constraint: output (USM_SENS_*) <= value (upper = 1) or >= value. */
typedef struct usm_opt_constraint {
    int output;
    int upper;
    double value;
} usm_opt_constraint;

/* What to optimise.  Fill with usm_opt_problem_init, then the add functions. */
typedef struct usm_opt_problem {
    int objective;                 /* USM_SENS_* (-1: not set) */
    int minimize;                  /* 0: maximize */
    int nvary;
    int vary[USM_NPARAMS];         /* usm_param_table indices */
    double lo[USM_NPARAMS], hi[USM_NPARAMS];
    int ncons;
    usm_opt_constraint cons[USM_OPT_MAX_CONSTRAINTS];
    double margin;                 /* stability margin D in [0, 1): max_modulus <= 1 - D */
    int allow_slip;                /* drop the stick constraint */
    int starts;                    /* 1 to 1000 */
} usm_opt_problem;

/* No objective, nothing varied, no constraint, margin 0.01, 8 starts. */
void usm_opt_problem_init(usm_opt_problem *pb);
/* Vary parameter `name` in [lo, hi].  USM_OK, or USM_EINPUT with
 * "vary: reason" in msg (unknown parameter, given twice, lo >= hi). */
int usm_opt_problem_add_vary(usm_opt_problem *pb, const char *name, double lo, double hi,
                             char msg[USM_MSG_LEN]);
/* Add the constraint `output` <= value (upper = 1) or >= value.  USM_OK, or
 * USM_EINPUT with "constraint: reason" in msg (unknown output, too many). */
int usm_opt_problem_add_constraint(usm_opt_problem *pb, const char *output, int upper,
                                   double value, char msg[USM_MSG_LEN]);
/* The whole problem for model m around parameters p: an objective, at least
 * one varied parameter, margin and starts in range, every corner of the box
 * admissible parameters (usm_params_check), no I_yy varied in an
 * axisymmetric model.  USM_OK, or USM_EINPUT with "FIELD: reason" in msg,
 * FIELD one of objective, vary, stability-margin, starts. */
int usm_opt_problem_check(const usm_opt_problem *pb, const usm_model *m, const usm_params *p,
                          char msg[USM_MSG_LEN]);

/* The optimum. */
typedef struct usm_opt_result {
    double value;                  /* the objective there (rotor_speed: magnitude) */
    usm_params params;             /* all parameters there */
    usm_steady_solution sol;       /* the primary stationary solution there */
    usm_floquet_result floquet;    /* its multipliers (usm_floquet_compute, t0 = 0) */
    int nactive;                   /* active constraints and bounds, as text */
    char active[USM_OPT_MAX_ACTIVE][USM_OPT_TEXT_LEN];
    double kkt_residual;
    int evaluations;               /* stationary solutions computed, all starts */
} usm_opt_result;

/* Workspace of one model (opaque). */
typedef struct usm_optimize usm_optimize;

/* Workspace for model m (not NULL), or NULL when out of memory. */
usm_optimize *usm_optimize_alloc(const usm_model *m);
/* Free o; NULL is allowed. */
void usm_optimize_free(usm_optimize *o);

/* Solve problem pb around parameters p (the values of the parameters not
 * varied).  USM_OK with *out; USM_EINPUT (usm_opt_problem_check failed);
 * USM_ENOSOLUTION when no start ends feasible (the message names the
 * constraint that cannot be met, or says no stationary solution exists);
 * USM_EFAILED on a numerical failure.  The message is in usm_optimize_message. */
int usm_optimize_run(usm_optimize *o, const usm_params *p, const usm_opt_problem *pb,
                     usm_opt_result *out);
/* Every stationary solution at the optimum of the last successful run (root
 * 0 is out->sol), owned by o, valid until the next run. */
const usm_steady *usm_optimize_steady(const usm_optimize *o);
/* Why the last run did not succeed, or "". */
const char *usm_optimize_message(const usm_optimize *o);

/* The `usm optimize --json` object of the last successful run of o (model m,
 * problem pb, result res) and a newline to out: objective, sense, value,
 * varied, parameters, active_constraints, kkt_residual, evaluations and the
 * stationary solution at the optimum as `usm steady --json` writes it
 * ("solution").  0, or -1 on a write error or when out of memory. */
int usm_optimize_write_json(const usm_optimize *o, const usm_model *m, const usm_opt_problem *pb,
                            const usm_opt_result *res, FILE *out);

#ifdef __cplusplus
}
#endif

#endif /* USM_OPTIMIZE_H */
