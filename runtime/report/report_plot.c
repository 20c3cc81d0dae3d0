/* The report's data files (CSV), gnuplot scripts and the gnuplot runs.
 *
 * Every figure NAME has NAME.gp, which reads CSV files in the same directory
 * and writes NAME.png (pngcairo) and NAME.svg (svg): `cd DIR && gnuplot
 * NAME.gp` re-plots it.  The scripts are static files (data/plots/, installed
 * as share/usm/plots/) copied into DIR: they address columns by name and take
 * the values they mark (limits, the operating point) and their axis ranges
 * from the data (usm_report_values.csv), so --set changes the axes too.
 */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "io/csv_out.h"
#include "io/data_dir.h"
#include "io/plot_run.h"
#include "report_internal.h"
#include "io/template.h"


const usm_report_figure usm_report_figures[REPORT_NFIGURES] = {
    {"fig09_speed_frequency", "Rotor speed vs excitation frequency (paper Fig. 9)"},
    {"fig10_speed_load", "Rotor speed vs load torque (paper Fig. 10)"},
    {"fig11_speed_amplitude", "Rotor speed vs excitation amplitude m0 (paper Fig. 11)"},
    {"fig12_multipliers_3dof", "Floquet multipliers, 3-DOF stick model (paper Fig. 12, Table 3)"},
    {"fig14_multipliers_4dof", "Floquet multipliers, 4-DOF slip model (paper Fig. 14, Table 4)"},
    {"map_3dof", "Stability map f x T, 3-DOF stick model"},
    {"map_4dof", "Stability map f x T, 4-DOF slip model"},
    {"datasheet", "Motor datasheet: rotor speed, output power and efficiency vs load torque"},
    {"elasticity", "Elasticities of rotor speed and of the largest Floquet modulus at the paper's point"},
    {"nonideal_curves", "The non-ideal motor: rotor-speed ripple, smallest contact force, largest |λ|, mean rotor speed and largest impact velocity vs phase error and mode split; past contact loss (dashed) the orbits with separation"},
    {"nonideal_orbit", "One periodic orbit of the non-ideal motor: the tilt vector in the housing plane over a period, the ideal circle beside it"},
    {"squeal_motion", "What the motor does past its last periodic orbit (4-DOF, unilateral contact): the rotor speed and the tilt once a period over the mode split (bifurcation diagram), and the audible lines of the stator rim's axial velocity coloured by level"},
    {"squeal", "The bilateral model's squeal: the spectrum of the contact force just past the 4-DOF Neimark-Sacker point, and the parasitic vibration against the mode split"},
    {"envelope", "The operating envelope of the 3-DOF motor over f x F0, started from rest: the regions by operating class, the boundaries continued as curves, their codimension-two point"},
};

