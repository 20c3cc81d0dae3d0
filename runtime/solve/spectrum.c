/* Amplitude spectra of a simulation (usm_spectrum.h): GSL's mixed-radix real
 * FFT of the Hann-windowed samples, lines by the Hann window's two-bin
 * interpolation, and a recorder of a run's samples whose settled part it
 * transforms. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_fft_real.h>
#include <gsl/gsl_spline.h>

#include "core/grow.h"
#include "usm_spectrum.h"

#define PI 3.14159265358979323846264338327950
#define HARMONIC_BINS 1.5   /* a line within this many bins of k f is the harmonic k f */
#define LINE_FLOOR 1e-9     /* lines below this fraction of the strongest are noise */
#define ON_GRID 1e-7        /* a sample within this fraction of dt of a grid point is it */

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int usm_spectrum_amplitude(const double *x, size_t n, double dt, double *amp,
                           char msg[USM_MSG_LEN])
{
    if (n < 4) {
        snprintf(msg, USM_MSG_LEN, "samples: %zu, at least 4 are needed for a spectrum", n);
        return USM_EINPUT;
    }
    if (!isfinite(dt) || dt <= 0) {
        snprintf(msg, USM_MSG_LEN, "dt: must be finite and positive (got %g)", dt);
        return USM_EINPUT;
    }
    double mean = 0.0;
    for (size_t j = 0; j < n; ++j) {
        if (!isfinite(x[j])) {
            snprintf(msg, USM_MSG_LEN, "samples: sample %zu is not finite", j);
            return USM_EINPUT;
        }
        mean += x[j];
    }
    mean /= (double)n;
    double *data = malloc(n * sizeof *data);
    gsl_fft_real_wavetable *wt = gsl_fft_real_wavetable_alloc(n);
    gsl_fft_real_workspace *ws = gsl_fft_real_workspace_alloc(n);
    int status = USM_OK;
    if (!data || !wt || !ws) {
        snprintf(msg, USM_MSG_LEN, "out of memory (a spectrum of %zu samples)", n);
        status = USM_EFAILED;
        goto done;
    }
    /* the periodic Hann window: sum_j w_j = n / 2 */
    for (size_t j = 0; j < n; ++j)
        data[j] = (x[j] - mean) * 0.5 * (1.0 - cos(2.0 * PI * (double)j / (double)n));
    if (gsl_fft_real_transform(data, 1, n, wt, ws) != GSL_SUCCESS) {
        snprintf(msg, USM_MSG_LEN, "the FFT of %zu samples failed (GSL)", n);
        status = USM_EFAILED;
        goto done;
    }
    /* halfcomplex: data[0] = X_0, then (Re X_k, Im X_k) at 2k - 1, 2k; for
     * an even n, data[n - 1] = X_{n/2} (real) */
    const double g = 4.0 / (double)n; /* 2 / sum w */
    amp[0] = 0.5 * g * fabs(data[0]);
    for (size_t k = 1; 2 * k < n; ++k)
        amp[k] = g * hypot(data[2 * k - 1], data[2 * k]);
    if (n % 2 == 0)
        amp[n / 2] = 0.5 * g * fabs(data[n - 1]);
done:
    free(data);
    if (wt)
        gsl_fft_real_wavetable_free(wt);
    if (ws)
        gsl_fft_real_workspace_free(ws);
    return status;
}

/* The Hann window's response to a sinusoid delta bins off a bin, 1 at 0. */
static double hann_response(double delta)
{
    const double d = fabs(delta);
    if (d < 1e-12)
        return 1.0;
    if (fabs(d - 1.0) < 1e-12)
        return 0.5;
    return fabs(sin(PI * d) / (PI * d)) / fabs(1.0 - d * d);
}

static int by_amplitude(const void *a, const void *b)
{
    const usm_spectrum_line *x = a, *y = b;
    if (x->amplitude != y->amplitude)
        return x->amplitude < y->amplitude ? 1 : -1;
    return x->bin < y->bin ? -1 : x->bin > y->bin;
}

