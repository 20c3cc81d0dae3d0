/* Parameter files: a JSON object {"NAME": number, ...}, read with jansson
 * (as the start state of io/simulate_start.c).
 *
 * Each number reaches the same parser as --set NAME=VALUE (usm_parse_number)
 * as the text the user wrote: converted by a JSON library first, 1e-400
 * would become 0 and 1e999 an error without the field's name.  So before
 * jansson reads the text, every number token (RFC 8259 grammar, outside
 * strings) is replaced by "0" and blanks of the same length (lines and
 * columns of jansson's messages stay those of the file), and the tokens that
 * are the top-level object's member values are kept, in order: jansson keeps
 * an object's members in the order of the text, so the k-th member whose
 * value is a number has the k-th such token.
 *
 * Rejected, with USM_EINPUT and the file's name in the message:
 *   - malformed JSON (jansson's reason, at LINE:COLUMN), comments, a NUL
 *     byte and text after the object included;
 *   - a name given twice ("duplicate name");
 *   - a top level that is not an object ("expected a JSON object");
 *   - an unknown name, a value that is not a number, a number that
 *     usm_parse_number refuses (not finite, overflow, underflow).
 * A number is in the parameter's SI unit; a string is a value with a unit,
 * as --set takes it ("f": "37.5 kHz", usm_parse_quantity). */
#include "core/grow.h"
#include "usm_io.h"
#include "io_msg.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include <jansson.h>

/* A member's key is shown up to this length in messages. */
#define KEY_LEN 64

/* The number tokens that are member values of the top-level object. */
typedef struct numbers {
    size_t n, cap;
    size_t *at, *len; /* offset and length in the text */
} numbers;

static int is_digit(char c) { return c >= '0' && c <= '9'; }

static size_t digits(const char *s, size_t n, size_t i)
{
    while (i < n && is_digit(s[i]))
        ++i;
    return i;
}

/* The length of the JSON number (RFC 8259 grammar) at s[0..n), or 0 when
 * the text there is no such number. */
static size_t number_len(const char *s, size_t n)
{
    size_t i = 0, j;
    if (i < n && s[i] == '-')
        ++i;
    if (i < n && s[i] == '0')
        ++i;
    else if ((j = digits(s, n, i)) == i)
        return 0;
    else
        i = j;
    if (i < n && s[i] == '.') {
        if ((j = digits(s, n, i + 1)) == i + 1)
            return 0;
        i = j;
    }
    if (i < n && (s[i] == 'e' || s[i] == 'E')) {
        ++i;
        if (i < n && (s[i] == '+' || s[i] == '-'))
            ++i;
        if ((j = digits(s, n, i)) == i)
            return 0;
        i = j;
    }
    return i;
}

/* The characters of a number: a run of them that is not one number ("01",
 * "1.", "1-2") is left to jansson, which rejects it. */
static int in_number(char c) { return c != '\0' && (is_digit(c) || strchr(".eE+-", c)); }

static int keep(numbers *nums, size_t at, size_t len)
{
    /* two arrays of one capacity: the same doubling for each */
    size_t cap_len = nums->cap;
    if (usm_grow((void **)&nums->len, &cap_len, nums->n + 1, sizeof *nums->len) != 0 ||
        usm_grow((void **)&nums->at, &nums->cap, nums->n + 1, sizeof *nums->at) != 0)
        return -1;
    nums->at[nums->n] = at;
    nums->len[nums->n++] = len;
    return 0;
}

/* Replace the number tokens of text (len bytes, a copy) by "0" and blanks;
 * those at depth 1 (the member values when the top level is an object) go
 * to nums.  0, or -1 when out of memory. */
static int mask_numbers(char *text, size_t len, numbers *nums)
{
    int depth = 0;
    for (size_t i = 0; i < len;) {
        const char c = text[i];
        if (c == '"') { /* a string: to its closing quote (jansson checks it) */
            for (++i; i < len && text[i] != '"'; ++i)
                if (text[i] == '\\')
                    ++i;
            ++i;
        } else if (c == '{' || c == '[') {
            ++depth, ++i;
        } else if (c == '}' || c == ']') {
            --depth, ++i;
        } else if (c == '-' || is_digit(c)) {
            size_t run = i + 1;
            while (run < len && in_number(text[run]))
                ++run;
            run -= i;
            if (number_len(text + i, run) == run) {
                if (depth == 1 && keep(nums, i, run) != 0)
                    return -1;
                text[i] = '0';
                memset(text + i + 1, ' ', run - 1);
            }
            i += run;
        } else {
            ++i;
        }
    }
    return 0;
}

static const char *kind_of(const json_t *v)
{
    switch (json_typeof(v)) {
    case JSON_OBJECT: return "an object";
    case JSON_ARRAY: return "an array";
    case JSON_STRING: return "a string";
    case JSON_INTEGER:
    case JSON_REAL: return "a number";
    case JSON_TRUE:
    case JSON_FALSE: return "a boolean";
    case JSON_NULL: break;
    }
    return "null";
}

/* A key as messages show it: at most KEY_LEN - 1 bytes ("..." after a longer
 * one, not cutting a UTF-8 sequence), control characters as '?'. */
