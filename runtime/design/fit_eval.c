/* The evaluation of a fit (fit_internal.h): the measured outputs' names and
 * values, and the residuals and Jacobian at a point of the fitted parameters.
 * Each evaluation solves every row's stationary roots, decides its operating
 * point and differentiates that root analytically (a datasheet quantity by
 * central differences), so one pass gives the residuals and the Jacobian
 * together.  fit.c's least-squares driver and fit_stats.c's statistics both
 * call it.  The measurements' container (usm_fit_data) lives here too. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/grow.h"
#include "fit_internal.h"
#include "usm_fit.h"
#include "usm_robust.h"
#include "usm_sweep.h"

/* ---- outputs ------------------------------------------------------------------- */

static const char *const out_units[USM_FIT_NOUTPUTS] = {
    "rad", "1/s", "N", "N", "1", "N", NULL, "W", "W", "1/s", "N m", "1/s", "W", "Hz"};

/* the datasheet quantities by fit output (usm_robust.h) */
static int datasheet_quantity(int k)
{
    switch (k) {
    case USM_FIT_STALL_TORQUE: return USM_ROBUST_STALL_TORQUE;
    case USM_FIT_NO_LOAD_SPEED: return USM_ROBUST_NO_LOAD_SPEED;
    case USM_FIT_MAX_POWER: return USM_ROBUST_MAX_POWER;
    default: return -1;
    }
}

int usm_fit_output_is_datasheet(int k)
{
    return datasheet_quantity(k) >= 0 || k == USM_FIT_SPEED_MAX_FREQUENCY;
}

const char *usm_fit_output_name(int k)
{
    if (k == USM_FIT_SPEED)
        return "speed";
    if (k == USM_FIT_SPEED_MAX_FREQUENCY)
        return "speed_max_frequency";
    if (usm_fit_output_is_datasheet(k))
        return usm_robust_quantity_name(datasheet_quantity(k));
    return k >= 0 && k < USM_SENS_COUNT && k != USM_SENS_MAX_MODULUS
               ? usm_sensitivity_output_name(k)
               : NULL;
}

const char *usm_fit_output_unit(int k)
{
    return usm_fit_output_name(k) ? out_units[k] : NULL;
}

int usm_fit_output_find(const char *name)
{
    for (int k = 0; k < USM_FIT_NOUTPUTS; ++k)
        if (usm_fit_output_name(k) && strcmp(name, usm_fit_output_name(k)) == 0)
            return k;
    return -1;
}

double usm_fit_output_value(int k, const usm_steady_solution *s, const usm_params *p)
{
    switch (k) {
    case USM_SENS_THETA: return s->theta;
    case USM_SENS_ROTOR_SPEED: return s->rotor_speed;
    case USM_SENS_F_N: return s->F_n;
    case USM_SENS_F_T: return s->F_t;
    case USM_SENS_EFFICIENCY: return s->efficiency;
    case USM_SENS_STICK_MARGIN: return p->mu0 * s->F_n - s->F_t;
    case USM_SENS_POWER_IN: return s->power_in;
    case USM_SENS_POWER_OUT: return s->power_out;
    case USM_FIT_SPEED: return -s->rotor_speed;
    default: return NAN;
    }
}

/* d(output k)/d(parameter j) from a sensitivity result */
static double output_derivative(int k, const usm_sensitivity_result *r, int j)
{
    if (k == USM_FIT_SPEED)
        return -r->d[USM_SENS_ROTOR_SPEED][j];
    return k < USM_SENS_COUNT && r->defined[k] ? r->d[k][j] : NAN;
}

/* A parameter fitted in log scale: its range allows no negative value. */
int fit_log_scale(int k)
{
    return usm_param_ranges[k].lo >= 0.0;
}

/* ---- one evaluation ------------------------------------------------------------------ */

