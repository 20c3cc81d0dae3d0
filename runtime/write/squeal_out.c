/* The squeal study's points as JSON and CSV, and its bifurcation diagram's
 * samples (usm_squeal_study.h). */
#include <jansson.h>
#include <math.h>
#include <stdio.h>

#include "io/csv_out.h"
#include "io/json_out.h"
#include "usm_squeal_study.h"

#define CSV_LINES 3

static json_t *point_json(const usm_squeal_study *s, size_t i)
{
    const usm_squeal_point *pt = usm_squeal_point_at(s, i);
    json_t *o = json_object();
    int ok = o != NULL;
    if (!o)
        return NULL;
    usm_json_put(o, "value", usm_json_real(pt->value), &ok);
    usm_json_put(o, "motion", json_string(usm_motion_name(pt->motion)), &ok);
    usm_json_put(o, "period", json_integer(pt->period), &ok);
    usm_json_put(o, "second_frequency", usm_json_real(pt->second_frequency), &ok);
    usm_json_put(o, "lyapunov", usm_json_real(pt->lyapunov), &ok);
    usm_json_put(o, "lyapunov_2", usm_json_real(pt->lyapunov2), &ok);
    usm_json_put(o, "lyapunov_per_period", usm_json_real(pt->lyapunov_per_period), &ok);
    json_t *lines = json_array();
    for (size_t k = 0; lines && k < pt->nlines; ++k) {
        json_t *l = json_object();
        int lok = l != NULL;
        usm_json_put(l, "frequency", usm_json_real(pt->lines[k].frequency), &lok);
        usm_json_put(l, "level_db", usm_json_real(pt->lines[k].level_db), &lok);
        usm_json_put(l, "amplitude", usm_json_real(pt->lines[k].amplitude), &lok);
        if (!lok || json_array_append_new(lines, l) != 0)
            ok = 0;
    }
    usm_json_put(o, "lines", lines, &ok);
    usm_json_put(o, "bin", usm_json_real(pt->df), &ok);
    usm_json_put(o, "rotor_speed_mean", usm_json_real(pt->rotor_speed_mean), &ok);
    usm_json_put(o, "rotor_speed_ripple", usm_json_real(pt->rotor_speed_ripple), &ok);
    usm_json_put(o, "theta_mean", usm_json_real(pt->theta_mean), &ok);
    usm_json_put(o, "open_fraction", usm_json_real(pt->open_fraction), &ok);
    usm_json_put(o, "impacts_per_period", usm_json_real(pt->impacts_per_period), &ok);
    usm_json_put(o, "impact_velocity_max", usm_json_real(pt->impact_velocity_max), &ok);
    if (pt->power.periods > 0) {
        const usm_squeal_power *w = &pt->power;
        json_t *pw = json_object();
        int pok = pw != NULL;
        usm_json_put(pw, "excitation", usm_json_real(w->excitation), &pok);
        usm_json_put(pw, "damping", usm_json_real(w->damping), &pok);
        usm_json_put(pw, "load", usm_json_real(w->load), &pok);
        usm_json_put(pw, "friction", usm_json_real(w->friction), &pok);
        usm_json_put(pw, "friction_stator", usm_json_real(w->friction_stator), &pok);
        usm_json_put(pw, "friction_rotor", usm_json_real(w->friction_rotor), &pok);
        usm_json_put(pw, "normal_stator", usm_json_real(w->normal_stator), &pok);
        usm_json_put(pw, "impacts", usm_json_real(w->impacts_power), &pok);
        usm_json_put(pw, "periods", json_integer(w->periods), &pok);
        usm_json_put(o, "power", usm_json_finish(pw, pok), &ok);
        usm_json_put(o, "energy_balance_error", usm_json_real(w->balance_error), &ok);
    } else {
        usm_json_put(o, "power", json_null(), &ok);
        usm_json_put(o, "energy_balance_error", json_null(), &ok);
    }
    if (pt->rest_checked) {
        json_t *r = json_object();
        int rok = r != NULL;
        usm_json_put(r, "motion", json_string(usm_motion_name(pt->rest_motion)), &rok);
        usm_json_put(r, "period", json_integer(pt->rest_period), &rok);
        usm_json_put(r, "rotor_speed_mean", usm_json_real(pt->rest_speed_mean), &rok);
        usm_json_put(o, "from_rest", usm_json_finish(r, rok), &ok);
    } else
        usm_json_put(o, "from_rest", json_null(), &ok);
    usm_json_put(o, "coexisting", json_boolean(pt->coexisting), &ok);
    usm_json_put(o, "error", pt->status == USM_OK ? json_null() : json_string(pt->message), &ok);
    usm_json_put(o, "seconds", usm_json_real(pt->seconds), &ok);
    return usm_json_finish(o, ok);
}

