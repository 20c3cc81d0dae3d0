/* The default Floquet method against CVODES.
 *
 * The default (USM_FLOQUET_AUTO: the Magnus integrator, one matrix exponential
 * under the integrated twist law) must give the multipliers of CVODES on the
 * variational equations at rtol 1e-12 (the independent check) to 1e-9 (see
 * TOL_MULTIPLIERS: what the reference delivers), for
 * the paper's models and the twist_integrated ones, at the paper's point and
 * at other frequencies, loads and start times.  Also: the method names, the
 * fall-back where the Magnus series diverges (a stiff linearisation), and the
 * Magnus method's general path for coefficients that are neither constant nor
 * affine in t (no generated model has them: a model whose Jacobian is
 * modulated in time here), again against CVODES.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <gsl/gsl_errno.h>

#include "usm.h"

#include "check.h"

/* Tolerances, from what the reference delivers (measured at the points of
 * check_model).  The reference is CVODES on the variational
 * equations at rtol 1e-12: it is within 3.7e-11 of CVODES at rtol 1e-13 (the
 * multipliers, matched by nearest pairs) and 2.9e-13 in max |lambda|; the
 * default method is within 3.9e-11 and 9e-13 of it.  A last-bit change of
 * the input (f or the tilt one ulp away) moves the reference by up to 2.4e-10
 * (4dof at 30 kHz, T = 0) and 6.9e-12 in max |lambda|, and the default with
 * it; a last-bit change of the kernels (the fused `linearisation` kernel in
 * place of mass, jac_rhs, jac_mass) moved every method by up to 4.1e-8
 * (before the coordinates work formed G without inverting M alone: test
 * multipliers_reference)
 * (3dof: M(xbar) is ill-conditioned near theta = 1e-4), all of them alike:
 * the two still agree to 4e-11.  Both compute the same coefficient matrix
 * G(t), so what is compared is the integration of one linear system:
 * TOL_MULTIPLIERS 1e-9 is 25 times the reference's own error, TOL_MODULUS
 * 1e-10 over 10 times its last-bit motion. */
#define TOL_MULTIPLIERS 1e-9
#define TOL_MODULUS 1e-10

/* Multipliers of a and b matched by nearest pairs (check.h). */
static double distance(const usm_floquet_result *a, const usm_floquet_result *b)
{
    return MULTIPLIERS_DISTANCE(*a, *b);
}

typedef struct {
    double f, T, t0;
} point;

static void check_model(const char *name)
{
    const usm_model *m = usm_model_find(name);
    CHECK(m != NULL, "model %s not generated", name);
    if (!m)
        return;
    const point pts[] = {{37000, 6.46e-5, 0},     {30000, 0, 0},        {44000, 1e-3, 0},
                         {37000, 6.46e-5, 0.01},  {37000, -2e-4, 0},    {33000, 3e-4, 2e-3}};
    usm_steady *s = usm_steady_alloc(m);
    usm_floquet *f = usm_floquet_alloc(m);
    for (size_t k = 0; k < sizeof pts / sizeof pts[0]; ++k) {
        usm_params p;
        usm_params_default(&p);
        p.f = pts[k].f;
        p.T = pts[k].T;
        if (usm_steady_solve(s, &p, NULL) != USM_OK) {
            /* only the slip models' friction saturates, at T = mu0 pi/2 F0 R (0.95 mN m) */
            CHECK(m->slip && p.T > 0.95e-3, "%s f = %g T = %g: no stationary solution: %s", name,
                  p.f, p.T, usm_steady_message(s));
            printf("%s f = %g T = %g: no stationary solution (friction saturated), as expected\n",
                   name, p.f, p.T);
            continue;
        }
        const usm_steady_solution *sol = usm_steady_root(s, 0);
        usm_floquet_options ref_opt;
        usm_floquet_result ref, res;
        usm_floquet_options_default(&ref_opt);
        ref_opt.method = USM_FLOQUET_VARIATIONAL;
        ref_opt.rtol = 1e-12;
        ref_opt.atol = 1e-16;
        int rc = usm_floquet_compute(f, &p, sol, pts[k].t0, &ref_opt, &ref);
        CHECK(rc == USM_OK, "%s: CVODES: %s", name, usm_floquet_message(f));
        rc = usm_floquet_compute(f, &p, sol, pts[k].t0, NULL, &res);
        CHECK(rc == USM_OK, "%s: default method: %s", name, usm_floquet_message(f));
        if (rc != USM_OK)
            continue;
        const double d = distance(&res, &ref);
        printf("%-22s f = %5.0f Hz T = %8.2e N m t0 = %5.3f s: |lambda|max %.10f, default (%s) "
               "vs CVODES rtol 1e-12: %.1e\n",
               name, p.f, p.T, pts[k].t0, res.max_modulus, usm_floquet_method_name(res.method), d);
        CHECK(d <= TOL_MULTIPLIERS, "%s f = %g T = %g t0 = %g: default and CVODES differ by %.2e",
              name, p.f, p.T, pts[k].t0, d);
        CHECK(res.method == USM_FLOQUET_MAGNUS, "%s: the default used %s", name,
              usm_floquet_method_name(res.method));
        CHECK(fabs(res.max_modulus - ref.max_modulus) <= TOL_MODULUS && res.stable == ref.stable,
              "%s: max_modulus %.12f vs %.12f", name, res.max_modulus, ref.max_modulus);
        int ca = 0, cb = 0;
        for (int i = 0; i < res.n; ++i) {
            ca += res.cyclic[i];
            cb += ref.cyclic[i];
        }
        CHECK(ca == cb, "%s: %d cyclic multipliers, CVODES %d", name, ca, cb);
    }
    usm_floquet_free(f);
    usm_steady_free(s);
}

