/* Everything `usm report` shows, computed through libusm: stationary
 * solutions and multipliers at the paper's parameters, the t0 study, the
 * checks of the values the paper leaves out, the characteristic curves
 * (usm_sweep), their key numbers (the sweeps' events: extrema and crossings of
 * monitors, ends of the branch, stick limit, stability change) and the maps. */
#define _POSIX_C_SOURCE 200809L

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "report_internal.h"
#include "usm_map.h"
#include "usm_squeal_study.h"

#define TWO_PI 6.283185307179586476925286766559
#define PI 3.14159265358979323846264338327950

const double usm_report_t0_fraction[REPORT_NT0] = {0.0, 0.25, 0.5, 10.0, 100.0, 1000.0};
const char *const usm_report_t0_label[REPORT_NT0] = {"0", "T/4", "T/2", "10 T", "100 T", "1000 T"};

double usm_report_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* ---- small solvers ------------------------------------------------------------ */

typedef struct solver {
    const usm_model *m;
    usm_steady *steady;
    usm_floquet *floquet;
} solver;

static int solver_init(solver *s, const usm_model *m)
{
    s->m = m;
    s->steady = usm_steady_alloc(m);
    s->floquet = usm_floquet_alloc(m);
    return s->steady && s->floquet ? 0 : -1;
}

static void solver_free(solver *s)
{
    usm_steady_free(s->steady);
    usm_floquet_free(s->floquet);
    s->steady = NULL;
    s->floquet = NULL;
}

/* Primary root and multipliers at p.  USM_OK, USM_ENOSOLUTION or USM_EFAILED
 * with msg. */
static int solve_point(solver *s, const usm_params *p, double t0, usm_steady_solution *sol,
                       usm_floquet_result *fl, char msg[USM_IO_MSG_LEN])
{
    usm_point pt;
    if (usm_point_evaluate(s->steady, s->floquet, p, NULL, NULL, fl != NULL, t0, NULL, &pt) != USM_OK) {
        usm_io_msg(msg, "%s: no stationary solution: %s", s->m->name, pt.error);
        return USM_EINPUT;
    }
    if (!pt.exists) {
        usm_io_msg(msg, "%s: no stationary solution: %s", s->m->name, pt.error);
        return USM_ENOSOLUTION;
    }
    *sol = pt.sol;
    if (fl && !pt.has_floquet) {
        usm_io_msg(msg, "%s: %s", s->m->name, pt.error);
        return USM_EFAILED;
    }
    if (fl)
        *fl = pt.floquet;
    return USM_OK;
}

int usm_report_match_multiplier(const usm_floquet_result *r, double re, double im, int *used)
{
    int best = -1;
    double dbest = INFINITY;
    for (int k = 0; k < r->n; ++k) {
        double d = hypot(r->re[k] - re, r->im[k] - im);
        if (!used[k] && d < dbest) {
            dbest = d;
            best = k;
        }
    }
    if (best >= 0)
        used[best] = 1;
    return best;
}

double usm_report_table_distance(const usm_report_published_multiplier *t, int nt,
                                 const usm_floquet_result *r, int skip_first)
{
    int used[USM_MAX_NX] = {0};
    double dev = 0;
    for (int k = 0; k < nt; ++k)
        for (int sgn = 1; sgn >= (t[k].im > 0 ? -1 : 1); sgn -= 2) {
            int j = usm_report_match_multiplier(r, t[k].re, sgn * t[k].im, used);
            if (j < 0)
                return INFINITY;
            if (!(skip_first && k == 0))
                dev = fmax(dev, hypot(r->re[j] - t[k].re, r->im[j] - sgn * t[k].im));
        }
    return dev;
}

/* ---- key numbers: the sweeps' events ------------------------------------------ */

/* Monitors of the curves: the quantities whose extrema and crossings the
 * report quotes, located by the sweep along the branch. */
static double mon_speed(const usm_steady_solution *sol, const usm_params *p, void *ctx)
{
    (void)p;
    (void)ctx;
    return -sol->rotor_speed; /* w_R, positive when driving */
}

static double mon_tilt(const usm_steady_solution *sol, const usm_params *p, void *ctx)
{
    (void)p;
    (void)ctx;
    return sol->theta;
}

