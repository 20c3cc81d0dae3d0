/* bench_python: the C side of the Python module's measures (bench/bench_python.py prints the comparison).  Prints, one per line:
 *   rhs_loop_s N SECONDS      the generated rhs over N states in a C loop
 *                             (best of 5), the loop usm.Model.rhs runs
 *   steady_call_us US         usm_run_steady and usm_run_json (usm_run.h: the
 *                             steady analysis and its JSON text) per call
 *   steady_nojson_us US       usm_run_steady: the same library calls without
 *                             the JSON, what usm.Model.steady() calls
 * Run: build/bench/bench_python [N] */
#define _POSIX_C_SOURCE 200809L
#include <gsl/gsl_errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "usm_run.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts); /* CPU time: the machine is shared */
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int main(int argc, char **argv)
{
    const usm_model *m = usm_model_find("3dof");
    usm_params p;
    long n = argc > 1 ? atol(argv[1]) : 1000000;
    int nx = m->nx;
    double *x = malloc((size_t)n * (size_t)nx * sizeof *x);
    double *out = malloc((size_t)n * (size_t)nx * sizeof *out);
    if (!x || !out || n < 1)
        return 1;
    gsl_set_error_handler_off();
    usm_params_default(&p);
    uint64_t s = 27;
    for (long i = 0; i < n * nx; ++i) { /* the same distribution as bench_python.py */
        s = s * 6364136223846793005ULL + 1442695040888963407ULL;
        x[i] = 0.01 + 0.19 * (double)(s >> 11) * 0x1.0p-53;
    }
    double best = 1e300;
    for (int r = 0; r < 5; ++r) {
        double t0 = now();
        for (long i = 0; i < n; ++i)
            m->rhs(x + i * nx, 1e-5, &p, out + i * nx);
        double dt = now() - t0;
        best = dt < best ? dt : best;
    }
    printf("rhs_loop_s %ld %.6f\n", n, best);

    usm_floquet_options fo;
    usm_op_options op;
    usm_floquet_options_default(&fo);
    usm_op_options_default(&op);
    /* per call: the best mean of 10 batches of 50 calls (the machine is shared) */
    double best_json = 1e300, best_bare = 1e300;
    for (int b = 0; b < 10; ++b) {
        double t0 = now();
        for (int k = 0; k < 50; ++k) {
            usm_run *r = usm_run_steady(m, &p, 0.0, &fo, &op);
            free(usm_run_json(r, NULL));
            usm_run_free(r);
        }
        double dt = (now() - t0) / 50;
        best_json = dt < best_json ? dt : best_json;
        t0 = now();
        for (int k = 0; k < 50; ++k) {
            usm_run_free(usm_run_steady(m, &p, 0.0, &fo, &op));
        }
        dt = (now() - t0) / 50;
        best_bare = dt < best_bare ? dt : best_bare;
    }
    printf("steady_call_us %.3f\n", 1e6 * best_json);
    printf("steady_nojson_us %.3f\n", 1e6 * best_bare);
    free(x);
    free(out);
    return 0;
}
