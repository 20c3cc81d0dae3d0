/* run_envelope.c: usm envelope as a library call (usm_run.h). */
#include <stdlib.h>
#include <string.h>

#include "run_internal.h"
#include "usm_envelope.h"

static void envelope_data_free(void *data) { usm_envelope_free(data); }

static int envelope_json(const usm_run *r, FILE *out)
{
    return usm_envelope_write_json(r->data, r->model, out);
}

usm_run *usm_run_envelope(const usm_model *m, const usm_params *p,
                          const usm_envelope_options *opt)
{
    usm_envelope *e = usm_envelope_alloc(m);
    usm_run *r = run_new(RUN_ENVELOPE, m, p, e, envelope_data_free);
    if (!r)
        return NULL;
    r->write_json = envelope_json;
    if (!e) {
        run_fail(r, USM_EFAILED, "out of memory");
        return r;
    }
    const int status = usm_envelope_run(e, &r->params, opt);
    if (status == USM_EINPUT)
        run_fail(r, USM_EINPUT, "%s", usm_envelope_message(e));
    else if (status != USM_OK)
        run_fail(r, USM_EFAILED, "envelope: %s", usm_envelope_message(e));
    else
        r->has_json = 1;
    return r;
}

const usm_envelope *usm_run_envelope_result(const usm_run *r)
{
    const usm_envelope *e = run_data(r, RUN_ENVELOPE);
    return e && r->status == USM_OK ? e : NULL;
}
