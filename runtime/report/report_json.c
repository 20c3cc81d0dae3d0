/* report.json: every number the report shows, by name, SI units unless the
 * key names another (kHz, Nmm, mNm: the units report.md prints).  report.md
 * and report.html are rendered from it by templates (data/report/). */
#include <math.h>
#include <string.h>

#include "report_internal.h"

#ifndef USM_VERSION
#define USM_VERSION "unknown"
#endif

#define TWO_PI 6.283185307179586476925286766559
#define PI 3.14159265358979323846264338327950

static const char *const tag[REPORT_NMODELS] = {"3dof", "4dof"};

/* a number, or null where it does not exist */
static void num(json_t *o, const char *key, double v)
{
    json_object_set_new(o, key, isfinite(v) ? json_real(v) : json_null());
}

static void str(json_t *o, const char *key, const char *s)
{
    json_object_set_new(o, key, json_string(s ? s : ""));
}

static void flag(json_t *o, const char *key, int b)
{
    json_object_set_new(o, key, json_boolean(b));
}

static void integer(json_t *o, const char *key, long long v)
{
    json_object_set_new(o, key, json_integer(v));
}

/* The multipliers, a conjugate pair once ("pair": re ± im i). */
static json_t *multipliers(const usm_floquet_result *r)
{
    json_t *a = json_array();
    for (int k = 0; k < r->n; ++k) {
        json_t *m = json_object();
        const int pair = r->im[k] > 0 && k + 1 < r->n && r->im[k + 1] == -r->im[k] &&
                         r->re[k + 1] == r->re[k];
        num(m, "re", r->re[k]);
        num(m, "im", r->im[k]);
        num(m, "im_abs", fabs(r->im[k]));
        num(m, "modulus", hypot(r->re[k], r->im[k]));
        flag(m, "pair", pair);
        flag(m, "single", !pair && r->im[k] != 0);
        str(m, "sign", r->im[k] < 0 ? "-" : "+");
        flag(m, "cyclic", r->cyclic[k]);
        json_array_append_new(a, m);
        k += pair;
    }
    return a;
}

static json_t *floquet(const usm_floquet_result *r, const char *label, double distance)
{
    json_t *o = json_object();
    str(o, "label", label);
    num(o, "max_modulus", r->max_modulus);
    flag(o, "stable", r->stable);
    flag(o, "t0_dependent", r->t0_dependent);
    num(o, "distance", distance);
    json_object_set_new(o, "multipliers", multipliers(r));
    return o;
}

static json_t *solution(const usm_steady_solution *s, double f)
{
    json_t *o = json_object();
    num(o, "theta", s->theta);
    num(o, "alpha", s->alpha);
    num(o, "beta", s->beta);
    num(o, "beta_plus_pi", s->beta + PI);
    num(o, "rotor_speed", s->rotor_speed);
    num(o, "speed", -s->rotor_speed);
    num(o, "F_n", s->F_n);
    num(o, "F_t", s->F_t);
    num(o, "R_star", s->R_star);
    num(o, "v_rel", s->v_rel);
    num(o, "mu_used", s->mu_used);
    flag(o, "stick_admissible", s->stick_admissible);
    num(o, "contact_moment_mNm", s->F_n * s->R_star * 1e3);
    num(o, "speed_ratio", TWO_PI * f / fabs(s->rotor_speed));
    num(o, "power_in", s->power_in);
    num(o, "power_out", s->power_out);
    num(o, "power_damping", s->power_damping);
    num(o, "power_slip", s->power_slip);
    num(o, "efficiency", s->efficiency);
    return o;
}

/* A located value: SI "value", the same in the report's unit, the solution there. */
/* A located value: SI "value", the same in the report's unit, the solution
 * there (only when one exists there: has_solution), the event it is
 * ("event", and "by.NAME" true for that event's name only, so the template
 * can say what ends a branch), or ok = false and a note saying what was
 * searched. */
static json_t *located(const usm_report_located *l, const char *unit, double scale)
{
    json_t *o = l->ok && l->has_sol ? solution(&l->sol, NAN) : json_object(), *by = json_object();
    flag(o, "ok", l->ok);
    flag(o, "has_solution", l->ok && l->has_sol);
    num(o, "value", l->ok ? l->value : NAN);
    num(o, unit, l->ok ? l->value * scale : NAN);
    num(o, "range_from", l->from * scale);
    num(o, "range_to", l->to * scale);
    str(o, "event", l->ok ? usm_event_name(l->type) : "");
    for (int t = USM_EVENT_FOLD; t <= USM_EVENT_CROSSING; ++t)
        flag(by, usm_event_name((usm_event_type)t), l->ok && l->type == (usm_event_type)t);
    json_object_set_new(o, "by", by);
    str(o, "note", l->note);
    return o;
}

static json_t *model(const usm_report_data *d, int k)
{
    const usm_report_model_result *r = &d->model[k];
    const usm_report_paper *pv = &d->paper;
    const usm_report_published_multiplier *t = k == REPORT_3DOF ? pv->table3 : pv->table4;
    const int nt = k == REPORT_3DOF ? pv->n3 : pv->n4;
    json_t *o = solution(&r->sol, d->params.f), *t0 = json_array(), *in = json_array();
    str(o, "name", r->model->name);
    for (int i = 0; i < REPORT_NT0; ++i)
        json_array_append_new(t0, floquet(&r->fl[i], usm_report_t0_label[i],
                                          usm_report_table_distance(t, nt, &r->fl[i], k == REPORT_4DOF)));
    for (int i = 0; r->integrated && i < 2; ++i)
        json_array_append_new(in, floquet(&r->fl_integrated[i], i ? "T/2" : "0",
                                          usm_report_table_distance(t, nt, &r->fl_integrated[i],
                                                         k == REPORT_4DOF)));
    json_object_set_new(o, "t0", t0);
    json_object_set_new(o, "integrated", in);
    return o;
}

