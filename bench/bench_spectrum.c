/* bench_spectrum: the cost of `usm simulate --spectrum` beside the
 * simulation it analyses.  For windows of 185, 370, 3700 and 37000
 * excitation periods at 10 samples per period (the default rate): the
 * recorder's usm_sim_spectrum_compute (grid, three FFTs, lines, the
 * synchronous average), best of 5 runs, CPU time of the process; then one
 * 10 ms simulation from rest of the 4-DOF imperfect motor at mode split
 * 8.8 % (the report's squeal run) with and without recording its samples.
 *
 * Usage: bench_spectrum */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include <gsl/gsl_errno.h>

#include "usm_simulate.h"
#include "usm_spectrum.h"

#define PI 3.14159265358979323846264338327950

static double cpu(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int record(const usm_sim_sample *s, void *data) { return usm_sim_spectrum_add(data, s); }

int main(void)
{
    const double f = 37000.0;
    static const long periods[] = {185, 370, 3700, 37000};
    char msg[USM_MSG_LEN];
    gsl_set_error_handler_off();
    printf("usm_sim_spectrum_compute, 10 samples per period, best of 5 (CPU):\n");
    for (size_t q = 0; q < sizeof periods / sizeof periods[0]; ++q) {
        usm_sim_spectrum *s = usm_sim_spectrum_alloc();
        usm_sim_sample smp;
        double x[1] = {0};
        memset(&smp, 0, sizeof smp);
        smp.nx = 1;
        smp.x = smp.xdot = x;
        const long n = 2 * periods[q] * 10; /* the window is the second half */
        for (long j = 0; j <= n; ++j) {
            smp.t = (double)j / (10 * f);
            smp.theta = 8e-5 + 4e-6 * sin(2 * PI * 2 * f * smp.t) + 1e-7 * sin(2 * PI * 53351.3 * smp.t);
            smp.rotor_speed = -13 + 0.2 * sin(2 * PI * 2 * f * smp.t);
            smp.out[USM_OUT_F_N] = 0.6 + 2.6 * sin(2 * PI * 2 * f * smp.t);
            usm_sim_spectrum_add(s, &smp);
        }
        usm_sim_spectrum_options o;
        usm_sim_spectrum_result r;
        usm_sim_spectrum_options_default(&o);
        o.f = f;
        double best = INFINITY;
        for (int rep = 0; rep < 5; ++rep) {
            const double t = cpu();
            if (usm_sim_spectrum_compute(s, &o, &r, msg) != USM_OK) {
                printf("failed: %s\n", msg);
                return 1;
            }
            best = fmin(best, cpu() - t);
        }
        printf("  %6ld periods (%7zu samples): %9.3f ms\n", r.periods, r.samples, 1e3 * best);
        usm_sim_spectrum_free(s);
    }
    /* the simulation it analyses */
    const usm_model *m = usm_model_variant("4dof", "imperfect");
    if (!m) {
        printf("4dof_imperfect not built\n");
        return 0;
    }
    usm_params p;
    usm_params_default(&p);
    p.mode_split = 0.088;
    usm_sim *sim = usm_sim_alloc(m);
    usm_sim_spectrum *s = usm_sim_spectrum_alloc();
    usm_sim_options so;
    usm_sim_summary sum;
    usm_sim_options_default(&so);
    so.duration = 370 / f;
    so.rate = 10 * f;
    for (int with = 0; with < 2; ++with) {
        usm_sim_callbacks cb = {with ? record : NULL, NULL, s, NULL};
        usm_sim_spectrum_reset(s);
        double t = cpu();
        usm_sim_run(sim, &p, &so, &cb, &sum);
        const double run = cpu() - t;
        double spec = 0;
        if (with) {
            usm_sim_spectrum_options o;
            usm_sim_spectrum_result r;
            usm_sim_spectrum_options_default(&o);
            o.f = f;
            t = cpu();
            usm_sim_spectrum_compute(s, &o, &r, msg);
            spec = cpu() - t;
        }
        printf("4dof_imperfect, mode split 8.8 %%, 10 ms from rest: simulation %.3f s%s",
               run, with ? " (recording the samples)" : "\n");
        if (with)
            printf(", spectrum %.3f ms\n", 1e3 * spec);
    }
    usm_sim_free(sim);
    usm_sim_spectrum_free(s);
    return 0;
}
