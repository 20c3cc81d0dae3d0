/* usm_robust.h: robust design: the yield of a design under
 * manufacturing scatter with common random numbers, datasheet quantities
 * over an operating range, the robust optimum and the Pareto front of two
 * outputs.
 *
 * Yield with common random numbers (CRN).  A usm_yield holds one fixed set
 * of standard variates z[i][j] (sample i, scattered parameter j), drawn once
 * from the seed (GSL's mt19937, gsl_ran_gaussian_ziggurat for normal and
 * 2 u - 1 for uniform scatter), serially, so the set is the same for every
 * thread count.  At a design p, sample i is parameter j at
 *   normal:P%      p_j (1 + P/100 z)        normal:SIGMA    p_j + SIGMA z
 *   uniform:P%     p_j (1 + P/100 z)        uniform:LO:HI   LO + (HI - LO)(z + 1)/2
 * (the DIST syntax of `usm tolerance`, parsed by usm_tolerance_vary_parse).
 * Every design sees the same z: the yield is a deterministic function of the
 * design (bit for bit reproducible for a seed, equal across thread counts)
 * and differences between designs carry no sampling noise of their own.  A
 * sample is good as in `usm tolerance` (one rule for both): its operating
 * point (usm_point_evaluate_op) exists, is stable (max_modulus < 1), valid
 * (usm_validity), meets every spec and drives its load (power_out >= 0, the
 * optimizer's constraint "drives"; unless usm_yield_allow_driven, which the
 * robust optimizer sets from the problem's allow_driven).  A sample outside a parameter's
 * physical range (usm_params_check) is not redrawn (that would break the
 * common numbers): it counts as not good ("unphysical").
 *
 * Thread safety: as usm.h; distinct objects in distinct threads.
 */
#ifndef USM_ROBUST_H
#define USM_ROBUST_H

#include <stdint.h>
#include <stdio.h>

#include "usm.h"
#include "usm_optimize.h"
#include "usm_tolerance.h"

