/* The start at rest and the start threshold (usm_operating_point.h).
 *
 * A motor at rest has no tilt: the start-up from rest must not depend on the
 * start tilt as long as it lies below every unstable root, and the threshold
 * in the preload F0 above which the motor does not start must be where the
 * preload's moment at theta = 0 exceeds the excitation's reach: the tilt_zero
 * condition, where the smallest root is born at theta = 0.  Its closed form,
 * from the moment balance of the stator at theta = 0 (tests/study/sweep_tilt_zero.py
 * derives it with sympy): m0 cos(alpha) = R F0, m0 sin(alpha) = H T / R, so
 *     F0* = sqrt(m0^2 - (H T / R)^2) / R.
 *
 * 1. The verdict does not depend on the start tilt: at five points across the
 *    threshold (F0 = 0.99, 0.999, 1.001, 1.01, 1.1 N; 3-DOF, f = 38 kHz)
 *    every point is simulated from 1e-1, 1e-2 and 1e-3 of the smallest
 *    unstable root's tilt (of the only root's below the threshold, where no
 *    root is unstable): one verdict per point, the motor starting below
 *    F0* and not above.
 * 2. The threshold found by the start-up verdict alone lies within 1e-3
 *    (relative) of the closed form at three loads (T = 0, the paper's
 *    6.46e-5 and 2.5e-4 N m): the motor starts from rest at (1 - 1e-3) F0*
 *    and does not at (1 + 1e-3) F0*; three bisection steps in F0 between
 *    them give the measured threshold (starts from 1e-1 of the smallest
 *    unstable tilt: near the threshold 1e-2 of it lies below 1e-10 rad).  The library's start margin
 *    (usm_op_start_margin, from the model's stationary equations at
 *    theta = 0) changes sign at F0* within 1e-9.  Under larger loads the
 *    threshold moves above F0* (docs/operating-point.md): the load's moment
 *    H T / R at right angles to the tilt pumps the wobble near the axis
 *    (3-DOF, T = 1 mN m: the motor starts at 1.005 F0*).
 * Prints the measurements.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <gsl/gsl_errno.h>

#include "usm.h"
#include "usm_operating_point.h"
#include "usm_simulate.h"

#include "check.h"

/* The verdict of a start-up from rest at F0 (every point simulated): 1 the
 * motor starts (reached a stable root), 0 it does not, -1 undecided.  tilt:
 * the start tilt (0: the library's start at rest; < 0: -tilt times *th_ref);
 * *th_ref: the smallest
 * unstable root's tilt (the only root's when none is unstable). */
static int verdict(const usm_model *m, usm_params p, double tilt, double *th_ref,
                   usm_op_result *r)
{
    usm_steady *s = usm_steady_alloc(m);
    usm_floquet *f = usm_floquet_alloc(m);
    usm_floquet_result fl[16];
    int v = -1;
    if (!s || !f || usm_steady_solve(s, &p, NULL) != USM_OK || usm_steady_count(s) > 16 ||
        usm_floquet_roots(f, &p, s, 0.0, NULL, fl) != USM_OK)
        goto done;
    *th_ref = usm_steady_root(s, 0)->theta;
    for (size_t k = usm_steady_count(s); k-- > 0;)
        if (!fl[k].stable)
            *th_ref = usm_steady_root(s, k)->theta;
    usm_op_options o;
    usm_op_options_default(&o);
    o.from_rest = USM_OP_FROM_REST_ALWAYS;
    o.sim.tilt0 = tilt < 0 ? -tilt * *th_ref : tilt;
    if (usm_operating_point(m, &p, s, fl, &o, r) != USM_OK)
        goto done;
    v = r->reason == USM_OP_REACHED_FROM_REST ? 1 : r->reason == USM_OP_DOES_NOT_START ? 0 : -1;
done:
    usm_floquet_free(f);
    usm_steady_free(s);
    return v;
}

static double closed_form(const usm_params *p)
{
    const double ht = p->H * p->T / p->R;
    return sqrt(p->m0 * p->m0 - ht * ht) / p->R;
}

