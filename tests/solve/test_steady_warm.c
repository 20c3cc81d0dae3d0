/* The warm start (usm_steady_solve_warm) against the full search
 * (usm_steady_solve, run on a freshly allocated solver each time, so that
 * nothing kept between solves, the tilt grid or the friction analysis, can
 * make the two agree by sharing state):
 *
 * 1. At random parameter points of every model (f, T, m0, F0, c_r, mu0,
 *    kappa scattered over wide ranges around the paper's point) the warm
 *    start from the primary root of a neighbouring point (1 % away) returns
 *    the full search's primary root, bit for bit (and so to 1e-12), or the
 *    same status when none exists.
 * 2. Near folds, where two roots close in on each other: points 1e-8 to
 *    3e-2 relative from the folds that sweeps (continuation) locate in T and
 *    m0 on the negative-load branch (3dof, 4dof), where the full search finds
 *    two or more roots; each root the full search finds is used as the
 *    guess in turn (the non-primary ones are deliberately the wrong branch),
 *    and the warm start must still return the primary.
 * 3. Bad guesses (tilt 0.19 rad near the range's end, tilt 1e-12 below it,
 *    a NaN) still give the full search's answer.
 * 4. The outcomes are exercised: Newton confirmed the primary, converged
 *    to another root, and failed, each at least once.
 * 5. usm_point_evaluate_warm gives the multipliers of usm_point_evaluate,
 *    and a map with warm_start gives the cells and boundaries of the map
 *    without it.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>

#include "usm_map.h"
#include "usm_sweep.h"

#include "check.h"

static int outcomes[4];
static int compared, multi;

/* Deterministic random numbers (check.h); no global state in the library. */
static uint64_t rng = 0x9E3779B97F4A7C15ull;

/* The warm start on `warm` (kept between calls) from guess agrees with a
 * fresh full search at p. */
static void compare(usm_steady *warm, const usm_model *m, const usm_params *p,
                    const usm_steady_solution *guess, const char *what)
{
    usm_steady *full = usm_steady_alloc(m);
    const int sf = usm_steady_solve(full, p, NULL);
    const int sw = usm_steady_solve_warm(warm, p, NULL, guess);
    ++compared;
    ++outcomes[usm_steady_warm(warm)];
    CHECK(sf == sw, "%s %s f=%.9g T=%.9g: full search status %d (%s), warm %d (%s)", m->name,
          what, p->f, p->T, sf, usm_steady_message(full), sw, usm_steady_message(warm));
    if (sf == USM_OK && sw == USM_OK) {
        const usm_steady_solution *a = usm_steady_root(full, 0), *b = usm_steady_root(warm, 0);
        multi += usm_steady_count(full) > 1;
        CHECK(usm_steady_count(warm) == 1, "%s: warm count %zu", m->name, usm_steady_count(warm));
        double rel = 0;
        for (int i = 0; i < m->nu; ++i)
            rel = fmax(rel, fabs(a->u[i] - b->u[i]) / fmax(fabs(a->u[i]), 1e-300));
        CHECK(rel <= 1e-12 && memcmp(a, b, sizeof *a) == 0,
              "%s %s f=%.9g T=%.9g m0=%.9g: warm root (%.15g, %.15g) differs from the full "
              "search's primary (%.15g, %.15g) by %.3g relative (%zu roots)",
              m->name, what, p->f, p->T, p->m0, b->u[0], b->u[1], a->u[0], a->u[1], rel,
              usm_steady_count(full));
    } else if (sf == sw)
        CHECK(strcmp(usm_steady_message(full), usm_steady_message(warm)) == 0,
              "%s: messages differ: \"%s\" / \"%s\"", m->name, usm_steady_message(full),
              usm_steady_message(warm));
    usm_steady_free(full);
}

/* A random point around the paper's, wide enough to leave the existence
 * region and to reach loads with several roots. */
