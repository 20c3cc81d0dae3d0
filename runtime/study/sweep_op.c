/* The operating point along a sweep (usm_sweep.h, usm_operating_point.h).
 *
 * At every grid point the rule of usm_operating_point over all roots and
 * their multipliers: where the row has one root (its count is the full
 * search's, sweep_finish_points) and its multipliers, from those and the
 * search's refinement of the root's cell alone (op_one_root: the same
 * decision bit for bit, without a second full search and Floquet); elsewhere
 * usm_point_evaluate_op (the map's point evaluator: the full search, every
 * root's multipliers).  The points are independent, so the worker pool hands
 * them out.  Then, between
 * neighbouring grid points a and b, an operating_point_jump event where:
 *  - both have an operating point, and they are not one branch: the branch of
 *    a's root continued by the engine (sweep_branch_connects) ends (a fold,
 *    the tilt's zero) before b's value or arrives at another root there (every
 *    unknown within 1e-6).  Newton from one grid value's root at the next
 *    (usm_steady_solve_from, both ways, tilt within 1e-6 relative) only where
 *    the continuation is lost: across a coarse grid it misses a root of the
 *    same branch and reported a jump that a finer grid did not;
 *  - one has an operating point and the other does not start from rest;
 *  - one has an operating point and at the other no root is stable, unless
 *    the operating point is the sweep's branch root there (then the branch
 *    loses its stability and the stability_change event says so).
 * A point whose operating point is unknown (several roots and no simulation
 * from rest, or undecided) or that has no solution makes no event: nothing is
 * known there.
 *
 * The jump is located between a and b:
 *  - the motor starts on one side and not on the other, and the start margin
 *    (usm_op_start_margin: smooth in the parameter, zero where the preload's
 *    moment at rest equals the excitation's reach) changes sign between them:
 *    its zero, by Brent on the parameter (core/root.h) to 1e-12 relative;
 *  - otherwise the operating point is a yes/no property ("the same operating
 *    point as at a": the same class and, for a stable root, on one branch with
 *    a's, as above) with no value to
 *    interpolate: bisection (usm_root_bisect) to 1e-10 relative, each step the
 *    rule at the midpoint.  Where the rule is undecided at a midpoint the
 *    value stays the midpoint of the last bracket and the text says "not
 *    located".
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/pool_internal.h"
#include "core/root.h"
#include "point_worker.h"
#include "solve/steady_cell.h"
#include "sweep_branch.h"
#include "sweep_op.h"
#include "usm_map.h"

/* Two tilts are one root when they agree to this, relative. */
#define SAME_ROOT_RTOL 1e-6

typedef struct op_pass {
    const usm_model *m;
    const usm_params *p;
    const usm_sweep_options *opt;
    const usm_param_info *info;
    usm_sweep_point *pts;
    char *msgs; /* per point: why it stopped (USM_EINPUT) */
} op_pass;

static void *op_alloc(void *ctx)
{
    const op_pass *c = ctx;
    return point_worker_alloc(c->m);
}

/* The rule at a grid point with one root whose multipliers the sweep has
 * already computed (the row's root and multipliers): what
 * usm_point_evaluate_op decides there, without its full search and
 * multipliers again.  The root set is the full search's bit for bit
 * (usm_steady_solve_cell: the search's refinement of the cell holding the
 * row's root; the row's count, 1, is the search's: sweep_finish_points).
 * 1 and pt->op set; 0 where the point needs the full evaluation; -1 on bad
 * options (USM_EINPUT, message into msg). */
static int op_one_root(op_pass *c, point_worker *w, usm_sweep_point *pt, const usm_params *q,
                       char *msg)
{
    if (!pt->converged || pt->roots != 1 || !pt->has_floquet ||
        !isfinite(pt->floquet.max_modulus) ||
        usm_steady_solve_cell(w->steady, q, &c->opt->steady, pt->sol.u) != USM_OK ||
        usm_steady_count(w->steady) != 1 ||
        memcmp(usm_steady_root(w->steady, 0)->u, pt->sol.u, sizeof pt->sol.u) != 0)
        return 0;
    usm_point_op *op = &pt->op;
    usm_op_result res;
    memset(op, 0, sizeof *op);
    op->index = -1;
    op->stable_roots = pt->floquet.stable != 0;
    const int orc = usm_operating_point(c->m, q, w->steady, &pt->floquet, &c->opt->op, &res);
    if (orc == USM_EINPUT) {
        snprintf(msg, USM_MSG_LEN, "%s", res.message);
        return -1;
    }
    point_op_classify(op, orc, &res, w->steady, NULL, &pt->floquet);
    pt->has_op = 1;
    return 1;
}

