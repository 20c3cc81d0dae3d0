/* Parameter files: a JSON object {"NAME": number, ...}.
 *
 * The file is read by a small parser of its own rather than a general JSON
 * library so that each number reaches the same parser as --set NAME=VALUE
 * (number.h) as the text the user wrote: a library converts it first and
 * turns 1e-400 into 0 or an integer beyond 2^63 into an error of its own. */
#include "usm_io.h"
#include "io_msg.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "usm_io.h"

/* A member's key is kept up to this length; longer keys are no parameter. */
#define KEY_LEN 64
/* Nesting allowed inside a (wrong) array or object value. */
#define MAX_DEPTH 64

typedef struct scan {
    const char *s;
    size_t n, i;
    const char *path;
    char *msg;
} scan;

static void ws(scan *sc)
{
    while (sc->i < sc->n && strchr(" \t\r\n", sc->s[sc->i]) && sc->s[sc->i] != '\0')
        ++sc->i;
}

static int malformed(scan *sc, const char *reason)
{
    int line = 1, col = 1;
    for (size_t k = 0; k < sc->i && k < sc->n; ++k) {
        if (sc->s[k] == '\n') {
            ++line;
            col = 1;
        } else {
            ++col;
        }
    }
    usm_io_msg(sc->msg, "%s:%d:%d: malformed JSON: %s", sc->path, line, col, reason);
    return USM_EINPUT;
}

static int hex4(const char *p)
{
    int v = 0;
    for (int k = 0; k < 4; ++k) {
        char c = p[k];
        int d = c >= '0' && c <= '9' ? c - '0'
              : c >= 'a' && c <= 'f' ? c - 'a' + 10
              : c >= 'A' && c <= 'F' ? c - 'A' + 10 : -1;
        if (d < 0)
            return -1;
        v = 16 * v + d;
    }
    return v;
}

/* A string at sc->i (the opening quote).  Its first KEY_LEN-1 characters go to
 * key (non-ASCII as '?': no parameter name has any); *long_key when longer. */
static int string(scan *sc, char key[KEY_LEN], int *long_key)
{
    size_t used = 0;
    *long_key = 0;
    ++sc->i;
    for (;;) {
        char c;
        if (sc->i >= sc->n)
            return malformed(sc, "unterminated string");
        c = sc->s[sc->i];
        if (c == '"')
            break;
        if ((unsigned char)c < 0x20)
            return malformed(sc, "control character in a string");
        if (c == '\\') {
            if (sc->i + 1 >= sc->n)
                return malformed(sc, "unterminated string");
            c = sc->s[sc->i + 1];
            if (c == 'u') {
                int v = sc->i + 6 <= sc->n ? hex4(sc->s + sc->i + 2) : -1;
                if (v < 0)
                    return malformed(sc, "invalid \\u escape");
                if (v == 0)
                    return malformed(sc, "\\u0000 is not allowed");
                c = v < 0x80 ? (char)v : '?';
                sc->i += 6;
            } else {
                const char *from = strchr("\"\\/bfnrt", c);
                if (!from || c == '\0')
                    return malformed(sc, "invalid escape");
                c = "\"\\/\b\f\n\r\t"[from - "\"\\/bfnrt"];
                sc->i += 2;
            }
        } else {
            ++sc->i;
        }
        if (used + 1 < KEY_LEN)
            key[used++] = c;
        else
            *long_key = 1;
    }
    ++sc->i;
    key[used] = '\0';
    return USM_OK;
}

static size_t digits(scan *sc)
{
    size_t from = sc->i;
    while (sc->i < sc->n && sc->s[sc->i] >= '0' && sc->s[sc->i] <= '9')
        ++sc->i;
    return sc->i - from;
}

