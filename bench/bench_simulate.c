/* bench_simulate: start-up of the motor from rest to the stationary solution.
 *
 * For each model at the paper's parameters and three tolerances: the
 * simulated settling time (period means of tilt and rotor speed within 1e-3
 * of usm_steady_solve, held for 100 periods), the wall time of the shortest
 * run that shows it (t_settle + 100 periods), the integrator's work and the
 * difference left at the end.  Then the rate of the final approach, measured
 * from the period means, next to the one the largest Floquet multiplier
 * predicts (tau = -T / ln |lambda|): the slowest mode of the start-up.
 *
 * Usage: bench_simulate [repetitions]   (default 3)
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include <gsl/gsl_errno.h>

#include "usm.h"
#include "usm_simulate.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Period means of the tilt error, sampled at the period ends. */
typedef struct decay {
    double theta_bar, speed_bar;
    double t[4096], e_theta[4096], e_speed[4096];
    int n;
} decay;

static int record(const usm_sim_sample *s, void *data)
{
    decay *d = data;
    if (s->have_avg && d->n < 4096) {
        d->t[d->n] = s->t;
        d->e_theta[d->n] = fabs(s->theta_avg - d->theta_bar) / d->theta_bar;
        d->e_speed[d->n] = fabs(s->rotor_speed_avg - d->speed_bar) / fabs(d->speed_bar);
        d->n++;
    }
    return 0;
}

/* e-folding time of e over the samples where it lies in [lo, hi]: least
 * squares on log e. */
static double efold(const decay *d, const double *e, double lo, double hi)
{
    double st = 0, sy = 0, stt = 0, sty = 0;
    int n = 0;
    for (int k = 0; k < d->n; ++k)
        if (e[k] >= lo && e[k] <= hi) {
            const double y = log(e[k]);
            st += d->t[k];
            sy += y;
            stt += d->t[k] * d->t[k];
            sty += d->t[k] * y;
            ++n;
        }
    if (n < 3)
        return NAN;
    const double slope = (n * sty - st * sy) / (n * stt - st * st);
    return -1.0 / slope;
}

int main(int argc, char **argv)
{
    const int reps = argc > 1 ? atoi(argv[1]) : 3;
    const double rtols[] = {1e-6, 1e-8, 1e-10};
    if (reps < 1) {
        fprintf(stderr, "bench_simulate: repetitions: must be a positive integer\n");
        return 2;
    }
    gsl_set_error_handler_off();
    printf("start-up from rest (tilt0 1e-6 rad), paper's parameters; settled = period means "
           "within 1e-3, held 100 periods\n");
    printf("%-6s %-7s %12s %9s %12s %9s %11s %11s\n", "model", "rtol", "t_settle", "periods",
           "wall", "steps", "theta end", "speed end");
    for (int k = 0; k < USM_NMODELS; ++k) {
        const usm_model *m = usm_models[k];
        usm_params p;
        usm_params_default(&p);
        usm_sim *s = usm_sim_alloc(m);
        if (!s) {
            fprintf(stderr, "bench_simulate: out of memory\n");
            return 1;
        }
        for (size_t r = 0; r < sizeof rtols / sizeof rtols[0]; ++r) {
            usm_sim_options o;
            usm_sim_summary sum;
            usm_sim_options_default(&o);
            o.rtol = rtols[r];
            o.duration = 5e-3;
            if (usm_sim_run(s, &p, &o, NULL, &sum) != USM_OK || !sum.settled) {
                fprintf(stderr, "bench_simulate: %s: no settling: %s\n", m->name,
                        usm_sim_message(s));
                return 1;
            }
            const double t_settle = sum.t_settle;
            o.duration = t_settle + o.settle_periods / p.f * 1.001;
            double t0 = now();
            for (int i = 0; i < reps; ++i)
                if (usm_sim_run(s, &p, &o, NULL, &sum) != USM_OK) {
                    fprintf(stderr, "bench_simulate: %s: %s\n", m->name, usm_sim_message(s));
                    return 1;
                }
            const double wall = (now() - t0) / reps;
            printf("%-6s %-7.0e %9.4f ms %9.0f %10.3f s %9ld %+11.2e %+11.2e%s\n", m->name,
                   rtols[r], t_settle * 1e3, t_settle * p.f, wall, sum.steps, sum.theta_rel_end,
                   sum.rotor_speed_rel_end, sum.settled ? "" : "  (not settled!)");
        }
        /* the final approach */
        {
            usm_sim_options o;
            usm_sim_summary sum;
            usm_floquet *fl = usm_floquet_alloc(m);
            usm_floquet_result fr;
            decay *d = calloc(1, sizeof *d);
            if (!fl || !d)
                return 1;
            usm_sim_options_default(&o);
            o.duration = 3e-3;
            o.rate = p.f; /* one sample per period end */
            o.rtol = 1e-10;
            usm_sim_callbacks cb = {record, NULL, d, NULL};
            usm_sim_run(s, &p, &o, NULL, &sum);
            d->theta_bar = sum.steady.theta;
            d->speed_bar = sum.steady.rotor_speed;
            usm_sim_run(s, &p, &o, &cb, &sum);
            usm_floquet_compute(fl, &p, &sum.steady, 0.0, NULL, &fr);
            printf("%-6s final approach: e-folding time %.4g ms (tilt), %.4g ms (rotor speed) "
                   "over relative errors 1e-2..1e-6; largest Floquet multiplier %.4f gives %.4g ms\n",
                   m->name, efold(d, d->e_theta, 1e-6, 1e-2) * 1e3,
                   efold(d, d->e_speed, 1e-6, 1e-2) * 1e3, fr.max_modulus,
                   -1.0 / (p.f * log(fr.max_modulus)) * 1e3);
            usm_floquet_free(fl);
            free(d);
        }
        usm_sim_free(s);
    }
    return 0;
}
