/* usm_optimize.h: the best design over parameter bounds (20).
 *
 * Maximize (or minimize) one output of the primary stationary solution over
 * chosen parameters within bounds, subject to: a stationary solution exists;
 * its largest non-cyclic Floquet modulus (from t0) is at most 1 - margin;
 * the motor drives the load, power_out >= 0, unless allow_driven; stick is
 * admissible (F_t <= mu0 F_n) in a stick model unless allow_slip; and each
 * user constraint OUTPUT <= X or OUTPUT >= X.  The outputs are
 * usm_design.h's USM_SENS_*, the rotor speed signed in the driving
 * direction: USM_OPT_SPEED = -rotor_speed (positive when the motor drives),
 * named "speed" with "rotor_speed" an alias (usm_opt_output_find); a
 * constraint may also name the further scalar outputs of `usm steady` below
 * (central differences where no analytic derivative exists), those of any
 * root by its number (rootR.NAME), and the number of roots as a filter.  NLopt's
 * SLSQP with the analytic sensitivities (usm_sensitivity_compute) as
 * gradients, in variables normalised to [0, 1], from `starts` deterministic
 * points of a rank-1 lattice over the box; the best feasible end point wins;
 * an interior optimum is polished by Newton steps on the gradient.
 *
 * At the optimum the result carries: the active constraints and bounds, each
 * with its Lagrange multiplier expressed as d(value)/d(bound), the change of
 * the optimal objective per unit of that bound; the KKT residual (the
 * projected gradient of the Lagrangian, 0 at an optimum); and which varied
 * parameters are flat (their interval of near-optimal values, objective
 * within 1e-4 relative with the other varied parameters re-optimised, covers
 * more than a tenth of their bounds).  Max_modulus everywhere (search,
 * derivatives, the multipliers reported at the optimum) is one
 * discretisation: usm_floquet_compute's exponential method with
 * USM_SENSITIVITY_STEPS sub-intervals, from t0.
 *
 * Thread safety: no global mutable state; distinct usm_optimize objects may
 * be used from distinct threads at the same time, one object must not be
 * shared without a lock.
 */
#ifndef USM_OPTIMIZE_H
#define USM_OPTIMIZE_H

#include <stdio.h>

#include "usm.h"
#include "usm_progress.h"
#include "usm_design.h"
#include "usm_operating_point.h"

