/* The squeal frequency: the vibration a complex pair of Floquet multipliers
 * describes (usm.h, "the squeal frequency"). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "usm.h"

#define TWO_PI 6.283185307179586476925286766559

double usm_squeal_frequency(double f, double re, double im)
{
    if (!isfinite(f) || f <= 0 || !isfinite(re) || !isfinite(im) || (re == 0 && im == 0))
        return NAN;
    /* atan2 in [-pi, pi]: |arg| in [0, pi], the frequency in [0, f/2] */
    return f * fabs(atan2(im, re)) / TWO_PI;
}

int usm_floquet_squeal(const usm_floquet_result *r, double f, usm_squeal *out)
{
    memset(out, 0, sizeof *out);
    out->index = -1;
    out->re = out->im = out->modulus = out->frequency = NAN;
    if (!isfinite(f) || f <= 0) {
        snprintf(out->reason, sizeof out->reason, "f: must be finite and positive (got %g)", f);
        return USM_EINPUT;
    }
    double best = -1.0;
    for (int k = 0; k < r->n && k < USM_MAX_NX; ++k) {
        const double re = r->re[k], im = r->im[k], mod = hypot(re, im);
        if (r->cyclic[k] || !(im > USM_COMPLEX_PAIR_TOL * mod) || !isfinite(mod))
            continue; /* the member with im > 0 stands for the pair */
        if (mod > best) {
            best = mod;
            out->index = k;
        }
    }
    if (out->index < 0) {
        snprintf(out->reason, sizeof out->reason,
                 "no complex pair among the %d multipliers (all real: no oscillatory mode)",
                 r->n);
        return USM_OK;
    }
    out->found = 1;
    out->re = r->re[out->index];
    out->im = r->im[out->index];
    out->modulus = best;
    out->frequency = usm_squeal_frequency(f, out->re, out->im);
    return USM_OK;
}