/* Every line of amp (the header's rule), strongest first; *count of them.
 * NULL with *count = 0 when there are none; NULL with *count = SIZE_MAX when
 * out of memory. */
static usm_spectrum_line *all_lines(const double *amp, size_t nb, double df, double f,
                                    size_t *count)
{
    double top = 0.0;
    size_t n = 0, cap = 0;
    usm_spectrum_line *l = NULL;
    *count = 0;
    for (size_t k = 1; k + 1 < nb; ++k)
        top = fmax(top, amp[k]);
    if (!(top > 0))
        return NULL;
    for (size_t k = 1; k + 1 < nb; ++k) {
        const double a = amp[k - 1], b = amp[k], c = amp[k + 1];
        if (!(b > a && b >= c && b > LINE_FLOOR * top))
            continue;
        if (usm_grow((void **)&l, &cap, n + 1, sizeof *l) != 0) {
            free(l);
            *count = (size_t)-1;
            return NULL;
        }
        /* Grandke's estimator for the Hann window (header comment) */
        const int up = c >= a;
        const double alpha = (up ? c : a) / b;
        double delta = (2.0 * alpha - 1.0) / (alpha + 1.0);
        delta = fmin(fmax(delta, -0.5), 0.5);
        if (!up)
            delta = -delta;
        usm_spectrum_line *e = &l[n++];
        memset(e, 0, sizeof *e);
        e->bin = k;
        e->frequency = ((double)k + delta) * df;
        e->amplitude = b / hann_response(delta);
        if (f > 0) {
            const double kk = round(e->frequency / f);
            e->order = e->frequency / f;
            e->folded = fabs(e->frequency - kk * f);
            e->harmonic = kk >= 1 && e->folded <= HARMONIC_BINS * df ? (int)kk : 0;
        } else
            e->order = e->folded = NAN;
    }
    if (n > 1)
        qsort(l, n, sizeof *l, by_amplitude);
    *count = n;
    return l;
}

size_t usm_spectrum_lines(const double *amp, size_t nb, double df, double f, size_t max,
                          usm_spectrum_line *lines)
{
    size_t n;
    usm_spectrum_line *l = all_lines(amp, nb, df, f, &n);
    if (!l)
        return 0;
    if (n > max)
        n = max;
    memcpy(lines, l, n * sizeof *l);
    free(l);
    return n;
}

/* ---- the simulation's spectrum ------------------------------------------------ */

const char *usm_spectrum_channel_name(int channel)
{
    static const char *const name[USM_SPECTRUM_NCHANNELS] = {"rotor_speed", "theta", "F_n"};
    return channel >= 0 && channel < USM_SPECTRUM_NCHANNELS ? name[channel] : NULL;
}

const char *usm_spectrum_channel_unit(int channel)
{
    static const char *const unit[USM_SPECTRUM_NCHANNELS] = {"1/s", "rad", "N"};
    return channel >= 0 && channel < USM_SPECTRUM_NCHANNELS ? unit[channel] : NULL;
}

struct usm_sim_spectrum {
    double *t, *y[USM_SPECTRUM_NCHANNELS]; /* recorded samples */
    size_t n, cap;
    double *amp[USM_SPECTRUM_NCHANNELS];   /* of the last compute */
    size_t bins;
};

void usm_sim_spectrum_options_default(usm_sim_spectrum_options *opt)
{
    memset(opt, 0, sizeof *opt);
    opt->lines = 6;
}

usm_sim_spectrum *usm_sim_spectrum_alloc(void) { return calloc(1, sizeof(usm_sim_spectrum)); }

static void drop_amplitudes(usm_sim_spectrum *s)
{
    for (int c = 0; c < USM_SPECTRUM_NCHANNELS; ++c) {
        free(s->amp[c]);
        s->amp[c] = NULL;
    }
    s->bins = 0;
}

