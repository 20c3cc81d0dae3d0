/* A 200-point phase-error sweep (0 to 30 degrees) of the periodic orbit with
 * its events (usm_periodic_sweep_run), per model of the variant imperfect,
 * and one over 0 to 0.25 rad, which holds no event: the cost a grid point.
 * Goal: <= 5 s.  Run: build/bench/bench_periodic_sweep [points] */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "usm_periodic_sweep.h"

/* CPU time of this process: the machine may be shared, and wall time then
 * measures the other users too. */
static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

int main(int argc, char **argv)
{
    const int points = argc > 1 ? atoi(argv[1]) : 200;
    const char *bases[] = {"3dof", "4dof"};
    for (int b = 0; b < 2; ++b) {
        const usm_model *m = usm_model_variant(bases[b], "imperfect");
        usm_periodic_sweep *s = m ? usm_periodic_sweep_alloc(m) : NULL;
        usm_params p;
        usm_periodic_sweep_options o;
        if (!s)
            return 1;
        usm_params_default(&p);
        usm_periodic_sweep_options_default(&o);
        o.over = "phase_error";
        o.from = 0;
        o.to = 0.5235987755982988; /* 30 degrees */
        o.points = points;
        const double t0 = now();
        if (usm_periodic_sweep_run(s, &p, &o) != USM_OK) {
            fprintf(stderr, "%s: %s\n", m->name, usm_periodic_sweep_message(s));
            return 1;
        }
        const double t = now() - t0;
        printf("%-16s %d-point phase-error sweep, 0 to 30 deg, with %zu events: %.2f s CPU time "
               "(%.2f ms a grid point)\n", m->name, points, usm_periodic_sweep_event_count(s), t,
               1e3 * t / points);
        /* the same branch without events: the per-point cost of the
         * continuation alone (phase error 0 to 14 deg holds none) */
        o.to = 0.25;
        const double t1 = now();
        if (usm_periodic_sweep_run(s, &p, &o) != USM_OK || usm_periodic_sweep_event_count(s)) {
            fprintf(stderr, "%s: %s\n", m->name, usm_periodic_sweep_message(s));
            return 1;
        }
        const double te = now() - t1;
        printf("%-16s %d-point phase-error sweep, 0 to 14.3 deg, no events: %.2f s CPU time "
               "(%.2f ms a grid point)\n", m->name, points, te, 1e3 * te / points);
        usm_periodic_sweep_free(s);
    }
    return 0;
}
