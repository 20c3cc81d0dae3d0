/* test_kernels_imperfect: the imperfect variant with its three
 * imperfections at 0 is the integrated-twist model it is built on.
 *
 * The two models are derived separately (derive/variants.py: "imperfect" adds
 * the driver's amplitude imbalance and phase error and the stator's mode split
 * to "twist_integrated"), so this compares two derivations, not one with
 * itself.  At NSAMPLES random states, times and parameter sets (defaults times
 * log-uniform factors in [1/2, 2], imperfections 0) every kernel of
 * usm_<base>_imperfect must equal that of usm_<base>_twist_integrated to
 * rounding: |a - b| <= TOL * (largest |entry| of the row in either), TOL =
 * 1e-12 (the imperfection terms are exact zeros there, so only the order of
 * operations of the emitted code can differ).  A second check with the
 * imperfections set makes sure the comparison can fail: the right-hand sides
 * must then differ by more than 1e-6 of their row sizes.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "usm.h"

#include "check.h"

#define NSAMPLES 100
/* The two models are derived from the same equations (the imperfection terms
 * vanish at zero), but their expressions are simplified and common
 * subexpressions taken separately: measured (printed) up to 1.3e-14 of a row's
 * size, so 1e-12 */
#define TOL 1e-12
#define NMAX (3 * USM_MAX_NX * USM_MAX_NX + USM_MAX_NX * USM_NPARAMS)

static uint64_t rng = 0x1a2b3c4d5eULL;
static int reported; /* failures printed (the first 10) */
static double worst;  /* largest difference seen, relative to its row's size */

/* rows x cols arrays a, b: equal to TOL of each row's size. */
static void compare(const char *model, const char *kernel, int rows, int cols, const double *a,
                    const double *b)
{
    for (int i = 0; i < rows; ++i) {
        double size = 0;
        for (int j = 0; j < cols; ++j)
            size = fmax(size, fmax(fabs(a[i * cols + j]), fabs(b[i * cols + j])));
        for (int j = 0; j < cols; ++j) {
            const double d = fabs(a[i * cols + j] - b[i * cols + j]);
            if (size > 0)
                worst = fmax(worst, d / size);
            if (d <= TOL * size)
                continue;
            if (reported++ < 10)
                CHECK(0, "%s %s[%d,%d]: %.17g vs %.17g (row size %g)", model, kernel, i, j,
                      a[i * cols + j], b[i * cols + j], size);
            else
                ++failures;
        }
    }
}

static void random_sample(const usm_model *m, usm_params *p, double *x, double *v, double *t,
                          double *u)
{
    usm_params_default(p);
    for (int i = 0; i < USM_NPARAMS; ++i)
        *usm_params_field(p, &usm_param_table[i]) *= exp(rng_range(&rng, log(0.5), log(2.0)));
    p->I_yy = p->I_xx;
    const double W = 2.0 * 3.141592653589793 * p->f;
    for (int i = 0; i < m->nx; ++i) {
        x[i] = rng_range(&rng, -10.0, 10.0);
        v[i] = rng_range(&rng, -1.0, 1.0) * W;
    }
    x[m->x_theta] = exp(rng_range(&rng, log(1e-5), log(0.3)));
    x[m->x_phidot] = W * rng_range(&rng, 0.5, 1.5);
    x[m->x_psidot] = -W * rng_range(&rng, 0.5, 1.5);
    x[m->x_thetadot] = 0.05 * W * rng_range(&rng, -1.0, 1.0);
    x[m->x_tau] = rng_range(&rng, -1e-6, 1e-6);
    *t = rng_range(&rng, 0.0, 1e-3);
    for (int i = 0; i < m->nu; ++i)
        u[i] = rng_range(&rng, -10.0, 10.0);
    u[m->u_theta] = exp(rng_range(&rng, log(1e-5), log(0.3)));
}

