/* The envelope's codimension-two points on fold curves, and where the
 * stability curve ends near the axis, against a second Floquet method.
 *
 * 1. Fold curves (3-DOF twist_integrated, f 20-40 kHz x m0 15-100 N m, the
 *    tilt range up to 1 rad): the stability function is noise along a fold
 *    (one multiplier is 1 there), so the fold curve monitors the other
 *    multipliers instead.  Both stability curves of the box end on the fold;
 *    each end is a fold/stability point (fold-Hopf) found on the fold curve.
 *    Independent check: at each point the multipliers by CVODES on the
 *    variational equations (rtol 1e-12, not the library's default
 *    exponential) have one multiplier at 1 and another on the unit circle, at
 *    an angle away from 0 (so not a Bogdanov-Takens point), and no
 *    bogdanov_takens point is reported in the box (none exists there: the
 *    second multiplier nearest 1 stays below 0.93 in modulus on the fold).
 * 2. The stability boundary near the axis (3-DOF, F0 0.2-1.5 N x T 0-8 mN m):
 *    the curve from F0 = 0.2 N turns at a corner (stability/stability: two
 *    pairs on the unit circle, checked by the variational method), the
 *    other pair's leg is continued from there down to the axis, where it is
 *    lost at a tilt below 1e-7 rad, not at theta = 0.  Its end and a point
 *    five steps inside are on the unit circle by the variational method too
 *    (the curve is right up to its end).
 *    Why it cannot reach theta = 0: the linearisation has a pair whose
 *    frequency grows without bound as theta -> 0, in the tilt-vector
 *    coordinates (regular at the axis) as well: d arg(lambda) / d theta
 *    grows as theta^-1.5 from theta = 3e-7 to 3e-8 (arg ~ theta^-1/2), so
 *    the multipliers have no limit on the axis (their moduli converge).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>

#include "usm.h"
#include "usm_envelope.h"

#include "check.h"

static const usm_envelope_curve *curve_of(const usm_envelope *e, usm_envelope_kind kind,
                                          size_t skip)
{
    for (size_t i = 0; i < usm_envelope_curve_count(e); ++i)
        if (usm_envelope_curve_at(e, i)->kind == kind && skip-- == 0)
            return usm_envelope_curve_at(e, i);
    return NULL;
}

/* Multipliers at a curve point by the variational method (CVODES). */
static int variational(const usm_model *m, const usm_params *p, const double *u,
                       usm_floquet_result *r)
{
    usm_steady_solution sol;
    usm_floquet_options fo;
    usm_floquet *fl = usm_floquet_alloc(m);
    memset(&sol, 0, sizeof sol);
    memcpy(sol.u, u, sizeof(double) * (size_t)m->nu);
    usm_steady_evaluate(m, p, &sol);
    usm_floquet_options_default(&fo);
    fo.method = USM_FLOQUET_VARIATIONAL;
    fo.rtol = 1e-12;
    fo.atol = 1e-16;
    const int rc = usm_floquet_compute(fl, p, &sol, 0.0, &fo, r);
    usm_floquet_free(fl);
    return rc;
}

