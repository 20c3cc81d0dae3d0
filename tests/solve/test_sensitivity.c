/* test_sensitivity: every derivative of usm_sensitivity_compute against central
 * finite differences of the solvers themselves.
 *
 * For parameter p_j the solution is re-solved at p_j +- h_j, p_j +- 2 h_j with
 * usm_steady_solve_from (Newton from the nominal root: the same branch) and
 * the outputs taken from it; max_modulus from usm_sensitivity_max_modulus, the
 * value the derivative is of (the exponential method's monodromy matrix,
 * eigenvalues in balanced coordinates), which must itself agree with
 * usm_floquet_compute (variational and exponential) to 1e-6.  Fourth-order
 * central differences.  Steps: stationary outputs h_j = 1e-3 |p_j| (1e-4 |f|
 * for f, whose scale is the resonance's width ~0.03 f): truncation
 * ~(h/scale)^4 <= 1e-10; max_modulus h_j = 1e-4 |p_j| (it curves on a scale
 * of ~1e-2 in c_r in the 4dof model; its value is smooth to ~1e-12).
 * The stationary outputs round to up to ~1e-9 relative (F_t = mu(v_rel) F_n in
 * the slip model and rotor_speed = v_c / R* come from differences of nearly
 * equal numbers), which the differences turn into ~1e-6 of an elasticity.
 * In the axisymmetric models I_xx and I_yy move together (the kernels use
 * I_xx for both) and the derivative in I_yy must be exactly 0.
 * Pass: |d - fd| <= 1e-5 |fd| + floor, floor = 1e-6 |y| / |p_j| (an elasticity
 * of 1e-6, the differences' own rounding) for the stationary outputs and
 * 1e-7 |y| / |p_j| for max_modulus.  The run prints the worst ratio
 * |d - fd| / bound (0.45 when written).
 * Also: at a crossing of two multipliers' moduli (check_kink) the derivative of
 * max_modulus is reported undefined.
 * Points: the paper's and 20 random parameter sets (every parameter scaled by
 * a factor in [0.85, 1.18], I_yy = I_xx) for 3dof and 4dof; the paper's point
 * for both twist_integrated models (the one-exponential path).
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <gsl/gsl_errno.h>

#include "check.h"
#include "usm_design.h"

#define NRANDOM 20
#define REL_STEP 1e-3
#define REL_STEP_F 1e-4 /* f: the resonance's width (~0.03 f) is the scale */
#define REL_STEP_MOD 1e-4 /* max_modulus: curves on a scale of ~1e-2 (c_r, 4dof) */
#define FLOOR 1e-6     /* elasticity resolved by the differences, stationary outputs */
#define FLOOR_MOD 1e-7 /* and max_modulus */
/* |max_modulus - usm_floquet_compute's| (its eigenvalues are taken in the
   ill-conditioned Euler-angle coordinates).  What the reference delivers
: usm_floquet_compute at its default rtol 1e-8 (CVODES) is within
   1.3e-7 of CVODES at rtol 1e-12 and moves by up to 2.1e-7 under a last-bit
   change of the tilt (tests/solve/test_steady_floquet.c); the exponential method is
   within 2e-11; measured here (printed at the end): up to 1.1e-7 */
#define MODULUS_AGREE 1e-6
/* The fourth-order differences at REL_STEP: their truncation and rounding
   (FLOOR, FLOOR_MOD) measured up to 0.45 of the bound TOL |fd| + floor
   (printed at the end) */
#define TOL 1e-5

static void random_params(uint64_t *state, usm_params *p)
{
    usm_params_default(p);
    for (int i = 0; i < USM_NPARAMS; ++i) {
        const usm_param_info *info = &usm_param_table[i];
        if (usm_params_get(p, info) == 0.0)
            continue; /* the imperfections (0: the ideal motor); no draw, so the
                         points stay those of the 19 parameters of the paper */
        *usm_params_field(p, info) *= exp(rng_range(state, log(0.85), log(1.18)));
    }
    p->I_yy = p->I_xx;
}

/* Outputs of the solver at p, from the root polished from u0. */
static int outputs_at(usm_sensitivity *sens, usm_steady *st, const usm_params *p,
                      const double *u0, int modulus, double y[USM_SENS_COUNT])
{
    if (usm_steady_solve_from(st, p, u0) != USM_OK || usm_steady_count(st) < 1)
        return -1;
    const usm_steady_solution *s = usm_steady_root(st, 0);
    if (fabs(s->theta - u0[0]) > 0.05 * fabs(u0[0]))
        return -1;
    y[USM_SENS_THETA] = s->theta;
    y[USM_SENS_ROTOR_SPEED] = s->rotor_speed;
    y[USM_SENS_F_N] = s->F_n;
    y[USM_SENS_F_T] = s->F_t;
    y[USM_SENS_EFFICIENCY] = s->efficiency;
    y[USM_SENS_STICK_MARGIN] = p->mu0 * s->F_n - s->F_t;
    y[USM_SENS_POWER_IN] = s->power_in;
    y[USM_SENS_POWER_OUT] = s->power_out;
    y[USM_SENS_MAX_MODULUS] = NAN;
    if (modulus && usm_sensitivity_max_modulus(sens, p, s, &y[USM_SENS_MAX_MODULUS]) != USM_OK)
        return -1;
    return 0;
}

