/* Stability maps (usm_map.h), checked against computations that do not use
 * the map:
 *
 * 1. Every cell of a small f x T map equals usm_steady_solve (existence, root
 *    count, tilt) and usm_floquet_compute on its primary root, bit for bit;
 *    1 and 3 worker threads give the same cells.
 * 2. Each located boundary point is a change of its indicator: direct solves
 *    just below and above it (1e-6 of the y range) are on opposite sides.
 * 3. A cell whose multipliers fail (d_R = 1e12) is marked with the reason and
 *    the others keep theirs; the run succeeds.
 * 4. Bad options: USM_EINPUT with a message naming the field.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <gsl/gsl_errno.h>

#include "usm_map.h"

#include "check.h"

static usm_map *run(const char *model, const usm_params *p, const usm_map_options *o)
{
    usm_map *map = usm_map_alloc(usm_model_find(model));
    const int rc = usm_map_run(map, p, o);
    CHECK(rc == USM_OK, "map: status %d: %s", rc, usm_map_message(map));
    return map;
}

static void check_cells(void)
{
    usm_params p;
    usm_map_options o;
    usm_params_default(&p);
    usm_map_options_default(&o);
    o.x = (usm_map_axis){"f", 34000, 40000, 4};
    o.y = (usm_map_axis){"T", 0, 0.008, 5};
    o.threads = 1;
    usm_map *one = run("3dof", &p, &o);
    o.threads = 3;
    usm_map *three = run("3dof", &p, &o);
    usm_steady *s = usm_steady_alloc(usm_model_find("3dof"));
    usm_floquet *f = usm_floquet_alloc(usm_model_find("3dof"));
    int cells = 0, solved = 0;
    for (int j = 0; j < o.y.points; ++j)
        for (int i = 0; i < o.x.points; ++i) {
            const usm_map_cell *c = usm_map_cell_at(one, i, j), *d = usm_map_cell_at(three, i, j);
            usm_params q = p;
            q.f = usm_map_axis_value(&o.x, i);
            q.T = usm_map_axis_value(&o.y, j);
            const int has = usm_steady_solve(s, &q, NULL) == USM_OK;
            CHECK(c && d && c->x == q.f && c->y == q.T, "cell (%d, %d): coordinates", i, j);
            if (!c || !d)
                continue;
            ++cells;
            CHECK(c->point.exists == has, "f = %g, T = %g: exists %d, steady %d", q.f, q.T,
                  c->point.exists, has);
            CHECK(memcmp(&c->point, &d->point, sizeof c->point) == 0,
                  "f = %g, T = %g: 1 and 3 threads differ", q.f, q.T);
            if (!has || !c->point.exists) {
                CHECK(c->point.error[0] != '\0', "f = %g, T = %g: no reason given", q.f, q.T);
                continue;
            }
            usm_floquet_result r;
            CHECK(c->point.roots == (int)usm_steady_count(s) &&
                      c->point.sol.theta == usm_steady_root(s, 0)->theta,
                  "f = %g, T = %g: root differs from usm_steady_solve", q.f, q.T);
            CHECK(usm_floquet_compute(f, &q, usm_steady_root(s, 0), 0.0, NULL, &r) == USM_OK &&
                      c->point.has_floquet && r.max_modulus == c->point.floquet.max_modulus,
                  "f = %g, T = %g: multipliers differ from usm_floquet_compute", q.f, q.T);
            ++solved;
        }
    printf("map cells: %d of %d solved, each equal to usm_steady_solve + usm_floquet_compute, "
           "1 and 3 threads identical\n",
           solved, cells);

    /* 2. boundaries */
    const double dy = 1e-6 * (o.y.to - o.y.from);
    int located = 0;
    for (int k = 0; k < USM_MAP_NBOUNDARY; ++k)
        for (size_t q = 0; q < usm_map_boundary_count(one, (usm_map_boundary_kind)k); ++q) {
            const usm_map_boundary_point *b = usm_map_boundary_at(one, (usm_map_boundary_kind)k, q);
            int ind[2];
            for (int side = 0; side < 2; ++side) {
                usm_params r = p;
                usm_point pt;
                r.f = b->x;
                r.T = b->y + (side ? dy : -dy);
                usm_point_evaluate(s, f, &r, NULL, NULL, 1, 0.0, NULL, &pt);
                ind[side] = usm_map_indicator((usm_map_boundary_kind)k, &pt);
            }
            CHECK(ind[0] >= 0 && ind[1] >= 0 && ind[0] != ind[1],
                  "%s boundary at f = %g, T = %.9g: indicator %d below, %d above",
                  usm_map_boundary_name((usm_map_boundary_kind)k), b->x, b->y, ind[0], ind[1]);
            ++located;
        }
    CHECK(located > 0, "no boundary located");
    printf("map boundaries: %d points, each a change of its indicator within 1e-6 of the range\n",
           located);
    usm_floquet_free(f);
    usm_steady_free(s);
    usm_map_free(one);
    usm_map_free(three);
}

static void check_floquet_failure(void)
{
    usm_params p;
    usm_map_options o;
    usm_params_default(&p);
    usm_map_options_default(&o);
    o.x = (usm_map_axis){"d_R", 0.1632, 1e12, 2};
    o.y = (usm_map_axis){"T", 0, 0.001, 2};
    o.boundaries = 0;
    o.floquet.method = USM_FLOQUET_VARIATIONAL; /* CVODES gives up at d_R = 1e12 */
    usm_map *map = run("3dof", &p, &o);
    const usm_map_cell *ok = usm_map_cell_at(map, 0, 0), *bad = usm_map_cell_at(map, 1, 0);
    CHECK(ok && ok->point.has_floquet, "d_R = 0.1632: no multipliers");
    CHECK(bad && bad->point.exists && !bad->point.has_floquet &&
              strncmp(bad->point.error, "floquet:", 8) == 0,
          "d_R = 1e12: want a marked Floquet failure");
    CHECK(usm_map_floquet_failures(map) == 2, "floquet failures %zu, want 2",
          usm_map_floquet_failures(map));
    if (bad)
        printf("map: a failed point is marked and the map goes on: %s\n", bad->point.error);
    usm_map_free(map);
}

static void expect_einput(const usm_map_options *o, const char *field)
{
    usm_params p;
    usm_params_default(&p);
    usm_map *map = usm_map_alloc(usm_model_find("3dof"));
    const int rc = usm_map_run(map, &p, o);
    CHECK(rc == USM_EINPUT && strstr(usm_map_message(map), field),
          "want USM_EINPUT naming %s, got %d: %s", field, rc, usm_map_message(map));
    usm_map_free(map);
}

static void check_bad_options(void)
{
    usm_map_options d, o;
    usm_map_options_default(&d);
    o = d;
    o.x.points = 1;
    expect_einput(&o, "x-points");
    o = d;
    o.y.name = "nosuch";
    expect_einput(&o, "y:");
    o = d;
    o.y.name = "f";
    expect_einput(&o, "y:");
    o = d;
    o.threads = 0;
    expect_einput(&o, "threads");
    o = d;
    o.x = (usm_map_axis){"f", -1000, 1000, 3};
    expect_einput(&o, "f:");
}

int main(void)
{
    gsl_set_error_handler_off();
    check_cells();
    check_floquet_failure();
    check_bad_options();
    if (failures) {
        printf("%d check(s) failed\n", failures);
        return 1;
    }
    printf("all map checks passed\n");
    return 0;
}
