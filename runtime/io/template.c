/* Text with named placeholders filled from a JSON object (see template.h). */
#include "template.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "usm.h"

#define MAX_DEPTH 8

typedef struct render {
    const char *tpl, *name;
    json_t *scope[MAX_DEPTH + 1]; /* scope[0] the data, then #each elements */
    int first[MAX_DEPTH + 1];     /* @first of each scope */
    int depth, row;
    FILE *out;                    /* NULL while skipping a false branch */
    char *msg;
} render;

static int fail(render *r, const char *at, const char *what, const char *tag, size_t len)
{
    int line = 1;
    for (const char *p = r->tpl; p < at; ++p)
        line += *p == '\n';
    usm_io_msg(r->msg, "%s:%d: %s {{%.*s}}", r->name, line, what, (int)(len > 80 ? 80 : len), tag);
    return USM_EFAILED;
}

/* The value at a dotted path in one object, or NULL. */
static json_t *lookup_in(json_t *v, const char *path, size_t len)
{
    while (v && len > 0) {
        const char *dot = memchr(path, '.', len);
        size_t n = dot ? (size_t)(dot - path) : len;
        char key[96];
        if (n >= sizeof key)
            return NULL;
        memcpy(key, path, n);
        key[n] = '\0';
        if (json_is_array(v)) {
            char *end;
            unsigned long i = strtoul(key, &end, 10);
            v = *end == '\0' && n > 0 ? json_array_get(v, i) : NULL;
        } else {
            v = json_object_get(v, key);
        }
        path += n + (dot != NULL);
        len -= n + (dot != NULL);
    }
    return v;
}

/* A path, innermost scope first (a key present with null is found: it is
 * printed n/a); @first as a boolean.  While skipping (out NULL) a name that
 * is not there counts as found: an empty #each has no element to look in. */
static json_t *lookup(render *r, const char *path, size_t len, int *found)
{
    *found = 1;
    if (len == 1 && path[0] == '.') /* the element itself, e.g. a string */
        return r->scope[r->depth];
    if (len == 6 && memcmp(path, "@first", 6) == 0)
        return r->first[r->depth] ? json_true() : json_false();
    for (int d = r->depth; d >= 0; --d) {
        json_t *v = lookup_in(r->scope[d], path, len);
        if (v)
            return v;
    }
    *found = r->out == NULL;
    return NULL;
}

static int truthy(json_t *v)
{
    switch (v ? json_typeof(v) : JSON_NULL) {
    case JSON_TRUE: return 1;
    case JSON_INTEGER:
    case JSON_REAL: return json_number_value(v) != 0;
    case JSON_STRING: return json_string_length(v) > 0;
    case JSON_ARRAY: return json_array_size(v) > 0;
    case JSON_OBJECT: return 1;
    default: return 0;
    }
}

static int valid_format(const char *f, size_t n)
{
    size_t i = 0;
    if (i < n && (f[i] == '+' || f[i] == ' '))
        ++i;
    if (i < n && f[i] == '.') {
        ++i;
        if (i >= n || !isdigit((unsigned char)f[i]))
            return 0;
        while (i < n && isdigit((unsigned char)f[i]))
            ++i;
    }
    return i + 1 == n && strchr("gfem", f[i]) != NULL;
}

/* x as %.Ng (spec: the flags and ".N" of FMT, N default 6), with as many more
 * digits as it takes for the text to lie on the same side of 1 as x: a
 * modulus 0.9999999 is not printed "1", nor 1.0000001 "1". */
static void put_modulus(FILE *out, double x, const char *fmt, size_t flen)
{
    char buf[64];
    size_t i = 0;
    const int sign = flen > 0 && (fmt[0] == '+' || fmt[0] == ' ') ? fmt[i++] : 0;
    int digits = 6;
    if (i < flen && fmt[i] == '.')
        digits = atoi(fmt + i + 1);
    if (digits < 1)
        digits = 1;
    for (int d = digits; d <= 17; ++d) {
        double y;
        if (sign)
            snprintf(buf, sizeof buf, sign == '+' ? "%+.*g" : "% .*g", d, x);
        else
            snprintf(buf, sizeof buf, "%.*g", d, x);
        y = strtod(buf, NULL);
        if ((x < 1) == (y < 1) && (x > 1) == (y > 1))
            break;
    }
    fputs(buf, out);
}

static void put_value(render *r, json_t *v, const char *fmt, size_t flen)
{
    if (!r->out)
        return;
    if (json_is_number(v) && isfinite(json_number_value(v)) && flen > 0 && fmt[flen - 1] == 'm') {
        put_modulus(r->out, json_number_value(v), fmt, flen);
    } else if (json_is_number(v) && isfinite(json_number_value(v))) {
        char spec[16] = "%.10g";
        if (flen > 0 && flen < 10) {
            spec[0] = '%';
            memcpy(spec + 1, fmt, flen);
            spec[flen + 1] = '\0';
        }
        fprintf(r->out, spec, json_number_value(v));
    } else if (json_is_string(v)) {
        const char *s = json_string_value(v);
        if (flen == 4 && memcmp(fmt, "cell", 4) == 0) {
            for (; *s; ++s)
                if (*s == '|')
                    fputs("\\|", r->out);
                else
                    fputc(*s == '\n' ? ' ' : *s, r->out);
        } else {
            fputs(s, r->out);
        }
    } else if (json_is_boolean(v)) {
        fputs(json_is_true(v) ? "yes" : "no", r->out);
    } else {
        fputs("n/a", r->out);
    }
}

