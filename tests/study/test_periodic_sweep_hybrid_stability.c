/* sweep --periodic: the stability changes of the followed orbit with
 * separation (docs/unilateral.md, "Continuation past contact loss"; event
 * stability_change with has_hybrid).
 *
 * 1. 4-DOF, mode split 1.8 to 2.2 % (5 points): the orbit continued from
 *    contact loss turns unstable near 1.94717 % through a real multiplier +1
 *    and the sweep switches to the coexisting stable orbit at 2 %
 *    (branch_switch).  Exactly one stability_change on the separating
 *    branch, kind fold (the kind names the multiplier, a real one through
 *    +1; the branch goes on through it, unstable: not a turning point), at
 *    the branch_switch's unstable_from.
 * 2. 4-DOF, mode split 3.2 to 3.4 % (3 points): the one-impact orbit (coc)
 *    found from rest at 3.2 % is unstable and becomes stable near 3.373 %
 *    through a real multiplier -1 (no branch_switch: no stable orbit
 *    coexists at 3.2 or 3.3 %).  One stability_change, kind period_doubling.
 *
 * Independent truth: where max |lambda| = 1, the linear interpolation of
 * max |lambda| between two orbits 1e-5 apart bracketing the event (each
 * solved by usm_hybrid_solve_from, not by the sweep's locator); the kind by
 * simulations (no shooting, no multipliers) started on the unstable orbits,
 * slightly perturbed: at 3.3 % the deviation from the orbit at the section
 * changes sign every period and grows by the critical multiplier's modulus,
 * as a real multiplier below -1 makes it; on the continued orbit at 2 % it
 * keeps its sign and grows by the multiplier above +1 (kind fold). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "usm.h"
#include "usm_periodic.h"
#include "usm_periodic_sweep.h"
#include "usm_simulate.h"

static const char *NAME = "4dof_imperfect_unilateral";

static usm_periodic_sweep *sweep(double from, double to, int points)
{
    usm_params p;
    usm_params_default(&p);
    usm_periodic_sweep *sw = usm_periodic_sweep_alloc(usm_model_find(NAME));
    usm_periodic_sweep_options o;
    usm_periodic_sweep_options_default(&o);
    o.over = "mode_split";
    o.from = from;
    o.to = to;
    o.points = points;
    if (!CHECK(usm_periodic_sweep_run(sw, &p, &o) == USM_OK, "sweep: %s",
               usm_periodic_sweep_message(sw))) {
        usm_periodic_sweep_free(sw);
        return NULL;
    }
    for (size_t i = 0; i < usm_periodic_sweep_event_count(sw); ++i) {
        const usm_periodic_event *e = usm_periodic_sweep_event_at(sw, i);
        printf("  event %s at %.10g: %s\n", usm_pevent_name(e->type), e->value, e->what);
    }
    for (size_t i = 0; i < usm_periodic_sweep_count(sw); ++i) {
        const usm_periodic_point *pt = usm_periodic_sweep_point_at(sw, i);
        printf("  mode split %.4f: %s max |lambda| %.6f%s\n", pt->value,
               pt->separating ? pt->hybrid.mode_sequence : "-",
               pt->separating ? pt->hybrid.floquet.max_modulus : NAN,
               pt->switched ? " (switched)" : "");
    }
    return sw;
}

/* The one stability_change of an orbit with separation (*n: how many). */
static const usm_periodic_event *separating_change(const usm_periodic_sweep *sw, int *n)
{
    const usm_periodic_event *e = NULL;
    *n = 0;
    for (size_t i = 0; i < usm_periodic_sweep_event_count(sw); ++i) {
        const usm_periodic_event *ei = usm_periodic_sweep_event_at(sw, i);
        if (ei->type == USM_PEVENT_STABILITY_CHANGE && ei->has_hybrid && (*n)++ == 0)
            e = ei;
    }
    return e;
}

/* What every such event must carry, and its location against the linear
 * interpolation of max |lambda| = 1 between the orbits at the multiples of
 * 1e-5 around it (Newton from the event's orbit). */
