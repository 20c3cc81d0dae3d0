/* usm_fit.h: the parameters of one motor identified from its measured
 * characteristics (docs/fit.md).
 *
 * Data: rows of measurements, each row at its conditions (the values of some
 * parameters: f, T, F0, ...) with measured outputs (speed, rotor_speed,
 * power_in, ...) and optionally their standard deviations
 * (usm_fit_data; read from a CSV file by usm_fit_data_read, usm_io.h).
 *
 * The fit: weighted least squares, min sum_i ((y_model_i - y_i) / sigma_i)^2
 * over the fitted parameters, by GSL's multifit_nlinear (Levenberg-Marquardt
 * with geodesic acceleration).  Each measurement is evaluated at the motor's
 * operating point at its row's conditions (usm_operating_point.h, the
 * start-up from rest simulated where several roots exist); its Jacobian row
 * comes from the analytic sensitivities of that root (usm_design.h).  A
 * parameter whose range is non-negative is fitted in log scale (the chain
 * rule dy/dlog p = p dy/dp), so it stays positive.  Several starts: the given
 * values, and the best (lowest sum of squares) of a deterministic Sobol
 * sample of the box around them (a factor opt->spread either way in log
 * scale), clipped to the parameters' physical ranges (usm_param_ranges); the
 * best minimum is kept and the starts that reached it counted.
 *
 * A measured point where the model has no operating point (no stationary
 * solution, every root unstable, the motor does not start) is kept as a
 * residual against a motor at rest (every output 0, no derivative), flagged
 * with its reason; a point where the model is not valid (the contact opens,
 * the stick is not admissible) keeps its model value and is flagged too.
 * Nothing is dropped.
 *
 * What it reports (usm_fit_result): estimates, standard errors from the
 * Jacobian at the minimum (covariance s^2 (J^T J)^-1 in the fitted scale;
 * s = 1 with sigmas given, else estimated from the residuals), 95 %
 * intervals (normal quantile with sigmas given, Student t with n - p degrees
 * of freedom when estimated; a log-scale parameter's interval is the
 * log-scale interval mapped back, so it stays positive), the correlation
 * matrix, chi^2 with its p-value (sigmas given only), the residuals, and the
 * identifiability: the singular values of the Jacobian with unit-norm
 * columns (the sensitivity of the data to each parameter taken alone is 1);
 * a singular value below opt->ident_tol names a combination of parameters
 * the data do not determine, with the measurement (output and conditions)
 * that would determine it best.
 *
 * Thread safety: no global mutable state.
 */
#ifndef USM_FIT_H
#define USM_FIT_H

#include <stddef.h>

#include "usm.h"
#include "usm_design.h"
#include "usm_operating_point.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The outputs a measurement may name: usm_design.h's USM_SENS_* but
 * max_modulus, speed = -rotor_speed (positive when the motor drives the
 * load, the sense of a datasheet), and the datasheet quantities of
 * usm_robust.h at the row's conditions (stall_torque [N m]: the load where
 * the speed reaches 0 in a sweep over T from 0 to USM_ROBUST_T_MAX;
 * no_load_speed [1/s]: the speed at T = 0; max_power [W]: the largest
 * power_out over that load range), which ignore the row's T;
 * speed_max_frequency [Hz]: the frequency of the speed maximum over f, the
 * maximum event `usm sweep --over f --extremum speed` locates (a sweep
 * from USM_FIT_F_LO to USM_FIT_F_HI; the largest maximum where there are
 * several), which ignores the row's f.  A datasheet quantity's Jacobian
 * row comes from central differences (usm_fit_run). */
#define USM_FIT_SPEED USM_SENS_COUNT
#define USM_FIT_STALL_TORQUE (USM_SENS_COUNT + 1)
#define USM_FIT_NO_LOAD_SPEED (USM_SENS_COUNT + 2)
#define USM_FIT_MAX_POWER (USM_SENS_COUNT + 3)
#define USM_FIT_SPEED_MAX_FREQUENCY (USM_SENS_COUNT + 4)
#define USM_FIT_NOUTPUTS (USM_SENS_COUNT + 5)
/* The frequency range searched for speed_max_frequency [Hz] (the range of
 * docs/sweep.md's speed maximum) and its grid. */
#define USM_FIT_F_LO 30000.0
#define USM_FIT_F_HI 46000.0
#define USM_FIT_F_POINTS 33

/* 1 when output k is a datasheet quantity (a sweep, not one operating point). */
int usm_fit_output_is_datasheet(int k);
/* The fitted-scale step of the central differences of a datasheet quantity
 * (of log p for a log-scale parameter: a relative step of 1e-3). */
#define USM_FIT_DATASHEET_STEP 1e-3

/* Name ("speed", "rotor_speed", "power_in", ...) of output k, NULL when k
 * is not an output a measurement may name. */