static void check_base(const char *base)
{
    const usm_model *a = usm_model_variant(base, "imperfect");
    const usm_model *b = usm_model_variant(base, "twist_integrated");
    if (!CHECK(a && b && a->nx == b->nx && a->nu == b->nu && a->imperfect && !b->imperfect,
               "%s: imperfect / twist_integrated models missing or unlike", base))
        return;
    const int n = a->nx, nu = a->nu;
    static double oa[NMAX], ob[NMAX];
    int differs = 0;
    for (int k = 0; k < NSAMPLES; ++k) {
        usm_params p;
        double x[USM_MAX_NX], v[USM_MAX_NX], t, u[USM_MAX_NU], du[USM_MAX_NU];
        random_sample(a, &p, x, v, &t, u);
        a->mass(x, &p, oa), b->mass(x, &p, ob), compare(a->name, "mass", n, n, oa, ob);
        a->rhs(x, t, &p, oa), b->rhs(x, t, &p, ob), compare(a->name, "rhs", n, 1, oa, ob);
        a->jac_rhs(x, t, &p, oa), b->jac_rhs(x, t, &p, ob), compare(a->name, "jac_rhs", n, n, oa, ob);
        a->jac_mass(x, v, &p, oa), b->jac_mass(x, v, &p, ob);
        compare(a->name, "jac_mass", n, n, oa, ob);
        a->linearisation(x, v, t, &p, oa), b->linearisation(x, v, t, &p, ob);
        compare(a->name, "linearisation", 3 * n, n, oa, ob);
        a->outputs(x, v, t, &p, oa), b->outputs(x, v, t, &p, ob);
        compare(a->name, "outputs", USM_OUT_COUNT, 1, oa, ob);
        a->tangent_map(x, &p, oa), b->tangent_map(x, &p, ob);
        compare(a->name, "tangent_map", n, n, oa, ob);
        a->steady_residual(u, &p, oa), b->steady_residual(u, &p, ob);
        compare(a->name, "steady_residual", nu, 1, oa, ob);
        a->steady_jacobian(u, &p, oa), b->steady_jacobian(u, &p, ob);
        compare(a->name, "steady_jacobian", nu, nu, oa, ob);
        a->steady_jacobian_params(u, &p, oa), b->steady_jacobian_params(u, &p, ob);
        compare(a->name, "steady_jacobian_params", nu, USM_NPARAMS, oa, ob);
        a->steady_outputs(u, &p, oa), b->steady_outputs(u, &p, ob);
        compare(a->name, "steady_outputs", USM_STEADY_COUNT, 1, oa, ob);
        a->steady_seed(u[0], &p, oa), b->steady_seed(u[0], &p, ob);
        compare(a->name, "steady_seed", USM_SEED_COUNT, 1, oa, ob);
        a->steady_state(u, 0.3, t, &p, oa), b->steady_state(u, 0.3, t, &p, ob);
        compare(a->name, "steady_state", 2 * n, 1, oa, ob);
        a->steady_power(u, &p, oa), b->steady_power(u, &p, ob);
        compare(a->name, "steady_power", USM_POWER_COUNT, 1, oa, ob);
        usm_params dp;
        for (int i = 0; i < USM_NPARAMS; ++i)
            *usm_params_field(&dp, &usm_param_table[i]) = rng_range(&rng, -1.0, 1.0);
        for (int i = 0; i < nu; ++i)
            du[i] = rng_range(&rng, -1.0, 1.0);
        a->floquet_direction(u, t, du, 1e-6, &p, &dp, oa);
        b->floquet_direction(u, t, du, 1e-6, &p, &dp, ob);
        compare(a->name, "floquet_direction", 2 * n, n, oa, ob);
        /* the comparison can fail: with imperfections the dynamics differ */
        p.amp_imbalance = 0.1;
        p.phase_error = 0.2;
        p.mode_split = 0.05;
        a->rhs(x, t, &p, oa), b->rhs(x, t, &p, ob);
        int d = 0;
        for (int i = 0; i < n; ++i)
            d |= fabs(oa[i] - ob[i]) > 1e-6 * fmax(fabs(oa[i]), fabs(ob[i]));
        differs += d;
    }
    CHECK(differs >= NSAMPLES / 2, "%s: imperfections change rhs in only %d of %d samples",
          a->name, differs, NSAMPLES);
}

int main(void)
{
    check_base("3dof");
    check_base("4dof");
    if (failures) {
        fprintf(stderr, "test_kernels_imperfect: %d failures\n", failures);
        return 1;
    }
    printf("test_kernels_imperfect: imperfect == twist_integrated at zero imperfection "
           "(%d samples per model; largest difference %.2g of a row)\n", NSAMPLES, worst);
    return 0;
}