/* Section 2's multiplier rows: each published value beside its nearest. */
static json_t *table_rows(const usm_report_published_multiplier *t, int nt,
                          const usm_floquet_result *r, int table4)
{
    json_t *a = json_array();
    int used[USM_MAX_NX] = {0};
    for (int k = 0; k < nt; ++k) {
        int j = usm_report_match_multiplier(r, t[k].re, t[k].im, used);
        json_t *o;
        double mod, dl;
        if (j < 0)
            continue;
        if (t[k].im > 0) /* its conjugate is taken too */
            (void)usm_report_match_multiplier(r, t[k].re, -t[k].im, used);
        mod = hypot(r->re[j], r->im[j]);
        dl = hypot(r->re[j] - t[k].re, fabs(r->im[j]) - t[k].im);
        o = json_object();
        str(o, "label", t[k].label);
        str(o, "printed", t[k].printed);
        str(o, "modulus_printed", t[k].modulus_printed);
        num(o, "re", r->re[j]);
        num(o, "im", fabs(r->im[j]));
        num(o, "modulus", mod);
        flag(o, "cyclic", r->cyclic[j]);
        num(o, "dlambda", dl);
        num(o, "dmodulus", mod - t[k].modulus);
        str(o, "verdict", table4 && k == 0 ? "**differs**, (c)" : dl > 2e-3 ? "**differs**"
                                                                            : "agrees");
        json_array_append_new(a, o);
    }
    return a;
}

static json_t *compare(const usm_report_data *d)
{
    const usm_report_paper *pv = &d->paper;
    const usm_report_model_result *r3 = &d->model[REPORT_3DOF], *r4 = &d->model[REPORT_4DOF];
    const usm_steady_solution *s3 = &r3->sol, *s4 = &r4->sol;
    const usm_floquet_result *fl4 = &r4->fl[0];
    int used[USM_MAX_NX] = {0};
    const int j = usm_report_match_multiplier(fl4, pv->table4[0].re, pv->table4[0].im, used);
    const double mod_c = j >= 0 ? hypot(fl4->re[j], fl4->im[j]) : NAN;
    json_t *o = json_object();
    num(o, "theta3_rel", s3->theta / pv->theta3.value - 1);
    num(o, "alpha3_diff", s3->alpha - pv->alpha3.value);
    num(o, "alpha3_printed_as_rad", pv->alpha3.value * PI / 180);
    num(o, "beta3_diff", s3->beta + PI - pv->beta3.value);
    num(o, "speed4_diff", s4->rotor_speed - pv->speed4.value);
    num(o, "theta4_rel", s4->theta / pv->theta4.value - 1);
    num(o, "alpha4_diff", s4->alpha - pv->alpha4.value);
    num(o, "beta4_diff", s4->beta - pv->beta4.value);
    json_object_set_new(o, "table3", table_rows(pv->table3, pv->n3, &r3->fl[0], 0));
    json_object_set_new(o, "table4", table_rows(pv->table4, pv->n4, fl4, 1));
    str(o, "stable_verdict", r3->fl[0].stable && fl4->stable ? "agrees" : "**differs**");
    num(o, "f_max_diff", d->f_max[0].ok ? d->f_max[0].value - pv->f_max.value : NAN);
    num(o, "f_max_diff_percent",
        d->f_max[0].ok ? 100 * (d->f_max[0].value / pv->f_max.value - 1) : NAN);
    num(o, "stick_limit_diff_Nmm",
        d->stick_limit.ok ? (d->stick_limit.value - pv->slip_load.value) * 1e3 : NAN);
    num(o, "stick_limit_sat_diff_Nmm",
        d->stick_limit_sat.ok ? (d->stick_limit_sat.value - pv->slip_load.value) * 1e3 : NAN);
    num(o, "existence_T_3dof_diff_Nmm",
        d->existence_T[0].ok ? (d->existence_T[0].value - pv->slip_load.value) * 1e3 : NAN);
    num(o, "small_angle_speed", d->params.H * s3->theta * TWO_PI * d->params.f / d->params.R);
    /* (c): Table 4's first pair */
    num(o, "table4_first_re", j >= 0 ? fl4->re[j] : NAN);
    num(o, "table4_first_im", j >= 0 ? fabs(fl4->im[j]) : NAN);
    num(o, "table4_first_modulus", mod_c);
    num(o, "table4_first_angle", j >= 0 ? atan2(fabs(fl4->im[j]), fl4->re[j]) : NAN);
    num(o, "table4_first_angle_paper", atan2(pv->table4[0].im, pv->table4[0].re));
    num(o, "table4_first_modulus_percent", 100 * (mod_c / pv->table4[0].modulus - 1));
    num(o, "tables_distance_others",
        fmax(usm_report_table_distance(pv->table3, pv->n3, &r3->fl[0], 0),
             usm_report_table_distance(pv->table4, pv->n4, fl4, 1)));
    /* (e): the friction coefficient the paper's slip load would need */
    num(o, "mu_needed", pv->slip_load.value / (s3->R_star * s3->F_n));
    return o;
}

/* Whether parameter k is one of the imperfections (amp_imbalance, ...). */
static int is_imperfection(int k)
{
    for (int j = 0; j < USM_NIMPERFECTIONS; ++j)
        if (usm_param_imperfections[j] == k)
            return 1;
    return 0;
}

