/* Every root of the stationary equations, checked against truths that do not
 * use usm_steady_solve's search:
 *
 * 1. Close pairs near folds.  Sweeps (usm_sweep: continuation, a second
 *    method) locate folds where the branch turns back, in T (3dof; 4dof with a
 *    friction law that transmits the load), m0 and f (3dof, 4dof).  At
 *    1e-6 and 1e-4 relative from each fold on the side where solutions
 *    exist, the two roots near the fold's tilt are counted independently by
 *    the sign changes of the seed kernel's amplitude mismatch on a fine grid
 *    (4e5 points over +-20 % of the fold's tilt); steady must find as
 *    many, each with a vanishing residual.
 * 2. Agreement with the sweeps: at every converged grid point of those sweeps
 *    and of the sweeps along the negative-load branch (T < 0, both of its
 *    halves), the sweep's root is among steady's roots (tilt and rotor speed
 *    to 1e-9 relative); at 20 loads from the negative-load fold to 0, steady
 *    finds as many roots as the amplitude mismatch has sign changes on a
 *    grid of 4e5 tilts.
 * 3. Non-monotone friction (4dof_friction_stribeck, kappa = 1000 s/m): at
 *    loads where two slip speeds balance the rotor, steady finds as many
 *    rotor speeds at the stationary tilt as a fine scan of the rotor residual
 *    over the rotor speed has sign changes, each root's residual vanishes,
 *    and the sweep's points are among steady's roots.  The message "exceeds
 *    what the friction law can transmit" comes exactly when the friction
 *    needed is above the law's maximum (found here by golden section), and
 *    usm_steady_friction_range gives that maximum (and the atan law's
 *    closed-form range mu0 pi/2).
 * 4. Messages for extreme inputs name no "inf" or "nan".
 */
#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>

#include "usm_sweep.h"

#include "check.h"

#define HALF_PI 1.5707963267948966192313216916397514

/* ---- helpers ------------------------------------------------------------------- */

/* Sign changes of the amplitude mismatch over [lo, hi], n log-spaced tilts. */
static int mismatch_sign_changes(const usm_model *m, const usm_params *p, double lo, double hi,
                                 int n)
{
    int changes = 0;
    double prev = NAN;
    for (int i = 0; i < n; ++i) {
        double out[USM_SEED_COUNT], th = lo * exp(log(hi / lo) * i / (n - 1));
        m->steady_seed(th, p, out);
        const double h = out[USM_SEED_AMPLITUDE_MISMATCH];
        if (i > 0 && isfinite(prev) && isfinite(h) && (h < 0) != (prev < 0))
            ++changes;
        prev = h;
    }
    return changes;
}

/* Residual of every root checked, relative to m0 + |T| (printed at the end).
 * The roots are polished by Newton to xtol 1e-13 in theta, the residual then
 * carries the rounding of the balance's larger torques: measured up to
 * 2.5e-11; the tolerance below is 1e-10. */
static double worst_residual;

static int close_to(double a, double b, double rel)
{
    return fabs(a - b) <= rel * fmax(fabs(a), fabs(b));
}

/* Index of the root of s equal to sol (tilt and rotor speed to rel), or -1. */
static int find_root(const usm_steady *s, const usm_steady_solution *sol, double rel)
{
    for (size_t k = 0; k < usm_steady_count(s); ++k) {
        const usm_steady_solution *r = usm_steady_root(s, k);
        if (close_to(r->theta, sol->theta, rel) && close_to(r->rotor_speed, sol->rotor_speed, rel))
            return (int)k;
    }
    return -1;
}

static usm_sweep *sweep(const usm_model *m, const usm_params *p, const char *over, double from,
                        double to, int points)
{
    usm_sweep_options o;
    usm_sweep *sw = usm_sweep_alloc(m);
    usm_sweep_options_default(&o);
    o.over = over;
    o.from = from;
    o.to = to;
    o.points = points;
    o.floquet = 0;
    const int rc = usm_sweep_run(sw, p, &o);
    CHECK(rc == USM_OK, "%s sweep over %s: status %d: %s", m->name, over, rc,
          usm_sweep_message(sw));
    return sw;
}

