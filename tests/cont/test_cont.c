/* The continuation engine (usm_cont.h) on problems whose branches and
 * events are known in closed form:
 *  - the circle u^2 / a^2 + p^2 = 1: folds at p = +-1 (u = 0), located to
 *    1e-12; followed across them when asked, the branch comes back on the
 *    other side (u changes sign) and closes after one turn (arclength 2 pi
 *    for a = 1); ended at the first fold by default, also when the fold
 *    lies inside the first step.  With a = 1e-4 and the
 *    scale (a, 1) the same folds are found, the unknowns ten thousand times
 *    apart in size; with the chord corrector (the Jacobian factored once a
 *    correction) the same folds.
 *  - a monitor u - 1/2 on the circle crosses at p = sqrt(3)/2; a stopping
 *    test p - 0.9 ends the branch at p = 0.9; a grid value p = 0.3 is reached
 *    by usm_cont_arc_locate and usm_cont_correct_fixed exactly.
 *  - the Hopf normal form (p + i) z - z |z|^2 = 0 (z = u1 + i u2) on its
 *    trivial branch z = 0: the real part of the eigenvalues of dF/du, the
 *    test function of stability, changes sign at p = 0, located to 1e-12,
 *    and the branch goes on along z = 0 (dF/du = [[p, -1], [1, p]] stays
 *    regular there, so the crossing is a test function's, not a singular
 *    Jacobian's).
 *  - branch points of the normal forms x^2 - p x = 0 (transcritical) and
 *    x^3 - p x = 0 (pitchfork), and of the transcritical one with a curved
 *    trivial branch in rotated coordinates (two equations): the sign change
 *    of det [dF/dx; t] along x = 0 is located at p = 0 to 1e-12; the other
 *    branch's tangent by the algebraic branching equation is (1, 1) (resp.
 *    (1, 0)); started from the branch point in either direction, the new
 *    branch is followed on x = p (resp. x^2 = p) to 1e-10.  Around the
 *    circle's fold the test does not fire (the bordered matrix is regular
 *    there).
 */
#include <math.h>
#include <stdio.h>

#include "check.h"

#define PI 3.14159265358979323846
#include "usm_cont.h"

static int circle(const double *x, double *F, double *J, void *ctx)
{
    const double a = *(const double *)ctx;
    F[0] = x[0] * x[0] / (a * a) + x[1] * x[1] - 1.0;
    if (J) {
        J[0] = 2.0 * x[0] / (a * a);
        J[1] = 2.0 * x[1];
    }
    return 0;
}

static int hopf(const double *x, double *F, double *J, void *ctx)
{
    const double a = x[0], b = x[1], p = x[2], r2 = a * a + b * b;
    (void)ctx;
    F[0] = p * a - b - a * r2;
    F[1] = a + p * b - b * r2;
    if (J) {
        J[0] = p - 3 * a * a - b * b;
        J[1] = -1 - 2 * a * b;
        J[2] = a;
        J[3] = 1 - 2 * a * b;
        J[4] = p - a * a - 3 * b * b;
        J[5] = b;
    }
    return 0;
}

/* the normal forms: kind 2 x^2 - p x, kind 3 x^3 - p x (x = (x, p)); kind 4
 * the transcritical one in rotated coordinates u = R (x, y) with a second
 * equation y = p^2 + x^2, so that its trivial branch x = 0 is curved in u
 * (x = (u1, u2, p)) and the other branch is x = p, y = 2 p^2 */