static double mon_mu(const usm_steady_solution *sol, const usm_params *p, void *ctx)
{
    (void)p;
    (void)ctx;
    return sol->mu_used;
}

static void from_event(const usm_sweep_event *e, usm_report_located *out)
{
    out->ok = 1;
    out->value = e->value;
    out->type = e->type;
    out->has_sol = e->has_sol;
    if (e->has_sol)
        out->sol = e->sol;
}

/* The event of `type` on a curve (for maxima: of monitor `monitor`, the
 * largest); ok = 0 with a note when the sweep reports none. */
static void curve_event(const usm_report_curve *cv, usm_event_type type, const char *monitor,
                        usm_report_located *out)
{
    const size_t n = cv->sweep ? usm_sweep_event_count(cv->sweep) : 0;
    const usm_sweep_event *best = NULL;
    memset(out, 0, sizeof *out);
    out->from = cv->from;
    out->to = cv->to;
    for (size_t i = 0; i < n; ++i) {
        const usm_sweep_event *e = usm_sweep_event_at(cv->sweep, i);
        if (e->type != type || (monitor && strcmp(e->monitor, monitor) != 0))
            continue;
        if (!best || (type == USM_EVENT_MAXIMUM && e->monitor_value > best->monitor_value))
            best = e;
        if (type != USM_EVENT_MAXIMUM)
            break;
    }
    if (best)
        from_event(best, out);
    else
        snprintf(out->note, USM_MSG_LEN, "the sweep of %s from %g to %g reports no %s%s%s",
                 cv->over, cv->from, cv->to, usm_event_name(type), monitor ? " of " : "",
                 monitor ? monitor : "");
}

/* Where the branch of a curve ends (its solution stops existing): the first
 * end event in sweep order. */
static void curve_end(const usm_report_curve *cv, usm_report_located *out)
{
    const size_t n = cv->sweep ? usm_sweep_event_count(cv->sweep) : 0;
    memset(out, 0, sizeof *out);
    out->from = cv->from;
    out->to = cv->to;
    for (size_t i = 0; i < n; ++i) {
        const usm_sweep_event *e = usm_sweep_event_at(cv->sweep, i);
        if (e->type == USM_EVENT_FOLD || e->type == USM_EVENT_TILT_ZERO ||
            e->type == USM_EVENT_RANGE_END || e->type == USM_EVENT_FRICTION_SATURATION) {
            from_event(e, out);
            return;
        }
    }
    snprintf(out->note, USM_MSG_LEN, "the branch does not end along %s from %g to %g (the range swept)",
             cv->over, cv->from, cv->to);
}

/* ---- the characteristic curves ------------------------------------------------- */

static void curve_setup(usm_report_curve *cv, const char *over, double from, double to, int points)
{
    cv->over = over;
    cv->from = from;
    cv->to = to;
    cv->points = points;
}

static int run_curve(usm_report_curve *cv, const usm_model *m, const usm_params *p, int threads,
                     int floquet, char msg[USM_IO_MSG_LEN])
{
    /* every curve watches the speed and tilt extrema and the friction
     * coefficient the stick model needs reaching the atan law's maximum */
    usm_sweep_monitor mon[3] = {
        {"speed", mon_speed, NULL, 1, 0, {0}},
        {"theta", mon_tilt, NULL, 1, 0, {0}},
        {"mu_used", mon_mu, NULL, 0, 1, {p->mu0 * 0.5 * PI}},
    };
    usm_sweep_options opt;
    usm_sweep_options_default(&opt);
    opt.over = cv->over;
    opt.from = cv->from;
    opt.to = cv->to;
    opt.points = cv->points;
    opt.floquet = floquet;
    opt.t0 = 0.0;
    opt.threads = threads;
    opt.monitors = mon;
    opt.nmonitors = 3;
    if (!(cv->sweep = usm_sweep_alloc(m))) {
        usm_io_msg(msg, "out of memory");
        return USM_EFAILED;
    }
    if (usm_sweep_run(cv->sweep, p, &opt) != USM_OK) {
        usm_io_msg(msg, "sweep %s of %s from %g to %g: %s", cv->over, m->name, cv->from, cv->to,
                usm_sweep_message(cv->sweep));
        return USM_EFAILED;
    }
    return USM_OK;
}

