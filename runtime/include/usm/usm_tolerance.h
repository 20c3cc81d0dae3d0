/* usm_tolerance.h: Monte Carlo tolerance (yield) studies.
 *
 * Every manufactured motor scatters around the nominal design: each varied
 * parameter is drawn from its distribution, and at that parameter point the
 * stationary solution (full search, primary root) and its Floquet multipliers
 * are computed by usm_point_evaluate (usm_map.h).  The study reports
 *   - the yield: the fraction of samples whose operating point exists, is
 *     stable (largest non-cyclic multiplier < 1), meets every spec, is
 *     valid (the model describes the motor there: usm_validity) and drives
 *     its load (power_out >= 0, as usm_optimize's constraint "drives";
 *     unless allow_driven), with its 95 % Wilson score interval -- the rule
 *     of usm_yield_eval (usm_robust.h) too;
 *   - the 1, 5, 50, 95, 99 % quantiles of every numeric output (over the
 *     samples where it exists; gsl_stats_quantile_from_sorted_data's
 *     definition, from exact order statistics);
 *   - the influence of each varied parameter on each numeric output: the
 *     Spearman rank correlation over the samples where the output exists
 *     (ties averaged; exact integer sums of the ranks, rounded once).
 * The statistics need no gathering of the samples: under MPI
 * (usm_tolerance_run_mpi, the command's) every rank keeps its own samples
 * and the same statistics are computed by reductions and a sample sort.
 *
 * Determinism: sample i is a pure function of (seed, i): its random stream
 * is a splitmix64 generator started at a hash of (seed, i), so the result is
 * bit-identical for any number of threads, MPI ranks or checkpoint resumes.
 *
 * Redraws: a draw that leaves a parameter's physical range (usm_params_check
 * refuses the point) is drawn again from the same stream and counted.
 *
 * Checkpoints: the samples are computed in blocks of USM_TOLERANCE_BLOCK; the
 * completed blocks are written to the checkpoint file atomically (temporary
 * file, then rename) at most every `checkpoint_interval` seconds (and at
 * most 1/20 of the time: a write taking w seconds waits 20 w) and at the
 * end; a run with the same checkpoint file loads them and computes only the
 * rest.  The file records the library version, the study's configuration
 * and a CRC-32 of its bytes; a file of another configuration or version, or
 * a damaged or truncated one, is refused (USM_EINPUT, the message says
 * what differs; docs/tolerance.md).
 *
 * Life cycle (GSL style): usm_tolerance_alloc, usm_tolerance_vary_add,
 * usm_tolerance_spec_add, usm_tolerance_run, accessors and writers,
 * usm_tolerance_free.  Thread safety: as usm.h.
 */
#ifndef USM_TOLERANCE_H
#define USM_TOLERANCE_H

#include <stdint.h>
#include <stdio.h>

#include "usm.h"
#include "usm_operating_point.h"
#include "usm_progress.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Samples per block: the unit of work handed to a thread or rank, and of the
 * checkpoint. */
#define USM_TOLERANCE_BLOCK 64

/* Most samples of one study. */
#define USM_TOLERANCE_MAX_SAMPLES 1000000000ULL
/* The largest seed of a study (usm tolerance, usm optimize's scatter and its
 * verification's seed + 1, the Python package): 2^53 - 1, so that every seed
 * written into a JSON file (a double) reads back exactly.  Seeds are
 * 0 .. USM_SEED_MAX. */
#define USM_SEED_MAX 9007199254740991ULL
#define USM_SEED_MAX_TEXT "9007199254740991" /* the same, for help texts */

/* ---- distributions ------------------------------------------------------------ */

typedef enum {
    USM_DIST_NORMAL = 0,   /* nominal + sigma N(0, 1) */
    USM_DIST_UNIFORM = 1   /* uniform on [lo, hi] */
} usm_dist_kind;

/* One varied parameter: `NAME=DIST` with DIST one of
 *   normal:5%     standard deviation 5 % of the nominal value
 *   normal:0.01   standard deviation 0.01 (the parameter's unit)
 *   uniform:2%    nominal +- 2 % of the nominal value
 *   uniform:LO:HI uniform on [LO, HI] */
typedef struct usm_tolerance_vary {
    const usm_param_info *param;
    usm_dist_kind kind;
    int relative;          /* width given in % of the nominal value */
    double width;          /* sigma, or half-width (relative: a fraction, 0.05 for 5%) */
    double lo, hi;         /* uniform:LO:HI (relative == 0 and width == 0) */
} usm_tolerance_vary;

/* Parse "NAME=DIST" into v.  USM_OK or USM_EINPUT with "NAME: reason" (or
 * "DIST: reason") in msg. */
