/* test_io: the library's readers and writers (usm_io.h) give back exactly
 * what was computed.
 *
 * Truth: the values in memory that were written.
 *  - usm_steady_write_json: every root's theta, alpha, rotor_speed, F_n and
 *    the Floquet multipliers read back bit for bit (17 digits);
 *  - usm_sim_csv_row + usm_sim_read_start: a run's time history read back
 *    gives its last sample's state and rotor angle bit for bit, so a run
 *    continued from the file starts where the first one stopped; likewise the
 *    JSON summary's final_state (usm_sim_write_json) against
 *    usm_sim_summary.final_x;
 *  - usm_params_read_file: the values of a file; a malformed file is
 *    USM_EINPUT naming PATH:LINE:COLUMN and leaves the parameters unchanged;
 *    a string value is a value with a unit;
 *  - usm_parse_quantity: every row of the units table (1.5 UNIT is 1.5 x its
 *    scale, with and without a blank, micro as u, U+00B5 and U+03BC), the
 *    worked examples (37.5kHz, 400mN, 0.5mNm, 10deg) exactly, and a unit of
 *    another dimension or no unit at all refused with the accepted list;
 *  - JSON numbers (usm_steady_write_json): every real is the shortest text
 *    that reads back to the same double (no shorter %.*g does), so the
 *    paper's m0 prints as 0.005.
 */
#define _POSIX_C_SOURCE 200809L /* mkstemp, fdopen */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>
#include <jansson.h>

#include "check.h"
#include "usm.h"
#include "usm_io.h"
#include "usm_simulate.h"

typedef struct last_sample {
    FILE *csv;
    int nx;
    double x[USM_MAX_NX], rotor_angle, t;
} last_sample;

static int on_sample(const usm_sim_sample *s, void *data)
{
    last_sample *l = data;
    l->nx = s->nx;
    memcpy(l->x, s->x, sizeof(double) * (size_t)s->nx);
    l->rotor_angle = s->rotor_angle;
    l->t = s->t;
    return usm_sim_csv_row(s, l->csv) != 0;
}

static void steady_json(void)
{
    const usm_model *m = usm_model_find("3dof");
    usm_steady *st = usm_steady_alloc(m);
    usm_floquet *fl = usm_floquet_alloc(m);
    usm_floquet_result fr;
    usm_params p;
    usm_params_default(&p);
    CHECK(st && fl && usm_steady_solve(st, &p, NULL) == USM_OK &&
              usm_floquet_compute(fl, &p, usm_steady_root(st, 0), 0.0, NULL, &fr) == USM_OK,
          "steady: no solution at the paper's parameters");
    FILE *f = tmpfile();
    usm_steady_report rep = {m, &p, st, NULL, &fr, NULL, NULL};
    CHECK(f && usm_steady_write_json(&rep, f) == 0, "usm_steady_write_json failed");
    rewind(f);
    json_error_t err;
    json_t *o = json_loadf(f, 0, &err);
    CHECK(o != NULL, "steady JSON does not parse: %s", err.text);
    json_t *roots = json_object_get(o, "roots");
    CHECK(json_array_size(roots) == usm_steady_count(st), "roots: %zu, want %zu",
          json_array_size(roots), usm_steady_count(st));
    for (size_t k = 0; k < json_array_size(roots) && k < usm_steady_count(st); ++k) {
        const usm_steady_solution *s = usm_steady_root(st, k);
        json_t *r = json_array_get(roots, k);
        CHECK(json_real_value(json_object_get(r, "theta")) == s->theta &&
                  json_real_value(json_object_get(r, "alpha")) == s->alpha &&
                  json_real_value(json_object_get(r, "rotor_speed")) == s->rotor_speed &&
                  json_real_value(json_object_get(r, "F_n")) == s->F_n,
              "root %zu: values do not read back exactly", k);
    }
    json_t *mult = json_object_get(json_object_get(o, "floquet"), "multipliers");
    CHECK((int)json_array_size(mult) == fr.n, "multipliers: %zu, want %d", json_array_size(mult),
          fr.n);
    for (int k = 0; k < fr.n && k < (int)json_array_size(mult); ++k) {
        json_t *z = json_array_get(mult, (size_t)k);
        CHECK(json_number_value(json_array_get(z, 0)) == fr.re[k] &&
                  json_number_value(json_array_get(z, 1)) == fr.im[k],
              "multiplier %d does not read back exactly", k);
    }
    json_decref(o);
    if (f)
        fclose(f);
    usm_floquet_free(fl);
    usm_steady_free(st);
}