/* ---- sensitivities (usm_design.h) ----------------------------------------------- */

const int usm_report_sens_outputs[REPORT_NSENS_OUT] = {USM_SENS_ROTOR_SPEED, USM_SENS_MAX_MODULUS};

int usm_report_elasticity_order(const usm_params *p, const usm_sensitivity_result *r, int k,
                            int idx[USM_NPARAMS])
{
    double e[USM_NPARAMS];
    int n = 0;
    for (int j = 0; j < USM_NPARAMS; ++j) {
        e[j] = usm_sensitivity_elasticity(p, r, k, j);
        if (isfinite(e[j]) && e[j] != 0)
            idx[n++] = j;
    }
    /* insertion sort: 19 entries, stable, so ties keep usm_params order */
    for (int a = 1; a < n; ++a)
        for (int b = a; b > 0 && fabs(e[idx[b]]) > fabs(e[idx[b - 1]]); --b) {
            int t = idx[b];
            idx[b] = idx[b - 1];
            idx[b - 1] = t;
        }
    return n;
}

/* Sensitivities of each model's primary solution at the report's parameters.
 * A failure (a fold, a failed exponential) is shown in the report, not an
 * error of the report: have_sens = 0 and sens_note says why. */
static int sensitivities(usm_report_data *d, char msg[USM_IO_MSG_LEN])
{
    for (int k = 0; k < REPORT_NMODELS; ++k) {
        usm_sensitivity *s = usm_sensitivity_alloc(d->model[k].model);
        if (!s) {
            usm_io_msg(msg, "out of memory");
            return USM_EFAILED;
        }
        d->have_sens[k] = usm_sensitivity_compute(s, &d->params, &d->model[k].sol, 1,
                                                  &d->sens[k]) == USM_OK;
        snprintf(d->sens_note[k], USM_MSG_LEN, "%s",
                 d->have_sens[k] ? "" : usm_sensitivity_message(s));
        usm_sensitivity_free(s);
    }
    return USM_OK;
}

/* ---- the whole computation ------------------------------------------------------- */

static int model_tables(usm_report_data *d, int k, solver *s, char msg[USM_IO_MSG_LEN])
{
    usm_report_model_result *r = &d->model[k];
    const double period = 1.0 / d->params.f;
    int st;
    for (int i = 0; i < REPORT_NT0; ++i) {
        st = solve_point(s, &d->params, usm_report_t0_fraction[i] * period, &r->sol, &r->fl[i], msg);
        if (st != USM_OK)
            return st; /* USM_ENOSOLUTION: no operating point to report on */
    }
    return USM_OK;
}

/* Each variant's stationary solution and multipliers from three start times:
 * the comparison of the assumptions.  A variant without a solution is shown
 * as such, not an error of the report. */
static int variants_side_by_side(usm_report_data *d, char msg[USM_IO_MSG_LEN])
{
    const double period = 1.0 / d->params.f;
    const double t0[REPORT_NVARIANT_T0] = {0.0, 0.5 * period, 100.0 * period};
    for (int k = 0; k < USM_NMODELS; ++k) {
        usm_report_variant_result *v = &d->variant[k];
        solver s;
        int st = USM_OK;
        v->model = usm_models[k];
        if (solver_init(&s, v->model) != 0) {
            solver_free(&s);
            usm_io_msg(msg, "out of memory");
            return USM_EFAILED;
        }
        for (int i = 0; i < REPORT_NVARIANT_T0 && st == USM_OK; ++i)
            st = solve_point(&s, &d->params, t0[i], &v->sol, &v->fl[i], msg);
        solver_free(&s);
        v->ok = st == USM_OK;
        if (st == USM_ENOSOLUTION)
            snprintf(v->note, sizeof v->note, "%s", msg);
        else if (st != USM_OK)
            return st;
    }
    /* the t0 study of section 4 shows the twist_integrated multipliers at
     * t0 = 0 and T/2: the first two start times computed here */
    for (int m = 0; m < REPORT_NMODELS; ++m) {
        usm_report_model_result *r = &d->model[m];
        const usm_model *mi = usm_model_variant(r->model->base, "twist_integrated");
        r->integrated = NULL;
        for (int k = 0; mi && k < USM_NMODELS; ++k)
            if (d->variant[k].model == mi && d->variant[k].ok) {
                r->integrated = mi;
                r->fl_integrated[0] = d->variant[k].fl[0];
                r->fl_integrated[1] = d->variant[k].fl[1];
            }
    }
    return USM_OK;
}

