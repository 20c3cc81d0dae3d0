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
#include "core/units.h"

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

/* ---- values with units (the table: core/units.c) ------------------------------ */

int usm_parse_quantity(const char *field, const char *unit, const char *text, size_t len,
                       double *out, char msg[USM_IO_MSG_LEN])
{
    char small[64];
    char key[32];
    size_t numlen = 0;
    int row = -1;
    if (!unit || len == 0 || isspace((unsigned char)text[0]))
        return usm_parse_number(field, text, len, out, msg);
    /* the number: what strtod reads of it; the rest is the unit */
    {
        char *buf = len < sizeof small ? small : malloc(len + 1);
        char *end;
        if (!buf) {
            usm_io_msg(msg, "%s: out of memory", field);
            return USM_EFAILED;
        }
        memcpy(buf, text, len);
        buf[len] = '\0';
        (void)strtod(buf, &end);
        numlen = (size_t)(end - buf);
        if (buf != small)
            free(buf);
    }
    if (numlen == 0 || numlen == len || memchr(text, '\0', len))
        return usm_parse_number(field, text, len, out, msg);
    if (!usm_unit_key(text + numlen, len - numlen, key, sizeof key) || key[0] == '\0')
        return usm_parse_number(field, text, len, out, msg);
    for (int k = 0; k < usm_unit_rows && row < 0; ++k)
        if (strcmp(usm_unit_table[k].si, unit) == 0 && strcmp(usm_unit_table[k].name, key) == 0)
            row = k;
    if (row < 0) {
        char known[512];
        int is_unit = 0;
        for (int k = 0; k < usm_unit_rows; ++k)
            is_unit |= strcmp(usm_unit_table[k].name, key) == 0;
        if (usm_units_accepted(unit, known, sizeof known) == 0)
            snprintf(known, sizeof known, "none, a number in %s", unit);
        if (is_unit)
            usm_io_msg(msg, "%s: \"%.*s\": %s is not a unit of a value in [%s] (accepted: %s)",
                       field, len > 200 ? 200 : (int)len, text, key, unit, known);
        else
            usm_io_msg(msg, "%s: \"%.*s\" is not a number, nor a number with a unit of [%s] "
                       "(accepted: %s)", field, len > 200 ? 200 : (int)len, text, unit, known);
        return USM_EINPUT;
    }
    /* the number as usm_parse_number takes it (its messages), then a decimal
     * one scaled in its exponent (400mN reads as 400e-3, the double nearest
     * 0.4); a hexadecimal one by multiplication */
    double v;
    const usm_unit_row *u = &usm_unit_table[row];
    if (usm_parse_number(field, text, numlen, &v, msg) != USM_OK)
        return USM_EINPUT;
    const int decimal = memchr(text, 'x', numlen) == NULL && memchr(text, 'X', numlen) == NULL;
    if (u->exp10 != 0 && decimal) {
        char scaled[128];
        const char *e = NULL;
        for (size_t k = 0; k < numlen; ++k)
            if (text[k] == 'e' || text[k] == 'E')
                e = text + k;
        const long ex = e ? strtol(e + 1, NULL, 10) : 0;
        const size_t mant = e ? (size_t)(e - text) : numlen;
        if (mant <= 80 && ex > -100000 && ex < 100000) {
            snprintf(scaled, sizeof scaled, "%.*se%ld", (int)mant, text, ex + u->exp10);
            v = strtod(scaled, NULL);
        } else {
            v *= pow(10.0, u->exp10);
        }
    } else {
        v *= pow(10.0, u->exp10);
    }
    v *= u->factor;
    if (!isfinite(v) || (v != 0.0 && fabs(v) < DBL_MIN)) {
        usm_io_msg(msg, "%s: \"%.*s\" is out of range for a double", field,
                   len > 200 ? 200 : (int)len, text);
        return USM_EINPUT;
    }
    *out = v;
    return USM_OK;
}
