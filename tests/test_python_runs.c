/* test_python_runs.c: the C half of the Python module (python/usm/runs.c)
 * without Python, so that the sanitizer build checks it for leaks (the
 * Python tests run there with LeakSanitizer off: CPython's own objects would
 * be reported).  Every analysis on a good and a bad input: the status the
 * command exits with, a JSON object where the command prints one, the time
 * history's rows at the requested rate. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <gsl/gsl_errno.h>

#include "check.h"
#include "runs.h"

static int json_object(const usmpy_out *o)
{
    return o->json && o->len > 2 && o->json[0] == '{' && o->json[o->len - 1] == '\n' &&
           strlen(o->json) == o->len;
}

int main(void)
{
    const usm_model *m3 = usm_model_find("3dof"), *m4 = usm_model_find("4dof");
    const usm_model *mi = usm_model_variant("3dof", "imperfect");
    usm_params p, bad;
    usm_floquet_options fo;
    usm_op_options op;
    usmpy_out o;
    gsl_set_error_handler_off();
    usm_params_default(&p);
    usm_floquet_options_default(&fo);
    usm_op_options_default(&op);

    usmpy_steady(m3, &p, 0.0, &fo, &op, &o);
    CHECK(o.status == USM_OK && json_object(&o), "steady: %d %s", o.status, o.msg);
    CHECK(strstr(o.json, "\"converged\": true") != NULL, "steady converged");
    usmpy_out_free(&o);
    bad = p;
    bad.T = 0.1; /* beyond the stall load: no stationary solution (exit 3, converged false) */
    usmpy_steady(m4, &bad, 0.0, &fo, &op, &o);
    CHECK(o.status == USM_ENOSOLUTION && json_object(&o), "steady T = 0.1: %d", o.status);
    CHECK(strncmp(o.msg, "no stationary solution: ", 24) == 0, "message: %s", o.msg);
    CHECK(strstr(o.json, "\"converged\": false") != NULL, "converged false");
    usmpy_out_free(&o);

    usm_sweep_options so;
    usm_sweep_options_default(&so);
    so.over = "f";
    so.from = 36000;
    so.to = 38000;
    so.points = 3;
    usmpy_sweep(m4, &p, &so, &o);
    CHECK(o.status == USM_OK && json_object(&o), "sweep: %d %s", o.status, o.msg);
    usmpy_out_free(&o);
    so.points = 1;
    usmpy_sweep(m3, &p, &so, &o);
    CHECK(o.status == USM_EINPUT && !o.json && strncmp(o.msg, "points:", 7) == 0,
          "sweep points 1: %d %s", o.status, o.msg);
    usmpy_out_free(&o);

    usm_periodic_sweep_options po;
    usm_periodic_sweep_options_default(&po);
    po.over = "f";
    po.from = 36900;
    po.to = 37100;
    po.points = 2;
    usmpy_periodic_sweep(mi, &p, &po, &o);
    CHECK(o.status == USM_OK && json_object(&o), "periodic sweep: %d %s", o.status, o.msg);
    usmpy_out_free(&o);

    usm_sim_options sim;
    usm_sim_options_default(&sim);
    sim.duration = 5.0 / p.f;
    sim.rate = 10.0 * p.f;
    usmpy_simulate(m3, &p, &sim, &o);
    CHECK(o.status == USM_OK && json_object(&o), "simulate: %d %s", o.status, o.msg);
    /* samples at t0 + k / rate for k = 0 .. 50, the end included */
    CHECK(o.rows && o.ncols == USMPY_SIM_COLUMNS && o.nrows == 51, "rows %zu", o.nrows);
    CHECK(o.rows[0] == 0.0 && fabs(o.rows[50 * o.ncols] - 5.0 / p.f) < 1e-18, "t");
    usmpy_out_free(&o);
    sim.max_steps = 10; /* stopped early: the command's exit 1, with its summary */
    usmpy_simulate(m3, &p, &sim, &o);
    CHECK(o.status == USM_EFAILED && json_object(&o), "simulate max_steps: %d", o.status);
    usmpy_out_free(&o);
    sim.duration = -1;
    usmpy_simulate(m3, &p, &sim, &o);
    CHECK(o.status == USM_EINPUT && !o.json && strncmp(o.msg, "duration:", 9) == 0,
          "simulate duration -1: %d %s", o.status, o.msg);
    usmpy_out_free(&o);

    bad = p;
    bad.amp_imbalance = 0.05;
    usmpy_periodic(mi, &bad, &o);
    CHECK(o.status == USM_OK && json_object(&o), "periodic: %d %s", o.status, o.msg);
    usmpy_out_free(&o);

    int want[USM_SENS_COUNT];
    for (int k = 0; k < USM_SENS_COUNT; ++k)
        want[k] = 1;
    usmpy_sensitivity(m4, &p, want, &o);
    CHECK(o.status == USM_OK && json_object(&o), "sensitivity: %d %s", o.status, o.msg);
    usmpy_out_free(&o);

    usm_map_options mo;
    usm_map_options_default(&mo);
    mo.x.points = 3;
    mo.y.points = 2;
    usmpy_map(m3, &p, &mo, &o);
    CHECK(o.status == USM_OK && json_object(&o), "map: %d %s", o.status, o.msg);
    usmpy_out_free(&o);
    mo.x.name = "nonsense";
    usmpy_map(m3, &p, &mo, &o);
    CHECK(o.status == USM_EINPUT && !o.json, "map nonsense: %d %s", o.status, o.msg);
    usmpy_out_free(&o);
    if (failures)
        printf("%d check(s) failed\n", failures);
    else
        printf("python_runs: all checks passed\n");
    return failures != 0;
}