/* Every converged point of the sweep is among steady's roots there. */
static int sweep_points_found(const usm_model *m, const usm_params *p, const usm_sweep *sw,
                              const char *over)
{
    usm_steady *s = usm_steady_alloc(m);
    int n = 0;
    for (size_t i = 0; i < usm_sweep_count(sw); ++i) {
        const usm_sweep_point *pt = usm_sweep_point_at(sw, i);
        if (!pt->converged)
            continue;
        usm_params q = *p;
        *usm_params_field(&q, usm_params_find(over)) = pt->value;
        const int rc = usm_steady_solve(s, &q, NULL);
        /* the sweep polishes its points with the same solver (tests/study/test_sweep.c
         * measures 0 difference): 1e-9 only tells roots apart */
        CHECK(rc == USM_OK && find_root(s, &pt->sol, 1e-9) >= 0,
              "%s, %s = %.12g: the sweep's root theta = %.15g, rotor speed %.15g is not among "
              "steady's %zu roots (status %d: %s)",
              m->name, over, pt->value, pt->sol.theta, pt->sol.rotor_speed, usm_steady_count(s), rc,
              usm_steady_message(s));
        ++n;
    }
    usm_steady_free(s);
    return n;
}

/* ---- 1, 2: close pairs near folds, sweeps agree ---------------------------------- */

typedef struct fold_case {
    const char *model;
    const char *over;
    double from, to;
    const char *set1; /* a parameter changed from the defaults, or NULL */
    double val1;
    const char *set2;
    double val2;
} fold_case;

static void check_fold(const fold_case *c)
{
    const usm_model *m = usm_model_find(c->model);
    usm_params p;
    char msg[USM_MSG_LEN];
    usm_params_default(&p);
    if (c->set1)
        usm_params_set(&p, c->set1, c->val1, msg);
    if (c->set2)
        usm_params_set(&p, c->set2, c->val2, msg);
    usm_sweep *sw = sweep(m, &p, c->over, c->from, c->to, 41);
    const int agreed = sweep_points_found(m, &p, sw, c->over);
    CHECK(agreed > 0, "%s over %s: no converged sweep point", c->model, c->over);
    const usm_sweep_event *fold = NULL;
    for (size_t i = 0; i < usm_sweep_event_count(sw); ++i) {
        const usm_sweep_event *e = usm_sweep_event_at(sw, i);
        /* a turning point inside the tilt range, not its end */
        if (e->type == USM_EVENT_FOLD && e->has_sol && e->sol.theta > 1e-6 && e->sol.theta < 0.15)
            fold = e;
    }
    CHECK(fold != NULL, "%s over %s: the sweep finds no fold (turning point)", c->model, c->over);
    if (fold) {
        const double side = c->from > fold->value ? 1.0 : -1.0; /* where the branch was */
        const double theta_f = fold->sol.theta;
        usm_steady *s = usm_steady_alloc(m);
        for (int k = 0; k < 2; ++k) {
            const double rel = k == 0 ? 1e-6 : 1e-4;
            usm_params q = p;
            double *field = usm_params_field(&q, usm_params_find(c->over));
            *field = fold->value + side * rel * fabs(fold->value);
            const double lo = theta_f / 1.2, hi = theta_f * 1.2;
            const int truth = mismatch_sign_changes(m, &q, lo, hi, 400000);
            const int rc = usm_steady_solve(s, &q, NULL);
            int near = 0, distinct_tilts = 0;
            double last = NAN;
            for (size_t i = 0; i < usm_steady_count(s); ++i) {
                const usm_steady_solution *r = usm_steady_root(s, i);
                if (r->theta < lo || r->theta > hi)
                    continue;
                ++near;
                if (!(r->theta == last))
                    ++distinct_tilts;
                last = r->theta;
                worst_residual = fmax(worst_residual, r->residual_norm / (q.m0 + fabs(q.T)));
                CHECK(r->residual_norm <= 1e-10 * (q.m0 + fabs(q.T)),
                      "%s %s = %.15g: residual %.3g", c->model, c->over, *field,
                      r->residual_norm);
            }
            printf("%s, %s = fold %+g relative (%.12g; fold tilt %.6g rad): %d roots near the "
                   "fold, fine-grid sign changes %d\n",
                   c->model, c->over, side * rel, *field, theta_f, near, truth);
            CHECK(truth == 2, "%s %s = %.15g: the fine grid shows %d sign changes, not 2",
                  c->model, c->over, *field, truth);
            CHECK(rc == USM_OK && distinct_tilts == truth,
                  "%s %s = %.15g: steady finds %d tilts near the fold (status %d: %s), the fine "
                  "grid %d",
                  c->model, c->over, *field, distinct_tilts, rc, usm_steady_message(s), truth);
        }
        usm_steady_free(s);
    }
    usm_sweep_free(sw);
}