static int parameter_checks(usm_report_data *d, solver *s3, char msg[USM_IO_MSG_LEN])
{
    const usm_params *p = &d->params;
    usm_params q;
    usm_steady_solution sol;
    usm_floquet_result fl;
    d->f_from_cr = sqrt(p->c_r / p->I_xx) / TWO_PI;
    d->dr_3pct = 2 * 0.03 * sqrt(p->c_r * p->I_xx);
    d->dt_3pct = 2 * 0.03 * sqrt(p->c_t * p->I_zz);
    d->M_disk = 2 * p->I_R / (p->R * p->R);
    d->M_from_dR = (p->d_R / 0.06) * (p->d_R / 0.06) / p->c_R;
    q = *p;
    q.f = d->paper.f_max.value;
    d->theta_at_fmax_paper = solve_point(s3, &q, 0, &sol, NULL, msg) == USM_OK ? sol.theta : NAN;
    d->M_trial[0] = 0.0;
    d->M_trial[1] = d->M_disk;
    d->M_trial[2] = d->M_from_dR;
    for (int i = 0; i < 3; ++i) {
        q = *p;
        q.M = d->M_trial[i];
        d->M_trial_dev[i] = solve_point(s3, &q, 0, &sol, &fl, msg) == USM_OK
                                ? usm_report_table_distance(d->paper.table3, d->paper.n3, &fl, 0)
                                : NAN;
    }
    return USM_OK;
}

