/* The imperfect motor's stability curve in (mode_split, F0)
 * (runtime/envelope/envelope_periodic_stability.c), against the
 * one-parameter periodic sweep.
 *
 * The 4-DOF orbit at 2.5 % mode split loses stability with its contact
 * closed at F0 = 0.99995 N through a complex pair (neimark_sacker, squeal
 * frequency 2864.5 Hz; docs/squeal.md).  The envelope continues that
 * crossing in (mode_split, F0) from the sweeps along the box's edges.  At
 * three values of mode_split on the curve (the end it reached at the far
 * side and two interior points) a periodic sweep in F0 (its own
 * continuation in one parameter and its own location of the event on the
 * branch's arc) locates the neimark_sacker event: the curve's F0 equals it
 * to 1e-7 relative, and the curve's frequency there equals the event's
 * squeal frequency to 1e-6 relative.
 *
 * The regions on either side: above the curve the orbit is unstable through
 * the complex pair with its contact closed, `squeal`, its frequency within
 * 1 % of the curve's; below it is stable, `contact_closed`.  Each region's
 * class agrees with the orbit solved at its sample point here (from the
 * nearest curve point's orbit) and its multipliers read by usm_squeal.
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

/* The neimark_sacker event of a sweep in F0 over from..to at mode_split
 * ms: its F0 and squeal frequency (NaN when none).  The sweep starts
 * below the curve, where the ideal motor's start finds the followed orbit
 * (at 0.99994 N it finds another). */
static void sweep_ns(const usm_model *m, double ms, double from, double to, double *f0,
                     double *freq)
{
    usm_params p;
    usm_params_default(&p);
    p.mode_split = ms;
    usm_periodic_sweep *s = usm_periodic_sweep_alloc(m);
    usm_periodic_sweep_options o;
    usm_periodic_sweep_options_default(&o);
    o.over = "F0";
    o.from = from;
    o.to = to;
    o.points = 2;
    /* 1e-9 N: well inside the 1e-7 checked, at a third of the default's cost */
    o.event_tol = 1e-6;
    *f0 = *freq = NAN;
    const int rc = usm_periodic_sweep_run(s, &p, &o);
    CHECK(rc == USM_OK, "sweep in F0 at mode_split %g: %s", ms, usm_periodic_sweep_message(s));
    for (size_t i = 0; rc == USM_OK && i < usm_periodic_sweep_event_count(s); ++i) {
        const usm_periodic_event *ev = usm_periodic_sweep_event_at(s, i);
        if (ev->type == USM_PEVENT_STABILITY_CHANGE && ev->kind == USM_CROSSING_NEIMARK_SACKER) {
            *f0 = ev->value;
            *freq = ev->squeal_frequency;
            break;
        }
    }
    usm_periodic_sweep_free(s);
}