static json_t *params(const usm_report_data *d)
{
    json_t *a = json_array();
    usm_params def;
    usm_params_default(&def);
    for (int k = 0; k < USM_NPARAMS; ++k) {
        const usm_param_info *info = &usm_param_table[k];
        const double v = usm_params_get(&d->params, info);
        json_t *o = json_object();
        const char *source = is_imperfection(k)
            ? "**not in the paper**: chosen by usm, 0 (the ideal motor the paper models; "
              "set with `--set` for the non-ideal motor of section 9)"
            : k == USM_P_f ? "**not in the paper**: chosen, see below"
            : k == USM_P_M ? "**not in the paper**: 2 I_R / R^2, see below"
            : k == USM_P_mu0 || k == USM_P_kappa ? "Sec. 5 text"
            : k == USM_P_e_impact
                ? "**not in the paper**: usm's assumption (the restitution of the impacts of "
                  "the unilateral contact, variant `imperfect_unilateral`; the paper's contact "
                  "never opens)"
            : "Appendix A, Table 5";
        str(o, "name", info->name);
        num(o, "value", v);
        str(o, "unit", info->unit);
        str(o, "description", info->description);
        str(o, "source", v == usm_params_get(&def, info) ? source
                                                         : "**changed** (`--set`/`--params`)");
        json_array_append_new(a, o);
    }
    return a;
}

static json_t *choices(const usm_report_data *d)
{
    json_t *o = json_object(), *dev = json_array();
    num(o, "f_kHz", d->params.f / 1000);
    num(o, "f_from_cr", d->f_from_cr);
    num(o, "f_from_cr_kHz", d->f_from_cr / 1000);
    num(o, "dr_3pct", d->dr_3pct);
    num(o, "dt_3pct", d->dt_3pct);
    num(o, "M_disk", d->M_disk);
    num(o, "M_from_dR", d->M_from_dR);
    num(o, "theta_at_fmax_paper", d->theta_at_fmax_paper);
    num(o, "m0_mNm", d->params.m0 * 1e3);
    num(o, "small_F0", REPORT_SMALL_F0);
    for (int i = 0; i < 3; ++i)
        json_array_append_new(dev, isfinite(d->M_trial_dev[i]) ? json_real(d->M_trial_dev[i])
                                                               : json_null());
    json_object_set_new(o, "M_trial_dev", dev);
    return o;
}

static json_t *figure(int fig)
{
    json_t *o = json_object(), *files = json_array();
    const char *name = usm_report_figures[fig].name;
    const size_t len = strlen(name);
    str(o, "name", name);
    str(o, "title", usm_report_figures[fig].title);
    for (int k = 0; usm_report_files[k]; ++k)
        if (strncmp(usm_report_files[k], name, len) == 0 &&
            (usm_report_files[k][len] == '.' || usm_report_files[k][len] == '_'))
            json_array_append_new(files, json_string(usm_report_files[k]));
    json_object_set_new(o, "files", files);
    return o;
}

static json_t *figures(int from, int to)
{
    json_t *a = json_array();
    for (int i = from; i < to; ++i)
        json_array_append_new(a, figure(i));
    return a;
}

/* One end of a valid range: SI value and why it ends there. */
typedef struct valid_end {
    double value;
    const char *by; /* "range" (the curve's end), "stick_limit" (the event),
                     * "no_solution", or the first invalid point's reason
                     * ("contact_open", "stick_not_admissible": located to the grid) */
} valid_end;

static const char *valid_phrase(const char *by)
{
    return strcmp(by, "stick_limit") == 0    ? "stick limit F_t = mu0 F_n"
           : strcmp(by, "no_solution") == 0  ? "end of the solution branch"
           : strcmp(by, "contact_open") == 0 ? "the contact opens beyond, to the grid"
                                             : "stick not admissible beyond, to the grid";
}

/* Between the valid grid value a and the invalid b: the stick_limit event
 * located between them, else a (the grid's resolution). */
static valid_end valid_boundary(const usm_sweep *sw, double a, const usm_steady_solution *bad,
                                double b)
{
    valid_end e = {a, usm_validity_name(bad->validity)};
    for (size_t i = 0; i < usm_sweep_event_count(sw); ++i) {
        const usm_sweep_event *ev = usm_sweep_event_at(sw, i);
        if (ev->type == USM_EVENT_STICK_LIMIT && bad->validity == USM_INVALID_STICK &&
            fmin(a, b) <= ev->value && ev->value <= fmax(a, b)) {
            e.value = ev->value;
            e.by = "stick_limit";
        }
    }
    return e;
}

/* Where a curve's model describes the motor (usm_steady_solution.validity):
 * {all, none, intervals: [{from, to, from_by, to_by}] in increasing order,
 * text}: an end between a valid and an invalid grid point is the sweep's
 * stick_limit event there, else the last valid grid point.  text in the
 * report's units (scale, unit). */
