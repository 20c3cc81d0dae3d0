/* The stationary solution followed in one parameter, posed to the
 * continuation engine (cont/, usm_cont.h), and the events on its branch.
 *
 * The zero problem: x = (u, lambda), F(x) = r(u; lambda) (steady_residual),
 * its Jacobian [r_u, r_lambda] from steady_jacobian and the swept column of
 * steady_jacobian_params; the engine works in z = (u / su, lambda / Lambda)
 * (the components differ by ten orders of magnitude: theta ~ 1e-4 rad,
 * f ~ 4e4 Hz), the scales growing with the unknowns (rescale).  The engine
 * predicts, corrects, controls the step and locates the zeros of the test
 * functions on each step's arc to 1e-15 in the scaled arclength:
 *   fold      its own (d lambda/ds; lambda is extremal there, so its error is
 *             quadratic in the error of s); the branch ends there
 *   boundary  theta - theta_min, theta_max - theta: the branch ends there
 *   stick     |F_t| - mu0 F_n (stick models)
 *   stall     the rotor speed phidot_R (slip models), then Newton with it
 *             fixed at 0 exactly
 *   monitors  y - level for each level, dy/ds for extrema
 * This file keeps what is the sweep's own: the grid values landed on (the
 * arc's point at the value's share of the step, then Newton with lambda
 * fixed), the full searches where a branch starts or is lost, the tilt's
 * zero and the friction saturation (Newton with theta or the rotor speed
 * fixed: usm_cont_correct_fixed), and the points and events passed on.
 */
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/dense.h"
#include "core/grow.h"
#include "solve/steady_cell.h"
#include "sweep_branch.h"

#define H_MAX 0.05            /* longest step: 1/20 of the sweep range in lambda */
#define H_MIN 1e-13
/* Once F_t / F_n is this close to the friction law's supremum the saturation
 * point is computed directly instead of following the diverging rotor speed. */
#define SAT_TRIGGER 0.999
#define V_HUGE 1e15           /* slip velocity [m/s] that stands for infinity */
#define TWO_PI 6.283185307179586476925286766559

int sweep_branch_alloc(sweep_branch *b, const usm_model *m)
{
    memset(b, 0, sizeof *b);
    b->m = m;
    b->nu = m->nu;
    b->n = m->nu + 1;
    b->rotor = m->friction ? m->u_phidot_R : -1;
    b->steady = usm_steady_alloc(m);
    return b->steady ? 0 : -1;
}

void sweep_branch_free(sweep_branch *b)
{
    usm_cont_free(b->cont);
    free(b->tests);
    usm_steady_free(b->steady);
    free(b->pev);
    free(b->ppt);
    memset(b, 0, sizeof *b);
}

/* ---- what a step finds, passed on once the step is accepted --------------------- */

struct sweep_pending_point {
    size_t i;
    int has_sol, roots;
    usm_steady_solution sol;
    char error[USM_MSG_LEN];
};

static void emit_point(sweep_branch *b, size_t i, const usm_steady_solution *sol, int roots,
                       const char *error)
{
    if (usm_grow((void **)&b->ppt, &b->pptcap, b->nppt + 1, sizeof *b->ppt) != 0) {
        b->oom = 1;
        return;
    }
    struct sweep_pending_point *pp = &b->ppt[b->nppt++];
    pp->i = i;
    pp->has_sol = sol != NULL;
    if (sol)
        pp->sol = *sol;
    pp->roots = roots;
    snprintf(pp->error, USM_MSG_LEN, "%s", error ? error : "");
}

/* A new pending event, or NULL when out of memory. */
static usm_sweep_event *emit_event(sweep_branch *b, usm_event_type type, double value,
                                   const usm_steady_solution *sol, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 5, 6)))
#endif
    ;

static usm_sweep_event *emit_event(sweep_branch *b, usm_event_type type, double value,
                                   const usm_steady_solution *sol, const char *fmt, ...)
{
    if (usm_grow((void **)&b->pev, &b->pevcap, b->npev + 1, sizeof *b->pev) != 0) {
        b->oom = 1;
        return NULL;
    }
    usm_sweep_event *e = &b->pev[b->npev++];
    memset(e, 0, sizeof *e);
    e->type = type;
    e->value = value;
    if (sol) {
        e->sol = *sol;
        e->has_sol = 1;
    }
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(e->what, USM_MSG_LEN, fmt, ap);
    va_end(ap);
    return e;
}

static void flush(sweep_branch *b)
{
    for (size_t k = 0; k < b->nppt; ++k) {
        const struct sweep_pending_point *pp = &b->ppt[k];
        b->sink->point(b->sink->ctx, pp->i, pp->has_sol ? &pp->sol : NULL, pp->roots, pp->error);
        if (pp->has_sol) {
            b->last = pp->sol;
            if (pp->roots == SWEEP_ROOTS_PENDING) { /* only u is set: the rest, alpha wrapped */
                usm_params q = b->p;
                *usm_params_field(&q, b->info) = b->grid[pp->i];
                usm_steady_evaluate(b->m, &q, &b->last);
            }
        }
    }
    for (size_t k = 0; k < b->npev; ++k)
        if (b->sink->event(b->sink->ctx, &b->pev[k]) != 0)
            b->oom = 1;
    b->nppt = b->npev = 0;
}

static void discard(sweep_branch *b) { b->nppt = b->npev = 0; }

/* ---- the problem posed to the engine ---------------------------------------------- */

static double lambda_of(const sweep_branch *b, const double *x) { return x[b->nu]; }

static void set_lambda(sweep_branch *b, double lambda) { *usm_params_field(&b->p, b->info) = lambda; }

/* The swept parameter inside its physical range (kappa > 0, c_r >= 0, ...):
 * Newton must not land on the mirror image of the branch at kappa < 0. */
static int admissible(const sweep_branch *b, double lambda)
{
    const usm_constraint c = usm_param_constraints[usm_param_index(b->info)];
    if (c == USM_CONSTRAINT_POSITIVE)
        return lambda > 0.0;
    if (c == USM_CONSTRAINT_NONNEGATIVE)
        return lambda >= 0.0;
    return isfinite(lambda);
}

/* The engine's residual: r(u; lambda) and [r_u, r_lambda] from the generated
 * kernels, x = (u, lambda). */
static int branch_residual(const double *x, double *F, double *Jx, void *ctx)
{
    sweep_branch *b = ctx;
    const int nu = b->nu, N = b->n;
    double J[USM_MAX_NU * USM_MAX_NU], Jp[USM_MAX_NU * USM_NPARAMS];
    if (!admissible(b, lambda_of(b, x)))
        return -1;
    set_lambda(b, lambda_of(b, x));
    b->m->steady_residual(x, &b->p, F);
    if (!Jx)
        return 0;
    b->m->steady_jacobian(x, &b->p, J);
    b->m->steady_jacobian_params(x, &b->p, Jp);
    for (int i = 0; i < nu; ++i) {
        for (int j = 0; j < nu; ++j)
            Jx[i * N + j] = J[i * nu + j];
        Jx[i * N + nu] = Jp[i * USM_NPARAMS + b->col];
    }
    return 0;
}

