/* The operating point (issue 20): usm_operating_point's rule checked against
 * simulations from rest, and usm_sim_run's settled_on.
 *
 * 1. One stable root (the paper's point): only_stable_root, root 0, no
 *    simulation; with a simulation asked: reached_from_rest, root 0.
 * 2. No stable root (f = 32 kHz, T = 4 N mm): no_stable_root, none.
 * 3. F0 = 1.001 N, f = 38 kHz: two roots, #1 (theta 1.03e-7) unstable; not
 *    asked: undecided; from rest: reached_from_rest, root #2 (theta
 *    8.635e-5, rotor speed -12.37 1/s), starts_from_rest.  Checked against
 *    an independent simulation from rest (twist_integrated model, whose
 *    stationary roots and stability are the paper model's at t0 = 0,
 *    rtol 1e-10, its own settling): its period means end within 1e-3 of
 *    root #2 and far from root #1.
 * 4. F0 = 1.2 N, f = 38 kHz: root #1 unstable, root #2 stable; from rest the
 *    wobble decays: does_not_start, starts_from_rest 0.  Checked against a
 *    simulation from rest that is not stopped by the decay rule
 *    (rest_fraction 0) and runs on until the step cap: the tilt never
 *    rises again above the decayed value, never approaches either root, and
 *    ends below the value at which the rule fired.
 * Prints the steps of the start-ups (the measure).
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <gsl/gsl_errno.h>

#include "usm.h"
#include "usm_operating_point.h"
#include "usm_simulate.h"

#include "check.h"

typedef struct point {
    usm_steady *s;
    usm_floquet_result fl[16];
    size_t n;
} point;

static int solve(const usm_model *m, const usm_params *p, point *pt)
{
    usm_floquet *f = usm_floquet_alloc(m);
    pt->s = usm_steady_alloc(m);
    int ok = f && pt->s && usm_steady_solve(pt->s, p, NULL) == USM_OK &&
             (pt->n = usm_steady_count(pt->s)) <= 16 &&
             usm_floquet_roots(f, p, pt->s, 0.0, NULL, pt->fl) == USM_OK;
    usm_floquet_free(f);
    return ok;
}

static usm_op_result op_at(const usm_model *m, const usm_params *p, const point *pt,
                           int from_rest)
{
    usm_op_options o;
    usm_op_result r;
    usm_op_options_default(&o);
    o.from_rest = from_rest;
    int rc = usm_operating_point(m, p, pt->s, pt->fl, &o, &r);
    CHECK(rc == USM_OK, "usm_operating_point: %s", r.message);
    if (r.simulated)
        printf("  from rest: %ld steps to t = %.4g ms, stop %s, settled_on %d (%.2f s)\n",
               r.sim.steps, 1e3 * r.sim.t_reached, usm_sim_stop_name(r.sim.stop),
               r.sim.settled_on, r.wall);
    return r;
}

static void one_stable_root(const usm_model *m)
{
    usm_params p;
    point pt;
    usm_params_default(&p);
    if (CHECK(solve(m, &p, &pt), "paper's point") && CHECK(pt.n == 1, "%zu roots", pt.n)) {
        usm_op_result r = op_at(m, &p, &pt, 0);
        CHECK(r.index == 0 && r.reason == USM_OP_ONLY_STABLE_ROOT && r.starts_from_rest == -1 &&
                  !r.simulated,
              "%s paper: index %d reason %s", m->name, r.index, usm_op_reason_name(r.reason));
        r = op_at(m, &p, &pt, 1);
        CHECK(r.index == 0 && r.reason == USM_OP_REACHED_FROM_REST && r.starts_from_rest == 1,
              "%s paper from rest: index %d reason %s (%s)", m->name, r.index,
              usm_op_reason_name(r.reason), r.message);
    }
    usm_steady_free(pt.s);
}

static void no_stable_root(const usm_model *m)
{
    usm_params p;
    point pt;
    usm_params_default(&p);
    p.f = 32000;
    p.T = 0.004;
    if (CHECK(solve(m, &p, &pt), "f 32 kHz T 4 N mm")) {
        usm_op_result r = op_at(m, &p, &pt, 0);
        CHECK(r.index == -1 && r.reason == USM_OP_NO_STABLE_ROOT,
              "%s f 32 kHz: index %d reason %s", m->name, r.index, usm_op_reason_name(r.reason));
    }
    usm_steady_free(pt.s);
}

static void reaches_second_root(void)
{
    const usm_model *m = usm_model_find("3dof");
    usm_params p;
    point pt;
    usm_params_default(&p);
    p.F0 = 1.001;
    p.f = 38000;
    if (!CHECK(solve(m, &p, &pt) && pt.n == 2, "F0 1.001: want 2 roots"))
        goto done;
    CHECK(!pt.fl[0].stable && pt.fl[1].stable, "F0 1.001: root #1 must be unstable, #2 stable");
    usm_op_result r = op_at(m, &p, &pt, 0);
    CHECK(r.index == -1 && r.reason == USM_OP_UNDECIDED && r.starts_from_rest == -1,
          "F0 1.001 not asked: index %d reason %s", r.index, usm_op_reason_name(r.reason));
    printf("F0 = 1.001 N, f = 38 kHz:\n");
    r = op_at(m, &p, &pt, 1);
    const usm_steady_solution *r2 = usm_steady_root(pt.s, 1);
    CHECK(r.index == 1 && r.reason == USM_OP_REACHED_FROM_REST && r.starts_from_rest == 1,
          "F0 1.001 from rest: index %d reason %s (%s)", r.index, usm_op_reason_name(r.reason),
          r.message);
    CHECK(fabs(r2->theta - 8.635e-5) < 1e-8 && fabs(r2->rotor_speed + 12.37) < 5e-3,
          "root #2: theta %.6g rotor speed %.6g", r2->theta, r2->rotor_speed);
    /* independent: the integrated twist law, tighter tolerance, no settling rule */
    const usm_model *mi = usm_model_variant("3dof", "twist_integrated");
    usm_sim *sim = usm_sim_alloc(mi);
    usm_sim_options o;
    usm_sim_summary sum;
    usm_sim_options_default(&o);
    o.duration = 300 / p.f;
    o.rtol = 1e-10;
    o.rest_fraction = 0;
    int rc = usm_sim_run(sim, &p, &o, NULL, &sum);
    printf("  twist_integrated, rtol 1e-10: %ld steps, end means theta %.10g, rotor speed %.10g\n",
           sum.steps, sum.theta_avg_end, sum.rotor_speed_avg_end);
    CHECK(rc == USM_OK && fabs(sum.theta_avg_end / r2->theta - 1) < 1e-3 &&
              fabs(sum.rotor_speed_avg_end / r2->rotor_speed - 1) < 1e-3,
          "independent start-up does not end on root #2 (rc %d, theta %.6g)", rc,
          sum.theta_avg_end);
    CHECK(sum.settled_on == 1, "independent start-up: settled_on %d, want 1", sum.settled_on);
    usm_sim_free(sim);
