/* report.h: `usm report`, the paper reproduced in a Markdown report with
 * figures (internal to the usm command).
 *
 *   report_paper.c         the paper's published values, read from data/paper_values.json
 *   report_compute.c       everything the report shows, computed through libusm
 *   report_map.c           the 2-D stability map (threads), also `usm map`
 *   report_plot.c          CSV data, gnuplot scripts, running gnuplot
 *   report_json.c          report.json: every number by name (report.md and
 *                          report.html are rendered from it by templates)
 *   report_cmd.c           options, output directory, the run
 */
#ifndef USM_CLI_REPORT_H
#define USM_CLI_REPORT_H

#include <stdio.h>

#include <jansson.h>

#include "diag.h"
#include "report_map.h"
#include "usm.h"
#include "usm_design.h"
#include "usm_sweep.h"

/* ---- the paper's published values (report_paper.c) ------------------------ */

typedef struct report_published {
    char where[48];    /* where the paper prints it */
    char what[96];     /* the quantity */
    char printed[48];  /* exactly as printed */
    double value;      /* the printed number, in the printed unit */
    char unit[24];     /* the printed unit */
} report_published;

typedef struct report_published_multiplier {
    char label[24];           /* "lambda_1,2" */
    char printed[48];         /* "-0.7101 ± 0.5908i" */
    double re, im;            /* im > 0: the pair re ± im i */
    char modulus_printed[24]; /* the table's "absolute value" column */
    double modulus;
} report_published_multiplier;

typedef struct report_paper {
    report_published theta3, alpha3, beta3;
    report_published speed4, theta4, alpha4, beta4;
    report_published_multiplier table3[4];
    int n3;
    report_published_multiplier table4[6];
    int n4;
    report_published f_max, slip_load, speed_ratio;
} report_paper;

/* Read data/paper_values.json (see data_dir.h).  Called once before anything
 * else of the report; USM_OK, or USM_EFAILED with msg naming the file. */
int report_paper_load(char msg[CLI_MSG_LEN]);
/* The values read by report_paper_load(). */
const report_paper *report_paper_get(void);
#define report_paper_values (*report_paper_get())

/* ---- what the report computes (report_compute.c) -------------------------- */

/* Start times of the t0 study, in periods: 0, 1/4, 1/2, 10, 100, 1000. */
#define REPORT_NT0 6
extern const double report_t0_fraction[REPORT_NT0];
extern const char *const report_t0_label[REPORT_NT0]; /* "0", "T/4", ... */

typedef struct report_model_result {
    const usm_model *model;
    usm_steady_solution sol;                /* primary root, paper's parameters */
    usm_floquet_result fl[REPORT_NT0];      /* at t0 = fraction * period */
    /* twist_integrated variant of the same model (NULL when not generated or
     * without a solution), taken from report_data.variant */
    const usm_model *integrated;
    usm_floquet_result fl_integrated[2];    /* at t0 = 0 and T/2 */
} report_model_result;

/* Every generated model (variant) at the report's parameters, side by side. */
#define REPORT_NVARIANT_T0 3 /* t0 = 0, T/2, 100 T */
typedef struct report_variant_result {
    const usm_model *model;
    int ok;                                  /* a stationary solution exists */
    usm_steady_solution sol;
    usm_floquet_result fl[REPORT_NVARIANT_T0];
    char note[USM_MSG_LEN];                  /* why not ok */
} report_variant_result;

/* A located value (bisection or golden section); ok = 0 when not found in
 * the range searched (text in note). */
typedef struct report_located {
    int ok;
    double value;
    usm_steady_solution sol; /* there (last point with a solution) */
    char note[USM_MSG_LEN];
} report_located;

/* One characteristic curve: a sweep of one parameter, one model. */
typedef struct report_curve {
    const char *over;
    double from, to;
    int points;
    usm_sweep *sweep;       /* owns the points and events */
} report_curve;

enum { REPORT_CURVE_F = 0, REPORT_CURVE_T = 1, REPORT_CURVE_M0 = 2, REPORT_NCURVES = 3 };
enum { REPORT_3DOF = 0, REPORT_4DOF = 1, REPORT_NMODELS = 2 };

typedef struct report_options {
    int quick;    /* coarser grids */
    int threads;  /* >= 1 */
    int plots;    /* run gnuplot */
} report_options;

/* A nearly vanishing preload [N], to show what the contact moment does. */
#define REPORT_SMALL_F0 0.01