const char *const usm_report_files[] = {
    "report.md", "report.json", "report.html", "report_values.csv",
    "gnuplot.log",
    "fig09_speed_frequency.gp", "fig09_speed_frequency.png", "fig09_speed_frequency.svg",
    "fig09_speed_frequency_3dof.csv", "fig09_speed_frequency_4dof.csv",
    "fig10_speed_load.gp", "fig10_speed_load.png", "fig10_speed_load.svg",
    "fig10_speed_load_3dof.csv", "fig10_speed_load_4dof.csv",
    "fig11_speed_amplitude.gp", "fig11_speed_amplitude.png", "fig11_speed_amplitude.svg",
    "fig11_speed_amplitude_3dof.csv", "fig11_speed_amplitude_4dof.csv",
    "fig12_multipliers_3dof.gp", "fig12_multipliers_3dof.png", "fig12_multipliers_3dof.svg",
    "fig12_multipliers_3dof.csv",
    "fig14_multipliers_4dof.gp", "fig14_multipliers_4dof.png", "fig14_multipliers_4dof.svg",
    "fig14_multipliers_4dof.csv",
    "map_3dof.gp", "map_3dof.png", "map_3dof.svg", "map_3dof.csv",
    "map_3dof_existence.csv", "map_3dof_stability.csv", "map_3dof_stick.csv",
    "map_4dof.gp", "map_4dof.png", "map_4dof.svg", "map_4dof.csv",
    "map_4dof_existence.csv", "map_4dof_stability.csv", "map_4dof_stick.csv",
    "datasheet.gp", "datasheet.png", "datasheet.svg", "datasheet_3dof.csv", "datasheet_4dof.csv",
    "elasticity.gp", "elasticity.png", "elasticity.svg",
    "elasticity_rotor_speed_3dof.csv", "elasticity_rotor_speed_4dof.csv",
    "elasticity_max_modulus_3dof.csv", "elasticity_max_modulus_4dof.csv",
    "nonideal_curves.gp", "nonideal_curves.png", "nonideal_curves.svg",
    "nonideal_curves_phase_error_3dof.csv", "nonideal_curves_phase_error_4dof.csv",
    "nonideal_curves_mode_split_3dof.csv", "nonideal_curves_mode_split_4dof.csv",
    "nonideal_curves_values.csv",
    "nonideal_orbit.gp", "nonideal_orbit.png", "nonideal_orbit.svg", "nonideal_orbit.csv",
    "nonideal_orbit_circle.csv",
    "squeal_motion.gp", "squeal_motion.png", "squeal_motion.svg", "squeal_motion.csv",
    "squeal_motion_points.csv",
    "squeal.gp", "squeal.png", "squeal.svg", "squeal_spectrum.csv", "squeal_amplitude.csv",
    "squeal_values.csv",
    "envelope.gp", "envelope.png", "envelope.svg", "envelope.csv",
    NULL,
};

static const char *const model_tag[REPORT_NMODELS] = {"3dof", "4dof"};

/* ---- helpers ------------------------------------------------------------------ */

int usm_report_path(char *buf, size_t len, const char *dir, const char *name)
{
    int n = snprintf(buf, len, "%s/%s", dir, name);
    return n < 0 || (size_t)n >= len ? -1 : 0;
}

FILE *usm_report_open(usm_io_file *out, const char *dir, const char *name,
                      char msg[USM_IO_MSG_LEN])
{
    char path[4096];
    int status;
    if (usm_report_path(path, sizeof path, dir, name) != 0) {
        usm_io_msg(msg, "--out %s: path too long", dir);
        return NULL;
    }
    /* the report replaces its own files (check_dir guards the directory):
     * force, so a symlink planted there is replaced, never written through */
    return usm_io_create(out, path, 1, msg, &status);
}

int usm_report_close(usm_io_file *out, char msg[USM_IO_MSG_LEN])
{
    return usm_io_commit(out, msg) == USM_OK ? USM_OK : USM_EFAILED;
}

/* ---- CSV (csv_out.h) ------------------------------------------------------------- */

static void write_curve_csv(FILE *f, const usm_report_curve *cv)
{
    const size_t n = cv->sweep ? usm_sweep_count(cv->sweep) : 0;
    const usm_param_info *over = usm_params_find(cv->over);
    const usm_csv_column cols[] = {
        {cv->over, over ? over->unit : "1"}, {"converged", NULL}, {"rotor_speed", "1/s"},
        {"speed", "1/s"}, {"theta", "rad"}, {"alpha", "rad"}, {"beta", "rad"}, {"F_n", "N"},
        {"F_t", "N"}, {"mu_used", "1"}, {"stick_admissible", NULL}, {"v_rel", "m/s"},
        {"max_modulus", "1"}, {"stable", NULL}, {"valid", NULL}, {"invalid_reason", NULL}};
    usm_csv_header(f, cols, (int)(sizeof cols / sizeof cols[0]));
    for (size_t i = 0; i < n; ++i) {
        const usm_sweep_point *pt = usm_sweep_point_at(cv->sweep, i);
        const usm_steady_solution *s = &pt->sol;
        const int ok = pt->converged, fl = ok && pt->has_floquet;
        usm_csv_num(f, 1, pt->value);
        usm_csv_bool(f, 0, ok);
        usm_csv_num(f, 0, ok ? s->rotor_speed : NAN);
        usm_csv_num(f, 0, ok ? -s->rotor_speed : NAN);
        usm_csv_num(f, 0, ok ? s->theta : NAN);
        usm_csv_num(f, 0, ok ? s->alpha : NAN);
        usm_csv_num(f, 0, ok ? s->beta : NAN);
        usm_csv_num(f, 0, ok ? s->F_n : NAN);
        usm_csv_num(f, 0, ok ? s->F_t : NAN);
        usm_csv_num(f, 0, ok ? s->mu_used : NAN);
        usm_csv_bool(f, 0, ok && s->stick_admissible);
        usm_csv_num(f, 0, ok ? s->v_rel : NAN);
        usm_csv_num(f, 0, fl ? pt->floquet.max_modulus : NAN);
        usm_csv_bool(f, 0, fl && pt->floquet.stable);
        usm_csv_validity(f, ok, s->validity);
        fputc('\n', f);
    }
}

