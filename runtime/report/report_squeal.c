/* The squeal in the report: where the 4-DOF periodic orbit
 * of the variant "imperfect" loses stability along the mode split (the
 * Neimark-Sacker event of the library's periodic sweep, usm_periodic_sweep.h,
 * with its squeal_frequency), and a few simulations from rest around it
 * (usm_simulate.h) whose spectra (usm_spectrum.h) show the emerging
 * vibration: the spectrum just past the point, and the vibration's amplitude
 * (the part of the motion that does not repeat with the excitation period)
 * against the mode split.
 *
 * Each mode split is one task of the library's pool (pool_internal.h); each
 * simulation covers 370 excitation periods (10 ms at 37 kHz), the spectrum
 * its second half. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "core/pool_internal.h"
#include "io/csv_out.h"
#include "report_internal.h"
#include "usm_periodic_sweep.h"
#include "usm_simulate.h"
#include "usm_squeal_study.h"

/* The mode splits simulated, relative to the Neimark-Sacker point's: s =
 * s_NS (1 + r); the spectrum drawn is that of +2 % (8.8 % at the paper's
 * parameters).  --quick: three of them. */
static const double rel_full[] = {-0.06, -0.02, 0.02, 0.06, 0.10, 0.16};
static const double rel_quick[] = {-0.02, 0.02};
#define REL_SPECTRUM 0.02
/* Excitation periods simulated from rest: the first half the start-up, the
 * second the spectrum's window. */
#define SIM_PERIODS 370.0

typedef struct sq_state {
    usm_sim *sim;
    usm_sim_spectrum *spec;
    usm_periodic *w;
} sq_state;

static void state_free(void *state)
{
    sq_state *s = state;
    if (!s)
        return;
    usm_sim_free(s->sim);
    usm_sim_spectrum_free(s->spec);
    usm_periodic_free(s->w);
    free(s);
}

static void *state_alloc(void *ctx)
{
    const usm_report_data *d = ctx;
    sq_state *s = calloc(1, sizeof *s);
    if (s && (s->sim = usm_sim_alloc(d->squeal.model)) && (s->spec = usm_sim_spectrum_alloc()) &&
        (s->w = usm_periodic_alloc(d->squeal.model)))
        return s;
    state_free(s);
    return NULL;
}

static int record(const usm_sim_sample *smp, void *data)
{
    return usm_sim_spectrum_add(data, smp);
}

/* The parameters at mode split s: the report's, the other imperfections 0. */
static usm_params at_split(const usm_params *base, double s)
{
    usm_params p = *base;
    p.amp_imbalance = p.phase_error = 0.0;
    p.mode_split = s;
    return p;
}