typedef struct report_data {
    usm_params params;
    report_options opt;
    report_model_result model[REPORT_NMODELS];

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
    report_curve curve[REPORT_NCURVES][REPORT_NMODELS];

    /* key numbers */
    report_located f_max[REPORT_NMODELS];       /* speed maximum over f */
    report_located f_theta_max;                 /* tilt maximum over f (3dof) */
    report_located f_theta_max_small_F0;        /* the same with F0 = REPORT_SMALL_F0 */
    report_located stick_limit;                 /* T where F_t = mu0 F_n (3dof) */
    report_located stick_limit_sat;             /* T where F_t = mu0 (pi/2) F_n (3dof) */
    report_located existence_T[REPORT_NMODELS]; /* largest T with a solution */
    report_located stability_T;                 /* T where the 3dof |lambda| reaches 1 */
    report_located existence_m0[REPORT_NMODELS];/* smallest m0 with a solution */

    /* every generated model, in usm_models order */
    report_variant_result variant[USM_NMODELS];

    /* stability maps (f x T) */
    report_map map[REPORT_NMODELS];
    int have_map[REPORT_NMODELS];

    /* sensitivities of the primary solution at the paper's point (issue 13):
     * have_sens[k] = 0 when usm_sensitivity_compute failed (sens_note says why) */
    usm_sensitivity_result sens[REPORT_NMODELS];
    int have_sens[REPORT_NMODELS];
    char sens_note[REPORT_NMODELS][USM_MSG_LEN];

    double seconds[4]; /* timing: tables, curves, maps, plots */
} report_data;

/* Compute everything but the maps.  USM_OK or an error status with msg. */
int report_compute(report_data *d, char msg[CLI_MSG_LEN]);
/* The stability maps.  USM_OK or an error status with msg. */
int report_compute_maps(report_data *d, char msg[CLI_MSG_LEN]);
void report_data_free(report_data *d);

/* Nearest computed multiplier to (re, im) among the non-cyclic and cyclic
 * ones of r (each computed one used once: `used` flags, n entries). */
int report_match_multiplier(const usm_floquet_result *r, double re, double im, int *used);

/* ---- files (report_plot.c) -------------------------------------------------- */

typedef struct report_figure {
    const char *name;    /* file stem: NAME.png, NAME.svg, NAME.gp */
    const char *title;   /* caption */
} report_figure;

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
    REPORT_NFIGURES
};
extern const report_figure report_figures[REPORT_NFIGURES];

/* The report's own-output marker: written into DIR before any other file,
 * its first line REPORT_MANIFEST_MARKER, then the names of report_files.  A
 * directory holding it has only the report's files under those names (a run
 * interrupted before report.md still leaves it), so the next run replaces them. */
#define REPORT_MANIFEST ".usm-report"
#define REPORT_MANIFEST_MARKER "usm report: files written by `usm report` (the next run replaces them)"

/* The outputs whose elasticities the report charts (usm_design.h indices). */
#define REPORT_NSENS_OUT 2
extern const int report_sens_outputs[REPORT_NSENS_OUT];

/* Elasticity (p_j / y) dy/dp_j of output k (as `usm sensitivity`): NaN where
 * the derivative is undefined or y = 0. */
double report_elasticity(const usm_params *p, const usm_sensitivity_result *r, int k, int j);
/* Parameter indices j of output k with a nonzero elasticity, sorted by
 * decreasing |elasticity| (ties in usm_params order); returns their count
 * (0 when the derivative is undefined).  The parameters the output does not
 * depend on (elasticity exactly 0) are left out. */
int report_elasticity_order(const usm_params *p, const usm_sensitivity_result *r, int k,
                            int idx[USM_NPARAMS]);

/* Every file name `usm report` writes into its directory (NULL-terminated). */
extern const char *const report_files[];

/* Write every CSV file and gnuplot script into dir.  USM_OK or USM_EFAILED. */
int report_write_data(const report_data *d, const char *dir, char msg[CLI_MSG_LEN]);

/* Run gnuplot on every script (up to `jobs` at a time), with dir as working
 * directory.  USM_OK, or USM_EFAILED with msg (gnuplot missing or failing;
 * its messages are in dir/gnuplot.log). */
int report_run_gnuplot(const char *dir, int jobs, char msg[CLI_MSG_LEN]);

/* ---- report.json, report.md, report.html (report_json.c, data/report/) ----- */

/* The first line of every report.md that usm writes. */
#define REPORT_MARKER "<!-- usm report: written by `usm report`; the next run overwrites this file -->"

/* Every number the report shows, by name (written as report.json; the
 * templates data/report/report.{md,html}.in are rendered from it).
 * plots_ok: the figures were rendered (or not asked for); plot_note: why not. */
json_t *report_json(const report_data *d, int plots_ok, const char *plot_note);

/* report.md (text md) as one self-contained HTML page to out, the figures
 * dir/NAME.svg inlined in place of the images NAME.png.  0 or -1. */
int report_html_write(const char *md, const char *dir, FILE *out);

/* ---- helpers ------------------------------------------------------------------- */

/* dir + "/" + name into buf (size len); 0, or -1 when too long. */
int report_path(char *buf, size_t len, const char *dir, const char *name);

/* Open dir/name for writing; NULL with msg on failure. */
FILE *report_open(const char *dir, const char *name, char msg[CLI_MSG_LEN]);
/* Close f; USM_OK, or USM_EFAILED with msg naming dir/name on a write error. */
int report_close(FILE *f, const char *dir, const char *name, char msg[CLI_MSG_LEN]);

/* Seconds of a monotonic clock. */
double report_now(void);

#endif /* USM_CLI_REPORT_H */