/* The negative-load branch: both halves, from its fold to T = 0. */
static void check_negative_load(const char *model, double mu0)
{
    const usm_model *m = usm_model_find(model);
    usm_params p;
    usm_params_default(&p);
    p.mu0 = mu0;
    /* upper half: from T = 0 down to the fold */
    usm_sweep *sw = sweep(m, &p, "T", 0.0, -2.0, 41);
    int n = sweep_points_found(m, &p, sw, "T");
    usm_sweep_free(sw);
    /* lower half: from near the fold up towards 0 (the tilt runs to 0) */
    sw = sweep(m, &p, "T", -2.1, 0.0, 43);
    n += sweep_points_found(m, &p, sw, "T");
    usm_sweep_free(sw);
    printf("%s (mu0 = %g), negative-load branch: steady contains the sweep's root at %d points\n",
           model, mu0, n);
    CHECK(n >= 60, "%s: only %d converged sweep points on the negative-load branch", model, n);
    /* two roots wherever the fine grid sees two */
    usm_steady *s = usm_steady_alloc(m);
    for (int i = 1; i <= 20; ++i) {
        p.T = -2.1 * i / 20.0;
        const int truth = mismatch_sign_changes(m, &p, 1e-9, 0.2, 400000);
        const int rc = usm_steady_solve(s, &p, NULL);
        CHECK(rc == USM_OK && (int)usm_steady_count(s) == truth,
              "%s T = %g: steady finds %zu roots (status %d: %s), the fine grid %d", model, p.T,
              usm_steady_count(s), rc, usm_steady_message(s), truth);
    }
    usm_steady_free(s);
}

/* ---- 3: non-monotone friction ------------------------------------------------- */

/* Sign changes of the rotor residual over the rotor speed at (theta, alpha),
 * on a fine grid mapped from slip speeds |v_rel| in [1e-9, 1e3] m/s. */
static int rotor_sign_changes(const usm_model *m, const usm_params *p, double theta,
                              double alpha)
{
    /* v_rel = v0 + R* phidot_R: read v0 and R* from the outputs kernel */
    double u[3] = {theta, alpha, 0.0}, y[USM_STEADY_COUNT];
    m->steady_outputs(u, p, y);
    const double v0 = y[USM_STEADY_V_REL];
    u[2] = 1.0;
    m->steady_outputs(u, p, y);
    const double slope = y[USM_STEADY_V_REL] - v0;
    const int n = 200000;
    int changes = 0;
    double prev = NAN;
    for (int i = -n; i <= n; ++i) {
        const double mag = 1e-9 * pow(1e12, fabs((double)i) / n);
        const double v = i < 0 ? -mag : mag;
        double r[3];
        u[2] = (v - v0) / slope;
        m->steady_residual(u, p, r);
        if (i > -n && (r[0] < 0) != (prev < 0))
            ++changes;
        prev = r[0];
    }
    return changes;
}

/* Largest value of the friction law over v > 0 (golden section around its
 * peak, bracketed on a coarse grid). */
static double law_max(const usm_model *m, const usm_params *p)
{
    double best = -INFINITY, vbest = 0, out[2];
    for (int i = 0; i <= 1200; ++i) {
        const double v = 1e-9 * pow(10.0, i / 100.0);
        m->friction(v, p, out);
        if (out[0] > best) {
            best = out[0];
            vbest = v;
        }
    }
    double a = vbest / 1.03, b = vbest * 1.03;
    for (int it = 0; it < 200; ++it) {
        const double c = b - 0.6180339887498949 * (b - a), d = a + 0.6180339887498949 * (b - a);
        double fc[2], fd[2];
        m->friction(c, p, fc);
        m->friction(d, p, fd);
        if (fc[0] > fd[0])
            b = d;
        else
            a = c;
    }
    m->friction(0.5 * (a + b), p, out);
    return fmax(best, out[0]);
}

