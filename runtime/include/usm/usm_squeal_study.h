/* usm_squeal_study.h: what the motor does over one parameter where no
 * periodic orbit need be stable (`usm squeal`, docs/squeal.md).
 *
 * For each of `points` values of one parameter (a model whose contact may
 * open: usm_model.unilateral, the variant imperfect_unilateral):
 *  - a long event-driven run (usm_sim_run, simulate.c) of settle + window
 *    excitation periods, the first value from rest, each next one from the
 *    previous value's end state (continuation: the attractor the motor is
 *    on follows the parameter); with check_rest, also a fresh start from
 *    rest at the same value, compared (coexisting attractors);
 *  - the settled window: its last `window` periods, sampled
 *    samples_per_period times a period (a grid of whole periods, so the
 *    excitation's harmonics fall on bins): the stroboscopic samples (once a
 *    period, at t = k T) of the rotor speed, the tilt and the gap (the
 *    bifurcation diagram), the mean rotor speed and its ripple (peak to
 *    peak of the samples);
 *  - the largest Lyapunov exponents (usm_hybrid_lyapunov, usm_periodic.h:
 *    tangent vectors through the saltation matrix at every switch,
 *    renormalised every period) from the window's first state, over
 *    lyapunov_skip + lyapunov_periods periods; the impact rate and the
 *    largest impact velocity are counted over that run;
 *  - the classification: periodic with period k (the smallest k <= 16 with
 *    every stroboscopic sample repeating after k periods to period_tol of
 *    its channel's scale), else chaotic when lambda T > exponent_tol, else
 *    quasi-periodic with the second frequency of the strongest line of the
 *    stroboscopic tilt's spectrum (in (0, f/2]), or "settling" when the
 *    motion repeats nowhere yet lambda T < -exponent_tol (a slowly
 *    contracting transient: the window is too early);
 *  - the audible spectrum (20 Hz to 20 kHz) of the sound source: the
 *    stator rim's axial velocity at the contact point, v = dZ(theta)/dt =
 *    (R cos theta - H sin theta) theta' (Z(theta) = R sin theta + H cos
 *    theta, the height of the crest of the tilted stator's rim on which the
 *    rotor rests; the rotor's own axial velocity while closed), through
 *    usm_spectrum_amplitude (Hann window, GSL FFT) and usm_spectrum_lines
 *    (two-bin interpolation); the strongest `lines` local maxima between
 *    20 Hz and 20 kHz, their level in dB re 1e-9 m/s RMS (velocity level,
 *    ISO 1683): 20 log10(A / sqrt(2) / 1e-9);
 *  - the power each force feeds into the motion over power_periods from the
 *    window's first state, and the energy balance that checks it
 *    (usm_squeal_energy, below).
 * After the points: the origin at the end of the period-1 branch
 * (usm_squeal_origin) and, with `sensitivities`, the onset located past it
 * and its derivatives in the design parameters (usm_squeal_onset).
 *
 * Thread safety: no global state; one study per thread.  The caller sets
 * GSL's error handler (usm.h).
 */
#ifndef USM_SQUEAL_STUDY_H
#define USM_SQUEAL_STUDY_H

#include <stddef.h>
#include <stdio.h>

#include "usm.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
    USM_MOTION_PERIODIC = 0,       /* period-k orbit (period) */
    USM_MOTION_QUASI_PERIODIC = 1, /* a second frequency (second_frequency) */
    USM_MOTION_CHAOTIC = 2,        /* positive largest Lyapunov exponent */
    USM_MOTION_SETTLING = 3,       /* contracting, but not yet periodic in the window */
    USM_MOTION_REST = 4,           /* the wobble decayed: the motor stands */
    USM_MOTION_FAILED = 5          /* the run failed (message) */
} usm_motion;

/* "periodic", "quasi_periodic", "chaotic", "settling", "rest", "failed". */
const char *usm_motion_name(usm_motion m);

/* Audible lines kept per point (at most). */
#define USM_SQUEAL_MAX_LINES 16
/* Longest period k tested for. */
#define USM_SQUEAL_MAX_PERIOD 16

