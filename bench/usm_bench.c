/* usm_bench: speed of the stationary solver and of the Floquet multipliers.
 *
 * For each model: the mean CPU time of one stationary solution (full search
 * from the parameters alone) at the paper's point, the best-batch times of
 * the full search and of the warm start (usm_steady_solve_warm) at a point
 * 0.1 % away in f from the paper's root, and for each Floquet
 * method the mean time per point and the number of correct digits, measured
 * against CVODES on the variational equations at rtol 1e-12 (atol 1e-16), at
 * several points (the paper's, other f and T, a later start time t0).
 * "digits" is -log10 of the largest distance between corresponding
 * multipliers, the worst over the points.  The reference itself is good to
 * about 11 digits: the line "variational rtol 1e-13" shows how far CVODES at
 * 1e-13 is from it.  The targets set for the library are printed beside the default
 * method's figures.  "floor" is one matrix exponential of T S G(t0) S^{-1}
 * (the scaling and squaring every method uses) and the multipliers'
 * eigenproblem of the result, what a constant coefficient matrix costs, at the
 * paper's point; "auto / floor" is the default method's time at the paper's
 * point over it (the goal for the 3-DOF paper model: at most 3).
 *
 * Usage: usm_bench [repetitions]   (default 200; each Floquet time is the best
 * of 5 batches of `repetitions` calls, repetitions / 10 for the slow methods,
 * because the machine may be shared)
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <gsl/gsl_errno.h>

#include "solve/floquet_floor.h"
#include "usm.h"

/* CPU time of this (single-threaded) process: on an idle core the wall time,
 * and on a machine shared with other work (the 2 cores usually are) the
 * work done, not the waiting. */
static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Largest distance from a multiplier of a to the nearest of b. */
static double multiplier_error(const usm_floquet_result *a, const usm_floquet_result *b)
{
    double worst = 0;
    for (int i = 0; i < a->n; ++i) {
        double best = INFINITY;
        for (int j = 0; j < b->n; ++j)
            best = fmin(best, hypot(a->re[i] - b->re[j], a->im[i] - b->im[j]));
        worst = fmax(worst, best);
    }
    return worst;
}

typedef struct {
    double f, T, t0;
} point;

static const point points[] = {
    {37000, 6.46e-5, 0}, {30000, 0, 0}, {37000, 6.46e-5, 0.01}, {33000, 3e-4, 2e-3}};
#define NPOINTS (sizeof points / sizeof points[0])

typedef struct {
    const char *name;
    usm_floquet_method method;
    double rtol, atol;
    int slow; /* CVODES: fewer repetitions */
} method_case;

static const method_case methods[] = {
    {"auto (default)", USM_FLOQUET_AUTO, 1e-8, 1e-12, 0},
    {"magnus", USM_FLOQUET_MAGNUS, 1e-8, 1e-12, 0},
    {"exponential", USM_FLOQUET_EXPONENTIAL, 1e-8, 1e-12, 1},
    {"variational rtol 1e-8", USM_FLOQUET_VARIATIONAL, 1e-8, 1e-12, 1},
    {"variational rtol 1e-13", USM_FLOQUET_VARIATIONAL, 1e-13, 1e-17, 1},
};
#define NMETHODS (sizeof methods / sizeof methods[0])