/* A JSON number (RFC 8259 grammar) at sc->i. */
static int number(scan *sc)
{
    if (sc->s[sc->i] == '-')
        ++sc->i;
    if (sc->i < sc->n && sc->s[sc->i] == '0')
        ++sc->i;
    else if (digits(sc) == 0)
        return malformed(sc, "invalid number");
    if (sc->i < sc->n && sc->s[sc->i] == '.') {
        ++sc->i;
        if (digits(sc) == 0)
            return malformed(sc, "invalid number");
    }
    if (sc->i < sc->n && (sc->s[sc->i] == 'e' || sc->s[sc->i] == 'E')) {
        ++sc->i;
        if (sc->i < sc->n && (sc->s[sc->i] == '+' || sc->s[sc->i] == '-'))
            ++sc->i;
        if (digits(sc) == 0)
            return malformed(sc, "invalid number");
    }
    return USM_OK;
}

/* An object member's `"key" :` at sc->i (after blanks). */
static int member_key(scan *sc, char key[KEY_LEN], int *long_key)
{
    ws(sc);
    if (sc->i >= sc->n || sc->s[sc->i] != '"')
        return malformed(sc, "expected a string as the key");
    if (string(sc, key, long_key) != USM_OK)
        return USM_EINPUT;
    ws(sc);
    if (sc->i >= sc->n || sc->s[sc->i] != ':')
        return malformed(sc, "expected ':'");
    ++sc->i;
    return USM_OK;
}

/* Any JSON value at sc->i; *kind names it for messages ("a number", ...). */
static int value(scan *sc, int depth, const char **kind)
{
    static const char *const lit[] = {"true", "false", "null"};
    char skip[KEY_LEN];
    int long_key;
    char c;
    ws(sc);
    if (sc->i >= sc->n)
        return malformed(sc, "expected a value, found the end of the file");
    c = sc->s[sc->i];
    if (c == '-' || (c >= '0' && c <= '9')) {
        *kind = "a number";
        return number(sc);
    }
    if (c == '"') {
        *kind = "a string";
        return string(sc, skip, &long_key);
    }
    for (int k = 0; k < 3; ++k) {
        size_t len = strlen(lit[k]);
        if (sc->n - sc->i >= len && memcmp(sc->s + sc->i, lit[k], len) == 0) {
            *kind = k < 2 ? "a boolean" : "null";
            sc->i += len;
            return USM_OK;
        }
    }
    if (c != '[' && c != '{')
        return malformed(sc, "expected a value");
    if (depth >= MAX_DEPTH)
        return malformed(sc, "nested too deeply");
    *kind = c == '[' ? "an array" : "an object";
    ++sc->i;
    ws(sc);
    if (sc->i < sc->n && sc->s[sc->i] == (c == '[' ? ']' : '}')) {
        ++sc->i;
        return USM_OK;
    }
    for (;;) {
        const char *inner;
        if (c == '{' && member_key(sc, skip, &long_key) != USM_OK)
            return USM_EINPUT;
        if (value(sc, depth + 1, &inner) != USM_OK)
            return USM_EINPUT;
        ws(sc);
        if (sc->i < sc->n && sc->s[sc->i] == ',') {
            ++sc->i;
            continue;
        }
        if (sc->i < sc->n && sc->s[sc->i] == (c == '[' ? ']' : '}')) {
            ++sc->i;
            return USM_OK;
        }
        return malformed(sc, c == '[' ? "expected ',' or ']'" : "expected ',' or '}'");
    }
}

/* The top-level object.  With p == NULL only the syntax is checked; with p
 * the members are checked and applied in order (the syntax known good). */
