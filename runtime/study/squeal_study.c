/* The motion over one parameter beyond the last periodic orbit
 * (usm_squeal_study.h, docs/squeal.md): long event-driven runs, their
 * stroboscopic samples, Lyapunov exponents, classification and audible
 * spectrum. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <gsl/gsl_complex_math.h>
#include <gsl/gsl_eigen.h>

#include "core/grow.h"
#include "usm_periodic.h"
#include "usm_simulate.h"
#include "usm_spectrum.h"
#include "usm_squeal_study.h"

#define AUDIBLE_LO 20.0
#define AUDIBLE_HI 20000.0
#define V_REF 1e-9 /* m/s: velocity level reference (ISO 1683) */
#define COEXIST_SPEED 0.02

typedef struct strobe {
    size_t n;
    double *speed, *theta, *gap;
} strobe;

struct usm_squeal_study {
    const usm_model *m;
    usm_sim *sim;
    usm_hybrid *hyb;
    usm_squeal_options o;
    char over[64];
    usm_squeal_point *pts;
    double *f;
    strobe *st;
    double (*x_last)[USM_MAX_NX]; /* each value's last closed state and its time: */
    double *t_last;               /* where its orbit is sought (the origin) */
    usm_params base;
    usm_squeal_origin origin;
    double origin_t0, origin_x0[USM_MAX_NX]; /* the origin's orbit: where the onset's search
                                                starts */
    usm_squeal_onset onset;
    int onset_done;
    size_t npts;
    char msg[USM_MSG_LEN];
};

/* the recorder of one run's window */
typedef struct rec {
    long first, m, n;      /* first sample index of the window, samples a period, periods */
    long k;                /* samples seen */
    double R, H;
    double *v, *speed, *theta, *gap;
    int *open;
    int have_y, open0;
    double t0;
    double y0[USM_MAX_NY];
    int have_closed;       /* the last sample with the contact closed: where the next
                              value's run starts (a closed state needs no rotor height) */
    double t_closed;
    double x_closed[USM_MAX_NX];
} rec;

const char *usm_motion_name(usm_motion m)
{
    static const char *const names[] = {"periodic", "quasi_periodic", "chaotic",
                                        "settling", "rest",           "failed"};
    return (unsigned)m < sizeof names / sizeof *names ? names[m] : "unknown";
}

void usm_squeal_options_default(usm_squeal_options *opt)
{
    memset(opt, 0, sizeof *opt);
    opt->settle = 400;
    opt->window = 1024;
    opt->samples_per_period = 8;
    opt->lyapunov_skip = 50;
    opt->lyapunov_periods = 200;
    opt->rtol = 1e-8;
    opt->lyapunov_rtol = 1e-8;
    opt->period_tol = 1e-3;
    opt->exponent_tol = 0.01;
    opt->check_rest = 1;
    opt->lines = 6;
    opt->origin = 1;
    opt->power_periods = 200;
    opt->power_rtol = 1e-9;
    opt->sensitivities = 0;
    opt->sensitivity_h = 1e-3;
    opt->onset_tol = 1e-6;
}

usm_squeal_study *usm_squeal_alloc(const usm_model *m)
{
    if (!m)
        return NULL;
    usm_squeal_study *s = calloc(1, sizeof *s);
    if (!s)
        return NULL;
    s->m = m;
    s->sim = usm_sim_alloc(m);
    s->hyb = m->unilateral ? usm_hybrid_alloc(m) : NULL;
    if (!s->sim || (m->unilateral && !s->hyb)) {
        usm_squeal_free(s);
        return NULL;
    }
    return s;
}

static void clear_points(usm_squeal_study *s)
{
    for (size_t i = 0; s->st && i < s->npts; ++i) {
        free(s->st[i].speed);
        free(s->st[i].theta);
        free(s->st[i].gap);
    }
    free(s->st);
    free(s->pts);
    free(s->f);
    free(s->x_last);
    free(s->t_last);
    s->x_last = NULL;
    s->t_last = NULL;
    s->st = NULL;
    s->pts = NULL;
    s->f = NULL;
    s->npts = 0;
}

