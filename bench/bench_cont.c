/* bench_cont: the cost per point of following the 3-DOF load branch, T = 0
 * to theta = 0 (the tilt vanishes), at the paper's other parameters.
 *
 *  1. The continuation engine alone (usm_cont.h) on the stationary problem
 *     (the generated residual and Jacobians): steps of at most 1/1001 of the
 *     range in the scaled arclength, about 1,002 points as a continuation
 *     program would print them, up to the zero of theta (a stopping test).
 *  2. The same, landing on 1,002 grid values (the arc's point, then Newton
 *     with T held).
 *  4. (printed last) 1 with the chord corrector (options.chord: the
 *     Jacobian factored once a correction, the tangent afresh).
 *  3. usm_sweep_run over the same 1,002 grid values without multipliers or
 *     operating points (its full search at every grid value included: the
 *     root count and the polish of each row, docs/sweep.md).
 * The best of `repetitions` runs; CPU time of the process (the machine may
 * be shared).
 *
 * Usage: bench_cont [repetitions]   (default 5)
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <gsl/gsl_errno.h>

#include "usm_cont.h"
#include "usm_sweep.h"

#define GRID 1002

static double cpu_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

typedef struct branch {
    const usm_model *m;
    usm_params p;
    int col; /* T's column of steady_jacobian_params */
} branch;

static int residual(const double *x, double *F, double *Jx, void *ctx)
{
    branch *b = ctx;
    const int nu = b->m->nu, N = nu + 1;
    double J[USM_MAX_NU * USM_MAX_NU], Jp[USM_MAX_NU * USM_NPARAMS];
    b->p.T = x[nu];
    b->m->steady_residual(x, &b->p, F);
    if (!Jx)
        return 0;
    b->m->steady_jacobian(x, &b->p, J);
    b->m->steady_jacobian_params(x, &b->p, Jp);
    for (int i = 0; i < nu; ++i) {
        for (int j = 0; j < nu; ++j)
            Jx[i * N + j] = J[i * nu + j];
        Jx[i * N + nu] = Jp[i * USM_NPARAMS + b->col];
    }
    return 0;
}

static double theta_test(const double *x, const double *dx, void *ctx)
{
    (void)dx;
    (void)ctx;
    return x[0];
}

/* One run of the engine from u0 at T = 0 to theta = 0; with land, also the
 * grid values T_k = k T_end / (GRID - 1) below T_end.  Steps (and landings
 * into *landed), the end's T into *t_end; -1 on failure. */
static int follow(branch *b, const double *u0, double t_scale, int land, int chord, double *t_end,
                  int *landed)
{
    const int nu = b->m->nu;
    double x0[USM_MAX_NU + 1], scale[USM_MAX_NU + 1];
    usm_cont *c = usm_cont_alloc(nu);
    usm_cont_options o;
    int steps = 0, next = 1;
    if (!c)
        return -1;
    memcpy(x0, u0, sizeof(double) * (size_t)nu);
    x0[nu] = 0.0;
    scale[0] = fabs(u0[0]);
    for (int i = 1; i < nu; ++i)
        scale[i] = fmax(1.0, fabs(u0[i]));
    scale[nu] = t_scale;
    usm_cont_options_default(&o);
    o.h_max = 1.0 / (GRID - 1);
    o.h0 = o.h_max;
    o.chord = chord;
    usm_cont_set_problem(c, residual, b);
    usm_cont_set_options(c, &o);
    usm_cont_set_scale(c, scale);
    usm_cont_add_test(c, theta_test, NULL, USM_CONT_TEST_STOP);
    *landed = 0;
    if (usm_cont_start(c, x0, 1) != 0) {
        usm_cont_free(c);
        return -1;
    }
    for (;;) {
        const int rc = usm_cont_step(c);
        if (rc != USM_CONT_STEP && rc != USM_CONT_END)
            break;
        ++steps;
        if (land) {
            const double *xa;
            const double s_end = usm_cont_step_arc(c, &xa);
            const double ta = xa[nu], tb = usm_cont_point(c)[nu];
            for (; next < GRID; ++next) {
                const double g = next * (*t_end) / (GRID - 1);
                double x[USM_MAX_NU + 1];
                if (g > tb)
                    break;
                if (usm_cont_arc_point(c, s_end * (g - ta) / (tb - ta), x, NULL) == 0 &&
                    usm_cont_correct_fixed(c, x, nu, g) >= 0)
                    ++*landed;
            }
        }
        if (rc == USM_CONT_END) {
            if (!land)
                *t_end = usm_cont_point(c)[nu];
            usm_cont_free(c);
            return steps;
        }
    }
    usm_cont_free(c);
    return -1;
}