/* The datasheet: the load curve (sweep over T) with power and efficiency. */
static void write_datasheet_csv(FILE *f, const usm_report_curve *cv)
{
    const size_t n = cv->sweep ? usm_sweep_count(cv->sweep) : 0;
    static const usm_csv_column cols[] = {
        {"T", "N m"},          {"converged", NULL},    {"speed", "1/s"},
        {"power_in", "W"},     {"power_out", "W"},     {"power_damping", "W"},
        {"power_slip", "W"},   {"efficiency", "1"},    {"stick_admissible", NULL},
        {"stable", NULL},      {"valid", NULL},        {"invalid_reason", NULL}};
    usm_csv_header(f, cols, (int)(sizeof cols / sizeof cols[0]));
    for (size_t i = 0; i < n; ++i) {
        const usm_sweep_point *pt = usm_sweep_point_at(cv->sweep, i);
        const usm_steady_solution *s = &pt->sol;
        const int ok = pt->converged;
        usm_csv_num(f, 1, pt->value);
        usm_csv_bool(f, 0, ok);
        usm_csv_num(f, 0, ok ? -s->rotor_speed : NAN);
        usm_csv_num(f, 0, ok ? s->power_in : NAN);
        usm_csv_num(f, 0, ok ? s->power_out : NAN);
        usm_csv_num(f, 0, ok ? s->power_damping : NAN);
        usm_csv_num(f, 0, ok ? s->power_slip : NAN);
        usm_csv_num(f, 0, ok ? s->efficiency : NAN);
        usm_csv_bool(f, 0, ok && s->stick_admissible);
        usm_csv_bool(f, 0, ok && pt->has_floquet && pt->floquet.stable);
        usm_csv_validity(f, ok, s->validity);
        fputc('\n', f);
    }
}

/* The nonzero elasticities of one output, by decreasing magnitude. */
static void write_elasticity_csv(FILE *f, const usm_report_data *d, int k, int out)
{
    static const usm_csv_column cols[] = {
        {"rank", NULL}, {"parameter", NULL}, {"elasticity", "1"}, {"abs_elasticity", "1"}};
    int idx[USM_NPARAMS];
    const int n = d->have_sens[k] ? usm_report_elasticity_order(&d->params, &d->sens[k], out, idx) : 0;
    usm_csv_header(f, cols, 4);
    for (int i = 0; i < n; ++i) {
        const double e = usm_sensitivity_elasticity(&d->params, &d->sens[k], out, idx[i]);
        usm_csv_num(f, 1, i + 1);
        usm_csv_text(f, 0, usm_param_table[idx[i]].name);
        usm_csv_num(f, 0, e);
        usm_csv_num(f, 0, fabs(e));
        fputc('\n', f);
    }
}

