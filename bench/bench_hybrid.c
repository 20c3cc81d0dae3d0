/* One periodic orbit with separation and its multipliers (usm_hybrid_solve,
 * docs/unilateral.md), per model of the variant imperfect_unilateral past contact loss
 * (phase error 35 deg 3-DOF, 30 deg 4-DOF): the whole solve (the start-up
 * simulation from rest that gives the section and start included), and one
 * period map with the monodromy from the converged state (the cost of the
 * orbit and its multipliers once started near it; a Newton step is one).
 * Goal: under 50 ms per orbit.
 * With an argument (3dof or 4dof, and optionally "mode_split"): the orbits with
 * separation from contact loss on, each warm-started from the last
 * (usm_hybrid_solve_from; a simulation when that fails), with their cost and
 * the measures of the orbits with separation.  Run: build/bench/bench_hybrid [3dof|4dof [mode_split]] */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "usm_periodic.h"

/* CPU time of this process: the machine may be shared. */
static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static int sweep(const char *base, const char *over)
{
    const usm_model *m = usm_model_variant(base, "imperfect_unilateral");
    usm_hybrid *h = m ? usm_hybrid_alloc(m) : NULL;
    usm_params p;
    usm_hybrid_result r, last;
    int have = 0;
    if (!h)
        return 1;
    usm_params_default(&p);
    const int ms = strcmp(over, "mode_split") == 0;
    printf("%-10s %5s %10s %14s %8s %4s %10s %-12s %10s\n", over, "iter", "ms", "rotor_speed",
           "open", "imp", "v_imp", "modes", "max|mult|");
    for (int k = 0; k <= 60; ++k) {
        const double v = ms ? 0.014 + 0.002 * k : 24.0 + k;
        if (ms)
            p.mode_split = v;
        else
            p.phase_error = v * 3.14159265358979323846 / 180;
        double t0 = now();
        int rc = have ? usm_hybrid_solve_from(h, &p, NULL, last.t0, last.x0, &r) : -1;
        if (rc != USM_OK)
            rc = usm_hybrid_solve(h, &p, NULL, &r);
        double t1 = now();
        if (rc != USM_OK) {
            printf("%-10g failed: %s\n", v, usm_hybrid_message(h));
            have = 0;
            continue;
        }
        printf("%-10g %5d %10.1f %14.8f %8.5f %4d %10.3e %-12s %10.6f\n", v, r.iterations,
               1e3 * (t1 - t0), r.rotor_speed_mean, r.separation_fraction, r.impacts_per_period,
               r.impact_velocity_max, r.mode_sequence, r.floquet.max_modulus);
        fflush(stdout);
        last = r;
        have = 1;
    }
    usm_hybrid_free(h);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc > 1)
        return sweep(argv[1], argc > 2 ? argv[2] : "phase_error");
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
