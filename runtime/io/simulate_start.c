/* The start state of `usm simulate --from FILE` (see simulate_start.h). */
#define _POSIX_C_SOURCE 200809L
#include "usm_io.h"
#include "csv_out.h"
#include "io_msg.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <jansson.h>

#include "usm_io.h"
#include "core/units.h"

/* ---- --from FILE -------------------------------------------------------------- */

/* The column name without its " [unit]". */
static void bare_name(const char *field, char *out, size_t len)
{
    size_t n = 0;
    while (isspace((unsigned char)*field))
        ++field;
    while (field[n] && field[n] != '[' && n + 1 < len)
        ++n;
    while (n > 0 && isspace((unsigned char)field[n - 1]))
        --n;
    memcpy(out, field, n);
    out[n] = '\0';
}

/* The SI value of v given in the column's " [unit]": a file written with
 * --units rpm,deg continues a run as one written in SI.  USM_EINPUT for a
 * unit the table does not know: reading it as SI would be a silent error. */
static int column_si(const char *field, const char *column, double *v, char msg[USM_IO_MSG_LEN])
{
    const char *open = strchr(column, '['), *close = open ? strchr(open, ']') : NULL;
    char key[32];
    if (!open)
        return USM_OK;
    if (!close || !usm_unit_key(open + 1, (size_t)(close - open - 1), key, sizeof key)) {
        usm_io_msg(msg, "%s: the header's unit \"%s\" is not a unit", field, column);
        return USM_EINPUT;
    }
    for (int k = 0; k < usm_unit_rows; ++k) {
        const usm_unit_row *u = &usm_unit_table[k];
        char si[32];
        usm_unit_key(u->si, strlen(u->si), si, sizeof si);
        if (strcmp(si, key) == 0)
            return USM_OK;
        if (strcmp(u->name, key) == 0) {
            double scale;
            usm_unit_at(k, NULL, NULL, &scale);
            *v *= scale;
            return USM_OK;
        }
    }
    usm_io_msg(msg, "%s: the header's unit [%s] is not a unit usm knows: the value cannot be "
               "read in SI", field, key);
    return USM_EINPUT;
}

typedef struct start_state {
    double x[USM_MAX_NX];
    int have[USM_MAX_NX];
    double t;
    int have_t;
    double rotor_angle;
    int have_rotor_angle;
} start_state;

/* Store `value` under `name` if it is a state variable (or t, or the stick
 * model's phi_R).  1 if used. */
static int assign(const usm_model *m, start_state *st, const char *name, double value)
{
    if (strcmp(name, "t") == 0) {
        st->t = value;
        st->have_t = 1;
        return 1;
    }
    for (int i = 0; i < m->nx; ++i)
        if (strcmp(name, m->state_names[i]) == 0) {
            st->x[i] = value;
            st->have[i] = 1;
            return 1;
        }
    if (strcmp(name, "phi_R") == 0) {
        st->rotor_angle = value;
        st->have_rotor_angle = 1;
        return 1;
    }
    return 0;
}

static int read_csv_state(const char *path, FILE *f, const usm_model *m, start_state *st,
                          char msg[USM_IO_MSG_LEN])
{
    char *line = NULL, *last = NULL;
    size_t cap = 0;
    ssize_t len;
    char *names[64], *values[64];
    char header[65536];
    int nnames, nvalues;
    long lineno = 0, last_lineno = 0;
    if ((len = getline(&line, &cap, f)) < 0) {
        free(line);
        usm_io_msg(msg, "%s: empty file", path);
        return USM_EINPUT;
    }
    ++lineno;
    snprintf(header, sizeof header, "%s", line);
    while ((len = getline(&line, &cap, f)) >= 0) {
        ++lineno;
        if (strspn(line, " \t\r\n") == (size_t)len)
            continue;
        free(last);
        last = strdup(line);
        last_lineno = lineno;
        if (!last) {
            free(line);
            usm_io_msg(msg, "out of memory");
            return USM_EFAILED;
        }
    }
    free(line);
    if (!last) {
        usm_io_msg(msg, "%s: no data row after the header", path);
        return USM_EINPUT;
    }
    nnames = usm_csv_split(header, names, 64);
    nvalues = usm_csv_split(last, values, 64);
    if (nnames < 0 || nvalues != nnames) {
        usm_io_msg(msg, "%s:%ld: %d fields, the header has %d", path, last_lineno, nvalues,
                nnames);
        free(last);
        return USM_EINPUT;
    }
    for (int k = 0; k < nnames; ++k) {
        char name[64], field[256];
        double v;
        bare_name(names[k], name, sizeof name);
        if (!assign(m, st, name, 0.0))
            continue;
        if (values[k][0] == '\0')
            continue;
        snprintf(field, sizeof field, "%s:%ld: %s", path, last_lineno, name);
        if (usm_parse_number(field, values[k], strlen(values[k]), &v, msg) != USM_OK ||
            column_si(field, names[k], &v, msg) != USM_OK) {
            free(last);
            return USM_EINPUT;
        }
        assign(m, st, name, v);
    }
    free(last);
    return USM_OK;
}