static void multiplier_row(FILE *f, int series, const char *label, double re, double im,
                           double modulus, int cyclic)
{
    usm_csv_num(f, 1, series);
    usm_csv_text(f, 0, label);
    usm_csv_num(f, 0, re);
    usm_csv_num(f, 0, im);
    usm_csv_num(f, 0, modulus);
    usm_csv_bool(f, 0, cyclic);
    fputc('\n', f);
}

/* series: 0 .. REPORT_NT0 - 1 computed at the start times usm_report_t0_label,
 * 8 the twist_integrated variant at t0 = 0 and T/2, 9 the paper's table. */
static void write_multiplier_csv(FILE *f, const usm_report_model_result *r,
                                 const usm_report_published_multiplier *table, int ntable)
{
    static const usm_csv_column cols[] = {{"series", NULL}, {"label", NULL}, {"re", "1"},
                                          {"im", "1"},     {"modulus", "1"}, {"cyclic", NULL}};
    char label[96];
    usm_csv_header(f, cols, 6);
    for (int i = 0; i < REPORT_NT0 + 2; ++i) {
        const usm_floquet_result *fl = i < REPORT_NT0 ? &r->fl[i] : &r->fl_integrated[i - REPORT_NT0];
        if (i >= REPORT_NT0 && !r->integrated)
            break;
        if (i < REPORT_NT0)
            snprintf(label, sizeof label, "computed t0 = %s", usm_report_t0_label[i]);
        else
            snprintf(label, sizeof label, "twist_integrated t0 = %s", i > REPORT_NT0 ? "T/2" : "0");
        for (int k = 0; k < fl->n; ++k)
            multiplier_row(f, i < REPORT_NT0 ? i : 8, label, fl->re[k], fl->im[k],
                           hypot(fl->re[k], fl->im[k]), fl->cyclic[k]);
    }
    for (int k = 0; k < ntable; ++k)
        for (int sgn = 1; sgn >= (table[k].im > 0 ? -1 : 1); sgn -= 2) {
            snprintf(label, sizeof label, "paper %.60s", table[k].label);
            multiplier_row(f, 9, label, table[k].re, sgn * table[k].im, table[k].modulus, 0);
        }
}

/* The values the figures mark (limits, the operating point), one row. */
static void write_values_csv(FILE *f, const usm_report_data *d)
{
    const usm_report_located *loc[] = {&d->stick_limit, &d->stick_limit_sat, &d->existence_T[0],
                                   &d->existence_T[1], &d->stability_T, &d->f_max[0],
                                   &d->f_max[1], &d->existence_m0[0], &d->existence_m0[1]};
    static const usm_csv_column cols[] = {
        {"stick_limit", "N m"}, {"stick_limit_sat", "N m"}, {"existence_T_3dof", "N m"},
        {"existence_T_4dof", "N m"}, {"stability_T", "N m"}, {"f_max_3dof", "Hz"},
        {"f_max_4dof", "Hz"}, {"existence_m0_3dof", "N m"}, {"existence_m0_4dof", "N m"},
        {"slip_load_paper", "N m"}, {"f_max_paper", "Hz"}, {"m0", "N m"}, {"f", "Hz"},
        {"T", "N m"}, {"speed_3dof", "1/s"}, {"map_3dof_existence", "1"},
        {"map_3dof_stability", "1"}, {"map_3dof_stick", "1"}, {"map_4dof_existence", "1"},
        {"map_4dof_stability", "1"}, {"map_4dof_stick", "1"}};
    const int nloc = (int)(sizeof loc / sizeof loc[0]);
    usm_csv_header(f, cols, (int)(sizeof cols / sizeof cols[0]));
    for (int k = 0; k < nloc; ++k)
        usm_csv_num(f, k == 0, loc[k]->ok ? loc[k]->value : NAN);
    usm_csv_num(f, 0, d->paper.slip_load.value);
    usm_csv_num(f, 0, d->paper.f_max.value);
    usm_csv_num(f, 0, d->params.m0);
    usm_csv_num(f, 0, d->params.f);
    usm_csv_num(f, 0, d->params.T);
    usm_csv_num(f, 0, -d->model[REPORT_3DOF].sol.rotor_speed);
    for (int k = 0; k < REPORT_NMODELS; ++k)
        for (int b = 0; b < USM_REPORT_NBOUNDARY; ++b)
            usm_csv_num(f, 0, d->have_map[k] ? (double)d->map[k].nbnd[b] : 0);
    fputc('\n', f);
}

