/* The paper's published values, read from data/paper_values.json (installed
 * as share/usm/paper_values.json), the one file that holds them: the report
 * and tests/solve/steady_paper_check.py both read it.  Misprints are kept as printed; the
 * report explains them. */
#include <string.h>

#include <jansson.h>

#include "io/data_dir.h"
#include "report_internal.h"

static int text(json_t *obj, const char *key, char *out, size_t len, const char *where,
                char msg[USM_IO_MSG_LEN])
{
    const char *s = json_string_value(json_object_get(obj, key));
    if (!s || strlen(s) >= len) {
        usm_io_msg(msg, "%s: \"%s\": missing, not a string or too long", where, key);
        return -1;
    }
    memcpy(out, s, strlen(s) + 1);
    return 0;
}

static int number(json_t *obj, const char *key, double *out, const char *where,
                  char msg[USM_IO_MSG_LEN])
{
    json_t *v = json_object_get(obj, key);
    if (!json_is_number(v)) {
        usm_io_msg(msg, "%s: \"%s\": missing or not a number", where, key);
        return -1;
    }
    *out = json_number_value(v);
    return 0;
}

static int value(json_t *root, const char *key, usm_report_published *p, const char *path,
                 char msg[USM_IO_MSG_LEN])
{
    char where[4200];
    json_t *o = json_object_get(root, key);
    snprintf(where, sizeof where, "%s: %s", path, key);
    if (!json_is_object(o)) {
        usm_io_msg(msg, "%s: missing or not an object", where);
        return -1;
    }
    return text(o, "where", p->where, sizeof p->where, where, msg) ||
                   text(o, "what", p->what, sizeof p->what, where, msg) ||
                   text(o, "printed", p->printed, sizeof p->printed, where, msg) ||
                   text(o, "unit", p->unit, sizeof p->unit, where, msg) ||
                   number(o, "value", &p->value, where, msg)
               ? -1
               : 0;
}

static int table(json_t *root, const char *key, usm_report_published_multiplier *t, int cap, int *n,
                 const char *path, char msg[USM_IO_MSG_LEN])
{
    char where[4200];
    json_t *a = json_object_get(root, key);
    size_t i;
    json_t *o;
    snprintf(where, sizeof where, "%s: %s", path, key);
    if (!json_is_array(a) || json_array_size(a) == 0 || json_array_size(a) > (size_t)cap) {
        usm_io_msg(msg, "%s: want an array of 1 to %d multipliers", where, cap);
        return -1;
    }
    json_array_foreach(a, i, o) {
        usm_report_published_multiplier *m = &t[i];
        if (text(o, "label", m->label, sizeof m->label, where, msg) ||
            text(o, "printed", m->printed, sizeof m->printed, where, msg) ||
            text(o, "modulus_printed", m->modulus_printed, sizeof m->modulus_printed, where, msg) ||
            number(o, "re", &m->re, where, msg) || number(o, "im", &m->im, where, msg) ||
            number(o, "modulus", &m->modulus, where, msg))
            return -1;
    }
    *n = (int)json_array_size(a);
    return 0;
}

int usm_report_paper_load(usm_report_paper *paper, char msg[USM_IO_MSG_LEN])
{
    static const char *const keys[] = {"theta3", "alpha3", "beta3", "speed4", "theta4", "alpha4",
                                       "beta4", "f_max", "slip_load", "speed_ratio"};
    usm_report_published *const slot[] = {&paper->theta3, &paper->alpha3, &paper->beta3, &paper->speed4,
                                      &paper->theta4, &paper->alpha4, &paper->beta4, &paper->f_max,
                                      &paper->slip_load, &paper->speed_ratio};
    char path[4096];
    json_error_t err;
    json_t *root;
    int bad = 0;
    if (usm_data_path("paper_values.json", path, sizeof path) != 0) {
        usm_io_msg(msg, "%s: the paper's values are not installed (set USM_DATA_DIR to the "
                     "directory holding paper_values.json)", path);
        return USM_EFAILED;
    }
    if (!(root = json_load_file(path, JSON_REJECT_DUPLICATES, &err))) {
        usm_io_msg(msg, "%s:%d: %s", path, err.line, err.text);
        return USM_EFAILED;
    }
    for (size_t k = 0; !bad && k < sizeof keys / sizeof keys[0]; ++k)
        bad = value(root, keys[k], slot[k], path, msg);
    bad = bad || table(root, "table3", paper->table3, 4, &paper->n3, path, msg) ||
          table(root, "table4", paper->table4, 6, &paper->n4, path, msg);
    json_decref(root);
    return bad ? USM_EFAILED : USM_OK;
}