static void fold_hopf(void)
{
    const usm_model *m = usm_model_find("3dof_twist_integrated");
    usm_params p;
    usm_envelope_options o;
    usm_params_default(&p);
    usm_envelope_options_default(&o);
    o.x = (usm_envelope_axis){"f", 20000, 40000};
    o.y = (usm_envelope_axis){"m0", 15, 100};
    o.steady.theta_max = 1.0;
    usm_envelope *e = usm_envelope_alloc(m);
    CHECK(usm_envelope_run(e, &p, &o) == USM_OK, "run: %s", usm_envelope_message(e));
    size_t nfh = 0, nbt = 0;
    double worst_one = 0, worst_circle = 0, least_angle = INFINITY, worst_end = 0;
    for (size_t i = 0; i < usm_envelope_codim2_count(e); ++i) {
        const usm_envelope_codim2 *c = usm_envelope_codim2_at(e, i);
        if (strcmp(c->type, "bogdanov_takens") == 0)
            nbt++;
        if (strcmp(c->type, "fold/stability") != 0)
            continue;
        nfh++;
        usm_params q = p;
        q.f = c->x;
        q.m0 = c->y;
        usm_floquet_result r;
        if (!CHECK(variational(m, &q, c->u, &r) == USM_OK, "variational at fold/stability"))
            continue;
        /* the multiplier nearest 1, then the largest modulus of the others */
        int a = -1;
        double da = INFINITY;
        for (int k = 0; k < r.n; ++k)
            if (!r.cyclic[k] && hypot(r.re[k] - 1, r.im[k]) < da) {
                da = hypot(r.re[k] - 1, r.im[k]);
                a = k;
            }
        double mx = 0, ang = 0;
        for (int k = 0; k < r.n; ++k)
            if (!r.cyclic[k] && k != a && hypot(r.re[k], r.im[k]) > mx) {
                mx = hypot(r.re[k], r.im[k]);
                ang = fabs(atan2(r.im[k], r.re[k]));
            }
        worst_one = fmax(worst_one, da);
        worst_circle = fmax(worst_circle, fabs(mx - 1));
        least_angle = fmin(least_angle, ang);
        printf("fold/stability at f = %.6f Hz, m0 = %.8f N m, theta = %.4f: multiplier 1 to "
               "%.2g, the pair's modulus 1 to %.2g at %.4f rad\n",
               c->x, c->y, c->u[m->u_theta], da, fabs(mx - 1), ang);
    }
    /* every stability curve ends at one of them */
    for (size_t s = 0;; ++s) {
        const usm_envelope_curve *cv = curve_of(e, USM_ENVELOPE_STABILITY, s);
        if (!cv)
            break;
        double best = INFINITY;
        for (int end = 0; end < 2; ++end) {
            const double *xy = cv->xy + (end ? 2 * (cv->npoints - 1) : 0);
            for (size_t i = 0; i < usm_envelope_codim2_count(e); ++i) {
                const usm_envelope_codim2 *c = usm_envelope_codim2_at(e, i);
                if (strcmp(c->type, "fold/stability") == 0)
                    best = fmin(best, fmax(fabs(xy[0] - c->x) / 20000, fabs(xy[1] - c->y) / 85));
            }
        }
        worst_end = fmax(worst_end, best);
    }
    CHECK(nfh == 2, "%zu fold/stability points, 2 expected", nfh);
    CHECK(nbt == 0, "%zu bogdanov_takens points where none exists", nbt);
    CHECK(worst_one <= 1e-8, "a multiplier at 1 to %.3g only (variational)", worst_one);
    CHECK(worst_circle <= 1e-8, "the pair on the unit circle to %.3g only", worst_circle);
    CHECK(least_angle >= 0.1, "a pair at %.3g rad: nearly a double multiplier 1", least_angle);
    CHECK(worst_end <= 1e-5, "a stability curve ends %.3g of the box from a fold/stability point",
          worst_end);
    printf("stability curves end at the fold/stability points to %.2g of the box\n", worst_end);
    usm_envelope_free(e);
}