static int normal_form(const double *x, double *F, double *J, void *ctx)
{
    const int kind = *(const int *)ctx;
    if (kind == 4) {
        const double r = sqrt(0.5), u1 = x[0], u2 = x[1], p = x[2];
        const double xx = r * (u1 + u2), yy = r * (u1 - u2);
        F[0] = xx * (xx - p);
        F[1] = yy - p * p - xx * xx;
        if (J) {
            const double f0x = 2 * xx - p, f1x = -2 * xx;
            J[0] = f0x * r;
            J[1] = f0x * r;
            J[2] = -xx;
            J[3] = f1x * r + r;
            J[4] = f1x * r - r;
            J[5] = -2 * p;
        }
        return 0;
    }
    const double u = x[0], p = x[1];
    F[0] = kind == 2 ? u * u - p * u : u * u * u - p * u;
    if (J) {
        J[0] = kind == 2 ? 2 * u - p : 3 * u * u - p;
        J[1] = -u;
    }
    return 0;
}

/* the normal form's x: u for kinds 2, 3; (u1 + u2) / sqrt 2 for kind 4 */
static double nf_x(int kind, const double *x)
{
    return kind == 4 ? sqrt(0.5) * (x[0] + x[1]) : x[0];
}

static double level(const double *x, const double *dx, void *ctx)
{
    const double *l = ctx; /* component, level */
    (void)dx;
    return x[(int)l[0]] - l[1];
}

/* half the trace of dF/du: the eigenvalues' real part where they are complex */
static double hopf_real_part(const double *x, const double *dx, void *ctx)
{
    const double a = x[0], b = x[1], p = x[2];
    (void)dx;
    (void)ctx;
    return 0.5 * ((p - 3 * a * a - b * b) + (p - a * a - 3 * b * b));
}

/* Follows the circle of half-axis a (scale (a, 1)) from (0.8 a, 0.6) upwards
 * across its folds for one turn; the folds' p and u into fp[], fu[]. */
static int circle_turn(double a, int chord, double *fp, double *fu, int nmax, double *closure)
{
    usm_cont *c = usm_cont_alloc(1);
    usm_cont_options o;
    usm_cont_options_default(&o);
    o.across_fold = 1;
    o.h_max = 0.1;
    o.chord = chord;
    const double scale[2] = {a, 1.0}, x0[2] = {0.8 * a, 0.6};
    int nf = 0;
    double arclength = 0, best = INFINITY;
    usm_cont_set_problem(c, circle, &a);
    CHECK(usm_cont_set_options(c, &o) == 0, "options refused");
    CHECK(usm_cont_set_scale(c, scale) == 0, "scale refused");
    CHECK(usm_cont_start(c, x0, 1) == 0, "start failed");
    while (arclength < 2.0 * PI + 0.05) {
        const int rc = usm_cont_step(c);
        if (!CHECK(rc == USM_CONT_STEP, "step: %d at arclength %g", rc, arclength))
            break;
        for (int k = 0; k < usm_cont_event_count(c); ++k) {
            const usm_cont_event *e = usm_cont_event_at(c, k);
            if (e->test == USM_CONT_FOLD && nf < nmax) {
                fp[nf] = e->x[1];
                fu[nf++] = e->x[0];
            }
        }
        arclength += usm_cont_step_arc(c, NULL);
        const double *x = usm_cont_point(c);
        if (arclength > PI)
            best = fmin(best, hypot((x[0] - x0[0]) / a, x[1] - x0[1]));
        /* the point stays on the circle */
        CHECK(fabs(x[0] * x[0] / (a * a) + x[1] * x[1] - 1.0) < 1e-9, "off the circle at %g",
              x[1]);
    }
    *closure = best;
    usm_cont_free(c);
    return nf;
}

