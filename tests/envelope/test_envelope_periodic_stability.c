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
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "usm.h"
#include "usm_envelope.h"
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
    o.y = (usm_envelope_axis){"F0", 0.999, 1.0};
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
    usm_envelope_free(e);
    printf("total: %.2f s CPU\n", (double)(clock() - c0) / CLOCKS_PER_SEC);
    return failures != 0;
}
