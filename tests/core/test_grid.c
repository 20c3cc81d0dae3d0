/* The grid values (core/grid.h): usm_grid_fill, which starts each value's
 * search for its shortest decimal form from its neighbour's precision, gives
 * bit for bit the values of usm_grid_value (the bisection on the precision
 * alone) on decimal grids, on grids of values with no short form, across
 * zero, downwards and on tiny and huge ranges; and the documented examples. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "check.h"
#include "core/grid.h"

static int compare(double from, double to, long n, double *buf)
{
    usm_grid_fill(from, to, n, buf);
    for (long i = 0; i < n; ++i) {
        const double v = usm_grid_value(from, to, i, n);
        if (!(buf[i] == v)) {
            CHECK(0, "grid %.17g .. %.17g in %ld: value %ld is %.17g, usm_grid_value %.17g", from,
                  to, n, i, buf[i], v);
            return 1;
        }
    }
    return 0;
}

int main(void)
{
    static double buf[5000];
    const double fixed[][3] = {{0, 0.01, 1002},      {36000, 39000, 301}, {0.001, 0.005, 9},
                               {-1, 1, 2001},        {39000, 36000, 61},  {0.9, 1.3, 101},
                               {0, 7.637626158e-3, 1002}, {1e-300, 3e-300, 7}, {-5e300, 5e300, 11},
                               {0.1, 0.7, 4999},     {1, 1 + 1e-12, 13}};
    int bad = 0;
    for (size_t k = 0; k < sizeof fixed / sizeof fixed[0]; ++k)
        bad += compare(fixed[k][0], fixed[k][1], (long)fixed[k][2], buf);
    /* random ends (some short decimals, some not) and sizes */
    uint64_t state = 12345;
    for (int k = 0; k < 400; ++k) {
        const double e = pow(10.0, floor(rng_uniform(&state) * 12) - 6);
        double a = (rng_uniform(&state) - 0.5) * e, b = (rng_uniform(&state) - 0.5) * e;
        if (k % 2) { /* short decimals */
            a = round(a * 1000 / e) * e / 1000;
            b = round(b * 1000 / e) * e / 1000;
        }
        if (a == b)
            continue;
        bad += compare(a, b, 2 + (long)(rng_uniform(&state) * 400), buf);
    }
    usm_grid_fill(0.001, 0.005, 9, buf);
    CHECK(buf[5] == 0.0035, "0.001 .. 0.005 in 9: value 5 is %.17g", buf[5]);
    usm_grid_fill(36000, 39000, 301, buf);
    CHECK(buf[1] == 36010 && buf[0] == 36000 && buf[300] == 39000, "36000 .. 39000: %.17g",
          buf[1]);
    printf("%s: %d failure(s), %d grids differing\n", failures ? "FAIL" : "ok", failures, bad);
    return failures != 0;
}
