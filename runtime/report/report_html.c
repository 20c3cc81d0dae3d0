/* report.html: report.md turned into one self-contained page.  Only the
 * Markdown report.md uses is understood (headings, paragraphs, lists, block
 * quotes, tables, **bold**, *italic*, `code`, links, images); each image
 * NAME.png is replaced by the figure's NAME.svg, inlined, so the page needs
 * no other file and no network.  Equations are plain text, as in report.md. */
#define _POSIX_C_SOURCE 200809L

#include <ctype.h>
#include <stdlib.h>
#include <string.h>

#include "report_internal.h"
#include "io/template.h"

static const char *const style =
    "body{font-family:'DejaVu Sans',sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;"
    "line-height:1.45;color:#222}\n"
    "table{border-collapse:collapse;margin:1em 0;font-size:0.92em}\n"
    "th,td{border:1px solid #bbb;padding:0.25em 0.5em;vertical-align:top}\n"
    "th{background:#eee}\n"
    "code{background:#f3f3f3;padding:0 0.2em}\n"
    "blockquote{border-left:4px solid #c0392b;margin:1em 0;padding:0.2em 1em;background:#fbeeee}\n"
    "figure{margin:1.5em 0}\n"
    "figure svg{display:block;width:100%;max-width:1000px;height:auto;border:1px solid #ddd}\n"
    "figcaption{font-style:italic;margin-top:0.3em}\n";

static void escaped(FILE *out, const char *s, size_t n)
{
    for (size_t i = 0; i < n; ++i)
        switch (s[i]) {
        case '&': fputs("&amp;", out); break;
        case '<': fputs("&lt;", out); break;
        case '>': fputs("&gt;", out); break;
        case '"': fputs("&quot;", out); break;
        default: fputc(s[i], out);
        }
}

static void inline_md(FILE *out, const char *s, size_t n, const char *dir);

/* dir/NAME.svg without its XML prologue, or a note that it is missing, in a
   <figure> whose caption is the inline Markdown cap[0..cap_n). */
static void inline_svg(FILE *out, const char *dir, const char *src, size_t n, const char *cap,
                       size_t cap_n)
{
    char name[512], path[4096], msg[USM_IO_MSG_LEN];
    char *svg = NULL, *start;
    if (n > 4 && n < sizeof name && memcmp(src + n - 4, ".png", 4) == 0) {
        snprintf(name, sizeof name, "%.*s.svg", (int)(n - 4), src);
        if (usm_report_path(path, sizeof path, dir, name) == 0)
            svg = usm_template_read(path, msg);
    }
    fputs("<figure>", out);
    if (svg && (start = strstr(svg, "<svg")) != NULL) {
        fputs(start, out);
    } else {
        fputs("<p>[figure not rendered: ", out);
        escaped(out, src, n);
        fputs("]</p>", out);
    }
    fputs("<figcaption>", out);
    inline_md(out, cap, cap_n, dir);
    fputs("</figcaption></figure>", out);
    free(svg);
}

/* The inline Markdown of s[0..n). */
static void inline_md(FILE *out, const char *s, size_t n, const char *dir)
{
    int bold = 0, italic = 0;
    for (size_t i = 0; i < n; ++i) {
        const char c = s[i];
        if (c == '\\' && i + 1 < n && strchr("|*`_[]\\", s[i + 1])) {
            escaped(out, s + ++i, 1);
        } else if (c == '`') {
            const char *end = memchr(s + i + 1, '`', n - i - 1);
            size_t len = end ? (size_t)(end - s) - i - 1 : n - i - 1;
            fputs("<code>", out);
            escaped(out, s + i + 1, len);
            fputs("</code>", out);
            i += len + 1;
        } else if (c == '*' && i + 1 < n && s[i + 1] == '*') {
            fputs(bold ? "</strong>" : "<strong>", out);
            bold = !bold;
            ++i;
        } else if (c == '*' && (italic || (i + 1 < n && !isspace((unsigned char)s[i + 1])))) {
            fputs(italic ? "</em>" : "<em>", out);
            italic = !italic;
        } else if ((c == '[' || (c == '!' && i + 1 < n && s[i + 1] == '['))) {
            /* [text](href) or ![alt](src) */
            const int image = c == '!';
            const char *t = s + i + 1 + image;
            const char *close = memchr(t, ']', n - (size_t)(t - s));
            if (!close || close + 1 >= s + n || close[1] != '(' ||
                !memchr(close, ')', n - (size_t)(close - s))) {
                escaped(out, s + i, 1);
                continue;
            }
            {
                const char *href = close + 2;
                const char *end = memchr(href, ')', n - (size_t)(href - s));
                if (image) {
                    inline_svg(out, dir, href, (size_t)(end - href), t, (size_t)(close - t));
                } else {
                    fputs("<a href=\"", out);
                    escaped(out, href, (size_t)(end - href));
                    fputs("\">", out);
                    inline_md(out, t, (size_t)(close - t), dir);
                    fputs("</a>", out);
                }
                i = (size_t)(end - s);
            }
        } else {
            escaped(out, s + i, 1);
        }
    }
    if (italic)
        fputs("</em>", out);
    if (bold)
        fputs("</strong>", out);
}