static json_t *valid_ranges(const usm_sweep *sw, const char *name, const char *unit, double scale)
{
    json_t *o = json_object(), *iv = json_array();
    const size_t n = sw ? usm_sweep_count(sw) : 0;
    const int down = n > 1 && usm_sweep_point_at(sw, n - 1)->value < usm_sweep_point_at(sw, 0)->value;
    char text[1024] = "";
    size_t len = 0;
    int open = 0, nvalid = 0, ninvalid = 0;
    valid_end from = {0, "range"};
    const usm_sweep_point *prev = NULL; /* the previous point in increasing order */
    for (size_t q = 0; q <= n; ++q) {
        const usm_sweep_point *pt = q < n ? usm_sweep_point_at(sw, down ? n - 1 - q : q) : NULL;
        const int valid = pt && pt->converged && pt->sol.validity == USM_VALID;
        if (pt && pt->converged)
            valid ? ++nvalid : ++ninvalid;
        if (valid && !open) {
            open = 1;
            from = (valid_end){pt->value, "range"};
            if (prev && !prev->converged)
                from.by = "no_solution";
            else if (prev)
                from = valid_boundary(sw, pt->value, &prev->sol, prev->value);
        } else if (!valid && open) {
            open = 0;
            valid_end to = {prev->value, !pt ? "range" : !pt->converged ? "no_solution" : ""};
            if (pt && pt->converged)
                to = valid_boundary(sw, prev->value, &pt->sol, pt->value);
            json_t *r = json_object();
            num(r, "from", from.value);
            num(r, "to", to.value);
            str(r, "from_by", from.by);
            str(r, "to_by", to.by);
            json_array_append_new(iv, r);
            /* the ends that validity sets (not the curve's or the branch's end) */
            const int a = strcmp(from.by, "range") != 0 && strcmp(from.by, "no_solution") != 0;
            const int b = strcmp(to.by, "range") != 0 && strcmp(to.by, "no_solution") != 0;
            const int gap = !a && !b && (strcmp(from.by, "no_solution") == 0 ||
                                         strcmp(to.by, "no_solution") == 0);
            if (len < sizeof text)
                len += (size_t)snprintf(text + len, sizeof text - len, "%s", len ? "; " : "");
            if (len < sizeof text && !a && !b)
                len += (size_t)snprintf(text + len, sizeof text - len,
                                        "valid %s (%s from %.4g to %.4g %s)",
                                        gap ? "wherever a solution exists" : "over the whole curve",
                                        name, from.value * scale, to.value * scale, unit);
            else if (len < sizeof text && !a)
                len += (size_t)snprintf(text + len, sizeof text - len, "valid for %s <= %.4g %s (%s)",
                                        name, to.value * scale, unit, valid_phrase(to.by));
            else if (len < sizeof text && !b)
                len += (size_t)snprintf(text + len, sizeof text - len, "valid for %s >= %.4g %s (%s)",
                                        name, from.value * scale, unit, valid_phrase(from.by));
            else if (len < sizeof text)
                len += (size_t)snprintf(text + len, sizeof text - len,
                                        "valid for %.4g <= %s <= %.4g %s (%s; %s)",
                                        from.value * scale, name, to.value * scale, unit,
                                        valid_phrase(from.by), valid_phrase(to.by));
        }
        prev = pt;
    }
    if (nvalid == 0)
        snprintf(text, sizeof text, "%s", ninvalid ? "not valid anywhere on the curve"
                                                   : "no solution on the curve");
    flag(o, "all", nvalid > 0 && ninvalid == 0);
    flag(o, "none", nvalid == 0);
    json_object_set_new(o, "intervals", iv);
    str(o, "text", text);
    return o;
}

static json_t *characteristics(const usm_report_data *d)
{
    static const char *const cname[REPORT_NCURVES] = {"f [Hz]", "T [N m]", "m0 [N m]"};
    static const char *const vname[REPORT_NCURVES] = {"f", "T", "m0"};
    static const char *const vunit[REPORT_NCURVES] = {"kHz", "N mm", "mN m"};
    static const double vscale[REPORT_NCURVES] = {1e-3, 1e3, 1e3};
    json_t *o = json_object(), *curves = json_array(), *loc = json_object();
    integer(o, "points_min", d->curve[REPORT_CURVE_T][REPORT_4DOF].points);
    integer(o, "points_max", d->curve[REPORT_CURVE_F][0].points);
    for (int c = 0; c < REPORT_NCURVES; ++c)
        for (int k = 0; k < REPORT_NMODELS; ++k) {
            const usm_sweep *sw = d->curve[c][k].sweep;
            const size_t n = sw ? usm_sweep_event_count(sw) : 0;
            json_t *cv = json_object(), *ev = json_array();
            str(cv, "curve", cname[c]);
            str(cv, "over", d->curve[c][k].over);
            str(cv, "model", d->model[k].model->name);
            for (size_t i = 0; i < n; ++i) {
                const usm_sweep_event *e = usm_sweep_event_at(sw, i);
                json_t *eo = json_object();
                str(eo, "event", usm_event_name(e->type));
                num(eo, "at", e->value);
                str(eo, "what", e->what);
                json_array_append_new(ev, eo);
            }
            json_object_set_new(cv, "events", ev);
            json_object_set_new(cv, "valid", valid_ranges(sw, vname[c], vunit[c], vscale[c]));
            json_array_append_new(curves, cv);
        }
    json_object_set_new(o, "curves", curves);
    for (int k = 0; k < REPORT_NMODELS; ++k) {
        char key[64];
        snprintf(key, sizeof key, "f_max_%s", tag[k]);
        json_object_set_new(loc, key, located(&d->f_max[k], "kHz", 1e-3));
        snprintf(key, sizeof key, "existence_T_%s", tag[k]);
        json_object_set_new(loc, key, located(&d->existence_T[k], "Nmm", 1e3));
        snprintf(key, sizeof key, "existence_m0_%s", tag[k]);
        json_object_set_new(loc, key, located(&d->existence_m0[k], "mNm", 1e3));
    }
    json_object_set_new(loc, "f_theta_max", located(&d->f_theta_max, "kHz", 1e-3));
    json_object_set_new(loc, "f_theta_max_small_F0",
                        located(&d->f_theta_max_small_F0, "kHz", 1e-3));
    json_object_set_new(loc, "stick_limit", located(&d->stick_limit, "Nmm", 1e3));
    json_object_set_new(loc, "stick_limit_sat", located(&d->stick_limit_sat, "Nmm", 1e3));
    json_object_set_new(loc, "stability_T", located(&d->stability_T, "Nmm", 1e3));
    json_object_set_new(o, "located", loc);
    return o;
}

/* The classes of a map's cells by their operating point (usm_point_op_class),
 * as the map's CSV names them (op_class) and its figure labels them
 * (data/plots/map_3dof.gp, map_4dof.gp). */
static const struct {
    usm_point_op_class cls;
    const char *label;
} map_class[] = {{USM_POINT_OP_STABLE, "operating point"},
                 {USM_POINT_OP_NO_STABLE_ROOT, "no stable root"},
                 {USM_POINT_OP_DOES_NOT_START, "does not start from rest"},
                 {USM_POINT_OP_UNKNOWN, "unknown"},
                 {USM_POINT_OP_NO_SOLUTION, "no stationary solution"}};
#define NMAP_CLASS (sizeof map_class / sizeof map_class[0])

