/* report.h: `usm report`, the paper reproduced in a Markdown report with
 * figures (internal to the usm command).
 *
 *   usm_report_paper.c         the paper's published values, read from data/paper_values.json
 *   usm_report_compute.c       everything the report shows, computed through libusm
 *   usm_report_map.c           the 2-D stability map (threads), also `usm map`
 *   usm_report_plot.c          CSV data, gnuplot scripts, running gnuplot
 *   usm_report_json.c          report.json: every number by name (report.md and
 *                          report.html are rendered from it by templates)
 *   usm_report_cmd.c           options, output directory, the run
 */
#ifndef USM_REPORT_INTERNAL_H
#define USM_REPORT_INTERNAL_H

#include <stdio.h>

#include <jansson.h>

#include "io/io_msg.h"
#include "report_map.h"
#include "usm.h"
#include "usm_design.h"
#include "usm_report.h"
#include "usm_periodic.h"
#include "usm_spectrum.h"
#include "usm_sweep.h"

/* ---- the paper's published values (usm_report_paper.c) ------------------------ */

typedef struct usm_report_published {
    char where[48];    /* where the paper prints it */
    char what[96];     /* the quantity */
    char printed[48];  /* exactly as printed */
    double value;      /* the printed number, in the printed unit */
    char unit[24];     /* the printed unit */
} usm_report_published;

typedef struct usm_report_published_multiplier {
    char label[24];           /* "lambda_1,2" */
    char printed[48];         /* "-0.7101 ± 0.5908i" */
    double re, im;            /* im > 0: the pair re ± im i */
    char modulus_printed[24]; /* the table's "absolute value" column */
    double modulus;
} usm_report_published_multiplier;

typedef struct usm_report_paper {
    usm_report_published theta3, alpha3, beta3;
    usm_report_published speed4, theta4, alpha4, beta4;
    usm_report_published_multiplier table3[4];
    int n3;
    usm_report_published_multiplier table4[6];
    int n4;
    usm_report_published f_max, slip_load, speed_ratio;
} usm_report_paper;

/* Read data/paper_values.json (see data_dir.h).  Called once before anything
 * else of the report; USM_OK, or USM_EFAILED with msg naming the file. */
int usm_report_paper_load(usm_report_paper *paper, char msg[USM_IO_MSG_LEN]);

/* ---- what the report computes (usm_report_compute.c) -------------------------- */

/* Start times of the t0 study, in periods: 0, 1/4, 1/2, 10, 100, 1000. */
#define REPORT_NT0 6
extern const double usm_report_t0_fraction[REPORT_NT0];
extern const char *const usm_report_t0_label[REPORT_NT0]; /* "0", "T/4", ... */

typedef struct usm_report_model_result {
    const usm_model *model;
    usm_steady_solution sol;                /* primary root, paper's parameters */
    usm_floquet_result fl[REPORT_NT0];      /* at t0 = fraction * period */
    /* twist_integrated variant of the same model (NULL when not generated or
     * without a solution), taken from usm_report_data.variant */
    const usm_model *integrated;
    usm_floquet_result fl_integrated[2];    /* at t0 = 0 and T/2 */
} usm_report_model_result;

/* Every generated model (variant) at the report's parameters, side by side. */
#define REPORT_NVARIANT_T0 3 /* t0 = 0, T/2, 100 T */
typedef struct usm_report_variant_result {
    const usm_model *model;
    int ok;                                  /* a stationary solution exists */
    usm_steady_solution sol;
    usm_floquet_result fl[REPORT_NVARIANT_T0];
    char note[USM_MSG_LEN];                  /* why not ok */
} usm_report_variant_result;

/* A located value (bisection or golden section); ok = 0 when not found in
 * the range searched (text in note). */
typedef struct usm_report_located {
    int ok;
    double value;
    double from, to;         /* the range searched (the curve's) */
    usm_event_type type;     /* the sweep event it was taken from (when ok):
                              * a branch can end at a fold, where the tilt
                              * falls to zero, where it leaves the searched
                              * range or where friction saturates */
    int has_sol;             /* sol holds the solution there (0: none exists
                              * at value, e.g. at friction saturation) */
    usm_steady_solution sol;
    char note[USM_MSG_LEN];
} usm_report_located;

/* One characteristic curve: a sweep of one parameter, one model. */
typedef struct usm_report_curve {
    const char *over;
    double from, to;
    int points;
    usm_sweep *sweep;       /* owns the points and events */
} usm_report_curve;

