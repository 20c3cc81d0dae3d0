/* The report's data files (CSV), gnuplot scripts and the gnuplot runs.
 *
 * Every figure NAME has NAME.gp, which reads CSV files in the same directory
 * and writes NAME.png (pngcairo) and NAME.svg (svg): `cd DIR && gnuplot
 * NAME.gp` re-plots it.  The scripts are written by this file with the
 * computed key numbers (lines marking limits) filled in.
 */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include "report.h"


const report_figure report_figures[REPORT_NFIGURES] = {
    {"fig09_speed_frequency", "Rotor speed vs excitation frequency (paper Fig. 9)"},
    {"fig10_speed_load", "Rotor speed vs load torque (paper Fig. 10)"},
    {"fig11_speed_amplitude", "Rotor speed vs excitation amplitude m0 (paper Fig. 11)"},
    {"fig12_multipliers_3dof", "Floquet multipliers, 3-DOF stick model (paper Fig. 12, Table 3)"},
    {"fig14_multipliers_4dof", "Floquet multipliers, 4-DOF slip model (paper Fig. 14, Table 4)"},
    {"map_3dof", "Stability map f x T, 3-DOF stick model"},
    {"map_4dof", "Stability map f x T, 4-DOF slip model"},
};

const char *const report_files[] = {
    "report.md", "report.json", "report.html",
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
    NULL,
};

static const char *const model_tag[REPORT_NMODELS] = {"3dof", "4dof"};
static const char *const model_title[REPORT_NMODELS] = {"3-DOF (stick)", "4-DOF (slip)"};
static const char *const model_color[REPORT_NMODELS] = {"#1f5fa8", "#c0392b"};

/* ---- helpers ------------------------------------------------------------------ */

int report_path(char *buf, size_t len, const char *dir, const char *name)
{
    int n = snprintf(buf, len, "%s/%s", dir, name);
    return n < 0 || (size_t)n >= len ? -1 : 0;
}

FILE *report_open(const char *dir, const char *name, char msg[CLI_MSG_LEN])
{
    char path[4096];
    FILE *f;
    if (report_path(path, sizeof path, dir, name) != 0) {
        cli_msg(msg, "--out %s: path too long", dir);
        return NULL;
    }
    if (!(f = fopen(path, "w")))
        cli_msg(msg, "%s: %s", path, strerror(errno));
    return f;
}

int report_close(FILE *f, const char *dir, const char *name, char msg[CLI_MSG_LEN])
{
    int bad = ferror(f);
    if (fclose(f) != 0 || bad) {
        cli_msg(msg, "%s/%s: write error", dir, name);
        return USM_EFAILED;
    }
    return USM_OK;
}

static void num(FILE *f, double v)
{
    if (isfinite(v))
        fprintf(f, "%.10g", v);
    else
        fputs("nan", f);
}

/* ---- CSV ------------------------------------------------------------------------ */

static void write_curve_csv(FILE *f, const report_curve *cv)
{
    const size_t n = cv->sweep ? usm_sweep_count(cv->sweep) : 0;
    fprintf(f, "%s,converged,rotor_speed,speed,theta,alpha,beta,F_n,F_t,mu_used,"
               "stick_admissible,v_rel,max_modulus,stable\n",
            cv->over);
    for (size_t i = 0; i < n; ++i) {
        const usm_sweep_point *pt = usm_sweep_point_at(cv->sweep, i);
        const usm_steady_solution *s = &pt->sol;
        const int ok = pt->converged;
        const int fl = ok && pt->has_floquet;
        num(f, pt->value);
        fprintf(f, ",%d,", ok);
        num(f, ok ? s->rotor_speed : NAN);
        fputc(',', f);
        num(f, ok ? -s->rotor_speed : NAN);
        fputc(',', f);
        num(f, ok ? s->theta : NAN);
        fputc(',', f);
        num(f, ok ? s->alpha : NAN);
        fputc(',', f);
        num(f, ok ? s->beta : NAN);
        fputc(',', f);
        num(f, ok ? s->F_n : NAN);
        fputc(',', f);
        num(f, ok ? s->F_t : NAN);
        fputc(',', f);
        num(f, ok ? s->mu_used : NAN);
        fprintf(f, ",%d,", ok ? s->stick_admissible : 0);
        num(f, ok ? s->v_rel : NAN);
        fputc(',', f);
        num(f, fl ? pt->floquet.max_modulus : NAN);
        fprintf(f, ",%d\n", fl ? pt->floquet.stable : 0);
    }
}