/* ---- quantities along the branch --------------------------------------------- */

static void outputs(sweep_branch *b, const double *x, double *y)
{
    set_lambda(b, lambda_of(b, x));
    b->m->steady_outputs(x, &b->p, y);
}

/* |F_t| - mu0 F_n: negative where stick is admissible (as usm_steady_evaluate). */
static double stick_gap(sweep_branch *b, const double *x)
{
    double y[USM_STEADY_COUNT];
    outputs(b, x, y);
    return fabs(y[USM_STEADY_F_T]) - b->p.mu0 * y[USM_STEADY_F_N];
}

/* The friction law's limit on the side of slip velocity v (p at lambda of the
 * last evaluation): the generated law evaluated at a huge speed, so that any
 * monotone law with a finite supremum works. */
static double friction_limit(const sweep_branch *b, double v)
{
    double mu[USM_FRICTION_COUNT];
    b->m->friction(copysign(V_HUGE, v), &b->p, mu);
    return fabs(mu[USM_FRICTION_MU]);
}

static void solution_at(sweep_branch *b, const double *x, usm_steady_solution *sol)
{
    memset(sol, 0, sizeof *sol);
    memcpy(sol->u, x, sizeof(double) * (size_t)b->nu);
    set_lambda(b, lambda_of(b, x));
    usm_steady_evaluate(b->m, &b->p, sol);
}

static double monitor_at(sweep_branch *b, const usm_sweep_monitor *mo, const double *x)
{
    usm_steady_solution sol;
    solution_at(b, x, &sol);
    return mo->fn(&sol, &b->p, mo->ctx);
}

/* Step of the central differences along the direction (scaled units, where
 * the components are of order one): truncation ~1e-12, rounding ~1e-10. */
#define SLOPE_STEP 1e-6

/* dy/ds at x on the branch with direction dx: by central differences (y is a
 * smooth function of x off the branch too). */
static double monitor_slope(sweep_branch *b, const usm_sweep_monitor *mo, const double *x,
                            const double *dx)
{
    double xp[SWEEP_MAX_N], xm[SWEEP_MAX_N];
    for (int j = 0; j < b->n; ++j) {
        xp[j] = x[j] + SLOPE_STEP * dx[j];
        xm[j] = x[j] - SLOPE_STEP * dx[j];
    }
    return (monitor_at(b, mo, xp) - monitor_at(b, mo, xm)) / (2.0 * SLOPE_STEP);
}

/* ---- the sweep's test functions ------------------------------------------------- */

static double test_value(const double *x, const double *dx, void *ctx)
{
    sweep_test *st = ctx;
    sweep_branch *b = st->b;
    switch (st->kind) {
    case SWEEP_TEST_THETA_LOW:
        return x[0] - b->theta_min;
    case SWEEP_TEST_THETA_HIGH:
        return b->theta_max - x[0];
    case SWEEP_TEST_ROTOR:
        return x[b->rotor];
    case SWEEP_TEST_MONITOR:
        return monitor_at(b, st->mo, x) - st->level;
    case SWEEP_TEST_SLOPE:
        return monitor_slope(b, st->mo, x, dx);
    default:
        return stick_gap(b, x);
    }
}

/* One test function of the engine; 0 or -1. */
static int add_test(sweep_branch *b, int kind, const usm_sweep_monitor *mo, double level,
                    int flags)
{
    sweep_test *st = &b->tests[b->ntests];
    *st = (sweep_test){b, kind, mo, level, 0};
    st->index = usm_cont_add_test(b->cont, test_value, st, flags);
    if (st->index < 0)
        return -1;
    b->ntests++;
    return 0;
}

/* The engine for one run and the test functions of its branch: the ends of
 * the tilt range (the branch ends there), the stick limit (stick models) or
 * the stall (slip models), the user monitors' levels and extrema.  The fold
 * is the engine's own; the branch ends there (across_fold 0). */
static int setup_engine(sweep_branch *b, size_t npts)
{
    const usm_sweep_options *opt = b->opt;
    usm_cont_options o;
    size_t ntests = 3;
    for (int k = 0; k < opt->nmonitors; ++k)
        ntests += (size_t)opt->monitors[k].nlevels + 1;
    usm_cont_free(b->cont);
    free(b->tests);
    b->ntests = 0;
    b->cont = usm_cont_alloc(b->nu);
    b->tests = calloc(ntests, sizeof *b->tests);
    if (!b->cont || !b->tests)
        return -1;
    usm_cont_set_problem(b->cont, branch_residual, b);
    usm_cont_options_default(&o);
    o.h_max = H_MAX;
    o.h_min = H_MIN;
    o.h0 = fmin(H_MAX, 0.5 / (double)(npts > 1 ? npts - 1 : 1));
    o.event_tol = 1e-15;
    o.across_fold = 0;
    if (usm_cont_set_options(b->cont, &o) != 0 ||
        add_test(b, SWEEP_TEST_THETA_LOW, NULL, 0, USM_CONT_TEST_STOP) != 0 ||
        add_test(b, SWEEP_TEST_THETA_HIGH, NULL, 0, USM_CONT_TEST_STOP) != 0 ||
        add_test(b, b->rotor >= 0 ? SWEEP_TEST_ROTOR : SWEEP_TEST_STICK, NULL, 0,
                 USM_CONT_TEST_MONITOR) != 0)
        return -1;
    for (int k = 0; k < opt->nmonitors; ++k) {
        const usm_sweep_monitor *mo = &opt->monitors[k];
        for (int l = 0; l < mo->nlevels; ++l)
            if (add_test(b, SWEEP_TEST_MONITOR, mo, mo->levels[l], USM_CONT_TEST_MONITOR) != 0)
                return -1;
        if (mo->extrema && add_test(b, SWEEP_TEST_SLOPE, mo, 0, USM_CONT_TEST_MONITOR) != 0)
            return -1;
    }
    return 0;
}

static const sweep_test *test_of(const sweep_branch *b, int index)
{
    for (int k = 0; k < b->ntests; ++k)
        if (b->tests[k].index == index)
            return &b->tests[k];
    return NULL;
}

/* ---- following the branch -------------------------------------------------------- */

enum { END_STOP, END_FOLD, END_BOUNDARY, END_SATURATION };

typedef struct trace {
    sweep_branch *b;
    ptrdiff_t next;     /* next grid point to land on */
    int step;           /* +1: the trace runs in sweep order, -1: backwards */
    double stop;        /* lambda where the trace ends */
    int sat_checked;    /* the saturation point was computed and lies beyond stop */
    /* outcome */
    int end;
    double end_value;
    usm_event_type end_type;
} trace;

static int within(const trace *tr, double lambda) { return (lambda - tr->stop) * tr->b->dir <= 0; }

