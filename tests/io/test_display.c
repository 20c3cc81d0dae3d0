/* Display units (--units): the conversions against the units' definitions
 * (1 rpm = 2 pi / 60 rad/s, 1 deg = pi / 180 rad, 1 mN m = 1e-3 N m), the
 * list's errors, and a CSV converted column by column with its event lines. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "usm.h"
#include "usm_io.h"

static const double PI = 3.14159265358979323846;

static int close_to(double a, double b)
{
    return fabs(a - b) <= 1e-14 * fabs(b);
}

static void conversions(void)
{
    usm_display d;
    char msg[USM_IO_MSG_LEN];
    const char *u;
    if (!CHECK(usm_display_parse("--units", "rpm, deg,mNm", &d, msg) == USM_OK, "%s", msg))
        return;
    CHECK(d.n == 3, "3 units, got %d", d.n);
    double v = usm_display_value(&d, "1/s", 100 * 2 * PI / 60, &u);
    CHECK(close_to(v, 100) && strcmp(u, "rpm") == 0, "100 rpm: %.17g %s", v, u);
    v = usm_display_value(&d, "rad/s", -2 * PI, &u);
    CHECK(close_to(v, -60) && strcmp(u, "rpm") == 0, "one turn a second is 60 rpm: %.17g %s", v, u);
    v = usm_display_value(&d, "rad", PI / 2, &u);
    CHECK(close_to(v, 90) && strcmp(u, "deg") == 0, "pi/2 is 90 deg: %.17g %s", v, u);
    v = usm_display_value(&d, "N m", 5e-4, &u);
    CHECK(close_to(v, 0.5) && strcmp(u, "mNm") == 0, "0.5 mNm: %.17g %s", v, u);
    v = usm_display_value(&d, "N", 0.4, &u);
    CHECK(v == 0.4 && strcmp(u, "N") == 0, "a force stays in N: %.17g %s", v, u);
    v = usm_display_value(NULL, "1/s", 3.5, &u);
    CHECK(v == 3.5 && strcmp(u, "1/s") == 0, "no display: SI");
    CHECK(usm_display_parse("--units", "si", &d, msg) == USM_OK && d.n == 0, "si: nothing changes");
}

static void refused(const char *spec, const char *want)
{
    usm_display d;
    char msg[USM_IO_MSG_LEN] = "";
    const int rc = usm_display_parse("--units", spec, &d, msg);
    CHECK(rc == USM_EINPUT && strncmp(msg, "--units: ", 9) == 0 && strstr(msg, want),
          "\"%s\": rc %d, message \"%s\" (want \"%s\")", spec, rc, msg, want);
}

static void errors(void)
{
    refused("furlong", "\"furlong\" is not a unit usm knows (units: Nm, mNm");
    refused("%", "a ratio");
    refused("rpm,rad/s", "rpm and rad/s are both units of [1/s]");
    refused("", "empty");
    refused("rpm,", "empty");
}

/* the converter's output for `in`, in a malloc'ed string */
static char *convert(const usm_display *d, const char *in)
{
    char *buf = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&buf, &len);
    CHECK(usm_display_csv(d, in, strlen(in), f) == 0, "write");
    fclose(f);
    return buf;
}

static void csv(void)
{
    usm_display d;
    char msg[USM_IO_MSG_LEN];
    CHECK(usm_display_parse("--units", "rpm,deg,mNm", &d, msg) == USM_OK, "%s", msg);
    const char *in = "T [N m],theta [rad],rotor_speed [1/s],F_n [N],valid,invalid_reason\n"
                     "0.001,0.5,-10.5,0.4,true,\n"
                     "0.002,,,,false,\"no root, none\"\n"
                     "# stick_limit at T = 0.0006: F_t = mu0 F_n at T = 0.0006 N m\n"
                     "# operating point rule: unchanged\n";
    char *out = convert(&d, in);
    char want[1024], a[32], b[32], c[32];
    snprintf(a, sizeof a, "%.17g", 0.5 * 180 / PI);
    snprintf(b, sizeof b, "%.17g", -10.5 * 60 / (2 * PI));
    /* the columns: name and unit; then each number read back against its definition */
    CHECK(strncmp(out, "T [mNm],theta [deg],rotor_speed [rpm],F_n [N],valid,invalid_reason\n", 67) == 0,
          "header: %s", out);
    const char *r1 = strchr(out, '\n') + 1;
    double T, th, w;
    char rest[64];
    CHECK(sscanf(r1, "%lf,%lf,%lf,%63s", &T, &th, &w, rest) == 4, "row 1: %s", r1);
    CHECK(close_to(T, 1.0) && close_to(th, atof(a)) && close_to(w, atof(b)),
          "row 1: %.17g %.17g %.17g", T, th, w);
    CHECK(strncmp(rest, "0.4,true,", 9) == 0, "other columns as they were: %s", rest);
    snprintf(c, sizeof c, "%s", "2,,,,false,\"no root, none\"\n");
    CHECK(strstr(out, c) != NULL, "row 2 (empty fields, quoted text): %s", out);
    snprintf(want, sizeof want, "# stick_limit at T = 0.6: F_t = mu0 F_n at T = 0.0006 N m\n");
    CHECK(strstr(out, want) != NULL, "event in the column's unit: %s", out);
    CHECK(strstr(out, "# operating point rule: unchanged\n") != NULL, "other comments as they are");
    free(out);
    /* no display: the text unchanged */
    usm_display si = {0};
    out = convert(&si, in);
    CHECK(strcmp(out, in) == 0, "SI: unchanged: %s", out);
    free(out);
}

int main(void)
{
    conversions();
    errors();
    csv();
    return failures != 0;
}