void usm_squeal_free(usm_squeal_study *s)
{
    if (!s)
        return;
    clear_points(s);
    usm_sim_free(s->sim);
    usm_hybrid_free(s->hyb);
    free(s);
}

const char *usm_squeal_message(const usm_squeal_study *s) { return s->msg; }
const usm_model *usm_squeal_model(const usm_squeal_study *s) { return s->m; }
size_t usm_squeal_count(const usm_squeal_study *s) { return s->npts; }
const char *usm_squeal_over(const usm_squeal_study *s) { return s->over; }

const usm_squeal_point *usm_squeal_point_at(const usm_squeal_study *s, size_t i)
{
    return i < s->npts ? &s->pts[i] : NULL;
}

double usm_squeal_f(const usm_squeal_study *s, size_t i) { return i < s->npts ? s->f[i] : NAN; }

int usm_squeal_strobe(const usm_squeal_study *s, size_t i, size_t *n, const double **speed,
                      const double **theta, const double **gap)
{
    if (i >= s->npts || !s->st[i].speed) {
        *n = 0;
        *speed = *theta = *gap = NULL;
        return -1;
    }
    *n = s->st[i].n;
    *speed = s->st[i].speed;
    *theta = s->st[i].theta;
    *gap = s->st[i].gap;
    return 0;
}

int usm_squeal_check(usm_squeal_study *s, const usm_params *p, const usm_squeal_options *o)
{
    char why[USM_MSG_LEN];
    s->msg[0] = '\0';
#define BAD(...)                                                                              \
    do {                                                                                      \
        snprintf(s->msg, USM_MSG_LEN, __VA_ARGS__);                                           \
        return USM_EINPUT;                                                                    \
    } while (0)
    if (!s->m->unilateral)
        BAD("model: %s has a contact that never opens; the motion past the last periodic "
            "orbit needs one that may (variant imperfect_unilateral)", s->m->name);
    if (!o->over || !*o->over)
        BAD("over: the parameter to vary is missing");
    const usm_param_info *info = usm_params_find(o->over);
    if (!info)
        BAD("over: unknown parameter \"%.60s\"", o->over);
    if (!isfinite(o->from) || !isfinite(o->to) || o->from == o->to)
        BAD("from, to: must be finite and different");
    if (o->points < 2 || o->points > 10000)
        BAD("points: %d, must be 2 to 10000", o->points);
    if (o->settle < 0 || o->settle > 10000000)
        BAD("settle: %ld periods, must be 0 to 1e7", o->settle);
    if (o->window < 16 || o->window > 10000000)
        BAD("window: %ld periods, must be 16 to 1e7", o->window);
    if (o->samples_per_period < 4 || o->samples_per_period > 64)
        BAD("samples_per_period: %d, must be 4 to 64", o->samples_per_period);
    if (o->lyapunov_skip < 0 || o->lyapunov_periods < 1)
        BAD("lyapunov_periods: must be at least 1 (lyapunov_skip at least 0)");
    if (!(o->period_tol > 0 && o->period_tol < 1))
        BAD("period_tol: must be in (0, 1)");
    if (!(o->exponent_tol > 0))
        BAD("exponent_tol: must be positive");
    if (o->lines < 1 || o->lines > USM_SQUEAL_MAX_LINES)
        BAD("lines: %d, must be 1 to %d", o->lines, USM_SQUEAL_MAX_LINES);
    if (!(o->lyapunov_rtol >= 1e-14 && o->lyapunov_rtol <= 1e-3))
        BAD("lyapunov_rtol: must be in [1e-14, 1e-3]");
    if (o->sensitivities && !(o->sensitivity_h > 0 && o->sensitivity_h < 0.1))
        BAD("sensitivity_h: must be in (0, 0.1)");
    if (o->sensitivities && !(o->onset_tol > 0 && o->onset_tol < 0.1))
        BAD("onset_tol: must be in (0, 0.1)");
    if (o->power_periods < 0 || o->power_periods > 10000000)
        BAD("power_periods: %ld, must be 0 to 1e7", o->power_periods);
    if (o->power_periods > 0 && !(o->power_rtol >= 1e-14 && o->power_rtol <= 1e-3))
        BAD("power_rtol: must be in [1e-14, 1e-3]");
    for (int end = 0; end < 2; ++end) {
        usm_params q = *p;
        *usm_params_field(&q, info) = end ? o->to : o->from;
        if (usm_params_check(&q, s->m, why) != USM_OK)
            BAD("%.200s (the study's %s)", why, end ? "to" : "from");
        usm_sim_options so;
        usm_sim_options_default(&so);
        so.duration = (double)(o->settle + o->window) / q.f;
        so.rtol = o->rtol;
        so.rate = o->samples_per_period * q.f;
        if (usm_sim_check(s->sim, &q, &so) != USM_OK)
            BAD("%.200s", usm_sim_message(s->sim));
    }
#undef BAD
    return USM_OK;
}