static void check_event(const usm_periodic_event *e, double mu_crit)
{
    usm_params p;
    usm_params_default(&p);
    CHECK(e->has_hybrid && !e->has_orbit, "has_hybrid %d, has_orbit %d", e->has_hybrid,
          e->has_orbit);
    /* the located orbit: Brent's last trial, within the location's
     * tolerance of the crossing (measured 1.0e-9 and 2.7e-9) */
    CHECK(fabs(e->hybrid.floquet.max_modulus - 1) < 1e-6, "the event's orbit: max |lambda| %.9f",
          e->hybrid.floquet.max_modulus);
    CHECK(e->hybrid.nmodes >= 2 && e->hybrid.separation_fraction > 0,
          "the event's orbit has no separation");
    /* the critical multiplier: real, +1 (fold) or -1 (period doubling) */
    CHECK(fabs(e->multiplier_re - mu_crit) < 1e-3 && fabs(e->multiplier_im) < 1e-3,
          "critical multiplier %.9f %+.9fi, want %g", e->multiplier_re, e->multiplier_im,
          mu_crit);
    CHECK(isnan(e->squeal_frequency), "squeal_frequency %g on a real crossing",
          e->squeal_frequency);
    usm_hybrid *h = usm_hybrid_alloc(usm_model_find(NAME));
    usm_hybrid_result r1, r2;
    const double v1 = floor(e->value * 1e5) / 1e5, v2 = v1 + 1e-5;
    usm_params q = p;
    q.mode_split = v2;
    int ok = usm_hybrid_solve_from(h, &q, NULL, e->hybrid.t0, e->hybrid.x0, &r2) == USM_OK;
    q.mode_split = v1;
    ok = ok && usm_hybrid_solve_from(h, &q, NULL, e->hybrid.t0, e->hybrid.x0, &r1) == USM_OK;
    if (CHECK(ok, "the followed branch near %g: %s", e->value, usm_hybrid_message(h)) &&
        CHECK(strcmp(r1.mode_sequence, e->hybrid.mode_sequence) == 0 &&
                  strcmp(r2.mode_sequence, e->hybrid.mode_sequence) == 0,
              "another mode sequence: %s, %s", r1.mode_sequence, r2.mode_sequence)) {
        const double l1 = r1.floquet.max_modulus, l2 = r2.floquet.max_modulus;
        const double lin = v1 + (v2 - v1) * (1 - l1) / (l2 - l1);
        printf("  located %.10g; max |lambda| %.9f at %.5f %%, %.9f at %.5f %%: linear "
               "interpolation %.10g (%.2g apart)\n", e->value, l1, 100 * v1, l2, 100 * v2, lin,
               fabs(e->value - lin));
        /* measured 6.6e-9 (fold) and 4.7e-9 (period doubling): the
         * location's tolerance (1e-6 of the range: 4e-9, 2e-9), its trial
         * orbits to Newton's 1e-7 (|lambda| moves by about 1e-6: 6e-9 and
         * 3e-8 of mode split at the slopes 175 and 33 per unit); the
         * interpolation over 1e-5: curvature below 1e-10 */
        CHECK((l1 - 1) * (l2 - 1) < 0 && fabs(e->value - lin) < 5e-8,
              "located %.10g, interpolated %.10g", e->value, lin);
    }
    usm_hybrid_free(h);
}

typedef struct sections sections;
static void run_sections(const usm_params *p, const usm_hybrid_result *r, const double *x0,
                         int periods, sections *out);
static void fold_by_simulation(const usm_periodic_event *bs);