enum { REPORT_CURVE_F = 0, REPORT_CURVE_T = 1, REPORT_CURVE_M0 = 2, REPORT_NCURVES = 3 };
enum { REPORT_3DOF = 0, REPORT_4DOF = 1, REPORT_NMODELS = 2 };


/* A nearly vanishing preload [N], to show what the contact moment does. */
#define REPORT_SMALL_F0 0.01

/* ---- the non-ideal motor (report_nonideal.c) -------------------------- */

/* The imperfections swept, each alone from 0: phase_error 0 to 30 degrees,
 * mode_split 0 to 2 %. */
enum { REPORT_IMP_PHASE = 0, REPORT_IMP_SPLIT = 1, REPORT_NIMP = 2 };
#define REPORT_NONIDEAL_MAXPTS 61

typedef struct usm_report_nonideal_point {
    double value;              /* the imperfection (SI: rad or 1) */
    int converged;             /* the periodic orbit was found (else the fields are NaN) */
    double speed_mean, ripple; /* rotor speed mean and peak to peak [1/s] */
    double F_n_min, F_n_max;   /* [N] */
    int openings;              /* the bilateral orbit's openings_per_period */
    double max_modulus;        /* largest non-cyclic |lambda| */
    double theta_h2;           /* 2 Omega amplitude of theta [rad] */
    usm_validity validity;     /* of the orbit (usm_periodic_result.validity) */
    /* past contact loss: the orbit with separation of the unilateral model
     * (usm_periodic_point.hybrid); NaN where separating = 0 */
    int separating;
    double sep_speed_mean, sep_ripple, sep_max_modulus; /* [1/s], [1/s], [1] */
    double sep_fraction, impact_velocity_max;            /* [1], [m/s] */
    usm_validity sep_validity;  /* of the orbit with separation (a stick model's impacts
                                   may need more than mu0: stick_not_admissible) */
} usm_report_nonideal_point;

/* A root of F_n_min (contact opens) or of max_modulus - 1 (stability lost)
 * along a curve, an event of the periodic sweep: found = 0 with a note when
 * not in the range. */
typedef struct usm_report_nonideal_root {
    int found;
    double value;
    int openings;               /* contact: the times a period the contact opens, counted
                                   on the first grid orbit past the root (0: unknown) */
    char note[USM_MSG_LEN];
} usm_report_nonideal_root;

typedef struct usm_report_nonideal_curve {
    const char *param;        /* "phase_error", "mode_split" */
    double from, to;          /* [rad] or [1] */
    int points;
    usm_report_nonideal_point pt[REPORT_NONIDEAL_MAXPTS];
    usm_report_nonideal_root contact;   /* F_n_min = 0 */
    usm_report_nonideal_root stability; /* max |lambda| = 1 */
    usm_report_nonideal_root valid_to;  /* the model stops describing the motor
                                         * (validity: contact opens, stick lost):
                                         * found = 0 when valid over the curve */
    /* past contact loss (the unilateral model): points with an orbit with
     * separation; the largest value up to which every orbit with separation
     * found drives the load (mean rotor speed of the ideal motor's sign);
     * the largest impact velocity and where */
    int sep_points, sep_drives_all;
    double sep_drives_to, sep_impact_max, sep_impact_at;
    /* of these, the unstable ones (largest non-cyclic |lambda| >= 1: the
     * motor does not stay on such an orbit), the first and last value where
     * one is, and the largest |lambda| of all orbits with separation */
    int sep_unstable;
    double sep_unstable_from, sep_unstable_to, sep_modulus_max;
    /* the sweep's branch switches (usm_periodic_sweep.h, branch_switch):
     * how many, and the first's value and the continued orbit's |lambda|
     * there */
    int sep_switches;
    double sep_switch_at, sep_switch_modulus, sep_switch_unstable_from;
    int tolerable_found;      /* the smaller of the two roots found */
    double tolerable;
    const char *tolerable_by; /* "contact" or "stability" */
} usm_report_nonideal_curve;