static int record(const usm_sim_sample *smp, void *data)
{
    rec *r = data;
    if (!smp->open) {
        r->have_closed = 1;
        r->t_closed = smp->t;
        memcpy(r->x_closed, smp->y, sizeof(double) * (size_t)smp->nx);
    }
    const long i = r->k++ - r->first;
    if (i < 0 || i >= r->n * r->m)
        return 0;
    if (i == 0) {
        r->t0 = smp->t;
        r->open0 = smp->open;
        r->have_y = 1;
        memcpy(r->y0, smp->y, sizeof(double) * (size_t)smp->ny);
    }
    const double th = smp->theta;
    r->v[i] = (r->R * cos(th) - r->H * sin(th)) * smp->thetadot;
    r->speed[i] = smp->rotor_speed;
    r->theta[i] = th;
    r->gap[i] = smp->gap;
    r->open[i] = smp->open;
    return 0;
}

/* The smallest k <= USM_SQUEAL_MAX_PERIOD after which every stroboscopic
 * sample repeats (0: none). */
static int period_of(const rec *r, double tol)
{
    const long n = r->n, m = r->m;
    double mean_w = 0, mean_t = 0;
    for (long j = 0; j < n; ++j) {
        mean_w += r->speed[j * m] / (double)n;
        mean_t += r->theta[j * m] / (double)n;
    }
    const double sw = fmax(fabs(mean_w), 1e-12), st = fmax(fabs(mean_t), 1e-15),
                 sg = r->R * st;
    for (int k = 1; k <= USM_SQUEAL_MAX_PERIOD && k < n / 2; ++k) {
        int ok = 1;
        for (long j = 0; ok && j + k < n; ++j) {
            const long a = j * m, b = (j + k) * m;
            ok = fabs(r->speed[b] - r->speed[a]) <= tol * sw &&
                 fabs(r->theta[b] - r->theta[a]) <= tol * st &&
                 fabs(r->gap[b] - r->gap[a]) <= tol * sg;
        }
        if (ok)
            return k;
    }
    return 0;
}

/* The strongest line of the stroboscopic tilt in (0, f/2] [Hz] (NaN: none). */
static double second_frequency(const rec *r, double f)
{
    const size_t n = (size_t)r->n;
    double *x = malloc(sizeof(double) * n), *amp = malloc(sizeof(double) * (n / 2 + 1));
    double out = NAN;
    char msg[USM_MSG_LEN];
    if (x && amp) {
        for (size_t j = 0; j < n; ++j)
            x[j] = r->theta[j * (size_t)r->m];
        usm_spectrum_line line;
        if (usm_spectrum_amplitude(x, n, 1.0 / f, amp, msg) == USM_OK &&
            usm_spectrum_lines(amp, n / 2 + 1, f / (double)n, 0.0, 1, &line) == 1)
            out = line.frequency;
    }
    free(x);
    free(amp);
    return out;
}

