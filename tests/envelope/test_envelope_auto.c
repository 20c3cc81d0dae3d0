/* The envelope's curves against AUTO-07p's two-parameter continuation of the
 * same boundaries (tests/envelope/auto_reference/, made by
 * bench/auto/reference.sh from the generated kernels; AUTO is not run here).
 *
 * 1. The fold of the 3-DOF model in (f, m0), tilt range up to 1 rad: every
 *    AUTO point from m0 = 100 N m through the "true fold" at 50 N m and the
 *    cusp near 21 N m up to the tilt range's end lies on usm's fold curve to
 *    1e-7 relative in f and m0, and usm's cusp is AUTO's CP to 1e-6.
 * 2. The stability boundary of twist_integrated in (f, T), f 35-40 kHz: the
 *    Hopf points of AUTO (an eigenvalue pair of the constant linearisation on
 *    the imaginary axis) lie on usm's stability curve to 1e-7.
 *
 * "Lies on the curve": usm's curve points are interpolated along the curve
 * (a cubic in the chord length through the four points around the nearest
 * one, in f, the other parameter and the tilt, so the curve's cusp in the
 * parameter plane is no corner for it) and the distance of the AUTO point
 * to that cubic is measured per component, relative.  The curve is traced
 * with a short step (h_max) so that the interpolation's own error (fourth
 * order in the spacing) stays far below the tolerance. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>

#include "usm.h"
#include "usm_envelope.h"

#include "check.h"

#define MAXREF 4000

typedef struct {
    char type[8];
    double x, y, theta;
} ref_point;

/* The reference CSV: comment lines, a header, then rows type,x,y,theta,... */
static size_t read_reference(const char *path, ref_point *r, size_t max)
{
    FILE *in = fopen(path, "r");
    if (!CHECK(in != NULL, "cannot open %s", path))
        return 0;
    char line[512];
    size_t n = 0;
    int header = 0;
    while (fgets(line, sizeof line, in) && n < max) {
        if (line[0] == '#')
            continue;
        if (!header) {
            header = 1;
            continue;
        }
        char *c = strchr(line, ',');
        if (!c)
            continue;
        *c = '\0';
        snprintf(r[n].type, sizeof r[n].type, "%.7s", line);
        if (sscanf(c + 1, "%lf,%lf,%lf", &r[n].x, &r[n].y, &r[n].theta) == 3)
            n++;
    }
    fclose(in);
    return n;
}

static const usm_envelope_curve *curve_of(const usm_envelope *e, usm_envelope_kind kind)
{
    for (size_t i = 0; i < usm_envelope_curve_count(e); ++i)
        if (usm_envelope_curve_at(e, i)->kind == kind)
            return usm_envelope_curve_at(e, i);
    return NULL;
}

/* Lagrange interpolation of the four values v at the chord lengths s. */
static double lagrange4(const double *s, const double *v, double t)
{
    double sum = 0;
    for (int i = 0; i < 4; ++i) {
        double w = 1;
        for (int j = 0; j < 4; ++j)
            if (j != i)
                w *= (t - s[j]) / (s[i] - s[j]);
        sum += w * v[i];
    }
    return sum;
}

/* The curve's point nearest (x, y, theta) along the cubic through four curve
 * points around the nearest one; dx, dy: the relative differences there.
 * Scales: the box's sides for x, y, and 1 rad for the tilt. */