static double worst; /* largest |d - fd| / (TOL |fd| + floor) seen */
static double worst_modulus; /* largest |max_modulus - usm_floquet_compute's| */

static int check_point(const usm_model *m, usm_steady *st, usm_sensitivity *sens,
                       usm_floquet *fl, const usm_params *p, const char *what)
{
    if (usm_steady_solve(st, p, NULL) != USM_OK)
        return 0;
    usm_steady_solution sol = *usm_steady_root(st, 0);
    usm_sensitivity_result r;
    int rc = usm_sensitivity_compute(sens, p, &sol, 1, &r);
    CHECK(rc == USM_OK, "%s %s: sensitivity failed: %s", m->name, what,
          usm_sensitivity_message(sens));
    if (rc != USM_OK)
        return 1;
    const int modulus = r.defined[USM_SENS_MAX_MODULUS];
    if (!modulus)
        printf("%s %s: max_modulus derivative undefined: %s\n", m->name, what,
               r.why[USM_SENS_MAX_MODULUS]);
    /* the value is the Floquet solver's (both of its methods) */
    for (int method = 0; method < 2; ++method) {
        usm_floquet_options opt;
        usm_floquet_result fr;
        usm_floquet_options_default(&opt);
        opt.method = method ? USM_FLOQUET_EXPONENTIAL : USM_FLOQUET_VARIATIONAL;
        CHECK(usm_floquet_compute(fl, p, &sol, 0.0, &opt, &fr) == USM_OK, "%s %s: floquet failed",
              m->name, what);
        worst_modulus = fmax(worst_modulus, fabs(fr.max_modulus - r.value[USM_SENS_MAX_MODULUS]));
        CHECK(fabs(fr.max_modulus - r.value[USM_SENS_MAX_MODULUS]) <= MODULUS_AGREE,
              "%s %s: max_modulus %.15g, floquet (%s) %.15g", m->name, what,
              r.value[USM_SENS_MAX_MODULUS], method ? "exponential" : "variational",
              fr.max_modulus);
    }
    for (int j = 0; j < USM_NPARAMS; ++j) {
        const char *pname = usm_param_table[j].name;
        /* an ideal model does not contain the imperfections, nor a
         * bilateral one e_impact: its
         * equations, and so every derivative, are independent of them */
        const int imperfection = strcmp(pname, "amp_imbalance") == 0 ||
                                 strcmp(pname, "phase_error") == 0 ||
                                 strcmp(pname, "mode_split") == 0 ||
                                 /* only the impact of a contact that opens */
                                 strcmp(pname, "e_impact") == 0;
        if ((m->axisymmetric_stator && strcmp(pname, "I_yy") == 0) || imperfection) {
            for (int k = 0; k < USM_SENS_COUNT; ++k)
                if (r.defined[k])
                    CHECK(r.d[k][j] == 0, "%s %s: d %s / d %s = %g, not 0", m->name, what,
                          usm_sensitivity_output_name(k), pname, r.d[k][j]);
            continue;
        }
        const double pj = usm_params_get(p, &usm_param_table[j]);
        /* y at p_j + s h, s = 1, -1, 2, -2; one step for the stationary
         * outputs, a smaller one for max_modulus */
        double y[2][4][USM_SENS_COUNT], hh[2];
        const double shift[4] = {1, -1, 2, -2};
        int solved = 1;
        for (int pass = 0; pass < 1 + modulus && solved; ++pass) {
            hh[pass] = (pass ? REL_STEP_MOD : strcmp(pname, "f") == 0 ? REL_STEP_F : REL_STEP) *
                       fabs(pj);
            for (int q = 0; q < 4 && solved; ++q) {
                usm_params pq = *p;
                *usm_params_field(&pq, &usm_param_table[j]) = pj + shift[q] * hh[pass];
                if (m->axisymmetric_stator && strcmp(pname, "I_xx") == 0)
                    pq.I_yy = pq.I_xx;
                solved = outputs_at(sens, st, &pq, sol.u, pass, y[pass][q]) == 0;
            }
        }
        if (!solved) {
            CHECK(0, "%s %s: no solution at %s +- h", m->name, what, pname);
            continue;
        }
        for (int k = 0; k < USM_SENS_COUNT; ++k) {
            if (!r.defined[k])
                continue;
            const int pass = k == USM_SENS_MAX_MODULUS;
            /* fourth-order central difference */
            const double fd = (8 * (y[pass][0][k] - y[pass][1][k]) -
                               (y[pass][2][k] - y[pass][3][k])) / (12 * hh[pass]);
            const double floor = (pass ? FLOOR_MOD : FLOOR) * fabs(r.value[k]) / fabs(pj);
            const double bound = TOL * fabs(fd) + floor;
            const double err = fabs(r.d[k][j] - fd);
            if (err / bound > worst)
                worst = err / bound;
            CHECK(err <= bound, "%s %s: d %s / d %s = %.12g, finite differences %.12g (rel %.2e)",
                  m->name, what, usm_sensitivity_output_name(k), pname, r.d[k][j], fd,
                  err / fabs(fd));
        }
    }
    return 1;
}