int fit_eval_init(fit_eval *e, const usm_model *m, const usm_params *p, const usm_fit_data *d,
                  const usm_fit_options *o)
{
    memset(e, 0, sizeof *e);
    e->m = m;
    e->base = *p;
    e->d = d;
    e->o = o;
    e->n = usm_fit_data_count(d);
    e->np = o->nfit;
    e->s = usm_steady_alloc(m);
    e->fl = usm_floquet_alloc(m);
    e->sens = usm_sensitivity_alloc(m);
    e->idx = malloc((size_t)e->n * sizeof *e->idx);
    e->w = malloc((size_t)e->n * sizeof *e->w);
    e->f = malloc((size_t)e->n * sizeof *e->f);
    e->J = malloc((size_t)e->n * (size_t)e->np * sizeof *e->J);
    e->model = malloc((size_t)e->n * sizeof *e->model);
    e->reason = calloc((size_t)e->n, sizeof *e->reason);
    if (!e->s || !e->fl || !e->sens || !e->idx || !e->w || !e->f || !e->J || !e->model ||
        !e->reason)
        return USM_EFAILED;
    /* the scale of an output without sigma: the RMS of its measured values, so
     * that outputs in different units weigh alike before sigma is estimated */
    double rms[USM_FIT_MAX_COLUMNS] = {0};
    int cnt[USM_FIT_MAX_COLUMNS] = {0};
    for (int r = 0; r < d->nrows; ++r)
        for (int c = 0; c < d->nout; ++c) {
            double y = d->y[(size_t)r * (size_t)d->nout + (size_t)c];
            if (!isnan(y)) {
                rms[c] += y * y;
                cnt[c]++;
            }
        }
    e->sigma_given = 1;
    for (int c = 0; c < d->nout; ++c) {
        rms[c] = cnt[c] ? sqrt(rms[c] / cnt[c]) : 1.0;
        if (!(rms[c] > 0))
            rms[c] = 1.0;
        e->sigma_given &= d->has_sigma[c];
    }
    int i = 0;
    for (int r = 0; r < d->nrows; ++r)
        for (int c = 0; c < d->nout; ++c) {
            size_t at = (size_t)r * (size_t)d->nout + (size_t)c;
            if (isnan(d->y[at]))
                continue;
            e->idx[i] = (int)at;
            e->w[i] = d->has_sigma[c] ? d->sigma[at] : rms[c];
            ++i;
        }
    for (int j = 0; j < e->np; ++j)
        e->log_scale[j] = fit_log_scale(o->fit[j]);
    return USM_OK;
}

void fit_eval_free(fit_eval *e)
{
    usm_steady_free(e->s);
    usm_floquet_free(e->fl);
    usm_sensitivity_free(e->sens);
    free(e->res);
    free(e->idx);
    free(e->w);
    free(e->f);
    free(e->J);
    free(e->model);
    free(e->reason);
    memset(e, 0, sizeof *e);
}

void fit_params_at(const fit_eval *e, const double *t, usm_params *p)
{
    *p = e->base;
    for (int j = 0; j < e->np; ++j)
        *usm_params_field(p, &usm_param_table[e->o->fit[j]]) =
            e->log_scale[j] ? exp(t[j]) : t[j];
}