/* ---- the non-ideal motor -------------------------------------------------------- */

#define PI_ 3.14159265358979323846264338327950

static double imp_display(int j, double v)
{
    return j == REPORT_IMP_PHASE ? v * 180.0 / PI_ : v * 100.0;
}

/* One curve: the imperfection (SI and as printed) and the orbit's numbers. */
static void write_nonideal_curve_csv(FILE *f, const usm_report_nonideal_curve *cv, int j)
{
    const usm_csv_column cols[] = {
        {cv->param, j == REPORT_IMP_PHASE ? "rad" : "1"},
        {j == REPORT_IMP_PHASE ? "phase_error_deg" : "mode_split_percent",
         j == REPORT_IMP_PHASE ? "deg" : "%"},
        {"converged", NULL}, {"rotor_speed_mean", "1/s"}, {"rotor_speed_ripple", "1/s"},
        {"F_n_min", "N"}, {"F_n_max", "N"}, {"max_modulus", "1"}, {"theta_harmonic_2", "rad"},
        {"contact_open", NULL}, {"valid", NULL}, {"invalid_reason", NULL},
        {"separating", NULL}, {"rotor_speed_mean_separating", "1/s"},
        {"rotor_speed_ripple_separating", "1/s"}, {"max_modulus_separating", "1"},
        {"separation_fraction", "1"}, {"impact_velocity_max", "m/s"}};
    usm_csv_header(f, cols, (int)(sizeof cols / sizeof cols[0]));
    for (int q = 0; q < cv->points; ++q) {
        const usm_report_nonideal_point *pt = &cv->pt[q];
        usm_csv_num(f, 1, pt->value);
        usm_csv_num(f, 0, imp_display(j, pt->value));
        usm_csv_bool(f, 0, pt->converged);
        usm_csv_num(f, 0, pt->speed_mean);
        usm_csv_num(f, 0, pt->ripple);
        usm_csv_num(f, 0, pt->F_n_min);
        usm_csv_num(f, 0, pt->F_n_max);
        usm_csv_num(f, 0, pt->max_modulus);
        usm_csv_num(f, 0, pt->theta_h2);
        usm_csv_bool(f, 0, pt->converged && pt->F_n_min < 0);
        usm_csv_validity(f, pt->converged, pt->validity);
        usm_csv_bool(f, 0, pt->separating);
        usm_csv_num(f, 0, pt->sep_speed_mean);
        usm_csv_num(f, 0, pt->sep_ripple);
        usm_csv_num(f, 0, pt->sep_max_modulus);
        usm_csv_num(f, 0, pt->sep_fraction);
        usm_csv_num(f, 0, pt->impact_velocity_max);
        fputc('\n', f);
    }
}

/* The located values the curves' figure marks, one row (empty: not in the
 * range): {contact,stability,tolerable}_{phase_error,mode_split}_{3dof,4dof}. */
static void write_nonideal_values_csv(FILE *f, const usm_report_nonideal *ni)
{
    static const char *const what[3] = {"contact", "stability", "tolerable"};
    static const char *const imp[REPORT_NIMP] = {"phase_error", "mode_split"};
    char names[3 * REPORT_NIMP * REPORT_NMODELS][48];
    usm_csv_column cols[3 * REPORT_NIMP * REPORT_NMODELS];
    int n = 0;
    for (int w = 0; w < 3; ++w)
        for (int j = 0; j < REPORT_NIMP; ++j)
            for (int k = 0; k < REPORT_NMODELS; ++k, ++n) {
                snprintf(names[n], sizeof names[n], "%s_%s_%s", what[w], imp[j], model_tag[k]);
                cols[n] = (usm_csv_column){names[n], j == REPORT_IMP_PHASE ? "deg" : "%"};
            }
    usm_csv_header(f, cols, n);
    n = 0;
    for (int w = 0; w < 3; ++w)
        for (int j = 0; j < REPORT_NIMP; ++j)
            for (int k = 0; k < REPORT_NMODELS; ++k, ++n) {
                const usm_report_nonideal_curve *cv = &ni->curve[k][j];
                const int found = w == 0 ? cv->contact.found
                                  : w == 1 ? cv->stability.found : cv->tolerable_found;
                const double v = w == 0 ? cv->contact.value
                                 : w == 1 ? cv->stability.value : cv->tolerable;
                usm_csv_num(f, n == 0, ni->ok && found ? imp_display(j, v) : NAN);
            }
    fputc('\n', f);
}