static void distance_to_curve(const usm_envelope_curve *c, double sx, double sy, const ref_point *r,
                              double *dx, double *dy)
{
    size_t best = 0;
    double dbest = INFINITY;
    for (size_t i = 0; i < c->npoints; ++i) {
        const double ex = (c->xy[2 * i] - r->x) / sx, ey = (c->xy[2 * i + 1] - r->y) / sy,
                     et = c->u[i * (size_t)c->nu] - r->theta;
        const double d = ex * ex + ey * ey + et * et;
        if (d < dbest) {
            dbest = d;
            best = i;
        }
    }
    size_t k0 = best >= 1 ? best - 1 : 0;
    if (k0 + 4 > c->npoints)
        k0 = c->npoints - 4;
    double s[4], X[4], Y[4], T[4];
    for (int i = 0; i < 4; ++i) {
        const size_t k = k0 + (size_t)i;
        X[i] = c->xy[2 * k] / sx;
        Y[i] = c->xy[2 * k + 1] / sy;
        T[i] = c->u[k * (size_t)c->nu];
        s[i] = i == 0 ? 0
                      : s[i - 1] + sqrt((X[i] - X[i - 1]) * (X[i] - X[i - 1]) +
                                        (Y[i] - Y[i - 1]) * (Y[i] - Y[i - 1]) +
                                        (T[i] - T[i - 1]) * (T[i] - T[i - 1]));
    }
    /* the nearest point of the cubic: golden-section search over the
     * interpolation's span, then the distance there */
    const double g = 0.5 * (sqrt(5.0) - 1);
    double a = s[0], b = s[3];
    for (int it = 0; it < 200 && b - a > 1e-15 * (s[3] + 1); ++it) {
        const double t1 = b - g * (b - a), t2 = a + g * (b - a);
        double d1 = 0, d2 = 0;
        const double t[2] = {t1, t2};
        double *d[2] = {&d1, &d2};
        for (int q = 0; q < 2; ++q) {
            const double ex = lagrange4(s, X, t[q]) - r->x / sx,
                         ey = lagrange4(s, Y, t[q]) - r->y / sy,
                         et = lagrange4(s, T, t[q]) - r->theta;
            *d[q] = ex * ex + ey * ey + et * et;
        }
        if (d1 < d2)
            b = t2;
        else
            a = t1;
    }
    const double t = 0.5 * (a + b);
    *dx = fabs(lagrange4(s, X, t) * sx - r->x) / fabs(r->x);
    *dy = fabs(lagrange4(s, Y, t) * sy - r->y) / fabs(r->y);
}

static void fold_f_m0(const char *dir)
{
    static ref_point r[MAXREF];
    char path[1024];
    snprintf(path, sizeof path, "%s/fold_f_m0.csv", dir);
    const size_t n = read_reference(path, r, MAXREF);
    if (!CHECK(n > 100, "%s: %zu points", path, n))
        return;

    usm_params p;
    usm_params_default(&p);
    usm_envelope_options o;
    usm_envelope_options_default(&o);
    o.x = (usm_envelope_axis){"f", 20000, 40000};
    o.y = (usm_envelope_axis){"m0", 15, 100};
    o.steady.theta_max = 1.0;
    o.stability = 0;
    o.h_max = 0.002;
    usm_envelope *e = usm_envelope_alloc(usm_model_find("3dof"));
    CHECK(usm_envelope_run(e, &p, &o) == USM_OK, "f x m0: %s", usm_envelope_message(e));
    const usm_envelope_curve *c = curve_of(e, USM_ENVELOPE_FOLD);
    if (!CHECK(c && c->npoints >= 4, "f x m0: no fold curve")) {
        usm_envelope_free(e);
        return;
    }
    double worst = 0, at_f = 0, at_m0 = 0;
    size_t compared = 0;
    const ref_point *cp = NULL;
    for (size_t i = 0; i < n; ++i) {
        if (strcmp(r[i].type, "CP") == 0)
            cp = &r[i];
        /* the far side beyond the tilt range searched is not on usm's curve;
         * the start of AUTO's fold run is its LP estimate of the branch run
         * (located to 1e-6 only, det r_u = -2.3 there), not a curve point */
        if (r[i].theta > 0.999 || strcmp(r[i].type, "start") == 0)
            continue;
        double dx, dy;
        distance_to_curve(c, 20000, 85, &r[i], &dx, &dy);
        const double d = fmax(dx, dy);
        if (d > worst) {
            worst = d;
            at_f = r[i].x;
            at_m0 = r[i].y;
        }
        compared++;
    }
    CHECK(compared > 100 && worst <= 1e-7,
          "fold f x m0: %zu AUTO points, worst relative distance %.3g at f = %.10g Hz, "
          "m0 = %.10g N m", compared, worst, at_f, at_m0);
    printf("fold in f x m0: %zu AUTO points on usm's curve (%zu points) to %.3g relative "
           "(worst at f = %.6f Hz, m0 = %.6f N m)\n", compared, c->npoints, worst, at_f, at_m0);

    const usm_envelope_codim2 *k = NULL;
    for (size_t i = 0; i < usm_envelope_codim2_count(e); ++i)
        if (strcmp(usm_envelope_codim2_at(e, i)->type, "cusp") == 0)
            k = usm_envelope_codim2_at(e, i);
    if (CHECK(k && cp, "f x m0: a cusp in usm (%d) and a CP in AUTO's reference (%d)", k != NULL,
              cp != NULL)) {
        const double df = fabs(k->x - cp->x) / cp->x, dm = fabs(k->y - cp->y) / cp->y;
        CHECK(df <= 1e-6 && dm <= 1e-6,
              "cusp: usm (%.10g Hz, %.10g N m), AUTO CP (%.10g Hz, %.10g N m): %.3g, %.3g",
              k->x, k->y, cp->x, cp->y, df, dm);
        printf("cusp: usm f = %.10g Hz, m0 = %.10g N m; AUTO CP f = %.10g Hz, m0 = %.10g N m; "
               "relative %.3g, %.3g\n", k->x, k->y, cp->x, cp->y, df, dm);
    }
    usm_envelope_free(e);
}