typedef struct usm_squeal_options {
    const char *over;        /* a parameter name (usm_params_find) */
    double from, to;         /* from != to */
    int points;              /* 2 .. 10000 */
    long settle;             /* periods before the window (default 400) */
    long window;             /* periods of the settled window (default 1024: lines
                                f / 1024 apart, 36 Hz at 37 kHz) */
    int samples_per_period;  /* 4 .. 64 (default 8) */
    long lyapunov_skip;      /* periods before the exponents are averaged (default 50) */
    long lyapunov_periods;   /* periods they are averaged over (default 200) */
    double rtol;             /* the simulation's (default 1e-8) */
    double lyapunov_rtol;    /* the tangent run's (default 1e-8) */
    double period_tol;       /* repetition of the stroboscopic samples (default 1e-3) */
    double exponent_tol;     /* |lambda| T below this is no decision (default 0.01) */
    int check_rest;          /* 1: a start from rest at every value but the first
                                (default 1) */
    int lines;               /* audible lines kept, 1 .. USM_SQUEAL_MAX_LINES (default 6) */
    int origin;              /* 1: the origin at the end of the period-1 branch
                                (usm_squeal_origin; default 1, an orbit solve) */
    long power_periods;      /* periods of the power account from the window's first
                                state (usm_squeal_energy; default 200; 0: none) */
    double power_rtol;       /* its tolerance (default 1e-9) */
    int sensitivities;       /* 1: the onset located past the origin and its sensitivities
                                to the design parameters (usm_squeal_onset_sensitivities,
                                about 10 s of CPU; default 0); needs origin */
    double sensitivity_h;    /* their relative step (default 1e-3) */
    double onset_tol;        /* the onset's tolerance, relative to the origin's bracket
                                (default 1e-6) */
    void (*progress)(double fraction, void *ctx); /* NULL: silent */
    void *progress_ctx;
} usm_squeal_options;

/* Defaults as above; over NULL, from = to = 0, points 0 (must be set). */
void usm_squeal_options_default(usm_squeal_options *opt);

typedef struct usm_squeal_line {
    double frequency;   /* [Hz] */
    double amplitude;   /* of the rim velocity [m/s] */
    double level_db;    /* dB re 1e-9 m/s RMS */
} usm_squeal_line;

/* The power fed into the motion by each force over a run of whole
 * excitation periods, and the energy balance that checks it
 * (usm_squeal_energy; docs/squeal.md "Power").  Mean powers [W] over the
 * run, positive where the force feeds the motion:
 *  - excitation: the driver's torque on the stator, tau_E . omega;
 *  - damping: -(d_r (omega_x1^2 + omega_y1^2) + d_t omega_z1^2 + d_R Z_R'^2);
 *  - load: the load torque on the rotor, -T w_R;
 *  - friction: the friction force on both bodies, -F_t v_rel (<= 0 where it
 *    opposes the slip), the sum of friction_stator = -F_t v_c (its power on
 *    the stator's vibration: > 0 feeds the vibration) and friction_rotor =
 *    F_t R* w_R (what drives the rotor);
 *  - normal_stator: the normal force's power on the stator, -F_n Z',
 *    returned to the rotor's axial motion (the two cancel);
 *  - impacts_power: the jumps of the mechanical energy at the resets (the
 *    kinetic energy the impacts take, <= 0 at e_impact <= 1), per second.
 * The mechanical energy E: the kinetic energy of stator and rotor (axial and
 * turning) and the potentials of the tilt spring, c_r theta^2 (1 + s cos 2
 * phi) / 2, the twist spring, c_t tau^2 / 2, and the preloaded spring, F0
 * (Z_R - H) + c_R (Z_R - H)^2 / 2 (usm_squeal_mechanical_energy).  balance_error =
 * |E(end) - E(start) - (sum of the works and jumps)| / (sum of their
 * absolute values): the integrator's error, a force missing would be O(1). */
