/* usm_spectrum.h: amplitude spectra of a simulation (the squeal).
 *
 * Math (solve/spectrum.c).  n uniformly spaced samples x_j, j = 0..n-1, of a
 * window of length L = n dt: the mean is removed, the periodic Hann window
 * w_j = (1 - cos(2 pi j / n)) / 2 applied, and GSL's mixed-radix real FFT
 * (gsl_fft_real_transform, any n; fastest when n has only small prime
 * factors) gives X_k.  The amplitude spectrum is
 *     amp_k = 2 |X_k| / sum_j w_j = 4 |X_k| / n,   k = 0..n/2,
 * at the frequencies k df, df = 1 / L: a sinusoid A sin(2 pi k df t) whose
 * frequency is a bin's shows as amp_k = A (amp_0 is the removed mean's
 * residue, about 0).
 *
 * Lines.  A line is a local maximum amp_k > amp_{k-1}, amp_k >= amp_{k+1}
 * (1 <= k < n/2).  Its frequency (k + delta) df and amplitude A = amp_k /
 * W(delta) are interpolated with the Hann window's exact two-bin estimator
 * (Grandke 1983): alpha = amp_{k+-1} / amp_k of the larger neighbour,
 * delta = +-(2 alpha - 1) / (alpha + 1), and W(delta) = |sinc(delta)| /
 * (1 - delta^2) the window's response to a sinusoid delta bins off a bin;
 * exact for one sinusoid, off by the leakage of the others (in the unit
 * test, four lines 200 bins or more apart: frequencies to 5e-9 bin,
 * amplitudes to 6e-10 relative).  Lines below 1e-9 of the strongest are not
 * reported.
 *
 * Harmonics.  With the excitation frequency f, a line is the harmonic k f
 * (k >= 1) when |frequency - k f| <= 1.5 df: the Hann main lobe is 2 bins
 * wide either side, so closer lines cannot be told apart.  Its folded
 * frequency |frequency - round(frequency / f) f| lies in [0, f/2] and is the
 * one to compare with usm_squeal_frequency (usm.h): a squeal at f_s shows as
 * lines at k f +- f_s, all of which fold onto f_s.
 *
 * The simulation's spectrum (usm_sim_spectrum).  The samples of a run
 * (usm_sim_callbacks.sample, at t0 + j / rate and at the end) are recorded:
 * rotor speed phidot_R [1/s], tilt theta [rad] and F_n [N].  The settled part
 * of the run is the last `periods` whole excitation periods (period T = 1/f)
 * before the last sample; by default the whole periods of the run's second
 * half (the first half is taken as the start-up transient).  A window of N
 * whole periods puts the harmonics k f exactly on the bins k N: they do not
 * leak.  The window [t_end - N T, t_end) is sampled on the uniform grid of
 * m = round(rate / f) >= 4 points per period, n = N m in all (rate: the
 * sampling rate, by default the recorded samples' mean rate); where a grid
 * point is not a sample (a rate that is not a multiple of f, samples not
 * uniform) the samples are resampled by a natural cubic spline (GSL) and
 * `resampled` says so (the spline's error then shows as weak image lines of
 * the strong ones, about (2 pi / points per period of the line)^4 / 384 of
 * their amplitude).
 *
 * The parasitic vibration.  parasitic_rms is the RMS over the window of the
 * signal minus its synchronous average (the mean over the window's N periods
 * of the grid points at the same phase): everything that does not repeat
 * with the excitation period, the squeal's lines and any drift (Parseval:
 * the power of the unwindowed spectrum off the bins k N).  On a periodic
 * orbit it is 0 up to the integration error; past a Neimark-Sacker point it
 * measures the emerging vibration.
 *
 * Thread safety: no global state; one usm_sim_spectrum per thread.  The
 * caller sets GSL's error handler (usm.h).
 */
#ifndef USM_SPECTRUM_H
#define USM_SPECTRUM_H

#include <stddef.h>
#include <stdio.h>

#include "usm.h"
#include "usm_simulate.h"