typedef struct usm_report_nonideal {
    int ok;                   /* computed (else note says why) */
    char note[USM_MSG_LEN];
    const usm_model *model[REPORT_NMODELS]; /* the variant "imperfect" */
    const usm_model *umodel[REPORT_NMODELS]; /* the variant "imperfect_unilateral" (the
                                                sweeps; NULL: not built, no orbits past
                                                contact loss) */
    double theta_ideal[REPORT_NMODELS];     /* stationary tilt of the ideal motor [rad] */
    usm_report_nonideal_curve curve[REPORT_NMODELS][REPORT_NIMP];
    /* the orbit drawn: 3-DOF at orbit_value of orbit_param */
    int orbit_ok;
    int orbit_imp;            /* REPORT_IMP_* */
    double orbit_value;
    char orbit_note[USM_MSG_LEN];
    int orbit_nx, orbit_x_phi, orbit_x_theta;
    double orbit[USM_PERIODIC_SAMPLES][USM_MAX_NX + 4]; /* usm_periodic_samples rows */
    double orbit_F_n_min;
    double orbit_period;      /* [s] */
    usm_periodic_options opt; /* of the sweeps' and the orbit's periodic solves */
    double root_xtol;         /* the roots to this fraction of the range */
    double seconds;
} usm_report_nonideal;

/* ---- the squeal (report_squeal.c) ------------------------------------ */

#define REPORT_SQUEAL_MAXPTS 8
#define REPORT_SQUEAL_MAXBINS 2048

/* One mode split past (or before) the Neimark-Sacker point: the periodic
 * orbit's multipliers and a simulation from rest with its spectrum. */
typedef struct usm_report_squeal_point {
    double mode_split;          /* [1] */
    int orbit_ok;               /* the periodic orbit converged */
    double max_modulus;         /* its largest non-cyclic |lambda| */
    double F_n_min;             /* its smallest normal force [N] */
    int valid;                  /* the model describes the motor on the orbit
                                   (usm_periodic_result.validity) */
    int has_pair;               /* it has a complex pair (usm_floquet_squeal) */
    double squeal_frequency;    /* of the dominant pair [Hz] */
    int sim_ok;                 /* simulated and its spectrum computed */
    char note[USM_MSG_LEN];     /* why not */
    double parasitic_rms[USM_SPECTRUM_NCHANNELS];
    int has_line;               /* F_n has a non-harmonic line */
    usm_spectrum_line line;     /* F_n's strongest non-harmonic line */
} usm_report_squeal_point;

/* What the unilateral motor does over the 4-DOF mode split past its last
 * stable periodic orbit (usm_squeal_study.h: long event-driven runs, their
 * stroboscopic samples, Lyapunov exponent, classification and audible lines). */
typedef struct usm_report_squeal_motion {
    int ok;                     /* computed (else note says why) */
    char note[USM_MSG_LEN];
    const usm_model *model;     /* 4dof_imperfect_unilateral */
    struct usm_squeal_study *study; /* its points and samples; owned */
    double from, to;            /* the mode split range */
    int points;
    long settle, window, lyapunov_skip, lyapunov_periods;
    double onset_lo, onset_hi;  /* the last periodic value and the first irregular one past it
                                   (NaN: no change from period-1 in the range) */
    double seconds;             /* CPU time of the study [s] */
} usm_report_squeal_motion;

typedef struct usm_report_squeal {
    usm_report_squeal_motion motion; /* the motor past its last orbit */
    int ok;                     /* the bilateral Neimark-Sacker part computed (else note says why) */
    char note[USM_MSG_LEN];
    const usm_model *model;     /* 4dof_imperfect */
    double from, to;            /* the mode split range searched for the NS point */
    double ns_value;            /* the Neimark-Sacker point's mode split */
    double ns_re, ns_im;        /* its critical multiplier (im > 0) */
    double ns_frequency;        /* its squeal_frequency [Hz] */
    usm_validity ns_validity;   /* of the orbit there: a squeal frequency of an orbit the
                                   model does not describe is printed with this flag */
    double f;                   /* excitation frequency [Hz] */
    double duration;            /* of each simulation [s] */
    long periods;               /* the spectrum's window [periods] */
    int npts;
    usm_report_squeal_point pt[REPORT_SQUEAL_MAXPTS];
    int spectrum_pt;            /* the point whose spectrum is drawn, just past NS */
    size_t bins;                /* of its spectrum (bin k at k df) */
    double df;
    double amp[USM_SPECTRUM_NCHANNELS][REPORT_SQUEAL_MAXBINS];
    double seconds;
} usm_report_squeal;

