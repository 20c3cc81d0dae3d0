/* bench_sensitivity: time of all sensitivities of one stationary solution.
 *
 * For each model at the paper's parameters: the mean CPU time of
 * usm_sensitivity_compute for every output and every parameter, without and
 * with max_modulus (the Floquet part dominates), and of the stationary solve
 * it starts from, for comparison; each the best of 5 batches (the machine may
 * be shared).  Target: <= 5 ms per point, printed beside it.
 *
 * Usage: bench_sensitivity [repetitions]   (default 20)
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include <gsl/gsl_errno.h>

#include "usm_design.h"

/* CPU time of this (single-threaded) process: on an idle core the wall time,
 * and on a machine shared with other work (the 2 cores usually are) the
 * work done, not the waiting. */
static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int main(int argc, char **argv)
{
    const int reps = argc > 1 ? atoi(argv[1]) : 20;
    if (reps < 1) {
        fprintf(stderr, "bench_sensitivity: repetitions: must be a positive integer\n");
        return 2;
    }
    gsl_set_error_handler_off();
    printf("%-22s %14s %20s %20s  %s\n", "model", "steady solve", "sens. stationary",
           "sens. all (+Floquet)", "target");
    for (int k = 0; k < USM_NMODELS; ++k) {
        const usm_model *m = usm_models[k];
        usm_params p;
        usm_params_default(&p);
        usm_steady *s = usm_steady_alloc(m);
        usm_sensitivity *sens = usm_sensitivity_alloc(m);
        usm_sensitivity_result *r = malloc(sizeof *r);
        if (!s || !sens || !r) {
            fprintf(stderr, "bench_sensitivity: out of memory\n");
            return 1;
        }
        double t0 = now();
        for (int i = 0; i < reps; ++i)
            if (usm_steady_solve(s, &p, NULL) != USM_OK) {
                fprintf(stderr, "bench_sensitivity: %s: %s\n", m->name, usm_steady_message(s));
                return 1;
            }
        double t_solve = (now() - t0) / reps;
        const usm_steady_solution *sol = usm_steady_root(s, 0);
        double t[2] = {INFINITY, INFINITY};
        for (int fl = 0; fl < 2; ++fl)
            for (int batch = 0; batch < 5; ++batch) {
                t0 = now();
                for (int i = 0; i < reps; ++i)
                    if (usm_sensitivity_compute(sens, &p, sol, fl, r) != USM_OK) {
                        fprintf(stderr, "bench_sensitivity: %s: %s\n", m->name,
                                usm_sensitivity_message(sens));
                        return 1;
                    }
                t[fl] = fmin(t[fl], (now() - t0) / reps);
            }
        printf("%-22s %11.3f ms %17.3f ms %17.3f ms  <= 5 ms\n", m->name, 1e3 * t_solve,
               1e3 * t[0], 1e3 * t[1]);
        free(r);
        usm_sensitivity_free(sens);
        usm_steady_free(s);
    }
    return 0;
}
