/* Every stationary root with its own stability:
 * usm_floquet_roots against an independent computation.
 *
 * Truth: CVODES on the variational equations (USM_FLOQUET_VARIATIONAL,
 * rtol 1e-12), root by root through usm_floquet_compute; the default method
 * (Magnus) of usm_floquet_roots must agree on every multiplier of every root
 * to 1e-8 (pairs matched by nearest distance, check.h), and on the
 * stability.  usm_floquet_roots' k-th result must be bit for bit
 * usm_floquet_compute's of root k with the same options.
 *
 * Points: F0 = 1.2 N, f = 38 kHz, where the smallest-tilt root is unstable
 * (max |lambda| 1.138) and the second (theta 8.0e-5) stable; F0 = 1.001 N,
 * f = 38 kHz (root #1 at theta 1.03e-7 unstable, root #2 at 8.635e-5); and
 * the paper's point (one root) -- for 3dof and 4dof, and twist_integrated.
 * Prints the cost per root (wall time of the default method).
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <gsl/gsl_errno.h>

#include "usm.h"

#include "check.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

typedef struct point {
    const char *base, *variant;
    double F0, f;
    int min_roots;         /* at least this many roots */
    int stable_first;      /* -1: not asserted; 0/1: root #1's stability */
    int stable_second;     /* -1: not asserted (or no second root) */
} point;

static double total_time;
static long total_roots;

static void check_point(const point *pt)
{
    const usm_model *m = usm_model_variant(pt->base, pt->variant);
    if (!CHECK(m != NULL, "%s/%s: model not generated", pt->base, pt->variant))
        return;
    usm_params p;
    usm_params_default(&p);
    p.F0 = pt->F0;
    p.f = pt->f;
    usm_steady *s = usm_steady_alloc(m);
    usm_floquet *fl = usm_floquet_alloc(m);
    usm_floquet_result *all = NULL;
    if (!CHECK(s && fl, "out of memory"))
        goto done;
    if (!CHECK(usm_steady_solve(s, &p, NULL) == USM_OK, "%s: F0 %g f %g: no root: %s", m->name,
               pt->F0, pt->f, usm_steady_message(s)))
        goto done;
    const size_t n = usm_steady_count(s);
    CHECK(n >= (size_t)pt->min_roots, "%s: F0 %g f %g: %zu roots, want >= %d", m->name, pt->F0,
          pt->f, n, pt->min_roots);
    all = calloc(n, sizeof *all);
    if (!CHECK(all != NULL, "out of memory"))
        goto done;
    const double t_start = now();
    const int rc = usm_floquet_roots(fl, &p, s, 0.0, NULL, all);
    const double dt = now() - t_start;
    if (!CHECK(rc == USM_OK, "%s: usm_floquet_roots: %s", m->name, usm_floquet_message(fl)))
        goto done;
    total_time += dt;
    total_roots += (long)n;
    printf("%s F0 = %g N, f = %g Hz: %zu roots, %.3g ms per root (default method)\n", m->name,
           pt->F0, pt->f, n, 1e3 * dt / (double)n);

    usm_floquet_options ref;
    usm_floquet_options_default(&ref);
    ref.method = USM_FLOQUET_VARIATIONAL;
    ref.rtol = 1e-12;
    ref.atol = 1e-16;
    for (size_t k = 0; k < n; ++k) {
        const usm_steady_solution *root = usm_steady_root(s, k);
        usm_floquet_result one, truth;
        /* the same as one root alone, bit for bit */
        if (CHECK(usm_floquet_compute(fl, &p, root, 0.0, NULL, &one) == USM_OK,
                  "%s: root #%zu: %s", m->name, k + 1, usm_floquet_message(fl)))
            CHECK(one.n == all[k].n && memcmp(one.re, all[k].re, sizeof one.re) == 0 &&
                      memcmp(one.im, all[k].im, sizeof one.im) == 0 &&
                      one.max_modulus == all[k].max_modulus && one.stable == all[k].stable,
                  "%s: root #%zu: usm_floquet_roots differs from usm_floquet_compute", m->name,
                  k + 1);
        if (!CHECK(usm_floquet_compute(fl, &p, root, 0.0, &ref, &truth) == USM_OK,
                   "%s: root #%zu: variational: %s", m->name, k + 1, usm_floquet_message(fl)))
            continue;
        const double d = MULTIPLIERS_DISTANCE(all[k], truth);
        printf("  root #%zu theta %.6g: max |lambda| %.10g (%s), variational %.10g, "
               "multipliers differ by %.2e\n",
               k + 1, root->theta, all[k].max_modulus, all[k].stable ? "stable" : "unstable",
               truth.max_modulus, d);
        CHECK(d <= 1e-8, "%s: root #%zu: multipliers differ from CVODES by %.3e", m->name, k + 1,
              d);
        CHECK(fabs(all[k].max_modulus - truth.max_modulus) <= 1e-8,
              "%s: root #%zu: max modulus %.12g, CVODES %.12g", m->name, k + 1,
              all[k].max_modulus, truth.max_modulus);
        CHECK(all[k].stable == truth.stable, "%s: root #%zu: stability differs from CVODES",
              m->name, k + 1);
    }
    if (pt->stable_first >= 0)
        CHECK(all[0].stable == pt->stable_first, "%s: F0 %g: root #1 stable %d, want %d", m->name,
              pt->F0, all[0].stable, pt->stable_first);
    if (pt->stable_second >= 0 && n >= 2)
        CHECK(all[1].stable == pt->stable_second, "%s: F0 %g: root #2 stable %d, want %d",
              m->name, pt->F0, all[1].stable, pt->stable_second);
done:
    free(all);
    usm_floquet_free(fl);
    usm_steady_free(s);
}