typedef struct usm_report_data {
    usm_report_paper paper;     /* the published values (usm_report_paper_load) */
    usm_params params;
    usm_report_options opt;
    usm_report_model_result model[REPORT_NMODELS];

    /* parameter choices, checked on the spot */
    double f_from_cr;           /* sqrt(c_r / I_xx) / (2 pi) [Hz] */
    double dr_3pct, dt_3pct;    /* 2 * 0.03 * sqrt(c I) */
    double M_disk;              /* 2 I_R / R^2 */
    double M_from_dR;           /* M if d_R were 3 % damping: (d_R / 0.06)^2 / c_R */
    double theta_at_fmax_paper; /* tilt at the paper's 36.8 kHz */
    /* Table 3 fit for rotor masses: 0, 2 I_R/R^2, (d_R/0.06)^2/c_R */
    double M_trial[3];
    double M_trial_dev[3];      /* largest |computed - Table 3| */

    /* characteristic curves [curve][model] */
    usm_report_curve curve[REPORT_NCURVES][REPORT_NMODELS];

    /* key numbers */
    usm_report_located f_max[REPORT_NMODELS];       /* speed maximum over f */
    usm_report_located f_theta_max;                 /* tilt maximum over f (3dof) */
    usm_report_located f_theta_max_small_F0;        /* the same with F0 = REPORT_SMALL_F0 */
    usm_report_located stick_limit;                 /* T where F_t = mu0 F_n (3dof) */
    usm_report_located stick_limit_sat;             /* T where F_t = mu0 (pi/2) F_n (3dof) */
    usm_report_located existence_T[REPORT_NMODELS]; /* largest T with a solution */
    usm_report_located stability_T;                 /* T where the 3dof |lambda| reaches 1 */
    usm_report_located existence_m0[REPORT_NMODELS];/* smallest m0 with a solution */

    /* every generated model, in usm_models order */
    usm_report_variant_result variant[USM_NMODELS];

    /* stability maps (f x T) */
    usm_report_map map[REPORT_NMODELS];
    int have_map[REPORT_NMODELS];

    /* sensitivities of the primary solution at the paper's point:
     * have_sens[k] = 0 when usm_sensitivity_compute failed (sens_note says why) */
    usm_sensitivity_result sens[REPORT_NMODELS];
    int have_sens[REPORT_NMODELS];
    char sens_note[REPORT_NMODELS][USM_MSG_LEN];

    double seconds[4]; /* timing: tables, curves, maps, plots */

    usm_report_nonideal nonideal; /* the non-ideal motor (report_nonideal.c) */
    usm_report_squeal squeal;     /* the squeal (report_squeal.c) */
    struct usm_report_paper_fit {  /* the paper's motor identified (report_fit.c) */
        int ok, pair_ok, pair_identifiable, fmax_ok;
        double c_r, c_r_se, c_r_lo, c_r_hi, chi2;   /* c_r fitted to Sec. 5's theta, speed */
        double pair_corr, pair_singular, pair_c_r, pair_I_xx, pair_dir[2]; /* c_r with I_xx */
        double fmax_model, fmax_c_r, fmax_sigmas;  /* the c_r Fig. 9's 36.8 kHz asks for */
        /* the located refit: c_r (and c_r with I_xx) fitted to theta, speed
         * and Fig. 9's speed maximum together */
        int loc_ok, loc_pair_ok, loc_pair_identifiable, loc_dof;
        double loc_c_r, loc_c_r_se, loc_chi2, loc_p, loc_fmax, loc_theta_res, loc_speed_res,
            loc_fmax_res, loc_pair_singular;
        double seconds;
        char note[USM_MSG_LEN];
    } paper_fit;

    struct usm_report_design *design; /* design under scatter (report_design.c); owned */

    struct usm_report_envelope {   /* the operating envelope (report_envelope.c) */
        int ok;                    /* computed (else note says why) */
        struct usm_envelope *e;    /* owned; freed by usm_report_envelope_free */
        int raster;                /* the regions' raster, cells a side */
        double seconds;
        char note[USM_MSG_LEN];
    } envelope;
} usm_report_data;

/* Compute everything but the maps.  USM_OK or an error status with msg. */
int usm_report_compute(usm_report_data *d, char msg[USM_IO_MSG_LEN]);
/* The stability maps.  USM_OK or an error status with msg. */
int usm_report_compute_maps(usm_report_data *d, char msg[USM_IO_MSG_LEN]);
/* Free what usm_report_compute and the maps allocated (the design section's
 * results: usm_report_design_free). */
