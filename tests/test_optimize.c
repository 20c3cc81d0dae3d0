/* test_optimize: the optimizer (usm_optimize.h, and `usm optimize` on top of
 * it) against a dense grid search (issue 13, part 3).
 *
 * Problem (3dof, the paper's other parameters): maximize efficiency over the
 * load T in [1e-5, 1e-3] N m and the preload F0 in [0.2, 0.6] N, subject to the
 * defaults: a stationary solution exists, max_modulus <= 0.99, stick
 * admissible (F_t <= mu0 F_n).  The optimum lies on the stick boundary.
 * Truth: a 201 x 201 grid of stationary solutions (usm_steady_solve); the
 * best grid point that is stick-admissible and (usm_floquet_compute, the
 * default variational method) stable with the margin.
 * Checks: the optimizer's point is within one grid spacing of the grid's best
 * in each parameter; its efficiency is at least the grid's best (minus 1e-9
 * relative: the grid can only be worse); it is feasible when re-solved
 * independently (stick to 1e-9 relative, max_modulus by the variational method
 * <= 0.99 + 1e-6); its KKT residual is below 1e-6 (the gradients the
 * optimizer used are consistent with its optimum; they are the sensitivities
 * that tests/test_sensitivity.c checks against finite differences).  The
 * library also: an infeasible problem is USM_ENOSOLUTION naming the
 * constraint; a box with an inadmissible corner, an unknown or repeated
 * parameter, LO >= HI, an unknown output are USM_EINPUT.
 *
 * usage: test_optimize PATH/TO/usm
 */
#define _POSIX_C_SOURCE 200809L /* popen */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>
#include <jansson.h>

#include "check.h"
#include "usm.h"
#include "usm_optimize.h"

#define NGRID 201
#define T_LO 1e-5
#define T_HI 1e-3
#define F_LO 0.2
#define F_HI 0.6
#define MARGIN 0.01

typedef struct cand {
    double eff, T, F0;
} cand;

static int by_eff_desc(const void *a, const void *b)
{
    const cand *x = a, *y = b;
    return (x->eff < y->eff) - (x->eff > y->eff);
}

/* The optimum (value at T, F0, with its KKT residual) against the grid's best
 * candidate g: within one grid spacing in each parameter, at least as good,
 * feasible when re-solved independently, KKT residual below 1e-6. */