const char *usm_fit_output_name(int k);
/* SI unit of output k ("1/s", "W", ...), NULL as usm_fit_output_name. */
const char *usm_fit_output_unit(int k);
/* The output called name, or -1 (also for max_modulus: not measurable). */
int usm_fit_output_find(const char *name);
/* Output k of a stationary solution (speed: -rotor_speed); NaN when k is
 * not a fit output or a datasheet quantity. */
double usm_fit_output_value(int k, const usm_steady_solution *sol, const usm_params *p);

/* The most columns of a data file. */
#define USM_FIT_MAX_COLUMNS 64

/* Measurements (usm_fit_data_alloc, or usm_fit_data_read from a file). */
typedef struct usm_fit_data {
    int nrows;
    int ncond;                          /* condition columns */
    int cond[USM_FIT_MAX_COLUMNS];      /* their parameters (USM_P_*) */
    int nout;                           /* measured columns */
    int out[USM_FIT_MAX_COLUMNS];       /* their outputs (usm_fit_output_name) */
    int has_sigma[USM_FIT_MAX_COLUMNS]; /* 1: a sigma_NAME column gives their sigmas */
    double *x;                          /* nrows x ncond conditions, SI */
    double *y;                          /* nrows x nout measured values, SI; NaN where a
                                           row leaves the output empty (not measured) */
    double *sigma;                      /* nrows x nout, SI (NaN without sigma) */
    long *line;                         /* each row's line in its file (0: none) */
} usm_fit_data;

/* Data of nrows rows, ncond conditions and nout outputs, every value NaN
 * (the caller fills cond, out, has_sigma, x, y, sigma); NULL when out of
 * memory or a count is out of range. */
usm_fit_data *usm_fit_data_alloc(int nrows, int ncond, int nout);
/* Free d; NULL is allowed. */
void usm_fit_data_free(usm_fit_data *d);
/* The measured values of d (the non-empty y). */
int usm_fit_data_count(const usm_fit_data *d);

/* How the fit runs (usm_fit_options_default). */
typedef struct usm_fit_options {
    int nfit;                 /* the fitted parameters, 1 .. USM_NPARAMS */
    int fit[USM_NPARAMS];     /* their USM_P_* */
    int starts;               /* starts of the local search (default 4; 1: the given values only):
                                 the given values and the starts - 1 best of
                                 USM_FIT_SCREEN * (starts - 1) Sobol points of the box */
    double spread;            /* the box of the starts: a log-scale parameter's given value
                                 divided and multiplied by spread, a linear one's +- spread
                                 times its magnitude; clipped to its physical range
                                 (default 100, 1 .. 1e6) */
    int max_iter;             /* iterations per start (default 100) */
    double ident_tol;         /* singular value (unit-norm columns) below which a direction
                                 is not determined (default 0.05: a collinearity index
                                 1/s above 20) */
    int advise;               /* 1: look for the measurement that separates an
                                 undetermined combination (default 1) */
    int profile;              /* 1: check each end of each interval by the profile
                                 likelihood and, where the two differ by more than 10 %,
                                 report the profile's end (default 1) */
    usm_op_options op;        /* the operating point (default: usm_op_options_default with
                                 from_rest = 1: a simulation decides between several roots) */
} usm_fit_options;

/* Sobol points screened (sum of squares without the Jacobian) per start
 * beyond the first. */
#define USM_FIT_SCREEN 8

/* Fill o with the defaults above (no fitted parameter yet). */
void usm_fit_options_default(usm_fit_options *o);

/* Parse "NAME[,NAME...]" (parameter names) into o->fit, o->nfit.  USM_OK, or
 * USM_EINPUT with "FIELD: reason" in msg (unknown, repeated, a parameter an
 * assumption of model m ties to another (I_yy: fit I_xx), none). */
int usm_fit_parse_names(const usm_model *m, const char *field, const char *text,
                        usm_fit_options *o, char msg[USM_MSG_LEN]);

/* Check data and options against model m and the starting parameters p:
 * every fitted parameter is free, not a condition column, and positive when
 * fitted in log scale; at least as many measured values as fitted
 * parameters.  USM_OK or USM_EINPUT with one line in msg. */
int usm_fit_check(const usm_model *m, const usm_params *p, const usm_fit_data *d,
                  const usm_fit_options *o, char msg[USM_MSG_LEN]);

/* One measured value and the model's value at the estimate. */
typedef struct usm_fit_point {
    int row;                  /* row in the data (from 0) */
    int column;               /* its measured column (index into data->out) */
    int output;               /* the output (usm_fit_output_name) */
    double measured, model;   /* SI */
    double sigma;             /* the sigma used (given, or estimated: see sigma_estimated) */
    double residual;          /* (model - measured) / sigma */
    int flagged;              /* 1: see reason */
    char reason[64];          /* "" or why: no_solution, no_stable_root, does_not_start,
                                 undecided, contact_open, stick_not_admissible,
                                 bad_parameters, failed */
} usm_fit_point;