void usm_report_data_free(usm_report_data *d);
/* The non-ideal motor's curves, tolerable imperfections and orbit
 * (d->nonideal).  A failure of the periodic orbits is reported in
 * d->nonideal.note, not an error of the report; USM_EFAILED (out of memory)
 * with msg. */
int usm_report_compute_nonideal(usm_report_data *d, char msg[USM_IO_MSG_LEN]);

/* The paper's published Sec. 5 values as data: c_r (and c_r, I_xx) fitted
 * to them, set against Fig. 9's maximum (d->paper_fit; report_fit.c).  A
 * failed fit is a note, not an error of the report: USM_OK. */
typedef struct usm_report_paper_fit usm_report_paper_fit;
int usm_report_compute_paper_fit(usm_report_data *d, char msg[USM_IO_MSG_LEN]);
/* Its numbers in report.json ("paper_fit"). */
json_t *usm_report_paper_fit_json(const usm_report_data *d);

/* The squeal past the 4-DOF Neimark-Sacker point along the mode split
 * (d->squeal).  A failure is reported in d->squeal.note, not an error of the
 * report; USM_EFAILED (out of memory) with msg. */
int usm_report_compute_squeal(usm_report_data *d, char msg[USM_IO_MSG_LEN]);
/* Its data files squeal_{spectrum,amplitude,values}.csv (when computed).
 * USM_OK or USM_EFAILED with msg. */
int usm_report_squeal_write_data(const usm_report_data *d, const char *dir,
                                 char msg[USM_IO_MSG_LEN]);
/* Its numbers in report.json ("squeal"; keys: docs/report.md). */
json_t *usm_report_squeal_json(const usm_report_data *d);

/* The 3-DOF operating envelope over f x F0 with start-up from rest
 * (d->envelope; report_envelope.c).  A failure is a note, not an error of
 * the report: USM_OK (USM_EFAILED only when out of memory). */
int usm_report_compute_envelope(usm_report_data *d, char msg[USM_IO_MSG_LEN]);
/* Its data file envelope.csv and script envelope.gp (when computed). */
int usm_report_envelope_write_data(const usm_report_data *d, const char *dir,
                                   char msg[USM_IO_MSG_LEN]);
/* Its values in report.json ("envelope"). */
json_t *usm_report_envelope_json(const usm_report_data *d);
void usm_report_envelope_free(usm_report_data *d);

/* ---- design under scatter (report_design.c) ---------------------------- */

/* The speed-efficiency front over (f, F0) and the robust optimum beside the
 * nominal one on the paper's 3-DOF motor, into d->design (allocated).  A
 * failure of the computation is reported in the section's note, not an
 * error of the report; USM_EFAILED (out of memory) with msg. */
int usm_report_compute_design(usm_report_data *d, char msg[USM_IO_MSG_LEN]);
/* The section's values ("design_robust" of report.json); NULL when out of memory. */
json_t *usm_report_design_json(const usm_report_data *d);
void usm_report_design_free(usm_report_data *d);
/* Seconds the section took (NaN when not computed). */
double usm_report_design_seconds(const usm_report_data *d);

/* Nearest computed multiplier to (re, im) among the non-cyclic and cyclic
 * ones of r (each computed one used once: `used` flags, n entries). */
int usm_report_match_multiplier(const usm_floquet_result *r, double re, double im, int *used);

/* ---- files (usm_report_plot.c) -------------------------------------------------- */

typedef struct usm_report_figure {
    const char *name;    /* file stem: NAME.png, NAME.svg, NAME.gp */
    const char *title;   /* caption */
} usm_report_figure;

enum {
    REPORT_FIG_SPEED_F = 0,
    REPORT_FIG_SPEED_T,
    REPORT_FIG_SPEED_M0,
    REPORT_FIG_MULT_3DOF,
    REPORT_FIG_MULT_4DOF,
    REPORT_FIG_MAP_3DOF,
    REPORT_FIG_MAP_4DOF,
    REPORT_FIG_DATASHEET,  /* speed, power_out, efficiency vs T (the T curves) */
    REPORT_FIG_ELASTICITY, /* elasticities of rotor_speed and max_modulus */
    REPORT_FIG_NONIDEAL,   /* ripple, F_n_min, max |lambda| vs phase error and mode split */
    REPORT_FIG_ORBIT,      /* one periodic orbit: the tilt vector in the housing plane */
    REPORT_FIG_SQUEAL_MOTION, /* the unilateral motor past its last orbit: bifurcation
                                 diagram and audible lines over the mode split */
    REPORT_FIG_SQUEAL,     /* the spectrum past the NS point, the vibration vs mode split */
    REPORT_FIG_ENVELOPE,   /* the operating envelope f x F0: regions, curves, codim-2 point */
    REPORT_NFIGURES
};
extern const usm_report_figure usm_report_figures[REPORT_NFIGURES];