/* The issue's numbers at F0 = 1.2 N, f = 38 kHz (3dof, paper's twist law). */
static void check_issue_numbers(void)
{
    const usm_model *m = usm_model_find("3dof");
    usm_params p;
    usm_params_default(&p);
    p.F0 = 1.2;
    p.f = 38000;
    usm_steady *s = usm_steady_alloc(m);
    usm_floquet *fl = usm_floquet_alloc(m);
    usm_floquet_result all[8];
    if (CHECK(usm_steady_solve(s, &p, NULL) == USM_OK && usm_steady_count(s) == 2,
              "3dof F0 1.2: want 2 roots") &&
        CHECK(usm_floquet_roots(fl, &p, s, 0.0, NULL, all) == USM_OK, "%s",
              usm_floquet_message(fl))) {
        CHECK(fabs(all[0].max_modulus - 1.1383964) < 1e-6 && !all[0].stable,
              "root #1: max |lambda| %.10g, want 1.1383964 (unstable)", all[0].max_modulus);
        CHECK(fabs(usm_steady_root(s, 1)->theta - 8.0137e-5) < 1e-8 && all[1].stable,
              "root #2: theta %.6g, stable %d; want 8.0137e-5, stable",
              usm_steady_root(s, 1)->theta, all[1].stable);
    }
    /* a failure names the root */
    usm_floquet_options bad;
    usm_floquet_options_default(&bad);
    bad.rtol = 1.0;
    CHECK(usm_floquet_roots(fl, &p, s, 0.0, &bad, all) == USM_EINPUT &&
              strstr(usm_floquet_message(fl), "root #1") &&
              strstr(usm_floquet_message(fl), "rtol"),
          "bad rtol: message \"%s\" does not name root #1 and rtol", usm_floquet_message(fl));
    usm_floquet_free(fl);
    usm_steady_free(s);
}

int main(void)
{
    gsl_set_error_handler_off();
    const point pts[] = {
        {"3dof", "paper", 1.2, 38000, 2, 0, 1},
        {"3dof", "paper", 1.001, 38000, 2, 0, -1},
        {"3dof", "paper", 0.4, 37000, 1, 1, -1},
        {"4dof", "paper", 1.2, 38000, 2, -1, -1},
        {"4dof", "paper", 1.001, 38000, 2, -1, -1},
        {"3dof", "twist_integrated", 1.2, 38000, 2, -1, -1},
        {"4dof", "twist_integrated", 1.001, 38000, 2, -1, -1},
    };
    for (size_t i = 0; i < sizeof pts / sizeof pts[0]; ++i)
        check_point(&pts[i]);
    check_issue_numbers();
    if (total_roots > 0)
        printf("per-root Floquet cost (default method): %.3g ms over %ld roots\n",
               1e3 * total_time / (double)total_roots, total_roots);
    printf("%d failures\n", failures);
    return failures != 0;
}