/* A run's outputs read back as the start of the next run. */
static void sim_round_trip(const char *model)
{
    const usm_model *m = usm_model_find(model);
    usm_sim *sim = usm_sim_alloc(m);
    usm_sim_options opt, back;
    usm_sim_summary sum;
    usm_params p;
    char csv_path[] = "/tmp/usm-test-io-XXXXXX", msg[USM_IO_MSG_LEN];
    last_sample last = {0};
    usm_params_default(&p);
    usm_sim_options_default(&opt);
    opt.duration = 20.0 / p.f;
    opt.rate = 2.0 * p.f + 0.5; /* not on the period grid: the last row is the end's */
    int fd = mkstemp(csv_path);
    last.csv = fd >= 0 ? fdopen(fd, "w") : NULL;
    CHECK(sim && last.csv, "%s: set-up failed", model);
    if (!sim || !last.csv)
        return;
    usm_sim_csv_header(last.csv);
    usm_sim_callbacks cb = {on_sample, NULL, &last, NULL};
    CHECK(usm_sim_run(sim, &p, &opt, &cb, &sum) == USM_OK, "%s: run: %s", model,
          usm_sim_message(sim));
    CHECK(fclose(last.csv) == 0, "%s: CSV not written", model);
    CHECK(last.t == sum.t_reached, "%s: the last row is at t = %.17g, the run ended at %.17g",
          model, last.t, sum.t_reached);

    usm_sim_options_default(&back);
    CHECK(usm_sim_read_start(csv_path, m, &back, msg) == USM_OK, "%s: CSV: %s", model, msg);
    CHECK(back.t0 == last.t, "%s: CSV t0 %.17g, want %.17g", model, back.t0, last.t);
    /* the stick model's rotor angle is no state variable: read apart */
    CHECK(m->slip || back.rotor_angle0 == last.rotor_angle,
          "%s: CSV rotor angle %.17g, want %.17g", model, back.rotor_angle0, last.rotor_angle);
    for (int i = 0; i < m->nx; ++i)
        CHECK(back.x0[i] == last.x[i], "%s: CSV %s = %.17g, want %.17g", model,
              m->state_names[i], back.x0[i], last.x[i]);

    char json_path[] = "/tmp/usm-test-io-XXXXXX";
    fd = mkstemp(json_path);
    FILE *jf = fd >= 0 ? fdopen(fd, "w") : NULL;
    usm_sim_report rep = {m, &p, &opt, NULL, csv_path, &sum, 0.0, NULL, NULL, NULL};
    CHECK(jf && usm_sim_write_json(&rep, jf) == 0 && fclose(jf) == 0, "%s: JSON not written",
          model);
    usm_sim_options_default(&back);
    CHECK(usm_sim_read_start(json_path, m, &back, msg) == USM_OK, "%s: JSON: %s", model, msg);
    CHECK(back.t0 == sum.t_reached && (m->slip || back.rotor_angle0 == sum.final_rotor_angle),
          "%s: JSON t0 %.17g / rotor angle %.17g", model, back.t0, back.rotor_angle0);
    for (int i = 0; i < m->nx; ++i)
        CHECK(back.x0[i] == sum.final_x[i], "%s: JSON %s = %.17g, want %.17g", model,
              m->state_names[i], back.x0[i], sum.final_x[i]);
    /* the state of another model is refused, naming the file */
    const usm_model *other = usm_model_find(strcmp(model, "3dof") ? "3dof" : "4dof");
    CHECK(usm_sim_read_start(json_path, other, &back, msg) == USM_EINPUT &&
              strstr(msg, json_path) != NULL,
          "%s: JSON of another model accepted (\"%s\")", model, msg);
    remove(csv_path);
    remove(json_path);
    usm_sim_free(sim);
}