static void check_names(void)
{
    char msg[USM_MSG_LEN];
    const usm_floquet_method all[] = {USM_FLOQUET_VARIATIONAL, USM_FLOQUET_EXPONENTIAL,
                                      USM_FLOQUET_MAGNUS, USM_FLOQUET_AUTO};
    for (size_t k = 0; k < sizeof all / sizeof all[0]; ++k) {
        usm_floquet_method back = (usm_floquet_method)-1;
        const char *name = usm_floquet_method_name(all[k]);
        CHECK(name != NULL, "method %d has no name", (int)all[k]);
        if (!name)
            continue;
        CHECK(usm_floquet_method_from_name(name, &back, msg) == USM_OK && back == all[k],
              "%s does not name method %d", name, (int)all[k]);
    }
    usm_floquet_method m = USM_FLOQUET_MAGNUS;
    CHECK(usm_floquet_method_from_name("runge-kutta", &m, msg) == USM_EINPUT &&
              strstr(msg, "runge-kutta") && strstr(msg, "magnus") && m == USM_FLOQUET_MAGNUS,
          "an unknown name: '%s'", msg);
    CHECK(usm_floquet_method_name((usm_floquet_method)17) == NULL, "a name for method 17");
    usm_floquet_options o;
    usm_floquet_options_default(&o);
    CHECK(o.method == USM_FLOQUET_AUTO, "the default method is %d", (int)o.method);
}

/* Stiff linearisations (d_R = 1e6 to 1e10 N s/m, |A| T up to ~1e9): the
 * default carries the stiff rotor mode in its exact flows (one exponential
 * of T Ga / M), so it answers where the sixth-order Magnus steps it replaced
 * diverged (d_R = 1e10: "Magnus step 1 of 1 failed: not finite", the default
 * then fell back to the product of exponentials).  Reference: the
 * exponential method (64 steps, Richardson), within 1.1e-10 of 256 steps at
 * d_R = 1e6, 2e-14 at 1e8; measured against it: 1.2e-10 (1e6), 1.7e-9 (1e8),
 * 6e-8 (1e10, where the exponential method is the less accurate one: the
 * default is within 3e-9 of 4096 Magnus steps on the same coefficient
 * matrices, the exponential method 6e-8).  So 1e-8 up to 1e8, 1e-6 at 1e10. */