static void check_stribeck(void)
{
    const usm_model *m = usm_model_find("4dof_friction_stribeck");
    CHECK(m != NULL, "model 4dof_friction_stribeck is not generated");
    if (!m)
        return;
    usm_params p;
    usm_params_default(&p);
    p.kappa = 1000;
    const double mu_max = law_max(m, &p);
    usm_steady *s = usm_steady_alloc(m);
    int multi = 0;
    /* loads from stick-like to beyond the law's peak, both signs */
    for (int i = -30; i <= 30; ++i) {
        p.T = 1e-3 * i / 30.0;
        double seed[USM_SEED_COUNT];
        const int rc = usm_steady_solve(s, &p, NULL);
        /* the tilt does not depend on the law: take the 3dof root as the truth */
        usm_steady *s3 = usm_steady_alloc(usm_model_find("3dof"));
        const int rc3 = usm_steady_solve(s3, &p, NULL);
        const double theta = rc3 == USM_OK ? usm_steady_root(s3, 0)->theta : NAN;
        usm_steady_free(s3);
        if (rc3 != USM_OK)
            continue;
        usm_params unit = p;
        unit.m0 = 1.0;
        m->steady_seed(theta, &unit, seed);
        const double alpha = atan2(seed[USM_SEED_SIN_ALPHA], seed[USM_SEED_COS_ALPHA]);
        const double mu_needed = seed[USM_SEED_F_T] / seed[USM_SEED_F_N];
        const int truth = rotor_sign_changes(m, &p, theta, alpha);
        int at_theta = 0;
        for (size_t k = 0; k < usm_steady_count(s); ++k) {
            const usm_steady_solution *r = usm_steady_root(s, k);
            if (!close_to(r->theta, theta, 1e-9))
                continue;
            ++at_theta;
            worst_residual = fmax(worst_residual, r->residual_norm / (p.m0 + fabs(p.T)));
            CHECK(r->residual_norm <= 1e-10 * (p.m0 + fabs(p.T)),
                  "stribeck T = %g root %zu: residual %.3g", p.T, k, r->residual_norm);
            if (k > 0 && close_to(usm_steady_root(s, k - 1)->theta, r->theta, 1e-9))
                CHECK(fabs(usm_steady_root(s, k - 1)->v_rel) <= fabs(r->v_rel),
                      "stribeck T = %g: roots at one tilt not ordered by |v_rel|", p.T);
        }
        if (truth >= 2)
            ++multi;
        CHECK(at_theta == truth,
              "stribeck T = %g (mu needed %.6g, law max %.6g): steady finds %d rotor speeds "
              "(status %d: %s), the fine scan %d",
              p.T, mu_needed, mu_max, at_theta, rc, usm_steady_message(s), truth);
        const int says_exceeds = rc == USM_ENOSOLUTION && strstr(usm_steady_message(s), "exceeds");
        CHECK(says_exceeds == (fabs(mu_needed) > mu_max),
              "stribeck T = %g: mu needed %.6g, law max %.6g, status %d: %s", p.T, mu_needed,
              mu_max, rc, usm_steady_message(s));
    }
    /* the solver's view of the law's range: the peak, not the value at large slip */
    double lo_mu, hi_mu;
    CHECK(usm_steady_friction_range(s, &p, &lo_mu, &hi_mu) == USM_OK, "friction range: %s",
          usm_steady_message(s));
    printf("stribeck law range: the solver's %.17g, the golden section's %.17g (relative %.2g)\n",
           hi_mu, mu_max, fabs(hi_mu - mu_max) / mu_max);
    /* both maximise the same kernel; a maximum is flat, so either is good to
     * rounding of mu (measured above): 1e-12 */
    CHECK(close_to(hi_mu, mu_max, 1e-12) && close_to(lo_mu, -mu_max, 1e-12),
          "stribeck law range [%.15g, %.15g], golden section max %.15g", lo_mu, hi_mu, mu_max);
    printf("4dof_friction_stribeck (kappa = 1000 s/m, law max %.6g): %d of 61 loads have "
           "several rotor speeds\n",
           mu_max, multi);
    CHECK(multi >= 4, "only %d loads with several slip roots: the test does not test", multi);
    usm_steady_free(s);

    /* the sweep's points are among steady's roots */
    usm_params_default(&p);
    p.kappa = 1000;
    usm_sweep *sw = sweep(m, &p, "T", 0.0, 9e-4, 31);
    const int n = sweep_points_found(m, &p, sw, "T");
    printf("4dof_friction_stribeck: steady contains the sweep's root at %d points\n", n);
    CHECK(n >= 10, "stribeck sweep: only %d converged points", n);
    usm_sweep_free(sw);
}

/* The range of the paper's law is mu0 (-pi/2, pi/2) in closed form; a stick
 * model has none. */
static void check_friction_range(void)
{
    usm_params p;
    double lo, hi;
    usm_params_default(&p);
    usm_steady *s = usm_steady_alloc(usm_model_find("4dof"));
    CHECK(usm_steady_friction_range(s, &p, &lo, &hi) == USM_OK, "4dof friction range: %s",
          usm_steady_message(s));
    CHECK(close_to(hi, p.mu0 * HALF_PI, 1e-15) && close_to(lo, -p.mu0 * HALF_PI, 1e-15),
          "atan law range [%.17g, %.17g], expected +-%.17g", lo, hi, p.mu0 * HALF_PI);
    usm_steady_free(s);
    s = usm_steady_alloc(usm_model_find("3dof"));
    CHECK(usm_steady_friction_range(s, &p, &lo, &hi) == USM_EINPUT &&
              strstr(usm_steady_message(s), "no friction law"),
          "3dof friction range: %s", usm_steady_message(s));
    usm_steady_free(s);
}