/* Task i: the orbit and a simulation at mode split pt[i]. */
static int point_task(void *ctx, void *state, size_t i)
{
    usm_report_data *d = ctx;
    usm_report_squeal *sq = &d->squeal;
    usm_report_squeal_point *pt = &sq->pt[i];
    sq_state *s = state;
    const usm_params p = at_split(&d->params, pt->mode_split);
    usm_periodic_result orbit;
    usm_periodic_options popt;
    usm_periodic_options_default(&popt);
    if (usm_periodic_solve(s->w, &p, NULL, &popt, &orbit) == USM_OK) {
        usm_squeal ss;
        pt->orbit_ok = 1;
        pt->max_modulus = orbit.floquet.max_modulus;
        pt->F_n_min = orbit.F_n_min;
        pt->valid = orbit.validity == USM_VALID;
        usm_floquet_squeal(&orbit.floquet, 1.0 / orbit.period, &ss);
        pt->has_pair = ss.found;
        pt->squeal_frequency = ss.frequency;
    } else {
        pt->max_modulus = pt->squeal_frequency = pt->F_n_min = NAN;
    }
    usm_sim_options so;
    usm_sim_callbacks cb = {record, NULL, s->spec, NULL};
    usm_sim_summary sum;
    memset(&sum, 0, sizeof sum);
    usm_sim_options_default(&so);
    so.duration = sq->duration;
    so.rate = 10.0 * p.f;
    usm_sim_spectrum_reset(s->spec);
    if (usm_sim_run(s->sim, &p, &so, &cb, &sum) != USM_OK || sum.stop != USM_SIM_COMPLETED) {
        snprintf(pt->note, USM_MSG_LEN, "the simulation stopped at t = %.6g s: %.150s",
                 sum.t_reached, usm_sim_message(s->sim));
        return USM_OK;
    }
    usm_sim_spectrum_options spo;
    usm_sim_spectrum_result r;
    char msg[USM_MSG_LEN];
    usm_sim_spectrum_options_default(&spo);
    spo.f = p.f;
    spo.rate = so.rate;
    if (usm_sim_spectrum_compute(s->spec, &spo, &r, msg) != USM_OK) {
        snprintf(pt->note, USM_MSG_LEN, "no spectrum: %.200s", msg);
        return USM_OK;
    }
    pt->sim_ok = 1;
    for (int c = 0; c < USM_SPECTRUM_NCHANNELS; ++c)
        pt->parasitic_rms[c] = r.parasitic_rms[c];
    pt->has_line = r.have_nonharmonic[USM_SPECTRUM_F_N];
    pt->line = r.nonharmonic[USM_SPECTRUM_F_N];
    if ((int)i == sq->spectrum_pt) {
        sq->periods = r.periods;
        sq->df = r.df;
        sq->bins = r.bins < REPORT_SQUEAL_MAXBINS ? r.bins : REPORT_SQUEAL_MAXBINS;
        for (int c = 0; c < USM_SPECTRUM_NCHANNELS; ++c)
            memcpy(sq->amp[c], usm_sim_spectrum_amplitudes(s->spec, c), sq->bins * sizeof(double));
    }
    return USM_OK;
}

/* The Neimark-Sacker point: the first stability_change of kind
 * neimark_sacker of the periodic sweep over the mode split.  0, or -1 with
 * sq->note. */
static int locate_ns(usm_report_data *d)
{
    usm_report_squeal *sq = &d->squeal;
    usm_periodic_sweep *sw = usm_periodic_sweep_alloc(sq->model);
    usm_periodic_sweep_options opt;
    const usm_params base = at_split(&d->params, 0.0);
    int rc = -1;
    if (!sw) {
        snprintf(sq->note, USM_MSG_LEN, "out of memory");
        return -1;
    }
    usm_periodic_sweep_options_default(&opt);
    opt.over = "mode_split";
    opt.from = sq->from;
    opt.to = sq->to;
    opt.points = d->opt.quick ? 4 : 10;
    opt.event_tol = d->opt.quick ? 1e-6 : 1e-9;
    if (d->opt.quick) {
        opt.periodic.rtol = 1e-9;
        opt.periodic.tol = 1e-7;
    }
    if (usm_periodic_sweep_run(sw, &base, &opt) != USM_OK) {
        snprintf(sq->note, USM_MSG_LEN, "the periodic sweep over the mode split failed: %.180s",
                 usm_periodic_sweep_message(sw));
        usm_periodic_sweep_free(sw);
        return -1;
    }
    for (size_t q = 0; q < usm_periodic_sweep_event_count(sw) && rc != 0; ++q) {
        const usm_periodic_event *e = usm_periodic_sweep_event_at(sw, q);
        if (e->type != USM_PEVENT_STABILITY_CHANGE || e->kind != USM_CROSSING_NEIMARK_SACKER)
            continue;
        sq->ns_value = e->value;
        sq->ns_re = e->multiplier_re;
        sq->ns_im = fabs(e->multiplier_im);
        sq->ns_frequency = e->squeal_frequency;
        sq->ns_validity = e->has_orbit ? e->orbit.validity : USM_VALID;
        rc = 0;
    }
    if (rc != 0)
        snprintf(sq->note, USM_MSG_LEN,
                 "the 4-DOF orbit has no Neimark-Sacker point for a mode split from %g to %g %%",
                 100 * sq->from, 100 * sq->to);
    usm_periodic_sweep_free(sw);
    return rc;
}

/* The motion of the unilateral 4-DOF motor over the mode split, across the
 * end of its stable orbit (3.0 to 3.5 % at the paper's parameters,
 * docs/results.md) into the irregular bouncing.  The full report: 8 values
 * with windows long enough for lines 290 Hz apart; --quick: three values
 * (periodic, and twice irregular) on short windows, for its cost (about
 * 0.1 s of CPU a value): the classification holds there, the lines are
 * coarse (2.3 kHz apart) and the exponent a 10-period estimate.  A failure
 * is reported in the note, not an error of the report. */