static int pending(const trace *tr)
{
    return tr->next >= 0 && tr->next < (ptrdiff_t)tr->b->npts;
}

static const char *side(int dir) { return dir > 0 ? "above" : "below"; }

/* Whether ua and ub are the same root: every unknown agrees, not the tilt
 * alone (the slip model's roots under a non-monotone friction law share
 * theta and alpha and differ only in the rotor speed). */
static int same_unknowns_nu(int nu, const double *ua, const double *ub)
{
    for (int i = 0; i < nu; ++i) {
        double d = fabs(ua[i] - ub[i]);
        if (i == 1) /* alpha, stored in [0, 2 pi) */
            d = fmin(d, fabs(TWO_PI - d));
        const double size = i == 0 ? fabs(ua[0]) : fmax(1.0, fmax(fabs(ua[i]), fabs(ub[i])));
        if (!(d <= 1e-6 * size))
            return 0;
    }
    return 1;
}

static int same_unknowns(const sweep_branch *b, const double *ua, const double *ub)
{
    return same_unknowns_nu(b->nu, ua, ub);
}

/* The root of the full search at q that is the branch's root u, or NULL;
 * *roots: the number of roots the search finds there. */
static const usm_steady_solution *same_root(sweep_branch *b, const usm_params *q, const double *u,
                                            int *roots)
{
    *roots = 0;
    if (usm_steady_solve(b->steady, q, &b->opt->steady) != USM_OK)
        return NULL;
    *roots = (int)usm_steady_count(b->steady);
    for (size_t k = 0; k < usm_steady_count(b->steady); ++k) {
        const usm_steady_solution *r = usm_steady_root(b->steady, k);
        if (same_unknowns(b, u, r->u))
            return r;
    }
    return NULL;
}

/* Grid point i from a point x on the branch at (nearly) its value. */
static void finish_point(trace *tr, size_t i, double *x)
{
    sweep_branch *b = tr->b;
    const double value = b->grid[i];
    usm_steady_solution sol;
    int roots;
    double u[USM_MAX_NU] = {0};
    /* on the branch at the grid value itself: the start of the polish below,
     * and the result where the polish fails (a failed Newton leaves x as it
     * was, already on the branch near the value) */
    usm_cont_correct_fixed(b->cont, x, b->nu, value);
    memcpy(u, x, sizeof(double) * (size_t)b->nu);
    if (b->defer) {
        /* the full search below is independent of the continuation: done
         * for every point at once by sweep_finish_points, on the workers */
        memset(&sol, 0, sizeof sol);
        memcpy(sol.u, u, sizeof u);
        emit_point(b, i, &sol, SWEEP_ROOTS_PENDING, "");
        return;
    }
    usm_params q = b->p;
    *usm_params_field(&q, b->info) = value;
    /* The continuation says which root; the full search's polish of that root
     * gives its value, so that a row equals `usm steady` at these parameters
     * bit for bit (the Floquet integration amplifies a last-bit difference to
     * ~1e-7).  Where the search misses the root, polish from the branch. */
    const usm_steady_solution *r = same_root(b, &q, u, &roots);
    /* the branch's root missed by the search is one more root */
    if (!r)
        roots++;
    if (!r && usm_steady_solve_from(b->steady, &q, u) == USM_OK)
        r = usm_steady_root(b->steady, 0);
    if (r && same_unknowns(b, u, r->u))
        sol = *r;
    else {
        memset(&sol, 0, sizeof sol);
        memcpy(sol.u, u, sizeof u);
        usm_steady_evaluate(b->m, &q, &sol);
    }
    emit_point(b, i, &sol, roots, "");
}

/* Land on every grid value reached by the last step (from xa to xend, arc
 * length s_end): from the step's arc at the value's share of the step in
 * lambda, then on the value exactly (finish_point). */
static int land_on_grid(trace *tr, const double *xa, double s_end, const double *xend)
{
    sweep_branch *b = tr->b;
    const int nu = b->nu;
    const double la = xa[nu], lb = xend[nu];
    while (pending(tr)) {
        const double g = b->grid[tr->next];
        double x[SWEEP_MAX_N];
        if ((g - lb) * b->dir > 0)
            break;
        const double w = lb != la ? (g - la) / (lb - la) : 1.0;
        if (usm_cont_arc_point(b->cont, fmin(fmax(w, 0.0), 1.0) * s_end, x, NULL) != 0)
            return -1;
        finish_point(tr, (size_t)tr->next, x);
        tr->next += tr->step;
    }
    return 0;
}

static void end_text(const trace *tr, char *buf, size_t len, const char *what, double value)
{
    char v[64];
    snprintf(buf, len, "%.140s: no stationary solution on this branch %s %.63s", what,
             side(tr->b->dir), sweep_value_text(tr->b->info, value, v));
}

/* Slip model: the rotor speed phidot_R changed sign at x0 (before: its sign
 * before; the rotor stops: the load equals the torque the motor can hold at
 * rest).  The point on the branch at rotor speed 0 exactly. */
static int stall_event(trace *tr, const double *x0, double before)
{
    sweep_branch *b = tr->b;
    double x[SWEEP_MAX_N];
    char v[64];
    memcpy(x, x0, sizeof(double) * (size_t)b->n);
    if (usm_cont_correct_fixed(b->cont, x, b->rotor, 0.0) < 0)
        return -1;
    const double lambda = lambda_of(b, x);
    if (!within(tr, lambda))
        return 0;
    usm_steady_solution sol;
    solution_at(b, x, &sol);
    /* driving is phidot_R < 0 (the paper's sign) */
    const int driving_dir = before < 0 ? -b->dir : b->dir;
    return emit_event(b, USM_EVENT_STALL, lambda, &sol,
                      "the rotor stands still (phidot_R = 0) at %s: it turns in the driving "
                      "direction %s it and is driven backwards by the load %s it",
                      sweep_value_text(b->info, lambda, v), side(driving_dir), side(-driving_dir))
               ? 0
               : -1;
}

/* Stick model: |F_t| - mu0 F_n changed sign at x (with slip built in,
 * F_t = mu(v) F_n holds by construction and stick has no meaning). */
static int stick_event(trace *tr, const double *x, double before)
{
    sweep_branch *b = tr->b;
    char v[64];
    const double lambda = lambda_of(b, x);
    if (!within(tr, lambda))
        return 0;
    usm_steady_solution sol;
    solution_at(b, x, &sol);
    /* admissible on the side where the gap is negative */
    const int admissible_dir = before < 0 ? -b->dir : b->dir;
    return emit_event(b, USM_EVENT_STICK_LIMIT, lambda, &sol,
                      "F_t = mu0 F_n (mu0 = %g) at %s: stick is admissible %s it, not %s",
                      b->p.mu0, sweep_value_text(b->info, lambda, v), side(admissible_dir),
                      side(-admissible_dir))
               ? 0
               : -1;
}

/* A user monitor's level crossing (level) or extremum (slope test, before
 * the slope's sign before) at x. */