/* The audible lines of the rim velocity over the window. */
static int audible(const rec *r, double f, int want, usm_squeal_point *pt)
{
    const size_t n = (size_t)(r->n * r->m), nb = n / 2 + 1;
    const double df = f / (double)r->n;
    double *amp = malloc(sizeof(double) * nb);
    usm_spectrum_line *lines = malloc(sizeof *lines * nb);
    char msg[USM_MSG_LEN];
    int rc = USM_EFAILED;
    pt->df = df;
    if (amp && lines && usm_spectrum_amplitude(r->v, n, 1.0 / (f * (double)r->m), amp, msg) ==
                            USM_OK) {
        const size_t nl = usm_spectrum_lines(amp, nb, df, f, nb, lines);
        pt->nlines = 0;
        for (size_t i = 0; i < nl && pt->nlines < (size_t)want; ++i) {
            if (lines[i].frequency < AUDIBLE_LO || lines[i].frequency > AUDIBLE_HI)
                continue;
            usm_squeal_line *l = &pt->lines[pt->nlines++];
            l->frequency = lines[i].frequency;
            l->amplitude = lines[i].amplitude;
            l->level_db = 20.0 * log10(lines[i].amplitude / sqrt(2.0) / V_REF);
        }
        rc = USM_OK;
    }
    free(amp);
    free(lines);
    return rc;
}

/* One run of settle + window periods from x0 (NULL: from rest); its window
 * into r, the end state into x_end. */
static int run_once(usm_squeal_study *s, const usm_params *q, const double *x0, double t0,
                    rec *r, usm_sim_summary *sum)
{
    const usm_squeal_options *o = &s->o;
    usm_sim_options so;
    usm_sim_options_default(&so);
    so.duration = (double)(o->settle + o->window) / q->f;
    so.rtol = o->rtol;
    so.rate = o->samples_per_period * q->f;
    so.settle_periods = 1;
    so.max_steps = 0;
    if (x0) {
        so.start = USM_SIM_FROM_STATE;
        so.t0 = t0;
        memcpy(so.x0, x0, sizeof(double) * (size_t)s->m->nx);
        so.rest_fraction = 0.0; /* a continued run is not a start-up */
    }
    r->first = o->settle * o->samples_per_period;
    r->m = o->samples_per_period;
    r->n = o->window;
    r->k = 0;
    r->have_y = 0;
    r->have_closed = 0;
    const usm_sim_callbacks cb = {record, NULL, r, NULL};
    const int rc = usm_sim_run(s->sim, q, &so, &cb, sum);
    if (rc != USM_OK)
        return rc;
    if (sum->stop == USM_SIM_REST)
        return USM_ENOSOLUTION;
    if (r->k < r->first + r->n * r->m) {
        snprintf(s->msg, USM_MSG_LEN, "the run gave %ld samples, %ld expected", r->k,
                 r->first + r->n * r->m);
        return USM_EFAILED;
    }
    return USM_OK;
}

static void classify(usm_squeal_study *s, const rec *r, double f, usm_squeal_point *pt)
{
    const int k = period_of(r, s->o.period_tol);
    const double lt = pt->lyapunov_per_period;
    pt->period = k;
    pt->second_frequency = NAN;
    if (k > 0)
        pt->motion = USM_MOTION_PERIODIC;
    else if (lt > s->o.exponent_tol)
        pt->motion = USM_MOTION_CHAOTIC;
    else if (lt < -s->o.exponent_tol)
        pt->motion = USM_MOTION_SETTLING;
    else {
        pt->motion = USM_MOTION_QUASI_PERIODIC;
        pt->second_frequency = second_frequency(r, f);
    }
}

static int alloc_rec(rec *r, long n)
{
    memset(r, 0, sizeof *r);
    r->v = malloc(sizeof(double) * (size_t)n);
    r->speed = malloc(sizeof(double) * (size_t)n);
    r->theta = malloc(sizeof(double) * (size_t)n);
    r->gap = malloc(sizeof(double) * (size_t)n);
    r->open = malloc(sizeof(int) * (size_t)n);
    return r->v && r->speed && r->theta && r->gap && r->open ? 0 : -1;
}

static void free_rec(rec *r)
{
    free(r->v);
    free(r->speed);
    free(r->theta);
    free(r->gap);
    free(r->open);
}