int fit_point(fit_eval *e, usm_params *p, const usm_steady_solution **sol,
              usm_sensitivity_result *sr, const char **reason)
{
    char msg[USM_MSG_LEN];
    *sol = NULL;
    *reason = "";
    e->evaluations++;
    usm_params_couple(e->m, p, -1);
    if (usm_params_check(p, e->m, msg) != USM_OK) {
        *reason = "bad_parameters";
        return USM_OK;
    }
    int st = usm_steady_solve(e->s, p, NULL);
    if (st == USM_ENOSOLUTION || st == USM_EINPUT) {
        *reason = st == USM_EINPUT ? "bad_parameters" : "no_solution";
        return USM_OK;
    }
    if (st != USM_OK) {
        *reason = "failed";
        return USM_OK;
    }
    size_t nr = usm_steady_count(e->s);
    if (nr > e->res_cap) {
        void *grown = e->res;
        if (usm_grow(&grown, &e->res_cap, nr, sizeof *e->res) != 0)
            return USM_EFAILED;
        e->res = grown;
    }
    if (usm_floquet_roots(e->fl, p, e->s, 0.0, NULL, e->res) != USM_OK) {
        *reason = "failed";
        return USM_OK;
    }
    usm_op_result op;
    st = usm_operating_point(e->m, p, e->s, e->res, &e->o->op, &op);
    if (st == USM_EFAILED)
        return USM_EFAILED;
    if (st != USM_OK || op.index < 0) {
        *reason = st != USM_OK ? "failed" : usm_op_reason_name(op.reason);
        return USM_OK;
    }
    *sol = usm_steady_root(e->s, (size_t)op.index);
    if (sr && usm_sensitivity_compute(e->sens, p, *sol, 0, sr) != USM_OK) {
        *sol = NULL;
        *reason = "failed";
        return USM_OK;
    }
    if ((*sol)->validity != USM_VALID)
        *reason = usm_validity_name((*sol)->validity);
    return USM_OK;
}

static double monitor_speed(const usm_steady_solution *sol, const usm_params *p, void *ctx)
{
    (void)p;
    (void)ctx;
    return -sol->rotor_speed;
}

/* The frequency of the speed maximum over f at p: the located maximum event
 * of the same continuation `usm sweep --over f --extremum speed` runs
 * (without multipliers, which do not move it), the largest where there are
 * several.  USM_ENOSOLUTION when the range holds no maximum. */
static int speed_max_frequency(const usm_model *m, const usm_params *p, double *value)
{
    usm_sweep *s = usm_sweep_alloc(m);
    usm_sweep_options o;
    const usm_sweep_monitor mon = {"speed", monitor_speed, NULL, 1, 0, {0}};
    if (!s)
        return USM_EFAILED;
    usm_sweep_options_default(&o);
    o.over = usm_param_table[USM_P_f].name;
    o.from = USM_FIT_F_LO;
    o.to = USM_FIT_F_HI;
    o.points = USM_FIT_F_POINTS;
    o.floquet = 0;
    o.operating_point = 0;
    o.threads = 1;
    o.monitors = &mon;
    o.nmonitors = 1;
    int rc = usm_sweep_run(s, p, &o);
    if (rc == USM_OK) {
        double best = -INFINITY;
        rc = USM_ENOSOLUTION;
        for (size_t i = 0; i < usm_sweep_event_count(s); ++i) {
            const usm_sweep_event *ev = usm_sweep_event_at(s, i);
            if (ev->type == USM_EVENT_MAXIMUM && ev->monitor_value > best) {
                best = ev->monitor_value;
                *value = ev->value;
                rc = USM_OK;
            }
        }
    }
    usm_sweep_free(s);
    return rc;
}

/* Datasheet quantity `out` at parameters p (a row's conditions set):
 * NaN with *reason when it does not exist there. */
static double datasheet_at(fit_eval *e, const usm_params *p, int out, const char **reason)
{
    usm_quantity_options qo;
    char msg[USM_MSG_LEN];
    double v = NAN;
    if (out == USM_FIT_SPEED_MAX_FREQUENCY) {
        e->evaluations++;
        int st = speed_max_frequency(e->m, p, &v);
        if (st != USM_OK || !isfinite(v)) {
            *reason = st == USM_ENOSOLUTION ? "no_solution" : "failed";
            return NAN;
        }
        return v;
    }
    memset(&qo, 0, sizeof qo);
    qo.range.param = -1;
    qo.band_threshold = NAN;
    e->evaluations++;
    int st = usm_robust_quantity_eval(e->m, p, datasheet_quantity(out), &qo, 1, &v, msg);
    if (st != USM_OK || !isfinite(v)) {
        *reason = st == USM_ENOSOLUTION ? "no_solution" : "failed";
        return NAN;
    }
    return v;
}