/* series: 0 .. REPORT_NT0 - 1 computed at the start times report_t0_label,
 * 8 the twist_integrated variant at t0 = 0 and T/2, 9 the paper's table.
 * The label is quoted (it contains commas). */
static void write_multiplier_csv(FILE *f, const report_model_result *r,
                                 const report_published_multiplier *table, int ntable)
{
    fputs("series,label,re,im,modulus,cyclic\n", f);
    for (int i = 0; i < REPORT_NT0; ++i)
        for (int k = 0; k < r->fl[i].n; ++k) {
            fprintf(f, "%d,\"computed t0 = %s\",", i, report_t0_label[i]);
            num(f, r->fl[i].re[k]);
            fputc(',', f);
            num(f, r->fl[i].im[k]);
            fputc(',', f);
            num(f, hypot(r->fl[i].re[k], r->fl[i].im[k]));
            fprintf(f, ",%d\n", r->fl[i].cyclic[k]);
        }
    for (int i = 0; r->integrated && i < 2; ++i)
        for (int k = 0; k < r->fl_integrated[i].n; ++k) {
            fprintf(f, "8,\"twist_integrated t0 = %s\",", i ? "T/2" : "0");
            num(f, r->fl_integrated[i].re[k]);
            fputc(',', f);
            num(f, r->fl_integrated[i].im[k]);
            fputc(',', f);
            num(f, hypot(r->fl_integrated[i].re[k], r->fl_integrated[i].im[k]));
            fprintf(f, ",%d\n", r->fl_integrated[i].cyclic[k]);
        }
    for (int k = 0; k < ntable; ++k)
        for (int sgn = 1; sgn >= (table[k].im > 0 ? -1 : 1); sgn -= 2) {
            fprintf(f, "9,\"paper %s\",", table[k].label);
            num(f, table[k].re);
            fputc(',', f);
            num(f, sgn * table[k].im);
            fputc(',', f);
            num(f, table[k].modulus);
            fputs(",0\n", f);
        }
}

/* ---- gnuplot scripts ----------------------------------------------------------- */

static void gp_head(FILE *f, const char *name, const char *title)
{
    fprintf(f,
            "# %s.gp: written by `usm report`.  Re-plot: cd into this directory and run\n"
            "#   gnuplot %s.gp\n"
            "# It reads the CSV files named below and writes %s.png and %s.svg.\n"
            "reset session\n"
            "set datafile separator \",\"\n"
            "set encoding utf8\n"
            "set title \"%s\"\n"
            "set grid lc rgb \"#dddddd\"\n",
            name, name, name, name, title);
}

/* Start the loop over the two output formats. */
static void gp_formats_begin(FILE *f, const char *name, int w, int h)
{
    fprintf(f,
            "do for [fmt in \"png svg\"] {\n"
            "  if (fmt eq \"png\") {\n"
            "    set terminal pngcairo size %d,%d enhanced font \"DejaVu Sans,11\"\n"
            "  } else {\n"
            "    set terminal svg size %d,%d dynamic enhanced font \"DejaVu Sans,11\"\n"
            "  }\n"
            "  set output \"%s.\".fmt\n",
            w, h, w, h, name);
}

static void gp_formats_end(FILE *f)
{
    fputs("  unset output\n}\n", f);
}

/* A vertical line at x (plot coordinates) with a key entry. */
static void gp_vline(FILE *f, int id, double x, const char *color, int dt)
{
    if (!isfinite(x))
        return;
    fprintf(f, "set arrow %d from %.10g, graph 0 to %.10g, graph 1 nohead lc rgb \"%s\" dt %d lw 1.5\n",
            id, x, x, color, dt);
}

