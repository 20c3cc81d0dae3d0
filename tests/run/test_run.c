/* test_run.c: every analysis as the command runs it (usm_run.h), on a good
 * and a bad input, without the command or Python, so that the sanitizer
 * build checks the runs for leaks (the Python tests run there with
 * LeakSanitizer off: CPython's own objects would be reported): the status
 * the command exits with, a JSON object where the command prints one (and
 * none where it prints none), the time history's rows at the requested rate.
 * That the objects equal the command's --json is asserted by the CLI and
 * Python tests (tests/python/test_analyses.py). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>

#include "check.h"
#include "usm_design.h"
#include "usm_run.h"
#include "usm_simulate.h"

static char *json;
static size_t len;

/* r's JSON in `json` (freed at the next call); 1 for a whole object */
static int json_object(const usm_run *r)
{
    free(json);
    json = usm_run_json(r, &len);
    return json && len > 2 && json[0] == '{' && json[len - 1] == '\n' && strlen(json) == len;
}

int main(void)
{
    const usm_model *m3 = usm_model_find("3dof"), *m4 = usm_model_find("4dof");
    const usm_model *mi = usm_model_variant("3dof", "imperfect");
    usm_params p, bad;
    usm_floquet_options fo;
    usm_op_options op;
    usm_run *r;
    gsl_set_error_handler_off();
    usm_params_default(&p);
    usm_floquet_options_default(&fo);
    usm_op_options_default(&op);

    r = usm_run_steady(m3, &p, 0.0, &fo, &op);
    CHECK(usm_run_status(r) == USM_OK && json_object(r), "steady: %d %s", usm_run_status(r), usm_run_message(r));
    CHECK(strstr(json, "\"converged\": true") != NULL, "steady converged");
    usm_run_free(r);
    bad = p;
    bad.T = 0.1; /* beyond the stall load: no stationary solution (exit 3, converged false) */
    r = usm_run_steady(m4, &bad, 0.0, &fo, &op);
    CHECK(usm_run_status(r) == USM_ENOSOLUTION && json_object(r), "steady T = 0.1: %d", usm_run_status(r));
    CHECK(strncmp(usm_run_message(r), "no stationary solution: ", 24) == 0, "message: %s", usm_run_message(r));
    CHECK(strstr(json, "\"converged\": false") != NULL, "converged false");
    usm_run_free(r);

    usm_sweep_options so;
    usm_sweep_options_default(&so);
    so.over = "f";
    so.from = 36000;
    so.to = 38000;
    so.points = 3;
    r = usm_run_sweep(m4, &p, &so);
    CHECK(usm_run_status(r) == USM_OK && json_object(r), "sweep: %d %s", usm_run_status(r), usm_run_message(r));
    usm_run_free(r);
    so.points = 1;
    r = usm_run_sweep(m3, &p, &so);
    CHECK(usm_run_status(r) == USM_EINPUT && !usm_run_has_json(r) && strncmp(usm_run_message(r), "points:", 7) == 0,
          "sweep points 1: %d %s", usm_run_status(r), usm_run_message(r));
    usm_run_free(r);

    usm_periodic_sweep_options po;
    usm_periodic_sweep_options_default(&po);
    po.over = "f";
    po.from = 36900;
    po.to = 37100;
    po.points = 2;
    r = usm_run_periodic_sweep(mi, &p, &po);
    CHECK(usm_run_status(r) == USM_OK && json_object(r), "periodic sweep: %d %s", usm_run_status(r), usm_run_message(r));
    usm_run_free(r);

    /* the squeal study: short runs (its leaks and statuses, not its numbers) */
    const usm_model *mu = usm_model_find("3dof_imperfect_unilateral");
    usm_squeal_options qo;
    usm_squeal_options_default(&qo);
    qo.over = "phase_error";
    qo.from = 0.90;
    qo.to = 0.93;
    qo.points = 2;
    qo.settle = 10;
    qo.window = 16;
    qo.lyapunov_periods = 5;
    r = usm_run_squeal(mu, &p, &qo);
    CHECK(usm_run_status(r) == USM_OK && json_object(r) && usm_run_squeal_result(r) &&
          usm_squeal_count(usm_run_squeal_result(r)) == 2,
          "squeal: %d %s", usm_run_status(r), usm_run_message(r));
    usm_run_free(r);
    qo.points = 1;
    r = usm_run_squeal(mu, &p, &qo);
    CHECK(usm_run_status(r) == USM_EINPUT && !usm_run_has_json(r) &&
          strncmp(usm_run_message(r), "squeal: points:", 15) == 0,
          "squeal points 1: %d %s", usm_run_status(r), usm_run_message(r));
    usm_run_free(r);

    usm_sim_options sim;
    usm_sim_options_default(&sim);
    sim.duration = 5.0 / p.f;
    sim.rate = 10.0 * p.f;
    r = usm_run_simulate(m3, &p, &sim, NULL, -1);
    CHECK(usm_run_status(r) == USM_OK && json_object(r), "simulate: %d %s", usm_run_status(r), usm_run_message(r));
    /* samples at t0 + k / rate for k = 0 .. 50, the end included */
    size_t nrows, ncols;
    const double *rows = usm_run_rows(r, &nrows, &ncols);
    CHECK(rows && ncols == USM_RUN_SIM_COLUMNS && nrows == 51, "rows %zu", nrows);
    CHECK(rows && rows[0] == 0.0 && fabs(rows[50 * ncols] - 5.0 / p.f) < 1e-18, "t");
    usm_run_free(r);
    sim.max_steps = 10; /* stopped early: the command's exit 1, with its summary */
    r = usm_run_simulate(m3, &p, &sim, NULL, -1);
    CHECK(usm_run_status(r) == USM_EFAILED && json_object(r), "simulate max_steps: %d", usm_run_status(r));
    usm_run_free(r);
    sim.duration = -1;
    r = usm_run_simulate(m3, &p, &sim, NULL, -1);
    CHECK(usm_run_status(r) == USM_EINPUT && !usm_run_has_json(r) && strncmp(usm_run_message(r), "duration:", 9) == 0,
          "simulate duration -1: %d %s", usm_run_status(r), usm_run_message(r));
    usm_run_free(r);

    bad = p;
    bad.amp_imbalance = 0.05;
    r = usm_run_periodic(mi, &bad);
    CHECK(usm_run_status(r) == USM_OK && json_object(r), "periodic: %d %s", usm_run_status(r), usm_run_message(r));
    usm_run_free(r);

    /* The clients' defaults are the library's, as docs/cli.md states them:
     * --rate 10 f; --of the first seven outputs, theta .. max_modulus. */
    {
        static const char *const seven[] = {"theta", "rotor_speed", "F_n", "F_t", "efficiency",
                                            "stick_margin", "max_modulus"};
        int def[USM_SENS_COUNT], n = 0;
        usm_params q = p;
        q.f = 40e3;
        CHECK(usm_sim_default_rate(&p) == 10.0 * p.f && usm_sim_default_rate(&q) == 4e5,
              "default rate %g", usm_sim_default_rate(&p));
        usm_sensitivity_outputs_default(def);
        for (int k = 0; k < USM_SENS_COUNT; ++k)
            n += def[k];
        for (int k = 0; k < 7; ++k)
            n -= def[usm_sensitivity_output_find(seven[k])];
        CHECK(n == 0, "default outputs: %d beyond the seven", n);
    }
    int want[USM_SENS_COUNT];
    for (int k = 0; k < USM_SENS_COUNT; ++k)
        want[k] = 1;
    r = usm_run_sensitivity(m4, &p, want);
    CHECK(usm_run_status(r) == USM_OK && json_object(r), "sensitivity: %d %s", usm_run_status(r), usm_run_message(r));
    usm_run_free(r);

    usm_map_options mo;
    usm_map_options_default(&mo);
    mo.x.points = 3;
    mo.y.points = 2;
    r = usm_run_map(m3, &p, &mo);
    CHECK(usm_run_status(r) == USM_OK && json_object(r), "map: %d %s", usm_run_status(r), usm_run_message(r));
    usm_run_free(r);
    mo.x.name = "nonsense";
    r = usm_run_map(m3, &p, &mo);
    CHECK(usm_run_status(r) == USM_EINPUT && !usm_run_has_json(r), "map nonsense: %d %s", usm_run_status(r), usm_run_message(r));
    usm_run_free(r);
    usm_tolerance_options to;
    usm_tolerance_vary tv;
    usm_tolerance_spec ts;
    char lib[USM_MSG_LEN];
    usm_tolerance_options_default(&to);
    to.samples = 20;
    CHECK(usm_tolerance_vary_parse("F0=normal:5%", &tv, lib) == USM_OK, "%s", lib);
    CHECK(usm_tolerance_spec_parse("theta<=1e-4", &ts, lib) == USM_OK, "%s", lib);
    r = usm_run_tolerance(m3, &p, &tv, 1, &ts, 1, &to, NULL);
    CHECK(usm_run_status(r) == USM_OK && json_object(r), "tolerance: %d %s",
          usm_run_status(r), usm_run_message(r));
    /* the rows, made when asked for: F0, the outputs, good, redraws */
    rows = usm_run_rows(r, &nrows, &ncols);
    CHECK(rows && nrows == 20 && ncols == 1 + USM_TOL_NOUTPUTS + 2, "rows %zu x %zu", nrows,
          ncols);
    CHECK(rows && rows[0] > 0.3 && rows[0] < 0.5, "F0 of sample 0: %g", rows ? rows[0] : 0.0);
    usm_run_free(r);
    ts.output = -1; /* a spec the study refuses: "spec ..." and no JSON */
    r = usm_run_tolerance(m3, &p, &tv, 1, &ts, 1, &to, NULL);
    CHECK(usm_run_status(r) == USM_EINPUT && !usm_run_has_json(r) &&
          strncmp(usm_run_message(r), "spec ", 5) == 0, "bad spec: %s", usm_run_message(r));
    usm_run_free(r);

    /* usm optimize (nominal, robust) and usm pareto on small problems */
    usm_opt_problem pb;
    usm_opt_problem_init(&pb);
    pb.starts = 1;
    CHECK(usm_opt_problem_add_vary(&pb, "F0", 0.3, 0.6, lib) == USM_OK, "%s", lib);
    pb.objective = usm_opt_output_find("speed");
    r = usm_run_optimize(m3, &p, &pb);
    CHECK(usm_run_status(r) == USM_OK && json_object(r) && usm_run_optimize_result(r),
          "optimize: %d %s", usm_run_status(r), usm_run_message(r));
    usm_run_free(r);
    usm_robust_problem rp;
    char iomsg[USM_IO_MSG_LEN];
    usm_robust_problem_init(&rp);
    CHECK(usm_robust_objective_parse(&rp, "q10:speed", iomsg) == USM_OK, "%s", iomsg);
    CHECK(usm_robust_constraint_parse(&rp, "speed>=1", iomsg) == 1, "an output's constraint");
    CHECK(usm_robust_constraint_parse(&rp, "yield>=2", iomsg) == USM_EINPUT &&
          strncmp(iomsg, "constraint: yield>=Y", 20) == 0, "%s", iomsg);
    CHECK(usm_tolerance_vary_parse("c_r=normal:2%", &rp.scatter[0], lib) == USM_OK, "%s", lib);
    rp.nscatter = 1;
    rp.samples = 100;
    rp.verify_samples = 100;
    rp.max_evals = 4;
    rp.nominal = pb;
    CHECK(usm_robust_problem_is_robust(&rp) &&
          usm_robust_problem_check(&rp, m3, &p, lib) == USM_OK, "robust problem: %s", lib);
    r = usm_run_robust(m3, &p, &rp);
    CHECK(usm_run_status(r) == USM_OK && json_object(r) && usm_run_robust_result(r),
          "robust: %d %s", usm_run_status(r), usm_run_message(r));
    usm_run_free(r);
    const int obj[2] = {usm_opt_output_find("speed"), usm_opt_output_find("efficiency")};
    const int mini[2] = {0, 0};
    r = usm_run_pareto(m3, &p, &pb, obj, mini, 3);
    CHECK(usm_run_status(r) == USM_OK && json_object(r) && usm_run_pareto_result(r) &&
          usm_run_pareto_result(r)->npoints >= 1, "pareto: %d %s", usm_run_status(r),
          usm_run_message(r));
    usm_run_free(r);
    bad = p;
    bad.amp_imbalance = 0.05; /* an imperfect motor: refused as usm steady refuses it */
    r = usm_run_pareto(m3, &bad, &pb, obj, mini, 3);
    CHECK(usm_run_status(r) != USM_OK && !usm_run_has_json(r), "pareto imperfect: %d %s",
          usm_run_status(r), usm_run_message(r));
    usm_run_free(r);

    /* the orbit with separation of a unilateral model (usm periodic chooses it) */
    bad = p;
    bad.phase_error = 35 * 3.14159265358979323846 / 180; /* 35 deg */
    r = usm_run_periodic(usm_model_variant("3dof", "imperfect_unilateral"), &bad);
    CHECK(usm_run_status(r) == USM_OK && json_object(r) && usm_run_hybrid_result(r) &&
          !usm_run_periodic_result(r) && strstr(json, "\"mode_sequence\""),
          "periodic with separation: %d %s", usm_run_status(r), usm_run_message(r));
    usm_run_free(r);

    /* the spectrum of a simulation's samples */
    usm_sim_options_default(&sim);
    sim.duration = 60.0 / p.f;
    sim.rate = 10.0 * p.f;
    r = usm_run_simulate(m3, &p, &sim, NULL, 0);
    CHECK(usm_run_status(r) == USM_OK && usm_run_spectrum(r) &&
          usm_run_spectrum_amplitudes(r, USM_SPECTRUM_THETA) && json_object(r) &&
          strstr(json, "\"spectrum\""), "simulate spectrum: %d %s", usm_run_status(r),
          usm_run_message(r));
    usm_run_free(r);

    free(json);
    if (failures)
        printf("%d check(s) failed\n", failures);
    else
        printf("run: all checks passed\n");
    return failures != 0;
}
