/* The operating point: usm_operating_point's rule checked against
 * simulations from rest, and usm_sim_run's settled_on.
 *
 * 1. One stable root (the paper's point): only_stable_root, root 0, no
 *    simulation even when simulations are asked (the point is not
 *    ambiguous: the start margin, m0 / sqrt((R F0)^2 + (H T / R)^2) - 1 in
 *    closed form, is 1.5); with every point simulated: reached_from_rest,
 *    root 0.
 * 2. No stable root (f = 32 kHz, T = 4 N mm): no_stable_root, none.
 * 3. F0 = 1.001 N, f = 38 kHz: two roots, #1 (theta 1.03e-7) unstable.  At
 *    rest the preload's moment R F0 exceeds the excitation's reach (the
 *    start threshold is F0 = 0.99997 N, where root #1 is born at theta = 0):
 *    the motor does not start.  Not asked: undecided; from rest (below
 *    root #1): does_not_start, starts_from_rest 0.  The old start at a tilt
 *    of 1e-6, above root #1, is checked to be no start at rest: an
 *    independent simulation from there (twist_integrated, rtol 1e-10, no
 *    decay rule) reaches root #2 (theta 8.635e-5, rotor speed -12.37 1/s).
 *    F0 = 0.999 N: its only root, only_stable_root, and reached from rest
 *    when simulated.
 * 5. The slip model at f = 38.5 kHz, F0 = 1.1 N under its default load:
 *    does_not_start (the rotor creeps backwards at the friction law's creep
 *    speed while the tilt decays; the decay rule decides on the tilt).
 * 6. A start-up that settles on no root: its message is whole, counts the
 *    periods integrated and names no option.
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

static usm_op_result op_with(const usm_model *m, const usm_params *p, const point *pt,
                             int from_rest, double periods);

static usm_op_result op_at(const usm_model *m, const usm_params *p, const point *pt,
                           int from_rest)
{
    return op_with(m, p, pt, from_rest, 400);
}

static usm_op_result op_with(const usm_model *m, const usm_params *p, const point *pt,
                             int from_rest, double periods)
{
    usm_op_options o;
    usm_op_result r;
    usm_op_options_default(&o);
    o.from_rest = from_rest;
    o.periods = periods;
    int rc = usm_operating_point(m, p, pt->s, pt->fl, &o, &r);
    CHECK(rc == USM_OK, "usm_operating_point: %s", r.message);
    if (r.simulated)
        printf("  from rest (%s, %s): %ld steps to t = %.4g ms, stop %s, settled_on %d "
               "(%.2f s)\n",
               r.sim_model ? r.sim_model->name : "?", r.sim.start_message, r.sim.steps,
               1e3 * r.sim.t_reached, usm_sim_stop_name(r.sim.stop), r.sim.settled_on, r.wall);
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
        const double closed = p.m0 / hypot(p.R * p.F0, p.H * p.T / p.R) - 1;
        CHECK(fabs(r.start_margin - closed) < 1e-10 * (1 + closed) && !r.ambiguous,
              "%s paper: start margin %.15g, closed form %.15g", m->name, r.start_margin, closed);
        r = op_at(m, &p, &pt, 1);
        CHECK(r.index == 0 && r.reason == USM_OP_ONLY_STABLE_ROOT && !r.simulated,
              "%s paper, ambiguous points simulated: index %d reason %s simulated %d", m->name,
              r.index, usm_op_reason_name(r.reason), r.simulated);
        r = op_at(m, &p, &pt, USM_OP_FROM_REST_ALWAYS);
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

static void just_above_threshold(void)
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
    CHECK(r.index == -1 && r.reason == USM_OP_UNDECIDED && r.starts_from_rest == -1 &&
              r.ambiguous,
          "F0 1.001 not asked: index %d reason %s", r.index, usm_op_reason_name(r.reason));
    /* the preload's moment at rest exceeds the excitation's reach */
    const double closed = p.m0 / hypot(p.R * p.F0, p.H * p.T / p.R) - 1;
    CHECK(closed < 0 && fabs(r.start_margin - closed) < 1e-10,
          "F0 1.001: start margin %.15g, closed form %.15g", r.start_margin, closed);
    printf("F0 = 1.001 N, f = 38 kHz (start margin %.6g):\n", r.start_margin);
    r = op_at(m, &p, &pt, 1);
    const double th1 = usm_steady_root(pt.s, 0)->theta;
    CHECK(r.index == -1 && r.reason == USM_OP_DOES_NOT_START && r.starts_from_rest == 0,
          "F0 1.001 from rest: index %d reason %s (%s)", r.index, usm_op_reason_name(r.reason),
          r.message);
    CHECK(r.sim.tilt_start > 0 && r.sim.tilt_start <= 1e-2 * th1 * (1 + 1e-12) &&
              strstr(r.sim.start_message, "at rest") != NULL,
          "F0 1.001: the start at rest %.3g rad is not below 1e-2 of root #1's tilt %.3g (%s)",
          r.sim.tilt_start, th1, r.sim.start_message);
    /* the old start, 1e-6 rad, lies above root #1: from there the motion
     * reaches root #2 (independently: the integrated twist law, rtol 1e-10,
     * no decay rule), which is why it is no start at rest */
    const usm_steady_solution *r2 = usm_steady_root(pt.s, 1);
    CHECK(fabs(r2->theta - 8.635e-5) < 1e-8 && fabs(r2->rotor_speed + 12.37) < 5e-3,
          "root #2: theta %.6g rotor speed %.6g", r2->theta, r2->rotor_speed);
    const usm_model *mi = usm_model_variant("3dof", "twist_integrated");
    usm_sim *sim = usm_sim_alloc(mi);
    usm_sim_options o;
    usm_sim_summary sum;
    usm_sim_options_default(&o);
    o.duration = 300 / p.f;
    o.rtol = 1e-10;
    o.tilt0 = 1e-6;
    o.rest_fraction = 0;
    int rc = usm_sim_run(sim, &p, &o, NULL, &sum);
    printf("  from 1e-6 rad (above root #1), twist_integrated, rtol 1e-10: %ld steps, end means "
           "theta %.10g, rotor speed %.10g (%s)\n",
           sum.steps, sum.theta_avg_end, sum.rotor_speed_avg_end, sum.start_message);
    CHECK(rc == USM_OK && fabs(sum.theta_avg_end / r2->theta - 1) < 1e-3 &&
              fabs(sum.rotor_speed_avg_end / r2->rotor_speed - 1) < 1e-3 && sum.settled_on == 1,
          "from 1e-6 rad the motion does not end on root #2 (rc %d, theta %.6g)", rc,
          sum.theta_avg_end);
    CHECK(strstr(sum.start_message, "not a start at rest") != NULL,
          "a start above root #1 is not called so: %s", sum.start_message);
    usm_sim_free(sim);