static int op_task(void *ctx, void *state, size_t i)
{
    op_pass *c = ctx;
    point_worker *w = state;
    usm_sweep_point *pt = &c->pts[i];
    usm_params q = *c->p;
    usm_point res;
    *usm_params_field(&q, c->info) = pt->value;
    char why[USM_MSG_LEN];
    const int one = op_one_root(c, w, pt, &q, why);
    if (one < 0) {
        snprintf(c->msgs + i * USM_MSG_LEN, USM_MSG_LEN, "operating point at %s = %g: %.180s",
                 c->info->name, pt->value, why);
        return USM_EINPUT;
    }
    if (one > 0)
        return USM_OK;
    if (usm_point_evaluate_op(w->steady, w->floquet, c->m, &q, c->opt->t0,
                              &c->opt->floquet_options, &c->opt->op, &res) != USM_OK) {
        snprintf(c->msgs + i * USM_MSG_LEN, USM_MSG_LEN, "operating point at %s = %g: %.180s",
                 c->info->name, pt->value, res.error);
        return USM_EINPUT;
    }
    pt->op = res.op;
    pt->has_op = 1;
    return USM_OK;
}

/* Whether root `from` (at a's parameters) continues to root `to` at value. */
static int continues(usm_steady *s, const usm_params *p, const usm_param_info *info,
                     double value, const usm_steady_solution *from,
                     const usm_steady_solution *to)
{
    usm_params q = *p;
    *usm_params_field(&q, info) = value;
    if (usm_steady_solve_from(s, &q, from->u) != USM_OK || usm_steady_count(s) == 0)
        return 0;
    const double th = usm_steady_root(s, 0)->theta;
    return fabs(th - to->theta) <= SAME_ROOT_RTOL * fmax(fabs(th), fabs(to->theta));
}

/* Whether root `from` at va and root `to` at vb lie on one stationary branch:
 * the branch of `from` continued to vb arrives at `to`.  Where the
 * continuation is lost, Newton from either root at the other's value reaches
 * it. */
static int one_branch(usm_steady *s, const usm_model *m, const usm_params *p,
                      const usm_param_info *info, double va, const usm_steady_solution *from,
                      double vb, const usm_steady_solution *to)
{
    const int c = sweep_branch_connects(m, p, info, va, from->u, vb, to->u);
    if (c >= 0)
        return c;
    return continues(s, p, info, vb, from, to) && continues(s, p, info, va, to, from);
}

/* Whether the operating point of pt is the sweep's branch root there. */
static int on_branch(const usm_sweep_point *pt)
{
    return pt->converged &&
           fabs(pt->op.sol.theta - pt->sol.theta) <=
               SAME_ROOT_RTOL * fmax(fabs(pt->op.sol.theta), fabs(pt->sol.theta));
}

static int decided(const usm_point_op *op)
{
    return op->cls == USM_POINT_OP_STABLE || op->cls == USM_POINT_OP_NO_STABLE_ROOT ||
           op->cls == USM_POINT_OP_DOES_NOT_START;
}

/* "root #2 (theta 8.6e-05 rad)" or the class. */
static void op_text(const usm_point_op *op, char buf[96])
{
    if (op->cls == USM_POINT_OP_STABLE)
        snprintf(buf, 96, "root #%d (theta %.4g rad, rotor speed %.4g 1/s)", op->index + 1,
                 op->sol.theta, op->sol.rotor_speed);
    else
        snprintf(buf, 96, "none (%s)", usm_point_op_class_name(op->cls));
}

/* Relative accuracy of a located jump. */
#define JUMP_RTOL 1e-10

typedef struct jump_loc {
    const usm_model *m;
    usm_params q;
    const usm_param_info *info;
    const usm_sweep_options *opt;
    point_worker *w;
    usm_steady *s;           /* continues()'s polish */
    const usm_point_op *ref; /* the operating point on the side where the indicator is 1 */
    double ref_value;
    int failed;
} jump_loc;

static double margin_at(double value, void *ctx)
{
    jump_loc *j = ctx;
    double mg;
    *usm_params_field(&j->q, j->info) = value;
    return usm_op_start_margin(j->m, &j->q, &mg) == USM_OK ? mg : NAN;
}

/* 1: the operating point at value is ref's, 0: it is not, or
 * USM_ROOT_UNDEFINED / USM_ROOT_FAILED. */
static int same_op_at(double value, void *ctx)
{
    jump_loc *j = ctx;
    usm_point res;
    *usm_params_field(&j->q, j->info) = value;
    if (usm_point_evaluate_op(j->w->steady, j->w->floquet, j->m, &j->q, j->opt->t0,
                              &j->opt->floquet_options, &j->opt->op, &res) != USM_OK)
        return USM_ROOT_FAILED;
    if (!res.has_op || !decided(&res.op))
        return USM_ROOT_UNDEFINED;
    if (res.op.cls != j->ref->cls)
        return 0;
    if (res.op.cls != USM_POINT_OP_STABLE)
        return 1;
    return one_branch(j->s, j->m, &j->q, j->info, j->ref_value, &j->ref->sol, value,
                      &res.op.sol);
}

/* Where the operating point changes between grid points a and b (a jump
 * between them): 1 and *at located, 0 and *at the midpoint; *how says by
 * what. */
