/* The values of an equally spaced grid (see grid.h). */
#include "grid.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

double usm_grid_value(double from, double to, long i, long n)
{
    if (n < 2 || i <= 0)
        return from;
    if (i >= n - 1)
        return to;
    const double m = (double)(n - 1);
    const double v = (from * (m - (double)i) + to * (double)i) / m;
    const double err = fmin(2.5 * DBL_EPSILON * fmax(fabs(from), fabs(to)),
                            0.25 * fabs(to - from) / m);
    /* The shortest precision by bisection, not by counting up (a sweep's
     * grid of 1,002 values paid up to 17 conversions each, more than its
     * continuation): whether v rounded to p digits lies within err is
     * monotone in p, since the value rounded to p digits is also a candidate
     * with p + 1 digits, and the nearest one is no farther. */
    int lo = 1, hi = 17;
    double best = v;
    while (lo <= hi) {
        const int prec = (lo + hi) / 2;
        char buf[40];
        snprintf(buf, sizeof buf, "%.*g", prec, v);
        const double w = strtod(buf, NULL);
        if (fabs(w - v) <= err) {
            best = w;
            hi = prec - 1;
        } else
            lo = prec + 1;
    }
    return best;
}
