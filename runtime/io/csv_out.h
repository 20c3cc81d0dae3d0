/* csv_out.h: the one CSV dialect of the usm command (sweep, map, simulate and
 * the report's data files; see docs/cli.md "CSV files"):
 *   - one header line; a column with a unit is named "NAME [UNIT]" (SI units,
 *     "[1]" for a pure number), a column without a unit (yes/no, text, an
 *     index) just "NAME";
 *   - numbers as the shortest text that reads back exactly (at least 6
 *     digits); an empty field where a value does not exist (never "nan");
 *   - yes/no as true/false; text quoted when it holds a comma or a quote;
 *   - the names are the JSON keys of the same quantities, everywhere.
 * gnuplot addresses the columns by name: column("theta [rad]"). */
#ifndef USM_CSV_OUT_H
#define USM_CSV_OUT_H

#include <stdio.h>

#include "usm.h"

/* The shortest %g text (at least 6 digits) that reads back as exactly v, in
 * buf; returns buf. */
const char *usm_shortest(char buf[32], double v);
/* The same text; returns its length (one print and one parse, nearly always). */
int usm_shortest_len(char buf[32], double v);

/* Split a line of the dialect in place at its commas (files read back are
 * numbers and names, never quoted), the trailing newline dropped: the number
 * of fields, or -1 when it has more than max. */
int usm_csv_split(char *line, char **fields, int max);

/* One column of a header: unit NULL for a yes/no or text column. */
typedef struct usm_csv_column {
    const char *name;
    const char *unit;
} usm_csv_column;

/* The header line of n columns. */
void usm_csv_header(FILE *f, const usm_csv_column *cols, int n);

/* One field; `first` is nonzero for a row's first field (no separator). */
void usm_csv_num(FILE *f, int first, double v);
void usm_csv_bool(FILE *f, int first, int b);
void usm_csv_text(FILE *f, int first, const char *s);

/* The two validity columns, valid and invalid_reason (appended at the end of
 * a row): ",true," or ",false,REASON" (usm_validity_name); ",," for a row
 * without a solution (has = 0). */
void usm_csv_validity(FILE *f, int has, usm_validity v);

#endif /* USM_CSV_OUT_H */