typedef struct usm_squeal_power {
    long periods;               /* 0: not computed */
    double duration;            /* [s] */
    double excitation, damping, load, friction, friction_stator, friction_rotor;
    double normal_stator, impacts_power;     /* [W] */
    double energy_start, energy_end;         /* [J] */
    double balance_error;       /* relative (above) */
    long separations, impacts;  /* over the run */
} usm_squeal_power;

/* The account above of the motion of unilateral model m from the state y0
 * at t0 (open: 1 with y0 the open mode's state, else the closed state) over
 * `periods` excitation periods, integrated at rtol with the simulation's
 * resets (an integration of its own, with the works as states).  USM_OK;
 * USM_EINPUT (a model whose contact never opens, periods < 1, rtol outside
 * [1e-14, 1e-3]) or USM_EFAILED (the integration failed), with the reason in
 * msg (USM_MSG_LEN). */
int usm_squeal_energy(const usm_model *m, const usm_params *p, double t0, int open,
                      const double *y0, long periods, double rtol, usm_squeal_power *out,
                      char *msg);

/* The mechanical energy E [J] (above) of unilateral model m at the state y
 * (open: the open mode's; else the closed state, the rotor on the crest);
 * NaN for a model whose contact never opens. */
double usm_squeal_mechanical_energy(const usm_model *m, const usm_params *p, int open,
                                    const double *y);

typedef struct usm_squeal_point {
    double value;               /* the parameter */
    int status;                 /* USM_OK, or USM_EFAILED (message) */
    char message[USM_MSG_LEN];
    usm_motion motion;
    int period;                 /* k for periodic motion, 0 otherwise */
    double second_frequency;    /* [Hz], quasi-periodic (NaN otherwise) */
    double lyapunov;            /* largest exponent [1/s] (NaN: not computed) */
    double lyapunov2;           /* the second [1/s] */
    double lyapunov_per_period; /* lyapunov T */
    double rotor_speed_mean;    /* [1/s] over the window */
    double rotor_speed_ripple;  /* peak to peak [1/s] */
    double theta_mean;          /* [rad] */
    double open_fraction;       /* samples of the window with the contact open */
    double impacts_per_period;  /* over the tangent run */
    double impact_velocity_max; /* [m/s], over the tangent run */
    size_t nlines;
    usm_squeal_line lines[USM_SQUEAL_MAX_LINES]; /* strongest first */
    double df;                  /* bin spacing f / window [Hz] */
    /* the start from rest at this value (check_rest) */
    int rest_checked;
    usm_motion rest_motion;
    int rest_period;
    double rest_speed_mean;     /* [1/s] */
    int coexisting;             /* 1: the start from rest ends elsewhere (another motion
                                   or period, or mean speed more than 2 % apart) */
    usm_squeal_power power;     /* over power_periods from the window's start (periods 0:
                                   not computed) */
    double seconds;             /* CPU time of this value [s] */
} usm_squeal_point;

/* Most degrees of freedom in an origin's participation. */
#define USM_SQUEAL_MAX_DOF 12

/* The origin of the irregular motion at the end of the stable period-1
 * branch within the study's range (usm_squeal_origin): at the last value
 * whose motion is period 1 before one that is not, the orbit with
 * separation (usm_hybrid_solve_from, from that value's last closed state)
 * and its monodromy with the saltation matrices:
 *  - kind: how the branch ends.  "closed_phase_vanishing" when the orbit is
 *    stable there (max |lambda| < 1): no smooth bifurcation, the closed phase
 *    shrinks to nothing (separation_fraction near 1) and the orbit ends where
 *    the rotor would no longer land; else "fold" (a real multiplier > 1),
 *    "period_doubling" (real < -1) or "neimark_sacker" (a complex pair);
 *  - the critical (largest non-cyclic) multiplier and its eigenvector as the
 *    participation of each degree of freedom: the share of DOF q is
 *    (|v_q|^2 + |v_qdot|^2 / (2 pi f)^2) / sum over all (the velocity
 *    expressed as the amplitude it has at the excitation frequency; all the
 *    coordinates are angles), normalised to sum 1; a state without a
 *    velocity partner is a DOF of its own. */