void usm_sim_spectrum_free(usm_sim_spectrum *s)
{
    if (!s)
        return;
    drop_amplitudes(s);
    free(s->t);
    for (int c = 0; c < USM_SPECTRUM_NCHANNELS; ++c)
        free(s->y[c]);
    free(s);
}

void usm_sim_spectrum_reset(usm_sim_spectrum *s)
{
    s->n = 0;
    drop_amplitudes(s);
}

size_t usm_sim_spectrum_count(const usm_sim_spectrum *s) { return s->n; }

int usm_sim_spectrum_add(usm_sim_spectrum *s, const usm_sim_sample *smp)
{
    size_t i = s->n;
    if (i > 0 && !(smp->t > s->t[i - 1])) {
        if (smp->t != s->t[i - 1])
            return 0; /* not after the last: ignored */
        --i;          /* the same time again: replaced */
    } else if (i == s->cap) {
        /* the channels first, each from the times' capacity */
        for (int c = 0; c < USM_SPECTRUM_NCHANNELS; ++c) {
            size_t cap = s->cap;
            if (usm_grow((void **)&s->y[c], &cap, i + 1, sizeof *s->y[c]) != 0)
                return -1;
        }
        if (usm_grow((void **)&s->t, &s->cap, i + 1, sizeof *s->t) != 0)
            return -1;
    }
    s->t[i] = smp->t;
    s->y[USM_SPECTRUM_ROTOR_SPEED][i] = smp->rotor_speed;
    s->y[USM_SPECTRUM_THETA][i] = smp->theta;
    s->y[USM_SPECTRUM_F_N][i] = smp->out[USM_OUT_F_N];
    if (i == s->n)
        ++s->n;
    return 0;
}

const double *usm_sim_spectrum_amplitudes(const usm_sim_spectrum *s, int channel)
{
    return channel >= 0 && channel < USM_SPECTRUM_NCHANNELS ? s->amp[channel] : NULL;
}

/* The window's grid values of every channel into g[c][0..n-1]: the samples
 * where a grid point is one, else a natural cubic spline through the samples
 * (from two before the window on).  *resampled = 1 when the spline was used.
 * 0, or -1 when out of memory. */
static int grid_values(const usm_sim_spectrum *s, double t_from, double dt, size_t n,
                       double *g[USM_SPECTRUM_NCHANNELS], int *resampled)
{
    size_t lo = 0, hi = s->n, i;
    while (hi - lo > 1) { /* the last sample at or before t_from */
        const size_t mid = lo + (hi - lo) / 2;
        if (s->t[mid] <= t_from)
            lo = mid;
        else
            hi = mid;
    }
    const size_t first = lo >= 2 ? lo - 2 : 0, m = s->n - first;
    gsl_spline *sp[USM_SPECTRUM_NCHANNELS] = {NULL};
    gsl_interp_accel *acc = NULL;
    int rc = 0;
    *resampled = 0;
    i = lo;
    for (size_t j = 0; j < n && rc == 0; ++j) {
        const double t = t_from + (double)j * dt;
        while (i + 1 < s->n && s->t[i + 1] <= t + ON_GRID * dt)
            ++i;
        if (fabs(s->t[i] - t) <= ON_GRID * dt) {
            for (int c = 0; c < USM_SPECTRUM_NCHANNELS; ++c)
                g[c][j] = s->y[c][i];
            continue;
        }
        if (!*resampled) {
            *resampled = 1;
            if (!(acc = gsl_interp_accel_alloc()))
                rc = -1;
            for (int c = 0; c < USM_SPECTRUM_NCHANNELS && rc == 0; ++c)
                if (!(sp[c] = gsl_spline_alloc(m >= 3 ? gsl_interp_cspline : gsl_interp_linear,
                                               m)) ||
                    gsl_spline_init(sp[c], s->t + first, s->y[c] + first, m) != GSL_SUCCESS)
                    rc = -1;
            if (rc)
                break;
        }
        for (int c = 0; c < USM_SPECTRUM_NCHANNELS; ++c)
            g[c][j] = gsl_spline_eval(sp[c], fmin(fmax(t, s->t[first]), s->t[s->n - 1]), acc);
    }
    for (int c = 0; c < USM_SPECTRUM_NCHANNELS; ++c)
        if (sp[c])
            gsl_spline_free(sp[c]);
    if (acc)
        gsl_interp_accel_free(acc);
    return rc;
}

