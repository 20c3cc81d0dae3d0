/* The amplitude spectrum (usm_spectrum.h) against synthetic signals whose
 * lines are known (frequency, amplitude), and the squeal frequency's folding
 * (usm.h) against the closed form f acos(Re lambda / |lambda|) / (2 pi).
 *
 *  - usm_spectrum_amplitude + usm_spectrum_lines on a mean, the harmonics 2 f
 *    and 4 f (on bins) and two lines between bins at f -+ f_s (the squeal's
 *    sidebands, as `usm simulate --spectrum` sees them): every frequency and
 *    amplitude, which lines are harmonics, and the folded frequency.
 *  - usm_sim_spectrum: the same signal recorded as a simulation's samples
 *    (the window is the last N periods: a start-up transient before it must
 *    not show), once on the grid (no resampling) and once at a rate that is
 *    not a multiple of f / N (cubic spline resampling).
 *  - usm_squeal_frequency for pairs with negative and positive real parts,
 *    conjugates, real multipliers; usm_floquet_squeal picks the complex pair
 *    of largest modulus, not the largest multiplier, and says when there is
 *    none. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>

#include "check.h"
#include "usm.h"
#include "usm_spectrum.h"

#define PI 3.14159265358979323846264338327950

static const double F = 37000.0;   /* the excitation frequency [Hz] */
static const double FS = 16351.25; /* a squeal frequency, not on a bin */

/* The synthetic signal: a mean, harmonics 2 f and 4 f, sidebands f - f_s and
 * f + f_s; amplitudes a[0..3]. */
static const double A[4] = {0.2, 0.02, 6e-3, 4.5e-3};
static double signal(double t)
{
    return -13.0 + A[0] * sin(2 * PI * 2 * F * t + 0.3) + A[1] * cos(2 * PI * 4 * F * t) +
           A[2] * sin(2 * PI * (F - FS) * t + 1.1) + A[3] * sin(2 * PI * (F + FS) * t - 0.7);
}
static const double FREQ[4] = {2 * F, 4 * F, F - FS, F + FS};
static const int HARM[4] = {2, 4, 0, 0};

/* The line of `lines` nearest to frequency fr, or NULL. */
static const usm_spectrum_line *nearest(const usm_spectrum_line *lines, size_t n, double fr)
{
    const usm_spectrum_line *best = NULL;
    for (size_t q = 0; q < n; ++q)
        if (!best || fabs(lines[q].frequency - fr) < fabs(best->frequency - fr))
            best = &lines[q];
    return best;
}

/* The four lines in lines[0..n-1] (strongest first): frequencies to ftol
 * bins, amplitudes to atol relative, harmonic flags, folded frequencies. */
static void check_lines(const char *what, const usm_spectrum_line *lines, size_t n, double df,
                        double ftol, double atol)
{
    double fe = 0, ae = 0;
    CHECK(n >= 4, "%s: %zu lines, want at least 4", what, n);
    for (int i = 0; i < 4; ++i) {
        const usm_spectrum_line *l = nearest(lines, n, FREQ[i]);
        if (!CHECK(l != NULL, "%s: no line near %g Hz", what, FREQ[i]))
            continue;
        fe = fmax(fe, fabs(l->frequency - FREQ[i]) / df);
        ae = fmax(ae, fabs(l->amplitude / A[i] - 1));
        CHECK(fabs(l->frequency - FREQ[i]) <= ftol * df, "%s: line %g Hz at %.9g Hz (%.2g bins)",
              what, FREQ[i], l->frequency, (l->frequency - FREQ[i]) / df);
        CHECK(fabs(l->amplitude / A[i] - 1) <= atol, "%s: line %g Hz amplitude %.9g, want %g",
              what, FREQ[i], l->amplitude, A[i]);
        CHECK(l->harmonic == HARM[i], "%s: line %g Hz harmonic %d, want %d", what, FREQ[i],
              l->harmonic, HARM[i]);
        if (!HARM[i])
            CHECK(fabs(l->folded - FS) <= ftol * df, "%s: line %g Hz folds to %.9g, want %g",
                  what, FREQ[i], l->folded, FS);
        CHECK(fabs(l->order - FREQ[i] / F) <= ftol * df / F, "%s: order %g", what, l->order);
    }
    printf("%s: frequencies to %.2g bin, amplitudes to %.2g relative\n", what, fe, ae);
    /* strongest first: the four in order of amplitude */
    CHECK(fabs(lines[0].frequency - 2 * F) < df && fabs(lines[1].frequency - 4 * F) < df &&
              fabs(lines[2].frequency - (F - FS)) < df && fabs(lines[3].frequency - (F + FS)) < df,
          "%s: lines not strongest first: %g %g %g %g", what, lines[0].frequency,
          lines[1].frequency, lines[2].frequency, lines[3].frequency);
}