static void check_stiff(void)
{
    const usm_model *m = usm_model_find("3dof");
    usm_steady *s = usm_steady_alloc(m);
    usm_floquet *f = usm_floquet_alloc(m);
    usm_floquet_options o;
    usm_floquet_result a, b;
    usm_params p;
    usm_params_default(&p);
    const double dR[] = {1e6, 1e8};
    for (int k = 0; k < 2; ++k) {
        p.d_R = dR[k];
        CHECK(usm_steady_solve(s, &p, NULL) == USM_OK, "steady d_R = %g", p.d_R);
        usm_floquet_options_default(&o);
        o.method = USM_FLOQUET_MAGNUS;
        CHECK(usm_floquet_compute(f, &p, usm_steady_root(s, 0), 0, &o, &a) == USM_OK,
              "magnus at d_R = %g: %s", p.d_R, usm_floquet_message(f));
        o.method = USM_FLOQUET_EXPONENTIAL;
        CHECK(usm_floquet_compute(f, &p, usm_steady_root(s, 0), 0, &o, &b) == USM_OK,
              "exponential at d_R = %g: %s", p.d_R, usm_floquet_message(f));
        const double d = distance(&a, &b);
        printf("3dof d_R = %g: magnus vs exponential %.1e\n", p.d_R, d);
        CHECK(d < 1e-8, "d_R = %g: magnus and exponential differ by %.2e", p.d_R, d);
    }
    p.d_R = 1e10;
    CHECK(usm_steady_solve(s, &p, NULL) == USM_OK, "steady d_R = 1e10");
    usm_floquet_options_default(&o);
    o.method = USM_FLOQUET_EXPONENTIAL;
    CHECK(usm_floquet_compute(f, &p, usm_steady_root(s, 0), 0, &o, &b) == USM_OK,
          "exponential at d_R = 1e10: %s", usm_floquet_message(f));
    CHECK(usm_floquet_compute(f, &p, usm_steady_root(s, 0), 0, NULL, &a) == USM_OK &&
              a.method == USM_FLOQUET_MAGNUS && usm_floquet_message(f)[0] == '\0',
          "the default at d_R = 1e10: %s", usm_floquet_message(f));
    printf("3dof d_R = 1e10: default vs exponential %.1e\n", distance(&a, &b));
    CHECK(distance(&a, &b) < 1e-6, "d_R = 1e10: default and exponential differ by %.2e",
          distance(&a, &b));
    o.rtol = 0;
    CHECK(usm_floquet_compute(f, &p, usm_steady_root(s, 0), 0, &o, &a) == USM_EINPUT &&
              strncmp(usm_floquet_message(f), "rtol", 4) == 0,
          "rtol 0 accepted");
    usm_floquet_free(f);
    usm_steady_free(s);
}

/* A model whose df/dx carries a parametric modulation 0.2 c_r cos(Omega t)
 * in one entry: the linear system of both Floquet methods changes alike, and
 * its coefficients are no longer affine in t.  The reference (CVODES, rtol
 * 1e-12) is within 2.1e-11 of rtol 1e-13 and moves by up to 1.1e-11 under a
 * last-bit change of the tilt; the default differs from it by up to 6.9e-11:
 * TOL_MULTIPLIERS (1e-9) holds. */
static usm_model modulated;
static const usm_model *modulated_base;

static void jac_rhs_modulated(const double *restrict x, double t, const usm_params *restrict p,
                              double *restrict out)
{
    const int n = modulated_base->nx;
    modulated_base->jac_rhs(x, t, p, out);
    out[4 * n + 1] += 0.2 * p->c_r * cos(6.283185307179586 * p->f * t);
}

static void check_general_coefficients(const char *name)
{
    modulated_base = usm_model_find(name);
    modulated = *modulated_base;
    modulated.jac_rhs = jac_rhs_modulated;
    usm_params p;
    usm_params_default(&p);
    usm_steady *s = usm_steady_alloc(modulated_base);
    usm_floquet *f = usm_floquet_alloc(&modulated);
    usm_floquet_options o;
    usm_floquet_result ref, res;
    CHECK(usm_steady_solve(s, &p, NULL) == USM_OK, "%s: steady", name);
    for (int k = 0; k < 2; ++k) {
        const double t0 = k == 0 ? 0.0 : 0.3 / p.f;
        usm_floquet_options_default(&o);
        o.method = USM_FLOQUET_VARIATIONAL;
        o.rtol = 1e-12;
        o.atol = 1e-16;
        CHECK(usm_floquet_compute(f, &p, usm_steady_root(s, 0), t0, &o, &ref) == USM_OK,
              "%s modulated: CVODES: %s", name, usm_floquet_message(f));
        CHECK(usm_floquet_compute(f, &p, usm_steady_root(s, 0), t0, NULL, &res) == USM_OK,
              "%s modulated: default: %s", name, usm_floquet_message(f));
        const double d = distance(&res, &ref);
        printf("%s with a modulated Jacobian, t0 = %g s: |lambda|max %.10f, default (%s) vs "
               "CVODES rtol 1e-12: %.1e\n",
               name, t0, res.max_modulus, usm_floquet_method_name(res.method), d);
        CHECK(d <= TOL_MULTIPLIERS && res.method == USM_FLOQUET_MAGNUS,
              "%s modulated: default (%s) and CVODES differ by %.2e", name,
              usm_floquet_method_name(res.method), d);
    }
    usm_floquet_free(f);
    usm_steady_free(s);
}

int main(void)
{
    gsl_set_error_handler_off();
    check_names();
    check_model("3dof");
    check_model("4dof");
    check_model("3dof_twist_integrated");
    check_model("4dof_twist_integrated");
    check_stiff();
    check_general_coefficients("3dof");
    check_general_coefficients("3dof_twist_integrated");
    if (failures)
        printf("%d failure(s)\n", failures);
    return failures != 0;
}
