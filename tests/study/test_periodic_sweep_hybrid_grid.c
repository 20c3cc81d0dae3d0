/* The events of the orbits with separation do not depend on the sweep's
 * grid (docs/unilateral.md, "Continuation past contact loss"): each is
 * located from 11, 41 and 101 grid points over the same range, and the three
 * values agree to 1e-8 relative.
 *  - stability_change: 4-DOF, mode split 3.39 down to 3.373 %, the one-impact
 *    orbit (coc) loses stability through a multiplier -1 near 3.3732 %
 *    (located on the continuation's arc; before, Brent on the parameter
 *    between the two grid points around it, from their orbits' linear
 *    interpolation: 1.8e-7 apart from 5 and 11 points at the branch point
 *    near 1.947 %);
 *  - branch end: 4-DOF, mode split 2.06 down to 1.91 %, the stable two-impact
 *    orbit's branch ends at a fold near 1.9129 % (branch_switch with
 *    branch_lost; branch_end, located; before, not located: only the last
 *    grid point with an orbit was said).
 * Independent truth: the orbits 1e-7 on either side of the stability change
 * (Newton from the event's orbit, not the sweep's locator) have max |lambda|
 * on either side of 1; at 1e-6 inside the branch end the orbit (Newton from
 * the branch's last grid orbit) has a multiplier within 2e-2 of +1, as a
 * fold's has, and none is found 1e-6 beyond it from there.
 * Prints the three values of each and their largest relative difference. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "usm.h"
#include "usm_periodic.h"
#include "usm_periodic_sweep.h"

static const char *NAME = "4dof_imperfect_unilateral";
static const int grids[3] = {11, 41, 101};

/* The value of the first event of type `type` (with has_hybrid; for
 * branch_switch, branch_lost) into *v, and its event into *e. */
static void run(double from, double to, int points, usm_pevent_type type, double *v,
                usm_periodic_event *e)
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
    *v = NAN;
    if (CHECK(usm_periodic_sweep_run(sw, &p, &o) == USM_OK, "sweep: %s",
              usm_periodic_sweep_message(sw)))
        for (size_t i = 0; i < usm_periodic_sweep_event_count(sw); ++i) {
            const usm_periodic_event *ei = usm_periodic_sweep_event_at(sw, i);
            if (ei->type != type || !ei->has_hybrid ||
                (type == USM_PEVENT_BRANCH_SWITCH && !ei->branch_lost))
                continue;
            *v = type == USM_PEVENT_BRANCH_SWITCH ? ei->branch_end : ei->value;
            *e = *ei;
            break;
        }
    usm_periodic_sweep_free(sw);
}

static void check_grids(const char *what, double from, double to, usm_pevent_type type,
                        usm_periodic_event *e)
{
    double v[3], spread = 0;
    for (int g = 0; g < 3; ++g) {
        run(from, to, grids[g], type, &v[g], e);
        CHECK(isfinite(v[g]), "%s: not located from %d points", what, grids[g]);
    }
    for (int g = 1; g < 3; ++g)
        spread = fmax(spread, fabs(v[g] / v[0] - 1));
    printf("%s from 11, 41, 101 points: %.15g %.15g %.15g (spread %.2g)\n", what, v[0], v[1],
           v[2], spread);
    CHECK(spread <= 1e-8, "%s: spread %.3g over the grids", what, spread);
}

int main(void)
{
    usm_periodic_event e;
    usm_params p;
    usm_params_default(&p);
    usm_hybrid *h = usm_hybrid_alloc(usm_model_find(NAME));
    usm_hybrid_result r1, r2;

    check_grids("stability_change", 0.0339, 0.03373, USM_PEVENT_STABILITY_CHANGE, &e);
    p.mode_split = e.value - 1e-7;
    int ok = usm_hybrid_solve_from(h, &p, NULL, e.hybrid.t0, e.hybrid.x0, &r1) == USM_OK;
    p.mode_split = e.value + 1e-7;
    ok = ok && usm_hybrid_solve_from(h, &p, NULL, e.hybrid.t0, e.hybrid.x0, &r2) == USM_OK;
    if (CHECK(ok, "the orbits around the stability change: %s", usm_hybrid_message(h))) {
        printf("  max |lambda| %.9f below, %.9f above\n", r1.floquet.max_modulus,
               r2.floquet.max_modulus);
        CHECK((r1.floquet.max_modulus - 1) * (r2.floquet.max_modulus - 1) < 0,
              "max |lambda| does not cross 1 within 1e-7 of the event");
    }

    check_grids("branch end (fold)", 0.0206, 0.0191, USM_PEVENT_BRANCH_SWITCH, &e);
    /* said as a fold in the event's field (the envelope seeds its fold
     * curves from it), as the multiplier next to it shows below */
    CHECK(e.branch_end_how == USM_BRANCH_END_FOLD, "the branch's end is \"%s\", not a fold",
          usm_branch_end_how_name(e.branch_end_how));
    const double ve = e.branch_end;
    p.mode_split = ve + 1e-6;
    ok = usm_hybrid_solve_from(h, &p, NULL, e.hybrid_left.t0, e.hybrid_left.x0, &r1) == USM_OK;
    if (CHECK(ok && strcmp(r1.mode_sequence, e.hybrid_left.mode_sequence) == 0,
              "no orbit of the branch 1e-6 inside its end: %s", usm_hybrid_message(h))) {
        double mu = NAN;
        for (int i = 0; i < r1.floquet.n; ++i)
            if (!r1.floquet.cyclic[i] && r1.floquet.im[i] == 0 &&
                (isnan(mu) || fabs(r1.floquet.re[i] - 1) < fabs(mu - 1)))
                mu = r1.floquet.re[i];
        printf("  1e-6 inside the end: the real multiplier nearest +1 %.6f\n", mu);
        CHECK(fabs(mu - 1) < 2e-2, "no multiplier near +1 next to the fold: %g", mu);
        /* beyond the fold, Newton from the orbit just inside finds none
         * within its neighbourhood */
        p.mode_split = ve - 1e-6;
        ok = usm_hybrid_solve_from(h, &p, NULL, r1.t0, r1.x0, &r2) == USM_OK &&
             fabs(r2.rotor_speed_mean / r1.rotor_speed_mean - 1) < 1e-4;
        CHECK(!ok, "an orbit of the branch 1e-6 beyond its end (speed %.9g)",
              r2.rotor_speed_mean);
    }
    usm_hybrid_free(h);
    printf("%s: %d failures\n", __FILE__, failures);
    return failures != 0;
}