static int monitor_event(trace *tr, const sweep_test *st, const double *x, double before)
{
    sweep_branch *b = tr->b;
    const usm_sweep_monitor *mo = st->mo;
    char v[64];
    const double lambda = lambda_of(b, x);
    if (!within(tr, lambda))
        return 0;
    usm_steady_solution sol;
    solution_at(b, x, &sol);
    const double y = mo->fn(&sol, &b->p, mo->ctx);
    usm_sweep_event *e;
    if (st->kind == SWEEP_TEST_MONITOR)
        e = emit_event(b, USM_EVENT_CROSSING, lambda, &sol, "%s crosses %.10g at %s", mo->name,
                       st->level, sweep_value_text(b->info, lambda, v));
    else
        e = emit_event(b, before > 0 ? USM_EVENT_MAXIMUM : USM_EVENT_MINIMUM, lambda, &sol,
                       "%s has a %s %.10g at %s", mo->name, before > 0 ? "maximum" : "minimum",
                       y, sweep_value_text(b->info, lambda, v));
    if (!e)
        return -1;
    snprintf(e->monitor, sizeof e->monitor, "%s", mo->name);
    e->monitor_value = y;
    return 0;
}

/* The events the engine located in its last step, but the branch's end:
 * 0, or -1 when one could not be completed. */
static int step_events(trace *tr)
{
    sweep_branch *b = tr->b;
    for (int k = 0; k < usm_cont_event_count(b->cont); ++k) {
        const usm_cont_event *e = usm_cont_event_at(b->cont, k);
        const sweep_test *st = test_of(b, e->test);
        int rc = 0;
        if (e->stop || !st)
            continue;
        if (st->kind == SWEEP_TEST_ROTOR)
            rc = stall_event(tr, e->x, e->before);
        else if (st->kind == SWEEP_TEST_STICK)
            rc = stick_event(tr, e->x, e->before);
        else
            rc = monitor_event(tr, st, e->x, e->before);
        if (rc != 0)
            return -1;
    }
    return 0;
}

/* How the last step ended the branch: END_FOLD or END_BOUNDARY. */
static int end_kind(const sweep_branch *b)
{
    const usm_cont_event *e = usm_cont_event_at(b->cont, usm_cont_event_count(b->cont) - 1);
    return e && e->test == USM_CONT_FOLD ? END_FOLD : END_BOUNDARY;
}

/* The branch left the tilt range at its lower end xb (theta = theta_min): the
 * residuals are regular at theta = 0 (R* -> R, Z -> H), so the branch runs on
 * through the limit where the tilt vanishes.  That limit, on the branch at
 * theta = 0 exactly: Newton on [F; theta = 0] from xb.  0 and xt, or -1
 * when the branch does not reach theta = 0 next to xb. */
static int tilt_zero(trace *tr, const double *xb, double *xt)
{
    sweep_branch *b = tr->b;
    memcpy(xt, xb, sizeof(double) * (size_t)b->n);
    if (usm_cont_correct_fixed(b->cont, xt, 0, 0.0) < 0)
        return -1;
    /* next to the boundary point: within the tilt's own size of the step */
    const double dl = fabs(xt[b->nu] - xb[b->nu]) / b->scale[b->nu];
    return dl <= 1e-3 ? 0 : -1;
}

static int report_end(trace *tr, const double *x)
{
    sweep_branch *b = tr->b;
    usm_steady_solution sol;
    char what[USM_MSG_LEN];
    double lambda = lambda_of(b, x);
    usm_event_type type = USM_EVENT_FOLD;
    solution_at(b, x, &sol);
    if (tr->end == END_FOLD)
        end_text(tr, what, sizeof what, "fold: the branch turns back (d lambda/ds = 0)", lambda);
    else {
        const int low = sol.theta < 0.5 * (b->theta_min + b->theta_max);
        double xt[SWEEP_MAX_N];
        char head[200];
        if (low && tilt_zero(tr, x, xt) == 0) {
            lambda = lambda_of(b, xt);
            solution_at(b, xt, &sol);
            type = USM_EVENT_TILT_ZERO;
            end_text(tr, what, sizeof what,
                     "the tilt vanishes (theta = 0): the stator no longer wobbles and the "
                     "motor stops driving",
                     lambda);
        } else {
            type = USM_EVENT_RANGE_END;
            snprintf(head, sizeof head,
                     "the tilt reaches theta_%s = %g rad, the end of the searched range "
                     "(steady options)",
                     low ? "min" : "max", low ? b->theta_min : b->theta_max);
            end_text(tr, what, sizeof what, head, lambda);
        }
    }
    tr->end_value = lambda;
    tr->end_type = type;
    return emit_event(b, type, lambda, &sol, "%s", what) ? 0 : -1;
}

/* Slip model: F_t / F_n approaches the friction law's supremum and the rotor
 * speed diverges.  The limit is the branch point at a rotor speed W so large
 * that the law equals its supremum to rounding: Newton on [F; rotor = W]. */
static int saturation(trace *tr, const double *x1, double *xs)
{
    sweep_branch *b = tr->b;
    const int r = b->rotor;
    double y[USM_STEADY_COUNT];
    outputs(b, x1, y);
    const double v = y[USM_STEADY_V_REL], w = x1[r];
    if (!(fabs(v) > 0) || !(fabs(w) > 0))
        return -1;
    const double W = w * (V_HUGE / fabs(v));
    memcpy(xs, x1, sizeof(double) * (size_t)b->n);
    xs[r] = W;
    return usm_cont_correct_fixed(b->cont, xs, r, W) >= 0 ? 0 : -1;
}

static double mu_ratio(sweep_branch *b, const double *x)
{
    double y[USM_STEADY_COUNT];
    outputs(b, x, y);
    const double lim = friction_limit(b, y[USM_STEADY_V_REL]);
    return lim > 0 ? fabs(y[USM_STEADY_F_T] / y[USM_STEADY_F_N]) / lim : 0.0;
}

/* Grid points between the branch at x1 and the saturation point xs: the
 * rotor speed diverges like 1/(lambda_sat - lambda), which continuation would
 * approach in ever shorter steps; the full search brackets the rotor speed
 * directly.  Of its roots the one nearest the branch's tilt is taken. */