static void independence(const usm_model *m)
{
    const double F0[5] = {0.99, 0.999, 1.001, 1.01, 1.1};
    const double frac[3] = {1e-1, 1e-2, 1e-3};
    printf("start tilt independence (3dof, f = 38 kHz, T = default):\n");
    for (int i = 0; i < 5; ++i) {
        usm_params p;
        usm_params_default(&p);
        p.f = 38000;
        p.F0 = F0[i];
        const int want = F0[i] < closed_form(&p);
        double th = 0;
        usm_op_result r;
        int v0 = verdict(m, p, 0.0, &th, &r);
        printf("  F0 %.4g: at rest (%s): %s\n", F0[i], r.sim.start_message,
               usm_op_reason_name(r.reason));
        CHECK(v0 == want, "F0 %g at rest: verdict %d, want %d (%s)", F0[i], v0, want, r.message);
        for (int j = 0; j < 3; ++j) {
            double th2;
            int v = verdict(m, p, frac[j] * th, &th2, &r);
            printf("    from %g of %.4g rad: %s, %ld steps, %.2f s\n", frac[j], th,
                   usm_op_reason_name(r.reason), r.sim.steps, r.wall);
            CHECK(v == want, "F0 %g from %g of %.4g rad: verdict %d, want %d (%s)", F0[i],
                  frac[j], th, v, want, r.message);
        }
    }
}

static void threshold(const usm_model *m, double T)
{
    usm_params p;
    usm_params_default(&p);
    p.f = 38000;
    p.T = T;
    const double want = closed_form(&p);
    double lo = (1 - 1e-3) * want, hi = (1 + 1e-3) * want, th;
    usm_op_result r;
    /* from 1e-1 of the smallest unstable tilt (part 1: the verdict does not
     * depend on it): close to the threshold that tilt is 1e-8 rad and less,
     * and 1e-2 of it costs more than CVODES' steps per period */
    p.F0 = lo;
    const int vlo = verdict(m, p, -0.1, &th, &r);
    p.F0 = hi;
    const int vhi = verdict(m, p, -0.1, &th, &r);
    if (!CHECK(vlo == 1 && vhi == 0, "T %g: the verdicts at the bracket's ends are %d, %d", T,
               vlo, vhi))
        return;
    for (int it = 0; it < 3; ++it) {
        p.F0 = 0.5 * (lo + hi);
        const int v = verdict(m, p, -0.1, &th, &r);
        if (!CHECK(v >= 0, "T %g F0 %.10g: undecided (%s)", T, p.F0, r.message))
            return;
        *(v ? &lo : &hi) = p.F0;
    }
    const double found = 0.5 * (lo + hi);
    /* the library's start margin is zero at the threshold */
    double mlo, mhi;
    p.F0 = want * (1 - 1e-9);
    const int okl = usm_op_start_margin(m, &p, &mlo) == USM_OK;
    p.F0 = want * (1 + 1e-9);
    const int okh = usm_op_start_margin(m, &p, &mhi) == USM_OK;
    printf("T = %g N m: start threshold by the start-up verdict F0 = %.6f N (bracket [%.6f, "
           "%.6f]), tilt_zero closed form %.6f N, relative difference %.2e; start margin "
           "%.3g / %.3g at 1 -+ 1e-9 of it\n",
           T, found, lo, hi, want, found / want - 1, mlo, mhi);
    CHECK(fabs(found / want - 1) < 1e-3, "T %g: threshold %.8g against the closed form %.8g", T,
          found, want);
    CHECK(okl && okh && mlo > 0 && mhi < 0 && fabs(mlo) < 1e-8 && fabs(mhi) < 1e-8,
          "T %g: the start margin does not change sign at the closed form (%g, %g)", T, mlo,
          mhi);
}

int main(void)
{
    gsl_set_error_handler_off();
    const usm_model *m = usm_model_find("3dof");
    independence(m);
    threshold(m, 0.0);
    threshold(m, 6.46e-5);
    threshold(m, 2.5e-4);
    printf("%d failures\n", failures);
    return failures != 0;
}