static void test_circle(void)
{
    for (int ia = 0; ia < 3; ++ia) {
        /* the third: a = 1 with the chord corrector */
        const double a = ia == 1 ? 1e-4 : 1.0;
        double fp[8], fu[8], closure;
        const int nf = circle_turn(a, ia == 2, fp, fu, 8, &closure);
        printf("circle a = %g%s: %d folds", a, ia == 2 ? " (chord)" : "", nf);
        for (int k = 0; k < nf && k < 8; ++k)
            printf(" (p %.17g, u/a %.3g)", fp[k], fu[k] / a);
        printf("; closest return %.3g\n", closure);
        if (CHECK(nf == 2, "a = %g: %d folds in one turn, not 2", a, nf)) {
            CHECK(fabs(fp[0] - 1.0) <= 1e-12, "first fold at p = %.17g, not 1", fp[0]);
            CHECK(fabs(fp[1] + 1.0) <= 1e-12, "second fold at p = %.17g, not -1", fp[1]);
            CHECK(fabs(fu[0] / a) <= 1e-7 && fabs(fu[1] / a) <= 1e-7, "folds off u = 0");
        }
        /* back at the start after one turn: the branch came round both folds */
        CHECK(closure < 0.06, "a = %g: the branch does not come back (closest %g)", a, closure);
    }

    /* by default the branch ends at the fold, which is its last point */
    double a = 1.0;
    usm_cont *c = usm_cont_alloc(1);
    const double x0[2] = {-0.8, -0.6};
    usm_cont_set_problem(c, circle, &a);
    CHECK(usm_cont_start(c, x0, -1) == 0, "start failed");
    int rc, steps = 0, seen_fold = 0;
    while ((rc = usm_cont_step(c)) == USM_CONT_STEP && ++steps < 10000) {
        /* the point on the side where the branch started: u stays negative */
        CHECK(usm_cont_point(c)[0] < 0, "past the fold at u = %g", usm_cont_point(c)[0]);
    }
    if (CHECK(rc == USM_CONT_END, "the branch did not end at the fold: %d", rc)) {
        const usm_cont_event *e = usm_cont_event_at(c, usm_cont_event_count(c) - 1);
        seen_fold = e && e->test == USM_CONT_FOLD && e->stop;
        CHECK(seen_fold, "the last event is not the stopping fold");
        CHECK(fabs(usm_cont_point(c)[1] + 1.0) <= 1e-12, "ended at p = %.17g, not -1",
              usm_cont_point(c)[1]);
        CHECK(usm_cont_step(c) == USM_CONT_EUSAGE, "a step after the end was taken");
    }
    usm_cont_free(c);

    /* a fold inside the branch's first step: the start is 0.05 of arclength
     * before it, the first step 0.08 long */
    usm_cont_options o;
    const double x1[2] = {0.05, sqrt(1 - 0.05 * 0.05)};
    c = usm_cont_alloc(1);
    usm_cont_set_problem(c, circle, &a);
    usm_cont_options_default(&o);
    o.h0 = o.h_max = 0.08;
    CHECK(usm_cont_set_options(c, &o) == 0, "options refused");
    CHECK(usm_cont_start(c, x1, 1) == 0, "start failed");
    rc = usm_cont_step(c);
    CHECK(rc == USM_CONT_END && fabs(usm_cont_point(c)[1] - 1.0) <= 1e-12,
          "a fold in the first step: %d, p = %.17g", rc, usm_cont_point(c)[1]);
    usm_cont_free(c);
}

