/* The largest Lyapunov exponent of the event-driven motion
 * (usm_hybrid_lyapunov: tangent vectors through the saltation matrices,
 * renormalised every period).
 *
 * Independent truth: on a stable periodic orbit with separation the
 * exponent is ln(max |lambda|) / T, the multipliers those of the shooting
 * solver's monodromy (usm_hybrid_solve: Newton's converged orbit, the
 * eigenvalues of the product of the flows' and the saltation matrices,
 * cyclic multipliers left out).  The two share the kernels and the saltation
 * formula but not the computation: one eigenvalue of one period's monodromy
 * against the growth of a vector over many periods of a free run.  Three
 * orbits: 3-DOF phase error 0.6 rad, 4-DOF mode split 2.5 % and 4-DOF phase
 * error 0.5 rad (orbits with two separations and two landings a period).
 *
 * And on the irregular bouncing of the 4-DOF motor at 5 % mode split (no
 * orbit with a closed phase from 3.6 %): the exponent is positive, and
 * halving the integration tolerance moves it by less than its spread over
 * a finite run (a chaotic run's trajectory itself changes with the
 * tolerance; its exponent must not). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "bouncing.h"
#include "check.h"
#include "usm.h"
#include "usm_periodic.h"
#include "usm_simulate.h"

static void check_orbit(const char *name, const char *par, double value)
{
    const usm_model *m = usm_model_find(name);
    usm_hybrid *h = usm_hybrid_alloc(m);
    usm_params p;
    usm_hybrid_result r;
    usm_params_default(&p);
    usm_params_set(&p, par, value, NULL);
    int rc = usm_hybrid_solve(h, &p, NULL, &r);
    if (!CHECK(rc == USM_OK && r.converged && r.floquet.stable, "%s %s = %g: no stable orbit: %s",
               name, par, value, usm_hybrid_message(h))) {
        usm_hybrid_free(h);
        return;
    }
    /* the dominant multiplier */
    int k0 = -1;
    for (int k = 0; k < r.floquet.n; ++k)
        if (!r.floquet.cyclic[k] && k0 < 0)
            k0 = k;
    const double want = log(r.floquet.max_modulus) / r.period;
    usm_hybrid_lyapunov_result ly;
    CHECK(usm_hybrid_set(h, &p, 1e-10) == USM_OK, "set: %s", usm_hybrid_message(h));
    rc = usm_hybrid_lyapunov(h, r.t0, 0, r.x0, 200, 60, &ly);
    printf("%s %s = %g: %s, max |lambda| %.9f (%.6f%+.6fi), ln/T %.6f 1/s; exponents %.6f %.6f "
           "1/s over %ld periods (%ld impacts)\n",
           name, par, value, r.mode_sequence, r.floquet.max_modulus, r.floquet.re[k0],
           r.floquet.im[k0], want, ly.exponents[0], ly.exponents[1], ly.periods, ly.impacts);
    CHECK(rc == USM_OK, "lyapunov failed: %s", usm_hybrid_message(h));
    CHECK(fabs(ly.exponents[0] - want) <= 1e-3 * fabs(want), "exponent %.9g, want %.9g (%.2e rel)",
          ly.exponents[0], want, fabs(ly.exponents[0] / want - 1));
    usm_hybrid_free(h);
}

static void check_chaotic(void)
{
    const usm_model *m;
    usm_params p;
    bouncing_state l;
    if (!bouncing_settle(&m, &p, &l))
        return;
    usm_hybrid *h = usm_hybrid_alloc(m);
    double lam[2];
    for (int k = 0; k < 2; ++k) {
        usm_hybrid_lyapunov_result ly;
        CHECK(usm_hybrid_set(h, &p, k ? 5e-9 : 1e-8) == USM_OK, "set: %s", usm_hybrid_message(h));
        const int rc = usm_hybrid_lyapunov(h, l.t, l.open, l.y, 20, 200, &ly);
        CHECK(rc == USM_OK, "chaotic lyapunov: %s", usm_hybrid_message(h));
        lam[k] = ly.exponents[0];
        printf("4-DOF mode split 5 %%, rtol %g: exponent %.1f 1/s (lambda T %.4f), %ld impacts\n",
               k ? 5e-9 : 1e-8, lam[k], lam[k] / p.f, ly.impacts);
    }
    CHECK(lam[0] > 0 && lam[1] > 0, "not positive: %g %g", lam[0], lam[1]);
    CHECK(fabs(lam[1] - lam[0]) <= 0.2 * fabs(lam[0]), "halving rtol moved it by %.1f %%",
          100 * fabs(lam[1] / lam[0] - 1));
    usm_hybrid_free(h);
}

int main(void)
{
    check_chaotic();
    check_orbit("3dof_imperfect_unilateral", "phase_error", 0.6);
    check_orbit("4dof_imperfect_unilateral", "mode_split", 0.025);
    check_orbit("4dof_imperfect_unilateral", "phase_error", 0.5);
    printf("%s: %d failures\n", __FILE__, failures);
    return failures != 0;
}
