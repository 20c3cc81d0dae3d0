/* The measurements of `usm fit --data FILE.csv` (usm_io.h, usm_fit_data_read).
 *
 * A header of "NAME [UNIT]" columns: a parameter's name is a condition of
 * each row, an output's name a measured value, "sigma_OUTPUT" its standard
 * deviation.  Values in a unit are converted to SI through the units table;
 * a unit that does not convert to the column's SI unit is refused, since
 * reading it as SI would be a silent error.  Each bad cell is one message
 * naming the line, the column and the reason. */
#define _POSIX_C_SOURCE 200809L
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/grow.h"
#include "core/units.h"
#include "csv_out.h"
#include "io_msg.h"
#include "usm_fit.h"
#include "usm_io.h"

#define SIGMA_PREFIX "sigma_"

/* What one header column is. */
typedef struct column {
    enum { COL_COND, COL_OUT, COL_SIGMA } kind;
    int index;          /* cond or out index in the data */
    double scale;       /* SI value of one unit of the column */
    char name[64];      /* as written, without the unit */
} column;

/* Trim blanks from both ends of s in place. */
static char *trim(char *s)
{
    while (isspace((unsigned char)*s))
        ++s;
    size_t n = strlen(s);
    while (n > 0 && isspace((unsigned char)s[n - 1]))
        s[--n] = '\0';
    return s;
}

/* The scale of the header's unit for a value wanted in SI unit si: 1 for no
 * unit or si itself; USM_EINPUT when the unit is unknown or of another
 * dimension. */
static int unit_scale(const char *where, const char *header, const char *si, double *scale,
                      char msg[USM_IO_MSG_LEN])
{
    const char *open = strchr(header, '['), *close = open ? strchr(open, ']') : NULL;
    char key[32], sikey[32], accepted[256];
    *scale = 1.0;
    if (!open)
        return USM_OK;
    if (!close || close[1 + strspn(close + 1, " \t")] != '\0' ||
        !usm_unit_key(open + 1, (size_t)(close - open - 1), key, sizeof key)) {
        usm_io_msg(msg, "%s: \"%s\" is not NAME [UNIT]", where, header);
        return USM_EINPUT;
    }
    usm_unit_key(si, strlen(si), sikey, sizeof sikey);
    if (strcmp(key, sikey) == 0 || (key[0] == '\0' && strcmp(si, "1") == 0))
        return USM_OK;
    for (int k = 0; k < usm_unit_rows; ++k) {
        const usm_unit_row *u = &usm_unit_table[k];
        if (strcmp(u->si, si) == 0 && strcmp(u->name, key) == 0) {
            usm_unit_at(k, NULL, NULL, scale);
            return USM_OK;
        }
    }
    if (usm_units_accepted(si, accepted, sizeof accepted) == 0)
        snprintf(accepted, sizeof accepted, "%s", si);
    usm_io_msg(msg, "%s: the unit [%s] does not convert to %s (accepted: %s)", where, key, si,
               accepted);
    return USM_EINPUT;
}