static int object(scan *sc, usm_params *p)
{
    unsigned char seen[USM_NPARAMS] = {0};
    const char *kind;
    sc->i = 0;
    ws(sc);
    if (sc->i < sc->n && sc->s[sc->i] != '{') {
        size_t at = sc->i;
        if (value(sc, 0, &kind) != USM_OK)
            return USM_EINPUT;
        usm_io_msg(sc->msg, "%s: malformed parameter file: expected a JSON object "
                         "{\"NAME\": number}, got %s", sc->path, kind);
        sc->i = at;
        return USM_EINPUT;
    }
    if (sc->i >= sc->n)
        return malformed(sc, "expected a JSON object, found the end of the file");
    ++sc->i;
    ws(sc);
    if (sc->i < sc->n && sc->s[sc->i] == '}')
        ++sc->i;
    else {
        for (;;) {
            char key[KEY_LEN];
            int long_key;
            size_t from;
            const usm_param_info *info;
            if (member_key(sc, key, &long_key) != USM_OK)
                return USM_EINPUT;
            ws(sc);
            from = sc->i;
            if (value(sc, 1, &kind) != USM_OK)
                return USM_EINPUT;
            if (p) {
                char field[KEY_LEN + 16];
                double v;
                info = long_key ? NULL : usm_params_find(key);
                if (!info) {
                    usm_io_msg(sc->msg, "%s: %s%s: unknown parameter (see usm steady --help)",
                            sc->path, key, long_key ? "..." : "");
                    return USM_EINPUT;
                }
                if (seen[info - usm_param_table]++) {
                    usm_io_msg(sc->msg, "%s: %s: duplicate name (a parameter may be given once)",
                            sc->path, key);
                    return USM_EINPUT;
                }
                if (strcmp(kind, "a number") != 0) {
                    usm_io_msg(sc->msg, "%s: %s: expected a number, got %s", sc->path, key, kind);
                    return USM_EINPUT;
                }
                snprintf(field, sizeof field, "%s", key);
                {
                    char inner[USM_IO_MSG_LEN];
                    if (usm_parse_number(field, sc->s + from, sc->i - from, &v, inner) != USM_OK) {
                        usm_io_msg(sc->msg, "%s: %.900s", sc->path, inner);
                        return USM_EINPUT;
                    }
                }
                *usm_params_field(p, info) = v;
            }
            ws(sc);
            if (sc->i < sc->n && sc->s[sc->i] == ',') {
                ++sc->i;
                continue;
            }
            if (sc->i < sc->n && sc->s[sc->i] == '}') {
                ++sc->i;
                break;
            }
            return malformed(sc, "expected ',' or '}'");
        }
    }
    ws(sc);
    if (sc->i < sc->n)
        return malformed(sc, "text after the object");
    return USM_OK;
}

int usm_params_parse_text(const char *path, const char *text, size_t len, usm_params *p,
                     char msg[USM_IO_MSG_LEN])
{
    scan sc = {text, len, 0, path, msg};
    usm_params tmp = *p;
    /* Syntax first: a file with a typo anywhere is reported as malformed
     * before any of its names; and nothing is set unless everything is good. */
    if (object(&sc, NULL) != USM_OK || object(&sc, &tmp) != USM_OK)
        return USM_EINPUT;
    *p = tmp;
    return USM_OK;
}

int usm_params_read_file(const char *path, usm_params *p, char msg[USM_IO_MSG_LEN])
{
    char *text = NULL;
    size_t len = 0, cap = 0;
    int status;
    FILE *fp = fopen(path, "rb");
    if (!fp) {
        usm_io_msg(msg, "%s: cannot open parameter file: %s", path, strerror(errno));
        return USM_EINPUT;
    }
    for (;;) {
        size_t got;
        if (len == cap) {
            char *more = cap < (1u << 24) ? realloc(text, cap ? 2 * cap : 4096) : NULL;
            if (!more) {
                usm_io_msg(msg, "%s: parameter file too large", path);
                free(text);
                fclose(fp);
                return USM_EINPUT;
            }
            text = more;
            cap = cap ? 2 * cap : 4096;
        }
        errno = 0;
        got = fread(text + len, 1, cap - len, fp);
        len += got;
        if (got == 0)
            break;
    }
    if (ferror(fp)) {
        /* e.g. a directory: fopen succeeds, reading fails. */
        int e = errno;
        usm_io_msg(msg, "%s: cannot read parameter file: %s", path, e ? strerror(e) : "read error");
        free(text);
        fclose(fp);
        return USM_EINPUT;
    }
    fclose(fp);
    status = usm_params_parse_text(path, text, len, p, msg);
    free(text);
    return status;
}
