/* The statistics of a tolerance study (usm_tolerance.h; its writers:
 * io/tolerance_out.c). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_sort.h>
#include <gsl/gsl_statistics_double.h>

#include "tolerance_stats.h"
#include "usm_map.h"

/* Two-sided 95 % normal quantile, z = Phi^-1(0.975). */
#define Z95 1.959963984540054

/* The Wilson score interval: unlike the normal (Wald) interval it stays in
 * [0, 1] and keeps its coverage near yields of 0 and 1, where a design
 * study's answers usually are. */
static void wilson(uint64_t k, uint64_t n, double *lo, double *hi)
{
    const double nn = (double)n, ph = (double)k / nn, z2 = Z95 * Z95;
    const double denom = 1.0 + z2 / nn;
    const double center = (ph + z2 / (2.0 * nn)) / denom;
    const double half = Z95 * sqrt(ph * (1.0 - ph) / nn + z2 / (4.0 * nn * nn)) / denom;
    *lo = k == 0 ? 0.0 : fmax(0.0, center - half);
    *hi = k == n ? 1.0 : fmin(1.0, center + half);
}

int tol_finish(usm_tolerance *t)
{
    usm_tolerance_summary *s = &t->sum;
    const uint64_t n = t->opt.samples;
    const int w = t->width;
    double *x = malloc(n * sizeof *x), *y = malloc(n * sizeof *y),
           *work = malloc(2 * n * sizeof *work);
    if (!x || !y || !work) {
        free(x);
        free(y);
        free(work);
        snprintf(t->msg, USM_MSG_LEN, "out of memory for the statistics");
        return USM_EFAILED;
    }
    s->samples = n;
    s->seed = t->opt.seed;
    s->good = s->exists = s->stable = s->failed = s->redrawn = 0;
    s->op_exists = s->op_no_stable_root = s->op_does_not_start = s->op_unknown = 0;
    s->invalid = s->invalid_contact_open = s->invalid_stick = 0;
    for (uint64_t i = 0; i < n; ++i) {
        const double *row = t->rows + i * (uint64_t)w, *out = row + t->nvary;
        s->good += row[TOL_ROW_GOOD(t)] != 0.0;
        /* a count, checked on load (tolerance_io.c); never an out-of-range conversion */
        const double r = row[TOL_ROW_REDRAWS(t)];
        s->redrawn += r >= 0.0 && r < (double)TOL_MAX_REDRAWS ? (uint64_t)r : 0;
        s->exists += out[USM_TOL_EXISTS] != 0.0;
        s->stable += out[USM_TOL_STABLE] == 1.0;
        s->failed += out[USM_TOL_EXISTS] != 0.0 && isnan(out[USM_TOL_MAX_MODULUS]);
        s->op_exists += out[USM_TOL_OP_CLASS] == (double)USM_POINT_OP_STABLE;
        s->op_no_stable_root += out[USM_TOL_OP_CLASS] == (double)USM_POINT_OP_NO_STABLE_ROOT;
        s->op_does_not_start += out[USM_TOL_OP_CLASS] == (double)USM_POINT_OP_DOES_NOT_START;
        s->op_unknown += out[USM_TOL_OP_CLASS] == (double)USM_POINT_OP_UNKNOWN;
        /* NaN (no solution) is neither valid nor invalid */
        s->invalid += out[USM_TOL_VALIDITY] > (double)USM_VALID;
        s->invalid_contact_open += out[USM_TOL_VALIDITY] == (double)USM_INVALID_CONTACT_OPEN;
        s->invalid_stick += out[USM_TOL_VALIDITY] == (double)USM_INVALID_STICK;
    }
    s->yield = (double)s->good / (double)n;
    wilson(s->good, n, &s->yield_lo, &s->yield_hi);
    for (int k = 0; k < USM_TOL_NNUMERIC; ++k) {
        size_t m = 0;
        for (uint64_t i = 0; i < n; ++i) {
            const double v = t->rows[i * (uint64_t)w + (uint64_t)(t->nvary + k)];
            if (isfinite(v))
                x[m++] = v;
        }
        s->count[k] = m;
        gsl_sort(x, 1, m);
        for (int q = 0; q < 5; ++q)
            s->quantile[k][q] =
                m ? gsl_stats_quantile_from_sorted_data(x, 1, m, USM_TOLERANCE_QUANTILES[q]) : NAN;
        for (int j = 0; j < t->nvary; ++j) {
            m = 0;
            for (uint64_t i = 0; i < n; ++i) {
                const double *row = t->rows + i * (uint64_t)w;
                if (isfinite(row[t->nvary + k])) {
                    x[m] = row[j];
                    y[m++] = row[t->nvary + k];
                }
            }
            /* a constant column has no ranks to correlate: GSL divides by 0 */
            double r = m >= 3 ? gsl_stats_spearman(x, 1, y, 1, m, work) : NAN;
            t->influence[k][j] = isfinite(r) ? r : NAN;
        }
    }
    free(x);
    free(y);
    free(work);
    t->have_result = 1;
    return USM_OK;
}