static void test_direct(void)
{
    /* 370 periods at 10 f: 3700 samples, bins of f / 370 = 100 Hz; f_s is
     * 0.51 bins off its nearest bin */
    const size_t n = 3700;
    const double dt = 1.0 / (10 * F), df = 1.0 / ((double)n * dt);
    double *x = malloc(n * sizeof *x), *amp = malloc((n / 2 + 1) * sizeof *amp);
    usm_spectrum_line lines[8];
    char msg[USM_MSG_LEN];
    for (size_t j = 0; j < n; ++j)
        x[j] = signal((double)j * dt);
    CHECK(usm_spectrum_amplitude(x, n, dt, amp, msg) == USM_OK, "amplitude: %s", msg);
    /* on a bin: exactly the amplitude (the window's gain corrected), the
     * neighbours half of it (the Hann window's main lobe), the mean removed */
    /* measured: 6e-10 (the sidelobes of the lines between bins) */
    CHECK(fabs(amp[740] / A[0] - 1) < 1e-8, "bin 740 (2 f): %.15g, want %g", amp[740], A[0]);
    CHECK(fabs(amp[739] / A[0] - 0.5) < 1e-4, "bin 739: %.15g, want half of %g", amp[739], A[0]);
    /* what is left at 0 Hz is the lines between bins' mean over the window,
     * about A / (2 pi k) for a line k bins up (measured 7e-6) */
    CHECK(amp[0] < 2e-5, "the mean is not removed: amp[0] = %g", amp[0]);
    const size_t nl = usm_spectrum_lines(amp, n / 2 + 1, df, F, 8, lines);
    /* measured: frequencies to 5e-9 bin, amplitudes to 6e-10 relative (the
     * leakage of the other lines, 200 bins and more away) */
    check_lines("direct", lines, nl, df, 1e-6, 1e-7);
    /* no excitation frequency: no harmonics, NaN order and folded */
    CHECK(usm_spectrum_lines(amp, n / 2 + 1, df, 0.0, 8, lines) >= 4 && lines[0].harmonic == 0 &&
              isnan(lines[0].order) && isnan(lines[0].folded),
          "f = 0: harmonic %d order %g", lines[0].harmonic, lines[0].order);
    /* bad input */
    CHECK(usm_spectrum_amplitude(x, 3, dt, amp, msg) == USM_EINPUT && strstr(msg, "samples"),
          "3 samples accepted: %s", msg);
    CHECK(usm_spectrum_amplitude(x, n, 0.0, amp, msg) == USM_EINPUT && strstr(msg, "dt"),
          "dt = 0 accepted: %s", msg);
    x[7] = NAN;
    CHECK(usm_spectrum_amplitude(x, n, dt, amp, msg) == USM_EINPUT && strstr(msg, "finite"),
          "a NaN sample accepted: %s", msg);
    free(x);
    free(amp);
}

/* The signal recorded as samples at `rate` from t = 0 to t1, plus one sample
 * at t1 (a run's end), with a start-up transient before t_transient. */