static void random_params(const usm_model *m, usm_params *p)
{
    usm_params_default(p);
    p->f = 30000 + 16000 * rng_uniform(&rng);
    p->T = (rng_uniform(&rng) < 0.2 ? -0.5 : 0.01) * rng_uniform(&rng);
    p->m0 *= exp(2 * (rng_uniform(&rng) - 0.5));
    p->F0 *= exp(rng_uniform(&rng) - 0.5);
    p->c_r *= exp(rng_uniform(&rng) - 0.5);
    if (m->friction) {
        p->mu0 = rng_uniform(&rng) < 0.2 ? 1e4 : 0.1 + 0.5 * rng_uniform(&rng);
        p->kappa *= exp(4 * (rng_uniform(&rng) - 0.5));
    }
}

/* 1, 3: random points, neighbouring and bad guesses. */
static void check_random(const usm_model *m, int n)
{
    usm_steady *warm = usm_steady_alloc(m), *near = usm_steady_alloc(m);
    for (int k = 0; k < n; ++k) {
        usm_params p, q;
        random_params(m, &p);
        q = p;
        q.f *= 1 + 0.02 * (rng_uniform(&rng) - 0.5);
        q.T += 0.01 * (rng_uniform(&rng) - 0.5) * fabs(q.T);
        q.m0 *= 1 + 0.02 * (rng_uniform(&rng) - 0.5);
        if (usm_steady_solve(near, &q, NULL) == USM_OK)
            compare(warm, m, &p, usm_steady_root(near, 0), "neighbour");
        else
            compare(warm, m, &p, NULL, "no guess");
        usm_steady_solution bad;
        memset(&bad, 0, sizeof bad);
        bad.u[0] = k % 3 == 0 ? 0.19 : k % 3 == 1 ? 1e-12 : NAN;
        bad.u[1] = 1.0;
        compare(warm, m, &p, &bad, "bad guess");
    }
    usm_steady_free(warm);
    usm_steady_free(near);
}

/* 2: around the folds a sweep finds, every root as the guess. */
static void check_folds(const char *model, const char *over, double from, double to,
                        const char *set, double val)
{
    const usm_model *m = usm_model_find(model);
    usm_params p;
    char msg[USM_MSG_LEN];
    usm_params_default(&p);
    if (set)
        usm_params_set(&p, set, val, msg);
    usm_sweep_options o;
    usm_sweep_options_default(&o);
    o.over = over;
    o.from = from;
    o.to = to;
    o.points = 41;
    o.floquet = 0;
    o.threads = 1;
    usm_sweep *sw = usm_sweep_alloc(m);
    CHECK(usm_sweep_run(sw, &p, &o) == USM_OK, "%s over %s: sweep failed", model, over);
    int folds = 0;
    usm_steady *warm = usm_steady_alloc(m), *full = usm_steady_alloc(m);
    const usm_param_info *info = usm_params_find(over);
    for (size_t e = 0; e < usm_sweep_event_count(sw); ++e) {
        const usm_sweep_event *ev = usm_sweep_event_at(sw, e);
        if (ev->type != USM_EVENT_FOLD)
            continue;
        ++folds;
        for (int k = 0; k < 40; ++k) {
            const double rel = pow(10.0, -8.0 + 6.5 * rng_uniform(&rng)) * (rng_uniform(&rng) < 0.5 ? -1 : 1);
            usm_params q = p;
            *usm_params_field(&q, info) = ev->value * (1 + rel);
            if (usm_steady_solve(full, &q, NULL) != USM_OK) {
                compare(warm, m, &q, &ev->sol, "fold, no root");
                continue;
            }
            const size_t nr = usm_steady_count(full);
            usm_steady_solution roots[8];
            for (size_t r = 0; r < nr && r < 8; ++r)
                roots[r] = *usm_steady_root(full, r);
            for (size_t r = 0; r < nr && r < 8; ++r)
                compare(warm, m, &q, &roots[r], r == 0 ? "fold, primary guess" : "fold, other root");
        }
    }
    CHECK(folds > 0, "%s over %s: the sweep finds no fold", model, over);
    usm_steady_free(warm);
    usm_steady_free(full);
    usm_sweep_free(sw);
}

