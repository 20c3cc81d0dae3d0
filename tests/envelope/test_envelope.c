/* The envelope's curves against independent truth.
 *
 * 1. tilt_zero in (F0, T) of the 3-DOF model is the closed form
 *    T = R sqrt(m0^2 - R^2 F0^2) / H (docs/operating-point.md) at every point,
 *    to 1e-12 relative (in F0, given T, where the curve falls steeply to
 *    T = 0 and T is ill-conditioned in F0).
 * 2. The start threshold from rest: in (f, F0) the tilt_zero curve is the
 *    line F0 = sqrt(m0^2 - (H T / R)^2) / R (1e-12; it does not depend on f),
 *    and the start margin of the operating-point rule (usm_op_start_margin,
 *    Newton on the stationary equations at theta = 0 with m0 free) vanishes
 *    on it (1e-10).
 * 3. Five points of each curve kind agree with the one-parameter sweep's
 *    located event across the curve (usm_sweep: its own continuation and its
 *    own location of the event): tilt_zero, fold, stick_limit, stability
 *    (3-DOF, f x T), stall (4-DOF, f x F0), friction_saturation (4-DOF,
 *    f x T), to 1e-8 of the box's side.
 * 4. Small maps (usm_map_run, 7 x 7; 3-DOF and 4-DOF, f x T): every cell
 *    whose neighbourhood (half a map cell each way) lies in one region has
 *    the class and root of that region.
 * 5. The cusp of the fold in (f, m0) (tilt range up to 1 rad): one, at the
 *    fold curve's least m0 and greatest f.
 * 6. Bad input: an unknown parameter, LO >= HI, the same parameter twice:
 *    USM_EINPUT with the field named.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>

#include "usm.h"
#include "usm_envelope.h"
#include "usm_map.h"
#include "usm_sweep.h"

#include "check.h"

static usm_envelope *envelope(const char *model, const usm_params *p, const char *x, double xlo,
                              double xhi, const char *y, double ylo, double yhi)
{
    usm_envelope_options o;
    usm_envelope_options_default(&o);
    o.x = (usm_envelope_axis){x, xlo, xhi};
    o.y = (usm_envelope_axis){y, ylo, yhi};
    usm_envelope *e = usm_envelope_alloc(usm_model_find(model));
    const int rc = usm_envelope_run(e, p, &o);
    CHECK(rc == USM_OK, "%s %s x %s: %d %s", model, x, y, rc, usm_envelope_message(e));
    return e;
}

static const usm_envelope_curve *curve_of(const usm_envelope *e, usm_envelope_kind kind)
{
    for (size_t i = 0; i < usm_envelope_curve_count(e); ++i)
        if (usm_envelope_curve_at(e, i)->kind == kind)
            return usm_envelope_curve_at(e, i);
    return NULL;
}

static double par(const usm_params *p, const char *name)
{
    return usm_params_get(p, usm_params_find(name));
}

static void closed_form_tilt_zero(void)
{
    usm_params p;
    usm_params_default(&p);
    usm_envelope *e = envelope("3dof", &p, "F0", 0.5, 1.5, "T", 0.0, 0.008);
    const usm_envelope_curve *c = curve_of(e, USM_ENVELOPE_TILT_ZERO);
    const double R = par(&p, "R"), H = par(&p, "H"), m0 = par(&p, "m0");
    double worst = 0;
    if (CHECK(c && c->npoints >= 10, "no tilt_zero curve in F0 x T")) {
        for (size_t i = 0; i < c->npoints; ++i) {
            const double F0 = c->xy[2 * i], T = c->xy[2 * i + 1];
            const double Tc = R * sqrt(m0 * m0 - R * R * F0 * F0) / H;
            /* where the curve falls steeply to T = 0 (F0 -> m0 / R) T is
             * ill-conditioned in F0: there F0 is compared, given T */
            const double F0c = sqrt(m0 * m0 - (H * T / R) * (H * T / R)) / R;
            const double slope = R * R * R * F0 / (H * sqrt(m0 * m0 - R * R * F0 * F0));
            const double err = slope * F0 / Tc <= 1.0 ? fabs(T - Tc) / Tc : fabs(F0 - F0c) / F0c;
            worst = fmax(worst, err);
        }
        CHECK(worst <= 1e-12, "tilt_zero against the closed form: %.3g relative", worst);
        printf("tilt_zero (F0, T): %zu points, closed form to %.2g relative\n", c->npoints, worst);
    }
    usm_envelope_free(e);
}

