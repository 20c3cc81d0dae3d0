/* Floquet multipliers along a sweep, and where stability changes.
 *
 * The multipliers of different grid points are independent: the library's one
 * worker pool (pool.c) hands them out, each worker with its own usm_floquet,
 * and usm_point_evaluate (usm_map.h), the one point evaluator, computes them.
 *
 * A stability change is a sign change of g(lambda) = max non-cyclic |multiplier| - 1
 * between neighbouring converged grid points; Brent's method on lambda locates
 * it, each evaluation solving the stationary equations on the branch (from the
 * neighbours' interpolation) and computing the multipliers.  The location is as
 * accurate as the multipliers (CVODES rtol 1e-8 gives max_modulus to ~1e-7).
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/pool_internal.h"
#include "core/root.h"
#include "sweep_stability.h"
#include "usm_map.h"

#define TWO_PI 6.283185307179586476925286766559

/* ---- the multipliers at the grid points --------------------------------------------- */

typedef struct floquet_pass {
    const usm_model *m;
    const usm_params *p;
    const usm_sweep_options *opt;
    const usm_param_info *info;
    usm_sweep_point *pts;
    const sweep_sink *sink;
    size_t done, total;
} floquet_pass;

static void *floquet_alloc(void *ctx)
{
    const floquet_pass *fp = ctx;
    return usm_floquet_alloc(fp->m);
}

static void floquet_free(void *state) { usm_floquet_free(state); }

/* The multipliers of grid point i, a task of the shared worker pool. */
static int point_task(void *ctx, void *state, size_t i)
{
    floquet_pass *fp = ctx;
    usm_sweep_point *pt = &fp->pts[i];
    usm_point res;
    if (!pt->converged)
        return 0;
    usm_params q = *fp->p;
    *usm_params_field(&q, fp->info) = pt->value;
    /* one point whose multipliers fail is marked and the others go on: the
     * stationary solution there is still valid */
    if (usm_point_evaluate(NULL, state, &q, NULL, &pt->sol, 1, fp->opt->t0, &fp->opt->floquet_options, &res) == USM_OK &&
        res.has_floquet) {
        pt->floquet = res.floquet;
        pt->has_floquet = 1;
    } else
        snprintf(pt->floquet_error, USM_MSG_LEN, "%s", res.error);
    return 0;
}

static void point_done(void *ctx, size_t i)
{
    floquet_pass *fp = ctx;
    if (!fp->pts[i].converged)
        return;
    ++fp->done;
    if (fp->sink->progress)
        fp->sink->progress(fp->sink->ctx, (double)fp->done / (double)fp->total);
}

int sweep_floquet_points(const usm_model *m, const usm_params *p, const usm_sweep_options *opt,
                         usm_sweep_point *pts, size_t n, const sweep_sink *sink,
                         char msg[USM_MSG_LEN])
{
    floquet_pass fp = {m, p, opt, usm_params_find(opt->over), pts, sink, 0, 0};
    for (size_t i = 0; i < n; ++i)
        fp.total += pts[i].converged != 0;
    if (fp.total == 0)
        return USM_OK;
    pool_job job = {n, opt->threads, &fp, floquet_alloc, floquet_free, point_task, point_done};
    return pool_run(&job, msg);
}

/* ---- stability changes ----------------------------------------------------------- */

typedef struct crossing {
    const usm_params *p;
    const usm_sweep_options *opt;
    const usm_param_info *info;
    usm_steady *steady;
    usm_floquet *f;
    const usm_sweep_point *pa, *pb;
    usm_steady_solution sol;
    usm_floquet_result res;
    int failed;
} crossing;

/* The stationary solution at `value` on the branch between the converged
 * points pa and pb: polished from their interpolation.  0 or -1. */
static int solve_between(crossing *c, double value)
{
    const usm_sweep_point *pa = c->pa, *pb = c->pb;
    const double w = (value - pa->value) / (pb->value - pa->value);
    double u[USM_MAX_NU] = {0};
    for (int i = 0; i < USM_MAX_NU; ++i) {
        double ub = pb->sol.u[i];
        /* alpha is stored in [0, 2 pi): undo a wrap between the two points */
        if (i == 1 && fabs(ub - pa->sol.u[i]) > 0.5 * TWO_PI)
            ub += ub > pa->sol.u[i] ? -TWO_PI : TWO_PI;
        u[i] = pa->sol.u[i] + w * (ub - pa->sol.u[i]);
    }
    usm_params q = *c->p;
    *usm_params_field(&q, c->info) = value;
    if (usm_steady_solve_from(c->steady, &q, u) != USM_OK)
        return -1;
    c->sol = *usm_steady_root(c->steady, 0);
    return 0;
}