int main(void)
{
    const usm_model *m = usm_model_variant("4dof", "imperfect");
    const clock_t c0 = clock();
    usm_params p;
    usm_params_default(&p);
    usm_envelope_options o;
    usm_envelope_options_default(&o);
    o.x = (usm_envelope_axis){"mode_split", 0.024, 0.026};
    /* the curve near the middle: a region on either side of it */
    o.y = (usm_envelope_axis){"F0", 0.999, 1.001};
    o.raster = 8;
    usm_envelope *e = usm_envelope_alloc(m);
    const int rc = usm_envelope_run(e, &p, &o);
    printf("envelope: %.2f s CPU\n", (double)(clock() - c0) / CLOCKS_PER_SEC);
    CHECK(rc == USM_OK, "envelope: %s", usm_envelope_message(e));
    const usm_envelope_curve *c = NULL;
    for (size_t i = 0; i < usm_envelope_curve_count(e); ++i) {
        const usm_envelope_curve *ci = usm_envelope_curve_at(e, i);
        printf("curve %zu %s: %zu points, (%.9g, %.12g) .. (%.9g, %.12g), ends %s %s\n", i,
               usm_envelope_kind_name(ci->kind), ci->npoints, ci->xy[0], ci->xy[1],
               ci->xy[2 * ci->npoints - 2], ci->xy[2 * ci->npoints - 1],
               usm_envelope_end_name(ci->end[0]), usm_envelope_end_name(ci->end[1]));
        if (ci->kind == USM_ENVELOPE_STABILITY && !c)
            c = ci;
    }
    if (CHECK(c != NULL, "no stability curve") &&
        CHECK(c->npoints >= 4 && c->frequency, "%zu points, frequency %s", c->npoints,
              c->frequency ? "given" : "NULL")) {
        /* box to box, the whole width */
        CHECK(c->end[0] == USM_ENVELOPE_END_BOX && c->end[1] == USM_ENVELOPE_END_BOX &&
                  fmin(c->xy[0], c->xy[2 * c->npoints - 2]) == 0.024 &&
                  fmax(c->xy[0], c->xy[2 * c->npoints - 2]) == 0.026,
              "the curve does not cross the box");
        const size_t at[3] = {c->npoints / 3, 2 * c->npoints / 3, c->npoints - 1};
        for (int j = 0; j < 3; ++j) {
            const double *q = c->xy + 2 * at[j];
            double f0, freq;
            sweep_ns(m, q[0], 0.999, q[1] + 2e-5, &f0, &freq);
            printf("mode_split %.9g: curve F0 %.12g N, %.6f Hz; sweep %.12g N (%.1e), %.6f Hz "
                   "(%.1e)\n",
                   q[0], q[1], c->frequency[at[j]], f0, fabs(q[1] / f0 - 1), freq,
                   fabs(c->frequency[at[j]] / freq - 1));
            CHECK(fabs(q[1] / f0 - 1) <= 1e-7, "mode_split %g: curve F0 %.12g, sweep %.12g",
                  q[0], q[1], f0);
            CHECK(fabs(c->frequency[at[j]] / freq - 1) <= 1e-6,
                  "mode_split %g: curve %.6f Hz, sweep %.6f Hz", q[0], c->frequency[at[j]], freq);
        }
    }
    /* the regions against the orbit and its multipliers at their samples */
    int above = 0, below = 0;
    usm_periodic *w = usm_periodic_alloc(m);
    for (size_t i = 0; c && i < usm_envelope_region_count(e); ++i) {
        const usm_envelope_region *r = usm_envelope_region_at(e, i);
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
        double f = NAN;
        (void)sscanf(strstr(r->message, "squeal at ") ? strstr(r->message, "squeal at ") : "",
                     "squeal at %lf", &f);
        printf("region %zu at (%.6g, %.7g), %zu cells: %s (%s); solved: max |lambda| %.9f, "
               "pair %.9f at %.6f Hz; curve there F0 %.9g, %.6f Hz\n",
               i, r->x, r->y, r->cells, r->class_name, r->message, res.floquet.max_modulus,
               sq.modulus, sq.frequency, c->xy[2 * j + 1], c->frequency[j]);
        CHECK(strcmp(r->class_name, want) == 0, "region at (%g, %g): %s, its orbit says %s", r->x,
              r->y, r->class_name, want);
        if (r->y > c->xy[2 * j + 1]) {
            above++;
            CHECK(strcmp(r->class_name, "squeal") == 0, "above the curve: %s", r->class_name);
            CHECK(fabs(f / c->frequency[j] - 1) <= 0.01 && fabs(f / sq.frequency - 1) <= 1e-6,
                  "squeal at %g Hz, curve %g Hz, orbit %g Hz", f, c->frequency[j], sq.frequency);
        } else {
            below++;
            CHECK(strcmp(r->class_name, "contact_closed") == 0, "below the curve: %s",
                  r->class_name);
        }
    }
    usm_periodic_free(w);
    CHECK(above >= 1 && below >= 1, "regions above %d, below %d", above, below);
    usm_envelope_free(e);
    printf("total: %.2f s CPU\n", (double)(clock() - c0) / CLOCKS_PER_SEC);
    return failures != 0;
}
