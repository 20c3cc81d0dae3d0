/* The imperfect motor's critical-multiplier curves in (mode_split, F0)
 * (runtime/envelope/envelope_periodic_stability.c), against the
 * one-parameter periodic sweep.
 *
 * The 4-DOF orbit at 2.5 % mode split loses stability with its contact
 * closed at F0 = 0.99995 N through a complex pair (neimark_sacker, squeal
 * frequency 2864.5 Hz; docs/squeal.md), is stable again from 1.0200 N
 * (another neimark_sacker) and ends at its fold at 1.0242 N.  In the box
 * 2.45-2.55 % x 0.995-1.03 N the envelope continues all three in
 * (mode_split, F0): two `stability` curves (the pair's angle an unknown)
 * and a `fold`.  At three points of each (its two ends, on the box's sides
 * mode_split = 2.45 % and 2.55 %, and an interior one) a periodic sweep in
 * F0 (its own continuation in one parameter and its own location of the
 * events on the branch's arc) locates the event: the curve's F0 equals it
 * to 1e-8 of the box's height, and on the stability curves the curve's
 * frequency equals the event's squeal frequency to 1e-6 relative.
 *
 * The regions: below the first curve the orbit is stable (contact_closed),
 * between the two stability curves unstable through the complex pair
 * (squeal), between the second and the fold stable again, above the fold
 * no orbit.  Each region's class agrees with the orbit solved at its sample
 * point here (from the nearest curve point's orbit) and its multipliers
 * read by usm_squeal.
 *
 * Before the extended system with the angle, the second stability curve was
 * lost on its way (the corrector with g = max |lambda| - 1 by differences)
 * and folds were not curves.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "usm.h"
#include "usm_envelope.h"
#include "usm_periodic.h"
#include "usm_periodic_sweep.h"

#include "check.h"

#define MS_LO 0.0245
#define MS_HI 0.0255
#define F0_LO 0.995
#define F0_HI 1.03

/* The events of a sweep in F0 from F0_LO at mode_split ms up to its fold:
 * the two neimark_sacker events (F0 and squeal frequency; NaN when not
 * found) and the fold's F0. */
typedef struct sweep_events {
    double ns[2], freq[2], fold;
} sweep_events;

static sweep_events sweep_at(const usm_model *m, double ms)
{
    sweep_events r = {{NAN, NAN}, {NAN, NAN}, NAN};
    usm_params p;
    usm_params_default(&p);
    p.mode_split = ms;
    usm_periodic_sweep *s = usm_periodic_sweep_alloc(m);
    usm_periodic_sweep_options o;
    usm_periodic_sweep_options_default(&o);
    o.over = "F0";
    o.from = F0_LO;
    o.to = F0_HI;
    o.points = 2;
    /* 3.5e-11 N: a tenth of the 1e-8 of the box checked */
    o.event_tol = 1e-9;
    const int rc = usm_periodic_sweep_run(s, &p, &o);
    CHECK(rc == USM_OK, "sweep in F0 at mode_split %g: %s", ms, usm_periodic_sweep_message(s));
    int nns = 0;
    for (size_t i = 0; rc == USM_OK && i < usm_periodic_sweep_event_count(s); ++i) {
        const usm_periodic_event *ev = usm_periodic_sweep_event_at(s, i);
        if (ev->type == USM_PEVENT_STABILITY_CHANGE && ev->kind == USM_CROSSING_NEIMARK_SACKER &&
            nns < 2) {
            r.ns[nns] = ev->value;
            r.freq[nns++] = ev->squeal_frequency;
        } else if (ev->type == USM_PEVENT_FOLD)
            r.fold = ev->value;
    }
    printf("sweep at mode_split %.9g: neimark_sacker %.12g N (%.6f Hz), %.12g N (%.6f Hz); "
           "fold %.12g N\n",
           ms, r.ns[0], r.freq[0], r.ns[1], r.freq[1], r.fold);
    usm_periodic_sweep_free(s);
    return r;
}

/* The curve's F0 at mode_split x, linear between its points (the region
 * samples' side of it). */
static double curve_at(const usm_envelope_curve *c, double x)
{
    for (size_t k = 1; k < c->npoints; ++k) {
        const double *a = c->xy + 2 * (k - 1), *b = c->xy + 2 * k;
        if ((x - a[0]) * (x - b[0]) <= 0 && a[0] != b[0])
            return a[1] + (b[1] - a[1]) * (x - a[0]) / (b[0] - a[0]);
    }
    return NAN;
}