#ifdef __cplusplus
extern "C" {
#endif

#define USM_ROBUST_MAX_SCATTER 16
/* The samples of a robust problem's common-random-number set and of its
 * verification (usm_robust_problem's samples, verify_samples; usm_yield_alloc):
 * USM_ROBUST_MIN_SAMPLES .. USM_ROBUST_MAX_SAMPLES (a yield judged on fewer
 * than 100 motors is no estimate). */
#define USM_ROBUST_MIN_SAMPLES 100ULL
#define USM_ROBUST_MAX_SAMPLES 10000000ULL
#define USM_ROBUST_SAMPLES_TEXT "100 to 10000000" /* the same, for help texts */
#define USM_ROBUST_MAX_DERIVED 8 /* constraints on derived quantities */


/* ---- the common-random-numbers yield --------------------------------------------- */

typedef struct usm_yield usm_yield;

/* What one evaluation found. */
typedef struct usm_yield_result {
    uint64_t samples, good;
    double yield;              /* good / samples */
    double yield_lo, yield_hi; /* 95 % Wilson interval */
    uint64_t op;               /* samples with a stable operating point (the output exists) */
    uint64_t unphysical;       /* samples outside a parameter's physical range */
    double mean;               /* the tracked output's mean over the `op` samples (NaN: none) */
    uint64_t driven;           /* samples not good only because the load drives the rotor
                                  backwards (power_out < 0; 0 with usm_yield_allow_driven) */
} usm_yield_result;

/* A sample set of `samples` (1 .. USM_ROBUST_MAX_SAMPLES) draws of the scatter (nscatter of
 * them, each parsed by usm_tolerance_vary_parse; distinct parameters) from
 * `seed`, for model m.  NULL with msg ("scatter: ..." / "samples: ...") on
 * bad input or when out of memory. */
usm_yield *usm_yield_alloc(const usm_model *m, const usm_tolerance_vary *scatter, int nscatter,
                           uint64_t samples, uint64_t seed, char msg[USM_MSG_LEN]);
/* Free y; NULL is allowed. */
void usm_yield_free(usm_yield *y);
/* A spec on optimizer output k (usm_optimize.h: speed, efficiency, power_out,
 * margin, ...): k <= bound (upper) or >= bound, judged at each sample's
 * operating point.  USM_OK or USM_EINPUT (at most USM_OPT_MAX_CONSTRAINTS). */
int usm_yield_spec_add(usm_yield *y, int k, int upper, double bound);
/* allow != 0: a sample whose load drives its rotor backwards (power_out < 0)
 * may be good, as usm_opt_problem's allow_driven drops the constraint
 * "drives" (default 0: it is not good, as in `usm tolerance`). */
void usm_yield_allow_driven(usm_yield *y, int allow);
/* Evaluate the set at design p: Floquet from t0 (usm_floquet_options_default),
 * `threads` workers (1 .. 64), tracking optimizer output `track` (-1: none)
 * for usm_yield_mean/quantile.  USM_OK or USM_EINPUT / USM_EFAILED with the
 * message in usm_yield_message. */
int usm_yield_eval(usm_yield *y, const usm_params *p, double t0, int threads, int track,
                   usm_yield_result *r);
/* The q-quantile (0 < q < 1; the order statistic ceil(q n)) of the tracked
 * output over all samples of the last evaluation, a sample without a
 * stable operating point counting as the worst value: -inf when `larger_better`,
 * +inf otherwise.  NaN before an evaluation. */
double usm_yield_quantile(usm_yield *y, double q, int larger_better);
/* Sample i of the last evaluation: its tracked output (NaN without an
 * operating point) and whether it is good.  USM_OK or USM_EINPUT. */
int usm_yield_sample(const usm_yield *y, uint64_t i, double *value, int *good);
/* Why the last call failed, or "". */
const char *usm_yield_message(const usm_yield *y);

/* ---- datasheet quantities and operating ranges ---------------------------------- */

/* Quantities beyond the optimizer's outputs (usm_opt_output_find): */
enum {
    USM_ROBUST_STALL_TORQUE = 64, /* slip models: the load T [N m] where the speed reaches
                                     0 (the sweep's stall event, usm_sweep.h) */
    USM_ROBUST_NO_LOAD_SPEED = 65, /* speed [1/s] at T = 0 */
    USM_ROBUST_MAX_POWER = 66,    /* the largest power_out [W] over the load range */
    USM_ROBUST_BAND_WIDTH = 67,   /* the length [Hz] of the frequency range where the speed
                                     is >= the threshold */
    USM_ROBUST_YIELD = 68         /* the CRN yield */
};

/* How an output is judged over a range of a parameter (--over-range). */
typedef enum {
    USM_RANGE_WORST = 0,    /* the least favourable grid value (the smallest when larger
                               is better, else the largest) */
    USM_RANGE_MEAN = 1,     /* integral / (HI - LO) */
    USM_RANGE_INTEGRAL = 2  /* trapezoid rule over the grid, in unit * the parameter's unit */
} usm_range_stat;

/* An operating range: parameter `param` (usm_param_table index) from lo to
 * hi on `points` (>= 2) equally spaced values, followed by continuation
 * (usm_sweep_run, no multipliers). */
typedef struct usm_robust_range {
    int param;              /* -1: none */
    double lo, hi;
    int points;             /* default 21 */
    usm_range_stat stat;
} usm_robust_range;

/* Name of quantity k: an optimizer output's, the derived ones' ("stall_torque",
 * "no_load_speed", "max_power", "band_width"), "yield"; NULL otherwise. */
const char *usm_robust_quantity_name(int k);
/* Unit of quantity k. */
const char *usm_robust_quantity_unit(int k);
/* Index of quantity `name` (optimizer outputs, derived quantities, yield), or -1. */
int usm_robust_quantity_find(const char *name);
/* "worst", "mean", "integral" <-> usm_range_stat; -1 for an unknown name. */
int usm_range_stat_find(const char *name);
/* The name of s ("worst", "mean", "integral"), NULL when out of range. */
const char *usm_range_stat_name(usm_range_stat s);

/* The options of the derived quantities. */
typedef struct usm_quantity_options {
    double t0;              /* Floquet start [s] */
    usm_robust_range range; /* the load range of stall_torque and max_power (param T;
                               none: T from 0 to USM_ROBUST_T_MAX), the frequency range
                               of band_width (param f, required), or the range of an
                               output (usm_robust_quantity_eval with range) */
    double band_threshold;  /* band_width: speed threshold [1/s] (NaN: not set) */
} usm_quantity_options;

#define USM_ROBUST_T_MAX 0.01

/* Quantity k at parameters p (model m).  Optimizer outputs: at the operating
 * point; with opt->range.param >= 0 judged over the range (opt->range.stat,
 * larger_better says which end is the worst).  stall_torque: the stall
 * event of a sweep over T (the first), ENOSOLUTION when none lies in the
 * range; no_load_speed: the operating point's speed at T = 0; max_power:
 * the maximum of power_out along the sweep over the load range (the
 * sweep's maximum event of power_out, else the largest grid value);
 * band_width: the total length of the parts of the frequency range where
 * speed >= threshold (grid values and the sweep's crossing events).
 * USM_OK with *value; USM_EINPUT (msg: the option missing or the model
 * unsuitable); USM_ENOSOLUTION (msg: why the quantity does not exist here). */
int usm_robust_quantity_eval(const usm_model *m, const usm_params *p, int k,
                             const usm_quantity_options *opt, int larger_better, double *value,
                             char msg[USM_MSG_LEN]);

/* ---- the robust optimum -------------------------------------------------------- */

typedef enum {
    USM_ROBUST_STAT_NOMINAL = 0, /* the quantity at the nominal design */
    USM_ROBUST_STAT_MEAN = 1,    /* its mean over the scatter (mean:NAME) */
    USM_ROBUST_STAT_QUANTILE = 2 /* a quantile over the scatter (q05:NAME = 5 %) */
} usm_robust_stat;

typedef struct usm_robust_constraint {
    int quantity;           /* usm_robust_quantity_find */
    int upper;
    double value;
} usm_robust_constraint;

typedef struct usm_robust_problem {
    usm_opt_problem nominal;  /* varied parameters and bounds, margin, allow_slip,
                                 allow_driven, t0, minimize, and the constraints on
                                 optimizer outputs (also the yield's specs) */
    int objective;            /* a quantity; USM_ROBUST_YIELD for --objective yield */
    usm_robust_stat stat;
    double quantile;          /* USM_ROBUST_STAT_QUANTILE: in (0, 1) */
    int nderived;             /* constraints on derived quantities (nominal design) */
    usm_robust_constraint derived[USM_ROBUST_MAX_DERIVED];
    double yield_min;         /* yield >= yield_min; NaN: no yield constraint */
    int nscatter;
    usm_tolerance_vary scatter[USM_ROBUST_MAX_SCATTER];
    uint64_t samples;         /* CRN samples per design (default 10000) */
    uint64_t seed;            /* default 1; the verification uses seed + 1 */
    uint64_t verify_samples;  /* fresh samples of the final check (default 100000) */
    int threads;              /* default 2 */
    int max_evals;            /* designs per COBYLA run (default 40) */
    usm_quantity_options qopt;
} usm_robust_problem;

/* Nothing varied, no objective, statistic nominal, quantile 0.05, no yield
 * constraint, no scatter, 10^4 samples, seed 1, 10^5 verification samples,
 * 2 threads, 40 designs per COBYLA run, no range (21 points when given),
 * no band threshold; rp->nominal as usm_opt_problem_init with no_flat. */
void usm_robust_problem_init(usm_robust_problem *rp);
/* Whether a problem needs the robust (derivative-free) path: a yield, a
 * statistic over the scatter, a range, or a derived quantity. */
int usm_robust_problem_is_robust(const usm_robust_problem *rp);
/* USM_OK or USM_EINPUT with "FIELD: reason". */
int usm_robust_problem_check(const usm_robust_problem *rp, const usm_model *m,
                             const usm_params *p, char msg[USM_MSG_LEN]);

/* The texts of usm optimize's options (runtime/io/robust_args.c; msg has
 * USM_IO_MSG_LEN = 1024 bytes).  --objective TEXT: NAME (an optimizer output
 * or a derived quantity), yield, mean:NAME or qNN:NAME (0 < NN < 100) into
 * rp->objective, stat, quantile: USM_OK, or USM_EINPUT with "objective:
 * reason".  A constraint on the yield (yield>=Y, 0 < Y < 1) or on a derived
 * quantity (NAME>=X, NAME<=X) into rp: USM_OK, USM_EINPUT with "constraint:
 * reason", or 1 when TEXT is neither (an optimizer output's constraint:
 * usm_opt_problem_add_constraint on rp->nominal). */
int usm_robust_objective_parse(usm_robust_problem *rp, const char *text, char msg[1024]);
/* The constraint text, as described above. */
int usm_robust_constraint_parse(usm_robust_problem *rp, const char *text, char msg[1024]);
/* --vary TEXT: NAME=LO:HI, LO and HI numbers or values with a unit of the
 * parameter's (usm_parse_quantity), into pb (usm_opt_problem_add_vary):
 * USM_OK, or USM_EINPUT with "vary: reason". */
int usm_opt_vary_parse(usm_opt_problem *pb, const char *text, char msg[1024]);
/* --constraint TEXT on an optimizer output: OUTPUT>=X or OUTPUT<=X, OUTPUT
 * NAME, rootR.NAME or roots, into pb (usm_opt_problem_add_constraint):
 * USM_OK, or USM_EINPUT with "constraint: reason". */
int usm_opt_constraint_parse(usm_opt_problem *pb, const char *text, char msg[1024]);
/* --over-range TEXT: P=LO:HI[:N] (2 <= N <= 100000, LO < HI, in the unit of
 * parameter P or with one) into r's param, lo, hi and points (kept when N is
 * not given): USM_OK, or USM_EINPUT with "over-range: reason". */
int usm_robust_range_parse(usm_robust_range *r, const char *text, char msg[1024]);
/* The option `name` (without its dashes) of robust design with its text
 * value into rp: scatter (a usm_tolerance_vary_parse_units text, up to
 * USM_ROBUST_MAX_SCATTER), samples and verify-samples (whole numbers
 * USM_ROBUST_MIN_SAMPLES to USM_ROBUST_MAX_SAMPLES), seed (0 to
 * USM_SEED_MAX), threads, max-evals, over-range (usm_robust_range_parse),
 * range-stat (worst, mean, integral), band-threshold.  USM_OK, USM_EINPUT
 * with "NAME: reason", or 1 when `name` is none of these. */
int usm_robust_option_parse(usm_robust_problem *rp, const char *name, const char *value,
                            char msg[1024]);
/* usm pareto's --objectives TEXT: "A,B", each an optimizer output with an
 * analytic gradient (usm_opt_output_analytic), prefixed max: (the default)
 * or min:, the two different, into output[2] and minimize[2]: USM_OK, or
 * USM_EINPUT with "objectives: reason". */
int usm_pareto_objectives_parse(const char *text, int output[2], int minimize[2],
                                char msg[1024]);

typedef struct usm_robust_design {
    int feasible;
    usm_params params;
    double value;             /* the objective (its statistic over the scatter, the
                                 yield, or the quantity) at this design */
    double nominal_value;     /* the objective's quantity at the nominal design
                                 (no scatter; NaN for the yield) */
    double speed, efficiency, power_out, max_modulus; /* nominal operating point */
    double crn_yield;         /* CRN yield (NaN without scatter) */
    double yield, yield_lo, yield_hi; /* fresh verification sample (NaN without scatter) */
    uint64_t verify_samples;
} usm_robust_design;

typedef struct usm_robust_result {
    usm_robust_design robust;  /* the robust optimum */
    usm_robust_design nominal; /* the nominal optimum (the same problem without yield
                                  and scatter statistics: usm_optimize_run when the
                                  objective is an analytic output; feasible = 0 otherwise) */
    int verified;              /* the fresh sample confirms the robust design: its yield
                                  meets yield_min (with a yield constraint), else the CRN
                                  and fresh yields agree within 3 standard errors */
    int evaluations;           /* designs evaluated */
    int nactive;
    char active[USM_OPT_MAX_ACTIVE][USM_OPT_TEXT_LEN];
    double seconds;
} usm_robust_result;

/* Solve rp around p (model m).  USM_OK (robust.feasible), USM_ENOSOLUTION
 * (no feasible design found; msg names the worst constraint), USM_EINPUT,
 * USM_EFAILED. */
int usm_robust_run(const usm_model *m, const usm_params *p, const usm_robust_problem *rp,
                   usm_robust_result *res, char msg[USM_MSG_LEN]);

/* The `usm optimize --json` object of a robust run: feasible, objective,
 * statistic, sense, value, varied, parameters, active_constraints,
 * evaluations, yield, yield_ci, samples, verified, crn {samples, seed,
 * yield}, nominal_optimum {...}.  0 or -1. */
int usm_robust_write_json(const usm_model *m, const usm_robust_problem *rp,
                          const usm_robust_result *res, FILE *out);

/* ---- Pareto fronts ----------------------------------------------------------------- */

#define USM_PARETO_MAX_POINTS 1000

typedef struct usm_pareto_point {
    double f[2];              /* the two objectives */
    usm_params params;
    int nactive;
    char active[USM_OPT_MAX_ACTIVE][USM_OPT_TEXT_LEN];
} usm_pareto_point;

typedef struct usm_pareto_result {
    int npoints;              /* non-dominated points, sorted by f[1] increasing */
    usm_pareto_point *points; /* owned: usm_pareto_result_free */
    int computed;             /* optimizations run (dominated and failed ones dropped) */
    double seconds;
} usm_pareto_result;

/* The front of objectives obj[0], obj[1] (analytic optimizer outputs;
 * minimize[i]: that one is minimized) over pb's varied parameters under
 * pb's constraints, by the epsilon-constraint method: the two single
 * optima bound the front; then obj[0] is optimized with obj[1] >= eps
 * (<= for a minimized one) at `points` levels between them, each
 * warm-started from its neighbour's design; dominated points are dropped.
 * USM_OK, USM_EINPUT, USM_ENOSOLUTION, USM_EFAILED; msg says why. */
int usm_pareto_run(const usm_model *m, const usm_params *p, const usm_opt_problem *pb,
                   const int obj[2], const int minimize[2], int points,
                   usm_pareto_result *res, char msg[USM_MSG_LEN]);
/* Free the points of res (not res itself); NULL is allowed. */
void usm_pareto_result_free(usm_pareto_result *res);

/* CSV in the usm command's dialect: point, OBJ0 [unit], OBJ1 [unit], each
 * varied parameter NAME [unit], active (the active constraints joined by
 * "; ").  JSON: {objectives [OBJ0, OBJ1], senses, points: [{OBJ0, OBJ1,
 * design {NAME: value}, active_constraints [...]}], computed, seconds}.
 * The figure: usm_plot_render with data/plots/pareto.gp on the CSV.
 * 0 or -1 on a write error. */
int usm_pareto_write_csv(const usm_opt_problem *pb, const int obj[2],
                         const usm_pareto_result *res, FILE *out);
/* The JSON object described above, and a newline. */
int usm_pareto_write_json(const usm_opt_problem *pb, const int obj[2], const int minimize[2],
                          const usm_pareto_result *res, FILE *out);

#ifdef __cplusplus
}
#endif

#endif /* USM_ROBUST_H */