int main(int argc, char **argv)
{
    const int reps = argc > 1 ? atoi(argv[1]) : 200;
    if (reps < 1) {
        fprintf(stderr, "usm_bench: repetitions: must be a positive integer\n");
        return 2;
    }
    gsl_set_error_handler_off();
    printf("Floquet: time per point (mean over %zu points: f, T, t0 = paper; 30 kHz, 0; "
           "paper, 10 ms; 33 kHz, 0.3 N mm, 2 ms),\n"
           "digits = agreement of the multipliers with CVODES at rtol 1e-12 (worst point)\n\n",
           NPOINTS);
    printf("%-22s %-26s %12s %8s  %s\n", "model", "task", "time", "digits", "target");
    for (int k = 0; k < USM_NMODELS; ++k) {
        const usm_model *m = usm_models[k];
        usm_steady *s = usm_steady_alloc(m);
        usm_floquet *f = usm_floquet_alloc(m);
        usm_params p[NPOINTS];
        usm_steady_solution sol[NPOINTS];
        usm_floquet_result ref[NPOINTS], res;
        int ok[NPOINTS], nok = 0;
        if (!s || !f) {
            fprintf(stderr, "usm_bench: out of memory\n");
            return 1;
        }
        usm_params_default(&p[0]);
        double t = now();
        for (int r = 0; r < reps; ++r)
            if (usm_steady_solve(s, &p[0], NULL) != USM_OK) {
                fprintf(stderr, "usm_bench: %s: %s\n", m->name, usm_steady_message(s));
                return 1;
            }
        printf("%-22s %-26s %9.1f us\n", m->name, "stationary solution", (now() - t) / reps * 1e6);
        {
            /* the warm start from the primary root at a point 0.1 % away in f
             * (a sweep's or Monte Carlo study's neighbour), best of 5 batches,
             * beside the full search timed the same way */
            usm_params q = p[0];
            q.f *= 1.001;
            const usm_steady_solution guess = *usm_steady_root(s, 0);
            double best[2] = {INFINITY, INFINITY};
            for (int batch = 0; batch < 5; ++batch)
                for (int w = 0; w < 2; ++w) {
                    t = now();
                    for (int r = 0; r < reps; ++r)
                        if ((w ? usm_steady_solve_warm(s, &q, NULL, &guess)
                               : usm_steady_solve(s, &q, NULL)) != USM_OK) {
                            fprintf(stderr, "usm_bench: %s: %s\n", m->name,
                                    usm_steady_message(s));
                            return 1;
                        }
                    best[w] = fmin(best[w], (now() - t) / reps);
                }
            printf("%-22s %-26s %9.1f us\n", m->name, "  full search (best batch)", best[0] * 1e6);
            printf("%-22s %-26s %9.1f us\n", m->name, "  warm start (best batch)", best[1] * 1e6);
        }
        for (size_t i = 0; i < NPOINTS; ++i) {
            usm_floquet_options ro;
            usm_params_default(&p[i]);
            p[i].f = points[i].f;
            p[i].T = points[i].T;
            usm_floquet_options_default(&ro);
            ro.method = USM_FLOQUET_VARIATIONAL;
            ro.rtol = 1e-12;
            ro.atol = 1e-16;
            ok[i] = usm_steady_solve(s, &p[i], NULL) == USM_OK;
            if (ok[i]) {
                sol[i] = *usm_steady_root(s, 0);
                ok[i] = usm_floquet_compute(f, &p[i], &sol[i], points[i].t0, &ro, &ref[i]) ==
                        USM_OK;
            }
            nok += ok[i];
        }
        {
            /* the floor, and the default method at the paper's point, timed
             * alike (best of 5 batches) */
            double A[USM_MAX_NX * USM_MAX_NX], best[2] = {INFINITY, INFINITY};
            if (ok[0] && usm_floquet_floor_setup(f, &p[0], &sol[0], 0.0, A) == 0) {
                for (int batch = 0; batch < 5; ++batch)
                    for (int w = 0; w < 2; ++w) {
                        t = now();
                        for (int r = 0; r < reps; ++r)
                            if ((w ? usm_floquet_compute(f, &p[0], &sol[0], 0.0, NULL, &res)
                                   : usm_floquet_floor(f, A)) != 0) {
                                fprintf(stderr, "usm_bench: %s: floor failed\n", m->name);
                                return 1;
                            }
                        best[w] = fmin(best[w], (now() - t) / reps);
                    }
                printf("%-22s %-26s %9.1f us\n", m->name, "floor: expm + eigenvalues",
                       best[0] * 1e6);
                printf("%-22s %-26s %9.1f us %8s  auto / floor = %.2f\n", m->name,
                       "auto at the paper's point", best[1] * 1e6, "", best[1] / best[0]);
            }
        }
        for (size_t j = 0; j < NMETHODS; ++j) {
            usm_floquet_options opt;
            usm_floquet_options_default(&opt);
            opt.method = methods[j].method;
            opt.rtol = methods[j].rtol;
            opt.atol = methods[j].atol;
            const int n = methods[j].slow ? (reps / 10 > 0 ? reps / 10 : 1) : reps;
            double err = 0, dt = 0;
            for (size_t i = 0; i < NPOINTS; ++i) {
                if (!ok[i])
                    continue;
                /* the best of 5 batches: the machine may be shared */
                double best = INFINITY;
                for (int batch = 0; batch < 5; ++batch) {
                    t = now();
                    for (int r = 0; r < n; ++r)
                        if (usm_floquet_compute(f, &p[i], &sol[i], points[i].t0, &opt, &res) !=
                            USM_OK) {
                            fprintf(stderr, "usm_bench: %s: %s\n", m->name,
                                    usm_floquet_message(f));
                            return 1;
                        }
                    best = fmin(best, (now() - t) / n);
                }
                dt += best;
                err = fmax(err, multiplier_error(&res, &ref[i]));
            }
            dt /= nok;
            char target[64] = "";
            if (methods[j].method == USM_FLOQUET_AUTO)
                snprintf(target, sizeof target, "<= %s us, 10 digits",
                         m->t0_independent ? "20" : "100");
            if (dt >= 1e-3)
                printf("%-22s %-26s %9.3f ms %8.1f  %s\n", m->name, methods[j].name, dt * 1e3,
                       err > 0 ? -log10(err) : 16.0, target);
            else
                printf("%-22s %-26s %9.1f us %8.1f  %s\n", m->name, methods[j].name, dt * 1e6,
                       err > 0 ? -log10(err) : 16.0, target);
        }
        usm_floquet_free(f);
        usm_steady_free(s);
    }
    return 0;
}
