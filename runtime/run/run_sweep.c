/* run_sweep.c: usm sweep, usm sweep --periodic and usm map --json as library
 * calls (usm_run.h). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "run_internal.h"
#include "usm_report_map.h"

/* ---- sweep ------------------------------------------------------------------------- */

typedef struct sweep_data {
    usm_sweep *s;
    char over[64];
} sweep_data;

static void sweep_data_free(void *data)
{
    sweep_data *d = data;
    if (d)
        usm_sweep_free(d->s);
    free(d);
}

static int sweep_json(const usm_run *r, FILE *out)
{
    const sweep_data *d = r->data;
    return usm_sweep_write_json(d->s, r->model, &r->params, d->over, out);
}

usm_run *usm_run_sweep(const usm_model *m, const usm_params *p, const usm_sweep_options *opt)
{
    sweep_data *d = calloc(1, sizeof *d);
    usm_run *r = run_new(RUN_SWEEP, m, p, d, sweep_data_free);
    if (!r)
        return NULL;
    r->write_json = sweep_json;
    snprintf(d->over, sizeof d->over, "%s", opt->over ? opt->over : "");
    if (!(d->s = usm_sweep_alloc(m))) {
        run_fail(r, USM_EFAILED, "out of memory");
        return r;
    }
    int status = usm_sweep_run(d->s, &r->params, opt);
    if (status == USM_EINPUT)
        run_fail(r, USM_EINPUT, "%s", usm_sweep_message(d->s));
    else if (status != USM_OK)
        run_fail(r, USM_EFAILED, "sweep: %s", usm_sweep_message(d->s));
    else
        r->has_json = 1;
    return r;
}

const usm_sweep *usm_run_sweep_result(const usm_run *r)
{
    const sweep_data *d = run_data(r, RUN_SWEEP);
    return d && r->status == USM_OK ? d->s : NULL;
}

/* ---- periodic sweep ---------------------------------------------------------------- */

static void psweep_free(void *data)
{
    usm_periodic_sweep_free(data);
}

static int psweep_json(const usm_run *r, FILE *out)
{
    return usm_periodic_sweep_write_json(r->data, &r->params, out);
}

usm_run *usm_run_periodic_sweep(const usm_model *m, const usm_params *p,
                                const usm_periodic_sweep_options *opt)
{
    usm_run *r = run_new(RUN_PERIODIC_SWEEP, m, p, usm_periodic_sweep_alloc(m), psweep_free);
    if (!r)
        return NULL;
    r->write_json = psweep_json;
    int status = usm_periodic_sweep_run(r->data, &r->params, opt);
    if (status != USM_OK)
        run_fail(r, status == USM_EINPUT ? USM_EINPUT : USM_EFAILED, "sweep: %s",
                 usm_periodic_sweep_message(r->data));
    else
        r->has_json = 1;
    return r;
}

const usm_periodic_sweep *usm_run_periodic_sweep_result(const usm_run *r)
{
    const usm_periodic_sweep *s = run_data(r, RUN_PERIODIC_SWEEP);
    return s && r->status == USM_OK ? s : NULL;
}

/* ---- map --------------------------------------------------------------------------- */

typedef struct map_data {
    usm_report_map map;
    usm_map_options opt;        /* map's floquet and op point into it */
    char xname[64], yname[64];  /* and its axes' names */
    int filled;
} map_data;

static void map_data_free(void *data)
{
    map_data *d = data;
    if (d && d->filled)
        usm_report_map_free(&d->map);
    free(d);
}

static int map_json(const usm_run *r, FILE *out)
{
    const map_data *d = r->data;
    return usm_report_map_write_json(&d->map, out);
}

usm_run *usm_run_map(const usm_model *m, const usm_params *p, const usm_map_options *opt)
{
    map_data *d = calloc(1, sizeof *d);
    usm_run *r = run_new(RUN_MAP, m, p, d, map_data_free);
    if (!r)
        return NULL;
    r->write_json = map_json;
    d->opt = *opt;
    usm_report_map *map = &d->map;
    map->model = m;
    map->params = *p;
    snprintf(d->xname, sizeof d->xname, "%s", opt->x.name ? opt->x.name : "");
    snprintf(d->yname, sizeof d->yname, "%s", opt->y.name ? opt->y.name : "");
    map->x.name = d->xname;
    map->x.from = opt->x.from;
    map->x.to = opt->x.to;
    map->x.points = opt->x.points;
    map->y.name = d->yname;
    map->y.from = opt->y.from;
    map->y.to = opt->y.to;
    map->y.points = opt->y.points;
    map->t0 = opt->t0;
    map->floquet = &d->opt.floquet;
    map->op = &d->opt.op;
    map->threads = opt->threads;
    map->boundaries = opt->boundaries; /* --json: 1 */
    map->progress = opt->progress;
    int status = usm_report_map_run(map, r->msg);
    if (status != USM_OK)
        r->status = status;
    else
        d->filled = r->has_json = 1;
    return r;
}

const usm_report_map *usm_run_map_result(const usm_run *r)
{
    const map_data *d = run_data(r, RUN_MAP);
    return d && d->filled ? &d->map : NULL;
}