static void script_speed_f(FILE *f, const report_data *d)
{
    const report_figure *fig = &report_figures[REPORT_FIG_SPEED_F];
    const double fp = report_paper_values.f_max.value;
    gp_head(f, fig->name, fig->title);
    fputs("set xlabel \"excitation frequency f [kHz]\"\n"
          "set ylabel \"rotor speed w_R = -dφ_R/dt [1/s]\"\n"
          "set key top right box opaque\n",
          f);
    for (int k = 0; k < REPORT_NMODELS; ++k)
        gp_vline(f, k + 1, d->f_max[k].ok ? d->f_max[k].value / 1000 : NAN, model_color[k], 2);
    gp_vline(f, 3, fp / 1000, "#555555", 3);
    gp_formats_begin(f, fig->name, 900, 560);
    fputs("  plot \\\n", f);
    for (int k = 0; k < REPORT_NMODELS; ++k) {
        fprintf(f,
                "    \"fig09_speed_frequency_%s.csv\" using ($1/1000):4 skip 1 with lines lw 2 "
                "lc rgb \"%s\" title \"%s\", \\\n",
                model_tag[k], model_color[k], model_title[k]);
        if (d->f_max[k].ok)
            fprintf(f,
                    "    keyentry with lines dt 2 lw 1.5 lc rgb \"%s\" title \"%s maximum: %.4g "
                    "kHz\", \\\n",
                    model_color[k], model_tag[k], d->f_max[k].value / 1000);
    }
    fprintf(f, "    keyentry with lines dt 3 lw 1.5 lc rgb \"#555555\" title \"paper: near %s\"\n",
            report_paper_values.f_max.printed);
    gp_formats_end(f);
}