/* 5: the point evaluator and the map. */
static void check_point_and_map(const char *model)
{
    const usm_model *m = usm_model_find(model);
    usm_params p, q;
    usm_params_default(&p);
    q = p;
    q.f *= 1.003;
    usm_steady *s = usm_steady_alloc(m);
    usm_floquet *f = usm_floquet_alloc(m);
    usm_point a, b;
    CHECK(usm_point_evaluate(s, f, &p, NULL, NULL, 1, 0.0, NULL, &a) == USM_OK && a.has_floquet,
          "%s: point", model);
    const usm_steady_solution guess = a.sol;
    CHECK(usm_point_evaluate(s, f, &q, NULL, NULL, 1, 0.0, NULL, &a) == USM_OK, "%s", model);
    CHECK(usm_point_evaluate_warm(s, f, &q, NULL, &guess, 1, 0.0, NULL, &b) == USM_OK, "%s",
          model);
    CHECK(a.exists && b.exists && memcmp(&a.sol, &b.sol, sizeof a.sol) == 0 &&
              a.floquet.max_modulus == b.floquet.max_modulus && b.roots == 0,
          "%s: usm_point_evaluate_warm differs from usm_point_evaluate (max modulus %.17g / "
          "%.17g, roots %d)",
          model, a.floquet.max_modulus, b.floquet.max_modulus, b.roots);
    usm_steady_free(s);
    usm_floquet_free(f);

    usm_map_options o;
    usm_map_options_default(&o);
    o.x.points = 7;
    o.y.points = 9;
    o.threads = 1;
    usm_map *cold = usm_map_alloc(m), *hot = usm_map_alloc(m);
    CHECK(usm_map_run(cold, &p, &o) == USM_OK, "%s: map", model);
    o.warm_start = 1;
    CHECK(usm_map_run(hot, &p, &o) == USM_OK, "%s: warm map", model);
    int same = 1;
    for (int i = 0; i < o.x.points; ++i)
        for (int j = 0; j < o.y.points; ++j) {
            const usm_point *x = &usm_map_cell_at(cold, i, j)->point,
                            *y = &usm_map_cell_at(hot, i, j)->point;
            same &= x->exists == y->exists && x->has_floquet == y->has_floquet;
            if (x->exists && y->exists)
                same &= memcmp(&x->sol, &y->sol, sizeof x->sol) == 0 &&
                        x->floquet.max_modulus == y->floquet.max_modulus;
        }
    for (int k = 0; k < USM_MAP_NBOUNDARY; ++k) {
        const usm_map_boundary_kind kind = (usm_map_boundary_kind)k;
        same &= usm_map_boundary_count(cold, kind) == usm_map_boundary_count(hot, kind);
        for (size_t i = 0; same && i < usm_map_boundary_count(cold, kind); ++i)
            same &= usm_map_boundary_at(cold, kind, i)->y == usm_map_boundary_at(hot, kind, i)->y;
    }
    CHECK(same, "%s: the warm-started map differs from the map", model);
    usm_map_free(cold);
    usm_map_free(hot);
}

int main(void)
{
    gsl_set_error_handler_off();
    for (int k = 0; k < USM_NMODELS; ++k)
        check_random(usm_models[k], 150);
    check_folds("3dof", "T", 0.0, -5.0, NULL, 0);
    check_folds("4dof", "T", 0.0, -5.0, "mu0", 1e4);
    check_folds("3dof", "m0", 0.1, 1e-4, "T", -0.5);
    check_point_and_map("3dof");
    check_point_and_map("4dof");
    printf("%d comparisons (%d with several roots): Newton confirmed the primary %d times, "
           "converged to another root %d, failed %d\n",
           compared, multi, outcomes[USM_WARM_CONFIRMED], outcomes[USM_WARM_OTHER_ROOT],
           outcomes[USM_WARM_NEWTON_FAILED]);
    CHECK(multi > 20, "only %d points with several roots", multi);
    CHECK(outcomes[USM_WARM_CONFIRMED] > 0 && outcomes[USM_WARM_OTHER_ROOT] > 0 &&
              outcomes[USM_WARM_NEWTON_FAILED] > 0,
          "an outcome of the warm start was not exercised");
    return failures != 0;
}