static void key_text(const char *key, char out[KEY_LEN + 4])
{
    size_t n = strlen(key);
    const int cut = n >= KEY_LEN;
    if (cut) {
        n = KEY_LEN - 1;
        while (n > 0 && ((unsigned char)key[n] & 0xC0) == 0x80)
            --n;
    }
    for (size_t k = 0; k < n; ++k)
        out[k] = (unsigned char)key[k] < 0x20 || key[k] == 0x7f ? '?' : key[k];
    strcpy(out + n, cut ? "..." : "");
}

/* jansson's message on malformed text.  A duplicate name is named. */
static void malformed(const char *path, const json_error_t *err, char msg[USM_IO_MSG_LEN])
{
    const int col = err->column < 1 ? 1 : err->column;
    if (err->line < 1) { /* not about a place in the text: out of memory */
        usm_io_msg(msg, "%s: %s", path, err->text);
        return;
    }
    if (json_error_code(err) == json_error_duplicate_key) {
        /* "duplicate object key near '"NAME"'" */
        const char *near = strstr(err->text, "near '\"");
        const size_t n = near ? strlen(near + 7) : 0;
        if (n >= 2 && strcmp(near + 7 + n - 2, "\"'") == 0) {
            usm_io_msg(msg, "%s:%d:%d: %.*s: duplicate name (a parameter may be given once)",
                       path, err->line, col, (int)(n - 2), near + 7);
            return;
        }
        usm_io_msg(msg, "%s:%d:%d: duplicate name (a parameter may be given once): %s", path,
                   err->line, col, err->text);
        return;
    }
    usm_io_msg(msg, "%s:%d:%d: malformed JSON: %s", path, err->line, col, err->text);
}

/* The members of obj, in order, into *p; the k-th numeric value's text is
 * text[nums->at[k]] (nums->len[k] bytes). */
static int apply(const char *path, const char *text, json_t *obj, const numbers *nums,
                 usm_params *p, char msg[USM_IO_MSG_LEN])
{
    const char *key;
    json_t *v;
    size_t k = 0;
    json_object_foreach(obj, key, v) {
        char shown[KEY_LEN + 4];
        const usm_param_info *info = usm_params_find(key);
        key_text(key, shown);
        if (!info) {
            usm_io_msg(msg, "%s: %s: unknown parameter (see usm steady --help)", path, shown);
            return USM_EINPUT;
        }
        char inner[USM_IO_MSG_LEN];
        double x;
        if (json_is_string(v)) {
            if (usm_parse_quantity(shown, info->unit, json_string_value(v), json_string_length(v),
                                   &x, inner) != USM_OK) {
                usm_io_msg(msg, "%s: %.900s", path, inner);
                return USM_EINPUT;
            }
            *usm_params_field(p, info) = x;
            continue;
        }
        if (!json_is_number(v)) {
            usm_io_msg(msg, "%s: %s: expected a number (SI) or a string with a unit, got %s",
                       path, shown, kind_of(v));
            return USM_EINPUT;
        }
        if (k >= nums->n) { /* cannot happen: every number value was masked */
            usm_io_msg(msg, "%s: %s: number not found in the text", path, shown);
            return USM_EFAILED;
        }
        if (usm_parse_number(shown, text + nums->at[k], nums->len[k], &x, inner) != USM_OK) {
            usm_io_msg(msg, "%s: %.900s", path, inner);
            return USM_EINPUT;
        }
        ++k;
        *usm_params_field(p, info) = x;
    }
    return USM_OK;
}

int usm_params_parse_text(const char *path, const char *text, size_t len, usm_params *p,
                          char msg[USM_IO_MSG_LEN])
{
    numbers nums = {0, 0, NULL, NULL};
    char *masked = malloc(len + 1);
    json_t *root = NULL;
    json_error_t err;
    usm_params tmp = *p;
    int status = USM_EFAILED;
    if (masked && len > 0)
        memcpy(masked, text, len);
    if (!masked || mask_numbers(masked, len, &nums) != 0) {
        usm_io_msg(msg, "%s: out of memory", path);
        goto done;
    }
    /* Syntax first: a file with a typo anywhere is reported as malformed
     * before any of its names; and nothing is set unless everything is good. */
    status = USM_EINPUT;
    const char *nul = len > 0 ? memchr(text, '\0', len) : NULL;
    if (nul) { /* jansson reads past a NUL byte as if it were not there */
        int line = 1, col = 1;
        for (const char *c = text; c < nul; ++c) {
            if (*c == '\n') {
                ++line;
                col = 1;
            } else {
                ++col;
            }
        }
        usm_io_msg(msg, "%s:%d:%d: malformed JSON: a NUL byte", path, line, col);
        goto done;
    }
    if (!(root = json_loadb(masked, len, JSON_REJECT_DUPLICATES | JSON_DECODE_ANY, &err))) {
        malformed(path, &err, msg);
        goto done;
    }
    if (!json_is_object(root)) {
        usm_io_msg(msg, "%s: malformed parameter file: expected a JSON object "
                        "{\"NAME\": number}, got %s", path, kind_of(root));
        goto done;
    }
    if ((status = apply(path, text, root, &nums, &tmp, msg)) == USM_OK)
        *p = tmp;
done:
    json_decref(root);
    free(masked);
    free(nums.at);
    free(nums.len);
    return status;
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
            if (cap >= (1u << 24) || usm_grow((void **)&text, &cap, len + 4096, 1) != 0) {
                usm_io_msg(msg, "%s: parameter file too large", path);
                free(text);
                fclose(fp);
                return USM_EINPUT;
            }
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