static int json_number(const json_t *v, double *out)
{
    if (!json_is_number(v))
        return -1;
    *out = json_number_value(v);
    return isfinite(*out) ? 0 : -1;
}

static int read_json_state(const char *path, const usm_model *m, start_state *st,
                           char msg[USM_IO_MSG_LEN])
{
    json_error_t err;
    json_t *root = json_load_file(path, JSON_REJECT_DUPLICATES, &err), *obj, *v;
    const char *key;
    int rc = USM_OK;
    if (!root) {
        usm_io_msg(msg, "%s:%d:%d: malformed JSON: %s", path, err.line, err.column, err.text);
        return USM_EINPUT;
    }
    obj = root;
    if (json_is_object(root) && json_is_object(json_object_get(root, "final_state")))
        obj = json_object_get(root, "final_state"); /* a `usm simulate --json` summary */
    if (!json_is_object(obj)) {
        usm_io_msg(msg, "%s: expected a JSON object", path);
        json_decref(root);
        return USM_EINPUT;
    }
    if ((v = json_object_get(root, "model")) && json_is_string(v) &&
        strcmp(json_string_value(v), m->name) != 0) {
        usm_io_msg(msg, "%s: the state is of model %s, not %s", path, json_string_value(v),
                m->name);
        json_decref(root);
        return USM_EINPUT;
    }
    json_object_foreach(obj, key, v) {
        double d;
        if (strcmp(key, "x") == 0) {
            if (!json_is_array(v) || (int)json_array_size(v) != m->nx) {
                usm_io_msg(msg, "%s: \"x\" must be a list of %d numbers (model %s)", path,
                        m->nx, m->name);
                rc = USM_EINPUT;
                break;
            }
            for (int i = 0; i < m->nx; ++i) {
                if (json_number(json_array_get(v, (size_t)i), &d) != 0) {
                    usm_io_msg(msg, "%s: \"x\"[%d] is not a finite number", path, i);
                    rc = USM_EINPUT;
                    break;
                }
                st->x[i] = d;
                st->have[i] = 1;
            }
            if (rc != USM_OK)
                break;
            continue;
        }
        if (!assign(m, st, key, 0.0))
            continue; /* other keys (names, model, ...) are allowed */
        if (json_number(v, &d) != 0) {
            usm_io_msg(msg, "%s: \"%s\" is not a finite number", path, key);
            rc = USM_EINPUT;
            break;
        }
        assign(m, st, key, d);
    }
    json_decref(root);
    return rc;
}

int usm_sim_read_start(const char *path, const usm_model *m, usm_sim_options *opt,
                       char msg[USM_IO_MSG_LEN])
{
    start_state st;
    int c, rc;
    FILE *f = fopen(path, "r");
    memset(&st, 0, sizeof st);
    if (!f) {
        usm_io_msg(msg, "%s: %s", path, strerror(errno));
        return USM_EINPUT;
    }
    do
        c = fgetc(f);
    while (c != EOF && isspace(c));
    if (c == '{') {
        fclose(f);
        rc = read_json_state(path, m, &st, msg);
    } else {
        rewind(f);
        rc = read_csv_state(path, f, m, &st, msg);
        fclose(f);
    }
    if (rc != USM_OK)
        return rc;
    for (int i = 0; i < m->nx; ++i)
        if (!st.have[i]) {
            usm_io_msg(msg, "%s: no value for %s (model %s needs %d state variables)",
                    path, m->state_names[i], m->name, m->nx);
            return USM_EINPUT;
        }
    memcpy(opt->x0, st.x, sizeof st.x);
    opt->t0 = st.have_t ? st.t : 0.0;
    if (st.have_rotor_angle)
        opt->rotor_angle0 = st.rotor_angle;
    return USM_OK;
}

