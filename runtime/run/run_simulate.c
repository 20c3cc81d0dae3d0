/* run_simulate.c: usm simulate's run as a library call (usm_run.h): the
 * check, the integration timed as the command times it, the caller's
 * callbacks or the kept time history, the spectrum of the samples, the
 * --json summary. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "core/grow.h"
#include "run_internal.h"

typedef struct sim_data {
    usm_sim *s;
    usm_sim_options opt;
    usm_sim_summary sum;
    double wall;
    usm_sim_spectrum *spec;          /* spectrum_periods >= 0 */
    usm_sim_spectrum_result spec_res;
    int have_spec;
    char spec_error[USM_MSG_LEN];    /* why there is none ("" before the run) */
    /* during the run: the caller's callbacks, or the history being kept */
    const usm_sim_callbacks *user;
    usm_run *run;
    size_t cap;
    int history_oom, spec_oom;
} sim_data;

static void sim_data_free(void *data)
{
    sim_data *d = data;
    if (!d)
        return;
    usm_sim_spectrum_free(d->spec);
    usm_sim_free(d->s);
    free(d);
}

void usm_run_sim_report(const usm_run *r, usm_sim_report *rep)
{
    const sim_data *d = run_data(r, RUN_SIMULATE);
    memset(rep, 0, sizeof *rep);
    if (!d || !r->has_json)
        return;
    rep->model = r->model;
    rep->params = &r->params;
    rep->opt = &d->opt;
    rep->summary = &d->sum;
    rep->wall = d->wall;
    rep->spectrum = d->have_spec ? &d->spec_res : NULL;
    rep->spectrum_error = d->spec ? d->spec_error : NULL;
}

static int sim_json(const usm_run *r, FILE *out)
{
    usm_sim_report rep;
    usm_run_sim_report(r, &rep);
    return usm_sim_write_json(&rep, out);
}

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* One row of the history in usm_sim_csv_header's columns. */
static int keep_row(sim_data *d, const usm_sim_sample *s)
{
    usm_run *r = d->run;
    if (usm_grow((void **)&r->rows, &d->cap, r->nrows + 1,
                 USM_RUN_SIM_COLUMNS * sizeof *r->rows) != 0)
        return d->history_oom = 1;
    const double v[USM_RUN_SIM_COLUMNS] = {
        s->t, s->phi, s->theta, s->psi, s->phidot, s->thetadot, s->psidot, s->rotor_angle,
        s->rotor_speed, s->out[USM_OUT_F_N], s->out[USM_OUT_F_T], s->out[USM_OUT_V_REL],
        s->have_avg ? s->theta_avg : NAN, s->have_avg ? s->rotor_speed_avg : NAN,
        (double)s->validity};
    memcpy(r->rows + r->nrows * USM_RUN_SIM_COLUMNS, v, sizeof v);
    r->nrows++;
    return 0;
}

/* A sample: the spectrum's, then the caller's or the history's. */
static int on_sample(const usm_sim_sample *s, void *data)
{
    sim_data *d = data;
    if (d->spec && usm_sim_spectrum_add(d->spec, s) != 0)
        return d->spec_oom = 1;
    if (d->user)
        return d->user->sample ? d->user->sample(s, d->user->data) : 0;
    return keep_row(d, s);
}

static void on_progress(double t, double t0, double t1, void *data)
{
    const sim_data *d = data;
    d->user->progress(t, t0, t1, d->user->data);
}

static void on_warning(const char *msg, void *data)
{
    const sim_data *d = data;
    d->user->warning(msg, d->user->data);
}