/* Render from *p up to the closing tag `close` ("/each", "/if", or NULL for
 * the end of the text), leaving *p after it; with saw_else, an {{else}} also
 * ends the block and sets *saw_else. */
static int block(render *r, const char **p, const char *close, int *saw_else)
{
    const char *s = *p;
    for (;;) {
        const char *open = strstr(s, "{{");
        const char *end, *tag;
        size_t len;
        if (!open) {
            if (r->out)
                fputs(s, r->out);
            *p = s + strlen(s);
            return close ? fail(r, s, "missing closing tag for", close, strlen(close)) : USM_OK;
        }
        if (r->out)
            fwrite(s, 1, (size_t)(open - s), r->out);
        tag = open + 2;
        if (!(end = strstr(tag, "}}")))
            return fail(r, open, "unterminated placeholder", tag, strcspn(tag, "\n"));
        len = (size_t)(end - tag);
        s = end + 2;
        if (close && len == strlen(close) && memcmp(tag, close, len) == 0) {
            *p = s;
            return USM_OK;
        }
        if (len == 4 && memcmp(tag, "else", 4) == 0) {
            if (!saw_else || *saw_else)
                return fail(r, open, "unexpected", tag, len);
            *saw_else = 1;
            *p = s;
            return USM_OK;
        }
        if (len == 4 && memcmp(tag, "@row", 4) == 0) {
            if (r->out) /* a row skipped is not counted */
                fprintf(r->out, "%d", ++r->row);
            continue;
        }
        if (len > 6 && memcmp(tag, "#each ", 6) == 0) {
            int found;
            json_t *arr = lookup(r, tag + 6, len - 6, &found);
            FILE *saved = r->out;
            /* while skipping, the body is parsed once, not once per element:
             * the cost stays linear in the template however deep the nesting */
            size_t n = saved && json_is_array(arr) ? json_array_size(arr) : 0;
            const char *body = s;
            if (!found || (arr && !json_is_array(arr) && !json_is_null(arr)))
                return fail(r, open, found ? "not an array:" : "unknown name in", tag, len);
            if (r->depth >= MAX_DEPTH)
                return fail(r, open, "nested too deeply:", tag, len);
            ++r->depth;
            for (size_t i = 0; i < (n ? n : 1); ++i) {
                /* with no element the body is still parsed (errors show), not written */
                r->scope[r->depth] = n ? json_array_get(arr, i) : NULL;
                r->first[r->depth] = i == 0;
                r->out = n ? saved : NULL;
                s = body;
                if (block(r, &s, "/each", NULL) != USM_OK)
                    return USM_EFAILED;
            }
            r->out = saved;
            --r->depth;
            continue;
        }
        if ((len > 4 && memcmp(tag, "#if ", 4) == 0) ||
            (len > 8 && memcmp(tag, "#unless ", 8) == 0)) {
            const int neg = tag[1] == 'u';
            const size_t skip = neg ? 8 : 4;
            int found, other = 0;
            json_t *v = lookup(r, tag + skip, len - skip, &found);
            FILE *saved = r->out;
            int cond;
            if (!found)
                return fail(r, open, "unknown name in", tag, len);
            cond = truthy(v) != neg;
            r->out = cond ? saved : NULL;
            if (block(r, &s, "/if", &other) != USM_OK)
                return USM_EFAILED;
            if (other) {
                r->out = cond ? NULL : saved;
                if (block(r, &s, "/if", NULL) != USM_OK)
                    return USM_EFAILED;
            }
            r->out = saved;
            continue;
        }
        if (len == 0 || tag[0] == '#' || tag[0] == '/')
            return fail(r, open, "unexpected", tag, len);
        {
            const char *colon = memchr(tag, ':', len);
            const size_t plen = colon ? (size_t)(colon - tag) : len;
            const size_t flen = colon ? len - plen - 1 : 0;
            int found;
            json_t *v = lookup(r, tag, plen, &found);
            if (!found)
                return fail(r, open, "unknown name", tag, len);
            if (colon && !(flen == 4 && memcmp(colon + 1, "cell", 4) == 0) &&
                !valid_format(colon + 1, flen))
                return fail(r, open, "bad number format in", tag, len);
            put_value(r, v, colon ? colon + 1 : NULL, flen);
        }
    }
}

int usm_template_render(const char *tpl, const char *name, json_t *data, FILE *out,
                        char msg[USM_IO_MSG_LEN])
{
    render r;
    const char *p = tpl;
    memset(&r, 0, sizeof r);
    r.tpl = tpl;
    r.name = name;
    r.scope[0] = data;
    r.first[0] = 1;
    r.out = out;
    r.msg = msg;
    return block(&r, &p, NULL, NULL);
}

char *usm_template_read(const char *path, char msg[USM_IO_MSG_LEN])
{
    FILE *f = fopen(path, "rb");
    char *text = NULL;
    long len;
    if (!f) {
        usm_io_msg(msg, "%s: %s", path, strerror(errno));
        return NULL;
    }
    if (fseek(f, 0, SEEK_END) == 0 && (len = ftell(f)) >= 0 && fseek(f, 0, SEEK_SET) == 0 &&
        (text = malloc((size_t)len + 1)) != NULL && fread(text, 1, (size_t)len, f) == (size_t)len) {
        text[len] = '\0';
        fclose(f);
        return text;
    }
    usm_io_msg(msg, "%s: cannot read", path);
    free(text);
    fclose(f);
    return NULL;
}