/* The tilt vector rho = theta (cos phi, sin phi) in the housing plane over
 * one period (the samples and, closing the curve, the state at t0 + T, which
 * is the first sample's with phi advanced by 2 pi), its tilt relative to the
 * ideal motor's. */
/* valid, invalid_reason per sample: the contact closed and, the 3-DOF model
 * being a stick model, |F_t| <= mu0 F_n at that instant. */
static void write_orbit_csv(FILE *f, const usm_report_nonideal *ni, double mu0)
{
    static const usm_csv_column cols[] = {
        {"t", "s"}, {"t_over_T", "1"}, {"phi", "rad"}, {"theta", "rad"}, {"rho_X", "rad"},
        {"rho_Y", "rad"}, {"angle", "deg"}, {"radial", "%"}, {"F_n", "N"},
        {"valid", NULL}, {"invalid_reason", NULL}};
    const int nx = ni->orbit_nx;
    const double th0 = ni->theta_ideal[REPORT_3DOF];
    usm_csv_header(f, cols, (int)(sizeof cols / sizeof cols[0]));
    if (!ni->ok || !ni->orbit_ok)
        return;
    const double period = ni->orbit_period;
    for (int q = 0; q <= USM_PERIODIC_SAMPLES; ++q) {
        const double *row = ni->orbit[q % USM_PERIODIC_SAMPLES];
        const double t = q < USM_PERIODIC_SAMPLES ? row[0] : row[0] + period;
        const double phi = row[1 + ni->orbit_x_phi] + (q < USM_PERIODIC_SAMPLES ? 0.0 : 2 * PI_);
        const double th = row[1 + ni->orbit_x_theta];
        double ang = fmod(phi * 180.0 / PI_, 360.0);
        if (ang < 0)
            ang += 360.0;
        usm_csv_num(f, 1, t);
        usm_csv_num(f, 0, (t - ni->orbit[0][0]) / period);
        usm_csv_num(f, 0, phi);
        usm_csv_num(f, 0, th);
        usm_csv_num(f, 0, th * cos(phi));
        usm_csv_num(f, 0, th * sin(phi));
        usm_csv_num(f, 0, ang);
        usm_csv_num(f, 0, (th / th0 - 1) * 100);
        usm_csv_num(f, 0, row[1 + nx]);
        usm_csv_validity(f, 1, !(row[1 + nx] > 0)                       ? USM_INVALID_CONTACT_OPEN
                               : fabs(row[2 + nx]) > mu0 * row[1 + nx] ? USM_INVALID_STICK
                                                                       : USM_VALID);
        fputc('\n', f);
    }
}

/* The ideal motor's path: the circle of radius theta (the stationary tilt). */
static void write_circle_csv(FILE *f, const usm_report_nonideal *ni)
{
    static const usm_csv_column cols[] = {{"angle", "deg"}, {"rho_X", "rad"}, {"rho_Y", "rad"},
                                          {"radius", "rad"}};
    const double th0 = ni->theta_ideal[REPORT_3DOF];
    usm_csv_header(f, cols, 4);
    for (int q = 0; q <= 360; ++q) {
        const double a = q * PI_ / 180.0;
        usm_csv_num(f, 1, q);
        usm_csv_num(f, 0, th0 * cos(a));
        usm_csv_num(f, 0, th0 * sin(a));
        usm_csv_num(f, 0, th0);
        fputc('\n', f);
    }
}