static void script_speed_T(FILE *f, const report_data *d)
{
    const report_figure *fig = &report_figures[REPORT_FIG_SPEED_T];
    const double stick = d->stick_limit.ok ? d->stick_limit.value * 1e3 : NAN;
    const double sat = d->stick_limit_sat.ok ? d->stick_limit_sat.value * 1e3 : NAN;
    const double ex3 = d->existence_T[REPORT_3DOF].ok ? d->existence_T[REPORT_3DOF].value * 1e3 : NAN;
    const double ex4 = d->existence_T[REPORT_4DOF].ok ? d->existence_T[REPORT_4DOF].value * 1e3 : NAN;
    const double stab = d->stability_T.ok ? d->stability_T.value * 1e3 : NAN;
    const double paper = report_paper_values.slip_load.value * 1e3;
    gp_head(f, fig->name, fig->title);
    fprintf(f,
            "# limits computed by usm report [N mm]\n"
            "stick = %.10g   # F_t = mu0 F_n\n"
            "sat = %.10g     # F_t = mu0 (pi/2) F_n\n"
            "ex3 = %.10g     # the 3-DOF solution stops existing\n"
            "ex4 = %.10g     # the 4-DOF solution stops existing (friction saturated)\n"
            "stab = %.10g    # 3-DOF: largest |lambda| reaches 1\n"
            "paper = %.10g   # paper: slip above this load\n",
            stick, sat, ex3, ex4, stab, paper);
    fputs("set xlabel \"load torque T [N mm]\"\n"
          "set ylabel \"rotor speed w_R = -dφ_R/dt [1/s]\"\n"
          "set key box opaque\n"
          "# 3-DOF: solid where F_t <= mu0 F_n (stick admissible), thin where not;\n"
          "# circles where the stationary solution is unstable\n",
          f);
    gp_formats_begin(f, fig->name, 1200, 560);
    fputs("  set multiplot layout 1,2 title \"Rotor speed vs load torque (paper Fig. 10)\"\n"
          "  unset title\n",
          f);
    /* left panel: the full range */
    fputs("  unset arrow\n"
          "  set key top right\n"
          "  set xrange [0:10.2]\n"
          "  set yrange [-3:15]\n",
          f);
    gp_vline(f, 1, stick, "#2e8b57", 2);
    gp_vline(f, 2, ex3, model_color[REPORT_3DOF], 4);
    gp_vline(f, 3, stab, "#ff8c00", 5);
    gp_vline(f, 4, paper, "#555555", 3);
    fprintf(f,
            "  plot \\\n"
            "    \"fig10_speed_load_3dof.csv\" using ($1*1e3):($11 > 0 ? $4 : NaN) skip 1 with lines lw 2.5 "
            "lc rgb \"%s\" title \"3-DOF (stick), F_t <= μ_0 F_n\", \\\n"
            "    \"fig10_speed_load_3dof.csv\" using ($1*1e3):4 skip 1 with lines lw 1 dt 1 "
            "lc rgb \"%s\" title \"3-DOF, stick not admissible\", \\\n"
            "    \"fig10_speed_load_3dof.csv\" using ($1*1e3):(($13 == $13 && $13 >= 1) ? $4 : NaN) skip 1 "
            "with points pt 6 ps 0.6 lc rgb \"#ff8c00\" title \"3-DOF unstable (max |λ| > 1)\", \\\n"
            "    \"fig10_speed_load_4dof.csv\" using ($1*1e3):4 skip 1 with lines lw 2.5 "
            "lc rgb \"%s\" title \"4-DOF (slip)\", \\\n"
            "    keyentry with lines dt 2 lw 1.5 lc rgb \"#2e8b57\" title sprintf(\"stick limit F_t = μ_0 F_n: %%.3g N mm\", stick), \\\n"
            "    keyentry with lines dt 4 lw 1.5 lc rgb \"%s\" title sprintf(\"3-DOF solution exists up to %%.3g N mm\", ex3), \\\n"
            "    keyentry with lines dt 5 lw 1.5 lc rgb \"#ff8c00\" title sprintf(\"3-DOF unstable above %%.3g N mm\", stab), \\\n"
            "    keyentry with lines dt 3 lw 1.5 lc rgb \"#555555\" title \"paper: slip above %s\"\n",
            model_color[REPORT_3DOF], model_color[REPORT_3DOF], model_color[REPORT_4DOF],
            model_color[REPORT_3DOF], report_paper_values.slip_load.printed);
    /* right panel: the stick/slip region */
    fputs("  unset arrow\n"
          "  set xrange [0:1.2]\n"
          "  set yrange [-40:15]\n"
          "  set key bottom left\n",
          f);
    gp_vline(f, 1, stick, "#2e8b57", 2);
    gp_vline(f, 2, sat, "#8e44ad", 2);
    gp_vline(f, 3, ex4, model_color[REPORT_4DOF], 4);
    fprintf(f,
            "  plot \\\n"
            "    \"fig10_speed_load_3dof.csv\" using ($1*1e3):($11 > 0 ? $4 : NaN) skip 1 with linespoints lw 2.5 pt 7 ps 0.4 "
            "lc rgb \"%s\" title \"3-DOF (stick), F_t <= μ_0 F_n\", \\\n"
            "    \"fig10_speed_load_3dof.csv\" using ($1*1e3):4 skip 1 with lines lw 1 "
            "lc rgb \"%s\" notitle, \\\n"
            "    \"fig10_speed_load_4dof.csv\" using ($1*1e3):4 skip 1 with linespoints lw 2.5 pt 7 ps 0.4 "
            "lc rgb \"%s\" title \"4-DOF (slip)\", \\\n"
            "    keyentry with lines dt 2 lw 1.5 lc rgb \"#2e8b57\" title sprintf(\"F_t = μ_0 F_n: %%.3g N mm\", stick), \\\n"
            "    keyentry with lines dt 2 lw 1.5 lc rgb \"#8e44ad\" title sprintf(\"F_t = μ_0 (π/2) F_n: %%.3g N mm\", sat), \\\n"
            "    keyentry with lines dt 4 lw 1.5 lc rgb \"%s\" title sprintf(\"4-DOF solution exists up to %%.3g N mm\", ex4)\n"
            "  unset multiplot\n",
            model_color[REPORT_3DOF], model_color[REPORT_3DOF], model_color[REPORT_4DOF],
            model_color[REPORT_4DOF]);
    gp_formats_end(f);
}