/* Resolve the header into columns; d's cond/out/has_sigma filled. */
static int read_header(const char *path, char **names, int n, column *cols, usm_fit_data *d,
                       char msg[USM_IO_MSG_LEN])
{
    int seen_param[USM_NPARAMS] = {0}, seen_out[USM_FIT_NOUTPUTS] = {0};
    int sigma_of[USM_FIT_NOUTPUTS];
    for (int k = 0; k < USM_FIT_NOUTPUTS; ++k)
        sigma_of[k] = -1;
    d->ncond = d->nout = 0;
    for (int c = 0; c < n; ++c) {
        char *h = trim(names[c]), where[160];
        size_t len = strcspn(h, "[");
        while (len > 0 && isspace((unsigned char)h[len - 1]))
            --len;
        if (len == 0 || len >= sizeof cols[c].name) {
            usm_io_msg(msg, "%s:1: column %d: %s", path, c + 1,
                       len ? "name too long" : "no name in the header");
            return USM_EINPUT;
        }
        memcpy(cols[c].name, h, len);
        cols[c].name[len] = '\0';
        const char *name = cols[c].name;
        snprintf(where, sizeof where, "%s:1: column %.60s", path, name);
        const usm_param_info *pi = usm_params_find(name);
        int o = usm_fit_output_find(name);
        const char *si;
        if (pi) {
            int k = usm_param_index(pi);
            if (seen_param[k]++) {
                usm_io_msg(msg, "%s: appears twice", where);
                return USM_EINPUT;
            }
            cols[c].kind = COL_COND;
            cols[c].index = d->ncond;
            d->cond[d->ncond++] = k;
            si = pi->unit;
        } else if (o >= 0) {
            if (seen_out[o]++) {
                usm_io_msg(msg, "%s: appears twice", where);
                return USM_EINPUT;
            }
            cols[c].kind = COL_OUT;
            cols[c].index = d->nout;
            d->out[d->nout++] = o;
            si = usm_fit_output_unit(o);
        } else if (strncmp(name, SIGMA_PREFIX, strlen(SIGMA_PREFIX)) == 0 &&
                   (o = usm_fit_output_find(name + strlen(SIGMA_PREFIX))) >= 0) {
            if (sigma_of[o] >= 0) {
                usm_io_msg(msg, "%s: appears twice", where);
                return USM_EINPUT;
            }
            sigma_of[o] = c;
            cols[c].kind = COL_SIGMA;
            cols[c].index = o; /* resolved to the output's column below */
            si = usm_fit_output_unit(o);
        } else {
            char known[512] = "";
            size_t used = 0;
            for (int k = 0; k < USM_FIT_NOUTPUTS && used < sizeof known; ++k)
                if (usm_fit_output_name(k))
                    used += (size_t)snprintf(known + used, sizeof known - used, "%s%s",
                                             used ? ", " : "", usm_fit_output_name(k));
            usm_io_msg(msg, "%s: neither a parameter nor a measured output (outputs: %s; "
                       "sigma_OUTPUT for a standard deviation)", where, known);
            return USM_EINPUT;
        }
        if (unit_scale(where, h, si, &cols[c].scale, msg) != USM_OK)
            return USM_EINPUT;
    }
    if (d->nout == 0) {
        usm_io_msg(msg, "%s:1: no measured column (an output such as speed [rpm], "
                   "rotor_speed [1/s], power_in [W])", path);
        return USM_EINPUT;
    }
    int given = 0;
    for (int c = 0; c < n; ++c)
        if (cols[c].kind == COL_SIGMA) {
            int o = cols[c].index, j = -1;
            for (int k = 0; k < d->nout; ++k)
                if (d->out[k] == o)
                    j = k;
            if (j < 0) {
                usm_io_msg(msg, "%s:1: column %s: its output column %s is missing", path,
                           cols[c].name, usm_fit_output_name(o));
                return USM_EINPUT;
            }
            cols[c].index = j;
            d->has_sigma[j] = 1;
            ++given;
        }
    if (given > 0 && given < d->nout)
        for (int k = 0; k < d->nout; ++k)
            if (!d->has_sigma[k]) {
                usm_io_msg(msg, "%s:1: column %s has no sigma_%s column while others have "
                           "theirs: give a sigma for every output or for none", path,
                           usm_fit_output_name(d->out[k]), usm_fit_output_name(d->out[k]));
                return USM_EINPUT;
            }
    return USM_OK;
}

/* One data row into row r of d. */
static int read_row(const char *path, long lineno, char **fields, int n, const column *cols,
                    usm_fit_data *d, int r, char msg[USM_IO_MSG_LEN])
{
    d->line[r] = lineno;
    for (int c = 0; c < n; ++c) {
        char *text = trim(fields[c]), where[200];
        double v;
        snprintf(where, sizeof where, "%s:%ld: column %s", path, lineno, cols[c].name);
        if (text[0] == '\0') {
            if (cols[c].kind == COL_COND) {
                usm_io_msg(msg, "%s: empty (a condition needs a value in every row)", where);
                return USM_EINPUT;
            }
            continue; /* an output not measured in this row; its sigma checked below */
        }
        if (usm_parse_number(where, text, strlen(text), &v, msg) != USM_OK)
            return USM_EINPUT;
        v *= cols[c].scale;
        if (cols[c].kind == COL_COND) {
            char pmsg[USM_MSG_LEN];
            if (usm_param_check_value(d->cond[cols[c].index], v, pmsg) != USM_OK) {
                usm_io_msg(msg, "%s:%ld: %s", path, lineno, pmsg);
                return USM_EINPUT;
            }
            d->x[(size_t)r * (size_t)d->ncond + (size_t)cols[c].index] = v;
        } else if (cols[c].kind == COL_OUT) {
            d->y[(size_t)r * (size_t)d->nout + (size_t)cols[c].index] = v;
        } else {
            if (!(v > 0)) {
                usm_io_msg(msg, "%s: \"%s\" is not a standard deviation (must be > 0)", where,
                           text);
                return USM_EINPUT;
            }
            d->sigma[(size_t)r * (size_t)d->nout + (size_t)cols[c].index] = v;
        }
    }
    for (int k = 0; k < d->nout; ++k) {
        size_t i = (size_t)r * (size_t)d->nout + (size_t)k;
        if (d->has_sigma[k] && !isnan(d->y[i]) && isnan(d->sigma[i])) {
            usm_io_msg(msg, "%s:%ld: column sigma_%s: empty where %s is measured", path, lineno,
                       usm_fit_output_name(d->out[k]), usm_fit_output_name(d->out[k]));
            return USM_EINPUT;
        }
    }
    return USM_OK;
}

