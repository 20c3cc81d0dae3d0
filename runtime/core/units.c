/* The units a value may be typed in (usm_io.h, usm_unit_at): one table for
 * the parser of values with units (io/number.c) and for the library's hint at
 * the unit a value out of its parameter's range was likely meant in
 * (core/params.c). */
#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "usm_io.h"
#include "units.h"

/* The units a value may be typed in, by physical dimension: `si` is the
 * unit a contract gives (usm_param_table[].unit, the outputs' units), `name`
 * what the user types (compared with blanks removed and a micro sign read as
 * u), the value in SI = number x 10^exp10 x factor.  The SI unit itself is the
 * first row of its dimension.  README.md and docs/cli.md show this table. */
#define USM_PI 3.14159265358979323846

const usm_unit_row usm_unit_table[] = {
    {"N m", "Nm", 0, 1},          {"N m", "mNm", -3, 1},     {"N m", "Nmm", -3, 1},
    {"N m", "uNm", -6, 1},        {"N", "N", 0, 1},          {"N", "kN", 3, 1},
    {"N", "mN", -3, 1},           {"N", "uN", -6, 1},        {"N/m", "N/m", 0, 1},
    {"N/m", "kN/m", 3, 1},        {"N/m", "MN/m", 6, 1},     {"N/m", "N/mm", 3, 1},
    {"N/m", "N/um", 6, 1},        {"N s/m", "Ns/m", 0, 1},   {"N s/m", "Ns/mm", 3, 1},
    {"N m/rad", "Nm/rad", 0, 1},  {"N m/rad", "mNm/rad", -3, 1},
    {"N m/rad", "Nmm/rad", -3, 1}, {"N m s/rad", "Nms/rad", 0, 1},
    {"N m s/rad", "mNms/rad", -3, 1}, {"N m s/rad", "uNms/rad", -6, 1},
    {"m", "m", 0, 1},             {"m", "cm", -2, 1},        {"m", "mm", -3, 1},
    {"m", "um", -6, 1},           {"m", "nm", -9, 1},        {"kg m^2", "kgm^2", 0, 1},
    {"kg m^2", "kgmm^2", -6, 1},  {"kg m^2", "gcm^2", -7, 1}, {"kg m^2", "gmm^2", -9, 1},
    {"kg", "kg", 0, 1},           {"kg", "g", -3, 1},        {"kg", "mg", -6, 1},
    {"Hz", "Hz", 0, 1},           {"Hz", "kHz", 3, 1},       {"Hz", "MHz", 6, 1},
    {"1", "%", -2, 1},            {"s/m", "s/m", 0, 1},      {"s/m", "s/mm", 3, 1},
    {"s/m", "ms/m", -3, 1},       {"rad", "rad", 0, 1},      {"rad", "mrad", -3, 1},
    {"rad", "urad", -6, 1},       {"rad", "deg", 0, USM_PI / 180}, {"rad", "\xc2\xb0", 0, USM_PI / 180},
    {"s", "s", 0, 1},             {"s", "ms", -3, 1},        {"s", "us", -6, 1},
    {"1/s", "1/s", 0, 1},         {"1/s", "rad/s", 0, 1},    {"1/s", "rpm", 0, 2 * USM_PI / 60},
    {"W", "W", 0, 1},             {"W", "mW", -3, 1},
};
const int usm_unit_rows = (int)(sizeof usm_unit_table / sizeof usm_unit_table[0]);

int usm_unit_count(void)
{
    return usm_unit_rows;
}

int usm_unit_at(int k, const char **si, const char **name, double *scale)
{
    if (k < 0 || k >= usm_unit_rows)
        return USM_EINPUT;
    if (si)
        *si = usm_unit_table[k].si;
    if (name)
        *name = usm_unit_table[k].name;
    if (scale)
        *scale = pow(10.0, usm_unit_table[k].exp10) * usm_unit_table[k].factor;
    return USM_OK;
}

int usm_units_accepted(const char *si, char *buf, size_t len)
{
    size_t used = 0;
    int n = 0;
    if (len)
        buf[0] = '\0';
    for (int k = 0; si && k < usm_unit_rows; ++k) {
        if (strcmp(usm_unit_table[k].si, si) != 0)
            continue;
        int w = snprintf(buf + used, used < len ? len - used : 0, "%s%s", n ? ", " : "",
                         usm_unit_table[k].name);
        if (w > 0 && used + (size_t)w < len)
            used += (size_t)w;
        ++n;
    }
    return n;
}

int usm_unit_key(const char *text, size_t len, char *out, size_t size)
{
    size_t n = 0;
    for (size_t k = 0; k < len; ++k) {
        unsigned char c = (unsigned char)text[k];
        if (isspace(c))
            continue;
        if (k + 1 < len && ((c == 0xc2 && (unsigned char)text[k + 1] == 0xb5) ||
                            (c == 0xce && (unsigned char)text[k + 1] == 0xbc))) {
            c = 'u';
            ++k;
        }
        if (n + 1 >= size)
            return 0;
        out[n++] = (char)c;
    }
    out[n] = '\0';
    return 1;
}