static void script_speed_m0(FILE *f, const report_data *d)
{
    const report_figure *fig = &report_figures[REPORT_FIG_SPEED_M0];
    gp_head(f, fig->name, fig->title);
    fputs("set xlabel \"excitation torque amplitude m_0 [mN m]\"\n"
          "set ylabel \"rotor speed w_R = -dφ_R/dt [1/s]\"\n"
          "set key top left box opaque\n",
          f);
    for (int k = 0; k < REPORT_NMODELS; ++k)
        gp_vline(f, k + 1,
                 d->existence_m0[k].ok ? d->existence_m0[k].value * 1e3 : NAN, model_color[k],
                 2 + 2 * k);
    gp_formats_begin(f, fig->name, 900, 560);
    fputs("  plot \\\n", f);
    for (int k = 0; k < REPORT_NMODELS; ++k) {
        fprintf(f,
                "    \"fig11_speed_amplitude_%s.csv\" using ($1*1e3):4 skip 1 with lines lw 2 "
                "lc rgb \"%s\" title \"%s\", \\\n",
                model_tag[k], model_color[k], model_title[k]);
        if (d->existence_m0[k].ok)
            fprintf(f,
                    "    keyentry with lines dt %d lw 1.5 lc rgb \"%s\" title \"%s: a solution "
                    "exists from m_0 = %.5g mN m\", \\\n",
                    2 + 2 * k, model_color[k], model_tag[k], d->existence_m0[k].value * 1e3);
    }
    fprintf(f,
            "    \"+\" using (%.10g):(%.10g) every ::0::0 with points pt 3 ps 2 lc rgb \"black\" "
            "title \"Appendix A: m_0 = %g mN m\"\n",
            d->params.m0 * 1e3, -d->model[REPORT_3DOF].sol.rotor_speed, d->params.m0 * 1e3);
    gp_formats_end(f);
}

static void script_multipliers(FILE *f, int fig_id, int k, const char *csv, const char *table,
                               int integrated)
{
    const report_figure *fig = &report_figures[fig_id];
    /* start times drawn besides t0 = 0: T/2, 100 T, 1000 T */
    static const int shown[3] = {2, 4, 5};
    static const char *const color[3] = {"#76d7c4", "#f0b27a", "#e74c3c"};
    static const int pt[3] = {8, 4, 10};
    gp_head(f, fig->name, fig->title);
    fprintf(f,
            "set xlabel \"Re λ\"\n"
            "set ylabel \"Im λ\"\n"
            "set size ratio -1\n"
            "set xrange [-1.3:1.3]\n"
            "set yrange [-1.3:1.3]\n"
            "set key outside right top box opaque\n"
            "set object 1 circle at 0,0 size 1 fillstyle empty border lc rgb \"black\" lw 1\n"
            "# column 1, series: 0-%d computed from the start times t0 below, 8 the\n"
            "# twist_integrated variant, 9 the paper's %s\n"
            "sel(s) = (column(1) == s) ? column(4) : NaN\n",
            REPORT_NT0 - 1, table);
    for (int i = 0; i < REPORT_NT0; ++i)
        fprintf(f, "#   %d: t0 = %s\n", i, report_t0_label[i]);
    gp_formats_begin(f, fig->name, 900, 640);
    fputs("  plot \\\n", f);
    for (int i = 0; i < 3; ++i)
        fprintf(f,
                "    \"%s\" using 3:(sel(%d)) skip 1 with points pt %d ps 1.2 lw 1.5 lc rgb \"%s\" "
                "title \"computed, t0 = %s\", \\\n",
                csv, shown[i], pt[i], color[i], report_t0_label[shown[i]]);
    if (integrated)
        fprintf(f,
                "    \"%s\" using 3:(sel(8)) skip 1 with points pt 12 ps 1.8 lc rgb \"#888888\" "
                "title \"twist integrated (any t0)\", \\\n",
                csv);
    fprintf(f,
            "    \"%s\" using 3:(sel(0)) skip 1 with points pt 7 ps 1.2 lc rgb \"%s\" title \"computed, t0 = 0\", \\\n"
            "    \"%s\" using 3:(sel(9)) skip 1 with points pt 2 ps 2.0 lw 2 lc rgb \"black\" title \"paper, %s\"\n",
            csv, model_color[k], csv, table);
    gp_formats_end(f);
}