int usm_fit_data_parse_text(const char *path, const char *text, size_t len, usm_fit_data **out,
                            char msg[USM_IO_MSG_LEN])
{
    char *buf = malloc(len + 1), *fields[USM_FIT_MAX_COLUMNS + 1];
    char *header[USM_FIT_MAX_COLUMNS + 1];
    column cols[USM_FIT_MAX_COLUMNS];
    usm_fit_data *d = NULL, probe;
    int nh, rows = 0, status = USM_EINPUT;
    *out = NULL;
    if (!buf) {
        usm_io_msg(msg, "out of memory");
        return USM_EFAILED;
    }
    memcpy(buf, text, len);
    buf[len] = '\0';
    if (memchr(text, '\0', len)) {
        usm_io_msg(msg, "%s: a NUL byte: not a text file", path);
        goto done;
    }
    /* lines: the header is the first line that is not blank or a comment */
    char *line = buf, *next;
    long lineno = 0, header_line = 0;
    for (; line; line = next) {
        next = strchr(line, '\n');
        if (next)
            *next++ = '\0';
        ++lineno;
        char *t = line + strspn(line, " \t\r");
        if (*t == '\0' || *t == '#')
            continue;
        header_line = lineno;
        break;
    }
    if (!line) {
        usm_io_msg(msg, "%s: empty file (a header and rows of measurements expected)", path);
        goto done;
    }
    if ((nh = usm_csv_split(line, header, USM_FIT_MAX_COLUMNS)) < 0) {
        usm_io_msg(msg, "%s:%ld: more than %d columns", path, header_line, USM_FIT_MAX_COLUMNS);
        goto done;
    }
    memset(&probe, 0, sizeof probe);
    if (read_header(path, header, nh, cols, &probe, msg) != USM_OK)
        goto done;
    /* count the rows, then read them */
    for (char *p = next; p && *p; ) {
        char *e = strchr(p, '\n');
        size_t n = e ? (size_t)(e - p) : strlen(p);
        size_t b = strspn(p, " \t\r");
        if (b < n && p[b] != '#')
            ++rows;
        p = e ? e + 1 : NULL;
    }
    if (rows == 0) {
        usm_io_msg(msg, "%s: no data row after the header", path);
        goto done;
    }
    if (!(d = usm_fit_data_alloc(rows, probe.ncond, probe.nout))) {
        usm_io_msg(msg, "out of memory");
        status = USM_EFAILED;
        goto done;
    }
    memcpy(d->cond, probe.cond, sizeof d->cond);
    memcpy(d->out, probe.out, sizeof d->out);
    memcpy(d->has_sigma, probe.has_sigma, sizeof d->has_sigma);
    int r = 0;
    for (line = next; line; line = next) {
        next = strchr(line, '\n');
        if (next)
            *next++ = '\0';
        ++lineno;
        char *t = line + strspn(line, " \t\r");
        if (*t == '\0' || *t == '#')
            continue;
        int nf = usm_csv_split(line, fields, USM_FIT_MAX_COLUMNS + 1);
        if (nf != nh) {
            usm_io_msg(msg, "%s:%ld: %d fields, the header has %d", path, lineno,
                       nf < 0 ? USM_FIT_MAX_COLUMNS + 1 : nf, nh);
            goto done;
        }
        if (read_row(path, lineno, fields, nf, cols, d, r, msg) != USM_OK)
            goto done;
        int any = 0;
        for (int k = 0; k < d->nout; ++k)
            any |= !isnan(d->y[(size_t)r * (size_t)d->nout + (size_t)k]);
        if (!any) {
            usm_io_msg(msg, "%s:%ld: no measured value in this row", path, lineno);
            goto done;
        }
        ++r;
    }
    *out = d;
    d = NULL;
    status = USM_OK;
done:
    usm_fit_data_free(d);
    free(buf);
    return status;
}

int usm_fit_data_read(const char *path, usm_fit_data **out, char msg[USM_IO_MSG_LEN])
{
    FILE *f = fopen(path, "rb");
    char *text = NULL;
    size_t len = 0, cap = 0;
    *out = NULL;
    if (!f) {
        usm_io_msg(msg, "%s: %s", path, strerror(errno));
        return USM_EINPUT;
    }
    for (;;) {
        void *grown = text;
        if (usm_grow(&grown, &cap, len + 65536 + 1, 1) != 0) {
            free(text);
            fclose(f);
            usm_io_msg(msg, "out of memory");
            return USM_EFAILED;
        }
        text = grown;
        size_t got = fread(text + len, 1, cap - len - 1, f);
        len += got;
        if (got == 0)
            break;
    }
    int bad = ferror(f);
    fclose(f);
    if (bad) {
        free(text);
        usm_io_msg(msg, "%s: read error", path);
        return USM_EINPUT;
    }
    int status = usm_fit_data_parse_text(path, text ? text : "", len, out, msg);
    free(text);
    return status;
}