static json_t *map_summary(const usm_report_map *m, int fig)
{
    const size_t n = (size_t)m->x.points * (size_t)m->y.points;
    size_t exist = 0, unstable = 0, unstable_stick = 0, invalid = 0, several = 0;
    size_t count[NMAP_CLASS] = {0}, other = 0;
    double maxmod = 0, maxmod_stick = 0, op_maxmod = NAN;
    json_t *o = figure(fig), *classes = json_object();
    char absent[160] = "";
    for (size_t q = 0; q < n; ++q) {
        const usm_report_map_cell *c = &m->cells[q];
        size_t k = 0;
        while (k < NMAP_CLASS && (int)map_class[k].cls != c->op_class)
            ++k;
        if (k < NMAP_CLASS)
            ++count[k];
        else
            ++other; /* not evaluated: the report always asks (usm_map_options) */
        if (c->op_index >= 0)
            op_maxmod = isnan(op_maxmod) ? c->op_max_modulus : fmax(op_maxmod, c->op_max_modulus);
        several += c->roots > 1;
        if (!c->exists)
            continue;
        invalid += c->validity != USM_VALID;
        ++exist;
        if (c->floquet_ok) {
            maxmod = fmax(maxmod, c->max_modulus);
            unstable += !c->stable;
            if (c->stick_admissible) {
                maxmod_stick = fmax(maxmod_stick, c->max_modulus);
                unstable_stick += !c->stable;
            }
        }
    }
    str(o, "model", m->model->name);
    integer(o, "x_points", m->x.points);
    integer(o, "y_points", m->y.points);
    num(o, "f_from_kHz", m->x.from / 1000);
    num(o, "f_to_kHz", m->x.to / 1000);
    num(o, "T_from_Nmm", m->y.from * 1e3);
    num(o, "T_to_Nmm", m->y.to * 1e3);
    integer(o, "points", (long long)n);
    integer(o, "exist", (long long)exist);
    integer(o, "unstable", (long long)unstable);
    num(o, "max_modulus", maxmod);
    integer(o, "unstable_stick", (long long)unstable_stick);
    num(o, "max_modulus_stick", maxmod_stick);
    flag(o, "floquet_failures", m->floquet_failures != 0);
    /* by the operating point: cells per class, and the absent ones */
    for (size_t k = 0; k < NMAP_CLASS; ++k) {
        integer(classes, usm_point_op_class_name(map_class[k].cls), (long long)count[k]);
        if (!count[k])
            snprintf(absent + strlen(absent), sizeof absent - strlen(absent), "%s%s",
                     absent[0] ? ", " : "", map_class[k].label);
    }
    integer(classes, "not_evaluated", (long long)other);
    json_object_set_new(o, "classes", classes);
    str(o, "absent", absent);
    num(o, "op_max_modulus", op_maxmod);
    integer(o, "several_roots", (long long)several);
    integer(o, "invalid", (long long)invalid);
    flag(o, "from_rest", m->op && m->op->from_rest);
    str(o, "operating_point_rule", usm_op_rule_text(m->op));
    return o;
}

static json_t *variants(const usm_report_data *d)
{
    json_t *a = json_array();
    for (int k = 0; k < USM_NMODELS; ++k) {
        const usm_report_variant_result *v = &d->variant[k];
        json_t *o = v->ok ? solution(&v->sol, d->params.f) : json_object(), *mm = json_array();
        str(o, "name", v->model->name);
        str(o, "assumptions", v->model->assumptions);
        flag(o, "ok", v->ok);
        str(o, "note", v->note);
        for (int i = 0; v->ok && i < REPORT_NVARIANT_T0; ++i)
            json_array_append_new(mm, isfinite(v->fl[i].max_modulus)
                                          ? json_real(v->fl[i].max_modulus) : json_null());
        json_object_set_new(o, "max_modulus", mm);
        flag(o, "t0_dependent", v->ok && v->fl[0].t0_dependent);
        json_array_append_new(a, o);
    }
    return a;
}

/* The datasheet's key numbers on the grid of the load curve (sweep over T):
 * maxima of efficiency and output power, where they lie, the no-load speed.
 * The maxima only where the model describes the motor (validity: the stick
 * model continued beyond its stick limit no longer does). */
static json_t *datasheet_model(const usm_report_curve *cv)
{
    json_t *o = json_object();
    const size_t n = cv->sweep ? usm_sweep_count(cv->sweep) : 0;
    const usm_sweep_point *best_eta = NULL, *best_p = NULL, *first = NULL;
    int converged = 0;
    for (size_t i = 0; i < n; ++i) {
        const usm_sweep_point *pt = usm_sweep_point_at(cv->sweep, i);
        if (!pt->converged)
            continue;
        ++converged;
        if (!first)
            first = pt;
        if (pt->sol.validity != USM_VALID)
            continue;
        if (isfinite(pt->sol.efficiency) &&
            (!best_eta || pt->sol.efficiency > best_eta->sol.efficiency))
            best_eta = pt;
        if (!best_p || pt->sol.power_out > best_p->sol.power_out)
            best_p = pt;
    }
    integer(o, "points", (long long)n);
    integer(o, "converged", converged);
    num(o, "T_from_Nmm", cv->from * 1e3);
    num(o, "T_to_Nmm", cv->to * 1e3);
    num(o, "speed_first", first ? -first->sol.rotor_speed : NAN);
    num(o, "T_first_Nmm", first ? first->value * 1e3 : NAN);
    num(o, "efficiency_max", best_eta ? best_eta->sol.efficiency : NAN);
    num(o, "efficiency_max_T", best_eta ? best_eta->value : NAN);
    num(o, "efficiency_max_T_Nmm", best_eta ? best_eta->value * 1e3 : NAN);
    num(o, "efficiency_max_speed", best_eta ? -best_eta->sol.rotor_speed : NAN);
    num(o, "efficiency_max_power_out", best_eta ? best_eta->sol.power_out : NAN);
    num(o, "power_out_max", best_p ? best_p->sol.power_out : NAN);
    num(o, "power_out_max_mW", best_p ? best_p->sol.power_out * 1e3 : NAN);
    num(o, "power_out_max_T", best_p ? best_p->value : NAN);
    num(o, "power_out_max_T_Nmm", best_p ? best_p->value * 1e3 : NAN);
    num(o, "power_out_max_efficiency", best_p ? best_p->sol.efficiency : NAN);
    json_object_set_new(o, "valid", valid_ranges(cv->sweep, "T", "N mm", 1e3));
    return o;
}

