/* check.h: the shared helper of the C tests.
 *
 * CHECK(cond, fmt, ...) counts and reports a failure with its place and keeps
 * going, so one run shows every failing check; main() returns failures != 0.
 * CHECK is an expression with the value of cond (1 or 0), so a check of an
 * optional result guards the checks that use it:
 *
 *     const usm_sweep_event *e = find_event(...);
 *     if (CHECK(e != NULL, "no fold event")) { ... checks of e ... }
 *
 * The arguments after cond are evaluated only when the check fails.
 *
 * rng_*: the tests' deterministic random numbers, splitmix64 on a state the
 * caller owns (uint64_t, any seed), uniform doubles with 53 random bits.
 *
 * multipliers_distance: Floquet multipliers compared as sets, pair by pair
 * (nearest pairs first), so two methods that order equal-modulus multipliers
 * differently still agree and a lost or doubled multiplier does not. */
#ifndef USM_TEST_CHECK_H
#define USM_TEST_CHECK_H

#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>

static int failures;

#if defined(__GNUC__)
__attribute__((format(printf, 3, 4)))
#endif
static inline int check_fail_(const char *file, int line, const char *fmt, ...)
{
    va_list ap;
    ++failures;
    printf("FAIL %s:%d: ", file, line);
    va_start(ap, fmt);
    vprintf(fmt, ap);
    va_end(ap);
    printf("\n");
    fflush(stdout);
    return 0;
}

static inline int check_pass_(void) { return 1; }

#define CHECK(cond, ...) ((cond) ? check_pass_() : check_fail_(__FILE__, __LINE__, __VA_ARGS__))

/* ---- random numbers: splitmix64 ------------------------------------------ */

static inline uint64_t rng_next(uint64_t *state)
{
    uint64_t z = (*state += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

/* uniform in [0, 1) */
static inline double rng_uniform(uint64_t *state)
{
    return (double)(rng_next(state) >> 11) * 0x1.0p-53;
}

/* uniform in [a, b) */
static inline double rng_range(uint64_t *state, double a, double b)
{
    return a + (b - a) * rng_uniform(state);
}

/* log-uniform in [a, b), 0 < a < b */
static inline double rng_log_range(uint64_t *state, double a, double b)
{
    return exp(rng_range(state, log(a), log(b)));
}

/* ---- Floquet multipliers matched by nearest pairs ------------------------- */

#define CHECK_MAX_MULTIPLIERS 64

/* The multipliers a (na: are + i aim) and b (nb) paired one to one, the
 * nearest pair of the unpaired ones first; the largest distance |a_i - b_j|
 * of a pair.  INFINITY when the counts differ (or exceed
 * CHECK_MAX_MULTIPLIERS); NAN when a multiplier is not finite. */
static inline double multipliers_distance(int na, const double *are, const double *aim, int nb,
                                          const double *bre, const double *bim)
{
    if (na != nb || na > CHECK_MAX_MULTIPLIERS)
        return INFINITY;
    int used_a[CHECK_MAX_MULTIPLIERS] = {0}, used_b[CHECK_MAX_MULTIPLIERS] = {0};
    double worst = 0;
    for (int pair = 0; pair < na; ++pair) {
        double best = INFINITY;
        int bi = -1, bj = -1;
        for (int i = 0; i < na; ++i)
            for (int j = 0; !used_a[i] && j < nb; ++j) {
                const double d = hypot(are[i] - bre[j], aim[i] - bim[j]);
                if (!used_b[j] && (bi < 0 || d < best)) {
                    best = d;
                    bi = i;
                    bj = j;
                }
            }
        if (!isfinite(best))
            return NAN;
        used_a[bi] = used_b[bj] = 1;
        worst = fmax(worst, best);
    }
    return worst;
}

/* The same for two results with members n, re[], im[] (usm_floquet_result,
 * the floquet member of usm_periodic_result, ...). */
#define MULTIPLIERS_DISTANCE(a, b)                                                                 \
    multipliers_distance((a).n, (a).re, (a).im, (b).n, (b).re, (b).im)

#endif /* USM_TEST_CHECK_H */
