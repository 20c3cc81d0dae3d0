/* The outputs of a simulation (usm_io.h): the time history as CSV, the
 * summary as a table or one JSON object. */
#include <math.h>
#include <stdio.h>

#include <jansson.h>

#include "io/csv_out.h"
#include "io/json_out.h"
#include "spectrum_out.h"
#include "usm_io.h"

/* The time history's columns (csv_out.h), read back by usm_sim_read_start. */
static const usm_csv_column columns[] = {
    {"t", "s"},           {"phi", "rad"},         {"theta", "rad"},    {"psi", "rad"},
    {"phidot", "rad/s"},  {"thetadot", "rad/s"},  {"psidot", "rad/s"}, {"phi_R", "rad"},
    {"phi_Rdot", "rad/s"}, {"F_n", "N"},          {"F_t", "N"},        {"v_rel", "m/s"},
    {"theta_avg", "rad"}, {"phi_Rdot_avg", "rad/s"},
    {"valid", NULL}, {"invalid_reason", NULL}}; /* last: usm_sim_sample.validity */

#define NCOLUMNS (sizeof columns / sizeof columns[0])

void usm_sim_csv_header(FILE *f)
{
    usm_sim_csv_header_in(NULL, f);
}

void usm_sim_csv_header_in(const usm_display *d, FILE *f)
{
    usm_csv_column shown[NCOLUMNS];
    for (size_t k = 0; k < NCOLUMNS; ++k) {
        shown[k] = columns[k];
        if (columns[k].unit)
            usm_display_value(d, columns[k].unit, 0, &shown[k].unit);
    }
    usm_csv_header(f, shown, (int)NCOLUMNS);
}

int usm_sim_csv_row(const usm_sim_sample *s, FILE *f)
{
    return usm_sim_csv_row_in(s, NULL, f);
}

int usm_sim_csv_row_in(const usm_sim_sample *s, const usm_display *d, FILE *f)
{
    /* shortest exact text: a run started from this file continues exactly */
    const double v[] = {s->t, s->phi, s->theta, s->psi, s->phidot, s->thetadot, s->psidot,
                        s->rotor_angle, s->rotor_speed, s->out[USM_OUT_F_N],
                        s->out[USM_OUT_F_T], s->out[USM_OUT_V_REL],
                        s->have_avg ? s->theta_avg : NAN, s->have_avg ? s->rotor_speed_avg : NAN};
    for (size_t k = 0; k < sizeof v / sizeof v[0]; ++k)
        usm_csv_num(f, k == 0, usm_display_value(d, columns[k].unit, v[k], NULL));
    usm_csv_validity(f, 1, s->validity);
    fputc('\n', f);
    return ferror(f) ? -1 : 0;
}

static const char *start_text(const usm_sim_report *a, char *buf, size_t len)
{
    switch (a->opt->start) {
    case USM_SIM_FROM_REST:
        snprintf(buf, len, "rest (%s; about the excitation axis, zero rates)",
                 a->summary->start_message);
        break;
    case USM_SIM_FROM_STATIONARY:
        snprintf(buf, len, "the stationary orbit");
        break;
    case USM_SIM_FROM_STATE:
        snprintf(buf, len, "the state in %s", a->from_file);
        break;
    }
    return buf;
}

static void episodes_line(FILE *out, const char *what, const usm_sim_episodes *e,
                          const char *worst_what, const char *unit)
{
    fprintf(out, "  %-22s %ld interval%s, first from t = %.6g s, last until t = %.6g s, total "
                 "%.6g s; %s %.4g %s\n",
            what, e->count, e->count == 1 ? "" : "s", e->first, e->last, e->total, worst_what,
            e->worst, unit);
}

/* "theta = X UNIT, rotor speed = Y UNIT" in the display units d */
static void theta_speed(FILE *out, const usm_display *d, double theta, double speed)
{
    const char *ua, *us;
    theta = usm_display_value(d, "rad", theta, &ua);
    speed = usm_display_value(d, "1/s", speed, &us);
    fprintf(out, "theta = %.10g %s, rotor speed = %.10g %s", theta, ua, speed, us);
}

void usm_sim_write_table(const usm_sim_report *a, FILE *out)
{
    usm_sim_write_table_in(a, NULL, out);
}