static void land_before_saturation(trace *tr, const double *x1, const double *xs)
{
    sweep_branch *b = tr->b;
    const int nu = b->nu;
    while (pending(tr)) {
        const double value = b->grid[tr->next];
        if ((value - xs[nu]) * b->dir >= 0)
            break;
        const double w = (value - x1[nu]) / (xs[nu] - x1[nu]);
        const double theta = x1[0] + w * (xs[0] - x1[0]);
        usm_params q = b->p;
        *usm_params_field(&q, b->info) = value;
        if (usm_steady_solve(b->steady, &q, &b->opt->steady) == USM_OK) {
            /* nearest in tilt; of roots with that tilt (a non-monotone
             * friction law) the fastest rotor, the one that diverges */
            size_t best = 0;
            for (size_t k = 1; k < usm_steady_count(b->steady); ++k) {
                const usm_steady_solution *rk = usm_steady_root(b->steady, k),
                                          *rb = usm_steady_root(b->steady, best);
                const double dk = fabs(rk->theta - theta), db = fabs(rb->theta - theta);
                if (dk < db - 1e-6 * fabs(theta) ||
                    (dk <= db + 1e-6 * fabs(theta) && fabs(rk->rotor_speed) > fabs(rb->rotor_speed)))
                    best = k;
            }
            emit_point(b, (size_t)tr->next, usm_steady_root(b->steady, best),
                       (int)usm_steady_count(b->steady), "");
        } else
            emit_point(b, (size_t)tr->next, NULL, 0, usm_steady_message(b->steady));
        tr->next += tr->step;
    }
}

/* Whether the friction law approaches its value at infinite slip monotonically
 * from slip velocity v on (the tail where the rotor speed diverges).  A
 * non-monotone law (Stribeck-like hump) may need F_t/F_n near that value at a
 * small slip velocity too, where the branch goes on to a fold instead. */
static int in_tail(const sweep_branch *b, double v)
{
    double mu[USM_FRICTION_COUNT], prev;
    if (!(fabs(v) > 0))
        return 0;
    b->m->friction(v, &b->p, mu);
    prev = fabs(mu[USM_FRICTION_MU]);
    const double lim = friction_limit(b, v);
    const int rising = prev <= lim;
    for (int k = 1; k <= 200; ++k) {
        const double vk = v * pow(V_HUGE / fabs(v), k / 200.0);
        b->m->friction(vk, &b->p, mu);
        const double m = fabs(mu[USM_FRICTION_MU]);
        if (rising ? m < prev - 1e-12 * lim : m > prev + 1e-12 * lim)
            return 0;
        prev = m;
    }
    return 1;
}

/* Returns 1 when the branch ended in saturation within the trace. */
static int check_saturation(trace *tr, const double *x1)
{
    sweep_branch *b = tr->b;
    double xs[SWEEP_MAX_N], y[USM_STEADY_COUNT];
    char v[64];
    if (b->rotor < 0 || tr->sat_checked || mu_ratio(b, x1) < SAT_TRIGGER)
        return 0;
    outputs(b, x1, y);
    if (!in_tail(b, y[USM_STEADY_V_REL]))
        return 0;
    if (saturation(tr, x1, xs) != 0)
        return 0; /* keep following the branch; the step control decides */
    const double lambda = lambda_of(b, xs);
    if (!within(tr, lambda) || (lambda - lambda_of(b, x1)) * b->dir <= 0) {
        tr->sat_checked = 1;
        return 0;
    }
    land_before_saturation(tr, x1, xs);
    outputs(b, xs, y);
    tr->end = END_SATURATION;
    tr->end_value = lambda;
    tr->end_type = USM_EVENT_FRICTION_SATURATION;
    emit_event(b, USM_EVENT_FRICTION_SATURATION, lambda, NULL,
               "F_t / F_n reaches the friction law's supremum %.6g at %s (theta = %.6g rad): "
               "the rotor speed diverges and no stationary solution exists %s it",
               fabs(y[USM_STEADY_F_T] / y[USM_STEADY_F_N]), sweep_value_text(b->info, lambda, v),
               xs[0], side(b->dir));
    return 1;
}

/* Scale each unknown by the largest size it has had: the rotor speed may grow
 * by many orders of magnitude towards friction saturation. */
static int rescale(sweep_branch *b, const double *x)
{
    int changed = 0;
    for (int i = 0; i < b->nu; ++i) {
        const double size = fabs(x[i]);
        /* the tilt by its own size in both directions: it may fall by decades
         * (theta ~ 1/c_r), and a step measured in the first size would then
         * jump across theta = 0 */
        if (size > b->scale[i] || (i == 0 && size < 0.25 * b->scale[i] && size > 0)) {
            b->scale[i] = size;
            changed = 1;
        }
    }
    return changed ? usm_cont_set_scale(b->cont, b->scale) : 0;
}

/* Follow the branch from the solution u0 at lambda0 in direction b->dir until
 * lambda passes tr->stop or the branch ends.  0, or -1 when it is lost. */
static int follow(trace *tr, const double *u0, double lambda0)
{
    sweep_branch *b = tr->b;
    const int nu = b->nu;
    double x0[SWEEP_MAX_N];
    tr->end = END_STOP;
    memcpy(x0, u0, sizeof(double) * (size_t)nu);
    x0[nu] = lambda0;
    if (usm_cont_set_scale(b->cont, b->scale) != 0 || usm_cont_start(b->cont, x0, b->dir) != 0)
        return -1;
    for (;;) {
        const int rc = usm_cont_step(b->cont);
        if (rc != USM_CONT_STEP && rc != USM_CONT_END)
            return -1;
        const double *xa;
        const double s_end = usm_cont_step_arc(b->cont, &xa);
        double xstart[SWEEP_MAX_N], x1[SWEEP_MAX_N];
        memcpy(xstart, xa, sizeof(double) * (size_t)b->n);
        memcpy(x1, usm_cont_point(b->cont), sizeof(double) * (size_t)b->n);
        if (step_events(tr) != 0 || land_on_grid(tr, xstart, s_end, x1) != 0) {
            discard(b);
            return -1;
        }
        flush(b);
        if (rc == USM_CONT_END) {
            tr->end = end_kind(b);
            if (within(tr, lambda_of(b, x1))) {
                const int r = report_end(tr, x1);
                flush(b);
                return r;
            }
            tr->end = END_STOP; /* the branch ends beyond the range asked for */
            return 0;
        }
        if (!within(tr, lambda_of(b, x1)))
            return 0;
        if (check_saturation(tr, x1)) {
            flush(b);
            return 0;
        }
        if (rescale(b, x1) != 0)
            return -1;
    }
}

/* ---- whether two roots lie on one branch ------------------------------------------ */

typedef struct reach_stop {
    int k;        /* the unknown */
    double value; /* where the branch is stopped */
} reach_stop;

static double reach_test(const double *x, const double *dx, void *ctx)
{
    const reach_stop *r = ctx;
    (void)dx;
    return x[r->k] - r->value;
}

