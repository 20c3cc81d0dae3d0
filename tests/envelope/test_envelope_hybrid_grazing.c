/* Where the orbit with separation's closed phases vanish, continued in two
 * parameters (runtime/envelope/envelope_hybrid_grazing.c, curve kind
 * separation_grazing), against the stroboscopic solver of the orbits with
 * separation (usm_hybrid_solve_from: another map, with a fixed section
 * inside a closed phase).
 *
 * 3-DOF motor, box phase error 0.90 to 0.93 rad x mode split 0 to 0.1 %:
 * the two-impact orbit `cococ` rests on the stator after each landing until
 * F_n falls to 0; the curve is where F_n just after the landing is 0.
 * Checked: one separation_grazing curve, box to box; its end on the axis
 * mode split 0 at the boundary (0.9135333 rad, docs/envelope.md), past the
 * periodic sweep's branch end (0.913379117: its corrector fails there as the
 * closed phase leaves its fixed section) by less than 2e-4; at the end and
 * two interior points, the stroboscopic solver's orbits continued towards
 * the curve (the section moved to the middle of the longest closed phase
 * after each), as near as they go (3.5e-5 or 5e-5 rad before it: nearer, the
 * closed phase, 1e-7 s, moves past the section between two of them), whose F_n
 * just after the landing, extrapolated along the chord through the last
 * two to 0, falls past the curve by at most STROBE_TOL.  That is the
 * stroboscopic map's reach, not the curve's accuracy: the curve's points
 * solve the extended system to the map's noise (about 1e-9 rad).  Cost:
 * the envelope's edge sweeps (cold starts) and the stroboscopic orbits,
 * 12 s.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "usm.h"
#include "usm_envelope.h"
#include "usm_periodic.h"

#include "check.h"

/* The stroboscopic orbits' extrapolation lies past the curve by at most
 * this [rad] (measured 1.5e-5, 1.5e-5, 2.5e-5): F_n after the landing over
 * the distance to the boundary grows from 440 N/rad at 1e-4 rad to 900 at
 * 1e-6 (the impact map's orbits), so a chord from 5e-5 and 3.5e-5 rad
 * before it reaches 0 past it */
#define STROBE_TOL 4e-5

/* The orbit r moved to a section in the middle of its longest closed phase
 * (solved again there); 0 or -1. */
static int resect(usm_hybrid *h, const usm_model *m, const usm_params *p, usm_hybrid_result *r)
{
    const int nx = m->nx, cols = USM_HYBRID_SAMPLE_COLS(nx), n = 400;
    double *rows = malloc(sizeof(double) * (size_t)USM_HYBRID_SAMPLE_ROWS(n) * (size_t)cols);
    int nrows = 0, best = -1, len = 0, rc = -1;
    if (rows && usm_hybrid_orbit_samples(h, p, r, 0.0, n, rows, &nrows) == USM_OK) {
        for (int i = 0; i < nrows;) {
            int j = i;
            while (j < nrows && rows[(size_t)j * (size_t)cols + 1] == 0.0)
                ++j;
            if (j - i > len) {
                len = j - i;
                best = i + (j - i) / 2;
            }
            i = j > i ? j : i + 1;
        }
        usm_hybrid_result r2;
        if (best >= 0 && best < nrows &&
            usm_hybrid_solve_from(h, p, NULL, rows[(size_t)best * (size_t)cols],
                                  rows + (size_t)best * (size_t)cols + 2, &r2) == USM_OK &&
            r2.impacts_per_period == 2) {
            *r = r2;
            rc = 0;
        }
    }
    free(rows);
    return rc;
}

/* F_n just after the first landing of the stroboscopic orbit r at p. */
static double fn_after_landing(usm_hybrid *h, const usm_model *m, const usm_params *p,
                               const usm_hybrid_result *r)
{
    const int nx = m->nx, cols = USM_HYBRID_SAMPLE_COLS(nx), n = 50;
    double *rows = malloc(sizeof(double) * (size_t)USM_HYBRID_SAMPLE_ROWS(n) * (size_t)cols);
    int nrows = 0;
    double fn = NAN;
    if (rows && usm_hybrid_orbit_samples(h, p, r, 0.0, n, rows, &nrows) == USM_OK)
        for (int i = 1; i < nrows; ++i)
            if (rows[(size_t)(i - 1) * (size_t)cols + 1] == 1.0 &&
                rows[(size_t)i * (size_t)cols + 1] == 0.0) {
                fn = rows[(size_t)i * (size_t)cols + nx + 3];
                break;
            }
    free(rows);
    return fn;
}

/* The phase error where the stroboscopic orbits' F_n after the landing,
 * extrapolated, is 0, near xc at mode split y; NaN when they fail. */
