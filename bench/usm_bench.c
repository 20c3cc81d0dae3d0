/* usm_bench: speed of the stationary solver and the Floquet multipliers.
 *
 * For each model at the paper's parameters: the mean wall time of one
 * stationary solution (full search from the parameters alone) and of one set
 * of Floquet multipliers for each method at its default tolerance, and the
 * number of correct digits achieved, measured against a reference run at much
 * tighter tolerance (CVODES rtol 1e-12, atol 1e-16).
 *
 * Usage: usm_bench [repetitions]   (default 200)
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include <gsl/gsl_errno.h>

#include "usm.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Largest distance between corresponding multipliers (both sorted alike). */
static double multiplier_error(const usm_floquet_result *a, const usm_floquet_result *b)
{
    double e = 0;
    for (int i = 0; i < a->n; ++i)
        e = fmax(e, hypot(a->re[i] - b->re[i], a->im[i] - b->im[i]));
    return e;
}

int main(int argc, char **argv)
{
    const int reps = argc > 1 ? atoi(argv[1]) : 200;
    if (reps < 1) {
        fprintf(stderr, "usm_bench: repetitions: must be a positive integer\n");
        return 2;
    }
    gsl_set_error_handler_off();
    printf("%-6s %-28s %12s %10s\n", "model", "task", "time", "digits");
    for (int k = 0; k < USM_NMODELS; ++k) {
        const usm_model *m = usm_models[k];
        usm_params p;
        usm_params_default(&p);
        usm_steady *s = usm_steady_alloc(m);
        usm_floquet *f = usm_floquet_alloc(m);
        if (!s || !f) {
            fprintf(stderr, "usm_bench: out of memory\n");
            return 1;
        }
        double t0 = now();
        for (int r = 0; r < reps; ++r)
            if (usm_steady_solve(s, &p, NULL) != USM_OK) {
                fprintf(stderr, "usm_bench: %s: %s\n", m->name, usm_steady_message(s));
                return 1;
            }
        printf("%-6s %-28s %9.1f us %10s\n", m->name, "stationary solution",
               (now() - t0) / reps * 1e6, "");
        const usm_steady_solution *sol = usm_steady_root(s, 0);

        usm_floquet_options ref_opt;
        usm_floquet_result ref, res;
        usm_floquet_options_default(&ref_opt);
        ref_opt.rtol = 1e-12;
        ref_opt.atol = 1e-16;
        if (usm_floquet_compute(f, &p, sol, 0.0, &ref_opt, &ref) != USM_OK) {
            fprintf(stderr, "usm_bench: %s: %s\n", m->name, usm_floquet_message(f));
            return 1;
        }
        const struct {
            const char *name;
            usm_floquet_method method;
        } methods[] = {{"Floquet, variational (CVODES)", USM_FLOQUET_VARIATIONAL},
                       {"Floquet, exponential", USM_FLOQUET_EXPONENTIAL}};
        for (int j = 0; j < 2; ++j) {
            usm_floquet_options opt;
            usm_floquet_options_default(&opt);
            opt.method = methods[j].method;
            const int freps = reps / 10 > 0 ? reps / 10 : 1;
            t0 = now();
            for (int r = 0; r < freps; ++r)
                if (usm_floquet_compute(f, &p, sol, 0.0, &opt, &res) != USM_OK) {
                    fprintf(stderr, "usm_bench: %s: %s\n", m->name, usm_floquet_message(f));
                    return 1;
                }
            const double dt = (now() - t0) / freps;
            const double err = multiplier_error(&res, &ref);
            printf("%-6s %-28s %9.3f ms %10.1f\n", m->name, methods[j].name, dt * 1e3,
                   err > 0 ? -log10(err) : 16.0);
        }
        usm_floquet_free(f);
        usm_steady_free(s);
    }
    return 0;
}