/* Where two distinct multipliers exchange the largest modulus, max_modulus has
 * a kink and no derivative: the 4dof model near f = 36917.5 Hz, where a real
 * multiplier overtakes a complex pair (found by a scan of f).  Bisect on which
 * one is largest (the sign of its imaginary part) to 1e-6 Hz, then the
 * derivative there must be reported undefined, and 1 Hz away defined. */
static void check_kink(void)
{
    const usm_model *m = usm_model_find("4dof");
    usm_steady *st = usm_steady_alloc(m);
    usm_sensitivity *sens = usm_sensitivity_alloc(m);
    usm_sensitivity_result r;
    usm_params p;
    usm_params_default(&p);
    double lo = 36917.0, hi = 36918.0; /* complex pair largest at lo, real at hi */
    int side[2];
    for (int k = 0; k < 2; ++k) {
        p.f = k ? hi : lo;
        CHECK(usm_steady_solve(st, &p, NULL) == USM_OK &&
                  usm_sensitivity_compute(sens, &p, usm_steady_root(st, 0), 1, &r) == USM_OK,
              "kink: solve at f = %g", p.f);
        side[k] = r.multiplier_im != 0;
        CHECK(r.defined[USM_SENS_MAX_MODULUS], "kink: undefined 0.5 Hz away at f = %g: %s", p.f,
              r.why[USM_SENS_MAX_MODULUS]);
    }
    CHECK(side[0] && !side[1], "kink: no exchange of the largest multiplier in [%g, %g]", lo, hi);
    while (hi - lo > 1e-6) {
        p.f = 0.5 * (lo + hi);
        if (usm_steady_solve(st, &p, NULL) != USM_OK)
            break;
        usm_sensitivity_compute(sens, &p, usm_steady_root(st, 0), 1, &r);
        if ((r.multiplier_im != 0) == side[0])
            lo = p.f;
        else
            hi = p.f;
    }
    p.f = 0.5 * (lo + hi);
    CHECK(usm_steady_solve(st, &p, NULL) == USM_OK &&
              usm_sensitivity_compute(sens, &p, usm_steady_root(st, 0), 1, &r) == USM_OK,
          "kink: solve at the crossing");
    CHECK(!r.defined[USM_SENS_MAX_MODULUS] &&
              strstr(r.why[USM_SENS_MAX_MODULUS], "equal modulus") != NULL,
          "kink: at f = %.7f the derivative is not reported undefined (%s)", p.f,
          r.why[USM_SENS_MAX_MODULUS]);
    CHECK(r.defined[USM_SENS_ROTOR_SPEED], "kink: the stationary outputs stay defined");
    printf("4dof: max_modulus kink at f = %.7f Hz reported: %s\n", p.f,
           r.why[USM_SENS_MAX_MODULUS]);
    usm_sensitivity_free(sens);
    usm_steady_free(st);
}

int main(void)
{
    gsl_set_error_handler_off();
    check_kink();
    const char *names[] = {"3dof", "4dof", "3dof_twist_integrated", "4dof_twist_integrated"};
    for (size_t k = 0; k < sizeof names / sizeof names[0]; ++k) {
        const usm_model *m = usm_model_find(names[k]);
        CHECK(m != NULL, "model %s missing", names[k]);
        if (!m)
            continue;
        usm_steady *st = usm_steady_alloc(m);
        usm_sensitivity *sens = usm_sensitivity_alloc(m);
        usm_floquet *fl = usm_floquet_alloc(m);
        usm_params p;
        usm_params_default(&p);
        CHECK(check_point(m, st, sens, fl, &p, "paper"), "%s: no solution at the paper's point",
              m->name);
        const int nrandom = m->t0_independent ? 0 : NRANDOM;
        uint64_t rng = 0x5e5e17ULL + k;
        int done = 0, tries = 0;
        char what[64];
        while (done < nrandom && tries < 20 * NRANDOM) {
            random_params(&rng, &p);
            snprintf(what, sizeof what, "random point %d", tries++);
            done += check_point(m, st, sens, fl, &p, what);
        }
        CHECK(done == nrandom, "%s: only %d of %d random points solved", m->name, done, nrandom);
        printf("%s: derivatives checked at the paper's point and %d random points\n", m->name,
               done);
        usm_floquet_free(fl);
        usm_sensitivity_free(sens);
        usm_steady_free(st);
    }
    printf("worst |d - fd| / (1e-5 |fd| + floor) = %.3g; max_modulus against usm_floquet_compute "
           "%.2g\n", worst, worst_modulus);
    if (failures)
        printf("%d failures\n", failures);
    return failures != 0;
}
