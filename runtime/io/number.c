/* The one parser for numbers the user types (see usm_io.h). */
#include "usm_io.h"
#include "io_msg.h"

#include <ctype.h>
#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "usm.h"

int usm_parse_number(const char *field, const char *text, size_t len, double *out,
                     char msg[USM_IO_MSG_LEN])
{
    char small[64];
    char *buf = len < sizeof small ? small : malloc(len + 1);
    char *end = buf;
    double v;
    int status = USM_EINPUT;
    if (!buf) {
        usm_io_msg(msg, "%s: out of memory", field);
        return USM_EFAILED;
    }
    memcpy(buf, text, len);
    buf[len] = '\0';
    /* strtod skips leading blanks and accepts "nan"/"inf"; a value typed with
     * a stray blank, an embedded NUL or a non-finite value is a mistake. */
    int typed = len > 0 && !isspace((unsigned char)buf[0]) && strlen(buf) == len;
    errno = 0;
    v = typed ? strtod(buf, &end) : 0.0;
    if (!typed || end == buf || *end != '\0')
        usm_io_msg(msg, "%s: \"%.*s\" is not a number", field, len > 200 ? 200 : (int)len, text);
    else if (isnan(v) || (isinf(v) && errno != ERANGE))
        usm_io_msg(msg, "%s: \"%s\" is not a finite number", field, buf);
    else if (isinf(v) || fabs(v) > DBL_MAX)
        usm_io_msg(msg, "%s: \"%.200s\" is out of range for a double (overflow: its magnitude "
                     "exceeds %.3g)", field, buf, DBL_MAX);
    else if ((v != 0.0 && fabs(v) < DBL_MIN) || (v == 0.0 && errno == ERANGE))
        usm_io_msg(msg, "%s: \"%.200s\" is out of range for a double (underflow: its magnitude "
                     "is below %.3g, the smallest normal double)", field, buf, DBL_MIN);
    else {
        *out = v;
        status = USM_OK;
    }
    if (buf != small)
        free(buf);
    return status;
}