int usm_report_compute(usm_report_data *d, char msg[USM_IO_MSG_LEN])
{
    const int quick = d->opt.quick;
    const int nf = quick ? 41 : 161, nT = quick ? 41 : 161, nTs = quick ? 25 : 121,
              nm = quick ? 41 : 111;
    solver s[REPORT_NMODELS];
    double t = usm_report_now();
    int st = USM_OK;

    memset(s, 0, sizeof s);
    d->model[REPORT_3DOF].model = usm_model_find("3dof");
    d->model[REPORT_4DOF].model = usm_model_find("4dof");
    for (int k = 0; k < REPORT_NMODELS; ++k)
        if (!d->model[k].model || solver_init(&s[k], d->model[k].model) != 0) {
            usm_io_msg(msg, "%s", d->model[k].model ? "out of memory" : "model 3dof/4dof not built");
            st = USM_EFAILED;
            goto done;
        }
    for (int k = 0; k < REPORT_NMODELS; ++k)
        if ((st = model_tables(d, k, &s[k], msg)) != USM_OK)
            goto done;
    if ((st = parameter_checks(d, &s[REPORT_3DOF], msg)) != USM_OK)
        goto done;
    if ((st = variants_side_by_side(d, msg)) != USM_OK)
        goto done;
    if ((st = sensitivities(d, msg)) != USM_OK)
        goto done;
    d->seconds[0] = usm_report_now() - t;
    t = usm_report_now();

    /* Figs. 9-11.  The slip model's load curve ends near mu0 pi/2 F_n R*,
     * far below the stick model's, so it gets its own (shorter) range. */
    curve_setup(&d->curve[REPORT_CURVE_F][REPORT_3DOF], "f", 30000, 46000, nf);
    curve_setup(&d->curve[REPORT_CURVE_F][REPORT_4DOF], "f", 30000, 46000, nf);
    curve_setup(&d->curve[REPORT_CURVE_T][REPORT_3DOF], "T", 0, 8e-3, nT);
    curve_setup(&d->curve[REPORT_CURVE_T][REPORT_4DOF], "T", 0, 1.2e-3, nTs);
    curve_setup(&d->curve[REPORT_CURVE_M0][REPORT_3DOF], "m0", 1e-3, 12e-3, nm);
    curve_setup(&d->curve[REPORT_CURVE_M0][REPORT_4DOF], "m0", 1e-3, 12e-3, nm);
    for (int c = 0; c < REPORT_NCURVES; ++c)
        for (int k = 0; k < REPORT_NMODELS; ++k)
            if ((st = run_curve(&d->curve[c][k], d->model[k].model, &d->params, d->opt.threads,
                                1, msg)) != USM_OK)
                goto done;

    /* key numbers: the sweeps' events */
    for (int k = 0; k < REPORT_NMODELS; ++k) {
        curve_event(&d->curve[REPORT_CURVE_F][k], USM_EVENT_MAXIMUM, "speed", &d->f_max[k]);
        curve_end(&d->curve[REPORT_CURVE_T][k], &d->existence_T[k]);
        curve_end(&d->curve[REPORT_CURVE_M0][k], &d->existence_m0[k]);
    }
    curve_event(&d->curve[REPORT_CURVE_F][REPORT_3DOF], USM_EVENT_MAXIMUM, "theta",
                &d->f_theta_max);
    {
        /* the tilt peak with a nearly vanishing preload: without the contact
         * moment F_n R* it sits at the stator's damped eigenfrequency */
        usm_params q = d->params;
        usm_report_curve small;
        memset(&small, 0, sizeof small);
        q.F0 = REPORT_SMALL_F0;
        curve_setup(&small, "f", 30000, 46000, 161);
        if ((st = run_curve(&small, d->model[REPORT_3DOF].model, &q, d->opt.threads, 0, msg)) !=
            USM_OK) {
            usm_sweep_free(small.sweep);
            goto done;
        }
        curve_event(&small, USM_EVENT_MAXIMUM, "theta", &d->f_theta_max_small_F0);
        usm_sweep_free(small.sweep);
    }
    curve_event(&d->curve[REPORT_CURVE_T][REPORT_3DOF], USM_EVENT_STICK_LIMIT, NULL,
                &d->stick_limit);
    curve_event(&d->curve[REPORT_CURVE_T][REPORT_3DOF], USM_EVENT_CROSSING, "mu_used",
                &d->stick_limit_sat);
    curve_event(&d->curve[REPORT_CURVE_T][REPORT_3DOF], USM_EVENT_STABILITY_CHANGE, NULL,
                &d->stability_T);
    d->seconds[1] = usm_report_now() - t;
done:
    for (int k = 0; k < REPORT_NMODELS; ++k)
        solver_free(&s[k]);
    return st;
}

int usm_report_compute_maps(usm_report_data *d, char msg[USM_IO_MSG_LEN])
{
    const int quick = d->opt.quick;
    const double t = usm_report_now();
    for (int k = 0; k < REPORT_NMODELS; ++k) {
        usm_report_map *m = &d->map[k];
        int st;
        memset(m, 0, sizeof *m);
        m->model = d->model[k].model;
        m->params = d->params;
        m->x.name = "f";
        m->x.from = 30000;
        m->x.to = 46000;
        m->x.points = quick ? 17 : 41;
        m->y.name = "T";
        m->y.from = 0;
        m->y.to = k == REPORT_3DOF ? 8e-3 : 1.2e-3;
        m->y.points = quick ? 13 : 33;
        m->t0 = 0;
        m->threads = d->opt.threads;
        m->boundaries = 1;
        if ((st = usm_report_map_run(m, msg)) != USM_OK)
            return st;
        d->have_map[k] = 1;
    }
    d->seconds[2] = usm_report_now() - t;
    return USM_OK;
}

void usm_report_data_free(usm_report_data *d)
{
    for (int c = 0; c < REPORT_NCURVES; ++c)
        for (int k = 0; k < REPORT_NMODELS; ++k) {
            usm_sweep_free(d->curve[c][k].sweep);
            d->curve[c][k].sweep = NULL;
        }
    for (int k = 0; k < REPORT_NMODELS; ++k)
        if (d->have_map[k]) {
            usm_report_map_free(&d->map[k]);
            d->have_map[k] = 0;
        }
    usm_squeal_free(d->squeal.motion.study);
    d->squeal.motion.study = NULL;
}