static int locate_jump(jump_loc *j, const usm_sweep_point *a, const usm_sweep_point *b,
                       double *at, const char **how)
{
    *at = 0.5 * (a->value + b->value);
    *how = "not located: the rule is undecided";
    const int start_a = a->op.cls == USM_POINT_OP_DOES_NOT_START,
              start_b = b->op.cls == USM_POINT_OP_DOES_NOT_START;
    if (start_a != start_b) {
        const double ma = margin_at(a->value, j), mb = margin_at(b->value, j);
        usm_root *r = usm_root_alloc();
        const usm_root_stop stop = {0.0, 1e-12, 200};
        double x;
        if (r && isfinite(ma) && isfinite(mb) && (ma <= 0) != (mb <= 0) &&
            usm_root_brent(r, margin_at, j, a->value, b->value, ma, mb, &stop, &x) == 0) {
            usm_root_free(r);
            *at = x;
            *how = "located: the start margin is 0";
            return 1;
        }
        usm_root_free(r);
    }
    j->ref = &a->op;
    j->ref_value = a->value;
    double x;
    const double tol = JUMP_RTOL * fmax(fabs(a->value), fabs(b->value));
    const int rc = usm_root_bisect(same_op_at, j, a->value, 1, b->value, tol, 200, &x);
    if (rc == 1) {
        *at = x;
        *how = "located by bisection";
        return 1;
    }
    return 0;
}

static int jump_events(const usm_model *m, const usm_params *p, const usm_sweep_options *opt,
                       const usm_param_info *info, const usm_sweep_point *pts, size_t n,
                       const sweep_sink *sink, char msg[USM_MSG_LEN])
{
    usm_steady *s = usm_steady_alloc(m);
    point_worker *w = point_worker_alloc(m);
    if (!s || !w) {
        usm_steady_free(s);
        point_worker_free(w);
        snprintf(msg, USM_MSG_LEN, "out of memory");
        return USM_EFAILED;
    }
    jump_loc loc = {m, *p, info, opt, w, s, NULL, 0.0, 0};
    for (size_t i = 0; i + 1 < n; ++i) {
        const usm_sweep_point *a = &pts[i], *b = &pts[i + 1];
        if (!a->has_op || !b->has_op || !decided(&a->op) || !decided(&b->op))
            continue;
        int jump = 0;
        if (a->op.cls == USM_POINT_OP_STABLE && b->op.cls == USM_POINT_OP_STABLE)
            jump = !one_branch(s, m, p, info, a->value, &a->op.sol, b->value, &b->op.sol);
        else if (a->op.cls == USM_POINT_OP_STABLE || b->op.cls == USM_POINT_OP_STABLE) {
            const usm_sweep_point *on = a->op.cls == USM_POINT_OP_STABLE ? a : b;
            const usm_sweep_point *off = on == a ? b : a;
            jump = off->op.cls == USM_POINT_OP_DOES_NOT_START || !on_branch(on);
        }
        if (!jump)
            continue;
        usm_sweep_event e;
        char va[64], vb[64], ta[96], tb[96];
        const char *how;
        double at;
        memset(&e, 0, sizeof e);
        e.type = USM_EVENT_OPERATING_POINT_JUMP;
        locate_jump(&loc, a, b, &at, &how);
        e.value = at;
        e.has_sol = b->op.cls == USM_POINT_OP_STABLE;
        if (e.has_sol)
            e.sol = b->op.sol;
        op_text(&a->op, ta);
        op_text(&b->op, tb);
        snprintf(e.what, USM_MSG_LEN,
                 "the operating point moves between %.26s and %.26s (%.36s): %.58s -> %.58s",
                 sweep_value_text(info, a->value, va), sweep_value_text(info, b->value, vb), how,
                 ta, tb);
        if (sink->event(sink->ctx, &e) != 0) {
            usm_steady_free(s);
            point_worker_free(w);
            snprintf(msg, USM_MSG_LEN, "out of memory for the events");
            return USM_EFAILED;
        }
    }
    usm_steady_free(s);
    point_worker_free(w);
    return USM_OK;
}

int sweep_operating_points(const usm_model *m, const usm_params *p,
                           const usm_sweep_options *opt, usm_sweep_point *pts, size_t n,
                           const sweep_sink *sink, char msg[USM_MSG_LEN])
{
    op_pass c = {m, p, opt, usm_params_find(opt->over), pts, calloc(n ? n : 1, USM_MSG_LEN)};
    if (!c.msgs) {
        snprintf(msg, USM_MSG_LEN, "out of memory");
        return USM_EFAILED;
    }
    pool_job job = {n, opt->threads, &c, op_alloc, point_worker_free, op_task, NULL};
    int status = pool_run(&job, msg);
    if (status == USM_EINPUT)
        for (size_t i = 0; i < n; ++i)
            if (c.msgs[i * USM_MSG_LEN]) {
                snprintf(msg, USM_MSG_LEN, "%s", c.msgs + i * USM_MSG_LEN);
                break;
            }
    free(c.msgs);
    if (status == USM_OK)
        status = jump_events(m, p, opt, c.info, pts, n, sink, msg);
    return status;
}
