/* bench_robust: the measures of robust design (yield, datasheet quantities, robust optimum, Pareto front).
 *  - a robust 2-parameter optimization (f, F0 of the paper's 3-DOF motor:
 *    maximize efficiency, speed >= 6 1/s, yield >= 0.99 under 2 % c_r and 1 %
 *    f scatter) with 10^4 common-random-number samples per design and the
 *    final check on 10^5 fresh samples (goal: under 60 s on 2 cores);
 *  - a 30-point Pareto front speed vs efficiency over (f, F0) (goal: under 30 s);
 *  - the yield the robust design gains over the nominal optimum, and the
 *    efficiency and speed it costs.
 * Prints wall and CPU time (the CPU time shows the work when other processes
 * share the cores).
 *
 * Usage: bench_robust [samples [verify [threads]]]   (default 10000 100000 2)
 */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include <gsl/gsl_errno.h>

#include "usm_robust.h"

static double clock_s(clockid_t id)
{
    struct timespec ts;
    clock_gettime(id, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int main(int argc, char **argv)
{
    const usm_model *m = usm_model_find("3dof");
    char msg[USM_MSG_LEN];
    usm_params p;
    usm_robust_problem rp;
    usm_robust_result *res = malloc(sizeof *res);
    gsl_set_error_handler_off();
    usm_params_default(&p);
    usm_robust_problem_init(&rp);
    rp.samples = argc > 1 ? strtoull(argv[1], NULL, 10) : 10000;
    rp.verify_samples = argc > 2 ? strtoull(argv[2], NULL, 10) : 100000;
    rp.threads = argc > 3 ? atoi(argv[3]) : 2;
    usm_opt_problem_add_vary(&rp.nominal, "f", 34000, 42000, msg);
    usm_opt_problem_add_vary(&rp.nominal, "F0", 0.2, 1.0, msg);
    usm_opt_problem_add_constraint(&rp.nominal, "speed", 0, 6.0, msg);
    rp.objective = USM_SENS_EFFICIENCY;
    rp.yield_min = 0.99;
    usm_tolerance_vary_parse("c_r=normal:2%", &rp.scatter[0], msg);
    usm_tolerance_vary_parse("f=normal:1%", &rp.scatter[1], msg);
    rp.nscatter = 2;
    double w = clock_s(CLOCK_MONOTONIC), c = clock_s(CLOCK_PROCESS_CPUTIME_ID);
    int rc = usm_robust_run(m, &p, &rp, res, msg);
    w = clock_s(CLOCK_MONOTONIC) - w;
    c = clock_s(CLOCK_PROCESS_CPUTIME_ID) - c;
    if (rc != USM_OK || !res->nominal.feasible) {
        fprintf(stderr, "bench_robust: %s\n", msg);
        return 1;
    }
    const usm_robust_design *r = &res->robust, *n = &res->nominal;
    printf("robust optimization, %llu CRN samples per design, %llu fresh, %d threads: "
           "%.2f s wall, %.2f s CPU, %d designs\n", (unsigned long long)rp.samples,
           (unsigned long long)rp.verify_samples, rp.threads, w, c, res->evaluations);
    printf("  nominal optimum: f %.6g Hz, F0 %.4g N, efficiency %.4f %%, speed %.4g 1/s, "
           "yield %.4f [%.4f, %.4f]\n", n->params.f, n->params.F0, 100 * n->efficiency, n->speed,
           n->yield, n->yield_lo, n->yield_hi);
    printf("  robust optimum:  f %.6g Hz, F0 %.4g N, efficiency %.4f %%, speed %.4g 1/s, "
           "yield %.4f [%.4f, %.4f] (CRN %.4f), verified %s\n", r->params.f, r->params.F0,
           100 * r->efficiency, r->speed, r->yield, r->yield_lo, r->yield_hi, r->crn_yield,
           res->verified ? "yes" : "no");
    printf("  yield gained %+.2f points; efficiency cost %.1f %% of the nominal's; "
           "speed %+.3g 1/s\n",
           100 * (r->yield - n->yield), 100 * (1 - r->efficiency / n->efficiency),
           r->speed - n->speed);
    usm_pareto_result pr;
    const int obj[2] = {USM_OPT_SPEED, USM_SENS_EFFICIENCY}, mn[2] = {0, 0};
    w = clock_s(CLOCK_MONOTONIC);
    c = clock_s(CLOCK_PROCESS_CPUTIME_ID);
    usm_opt_problem pb; /* the report's front: no speed spec */
    usm_opt_problem_init(&pb);
    usm_opt_problem_add_vary(&pb, "f", 34000, 42000, msg);
    usm_opt_problem_add_vary(&pb, "F0", 0.2, 1.0, msg);
    rc = usm_pareto_run(m, &p, &pb, obj, mn, 30, &pr, msg);
    w = clock_s(CLOCK_MONOTONIC) - w;
    c = clock_s(CLOCK_PROCESS_CPUTIME_ID) - c;
    if (rc != USM_OK) {
        fprintf(stderr, "bench_robust: pareto: %s\n", msg);
        return 1;
    }
    printf("Pareto front speed vs efficiency over (f, F0), 30 levels: %d points, %d optimizations, "
           "%.2f s wall, %.2f s CPU\n", pr.npoints, pr.computed, w, c);
    usm_pareto_result_free(&pr);
    free(res);
    return 0;
}
