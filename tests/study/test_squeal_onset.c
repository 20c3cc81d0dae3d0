/* The onset of the irregular motion located, and its sensitivity to a
 * design parameter (usm_squeal_locate_onset, usm_squeal_onset_sensitivities).
 *
 * Independent truth: (1) the squeal study's own change of motion on the
 * 3-DOF phase error (period 1 at 0.91 rad, chaotic at 0.92: docs/squeal.md)
 * brackets the located end of the stable orbit; (2) the central difference
 * of the onset in the preload F0 (at F0 (1 +- 1e-3)) predicts the onset
 * relocated directly at a preload shifted by another amount (+0.5 %), to
 * 1e-4 of the onset: the linearisation and a second location agree, which
 * a located value wandering with the start (noise) or a derivative of
 * another parameter would not. */
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
    const usm_model *m = usm_model_find("3dof_imperfect_unilateral");
    usm_params p;
    usm_params_default(&p);
    usm_params_set(&p, "phase_error", 0.91, NULL);
    usm_hybrid *h = usm_hybrid_alloc(m);
    usm_hybrid_result r;
    const int rc = usm_hybrid_solve(h, &p, NULL, &r);
    usm_hybrid_free(h);
    if (!CHECK(rc == USM_OK && r.converged && r.floquet.stable, "no stable orbit at 0.91 rad"))
        return 1;
    static const char *const names[] = {"F0"};
    usm_squeal_onset o;
    CHECK(usm_squeal_onset_sensitivities(m, &p, "phase_error", 0.91, 0.92, r.t0, r.x0, names, 1,
                                         1e-3, 1e-5, &o) == USM_OK && o.found,
          "onset: %s", o.message);
    printf("onset %.9f rad (%s; last orbit %.9f, closed fraction %.4f), %d solves; d onset / d F0 "
           "= %.6g rad/N, elasticity %.4f\n", o.value, o.kind, o.last_orbit, o.closed_fraction,
           o.solves, o.sens[0].d_onset, o.sens[0].elasticity);
    CHECK(o.value > 0.91 && o.value < 0.92, "the onset %.9g lies outside the study's change "
          "(0.91, 0.92)", o.value);
    CHECK(strcmp(o.kind, "branch_end") == 0 && o.nsens == 1 && isfinite(o.sens[0].d_onset) &&
          strcmp(o.most_sensitive, "F0") == 0, "kind %s, %d sensitivities", o.kind, o.nsens);
    /* a second location at a preload shifted by 0.5 % */
    const double dF = 0.005 * p.F0;
    usm_params q = p;
    q.F0 += dF;
    usm_squeal_onset o2;
    CHECK(usm_squeal_locate_onset(m, &q, "phase_error", 0.91, 0.92, r.t0, r.x0, 1e-5, &o2) ==
              USM_OK && o2.found, "shifted onset: %s", o2.message);
    const double want = o.value + o.sens[0].d_onset * dF;
    printf("at F0 + 0.5 %%: onset %.9f rad located, %.9f predicted (%.2e relative)\n", o2.value,
           want, fabs(o2.value - want) / o.value);
    CHECK(fabs(o2.value - want) <= 1e-4 * o.value, "located %.9g, predicted %.9g", o2.value,
          want);
    /* bad input: one message naming the field */
    static const char *const bad[] = {"no_such"};
    CHECK(usm_squeal_onset_sensitivities(m, &p, "phase_error", 0.91, 0.92, r.t0, r.x0, bad, 1,
                                         1e-3, 1e-6, &o) == USM_EINPUT &&
              strncmp(o.message, "names:", 6) == 0, "unknown name: %s", o.message);
    CHECK(usm_squeal_locate_onset(m, &p, "phase_error", 0.91, 0.91, r.t0, r.x0, 1e-6, &o) ==
              USM_EINPUT, "value == toward accepted");
    printf("%.2f s CPU\n%s: %d failures\n", (double)(clock() - c0) / CLOCKS_PER_SEC, __FILE__,
           failures);
    return failures != 0;
}