static void start_threshold(void)
{
    usm_params p;
    usm_params_default(&p);
    const usm_model *m = usm_model_find("3dof");
    usm_envelope *e = envelope("3dof", &p, "f", 36000, 40000, "F0", 0.1, 2.0);
    const usm_envelope_curve *c = curve_of(e, USM_ENVELOPE_TILT_ZERO);
    const double R = par(&p, "R"), H = par(&p, "H"), m0 = par(&p, "m0"), T = par(&p, "T");
    const double F0s = sqrt(m0 * m0 - (H * T / R) * (H * T / R)) / R;
    if (CHECK(c && c->npoints >= 10, "no tilt_zero curve in f x F0")) {
        double worst = 0, fmin_ = INFINITY, fmax_ = -INFINITY, margin_worst = 0;
        for (size_t i = 0; i < c->npoints; ++i) {
            worst = fmax(worst, fabs(c->xy[2 * i + 1] - F0s) / F0s);
            fmin_ = fmin(fmin_, c->xy[2 * i]);
            fmax_ = fmax(fmax_, c->xy[2 * i]);
        }
        for (int k = 0; k < 5; ++k) {
            const size_t i = c->npoints * (size_t)(k + 1) / 6;
            usm_params q = p;
            q.f = c->xy[2 * i];
            q.F0 = c->xy[2 * i + 1];
            double margin = NAN;
            CHECK(usm_op_start_margin(m, &q, &margin) == USM_OK, "start margin at f = %g", q.f);
            margin_worst = fmax(margin_worst, fabs(margin));
        }
        CHECK(worst <= 1e-12, "the start threshold depends on f: %.3g relative off F0*", worst);
        CHECK(fmin_ == 36000 && fmax_ == 40000, "tilt_zero spans f %g .. %g, not the box", fmin_,
              fmax_);
        CHECK(margin_worst <= 1e-10, "start margin on tilt_zero: %.3g", margin_worst);
        printf("start threshold: F0 = %.16g on all %zu points (F0* to %.2g), start margin <= %.2g\n",
               c->xy[1], c->npoints, worst, margin_worst);
    }
    usm_envelope_free(e);
}

static usm_event_type event_of(usm_envelope_kind k)
{
    switch (k) {
    case USM_ENVELOPE_TILT_ZERO:
        return USM_EVENT_TILT_ZERO;
    case USM_ENVELOPE_FOLD:
        return USM_EVENT_FOLD;
    case USM_ENVELOPE_STICK_LIMIT:
        return USM_EVENT_STICK_LIMIT;
    case USM_ENVELOPE_STALL:
        return USM_EVENT_STALL;
    case USM_ENVELOPE_FRICTION_SATURATION:
        return USM_EVENT_FRICTION_SATURATION;
    default:
        return USM_EVENT_STABILITY_CHANGE;
    }
}

/* The sweep's event of `type` nearest to `expect`, sweeping `over` across
 * [lo, hi] (both directions: the event may lie on the branch of another
 * start) with the other parameter `fixed_name` at `fixed`. */
static double sweep_event(const char *model, const usm_params *p0, const char *over, double lo,
                          double hi, const char *fixed_name, double fixed, usm_event_type type,
                          double expect)
{
    usm_params p = *p0;
    *usm_params_field(&p, usm_params_find(fixed_name)) = fixed;
    double best = NAN;
    for (int d = 0; d < 2; ++d) {
        usm_sweep_options o;
        usm_sweep_options_default(&o);
        o.over = over;
        o.from = d == 0 ? lo : hi;
        o.to = d == 0 ? hi : lo;
        o.points = 5;
        o.floquet = type == USM_EVENT_STABILITY_CHANGE;
        o.operating_point = 0;
        o.threads = 1;
        usm_sweep *s = usm_sweep_alloc(usm_model_find(model));
        if (usm_sweep_run(s, &p, &o) == USM_OK)
            for (size_t k = 0; k < usm_sweep_event_count(s); ++k) {
                const usm_sweep_event *ev = usm_sweep_event_at(s, k);
                if (ev->type == type && !(fabs(ev->value - expect) >= fabs(best - expect)))
                    best = ev->value;
            }
        usm_sweep_free(s);
    }
    return best;
}

/* Five interior points of the curve of `kind`, each against the sweep across
 * it (over the parameter the curve moves least in there). */