int usm_tolerance_vary_parse(const char *text, usm_tolerance_vary *v, char msg[USM_MSG_LEN]);
/* Whether scatter v suits model m at nominal parameters p: the one check of
 * usm tolerance's --vary, usm optimize's --scatter (usm_robust_problem_check)
 * and the Python package.  Refused: a parameter model m does not read (an
 * imperfection of an ideal model, a parameter its assumptions tie to
 * another); a relative width of a nominal 0; uniform:LO:HI wholly outside the
 * parameter's range (usm_param_ranges; one that overlaps it is drawn, the
 * draws outside redrawn); a standard deviation or half-width wider than half
 * the range (phase_error=normal:5: 5 rad), or, for a parameter of one sign,
 * than its nominal value
 * (F0=normal:5 on 0.4 N: a width typed as a number meant in %).  USM_OK or
 * USM_EINPUT with "NAME: reason" in msg. */
int usm_tolerance_vary_check(const usm_tolerance_vary *v, const usm_model *m,
                             const usm_params *p, char msg[USM_MSG_LEN]);
/* The same with a unit allowed in the absolute numbers (normal:SIGMA,
 * uniform:LO:HI, e.g. F0=uniform:350mN:450mN; usm_parse_quantity in the
 * parameter's unit), as usm tolerance's --vary, usm optimize's --scatter and
 * the Python package's vary and scatter take it (runtime/io/vary_text.c;
 * msg has USM_IO_MSG_LEN = 1024 bytes).  USM_OK, or USM_EINPUT with "FIELD
 * NAME: reason" in msg (FIELD e.g. "--vary"). */
int usm_tolerance_vary_parse_units(const char *field, const char *text, usm_tolerance_vary *v,
                                   char msg[1024]);

/* The 95 % Wilson score interval [lo, hi] of k good samples out of n (the
 * yield's interval of usm tolerance and of usm optimize's yield; n = 0:
 * [0, 1]). */
void usm_tolerance_wilson(uint64_t k, uint64_t n, double *lo, double *hi);

/* ---- outputs and specs ---------------------------------------------------------- */

/* The recorded outputs of a sample: the numeric ones first.  They describe
 * the sample's operating point (usm_point_evaluate_op, usm_operating_point.h)
 * when it has one, else its smallest-tilt root (as `usm steady`'s top
 * level); operating_point and op_class say which. */
enum {
    USM_TOL_THETA = 0,       /* tilt [rad] */
    USM_TOL_ROTOR_SPEED = 1, /* phidot_R [1/s] (the paper's sign: negative when driving) */
    USM_TOL_F_N = 2,         /* [N] */
    USM_TOL_F_T = 3,         /* [N] */
    USM_TOL_MAX_MODULUS = 4, /* largest non-cyclic |multiplier| */
    USM_TOL_EFFICIENCY = 5,  /* power_out / power_in */
    USM_TOL_NNUMERIC = 6,
    USM_TOL_STABLE = 6,           /* max_modulus < 1 */
    USM_TOL_STICK_ADMISSIBLE = 7, /* F_t <= mu0 F_n */
    USM_TOL_EXISTS = 8,           /* a stationary solution exists */
    USM_TOL_OPERATING_POINT = 9,  /* the operating point's root index (NaN: none) */
    USM_TOL_OP_CLASS = 10,        /* usm_point_op_class (usm_map.h) as a number */
    USM_TOL_VALIDITY = 11,        /* usm_validity (usm.h) of the solution the sample
                                     describes, as a number (NaN: no solution); a sample
                                     counts for the yield only where it is USM_VALID */
    USM_TOL_NOUTPUTS = 12
};

/* Name of output k ("theta", ...), NULL when out of range. */
const char *usm_tolerance_output_name(int k);
/* SI unit of output k ("rad", "1/s", "N", "1"); NULL for the yes/no outputs. */
const char *usm_tolerance_output_unit(int k);
/* Index of the output called `name`, or -1. */
int usm_tolerance_output_find(const char *name);

/* A spec `OUTPUT>=X` or `OUTPUT<=X` on a numeric output. */
typedef struct usm_tolerance_spec {
    int output;    /* USM_TOL_THETA .. USM_TOL_EFFICIENCY */
    int upper;     /* 1: OUTPUT <= bound, 0: OUTPUT >= bound */
    double bound;
} usm_tolerance_spec;

/* Parse "OUTPUT>=X" or "OUTPUT<=X".  USM_OK or USM_EINPUT with a reason. */
int usm_tolerance_spec_parse(const char *text, usm_tolerance_spec *s, char msg[USM_MSG_LEN]);

/* ---- the study ------------------------------------------------------------------ */