static void stability_f_T(const char *dir)
{
    static ref_point r[MAXREF];
    char path[1024];
    snprintf(path, sizeof path, "%s/stability_f_T.csv", dir);
    const size_t n = read_reference(path, r, MAXREF);
    if (!CHECK(n > 100, "%s: %zu points", path, n))
        return;

    usm_params p;
    usm_params_default(&p);
    usm_envelope_options o;
    usm_envelope_options_default(&o);
    o.x = (usm_envelope_axis){"f", 35000, 40000};
    o.y = (usm_envelope_axis){"T", 0.0021, 0.0038};
    o.h_max = 0.002;
    usm_envelope *e = usm_envelope_alloc(usm_model_variant("3dof", "twist_integrated"));
    CHECK(usm_envelope_run(e, &p, &o) == USM_OK, "f x T: %s", usm_envelope_message(e));
    const usm_envelope_curve *c = curve_of(e, USM_ENVELOPE_STABILITY);
    if (!CHECK(c && c->npoints >= 4, "f x T: no stability curve")) {
        usm_envelope_free(e);
        return;
    }
    double worst = 0, at_f = 0, at_T = 0;
    size_t compared = 0;
    for (size_t i = 0; i < n; ++i) {
        /* the start of AUTO's run is its HB estimate of the branch run */
        if (strcmp(r[i].type, "start") == 0)
            continue;
        double dx, dy;
        distance_to_curve(c, 5000, 0.0017, &r[i], &dx, &dy);
        const double d = fmax(dx, dy);
        if (d > worst) {
            worst = d;
            at_f = r[i].x;
            at_T = r[i].y;
        }
        compared++;
    }
    CHECK(compared > 100 && worst <= 1e-7,
          "stability f x T: %zu AUTO points, worst relative distance %.3g at f = %.10g Hz, "
          "T = %.10g N m", compared, worst, at_f, at_T);
    printf("stability of twist_integrated in f x T: %zu AUTO points on usm's curve (%zu points) "
           "to %.3g relative (worst at f = %.6f Hz, T = %.9f N m)\n", compared, c->npoints, worst,
           at_f, at_T);
    usm_envelope_free(e);
}

int main(int argc, char **argv)
{
    gsl_set_error_handler_off();
    if (argc != 2) {
        fprintf(stderr, "usage: test_envelope_auto REFERENCE_DIR\n");
        return 2;
    }
    fold_f_m0(argv[1]);
    stability_f_T(argv[1]);
    return failures != 0;
}