int main(int argc, char **argv)
{
    const int reps = argc > 1 ? atoi(argv[1]) : 5;
    if (reps < 1) {
        fprintf(stderr, "bench_cont: usage: bench_cont [repetitions >= 1]\n");
        return 2;
    }
    gsl_set_error_handler_off();
    branch b;
    b.m = usm_model_find("3dof");
    usm_params_default(&b.p);
    b.p.T = 0.0;
    b.col = USM_P_T;
    usm_steady *s = usm_steady_alloc(b.m);
    if (!s || usm_steady_solve(s, &b.p, NULL) != USM_OK) {
        fprintf(stderr, "bench_cont: no stationary solution at T = 0\n");
        return 1;
    }
    double u0[USM_MAX_NU];
    memcpy(u0, usm_steady_root(s, 0)->u, sizeof u0);
    usm_steady_free(s);

    /* the end of the branch, which also sets the grid */
    double t_end = 0.01;
    int landed = 0;
    if (follow(&b, u0, 0.01, 0, 0, &t_end, &landed) < 0) {
        fprintf(stderr, "bench_cont: the branch was lost\n");
        return 1;
    }
    printf("3-DOF load branch T = 0 .. %.10g N m (theta = 0), best of %d runs, CPU time\n",
           t_end, reps);
    printf("%-48s %8s %12s %12s\n", "task", "points", "cpu [ms]", "cpu/point");

    double best[4] = {INFINITY, INFINITY, INFINITY, INFINITY};
    int npts[4] = {0, 0, 0, 0};
    /* one sweep for every run, as a program sweeping again reuses it: the
     * first run pays the page faults of its 3 MB of points */
    usm_sweep *sw = usm_sweep_alloc(b.m);
    for (int r = 0; r < reps; ++r) {
        double c0 = cpu_s(), te = t_end;
        npts[0] = follow(&b, u0, t_end, 0, 0, &te, &landed) + 1;
        best[0] = fmin(best[0], cpu_s() - c0);
        c0 = cpu_s();
        te = t_end;
        follow(&b, u0, t_end, 1, 0, &te, &landed);
        npts[1] = landed + 1;
        best[1] = fmin(best[1], cpu_s() - c0);
        c0 = cpu_s();
        te = t_end;
        npts[3] = follow(&b, u0, t_end, 0, 1, &te, &landed) + 1;
        best[3] = fmin(best[3], cpu_s() - c0);

        usm_sweep_options o;
        usm_sweep_options_default(&o);
        o.over = "T";
        o.from = 0.0;
        o.to = t_end * (1 - 1e-9);
        o.points = GRID;
        o.floquet = 0;
        o.operating_point = 0;
        o.threads = 1;
        c0 = cpu_s();
        if (usm_sweep_run(sw, &b.p, &o) != USM_OK) {
            fprintf(stderr, "bench_cont: %s\n", usm_sweep_message(sw));
            return 1;
        }
        best[2] = fmin(best[2], cpu_s() - c0);
        npts[2] = (int)usm_sweep_count(sw);
    }
    usm_sweep_free(sw);
    const char *task[4] = {"engine: continuation points (steps <= 1/1001)",
                           "engine: landed on 1002 grid values",
                           "usm_sweep_run, 1002 points, no Floquet/op",
                           "engine: continuation points, chord corrector"};
    for (int k = 0; k < 4; ++k)
        printf("%-48s %8d %12.3f %9.2f us\n", task[k], npts[k], best[k] * 1e3,
               best[k] / npts[k] * 1e6);
    return 0;
}