static void params_file(void)
{
    char path[] = "/tmp/usm-test-io-XXXXXX", msg[USM_IO_MSG_LEN];
    usm_params p, q;
    int fd = mkstemp(path);
    FILE *f = fd >= 0 ? fdopen(fd, "w") : NULL;
    CHECK(f != NULL, "params: temporary file");
    if (!f)
        return;
    fputs("{\n  \"f\": 36000.5,\n  \"T\": 1.25e-4\n}\n", f);
    fclose(f);
    usm_params_default(&p);
    q = p;
    CHECK(usm_params_read_file(path, &p, msg) == USM_OK, "params: %s", msg);
    CHECK(p.f == 36000.5 && p.T == 1.25e-4, "params: f %.17g, T %.17g", p.f, p.T);
    CHECK(p.m0 == q.m0 && p.mu0 == q.mu0, "params: a parameter not in the file changed");
    f = fopen(path, "w");
    fputs("{\n  \"f\": 36000.5,\n  \"T\": nan\n}\n", f);
    fclose(f);
    q = p;
    CHECK(usm_params_read_file(path, &p, msg) == USM_EINPUT, "params: a NaN accepted");
    char where[sizeof path + 8];
    snprintf(where, sizeof where, "%s:3:", path);
    CHECK(strstr(msg, where) == msg, "params: message \"%s\" does not start with %s", msg, where);
    CHECK(memcmp(&p, &q, sizeof p) == 0, "params: a bad file changed the parameters");
    remove(path);
}

/* Significant digits of a number token ("0.0035" -> 2, "1.0" -> 1). */
static int sig_digits(const char *tok, size_t len)
{
    int n = 0, lead = 1, zeros = 0;
    for (size_t k = 0; k < len && tok[k] != 'e' && tok[k] != 'E'; ++k) {
        if (tok[k] < '0' || tok[k] > '9')
            continue;
        if (tok[k] == '0' && lead)
            continue;
        lead = 0;
        if (tok[k] == '0') {
            ++zeros; /* trailing zeros are not significant */
        } else {
            n += zeros + 1;
            zeros = 0;
        }
    }
    return n ? n : 1;
}

static void json_shortest(void)
{
    const usm_model *m = usm_model_find("3dof");
    usm_steady *st = usm_steady_alloc(m);
    usm_params p;
    usm_params_default(&p);
    CHECK(st && usm_steady_solve(st, &p, NULL) == USM_OK, "json_shortest: no solution");
    FILE *f = tmpfile();
    usm_steady_report rep = {m, &p, st, NULL, NULL, NULL, NULL};
    CHECK(f && usm_steady_write_json(&rep, f) == 0, "usm_steady_write_json failed");
    long size = f ? (fseek(f, 0, SEEK_END), ftell(f)) : 0;
    char *text = size > 0 ? malloc((size_t)size + 1) : NULL;
    CHECK(text != NULL, "json_shortest: empty output");
    if (!text) {
        usm_steady_free(st);
        return;
    }
    rewind(f);
    text[fread(text, 1, (size_t)size, f)] = '\0';
    fclose(f);
    CHECK(strstr(text, "\"m0\": 0.005,") != NULL, "m0 is not printed as 0.005");
    int reals = 0, in_string = 0;
    for (char *c = text; *c; ++c) {
        if (in_string) {
            if (*c == '\\' && c[1])
                ++c;
            else if (*c == '"')
                in_string = 0;
            continue;
        }
        if (*c == '"') {
            in_string = 1;
            continue;
        }
        if (!(*c == '-' || (*c >= '0' && *c <= '9')))
            continue;
        size_t len = strspn(c, "-+0123456789.eE");
        if (strcspn(c, ".eE") < len) {
            char *end;
            const double v = strtod(c, &end);
            const int n = sig_digits(c, len);
            char shorter[400];
            snprintf(shorter, sizeof shorter, "%.*g", n - 1, v);
            CHECK(end == c + len, "JSON number %.*s does not read back", (int)len, c);
            CHECK(n == 1 || strtod(shorter, NULL) != v,
                  "JSON number %.*s is not the shortest: %s reads back the same", (int)len, c,
                  shorter);
            ++reals;
        }
        c += len - 1;
    }
    CHECK(reals > 30, "json_shortest: only %d real numbers checked", reals);
    free(text);
    usm_steady_free(st);
}