static void test_monitors(void)
{
    double a = 1.0, half[2] = {0, 0.5}, stop[2] = {1, 0.9};
    usm_cont *c = usm_cont_alloc(1);
    const double x0[2] = {0.99, -sqrt(1 - 0.99 * 0.99)};
    usm_cont_set_problem(c, circle, &a);
    const int k_half = usm_cont_add_test(c, level, half, USM_CONT_TEST_MONITOR);
    const int k_stop = usm_cont_add_test(c, level, stop, USM_CONT_TEST_STOP);
    CHECK(k_half == 1 && k_stop == 2, "test indices %d %d", k_half, k_stop);
    CHECK(usm_cont_start(c, x0, 1) == 0, "start failed");
    double p_half = NAN, p_grid = NAN, u_grid = NAN;
    int rc, guard = 0;
    while ((rc = usm_cont_step(c)) == USM_CONT_STEP || rc == USM_CONT_END) {
        const double *xa;
        const double s_end = usm_cont_step_arc(c, &xa);
        const double pa = xa[1], pb = usm_cont_point(c)[1];
        double g[2] = {1, 0.3};
        if ((pa - 0.3) * (pb - 0.3) < 0) {
            double s, x[2];
            if (CHECK(usm_cont_arc_locate(c, level, g, pa - 0.3, pb - 0.3, &s, x) == 0,
                      "grid value not located") &&
                CHECK(s > 0 && s < s_end, "s = %g outside the step", s) &&
                CHECK(usm_cont_correct_fixed(c, x, 1, 0.3) >= 0, "landing failed")) {
                p_grid = x[1];
                u_grid = x[0];
            }
        }
        for (int k = 0; k < usm_cont_event_count(c); ++k)
            if (usm_cont_event_at(c, k)->test == k_half)
                p_half = usm_cont_event_at(c, k)->x[1];
        if (rc == USM_CONT_END || ++guard > 10000)
            break;
    }
    CHECK(rc == USM_CONT_END, "the stopping test did not end the branch: %d", rc);
    CHECK(fabs(usm_cont_point(c)[1] - 0.9) <= 1e-12, "ended at p = %.17g, not 0.9",
          usm_cont_point(c)[1]);
    CHECK(fabs(p_half - sqrt(0.75)) <= 1e-12, "u = 1/2 at p = %.17g, not sqrt(3)/2", p_half);
    CHECK(p_grid == 0.3 && fabs(u_grid - sqrt(0.91)) <= 1e-14, "landed at (%.17g, %.17g)",
          u_grid, p_grid);
    printf("monitor u = 1/2 at p = %.17g (sqrt(3)/2 %+.2g); stop at p = %.17g\n", p_half,
           p_half - sqrt(0.75), usm_cont_point(c)[1]);
    usm_cont_free(c);
}

static void test_hopf(void)
{
    usm_cont *c = usm_cont_alloc(2);
    const double x0[3] = {0.0, 0.0, -1.0};
    usm_cont_set_problem(c, hopf, NULL);
    const int k = usm_cont_add_test(c, hopf_real_part, NULL, USM_CONT_TEST_MONITOR);
    CHECK(usm_cont_start(c, x0, 1) == 0, "start failed");
    int n_ev = 0;
    double p_ev = NAN, before = NAN;
    while (usm_cont_point(c)[2] < 1.0) {
        if (!CHECK(usm_cont_step(c) == USM_CONT_STEP, "step failed at p = %g",
                   usm_cont_point(c)[2]))
            break;
        for (int j = 0; j < usm_cont_event_count(c); ++j)
            if (usm_cont_event_at(c, j)->test == k) {
                ++n_ev;
                p_ev = usm_cont_event_at(c, j)->x[2];
                before = usm_cont_event_at(c, j)->before;
            }
        CHECK(usm_cont_point(c)[0] == 0.0 && usm_cont_point(c)[1] == 0.0,
              "left the trivial branch: u = (%g, %g)", usm_cont_point(c)[0], usm_cont_point(c)[1]);
    }
    CHECK(n_ev == 1, "%d stability changes, not 1", n_ev);
    CHECK(fabs(p_ev) <= 1e-12, "stability change at p = %.3g, not 0", p_ev);
    CHECK(before < 0, "the eigenvalue before the change is %g, not negative", before);
    printf("Hopf: Re lambda = 0 at p = %.3g\n", p_ev);
    usm_cont_free(c);
}

/* Follows the branch the engine is on until p leaves [-1, 1]; the largest
 * distance from the branch x = p (kind 2, 4) or x^2 = p (kind 3) and of
 * y from 2 p^2 (kind 4); the sign of x all along into *sign (0: mixed). */
