/* Display units (usm_io.h, --units): values shown to people in the unit they
 * chose, JSON left in SI.  The conversion works on the CSV text every
 * command already writes, so each table gets it once, here, instead of in
 * every writer: a column is converted when its header names a unit of a
 * chosen dimension ("rotor_speed [1/s]" -> "rotor_speed [rpm]"). */
#include <stdlib.h>
#include <string.h>

#include "usm.h"
#include "usm_io.h"
#include "core/units.h"
#include "csv_out.h"
#include "io_msg.h"

/* The entry of d that shows values in SI unit `si`: an angular rate in rad/s
 * is a rate in 1/s (the rotor speed's columns use both). */
static int entry(const usm_display *d, const char *si, size_t len)
{
    for (int i = 0; d && i < d->n; ++i) {
        const char *e = d->unit[i].si;
        if ((strlen(e) == len && strncmp(e, si, len) == 0) ||
            (strcmp(e, "1/s") == 0 && len == 5 && strncmp(si, "rad/s", 5) == 0))
            return i;
    }
    return -1;
}

double usm_display_value(const usm_display *d, const char *si, double v, const char **unit)
{
    const int i = si ? entry(d, si, strlen(si)) : -1;
    if (unit)
        *unit = i < 0 ? si : d->unit[i].name;
    return i < 0 ? v : v / d->unit[i].scale;
}

static void all_names(char *buf, size_t len)
{
    size_t used = 0;
    buf[0] = '\0';
    for (int k = 0; k < usm_unit_rows; ++k) {
        if (strcmp(usm_unit_table[k].si, "1") == 0)
            continue;
        int w = snprintf(buf + used, len - used, "%s%s", used ? ", " : "", usm_unit_table[k].name);
        if (w < 0 || used + (size_t)w >= len)
            break;
        used += (size_t)w;
    }
}

int usm_display_parse(const char *field, const char *spec, usm_display *d,
                      char msg[USM_IO_MSG_LEN])
{
    memset(d, 0, sizeof *d);
    const char *s = spec ? spec : "";
    char key[32];
    if (usm_unit_key(s, strlen(s), key, sizeof key) && (strcmp(key, "si") == 0 || strcmp(key, "SI") == 0))
        return USM_OK;
    for (;;) {
        const size_t len = strcspn(s, ",");
        if (!usm_unit_key(s, len, key, sizeof key) || key[0] == '\0') {
            usm_io_msg(msg, "%s: \"%s\": an empty or overlong unit name (a list like rpm,deg, or si)",
                       field, spec ? spec : "");
            return USM_EINPUT;
        }
        int row = -1;
        for (int k = 0; k < usm_unit_rows && row < 0; ++k)
            if (strcmp(usm_unit_table[k].name, key) == 0)
                row = k;
        if (row < 0) {
            char names[600];
            all_names(names, sizeof names);
            usm_io_msg(msg, "%s: \"%s\" is not a unit usm knows (units: %s)", field, key, names);
            return USM_EINPUT;
        }
        const usm_unit_row *u = &usm_unit_table[row];
        if (strcmp(u->si, "1") == 0) {
            usm_io_msg(msg, "%s: \"%s\" is a ratio, not a unit of one quantity: ratio columns "
                       "(efficiency, mu) stay ratios", field, key);
            return USM_EINPUT;
        }
        const int twice = entry(d, u->si, strlen(u->si));
        if (twice >= 0) {
            usm_io_msg(msg, "%s: %s and %s are both units of [%s]: choose one", field,
                       d->unit[twice].name, key, u->si);
            return USM_EINPUT;
        }
        if (d->n == USM_DISPLAY_MAX) {
            usm_io_msg(msg, "%s: more than %d units", field, USM_DISPLAY_MAX);
            return USM_EINPUT;
        }
        d->unit[d->n].si = u->si;
        d->unit[d->n].name = u->name;
        usm_unit_at(row, NULL, NULL, &d->unit[d->n].scale);
        ++d->n;
        if (s[len] == '\0')
            return USM_OK;
        s += len + 1;
    }
}

/* ---- the CSV text ------------------------------------------------------------- */

#define MAX_COLUMNS 256

typedef struct column {
    const char *name; /* in the header's text, not terminated */
    size_t name_len;
    int shown;        /* the entry of d, or -1: copied */
} column;

