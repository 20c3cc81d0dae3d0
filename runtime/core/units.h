/* core/units.h: the units table (usm_io.h's usm_unit_at, usm_parse_quantity). */
#ifndef USM_CORE_UNITS_H
#define USM_CORE_UNITS_H

#include <stddef.h>

/* One unit: `si` is the unit a contract gives (usm_param_table[].unit), `name`
 * what the user types, the value in SI = number x 10^exp10 x factor. */
typedef struct usm_unit_row {
    const char *si;
    const char *name;
    int exp10;
    double factor;
} usm_unit_row;

extern const usm_unit_row usm_unit_table[];
extern const int usm_unit_rows;

/* A unit as typed, made comparable with the table's names: `text` (len bytes)
 * without blanks, the micro signs (U+00B5, U+03BC) as u.  0 when it does not
 * fit `out` (size bytes). */
int usm_unit_key(const char *text, size_t len, char *out, size_t size);

#endif /* USM_CORE_UNITS_H */