static int compute_motion(usm_report_data *d)
{
    usm_report_squeal_motion *mo = &d->squeal.motion;
    const clock_t c0 = clock();
    const usm_model *m = d->model[REPORT_4DOF].model;
    mo->onset_lo = mo->onset_hi = NAN;
    mo->model = m ? usm_model_variant(m->base, "imperfect_unilateral") : NULL;
    if (!mo->model) {
        snprintf(mo->note, USM_MSG_LEN, "the variant imperfect_unilateral of 4dof is not built");
        return USM_OK;
    }
    if (!(mo->study = usm_squeal_alloc(mo->model)))
        return USM_EFAILED;
    usm_squeal_options o;
    usm_squeal_options_default(&o);
    o.over = "mode_split";
    o.check_rest = 0; /* one attractor a value: the study's rest check is `usm squeal`'s */
    o.lines = 3;
    o.origin = 0; /* the origin is `usm squeal`'s (an orbit solve) */
    if (d->opt.quick) {
        o.from = 0.03;
        o.to = 0.05;
        o.points = 3;
        o.settle = 30;
        o.window = 16;
        o.lyapunov_skip = 20;
        o.lyapunov_periods = 10;
        o.power_periods = 0; /* the power account is the full report's */
    } else {
        o.from = 0.025;
        o.to = 0.06;
        o.points = 8;
        o.settle = 150;
        o.window = 128;
        o.lyapunov_skip = 30;
        o.lyapunov_periods = 70;
        o.power_periods = 60;
    }
    usm_params p = at_split(&d->params, 0.0);
    const int rc = usm_squeal_run(mo->study, &p, &o);
    mo->from = o.from;
    mo->to = o.to;
    mo->points = o.points;
    mo->settle = o.settle;
    mo->window = o.window;
    mo->lyapunov_skip = o.lyapunov_skip;
    mo->lyapunov_periods = o.lyapunov_periods;
    mo->seconds = (double)(clock() - c0) / CLOCKS_PER_SEC;
    if (rc == USM_EFAILED && !usm_squeal_count(mo->study))
        return USM_EFAILED; /* out of memory */
    if (rc != USM_OK) {
        snprintf(mo->note, USM_MSG_LEN, "the squeal study failed: %.200s",
                 usm_squeal_message(mo->study));
        return USM_OK;
    }
    for (size_t i = 1; i < usm_squeal_count(mo->study); ++i) {
        const usm_squeal_point *a = usm_squeal_point_at(mo->study, i - 1),
                               *b = usm_squeal_point_at(mo->study, i);
        if (a->motion == USM_MOTION_PERIODIC && a->period == 1 &&
            !(b->motion == USM_MOTION_PERIODIC && b->period == 1)) {
            mo->onset_lo = a->value;
            mo->onset_hi = b->value;
            break;
        }
    }
    mo->ok = 1;
    return USM_OK;
}