#ifdef __cplusplus
extern "C" {
#endif

#define USM_OPT_MAX_CONSTRAINTS 32
/* Room for every active constraint's text: the user ones, stability, drives,
 * stick and one bound per varied parameter. */
#define USM_OPT_MAX_ACTIVE (USM_OPT_MAX_CONSTRAINTS + 3 + USM_NPARAMS)
#define USM_OPT_TEXT_LEN 128

/* The optimizer's outputs are usm_design.h's USM_SENS_* (0 .. USM_SENS_COUNT - 1)
 * with one difference: its output USM_SENS_ROTOR_SPEED is the speed in the
 * driving direction, -rotor_speed [1/s] (positive when the motor drives the
 * load), named "speed". */
#define USM_OPT_SPEED USM_SENS_ROTOR_SPEED

/* Beyond the sensitivity outputs, a constraint may name the other scalar
 * outputs of `usm steady --json` for the judged root (the operating point):
 * indices USM_SENS_COUNT .. USM_OPT_OUTPUT_COUNT - 1, in this order: alpha,
 * beta, mu_used, v_c, v_rel, R_star, Z, power_damping, power_slip and
 * margin = 1 - max_modulus.  Derivatives: analytic where usm_sensitivity has
 * them (the USM_SENS_* outputs, and margin from max_modulus); the others by
 * central differences in the varied parameters (usm_opt_output_analytic,
 * USM_OPT_FD_STEP).  Stability and stick_admissible are not outputs here:
 * flags have no derivative (the stability and stick constraints judge them);
 * the count of roots is a filter (USM_OPT_ROOTS below), and a constraint
 * may name another root's output (usm_opt_constraint.root). */
#define USM_OPT_MARGIN (USM_SENS_COUNT + 9)
#define USM_OPT_OUTPUT_COUNT (USM_SENS_COUNT + 10)

/* The finite-difference step in the box variable z = (p - LO) / (HI - LO):
 * the derivative of a non-analytic output in a varied parameter is
 * (y(z + h) - y(z - h)) / 2h, h = USM_OPT_FD_STEP (the second-order one-sided
 * stencil (-3 y(z) + 4 y(z +- h) - y(z +- 2h)) / +-2h where z -+ h leaves the
 * box), every y the judged root continued by Newton (usm_steady_solve_from,
 * to 1e-13 relative).  Error: truncation h^2 |y'''| / 6 plus the solutions'
 * rounding ~1e-13 |y| / h: about 1e-8 relative (README: measured). */
#define USM_OPT_FD_STEP 1e-4

/* Output k of solution sol at parameters p whose multipliers have largest
 * modulus max_modulus (USM_OPT_SPEED: -rotor_speed; margin: 1 - max_modulus);
 * NaN when k is out of range. */
double usm_opt_output_value(int k, const usm_steady_solution *sol, const usm_params *p,
                            double max_modulus);
/* Name of output k ("speed", "efficiency", "v_rel", ...), NULL when out of range. */
const char *usm_opt_output_name(int k);
/* Unit of output k ("1/s", "N", ...), NULL when out of range. */
const char *usm_opt_output_unit(int k);
/* 1 when output k's derivative is analytic (usm_sensitivity), 0 when it is
 * a central difference, -1 when k is out of range. */
int usm_opt_output_analytic(int k);
/* The names of every output, ", "-separated, into buf (truncated to len):
 * for the messages that list what may be named. */
void usm_opt_output_list(char *buf, size_t len);
/* Index of the output called `name`, or -1: the names of
 * usm_sensitivity_output_name and of the further outputs above (looked up
 * through the optimizer's output table, names from the generated contracts
 * usm_steady_outputs and usm_power_outputs where they have them) and "speed",
 * with "rotor_speed" an alias of
 * "speed" (-rotor_speed, positive when the motor drives the load: the
 * quantity `usm sweep --extremum speed` follows), so that maximizing it is a
 * faster motor, not one driven backwards. */
int usm_opt_output_find(const char *name);

/* Tolerance of "near-optimal" for the flat parameters: relative to |value|. */
#define USM_OPT_FLAT_TOL 1e-4
/* A parameter is flat when its near-optimal interval exceeds this fraction of its bounds. */
#define USM_OPT_FLAT_FRACTION 0.1

/* A user constraint: output (USM_OPT outputs) <= value (upper = 1) or >= value.
 *
 * Per-root constraints: root = r >= 1 names output k of the r-th
 * stationary root as `usm steady` numbers them (from 1, in its order),
 * written "rootR.NAME" (root2.theta); root = 0 is the judged root (the
 * operating point), written NAME.  Every output but max_modulus and margin
 * may be named per root (only the judged root's multipliers are computed
 * at every design).  Where root r does not exist the constraint is violated:
 * scaled value 1 (the value of an undefined constraint) and no direction
 * (zero gradient), as at a design without a solution.  Its derivatives are
 * central differences along root r, continued by Newton from its current
 * value (usm_steady_solve_from, USM_OPT_FD_STEP), as for the judged root.
 *
 * output = USM_OPT_ROOTS ("roots", root 0) is the number of stationary
 * roots: it has no derivative, so it is no constraint of SLSQP but a
 * feasibility filter: a design whose count violates it is refused (an
 * infeasible evaluation, like several roots without from_rest).  roots >= X
 * with X > 1 needs from_rest (several roots are refused without it). */
#define USM_OPT_ROOTS USM_OPT_OUTPUT_COUNT
/* The largest root number a constraint may name. */
#define USM_OPT_MAX_ROOT 64
typedef struct usm_opt_constraint {
    int output;
    int upper;
    double value;
    int root;                      /* 0: the judged root; r >= 1: root r (from 1) */
} usm_opt_constraint;

/* What to optimise.  Fill with usm_opt_problem_init, then the add functions. */
typedef struct usm_opt_problem {
    int objective;                 /* an analytic output (USM_SENS_*, USM_OPT_SPEED,
                                      USM_OPT_MARGIN; -1: not set); constraints may name
                                      any output < USM_OPT_OUTPUT_COUNT */
    int minimize;                  /* 0: maximize */
    int nvary;
    int vary[USM_NPARAMS];         /* usm_param_table indices */
    double lo[USM_NPARAMS], hi[USM_NPARAMS];
    int ncons;
    usm_opt_constraint cons[USM_OPT_MAX_CONSTRAINTS];
    double margin;                 /* stability margin D in [0, 1): max_modulus <= 1 - D */
    int allow_slip;                /* drop the stick constraint */
    int allow_driven;              /* drop power_out >= 0 (the load may drive the rotor) */
    int starts;                    /* 1 to 1000 */
    double t0;                     /* start of the Floquet period [s] (usm_floquet_compute) */
    int no_flat;                   /* skip the flat parameters' intervals (their cost) */
    /* The design is judged by its operating point (usm_operating_point.h):
     * with one root, that root (stable by the stability constraint: the
     * cheap rule); with several roots the design is refused (no point
     * there: an infeasible evaluation) unless from_rest = 1, which
     * simulates the start-up from rest at such designs (0.2 .. 1.2 s each)
     * and judges the root it reaches (none: refused). */
    int from_rest;                 /* default 0 */
    double from_rest_periods;      /* its length in excitation periods (0: 400) */
    /* A warm start: with has_start = 1 the first start is the
     * design start[i] (the value of varied parameter pb->vary[i], clamped
     * to its bounds) instead of the lattice's first point. */
    int has_start;
    double start[USM_NPARAMS];
    /* Read by usm_pareto_run, the front's optimizations as they finish
     * ("front points", total = its points), and by usm_robust_run (as
     * rp->nominal.progress), the designs evaluated ("designs": total = the
     * searches' budgets plus the verification sample in designs' worth; it
     * grows when a search starts again, and the last call has done = total).
     * usm_optimize_run does not report.  Default silent. */
    usm_progress progress;
} usm_opt_problem;

/* No objective, nothing varied, no constraint, margin 0.01, power_out >= 0
 * required, 8 starts, t0 = 0, flat parameters computed. */
void usm_opt_problem_init(usm_opt_problem *pb);
/* Vary parameter `name` in [lo, hi].  USM_OK, or USM_EINPUT with
 * "vary: reason" in msg (unknown parameter, given twice, lo >= hi). */
int usm_opt_problem_add_vary(usm_opt_problem *pb, const char *name, double lo, double hi,
                             char msg[USM_MSG_LEN]);
/* Add the constraint `output` <= value (upper = 1) or >= value; `output` is
 * NAME (the judged root), rootR.NAME (root R, 1 <= R <= USM_OPT_MAX_ROOT) or
 * roots (their count).  USM_OK, or USM_EINPUT with "constraint: reason" in
 * msg (unknown output, bad root number, too many).  max_modulus and margin
 * of root R come from that root's own multipliers (analytic derivative). */
int usm_opt_problem_add_constraint(usm_opt_problem *pb, const char *output, int upper,
                                   double value, char msg[USM_MSG_LEN]);
/* The whole problem for model m around parameters p: an ideal motor (p
 * passes usm_params_check_ideal: otherwise its message, as usm_steady_solve
 * gives it, e.g. "phase_error: must be 0 here: ..."; a model with
 * imperfections is refused even at zero imperfections, "variant: ...", since
 * its sensitivities are not defined), an objective with an analytic
 * gradient (usm_opt_output_analytic), at least one varied parameter,
 * margin, starts and t0 in range, every corner of the box admissible
 * parameters (usm_params_check and usm_params_check_ideal), no
 * I_yy varied in an axisymmetric model.  USM_OK, or USM_EINPUT with
 * "FIELD: reason" in msg, FIELD one of objective, vary, stability-margin,
 * starts, t0, variant or an imperfection's name. */
int usm_opt_problem_check(const usm_opt_problem *pb, const usm_model *m, const usm_params *p,
                          char msg[USM_MSG_LEN]);

/* The optimum (feasible = 1), or after USM_ENOSOLUTION the point of least
 * violation (feasible = 0: value, params, least_violation, violated; sol
 * when a stationary solution exists there). */
typedef struct usm_opt_result {
    int feasible;
    double value;                  /* the objective there (speed: -rotor_speed; max_modulus:
                                      floquet.max_modulus exactly) */
    usm_params params;             /* all parameters there */
    int solved;                    /* a stationary solution exists there (sol valid) */
    usm_steady_solution sol;       /* the primary stationary solution there */
    usm_floquet_result floquet;    /* its multipliers: usm_floquet_compute from t0, exponential
                                      method, USM_SENSITIVITY_STEPS sub-intervals */
    int nactive;                   /* active constraints and bounds, as text */
    char active[USM_OPT_MAX_ACTIVE][USM_OPT_TEXT_LEN];
    /* multiplier[i] of active[i]: d(value)/d(bound), the change of the optimal
     * objective per unit of the constraint's bound X (user constraints, in
     * the output's unit; stability: per unit of 1 - margin; drives: per W of
     * the bound 0 on power_out; stick: per N of a bound mu0 F_n - F_t >= X)
     * or of the parameter's bound LO or HI (per the parameter's unit) */
    double multiplier[USM_OPT_MAX_ACTIVE];
    double kkt_residual;           /* max over the varied parameters of the projected gradient
                                      of the Lagrangian in box units, relative to |value|
                                      (|value| = 0: absolute): 0 at a KKT point */
    int evaluations;               /* stationary solutions computed, all starts and the
                                      flat parameters' intervals */
    /* per varied parameter (index as pb->vary): the near-optimal interval
     * [near_lo, near_hi] (objective within USM_OPT_FLAT_TOL |value|, the other
     * varied parameters re-optimised; located to 1e-3 of the bounds, assumed
     * to be one interval) and flat = its length > USM_OPT_FLAT_FRACTION of the
     * bounds (NaN and 0 when pb->no_flat) */
    double near_lo[USM_NPARAMS], near_hi[USM_NPARAMS];
    int flat[USM_NPARAMS];
    /* infeasible: the largest scaled violation at the point of least
     * violation (NaN when no start ended with a stationary solution) and
     * the constraints violated there */
    double least_violation;
    int nviolated;
    char violated[USM_OPT_MAX_ACTIVE][USM_OPT_TEXT_LEN];
    double violation[USM_OPT_MAX_ACTIVE]; /* each one's scaled violation */
} usm_opt_result;

/* Workspace of one model (opaque). */
typedef struct usm_optimize usm_optimize;

/* Workspace for model m (not NULL), or NULL when out of memory. */
usm_optimize *usm_optimize_alloc(const usm_model *m);
/* Free o; NULL is allowed. */
void usm_optimize_free(usm_optimize *o);

/* Solve problem pb around parameters p (the values of the parameters not
 * varied).  USM_OK with *out (feasible = 1); USM_EINPUT (usm_opt_problem_check
 * failed); USM_ENOSOLUTION when no start ends feasible, *out the point of
 * least violation (feasible = 0; the message names the constraint that
 * cannot be met, or says no stationary solution exists); USM_EFAILED on a
 * numerical failure.  The message is in usm_optimize_message. */
int usm_optimize_run(usm_optimize *o, const usm_params *p, const usm_opt_problem *pb,
                     usm_opt_result *out);
/* Every stationary solution at the optimum of the last successful run (root
 * 0 is out->sol), or at the point of least violation after USM_ENOSOLUTION
 * (none when no solution exists there), owned by o, valid until the next run.
 * Where the operating point is not root 0, out->sol is that root. */
const usm_steady *usm_optimize_steady(const usm_optimize *o);

/* The operating point at the optimum of the last feasible run (the root
 * that result's `sol` is).  NULL before a feasible run. */
const usm_op_result *usm_optimize_op(const usm_optimize *o);
/* The multipliers of every root at that optimum
 * (usm_steady_count(usm_optimize_steady(o)) of them, the result's floquet's
 * method: the exponential product).  NULL before a feasible run. */
const usm_floquet_result *usm_optimize_roots_floquet(const usm_optimize *o);

/* Output k (< USM_OPT_OUTPUT_COUNT) of the design p as the optimizer judges
 * it (problem pb: its varied parameters, t0 and operating-point rule; p
 * inside the box) and its derivative d[i] per unit of varied parameter
 * pb->vary[i] as the optimizer computes it: analytic where
 * usm_opt_output_analytic(k), else central differences with step `step` in
 * box units (0: USM_OPT_FD_STEP); fd = 1 takes differences for an analytic
 * output too (to measure their accuracy).  USM_OK; USM_EINPUT (the problem,
 * k, step, or p outside the box); USM_ENOSOLUTION (no judged root at p, or
 * the derivative is not defined there).  Message in usm_optimize_message.
 * Replaces what usm_optimize_steady, _op and _roots_floquet describe. */
int usm_optimize_output_derivative(usm_optimize *o, const usm_params *p,
                                   const usm_opt_problem *pb, int k, double step, int fd,
                                   double *value, double d[USM_NPARAMS]);

/* Why the last run did not succeed, or "". */
const char *usm_optimize_message(const usm_optimize *o);

/* The `usm optimize --json` object of the last run of o (model m, problem pb,
 * result res) and a newline to out.  Feasible: feasible (true), objective,
 * sense, value, varied, parameters, active_constraints, multipliers,
 * kkt_residual, flat, near_optimal, evaluations and the stationary solution
 * at the optimum as `usm steady --json` writes it ("solution", its floquet
 * from pb->t0).  After USM_ENOSOLUTION: feasible (false), objective, sense,
 * least_violation, violated, value, varied, parameters, evaluations (at the
 * point of least violation).  Keys: README.md.  0, or -1 on a write error or
 * when out of memory. */
int usm_optimize_write_json(const usm_optimize *o, const usm_model *m, const usm_opt_problem *pb,
                            const usm_opt_result *res, FILE *out);

#ifdef __cplusplus
}
#endif

#endif /* USM_OPTIMIZE_H */
