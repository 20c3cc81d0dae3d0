/* The squeal study's quasi-periodic case (usm_squeal_run): its second
 * frequency is the Neimark-Sacker angle's near the onset.
 *
 * Independent truth: the Floquet multipliers of the periodic orbit (the
 * shooting solver of runtime/solve/periodic.c, continued in the preload from
 * the ideal motor's stationary start) at the 4-DOF motor with 2.5 % mode
 * split: its critical pair crosses the unit circle at F0 = 0.99995 N with
 * the contact closed (F_n_min 0.88 N), and at F0 = 1.0 N, just past it
 * (|lambda| 1.0101), its angle gives 2863 Hz.  The event-driven runs there
 * (the unilateral model, whose contact then stays closed) settle on the
 * torus born at that crossing: motion "quasi_periodic" with a second
 * frequency within one bin (f / window) of angle f / (2 pi). */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "check.h"
#include "usm.h"
#include "usm_periodic.h"
#include "usm_squeal_study.h"

int main(void)
{
    const clock_t c0 = clock();
    /* the orbit's critical pair at F0 = 1.0 N, continued from 0.8 N */
    const usm_model *mb = usm_model_find("4dof_imperfect");
    usm_periodic *w = usm_periodic_alloc(mb);
    usm_params p;
    usm_params_default(&p);
    p.mode_split = 0.025;
    static const double F[] = {0.8, 0.95, 0.99, 0.997, 0.999, 0.9997, 1.0};
    double x0[USM_MAX_NX];
    usm_periodic_result r;
    int ok = 1;
    for (size_t i = 0; i < sizeof F / sizeof F[0] && ok; ++i) {
        p.F0 = F[i];
        ok = usm_periodic_solve(w, &p, i ? x0 : NULL, NULL, &r) == USM_OK && r.converged;
        memcpy(x0, r.x0, sizeof x0);
    }
    if (!CHECK(ok, "no orbit at F0 = %g: %s", p.F0, usm_periodic_message(w)))
        return 1;
    usm_periodic_free(w);
    double angle = NAN;
    for (int k = 0; k < r.floquet.n; ++k)
        if (hypot(r.floquet.re[k], r.floquet.im[k]) == r.floquet.max_modulus)
            angle = atan2(fabs(r.floquet.im[k]), r.floquet.re[k]);
    const double want = angle * p.f / (2.0 * 3.14159265358979323846);
    printf("orbit at F0 = 1.0 N: max |lambda| %.6f, F_n_min %.3f N, angle %.6f rad -> %.2f Hz\n",
           r.floquet.max_modulus, r.F_n_min, angle, want);
    CHECK(r.floquet.max_modulus > 1.0 && r.floquet.max_modulus < 1.02 && r.F_n_min > 0.5,
          "not just past a crossing with the contact closed");
    /* the study: from rest at 1.0002 N, then on to 1.0 N from there */
    const usm_model *m = usm_model_find("4dof_imperfect_unilateral");
    usm_squeal_study *s = usm_squeal_alloc(m);
    usm_squeal_options o;
    usm_squeal_options_default(&o);
    o.over = "F0";
    o.from = 1.0002;
    o.to = 1.0;
    o.points = 2;
    o.settle = 600;
    o.window = 512;
    o.lyapunov_skip = 150; /* the tangent vectors turn into the torus first */
    o.lyapunov_periods = 50;
    o.check_rest = 0;
    o.origin = 0;
    o.power_periods = 0;
    p.F0 = 1.0;
    CHECK(usm_squeal_run(s, &p, &o) == USM_OK, "study: %s", usm_squeal_message(s));
    const usm_squeal_point *pt = usm_squeal_point_at(s, 1);
    if (CHECK(pt != NULL, "no point")) {
        printf("study at F0 = %.4f N: %s, second frequency %.2f Hz (bin %.1f Hz), lambda T %.5f, "
               "open fraction %g\n", pt->value, usm_motion_name(pt->motion),
               pt->second_frequency, pt->df, pt->lyapunov_per_period, pt->open_fraction);
        CHECK(pt->motion == USM_MOTION_QUASI_PERIODIC, "motion %s", usm_motion_name(pt->motion));
        CHECK(fabs(pt->second_frequency - want) <= pt->df, "second frequency %.2f Hz, the "
              "Neimark-Sacker angle's %.2f Hz (bin %.1f Hz)", pt->second_frequency, want, pt->df);
        CHECK(pt->open_fraction == 0.0, "the contact opened (%g)", pt->open_fraction);
    }
    usm_squeal_free(s);
    printf("%.2f s CPU\n%s: %d failures\n", (double)(clock() - c0) / CLOCKS_PER_SEC, __FILE__,
           failures);
    return failures != 0;
}