int usm_report_compute_squeal(usm_report_data *d, char msg[USM_IO_MSG_LEN])
{
    usm_report_squeal *sq = &d->squeal;
    const double t = usm_report_now();
    const double *rel = d->opt.quick ? rel_quick : rel_full;
    const int n = d->opt.quick ? (int)(sizeof rel_quick / sizeof rel_quick[0])
                               : (int)(sizeof rel_full / sizeof rel_full[0]);
    char pmsg[USM_MSG_LEN];
    memset(sq, 0, sizeof *sq);
    if (compute_motion(d) != USM_OK) {
        usm_io_msg(msg, "the squeal: out of memory");
        return USM_EFAILED;
    }
    sq->from = 0.06;
    sq->to = 0.15;
    sq->f = d->params.f;
    sq->duration = SIM_PERIODS / d->params.f;
    const usm_model *m = d->model[REPORT_4DOF].model;
    sq->model = m ? usm_model_variant(m->base, "imperfect") : NULL;
    if (!sq->model) {
        snprintf(sq->note, USM_MSG_LEN, "the variant imperfect of 4dof is not built");
        return USM_OK;
    }
    if (locate_ns(d) != 0) {
        sq->seconds = usm_report_now() - t;
        return USM_OK;
    }
    sq->npts = n;
    sq->spectrum_pt = -1;
    for (int i = 0; i < n; ++i) {
        sq->pt[i].mode_split = sq->ns_value * (1.0 + rel[i]);
        if (rel[i] == REL_SPECTRUM)
            sq->spectrum_pt = i;
    }
    if (sq->spectrum_pt < 0) /* not reached: both lists hold REL_SPECTRUM */
        sq->spectrum_pt = 0;
    pool_job job = {(size_t)n, d->opt.threads, d, state_alloc, state_free, point_task, NULL};
    if (pool_run(&job, pmsg) != USM_OK) {
        usm_io_msg(msg, "the squeal: %s", pmsg[0] ? pmsg : "out of memory");
        return USM_EFAILED;
    }
    const usm_report_squeal_point *sp = &sq->pt[sq->spectrum_pt];
    if (!sp->sim_ok)
        snprintf(sq->note, USM_MSG_LEN, "no spectrum at mode split %.4g %%: %.180s",
                 100 * sp->mode_split, sp->note);
    sq->ok = sp->sim_ok;
    sq->seconds = usm_report_now() - t;
    return USM_OK;
}

/* ---- files ---------------------------------------------------------------------- */

static int write_file(const usm_report_data *d, const char *dir, const char *name, int which,
                      char msg[USM_IO_MSG_LEN])
{
    const usm_report_squeal *sq = &d->squeal;
    usm_io_file out;
    FILE *f = usm_report_open(&out, dir, name, msg);
    if (!f)
        return USM_EFAILED;
    if (which == 0) { /* the spectrum just past the point */
        static const usm_csv_column cols[] = {{"frequency_kHz", "kHz"}, {"rotor_speed", "1/s"},
                                              {"theta", "rad"}, {"F_n", "N"}};
        usm_csv_header(f, cols, 4);
        for (size_t k = 1; k < sq->bins; ++k) {
            usm_csv_num(f, 1, 1e-3 * (double)k * sq->df);
            for (int c = 0; c < USM_SPECTRUM_NCHANNELS; ++c)
                usm_csv_num(f, 0, sq->amp[c][k]);
            fputc('\n', f);
        }
    } else if (which == 1) { /* the points */
        static const usm_csv_column cols[] = {
            {"mode_split_percent", "%"},        {"max_modulus", "1"},
            {"squeal_frequency_kHz", "kHz"},    {"line_frequency_kHz", "kHz"},
            {"line_folded_kHz", "kHz"},         {"rms_rotor_speed", "1/s"},
            {"rms_theta", "rad"},               {"rms_F_n", "N"},
            {"valid", NULL},                    {"invalid_reason", NULL}};
        usm_csv_header(f, cols, 10);
        for (int i = 0; i < sq->npts; ++i) {
            const usm_report_squeal_point *pt = &sq->pt[i];
            usm_csv_num(f, 1, 100 * pt->mode_split);
            usm_csv_num(f, 0, pt->max_modulus);
            usm_csv_num(f, 0, pt->has_pair ? 1e-3 * pt->squeal_frequency : NAN);
            usm_csv_num(f, 0, pt->has_line ? 1e-3 * pt->line.frequency : NAN);
            usm_csv_num(f, 0, pt->has_line ? 1e-3 * pt->line.folded : NAN);
            for (int c = 0; c < USM_SPECTRUM_NCHANNELS; ++c)
                usm_csv_num(f, 0, pt->sim_ok ? pt->parasitic_rms[c] : NAN);
            /* of the orbit, whose max_modulus and squeal frequency the row holds */
            usm_csv_validity(f, pt->orbit_ok, pt->valid ? USM_VALID : USM_INVALID_CONTACT_OPEN);
            fputc('\n', f);
        }
    } else { /* the values the figure marks */
        static const usm_csv_column cols[] = {
            {"ns_percent", "%"}, {"squeal_frequency_kHz", "kHz"}, {"f_kHz", "kHz"},
            {"spectrum_percent", "%"}, {"valid", NULL}, {"invalid_reason", NULL}};
        usm_csv_header(f, cols, 6);
        usm_csv_num(f, 1, 100 * sq->ns_value);
        usm_csv_num(f, 0, 1e-3 * sq->ns_frequency);
        usm_csv_num(f, 0, 1e-3 * sq->f);
        usm_csv_num(f, 0, 100 * sq->pt[sq->spectrum_pt].mode_split);
        usm_csv_validity(f, 1, sq->ns_validity); /* of the orbit at the point */
        fputc('\n', f);
    }
    return usm_report_close(&out, msg);
}

