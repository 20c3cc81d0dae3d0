/* run_periodic.c: usm periodic as a library call (usm_run.h): the shooting,
 * and for a unilateral model whose orbit opens the contact the orbit with
 * separation (docs/unilateral.md). */
#include <stdlib.h>

#include "run_internal.h"

typedef struct periodic_data {
    usm_periodic *w;            /* the bilateral shooting (NULL after the hybrid one) */
    usm_periodic_result res;
    usm_hybrid *h;              /* the orbit with separation, or NULL */
    usm_hybrid_result hres;
    int solved;                 /* res or hres holds an orbit */
} periodic_data;

static void periodic_data_free(void *data)
{
    periodic_data *d = data;
    if (!d)
        return;
    usm_periodic_free(d->w);
    usm_hybrid_free(d->h);
    free(d);
}

/* --json prints the object with "error" on a failure too */
static int periodic_json(const usm_run *r, FILE *out)
{
    const periodic_data *d = r->data;
    if (d->h)
        return usm_hybrid_write_json(r->model, &r->params, d->solved ? &d->hres : NULL,
                                     usm_hybrid_message(d->h), out);
    return usm_periodic_write_json(d->w, &r->params, d->solved ? &d->res : NULL, out);
}

static void hybrid(usm_run *r, periodic_data *d)
{
    usm_periodic_free(d->w);
    d->w = NULL;
    if (!(d->h = usm_hybrid_alloc(r->model))) {
        run_fail(r, USM_EFAILED, "out of memory");
        return;
    }
    int status = usm_hybrid_solve(d->h, &r->params, NULL, &d->hres);
    if (status == USM_EINPUT) {
        run_fail(r, USM_EINPUT, "%s", usm_hybrid_message(d->h));
        return;
    }
    r->has_json = 1;
    if (status != USM_OK)
        run_fail(r, status, "periodic: %s", usm_hybrid_message(d->h));
    else
        d->solved = 1;
}

usm_run *usm_run_periodic(const usm_model *m, const usm_params *p)
{
    periodic_data *d = calloc(1, sizeof *d);
    usm_run *r = run_new(RUN_PERIODIC, m, p, d, periodic_data_free);
    if (!r)
        return NULL;
    r->write_json = periodic_json;
    if (!(d->w = usm_periodic_alloc(m))) {
        run_fail(r, USM_EFAILED, "out of memory");
        return r;
    }
    int status = usm_periodic_solve(d->w, &r->params, NULL, NULL, &d->res);
    if (m->unilateral && status != USM_EINPUT && !(status == USM_OK && !d->res.contact_open)) {
        /* the contact opens on the bilateral orbit (or there is none): the
         * orbit with separation */
        hybrid(r, d);
        return r;
    }
    if (status == USM_EINPUT) {
        run_fail(r, USM_EINPUT, "%s", usm_periodic_message(d->w));
        return r;
    }
    r->has_json = 1;
    if (status != USM_OK)
        run_fail(r, status == USM_ENOSOLUTION ? USM_ENOSOLUTION : USM_EFAILED, "periodic: %s",
                 usm_periodic_message(d->w));
    else
        d->solved = 1;
    return r;
}

const usm_periodic_result *usm_run_periodic_result(const usm_run *r)
{
    const periodic_data *d = run_data(r, RUN_PERIODIC);
    return d && d->solved && d->w ? &d->res : NULL;
}

const usm_periodic *usm_run_periodic_solver(const usm_run *r)
{
    const periodic_data *d = run_data(r, RUN_PERIODIC);
    return d && d->solved && d->w ? d->w : NULL;
}

const usm_hybrid_result *usm_run_hybrid_result(const usm_run *r)
{
    const periodic_data *d = run_data(r, RUN_PERIODIC);
    return d && d->solved && d->h ? &d->hres : NULL;
}