static void units(void)
{
    char msg[USM_IO_MSG_LEN];
    double v;
    const int n = usm_unit_count();
    CHECK(n > 30, "units: only %d rows", n);
    for (int k = 0; k < n; ++k) {
        const char *si, *name;
        double scale;
        char text[64];
        CHECK(usm_unit_at(k, &si, &name, &scale) == USM_OK, "units: row %d", k);
        for (int j = 0; j < k; ++j) {
            const char *si2, *name2;
            usm_unit_at(j, &si2, &name2, NULL);
            CHECK(strcmp(si, si2) != 0 || strcmp(name, name2) != 0, "units: %s twice in [%s]",
                  name, si);
        }
        const double want = 1.5 * scale;
        for (int form = 0; form < 4; ++form) {
            if (form >= 2 && name[0] != 'u')
                break;
            if (form == 0 && name[0] >= '0' && name[0] <= '9')
                continue; /* "1.51/s" is 1.51 /s: a unit that starts with a digit needs a blank */
            if (form < 2)
                snprintf(text, sizeof text, "1.5%s%s", form ? " " : "", name);
            else
                snprintf(text, sizeof text, "1.5%s%s", form == 2 ? "\xc2\xb5" : "\xce\xbc",
                         name + 1);
            CHECK(usm_parse_quantity("unit", si, text, strlen(text), &v, msg) == USM_OK &&
                      fabs(v - want) <= 4e-16 * fabs(want),
                  "units: \"%s\" in [%s] gives %.17g, want %.17g (%s)", text, si, v, want, msg);
        }
        /* a value in SI without a unit is the number itself */
        CHECK(usm_parse_quantity("unit", si, "2.5", 3, &v, msg) == USM_OK && v == 2.5,
              "units: 2.5 in [%s]", si);
    }
    static const struct {
        const char *si, *text;
        double want;
    } exact[] = {{"Hz", "37.5kHz", 37500.0},  {"N", "400mN", 0.4},      {"N m", "0.5mNm", 0.0005},
                 {"N m", "6.46e-2 mNm", 6.46e-5}, {"rad", "10deg", 10 * 3.14159265358979323846 / 180},
                 {"1", "5%", 0.05},           {"m", "5mm", 0.005},      {"kg", "636.176mg", 636.176e-6}};
    for (size_t k = 0; k < sizeof exact / sizeof exact[0]; ++k)
        CHECK(usm_parse_quantity("x", exact[k].si, exact[k].text, strlen(exact[k].text), &v, msg) ==
                      USM_OK && v == exact[k].want,
              "units: \"%s\" gives %.17g, want %.17g", exact[k].text, v, exact[k].want);
    /* refused: a unit of another dimension, an unknown one, a unit where none is accepted */
    static const struct {
        const char *si, *text;
    } bad[] = {{"N m", "5kHz"}, {"N m", "5xyz"}, {"Hz", "1e5x"}, {"rad", "10 degrees"},
               {"N", "1N m"},   {"N/m", "5kHz"}};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; ++k) {
        char known[256];
        usm_units_accepted(bad[k].si, known, sizeof known);
        CHECK(usm_parse_quantity("--set X", bad[k].si, bad[k].text, strlen(bad[k].text), &v, msg) ==
                      USM_EINPUT && strstr(msg, "--set X") && strstr(msg, known),
              "units: \"%s\" in [%s] not refused with the list (%s): %s", bad[k].text, bad[k].si,
              known, msg);
    }
    /* without a unit to read, the number parser's own messages */
    CHECK(usm_parse_quantity("x", NULL, "5kHz", 4, &v, msg) == USM_EINPUT &&
              strstr(msg, "not a number"), "units: NULL unit takes a unit: %s", msg);
    CHECK(usm_parse_quantity("x", "Hz", "inf", 3, &v, msg) == USM_EINPUT &&
              strstr(msg, "not a finite number"), "units: inf: %s", msg);
    CHECK(usm_parse_quantity("x", "Hz", "1e400kHz", 8, &v, msg) == USM_EINPUT,
          "units: 1e400kHz accepted");
    /* a parameter file's string is a value with a unit */
    usm_params p;
    usm_params_default(&p);
    const char *file = "{\"f\": \"37.5 kHz\", \"T\": 1e-4, \"phase_error\": \"10deg\"}";
    CHECK(usm_params_parse_text("p.json", file, strlen(file), &p, msg) == USM_OK && p.f == 37500.0 &&
              p.T == 1e-4 && p.phase_error == 10 * 3.14159265358979323846 / 180,
          "units: parameter file with units: %s", msg);
    const char *badfile = "{\"f\": \"37.5 kN\"}";
    CHECK(usm_params_parse_text("p.json", badfile, strlen(badfile), &p, msg) == USM_EINPUT &&
              strstr(msg, "p.json") && strstr(msg, "Hz, kHz, MHz"),
          "units: a bad unit in a file: %s", msg);
}

