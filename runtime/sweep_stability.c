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

#include <gsl/gsl_errno.h>
#include <gsl/gsl_roots.h>

#include "pool_internal.h"
#include "sweep_internal.h"
#include "usm_map.h"

/* The multipliers of grid point i, a task of the shared worker pool. */
static void *floquet_alloc(void *ctx)
{
    usm_sweep *s = ctx;
    return usm_floquet_alloc(s->m);
}

static void floquet_free(void *state) { usm_floquet_free(state); }

static int point_task(void *ctx, void *state, size_t i)
{
    usm_sweep *s = ctx;
    usm_sweep_point *pt = &s->pts[i];
    usm_point res;
    if (!pt->converged)
        return 0;
    usm_params q = *s->floquet_params;
    *usm_params_field(&q, s->br.info) = pt->value;
    /* one point whose multipliers fail is marked and the others go on: the
     * stationary solution there is still valid */
    if (usm_point_evaluate(NULL, state, &q, NULL, &pt->sol, 1, s->opt->t0, &res) == USM_OK &&
        res.has_floquet) {
        pt->floquet = res.floquet;
        pt->has_floquet = 1;
    } else
        snprintf(pt->floquet_error, USM_MSG_LEN, "%s", res.error);
    return 0;
}

static void point_done(void *ctx, size_t i)
{
    usm_sweep *s = ctx;
    if (!s->pts[i].converged)
        return;
    ++s->floquet_done;
    sweep_progress(s, s->progress_split + (1.0 - s->progress_split) * (double)s->floquet_done /
                                              (double)s->floquet_total);
}

int sweep_floquet_points(usm_sweep *s, const usm_params *p, const usm_sweep_options *opt)
{
    s->floquet_params = p;
    s->floquet_done = s->floquet_total = 0;
    for (size_t i = 0; i < s->npts; ++i)
        s->floquet_total += s->pts[i].converged != 0;
    if (s->floquet_total == 0)
        return USM_OK;
    pool_job job = {s->npts, opt->threads, s, floquet_alloc, floquet_free, point_task, point_done};
    return pool_run(&job, s->msg);
}

/* ---- stability changes ----------------------------------------------------------- */

typedef struct crossing {
    usm_sweep *s;
    const usm_params *p;
    const usm_sweep_options *opt;
    usm_floquet *f;
    size_t a, b;
    usm_steady_solution sol;
    usm_floquet_result res;
    int failed;
} crossing;

static double margin(double value, void *ctx)
{
    crossing *c = ctx;
    usm_params q = *c->p;
    if (c->failed || sweep_solve_between(c->s, c->p, c->a, c->b, value, &c->sol) != 0) {
        c->failed = 1;
        return 0.0;
    }
    *usm_params_field(&q, c->s->br.info) = value;
    usm_point pt;
    if (usm_point_evaluate(NULL, c->f, &q, NULL, &c->sol, 1, c->opt->t0, &pt) != USM_OK ||
        !pt.has_floquet) {
        c->failed = 1;
        return 0.0;
    }
    c->res = pt.floquet;
    return c->res.max_modulus - 1.0;
}

static int locate(crossing *c, gsl_root_fsolver *brent, double *value)
{
    const double va = c->s->pts[c->a].value, vb = c->s->pts[c->b].value;
    double lo = fmin(va, vb), hi = fmax(va, vb);
    gsl_function F = {margin, c};
    if (gsl_root_fsolver_set(brent, &F, lo, hi) != GSL_SUCCESS || c->failed)
        return -1;
    for (int it = 0; it < 100; ++it) {
        if (gsl_root_fsolver_iterate(brent) != GSL_SUCCESS || c->failed)
            return -1;
        lo = gsl_root_fsolver_x_lower(brent);
        hi = gsl_root_fsolver_x_upper(brent);
        if (gsl_root_test_interval(lo, hi, 1e-12 * fabs(vb - va), 1e-10) == GSL_SUCCESS)
            break;
    }
    *value = gsl_root_fsolver_root(brent);
    /* the solution stored with the event is the one at the reported value */
    margin(*value, c);
    return c->failed ? -1 : 0;
}

int sweep_stability_events(usm_sweep *s, const usm_params *p, const usm_sweep_options *opt)
{
    crossing c;
    memset(&c, 0, sizeof c);
    c.s = s;
    c.p = p;
    c.opt = opt;
    c.f = usm_floquet_alloc(s->m);
    gsl_root_fsolver *brent = gsl_root_fsolver_alloc(gsl_root_fsolver_brent);
    int status = USM_OK;
    char v[64];
    if (!c.f || !brent) {
        snprintf(s->msg, USM_MSG_LEN, "out of memory");
        status = USM_EFAILED;
        goto done;
    }
    for (size_t i = 0; i + 1 < s->npts; ++i) {
        const usm_sweep_point *pa = &s->pts[i], *pb = &s->pts[i + 1];
        if (!pa->has_floquet || !pb->has_floquet || pa->floquet.stable == pb->floquet.stable)
            continue;
        double value;
        c.a = i;
        c.b = i + 1;
        c.failed = 0;
        const int located = locate(&c, brent, &value) == 0;
        if (!located) /* still worth reporting: between two grid points */
            value = pa->value + (1.0 - pa->floquet.max_modulus) /
                                    (pb->floquet.max_modulus - pa->floquet.max_modulus) *
                                    (pb->value - pa->value);
        const int stable_dir = (pb->value > pa->value) == (pa->floquet.stable != 0) ? -1 : 1;
        if (sweep_add_event(s, USM_EVENT_STABILITY_CHANGE, value, located ? &c.sol : NULL,
                            "the largest non-cyclic Floquet multiplier crosses |lambda| = 1 "
                            "(t0 = %g s) at %s: stable %s it, unstable %s%s",
                            opt->t0, sweep_value_text(s, value, v), stable_dir > 0 ? "above" : "below",
                            stable_dir > 0 ? "below" : "above",
                            located ? "" : " (interpolated between grid points)") != 0) {
            snprintf(s->msg, USM_MSG_LEN, "out of memory");
            status = USM_EFAILED;
            goto done;
        }
    }
done:
    usm_floquet_free(c.f);
    if (brent)
        gsl_root_fsolver_free(brent);
    return status;
}