/* A combination of the fitted parameters the data do not determine. */
typedef struct usm_fit_unidentified {
    double singular_value;    /* of the Jacobian with unit-norm columns */
    double direction[USM_NPARAMS]; /* per fitted parameter (in o->fit order), the change of
                                      its fitted-scale value (log p, or p) along which the
                                      data hardly change; largest |entry| 1 */
    int advice;               /* 1: a separating measurement was found */
    int advice_output;        /* its output */
    double advice_cond[USM_FIT_MAX_COLUMNS]; /* at these conditions (data->cond order) */
    double advice_score;      /* |d ln y / d t| along the direction */
} usm_fit_unidentified;

/* Everything a fit reports (usm_fit_run; usm_fit_result_free). */
typedef struct usm_fit_result {
    int status;               /* USM_OK, or the failure (message) */
    char message[USM_MSG_LEN];
    int nfit;
    int fit[USM_NPARAMS];
    int log_scale[USM_NPARAMS];
    double start[USM_NPARAMS];    /* the given values */
    double estimate[USM_NPARAMS];
    double se[USM_NPARAMS];       /* standard error of the estimate (delta method in log scale);
                                     infinite where the data do not determine it */
    double lo[USM_NPARAMS], hi[USM_NPARAMS]; /* 95 % interval */
    double se_scaled[USM_NPARAMS]; /* standard error in the fitted scale (log p or p) */
    /* The profile likelihood's 95 % interval (opt->profile): where the sum of
     * squares minimized over the other parameters rises by quantile^2 s^2.
     * profiled[j] = 1 when either end differs from the Jacobian's by more
     * than 10 % of its half-width (then profile_lo/hi hold the profile's ends,
     * infinite where the profile stays below the level within the
     * parameter's range); 0: the Jacobian's interval stands (profile_lo/hi
     * equal lo/hi). */
    int profiled[USM_NPARAMS];
    double profile_lo[USM_NPARAMS], profile_hi[USM_NPARAMS];
    double corr[USM_NPARAMS * USM_NPARAMS]; /* row-major nfit x nfit */
    double quantile;          /* of the intervals (1.96 or Student t) */
    double chi2;              /* sum of squared residuals (weighted) */
    int dof;                  /* measured values - nfit */
    double p_value;           /* P(chi^2_dof >= chi2); NaN when sigma_estimated */
    int sigma_estimated;      /* 1: some sigma was not given: estimated from the residuals */
    double sigma_scale;       /* s: the sigmas not given are s times the RMS of their
                                 output's measured values (1 when all were given) */
    double singular[USM_NPARAMS]; /* descending */
    int identifiable;         /* no singular value below ident_tol */
    int nunidentified;
    usm_fit_unidentified unidentified[USM_NPARAMS];
    int npoints;
    usm_fit_point *points;    /* npoints (malloc'd) */
    int nflagged;
    int starts, iterations, evaluations; /* starts run, iterations and point evaluations */
    int best_start;           /* the start whose minimum was kept (from 0: the given values) */
    int starts_at_best;       /* the starts whose minimum's sum of squares is the best's
                                 (within 1e-6 of it): 1 says the others found other minima */
    double wall;              /* seconds */
} usm_fit_result;

/* Fit the parameters o->fit of model m to data d, starting from p (the
 * other parameters are held at p's values; each row sets its conditions).
 * USM_OK (out filled; flagged points are part of the result), USM_EINPUT
 * (usm_fit_check's message), USM_ENOSOLUTION (no start gives a finite sum
 * of squares), USM_EFAILED (out of memory, the solver failed); out->message.
 * Free out with usm_fit_result_free (also after a failure). */
int usm_fit_run(const usm_model *m, const usm_params *p, const usm_fit_data *d,
                const usm_fit_options *o, usm_fit_result *out);
/* Free what usm_fit_run allocated in r (r itself is the caller's). */
void usm_fit_result_free(usm_fit_result *r);

/* The residuals and Jacobian of the fit at the fitted-scale point t
 * (t[j] = log p or p of parameter o->fit[j]): f[i] = (model - measured) /
 * sigma_i for the usm_fit_data_count(d) measured values in row order, J row
 * major (n x nfit), sigma the given sigmas and 1 elsewhere.  For a second
 * optimizer and tests.  USM_OK, or USM_EFAILED when out of memory. */
int usm_fit_residuals(const usm_model *m, const usm_params *p, const usm_fit_data *d,
                      const usm_fit_options *o, const double *t, double *f, double *J);

#ifdef __cplusplus
}
#endif

#endif /* USM_FIT_H */