/* The RMS of x[0..N m - 1] (N periods of m points) minus its synchronous
 * average: the mean over the N periods of the points at the same phase. */
static double parasitic_rms(const double *x, size_t N, size_t m)
{
    double sum = 0.0;
    for (size_t i = 0; i < m; ++i) {
        double avg = 0.0;
        for (size_t k = 0; k < N; ++k)
            avg += x[k * m + i];
        avg /= (double)N;
        for (size_t k = 0; k < N; ++k) {
            const double r = x[k * m + i] - avg;
            sum += r * r;
        }
    }
    return sqrt(sum / (double)(N * m));
}

/* The grid: m = round(rate / f) >= 4 points per period, n = N m in all
 * (at most 1e9).  USM_OK, or USM_EINPUT with msg. */
static int grid_size(double rate, double f, long N, size_t *m_out, char msg[USM_MSG_LEN])
{
    const double m = round(rate / f);
    if (!(m >= 4) || m * (double)N > 1e9) {
        snprintf(msg, USM_MSG_LEN,
                 "rate: %.6g samples per second give %.0f points per excitation period and "
                 "%.0f over the window (at least 4 per period, at most 1e9 in all)",
                 rate, m, m * (double)N);
        return USM_EINPUT;
    }
    if (m_out)
        *m_out = (size_t)m;
    return USM_OK;
}

/* The options, and the window's N whole periods for samples spanning span
 * seconds. */
static int check(const usm_sim_spectrum_options *opt, double span, long *N_out,
                 char msg[USM_MSG_LEN])
{
    if (!isfinite(opt->f) || opt->f <= 0) {
        snprintf(msg, USM_MSG_LEN, "f: must be finite and positive (got %g)", opt->f);
        return USM_EINPUT;
    }
    if (opt->periods < 0) {
        snprintf(msg, USM_MSG_LEN, "periods: must be 0 (half the run) or positive (got %ld)",
                 opt->periods);
        return USM_EINPUT;
    }
    if (!isfinite(opt->rate) || opt->rate < 0) {
        snprintf(msg, USM_MSG_LEN, "rate: must be 0 (the samples' rate) or positive (got %g)",
                 opt->rate);
        return USM_EINPUT;
    }
    if (opt->lines < 1 || opt->lines > USM_SPECTRUM_MAX_LINES) {
        snprintf(msg, USM_MSG_LEN, "lines: must be in [1, %d] (got %d)", USM_SPECTRUM_MAX_LINES,
                 opt->lines);
        return USM_EINPUT;
    }
    const double f = opt->f, T = 1.0 / f;
    /* whole periods, forgiving the rounding of a span of exactly k T */
    const long whole = (long)floor(span * f * (1.0 + 1e-12));
    const long N = opt->periods ? opt->periods : (long)floor(0.5 * span * f * (1.0 + 1e-12));
    if (opt->periods == 0 && N < 2) {
        snprintf(msg, USM_MSG_LEN,
                 "periods: the samples span %.6g s, %ld excitation period%s: at least 4 are "
                 "needed (their second half is the spectrum's window)",
                 span, whole, whole == 1 ? "" : "s");
        return USM_EINPUT;
    }
    if (N > whole) {
        snprintf(msg, USM_MSG_LEN,
                 "periods: %ld excitation periods (%.6g s) asked for, the samples span only "
                 "%.6g s (%ld whole periods)", N, (double)N * T, span, whole);
        return USM_EINPUT;
    }
    if (opt->rate > 0 && grid_size(opt->rate, f, N, NULL, msg) != USM_OK)
        return USM_EINPUT;
    *N_out = N;
    return USM_OK;
}