/* The motion's files: the figure's data (usm_squeal_write_plot_csv) and a
 * row per value (usm_squeal_write_csv). */
static int write_motion(const usm_report_data *d, const char *dir, char msg[USM_IO_MSG_LEN])
{
    static const char *const name[2] = {"squeal_motion.csv", "squeal_motion_points.csv"};
    const usm_squeal_study *st = d->squeal.motion.study;
    int rc = USM_OK;
    for (int k = 0; k < 2 && rc == USM_OK; ++k) {
        usm_io_file out;
        FILE *f = usm_report_open(&out, dir, name[k], msg);
        if (!f)
            return USM_EFAILED;
        if ((k == 0 ? usm_squeal_write_plot_csv(st, f) : usm_squeal_write_csv(st, f)) != 0) {
            usm_io_abort(&out);
            usm_io_msg(msg, "%s/%s: write error", dir, name[k]);
            return USM_EFAILED;
        }
        rc = usm_report_close(&out, msg);
    }
    return rc;
}

int usm_report_squeal_write_data(const usm_report_data *d, const char *dir,
                                 char msg[USM_IO_MSG_LEN])
{
    static const char *const name[3] = {"squeal_spectrum.csv", "squeal_amplitude.csv",
                                        "squeal_values.csv"};
    int st = d->squeal.motion.ok ? write_motion(d, dir, msg) : USM_OK;
    for (int k = 0; k < 3 && st == USM_OK && d->squeal.ok; ++k)
        st = write_file(d, dir, name[k], k, msg);
    return st;
}

/* ---- report.json ---------------------------------------------------------------- */

static void num(json_t *o, const char *key, double v)
{
    json_object_set_new(o, key, isfinite(v) ? json_real(v) : json_null());
}