static json_t *datasheet(const usm_report_data *d)
{
    json_t *o = json_object();
    for (int k = 0; k < REPORT_NMODELS; ++k)
        json_object_set_new(o, tag[k], datasheet_model(&d->curve[REPORT_CURVE_T][k]));
    return o;
}

/* One output's sensitivities: value, every elasticity and derivative by
 * parameter name, and the nonzero ones ranked by magnitude. */
static json_t *sens_output(const usm_report_data *d, int k, int out)
{
    const usm_sensitivity_result *r = &d->sens[k];
    json_t *o = json_object(), *e = json_object(), *dd = json_object(), *ranked = json_array();
    int idx[USM_NPARAMS];
    const int n = d->have_sens[k] ? usm_report_elasticity_order(&d->params, r, out, idx) : 0;
    const int defined = d->have_sens[k] && r->defined[out];
    num(o, "value", d->have_sens[k] ? r->value[out] : NAN);
    flag(o, "defined", defined);
    str(o, "why", !d->have_sens[k] ? d->sens_note[k] : defined ? "" : r->why[out]);
    for (int j = 0; j < USM_NPARAMS; ++j) {
        num(e, usm_param_table[j].name, usm_sensitivity_elasticity(&d->params, r, out, j));
        num(dd, usm_param_table[j].name, defined ? r->d[out][j] : NAN);
    }
    for (int i = 0; i < n; ++i) {
        json_t *x = json_object();
        const double el = usm_sensitivity_elasticity(&d->params, r, out, idx[i]);
        integer(x, "rank", i + 1);
        str(x, "parameter", usm_param_table[idx[i]].name);
        num(x, "elasticity", el);
        num(x, "abs_elasticity", fabs(el));
        num(x, "d", r->d[out][idx[i]]);
        json_array_append_new(ranked, x);
    }
    integer(o, "nonzero", n);
    integer(o, "zero", defined ? USM_NPARAMS - n : 0);
    json_object_set_new(o, "elasticity", e);
    json_object_set_new(o, "d", dd);
    json_object_set_new(o, "ranked", ranked);
    if (out == USM_SENS_MAX_MODULUS && n > 0) {
        /* relative change of the dominant parameter that brings the largest
         * modulus to 1, to first order: (1 - y) / (y e) */
        const double y = r->value[out], el = usm_sensitivity_elasticity(&d->params, r, out, idx[0]);
        num(o, "margin", 1.0 - y);
        num(o, "to_unstable_percent", 100.0 * (1.0 - y) / (y * el));
        num(o, "to_unstable_abs_percent", fabs(100.0 * (1.0 - y) / (y * el)));
    }
    return o;
}

static json_t *sensitivity(const usm_report_data *d)
{
    json_t *o = json_object();
    for (int k = 0; k < REPORT_NMODELS; ++k) {
        json_t *m = json_object();
        flag(m, "ok", d->have_sens[k]);
        str(m, "note", d->sens_note[k]);
        for (int i = 0; i < REPORT_NSENS_OUT; ++i)
            json_object_set_new(m, usm_sensitivity_output_name(usm_report_sens_outputs[i]),
                                sens_output(d, k, usm_report_sens_outputs[i]));
        json_object_set_new(o, tag[k], m);
    }
    return o;
}

/* ---- the non-ideal motor (report_nonideal.c) ---- */

/* A value of an imperfection in the unit the report prints: phase error in
 * degrees, mode split in per cent. */
static double imp_display(int j, double v)
{
    return j == REPORT_IMP_PHASE ? v * 180.0 / PI : v * 100.0;
}

static json_t *nonideal_root(const usm_report_nonideal_root *r, int j)
{
    json_t *o = json_object();
    flag(o, "found", r->found);
    num(o, "value", r->found ? r->value : NAN);
    num(o, "display", r->found ? imp_display(j, r->value) : NAN);
    str(o, "note", r->note);
    /* the times a period, as words for the text: counted on the orbit */
    json_object_set_new(o, "openings", json_integer(r->openings));
    str(o, "openings_text", r->openings == 1   ? "once"
                            : r->openings == 2 ? "twice"
                            : r->openings == 3 ? "three times"
                            : r->openings == 4 ? "four times"
                                               : "several times");
    return o;
}

