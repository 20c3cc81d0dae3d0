/* bench_tolerance: throughput of a Monte Carlo tolerance study (target: 10^5 samples with Floquet <= 10 s on this 2-core machine).
 *
 * The study varies F0, c_t and T around the paper's point (3dof, default
 * Floquet method); every sample is the full stationary search and the
 * multipliers.  Prints, for 1 and 2 threads, the wall and CPU time, samples
 * per second and per CPU-second (per core), and the time 10^5 samples take.
 * The CPU time shows the work when other processes share the cores.  Then
 * the cost of writing samples.csv (usm_tolerance_write_csv into /dev/null,
 * CPU microseconds per row; the goal: under 5).
 *
 * Usage: bench_tolerance [samples [model]]   (default 100000 3dof)
 */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include <gsl/gsl_errno.h>

#include "usm_tolerance.h"

static double clock_s(clockid_t id)
{
    struct timespec ts;
    clock_gettime(id, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int main(int argc, char **argv)
{
    static const char *const vary[] = {"F0=normal:10%", "c_t=normal:5%", "T=uniform:0:0.004"};
    const unsigned long long n = argc > 1 ? strtoull(argv[1], NULL, 10) : 100000ULL;
    const usm_model *m = usm_model_find(argc > 2 ? argv[2] : "3dof");
    char msg[USM_MSG_LEN];
    usm_params p;
    gsl_set_error_handler_off();
    if (!m || n == 0) {
        fprintf(stderr, "usage: bench_tolerance [samples [model]]\n");
        return 2;
    }
    usm_params_default(&p);
    printf("tolerance study, model %s, %llu samples (stationary search + Floquet each)\n",
           m->name, n);
    printf("threads   wall [s]   cpu [s]   samples/s   samples/s/core   10^5 samples [s]\n");
    for (int threads = 1; threads <= 2; ++threads) {
        usm_tolerance *t = usm_tolerance_alloc(m);
        usm_tolerance_options opt;
        for (int j = 0; j < 3; ++j) {
            usm_tolerance_vary v;
            if (usm_tolerance_vary_parse(vary[j], &v, msg) != USM_OK ||
                usm_tolerance_vary_add(t, &v) != USM_OK) {
                fprintf(stderr, "bench_tolerance: %s\n", msg);
                return 1;
            }
        }
        usm_tolerance_options_default(&opt);
        opt.samples = n;
        opt.threads = threads;
        const double w0 = clock_s(CLOCK_MONOTONIC), c0 = clock_s(CLOCK_PROCESS_CPUTIME_ID);
        if (usm_tolerance_run(t, &p, &opt) != USM_OK) {
            fprintf(stderr, "bench_tolerance: %s\n", usm_tolerance_message(t));
            return 1;
        }
        const double wall = clock_s(CLOCK_MONOTONIC) - w0,
                     cpu = clock_s(CLOCK_PROCESS_CPUTIME_ID) - c0;
        const usm_tolerance_summary *s = usm_tolerance_result(t);
        printf("%7d %10.3f %9.3f %11.0f %16.0f %18.2f\n", threads, wall, cpu, (double)n / wall,
               (double)n / cpu, 1e5 * wall / (double)n);
        if (threads == 2) {
            printf("yield %.4f [%.4f, %.4f]; %llu of %llu exist, %llu stable\n", s->yield,
                   s->yield_lo, s->yield_hi, (unsigned long long)s->exists,
                   (unsigned long long)s->samples, (unsigned long long)s->stable);
            FILE *null = fopen("/dev/null", "w");
            const double c1 = clock_s(CLOCK_PROCESS_CPUTIME_ID);
            const int bad = !null || usm_tolerance_write_csv(t, null) != 0;
            const double csv = clock_s(CLOCK_PROCESS_CPUTIME_ID) - c1;
            if (null)
                fclose(null);
            printf("samples.csv: %s%.2f us of CPU per row (%llu rows in %.3f s)\n",
                   bad ? "WRITE ERROR " : "", 1e6 * csv / (double)n, (unsigned long long)n, csv);
        }
        usm_tolerance_free(t);
    }
    return 0;
}