/* The end of the field starting at p (quotes respected): at ',', '\n' or end. */
static const char *field_end(const char *p, const char *end)
{
    if (p < end && *p == '"') {
        for (++p; p < end; ++p)
            if (*p == '"') {
                if (p + 1 < end && p[1] == '"')
                    ++p;
                else
                    return field_end(p + 1, end);
            }
        return end;
    }
    while (p < end && *p != ',' && *p != '\n')
        ++p;
    return p;
}

/* A number of a converted column, scaled; anything else (an empty field,
 * text) as it is. */
static void put_value(const usm_display *d, int shown, const char *p, size_t len, FILE *out)
{
    char buf[64], num[32];
    if (shown >= 0 && len > 0 && len < sizeof buf) {
        memcpy(buf, p, len);
        buf[len] = '\0';
        char *stop;
        const double v = strtod(buf, &stop);
        if (stop == buf + len) {
            fputs(usm_shortest(num, v / d->unit[shown].scale), out);
            return;
        }
    }
    fwrite(p, 1, len, out);
}

static int header(const usm_display *d, const char *p, const char *end, column *cols, FILE *out)
{
    int n = 0;
    for (;;) {
        const char *e = field_end(p, end);
        const char *open = NULL;
        for (const char *q = p; q + 1 < e; ++q)
            if (q[0] == ' ' && q[1] == '[')
                open = q;
        /* columns past MAX_COLUMNS are copied as they are, header and rows alike */
        const int shown = n < MAX_COLUMNS && open && e[-1] == ']'
                              ? entry(d, open + 2, (size_t)(e - 1 - (open + 2)))
                              : -1;
        if (n < MAX_COLUMNS) {
            cols[n].name = p;
            cols[n].name_len = (size_t)((open ? open : e) - p);
            cols[n].shown = shown;
            ++n;
        }
        if (shown >= 0)
            fprintf(out, "%.*s [%s]", (int)(open - p), p, d->unit[shown].name);
        else
            fwrite(p, 1, (size_t)(e - p), out);
        if (e >= end || *e != ',')
            return n;
        fputc(',', out);
        p = e + 1;
    }
}

static void row(const usm_display *d, const char *p, const char *end, const column *cols, int n,
                FILE *out)
{
    for (int k = 0;; ++k) {
        const char *e = field_end(p, end);
        put_value(d, k < n ? cols[k].shown : -1, p, (size_t)(e - p), out);
        if (e >= end || *e != ',')
            return;
        fputc(',', out);
        p = e + 1;
    }
}

/* "# TYPE ... at NAME = VALUE: what": VALUE in its column's unit shown. */
static void event(const usm_display *d, const char *p, const char *end, const column *cols,
                  int n, FILE *out)
{
    const char *at = NULL;
    for (const char *q = p; q + 4 <= end && !at; ++q)
        if (memcmp(q, " at ", 4) == 0)
            at = q + 4;
    const char *eq = at ? at : end;
    while (eq + 3 <= end && memcmp(eq, " = ", 3) != 0 && *eq != ':')
        ++eq;
    int shown = -1;
    if (at && eq + 3 <= end && memcmp(eq, " = ", 3) == 0)
        for (int k = 0; k < n && shown < 0; ++k)
            if (cols[k].name_len == (size_t)(eq - at) && memcmp(cols[k].name, at, cols[k].name_len) == 0)
                shown = cols[k].shown;
    if (shown < 0) {
        fwrite(p, 1, (size_t)(end - p), out);
        return;
    }
    const char *v = eq + 3, *colon = v;
    while (colon < end && *colon != ':')
        ++colon;
    fwrite(p, 1, (size_t)(v - p), out);
    put_value(d, shown, v, (size_t)(colon - v), out);
    fwrite(colon, 1, (size_t)(end - colon), out);
}

int usm_display_csv(const usm_display *d, const char *text, size_t len, FILE *out)
{
    column *cols = calloc(MAX_COLUMNS, sizeof *cols);
    int n = -1;
    const char *p = text, *end = text + len;
    if (!cols)
        return -1;
    while (p < end) {
        const char *nl = memchr(p, '\n', (size_t)(end - p));
        const char *e = nl ? nl : end;
        if (*p == '#')
            event(d, p, e, cols, n < 0 ? 0 : n, out);
        else if (n < 0)
            n = header(d, p, e, cols, out);
        else
            row(d, p, e, cols, n, out);
        if (nl)
            fputc('\n', out);
        p = nl ? nl + 1 : end;
    }
    free(cols);
    return ferror(out) ? -1 : 0;
}