usm_run *usm_run_simulate(const usm_model *m, const usm_params *p, const usm_sim_options *opt,
                          const usm_sim_callbacks *cb, long spectrum_periods)
{
    sim_data *d = calloc(1, sizeof *d);
    usm_run *r = run_new(RUN_SIMULATE, m, p, d, sim_data_free);
    usm_sim_callbacks own = {NULL, NULL, NULL, NULL};
    usm_sim_spectrum_options so;
    char lib[USM_MSG_LEN];
    if (!r)
        return NULL;
    r->write_json = sim_json;
    d->opt = *opt;
    d->run = r;
    d->user = cb;
    r->ncols = USM_RUN_SIM_COLUMNS;
    if (!(d->s = usm_sim_alloc(m))) {
        run_fail(r, USM_EFAILED, "out of memory");
        return r;
    }
    if (usm_sim_check(d->s, &r->params, &d->opt) != USM_OK) {
        run_fail(r, USM_EINPUT, "%s", usm_sim_message(d->s));
        return r;
    }
    if (spectrum_periods >= 0) {
        usm_sim_spectrum_options_default(&so);
        so.f = r->params.f;
        so.periods = spectrum_periods;
        so.rate = d->opt.rate;
        if (usm_sim_spectrum_check(&so, d->opt.duration, lib) != USM_OK) {
            run_fail(r, USM_EINPUT, "spectrum: %s", lib);
            return r;
        }
        if (!(d->spec = usm_sim_spectrum_alloc())) {
            run_fail(r, USM_EFAILED, "out of memory");
            return r;
        }
    }
    own.data = d;
    if (d->spec || (cb ? cb->sample != NULL : d->opt.rate > 0))
        own.sample = on_sample;
    own.progress = cb && cb->progress ? on_progress : NULL;
    own.warning = cb && cb->warning ? on_warning : NULL;
    const double w0 = now();
    int rc = usm_sim_run(d->s, &r->params, &d->opt, &own, &d->sum);
    d->wall = now() - w0;
    if (d->history_oom) {
        run_fail(r, USM_EFAILED, "out of memory");
        return r;
    }
    if (rc == USM_EINPUT || rc == USM_ENOSOLUTION) {
        run_fail(r, rc, "%s", usm_sim_message(d->s));
        return r;
    }
    r->has_json = 1;
    if (d->spec_oom && d->sum.stop == USM_SIM_STOPPED)
        snprintf(d->sum.reason, sizeof d->sum.reason,
                 "out of memory recording the samples of the spectrum at t = %.9g s",
                 d->sum.t_reached);
    if (rc != USM_OK)
        run_fail(r, rc, "%s", d->spec_oom ? d->sum.reason : usm_sim_message(d->s));
    if (!d->spec)
        return r;
    /* the spectrum of what was simulated, also of a run that stopped early
     * (its window is then the end of what exists) */
    if (d->spec_oom)
        snprintf(d->spec_error, sizeof d->spec_error, "out of memory recording the samples");
    else if (usm_sim_spectrum_compute(d->spec, &so, &d->spec_res, lib) == USM_OK)
        d->have_spec = 1;
    else {
        snprintf(d->spec_error, sizeof d->spec_error, "%s", lib);
        if (r->status == USM_OK)
            run_fail(r, USM_EFAILED, "spectrum: %s", lib);
    }
    return r;
}

const usm_sim_summary *usm_run_sim_summary(const usm_run *r)
{
    const sim_data *d = run_data(r, RUN_SIMULATE);
    return d && r->has_json ? &d->sum : NULL;
}

const usm_sim_spectrum_result *usm_run_spectrum(const usm_run *r)
{
    const sim_data *d = run_data(r, RUN_SIMULATE);
    return d && d->have_spec ? &d->spec_res : NULL;
}

const char *usm_run_spectrum_error(const usm_run *r)
{
    const sim_data *d = run_data(r, RUN_SIMULATE);
    return d && d->spec && !d->have_spec && d->spec_error[0] ? d->spec_error : NULL;
}

const double *usm_run_spectrum_amplitudes(const usm_run *r, int channel)
{
    const sim_data *d = run_data(r, RUN_SIMULATE);
    return d && d->have_spec ? usm_sim_spectrum_amplitudes(d->spec, channel) : NULL;
}

int usm_run_spectrum_write_csv(const usm_run *r, FILE *out)
{
    const sim_data *d = run_data(r, RUN_SIMULATE);
    return d && d->have_spec ? usm_sim_spectrum_write_csv(d->spec, &d->spec_res, out) : -1;
}