/* ---- writing everything ------------------------------------------------------- */

/* Copy the static script data/plots/NAME.gp into dir. */
static int copy_script(const char *dir, const char *name, char msg[USM_IO_MSG_LEN])
{
    char src[4096], file[160];
    char *text;
    usm_io_file out;
    FILE *f;
    snprintf(file, sizeof file, "plots/%s.gp", name);
    if (usm_data_path(file, src, sizeof src) != 0) {
        usm_io_msg(msg, "%s: the report's gnuplot script is not installed (set USM_DATA_DIR)", src);
        return USM_EFAILED;
    }
    if (!(text = usm_template_read(src, msg)))
        return USM_EFAILED;
    snprintf(file, sizeof file, "%s.gp", name);
    if (!(f = usm_report_open(&out, dir, file, msg))) {
        free(text);
        return USM_EFAILED;
    }
    fputs(text, f);
    free(text);
    return usm_report_close(&out, msg);
}

typedef enum {
    DATA_CURVE, DATA_MULTIPLIERS, DATA_VALUES, DATA_MAP, DATA_BOUNDARY, DATA_DATASHEET,
    DATA_ELASTICITY, DATA_NONIDEAL, DATA_NONIDEAL_VALUES, DATA_ORBIT, DATA_CIRCLE
} data_kind;

static int write_data_file(const usm_report_data *d, const char *dir, const char *name,
                           data_kind kind, int k, int c, char msg[USM_IO_MSG_LEN])
{
    const usm_report_paper *pv = &d->paper;
    usm_io_file out;
    FILE *f = usm_report_open(&out, dir, name, msg);
    if (!f)
        return USM_EFAILED;
    switch (kind) {
    case DATA_CURVE: write_curve_csv(f, &d->curve[c][k]); break;
    case DATA_MULTIPLIERS:
        write_multiplier_csv(f, &d->model[k], k == REPORT_3DOF ? pv->table3 : pv->table4,
                             k == REPORT_3DOF ? pv->n3 : pv->n4);
        break;
    case DATA_VALUES: write_values_csv(f, d); break;
    case DATA_MAP: usm_report_map_write_csv(&d->map[k], f); break;
    case DATA_BOUNDARY: usm_report_map_write_boundary_csv(&d->map[k], c, f); break;
    case DATA_DATASHEET: write_datasheet_csv(f, &d->curve[REPORT_CURVE_T][k]); break;
    case DATA_ELASTICITY: write_elasticity_csv(f, d, k, c); break;
    case DATA_NONIDEAL: write_nonideal_curve_csv(f, &d->nonideal.curve[k][c], c); break;
    case DATA_NONIDEAL_VALUES: write_nonideal_values_csv(f, &d->nonideal); break;
    case DATA_ORBIT: write_orbit_csv(f, &d->nonideal, d->params.mu0); break;
    case DATA_CIRCLE: write_circle_csv(f, &d->nonideal); break;
    }
    return usm_report_close(&out, msg);
}