static void record(usm_sim_spectrum *s, double rate, double t1, double t_transient)
{
    double xs[1] = {0};
    usm_sim_sample smp;
    memset(&smp, 0, sizeof smp);
    smp.nx = 1;
    smp.x = smp.xdot = xs;
    usm_sim_spectrum_reset(s);
    for (long j = 0;; ++j) {
        double t = (double)j / rate;
        if (t > t1)
            t = t1;
        const double v = signal(t) + (t < t_transient ? 5.0 * sin(2 * PI * 3e4 * t) : 0.0);
        smp.t = t;
        smp.rotor_speed = v;
        smp.theta = 1e-5 * v;
        smp.out[USM_OUT_F_N] = 10.0 * v;
        CHECK(usm_sim_spectrum_add(s, &smp) == 0, "add: out of memory");
        if (t >= t1)
            break;
    }
}

static void test_recorder(void)
{
    usm_sim_spectrum *s = usm_sim_spectrum_alloc();
    usm_sim_spectrum_options opt;
    usm_sim_spectrum_result r;
    char msg[USM_MSG_LEN];
    if (!CHECK(s != NULL, "alloc"))
        return;
    usm_sim_spectrum_options_default(&opt);
    opt.f = F;
    opt.lines = 8;
    /* 740 periods at 10 f, a transient over the first 300: the default window
     * is the last 370 periods, on the samples */
    record(s, 10 * F, 740 / F, 300 / F);
    CHECK(usm_sim_spectrum_compute(s, &opt, &r, msg) == USM_OK, "compute: %s", msg);
    CHECK(r.periods == 370 && r.samples == 3700 && !r.resampled && r.recorded == 3700,
          "window: %ld periods, %zu samples, resampled %d, recorded %zu", r.periods, r.samples,
          r.resampled, r.recorded);
    CHECK(fabs(r.t_from - 370 / F) < 1e-12 && fabs(r.df - F / 370) < 1e-6, "t_from %g df %g",
          r.t_from, r.df);
    /* measured: as above (2e-9 bin, 6e-10): the transient is not in the window */
    check_lines("recorded rotor_speed", r.lines[USM_SPECTRUM_ROTOR_SPEED],
                r.nlines[USM_SPECTRUM_ROTOR_SPEED], r.df, 1e-6, 1e-7);
    /* the other channels are the same signal scaled */
    const usm_spectrum_line *th = nearest(r.lines[USM_SPECTRUM_THETA], r.nlines[USM_SPECTRUM_THETA],
                                          F - FS);
    CHECK(th && fabs(th->amplitude / (1e-5 * A[2]) - 1) < 1e-3, "theta line %g",
          th ? th->amplitude : NAN);
    for (int c = 0; c < USM_SPECTRUM_NCHANNELS; ++c)
        CHECK(r.have_nonharmonic[c] && fabs(r.nonharmonic[c].frequency - (F - FS)) < 1e-3 * r.df,
              "channel %d: strongest non-harmonic %g Hz, want %g", c, r.nonharmonic[c].frequency,
              F - FS);
    /* the parasitic vibration: the two sidebands' RMS, the harmonics and the
     * mean removed by the synchronous average (measured 1.2e-5 relative: the
     * sidebands' own average over 370 periods) */
    {
        const double want = sqrt((A[2] * A[2] + A[3] * A[3]) / 2);
        printf("parasitic_rms: %.3g relative\n",
               fabs(r.parasitic_rms[USM_SPECTRUM_ROTOR_SPEED] / want - 1));
        CHECK(fabs(r.parasitic_rms[USM_SPECTRUM_ROTOR_SPEED] / want - 1) < 1e-4 &&
                  fabs(r.parasitic_rms[USM_SPECTRUM_F_N] / (10 * want) - 1) < 1e-4,
              "parasitic_rms %.9g, want %.9g", r.parasitic_rms[USM_SPECTRUM_ROTOR_SPEED], want);
    }
    /* a window of 100 periods: 1000 samples */
    opt.periods = 100;
    CHECK(usm_sim_spectrum_compute(s, &opt, &r, msg) == USM_OK && r.samples == 1000 &&
              fabs(r.df - F / 100) < 1e-6,
          "100 periods: %zu samples, df %g (%s)", r.samples, r.df, msg);
    /* more periods than recorded, or than a window of half the run */
    opt.periods = 741;
    CHECK(usm_sim_spectrum_compute(s, &opt, &r, msg) == USM_EINPUT && strstr(msg, "periods"),
          "741 periods of 740 accepted: %s", msg);
    opt.periods = 0;
    CHECK(usm_sim_spectrum_check(&opt, 3.5 / F, msg) == USM_EINPUT && strstr(msg, "periods"),
          "3.5 periods accepted: %s", msg);
    CHECK(usm_sim_spectrum_check(&opt, 4 / F, msg) == USM_OK, "4 periods refused: %s", msg);

    /* samples at 23.37 f (not a multiple of f / N) with the run's end between
     * samples: resampled by the spline onto round(N T rate) points */
    record(s, 23.37 * F, 740.0 / F, 300 / F);
    opt.periods = 370;
    CHECK(usm_sim_spectrum_compute(s, &opt, &r, msg) == USM_OK, "resampled: %s", msg);
    CHECK(r.resampled && r.samples == 370 * 23, "resampled %d samples %zu",
          r.resampled, r.samples);
    /* measured: frequencies to 2e-9 bin, amplitudes to 2.4e-3 relative (the
     * spline's error at 5.8 samples per period of the 4 f line) */
    check_lines("resampled", r.lines[USM_SPECTRUM_ROTOR_SPEED], r.nlines[USM_SPECTRUM_ROTOR_SPEED],
                r.df, 1e-3, 5e-3);
    CHECK(usm_sim_spectrum_amplitudes(s, 0) != NULL && usm_sim_spectrum_amplitudes(s, 3) == NULL,
          "amplitudes accessor");
    usm_sim_spectrum_free(s);
}