static void check_fold(void)
{
    printf("4-DOF mode split 1.8 to 2.2 %%: loses stability, then branch_switch\n");
    usm_periodic_sweep *sw = sweep(0.018, 0.022, 5);
    if (!sw)
        return;
    int n, nsw = 0;
    const usm_periodic_event *e = separating_change(sw, &n), *bs = NULL;
    size_t ie = 0, ibs = 0;
    for (size_t i = 0; i < usm_periodic_sweep_event_count(sw); ++i) {
        const usm_periodic_event *ei = usm_periodic_sweep_event_at(sw, i);
        if (ei == e)
            ie = i;
        if (ei->type == USM_PEVENT_BRANCH_SWITCH && nsw++ == 0)
            bs = ei, ibs = i;
    }
    if (CHECK(e && n == 1, "%d stability_change events on the separating branch, want 1", n) &&
        CHECK(bs && nsw == 1 && !bs->branch_lost, "%d branch switches", nsw)) {
        CHECK(e->kind == USM_CROSSING_FOLD, "kind %s", usm_crossing_name(e->kind));
        CHECK(strstr(e->what, "loses stability") != NULL, "what: %s", e->what);
        /* the same location (one Brent run gives both) */
        CHECK(fabs(e->value - bs->unstable_from) <= 1e-9 * fabs(bs->unstable_from),
              "stability_change at %.12g, unstable_from %.12g", e->value, bs->unstable_from);
        CHECK(ie < ibs && e->value < bs->value, "not in sweep order");
        check_event(e, 1.0);
        fold_by_simulation(bs);
    }
    usm_periodic_sweep_free(sw);
}

/* The mean rotor speed at the section times t0 + k T of a run from x0 over
 * n periods (the sample callback at rate 1 / T). */
struct sections {
    int n;
    double w[64];
};

static int keep_section(const usm_sim_sample *s, void *data)
{
    sections *c = data;
    if (c->n < 64)
        c->w[c->n++] = s->rotor_speed;
    return 0;
}

static void run_sections(const usm_params *p, const usm_hybrid_result *r, const double *x0,
                         int periods, sections *out)
{
    usm_sim *s = usm_sim_alloc(usm_model_find(NAME));
    usm_sim_options o;
    usm_sim_summary sum;
    usm_sim_callbacks cb = {keep_section, NULL, out, NULL};
    usm_sim_options_default(&o);
    o.start = USM_SIM_FROM_STATE;
    o.t0 = r->t0;
    o.duration = periods * r->period;
    o.rate = 1.0 / r->period;
    o.rtol = 1e-11;
    memcpy(o.x0, x0, sizeof(double) * (size_t)r->nx);
    out->n = 0;
    CHECK(usm_sim_run(s, p, &o, &cb, &sum) == USM_OK, "run failed: %s", usm_sim_message(s));
    usm_sim_free(s);
}

/* The kind fold by a simulation: on the unstable continued orbit at 2 %
 * (the branch_switch's hybrid_left, max |lambda| 1.081), a deviation of the
 * start grows without changing sign, by the real multiplier above +1. */
static void fold_by_simulation(const usm_periodic_event *bs)
{
    const usm_hybrid_result *r = &bs->hybrid_left;
    usm_params q;
    usm_params_default(&q);
    q.mode_split = bs->value;
    double x[USM_MAX_NX], mu = NAN;
    memcpy(x, r->x0, sizeof x);
    for (int i = 0; i < r->nx; ++i)
        x[i] *= 1 + 1e-7;
    for (int i = 0; i < r->floquet.n; ++i)
        if (!r->floquet.cyclic[i] && r->floquet.im[i] == 0 && r->floquet.re[i] > 1)
            mu = r->floquet.re[i];
    sections a, b;
    run_sections(&q, r, r->x0, 41, &a);
    run_sections(&q, r, x, 41, &b);
    int same_sign = a.n >= 41 && b.n >= 41, k;
    double ratio = NAN;
    for (k = 20; same_sign && k < 40; ++k) {
        const double d0 = b.w[k] - a.w[k], d1 = b.w[k + 1] - a.w[k + 1];
        ratio = d1 / d0;
        same_sign = ratio > 0;
    }
    printf("  simulation on the continued orbit at %.4g %%: deviation ratio per period %.4f "
           "(periods 39-40), the critical multiplier %.4f\n", 100 * bs->value, ratio, mu);
    /* measured 1.0799 against 1.0811 at periods 39-40 (1.1e-3: the other
     * multipliers, 0.84 and below, decay by (0.84 / 1.08)^k; the start 1e-7
     * off grows to 2e-6, still linear); the sign kept from period 20 on */
    CHECK(same_sign && fabs(ratio / mu - 1) < 1e-2, "the deviation does not grow by the "
          "multiplier without changing sign (ratio %g at period %d, multiplier %g)", ratio, k,
          mu);
}