/* Row r's datasheet value i: its value at t (the row's parameters p) and its
 * Jacobian row by central differences, a step of USM_FIT_DATASHEET_STEP in
 * the fitted scale (one-sided where one side has no value).  A value that
 * does not exist is the motor at rest's (0) with its reason. */
static void datasheet_row(fit_eval *e, const double *t, int r, int i, const char **reason)
{
    const usm_fit_data *d = e->d;
    const int out = d->out[e->idx[i] % d->nout];
    usm_params p;
    double *J = e->J + (size_t)i * (size_t)e->np;
    fit_params_at(e, t, &p);
    for (int c = 0; c < d->ncond; ++c)
        *usm_params_field(&p, &usm_param_table[d->cond[c]]) =
            d->x[(size_t)r * (size_t)d->ncond + (size_t)c];
    usm_params_couple(e->m, &p, -1);
    const char *why = "";
    double v = datasheet_at(e, &p, out, &why);
    *reason = why;
    for (int j = 0; j < e->np; ++j)
        J[j] = 0.0;
    if (isnan(v)) {
        e->model[i] = 0.0;
        return;
    }
    e->model[i] = v;
    for (int j = 0; j < e->np && !e->no_jacobian; ++j) {
        double ts[USM_NPARAMS], y[2];
        const double h = USM_FIT_DATASHEET_STEP *
                         (e->log_scale[j] ? 1.0 : fmax(fabs(t[j]), 1e-6));
        for (int side = 0; side < 2; ++side) {
            const char *ignored = "";
            memcpy(ts, t, (size_t)e->np * sizeof *ts);
            ts[j] += side ? h : -h;
            usm_params q;
            fit_params_at(e, ts, &q);
            for (int c = 0; c < d->ncond; ++c)
                *usm_params_field(&q, &usm_param_table[d->cond[c]]) =
                    d->x[(size_t)r * (size_t)d->ncond + (size_t)c];
            usm_params_couple(e->m, &q, -1);
            y[side] = datasheet_at(e, &q, out, &ignored);
        }
        double g = !isnan(y[0]) && !isnan(y[1]) ? (y[1] - y[0]) / (2 * h)
                   : !isnan(y[1])                 ? (y[1] - v) / h
                   : !isnan(y[0])                 ? (v - y[0]) / h
                                                  : 0.0;
        J[j] = g / e->w[i];
    }
}

