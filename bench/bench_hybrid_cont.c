/* An orbit with separation from a nearby start, and the sweep of them posed
 * to the continuation engine (study/periodic_sweep_hybrid.c): where the time
 * goes.  4-DOF imperfect_unilateral, mode split 1.4 to 1.9 % (the two-impact
 * orbit cococ, stable), steps of 5e-5:
 *   - one period map without and with the monodromy (the engine's corrector
 *     takes one of each an iteration: the Jacobian and its parameter column);
 *   - usm_hybrid_solve_from from the last orbit (the previous point of a
 *     branch: zero order), and from the secant of the last two (first order,
 *     as the engine's predictor is): CPU per orbit, Newton's maps with the
 *     monodromy;
 *   - usm_periodic_sweep over the same range at 11 and 101 points: CPU per
 *     grid point (the bilateral orbit at each point included).
 * Run: build/bench/bench_hybrid_cont */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "usm_periodic.h"
#include "usm_periodic_sweep.h"

/* CPU time of this process: the machine may be shared. */
static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

#define FROM 0.014
#define TO 0.019
#define STEP 5e-5

int main(void)
{
    const usm_model *m = usm_model_variant("4dof", "imperfect_unilateral");
    usm_hybrid *h = m ? usm_hybrid_alloc(m) : NULL;
    usm_params p;
    usm_hybrid_result r[3];
    if (!h)
        return 1;
    usm_params_default(&p);
    p.mode_split = FROM;
    if (usm_hybrid_solve(h, &p, NULL, &r[0]) != USM_OK) {
        fprintf(stderr, "%s\n", usm_hybrid_message(h));
        return 1;
    }
    double x1[USM_MAX_NX], B[USM_MAX_NX * USM_MAX_NX];
    const int reps = 20;
    double t0 = now();
    for (int k = 0; k < reps; ++k)
        usm_hybrid_period_map(h, r[0].t0, r[0].x0, x1, NULL);
    double t1 = now();
    for (int k = 0; k < reps; ++k)
        usm_hybrid_period_map(h, r[0].t0, r[0].x0, x1, B);
    double t2 = now();
    printf("%s mode split %.3g %%: one period map %.2f ms, with the monodromy %.2f ms\n", m->name,
           100 * FROM, 1e3 * (t1 - t0) / reps, 1e3 * (t2 - t1) / reps);
    /* zero and first order starts along the branch */
    for (int order = 0; order <= 1; ++order) {
        usm_hybrid_result prev = r[0], prev2 = r[0];
        int n = 0, its = 0, fails = 0;
        double cpu = 0, worst = 0;
        for (double v = FROM + STEP; v <= TO + 1e-12; v += STEP) {
            double x[USM_MAX_NX];
            for (int i = 0; i < prev.nx; ++i)
                x[i] = prev.x0[i] + (order && n > 0 ? prev.x0[i] - prev2.x0[i] : 0.0);
            p.mode_split = v;
            usm_hybrid_result out;
            const double a = now();
            const int rc = usm_hybrid_solve_from(h, &p, NULL, prev.t0, x, &out);
            const double dt = now() - a;
            if (rc != USM_OK) {
                ++fails;
                break;
            }
            cpu += dt;
            worst = fmax(worst, dt);
            its += out.iterations;
            ++n;
            prev2 = prev;
            prev = out;
        }
        printf("usm_hybrid_solve_from from the %s (%d orbits, steps %g): %.1f ms per orbit "
               "(worst %.1f), %.2f maps with the monodromy each%s\n",
               order ? "secant of the last two orbits" : "last orbit", n, STEP,
               1e3 * cpu / (n ? n : 1), 1e3 * worst, (double)its / (n ? n : 1) + 1.0,
               fails ? " (a failure ended it)" : "");
    }
    usm_hybrid_free(h);
    /* the sweep posed to the engine */
    const int grids[2] = {11, 101};
    for (int g = 0; g < 2; ++g) {
        usm_periodic_sweep *sw = usm_periodic_sweep_alloc(m);
        usm_periodic_sweep_options o;
        usm_periodic_sweep_options_default(&o);
        o.over = "mode_split";
        o.from = FROM;
        o.to = TO;
        o.points = grids[g];
        usm_params_default(&p);
        const double a = now();
        const int rc = usm_periodic_sweep_run(sw, &p, &o);
        const double dt = now() - a;
        int sep = 0;
        for (size_t i = 0; i < usm_periodic_sweep_count(sw); ++i)
            sep += usm_periodic_sweep_point_at(sw, i)->separating;
        printf("usm_periodic_sweep %d points (%d with separation)%s: %.2f s, %.1f ms per point\n",
               grids[g], sep, rc == USM_OK ? "" : " FAILED", dt, 1e3 * dt / grids[g]);
        usm_periodic_sweep_free(sw);
    }
    return 0;
}