int main(void)
{
    const usm_model *m = usm_model_variant("4dof", "imperfect");
    const clock_t c0 = clock();
    usm_params p;
    usm_params_default(&p);
    usm_envelope_options o;
    usm_envelope_options_default(&o);
    o.x = (usm_envelope_axis){"mode_split", MS_LO, MS_HI};
    o.y = (usm_envelope_axis){"F0", F0_LO, F0_HI};
    /* the band between the second stability curve and the fold is an
     * eighth of the height: two cells */
    o.raster = 16;
    usm_envelope *e = usm_envelope_alloc(m);
    const int rc = usm_envelope_run(e, &p, &o);
    printf("envelope: %.2f s CPU\n", (double)(clock() - c0) / CLOCKS_PER_SEC);
    CHECK(rc == USM_OK, "envelope: %s", usm_envelope_message(e));
    /* the curves by their height: stability low, stability high, fold */
    const usm_envelope_curve *cs[3] = {NULL, NULL, NULL};
    for (size_t i = 0; i < usm_envelope_curve_count(e); ++i) {
        const usm_envelope_curve *ci = usm_envelope_curve_at(e, i);
        printf("curve %zu %s: %zu points, (%.9g, %.12g) .. (%.9g, %.12g), ends %s %s\n", i,
               usm_envelope_kind_name(ci->kind), ci->npoints, ci->xy[0], ci->xy[1],
               ci->xy[2 * ci->npoints - 2], ci->xy[2 * ci->npoints - 1],
               usm_envelope_end_name(ci->end[0]), usm_envelope_end_name(ci->end[1]));
        if (ci->kind == USM_ENVELOPE_FOLD) {
            CHECK(!cs[2], "two fold curves");
            cs[2] = ci;
        }
        else if (ci->kind == USM_ENVELOPE_STABILITY) {
            if (!cs[0])
                cs[0] = ci;
            else if (!cs[1])
                cs[1] = ci;
            else
                CHECK(0, "three stability curves");
        }
    }
    if (cs[0] && cs[1] && cs[0]->xy[1] > cs[1]->xy[1]) {
        const usm_envelope_curve *t = cs[0];
        cs[0] = cs[1];
        cs[1] = t;
    }
    const char *name[3] = {"stability (loss)", "stability (regained)", "fold"};
    int all = 1;
    for (int j = 0; j < 3; ++j) {
        const usm_envelope_curve *c = cs[j];
        all &= CHECK(c != NULL, "no %s curve", name[j]) &&
               CHECK(c->npoints >= 3 && (j == 2 ? !c->frequency : c->frequency != NULL),
                     "%s: %zu points, frequency %s", name[j], c->npoints,
                     c->frequency ? "given" : "NULL") &&
               /* box to box, the whole width */
               CHECK(c->end[0] == USM_ENVELOPE_END_BOX && c->end[1] == USM_ENVELOPE_END_BOX &&
                         fmin(c->xy[0], c->xy[2 * c->npoints - 2]) == MS_LO &&
                         fmax(c->xy[0], c->xy[2 * c->npoints - 2]) == MS_HI,
                     "%s: does not cross the box", name[j]);
    }
    if (all) {
        /* three sweeps check all three curves: at their ends on the sides
         * and at the first curve's middle point, where the others' points
         * lie within 5e-3 of the box's width (their F0 and frequency
         * there by the quadratic through their three nearest points) */
        const double tol = 1e-8 * (F0_HI - F0_LO);
        const size_t mid = cs[0]->npoints / 2;
        const double at_ms[3] = {MS_LO, MS_HI, cs[0]->xy[2 * mid]};
        for (int sw = 0; sw < 3; ++sw) {
            const sweep_events ev = sweep_at(m, at_ms[sw]);
            for (int j = 0; j < 3; ++j) {
                const usm_envelope_curve *c = cs[j];
                size_t at = 0;
                for (size_t k = 1; k < c->npoints; ++k)
                    if (fabs(c->xy[2 * k] - at_ms[sw]) < fabs(c->xy[2 * at] - at_ms[sw]))
                        at = k;
                double F0c = c->xy[2 * at + 1];
                double fc = j < 2 ? c->frequency[at] : NAN;
                if (c->xy[2 * at] != at_ms[sw]) {
                    CHECK(sw == 2 && fabs(c->xy[2 * at] - at_ms[sw]) <= 5e-3 * (MS_HI - MS_LO),
                          "%s: no point at mode_split %.9g (nearest %.9g)", name[j], at_ms[sw],
                          c->xy[2 * at]);
                    const size_t i0 = at == 0 ? 0 : at + 1 == c->npoints ? at - 2 : at - 1;
                    const double *P = c->xy + 2 * i0, x = at_ms[sw];
                    const double l0 = (x - P[2]) * (x - P[4]) / ((P[0] - P[2]) * (P[0] - P[4])),
                                 l1 = (x - P[0]) * (x - P[4]) / ((P[2] - P[0]) * (P[2] - P[4])),
                                 l2 = (x - P[0]) * (x - P[2]) / ((P[4] - P[0]) * (P[4] - P[2]));
                    F0c = P[1] * l0 + P[3] * l1 + P[5] * l2;
                    if (j < 2)
                        fc = c->frequency[i0] * l0 + c->frequency[i0 + 1] * l1 +
                             c->frequency[i0 + 2] * l2;
                }
                const double want = j == 2 ? ev.fold : ev.ns[j];
                printf("%s at mode_split %.9g: curve F0 %.12g N, sweep %.12g N (%.1e of the "
                       "box)",
                       name[j], at_ms[sw], F0c, want, fabs(F0c - want) / (F0_HI - F0_LO));
                CHECK(fabs(F0c - want) <= tol, "%s at %g: curve F0 %.12g, sweep %.12g", name[j],
                      at_ms[sw], F0c, want);
                if (j < 2) {
                    printf("; %.6f Hz, sweep %.6f Hz (%.1e)", fc, ev.freq[j],
                           fabs(fc / ev.freq[j] - 1));
                    CHECK(fabs(fc / ev.freq[j] - 1) <= 1e-6, "%s at %g: curve %.6f Hz, sweep %.6f Hz",
                          name[j], at_ms[sw], fc, ev.freq[j]);
                }
                printf("\n");
            }
        }
    }
    /* the regions against the orbit and its multipliers at their samples */
    int seen[4] = {0, 0, 0, 0};
    usm_periodic *w = usm_periodic_alloc(m);
    for (size_t i = 0; all && i < usm_envelope_region_count(e); ++i) {
        const usm_envelope_region *r = usm_envelope_region_at(e, i);
        int band = 0;
        for (int j = 0; j < 3; ++j)
            band += r->y > curve_at(cs[j], r->x);
        static const char *want_band[4] = {"contact_closed", "squeal", "contact_closed",
                                           "no_orbit"};
        seen[band]++;
        printf("region %zu at (%.6g, %.7g), %zu cells, band %d: %s (%s)\n", i, r->x, r->y,
               r->cells, band, r->class_name, r->message);
        CHECK(strcmp(r->class_name, want_band[band]) == 0, "region at (%g, %g): %s, band %d",
              r->x, r->y, r->class_name, band);
        if (band == 3)
            continue;
        /* the nearest curve point's orbit */
        const usm_envelope_curve *c = cs[band == 0 ? 0 : band - 1];
        size_t j = 0;
        for (size_t k = 1; k < c->npoints; ++k)
            if (fabs(c->xy[2 * k] - r->x) < fabs(c->xy[2 * j] - r->x))
                j = k;
        usm_params q = p;
        q.mode_split = r->x;
        q.F0 = r->y;
        usm_periodic_options po;
        usm_periodic_options_default(&po);
        usm_periodic_result res;
        if (!CHECK(usm_periodic_solve(w, &q, c->u + (size_t)c->nu * j, &po, &res) == USM_OK,
                   "no orbit at (%g, %g): %s", r->x, r->y, usm_periodic_message(w)))
            continue;
        usm_squeal sq;
        usm_floquet_squeal(&res.floquet, 1.0 / res.period, &sq);
        const int unstable = res.floquet.max_modulus > 1.0;
        const int pair =
            unstable && sq.found && fabs(sq.modulus / res.floquet.max_modulus - 1) <= 1e-12;
        const char *want = res.validity != USM_VALID ? "(invalid)"
                           : pair                    ? "squeal"
                           : unstable                ? "unstable"
                                                     : "contact_closed";
        printf("  solved: max |lambda| %.9f, pair %.9f at %.6f Hz\n", res.floquet.max_modulus,
               sq.modulus, sq.frequency);
        CHECK(strcmp(r->class_name, want) == 0, "region at (%g, %g): %s, its orbit says %s", r->x,
              r->y, r->class_name, want);
        if (pair) {
            double f = NAN;
            (void)sscanf(strstr(r->message, "squeal at ") ? strstr(r->message, "squeal at ") : "",
                         "squeal at %lf", &f);
            CHECK(fabs(f / sq.frequency - 1) <= 1e-6, "squeal at %g Hz, orbit %g Hz", f,
                  sq.frequency);
        }
    }
    usm_periodic_free(w);
    CHECK(!all || (seen[0] >= 1 && seen[1] >= 1 && seen[2] >= 1 && seen[3] >= 1),
          "regions in the bands: %d %d %d %d", seen[0], seen[1], seen[2], seen[3]);
    usm_envelope_free(e);
    printf("total: %.2f s CPU\n", (double)(clock() - c0) / CLOCKS_PER_SEC);
    return failures != 0;
}