static void against_sweep(const char *model, const usm_params *p, const usm_envelope *e,
                          const char *xname, double xlo, double xhi, const char *yname, double ylo,
                          double yhi, usm_envelope_kind kind)
{
    const usm_envelope_curve *c = curve_of(e, kind);
    if (!CHECK(c && c->npoints >= 12, "%s: no %s curve", model, usm_envelope_kind_name(kind)))
        return;
    double worst = 0;
    int compared = 0;
    /* ten candidates, of which the sweep sees at least five: beyond a
     * codimension-two point a curve may lie on a branch the sweep, which
     * follows the smallest root's, does not reach */
    for (int k = 0; k < 10 && compared < 5; ++k) {
        const size_t i = 1 + (c->npoints - 3) * (size_t)(2 * k + 1) / 20;
        const double x = c->xy[2 * i], y = c->xy[2 * i + 1];
        const double tx = (c->xy[2 * i + 2] - c->xy[2 * i - 2]) / (xhi - xlo),
                     ty = (c->xy[2 * i + 3] - c->xy[2 * i - 1]) / (yhi - ylo);
        const int over_y = fabs(tx) > fabs(ty);
        const double w = over_y ? yhi - ylo : xhi - xlo, v = over_y ? y : x;
        const double got =
            over_y ? sweep_event(model, p, yname, y - 0.02 * w, y + 0.02 * w, xname, x,
                                 event_of(kind), y)
                   : sweep_event(model, p, xname, x - 0.02 * w, x + 0.02 * w, yname, y,
                                 event_of(kind), x);
        const double err = fabs(got - v) / w;
        if (isnan(got))
            continue;
        compared++;
        CHECK(err <= 1e-8, "%s %s point %d (%.12g, %.12g): the sweep over %s has it at %.12g "
              "(%.3g of the side)", model, usm_envelope_kind_name(kind), k, x, y,
              over_y ? yname : xname, got, err);
        if (isfinite(err))
            worst = fmax(worst, err);
    }
    CHECK(compared == 5, "%s %s: the sweep saw only %d of ten points", model,
          usm_envelope_kind_name(kind), compared);
    printf("%s %s: %zu points, %d against the sweep's event: worst %.2g of the box's side\n",
           model, usm_envelope_kind_name(kind), c->npoints, compared, worst);
}

static void curves_against_sweeps(void)
{
    usm_params p;
    usm_params_default(&p);
    usm_envelope *e = envelope("3dof", &p, "f", 30000, 46000, "T", 0.0, 0.008);
    const usm_envelope_kind kinds[] = {USM_ENVELOPE_TILT_ZERO, USM_ENVELOPE_FOLD,
                                       USM_ENVELOPE_STICK_LIMIT, USM_ENVELOPE_STABILITY};
    for (int k = 0; k < 4; ++k)
        against_sweep("3dof", &p, e, "f", 30000, 46000, "T", 0.0, 0.008, kinds[k]);
    CHECK(usm_envelope_codim2_count(e) >= 1, "no codimension-two point in f x T");
    for (size_t k = 0; k < usm_envelope_codim2_count(e); ++k)
        printf("codim2 %s at (%.10g, %.10g)\n", usm_envelope_codim2_at(e, k)->type,
               usm_envelope_codim2_at(e, k)->x, usm_envelope_codim2_at(e, k)->y);
    usm_envelope_free(e);
    e = envelope("4dof", &p, "f", 36000, 40000, "F0", 0.1, 2.0);
    against_sweep("4dof", &p, e, "f", 36000, 40000, "F0", 0.1, 2.0, USM_ENVELOPE_STALL);
    usm_envelope_free(e);
    e = envelope("4dof", &p, "f", 30000, 46000, "T", 0.0, 0.008);
    against_sweep("4dof", &p, e, "f", 30000, 46000, "T", 0.0, 0.008,
                  USM_ENVELOPE_FRICTION_SATURATION);
    usm_envelope_free(e);
}

static void map_against_regions(const char *model, const char *xn, double xlo, double xhi,
                                const char *yn, double ylo, double yhi)
{
    usm_params p;
    usm_params_default(&p);
    const usm_model *m = usm_model_find(model);
    usm_envelope *e = envelope(model, &p, xn, xlo, xhi, yn, ylo, yhi);
    usm_map_options o;
    usm_map_options_default(&o);
    o.x = (usm_map_axis){xn, xlo, xhi, 7};
    o.y = (usm_map_axis){yn, ylo, yhi, 7};
    o.threads = 1;
    o.boundaries = 0;
    usm_map *map = usm_map_alloc(m);
    int compared = 0;
    if (CHECK(usm_map_run(map, &p, &o) == USM_OK, "map: %s", usm_map_message(map))) {
        const double hx = 0.5 * (xhi - xlo) / 6, hy = 0.5 * (yhi - ylo) / 6;
        for (int i = 0; i < 7; ++i)
            for (int j = 0; j < 7; ++j) {
                const usm_map_cell *cell = usm_map_cell_at(map, i, j);
                const int r = usm_envelope_region_of(e, cell->x, cell->y);
                int away = r >= 0;
                for (int c = 0; c < 4 && away; ++c) {
                    const double x = fmin(xhi, fmax(xlo, cell->x + (c & 1 ? hx : -hx)));
                    const double y = fmin(yhi, fmax(ylo, cell->y + (c & 2 ? hy : -hy)));
                    away = usm_envelope_region_of(e, x, y) == r;
                }
                if (!away)
                    continue;
                const usm_envelope_region *reg = usm_envelope_region_at(e, (size_t)r);
                compared++;
                CHECK(cell->point.op.cls == reg->cls && cell->point.op.index == reg->root,
                      "%s map cell (%g, %g): %s root %d, region %d: %s root %d", model, cell->x,
                      cell->y, usm_point_op_class_name(cell->point.op.cls), cell->point.op.index,
                      r, usm_point_op_class_name(reg->cls), reg->root);
            }
    }
    CHECK(compared >= 20, "%s: only %d map cells away from the curves", model, compared);
    printf("%s map 7 x 7 (%s x %s) against the regions: %d cells away from the curves compared\n",
           model, xn, yn, compared);
    usm_map_free(map);
    usm_envelope_free(e);
}