static double strobe_zero(const usm_model *m, double xc, double y)
{
    usm_params p;
    usm_params_default(&p);
    p.mode_split = y;
    usm_hybrid *h = usm_hybrid_alloc(m);
    usm_hybrid_result r;
    static const double d[] = {3e-3, 1e-3, 3e-4, 1e-4, 7e-5, 5e-5, 3.5e-5, 2.5e-5,
                               1.8e-5, 1.3e-5, 1e-5, 7e-6, 5e-6};
    enum { ND = sizeof d / sizeof d[0] };
    double fx[2] = {NAN, NAN}, fv[2] = {NAN, NAN};
    int k = 0, ok = 1;
    p.phase_error = xc - d[0];
    ok = usm_hybrid_solve(h, &p, NULL, &r) == USM_OK && r.impacts_per_period == 2 &&
         resect(h, m, &p, &r) == 0;
    for (int i = 1; ok && i < ND; ++i) {
        p.phase_error = xc - d[i];
        const usm_hybrid_result ra = r; /* the solve clears its output first */
        ok = usm_hybrid_solve_from(h, &p, NULL, ra.t0, ra.x0, &r) == USM_OK &&
             r.impacts_per_period == 2 && resect(h, m, &p, &r) == 0;
        if (!ok)
            printf("stroboscopic orbit at %.4g before the curve: %s\n", d[i],
                   usm_hybrid_message(h));
        if (ok) {
            /* the last two orbits */
            fx[0] = fx[1];
            fv[0] = fv[1];
            fx[1] = p.phase_error;
            fv[1] = fn_after_landing(h, m, &p, &r);
            k = k < 2 ? k + 1 : 2;
        }
    }
    ok = k == 2;
    usm_hybrid_free(h);
    CHECK(ok && k == 2, "the stroboscopic orbits before %.9g at mode split %g", xc, y);
    if (!ok || k != 2)
        return NAN;
    CHECK(fv[0] > fv[1] && fv[1] > 0, "F_n after the landing falls to 0: %.4g %.4g", fv[0],
          fv[1]);
    /* F_n is linear in the phase error within about 1e-5 rad of the
     * boundary (F_n / distance 850 to 960 N/rad from 1.25e-5 rad before it
     * to 1e-5 rad past it, measured on the impact map; 440 at 1e-4 rad) */
    printf("stroboscopic: F_n after the landing %.4g N at %.3g rad before the curve\n", fv[1],
           xc - fx[1]);
    return fx[1] - fv[1] * (fx[1] - fx[0]) / (fv[1] - fv[0]);
}

int main(void)
{
    const usm_model *m = usm_model_variant("3dof", "imperfect_unilateral");
    const clock_t c0 = clock();
    usm_params p;
    usm_params_default(&p);
    usm_envelope_options o;
    usm_envelope_options_default(&o);
    o.x = (usm_envelope_axis){"phase_error", 0.90, 0.93};
    o.y = (usm_envelope_axis){"mode_split", 0.0, 0.001};
    o.raster = 8;
    usm_envelope *e = usm_envelope_alloc(m);
    CHECK(m && e, "model and envelope");
    const int rc = usm_envelope_run(e, &p, &o);
    CHECK(rc == USM_OK, "envelope: %s", usm_envelope_message(e));
    printf("envelope: %.2f s CPU\n", (double)(clock() - c0) / CLOCKS_PER_SEC);
    const usm_envelope_curve *g = NULL;
    int ng = 0;
    for (size_t i = 0; i < usm_envelope_curve_count(e); ++i) {
        const usm_envelope_curve *c = usm_envelope_curve_at(e, i);
        const char *name = usm_envelope_kind_name(c->kind);
        if (name && strcmp(name, "separation_grazing") == 0) {
            g = c;
            ++ng;
        }
    }
    CHECK(ng == 1, "one separation_grazing curve (%d)", ng);
    if (!g) {
        usm_envelope_free(e);
        return failures != 0;
    }
    CHECK(g->npoints >= 4, "points on the curve (%zu)", g->npoints);
    CHECK(g->end[0] == USM_ENVELOPE_END_BOX && g->end[1] == USM_ENVELOPE_END_BOX,
          "box to box (%s, %s)", usm_envelope_end_name(g->end[0]),
          usm_envelope_end_name(g->end[1]));
    const double *axis = NULL;
    for (size_t i = 0; i < g->npoints; i += g->npoints - 1)
        if (g->xy[2 * i + 1] == 0.0)
            axis = g->xy + 2 * i;
    CHECK(axis != NULL, "the curve ends on mode_split = 0");
    if (axis) {
        CHECK(fabs(axis[0] - 0.9135333) <= 1e-7, "the documented 0.9135333 rad: %.12g",
              axis[0]);
        CHECK(axis[0] > 0.913379117 && axis[0] - 0.913379117 < 2e-4,
              "past the sweep's branch end 0.913379117 by %.3g", axis[0] - 0.913379117);
        const double v = strobe_zero(m, axis[0], 0.0);
        CHECK(v >= axis[0] && v - axis[0] <= STROBE_TOL, "on the axis: curve %.12g, "
              "stroboscopic %.12g", axis[0], v);
        printf("axis: curve %.12g stroboscopic %.12g (%.2g)\n", axis[0], v, axis[0] - v);
    }
    int inner = 0;
    for (size_t i = g->npoints / 3; i + 1 < g->npoints && inner < 2; i += g->npoints / 3) {
        const double x = g->xy[2 * i], y = g->xy[2 * i + 1];
        const double v = strobe_zero(m, x, y);
        CHECK(v >= x && v - x <= STROBE_TOL, "mode split %.6g: curve %.12g, stroboscopic %.12g",
              y, x, v);
        printf("mode split %.6g: curve %.12g stroboscopic %.12g (%.2g)\n", y, x, v, x - v);
        ++inner;
    }
    CHECK(inner == 2, "two interior points (%d)", inner);
    usm_envelope_free(e);
    printf("test_envelope_hybrid_grazing: %.2f s CPU\n", (double)(clock() - c0) / CLOCKS_PER_SEC);
    return failures != 0;
}
