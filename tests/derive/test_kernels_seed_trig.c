/* test_kernels_seed_trig: steady_seed_trig, given sin, cos and tan of the tilt as the
 * tilt search computes them (runtime/solve/steady.c keeps them with its grid), gives
 * the outputs of steady_seed bit for bit, for every model.
 *
 * The tilt search samples the trig variant but refines roots with steady_seed
 * (tilt_g), and the sweep's rows must equal `usm steady` bit for bit (the
 * Floquet multipliers amplify a last-bit difference), so equality to rounding
 * is not enough: every output must be the same double.  The reference is the
 * seed kernel with its own libm calls.  Tilts: 4000 log-spaced over
 * [1e-10, 0.3] rad (the search's range 1e-9 .. 0.2 and beyond) at the default
 * parameters and at 20 parameter sets (defaults times log-uniform factors in
 * [1/2, 2]).  So that the comparison can fail, the same check with sin theta
 * moved by one ulp must find a difference.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "usm.h"

#include "check.h"

#define NTILT 4000
#define NSETS 21

static uint64_t rng = 0x5eed7716ULL;

/* Samples where the two kernels differ (a NaN equal in bits counts as equal). */
static long differences(const usm_model *m, const usm_params *p, int perturb)
{
    long diff = 0;
    for (int i = 0; i < NTILT; ++i) {
        const double theta = 1e-10 * pow(0.3 / 1e-10, (double)i / (NTILT - 1));
        double trig[3] = {sin(theta), cos(theta), tan(theta)};
        if (perturb)
            trig[0] = nextafter(trig[0], 1.0);
        double a[USM_SEED_COUNT], b[USM_SEED_COUNT];
        m->steady_seed(theta, p, a);
        m->steady_seed_trig(theta, trig, p, b);
        if (memcmp(a, b, sizeof a) != 0)
            ++diff;
    }
    return diff;
}

int main(void)
{
    for (int k = 0; k < USM_NMODELS; ++k) {
        const usm_model *m = usm_models[k];
        usm_params base, p;
        usm_params_default(&base);
        for (int set = 0; set < NSETS; ++set) {
            p = base;
            if (set > 0)
                for (int j = 0; j < USM_NPARAMS; ++j) {
                    double *f = usm_params_field(&p, &usm_param_table[j]);
                    *f *= exp(log(2.0) * (2.0 * rng_uniform(&rng) - 1.0));
                }
            const long d = differences(m, &p, 0);
            CHECK(d == 0, "%s, parameter set %d: steady_seed_trig differs from steady_seed at %ld "
                          "of %d tilts",
                  m->name, set, d, NTILT);
        }
        const long d = differences(m, &base, 1);
        CHECK(d != 0, "%s: sin theta one ulp off changes no output: the comparison cannot fail",
              m->name);
        printf("%s: bit for bit at %d tilts x %d parameter sets; one ulp of sin theta "
               "changes %ld of %d\n", m->name, NTILT, NSETS, d, NTILT);
    }
    return failures != 0;
}