/* The motion past the last orbit ("squeal.motion"; keys: docs/report.md). */
static json_t *motion_json(const usm_report_squeal_motion *mo)
{
    json_t *o = json_object(), *pts = json_array();
    json_object_set_new(o, "ok", json_boolean(mo->ok));
    json_object_set_new(o, "note", json_string(mo->note));
    json_object_set_new(o, "model", json_string(mo->model ? mo->model->name : ""));
    num(o, "seconds", mo->seconds);
    num(o, "from_percent", 100 * mo->from);
    num(o, "to_percent", 100 * mo->to);
    json_object_set_new(o, "points_count", json_integer(mo->points));
    json_object_set_new(o, "settle", json_integer(mo->settle));
    json_object_set_new(o, "window", json_integer(mo->window));
    json_object_set_new(o, "lyapunov_skip", json_integer(mo->lyapunov_skip));
    json_object_set_new(o, "lyapunov_periods", json_integer(mo->lyapunov_periods));
    json_object_set_new(o, "onset_found", json_boolean(isfinite(mo->onset_lo)));
    num(o, "onset_lo_percent", 100 * mo->onset_lo);
    num(o, "onset_hi_percent", 100 * mo->onset_hi);
    const size_t n = mo->ok ? usm_squeal_count(mo->study) : 0;
    double loudest = -INFINITY, loudest_f = NAN, loudest_at = NAN;
    for (size_t i = 0; i < n; ++i) {
        const usm_squeal_point *pt = usm_squeal_point_at(mo->study, i);
        const int periodic = pt->motion == USM_MOTION_PERIODIC;
        json_t *p = json_object(), *lines = json_array();
        num(p, "value", pt->value);
        num(p, "percent", 100 * pt->value);
        json_object_set_new(p, "motion", json_string(usm_motion_name(pt->motion)));
        json_object_set_new(p, "period", json_integer(pt->period));
        json_object_set_new(p, "periodic", json_boolean(periodic));
        json_object_set_new(p, "chaotic", json_boolean(pt->motion == USM_MOTION_CHAOTIC));
        json_object_set_new(p, "error", json_string(pt->status == USM_OK ? "" : pt->message));
        num(p, "lyapunov", pt->lyapunov);
        num(p, "lyapunov_per_period", pt->lyapunov_per_period);
        num(p, "rotor_speed_mean", pt->rotor_speed_mean);
        num(p, "rotor_speed_ripple", pt->rotor_speed_ripple);
        num(p, "open_fraction", pt->open_fraction);
        num(p, "open_percent", 100 * pt->open_fraction);
        num(p, "impacts_per_period", pt->impacts_per_period);
        num(p, "impact_velocity_max", pt->impact_velocity_max);
        num(p, "impact_velocity_max_mm_s", 1e3 * pt->impact_velocity_max);
        num(p, "bin", pt->df);
        {
            /* the shares of the excitation's power taken by the dampers, the
               impacts and friction (NaN without the account: --quick) */
            const usm_squeal_power *w = &pt->power;
            const int have = pt->status == USM_OK && w->periods > 0 && w->excitation > 0;
            json_object_set_new(p, "power_found", json_boolean(have));
            num(p, "power_excitation", have ? w->excitation : NAN);
            num(p, "damping_percent", have ? -100 * w->damping / w->excitation : NAN);
            num(p, "impacts_percent", have ? -100 * w->impacts_power / w->excitation : NAN);
            num(p, "friction_percent", have ? -100 * w->friction / w->excitation : NAN);
            num(p, "load_percent", have ? -100 * w->load / w->excitation : NAN);
            num(p, "energy_balance_error", have ? w->balance_error : NAN);
        }
        for (size_t k = 0; k < pt->nlines; ++k) {
            json_t *l = json_object();
            num(l, "frequency", pt->lines[k].frequency);
            num(l, "frequency_kHz", 1e-3 * pt->lines[k].frequency);
            num(l, "level_db", pt->lines[k].level_db);
            json_array_append_new(lines, l);
            /* the loudest line of an irregular motion: a periodic orbit's lines
               are its harmonics' leakage, tens of dB below, and a settling one's
               its transient */
            if ((pt->motion == USM_MOTION_CHAOTIC || pt->motion == USM_MOTION_QUASI_PERIODIC) &&
                pt->lines[k].level_db > loudest) {
                loudest = pt->lines[k].level_db;
                loudest_f = pt->lines[k].frequency;
                loudest_at = pt->value;
            }
        }
        json_object_set_new(p, "lines", lines);
        json_object_set_new(p, "has_lines", json_boolean(pt->nlines > 0));
        {
            char buf[256] = "";
            size_t len = 0;
            for (size_t k = 0; k < pt->nlines && len < sizeof buf - 40; ++k)
                len += (size_t)snprintf(buf + len, sizeof buf - len, "%s%.3g kHz (%.0f dB)",
                                        k ? ", " : "", 1e-3 * pt->lines[k].frequency,
                                        pt->lines[k].level_db);
            json_object_set_new(p, "lines_text", json_string(pt->nlines ? buf : "none"));
        }
        json_array_append_new(pts, p);
    }
    json_object_set_new(o, "points", pts);
    num(o, "bin_kHz", n ? 1e-3 * usm_squeal_point_at(mo->study, 0)->df : NAN);
    json_object_set_new(o, "loud_found", json_boolean(isfinite(loudest_f)));
    num(o, "loudest_kHz", 1e-3 * loudest_f);
    num(o, "loudest_db", isfinite(loudest_f) ? loudest : NAN);
    num(o, "loudest_percent", 100 * loudest_at);
    return o;
}