typedef struct usm_squeal_origin {
    int found;                  /* 1: a change from period 1 in the range and its orbit */
    char message[USM_MSG_LEN];  /* why not, when there was a change but no orbit */
    double value;               /* the last period-1 value */
    double next_value;          /* the first value past it */
    char kind[32];
    double max_modulus;         /* of the orbit there */
    double multiplier_re, multiplier_im;
    double separation_fraction; /* time open per period */
    int impacts_per_period;
    char mode_sequence[40];
    int ndof;
    char dof[USM_SQUEAL_MAX_DOF][24];   /* the position's state name */
    double share[USM_SQUEAL_MAX_DOF];   /* sum 1 */
} usm_squeal_origin;

/* The onset of the irregular motion located: where the stable orbit with
 * separation continued from `value` towards `toward` ends
 * (usm_squeal_locate_onset), and how the design parameters move it
 * (usm_squeal_onset_sensitivities). */
typedef struct usm_squeal_sensitivity {
    char parameter[24];         /* a usm_params field */
    double h;                   /* the step of the central difference [its unit] */
    double d_onset;             /* d(onset) / d(parameter) [the swept one's unit per its own] */
    double elasticity;          /* (parameter / onset) d(onset) / d(parameter) [1] */
    double resolution;          /* |d_onset| below this is not resolved (the locations'
                                   tolerance over h): a d_onset of 0 means "below it" */
    char message[120];          /* why d_onset is NaN, or "" */
} usm_squeal_sensitivity;

/* The design parameters whose sensitivities are computed (the swept one
 * left out): preload F0, friction scale mu0, excitation frequency f, load
 * torque T, excitation amplitude m0. */
#define USM_SQUEAL_DESIGN_PARAMETERS 5
/* Most parameters of one sensitivity call. */
#define USM_SQUEAL_MAX_SENSITIVITIES 8
extern const char *const usm_squeal_design_parameters[USM_SQUEAL_DESIGN_PARAMETERS];

typedef struct usm_squeal_onset {
    int found;
    char message[USM_MSG_LEN];  /* why not */
    double value;               /* the onset [the swept parameter's unit] */
    char kind[32];              /* "branch_end" (Newton fails past it: the orbit ends, its
                                   closed phase small) or "stability_loss" (max |lambda| = 1) */
    double closed_fraction;     /* of the last orbit located */
    double last_orbit;          /* the value of the last orbit (branch_end) */
    int solves;                 /* orbit solves used, the sensitivities' included */
    int nsens;
    usm_squeal_sensitivity sens[USM_SQUEAL_MAX_SENSITIVITIES];
    char most_sensitive[24];    /* the parameter of the largest |elasticity| */
} usm_squeal_onset;

/* The end of the stable orbit with separation of unilateral model m at
 * parameters p, followed in `over` from `value` (its orbit from the section
 * (ts, x0), or with x0 NULL from rest: usm_hybrid_solve) towards `toward`:
 * continued by Newton with the section moved to the middle of each orbit's
 * closed phase, in steps halved where Newton fails, to the end of the branch
 * within tol times |toward - value| (branch_end); or, should an orbit on the
 * way be unstable, the zero of max |lambda| - 1 (regula falsi).  USM_OK
 * with out->found, or found 0 and out->message (no stable orbit at value,
 * no end in the range, a branch that ends otherwise); USM_EINPUT (bad arguments, message); USM_EFAILED (out of
 * memory). */
int usm_squeal_locate_onset(const usm_model *m, const usm_params *p, const char *over,
                            double value, double toward, double ts, const double *x0, double tol,
                            usm_squeal_onset *out);

/* usm_squeal_locate_onset, then for each of the nnames parameters `names`
 * (NULL: usm_squeal_design_parameters; at most USM_SQUEAL_MAX_SENSITIVITIES;
 * `over` left out) the onset located again at the parameter P (1 +- h) (its
 * orbit at `value` from the same start): d_onset by the central difference,
 * the elasticity, and the most sensitive parameter.  A parameter whose
 * shifted onset is not found or of another kind has d_onset NaN and a
 * message.  Returns as usm_squeal_locate_onset (USM_EINPUT also for h
 * outside (0, 0.1), an unknown name or too many). */