/* f acos(re / |lambda|) / (2 pi): the folded frequency by another formula */
static double closed_form(double f, double re, double im)
{
    return f * acos(re / hypot(re, im)) / (2 * PI);
}

static void test_squeal(void)
{
    /* the Neimark-Sacker pair: negative real part, arg near pi */
    const double re = -0.9348, im = 0.3552;
    const double fs = usm_squeal_frequency(F, re, im);
    CHECK(fabs(fs - closed_form(F, re, im)) < 1e-9, "NS pair: %.12g Hz, closed form %.12g", fs,
          closed_form(F, re, im));
    CHECK(fs > 0.25 * F && fs <= 0.5 * F, "NS pair: %g Hz not in (f/4, f/2]", fs);
    /* 0.44217 f: arg = pi - atan(0.3552 / 0.9348) */
    CHECK(fabs(fs / F - (PI - atan(0.3552 / 0.9348)) / (2 * PI)) < 1e-12, "NS pair: %g f",
          fs / F);
    CHECK(fabs(usm_squeal_frequency(F, re, -im) - fs) < 1e-12, "conjugate differs");
    /* a positive real part: below f/4 */
    CHECK(fabs(usm_squeal_frequency(F, 0.2557, 0.5036) - closed_form(F, 0.2557, 0.5036)) < 1e-9,
          "positive real part");
    /* real multipliers: 0 and f/2; nearly -1 from either side: just below f/2 */
    CHECK(usm_squeal_frequency(F, 0.9, 0.0) == 0.0, "lambda = 0.9: %g",
          usm_squeal_frequency(F, 0.9, 0.0));
    CHECK(fabs(usm_squeal_frequency(F, -0.9, 0.0) - F / 2) < 1e-9, "lambda = -0.9: %g",
          usm_squeal_frequency(F, -0.9, 0.0));
    CHECK(fabs(usm_squeal_frequency(F, -1.0, -1e-9) - F / 2) < 1e-4 &&
              usm_squeal_frequency(F, -1.0, -1e-9) <= F / 2,
          "lambda = -1 - 1e-9 i: %.12g", usm_squeal_frequency(F, -1.0, -1e-9));
    CHECK(isnan(usm_squeal_frequency(0.0, re, im)) && isnan(usm_squeal_frequency(F, 0.0, 0.0)) &&
              isnan(usm_squeal_frequency(F, NAN, 1.0)),
          "no NaN for f = 0, lambda = 0, NaN");

    /* the dominant complex pair: not the largest multiplier (1.2, real), not
     * a cyclic 1, but the pair of largest modulus */
    usm_floquet_result r;
    usm_squeal sq;
    memset(&r, 0, sizeof r);
    const double mre[8] = {1.2, 1.0, 0.2557, 0.2557, -0.9348, -0.9348, 0.5, -0.3};
    const double mim[8] = {0.0, 0.0, 0.5036, -0.5036, -0.3552, 0.3552, 0.0, 0.0};
    r.n = 8;
    for (int k = 0; k < 8; ++k)
        r.re[k] = mre[k], r.im[k] = mim[k];
    r.cyclic[1] = 1;
    CHECK(usm_floquet_squeal(&r, F, &sq) == USM_OK && sq.found && sq.index == 5 &&
              sq.im > 0 && fabs(sq.frequency - fs) < 1e-9 &&
              fabs(sq.modulus - hypot(re, im)) < 1e-15 && sq.reason[0] == '\0',
          "dominant pair: found %d index %d frequency %g", sq.found, sq.index, sq.frequency);
    /* without complex pairs: none, with a reason */
    r.im[2] = r.im[3] = r.im[4] = r.im[5] = 0.0;
    CHECK(usm_floquet_squeal(&r, F, &sq) == USM_OK && !sq.found && sq.index == -1 &&
              isnan(sq.frequency) && strstr(sq.reason, "no complex pair"),
          "no pair: found %d reason '%s'", sq.found, sq.reason);
    /* an imaginary part within rounding of a real multiplier is not a pair */
    r.im[4] = 1e-9, r.im[5] = -1e-9;
    CHECK(usm_floquet_squeal(&r, F, &sq) == USM_OK && !sq.found, "1e-9 i taken for a pair");
    CHECK(usm_floquet_squeal(&r, -1.0, &sq) == USM_EINPUT && strstr(sq.reason, "f:"),
          "f = -1 accepted");
}