#ifdef __cplusplus
extern "C" {
#endif

/* One spectral line (see the header comment). */
typedef struct usm_spectrum_line {
    double frequency;   /* [Hz], interpolated between the bins */
    double amplitude;   /* amplitude of the sinusoid [the signal's unit] */
    double order;       /* frequency / f (NaN when f is 0) */
    int harmonic;       /* k >= 1 when the line is the harmonic k f, else 0 */
    double folded;      /* |frequency - round(frequency / f) f| in [0, f/2] [Hz]
                         * (NaN when f is 0) */
    size_t bin;         /* the bin of the local maximum */
} usm_spectrum_line;

/* Amplitude spectrum amp[0..n/2] of x[0..n-1] (header comment: mean removed,
 * Hann window, amp_k the amplitude of a sinusoid at k / (n dt)).  n >= 4.
 * USM_OK; USM_EINPUT (n < 4, a sample not finite, dt not positive) or
 * USM_EFAILED (out of memory, GSL failed), with msg. */
int usm_spectrum_amplitude(const double *x, size_t n, double dt, double *amp,
                           char msg[USM_MSG_LEN]);

/* The strongest lines of amp[0..nb-1] (bins df apart; nb = n/2 + 1 of
 * usm_spectrum_amplitude), strongest first, at most max of them into lines;
 * f the excitation frequency for `harmonic`, `order` and `folded` (0: none).
 * Returns how many were written. */
size_t usm_spectrum_lines(const double *amp, size_t nb, double df, double f, size_t max,
                          usm_spectrum_line *lines);

/* The channels of the simulation's spectrum. */
enum {
    USM_SPECTRUM_ROTOR_SPEED = 0, /* phidot_R [1/s] */
    USM_SPECTRUM_THETA = 1,       /* tilt [rad] */
    USM_SPECTRUM_F_N = 2,         /* normal force [N] */
    USM_SPECTRUM_NCHANNELS = 3
};
/* "rotor_speed", "theta", "F_n" (NULL out of range). */
const char *usm_spectrum_channel_name(int channel);
/* "1/s", "rad", "N" (NULL out of range). */
const char *usm_spectrum_channel_unit(int channel);

/* Lines kept per channel. */
#define USM_SPECTRUM_MAX_LINES 16

typedef struct usm_sim_spectrum_options {
    double f;           /* excitation frequency [Hz] (the parameter f), > 0 */
    long periods;       /* the window in whole excitation periods; 0: the whole
                           periods of the second half of the recorded samples (default) */
    double rate;        /* grid [1/s]; 0: the recorded samples' mean rate (default) */
    int lines;          /* lines per channel, 1 .. USM_SPECTRUM_MAX_LINES (default 6) */
} usm_sim_spectrum_options;

/* Defaults as above (f = 0: must be set). */
void usm_sim_spectrum_options_default(usm_sim_spectrum_options *opt);

typedef struct usm_sim_spectrum_result {
    double f;                   /* [Hz] */
    double t_from, t_to;        /* the window [s] */
    long periods;               /* its whole excitation periods */
    size_t samples;             /* n, grid points in the window */
    size_t recorded;            /* recorded samples in the window */
    double dt, df;              /* grid spacing [s], bin spacing 1 / (t_to - t_from) [Hz] */
    size_t bins;                /* n / 2 + 1 */
    int resampled;              /* 1: grid points between samples (spline) */
    size_t nlines[USM_SPECTRUM_NCHANNELS];
    usm_spectrum_line lines[USM_SPECTRUM_NCHANNELS][USM_SPECTRUM_MAX_LINES];
    int have_nonharmonic[USM_SPECTRUM_NCHANNELS];
    usm_spectrum_line nonharmonic[USM_SPECTRUM_NCHANNELS]; /* the strongest line that is
                                   not a harmonic of f (among all local maxima) */
    double parasitic_rms[USM_SPECTRUM_NCHANNELS]; /* RMS of the part that does not
                                   repeat with the excitation period (header comment) */
    double seconds;             /* wall time of usm_sim_spectrum_compute [s] */
    double peak[USM_SPECTRUM_NCHANNELS]; /* largest amplitude of the bins k >= 1; 0 when the
                                   channel is constant over the window (zero throughout
                                   after its mean): its spectrum is empty, nlines 0 */
} usm_sim_spectrum_result;

/* The recorded samples of one run and the spectrum of the last compute
 * (opaque). */
typedef struct usm_sim_spectrum usm_sim_spectrum;

/* An empty recorder, or NULL when out of memory. */
usm_sim_spectrum *usm_sim_spectrum_alloc(void);
/* Free s; NULL is allowed. */
void usm_sim_spectrum_free(usm_sim_spectrum *s);
/* Forget the recorded samples (for the next run). */
void usm_sim_spectrum_reset(usm_sim_spectrum *s);
/* Record one sample (call it from usm_sim_callbacks.sample; samples in
 * increasing time; one at a time already recorded is replaced).  0, or -1
 * when out of memory. */
int usm_sim_spectrum_add(usm_sim_spectrum *s, const usm_sim_sample *smp);
/* Number of recorded samples. */
size_t usm_sim_spectrum_count(const usm_sim_spectrum *s);

/* Check opt for samples spanning `duration` seconds as usm_sim_spectrum_compute
 * does (call it before a run of that duration).  USM_OK, or USM_EINPUT with
 * "FIELD: reason" in msg (FIELD: f, periods, rate, lines). */
int usm_sim_spectrum_check(const usm_sim_spectrum_options *opt, double duration,
                           char msg[USM_MSG_LEN]);

/* The spectrum of the recorded samples' settled part (header comment).
 * USM_OK; USM_EINPUT for bad options or too few samples (fewer than 2 whole
 * periods, or more periods than recorded: message "periods: ..."), USM_EFAILED
 * when out of memory; with msg. */
int usm_sim_spectrum_compute(usm_sim_spectrum *s, const usm_sim_spectrum_options *opt,
                             usm_sim_spectrum_result *out, char msg[USM_MSG_LEN]);

/* The amplitudes of channel c of the last compute (out->bins values, bin k at
 * k df); NULL before a compute or out of range. */
const double *usm_sim_spectrum_amplitudes(const usm_sim_spectrum *s, int channel);

/* The last compute's spectrum (r: its result) as CSV in the project's
 * dialect (write/spectrum_out.c): frequency [Hz], order [1] (frequency / f),
 * rotor_speed [1/s], theta [rad], F_n [N] (the amplitudes), one row per bin
 * from k = 1 (the removed mean left out).  0, or -1 before a compute or on a
 * write error. */
int usm_sim_spectrum_write_csv(const usm_sim_spectrum *s, const usm_sim_spectrum_result *r,
                               FILE *out);

#ifdef __cplusplus
}
#endif

#endif /* USM_SPECTRUM_H */