/* Point i at parameters q from x0 (NULL: rest); its end state into x_end
 * (have_end 0 when there is none to continue from). */
static int one_point(usm_squeal_study *s, const usm_params *q, size_t i, const double *x0,
                     double t0, rec *r, double *x_end, double *t_end, int *have_end)
{
    usm_squeal_point *pt = &s->pts[i];
    usm_sim_summary sum;
    const double f = q->f;
    r->R = q->R;
    r->H = q->H;
    *have_end = 0;
    pt->lyapunov = pt->lyapunov2 = pt->lyapunov_per_period = NAN;
    pt->second_frequency = NAN;
    int rc = run_once(s, q, x0, t0, r, &sum);
    if (rc == USM_ENOSOLUTION) {
        pt->motion = USM_MOTION_REST;
        pt->status = USM_OK;
        return USM_OK;
    }
    if (rc != USM_OK) {
        pt->status = USM_EFAILED;
        pt->motion = USM_MOTION_FAILED;
        snprintf(pt->message, USM_MSG_LEN, "%s", s->msg[0] ? s->msg : usm_sim_message(s->sim));
        s->msg[0] = '\0';
        return USM_OK;
    }
    if (r->have_closed) {
        memcpy(x_end, r->x_closed, sizeof(double) * (size_t)s->m->nx);
        *t_end = r->t_closed;
    } else { /* never closed at a sample: the rotor lands on the crest at the start */
        memcpy(x_end, sum.final_x, sizeof(double) * (size_t)s->m->nx);
        *t_end = sum.t_reached;
    }
    *have_end = 1;
    memcpy(s->x_last[i], x_end, sizeof(double) * (size_t)s->m->nx);
    s->t_last[i] = *t_end;
    const long nw = r->n * r->m;
    double wmin = INFINITY, wmax = -INFINITY, wsum = 0, tsum = 0;
    long nopen = 0;
    for (long j = 0; j < nw; ++j) {
        wmin = fmin(wmin, r->speed[j]);
        wmax = fmax(wmax, r->speed[j]);
        wsum += r->speed[j];
        tsum += r->theta[j];
        nopen += r->open[j];
    }
    pt->rotor_speed_mean = wsum / (double)nw;
    pt->rotor_speed_ripple = wmax - wmin;
    pt->theta_mean = tsum / (double)nw;
    pt->open_fraction = (double)nopen / (double)nw;
    /* the exponents, from the window's first state */
    usm_hybrid_lyapunov_result ly;
    rc = usm_hybrid_set(s->hyb, q, s->o.lyapunov_rtol);
    if (rc == USM_OK)
        rc = usm_hybrid_lyapunov(s->hyb, r->t0, r->open0, r->y0, s->o.lyapunov_skip,
                                 s->o.lyapunov_periods, &ly);
    if (rc != USM_OK) {
        pt->status = USM_EFAILED;
        pt->motion = USM_MOTION_FAILED;
        snprintf(pt->message, USM_MSG_LEN, "Lyapunov exponent: %s",
                 usm_hybrid_message(s->hyb));
        return USM_OK;
    }
    const long lp = s->o.lyapunov_skip + s->o.lyapunov_periods;
    pt->lyapunov = ly.exponents[0];
    pt->lyapunov2 = ly.exponents[1];
    pt->lyapunov_per_period = ly.exponents[0] / f;
    pt->impacts_per_period = (double)ly.impacts / (double)lp;
    pt->impact_velocity_max = ly.impact_velocity_max;
    classify(s, r, f, pt);
    if (s->o.power_periods > 0) {
        char why[USM_MSG_LEN];
        if (usm_squeal_energy(s->m, q, r->t0, r->open0, r->y0, s->o.power_periods,
                              s->o.power_rtol, &pt->power, why) != USM_OK) {
            pt->status = USM_EFAILED;
            pt->motion = USM_MOTION_FAILED;
            snprintf(pt->message, USM_MSG_LEN, "power: %.200s", why);
            return USM_OK;
        }
    }
    if (audible(r, f, s->o.lines, pt) != USM_OK) {
        snprintf(s->msg, USM_MSG_LEN, "out of memory");
        return USM_EFAILED;
    }
    /* the bifurcation diagram's samples */
    strobe *st = &s->st[i];
    st->n = (size_t)r->n;
    st->speed = malloc(sizeof(double) * st->n);
    st->theta = malloc(sizeof(double) * st->n);
    st->gap = malloc(sizeof(double) * st->n);
    if (!st->speed || !st->theta || !st->gap) {
        snprintf(s->msg, USM_MSG_LEN, "out of memory");
        return USM_EFAILED;
    }
    for (size_t j = 0; j < st->n; ++j) {
        st->speed[j] = r->speed[j * (size_t)r->m];
        st->theta[j] = r->theta[j * (size_t)r->m];
        st->gap[j] = r->gap[j * (size_t)r->m];
    }
    pt->status = USM_OK;
    return USM_OK;
}