done:
    usm_steady_free(pt.s);
    /* just below the threshold: one root, the start not in doubt */
    usm_params_default(&p);
    p.F0 = 0.999;
    p.f = 38000;
    if (CHECK(solve(m, &p, &pt) && pt.n == 1 && pt.fl[0].stable, "F0 0.999: want 1 stable root")) {
        usm_op_result q = op_at(m, &p, &pt, 1);
        CHECK(q.index == 0 && q.reason == USM_OP_ONLY_STABLE_ROOT && q.start_margin > 0 &&
                  !q.simulated,
              "F0 0.999: index %d reason %s margin %g", q.index, usm_op_reason_name(q.reason),
              q.start_margin);
        printf("F0 = 0.999 N, f = 38 kHz (start margin %.6g), simulated anyway:\n",
               q.start_margin);
        q = op_at(m, &p, &pt, USM_OP_FROM_REST_ALWAYS);
        CHECK(q.index == 0 && q.reason == USM_OP_REACHED_FROM_REST,
              "F0 0.999 from rest: index %d reason %s (%s)", q.index,
              usm_op_reason_name(q.reason), q.message);
    }
    usm_steady_free(pt.s);
}

/* The slip model under its default load: the stopped rotor is back-driven at
 * the friction law's creep speed while the wobble decays. */
static void slip_does_not_start(void)
{
    const usm_model *m = usm_model_find("4dof");
    usm_params p;
    point pt;
    usm_params_default(&p);
    p.F0 = 1.1;
    p.f = 38500;
    if (!CHECK(solve(m, &p, &pt) && pt.n == 2, "4dof F0 1.1: want 2 roots"))
        goto done;
    printf("4dof, F0 = 1.1 N, f = 38.5 kHz:\n");
    usm_op_result r = op_at(m, &p, &pt, 1);
    CHECK(r.index == -1 && r.reason == USM_OP_DOES_NOT_START && r.starts_from_rest == 0,
          "4dof F0 1.1 from rest: index %d reason %s (%s)", r.index,
          usm_op_reason_name(r.reason), r.message);
    /* the creep: tan(T / (R F0 mu0)) / (kappa R), backwards (positive) */
    const double creep = tan(p.T / (p.R * p.F0 * p.mu0)) / (p.kappa * p.R);
    printf("  end: period-mean rotor speed %.4g 1/s, creep speed %.4g 1/s, tilt %.3g rad\n",
           r.sim.rotor_speed_avg_end, creep, r.sim.theta_avg_end);
    CHECK(r.sim.rotor_speed_avg_end > 0.5 * creep && r.sim.rotor_speed_avg_end < 1.5 * creep,
          "4dof: the rotor does not creep (%.4g 1/s against %.4g)", r.sim.rotor_speed_avg_end,
          creep);
done:
    usm_steady_free(pt.s);
}

/* A start-up too short to settle: undecided, with a whole message that
 * counts the periods integrated and tells no option to pass. */
static void undecided_message(void)
{
    const usm_model *m = usm_model_find("3dof");
    usm_params p;
    point pt;
    usm_params_default(&p);
    p.F0 = 1.001;
    p.f = 38000;
    if (CHECK(solve(m, &p, &pt) && pt.n == 2, "F0 1.001: want 2 roots")) {
        usm_op_result r = op_with(m, &p, &pt, 1, 3);
        printf("3 periods: %s\n", r.message);
        CHECK(r.reason == USM_OP_UNDECIDED && strstr(r.message, "after 3 of 3 periods") &&
                  strlen(r.message) < USM_MSG_LEN - 1 && r.message[strlen(r.message) - 1] == ')' &&
                  !strstr(r.message, "--"),
              "undecided message: %s", r.message);
    }
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
    /* against a run the decay rule does not stop, of the model and from the
     * start the decision used */
    usm_sim *sim = usm_sim_alloc(r.sim_model);
    usm_sim_options o;
    usm_sim_summary sum;
    usm_sim_options_default(&o);
    o.tilt0 = r.sim.tilt_start;
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
    just_above_threshold();
    does_not_start();
    slip_does_not_start();
    undecided_message();
    CHECK(strcmp(usm_op_reason_name(USM_OP_DOES_NOT_START), "does_not_start") == 0 &&
              usm_op_reason_name((usm_op_reason)99) == NULL,
          "usm_op_reason_name");
    printf("%d failures\n", failures);
    return failures != 0;
}