int sweep_branch_connects(const usm_model *m, const usm_params *p, const usm_param_info *info,
                          double va, const double *ua, double vb, const double *ub)
{
    sweep_branch b;
    memset(&b, 0, sizeof b);
    b.m = m;
    b.info = info;
    b.col = (int)(info - usm_param_table);
    b.nu = m->nu;
    b.n = m->nu + 1;
    b.p = *p;
    const int nu = b.nu;
    reach_stop at_vb = {nu, vb}, at_zero = {0, 0.0};
    double x[SWEEP_MAX_N];
    usm_cont_options o;
    usm_cont *c = usm_cont_alloc(nu);
    int result = -1, k_vb = -1;
    if (!c || va == vb)
        goto done;
    b.cont = c;
    b.scale[0] = fabs(ua[0]);
    for (int i = 1; i < nu; ++i)
        b.scale[i] = fmax(1.0, fabs(ua[i]));
    b.scale[nu] = fabs(vb - va);
    memcpy(x, ua, sizeof(double) * (size_t)nu);
    x[nu] = va;
    usm_cont_options_default(&o);
    o.h_max = o.h0 = H_MAX;
    o.h_min = H_MIN;
    o.max_steps = 100000;
    usm_cont_set_problem(c, branch_residual, &b);
    /* the branch ends at the other value, at a fold or where the tilt vanishes */
    if (usm_cont_set_options(c, &o) != 0 || usm_cont_set_scale(c, b.scale) != 0 ||
        (k_vb = usm_cont_add_test(c, reach_test, &at_vb, USM_CONT_TEST_STOP)) < 0 ||
        usm_cont_add_test(c, reach_test, &at_zero, USM_CONT_TEST_STOP) < 0 ||
        usm_cont_start(c, x, vb > va ? 1 : -1) != 0)
        goto done;
    for (;;) {
        const int rc = usm_cont_step(c);
        if (rc == USM_CONT_END) {
            const usm_cont_event *e = usm_cont_event_at(c, usm_cont_event_count(c) - 1);
            result = 0;
            memcpy(x, usm_cont_point(c), sizeof(double) * (size_t)b.n);
            if (e && e->test == k_vb && usm_cont_correct_fixed(c, x, nu, vb) >= 0)
                result = same_unknowns_nu(nu, x, ub);
            break;
        }
        if (rc != USM_CONT_STEP || rescale(&b, usm_cont_point(c)) != 0)
            break;
    }
done:
    usm_cont_free(c);
    return result;
}

/* ---- the grid ------------------------------------------------------------------- */

/* The grid points a trace did not reach, from tr->next on in its direction
 * up to (not including) `end`. */
static void mark_beyond(const trace *tr, ptrdiff_t end, const char *why)
{
    sweep_branch *b = tr->b;
    char msg[USM_MSG_LEN];
    for (ptrdiff_t i = tr->next; i >= 0 && i < (ptrdiff_t)b->npts && i != end; i += tr->step) {
        usm_params q = b->p;
        int roots = 0;
        *usm_params_field(&q, b->info) = b->grid[i];
        /* another root here lies on another branch; say so, but do not jump */
        if (usm_steady_solve(b->steady, &q, &b->opt->steady) == USM_OK &&
            (roots = (int)usm_steady_count(b->steady)) > 0)
            snprintf(msg, USM_MSG_LEN,
                     "%.150s; a stationary solution on another branch exists here "
                     "(theta = %.6g rad), not followed",
                     why, usm_steady_root(b->steady, 0)->theta);
        else
            snprintf(msg, USM_MSG_LEN, "%s", why);
        emit_point(b, (size_t)i, NULL, roots, msg);
    }
    flush(b);
}

static void setup_branch(sweep_branch *b, const double *u)
{
    /* the tilt by its own size; the phase (rad) and rotor speed (1/s) by at
     * least one unit, since their size depends on an arbitrary origin */
    b->scale[0] = fabs(u[0]);
    for (int i = 1; i < b->nu; ++i)
        b->scale[i] = fmax(1.0, fabs(u[i]));
    b->scale[b->nu] = fabs(b->opt->to - b->opt->from);
}

/* The first grid point from `from` on (step +1) where the full search finds a
 * solution (npts: none); the points before it get the search's reason.  Of
 * its roots the one nearest to `near` (every unknown, scaled; NULL: the
 * primary root) into *start. */
static size_t first_solution(sweep_branch *b, size_t from, const usm_steady_solution *near,
                             usm_steady_solution *start, int *status, char msg[USM_MSG_LEN])
{
    *status = USM_OK;
    for (size_t i = from; i < b->npts; ++i) {
        usm_params q = b->p;
        *usm_params_field(&q, b->info) = b->grid[i];
        const int rc = usm_steady_solve(b->steady, &q, &b->opt->steady);
        if (rc == USM_OK) {
            size_t best = 0;
            double dbest = INFINITY;
            for (size_t k = 0; near && k < usm_steady_count(b->steady); ++k) {
                const usm_steady_solution *r = usm_steady_root(b->steady, k);
                double d = 0;
                for (int j = 0; j < b->nu; ++j)
                    d += fabs(r->u[j] - near->u[j]) /
                         (j == 0 ? fabs(near->u[0]) : fmax(1.0, fabs(near->u[j])));
                if (d < dbest) {
                    dbest = d;
                    best = k;
                }
            }
            *start = *usm_steady_root(b->steady, best);
            emit_point(b, i, start, (int)usm_steady_count(b->steady), "");
            flush(b);
            return i;
        }
        if (rc != USM_ENOSOLUTION) {
            snprintf(msg, USM_MSG_LEN, "%s", usm_steady_message(b->steady));
            *status = rc;
            return b->npts;
        }
        emit_point(b, i, NULL, 0, usm_steady_message(b->steady));
        flush(b);
    }
    return b->npts;
}

int sweep_trace_grid(sweep_branch *b, const usm_params *p, const usm_sweep_options *opt,
                     const double *grid, size_t n, const sweep_sink *sink, char msg[USM_MSG_LEN])
{
    const int dir = opt->to > opt->from ? 1 : -1;
    int status;
    char v[64];
    usm_steady_solution start;
    b->info = usm_params_find(opt->over);
    b->col = (int)(b->info - usm_param_table);
    b->p = *p;
    b->theta_min = opt->steady.theta_min;
    b->theta_max = opt->steady.theta_max;
    b->opt = opt;
    b->grid = grid;
    b->npts = n;
    b->sink = sink;
    b->oom = 0;
    discard(b);
    size_t i = first_solution(b, 0, NULL, &start, &status, msg);
    if (i == n)
        return status;
    setup_branch(b, start.u);
    if (setup_engine(b, n) != 0) {
        snprintf(msg, USM_MSG_LEN, "out of memory for the continuation");
        return USM_EFAILED;
    }

    if (i > 0) {
        /* Where does the solution appear?  Follow the branch back to `from`:
         * a fold or range boundary on the way is an event, and grid points
         * the full search missed are landed on. */
        trace back = {b, (ptrdiff_t)i - 1, -1, opt->from, 0, END_STOP, 0, USM_EVENT_FOLD};
        b->dir = -dir;
        follow(&back, start.u, grid[i]);
        discard(b);
    }
    for (;;) {
        trace tr = {b, (ptrdiff_t)i + 1, 1, opt->to, 0, END_STOP, 0, USM_EVENT_FOLD};
        b->dir = dir;
        setup_branch(b, start.u);
        if (follow(&tr, start.u, grid[i]) == 0) {
            if (tr.end != END_STOP) {
                char why[USM_MSG_LEN];
                snprintf(why, sizeof why, "no stationary solution on the branch beyond %s at %s",
                         tr.end == END_FOLD ? "the fold" : usm_event_name(tr.end_type),
                         sweep_value_text(b->info, tr.end_value, v));
                mark_beyond(&tr, -1, why);
            }
            break;
        }
        /* The continuation lost the branch after the last grid point it
         * reached: the full search goes on from the next one, taking the
         * root nearest the branch's last. */
        discard(b);
        const usm_steady_solution near = b->last;
        if (!pending(&tr))
            break;
        i = first_solution(b, (size_t)tr.next, &near, &start, &status, msg);
        if (i == n)
            return status;
    }
    if (b->oom) {
        snprintf(msg, USM_MSG_LEN, "out of memory for the sweep's points and events");
        return USM_EFAILED;
    }
    return USM_OK;
}

