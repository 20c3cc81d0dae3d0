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
    char buf[40];
    for (int prec = 1; prec <= 17; ++prec) {
        snprintf(buf, sizeof buf, "%.*g", prec, v);
        const double w = strtod(buf, NULL);
        if (fabs(w - v) <= err)
            return w;
    }
    return v;
}
