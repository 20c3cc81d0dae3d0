/* The values of an equally spaced grid (see grid.h). */
#include "grid.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

/* v rounded to prec significant decimal digits and read back */
static double rounded(double v, int prec)
{
    char buf[40];
    snprintf(buf, sizeof buf, "%.*g", prec, v);
    return strtod(buf, NULL);
}

/* v rounded to prec digits, and whether it lies within err of v; 17 digits
 * give v itself back (no conversion needed) */
static int passes(double v, double err, int prec, double *w)
{
    *w = prec >= 17 ? v : rounded(v, prec);
    return fabs(*w - v) <= err;
}

/* The shortest decimal within err of v, its precision into *prec_out;
 * hint (1..17, or 0 for none) the precision of a neighbouring value.
 * Whether v rounded to p digits lies within err is monotone in p, since the
 * value rounded to p digits is also a candidate with p + 1 digits, and the
 * nearest one is no farther: the answer is the smallest p that passes.
 * Without a hint it is found by bisection (a sweep's grid of 1,002 values
 * paid up to 17 conversions each counting up); with one, by walking from
 * the neighbour's precision, which along a grid is this value's or next to
 * it: one or two conversions instead of five. */
static double shortest(double v, double err, int hint, int *prec_out)
{
    double w, best = v;
    *prec_out = 17;
    if (hint >= 1 && hint <= 17) {
        int p = hint;
        if (passes(v, err, p, &w)) {
            best = w;
            while (p > 1 && passes(v, err, p - 1, &w)) {
                best = w;
                --p;
            }
        } else {
            while (!passes(v, err, ++p, &w))
                ;
            best = w;
        }
        *prec_out = p;
        return best;
    }
    int lo = 1, hi = 17;
    while (lo <= hi) {
        const int prec = (lo + hi) / 2;
        if (passes(v, err, prec, &w)) {
            best = w;
            *prec_out = prec;
            hi = prec - 1;
        } else
            lo = prec + 1;
    }
    return best;
}

static double grid_value(double from, double to, long i, long n, int hint, int *prec)
{
    *prec = 0;
    if (n < 2 || i <= 0)
        return from;
    if (i >= n - 1)
        return to;
    const double m = (double)(n - 1);
    const double v = (from * (m - (double)i) + to * (double)i) / m;
    const double err = fmin(2.5 * DBL_EPSILON * fmax(fabs(from), fabs(to)),
                            0.25 * fabs(to - from) / m);
    return shortest(v, err, hint, prec);
}

double usm_grid_value(double from, double to, long i, long n)
{
    int prec;
    return grid_value(from, to, i, n, 0, &prec);
}

void usm_grid_fill(double from, double to, long n, double *out)
{
    int prec = 0;
    for (long i = 0; i < n; ++i)
        out[i] = grid_value(from, to, i, n, prec, &prec);
}
