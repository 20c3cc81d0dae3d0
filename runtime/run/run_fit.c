/* run_fit.c: usm fit as a library call (usm_run.h): the data read, the
 * fitted parameters parsed, the fit run, its JSON. */
#include <stdlib.h>
#include <string.h>

#include "run_internal.h"
#include "usm_fit.h"

typedef struct fit_data {
    usm_fit_data *data;
    usm_fit_options opt;
    usm_fit_result res;
} fit_data;

static void fit_data_free(void *p)
{
    fit_data *d = p;
    if (!d)
        return;
    usm_fit_result_free(&d->res);
    usm_fit_data_free(d->data);
    free(d);
}

static int fit_json(const usm_run *r, FILE *out)
{
    const fit_data *d = r->data;
    return usm_fit_write_json(r->model, &r->params, d->data, &d->res, out);
}

usm_run *usm_run_fit(const usm_model *m, const usm_params *p, const char *path, const char *text,
                     size_t len, const char *names, const usm_fit_options *opt)
{
    fit_data *d = calloc(1, sizeof *d);
    usm_run *r = run_new(RUN_FIT, m, p, d, fit_data_free);
    char msg[USM_IO_MSG_LEN];
    if (!r)
        return NULL;
    r->write_json = fit_json;
    if (opt)
        d->opt = *opt;
    else
        usm_fit_options_default(&d->opt);
    if (names && usm_fit_parse_names(m, "fit", names, &d->opt, msg) != USM_OK) {
        run_fail(r, USM_EINPUT, "%s", msg);
        return r;
    }
    int st = text ? usm_fit_data_parse_text(path, text, len, &d->data, msg)
                  : usm_fit_data_read(path, &d->data, msg);
    if (st != USM_OK) {
        run_fail(r, st, "%s", msg);
        return r;
    }
    st = usm_fit_run(m, &r->params, d->data, &d->opt, &d->res);
    if (st != USM_OK) {
        run_fail(r, st, "%s", d->res.message);
        return r;
    }
    r->has_json = 1;
    return r;
}

const usm_fit_result *usm_run_fit_result(const usm_run *r)
{
    const fit_data *d = run_data(r, RUN_FIT);
    return d && r->status == USM_OK ? &d->res : NULL;
}

const usm_fit_data *usm_run_fit_data(const usm_run *r)
{
    const fit_data *d = run_data(r, RUN_FIT);
    return d ? d->data : NULL;
}
