/* libFuzzer target: the parameter-file parser (runtime/io/params_file.c).
 *
 * Any bytes must give either USM_OK with every parameter finite and zero or
 * normal (the number parser's promise), or USM_EINPUT with a message; never a
 * crash, a leak or undefined behaviour (built with ASan and UBSan).  A good
 * text parsed twice gives the same parameters: parsing has no hidden state. */
#include <float.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "usm_io.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    usm_params p, q;
    char msg[USM_IO_MSG_LEN] = "";
    int status;
    usm_params_default(&p);
    q = p;
    status = usm_params_parse_text("fuzz.json", (const char *)data, size, &p, msg);
    if (status == USM_OK) {
        for (int k = 0; k < USM_NPARAMS; ++k) {
            double v = usm_params_get(&p, &usm_param_table[k]);
            if (!isfinite(v) || (v != 0.0 && fabs(v) < DBL_MIN))
                abort();
        }
        if (usm_params_parse_text("fuzz.json", (const char *)data, size, &q, msg) != USM_OK ||
            memcmp(&p, &q, sizeof p) != 0)
            abort();
    } else if (status != USM_EINPUT || msg[0] == '\0' ||
               memcmp(&p, &q, sizeof p) != 0 /* a bad file changes nothing */) {
        abort();
    }
    return 0;
}
