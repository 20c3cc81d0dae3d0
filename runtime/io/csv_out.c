/* The usm command's CSV dialect (see csv_out.h). */
#include "csv_out.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

const char *usm_shortest(char buf[32], double v)
{
    for (int prec = 6; prec <= 17; ++prec) {
        snprintf(buf, 32, "%.*g", prec, v);
        if (strtod(buf, NULL) == v)
            break;
    }
    return buf;
}

void usm_csv_header(FILE *f, const usm_csv_column *cols, int n)
{
    for (int k = 0; k < n; ++k) {
        fputs(k ? "," : "", f);
        fputs(cols[k].name, f);
        if (cols[k].unit)
            fprintf(f, " [%s]", cols[k].unit);
    }
    fputc('\n', f);
}

void usm_csv_num(FILE *f, int first, double v)
{
    char buf[32];
    if (!first)
        fputc(',', f);
    if (isfinite(v))
        fputs(usm_shortest(buf, v), f);
}

void usm_csv_bool(FILE *f, int first, int b)
{
    fputs(first ? "" : ",", f);
    fputs(b ? "true" : "false", f);
}

void usm_csv_text(FILE *f, int first, const char *s)
{
    if (!first)
        fputc(',', f);
    if (!strpbrk(s, ",\"\n")) {
        fputs(s, f);
        return;
    }
    fputc('"', f);
    for (; *s; ++s) {
        if (*s == '"')
            fputc('"', f);
        fputc(*s == '\n' ? ' ' : *s, f);
    }
    fputc('"', f);
}

void usm_csv_validity(FILE *f, int has, usm_validity v)
{
    if (!has) {
        fputs(",,", f);
        return;
    }
    usm_csv_bool(f, 0, v == USM_VALID);
    usm_csv_text(f, 0, usm_validity_name(v));
}