void usm_sim_write_table_in(const usm_sim_report *a, const usm_display *d, FILE *out)
{
    const usm_sim_summary *s = a->summary;
    const char *ua;
    const double theta_lo = usm_display_value(d, "rad", a->summary->theta_min, &ua);
    const double wall = a->wall;
    char buf[512];
    const double T = 1.0 / a->params->f;
    fprintf(out, "usm simulate: model %s from %s\n", a->model->name,
            start_text(a, buf, sizeof buf));
    fprintf(out, "  %-22s [%.9g, %.9g] s (%ld excitation periods of %.6g s)\n", "interval", s->t0,
            s->t1, s->periods, T);
    fprintf(out, "  %-22s %s%s%s\n", "stop", usm_sim_stop_name(s->stop), s->reason[0] ? ": " : "",
            s->reason);
    fprintf(out, "  %-22s %.9g s\n", "reached", s->t_reached);
    fprintf(out, "  %-22s %ld steps, %ld f evaluations, %ld Jacobians, %.3g s wall, rtol %g\n",
            "integrator", s->steps, s->rhs_evals, s->jac_evals, wall, a->opt->rtol);
    fprintf(out, "  %-22s [%.6g, %.6g] %s\n", "tilt range", theta_lo,
            usm_display_value(d, "rad", s->theta_max, NULL), ua);
    if (s->have_steady) {
        fprintf(out, "  %-22s ", "stationary solution");
        theta_speed(out, d, s->steady.theta, s->steady.rotor_speed);
        fputc('\n', out);
    } else
        fprintf(out, "  %-22s none (%s): settling is not defined\n", "stationary solution",
                s->steady_message);
    if (s->periods > 0) {
        fprintf(out, "  %-22s ", "last period mean");
        theta_speed(out, d, s->theta_avg_end, s->rotor_speed_avg_end);
        fputc('\n', out);
        if (s->have_steady)
            fprintf(out, "  %-22s theta %+.3e, rotor speed %+.3e (relative to stationary)\n",
                    "difference at the end", s->theta_rel_end, s->rotor_speed_rel_end);
    }
    if (s->settled)
        fprintf(out,
                "  %-22s yes, at t = %.6g s (%.0f periods after the start); period means of "
                "theta and rotor speed within %g of stationary from then to the end (%ld "
                "periods)\n",
                "settled", s->t_settle, (s->t_settle - s->t0) / T, s->settle_tol,
                s->periods - (long)floor((s->t_settle - s->t0) / T + 0.5));
    else if (s->have_steady && s->settled_on > 0)
        fprintf(out, "  %-22s no, not on the stationary solution above (#1): see \"settled on\"\n",
                "settled");
    else if (s->have_steady)
        fprintf(out,
                "  %-22s no (tolerance %g relative, held for %d periods to the end of the run)\n",
                "settled", s->settle_tol, s->settle_periods);
    if (s->settled_on >= 0) {
        fprintf(out, "  %-22s root #%d of %zu (", "settled on", s->settled_on + 1, s->roots);
        theta_speed(out, d, s->settled_root.theta, s->settled_root.rotor_speed);
        fprintf(out, "): period means within %g of it for the last %d periods\n", s->settle_tol,
                s->settle_periods);
    } else if (s->settled_on == USM_SIM_SETTLED_REST)
        fprintf(out,
                "  %-22s rest: the wobble decayed (period-mean tilt held below %g of %.3g %s "
                "by t = %.6g s); the motor does not start\n",
                "settled on", s->rest_fraction, usm_display_value(d, "rad", s->rest_theta_ref, NULL),
                ua, s->t_rest);
    else
        fprintf(out, "  %-22s none of the %zu stationary solution%s, and no decay to rest\n",
                "settled on", s->roots, s->roots == 1 ? "" : "s");
    if (s->unilateral) {
        fprintf(out, "  %-22s %ld separations, %ld impacts (largest approach velocity %.4g m/s), "
                "open %.6g of the time\n", "unilateral contact", s->separations, s->impacts,
                s->impact_velocity_max, s->open_fraction);
        if (s->periods > 0)
            fprintf(out, "  %-22s %.6g of the last period open (on a settled run: the orbit's "
                    "separation_fraction)\n", "", s->open_fraction_end);
        if (s->impacts_slipping)
            fprintf(out, "  %-22s %ld impacts needed a friction impulse above mu0 P_n (the stick "
                    "model sticks regardless: it does not describe them)\n", "impacts slipping",
                    s->impacts_slipping);
    } else if (s->contact_open.count)
        episodes_line(out, "F_n < 0 (contact opens)", &s->contact_open, "most negative F_n", "N");
    if (s->stick_checked && s->stick_exceeded.count)
        episodes_line(out, "|F_t| > mu0 F_n", &s->stick_exceeded, "largest |F_t| - mu0 F_n", "N");
    if (a->spectrum)
        usm_sim_spectrum_write_table(a->spectrum, a->spectrum_csv, out);
    else if (a->spectrum_error && a->spectrum_error[0])
        fprintf(out, "  %-22s none: %s\n", "spectrum", a->spectrum_error);
}