typedef struct usm_tolerance_options {
    uint64_t samples;        /* 1 .. USM_TOLERANCE_MAX_SAMPLES (default 1000) */
    uint64_t seed;           /* default 1 */
    int threads;             /* 1 .. 64 (default 2) */
    double t0;               /* Floquet start time [s] (default 0) */
    usm_floquet_options floquet; /* usm_floquet_options_default */
    const char *checkpoint;  /* checkpoint file, or NULL (default) */
    double checkpoint_interval; /* seconds between checkpoint writes (default 10) */
    uint64_t stop_after_blocks; /* stop (USM_EFAILED) once this many blocks were
                                   computed by this run and checkpointed; 0: never
                                   (default; a test hook for resuming) */
    usm_op_options op;       /* the operating point's rule (usm_op_options_default: no
                                simulation from rest, so a sample with several roots has
                                an unknown operating point and does not count) */
    int allow_driven;        /* 1: a sample whose load drives its rotor backwards
                                (power_out < 0) may count; 0 (default): it does not */
    usm_progress progress;   /* the samples as their blocks finish ("samples"; a resumed
                                checkpoint's count first); default silent */
} usm_tolerance_options;

/* Fill `opt` with the defaults listed above. */
void usm_tolerance_options_default(usm_tolerance_options *opt);

/* A study of one model (opaque). */
typedef struct usm_tolerance usm_tolerance;

/* A study for model m (not NULL), or NULL when out of memory. */
usm_tolerance *usm_tolerance_alloc(const usm_model *m);
/* Free t; NULL is allowed. */
void usm_tolerance_free(usm_tolerance *t);

/* Add a varied parameter.  USM_OK, or USM_EINPUT (a parameter
 * varied twice, I_yy of an axisymmetric model: vary I_xx, which moves I_yy
 * with it) with the reason in usm_tolerance_message. */
int usm_tolerance_vary_add(usm_tolerance *t, const usm_tolerance_vary *v);
/* Add a spec (at most 64).  USM_OK or USM_EINPUT. */
int usm_tolerance_spec_add(usm_tolerance *t, const usm_tolerance_spec *s);

/* Run the study around the nominal parameters p.  USM_OK; USM_EINPUT (bad
 * options or parameters, a relative distribution of a parameter whose nominal
 * value is 0, a distribution that almost never stays physical, a checkpoint of
 * another study); USM_EFAILED (out of memory, a checkpoint that cannot be
 * written, stopped by stop_after_blocks).  Message in usm_tolerance_message. */
int usm_tolerance_run(usm_tolerance *t, const usm_params *p, const usm_tolerance_options *opt);

/* ---- the result of the last run -------------------------------------------------- */

typedef struct usm_tolerance_summary {
    uint64_t samples;
    uint64_t seed;
    uint64_t good;          /* samples whose operating point exists (a stable root),
                               meets every spec, is valid (USM_VALID) and drives its
                               load (power_out >= 0, unless allow_driven) */
    double yield;           /* good / samples */
    double yield_lo, yield_hi; /* 95 % Wilson score interval */
    uint64_t exists, stable; /* samples with a solution; with stable multipliers */
    uint64_t failed;        /* samples with a solution whose multipliers failed */
    uint64_t redrawn;       /* draws refused as unphysical and drawn again */
    uint64_t resumed_blocks; /* blocks read from the checkpoint */
    /* by the operating point: samples that have one; whose roots are all
     * unstable; that do not start from rest; whose operating point is
     * unknown (several roots and no simulation from rest, or undecided) */
    uint64_t op_exists, op_no_stable_root, op_does_not_start, op_unknown;
    /* samples with a solution that the model does not describe (usm_validity
     * != USM_VALID): in all, with the contact open, past the stick limit */
    uint64_t invalid, invalid_contact_open, invalid_stick;
    /* samples that meet every other part of the rule but whose load drives the
     * rotor backwards (power_out < 0): not good for that alone (0 with
     * allow_driven; good + driven is the count allow_driven gives) */
    uint64_t driven;
    /* quantiles[k][q] of numeric output k at USM_TOLERANCE_QUANTILES[q] (NaN
     * when no sample has the output); count[k] samples have it */
    double quantile[USM_TOL_NNUMERIC][5];
    uint64_t count[USM_TOL_NNUMERIC];
} usm_tolerance_summary;

/* The quantile levels: 0.01, 0.05, 0.5, 0.95, 0.99. */
extern const double USM_TOLERANCE_QUANTILES[5];

/* Summary of the last run (NULL before a successful run). */
const usm_tolerance_summary *usm_tolerance_result(const usm_tolerance *t);

/* Number of varied parameters. */
int usm_tolerance_vary_count(const usm_tolerance *t);
/* Varied parameter j (in the order added), NULL when out of range. */
const usm_tolerance_vary *usm_tolerance_vary_at(const usm_tolerance *t, int j);

/* Spearman rank correlation of numeric output k with varied parameter j over
 * the samples where output k exists; NaN when it is undefined (fewer than 3
 * such samples, or a constant column). */