static double follow_new_branch(usm_cont *c, int kind, int *sign, int *steps)
{
    const int n = kind == 4 ? 2 : 1;
    double worst = 0;
    int rc, pos = 0, neg = 0;
    *steps = 0;
    while ((rc = usm_cont_step(c)) == USM_CONT_STEP || rc == USM_CONT_END) {
        const double *x = usm_cont_point(c), p = x[n], u = nf_x(kind, x);
        double d = kind == 3 ? fabs(u * u - p) : fabs(u - p);
        if (kind == 4)
            d = fmax(d, fabs(sqrt(0.5) * (x[0] - x[1]) - 2 * p * p));
        worst = fmax(worst, d);
        pos += u > 0;
        neg += u < 0;
        if (rc == USM_CONT_END || fabs(p) >= 1.0 || ++*steps > 10000)
            break;
    }
    *sign = pos && !neg ? 1 : neg && !pos ? -1 : 0;
    return worst;
}

static void test_branch_points(void)
{
    for (int kind = 2; kind <= 4; ++kind) {
        const int n = kind == 4 ? 2 : 1, N = n + 1;
        int k2 = kind;
        usm_cont *c = usm_cont_alloc(n);
        double x0[3] = {0, 0, 0};
        x0[n] = -1.0;
        if (kind == 4) { /* x = 0, y = p^2 = 1 */
            x0[0] = sqrt(0.5);
            x0[1] = -sqrt(0.5);
        }
        usm_cont_set_problem(c, normal_form, &k2);
        const int kb = usm_cont_add_branch_test(c, USM_CONT_TEST_MONITOR);
        CHECK(kb == 1, "branch test index %d", kb);
        CHECK(usm_cont_start(c, x0, 1) == 0, "start failed");
        int nbp = 0, nfold = 0, rc, guard = 0;
        double xb[3], dxb[3];
        while ((rc = usm_cont_step(c)) == USM_CONT_STEP && usm_cont_point(c)[n] < 1.0 &&
               ++guard < 10000)
            for (int k = 0; k < usm_cont_event_count(c); ++k) {
                const usm_cont_event *e = usm_cont_event_at(c, k);
                nfold += e->test == USM_CONT_FOLD;
                if (e->test == kb && nbp++ == 0)
                    for (int j = 0; j < N; ++j) {
                        xb[j] = e->x[j];
                        dxb[j] = e->dx[j];
                    }
            }
        CHECK(rc == USM_CONT_STEP, "kind %d: the trivial branch was lost: %d", kind, rc);
        CHECK(nfold == 0, "kind %d: %d folds on a branch without one", kind, nfold);
        if (!CHECK(nbp == 1, "kind %d: %d branch points, not 1", kind, nbp)) {
            usm_cont_free(c);
            continue;
        }
        printf("kind %d: branch point at p = %.3g, x = %.3g\n", kind, xb[n], nf_x(kind, xb));
        CHECK(fabs(xb[n]) <= 1e-12 && fabs(nf_x(kind, xb)) <= 1e-12,
              "kind %d: branch point at p = %.3g, x = %.3g, not 0", kind, xb[n], nf_x(kind, xb));
        double tau[3], phi[3];
        const int method = usm_cont_branch_tangent(c, xb, dxb, tau, phi);
        CHECK(method == USM_CONT_ABE, "kind %d: tangent by method %d", kind, method);
        if (method >= 0) {
            /* the other branch leaves along (x, p) = (1, 1) or (1, 0) */
            const double tx = nf_x(kind, tau), tp = tau[n], len = hypot(tx, tp);
            const double want = kind == 3 ? 0.0 : 1.0; /* dp/dx */
            CHECK(fabs(fabs(tp / tx) - want) <= 1e-6 && len > 0.99,
                  "kind %d: tangent (x %.6g, p %.6g)", kind, tx, tp);
        }
        for (int dir = 1; dir >= -1; dir -= 2) {
            int sign, steps;
            if (!CHECK(usm_cont_switch_branch(c, xb, dxb, dir, 0.0) == 0,
                       "kind %d: switch %+d failed", kind, dir))
                continue;
            const double worst = follow_new_branch(c, kind, &sign, &steps);
            printf("kind %d dir %+d: %d steps to p = %.3g, off the branch by %.3g\n", kind, dir,
                   steps, usm_cont_point(c)[n], worst);
            CHECK(worst <= 1e-10, "kind %d dir %+d: %.3g off the other branch", kind, dir, worst);
            CHECK(fabs(usm_cont_point(c)[n]) >= 1.0, "kind %d dir %+d: stopped at p = %g", kind,
                  dir, usm_cont_point(c)[n]);
            /* pitchfork: dir picks the sign of x; transcritical: of p = x */
            CHECK(sign == dir, "kind %d dir %+d: x of sign %d", kind, dir, sign);
        }
        /* at a regular point there is no other branch */
        CHECK(usm_cont_branch_tangent(c, x0, dxb, tau, NULL) == USM_CONT_LOST,
              "kind %d: a branch point at a regular point", kind);
        usm_cont_free(c);
    }

    /* around the circle's fold: a fold, no branch point */
    double a = 1.0;
    usm_cont *c = usm_cont_alloc(1);
    const double x0[2] = {-0.8, -0.6};
    usm_cont_set_problem(c, circle, &a);
    const int kb = usm_cont_add_branch_test(c, USM_CONT_TEST_MONITOR);
    usm_cont_options o;
    usm_cont_options_default(&o);
    o.across_fold = 1;
    usm_cont_set_options(c, &o);
    CHECK(usm_cont_start(c, x0, -1) == 0, "start failed");
    int nbp = 0, nfold = 0;
    for (int i = 0; i < 200 && usm_cont_step(c) == USM_CONT_STEP; ++i)
        for (int k = 0; k < usm_cont_event_count(c); ++k) {
            nfold += usm_cont_event_at(c, k)->test == USM_CONT_FOLD;
            nbp += usm_cont_event_at(c, k)->test == kb;
        }
    CHECK(nfold >= 1 && nbp == 0, "circle: %d folds, %d branch points", nfold, nbp);
    usm_cont_free(c);
}

