/* The events of a sweep do not depend on its grid: each is located from 11,
 * 41 and 101 grid points over the same range, and the three values agree to
 * 1e-8 relative.
 *  - stick_limit and stability_change: the load sweep of the 3-DOF paper
 *    model, T = 0 .. 0.01 N m (the stick limit on the branch's arc, the
 *    stability change by Brent on T between grid points);
 *  - fold: the true turning point of the 3-DOF branch over f at m0 = 50 N m
 *    (f = 20 .. 40 kHz, theta_max = 1 rad);
 *  - operating_point_jump: F0 = 0.9 .. 1.3 N at f = 38 kHz with the start
 *    from rest, where the motor stops starting (located at the start
 *    margin's zero; before, the midpoint of two grid values, which moved by
 *    the grid spacing), and it lies at the start threshold of the motor at
 *    rest, F0* = sqrt(m0^2 - (H T / R)^2) / R, to 1e-9.
 * And no jump where there is none: at F0 = 0.95 N the 3-DOF branch over
 * f = 36 .. 39 kHz is one stable root at every grid value; from 7 grid
 * points Newton from one grid value's root at the next (500 Hz away) missed
 * the root, and a jump was reported that 11 points did not see.  Whether two
 * operating points lie on one branch is now decided by continuing one to the
 * other.
 * Prints the three values of each and their largest relative difference.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "usm_sweep.h"

#include "check.h"

static const int grids[3] = {11, 41, 101};

/* The events of types[] from the three grids; their spread against 1e-8.
 * The value from 101 points into first (NULL: not wanted). */
static void check_grids(const char *what, const usm_model *m, const usm_params *p,
                        usm_sweep_options o, const usm_event_type *types, int ntypes,
                        double *first)
{
    double v[4][3];
    for (int g = 0; g < 3; ++g) {
        usm_sweep *sw = usm_sweep_alloc(m);
        o.points = grids[g];
        for (int k = 0; k < ntypes; ++k)
            v[k][g] = NAN;
        if (CHECK(usm_sweep_run(sw, p, &o) == USM_OK, "%s, %d points: %s", what, grids[g],
                  usm_sweep_message(sw)))
            for (int k = 0; k < ntypes; ++k) {
                int n = 0;
                for (size_t i = 0; i < usm_sweep_event_count(sw); ++i)
                    if (usm_sweep_event_at(sw, i)->type == types[k]) {
                        v[k][g] = usm_sweep_event_at(sw, i)->value;
                        ++n;
                    }
                CHECK(n == 1, "%s, %d points: %d %s events, want one", what, grids[g], n,
                      usm_event_name(types[k]));
            }
        usm_sweep_free(sw);
    }
    for (int k = 0; k < ntypes; ++k) {
        double spread = 0;
        for (int g = 1; g < 3; ++g)
            spread = fmax(spread, fabs(v[k][g] - v[k][0]) / fabs(v[k][0]));
        printf("%s: %s from 11, 41, 101 points: %.15g %.15g %.15g; spread %.2e\n", what,
               usm_event_name(types[k]), v[k][0], v[k][1], v[k][2], spread);
        CHECK(spread <= 1e-8, "%s: %s differs by %.3g relative between grids", what,
              usm_event_name(types[k]), spread);
    }
    if (first)
        *first = v[0][2];
}

int main(void)
{
    const usm_model *m = usm_model_find("3dof");
    usm_params p;
    usm_sweep_options o;

    usm_params_default(&p);
    usm_sweep_options_default(&o);
    o.over = "T";
    o.from = 0;
    o.to = 0.01;
    o.operating_point = 0;
    const usm_event_type load[2] = {USM_EVENT_STICK_LIMIT, USM_EVENT_STABILITY_CHANGE};
    check_grids("3dof load sweep", m, &p, o, load, 2, NULL);

    usm_params_default(&p);
    p.m0 = 50.0;
    usm_sweep_options_default(&o);
    o.over = "f";
    o.from = 20000;
    o.to = 40000;
    o.floquet = 0;
    o.operating_point = 0;
    o.steady.theta_max = 1.0;
    const usm_event_type fold[1] = {USM_EVENT_FOLD};
    check_grids("3dof f sweep at m0 = 50", m, &p, o, fold, 1, NULL);

    usm_params_default(&p);
    p.f = 38000;
    usm_sweep_options_default(&o);
    o.over = "F0";
    o.from = 0.9;
    o.to = 1.3;
    o.op.from_rest = 1;
    const usm_event_type jump[1] = {USM_EVENT_OPERATING_POINT_JUMP};
    double at = NAN;
    check_grids("3dof F0 sweep at 38 kHz", m, &p, o, jump, 1, &at);
    /* the start threshold at rest: the preload's moment at theta = 0 equals
     * the excitation's reach (tests/test_start_threshold.c) */
    const double ht = p.H * p.T / p.R, F0_star = sqrt(p.m0 * p.m0 - ht * ht) / p.R;
    printf("operating_point_jump at F0 = %.15g N, the start threshold %.15g N: "
           "relative difference %.2e\n", at, F0_star, fabs(at / F0_star - 1));
    CHECK(fabs(at / F0_star - 1) <= 1e-9, "the jump at F0 = %.15g, not at the start threshold %.15g",
          at, F0_star);

    usm_params_default(&p);
    p.F0 = 0.95;
    usm_sweep_options_default(&o);
    o.over = "f";
    o.from = 36000;
    o.to = 39000;
    o.op.from_rest = 1;
    for (int g = 0; g < 2; ++g) {
        usm_sweep *sw = usm_sweep_alloc(m);
        o.points = g ? 11 : 7;
        int n = 0;
        if (CHECK(usm_sweep_run(sw, &p, &o) == USM_OK, "F0 = 0.95: %s", usm_sweep_message(sw)))
            for (size_t i = 0; i < usm_sweep_event_count(sw); ++i)
                n += usm_sweep_event_at(sw, i)->type == USM_EVENT_OPERATING_POINT_JUMP;
        printf("3dof f sweep at F0 = 0.95 N, %d points: %d operating_point_jump events\n",
               o.points, n);
        CHECK(n == 0, "%d points: %d operating_point_jump events on one continuous branch",
              o.points, n);
        usm_sweep_free(sw);
    }

    printf("%s: %d failure(s)\n", failures ? "FAIL" : "ok", failures);
    return failures != 0;
}
