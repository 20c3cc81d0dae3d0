/* run_tolerance.c: usm tolerance in one process as a library call
 * (usm_run.h), with every sample as a row. */
#include <stdlib.h>

#include "run_internal.h"

static void tol_free(void *data)
{
    usm_tolerance_free(data);
}

static int tol_json(const usm_run *r, FILE *out)
{
    return usm_tolerance_write_json(r->data, out);
}

/* the samples: the varied parameters' values, the outputs, good, redraws */
static int tol_rows(usm_run *r)
{
    const usm_tolerance *t = r->data;
    const size_t nvary = (size_t)usm_tolerance_vary_count(t);
    const size_t cols = nvary + USM_TOL_NOUTPUTS + 2, rows = r->nrows;
    if (!(r->rows = malloc(rows * cols * sizeof *r->rows)))
        return -1;
    r->ncols = cols;
    for (size_t i = 0; i < rows; ++i) {
        double *row = r->rows + i * cols;
        int good = 0, redraws = 0;
        usm_tolerance_sample(t, i, row, row + nvary, &good, &redraws);
        row[cols - 2] = good;
        row[cols - 1] = redraws;
    }
    return 0;
}

usm_run *usm_run_tolerance(const usm_model *m, const usm_params *p,
                           const usm_tolerance_vary *vary, int nvary,
                           const usm_tolerance_spec *spec, int nspec,
                           const usm_tolerance_options *opt, usm_tolerance_runner runner)
{
    usm_run *r = run_new(RUN_TOLERANCE, m, p, usm_tolerance_alloc(m), tol_free);
    usm_tolerance *t;
    if (!r)
        return NULL;
    r->write_json = tol_json;
    t = r->data;
    for (int j = 0; j < nvary + nspec; ++j)
        if ((j < nvary ? usm_tolerance_vary_add(t, &vary[j])
                       : usm_tolerance_spec_add(t, &spec[j - nvary])) != USM_OK) {
            run_fail(r, USM_EINPUT, "%s %s", j < nvary ? "vary" : "spec",
                     usm_tolerance_message(t));
            return r;
        }
    int status = (runner ? runner : usm_tolerance_run)(t, &r->params, opt);
    if (status != USM_OK) {
        run_fail(r, status, "%s", usm_tolerance_message(t));
        return r;
    }
    r->nrows = (size_t)opt->samples;
    r->make_rows = tol_rows;
    r->has_json = 1;
    return r;
}

usm_tolerance *usm_run_tolerance_result(usm_run *r)
{
    return run_data(r, RUN_TOLERANCE);
}
