/* run_steady.c: usm steady and usm sensitivity as library calls (usm_run.h):
 * the stationary roots first, as both commands find them. */
#include <stdlib.h>

#include "run_internal.h"

/* usm_steady_solve with the commands' messages: USM_OK with at least one
 * root, else r failed ("no stationary solution: ..." for USM_ENOSOLUTION). */
static int solve_roots(usm_run *r, usm_steady *s)
{
    int status = usm_steady_solve(s, &r->params, NULL);
    if (status == USM_ENOSOLUTION)
        run_fail(r, USM_ENOSOLUTION, "no stationary solution: %s", usm_steady_message(s));
    else if (status == USM_EINPUT)
        run_fail(r, USM_EINPUT, "%s", usm_steady_message(s));
    else if (status != USM_OK || usm_steady_count(s) == 0)
        run_fail(r, USM_EFAILED, "steady: %s", usm_steady_message(s));
    else
        return USM_OK;
    return r->status;
}

/* ---- steady ------------------------------------------------------------------------ */

typedef struct steady_data {
    usm_steady *s;
    usm_floquet_result *res;    /* one per root */
    usm_op_result op;
    usm_steady_report rep;
} steady_data;

static void steady_data_free(void *data)
{
    steady_data *d = data;
    if (!d)
        return;
    free(d->res);
    usm_steady_free(d->s);
    free(d);
}

static int steady_json(const usm_run *r, FILE *out)
{
    const steady_data *d = r->data;
    return usm_steady_write_json(&d->rep, out);
}

usm_run *usm_run_steady(const usm_model *m, const usm_params *p, double t0,
                        const usm_floquet_options *fo, const usm_op_options *opo)
{
    steady_data *d = calloc(1, sizeof *d);
    usm_run *r = run_new(RUN_STEADY, m, p, d, steady_data_free);
    usm_floquet *fl = NULL;
    const char *bad;
    if (!r)
        return NULL;
    r->write_json = steady_json;
    d->rep = (usm_steady_report){.model = m, .params = &r->params};
    if (!(d->s = usm_steady_alloc(m))) {
        run_fail(r, USM_EFAILED, "out of memory");
        return r;
    }
    d->rep.steady = d->s;
    if (solve_roots(r, d->s) != USM_OK) {
        if (r->status == USM_ENOSOLUTION) { /* --json prints converged = false */
            d->rep.error = usm_steady_message(d->s);
            r->has_json = 1;
        }
        return r;
    }
    const size_t n = usm_steady_count(d->s);
    if (!(fl = usm_floquet_alloc(m)) || !(d->res = malloc(n * sizeof *d->res))) {
        run_fail(r, USM_EFAILED, "out of memory");
        goto done;
    }
    /* every root's multipliers; the top level keeps describing root 0 */
    int status = usm_floquet_roots(fl, &r->params, d->s, t0, fo, d->res);
    if (status != USM_OK) {
        run_fail(r, status == USM_EINPUT ? USM_EINPUT : USM_EFAILED, "floquet: %s",
                 usm_floquet_message(fl));
        goto done;
    }
    for (size_t k = 0; k < n; ++k)
        /* "never NaN in the output": a non-finite value is a numerical failure */
        if ((bad = usm_steady_nonfinite(usm_steady_root(d->s, k), &d->res[k]))) {
            run_fail(r, USM_EFAILED, "%s", bad);
            goto done;
        }
    /* the operating point: cheap where one root is stable, a simulation from
     * rest where asked (usm_operating_point.h) */
    status = usm_operating_point(m, &r->params, d->s, d->res, opo, &d->op);
    if (status != USM_OK) {
        run_fail(r, status, "%s", d->op.message);
        goto done;
    }
    d->rep.floquet = &d->res[0];
    d->rep.roots_floquet = d->res;
    d->rep.op = &d->op;
    r->has_json = 1;
done:
    usm_floquet_free(fl);
    return r;
}

const usm_steady_report *usm_run_steady_report(const usm_run *r)
{
    const steady_data *d = run_data(r, RUN_STEADY);
    return d && r->status == USM_OK ? &d->rep : NULL;
}

/* ---- sensitivity ------------------------------------------------------------------- */

typedef struct sens_data {
    usm_steady *s;
    usm_sensitivity *sens;
    usm_sensitivity_result res;
    int want[USM_SENS_COUNT];
} sens_data;

static void sens_data_free(void *data)
{
    sens_data *d = data;
    if (!d)
        return;
    usm_sensitivity_free(d->sens);
    usm_steady_free(d->s);
    free(d);
}

static int sens_json(const usm_run *r, FILE *out)
{
    const sens_data *d = r->data;
    return usm_sensitivity_write_json(r->model, &r->params, &d->res, d->want, out);
}

usm_run *usm_run_sensitivity(const usm_model *m, const usm_params *p,
                             const int want[USM_SENS_COUNT])
{
    sens_data *d = calloc(1, sizeof *d);
    usm_run *r = run_new(RUN_SENSITIVITY, m, p, d, sens_data_free);
    if (!r)
        return NULL;
    r->write_json = sens_json;
    for (int k = 0; k < USM_SENS_COUNT; ++k)
        d->want[k] = want[k];
    if (!(d->s = usm_steady_alloc(m))) {
        run_fail(r, USM_EFAILED, "out of memory");
        return r;
    }
    if (solve_roots(r, d->s) != USM_OK)
        return r;
    if (!(d->sens = usm_sensitivity_alloc(m))) {
        run_fail(r, USM_EFAILED, "out of memory");
        return r;
    }
    int status = usm_sensitivity_compute(d->sens, &r->params, usm_steady_root(d->s, 0),
                                         d->want[USM_SENS_MAX_MODULUS], &d->res);
    if (status != USM_OK)
        run_fail(r, status == USM_EINPUT ? USM_EINPUT : USM_EFAILED, "sensitivity: %s",
                 usm_sensitivity_message(d->sens));
    else
        r->has_json = 1;
    return r;
}

const usm_sensitivity_result *usm_run_sensitivity_result(const usm_run *r)
{
    const sens_data *d = run_data(r, RUN_SENSITIVITY);
    return d && r->status == USM_OK ? &d->res : NULL;
}
