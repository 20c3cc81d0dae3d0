/* The usm command's CSV dialect (see csv_out.h). */
#include "csv_out.h"
#include "usm_io.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The text of usm_shortest, defined as the first %.{P}g with P = 6, 7, ...,
 * 17 that reads back as v, computed with one print and one or two parses
 * (the definition's loop took up to 12 of each): v printed once
 * with 17 significant digits (%.16e, exact), rounded from those digits to 16
 * and to 15 (where the dropped digits are exactly 5, 50, the rounding of v
 * itself is printed instead), each candidate parsed back.  A P-digit decimal
 * that reads back lies within half an ulp of v (< 2.3e-16 |v| for a normal
 * double), closer than half the 15-digit spacing (>= 5e-16 |v|): so when any
 * P <= 15 reads back, v rounded to 15 digits is that decimal padded with
 * zeros, and the shortest is those digits without their trailing zeros (n of
 * them, P = max(6, n)); else 16 digits when they read back, else 17 (which
 * always do).  The text is then written by %g's rules for that P (exponent
 * X: %e style when X < -4 or X >= P, else plain; trailing zeros removed).
 * A subnormal v (where an ulp is no longer 2^-52 |v|) takes the definition's
 * loop.  tests: test_io compares it with the definition over 10^6 doubles. */

/* The n digits d (decimal exponent x, sign neg) read back as v.  Where the
 * digits as an integer D are below 2^53 and the scale 10^k (k = x - n + 1)
 * has |k| <= 22, D and 10^|k| are exact doubles and one multiplication or
 * division, correctly rounded, gives the decimal's correctly rounded value:
 * what strtod returns (Clinger's fast path), at a fraction of its cost. */
static int reads_back(int neg, const char *d, int n, int x, double v)
{
    static const double pow10[23] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                     1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                     1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
    const int k = x - n + 1;
    if (n <= 16 && k >= -22 && k <= 22) {
        long long D = 0;
        for (int i = 0; i < n; ++i)
            D = 10 * D + (d[i] - '0');
        if (D <= (1LL << 53)) {
            const double r = k >= 0 ? (double)D * pow10[k] : (double)D / pow10[-k];
            return (neg ? -r : r) == v;
        }
    }
    char t[40], *o = t;
    if (neg)
        *o++ = '-';
    *o++ = d[0];
    *o++ = '.';
    memcpy(o, d + 1, (size_t)n - 1);
    o += n - 1;
    snprintf(o, 12, "e%d", x);
    return strtod(t, NULL) == v;
}

/* d17 (17 digits, exponent x) rounded to p digits into out (*xo its
 * exponent); where the dropped digits are exactly 5 followed by zeros (their
 * rounding depends on v's digits beyond the 17th), |v| printed to p digits. */
static void round_to(const char *d17, int x, int p, double v, char *out, int *xo)
{
    int up = d17[p] > '5', tie = d17[p] == '5';
    for (int k = p + 1; k < 17 && tie; ++k)
        if (d17[k] != '0')
            tie = 0, up = 1;
    if (tie) {
        char e[40];
        snprintf(e, sizeof e, "%.*e", p - 1, fabs(v));
        out[0] = e[0];
        memcpy(out + 1, e + 2, (size_t)p - 1);
        *xo = atoi(e + p + 2);
        return;
    }
    memcpy(out, d17, (size_t)p);
    *xo = x;
    for (int k = p - 1; up && k >= 0; --k) {
        if (out[k] == '9')
            out[k] = '0';
        else
            out[k]++, up = 0;
    }
    if (up) { /* 99..9 -> 100..0 */
        out[0] = '1';
        ++*xo;
    }
}