/* The fold of the 3-DOF model in (f, m0) with the tilt range up to 1 rad:
 * its cusp, where the two fold branches meet, is the curve's extreme point
 * in both f and m0 (both derivatives along the curve vanish there), so the
 * located cusp is the curve point of least m0 and greatest f, to the
 * curve's spacing. */
static void cusp(void)
{
    usm_params p;
    usm_params_default(&p);
    usm_envelope_options o;
    usm_envelope_options_default(&o);
    o.x = (usm_envelope_axis){"f", 20000, 40000};
    o.y = (usm_envelope_axis){"m0", 15, 100};
    o.steady.theta_max = 1.0;
    o.stability = 0;
    usm_envelope *e = usm_envelope_alloc(usm_model_find("3dof"));
    CHECK(usm_envelope_run(e, &p, &o) == USM_OK, "f x m0: %s", usm_envelope_message(e));
    const usm_envelope_curve *c = curve_of(e, USM_ENVELOPE_FOLD);
    const usm_envelope_codim2 *k = NULL;
    int ncusp = 0;
    for (size_t i = 0; i < usm_envelope_codim2_count(e); ++i)
        if (strcmp(usm_envelope_codim2_at(e, i)->type, "cusp") == 0) {
            k = usm_envelope_codim2_at(e, i);
            ncusp++;
        }
    if (CHECK(c && k && ncusp == 1, "f x m0: %d cusps, want one on a fold curve", ncusp)) {
        double mmin = INFINITY, fmax_ = -INFINITY;
        for (size_t i = 0; i < c->npoints; ++i) {
            mmin = fmin(mmin, c->xy[2 * i + 1]);
            fmax_ = fmax(fmax_, c->xy[2 * i]);
        }
        CHECK(k->y <= mmin && mmin - k->y <= 1e-3 * k->y && k->x >= fmax_ &&
                  k->x - fmax_ <= 1e-4 * k->x,
              "cusp (%.10g, %.10g): the curve's least m0 %.10g, greatest f %.10g", k->x, k->y,
              mmin, fmax_);
        printf("cusp of the fold in f x m0: f = %.10g Hz, m0 = %.10g N m, theta = %.4g rad "
               "(%zu fold points)\n", k->x, k->y, k->u[0], c->npoints);
    }
    usm_envelope_free(e);
}

static void bad_input(void)
{
    usm_params p;
    usm_params_default(&p);
    usm_envelope *e = usm_envelope_alloc(usm_model_find("3dof"));
    usm_envelope_options o;
    usm_envelope_options_default(&o);
    struct {
        usm_envelope_axis x, y;
        const char *says;
    } cases[] = {{{"nope", 1, 2}, {"F0", 0.1, 2}, "x: unknown parameter 'nope'"},
                 {{"f", 40000, 36000}, {"F0", 0.1, 2}, "x: the range"},
                 {{"f", 36000, 40000}, {"F0", 2, 2}, "y: the range"},
                 {{"f", 36000, 40000}, {"f", 30000, 46000}, "y: the same parameter as x"}};
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
        o.x = cases[k].x;
        o.y = cases[k].y;
        const int rc = usm_envelope_run(e, &p, &o);
        CHECK(rc == USM_EINPUT && strstr(usm_envelope_message(e), cases[k].says),
              "case %zu: %d '%s'", k, rc, usm_envelope_message(e));
    }
    usm_envelope_free(e);
}

int main(void)
{
    gsl_set_error_handler_off();
    closed_form_tilt_zero();
    start_threshold();
    curves_against_sweeps();
    map_against_regions("3dof", "f", 30000, 46000, "T", 0.0, 0.008);
    map_against_regions("4dof", "f", 30000, 46000, "T", 0.0, 0.008);
    cusp();
    bad_input();
    return failures != 0;
}