int usm_sim_spectrum_check(const usm_sim_spectrum_options *opt, double duration,
                           char msg[USM_MSG_LEN])
{
    long N;
    return check(opt, duration, &N, msg);
}

int usm_sim_spectrum_compute(usm_sim_spectrum *s, const usm_sim_spectrum_options *opt,
                             usm_sim_spectrum_result *out, char msg[USM_MSG_LEN])
{
    const double wall = now();
    memset(out, 0, sizeof *out);
    drop_amplitudes(s);
    const double span = s->n >= 2 ? s->t[s->n - 1] - s->t[0] : 0.0;
    long N;
    if (check(opt, span, &N, msg) != USM_OK)
        return USM_EINPUT;
    const double f = opt->f, T = 1.0 / f;
    const double L = (double)N * T;
    const double rate = opt->rate > 0 ? opt->rate : (double)(s->n - 1) / span;
    size_t m;
    if (grid_size(rate, f, N, &m, msg) != USM_OK)
        return USM_EINPUT;
    const size_t n = (size_t)N * m, nb = n / 2 + 1;
    double *g[USM_SPECTRUM_NCHANNELS] = {NULL};
    int status = USM_OK;
    for (int c = 0; c < USM_SPECTRUM_NCHANNELS; ++c)
        if (!(g[c] = malloc(n * sizeof(double))) || !(s->amp[c] = malloc(nb * sizeof(double))))
            status = USM_EFAILED;
    out->f = f;
    out->t_to = s->t[s->n - 1];
    out->t_from = out->t_to - L;
    out->periods = N;
    out->samples = n;
    out->dt = L / (double)n;
    out->df = 1.0 / L;
    out->bins = nb;
    for (size_t i = 0; i < s->n; ++i)
        out->recorded += s->t[i] >= out->t_from - ON_GRID * out->dt && s->t[i] < out->t_to;
    if (status == USM_OK &&
        grid_values(s, out->t_from, out->dt, n, g, &out->resampled) != 0)
        status = USM_EFAILED;
    if (status != USM_OK)
        snprintf(msg, USM_MSG_LEN, "out of memory (a spectrum of %zu samples)", n);
    for (int c = 0; c < USM_SPECTRUM_NCHANNELS && status == USM_OK; ++c)
        out->parasitic_rms[c] = parasitic_rms(g[c], (size_t)N, m);
    for (int c = 0; c < USM_SPECTRUM_NCHANNELS && status == USM_OK; ++c) {
        size_t nl;
        if ((status = usm_spectrum_amplitude(g[c], n, out->dt, s->amp[c], msg)) != USM_OK) {
            char why[208];
            snprintf(why, sizeof why, "%.200s", msg);
            snprintf(msg, USM_MSG_LEN, "%s: %s", usm_spectrum_channel_name(c), why);
            break;
        }
        out->peak[c] = 0.0;
        for (size_t k = 1; k < nb; ++k)
            out->peak[c] = fmax(out->peak[c], s->amp[c][k]);
        usm_spectrum_line *l = all_lines(s->amp[c], nb, out->df, f, &nl);
        if (!l && nl) {
            snprintf(msg, USM_MSG_LEN, "out of memory (the lines of a spectrum)");
            status = USM_EFAILED;
            break;
        }
        out->nlines[c] = nl < (size_t)opt->lines ? nl : (size_t)opt->lines;
        if (out->nlines[c])
            memcpy(out->lines[c], l, out->nlines[c] * sizeof *l);
        for (size_t q = 0; q < nl; ++q)
            if (!l[q].harmonic) {
                out->nonharmonic[c] = l[q];
                out->have_nonharmonic[c] = 1;
                break;
            }
        free(l);
    }
    for (int c = 0; c < USM_SPECTRUM_NCHANNELS; ++c)
        free(g[c]);
    if (status != USM_OK) {
        drop_amplitudes(s);
        return status;
    }
    s->bins = nb;
    out->seconds = now() - wall;
    return USM_OK;
}