static void script_map(FILE *f, int fig_id, const report_map *m, const char *stem,
                       const usm_params *p)
{
    const report_figure *fig = &report_figures[fig_id];
    const double dx = (m->x.to - m->x.from) / (m->x.points - 1) / 1000;
    const double dy = (m->y.to - m->y.from) / (m->y.points - 1) * 1e3;
    gp_head(f, fig->name, fig->title);
    fprintf(f,
            "# %s.csv: the grid (f [Hz], T [N m], exists, roots, max_modulus, ...);\n"
            "# %s_{existence,stability,stick}.csv: boundaries located by bisection in T\n"
            "set xlabel \"excitation frequency f [kHz]\"\n"
            "set ylabel \"load torque T [N mm]\"\n"
            "set cblabel \"largest non-cyclic |λ| (log scale)\"\n"
            "set logscale cb\n"
            "set cbrange [0.8:1.25]\n"
            "set cbtics (0.8, 0.9, 1, 1.1, 1.25)\n"
            "set palette defined (0 \"#313695\", 0.25 \"#74add1\", 0.5 \"#ffffbf\", 0.75 \"#f46d43\", 1 \"#a50026\")\n"
            "set xrange [%.10g:%.10g]\n"
            "set yrange [%.10g:%.10g]\n"
            "# grey: no stationary solution\n"
            "set object 1 rectangle from graph 0,0 to graph 1,1 behind fillcolor rgb \"#bdbdbd\" fillstyle solid 1.0 noborder\n"
            "set key at screen 0.5, screen 0.01 center bottom horizontal box opaque maxrows 2 width 1\n"
            "set bmargin 7\n"
            "unset grid\n",
            stem, stem, m->x.from / 1000 - dx / 2, m->x.to / 1000 + dx / 2,
            m->y.from * 1e3 - dy / 2, m->y.to * 1e3 + dy / 2);
    gp_formats_begin(f, fig->name, 900, 720);
    fprintf(f,
            "  plot \\\n"
            "    \"%s.csv\" using ($1/1000):($2*1e3):($3 > 0 ? $5 : NaN) skip 1 with image notitle, \\\n",
            stem);
    /* an empty boundary (none in the range) is left out: gnuplot would warn */
    if (m->nbnd[REPORT_BOUNDARY_EXISTENCE])
        fprintf(f, "    \"%s_existence.csv\" using ($1/1000):($2*1e3) skip 1 with lines lw 3 "
                   "lc rgb \"black\" title \"solution stops existing\", \\\n",
                stem);
    if (m->nbnd[REPORT_BOUNDARY_STABILITY])
        fprintf(f, "    \"%s_stability.csv\" using ($1/1000):($2*1e3) skip 1 with lines lw 2.5 "
                   "dt 2 lc rgb \"white\" title \"|λ| = 1\", \\\n",
                stem);
    if (m->nbnd[REPORT_BOUNDARY_STICK])
        fprintf(f, "    \"%s_stick.csv\" using ($1/1000):($2*1e3) skip 1 with lines lw 2.5 "
                   "dt 4 lc rgb \"#1e8449\" title \"F_t = μ_0 F_n\", \\\n",
                stem);
    fprintf(f,
            "    keyentry with boxes fillstyle solid 1.0 lc rgb \"#bdbdbd\" title \"no stationary solution\", \\\n"
            "    \"+\" using (%.10g):(%.10g) every ::0::0 with points pt 3 ps 2.5 lw 2 lc rgb \"black\" title \"Appendix A (f = %g kHz, T = %g N mm)\"\n",
            p->f / 1000, p->T * 1e3, p->f / 1000, p->T * 1e3);
    gp_formats_end(f);
}

/* ---- writing everything ------------------------------------------------------- */

typedef void (*script_fn)(FILE *f, const report_data *d);