/* The start from rest at point i, compared with the continued run. */
static int rest_check(usm_squeal_study *s, const usm_params *q, size_t i, rec *r)
{
    usm_squeal_point *pt = &s->pts[i];
    usm_sim_summary sum;
    r->R = q->R;
    r->H = q->H;
    pt->rest_checked = 1;
    const int rc = run_once(s, q, NULL, 0.0, r, &sum);
    if (rc == USM_ENOSOLUTION) {
        pt->rest_motion = USM_MOTION_REST;
    } else if (rc != USM_OK) {
        pt->rest_motion = USM_MOTION_FAILED;
        s->msg[0] = '\0';
    } else {
        const long nw = r->n * r->m;
        double w = 0;
        for (long j = 0; j < nw; ++j)
            w += r->speed[j] / (double)nw;
        pt->rest_speed_mean = w;
        pt->rest_period = period_of(r, s->o.period_tol);
        pt->rest_motion = pt->rest_period > 0 ? USM_MOTION_PERIODIC
                          : pt->motion == USM_MOTION_PERIODIC ? USM_MOTION_SETTLING
                                                               : pt->motion;
    }
    pt->coexisting =
        pt->rest_motion != pt->motion || pt->rest_period != pt->period ||
        (pt->motion != USM_MOTION_REST &&
         !(fabs(pt->rest_speed_mean - pt->rotor_speed_mean) <=
           COEXIST_SPEED * fabs(pt->rotor_speed_mean)));
    return USM_OK;
}

const usm_squeal_origin *usm_squeal_origin_get(const usm_squeal_study *s)
{
    return s->pts ? &s->origin : NULL;
}

const usm_squeal_onset *usm_squeal_onset_get(const usm_squeal_study *s)
{
    return s->pts && s->onset_done ? &s->onset : NULL;
}

static int is_period1(const usm_squeal_point *pt)
{
    return pt->status == USM_OK && pt->motion == USM_MOTION_PERIODIC && pt->period == 1;
}

/* The participation of each degree of freedom in the eigenvector v (re, im
 * parts, stride between columns) of the critical multiplier (header). */
static void participation(const usm_model *m, double f, const double *vr, const double *vi,
                          usm_squeal_origin *o)
{
    const double w2 = pow(2.0 * 3.14159265358979323846 * f, 2.0);
    double e[USM_MAX_NX] = {0}, sum = 0.0;
    int used[USM_MAX_NX] = {0};
    o->ndof = 0;
    for (int i = 0; i < m->nx; ++i)
        e[i] = vr[i] * vr[i] + vi[i] * vi[i];
    for (int i = 0; i < m->nx && o->ndof < USM_SQUEAL_MAX_DOF; ++i) {
        const char *name = m->state_names[i];
        const size_t len = strlen(name);
        if (used[i] || (len > 3 && strcmp(name + len - 3, "dot") == 0))
            continue;
        double share = e[i];
        used[i] = 1;
        for (int j = 0; j < m->nx; ++j) { /* its velocity, NAMEdot */
            const char *nj = m->state_names[j];
            if (!used[j] && strlen(nj) == len + 3 && strncmp(nj, name, len) == 0 &&
                strcmp(nj + len, "dot") == 0) {
                share += e[j] / w2;
                used[j] = 1;
            }
        }
        snprintf(o->dof[o->ndof], sizeof o->dof[0], "%s", name);
        o->share[o->ndof++] = share;
        sum += share;
    }
    for (int k = 0; k < o->ndof; ++k)
        o->share[k] = sum > 0 ? o->share[k] / sum : NAN;
}

