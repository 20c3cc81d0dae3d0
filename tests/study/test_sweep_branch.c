/* The finish pass of the stationary sweep (study/sweep_branch.c) searches all
 * roots only where a span of grid points starts and where the tracked root
 * set may have changed; in between the roots are continued by Newton.  Its
 * rows must be those of the full search at every grid value, which is the
 * independent truth here (usm_steady_solve at each value):
 *  - the root count of every converged row;
 *  - the row's root, bit for bit one of the full search's.
 * The sweeps cross root count changes that the tracking cannot see, so only
 * the check at a span's end catches them:
 *  - 3dof over f at m0 = 50 N m, theta_max = 1 rad: a pair of roots appears
 *    near 29.15 kHz (one root, then three), away from the followed branch,
 *    which turns at a fold near 32.9 kHz;
 *  - the same downwards, and on a grid whose spans end elsewhere;
 *  - the load branch of the 3-DOF paper model (one root everywhere).
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "../check.h"
#include "usm.h"
#include "usm_sweep.h"

static void check_rows(const char *what, const usm_model *m, const usm_params *p,
                       const usm_sweep_options *o)
{
    usm_sweep *sw = usm_sweep_alloc(m);
    usm_steady *s = usm_steady_alloc(m);
    const usm_param_info *info = usm_params_find(o->over);
    if (!CHECK(sw && s, "%s: out of memory", what))
        return;
    if (!CHECK(usm_sweep_run(sw, p, o) == USM_OK, "%s: %s", what, usm_sweep_message(sw)))
        return;
    int converged = 0, counts[8] = {0};
    for (size_t i = 0; i < usm_sweep_count(sw); ++i) {
        const usm_sweep_point *pt = usm_sweep_point_at(sw, i);
        if (!pt->converged)
            continue;
        ++converged;
        usm_params q = *p;
        *usm_params_field(&q, info) = pt->value;
        const int rc = usm_steady_solve(s, &q, &o->steady);
        const int count = rc == USM_OK ? (int)usm_steady_count(s) : 0;
        counts[count < 7 ? count : 7]++;
        int same = 0;
        for (int k = 0; k < count && !same; ++k)
            same = memcmp(usm_steady_root(s, k)->u, pt->sol.u, sizeof pt->sol.u) == 0;
        /* the branch's root missed by the search counts once more */
        CHECK(pt->roots == count + !same, "%s, %s = %.10g: %d roots in the row, the search finds %d",
              what, o->over, pt->value, pt->roots, count);
        CHECK(same || count == 0, "%s, %s = %.10g: the row's root (theta %.17g) is none of the "
              "search's", what, o->over, pt->value, pt->sol.theta);
    }
    printf("%s: %d of %zu rows converged; full search: %d with 1 root, %d with 3\n", what,
           converged, usm_sweep_count(sw), counts[1], counts[3]);
    CHECK(converged > 0, "%s: no row converged", what);
    usm_steady_free(s);
    usm_sweep_free(sw);
}

int main(void)
{
    const usm_model *m = usm_model_find("3dof");
    usm_params p;
    usm_sweep_options o;
    usm_params_default(&p);
    usm_sweep_options_default(&o);
    o.floquet = 0;
    o.threads = 1;

    /* a pair of roots born inside a span */
    usm_params big = p;
    big.m0 = 50.0;
    o.over = "f";
    o.steady.theta_max = 1.0;
    const int grids[2] = {201, 97};
    for (int g = 0; g < 2; ++g) {
        char what[64];
        o.points = grids[g];
        o.from = 20000;
        o.to = 40000;
        snprintf(what, sizeof what, "m0 = 50, f up, %d points", grids[g]);
        check_rows(what, m, &big, &o);
        o.from = 40000;
        o.to = 20000;
        snprintf(what, sizeof what, "m0 = 50, f down, %d points", grids[g]);
        check_rows(what, m, &big, &o);
    }
    o.threads = 2;
    o.points = 201;
    o.from = 20000;
    o.to = 40000;
    check_rows("m0 = 50, f up, 201 points, 2 threads", m, &big, &o);

    /* the paper's load branch */
    usm_sweep_options_default(&o);
    o.floquet = 0;
    o.over = "T";
    o.from = 0;
    o.to = 0.0076;
    o.points = 301;
    check_rows("3dof T", m, &p, &o);
    return failures ? 1 : 0;
}
