/* core/units.h: the units table (usm_io.h's usm_unit_at, usm_parse_quantity). */
#ifndef USM_CORE_UNITS_H
#define USM_CORE_UNITS_H

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

#endif /* USM_CORE_UNITS_H */