int usm_report_write_data(const usm_report_data *d, const char *dir, char msg[USM_IO_MSG_LEN])
{
    static const int curve_fig[REPORT_NCURVES] = {REPORT_FIG_SPEED_F, REPORT_FIG_SPEED_T,
                                                  REPORT_FIG_SPEED_M0};
    char name[160];
    int st = write_data_file(d, dir, "report_values.csv", DATA_VALUES, 0, 0, msg);
    for (int k = 0; k < REPORT_NMODELS && st == USM_OK; ++k) {
        const int mult = k == REPORT_3DOF ? REPORT_FIG_MULT_3DOF : REPORT_FIG_MULT_4DOF;
        const int map = k == REPORT_3DOF ? REPORT_FIG_MAP_3DOF : REPORT_FIG_MAP_4DOF;
        for (int c = 0; c < REPORT_NCURVES && st == USM_OK; ++c) {
            snprintf(name, sizeof name, "%s_%s.csv", usm_report_figures[curve_fig[c]].name,
                     model_tag[k]);
            st = write_data_file(d, dir, name, DATA_CURVE, k, c, msg);
        }
        snprintf(name, sizeof name, "%s.csv", usm_report_figures[mult].name);
        if (st == USM_OK)
            st = write_data_file(d, dir, name, DATA_MULTIPLIERS, k, 0, msg);
        snprintf(name, sizeof name, "%s_%s.csv", usm_report_figures[REPORT_FIG_DATASHEET].name,
                 model_tag[k]);
        if (st == USM_OK)
            st = write_data_file(d, dir, name, DATA_DATASHEET, k, 0, msg);
        for (int o = 0; o < REPORT_NSENS_OUT && st == USM_OK; ++o) {
            const int out = usm_report_sens_outputs[o];
            snprintf(name, sizeof name, "%s_%s_%s.csv", usm_report_figures[REPORT_FIG_ELASTICITY].name,
                     usm_sensitivity_output_name(out), model_tag[k]);
            st = write_data_file(d, dir, name, DATA_ELASTICITY, k, out, msg);
        }
        if (!d->have_map[k])
            continue;
        snprintf(name, sizeof name, "%s.csv", usm_report_figures[map].name);
        if (st == USM_OK)
            st = write_data_file(d, dir, name, DATA_MAP, k, 0, msg);
        for (int b = 0; b < USM_REPORT_NBOUNDARY && st == USM_OK; ++b) {
            snprintf(name, sizeof name, "%s_%s.csv", usm_report_figures[map].name,
                     usm_report_boundary_name(b));
            st = write_data_file(d, dir, name, DATA_BOUNDARY, k, b, msg);
        }
    }
    for (int k = 0; k < REPORT_NMODELS && st == USM_OK; ++k)
        for (int j = 0; j < REPORT_NIMP && st == USM_OK; ++j) {
            snprintf(name, sizeof name, "nonideal_curves_%s_%s.csv",
                     j == REPORT_IMP_PHASE ? "phase_error" : "mode_split", model_tag[k]);
            st = d->nonideal.ok ? write_data_file(d, dir, name, DATA_NONIDEAL, k, j, msg) : st;
        }
    if (st == USM_OK && d->nonideal.ok)
        st = write_data_file(d, dir, "nonideal_curves_values.csv", DATA_NONIDEAL_VALUES, 0, 0, msg);
    if (st == USM_OK && d->nonideal.ok && d->nonideal.orbit_ok)
        st = write_data_file(d, dir, "nonideal_orbit.csv", DATA_ORBIT, 0, 0, msg);
    if (st == USM_OK && d->nonideal.ok && d->nonideal.orbit_ok)
        st = write_data_file(d, dir, "nonideal_orbit_circle.csv", DATA_CIRCLE, 0, 0, msg);
    for (int i = 0; i < REPORT_NFIGURES && st == USM_OK; ++i)
        if (i != REPORT_FIG_ENVELOPE) /* its script has a header: report_envelope.c */
            st = copy_script(dir, usm_report_figures[i].name, msg);
    return st;
}

/* ---- running gnuplot ------------------------------------------------------------ */

int usm_report_run_gnuplot(const char *dir, int jobs, int nfigures, char msg[USM_IO_MSG_LEN])
{
    const char *stems[REPORT_NFIGURES];
    char path[4096];
    if (nfigures < 1 || nfigures > REPORT_NFIGURES)
        nfigures = REPORT_NFIGURES;
    for (int i = 0; i < nfigures; ++i)
        stems[i] = usm_report_figures[i].name;
    if (usm_report_path(path, sizeof path, dir, "gnuplot.log") != 0) {
        usm_io_msg(msg, "--out %s: path too long", dir);
        return USM_EFAILED;
    }
    return usm_gnuplot_run(dir, stems, nfigures, jobs, path, msg);
}
