/* One periodic orbit with its multipliers (usm_periodic_solve), per model of
 * the variant imperfect, phase error 0.1 rad and mode split 1 %: the ideal
 * start (usm_steady) included, and the shooting alone from the converged
 * state.  Goal: <= 20 ms per orbit.  Run: build/bench/bench_periodic */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <time.h>

#include "usm_periodic.h"

/* CPU time of this process: the machine may be shared, and wall time then
 * measures the other users too. */
static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

int main(void)
{
    const char *bases[] = {"3dof", "4dof"};
    for (int b = 0; b < 2; ++b) {
        const usm_model *m = usm_model_variant(bases[b], "imperfect");
        usm_periodic *w = m ? usm_periodic_alloc(m) : NULL;
        usm_params p;
        usm_periodic_result r, r2;
        if (!w)
            return 1;
        usm_params_default(&p);
        p.phase_error = 0.1;
        p.mode_split = 0.01;
        const int reps = 10;
        double t0 = now();
        for (int k = 0; k < reps; ++k)
            if (usm_periodic_solve(w, &p, NULL, NULL, &r) != USM_OK) {
                fprintf(stderr, "%s: %s\n", m->name, usm_periodic_message(w));
                return 1;
            }
        double t1 = now();
        for (int k = 0; k < reps; ++k)
            if (usm_periodic_solve(w, &p, r.x0, NULL, &r2) != USM_OK)
                return 1;
        double t2 = now();
        printf("%-16s one orbit with multipliers (CPU time): %.1f ms from the ideal start (%d Newton "
               "iterations), %.1f ms from the converged state (one period map)\n",
               m->name, 1e3 * (t1 - t0) / reps, r.iterations, 1e3 * (t2 - t1) / reps);
        usm_periodic_free(w);
    }
    return 0;
}