int usm_squeal_onset_sensitivities(const usm_model *m, const usm_params *p, const char *over,
                                   double value, double toward, double ts, const double *x0,
                                   const char *const *names, int nnames, double h, double tol,
                                   usm_squeal_onset *out);

/* A study over one parameter with its points (opaque). */
typedef struct usm_squeal_study usm_squeal_study;

/* For model m (not NULL), or NULL when out of memory. */
usm_squeal_study *usm_squeal_alloc(const usm_model *m);
/* Free s; NULL is allowed. */
void usm_squeal_free(usm_squeal_study *s);

/* Check opt and p as usm_squeal_run does: USM_OK, or USM_EINPUT with
 * "FIELD: reason" in usm_squeal_message (FIELD over, from, to, points,
 * settle, window, ... or "model"). */
int usm_squeal_check(usm_squeal_study *s, const usm_params *p, const usm_squeal_options *opt);

/* Run the study (header comment).  USM_OK (a point whose run failed has
 * status USM_EFAILED and motion "failed"; the next starts from rest);
 * USM_EINPUT (as usm_squeal_check); USM_EFAILED (out of memory). */
int usm_squeal_run(usm_squeal_study *s, const usm_params *p, const usm_squeal_options *opt);

/* The origin of the last run (usm_squeal_origin above); NULL before a run. */
const usm_squeal_origin *usm_squeal_origin_get(const usm_squeal_study *s);
/* The onset and its sensitivities of the last run (options' sensitivities);
 * NULL when not computed (off, or no origin found). */
const usm_squeal_onset *usm_squeal_onset_get(const usm_squeal_study *s);
/* Points of the last run, in sweep order. */
size_t usm_squeal_count(const usm_squeal_study *s);
/* Point i of the last run, NULL when out of range. */
const usm_squeal_point *usm_squeal_point_at(const usm_squeal_study *s, size_t i);
/* The stroboscopic samples of point i: *n of them (the window's periods),
 * rotor speed [1/s], tilt [rad] and gap [m] (0 while closed); NULL when out
 * of range or the run failed. */
int usm_squeal_strobe(const usm_squeal_study *s, size_t i, size_t *n, const double **speed,
                      const double **theta, const double **gap);
/* The last run's options (over copied) and parameter name. */
const char *usm_squeal_over(const usm_squeal_study *s);
/* Excitation frequency of point i [Hz]. */
double usm_squeal_f(const usm_squeal_study *s, size_t i);
/* The model of s. */
const usm_model *usm_squeal_model(const usm_squeal_study *s);
/* Why the last call failed, or "". */
const char *usm_squeal_message(const usm_squeal_study *s);

/* The JSON object {"model", "over", "points": [{"value", "motion", "period",
 * "lyapunov", "lines": [{"frequency", "level_db"}], ...}]} and a newline
 * (write/squeal_out.c).  0, or -1 on a write error. */
int usm_squeal_write_json(const usm_squeal_study *s, FILE *out);
/* CSV: a header with units, one row per point (the three strongest lines
 * in columns).  0, or -1 on a write error. */
int usm_squeal_write_csv(const usm_squeal_study *s, FILE *out);
/* The bifurcation diagram's data as CSV: value, k, rotor_speed, theta, gap
 * for every stroboscopic sample of every point.  0, or -1. */
int usm_squeal_write_strobe_csv(const usm_squeal_study *s, FILE *out);

/* The data of `usm squeal --plot`: the stroboscopic samples (NAME, k,
 * rotor_speed, theta) and the audible lines (NAME, frequency, level_db) of
 * every point, each row one or the other (the other's fields empty), for
 * data/plots/squeal_study.gp.  0, or -1 on a write error. */
int usm_squeal_write_plot_csv(const usm_squeal_study *s, FILE *out);

#ifdef __cplusplus
}
#endif

#endif /* USM_SQUEAL_STUDY_H */