done:
    usm_steady_free(pt.s);
}

static void does_not_start(void)
{
    const usm_model *m = usm_model_find("3dof");
    usm_params p;
    point pt;
    usm_params_default(&p);
    p.F0 = 1.2;
    p.f = 38000;
    if (!CHECK(solve(m, &p, &pt) && pt.n == 2, "F0 1.2: want 2 roots"))
        goto done;
    CHECK(!pt.fl[0].stable && pt.fl[1].stable, "F0 1.2: root #1 must be unstable, #2 stable");
    printf("F0 = 1.2 N, f = 38 kHz:\n");
    usm_op_result r = op_at(m, &p, &pt, 1);
    if (!CHECK(r.index == -1 && r.reason == USM_OP_DOES_NOT_START && r.starts_from_rest == 0,
               "F0 1.2 from rest: index %d reason %s (%s)", r.index,
               usm_op_reason_name(r.reason), r.message))
        goto done;
    /* against a run the decay rule does not stop */
    usm_sim *sim = usm_sim_alloc(m);
    usm_sim_options o;
    usm_sim_summary sum;
    usm_sim_options_default(&o);
    o.duration = 100 / p.f;
    o.rest_fraction = 0;
    o.max_steps = 300000;
    (void)usm_sim_run(sim, &p, &o, NULL, &sum);
    printf("  without the decay rule: stop %s at t = %.4g ms after %ld steps; tilt in [%.3g, "
           "%.3g], end mean %.3g (rule fired at %.3g)\n",
           usm_sim_stop_name(sum.stop), 1e3 * sum.t_reached, sum.steps, sum.theta_min,
           sum.theta_max, sum.theta_avg_end, r.sim.theta_avg_end);
    CHECK(sum.settled_on == USM_SIM_SETTLED_NONE && sum.t_reached > r.sim.t_reached,
          "the run without the rule ended earlier than the rule (%.4g ms)", 1e3 * sum.t_reached);
    CHECK(sum.theta_max <= o.tilt0 * (1 + 1e-9) && sum.theta_avg_end < r.sim.theta_avg_end,
          "the tilt did not keep decaying (max %.3g, end mean %.3g)", sum.theta_max,
          sum.theta_avg_end);
    CHECK(sum.theta_max < 0.1 * usm_steady_root(pt.s, 0)->theta,
          "the tilt came near root #1 (%.3g)", sum.theta_max);
    usm_sim_free(sim);
done:
    usm_steady_free(pt.s);
}

int main(void)
{
    gsl_set_error_handler_off();
    const usm_model *m3 = usm_model_find("3dof"), *m4 = usm_model_find("4dof");
    printf("paper's point:\n");
    one_stable_root(m3);
    one_stable_root(m4);
    no_stable_root(m3);
    reaches_second_root();
    does_not_start();
    CHECK(strcmp(usm_op_reason_name(USM_OP_DOES_NOT_START), "does_not_start") == 0 &&
              usm_op_reason_name((usm_op_reason)99) == NULL,
          "usm_op_reason_name");
    printf("%d failures\n", failures);
    return failures != 0;
}
