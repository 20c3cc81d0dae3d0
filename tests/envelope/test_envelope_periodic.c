/* The imperfect motor's envelope in (phase_error, mode_split): contact_loss
 * and stick_loss as curves (runtime/envelope/envelope_periodic.c), against
 * independent truth.
 *
 * 1. The curves pass through the one-parameter onsets (docs/unilateral.md,
 *    docs/periodic.md) on both axes, where F_n has two equal minima a
 *    period: where contact_loss meets mode_split = 0 the phase error is
 *    0.501363295 rad = 28.726 deg, where it meets phase_error = 0 the mode
 *    split is 1.64256 % (3-DOF).  Each to the docs' digits, and to 1e-8
 *    relative of the one-parameter periodic sweep's located event along
 *    that axis.
 * 2. Five interior points of each curve agree with a one-parameter
 *    periodic sweep's located event across the curve (usm_periodic_sweep:
 *    its own continuation in one parameter and its own location of the
 *    event on the branch's arc), in the parameter the curve crosses most
 *    steeply, to 1e-8 of the box's side.
 * 3. The regions: below the curve the orbit's stick is lost (stick_loss
 *    lies at 0.2724860 rad on the axis), above it the contact opens.
 * 4. stick_loss (the orbit's largest |F_t| - mu0 F_n = 0) from its onset
 *    on mode_split = 0, 0.2724860 rad (docs/periodic.md), into the box:
 *    its end on the axis within 1e-8 (relative) of the sweep's located
 *    event, five points against sweeps across it to 1e-8 of the box's
 *    side, the stick admissible to its left and lost to its right.  (With
 *    the orbit's located extreme as the defining function, the former
 *    formulation, the points were 1e-5 of the side off.)
 * 5. stick_loss around its turn in phase_error (0.65228 rad near mode
 *    split 2.05 %, a fold of the curve in the plane): in a box of 0.005 rad
 *    x 0.1 % about it the curve enters at one side and leaves at the
 *    opposite one, its largest phase error inside, and that point agrees
 *    with a sweep across it (the engine's arclength passes the turn; with
 *    the parameters' columns by forward differences against the full shot
 *    the curve was lost there, in the box's small units).
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

#define DEG (3.14159265358979323846 / 180.0)
/* Boxes along mode_split = 0 around each onset (see the header: where two
 * equal minima a period compete the continuation is slow) */
static double box[4];

static const char *const axis[2] = {"phase_error", "mode_split"};

/* The located event `type` of a periodic sweep of `over` from..to, the
 * other parameter at `other` (NaN when none). */
static double sweep_event(const usm_model *m, int over, double other, double from, double to,
                          usm_pevent_type type)
{
    usm_params p;
    usm_params_default(&p);
    *usm_params_field(&p, usm_params_find(axis[1 - over])) = other;
    usm_periodic_sweep *s = usm_periodic_sweep_alloc(m);
    usm_periodic_sweep_options o;
    usm_periodic_sweep_options_default(&o);
    o.over = axis[over];
    o.from = from;
    o.to = to;
    o.points = 2;
    double v = NAN;
    const int rc = usm_periodic_sweep_run(s, &p, &o);
    CHECK(rc == USM_OK, "sweep %s at %s = %g: %s", axis[over], axis[1 - over], other,
          usm_periodic_sweep_message(s));
    for (size_t i = 0; rc == USM_OK && i < usm_periodic_sweep_event_count(s); ++i)
        if (usm_periodic_sweep_event_at(s, i)->type == type) {
            v = usm_periodic_sweep_event_at(s, i)->value;
            break;
        }
    usm_periodic_sweep_free(s);
    return v;
}

static const usm_envelope_curve *curve_of(const usm_envelope *e, usm_envelope_kind kind)
{
    for (size_t i = 0; i < usm_envelope_curve_count(e); ++i)
        if (usm_envelope_curve_at(e, i)->kind == kind)
            return usm_envelope_curve_at(e, i);
    return NULL;
}

/* The point where a curve of `kind` meets the axis `a` = 0 (an end of one
 * of them): its other coordinate, NaN when none does. */
static double on_axis(const usm_envelope *e, usm_envelope_kind kind, int a)
{
    for (size_t i = 0; i < usm_envelope_curve_count(e); ++i) {
        const usm_envelope_curve *c = usm_envelope_curve_at(e, i);
        for (int end = 0; c->kind == kind && end < 2; ++end) {
            const double *p = c->xy + 2 * (end ? c->npoints - 1 : 0);
            if (p[a] == 0.0)
                return p[1 - a];
        }
    }
    return NAN;
}

