/* sweep --periodic past a fold early in a grid step (docs/unilateral.md "Continuation past contact loss").
 *
 * 4-DOF, mode split swept down 2.06, 1.93, 1.80 %: the stable orbit with
 * separation found at 2.06 % (the second of the hysteresis) ends at a fold
 * near 1.915 %, 11 % into the step 1.93 -> 1.80 %; Newton from the secant
 * prediction lands on the other branch's orbit, whose speed and separation
 * fraction are no farther from the last orbit than 2.7 and 1.8 times the
 * last step's change (before: passed silently, the substep paths agreeing
 * on that orbit).  The sweep must say so: one branch_switch with
 * branch_lost, its last orbit at 1.93 %.
 *
 * Independent truth (simulations, no shooting): at 1.93 % two attractors
 * coexist, a run started on the sweep's 1.93 % orbit stays on it (mean speed
 * to 1e-6 relative) and one started from the 1.80 % orbit's state settles
 * elsewhere (more than 1e-3 away): the two are different orbits, which no
 * continuation joins within the step; at 1.80 % a run started on the 1.93 %
 * orbit's state settles on the sweep's 1.80 % orbit (the 1.93 % one's branch
 * no longer exists there). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "usm.h"
#include "usm_periodic.h"
#include "usm_periodic_sweep.h"
#include "usm_simulate.h"

static const char *NAME = "4dof_imperfect_unilateral";

/* the last period's mean rotor speed of a run from (t0, x0) over `periods` */
static double settle_from(const usm_params *p, double t0, const double *x0, int periods)
{
    const usm_model *m = usm_model_find(NAME);
    usm_sim *s = usm_sim_alloc(m);
    usm_sim_options o;
    usm_sim_summary sum;
    usm_sim_options_default(&o);
    o.duration = periods / p->f;
    o.rate = 0;
    o.start = USM_SIM_FROM_STATE;
    o.t0 = t0;
    memcpy(o.x0, x0, sizeof(double) * (size_t)m->nx);
    const int rc = usm_sim_run(s, p, &o, NULL, &sum);
    CHECK(rc == USM_OK, "run failed: %s", usm_sim_message(s));
    usm_sim_free(s);
    return sum.rotor_speed_avg_end;
}

int main(void)
{
    usm_params p;
    usm_params_default(&p);
    usm_periodic_sweep *sw = usm_periodic_sweep_alloc(usm_model_find(NAME));
    usm_periodic_sweep_options o;
    usm_periodic_sweep_options_default(&o);
    o.over = "mode_split";
    o.from = 0.0206;
    o.to = 0.0180;
    o.points = 3;
    if (!CHECK(usm_periodic_sweep_run(sw, &p, &o) == USM_OK, "sweep: %s",
               usm_periodic_sweep_message(sw))) {
        usm_periodic_sweep_free(sw);
        return 1;
    }
    const usm_periodic_event *e = NULL;
    int switches = 0;
    for (size_t i = 0; i < usm_periodic_sweep_event_count(sw); ++i) {
        const usm_periodic_event *ei = usm_periodic_sweep_event_at(sw, i);
        printf("event %s at %.6g: %s\n", usm_pevent_name(ei->type), ei->value, ei->what);
        if (ei->type == USM_PEVENT_BRANCH_SWITCH && switches++ == 0)
            e = ei;
    }
    for (size_t i = 0; i < usm_periodic_sweep_count(sw); ++i) {
        const usm_periodic_point *pt = usm_periodic_sweep_point_at(sw, i);
        printf("mode split %.4f: %s speed %.9f 1/s, open %.6f, max |lambda| %.4f%s\n", pt->value,
               pt->hybrid.mode_sequence, pt->hybrid.rotor_speed_mean,
               pt->hybrid.separation_fraction, pt->hybrid.floquet.max_modulus,
               pt->switched ? " (switched)" : "");
        CHECK(pt->separating, "mode split %g: no orbit with separation", pt->value);
    }
    if (CHECK(e && switches == 1 && e->has_hybrid && e->branch_lost,
              "%d branch switches (branch_lost %d): the fold passed silently", switches,
              e ? e->branch_lost : -1) &&
        CHECK(usm_periodic_sweep_count(sw) == 3, "points")) {
        const usm_periodic_point *p1 = usm_periodic_sweep_point_at(sw, 1);
        const usm_periodic_point *p2 = usm_periodic_sweep_point_at(sw, 2);
        CHECK(fabs(e->value - 0.018) < 1e-12 && fabs(e->branch_last - 0.0193) < 1e-12 &&
                  p2->switched,
              "switch at %g, last orbit at %g", e->value, e->branch_last);
        /* the event's orbits are the points' */
        CHECK(e->hybrid_left.rotor_speed_mean == p1->hybrid.rotor_speed_mean &&
                  e->hybrid.rotor_speed_mean == p2->hybrid.rotor_speed_mean,
              "the event's orbits are not the points'");
        usm_params q = p;
        q.mode_split = 0.0193;
        const double w_stay = settle_from(&q, p1->hybrid.t0, p1->hybrid.x0, 300);
        const double w_other = settle_from(&q, p2->hybrid.t0, p2->hybrid.x0, 300);
        q.mode_split = 0.018;
        const double w_low = settle_from(&q, p1->hybrid.t0, p1->hybrid.x0, 300);
        const double w1 = p1->hybrid.rotor_speed_mean, w2 = p2->hybrid.rotor_speed_mean;
        printf("simulations: at 1.93 %% from its orbit %.9f (orbit %.9f), from the 1.80 %% orbit "
               "%.9f; at 1.80 %% from the 1.93 %% orbit %.9f (orbit %.9f)\n", w_stay, w1,
               w_other, w_low, w2);
        /* 1e-6: the settling tolerance; measured 2.1e-7 (stay) and
         * 6.0e-7 (1.80 %: the simulation's floor at its rtol, the same after
         * 600 periods); 1e-3: the two attractors at 1.93 % differ by 1e-2 */
        CHECK(fabs(w_stay / w1 - 1) < 1e-6, "the 1.93 %% orbit is no attractor: %.9f vs %.9f",
              w_stay, w1);
        CHECK(fabs(w_other / w1 - 1) > 1e-3, "at 1.93 %% the other start ends on the same orbit");
        CHECK(fabs(w_low / w2 - 1) < 1e-6, "at 1.80 %% a start on the 1.93 %% orbit ends at "
              "%.9f, not the sweep's %.9f", w_low, w2);
    }
    usm_periodic_sweep_free(sw);
    printf("%s: %d failures\n", __FILE__, failures);
    return failures != 0;
}