/* ---- the deferred part of finish_point ------------------------------------------ */

/* Grid points between two full searches of the finish pass: the root count is
 * tracked in between and checked where the next span's search starts. */
#define FINISH_SPAN 32
/* Roots a span tracks; a point with more is searched in full. */
#define TRACK_MAX 16

typedef struct track_set {
    int count; /* -1: not tracked (a full search is needed) */
    double u[TRACK_MAX][USM_MAX_NU];
} track_set;

typedef struct finish_pass {
    const usm_model *m;
    const usm_params *p;
    const usm_sweep_options *opt;
    const usm_param_info *info;
    usm_sweep_point *pts;
    size_t n, nspans;
    track_set *ends;            /* per span: its roots tracked to the next span's start */
    track_set *starts;          /* per span: the full search's roots at its first point */
    unsigned char *full;        /* per span: 1: a full search at each of its points */
    unsigned char *bad;         /* per span: a tracked run failed its check */
    unsigned char *was_pending; /* per point: to be finished */
    double (*saved_u)[USM_MAX_NU]; /* per point: the branch's root */
} finish_pass;

static void *finish_alloc(void *ctx)
{
    const finish_pass *fp = ctx;
    return usm_steady_alloc(fp->m);
}

static void finish_free(void *state) { usm_steady_free(state); }

/* The full search at grid point i (pts[i].sol.u holds the branch's root
 * there): the root that is the branch's (bit for bit as usm_steady_solve
 * gives it, or the polish from u where the search misses it) and the number
 * of roots; their unknowns into *set (count -1 where they do not fit). */
static void finish_full(const finish_pass *fp, usm_steady *st, size_t i, track_set *set)
{
    usm_sweep_point *pt = &fp->pts[i];
    const int nu = fp->m->nu;
    double u[USM_MAX_NU];
    memcpy(u, pt->sol.u, sizeof u);
    usm_params q = *fp->p;
    *usm_params_field(&q, fp->info) = pt->value;
    const usm_steady_solution *r = NULL;
    int roots = 0;
    set->count = 0;
    if (usm_steady_solve(st, &q, &fp->opt->steady) == USM_OK) {
        roots = (int)usm_steady_count(st);
        for (size_t k = 0; k < usm_steady_count(st); ++k) {
            const usm_steady_solution *rk = usm_steady_root(st, k);
            if (!r && same_unknowns_nu(nu, u, rk->u))
                r = rk;
            if (set->count >= 0 && set->count < TRACK_MAX)
                memcpy(set->u[set->count++], rk->u, sizeof rk->u);
            else
                set->count = -1;
        }
    }
    /* the branch's root missed by the search is one more root */
    if (!r) {
        roots++;
        if (set->count >= 0 && set->count < TRACK_MAX)
            memcpy(set->u[set->count++], u, sizeof u);
        else
            set->count = -1;
    }
    if (!r && usm_steady_solve_from(st, &q, u) == USM_OK)
        r = usm_steady_root(st, 0);
    if (r && same_unknowns_nu(nu, u, r->u))
        pt->sol = *r;
    else {
        memset(&pt->sol, 0, sizeof pt->sol);
        memcpy(pt->sol.u, u, sizeof u);
        usm_steady_evaluate(fp->m, &q, &pt->sol);
    }
    pt->roots = roots;
}

/* Newton on the stationary residual from u at q, with the generated Jacobian:
 * 0 once every row vanishes to 1e-12 m0 plus the rounding of its terms (as
 * the search's polish accepts a root), -1 when it does not within 20 steps. */
static int newton_root(const usm_model *m, const usm_params *q, double *u)
{
    const int nu = m->nu;
    const double base = 1e-12 * (q->m0 > 0 ? q->m0 : 1.0);
    for (int it = 0; it < 20; ++it) {
        double r[USM_MAX_NU], J[USM_MAX_NU * USM_MAX_NU];
        m->steady_residual(u, q, r);
        m->steady_jacobian(u, q, J);
        int small = 1;
        for (int i = 0; i < nu && small; ++i) {
            double floor = 0;
            for (int j = 0; j < nu; ++j)
                floor += fabs(J[i * nu + j]) * fabs(u[j]);
            small = fabs(r[i]) <= base + 16 * DBL_EPSILON * (isfinite(floor) ? floor : 0);
        }
        if (small && it > 0)
            return 0;
        int piv[USM_MAX_NU];
        if (usm_lu_factor_dense(nu, J, piv) != 0)
            return -1;
        usm_lu_solve_dense(nu, J, piv, r, 1);
        for (int j = 0; j < nu; ++j) {
            u[j] -= r[j];
            if (!isfinite(u[j]))
                return -1;
        }
    }
    return -1;
}

/* Every root of *set continued by Newton to the value of grid point i: 0 and
 * the roots at i in *set, or -1 where the root set may have changed there
 * (a root lost or out of the tilt range, two roots merged: a fold). */
static int track_roots(const finish_pass *fp, size_t i, track_set *set)
{
    const int nu = fp->m->nu;
    usm_params q = *fp->p;
    *usm_params_field(&q, fp->info) = fp->pts[i].value;
    if (set->count < 0)
        return -1;
    for (int k = 0; k < set->count; ++k) {
        double *u = set->u[k];
        if (newton_root(fp->m, &q, u) != 0 || !(u[0] >= fp->opt->steady.theta_min) ||
            !(u[0] <= fp->opt->steady.theta_max))
            return -1;
        for (int l = 0; l < k; ++l)
            if (same_unknowns_nu(nu, u, set->u[l]))
                return -1;
    }
    return 0;
}

/* Grid point i from the tracked roots: the one that is the branch's, as the
 * full search gives it bit for bit (usm_steady_solve_cell: its refinement
 * of the one grid cell holding that root), so that a row still equals
 * `usm steady` at its parameters; 0, or -1 when none is or the cell does not
 * give it (a full search then). */