static void onset(const usm_model *m, const usm_envelope *e, usm_envelope_kind kind, int a,
                  double want, double docs_tol, usm_pevent_type type)
{
    const double v = on_axis(e, kind, a);
    const double ref = sweep_event(m, 1 - a, 0.0, box[2 * (1 - a)], box[2 * (1 - a) + 1], type);
    printf("%s %s at %s = 0: %.12g, sweep %.12g (%.2e), docs %.10g\n", m->name,
           usm_envelope_kind_name(kind), axis[a], v, ref, fabs(v / ref - 1), want);
    CHECK(fabs(v - want) <= docs_tol, "%s %s at %s = 0: %.12g, the docs say %.10g", m->name,
          usm_envelope_kind_name(kind), axis[a], v, want);
    CHECK(fabs(v / ref - 1) <= 1e-8, "%s %s at %s = 0: %.12g, the sweep's event %.12g",
          m->name, usm_envelope_kind_name(kind), axis[a], v, ref);
}

/* Point i (not the last) of the curve against a sweep across it: its
 * distance from the sweep's located event, of the box's side. */
static double point_check(const usm_model *m, const usm_envelope_curve *c, size_t i,
                          usm_pevent_type type)
{
    const double span[2] = {box[1] - box[0], box[3] - box[2]};
    const double *p = c->xy + 2 * i, *q = c->xy + 2 * (i + 1);
    /* the parameter in which the curve is steeper is the one swept */
    const int over = fabs((q[0] - p[0]) / span[0]) < fabs((q[1] - p[1]) / span[1]) ? 0 : 1;
    const double h = 0.02 * span[over];
    const double ref = sweep_event(m, over, p[1 - over], p[over] - h, p[over] + h, type);
    /* of the box's side, as the stationary curves' (near an axis the value
     * itself is small) */
    const double d = fabs(p[over] - ref) / span[over];
    printf("%s %s point %zu (%.9g, %.9g): sweep in %s %.12g (%.2e)\n", m->name,
           usm_envelope_kind_name(c->kind), i, p[0], p[1], axis[over], ref, d);
    CHECK(d <= 1e-8, "%s %s point %zu: %.12g, the sweep's event %.12g", m->name,
          usm_envelope_kind_name(c->kind), i, p[over], ref);
    return d;
}

/* Five interior points against sweeps across the curve. */
static void five_points(const usm_model *m, const usm_envelope_curve *c, usm_pevent_type type)
{
    CHECK(c->npoints >= 7, "%s: %zu points", usm_envelope_kind_name(c->kind), c->npoints);
    if (c->npoints < 7)
        return;
    double worst = 0;
    for (int j = 1; j <= 5; ++j)
        worst = fmax(worst, point_check(m, c, (size_t)j * (c->npoints - 1) / 6, type));
    printf("%s %s: five points, largest relative difference %.2e\n", m->name,
           usm_envelope_kind_name(c->kind), worst);
}

static usm_envelope *run(const usm_model *m, double x0, double x1, double y0, double y1)
{
    box[0] = x0;
    box[1] = x1;
    box[2] = y0;
    box[3] = y1;
    usm_params p;
    usm_params_default(&p);
    usm_envelope_options o;
    usm_envelope_options_default(&o);
    o.x = (usm_envelope_axis){"phase_error", x0, x1};
    o.y = (usm_envelope_axis){"mode_split", y0, y1};
    o.raster = 40;
    usm_envelope *e = usm_envelope_alloc(m);
    const clock_t c0 = clock();
    const int rc = usm_envelope_run(e, &p, &o);
    printf("%s envelope (%g..%g) x (%g..%g): %.2f s CPU\n", m->name, x0, x1, y0, y1,
           (double)(clock() - c0) / CLOCKS_PER_SEC);
    CHECK(rc == USM_OK, "%s: %s", m->name, usm_envelope_message(e));
    for (size_t i = 0; i < usm_envelope_curve_count(e); ++i) {
        const usm_envelope_curve *c = usm_envelope_curve_at(e, i);
        printf("%s curve %zu %s: %zu points, (%.9g, %.9g) .. (%.9g, %.9g), ends %s %s\n",
               m->name, i, usm_envelope_kind_name(c->kind), c->npoints, c->xy[0], c->xy[1],
               c->xy[2 * c->npoints - 2], c->xy[2 * c->npoints - 1],
               usm_envelope_end_name(c->end[0]), usm_envelope_end_name(c->end[1]));
    }
    for (size_t i = 0; i < usm_envelope_region_count(e); ++i) {
        const usm_envelope_region *r = usm_envelope_region_at(e, i);
        printf("%s region %zu: %s at (%.4g, %.4g), %zu cells\n", m->name, i, r->class_name,
               r->x, r->y, r->cells);
    }
    return e;
}