/* max |multiplier| - 1 at value; NaN when the solution or its multipliers
 * fail (c->failed). */
static double margin(double value, void *ctx)
{
    crossing *c = ctx;
    usm_params q = *c->p;
    if (c->failed || solve_between(c, value) != 0) {
        c->failed = 1;
        return NAN;
    }
    *usm_params_field(&q, c->info) = value;
    usm_point pt;
    if (usm_point_evaluate(NULL, c->f, &q, NULL, &c->sol, 1, c->opt->t0, &c->opt->floquet_options, &pt) != USM_OK ||
        !pt.has_floquet) {
        c->failed = 1;
        return NAN;
    }
    c->res = pt.floquet;
    return c->res.max_modulus - 1.0;
}

/* The stability change between c->pa and c->pb by the shared locator
 * (core/root.h); the margin at the grid points is evaluated again (the
 * polished solution there need not be the stored one to the last bit). */
static int locate(crossing *c, usm_root *root, double *value)
{
    const double va = c->pa->value, vb = c->pb->value;
    const usm_root_stop stop = {1e-12 * fabs(vb - va), 1e-10, 100};
    if (usm_root_brent_eval(root, margin, c, fmin(va, vb), fmax(va, vb), &stop, value) != 0)
        return -1;
    /* the solution stored with the event is the one at the reported value */
    margin(*value, c);
    return c->failed ? -1 : 0;
}

int sweep_stability_events(const usm_model *m, const usm_params *p,
                           const usm_sweep_options *opt, const usm_sweep_point *pts, size_t n,
                           const sweep_sink *sink, char msg[USM_MSG_LEN])
{
    crossing c;
    memset(&c, 0, sizeof c);
    c.p = p;
    c.opt = opt;
    c.info = usm_params_find(opt->over);
    c.steady = usm_steady_alloc(m);
    c.f = usm_floquet_alloc(m);
    usm_root *root = usm_root_alloc();
    int status = USM_OK;
    char v[64];
    if (!c.steady || !c.f || !root) {
        snprintf(msg, USM_MSG_LEN, "out of memory");
        status = USM_EFAILED;
        goto done;
    }
    for (size_t i = 0; i + 1 < n; ++i) {
        const usm_sweep_point *pa = &pts[i], *pb = &pts[i + 1];
        if (!pa->has_floquet || !pb->has_floquet || pa->floquet.stable == pb->floquet.stable)
            continue;
        double value;
        c.pa = pa;
        c.pb = pb;
        c.failed = 0;
        const int located = locate(&c, root, &value) == 0;
        if (!located) /* still worth reporting: between two grid points */
            value = pa->value + (1.0 - pa->floquet.max_modulus) /
                                    (pb->floquet.max_modulus - pa->floquet.max_modulus) *
                                    (pb->value - pa->value);
        const int stable_dir = (pb->value > pa->value) == (pa->floquet.stable != 0) ? -1 : 1;
        usm_sweep_event e;
        memset(&e, 0, sizeof e);
        e.type = USM_EVENT_STABILITY_CHANGE;
        e.value = value;
        if (located) {
            e.sol = c.sol;
            e.has_sol = 1;
        }
        snprintf(e.what, USM_MSG_LEN,
                 "the largest non-cyclic Floquet multiplier crosses |lambda| = 1 "
                 "(t0 = %g s) at %s: stable %s it, unstable %s%s",
                 opt->t0, sweep_value_text(c.info, value, v), stable_dir > 0 ? "above" : "below",
                 stable_dir > 0 ? "below" : "above",
                 located ? "" : " (interpolated between grid points)");
        if (sink->event(sink->ctx, &e) != 0) {
            snprintf(msg, USM_MSG_LEN, "out of memory");
            status = USM_EFAILED;
            goto done;
        }
    }
done:
    usm_steady_free(c.steady);
    usm_floquet_free(c.f);
    usm_root_free(root);
    return status;
}