static json_t *nonideal_curve(const usm_report_nonideal_curve *cv, int j)
{
    json_t *o = json_object(), *t = json_object();
    double ripple = -INFINITY, fnmin = INFINITY, lmax = -INFINITY, lmin = INFINITY;
    int conv = 0;
    for (int q = 0; q < cv->points; ++q) {
        const usm_report_nonideal_point *pt = &cv->pt[q];
        if (!pt->converged)
            continue;
        ++conv;
        ripple = fmax(ripple, pt->ripple);
        fnmin = fmin(fnmin, pt->F_n_min);
        lmax = fmax(lmax, pt->max_modulus);
        lmin = fmin(lmin, pt->max_modulus);
    }
    str(o, "parameter", cv->param);
    str(o, "display_unit", j == REPORT_IMP_PHASE ? "deg" : "%");
    num(o, "from", cv->from);
    num(o, "to", cv->to);
    num(o, "from_display", imp_display(j, cv->from));
    num(o, "to_display", imp_display(j, cv->to));
    integer(o, "points", cv->points);
    integer(o, "converged", conv);
    num(o, "ripple_max", ripple);
    num(o, "F_n_min_min", fnmin);
    num(o, "max_modulus_max", lmax);
    num(o, "max_modulus_min", lmin);
    num(o, "ripple_at_end", cv->pt[cv->points - 1].ripple);
    json_object_set_new(o, "contact_open", nonideal_root(&cv->contact, j));
    json_object_set_new(o, "stability_loss", nonideal_root(&cv->stability, j));
    /* valid_to: found = 0 when the model describes the motor over the whole curve;
     * note: stick_loss, contact_loss (events), or the first invalid point's reason */
    json_object_set_new(o, "valid_to", nonideal_root(&cv->valid_to, j));
    flag(t, "found", cv->tolerable_found);
    num(t, "value", cv->tolerable_found ? cv->tolerable : NAN);
    num(t, "display", cv->tolerable_found ? imp_display(j, cv->tolerable) : NAN);
    str(t, "by", cv->tolerable_by);
    str(t, "by_text", !cv->tolerable_found ? "" :
        strcmp(cv->tolerable_by, "contact") == 0 ? "the contact opening (F_n_min = 0)"
                                                : "the loss of stability (max |λ| = 1)");
    json_object_set_new(o, "tolerable", t);
    /* past contact loss: the unilateral model's orbits with separation */
    {
        json_t *sp = json_object();
        const usm_report_nonideal_point *last = NULL;
        for (int q = 0; q < cv->points; ++q) /* the last stable one */
            if (cv->pt[q].separating && cv->pt[q].sep_max_modulus < 1.0)
                last = &cv->pt[q];
        integer(sp, "points", cv->sep_points);
        flag(sp, "any", cv->sep_points > 0);
        flag(sp, "drives_all", cv->sep_points > cv->sep_unstable && cv->sep_drives_all);
        num(sp, "drives_to", cv->sep_drives_to);
        num(sp, "drives_to_display", imp_display(j, cv->sep_drives_to));
        num(sp, "impact_velocity_max", cv->sep_impact_max);
        num(sp, "impact_velocity_max_mm_s", cv->sep_impact_max * 1e3);
        num(sp, "impact_at", cv->sep_impact_at);
        num(sp, "impact_at_display", imp_display(j, cv->sep_impact_at));
        integer(sp, "unstable", cv->sep_unstable);
        flag(sp, "any_unstable", cv->sep_unstable > 0);
        num(sp, "unstable_from_display", imp_display(j, cv->sep_unstable_from));
        num(sp, "unstable_to_display", imp_display(j, cv->sep_unstable_to));
        num(sp, "max_modulus", cv->sep_modulus_max);
        integer(sp, "switches", cv->sep_switches);
        flag(sp, "any_switch", cv->sep_switches > 0);
        num(sp, "switch_at", cv->sep_switch_at);
        num(sp, "switch_at_display", imp_display(j, cv->sep_switch_at));
        num(sp, "switch_unstable_modulus", cv->sep_switch_modulus);
        num(sp, "switch_unstable_from", cv->sep_switch_unstable_from);
        num(sp, "switch_unstable_from_display", imp_display(j, cv->sep_switch_unstable_from));
        num(sp, "speed_at_end", last ? last->sep_speed_mean : NAN);
        num(sp, "ripple_at_end", last ? last->sep_ripple : NAN);
        num(sp, "fraction_at_end", last ? last->sep_fraction : NAN);
        num(sp, "last", last ? last->value : NAN);
        num(sp, "last_display", last ? imp_display(j, last->value) : NAN);
        /* the last stable orbit's speed and ripple carry their flag */
        flag(sp, "last_valid", last && last->sep_validity == USM_VALID);
        str(sp, "last_invalid_reason", last ? usm_validity_name(last->sep_validity) : "");
        json_object_set_new(o, "separating", sp);
    }
    return o;
}

static json_t *nonideal(const usm_report_data *d)
{
    const usm_report_nonideal *ni = &d->nonideal;
    static const char *const imp[REPORT_NIMP] = {"phase_error", "mode_split"};
    json_t *o = json_object();
    flag(o, "ok", ni->ok);
    str(o, "note", ni->note);
    num(o, "seconds", ni->seconds);
    {
        const int n = usm_report_figure_count(d);
        json_object_set_new(o, "figures",
                            figures(REPORT_FIG_NONIDEAL,
                                    n < REPORT_FIG_SQUEAL_MOTION ? n : REPORT_FIG_SQUEAL_MOTION));
    }
    if (!ni->ok)
        return o;
    integer(o, "points", ni->curve[0][0].points);
    for (int k = 0; k < REPORT_NMODELS; ++k) {
        json_t *m = json_object();
        str(m, "model", ni->model[k]->name);
        str(m, "unilateral_model", ni->umodel[k] ? ni->umodel[k]->name : "");
        num(m, "theta_ideal", ni->theta_ideal[k]);
        for (int j = 0; j < REPORT_NIMP; ++j)
            json_object_set_new(m, imp[j], nonideal_curve(&ni->curve[k][j], j));
        json_object_set_new(o, tag[k], m);
    }
    {
        json_t *b = json_object();
        double tmin = INFINITY, tmax = -INFINITY;
        const double th0 = ni->theta_ideal[REPORT_3DOF];
        flag(b, "ok", ni->orbit_ok);
        str(b, "note", ni->orbit_note);
        str(b, "model", ni->model[REPORT_3DOF]->name);
        str(b, "parameter", imp[ni->orbit_imp]);
        str(b, "display_unit", ni->orbit_imp == REPORT_IMP_PHASE ? "deg" : "%");
        num(b, "value", ni->orbit_value);
        num(b, "display", imp_display(ni->orbit_imp, ni->orbit_value));
        num(b, "theta_ideal", th0);
        for (int q = 0; ni->orbit_ok && q < USM_PERIODIC_SAMPLES; ++q) {
            const double th = ni->orbit[q][1 + ni->orbit_x_theta];
            tmin = fmin(tmin, th);
            tmax = fmax(tmax, th);
        }
        num(b, "theta_min", ni->orbit_ok ? tmin : NAN);
        num(b, "theta_max", ni->orbit_ok ? tmax : NAN);
        num(b, "radial_min_percent", ni->orbit_ok ? (tmin / th0 - 1) * 100 : NAN);
        num(b, "radial_max_percent", ni->orbit_ok ? (tmax / th0 - 1) * 100 : NAN);
        num(b, "F_n_min", ni->orbit_ok ? ni->orbit_F_n_min : NAN);
        integer(b, "samples", USM_PERIODIC_SAMPLES + 1);
        json_object_set_new(o, "orbit", b);
    }
    return o;
}

