/* bench_sweep: wall time of a frequency sweep with Floquet stability at every
 * point, the motor-characteristics use case.  Targets: the
 * 1000-point sweep with stability <= 0.1 s, stationary solution + Floquet
 * <= 50 us per point; printed beside the 2-thread row.  The CPU time per
 * point (all threads) is printed too: on a shared machine it shows the work
 * where the wall time shows the load.
 *
 * For each model: the continuation alone (no multipliers), then the full sweep
 * on 1 thread and on 2 threads, 36-39 kHz at the paper's parameters, and the
 * speed-up of the second thread.  The best of `repetitions` runs is printed
 * (the machine may be shared).
 *
 * Usage: bench_sweep [points [repetitions]]   (default 1000 3)
 */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include <gsl/gsl_errno.h>

#include "usm_sweep.h"

static double clock_s(clockid_t id)
{
    struct timespec ts;
    clock_gettime(id, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

typedef struct timing {
    double wall, cpu; /* of the fastest run (wall); cpu: all threads of the process */
} timing;

/* Fastest of `reps` runs; wall < 0 on failure.  The CPU time shows the work
 * when other processes share the cores and the wall time says little. */
static timing best_time(usm_sweep *s, const usm_params *p, const usm_sweep_options *o, int reps)
{
    timing best = {-1, 0};
    for (int r = 0; r < reps; ++r) {
        const double w0 = clock_s(CLOCK_MONOTONIC), c0 = clock_s(CLOCK_PROCESS_CPUTIME_ID);
        if (usm_sweep_run(s, p, o) != USM_OK) {
            fprintf(stderr, "bench_sweep: %s\n", usm_sweep_message(s));
            best.wall = -1;
            return best;
        }
        const timing t = {clock_s(CLOCK_MONOTONIC) - w0, clock_s(CLOCK_PROCESS_CPUTIME_ID) - c0};
        if (best.wall < 0 || t.wall < best.wall)
            best = t;
    }
    return best;
}

static void row(const char *model, const char *task, timing t, int points, const char *target)
{
    printf("%-22s %-24s %9.3f %9.3f %9.1f us %9.1f us  %s\n", model, task, t.wall, t.cpu,
           t.wall / points * 1e6, t.cpu / points * 1e6, target);
}

int main(int argc, char **argv)
{
    const int points = argc > 1 ? atoi(argv[1]) : 1000;
    const int reps = argc > 2 ? atoi(argv[2]) : 3;
    if (points < 2 || reps < 1) {
        fprintf(stderr, "bench_sweep: usage: bench_sweep [points >= 2 [repetitions >= 1]]\n");
        return 2;
    }
    gsl_set_error_handler_off();
    printf("%d-point sweep of f over 36-39 kHz, best of %d runs\n", points, reps);
    printf("%-22s %-24s %9s %9s %12s %12s  %s\n", "model", "task", "wall [s]", "cpu [s]",
           "wall/point", "cpu/point", "target");
    for (int k = 0; k < USM_NMODELS; ++k) {
        const usm_model *m = usm_models[k];
        usm_params p;
        usm_sweep_options o;
        usm_params_default(&p);
        usm_sweep_options_default(&o);
        o.over = "f";
        o.from = 36000;
        o.to = 39000;
        o.points = points;
        usm_sweep *s = usm_sweep_alloc(m);
        if (!s) {
            fprintf(stderr, "bench_sweep: out of memory\n");
            return 1;
        }
        o.floquet = 0;
        const timing t_cont = best_time(s, &p, &o, reps);
        o.floquet = 1;
        o.threads = 1;
        const timing t1 = best_time(s, &p, &o, reps);
        o.threads = 2;
        const timing t2 = best_time(s, &p, &o, reps);
        usm_sweep_free(s);
        if (t_cont.wall < 0 || t1.wall < 0 || t2.wall < 0)
            return 1;
        char target[64] = "";
        if (points == 1000)
            snprintf(target, sizeof target, "<= 0.1 s, <= 50 us/point");
        row(m->name, "continuation only", t_cont, points, "");
        row(m->name, "with Floquet, 1 thread", t1, points, "");
        row(m->name, "with Floquet, 2 threads", t2, points, target);
        printf("%-22s speed-up of the second thread: %.2f\n", m->name, t1.wall / t2.wall);
    }
    return 0;
}