static const char *class_at(const usm_envelope *e, double x, double y)
{
    const int r = usm_envelope_region_of(e, x, y);
    return r >= 0 ? usm_envelope_region_at(e, (size_t)r)->class_name : "(none)";
}

int main(void)
{
    const usm_model *m3 = usm_model_variant("3dof", "imperfect");

    /* 3-DOF contact_loss from mode_split = 0 into the box */
    usm_envelope *e = run(m3, 0.49, 0.53, 0.0, 0.004);
    const usm_envelope_curve *c = curve_of(e, USM_ENVELOPE_CONTACT_LOSS);
    if (CHECK(c != NULL, "3dof: no contact_loss curve")) {
        onset(m3, e, USM_ENVELOPE_CONTACT_LOSS, 1, 0.501363295, 1e-9, USM_PEVENT_CONTACT_LOSS);
        CHECK(fabs(on_axis(e, USM_ENVELOPE_CONTACT_LOSS, 1) / DEG - 28.726) <= 5e-4,
              "3dof contact_loss: not 28.726 deg");
        five_points(m3, c, USM_PEVENT_CONTACT_LOSS);
    }
    CHECK(strcmp(class_at(e, 0.491, 0.0035), "stick_lost") == 0, "3dof at (0.491, 0.0035): %s",
          class_at(e, 0.491, 0.0035));
    CHECK(strcmp(class_at(e, 0.529, 0.0002), "contact_open") == 0, "3dof at (0.529, 0.0002): %s",
          class_at(e, 0.529, 0.0002));
    usm_envelope_free(e);

    /* 3-DOF contact_loss from phase_error = 0 */
    e = run(m3, 0.0, 0.04, 0.015, 0.018);
    c = curve_of(e, USM_ENVELOPE_CONTACT_LOSS);
    if (CHECK(c != NULL, "3dof: no contact_loss curve at phase_error = 0")) {
        onset(m3, e, USM_ENVELOPE_CONTACT_LOSS, 0, 0.0164256, 5e-8, USM_PEVENT_CONTACT_LOSS);
        five_points(m3, c, USM_PEVENT_CONTACT_LOSS);
    }
    usm_envelope_free(e);

    /* 3-DOF stick_loss from mode_split = 0 */
    e = run(m3, 0.26, 0.29, 0.0, 0.004);
    c = curve_of(e, USM_ENVELOPE_STICK_LOSS);
    if (CHECK(c != NULL, "3dof: no stick_loss curve")) {
        onset(m3, e, USM_ENVELOPE_STICK_LOSS, 1, 0.2724860, 5e-8, USM_PEVENT_STICK_LOSS);
        five_points(m3, c, USM_PEVENT_STICK_LOSS);
    }
    CHECK(strcmp(class_at(e, 0.262, 0.0002), "stick_admissible") == 0,
          "3dof at (0.262, 0.0002): %s", class_at(e, 0.262, 0.0002));
    CHECK(strcmp(class_at(e, 0.288, 0.0002), "stick_lost") == 0, "3dof at (0.288, 0.0002): %s",
          class_at(e, 0.288, 0.0002));
    usm_envelope_free(e);

    /* 3-DOF stick_loss around its turn */
    e = run(m3, 0.65, 0.655, 0.020, 0.021);
    c = curve_of(e, USM_ENVELOPE_STICK_LOSS);
    if (CHECK(c != NULL && c->npoints >= 3, "3dof: no stick_loss curve at the turn")) {
        const double *first = c->xy, *last = c->xy + 2 * (c->npoints - 1);
        CHECK(c->end[0] == USM_ENVELOPE_END_BOX && c->end[1] == USM_ENVELOPE_END_BOX &&
                  fabs(fabs(first[1] - last[1]) - 0.001) < 1e-12,
              "3dof stick_loss at the turn: from (%.9g, %.9g) to (%.9g, %.9g), ends %s %s",
              first[0], first[1], last[0], last[1], usm_envelope_end_name(c->end[0]),
              usm_envelope_end_name(c->end[1]));
        size_t imax = 0;
        for (size_t i = 1; i < c->npoints; ++i)
            if (c->xy[2 * i] > c->xy[2 * imax])
                imax = i;
        printf("3dof_imperfect stick_loss: the turn at point %zu of %zu, phase error %.10g\n",
               imax, c->npoints, c->xy[2 * imax]);
        CHECK(c->xy[2 * imax] > fmax(first[0], last[0]) + 5e-4 && imax + 1 < c->npoints,
              "3dof stick_loss: the turn is not inside the box");
        if (imax + 1 < c->npoints)
            point_check(m3, c, imax, USM_PEVENT_STICK_LOSS);
    }
    usm_envelope_free(e);

    return failures != 0;
}