/* ---- 4: messages for extreme inputs ----------------------------------------------- */

/* q starts with the lower-case word w, ignoring case. */
static int starts_with_ci(const char *q, const char *w)
{
    for (; *w; ++q, ++w)
        if (tolower((unsigned char)*q) != *w)
            return 0;
    return 1;
}

/* "inf" or "nan" as a word of msg (case-insensitive). */
static int names_nonfinite(const char *msg)
{
    for (const char *q = msg; *q; ++q) {
        if (q > msg && isalpha((unsigned char)q[-1]))
            continue;
        if ((starts_with_ci(q, "inf") || starts_with_ci(q, "nan")) &&
            !isalpha((unsigned char)q[3]))
            return 1;
    }
    return 0;
}

static void check_messages(void)
{
    static const struct {
        const char *model, *name;
        double value;
    } cases[] = {
        {"3dof", "m0", 1e-300},  {"3dof", "m0", 1e300},  {"3dof", "m0", 4e-320},
        {"3dof", "c_r", 1e300},  {"3dof", "c_r", 1e308}, {"3dof", "c_r", 1e-300},
        {"3dof", "F0", 1e300},   {"3dof", "F0", 1e308},  {"4dof", "F0", 1e308},
        {"4dof", "m0", 1e-300},  {"4dof", "T", 1e300},   {"4dof", "T", -1e300},
        {"4dof", "c_r", 1e308},  {"4dof", "mu0", 1e-300}, {"4dof", "kappa", 1e300},
        {"4dof", "kappa", 1e-300}, {"3dof", "T", 1e308}, {"3dof", "f", 1e300},
    };
    CHECK(names_nonfinite("needs at least inf N m") && names_nonfinite("-nan") &&
              !names_nonfinite("infimum, finite"),
          "names_nonfinite does not recognise its words");
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        const usm_model *m = usm_model_find(cases[i].model);
        usm_params p;
        char msg[USM_MSG_LEN];
        usm_params_default(&p);
        usm_params_set(&p, cases[i].name, cases[i].value, msg);
        usm_steady *s = usm_steady_alloc(m);
        const int rc = usm_steady_solve(s, &p, NULL);
        const char *why = usm_steady_message(s);
        printf("%s %s = %g: status %d: %s\n", cases[i].model, cases[i].name, cases[i].value, rc,
               rc == USM_OK ? "(solved)" : why);
        CHECK(!names_nonfinite(why), "%s %s = %g: message names a non-finite number: %s",
              cases[i].model, cases[i].name, cases[i].value, why);
        CHECK(rc == USM_OK || why[0] != '\0', "%s %s = %g: status %d without a message",
              cases[i].model, cases[i].name, cases[i].value, rc);
        for (size_t k = 0; k < usm_steady_count(s); ++k) {
            worst_residual =
                fmax(worst_residual, usm_steady_root(s, k)->residual_norm / (p.m0 + fabs(p.T)));
            CHECK(usm_steady_root(s, k)->residual_norm <= 1e-10 * (p.m0 + fabs(p.T)),
                  "%s %s = %g: root %zu has residual %.3g", cases[i].model, cases[i].name,
                  cases[i].value, k, usm_steady_root(s, k)->residual_norm);
        }
        usm_steady_free(s);
    }
}

int main(void)
{
    gsl_set_error_handler_off();
    static const fold_case folds[] = {
        {"3dof", "T", 0.0, -5.0, NULL, 0, NULL, 0},
        {"4dof", "T", 0.0, -5.0, "mu0", 1e4, NULL, 0},
        {"3dof", "m0", 0.1, 1e-4, "T", -0.5, NULL, 0},
        {"4dof", "m0", 0.005, 1e-4, "T", -5e-4, NULL, 0},
        {"3dof", "f", 37000, 10000, "T", -1.0, NULL, 0},
        {"4dof", "f", 37000, 10000, "T", -1.0, "mu0", 1e4},
    };
    for (size_t i = 0; i < sizeof folds / sizeof folds[0]; ++i)
        check_fold(&folds[i]);
    check_negative_load("3dof", 0.3);
    check_negative_load("4dof", 1e4);
    check_stribeck();
    check_friction_range();
    check_messages();
    printf("largest residual of a root %.2g of m0 + |T| (tolerance 1e-10)\n", worst_residual);
    if (failures)
        printf("%d check(s) failed\n", failures);
    return failures != 0;
}