static void test_usage(void)
{
    usm_cont_options o;
    usm_cont *c = usm_cont_alloc(1);
    CHECK(usm_cont_alloc(0) == NULL, "an engine for 0 equations");
    usm_cont_options_default(&o);
    o.h_min = 0;
    CHECK(usm_cont_set_options(c, &o) == USM_CONT_EUSAGE, "h_min = 0 accepted");
    usm_cont_options_default(&o);
    o.chord = 2;
    CHECK(usm_cont_set_options(c, &o) == USM_CONT_EUSAGE, "chord = 2 accepted");
    const double bad[2] = {1.0, -1.0}, x0[2] = {1, 0};
    CHECK(usm_cont_set_scale(c, bad) == USM_CONT_EUSAGE, "a negative scale accepted");
    CHECK(usm_cont_add_test(c, hopf_real_part, NULL, 7) == USM_CONT_EUSAGE, "unknown flags accepted");
    CHECK(usm_cont_step(c) == USM_CONT_EUSAGE, "a step before the start");
    CHECK(usm_cont_start(c, x0, 1) == USM_CONT_EUSAGE, "a start without a problem");
    CHECK(usm_cont_add_branch_test(c, USM_CONT_TEST_POINT) == USM_CONT_EUSAGE,
          "a branch test of the point alone accepted");
    CHECK(usm_cont_add_test(c, NULL, NULL, 0) == USM_CONT_EUSAGE, "a test without a function");
    CHECK(usm_cont_switch_branch(c, x0, x0, 0, 0.0) == USM_CONT_EUSAGE, "dir 0 accepted");
    usm_cont_free(c);
}

int main(void)
{
    test_circle();
    test_monitors();
    test_hopf();
    test_branch_points();
    test_usage();
    printf("%s: %d failure(s)\n", failures ? "FAIL" : "ok", failures);
    return failures != 0;
}