int usm_shortest_len(char buf[32], double v)
{
    char e[40], d17[17], d[17];
    int x, xd, n, P;
    if (v == 0.0 || !isfinite(v))
        return snprintf(buf, 32, "%.6g", v);
    if (fabs(v) < DBL_MIN) { /* subnormal */
        for (int prec = 6; prec <= 17; ++prec) {
            snprintf(buf, 32, "%.*g", prec, v);
            if (strtod(buf, NULL) == v)
                break;
        }
        return (int)strlen(buf);
    }
    const int neg = v < 0;
    snprintf(e, sizeof e, "%.16e", fabs(v)); /* d.dddddddddddddddde[+-]XX */
    d17[0] = e[0];
    memcpy(d17 + 1, e + 2, 16);
    x = atoi(e + 19);
    round_to(d17, x, 16, v, d, &xd);
    if (!reads_back(neg, d, 16, xd, v)) {
        memcpy(d, d17, 17);
        xd = x;
        P = n = 17;
    } else {
        char d15[17];
        int x15;
        round_to(d17, x, 15, v, d15, &x15);
        if (reads_back(neg, d15, 15, x15, v)) {
            memcpy(d, d15, 15);
            xd = x15;
            n = 15;
            P = 0; /* from n below */
        } else {
            n = P = 16;
        }
    }
    while (n > 1 && d[n - 1] == '0')
        --n;
    if (P == 0)
        P = n > 6 ? n : 6;
    char *o = buf;
    if (neg)
        *o++ = '-';
    if (xd < -4 || xd >= P) {
        *o++ = d[0];
        if (n > 1) {
            *o++ = '.';
            memcpy(o, d + 1, (size_t)n - 1);
            o += n - 1;
        }
        *o++ = 'e';
        *o++ = xd < 0 ? '-' : '+';
        const int ax = xd < 0 ? -xd : xd;
        if (ax >= 100)
            *o++ = (char)('0' + ax / 100);
        *o++ = (char)('0' + ax / 10 % 10);
        *o++ = (char)('0' + ax % 10);
    } else if (xd >= 0) {
        for (int k = 0; k <= xd; ++k)
            *o++ = k < n ? d[k] : '0';
        if (n > xd + 1) {
            *o++ = '.';
            memcpy(o, d + xd + 1, (size_t)(n - xd - 1));
            o += n - xd - 1;
        }
    } else {
        *o++ = '0';
        *o++ = '.';
        for (int k = 0; k < -xd - 1; ++k)
            *o++ = '0';
        memcpy(o, d, (size_t)n);
        o += n;
    }
    *o = '\0';
    return (int)(o - buf);
}

int usm_format_shortest(char buf[32], double v)
{
    return usm_shortest_len(buf, v);
}

const char *usm_shortest(char buf[32], double v)
{
    usm_shortest_len(buf, v);
    return buf;
}

void usm_csv_header(FILE *f, const usm_csv_column *cols, int n)
{
    for (int k = 0; k < n; ++k) {
        fputs(k ? "," : "", f);
        fputs(cols[k].name, f);
        if (cols[k].unit)
            fprintf(f, " [%s]", cols[k].unit);
    }
    fputc('\n', f);
}

void usm_csv_num(FILE *f, int first, double v)
{
    char buf[32];
    if (!first)
        fputc(',', f);
    if (isfinite(v))
        fputs(usm_shortest(buf, v), f);
}

void usm_csv_bool(FILE *f, int first, int b)
{
    fputs(first ? "" : ",", f);
    fputs(b ? "true" : "false", f);
}

void usm_csv_text(FILE *f, int first, const char *s)
{
    if (!first)
        fputc(',', f);
    if (!strpbrk(s, ",\"\n")) {
        fputs(s, f);
        return;
    }
    fputc('"', f);
    for (; *s; ++s) {
        if (*s == '"')
            fputc('"', f);
        fputc(*s == '\n' ? ' ' : *s, f);
    }
    fputc('"', f);
}

void usm_csv_validity(FILE *f, int has, usm_validity v)
{
    if (!has) {
        fputs(",,", f);
        return;
    }
    usm_csv_bool(f, 0, v == USM_VALID);
    usm_csv_text(f, 0, usm_validity_name(v));
}

int usm_csv_split(char *line, char **fields, int max)
{
    int n = 0;
    char *p = line;
    line[strcspn(line, "\r\n")] = '\0';
    for (;;) {
        if (n == max)
            return -1;
        fields[n++] = p;
        char *c = strchr(p, ',');
        if (!c)
            return n;
        *c = '\0';
        p = c + 1;
    }
}