static void near_axis(void)
{
    const usm_model *m = usm_model_find("3dof");
    usm_params p;
    usm_envelope_options o;
    usm_params_default(&p);
    usm_envelope_options_default(&o);
    o.x = (usm_envelope_axis){"F0", 0.2, 1.5};
    o.y = (usm_envelope_axis){"T", 0.0, 0.008};
    usm_envelope *e = usm_envelope_alloc(m);
    CHECK(usm_envelope_run(e, &p, &o) == USM_OK, "run: %s", usm_envelope_message(e));
    /* the corner: two pairs on the unit circle (variational) */
    size_t ncorner = 0;
    for (size_t i = 0; i < usm_envelope_codim2_count(e); ++i) {
        const usm_envelope_codim2 *c = usm_envelope_codim2_at(e, i);
        if (strcmp(c->type, "stability/stability") != 0)
            continue;
        ncorner++;
        usm_params q = p;
        q.F0 = c->x;
        q.T = c->y;
        usm_floquet_result r;
        if (!CHECK(variational(m, &q, c->u, &r) == USM_OK, "variational at the corner"))
            continue;
        int on = 0;
        double worst = 0;
        for (int k = 0; k < r.n; ++k)
            if (!r.cyclic[k] && r.im[k] > 0 && fabs(hypot(r.re[k], r.im[k]) - 1) <= 1e-4) {
                on++;
                worst = fmax(worst, fabs(hypot(r.re[k], r.im[k]) - 1));
            }
        CHECK(on == 2, "%d pairs on the unit circle at the corner, 2 expected", on);
        printf("stability/stability at F0 = %.10f N, T = %.10g N m, theta = %.3g: two pairs on "
               "the unit circle to %.2g (variational)\n",
               c->x, c->y, c->u[m->u_theta], worst);
    }
    CHECK(ncorner == 1, "%zu stability/stability points, 1 expected", ncorner);
    /* the leg from the corner towards the axis: its end and a point five
     * steps inside on the unit circle by the second method, the end within
     * a few 1e-8 rad of the axis */
    const usm_envelope_curve *cv = NULL;
    int lost = -1;
    for (size_t k = 0; curve_of(e, USM_ENVELOPE_STABILITY, k); ++k) {
        const usm_envelope_curve *c = curve_of(e, USM_ENVELOPE_STABILITY, k);
        for (int end = 0; end < 2; ++end)
            if (c->end[end] == USM_ENVELOPE_END_LOST) {
                cv = c;
                lost = end;
            }
    }
    if (CHECK(cv && cv->npoints > 20, "no stability curve lost near the axis: update this test "
                                     "and docs/envelope.md")) {
        const size_t iend = lost == 0 ? 0 : cv->npoints - 1;
        const double th_end = cv->u[(size_t)cv->nu * iend + (size_t)m->u_theta];
        /* inside: the first point from the end at ten times its tilt */
        size_t iin = iend;
        for (size_t j = 0; j < cv->npoints; ++j) {
            const size_t i = lost == 0 ? j : cv->npoints - 1 - j;
            if (cv->u[(size_t)cv->nu * i + (size_t)m->u_theta] >= 10 * th_end) {
                iin = i;
                break;
            }
        }
        CHECK(th_end > 0 && th_end < 1e-7, "lost at theta = %.3g", th_end);
        for (int k = 0; k < 2; ++k) {
            const size_t i = k == 0 ? iend : iin;
            usm_params q = p;
            q.F0 = cv->xy[2 * i];
            q.T = cv->xy[2 * i + 1];
            const double th = cv->u[(size_t)cv->nu * i + (size_t)m->u_theta];
            const double F0z = sqrt(q.m0 * q.m0 - (q.H * q.T / q.R) * (q.H * q.T / q.R)) / q.R;
            /* g by both methods at the point and 1e-8 N further in F0 (the
             * root by Newton): the zero's distance in F0, in the box's side */
            usm_floquet_options fo[2];
            usm_floquet *fl = usm_floquet_alloc(m);
            usm_steady *st = usm_steady_alloc(m);
            double g[2][2] = {{NAN, NAN}, {NAN, NAN}};
            for (int meth = 0; meth < 2; ++meth) {
                usm_floquet_options_default(&fo[meth]);
                fo[meth].method = meth == 0 ? USM_FLOQUET_VARIATIONAL : USM_FLOQUET_EXPONENTIAL;
                fo[meth].rtol = 1e-12;
                fo[meth].atol = 1e-16;
                fo[meth].steps = 256;
            }
            for (int j = 0; j < 2; ++j) {
                usm_params qj = q;
                qj.F0 += j * 1e-8;
                if (usm_steady_solve_from(st, &qj, cv->u + (size_t)cv->nu * i) != USM_OK)
                    continue;
                for (int meth = 0; meth < 2; ++meth) {
                    usm_floquet_result r;
                    if (usm_floquet_compute(fl, &qj, usm_steady_root(st, 0), 0.0, &fo[meth], &r) ==
                        USM_OK)
                        g[meth][j] = r.max_modulus - 1;
                }
            }
            double dist[2];
            for (int meth = 0; meth < 2; ++meth)
                dist[meth] = fabs(g[meth][0]) * 1e-8 / fabs(g[meth][1] - g[meth][0]) / 1.3;
            CHECK(dist[0] <= 1e-9 && dist[1] <= 1e-9,
                  "the zero of |lambda|max - 1 %.3g (variational), %.3g (exponential) of the box "
                  "from point %zu",
                  dist[0], dist[1], i);
            printf("stability %s: F0 = %.10f N (F0* - %.2g), T = %.10g N m, theta = %.3g rad, "
                   "|lambda| - 1 = %.2g (variational), %.2g (exponential), its zero %.2g, %.2g of "
                   "the box away\n",
                   k ? "inside" : "end", q.F0, F0z - q.F0, q.T, th, g[0][0], g[1][0], dist[0],
                   dist[1]);
            usm_steady_free(st);
            usm_floquet_free(fl);
        }
    }
    usm_envelope_free(e);

    /* the dominant pair's argument in the tilt vector towards the axis, at
     * T = 0.72 mN m: d arg / d theta by a difference at theta ~ 3e-7, 3e-8 */
    const usm_model *mt = usm_model_find("3dof_tilt");
    usm_steady *s = usm_steady_alloc(mt);
    usm_floquet *fl = usm_floquet_alloc(mt);
    usm_steady_options so;
    usm_steady_options_default(&so);
    usm_params q = p;
    q.T = 0.00072;
    const double F0z = sqrt(q.m0 * q.m0 - (q.H * q.T / q.R) * (q.H * q.T / q.R)) / q.R;
    double rate[2] = {NAN, NAN}, th0[2] = {NAN, NAN}, mod[2] = {NAN, NAN};
    for (int k = 0; k < 2; ++k) {
        double arg[2] = {NAN, NAN}, th[2] = {NAN, NAN};
        for (int j = 0; j < 2; ++j) {
            /* theta ~ 1e-3 (F0* - F0) here */
            q.F0 = F0z - (k == 0 ? 3e-4 : 3e-5) - j * (k == 0 ? 3e-9 : 3e-10);
            usm_floquet_result r;
            if (usm_steady_solve(s, &q, &so) != USM_OK ||
                usm_floquet_compute(fl, &q, usm_steady_root(s, 0), 0.0, NULL, &r) != USM_OK)
                continue;
            th[j] = usm_steady_root(s, 0)->theta;
            for (int i = 0; i < r.n; ++i)
                if (!r.cyclic[i] && r.im[i] > 0 && hypot(r.re[i], r.im[i]) == r.max_modulus)
                    arg[j] = atan2(r.im[i], r.re[i]);
            mod[k] = r.max_modulus;
        }
        rate[k] = fabs((arg[1] - arg[0]) / (th[1] - th[0]));
        th0[k] = th[0];
    }
    /* d arg / d theta ~ theta^-q: q > 1 makes arg itself unbounded */
    const double q_exp = log(rate[1] / rate[0]) / log(th0[0] / th0[1]);
    CHECK(isfinite(q_exp) && q_exp >= 1.2 && q_exp <= 1.8,
          "d arg/d theta %.3g at theta %.3g, %.3g at %.3g: exponent %.3g, not 1.2 .. 1.8",
          rate[0], th0[0], rate[1], th0[1], q_exp);
    CHECK(fabs(mod[1] - mod[0]) <= 0.1, "the moduli %.5f, %.5f", mod[0], mod[1]);
    printf("tilt vector, T = 0.72 mN m: d arg/d theta = %.3g at theta = %.3g, %.3g at %.3g "
           "(theta^-%.2f); |lambda|max %.5f, %.5f\n",
           rate[0], th0[0], rate[1], th0[1], q_exp, mod[0], mod[1]);
    usm_floquet_free(fl);
    usm_steady_free(s);
}

int main(void)
{
    gsl_set_error_handler_off();
    fold_hopf();
    near_axis();
    return failures != 0;
}