static json_t *episodes_json(const usm_sim_episodes *e, const char *worst_key)
{
    json_t *o = json_object();
    int ok = o != NULL;
    usm_json_put(o, "count", json_integer(e->count), &ok);
    if (e->count) {
        usm_json_put(o, "first", usm_json_real(e->first), &ok);
        usm_json_put(o, "last", usm_json_real(e->last), &ok);
        usm_json_put(o, "total", usm_json_real(e->total), &ok);
        usm_json_put(o, worst_key, usm_json_real(e->worst), &ok);
    }
    return usm_json_finish(o, ok);
}

static json_t *summary_json(const usm_sim_report *a)
{
    const usm_sim_summary *s = a->summary;
    const double wall = a->wall;
    const usm_model *m = a->model;
    json_t *o = json_object(), *fs = json_object(), *x = json_array(), *names = json_array();
    int ok = o && fs && x && names;
    static const char *const start[] = {"rest", "stationary", "file"};
    usm_json_put(o, "model", json_string(m->name), &ok);
    usm_json_put(o, "parameters", usm_json_params(a->params), &ok);
    usm_json_put(o, "start", json_string(start[a->opt->start]), &ok);
    if (a->opt->start == USM_SIM_FROM_REST) {
        usm_json_put(o, "tilt0", usm_json_real(a->summary->tilt_start), &ok);
        usm_json_put(o, "start_message", json_string(a->summary->start_message), &ok);
    }
    if (a->from_file)
        usm_json_put(o, "from", json_string(a->from_file), &ok);
    usm_json_put(o, "out", a->out ? json_string(a->out) : json_null(), &ok);
    usm_json_put(o, "rate", usm_json_real(a->opt->rate), &ok);
    usm_json_put(o, "rtol", usm_json_real(a->opt->rtol), &ok);
    usm_json_put(o, "t0", usm_json_real(s->t0), &ok);
    usm_json_put(o, "t1", usm_json_real(s->t1), &ok);
    usm_json_put(o, "t_reached", usm_json_real(s->t_reached), &ok);
    usm_json_put(o, "completed", json_boolean(s->stop == USM_SIM_COMPLETED), &ok);
    usm_json_put(o, "stop", json_string(usm_sim_stop_name(s->stop)), &ok);
    if (s->reason[0])
        usm_json_put(o, "reason", json_string(s->reason), &ok);
    usm_json_put(o, "steps", json_integer(s->steps), &ok);
    usm_json_put(o, "rhs_evals", json_integer(s->rhs_evals), &ok);
    usm_json_put(o, "jac_evals", json_integer(s->jac_evals), &ok);
    usm_json_put(o, "error_test_fails", json_integer(s->error_test_fails), &ok);
    usm_json_put(o, "newton_fails", json_integer(s->newton_fails), &ok);
    usm_json_put(o, "twist_growth", usm_json_real(s->twist_growth), &ok);
    if (s->warning[0])
        usm_json_put(o, "warning", json_string(s->warning), &ok);
    usm_json_put(o, "samples", json_integer(s->samples), &ok);
    usm_json_put(o, "wall_time", usm_json_real(wall), &ok);
    usm_json_put(o, "periods", json_integer(s->periods), &ok);
    usm_json_put(o, "theta_min", usm_json_real(s->theta_min), &ok);
    usm_json_put(o, "theta_max", usm_json_real(s->theta_max), &ok);
    if (s->have_steady)
        usm_json_put(o, "stationary", usm_json_root(&s->steady), &ok);
    else {
        usm_json_put(o, "stationary", json_null(), &ok);
        usm_json_put(o, "stationary_error", json_string(s->steady_message), &ok);
    }
    usm_json_put(o, "settle_tol", usm_json_real(s->settle_tol), &ok);
    usm_json_put(o, "settle_periods", json_integer(s->settle_periods), &ok);
    usm_json_put(o, "settled", json_boolean(s->settled), &ok);
    usm_json_put(o, "t_settle", s->settled ? usm_json_real(s->t_settle) : json_null(), &ok);
    /* where it ended: a root index, "rest", or null (usm_simulate.h) */
    if (s->settled_on >= 0)
        usm_json_put(o, "settled_on", json_integer(s->settled_on), &ok);
    else if (s->settled_on == USM_SIM_SETTLED_REST)
        usm_json_put(o, "settled_on", json_string("rest"), &ok);
    else
        usm_json_put(o, "settled_on", json_null(), &ok);
    usm_json_put(o, "roots", json_integer((json_int_t)s->roots), &ok);
    if (s->settled_on >= 0)
        usm_json_put(o, "settled_root", usm_json_root(&s->settled_root), &ok);
    usm_json_put(o, "rest_fraction", usm_json_real(s->rest_fraction), &ok);
    usm_json_put(o, "rest_theta_ref", usm_json_real(s->rest_theta_ref), &ok);
    usm_json_put(o, "t_rest", s->settled_on == USM_SIM_SETTLED_REST ? usm_json_real(s->t_rest)
                                                                   : json_null(), &ok);
    if (s->periods > 0) {
        usm_json_put(o, "theta_avg_end", usm_json_real(s->theta_avg_end), &ok);
        usm_json_put(o, "rotor_speed_avg_end", usm_json_real(s->rotor_speed_avg_end), &ok);
        if (s->have_steady) {
            usm_json_put(o, "theta_rel_end", usm_json_real(s->theta_rel_end), &ok);
            usm_json_put(o, "rotor_speed_rel_end", usm_json_real(s->rotor_speed_rel_end), &ok);
        }
    }
    usm_json_put(o, "contact_open", episodes_json(&s->contact_open, "min_F_n"), &ok);
    if (s->unilateral) {
        /* a contact that may open (docs/unilateral.md) */
        usm_json_put(o, "separations", json_integer(s->separations), &ok);
        usm_json_put(o, "impacts", json_integer(s->impacts), &ok);
        usm_json_put(o, "impacts_slipping", json_integer(s->impacts_slipping), &ok);
        usm_json_put(o, "impact_velocity_max", usm_json_real(s->impact_velocity_max), &ok);
        usm_json_put(o, "open_fraction", usm_json_real(s->open_fraction), &ok);
        if (s->periods > 0)
            usm_json_put(o, "open_fraction_end", usm_json_real(s->open_fraction_end), &ok);
        usm_json_put(o, "final_open", json_boolean(s->final_open), &ok);
    }
    if (s->stick_checked)
        usm_json_put(o, "stick_exceeded", episodes_json(&s->stick_exceeded, "max_excess"), &ok);
    for (int i = 0; i < m->nx && ok; ++i) {
        ok = ok && json_array_append_new(x, usm_json_real(s->final_x[i])) == 0;
        ok = ok && json_array_append_new(names, json_string(m->state_names[i])) == 0;
    }
    usm_json_put(fs, "t", usm_json_real(s->t_reached), &ok);
    usm_json_put(fs, "x", x, &ok);
    usm_json_put(fs, "names", names, &ok);
    usm_json_put(fs, "phi_R", usm_json_real(s->final_rotor_angle), &ok);
    usm_json_put(o, "final_state", fs, &ok);
    if (a->spectrum)
        usm_json_put(o, "spectrum", usm_json_sim_spectrum(a->spectrum, a->spectrum_csv), &ok);
    else if (a->spectrum_error && a->spectrum_error[0]) {
        usm_json_put(o, "spectrum", json_null(), &ok);
        usm_json_put(o, "spectrum_error", json_string(a->spectrum_error), &ok);
    }
    return usm_json_finish(o, ok);
}

int usm_sim_write_json(const usm_sim_report *r, FILE *out)
{
    return usm_json_write(summary_json(r), out);
}