static int write_file_curve(const char *dir, const char *name, const report_curve *cv,
                            char msg[CLI_MSG_LEN])
{
    FILE *f = report_open(dir, name, msg);
    if (!f)
        return USM_EFAILED;
    write_curve_csv(f, cv);
    return report_close(f, dir, name, msg);
}

int report_write_data(const report_data *d, const char *dir, char msg[CLI_MSG_LEN])
{
    static const char *const curve_stem[REPORT_NCURVES] = {
        "fig09_speed_frequency", "fig10_speed_load", "fig11_speed_amplitude"};
    char name[128];
    FILE *f;
    int st;
    for (int c = 0; c < REPORT_NCURVES; ++c)
        for (int k = 0; k < REPORT_NMODELS; ++k) {
            snprintf(name, sizeof name, "%s_%s.csv", curve_stem[c], model_tag[k]);
            if ((st = write_file_curve(dir, name, &d->curve[c][k], msg)) != USM_OK)
                return st;
        }
    for (int k = 0; k < REPORT_NMODELS; ++k) {
        const int fig = k == REPORT_3DOF ? REPORT_FIG_MULT_3DOF : REPORT_FIG_MULT_4DOF;
        const report_paper *pv = &report_paper_values;
        snprintf(name, sizeof name, "%s.csv", report_figures[fig].name);
        if (!(f = report_open(dir, name, msg)))
            return USM_EFAILED;
        write_multiplier_csv(f, &d->model[k], k == REPORT_3DOF ? pv->table3 : pv->table4,
                             k == REPORT_3DOF ? pv->n3 : pv->n4);
        if ((st = report_close(f, dir, name, msg)) != USM_OK)
            return st;
        snprintf(name, sizeof name, "%s.gp", report_figures[fig].name);
        if (!(f = report_open(dir, name, msg)))
            return USM_EFAILED;
        {
            char csv[128];
            snprintf(csv, sizeof csv, "%s.csv", report_figures[fig].name);
            script_multipliers(f, fig, k, csv, k == REPORT_3DOF ? "Table 3" : "Table 4",
                               d->model[k].integrated != NULL);
        }
        if ((st = report_close(f, dir, name, msg)) != USM_OK)
            return st;
    }
    for (int k = 0; k < REPORT_NMODELS; ++k) {
        const int fig = k == REPORT_3DOF ? REPORT_FIG_MAP_3DOF : REPORT_FIG_MAP_4DOF;
        const char *stem = report_figures[fig].name;
        if (!d->have_map[k])
            continue;
        snprintf(name, sizeof name, "%s.csv", stem);
        if (!(f = report_open(dir, name, msg)))
            return USM_EFAILED;
        report_map_write_csv(&d->map[k], f);
        if ((st = report_close(f, dir, name, msg)) != USM_OK)
            return st;
        for (int b = 0; b < REPORT_NBOUNDARY; ++b) {
            snprintf(name, sizeof name, "%s_%s.csv", stem, report_boundary_name(b));
            if (!(f = report_open(dir, name, msg)))
                return USM_EFAILED;
            report_map_write_boundary_csv(&d->map[k], b, f);
            if ((st = report_close(f, dir, name, msg)) != USM_OK)
                return st;
        }
        snprintf(name, sizeof name, "%s.gp", stem);
        if (!(f = report_open(dir, name, msg)))
            return USM_EFAILED;
        script_map(f, fig, &d->map[k], stem, &d->params);
        if ((st = report_close(f, dir, name, msg)) != USM_OK)
            return st;
    }
    {
        static const script_fn fns[3] = {script_speed_f, script_speed_T, script_speed_m0};
        for (int c = 0; c < 3; ++c) {
            snprintf(name, sizeof name, "%s.gp", report_figures[c].name);
            if (!(f = report_open(dir, name, msg)))
                return USM_EFAILED;
            fns[c](f, d);
            if ((st = report_close(f, dir, name, msg)) != USM_OK)
                return st;
        }
    }
    return USM_OK;
}

/* ---- running gnuplot ------------------------------------------------------------ */