static void check_optimum(usm_steady *st, usm_floquet *fl, cand g, const char *who, double value,
                          double T, double F0, double kkt)
{
    const double dT = (T_HI - T_LO) / (NGRID - 1), dF = (F_HI - F_LO) / (NGRID - 1);
    usm_params p;
    usm_floquet_result r;
    printf("%s: efficiency %.10g at T = %.8g, F0 = %.8g, KKT residual %.3g\n", who, value, T, F0,
           kkt);
    CHECK(fabs(T - g.T) <= dT, "%s: T %.8g not within %.3g of the grid's %.8g", who, T, dT, g.T);
    CHECK(fabs(F0 - g.F0) <= dF, "%s: F0 %.8g not within %.3g of the grid's %.8g", who, F0, dF,
          g.F0);
    /* the optimum must be at least the grid's best (measured 9e-4 above it);
     * 1e-9 forgives the rounding of a re-solve at the grid's point */
    CHECK(value >= g.eff * (1 - 1e-9), "%s: efficiency %.12g below the grid's %.12g", who, value,
          g.eff);
    /* measured 0 (the optimum is on the constraint F0 = 0.6, its gradient
     * there points out of the box) */
    CHECK(kkt <= 1e-6, "%s: KKT residual %g", who, kkt);
    /* feasible, re-solved independently */
    usm_params_default(&p);
    p.T = T;
    p.F0 = F0;
    CHECK(usm_steady_solve(st, &p, NULL) == USM_OK, "%s: no solution at the optimum", who);
    const usm_steady_solution *s = usm_steady_root(st, 0);
    printf("%s re-solved: F_t / (mu0 F_n) - 1 = %.2g, efficiency differs by %.2g (relative)\n",
           who, s->F_t / (p.mu0 * s->F_n) - 1, fabs(s->efficiency - value) / value);
    /* the optimizer holds its constraints to 1e-10 of F_n (runtime/study/
     * optimize.c), 3.3e-10 in F_t / (mu0 F_n) at mu0 = 0.3; measured (printed
     * above) 1.5e-10 above the limit: 1e-9.  The efficiency re-solved: 0 */
    CHECK(s->F_t <= p.mu0 * s->F_n * (1 + 1e-9), "%s: stick violated: F_t %.12g > mu0 F_n %.12g",
          who, s->F_t, p.mu0 * s->F_n);
    CHECK(fabs(s->efficiency - value) <= 1e-9 * value, "%s: efficiency re-solved %.12g", who,
          s->efficiency);
    CHECK(usm_floquet_compute(fl, &p, s, 0.0, NULL, &r) == USM_OK &&
              r.max_modulus <= 1 - MARGIN + 1e-6,
          "%s: max_modulus %.10g above 1 - margin", who, r.max_modulus);
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: test_optimize PATH/TO/usm\n");
        return 2;
    }
    gsl_set_error_handler_off();
    const usm_model *m = usm_model_find("3dof");
    usm_steady *st = usm_steady_alloc(m);
    usm_floquet *fl = usm_floquet_alloc(m);
    cand *c = malloc(sizeof *c * NGRID * NGRID);
    int nc = 0;
    usm_params p;
    usm_params_default(&p);
    for (int i = 0; i < NGRID; ++i)
        for (int j = 0; j < NGRID; ++j) {
            p.T = T_LO + (T_HI - T_LO) * i / (NGRID - 1);
            p.F0 = F_LO + (F_HI - F_LO) * j / (NGRID - 1);
            if (usm_steady_solve(st, &p, NULL) != USM_OK)
                continue;
            const usm_steady_solution *s = usm_steady_root(st, 0);
            if (s->stick_admissible && isfinite(s->efficiency))
                c[nc++] = (cand){s->efficiency, p.T, p.F0};
        }
    qsort(c, (size_t)nc, sizeof c[0], by_eff_desc);
    int best = -1;
    for (int k = 0; k < nc && best < 0; ++k) {
        usm_floquet_result r;
        p.T = c[k].T;
        p.F0 = c[k].F0;
        if (usm_steady_solve(st, &p, NULL) == USM_OK &&
            usm_floquet_compute(fl, &p, usm_steady_root(st, 0), 0.0, NULL, &r) == USM_OK &&
            r.max_modulus <= 1 - MARGIN)
            best = k;
    }
    CHECK(best >= 0, "no feasible grid point");
    if (best < 0)
        return 1;
    printf("grid best: efficiency %.10g at T = %.6g, F0 = %.6g\n", c[best].eff, c[best].T,
           c[best].F0);

    /* the library (usm_optimize.h) */
    {
        usm_opt_problem pb;
        usm_opt_result *res = malloc(sizeof *res);
        usm_optimize *opt = usm_optimize_alloc(m);
        char msg[USM_MSG_LEN];
        usm_params_default(&p);
        usm_opt_problem_init(&pb);
        pb.objective = USM_SENS_EFFICIENCY;
        CHECK(usm_opt_problem_add_vary(&pb, "T", T_LO, T_HI, msg) == USM_OK &&
                  usm_opt_problem_add_vary(&pb, "F0", F_LO, F_HI, msg) == USM_OK,
              "add_vary: %s", msg);
        int rc = res && opt ? usm_optimize_run(opt, &p, &pb, res) : USM_EFAILED;
        CHECK(rc == USM_OK, "usm_optimize_run: %d %s", rc, opt ? usm_optimize_message(opt) : "");
        if (rc == USM_OK)
            check_optimum(st, fl, c[best], "library", res->value, res->params.T, res->params.F0,
                          res->kkt_residual);
        /* the optimum's solution is the one re-solved at its parameters */
        CHECK(rc != USM_OK || res->sol.efficiency == res->value, "library: value %.17g is not "
              "the solution's efficiency %.17g", res->value, res->sol.efficiency);
        /* infeasible: no design reaches 1 W out of this box; the message names it */
        usm_opt_problem_init(&pb);
        pb.objective = USM_SENS_EFFICIENCY;
        pb.starts = 2;
        usm_opt_problem_add_vary(&pb, "F0", 0.2, 0.8, msg);
        usm_opt_problem_add_constraint(&pb, "power_out", 0, 1.0, msg);
        rc = opt ? usm_optimize_run(opt, &p, &pb, res) : USM_EFAILED;
        CHECK(rc == USM_ENOSOLUTION && strstr(usm_optimize_message(opt), "power_out >= 1"),
              "infeasible: %d \"%s\"", rc, opt ? usm_optimize_message(opt) : "");
        /* a box with an inadmissible corner is refused before anything is solved */
        usm_opt_problem_init(&pb);
        pb.objective = USM_SENS_EFFICIENCY;
        usm_opt_problem_add_vary(&pb, "F0", -1.0, 0.5, msg);
        rc = opt ? usm_optimize_run(opt, &p, &pb, res) : USM_EFAILED;
        CHECK(rc == USM_EINPUT && strncmp(usm_optimize_message(opt), "vary: ", 6) == 0,
              "bad box: %d \"%s\"", rc, opt ? usm_optimize_message(opt) : "");
        CHECK(usm_opt_problem_add_vary(&pb, "F0", 0.3, 0.4, msg) == USM_EINPUT &&
                  usm_opt_problem_add_vary(&pb, "Q", 0.3, 0.4, msg) == USM_EINPUT &&
                  usm_opt_problem_add_vary(&pb, "T", 0.4, 0.3, msg) == USM_EINPUT &&
                  usm_opt_problem_add_constraint(&pb, "nothing", 1, 0, msg) == USM_EINPUT,
              "add_vary / add_constraint accepted a bad entry");
        usm_optimize_free(opt);
        free(res);
    }

    char cmd[512];
    snprintf(cmd, sizeof cmd,
             "%s optimize --objective efficiency --vary T=%g:%g --vary F0=%g:%g --json", argv[1],
             T_LO, T_HI, F_LO, F_HI);
    FILE *pipe = popen(cmd, "r");
    json_error_t jerr;
    json_t *o = pipe ? json_loadf(pipe, 0, &jerr) : NULL;
    int rc = pipe ? pclose(pipe) : -1;
    CHECK(o != NULL && rc == 0, "usm optimize failed (status %d)", rc);
    if (!o)
        return 1;
    const double value = json_real_value(json_object_get(o, "value"));
    json_t *varied = json_object_get(o, "varied");
    const double T = json_real_value(json_object_get(varied, "T"));
    const double F0 = json_real_value(json_object_get(varied, "F0"));
    const double kkt = json_real_value(json_object_get(o, "kkt_residual"));
    printf("optimizer: efficiency %.10g at T = %.8g, F0 = %.8g, KKT residual %.3g, %lld evaluations\n",
           value, T, F0, kkt, (long long)json_integer_value(json_object_get(o, "evaluations")));
    CHECK(strcmp(json_string_value(json_object_get(o, "objective")), "efficiency") == 0 &&
              strcmp(json_string_value(json_object_get(o, "sense")), "max") == 0,
          "objective / sense");
    check_optimum(st, fl, c[best], "command", value, T, F0, kkt);
    json_decref(o);
    free(c);
    usm_floquet_free(fl);
    usm_steady_free(st);
    if (failures)
        printf("%d failures\n", failures);
    return failures != 0;
}