/* The origin at the end of the period-1 branch in the range (header). */
static int find_origin(usm_squeal_study *s, const usm_param_info *info)
{
    usm_squeal_origin *o = &s->origin;
    size_t i = 0;
    while (i + 1 < s->npts && !(is_period1(&s->pts[i]) && !is_period1(&s->pts[i + 1])))
        ++i;
    if (i + 1 >= s->npts)
        return USM_OK; /* found 0: no change from period 1 */
    o->value = s->pts[i].value;
    o->next_value = s->pts[i + 1].value;
    usm_params q = s->base;
    *usm_params_field(&q, info) = o->value;
    usm_hybrid_options ho;
    usm_hybrid_result r;
    usm_hybrid_options_default(&ho);
    /* the value's last closed sample is on the orbit, but a period later the
       contact may be open there: then the solver's own section, from rest */
    if ((usm_hybrid_solve_from(s->hyb, &q, &ho, s->t_last[i], s->x_last[i], &r) != USM_OK ||
         !r.converged) &&
        (usm_hybrid_solve(s->hyb, &q, &ho, &r) != USM_OK || !r.converged)) {
        snprintf(o->message, USM_MSG_LEN, "no orbit with separation at %g: %.150s", o->value,
                 usm_hybrid_message(s->hyb));
        return USM_OK;
    }
    const int n = r.floquet.n;
    gsl_matrix *B = gsl_matrix_alloc((size_t)n, (size_t)n);
    gsl_vector_complex *ev = gsl_vector_complex_alloc((size_t)n);
    gsl_matrix_complex *V = gsl_matrix_complex_alloc((size_t)n, (size_t)n);
    gsl_eigen_nonsymmv_workspace *w = gsl_eigen_nonsymmv_alloc((size_t)n);
    int rc = USM_OK;
    if (!B || !ev || !V || !w) {
        snprintf(s->msg, USM_MSG_LEN, "out of memory");
        rc = USM_EFAILED;
    } else {
        for (int a = 0; a < n; ++a)
            for (int b = 0; b < n; ++b)
                gsl_matrix_set(B, (size_t)a, (size_t)b, r.floquet.monodromy[a * n + b]);
        if (gsl_eigen_nonsymmv(B, ev, V, w) != GSL_SUCCESS) {
            snprintf(o->message, USM_MSG_LEN, "the monodromy's eigenvectors failed");
        } else {
            /* the critical one: the eigenvalue nearest the largest non-cyclic multiplier */
            int best = -1;
            double bd = INFINITY, lre = 0, lim = 0;
            for (int k = 0; k < n; ++k)
                if (!r.floquet.cyclic[k] &&
                    hypot(r.floquet.re[k], r.floquet.im[k]) == r.floquet.max_modulus) {
                    lre = r.floquet.re[k];
                    lim = fabs(r.floquet.im[k]);
                }
            for (int k = 0; k < n; ++k) {
                const gsl_complex z = gsl_vector_complex_get(ev, (size_t)k);
                const double dd = hypot(GSL_REAL(z) - lre, fabs(GSL_IMAG(z)) - lim);
                if (dd < bd) {
                    bd = dd;
                    best = k;
                }
            }
            double vr[USM_MAX_NX], vi[USM_MAX_NX];
            for (int a = 0; a < n; ++a) {
                const gsl_complex z = gsl_matrix_complex_get(V, (size_t)a, (size_t)best);
                vr[a] = GSL_REAL(z);
                vi[a] = GSL_IMAG(z);
            }
            participation(s->m, q.f, vr, vi, o);
            o->multiplier_re = lre;
            o->multiplier_im = lim;
            o->max_modulus = r.floquet.max_modulus;
            o->separation_fraction = r.separation_fraction;
            o->impacts_per_period = r.impacts_per_period;
            snprintf(o->mode_sequence, sizeof o->mode_sequence, "%s", r.mode_sequence);
            s->origin_t0 = r.t0;
            memcpy(s->origin_x0, r.x0, sizeof(double) * (size_t)n);
            snprintf(o->kind, sizeof o->kind, "%s",
                     r.floquet.max_modulus < 1.0 ? "closed_phase_vanishing"
                     : lim > 1e-9 * r.floquet.max_modulus ? "neimark_sacker"
                     : lre > 0 ? "fold" : "period_doubling");
            o->found = 1;
        }
    }
    gsl_matrix_free(B);
    gsl_vector_complex_free(ev);
    gsl_matrix_complex_free(V);
    gsl_eigen_nonsymmv_free(w);
    return rc;
}