json_t *usm_report_squeal_json(const usm_report_data *d)
{
    const usm_report_squeal *sq = &d->squeal;
    json_t *o = json_object(), *pts = json_array();
    json_object_set_new(o, "motion", motion_json(&sq->motion));
    json_object_set_new(o, "ok", json_boolean(sq->ok));
    json_object_set_new(o, "note", json_string(sq->note));
    json_object_set_new(o, "model", json_string(sq->model ? sq->model->name : ""));
    num(o, "seconds", sq->seconds);
    num(o, "from_percent", 100 * sq->from);
    num(o, "to_percent", 100 * sq->to);
    num(o, "duration_ms", 1e3 * sq->duration);
    json_object_set_new(o, "periods", json_integer(sq->periods));
    num(o, "resolution", sq->ok ? sq->df : NAN);
    if (!sq->ok) {
        json_decref(pts);
        return o;
    }
    num(o, "ns_value", sq->ns_value);
    num(o, "ns_percent", 100 * sq->ns_value);
    num(o, "ns_re", sq->ns_re);
    num(o, "ns_im", sq->ns_im);
    num(o, "squeal_frequency", sq->ns_frequency);
    num(o, "squeal_frequency_kHz", 1e-3 * sq->ns_frequency);
    /* the flag of the squeal frequency: the bilateral orbit at the point */
    json_object_set_new(o, "ns_valid", json_boolean(sq->ns_validity == USM_VALID));
    json_object_set_new(o, "ns_invalid_reason",
                        sq->ns_validity == USM_VALID ? json_null()
                                                     : json_string(usm_validity_name(sq->ns_validity)));
    num(o, "squeal_order", sq->ns_frequency / sq->f);
    num(o, "lower_kHz", 1e-3 * (sq->f - sq->ns_frequency));
    num(o, "upper_kHz", 1e-3 * (sq->f + sq->ns_frequency));
    {
        const usm_report_squeal_point *sp = &sq->pt[sq->spectrum_pt];
        json_t *s = json_object();
        num(s, "percent", 100 * sp->mode_split);
        num(s, "line_kHz", sp->has_line ? 1e-3 * sp->line.frequency : NAN);
        num(s, "line_folded_kHz", sp->has_line ? 1e-3 * sp->line.folded : NAN);
        num(s, "line_amplitude", sp->has_line ? sp->line.amplitude : NAN);
        num(s, "squeal_frequency_kHz", sp->has_pair ? 1e-3 * sp->squeal_frequency : NAN);
        json_object_set_new(s, "valid", json_boolean(sp->orbit_ok && sp->valid));
        num(s, "deviation_percent", sp->has_line && sp->has_pair
                                        ? 100 * (sp->line.folded / sp->squeal_frequency - 1)
                                        : NAN);
        json_object_set_new(o, "spectrum", s);
    }
    for (int i = 0; i < sq->npts; ++i) {
        const usm_report_squeal_point *pt = &sq->pt[i];
        json_t *p = json_object();
        num(p, "mode_split", pt->mode_split);
        num(p, "percent", 100 * pt->mode_split);
        json_object_set_new(p, "past", json_boolean(pt->mode_split > sq->ns_value));
        json_object_set_new(p, "orbit_ok", json_boolean(pt->orbit_ok));
        num(p, "max_modulus", pt->max_modulus);
        num(p, "F_n_min", pt->F_n_min);
        json_object_set_new(p, "valid", json_boolean(pt->orbit_ok && pt->valid));
        num(p, "squeal_frequency_kHz", pt->has_pair ? 1e-3 * pt->squeal_frequency : NAN);
        json_object_set_new(p, "sim_ok", json_boolean(pt->sim_ok));
        json_object_set_new(p, "note", json_string(pt->note));
        num(p, "line_kHz", pt->sim_ok && pt->has_line ? 1e-3 * pt->line.frequency : NAN);
        num(p, "line_folded_kHz", pt->sim_ok && pt->has_line ? 1e-3 * pt->line.folded : NAN);
        num(p, "line_amplitude", pt->sim_ok && pt->has_line ? pt->line.amplitude : NAN);
        for (int c = 0; c < USM_SPECTRUM_NCHANNELS; ++c) {
            char key[48];
            snprintf(key, sizeof key, "rms_%s", usm_spectrum_channel_name(c));
            num(p, key, pt->sim_ok ? pt->parasitic_rms[c] : NAN);
        }
        json_array_append_new(pts, p);
    }
    json_object_set_new(o, "points", pts);
    {
        int any = 0;
        for (int i = 0; i < sq->npts; ++i)
            any |= sq->pt[i].orbit_ok && sq->pt[i].valid;
        /* the bilateral contact of the model: past contact loss it is not the motor */
        json_object_set_new(o, "any_valid", json_boolean(any));
    }
    return o;
}