static pid_t spawn_gnuplot(const char *exe, const char *dir, const char *script, int log_fd)
{
    pid_t pid = fork();
    if (pid == 0) {
        int null_fd = open("/dev/null", O_RDONLY);
        if (null_fd >= 0)
            dup2(null_fd, 0);
        dup2(log_fd, 1);
        dup2(log_fd, 2);
        if (chdir(dir) != 0)
            _exit(126);
        execlp(exe, exe, script, (char *)NULL);
        _exit(127);
    }
    return pid;
}

int report_run_gnuplot(const char *dir, int jobs, char msg[CLI_MSG_LEN])
{
    const char *exe = getenv("USM_GNUPLOT");
    char path[4096], script[128];
    pid_t pids[REPORT_NFIGURES];
    int running = 0, next = 0, failed = 0, missing = 0, log_fd;
    char failed_name[128] = "";
    if (!exe || !exe[0])
        exe = "gnuplot";
    if (jobs < 1)
        jobs = 1;
    if (report_path(path, sizeof path, dir, "gnuplot.log") != 0) {
        cli_msg(msg, "--out %s: path too long", dir);
        return USM_EFAILED;
    }
    if ((log_fd = open(path, O_WRONLY | O_CREAT | O_TRUNC | O_APPEND, 0666)) < 0) {
        cli_msg(msg, "%s: %s", path, strerror(errno));
        return USM_EFAILED;
    }
    fflush(NULL);
    for (int i = 0; i < REPORT_NFIGURES; ++i) {
        pids[i] = -1;
        /* a previous run's image must not pass for this run's */
        for (int e = 0; e < 2; ++e) {
            snprintf(script, sizeof script, "%s.%s", report_figures[i].name, e ? "svg" : "png");
            if (report_path(path, sizeof path, dir, script) == 0)
                unlink(path);
        }
    }
    while (next < REPORT_NFIGURES || running > 0) {
        if (next < REPORT_NFIGURES && running < jobs) {
            snprintf(script, sizeof script, "%s.gp", report_figures[next].name);
            pids[next] = spawn_gnuplot(exe, dir, script, log_fd);
            if (pids[next] < 0) {
                cli_msg(msg, "gnuplot: cannot start a process: %s", strerror(errno));
                failed = 1;
                next = REPORT_NFIGURES;
                continue;
            }
            ++next;
            ++running;
            continue;
        }
        {
            int status;
            pid_t pid = wait(&status);
            if (pid < 0) {
                if (errno == EINTR)
                    continue;
                break;
            }
            for (int i = 0; i < REPORT_NFIGURES; ++i)
                if (pids[i] == pid) {
                    --running;
                    pids[i] = -1;
                    if (WIFEXITED(status) && WEXITSTATUS(status) == 127)
                        missing = 1;
                    else if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
                        if (!failed_name[0])
                            snprintf(failed_name, sizeof failed_name, "%s.gp",
                                     report_figures[i].name);
                        failed = 1;
                    }
                }
        }
    }
    close(log_fd);
    if (missing) {
        cli_msg(msg, "%s: not found, figures not rendered (install gnuplot-nox, or set "
                     "USM_GNUPLOT; then run the *.gp scripts in %s)", exe, dir);
        return USM_EFAILED;
    }
    if (failed) {
        if (failed_name[0])
            cli_msg(msg, "gnuplot failed on %s/%s (see %s/gnuplot.log)", dir, failed_name, dir);
        return USM_EFAILED;
    }
    /* gnuplot may exit 0 without writing (a terminal missing, a script of
     * the user's): the report links only images that exist. */
    for (int i = 0; i < REPORT_NFIGURES; ++i)
        for (int e = 0; e < 2; ++e) {
            struct stat st;
            snprintf(script, sizeof script, "%s.%s", report_figures[i].name, e ? "svg" : "png");
            if (report_path(path, sizeof path, dir, script) != 0 || stat(path, &st) != 0 ||
                st.st_size == 0) {
                cli_msg(msg, "%s: gnuplot exited 0 but did not write %s/%s (see %s/gnuplot.log)",
                        exe, dir, script, dir);
                return USM_EFAILED;
            }
        }
    return USM_OK;
}