/* A channel that is zero throughout (here theta, F_n 0 while the rotor
 * speed carries the signal): its spectrum is empty, peak 0 and no line,
 * and the others are unaffected (`usm simulate --spectrum` draws and says
 * "an empty spectrum" from peak 0, where gnuplot's log scale failed). */
static void test_zero_channel(void)
{
    usm_sim_spectrum *s = usm_sim_spectrum_alloc();
    usm_sim_spectrum_options opt;
    usm_sim_spectrum_result r;
    char msg[USM_MSG_LEN];
    double xs[1] = {0};
    usm_sim_sample smp;
    if (!CHECK(s != NULL, "alloc"))
        return;
    memset(&smp, 0, sizeof smp);
    smp.nx = 1;
    smp.x = smp.xdot = xs;
    for (long j = 0; j <= 400; ++j) {
        smp.t = (double)j / (10 * F);
        smp.rotor_speed = signal(smp.t);
        CHECK(usm_sim_spectrum_add(s, &smp) == 0, "add: out of memory");
    }
    usm_sim_spectrum_options_default(&opt);
    opt.f = F;
    CHECK(usm_sim_spectrum_compute(s, &opt, &r, msg) == USM_OK, "zero channel: %s", msg);
    CHECK(r.peak[USM_SPECTRUM_THETA] == 0 && r.nlines[USM_SPECTRUM_THETA] == 0 &&
              r.peak[USM_SPECTRUM_F_N] == 0 && r.nlines[USM_SPECTRUM_F_N] == 0,
          "zero channels: peak %g, %zu lines", r.peak[USM_SPECTRUM_THETA],
          r.nlines[USM_SPECTRUM_THETA]);
    CHECK(fabs(r.peak[USM_SPECTRUM_ROTOR_SPEED] / A[0] - 1) < 1e-3 &&
              r.nlines[USM_SPECTRUM_ROTOR_SPEED] > 0,
          "rotor_speed: peak %g, want %g", r.peak[USM_SPECTRUM_ROTOR_SPEED], A[0]);
    usm_sim_spectrum_free(s);
}

int main(void)
{
    gsl_set_error_handler_off();
    test_direct();
    test_recorder();
    test_squeal();
    test_zero_channel();
    printf("test_spectrum_squeal: %d failures\n", failures);
    return failures != 0;
}