int usm_squeal_run(usm_squeal_study *s, const usm_params *p, const usm_squeal_options *opt)
{
    int rc = usm_squeal_check(s, p, opt);
    if (rc != USM_OK)
        return rc;
    clear_points(s);
    s->o = *opt;
    snprintf(s->over, sizeof s->over, "%s", opt->over);
    s->o.over = s->over;
    const usm_param_info *info = usm_params_find(opt->over);
    const size_t np = (size_t)opt->points;
    s->pts = calloc(np, sizeof *s->pts);
    s->st = calloc(np, sizeof *s->st);
    s->f = calloc(np, sizeof *s->f);
    s->x_last = calloc(np, sizeof *s->x_last);
    s->t_last = calloc(np, sizeof *s->t_last);
    s->base = *p;
    memset(&s->origin, 0, sizeof s->origin);
    memset(&s->onset, 0, sizeof s->onset);
    s->onset_done = 0;
    rec r;
    if (!s->pts || !s->st || !s->f || !s->x_last || !s->t_last || alloc_rec(&r, opt->window * opt->samples_per_period) != 0) {
        if (s->pts)
            free_rec(&r);
        clear_points(s);
        snprintf(s->msg, USM_MSG_LEN, "out of memory");
        return USM_EFAILED;
    }
    s->npts = np;
    double x_end[USM_MAX_NX], t_end = 0.0;
    int have_end = 0;
    rc = USM_OK;
    for (size_t i = 0; i < np && rc == USM_OK; ++i) {
        const clock_t c0 = clock();
        usm_params q = *p;
        const double v = opt->from + (opt->to - opt->from) * (double)i / (double)(np - 1);
        *usm_params_field(&q, info) = v;
        s->pts[i].value = v;
        s->f[i] = q.f;
        double x0[USM_MAX_NX];
        const int cont = have_end;
        const double t0 = cont ? t_end : 0.0;
        if (cont)
            memcpy(x0, x_end, sizeof x0);
        rc = one_point(s, &q, i, cont ? x0 : NULL, t0, &r, x_end, &t_end, &have_end);
        if (rc == USM_OK && cont && opt->check_rest)
            rc = rest_check(s, &q, i, &r);
        s->pts[i].seconds = (double)(clock() - c0) / CLOCKS_PER_SEC;
        if (opt->progress)
            opt->progress((double)(i + 1) / (double)np, opt->progress_ctx);
    }
    free_rec(&r);
    if (rc == USM_OK && opt->origin)
        rc = find_origin(s, info);
    if (rc == USM_OK && opt->origin && opt->sensitivities && s->origin.found) {
        rc = usm_squeal_onset_sensitivities(s->m, p, opt->over, s->origin.value,
                                            s->origin.next_value, s->origin_t0, s->origin_x0,
                                            NULL, 0, opt->sensitivity_h, opt->onset_tol,
                                            &s->onset);
        if (rc == USM_EINPUT) { /* checked before the study: not reached */
            snprintf(s->msg, USM_MSG_LEN, "%s", s->onset.message);
            return rc;
        }
        rc = rc == USM_EFAILED ? rc : USM_OK;
        s->onset_done = 1;
    }
    return rc;
}