/* One table row: cells split on unescaped '|'. */
static void table_row(FILE *out, const char *line, const char *cell_tag, const char *dir)
{
    const char *p = line + 1; /* after the leading '|' */
    fputs("<tr>", out);
    while (*p) {
        const char *q = p;
        while (*q && !(*q == '|' && q[-1] != '\\'))
            ++q;
        if (!*q)
            break;
        while (p < q && *p == ' ')
            ++p;
        fprintf(out, "<%s>", cell_tag);
        {
            const char *e = q;
            while (e > p && e[-1] == ' ')
                --e;
            inline_md(out, p, (size_t)(e - p), dir);
        }
        fprintf(out, "</%s>", cell_tag);
        p = q + 1;
    }
    fputs("</tr>\n", out);
}

static void heading(FILE *out, int level, const char *text, const char *dir)
{
    /* ids as GitHub makes them, so report.md's table of contents works here */
    fprintf(out, "<h%d id=\"", level);
    for (const char *c = text; *c; ++c)
        if (isalnum((unsigned char)*c))
            fputc(tolower((unsigned char)*c), out);
        else if (*c == ' ' || *c == '-')
            fputc('-', out);
    fputs("\">", out);
    inline_md(out, text, strlen(text), dir);
    fprintf(out, "</h%d>\n", level);
}

/* The kind of block a line of report.md belongs to. */
enum { NONE, PARA, UL, OL, QUOTE, TABLE };

static int line_kind(const char *line)
{
    const char *dot = strstr(line, ". ");
    if (line[0] == '|')
        return TABLE;
    if (strncmp(line, "- ", 2) == 0)
        return UL;
    if (dot && dot > line && strspn(line, "0123456789") == (size_t)(dot - line))
        return OL;
    if (strncmp(line, "> ", 2) == 0)
        return QUOTE;
    return strncmp(line, "<!--", 4) == 0 || line[0] == '#' ? NONE : PARA;
}

/* A line that is only an image, ![ALT](NAME.png): the figure, captioned once.
   report.md follows each figure with its caption paragraph "*ALT.* Vector
   version: ..."; when it does (after blank lines), that paragraph becomes the
   figure's caption and is consumed (*next moves past it), else ALT is the
   caption.  Returns 0 (nothing written) for any other line. */
static int figure_line(FILE *out, const char *line, char **next, const char *dir)
{
    const size_t len = strlen(line);
    const char *close, *src;
    char *p;
    size_t alt_n;
    if (len < 6 || strncmp(line, "![", 2) != 0 || line[len - 1] != ')' ||
        (close = strstr(line, "](")) == NULL || strchr(close + 2, ')') != line + len - 1)
        return 0;
    alt_n = (size_t)(close - line) - 2;
    src = close + 2;
    for (p = *next; p && *p == '\n'; ++p)
        ;
    if (p && p[0] == '*' && strncmp(p + 1, line + 2, alt_n) == 0 &&
        strncmp(p + 1 + alt_n, ".*", 2) == 0) {
        char *end = strchr(p, '\n');
        const size_t cap_n = end ? (size_t)(end - p) : strlen(p);
        inline_svg(out, dir, src, (size_t)(line + len - 1 - src), p, cap_n);
        *next = end ? end + 1 : NULL;
    } else {
        inline_svg(out, dir, src, (size_t)(line + len - 1 - src), line + 2, alt_n);
    }
    fputc('\n', out);
    return 1;
}

int usm_report_html_write(const char *md, const char *dir, FILE *out)
{
    static const char *const open_tag[] = {"", "<p>", "<ul>\n", "<ol>\n", "<blockquote>",
                                           "<table>\n"};
    static const char *const close_tag[] = {"", "</p>\n", "</ul>\n", "</ol>\n",
                                            "</blockquote>\n", "</table>\n"};
    char *text = strdup(md), *next;
    int open = NONE, row = 0;
    if (!text)
        return -1;
    fprintf(out, "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n"
                 "<title>usm report</title>\n<style>\n%s</style></head><body>\n", style);
    for (char *line = text; line; line = next) {
        int kind;
        const char *body;
        if ((next = strchr(line, '\n')) != NULL)
            *next++ = '\0';
        kind = line[0] ? line_kind(line) : NONE;
        if (kind != open || kind == NONE) { /* a blank line ends a block too */
            fputs(close_tag[open], out);
            open = NONE;
        }
        if (line[0] == '\0')
            continue;
        if (strncmp(line, "<!--", 4) == 0) { /* the marker comment */
            fprintf(out, "%s\n", line);
            continue;
        }
        if (line[0] == '#') {
            const int level = (int)strspn(line, "#");
            heading(out, level, line + level + (line[level] == ' '), dir);
            continue;
        }
        if (kind == PARA && open == NONE && figure_line(out, line, &next, dir))
            continue;
        body = kind == UL || kind == QUOTE ? line + 2 : kind == OL ? strstr(line, ". ") + 2 : line;
        if (open != kind) {
            fputs(open_tag[kind], out);
            open = kind;
            row = 0;
        } else if (kind == PARA || kind == QUOTE) {
            fputc('\n', out);
        }
        if (kind == TABLE) {
            if (row++ != 1) /* row 1 is the |---| line */
                table_row(out, line, row == 1 ? "th" : "td", dir);
        } else if (kind == UL || kind == OL) {
            fputs("<li>", out);
            inline_md(out, body, strlen(body), dir);
            fputs("</li>\n", out);
        } else {
            inline_md(out, body, strlen(body), dir);
        }
    }
    fputs(close_tag[open], out);
    fputs("</body></html>\n", out);
    free(text);
    return ferror(out) ? -1 : 0;
}