/* "origin": the end of the period-1 branch in the range (usm_squeal_origin). */
static json_t *origin_json(const usm_squeal_study *s)
{
    const usm_squeal_origin *g = usm_squeal_origin_get(s);
    json_t *o = json_object();
    int ok = o != NULL;
    if (!o || !g)
        return o;
    usm_json_put(o, "found", json_boolean(g->found), &ok);
    if (!g->found) {
        usm_json_put(o, "message", json_string(g->message), &ok);
        return usm_json_finish(o, ok);
    }
    usm_json_put(o, "value", usm_json_real(g->value), &ok);
    usm_json_put(o, "next_value", usm_json_real(g->next_value), &ok);
    usm_json_put(o, "kind", json_string(g->kind), &ok);
    usm_json_put(o, "max_modulus", usm_json_real(g->max_modulus), &ok);
    usm_json_put(o, "multiplier_re", usm_json_real(g->multiplier_re), &ok);
    usm_json_put(o, "multiplier_im", usm_json_real(g->multiplier_im), &ok);
    usm_json_put(o, "separation_fraction", usm_json_real(g->separation_fraction), &ok);
    usm_json_put(o, "impacts_per_period", json_integer(g->impacts_per_period), &ok);
    usm_json_put(o, "mode_sequence", json_string(g->mode_sequence), &ok);
    json_t *part = json_object();
    for (int k = 0; part && k < g->ndof; ++k)
        usm_json_put(part, g->dof[k], usm_json_real(g->share[k]), &ok);
    usm_json_put(o, "participation", part, &ok);
    return usm_json_finish(o, ok);
}

/* "onset": the end of the stable orbit located and its sensitivities
 * (usm_squeal_onset); null when not computed. */
static json_t *onset_json(const usm_squeal_study *s)
{
    const usm_squeal_onset *g = usm_squeal_onset_get(s);
    if (!g)
        return json_null();
    json_t *o = json_object();
    int ok = o != NULL;
    if (!o)
        return NULL;
    usm_json_put(o, "found", json_boolean(g->found), &ok);
    usm_json_put(o, "message", g->found ? json_null() : json_string(g->message), &ok);
    usm_json_put(o, "value", usm_json_real(g->value), &ok);
    usm_json_put(o, "kind", json_string(g->kind), &ok);
    usm_json_put(o, "last_orbit", usm_json_real(g->found ? g->last_orbit : NAN), &ok);
    usm_json_put(o, "closed_fraction", usm_json_real(g->found ? g->closed_fraction : NAN), &ok);
    usm_json_put(o, "solves", json_integer(g->solves), &ok);
    json_t *arr = json_array();
    for (int k = 0; arr && k < g->nsens; ++k) {
        const usm_squeal_sensitivity *v = &g->sens[k];
        json_t *e = json_object();
        int eok = e != NULL;
        usm_json_put(e, "parameter", json_string(v->parameter), &eok);
        usm_json_put(e, "d_onset", usm_json_real(v->d_onset), &eok);
        usm_json_put(e, "elasticity", usm_json_real(v->elasticity), &eok);
        usm_json_put(e, "h", usm_json_real(v->h), &eok);
        usm_json_put(e, "resolution", usm_json_real(v->resolution), &eok);
        usm_json_put(e, "error", v->message[0] ? json_string(v->message) : json_null(), &eok);
        if (!eok || json_array_append_new(arr, e) != 0)
            ok = 0;
    }
    usm_json_put(o, "sensitivities", arr, &ok);
    usm_json_put(o, "most_sensitive",
                 g->most_sensitive[0] ? json_string(g->most_sensitive) : json_null(), &ok);
    return usm_json_finish(o, ok);
}

int usm_squeal_write_json(const usm_squeal_study *s, FILE *out)
{
    json_t *obj = json_object();
    int ok = obj != NULL;
    if (!obj)
        return -1;
    usm_json_put(obj, "model", json_string(usm_squeal_model(s)->name), &ok);
    usm_json_put(obj, "over", json_string(usm_squeal_over(s)), &ok);
    usm_json_put(obj, "sound_source", json_string("stator rim's axial velocity at the contact "
                                                  "point, (R cos theta - H sin theta) thetadot "
                                                  "[m/s]; level dB re 1e-9 m/s RMS"), &ok);
    json_t *points = json_array();
    for (size_t i = 0; points && i < usm_squeal_count(s); ++i) {
        json_t *p = point_json(s, i);
        if (!p || json_array_append_new(points, p) != 0)
            ok = 0;
    }
    usm_json_put(obj, "points", points, &ok);
    usm_json_put(obj, "origin", origin_json(s), &ok);
    usm_json_put(obj, "onset", onset_json(s), &ok);
    return usm_json_write(usm_json_finish(obj, ok), out);
}

/* The varied parameter's column header: NAME [unit] (the display's
 * conversion reads the unit there). */
static void over_header(const usm_squeal_study *s, FILE *out)
{
    const usm_param_info *info = usm_params_find(usm_squeal_over(s));
    fprintf(out, "%s [%s]", usm_squeal_over(s), info && info->unit[0] ? info->unit : "1");
}

