/* run_optimize.c: usm optimize (nominal and robust) and usm pareto as
 * library calls (usm_run.h). */
#include <stdlib.h>

#include "run_internal.h"

/* ---- optimize ---------------------------------------------------------------------- */

typedef struct opt_data {
    usm_optimize *o;
    usm_opt_problem pb;
    usm_opt_result res;
} opt_data;

static void opt_data_free(void *data)
{
    opt_data *d = data;
    if (d)
        usm_optimize_free(d->o);
    free(d);
}

static int opt_json(const usm_run *r, FILE *out)
{
    const opt_data *d = r->data;
    return usm_optimize_write_json(d->o, r->model, &d->pb, &d->res, out);
}

usm_run *usm_run_optimize(const usm_model *m, const usm_params *p, const usm_opt_problem *pb)
{
    opt_data *d = calloc(1, sizeof *d);
    usm_run *r = run_new(RUN_OPTIMIZE, m, p, d, opt_data_free);
    if (!r)
        return NULL;
    r->write_json = opt_json;
    d->pb = *pb;
    if (!(d->o = usm_optimize_alloc(m))) {
        run_fail(r, USM_EFAILED, "out of memory");
        return r;
    }
    int status = usm_optimize_run(d->o, &r->params, &d->pb, &d->res);
    if (status == USM_ENOSOLUTION) { /* --json: {"feasible": false, ...} */
        run_fail(r, USM_ENOSOLUTION, "%s", usm_optimize_message(d->o));
        r->has_json = 1;
    } else if (status != USM_OK)
        run_fail(r, status == USM_EINPUT ? USM_EINPUT : USM_EFAILED, "optimize: %s",
                 usm_optimize_message(d->o));
    else
        r->has_json = 1;
    return r;
}

const usm_opt_result *usm_run_optimize_result(const usm_run *r)
{
    const opt_data *d = run_data(r, RUN_OPTIMIZE);
    return d && r->status == USM_OK ? &d->res : NULL;
}

/* ---- the robust optimum ------------------------------------------------------------ */

typedef struct robust_data {
    usm_robust_problem rp;
    usm_robust_result res;
} robust_data;

static int robust_json(const usm_run *r, FILE *out)
{
    const robust_data *d = r->data;
    return usm_robust_write_json(r->model, &d->rp, &d->res, out);
}

usm_run *usm_run_robust(const usm_model *m, const usm_params *p, const usm_robust_problem *rp)
{
    robust_data *d = calloc(1, sizeof *d);
    usm_run *r = run_new(RUN_ROBUST, m, p, d, free);
    char msg[USM_MSG_LEN];
    if (!r)
        return NULL;
    r->write_json = robust_json;
    d->rp = *rp;
    int status = usm_robust_run(m, &r->params, &d->rp, &d->res, msg);
    if (status == USM_ENOSOLUTION) { /* the message, and the JSON with feasible false */
        run_fail(r, status, "%s", msg);
        r->has_json = 1;
    } else if (status != USM_OK)
        run_fail(r, status, "optimize: %s", msg);
    else
        r->has_json = 1;
    return r;
}

const usm_robust_result *usm_run_robust_result(const usm_run *r)
{
    const robust_data *d = run_data(r, RUN_ROBUST);
    return d && r->has_json ? &d->res : NULL;
}

/* ---- pareto ------------------------------------------------------------------------ */

typedef struct pareto_data {
    usm_opt_problem pb;
    int obj[2], minimize[2];
    usm_pareto_result res;
} pareto_data;

static void pareto_data_free(void *data)
{
    pareto_data *d = data;
    if (d)
        usm_pareto_result_free(&d->res);
    free(d);
}

static int pareto_json(const usm_run *r, FILE *out)
{
    const pareto_data *d = r->data;
    return usm_pareto_write_json(&d->pb, d->obj, d->minimize, &d->res, out);
}

usm_run *usm_run_pareto(const usm_model *m, const usm_params *p, const usm_opt_problem *pb,
                        const int obj[2], const int minimize[2], int points)
{
    pareto_data *d = calloc(1, sizeof *d);
    usm_run *r = run_new(RUN_PARETO, m, p, d, pareto_data_free);
    char msg[USM_MSG_LEN];
    if (!r)
        return NULL;
    r->write_json = pareto_json;
    d->pb = *pb;
    for (int i = 0; i < 2; ++i) {
        d->obj[i] = obj[i];
        d->minimize[i] = minimize[i];
    }
    int status = usm_pareto_run(m, &r->params, &d->pb, d->obj, d->minimize, points, &d->res, msg);
    if (status != USM_OK)
        run_fail(r, status, "pareto: %s", msg);
    else
        r->has_json = 1;
    return r;
}

const usm_pareto_result *usm_run_pareto_result(const usm_run *r)
{
    const pareto_data *d = run_data(r, RUN_PARETO);
    return d && r->status == USM_OK ? &d->res : NULL;
}
