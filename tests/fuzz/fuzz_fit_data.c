/* libFuzzer target: the reader of measurements to fit (runtime/io/fit_data.c).
 *
 * Any bytes must give either USM_OK with data whose conditions and given
 * sigmas are finite, every row with a measured value and every sigma
 * positive, or USM_EINPUT with a message; never a crash, a leak or undefined
 * behaviour (built with ASan and UBSan).  A good text parsed twice gives the
 * same numbers: parsing has no hidden state. */
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "usm_io.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    usm_fit_data *a = NULL, *b = NULL;
    char msg[USM_IO_MSG_LEN] = "";
    int status = usm_fit_data_parse_text("fuzz.csv", (const char *)data, size, &a, msg);
    if (status == USM_OK) {
        if (!a || a->nrows < 1 || a->nout < 1)
            abort();
        for (int r = 0; r < a->nrows; ++r) {
            int any = 0;
            for (int c = 0; c < a->ncond; ++c)
                if (!isfinite(a->x[(size_t)r * (size_t)a->ncond + (size_t)c]))
                    abort();
            for (int c = 0; c < a->nout; ++c) {
                size_t i = (size_t)r * (size_t)a->nout + (size_t)c;
                any |= !isnan(a->y[i]);
                if (!isnan(a->y[i]) && (!isfinite(a->y[i]) ||
                                        (a->has_sigma[c] && !(a->sigma[i] > 0))))
                    abort();
            }
            if (!any)
                abort();
        }
        if (usm_fit_data_parse_text("fuzz.csv", (const char *)data, size, &b, msg) != USM_OK ||
            b->nrows != a->nrows ||
            memcmp(b->y, a->y, (size_t)a->nrows * (size_t)a->nout * sizeof *a->y) != 0)
            abort();
    } else if (status != USM_EINPUT || msg[0] == '\0' || a != NULL) {
        abort();
    }
    usm_fit_data_free(a);
    usm_fit_data_free(b);
    return 0;
}
