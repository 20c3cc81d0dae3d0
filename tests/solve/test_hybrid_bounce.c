/* Orbits with bouncing (e_impact > 0, docs/unilateral.md "Bouncing").
 *
 * At e_impact > 0 every impact throws the rotor off again (gap'+ = -e
 * gap'-), so a contact that closes again does so only at the end of an
 * accumulation of ever shorter bounces (Zeno).  usm_hybrid_solve refuses
 * such an orbit with a message ("chattering") instead of Newton stalling on
 * a period map whose number of bounces jumps; an orbit of impacts only (no
 * closed phase) is refused as well (its section would lie in the open mode).
 *
 * Independent truth: Newton's law alone.  Under a relative acceleration that
 * changes little over a bounce, each bounce returns at the speed it left
 * with, so the approach velocities fall as v0 e^k and the landing rule (a
 * rebound slower than v_land lands) cuts them after n rebounds with
 * e^(n+1) v0 <= v_land < e^n v0; the simulation (simulate.c, no shooting)
 * shows the accumulation too: several impacts per separation. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "usm.h"
#include "usm_periodic.h"
#include "usm_simulate.h"

#define PI 3.14159265358979323846

static void sim(const char *name, const usm_params *p, int periods, usm_sim_summary *sum)
{
    usm_sim *s = usm_sim_alloc(usm_model_find(name));
    usm_sim_options o;
    usm_sim_options_default(&o);
    o.duration = periods / p->f;
    o.rate = 0;
    const int rc = usm_sim_run(s, p, &o, NULL, sum);
    CHECK(rc == USM_OK, "%s: run failed: %s", name, usm_sim_message(s));
    usm_sim_free(s);
}

/* A chattering orbit: 4-DOF, phase error 35 deg (the orbit at e_impact = 0
 * has two separations and two landings a period). */
static void check_chattering(double e)
{
    const char *name = "4dof_imperfect_unilateral";
    usm_hybrid *h = usm_hybrid_alloc(usm_model_find(name));
    usm_params p;
    usm_hybrid_result r;
    usm_params_default(&p);
    usm_params_set(&p, "phase_error", 35 * PI / 180, NULL);
    usm_params_set(&p, "e_impact", e, NULL);
    const int rc = usm_hybrid_solve(h, &p, NULL, &r);
    const char *msg = usm_hybrid_message(h);
    printf("e_impact = %g: rc %d, %s\n", e, rc, msg);
    int n = -1;
    double v0 = NAN, vl = NAN, t = NAN, ee = NAN;
    if (CHECK(rc == USM_EFAILED && !r.converged && strstr(msg, "chattering"),
              "e_impact = %g: a landing after rebounds not refused", e) &&
        CHECK(sscanf(msg, "chattering at e_impact = %lf: the bounces accumulate (Zeno: %d "
                          "rebounds from %lf m/s, landing at t = %lf s below v_land = %lf",
                     &ee, &n, &v0, &t, &vl) == 5,
              "message not parsed: %s", msg)) {
        /* the geometric series: n = floor(log(v_land / v0) / log(e)), +-1
         * for the stator's motion during the bounces (measured: equal at
         * e = 0.3 (8.44) and 0.5 (13.68)) */
        const double nexp = log(vl / v0) / log(e);
        printf("  %d rebounds, geometric series %.3f\n", n, nexp);
        CHECK(fabs(ee - e) < 1e-12 && n >= 1 && abs(n - (int)floor(nexp)) <= 1,
              "e_impact = %g: %d rebounds from %g m/s to v_land %g, the series gives %.3f", e,
              n, v0, vl, nexp);
    }
    /* the simulation: the accumulations (cut at the simulation's own v_land,
     * rtol 1e-8) give several impacts per separation */
    usm_sim_summary sum;
    sim(name, &p, 40, &sum);
    printf("  simulation, 40 periods: %ld separations, %ld impacts\n", sum.separations,
           sum.impacts);
    CHECK(sum.separations > 0 && sum.impacts >= 3 * sum.separations,
          "e_impact = %g: no accumulation in the simulation (%ld impacts, %ld separations)", e,
          sum.impacts, sum.separations);
    usm_hybrid_free(h);
}

/* Bouncing without landing: 4-DOF, 35 deg, e_impact = 0.8: the simulation
 * settles open all the time (impacts only); the solve says so. */
static void check_impacts_only(void)
{
    const char *name = "4dof_imperfect_unilateral";
    usm_hybrid *h = usm_hybrid_alloc(usm_model_find(name));
    usm_params p;
    usm_hybrid_result r;
    usm_params_default(&p);
    usm_params_set(&p, "phase_error", 35 * PI / 180, NULL);
    usm_params_set(&p, "e_impact", 0.8, NULL);
    const int rc = usm_hybrid_solve(h, &p, NULL, &r);
    const char *msg = usm_hybrid_message(h);
    printf("e_impact = 0.8: rc %d, %s\n", rc, msg);
    CHECK(rc == USM_EFAILED && strstr(msg, "without landing"),
          "e_impact = 0.8: an orbit of impacts only not refused: %s", msg);
    usm_sim_summary sum;
    sim(name, &p, 200, &sum);
    printf("  simulation, 200 periods: open at the end %.12f, %ld impacts\n",
           sum.open_fraction_end, sum.impacts);
    /* measured: 1 - 6e-14 */
    CHECK(fabs(sum.open_fraction_end - 1) < 1e-9 && sum.impacts > 0,
          "e_impact = 0.8: the simulation lands (open %.12f)", sum.open_fraction_end);
    usm_hybrid_free(h);
}

/* No rebound, no refusal: at e_impact = 0 (a touch the closed mode would
 * pull off keeps the contact open: no rebound either) and at 1e-5 (the
 * rebound, 8.7e-8 m/s, slower than v_land: it lands at once) the orbit is
 * computed, and the two agree to O(e_impact) (measured 1.9e-6 relative in
 * the speed). */
static void check_no_rebound(void)
{
    const char *name = "4dof_imperfect_unilateral";
    usm_hybrid *h = usm_hybrid_alloc(usm_model_find(name));
    usm_params p;
    usm_hybrid_result r0, r1;
    usm_params_default(&p);
    usm_params_set(&p, "phase_error", 35 * PI / 180, NULL);
    int ok = usm_hybrid_solve(h, &p, NULL, &r0) == USM_OK;
    CHECK(ok, "e_impact = 0: %s", usm_hybrid_message(h));
    usm_params_set(&p, "e_impact", 1e-5, NULL);
    const int ok1 = usm_hybrid_solve(h, &p, NULL, &r1) == USM_OK;
    CHECK(ok1, "e_impact = 1e-5: %s", usm_hybrid_message(h));
    if (ok && ok1) {
        const double d = fabs(r1.rotor_speed_mean / r0.rotor_speed_mean - 1);
        printf("e_impact = 0 and 1e-5: %s, %s, speeds %.9f and %.9f (%.3g)\n", r0.mode_sequence,
               r1.mode_sequence, r0.rotor_speed_mean, r1.rotor_speed_mean, d);
        CHECK(strcmp(r0.mode_sequence, r1.mode_sequence) == 0 && d < 1e-4,
              "e_impact = 1e-5 is not the e_impact = 0 orbit (%.3g)", d);
    }
    usm_hybrid_free(h);
}

int main(void)
{
    check_no_rebound();
    check_chattering(0.3);
    check_chattering(0.5);
    check_impacts_only();
    printf("%s: %d failures\n", __FILE__, failures);
    return failures != 0;
}