/* usm_format_shortest (one print, one or two parses) against its
 * definition, the first %.{P}g, P = 6 ... 17, that strtod reads back as v:
 * the same text for random bit patterns (every exponent, subnormals),
 * short decimals, whole numbers around the %g style switch, and decimals of
 * 15 to 17 digits ending in 5 (where rounding the 17-digit print to fewer
 * digits is a tie that the definition decides on v's later digits). */
static uint64_t xs = 88172645463325252ULL;
static uint64_t xorshift(void)
{
    xs ^= xs << 13;
    xs ^= xs >> 7;
    xs ^= xs << 17;
    return xs;
}

static void shortest_definition(char buf[32], double v)
{
    for (int p = 6; p <= 17; ++p) {
        snprintf(buf, 32, "%.*g", p, v);
        if (strtod(buf, NULL) == v)
            return;
    }
}

static void shortest_writer(void)
{
    static const double special[] = {0.0, -0.0, 1, 1e6, 1e5, 123456, 1234567, 1e15, 1e16, 1e17,
                                     1e-5, 1e-4, 0.1, 0.30000000000000004, 1.5e-300, 5e-324,
                                     2.2250738585072014e-308, 1.7976931348623157e308, 100,
                                     999999.5, 9.9999999999999999e14, -0.005};
    char a[32], b[32], digits[32], text[64];
    long bad = 0, n = 0;
    for (size_t k = 0; k < sizeof special / sizeof special[0]; ++k, ++n) {
        shortest_definition(a, special[k]);
        bad += usm_format_shortest(b, special[k]) != (int)strlen(a) || strcmp(a, b) != 0;
    }
    for (long i = 0; i < 400000; ++i) {
        const uint64_t r = xorshift();
        double v;
        switch (i % 5) {
        case 0: memcpy(&v, &r, sizeof v); break;
        case 1: v = (double)(r % 2000000) / 1000.0; break;
        case 2: v = (double)(int64_t)(r % 200000000) - 1e8; break;
        case 3: v = ldexp((double)(r >> 11), -53) * pow(10, (int)(r % 40) - 20); break;
        default: /* 15, 16 or 17 digits ending in 5 (or 05) */
            snprintf(digits, sizeof digits, "%llu",
                     (unsigned long long)(r % 9000000000000000000ULL + 1000000000000000000ULL));
            {
                const int nd = 15 + (int)(i / 5 % 3);
                digits[nd] = '\0';
                digits[nd - 1] = '5';
                if (i / 15 % 2)
                    digits[nd - 2] = '0';
            }
            snprintf(text, sizeof text, "%s%c.%se%d", i % 2 ? "-" : "", digits[0], digits + 1,
                     (int)(xorshift() % 60) - 30);
            v = strtod(text, NULL);
        }
        if (!isfinite(v))
            continue;
        ++n;
        shortest_definition(a, v);
        if (usm_format_shortest(b, v) != (int)strlen(a) || strcmp(a, b) != 0) {
            if (bad < 5)
                printf("usm_format_shortest(%a) = %s, the definition gives %s\n", v, b, a);
            ++bad;
        }
    }
    CHECK(bad == 0, "usm_format_shortest: %ld of %ld texts differ from the definition", bad, n);
}

int main(void)
{
    gsl_set_error_handler_off();
    shortest_writer();
    units();
    json_shortest();
    steady_json();
    sim_round_trip("3dof");
    sim_round_trip("4dof");
    params_file();
    if (failures)
        printf("%d failures\n", failures);
    return failures != 0;
}
