/* Parameters identified from measured characteristics (usm_fit.h).
 *
 * Each evaluation solves every row's stationary roots, decides its
 * operating point and differentiates that root analytically, so one pass
 * gives the residuals and the Jacobian together; GSL asks for them
 * separately, so the pass of the last point asked for is kept. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <gsl/gsl_blas.h>
#include <gsl/gsl_cdf.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_linalg.h>
#include <gsl/gsl_matrix.h>
#include <gsl/gsl_multifit_nlinear.h>
#include <gsl/gsl_qrng.h>
#include <gsl/gsl_vector.h>

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

/* ---- options ------------------------------------------------------------------- */

void usm_fit_options_default(usm_fit_options *o)
{
    memset(o, 0, sizeof *o);
    o->starts = 4;
    o->spread = 100.0;
    o->max_iter = 100;
    o->ident_tol = 0.05;
    o->advise = 1;
    o->profile = 1;
    usm_op_options_default(&o->op);
    o->op.from_rest = 1;
}

int usm_fit_parse_names(const usm_model *m, const char *field, const char *text,
                        usm_fit_options *o, char msg[USM_MSG_LEN])
{
    char buf[512];
    if (!text || text[0] == '\0' || strlen(text) >= sizeof buf) {
        snprintf(msg, USM_MSG_LEN, "%s: expected NAME[,NAME...] (parameters to fit)", field);
        return USM_EINPUT;
    }
    strcpy(buf, text);
    o->nfit = 0;
    for (char *save = NULL, *tok = strtok_r(buf, ",", &save); tok;
         tok = strtok_r(NULL, ",", &save)) {
        while (*tok == ' ')
            ++tok;
        const usm_param_info *pi = usm_params_find(tok);
        if (!pi) {
            snprintf(msg, USM_MSG_LEN, "%s: unknown parameter \"%.60s\"", field, tok);
            return USM_EINPUT;
        }
        int k = usm_param_index(pi);
        const usm_param_coupling *c = m ? usm_param_coupled(m, k) : NULL;
        if (c) {
            snprintf(msg, USM_MSG_LEN, "%s: %s equals %s under the assumption of %s: fit %s",
                     field, tok, usm_param_table[c->equals].name, c->because,
                     usm_param_table[c->equals].name);
            return USM_EINPUT;
        }
        for (int j = 0; j < o->nfit; ++j)
            if (o->fit[j] == k) {
                snprintf(msg, USM_MSG_LEN, "%s: %s named twice", field, tok);
                return USM_EINPUT;
            }
        if (o->nfit == USM_NPARAMS) {
            snprintf(msg, USM_MSG_LEN, "%s: too many parameters", field);
            return USM_EINPUT;
        }
        o->fit[o->nfit++] = k;
    }
    if (o->nfit == 0) {
        snprintf(msg, USM_MSG_LEN, "%s: no parameter named", field);
        return USM_EINPUT;
    }
    return USM_OK;
}

/* A parameter fitted in log scale: its range allows no negative value. */
static int log_scale(int k)
{
    return usm_param_ranges[k].lo >= 0.0;
}