static void check_period_doubling(void)
{
    printf("4-DOF mode split 3.2 to 3.4 %%: the one-impact orbit becomes stable\n");
    usm_periodic_sweep *sw = sweep(0.032, 0.034, 3);
    if (!sw)
        return;
    int n, nsw = 0;
    const usm_periodic_event *e = separating_change(sw, &n);
    for (size_t i = 0; i < usm_periodic_sweep_event_count(sw); ++i)
        nsw += usm_periodic_sweep_event_at(sw, i)->type == USM_PEVENT_BRANCH_SWITCH;
    const usm_periodic_point *mid = usm_periodic_sweep_point_at(sw, 1);
    if (CHECK(e && n == 1, "%d stability_change events on the separating branch, want 1", n) &&
        CHECK(nsw == 0, "%d branch switches", nsw) &&
        CHECK(mid && mid->separating && mid->hybrid.floquet.max_modulus > 1,
              "no unstable orbit at 3.3 %%")) {
        CHECK(e->kind == USM_CROSSING_PERIOD_DOUBLING, "kind %s", usm_crossing_name(e->kind));
        CHECK(strstr(e->what, "becomes stable") != NULL, "what: %s", e->what);
        CHECK(e->value > 0.033 && e->value < 0.034, "at %g", e->value);
        check_event(e, -1.0);
        /* the simulation: from the 3.3 % orbit's state scaled by 1 + 1e-9,
         * against one from the orbit itself (which leaves it too, from
         * Newton's 1e-9, but both stay within the linear range); the
         * deviation of the rotor speed at the section, periods 8 to 20
         * (1e-6 growing to 1e-3 1/s: linear; 1e-6 relative made it
         * saturate by period 14) changes sign every period */
        usm_params q;
        usm_params_default(&q);
        q.mode_split = mid->value;
        const usm_hybrid_result *r = &mid->hybrid;
        double x[USM_MAX_NX];
        memcpy(x, r->x0, sizeof x);
        for (int i = 0; i < r->nx; ++i)
            x[i] *= 1 + 1e-9;
        sections a, b;
        run_sections(&q, r, r->x0, 21, &a);
        run_sections(&q, r, x, 21, &b);
        double mu = NAN;
        for (int i = 0; i < r->floquet.n; ++i)
            if (!r->floquet.cyclic[i] && r->floquet.im[i] == 0 && r->floquet.re[i] < -1)
                mu = r->floquet.re[i];
        int alternates = a.n >= 21 && b.n >= 21, k;
        double ratio = NAN;
        for (k = 8; alternates && k < 20; ++k) {
            const double d0 = b.w[k] - a.w[k], d1 = b.w[k + 1] - a.w[k + 1];
            ratio = d1 / d0;
            alternates = ratio < 0;
        }
        printf("  simulation at 3.3 %%: deviation ratio per period %.4f (periods 19-20), the "
               "critical multiplier %.4f\n", ratio, mu);
        /* the ratio tends to the multiplier as the others decay: measured
         * -1.4359 against -1.4413 at periods 19-20 (3.7e-3; -1.445 at 18-19:
         * the slower modes still present); 2e-2 allows for them */
        CHECK(alternates && fabs(ratio / mu - 1) < 2e-2,
              "the deviation does not alternate by the multiplier (ratio %g at period %d, "
              "multiplier %g)", ratio, k, mu);
    }
    usm_periodic_sweep_free(sw);
}

int main(void)
{
    check_fold();
    check_period_doubling();
    printf("%s: %d failures\n", __FILE__, failures);
    return failures != 0;
}
