/* One periodic orbit with separation and its multipliers (usm_hybrid_solve,
 * issue 24), per model of the variant imperfect_unilateral past contact loss
 * (phase error 35 deg 3-DOF, 30 deg 4-DOF): the whole solve (the simulation
 * from rest over 10 ms that gives the section and start included), and one
 * period map with the monodromy from the converged state (the cost of the
 * orbit and its multipliers once started near it; a Newton step is one).
 * Issue 24's goal: under 50 ms per orbit.  Run: build/bench/bench_hybrid */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <time.h>

#include "usm_periodic.h"

/* CPU time of this process: the machine may be shared. */
static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

int main(void)
{
    const char *bases[] = {"3dof", "4dof"};
    const double pe[] = {35.0, 30.0};
    for (int b = 0; b < 2; ++b) {
        const usm_model *m = usm_model_variant(bases[b], "imperfect_unilateral");
        usm_hybrid *h = m ? usm_hybrid_alloc(m) : NULL;
        usm_params p;
        usm_hybrid_result r;
        if (!h)
            return 1;
        usm_params_default(&p);
        p.phase_error = pe[b] * 3.14159265358979323846 / 180;
        double t0 = now();
        if (usm_hybrid_solve(h, &p, NULL, &r) != USM_OK) {
            fprintf(stderr, "%s: %s\n", m->name, usm_hybrid_message(h));
            return 1;
        }
        double t1 = now();
        const int reps = 20;
        double x1[USM_MAX_NX], B[USM_MAX_NX * USM_MAX_NX];
        for (int k = 0; k < reps; ++k)
            if (usm_hybrid_period_map(h, r.t0, r.x0, x1, B) != USM_OK)
                return 1;
        double t2 = now();
        printf("%s phase error %g deg: solve %.1f ms (%d Newton iterations, modes %s); one period "
               "map with monodromy %.2f ms; max |multiplier| %.8f\n", m->name, pe[b],
               1e3 * (t1 - t0), r.iterations, r.mode_sequence, 1e3 * (t2 - t1) / reps,
               r.floquet.max_modulus);
        usm_hybrid_free(h);
    }
    return 0;
}