double usm_tolerance_influence(const usm_tolerance *t, int k, int j);

/* Sample i of the last run: the varied parameters' values (vary_count of
 * them) into `values` (may be NULL), the outputs into `out`
 * (USM_TOL_NOUTPUTS; NaN where an output does not exist, 0/1 for yes/no), and
 * whether it counts for the yield (a sample whose outputs allow it but is
 * not good is one the load drives: power_out < 0).  USM_OK or USM_EINPUT (i
 * out of range). */
int usm_tolerance_sample(const usm_tolerance *t, uint64_t i, double *values, double *out,
                         int *good, int *redraws);

/* Wall seconds of the phases of the last run (usm tolerance --json's
 * "timings"; under MPI, rank 0's): compute, the samples; reduce, waiting
 * for and agreeing with the other ranks (their load imbalance) and reducing
 * the counts; statistics, the quantiles and Spearman correlations (sorts,
 * selections and, under MPI, the exchange of ranks); output, the checkpoint
 * writes plus what usm_tolerance_output_seconds_add adds (the command's
 * files).  compute_cpu and output_cpu: the process's CPU seconds (every
 * thread) in the compute and output phases, the figure to compare the two
 * by: unlike wall seconds it hardly moves with other processes' load. */
typedef struct usm_tolerance_timings {
    double compute, reduce, statistics, output;
    double compute_cpu, output_cpu;
} usm_tolerance_timings;
/* The timings of the last run of t (NULL before one). */
const usm_tolerance_timings *usm_tolerance_timings_get(const usm_tolerance *t);

/* Add `seconds` to the output phase of the last run's timings (a writer's
 * wall time, measured by its caller). */
void usm_tolerance_output_seconds_add(usm_tolerance *t, double seconds);
/* The same for the output phase's process CPU seconds (timings.output_cpu). */
void usm_tolerance_output_cpu_seconds_add(usm_tolerance *t, double seconds);

/* Why the last run failed, or "". */
const char *usm_tolerance_message(const usm_tolerance *t);

/* ---- writers ---------------------------------------------------------------------- */

/* The samples as CSV in the usm command's dialect (docs/cli.md, "CSV
 * files"): sample, the varied parameters "NAME [UNIT]", exists, stable,
 * stick_admissible, theta [rad], rotor_speed [1/s], F_n [N], F_t [N],
 * max_modulus [1], efficiency [1], good, redraws, operating_point (root
 * index or empty), op_class (usm_point_op_class_name), valid (true/false,
 * empty without a solution), invalid_reason (usm_validity_name).  0, or -1 on
 * a write error. */
int usm_tolerance_write_csv(const usm_tolerance *t, FILE *out);

/* The histograms that `usm tolerance --out DIR` draws (DIR/histograms.csv):
 * 40 bins of equal width over the range of every sample's rotor_speed and
 * max_modulus (the samples that have the output; a constant output: one
 * narrow bin), counted by the library over every thread and MPI rank, so
 * that a figure of 10^8 samples reads 40 rows.  CSV in the usm command's
 * dialect: bin, rotor_speed_lo [1/s], rotor_speed_hi [1/s],
 * rotor_speed_count, max_modulus_lo [1], max_modulus_hi [1],
 * max_modulus_count (lo, hi empty where no sample has the output).  0, or
 * -1 on a write error or without a result. */
int usm_tolerance_write_histograms(const usm_tolerance *t, FILE *out);

/* The result as one JSON object (2-space indent, numbers with 17 digits,
 * null where a value does not exist): samples, seed, yield, yield_ci [lo,
 * hi], quantiles {OUTPUT: {count, p1, p5, p50, p95, p99}}, influence
 * {OUTPUT: {PARAM: Spearman}}, failed, redrawn, exists, stable, good,
 * operating_point {exists, no_stable_root, does_not_start, unknown},
 * invalid (samples whose solution the model does not describe),
 * invalid_reasons {contact_open, stick_not_admissible}, driven (samples not
 * good only because the load drives them: usm_tolerance_summary's) (the
 * same bytes after a checkpoint resume, for any number of threads or MPI
 * ranks), and last, on
 * a line of its own, timings {compute, reduce, statistics, output, compute_cpu, output_cpu}
 * (usm_tolerance_timings_get: wall seconds, different in every run; compare
 * two runs' output without the line that starts with `  "timings"`).  0 or -1
 * on a write error. */
int usm_tolerance_write_json(const usm_tolerance *t, FILE *out);

/* summary.md: the study, the yield, quantiles and influence tables.
 * `histograms` names the figure file to link (NULL: none).  0 or -1. */
int usm_tolerance_write_summary(const usm_tolerance *t, FILE *out, const char *histograms);

#ifdef __cplusplus
}
#endif

#endif /* USM_TOLERANCE_H */