static int finish_tracked(const finish_pass *fp, usm_steady *st, size_t i, const track_set *set)
{
    usm_sweep_point *pt = &fp->pts[i];
    const int nu = fp->m->nu;
    for (int k = 0; k < set->count; ++k)
        if (same_unknowns_nu(nu, pt->sol.u, set->u[k])) {
            usm_params q = *fp->p;
            *usm_params_field(&q, fp->info) = pt->value;
            if (usm_steady_solve_cell(st, &q, &fp->opt->steady, set->u[k]) != USM_OK)
                return -1;
            for (size_t r = 0; r < usm_steady_count(st); ++r)
                if (same_unknowns_nu(nu, set->u[k], usm_steady_root(st, r)->u)) {
                    pt->sol = *usm_steady_root(st, r);
                    pt->roots = set->count;
                    return 0;
                }
            return -1;
        }
    return -1;
}

static int pending_point(const usm_sweep_point *pt)
{
    return pt->converged && pt->roots == SWEEP_ROOTS_PENDING;
}

/* Whether the roots of *full are those of *tracked (every unknown within
 * 1e-6, as the rows). */
static int same_sets(int nu, const track_set *full, const track_set *tracked)
{
    if (full->count < 0 || full->count != tracked->count)
        return 0;
    for (int r = 0; r < full->count; ++r) {
        int found = 0;
        for (int l = 0; l < tracked->count && !found; ++l)
            found = same_unknowns_nu(nu, full->u[r], tracked->u[l]);
        if (!found)
            return 0;
    }
    return 1;
}

/* Span k of the finish pass, a task of the worker pool: points [a, b),
 * a = k FINISH_SPAN.  The full search where the span starts, where the
 * tracking says the root set changed and where a tracked run ends; in
 * between the roots of the last search continued by Newton from point to
 * point.  The root count changes only where a branch folds or leaves the
 * tilt range, which the tracking sees (a root lost or out of range, two
 * merged), or where a new pair of roots appears, which it cannot: so every
 * tracked run is checked against a full search at its end, its own last
 * point or the next span's first (sweep_finish_points), and a span that
 * fails the check is searched in full at every point. */
static int finish_task(void *ctx, void *state, size_t k)
{
    finish_pass *fp = ctx;
    usm_steady *st = state;
    const int nu = fp->m->nu;
    const size_t a = k * FINISH_SPAN, b = a + FINISH_SPAN < fp->n ? a + FINISH_SPAN : fp->n;
    const int next_span_checks = b < fp->n && pending_point(&fp->pts[b]);
    track_set set = {-1, {{0}}};
    int tracked_prev = 0; /* the row before came from the tracking */
    fp->ends[k].count = -1;
    fp->starts[k].count = -1;
    for (size_t i = a; i < b; ++i) {
        if (!pending_point(&fp->pts[i])) {
            set.count = -1;
            tracked_prev = 0;
            continue;
        }
        if (fp->full[k]) {
            finish_full(fp, st, i, &set);
            continue;
        }
        const track_set before = set;
        const int tracked = track_roots(fp, i, &set) == 0;
        if (tracked && finish_tracked(fp, st, i, &set) == 0) {
            const int run_ends = i + 1 < b ? !pending_point(&fp->pts[i + 1]) : !next_span_checks;
            tracked_prev = 1;
            if (run_ends) {
                track_set full;
                finish_full(fp, st, i, &full);
                if (!same_sets(nu, &full, &set))
                    fp->bad[k] = 1;
                set = full;
                tracked_prev = 0;
            }
            continue;
        }
        /* the tracking ends here: the full search at i, and the run before
         * checked against one where it last held */
        track_set full;
        finish_full(fp, st, i, &full);
        if (tracked) {
            if (!same_sets(nu, &full, &set))
                fp->bad[k] = 1;
        } else if (tracked_prev) {
            track_set check;
            finish_full(fp, st, i - 1, &check);
            if (!same_sets(nu, &check, &before))
                fp->bad[k] = 1;
        }
        set = full;
        tracked_prev = 0;
        if (i == a)
            fp->starts[k] = set;
    }
    if (!fp->full[k] && next_span_checks && set.count >= 0) {
        fp->ends[k] = set;
        if (track_roots(fp, b, &fp->ends[k]) != 0)
            fp->ends[k].count = -1;
    }
    return 0;
}

/* Whether span k passed its checks: the roots tracked to its end are those
 * the full search found at the next span's first point. */
static int span_checked(const finish_pass *fp, size_t k)
{
    if (fp->bad[k])
        return 0;
    if (k + 1 >= fp->nspans || !fp->was_pending[(k + 1) * FINISH_SPAN] ||
        !fp->was_pending[(k + 1) * FINISH_SPAN - 1])
        return 1; /* no tracked run reaches the next span */
    return same_sets(fp->m->nu, &fp->starts[k + 1], &fp->ends[k]);
}

int sweep_finish_points(const usm_model *m, const usm_params *p, const usm_sweep_options *opt,
                        usm_sweep_point *pts, size_t n, char msg[USM_MSG_LEN])
{
    const size_t nspans = (n + FINISH_SPAN - 1) / FINISH_SPAN, ns = nspans ? nspans : 1;
    finish_pass fp = {m, p, opt, usm_params_find(opt->over), pts, n, nspans,
                      calloc(ns, sizeof(track_set)), calloc(ns, sizeof(track_set)),
                      calloc(ns, 1), calloc(ns, 1), calloc(n ? n : 1, 1),
                      malloc((n ? n : 1) * sizeof(double[USM_MAX_NU]))};
    int status = USM_EFAILED;
    if (!fp.ends || !fp.starts || !fp.full || !fp.bad || !fp.was_pending || !fp.saved_u) {
        snprintf(msg, USM_MSG_LEN, "out of memory");
        goto done;
    }
    /* the branch's roots, for the spans done again in full */
    for (size_t i = 0; i < n; ++i) {
        fp.was_pending[i] = (unsigned char)pending_point(&pts[i]);
        memcpy(fp.saved_u[i], pts[i].sol.u, sizeof fp.saved_u[i]);
    }
    pool_job job = {nspans, opt->threads, &fp, finish_alloc, finish_free, finish_task, NULL};
    status = pool_run(&job, msg);
    size_t redo = 0;
    for (size_t k = 0; status == USM_OK && k < nspans; ++k)
        if (!span_checked(&fp, k)) {
            const size_t a = k * FINISH_SPAN, b = a + FINISH_SPAN < n ? a + FINISH_SPAN : n;
            for (size_t i = a; i < b; ++i)
                if (fp.was_pending[i]) {
                    memcpy(pts[i].sol.u, fp.saved_u[i], sizeof fp.saved_u[i]);
                    pts[i].roots = SWEEP_ROOTS_PENDING;
                }
            fp.full[k] = 1;
            ++redo;
        }
    /* only the spans to be done again in full have pending points left */
    if (status == USM_OK && redo > 0)
        status = pool_run(&job, msg);
done:
    free(fp.ends);
    free(fp.starts);
    free(fp.full);
    free(fp.bad);
    free(fp.was_pending);
    free(fp.saved_u);
    return status;
}
