/* usm squeal as one library call (usm_run.h). */
#include "run_internal.h"
#include "usm_squeal_study.h"

static void squeal_free(void *data) { usm_squeal_free(data); }

static int squeal_json(const usm_run *r, FILE *out) { return usm_squeal_write_json(r->data, out); }

usm_run *usm_run_squeal(const usm_model *m, const usm_params *p, const usm_squeal_options *opt)
{
    usm_run *r = run_new(RUN_SQUEAL, m, p, usm_squeal_alloc(m), squeal_free);
    if (!r)
        return NULL;
    r->write_json = squeal_json;
    const int status = usm_squeal_run(r->data, &r->params, opt);
    if (status != USM_OK)
        run_fail(r, status == USM_EINPUT ? USM_EINPUT : USM_EFAILED, "squeal: %s",
                 usm_squeal_message(r->data));
    else
        r->has_json = 1;
    return r;
}

const usm_squeal_study *usm_run_squeal_result(const usm_run *r)
{
    const usm_squeal_study *s = run_data(r, RUN_SQUEAL);
    return s && r->status == USM_OK ? s : NULL;
}