/* The report's own-output marker: written into DIR before any other file,
 * its first line REPORT_MANIFEST_MARKER, then the names of usm_report_files.  A
 * directory holding it has only the report's files under those names (a run
 * interrupted before report.md still leaves it), so the next run replaces them. */
#define REPORT_MANIFEST ".usm-report"
#define REPORT_MANIFEST_MARKER "usm report: files written by `usm report` (the next run replaces them)"

/* The outputs whose elasticities the report charts (usm_design.h indices). */
#define REPORT_NSENS_OUT 2
extern const int usm_report_sens_outputs[REPORT_NSENS_OUT];

/* Parameter indices j of output k with a nonzero elasticity, sorted by
 * decreasing |elasticity| (ties in usm_params order); returns their count
 * (0 when the derivative is undefined).  The parameters the output does not
 * depend on (elasticity exactly 0) are left out. */
int usm_report_elasticity_order(const usm_params *p, const usm_sensitivity_result *r, int k,
                            int idx[USM_NPARAMS]);

/* Largest distance between a published table of nt multipliers (each pair
 * with both members) and the nearest computed ones in r, each used once
 * (INFINITY when one has no partner); skip_first: the first entry is
 * matched but not measured (Table 4's pair, whose modulus the paper
 * prints 1.5 % off). */
double usm_report_table_distance(const usm_report_published_multiplier *t, int nt,
                                 const usm_floquet_result *r, int skip_first);

/* Every file name `usm report` writes into its directory (NULL-terminated). */
extern const char *const usm_report_files[];

/* Write every CSV file and gnuplot script into dir but the squeal section's
 * (usm_report_squeal_write_data).  USM_OK or USM_EFAILED. */
int usm_report_write_data(const usm_report_data *d, const char *dir, char msg[USM_IO_MSG_LEN]);

/* Run gnuplot on the scripts of the first nfigures figures (up to `jobs` at a
 * time), with dir as working directory.  USM_OK, or USM_EFAILED with msg
 * (gnuplot missing or failing; its messages are in dir/gnuplot.log). */
int usm_report_run_gnuplot(const char *dir, int jobs, int nfigures, char msg[USM_IO_MSG_LEN]);

/* The figures whose data exist: the non-ideal motor's (the last three) only
 * when computed, the squeal's (the last) only with the non-ideal orbit's
 * (the figures rendered are a prefix of usm_report_figures). */
int usm_report_figure_count(const usm_report_data *d);

/* ---- report.json, report.md, report.html (usm_report_json.c, data/report/) ----- */

/* The first line of every report.md that usm writes. */
#define REPORT_MARKER "<!-- usm report: written by `usm report`; the next run overwrites this file -->"

/* Every number the report shows, by name (written as report.json; the
 * templates data/report/report.{md,html}.in are rendered from it).
 * plots_ok: the figures were rendered (or not asked for); plot_note: why not. */
json_t *usm_report_json(const usm_report_data *d, int plots_ok, const char *plot_note);

/* report.md (text md) as one self-contained HTML page to out, the figures
 * dir/NAME.svg inlined in place of the images NAME.png.  0 or -1. */
int usm_report_html_write(const char *md, const char *dir, FILE *out);

/* ---- helpers ------------------------------------------------------------------- */

/* dir + "/" + name into buf (size len); 0, or -1 when too long. */
int usm_report_path(char *buf, size_t len, const char *dir, const char *name);

/* Open dir/name for writing through usm_io_create (a temporary beside it;
 * replacing a file or a symlink there, never writing through one); NULL with
 * msg on failure. */
FILE *usm_report_open(usm_io_file *out, const char *dir, const char *name,
                      char msg[USM_IO_MSG_LEN]);
/* Rename the complete file into place; USM_OK, or USM_EFAILED with msg
 * naming dir/name (a write error: the old file is kept). */
int usm_report_close(usm_io_file *out, char msg[USM_IO_MSG_LEN]);

/* Seconds of a monotonic clock. */
double usm_report_now(void);

#endif /* USM_REPORT_INTERNAL_H */
