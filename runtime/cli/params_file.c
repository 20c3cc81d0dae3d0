/* Parameter files: a JSON object {"NAME": number, ...}. */
#include "params_file.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <jansson.h>

static const char *type_name(const json_t *v)
{
    switch (json_typeof(v)) {
    case JSON_OBJECT: return "an object";
    case JSON_ARRAY: return "an array";
    case JSON_STRING: return "a string";
    case JSON_INTEGER:
    case JSON_REAL: return "a number";
    case JSON_TRUE:
    case JSON_FALSE: return "a boolean";
    case JSON_NULL: return "null";
    }
    return "an unknown JSON value";
}

int cli_params_file_read(const char *path, usm_params *p, char msg[CLI_MSG_LEN])
{
    json_error_t err;
    json_t *root;
    const char *key;
    json_t *value;
    int status = USM_OK;
    /* Open it ourselves: jansson's own open error has no errno to report. */
    FILE *fp = fopen(path, "rb");
    if (!fp) {
        cli_msg(msg, "%s: cannot open parameter file: %s", path, strerror(errno));
        return USM_EINPUT;
    }
    /* A repeated name is almost certainly an editing mistake; say so rather
     * than silently keeping the last value. */
    errno = 0;
    root = json_loadf(fp, JSON_REJECT_DUPLICATES, &err);
    if (!root && ferror(fp)) {
        /* e.g. a directory: fopen succeeds, reading fails. */
        int e = errno;
        fclose(fp);
        cli_msg(msg, "%s: cannot read parameter file: %s", path,
                e ? strerror(e) : "read error");
        return USM_EINPUT;
    }
    fclose(fp);
    if (!root) {
        if (err.line > 0)
            cli_msg(msg, "%s:%d:%d: malformed JSON: %s", path, err.line, err.column, err.text);
        else
            cli_msg(msg, "%s: malformed JSON: %s", path, err.text);
        return USM_EINPUT;
    }
    if (!json_is_object(root)) {
        cli_msg(msg, "%s: malformed parameter file: expected a JSON object {\"NAME\": number}, got %s",
                path, type_name(root));
        json_decref(root);
        return USM_EINPUT;
    }
    json_object_foreach(root, key, value) {
        const usm_param_info *info = usm_params_find(key);
        double v;
        if (!info) {
            cli_msg(msg, "%s: %s: unknown parameter (see usm steady --help)", path, key);
            status = USM_EINPUT;
            break;
        }
        if (!json_is_number(value)) {
            cli_msg(msg, "%s: %s: expected a number, got %s", path, key, type_name(value));
            status = USM_EINPUT;
            break;
        }
        v = json_number_value(value);
        if (!isfinite(v)) { /* jansson rejects overflow, but be sure */
            cli_msg(msg, "%s: %s: is not a finite number", path, key);
            status = USM_EINPUT;
            break;
        }
        *usm_params_field(p, info) = v;
    }
    json_decref(root);
    return status;
}