int usm_fit_check(const usm_model *m, const usm_params *p, const usm_fit_data *d,
                  const usm_fit_options *o, char msg[USM_MSG_LEN])
{
    if (o->nfit < 1 || o->nfit > USM_NPARAMS) {
        snprintf(msg, USM_MSG_LEN, "fit: no parameter to fit");
        return USM_EINPUT;
    }
    if (o->starts < 1 || o->starts > 100 || o->max_iter < 1 || !(o->ident_tol > 0) ||
        !(o->spread >= 1 && o->spread <= 1e6)) {
        snprintf(msg, USM_MSG_LEN, "fit: starts must be 1..100, spread 1..1e6, max_iter >= 1, "
                 "ident_tol > 0");
        return USM_EINPUT;
    }
    for (int j = 0; j < o->nfit; ++j) {
        int k = o->fit[j];
        if (k < 0 || k >= USM_NPARAMS) {
            snprintf(msg, USM_MSG_LEN, "fit: parameter index %d out of range", k);
            return USM_EINPUT;
        }
        const char *name = usm_param_table[k].name;
        if (m && usm_param_coupled(m, k)) {
            snprintf(msg, USM_MSG_LEN, "%s: tied to %s by the model's assumptions: fit that",
                     name, usm_param_table[usm_param_coupled(m, k)->equals].name);
            return USM_EINPUT;
        }
        for (int c = 0; c < d->ncond; ++c)
            if (d->cond[c] == k) {
                snprintf(msg, USM_MSG_LEN, "%s: is a condition column of the data, it cannot "
                         "also be fitted", name);
                return USM_EINPUT;
            }
        double v = usm_params_get(p, &usm_param_table[k]);
        if (log_scale(k) && !(v > 0)) {
            snprintf(msg, USM_MSG_LEN, "%s: the start value %g must be positive (fitted in log "
                     "scale: --set a positive start)", name, v);
            return USM_EINPUT;
        }
    }
    const int n = usm_fit_data_count(d);
    int all_sigma = 1;
    for (int c = 0; c < d->nout; ++c)
        all_sigma &= d->has_sigma[c];
    if (n < o->nfit || (!all_sigma && n == o->nfit)) {
        snprintf(msg, USM_MSG_LEN, "data: %d measured value%s for %d fitted parameter%s: %s", n,
                 n == 1 ? "" : "s", o->nfit, o->nfit == 1 ? "" : "s",
                 n < o->nfit ? "fewer points than parameters"
                             : "no residual freedom left to estimate sigma (give sigma_ columns "
                               "or more points)");
        return USM_EINPUT;
    }
    return USM_OK;
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
        e->log_scale[j] = log_scale(o->fit[j]);
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

/* ---- the least-squares driver -------------------------------------------------------- */

static int same_point(const fit_eval *e, const gsl_vector *x)
{
    if (!e->have)
        return 0;
    for (int j = 0; j < e->np; ++j)
        if (gsl_vector_get(x, (size_t)j) != e->t[j])
            return 0;
    return 1;
}

static int ensure(fit_eval *e, const gsl_vector *x)
{
    double t[USM_NPARAMS];
    if (same_point(e, x))
        return GSL_SUCCESS;
    for (int j = 0; j < e->np; ++j)
        t[j] = gsl_vector_get(x, (size_t)j);
    if (fit_eval_at(e, t) != USM_OK) {
        e->failed = 1;
        return GSL_ENOMEM;
    }
    return GSL_SUCCESS;
}

static int lm_f(const gsl_vector *x, void *data, gsl_vector *f)
{
    fit_eval *e = data;
    int st = ensure(e, x);
    if (st != GSL_SUCCESS)
        return st;
    for (int i = 0; i < e->n; ++i)
        gsl_vector_set(f, (size_t)i, e->f[i]);
    return GSL_SUCCESS;
}

static int lm_df(const gsl_vector *x, void *data, gsl_matrix *J)
{
    fit_eval *e = data;
    int st = ensure(e, x);
    if (st != GSL_SUCCESS)
        return st;
    for (int i = 0; i < e->n; ++i)
        for (int j = 0; j < e->np; ++j)
            gsl_matrix_set(J, (size_t)i, (size_t)j, e->J[(size_t)i * (size_t)e->np + (size_t)j]);
    return GSL_SUCCESS;
}

/* One local search from t (replaced by its end); its sum of squares in *chi2. */
static int local_search(fit_eval *e, gsl_multifit_nlinear_workspace *w, double *t, double *chi2,
                        int *iters)
{
    gsl_multifit_nlinear_fdf fdf;
    gsl_vector_view x0 = gsl_vector_view_array(t, (size_t)e->np);
    int info;
    memset(&fdf, 0, sizeof fdf);
    fdf.f = lm_f;
    fdf.df = lm_df;
    fdf.fvv = NULL; /* geodesic acceleration's second directional derivative by differences */
    fdf.n = (size_t)e->n;
    fdf.p = (size_t)e->np;
    fdf.params = e;
    e->failed = 0;
    if (gsl_multifit_nlinear_init(&x0.vector, &fdf, w) != GSL_SUCCESS || e->failed)
        return e->failed ? USM_EFAILED : USM_ENOSOLUTION;
    int st = gsl_multifit_nlinear_driver((size_t)e->o->max_iter, 1e-10, 1e-10, 0.0, NULL, NULL,
                                         &info, w);
    if (e->failed)
        return USM_EFAILED;
    const gsl_vector *x = gsl_multifit_nlinear_position(w);
    for (int j = 0; j < e->np; ++j)
        t[j] = gsl_vector_get(x, (size_t)j);
    *iters += (int)gsl_multifit_nlinear_niter(w);
    (void)st; /* a search stopped at max_iter or unable to improve still has its best point */
    if (fit_eval_at(e, t) != USM_OK)
        return USM_EFAILED;
    *chi2 = e->chi2;
    return isfinite(e->chi2) ? USM_OK : USM_ENOSOLUTION;
}

/* The box of the starts in the fitted scale: a log-scale parameter from its
 * given value divided by o->spread to the value times o->spread, a linear one
 * the given value +- o->spread times its magnitude (at least a thousandth of
 * its range), both clipped into the physical range (usm_param_ranges). */
static void start_box(const fit_eval *e, int j, double *lo, double *hi)
{
    const int k = e->o->fit[j];
    const double v = usm_params_get(&e->base, &usm_param_table[k]), f = e->o->spread;
    const usm_param_range rg = usm_param_ranges[k];
    if (e->log_scale[j]) {
        *lo = log(v / f);
        *hi = log(v * f);
        if (rg.lo > 0 && *lo < log(rg.lo))
            *lo = log(rg.lo);
        if (*hi > log(rg.hi))
            *hi = log(rg.hi);
    } else {
        const double w = f * fmax(fabs(v), 1e-3 * (rg.hi - rg.lo));
        *lo = fmax(v - w, rg.lo);
        *hi = fmin(v + w, rg.hi);
    }
}

/* The candidates of the starts: the first `count` points of the Sobol
 * sequence in as many dimensions as parameters (GSL's gsl_qrng_sobol, the
 * all-zero corner skipped: deterministic, no seed), mapped into the box;
 * row-major count x np in t.  USM_OK or USM_EFAILED. */
static int start_candidates(const fit_eval *e, int count, double *t)
{
    double lo[USM_NPARAMS], hi[USM_NPARAMS], u[USM_NPARAMS];
    gsl_qrng *q = gsl_qrng_alloc(gsl_qrng_sobol, (unsigned)e->np);
    if (!q)
        return USM_EFAILED;
    for (int j = 0; j < e->np; ++j)
        start_box(e, j, &lo[j], &hi[j]);
    gsl_qrng_get(q, u); /* the corner (0, ..., 0) */
    for (int s = 0; s < count; ++s) {
        gsl_qrng_get(q, u);
        for (int j = 0; j < e->np; ++j)
            t[(size_t)s * (size_t)e->np + (size_t)j] = lo[j] + u[j] * (hi[j] - lo[j]);
    }
    gsl_qrng_free(q);
    return USM_OK;
}

/* The starts: the given values, then the start_count - 1 candidates with the
 * lowest sum of squares (evaluated without the Jacobian) among
 * USM_FIT_SCREEN per start, ties kept in the sequence's order.  t holds
 * o->starts x np; *nstarts the starts found (fewer when candidates fail). */
static int choose_starts(fit_eval *e, double *t, int *nstarts)
{
    const int np = e->np, want = e->o->starts - 1, ncand = USM_FIT_SCREEN * want;
    double *cand = NULL, *chi2 = NULL;
    int *order = NULL;
    *nstarts = 1;
    for (int j = 0; j < np; ++j)
        t[j] = e->log_scale[j]
                   ? log(usm_params_get(&e->base, &usm_param_table[e->o->fit[j]]))
                   : usm_params_get(&e->base, &usm_param_table[e->o->fit[j]]);
    if (want < 1)
        return USM_OK;
    cand = malloc((size_t)ncand * (size_t)np * sizeof *cand);
    chi2 = malloc((size_t)ncand * sizeof *chi2);
    order = malloc((size_t)ncand * sizeof *order);
    int st = cand && chi2 && order ? start_candidates(e, ncand, cand) : USM_EFAILED;
    e->no_jacobian = 1;
    for (int s = 0; s < ncand && st == USM_OK; ++s) {
        st = fit_eval_at(e, cand + (size_t)s * (size_t)np);
        chi2[s] = isfinite(e->chi2) ? e->chi2 : INFINITY;
        order[s] = s;
    }
    e->no_jacobian = 0;
    e->have = 0;
    if (st == USM_OK) {
        /* insertion sort: stable, and ncand is small */
        for (int a = 1; a < ncand; ++a)
            for (int b = a; b > 0 && chi2[order[b]] < chi2[order[b - 1]]; --b) {
                int tmp = order[b];
                order[b] = order[b - 1];
                order[b - 1] = tmp;
            }
        for (int s = 0; s < want && isfinite(chi2[order[s]]); ++s, ++*nstarts)
            memcpy(t + (size_t)*nstarts * (size_t)np, cand + (size_t)order[s] * (size_t)np,
                   (size_t)np * sizeof *t);
    }
    free(cand);
    free(chi2);
    free(order);
    return st;
}

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void usm_fit_result_free(usm_fit_result *r)
{
    if (!r)
        return;
    free(r->points);
    r->points = NULL;
    r->npoints = 0;
}

static int fail(usm_fit_result *out, int status, const char *fmt, const char *arg)
{
    out->status = status;
    snprintf(out->message, sizeof out->message, fmt, arg);
    return status;
}

/* ---- profile likelihood --------------------------------------------------------------- */

/* The sum of squares minimized over every fitted parameter but j, with j
 * held at the fitted-scale value z, started from the estimate t.  NaN when
 * z leaves the parameter's range or no finite minimum is found. */
static double profile_chi2(const usm_model *m, const usm_fit_data *d, const usm_fit_options *o,
                           const fit_eval *full, const double *t, int j, double z, int *evals)
{
    const int k = o->fit[j];
    const double v = full->log_scale[j] ? exp(z) : z;
    const usm_param_range rg = usm_param_ranges[k];
    if (!(v >= rg.lo && v <= rg.hi) || (full->log_scale[j] && !(v > 0)))
        return NAN;
    usm_params p;
    fit_params_at(full, t, &p);
    *usm_params_field(&p, &usm_param_table[k]) = v;
    usm_fit_options so = *o;
    double ts[USM_NPARAMS], chi2 = NAN;
    so.nfit = 0;
    for (int i = 0; i < o->nfit; ++i)
        if (i != j) {
            ts[so.nfit] = t[i];
            so.fit[so.nfit++] = o->fit[i];
        }
    fit_eval e;
    if (fit_eval_init(&e, m, &p, d, &so) == USM_OK) {
        if (so.nfit == 0) {
            if (fit_eval_at(&e, ts) == USM_OK)
                chi2 = e.chi2;
        } else {
            gsl_multifit_nlinear_parameters fp = gsl_multifit_nlinear_default_parameters();
            fp.trs = gsl_multifit_nlinear_trs_lmaccel;
            gsl_multifit_nlinear_workspace *w =
                gsl_multifit_nlinear_alloc(gsl_multifit_nlinear_trust, &fp, (size_t)e.n,
                                           (size_t)e.np);
            int iters = 0;
            if (w && local_search(&e, w, ts, &chi2, &iters) != USM_OK)
                chi2 = NAN;
            gsl_multifit_nlinear_free(w);
        }
    }
    *evals += e.evaluations;
    fit_eval_free(&e);
    return chi2;
}

/* Each end of each interval checked against the profile likelihood: the
 * profile's deviation at the Jacobian's end, g = sqrt(dchi2) / (q s) - 1
 * (0 for a quadratic sum of squares), decides; where |g| > 0.1 the end is
 * located by bisection in sqrt(dchi2) after stepping out by doubling. */
static void profile(const usm_model *m, const usm_fit_data *d, const usm_fit_options *o,
                    const fit_eval *e, const double *t, usm_fit_result *out)
{
    const double level = out->quantile * out->sigma_scale;
    for (int j = 0; j < out->nfit; ++j) {
        out->profiled[j] = 0;
        out->profile_lo[j] = out->lo[j];
        out->profile_hi[j] = out->hi[j];
        const double h = out->quantile * out->se_scaled[j];
        if (!isfinite(h) || !(h > 0) || !isfinite(level))
            continue;
        for (int side = -1; side <= 1; side += 2) {
            double a = 0, b = h, c2 = profile_chi2(m, d, o, e, t, j, t[j] + side * h,
                                                   &out->evaluations);
            double r = sqrt(fmax(c2 - out->chi2, 0)) / level; /* 1 for a quadratic */
            if (isfinite(r) && fabs(r - 1) <= 0.1)
                continue;
            out->profiled[j] = 1;
            double end = INFINITY;
            if (!isfinite(r) || r < 1) { /* flatter: step out until the level is passed */
                a = h;
                for (int k = 0; k < 8 && !(isfinite(r) && r >= 1); ++k) {
                    a = b;
                    b *= 2;
                    c2 = profile_chi2(m, d, o, e, t, j, t[j] + side * b, &out->evaluations);
                    r = sqrt(fmax(c2 - out->chi2, 0)) / level;
                    if (!isfinite(c2))
                        break;
                }
            }
            if (isfinite(r) && r >= 1) {
                for (int k = 0; k < 12; ++k) {
                    double mid = 0.5 * (a + b);
                    c2 = profile_chi2(m, d, o, e, t, j, t[j] + side * mid, &out->evaluations);
                    r = sqrt(fmax(c2 - out->chi2, 0)) / level;
                    if (isfinite(r) && r >= 1)
                        b = mid;
                    else
                        a = mid;
                }
                end = t[j] + side * b;
                end = e->log_scale[j] ? exp(end) : end;
            } else
                end = side < 0 ? (e->log_scale[j] ? 0.0 : -INFINITY) : INFINITY;
            if (side < 0)
                out->profile_lo[j] = end;
            else
                out->profile_hi[j] = end;
        }
    }
}

int usm_fit_run(const usm_model *m, const usm_params *p, const usm_fit_data *d,
                const usm_fit_options *o, usm_fit_result *out)
{
    fit_eval e;
    gsl_multifit_nlinear_workspace *w = NULL;
    double t0 = now(), best[USM_NPARAMS], best_chi2 = INFINITY;
    int status;
    memset(out, 0, sizeof *out);
    if ((status = usm_fit_check(m, p, d, o, out->message)) != USM_OK) {
        out->status = status;
        return status;
    }
    if (fit_eval_init(&e, m, p, d, o) != USM_OK) {
        fit_eval_free(&e);
        return fail(out, USM_EFAILED, "%s", "out of memory");
    }
    out->nfit = o->nfit;
    for (int j = 0; j < o->nfit; ++j) {
        out->fit[j] = o->fit[j];
        out->log_scale[j] = e.log_scale[j];
        out->start[j] = usm_params_get(p, &usm_param_table[o->fit[j]]);
    }
    gsl_multifit_nlinear_parameters fp = gsl_multifit_nlinear_default_parameters();
    fp.trs = gsl_multifit_nlinear_trs_lmaccel;
    if (!(w = gsl_multifit_nlinear_alloc(gsl_multifit_nlinear_trust, &fp, (size_t)e.n,
                                         (size_t)e.np))) {
        fit_eval_free(&e);
        return fail(out, USM_EFAILED, "%s", "out of memory");
    }
    double *starts = malloc((size_t)o->starts * (size_t)e.np * sizeof *starts), chi2s[100];
    int nstarts = 0;
    status = starts ? choose_starts(&e, starts, &nstarts) : USM_EFAILED;
    if (status == USM_OK)
        status = USM_ENOSOLUTION;
    for (int s = 0; s < nstarts && status != USM_EFAILED; ++s) {
        double t[USM_NPARAMS], chi2 = INFINITY;
        memcpy(t, starts + (size_t)s * (size_t)e.np, (size_t)e.np * sizeof *t);
        int st = local_search(&e, w, t, &chi2, &out->iterations);
        out->starts++;
        chi2s[s] = st == USM_OK ? chi2 : INFINITY;
        if (st == USM_EFAILED) {
            status = USM_EFAILED;
            break;
        }
        if (st == USM_OK && chi2 < best_chi2) {
            best_chi2 = chi2;
            memcpy(best, t, sizeof t);
            out->best_start = s;
            status = USM_OK;
        }
    }
    /* a start reached the best minimum when its sum of squares is the best's
     * within 1e-6 of it (and 1e-9 per value: an exact fit's is 0) */
    for (int s = 0; s < out->starts && status == USM_OK; ++s)
        out->starts_at_best += chi2s[s] <= best_chi2 + 1e-6 * best_chi2 + 1e-9 * e.n;
    free(starts);
    gsl_multifit_nlinear_free(w);
    if (status == USM_OK)
        status = fit_eval_at(&e, best);
    if (status == USM_OK)
        status = fit_statistics(&e, best, out);
    out->evaluations = e.evaluations;
    if (status == USM_OK && o->profile)
        profile(m, d, o, &e, best, out);
    if (status != USM_OK && !out->message[0])
        fail(out, status, "%s", status == USM_EFAILED ? "out of memory"
                                                        : "no start gives a finite sum of squares");
    fit_eval_free(&e);
    out->status = status;
    out->wall = now() - t0;
    return status;
}
