/* A parameter's scatter as text with units (usm_tolerance.h,
 * usm_tolerance_vary_parse_units): the one reading of usm tolerance's
 * --vary, usm optimize's --scatter and the Python package's vary and
 * scatter.  The absolute numbers are written in SI for the study's own
 * usm_tolerance_vary_parse; relative widths (P%), unknown names and other
 * forms pass as they are (that parser says what is wrong with them). */
#include <stdio.h>
#include <string.h>

#include "usm_io.h"
#include "usm_tolerance.h"

static int in_si(const char *field, const char *text, char *si, size_t len,
                 char msg[USM_IO_MSG_LEN])
{
    const char *eq = strchr(text, '=');
    char name[64], fname[160], lo_text[64];
    double lo, hi;
    snprintf(si, len, "%s", text);
    if (!eq || (size_t)(eq - text) >= sizeof name)
        return USM_OK;
    snprintf(name, sizeof name, "%.*s", (int)(eq - text), text);
    const usm_param_info *info = usm_params_find(name);
    const char *d = eq + 1, *colon = strchr(d, ':');
    const size_t dl = strlen(d);
    if (!info || dl == 0 || d[dl - 1] == '%' || !colon)
        return USM_OK;
    snprintf(fname, sizeof fname, "%.80s %s", field, name);
    if (strncmp(d, "uniform:", 8) == 0 && (colon = strchr(d + 8, ':')) &&
        (size_t)(colon - d - 8) < sizeof lo_text) {
        snprintf(lo_text, sizeof lo_text, "%.*s", (int)(colon - d - 8), d + 8);
        if (usm_parse_quantity(fname, info->unit, lo_text, strlen(lo_text), &lo, msg) != USM_OK ||
            usm_parse_quantity(fname, info->unit, colon + 1, strlen(colon + 1), &hi, msg) !=
                USM_OK)
            return USM_EINPUT;
        snprintf(si, len, "%s=uniform:%.17g:%.17g", name, lo, hi);
    } else if (strncmp(d, "normal:", 7) == 0) {
        if (usm_parse_quantity(fname, info->unit, d + 7, strlen(d + 7), &lo, msg) != USM_OK)
            return USM_EINPUT;
        snprintf(si, len, "%s=normal:%.17g", name, lo);
    }
    return USM_OK;
}

int usm_tolerance_vary_parse_units(const char *field, const char *text, usm_tolerance_vary *v,
                                   char msg[USM_IO_MSG_LEN])
{
    char si[256], lib[USM_MSG_LEN];
    if (!text || strlen(text) >= 200) {
        memset(v, 0, sizeof *v);
        snprintf(msg, USM_IO_MSG_LEN, "%.80s \"%.64s...\": too long", field, text ? text : "");
        return USM_EINPUT;
    }
    if (in_si(field, text, si, sizeof si, msg) != USM_OK)
        return USM_EINPUT;
    if (usm_tolerance_vary_parse(si, v, lib) != USM_OK) {
        snprintf(msg, USM_IO_MSG_LEN, "%.80s %s", field, lib);
        return USM_EINPUT;
    }
    return USM_OK;
}