json_t *usm_report_json(const usm_report_data *d, int plots_ok, const char *plot_note)
{
    json_t *o = json_object(), *maps = json_array(), *sec = json_object(), *models = json_object();
    int unstable = 0, total = 0;
    str(o, "marker", REPORT_MARKER);
    str(o, "usm_version", USM_VERSION);
    str(o, "generator_version", USM_GENERATOR_VERSION);
    flag(o, "quick", d->opt.quick);
    flag(o, "plots", d->opt.plots);
    str(o, "figures_missing", !plots_ok && plot_note ? plot_note : "");
    integer(o, "threads", d->opt.threads);
    json_object_set_new(o, "parameters", params(d));
    {
        json_t *byname = json_object();
        for (int k = 0; k < USM_NPARAMS; ++k)
            num(byname, usm_param_table[k].name, usm_params_get(&d->params, &usm_param_table[k]));
        json_object_set_new(o, "params", byname);
    }
    json_object_set_new(o, "choices", choices(d));
    for (int k = 0; k < REPORT_NMODELS; ++k) {
        json_object_set_new(models, tag[k], model(d, k));
        for (int i = 0; i < REPORT_NT0; ++i) {
            ++total;
            unstable += !d->model[k].fl[i].stable;
        }
    }
    json_object_set_new(o, "model", models);
    integer(o, "t0_unstable", unstable);
    integer(o, "t0_total", total);
    json_object_set_new(o, "compare", compare(d));
    json_object_set_new(o, "characteristics", characteristics(d));
    json_object_set_new(o, "figures_floquet", figures(REPORT_FIG_MULT_3DOF, REPORT_FIG_MAP_3DOF));
    json_object_set_new(o, "figures_curves", figures(REPORT_FIG_SPEED_F, REPORT_FIG_MULT_3DOF));
    json_object_set_new(o, "figures", figures(0, usm_report_figure_count(d)));
    json_object_set_new(o, "figures_datasheet",
                        figures(REPORT_FIG_DATASHEET, REPORT_FIG_DATASHEET + 1));
    json_object_set_new(o, "figures_elasticity",
                        figures(REPORT_FIG_ELASTICITY, REPORT_FIG_ELASTICITY + 1));
    json_object_set_new(o, "datasheet", datasheet(d));
    json_object_set_new(o, "sensitivity", sensitivity(d));
    for (int k = 0; k < REPORT_NMODELS; ++k)
        if (d->have_map[k])
            json_array_append_new(maps, map_summary(&d->map[k], k == REPORT_3DOF
                                                                    ? REPORT_FIG_MAP_3DOF
                                                                    : REPORT_FIG_MAP_4DOF));
    json_object_set_new(o, "maps", maps);
    json_object_set_new(o, "variants", variants(d));
    json_object_set_new(o, "nonideal", nonideal(d));
    {
        json_t *sq = usm_report_squeal_json(d);
        const int n = usm_report_figure_count(d);
        json_object_set_new(sq, "figures", figures(REPORT_FIG_SQUEAL,
                                                   n < REPORT_FIG_ENVELOPE ? n : REPORT_FIG_ENVELOPE));
        json_object_set_new(json_object_get(sq, "motion"), "figures",
                            figures(REPORT_FIG_SQUEAL_MOTION,
                                    n < REPORT_FIG_SQUEAL ? n : REPORT_FIG_SQUEAL));
        json_object_set_new(o, "squeal", sq);
    }
    json_object_set_new(o, "design_robust", usm_report_design_json(d));
    json_object_set_new(o, "paper_fit", usm_report_paper_fit_json(d));
    {
        json_t *en = usm_report_envelope_json(d);
        json_object_set_new(en, "figures", figures(REPORT_FIG_ENVELOPE, usm_report_figure_count(d)));
        json_object_set_new(o, "envelope", en);
    }
    num(sec, "tables", d->seconds[0]);
    num(sec, "curves", d->seconds[1]);
    num(sec, "maps", d->seconds[2]);
    num(sec, "plots", d->seconds[3]);
    num(sec, "nonideal", d->nonideal.seconds);
    num(sec, "squeal", d->squeal.seconds);
    num(sec, "design", usm_report_design_seconds(d));
    num(sec, "total", d->seconds[0] + d->seconds[1] + d->seconds[2] + d->seconds[3] +
                          d->nonideal.seconds + d->squeal.seconds +
                          (isfinite(usm_report_design_seconds(d)) ? usm_report_design_seconds(d) : 0));
    json_object_set_new(o, "seconds", sec);
    {
        /* the paper's values, as loaded */
        const usm_report_paper *pv = &d->paper;
        const usm_report_published *v[] = {&pv->theta3, &pv->alpha3, &pv->beta3, &pv->speed4,
                                       &pv->theta4, &pv->alpha4, &pv->beta4, &pv->f_max,
                                       &pv->slip_load, &pv->speed_ratio};
        static const char *const key[] = {"theta3", "alpha3", "beta3", "speed4", "theta4",
                                          "alpha4", "beta4", "f_max", "slip_load", "speed_ratio"};
        json_t *p = json_object();
        for (size_t k = 0; k < sizeof key / sizeof key[0]; ++k) {
            json_t *e = json_object();
            str(e, "where", v[k]->where);
            str(e, "what", v[k]->what);
            str(e, "printed", v[k]->printed);
            num(e, "value", v[k]->value);
            str(e, "unit", v[k]->unit);
            json_object_set_new(p, key[k], e);
        }
        json_object_set_new(o, "paper", p);
    }
    return o;
}