int fit_eval_at(fit_eval *e, const double *t)
{
    const usm_fit_data *d = e->d;
    usm_params pt;
    usm_sensitivity_result sr;
    fit_params_at(e, t, &pt);
    int i = 0;
    e->chi2 = 0;
    for (int r = 0; r < d->nrows && i < e->n; ++r) {
        if (e->idx[i] / d->nout != r)
            continue;
        usm_params p = pt;
        const usm_steady_solution *sol;
        const char *reason;
        for (int c = 0; c < d->ncond; ++c)
            *usm_params_field(&p, &usm_param_table[d->cond[c]]) =
                d->x[(size_t)r * (size_t)d->ncond + (size_t)c];
        /* a row of datasheet values only needs no operating point of its own */
        int steady = 0;
        for (int k = i; k < e->n && e->idx[k] / d->nout == r; ++k)
            steady |= !usm_fit_output_is_datasheet(d->out[e->idx[k] % d->nout]);
        sol = NULL;
        reason = "";
        if (steady && fit_point(e, &p, &sol, e->no_jacobian ? NULL : &sr, &reason) != USM_OK)
            return USM_EFAILED;
        const char *const row_reason = reason;
        for (; i < e->n && e->idx[i] / d->nout == r; ++i) {
            int out = d->out[e->idx[i] % d->nout];
            double y = d->y[e->idx[i]];
            reason = row_reason;
            if (usm_fit_output_is_datasheet(out)) {
                datasheet_row(e, t, r, i, &reason);
                e->f[i] = (e->model[i] - y) / e->w[i];
                e->reason[i] = reason;
                e->chi2 += e->f[i] * e->f[i];
                continue;
            }
            /* no operating point: the motor at rest, every output 0 */
            double v = sol ? usm_fit_output_value(out, sol, &p) : 0.0;
            int ok = isfinite(v);
            for (int j = 0; j < e->np && ok && !e->no_jacobian; ++j) {
                int k = e->o->fit[j];
                double dv = sol ? output_derivative(out, &sr, k) : 0.0;
                if (sol && e->log_scale[j])
                    dv *= usm_params_get(&p, &usm_param_table[k]);
                ok = isfinite(dv);
                e->J[(size_t)i * (size_t)e->np + (size_t)j] = dv / e->w[i];
            }
            if (!ok) { /* an output undefined here (efficiency without power in) */
                v = 0.0;
                for (int j = 0; j < e->np; ++j)
                    e->J[(size_t)i * (size_t)e->np + (size_t)j] = 0.0;
                reason = "failed";
            }
            e->model[i] = v;
            e->f[i] = (v - y) / e->w[i];
            e->reason[i] = reason;
            e->chi2 += e->f[i] * e->f[i];
        }
    }
    memcpy(e->t, t, (size_t)e->np * sizeof *t);
    e->have = 1;
    return USM_OK;
}

int usm_fit_residuals(const usm_model *m, const usm_params *p, const usm_fit_data *d,
                      const usm_fit_options *o, const double *t, double *f, double *J)
{
    fit_eval e;
    int st = fit_eval_init(&e, m, p, d, o);
    if (st == USM_OK)
        st = fit_eval_at(&e, t);
    if (st == USM_OK) {
        memcpy(f, e.f, (size_t)e.n * sizeof *f);
        if (J)
            memcpy(J, e.J, (size_t)e.n * (size_t)e.np * sizeof *J);
    }
    fit_eval_free(&e);
    return st;
}

/* ---- data ---------------------------------------------------------------------- */

usm_fit_data *usm_fit_data_alloc(int nrows, int ncond, int nout)
{
    if (nrows < 1 || ncond < 0 || nout < 1 || ncond > USM_FIT_MAX_COLUMNS ||
        nout > USM_FIT_MAX_COLUMNS)
        return NULL;
    usm_fit_data *d = calloc(1, sizeof *d);
    if (!d)
        return NULL;
    d->nrows = nrows;
    d->ncond = ncond;
    d->nout = nout;
    const size_t nx = (size_t)nrows * (size_t)(ncond ? ncond : 1), ny = (size_t)nrows * (size_t)nout;
    d->x = malloc(nx * sizeof *d->x);
    d->y = malloc(ny * sizeof *d->y);
    d->sigma = malloc(ny * sizeof *d->sigma);
    d->line = calloc((size_t)nrows, sizeof *d->line);
    if (!d->x || !d->y || !d->sigma || !d->line) {
        usm_fit_data_free(d);
        return NULL;
    }
    for (size_t i = 0; i < nx; ++i)
        d->x[i] = NAN;
    for (size_t i = 0; i < ny; ++i)
        d->y[i] = d->sigma[i] = NAN;
    return d;
}

void usm_fit_data_free(usm_fit_data *d)
{
    if (!d)
        return;
    free(d->x);
    free(d->y);
    free(d->sigma);
    free(d->line);
    free(d);
}

int usm_fit_data_count(const usm_fit_data *d)
{
    int n = 0;
    for (size_t i = 0; i < (size_t)d->nrows * (size_t)d->nout; ++i)
        n += !isnan(d->y[i]);
    return n;
}