int usm_squeal_write_csv(const usm_squeal_study *s, FILE *out)
{
    over_header(s, out);
    fprintf(out, ",motion,period,second_frequency [Hz],lyapunov [1/s],lyapunov_per_period [1],"
                 "rotor_speed_mean [1/s],rotor_speed_ripple [1/s],theta_mean [rad],"
                 "open_fraction [1],impacts_per_period [1],impact_velocity_max [m/s]");
    for (int k = 1; k <= CSV_LINES; ++k)
        fprintf(out, ",line_%d [Hz],level_%d [dB]", k, k);
    fputs(",power_excitation [W],power_damping [W],power_load [W],power_friction [W],"
          "power_friction_stator [W],power_impacts [W],energy_balance_error [1]", out);
    fputs(",rest_motion,coexisting,error,seconds [s]\n", out);
    for (size_t i = 0; i < usm_squeal_count(s); ++i) {
        const usm_squeal_point *pt = usm_squeal_point_at(s, i);
        usm_csv_num(out, 1, pt->value);
        usm_csv_text(out, 0, usm_motion_name(pt->motion));
        fprintf(out, ",%d", pt->period);
        const double v[] = {pt->second_frequency, pt->lyapunov, pt->lyapunov_per_period,
                            pt->rotor_speed_mean, pt->rotor_speed_ripple, pt->theta_mean,
                            pt->open_fraction, pt->impacts_per_period, pt->impact_velocity_max};
        for (size_t k = 0; k < sizeof v / sizeof v[0]; ++k) {
            if (pt->status == USM_OK && pt->motion != USM_MOTION_REST && v[k] == v[k])
                usm_csv_num(out, 0, v[k]);
            else
                fputc(',', out);
        }
        for (size_t k = 0; k < CSV_LINES; ++k) {
            if (k < pt->nlines) {
                usm_csv_num(out, 0, pt->lines[k].frequency);
                usm_csv_num(out, 0, pt->lines[k].level_db);
            } else
                fputs(",,", out);
        }
        const usm_squeal_power *w = &pt->power;
        const double pw[] = {w->excitation,      w->damping,       w->load,         w->friction,
                             w->friction_stator, w->impacts_power, w->balance_error};
        for (size_t k = 0; k < sizeof pw / sizeof pw[0]; ++k) {
            if (pt->status == USM_OK && w->periods > 0)
                usm_csv_num(out, 0, pw[k]);
            else
                fputc(',', out);
        }
        usm_csv_text(out, 0, pt->rest_checked ? usm_motion_name(pt->rest_motion) : "");
        usm_csv_bool(out, 0, pt->coexisting);
        usm_csv_text(out, 0, pt->status == USM_OK ? "" : pt->message);
        usm_csv_num(out, 0, pt->seconds);
        fputc('\n', out);
    }
    return ferror(out) ? -1 : 0;
}

int usm_squeal_write_strobe_csv(const usm_squeal_study *s, FILE *out)
{
    over_header(s, out);
    fputs(",k,rotor_speed [1/s],theta [rad],gap [m]\n", out);
    for (size_t i = 0; i < usm_squeal_count(s); ++i) {
        size_t n;
        const double *w, *th, *g;
        if (usm_squeal_strobe(s, i, &n, &w, &th, &g) != 0)
            continue;
        const double v = usm_squeal_point_at(s, i)->value;
        for (size_t j = 0; j < n; ++j) {
            usm_csv_num(out, 1, v);
            fprintf(out, ",%zu", j);
            usm_csv_num(out, 0, w[j]);
            usm_csv_num(out, 0, th[j]);
            usm_csv_num(out, 0, g[j]);
            fputc('\n', out);
        }
    }
    return ferror(out) ? -1 : 0;
}

int usm_squeal_write_plot_csv(const usm_squeal_study *s, FILE *out)
{
    over_header(s, out);
    fputs(",k,rotor_speed [1/s],theta [rad],frequency [Hz],level_db [dB]\n", out);
    for (size_t i = 0; i < usm_squeal_count(s); ++i) {
        const usm_squeal_point *pt = usm_squeal_point_at(s, i);
        size_t n;
        const double *w, *th, *g;
        if (usm_squeal_strobe(s, i, &n, &w, &th, &g) == 0)
            for (size_t j = 0; j < n; ++j) {
                usm_csv_num(out, 1, pt->value);
                fprintf(out, ",%zu", j);
                usm_csv_num(out, 0, w[j]);
                usm_csv_num(out, 0, th[j]);
                fputs(",,\n", out);
            }
        for (size_t k = 0; k < pt->nlines; ++k) {
            usm_csv_num(out, 1, pt->value);
            fputs(",,,", out);
            usm_csv_num(out, 0, pt->lines[k].frequency);
            usm_csv_num(out, 0, pt->lines[k].level_db);
            fputc('\n', out);
        }
    }
    return ferror(out) ? -1 : 0;
}
