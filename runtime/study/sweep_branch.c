/* Pseudo-arclength continuation of the stationary solution, and the events
 * on the branch (fold, tilt-range boundary, stick limit, friction saturation).
 *
 * Math: with z = (u / su, lambda / Lambda) the branch is F(z) = r(u; lambda) = 0,
 * one equation short of a square system.  Keller's bordered system adds one
 * linear row c.z = c0:
 *   tangent    [F_z; t_prev] t = e_n            (F_z from steady_jacobian and the
 *                                                 swept column of steady_jacobian_params)
 *   step       predictor z + h t, corrector Newton on [F; t.(z - z_k) - h] = 0
 *   landing    Newton on [F; z_lambda - g / Lambda] = 0   (a grid value g)
 *   saturation Newton on [F; z_rotor - W / su]     = 0   (rotor speed "infinite")
 * The bordered matrix stays regular at a fold, where F_u alone is singular, so
 * the branch is followed through points where lambda turns.
 *
 * An accepted step from z_k is the arc s -> z(s), s in [0, h], each z(s)
 * corrected onto the branch in the hyperplane t_k.(z - z_k) = s.  Events are
 * roots of scalar functions of s located by Brent's method on that arc:
 *   fold      the lambda component of the tangent (lambda is extremal there, so
 *             the error in lambda is quadratic in the error in s)
 *   boundary  theta(s) - theta_min, theta_max - theta(s)
 *   stick     |F_t| - mu0 F_n
 *   grid      lambda(s) - g, then the landing correction at exactly g.
 */
#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/dense.h"
#include "core/grow.h"
#include "sweep_branch.h"

#define NEWTON_MAX 12
#define NEWTON_TOL 1e-10      /* max |dz| of the last Newton step (scaled units) */
#define H_MAX 0.05            /* longest step: 1/20 of the sweep range in lambda */
#define H_MIN 1e-13
#define COS_MAX_TURN 0.9      /* successive tangents at most ~25 degrees apart */
#define MAX_STEPS 2000000
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
    b->root = usm_root_alloc();
    b->steady = usm_steady_alloc(m);
    return b->root && b->steady ? 0 : -1;
}

void sweep_branch_free(sweep_branch *b)
{
    usm_root_free(b->root);
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

/* ---- the bordered system ------------------------------------------------------ */

static double dot(const sweep_branch *b, const double *x, const double *y)
{
    double d = 0;
    for (int j = 0; j < b->n; ++j)
        d += x[j] * y[j];
    return d;
}

static double lambda_of(const sweep_branch *b, const double *z) { return z[b->nu] * b->scale[b->nu]; }

static void unscale(const sweep_branch *b, const double *z, double *u)
{
    for (int i = 0; i < b->nu; ++i)
        u[i] = z[i] * b->scale[i];
}

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

/* F(z) into F[0..nu-1]; with jac, the scaled F_z into rows 0..nu-1 of A. */
static int eval(sweep_branch *b, const double *z, double *F, int jac)
{
    const int nu = b->nu;
    double u[USM_MAX_NU], J[USM_MAX_NU * USM_MAX_NU], Jp[USM_MAX_NU * USM_NPARAMS];
    if (!admissible(b, lambda_of(b, z)))
        return -1;
    unscale(b, z, u);
    set_lambda(b, lambda_of(b, z));
    b->m->steady_residual(u, &b->p, F);
    for (int i = 0; i < nu; ++i)
        if (!isfinite(F[i]))
            return -1;
    if (!jac)
        return 0;
    b->m->steady_jacobian(u, &b->p, J);
    b->m->steady_jacobian_params(u, &b->p, Jp);
    const int n = b->n;
    for (int i = 0; i < nu; ++i) {
        for (int j = 0; j < nu; ++j)
            b->A[i * n + j] = J[i * nu + j] * b->scale[j];
        b->A[i * n + nu] = Jp[i * USM_NPARAMS + b->col] * b->scale[nu];
    }
    /* rows 0..nu-1 only: the last row is the border, set by solve_bordered */
    for (int k = 0; k < nu * n; ++k)
        if (!isfinite(b->A[k]))
            return -1;
    return 0;
}

/* x = A^{-1} rhs with the last row of A replaced by c (rows 0..nu-1 from eval). */
static int solve_bordered(sweep_branch *b, const double *c, const double *rhs, double *x)
{
    const int n = b->n;
    for (int j = 0; j < n; ++j) {
        b->A[b->nu * n + j] = c[j];
        x[j] = rhs[j];
    }
    if (usm_lu_factor_dense(n, b->A, b->piv) != 0)
        return -1;
    usm_lu_solve_dense(n, b->A, b->piv, x, 1);
    for (int j = 0; j < n; ++j)
        if (!isfinite(x[j]))
            return -1;
    return 0;
}

/* Newton on [F(z); c.z - c0] = 0 from z, in place.  Iterations used, or -1. */
static int correct(sweep_branch *b, double *z, const double *c, double c0)
{
    double F[SWEEP_MAX_N], dz[SWEEP_MAX_N], prev = INFINITY;
    for (int it = 1; it <= NEWTON_MAX; ++it) {
        if (eval(b, z, F, 1) != 0)
            return -1;
        F[b->nu] = dot(b, c, z) - c0;
        for (int j = 0; j < b->n; ++j)
            F[j] = -F[j];
        if (solve_bordered(b, c, F, dz) != 0)
            return -1;
        double norm = 0;
        for (int j = 0; j < b->n; ++j) {
            z[j] += dz[j];
            norm = fmax(norm, fabs(dz[j]));
        }
        if (norm <= NEWTON_TOL)
            return it;
        /* a growing update means the start lies outside Newton's basin of this
         * branch; giving up early lets the step control shorten the step */
        if (it >= 2 && norm > prev)
            return -1;
        prev = norm;
    }
    return -1;
}

/* Unit tangent at z (on the branch), oriented so that c.t > 0. */
static int tangent(sweep_branch *b, const double *z, const double *c, double *t)
{
    double F[SWEEP_MAX_N], rhs[SWEEP_MAX_N] = {0};
    rhs[b->nu] = 1.0;
    if (eval(b, z, F, 1) != 0 || solve_bordered(b, c, rhs, t) != 0)
        return -1;
    const double len = sqrt(dot(b, t, t));
    for (int j = 0; j < b->n; ++j)
        t[j] /= len;
    return 0;
}

/* ---- quantities along the branch --------------------------------------------- */

static void outputs(sweep_branch *b, const double *z, double *y)
{
    double u[USM_MAX_NU];
    unscale(b, z, u);
    set_lambda(b, lambda_of(b, z));
    b->m->steady_outputs(u, &b->p, y);
}

/* |F_t| - mu0 F_n: negative where stick is admissible (as usm_steady_evaluate). */
static double stick_gap(sweep_branch *b, const double *z)
{
    double y[USM_STEADY_COUNT];
    outputs(b, z, y);
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

static void solution_at(sweep_branch *b, const double *z, usm_steady_solution *sol)
{
    memset(sol, 0, sizeof *sol);
    unscale(b, z, sol->u);
    set_lambda(b, lambda_of(b, z));
    usm_steady_evaluate(b->m, &b->p, sol);
}

/* ---- events on the arc of one step ---------------------------------------------- */

typedef struct arc {
    double za[SWEEP_MAX_N], ta[SWEEP_MAX_N]; /* start and tangent of the step */
} arc;

enum { FN_LAMBDA, FN_TANGENT, FN_THETA_LOW, FN_THETA_HIGH, FN_STICK, FN_ROTOR, FN_MONITOR,
       FN_SLOPE };

typedef struct arc_fn {
    sweep_branch *b;
    const arc *a;
    int kind;
    double arg;
    const usm_sweep_monitor *mo;
} arc_fn;

/* ---- user monitors ---------------------------------------------------------------- */

static void solution_at(sweep_branch *b, const double *z, usm_steady_solution *sol);

static double monitor_at(sweep_branch *b, const usm_sweep_monitor *mo, const double *z)
{
    usm_steady_solution sol;
    solution_at(b, z, &sol);
    return mo->fn(&sol, &b->p, mo->ctx);
}

/* Step of the central differences along the tangent (scaled units, where the
 * components of z are of order one): truncation ~1e-12, rounding ~1e-10. */
#define SLOPE_STEP 1e-6

/* dy/ds at z on the branch with unit tangent t: the derivative of y along t,
 * by central differences (y is a smooth function of z off the branch too). */
static double monitor_slope(sweep_branch *b, const usm_sweep_monitor *mo, const double *z,
                            const double *t)
{
    double zp[SWEEP_MAX_N], zm[SWEEP_MAX_N];
    for (int j = 0; j < b->n; ++j) {
        zp[j] = z[j] + SLOPE_STEP * t[j];
        zm[j] = z[j] - SLOPE_STEP * t[j];
    }
    return (monitor_at(b, mo, zp) - monitor_at(b, mo, zm)) / (2.0 * SLOPE_STEP);
}

static int arc_point(sweep_branch *b, const arc *a, double s, double *z)
{
    for (int j = 0; j < b->n; ++j)
        z[j] = a->za[j] + s * a->ta[j];
    return correct(b, z, a->ta, dot(b, a->ta, a->za) + s) >= 0 ? 0 : -1;
}

static double arc_value(double s, void *ctx)
{
    arc_fn *f = ctx;
    sweep_branch *b = f->b;
    double z[SWEEP_MAX_N], t[SWEEP_MAX_N];
    if (arc_point(b, f->a, s, z) != 0)
        return NAN; /* failed: the locator stops */
    switch (f->kind) {
    case FN_LAMBDA:
        return z[b->nu] - f->arg;
    case FN_TANGENT:
        if (tangent(b, z, f->a->ta, t) != 0)
            return NAN;
        return t[b->nu] * b->dir;
    case FN_THETA_LOW:
        return z[0] * b->scale[0] - f->arg;
    case FN_THETA_HIGH:
        return f->arg - z[0] * b->scale[0];
    case FN_ROTOR:
        return z[b->rotor];
    case FN_MONITOR:
        return monitor_at(b, f->mo, z) - f->arg;
    case FN_SLOPE:
        if (tangent(b, z, f->a->ta, t) != 0)
            return NAN;
        return monitor_slope(b, f->mo, z, t);
    default:
        return stick_gap(b, z);
    }
}

/* Root in s of function `kind` on [lo, hi], where its values are flo and fhi
 * of opposite sign (or one of them zero).  0 and *s, or -1. */
static int arc_root_fn(sweep_branch *b, const arc *a, int kind, const usm_sweep_monitor *mo,
                       double arg, double lo, double hi, double flo, double fhi, double epsabs,
                       double *s)
{
    arc_fn f = {b, a, kind, arg, mo};
    const usm_root_stop stop = {epsabs, 0.0, 200};
    if (flo == 0.0 || fhi == 0.0) {
        *s = flo == 0.0 ? lo : hi;
        return 0;
    }
    if ((flo < 0) == (fhi < 0))
        return -1;
    /* FN_LAMBDA: the values at the ends are not evaluated again (that would
     * be two corrections per grid value, a third of landing on it); the
     * other functions are evaluated at the ends afresh */
    return kind == FN_LAMBDA ? usm_root_brent(b->root, arc_value, &f, lo, hi, flo, fhi, &stop, s)
                             : usm_root_brent_eval(b->root, arc_value, &f, lo, hi, &stop, s);
}

static int arc_root(sweep_branch *b, const arc *a, int kind, double arg, double lo, double hi,
                    double flo, double fhi, double epsabs, double *s)
{
    return arc_root_fn(b, a, kind, NULL, arg, lo, hi, flo, fhi, epsabs, s);
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

/* Grid point i from a point on the branch at (nearly) its value. */
static void finish_point(trace *tr, size_t i, double *z)
{
    sweep_branch *b = tr->b;
    const double value = b->grid[i];
    usm_steady_solution sol;
    int roots;
    double e[SWEEP_MAX_N] = {0}, u[USM_MAX_NU];
    e[b->nu] = 1.0;
    /* on the branch at the grid value itself: the start of the polish below,
     * and the result where the polish fails (a failed Newton leaves z as it
     * was, already on the branch near the value) */
    correct(b, z, e, value / b->scale[b->nu]);
    unscale(b, z, u);
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

/* Land on every grid value reached by the arc [0, s_end] (zend = z(s_end)). */
static int land_on_grid(trace *tr, const arc *a, double s_end, const double *zend)
{
    sweep_branch *b = tr->b;
    const int nu = b->nu;
    while (pending(tr)) {
        const double g = b->grid[tr->next] / b->scale[nu];
        double z[SWEEP_MAX_N], sg;
        if ((g - zend[nu]) * b->dir > 0)
            break;
        if (arc_root(b, a, FN_LAMBDA, g, 0.0, s_end, a->za[nu] - g, zend[nu] - g,
                     1e-10 * s_end, &sg) != 0 ||
            arc_point(b, a, sg, z) != 0)
            return -1;
        finish_point(tr, (size_t)tr->next, z);
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

/* Slip model: the rotor speed phidot_R changes sign inside the arc (the rotor
 * stops: the load equals the torque the motor can hold at rest). */
static int arc_stall(trace *tr, const arc *a, double s_end, const double *zend)
{
    sweep_branch *b = tr->b;
    const double w0 = a->za[b->rotor], w1 = zend[b->rotor];
    double s, z[SWEEP_MAX_N];
    char v[64];
    if ((w0 < 0) == (w1 < 0) || w0 == 0.0)
        return 0;
    if (arc_root(b, a, FN_ROTOR, 0.0, 0.0, s_end, w0, w1, 1e-15, &s) != 0 ||
        arc_point(b, a, s, z) != 0)
        return -1;
    /* on the branch at rotor speed 0 exactly: Newton on [F; z_rotor = 0] */
    double e[SWEEP_MAX_N] = {0};
    e[b->rotor] = 1.0;
    if (correct(b, z, e, 0.0) < 0)
        return -1;
    const double lambda = lambda_of(b, z);
    if (!within(tr, lambda))
        return 0;
    usm_steady_solution sol;
    solution_at(b, z, &sol);
    /* driving is phidot_R < 0 (the paper's sign) */
    const int driving_dir = w0 < 0 ? -b->dir : b->dir;
    return emit_event(b, USM_EVENT_STALL, lambda, &sol,
                           "the rotor stands still (phidot_R = 0) at %s: it turns in the driving "
                           "direction %s it and is driven backwards by the load %s it",
                           sweep_value_text(b->info, lambda, v), side(driving_dir),
                           side(-driving_dir))
               ? 0
               : -1;
}

/* Events of the arc [0, s_end] other than its end: the stick limit of a stick
 * model (with slip built in, F_t = mu(v) F_n holds by construction and stick
 * has no meaning), the stall of a slip model. */
static int monitor_event(trace *tr, const arc *a, const usm_sweep_monitor *mo, int kind,
                         double level, double s_end, double g0, double g1, usm_event_type type)
{
    sweep_branch *b = tr->b;
    double s, z[SWEEP_MAX_N];
    char v[64];
    if (arc_root_fn(b, a, kind, mo, level, 0.0, s_end, g0, g1, 1e-15, &s) != 0 ||
        arc_point(b, a, s, z) != 0)
        return -1;
    const double lambda = lambda_of(b, z);
    if (!within(tr, lambda))
        return 0;
    usm_steady_solution sol;
    solution_at(b, z, &sol);
    const double y = mo->fn(&sol, &b->p, mo->ctx);
    usm_sweep_event *e;
    if (type == USM_EVENT_CROSSING)
        e = emit_event(b, type, lambda, &sol, "%s crosses %.10g at %s", mo->name, level,
                       sweep_value_text(b->info, lambda, v));
    else
        e = emit_event(b, type, lambda, &sol, "%s has a %s %.10g at %s", mo->name,
                       type == USM_EVENT_MAXIMUM ? "maximum" : "minimum", y,
                       sweep_value_text(b->info, lambda, v));
    if (!e)
        return -1;
    snprintf(e->monitor, sizeof e->monitor, "%s", mo->name);
    e->monitor_value = y;
    return 0;
}

/* The user monitors' events inside the arc [0, s_end]: level crossings (sign
 * changes of y - level) and extrema (sign changes of dy/ds), each by Brent. */
static int arc_monitors(trace *tr, const arc *a, double s_end, const double *zend)
{
    sweep_branch *b = tr->b;
    const usm_sweep_options *opt = b->opt;
    double tend[SWEEP_MAX_N];
    int have_tend = 0;
    for (int k = 0; k < opt->nmonitors; ++k) {
        const usm_sweep_monitor *mo = &opt->monitors[k];
        const double y0 = monitor_at(b, mo, a->za), y1 = monitor_at(b, mo, zend);
        for (int l = 0; l < mo->nlevels; ++l) {
            const double g0 = y0 - mo->levels[l], g1 = y1 - mo->levels[l];
            if ((g0 < 0) != (g1 < 0) && g0 != 0.0 &&
                monitor_event(tr, a, mo, FN_MONITOR, mo->levels[l], s_end, g0, g1,
                              USM_EVENT_CROSSING) != 0)
                return -1;
        }
        if (!mo->extrema)
            continue;
        if (!have_tend) {
            if (tangent(b, zend, a->ta, tend) != 0)
                return -1;
            have_tend = 1;
        }
        const double d0 = monitor_slope(b, mo, a->za, a->ta), d1 = monitor_slope(b, mo, zend, tend);
        if ((d0 < 0) != (d1 < 0) && d0 != 0.0 &&
            monitor_event(tr, a, mo, FN_SLOPE, 0.0, s_end, d0, d1,
                          d0 > 0 ? USM_EVENT_MAXIMUM : USM_EVENT_MINIMUM) != 0)
            return -1;
    }
    return 0;
}

static int arc_events(trace *tr, const arc *a, double s_end, const double *zend)
{
    sweep_branch *b = tr->b;
    if (b->opt->nmonitors > 0 && arc_monitors(tr, a, s_end, zend) != 0)
        return -1;
    if (b->rotor >= 0)
        return arc_stall(tr, a, s_end, zend);
    const double g0 = stick_gap(b, a->za), g1 = stick_gap(b, zend);
    double s, z[SWEEP_MAX_N];
    char v[64];
    if ((g0 < 0) == (g1 < 0))
        return 0;
    if (arc_root(b, a, FN_STICK, 0.0, 0.0, s_end, g0, g1, 1e-15, &s) != 0 ||
        arc_point(b, a, s, z) != 0)
        return -1;
    const double lambda = lambda_of(b, z);
    if (!within(tr, lambda))
        return 0;
    usm_steady_solution sol;
    solution_at(b, z, &sol);
    /* admissible on the side where the gap is negative */
    const int admissible_dir = g0 < 0 ? -b->dir : b->dir;
    return emit_event(b, USM_EVENT_STICK_LIMIT, lambda, &sol,
                           "F_t = mu0 F_n (mu0 = %g) at %s: stick is admissible %s it, "
                           "not %s",
                           b->p.mu0, sweep_value_text(b->info, lambda, v), side(admissible_dir),
                           side(-admissible_dir))
               ? 0
               : -1;
}

/* The end of the branch inside the arc [0, h] ending at z1 (tangent t1): a fold
 * or the tilt leaving [theta_min, theta_max].  *s_end = h when neither. */
static int arc_end(trace *tr, const arc *a, double h, const double *z1, const double *t1,
                   double *s_end, int *end)
{
    sweep_branch *b = tr->b;
    const double th0 = a->za[0] * b->scale[0], th1 = z1[0] * b->scale[0];
    double s;
    *s_end = h;
    *end = END_STOP;
    if (t1[b->nu] * b->dir <= 0) {
        if (arc_root(b, a, FN_TANGENT, 0.0, 0.0, h, a->ta[b->nu] * b->dir, t1[b->nu] * b->dir,
                     1e-15, &s) != 0)
            return -1;
        *s_end = s;
        *end = END_FOLD;
    }
    if (th1 < b->theta_min) {
        if (arc_root(b, a, FN_THETA_LOW, b->theta_min, 0.0, h, th0 - b->theta_min,
                     th1 - b->theta_min, 1e-15, &s) != 0)
            return -1;
        if (s <= *s_end) {
            *s_end = s;
            *end = END_BOUNDARY;
        }
    } else if (th1 > b->theta_max) {
        if (arc_root(b, a, FN_THETA_HIGH, b->theta_max, 0.0, h, b->theta_max - th0,
                     b->theta_max - th1, 1e-15, &s) != 0)
            return -1;
        if (s <= *s_end) {
            *s_end = s;
            *end = END_BOUNDARY;
        }
    }
    return 0;
}

/* The branch left the tilt range at its lower end zb (theta = theta_min): the
 * residuals are regular at theta = 0 (R* -> R, Z -> H), so the branch runs on
 * through the limit where the tilt vanishes.  That limit, on the branch at
 * theta = 0 exactly: Newton on [F; z_theta = 0] from zb.  0 and zt, or -1
 * when the branch does not reach theta = 0 next to zb. */
static int tilt_zero(trace *tr, const double *zb, double *zt)
{
    sweep_branch *b = tr->b;
    double e[SWEEP_MAX_N] = {0};
    e[0] = 1.0;
    memcpy(zt, zb, sizeof(double) * (size_t)b->n);
    if (correct(b, zt, e, 0.0) < 0)
        return -1;
    /* next to the boundary point: within the tilt's own size of the step */
    const double dl = fabs(zt[b->nu] - zb[b->nu]);
    return dl <= 1e-3 ? 0 : -1;
}

static int report_end(trace *tr, const double *z)
{
    sweep_branch *b = tr->b;
    usm_steady_solution sol;
    char what[USM_MSG_LEN];
    double lambda = lambda_of(b, z);
    usm_event_type type = USM_EVENT_FOLD;
    solution_at(b, z, &sol);
    if (tr->end == END_FOLD)
        end_text(tr, what, sizeof what, "fold: the branch turns back (d lambda/ds = 0)", lambda);
    else {
        const int low = sol.theta < 0.5 * (b->theta_min + b->theta_max);
        double zt[SWEEP_MAX_N];
        char head[200];
        if (low && tilt_zero(tr, z, zt) == 0) {
            lambda = lambda_of(b, zt);
            solution_at(b, zt, &sol);
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
 * that the law equals its supremum to rounding: Newton on [F; z_rotor = W]. */
static int saturation(trace *tr, const double *z1, double *zs)
{
    sweep_branch *b = tr->b;
    const int r = b->rotor;
    double y[USM_STEADY_COUNT], e[SWEEP_MAX_N] = {0};
    outputs(b, z1, y);
    const double v = y[USM_STEADY_V_REL], w = z1[r] * b->scale[r];
    if (!(fabs(v) > 0) || !(fabs(w) > 0))
        return -1;
    const double W = w * (V_HUGE / fabs(v));
    memcpy(zs, z1, sizeof(double) * (size_t)b->n);
    zs[r] = W / b->scale[r];
    e[r] = 1.0;
    return correct(b, zs, e, zs[r]) >= 0 ? 0 : -1;
}

static double mu_ratio(sweep_branch *b, const double *z)
{
    double y[USM_STEADY_COUNT];
    outputs(b, z, y);
    const double lim = friction_limit(b, y[USM_STEADY_V_REL]);
    return lim > 0 ? fabs(y[USM_STEADY_F_T] / y[USM_STEADY_F_N]) / lim : 0.0;
}

/* Grid points between the branch at z1 and the saturation point zs: the
 * rotor speed diverges like 1/(lambda_sat - lambda), which continuation would
 * approach in ever shorter steps; the full search brackets the rotor speed
 * directly.  Of its roots the one nearest the branch's tilt is taken. */
static void land_before_saturation(trace *tr, const double *z1, const double *zs)
{
    sweep_branch *b = tr->b;
    const int nu = b->nu;
    while (pending(tr)) {
        const double value = b->grid[tr->next];
        const double g = value / b->scale[nu];
        if ((g - zs[nu]) * b->dir >= 0)
            break;
        const double w = (g - z1[nu]) / (zs[nu] - z1[nu]);
        const double theta = (z1[0] + w * (zs[0] - z1[0])) * b->scale[0];
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
static int check_saturation(trace *tr, const double *z1)
{
    sweep_branch *b = tr->b;
    double zs[SWEEP_MAX_N], y[USM_STEADY_COUNT];
    char v[64];
    if (b->rotor < 0 || tr->sat_checked || mu_ratio(b, z1) < SAT_TRIGGER)
        return 0;
    outputs(b, z1, y);
    if (!in_tail(b, y[USM_STEADY_V_REL]))
        return 0;
    if (saturation(tr, z1, zs) != 0)
        return 0; /* keep following the branch; the step control decides */
    const double lambda = lambda_of(b, zs);
    if (!within(tr, lambda) || (lambda - lambda_of(b, z1)) * b->dir <= 0) {
        tr->sat_checked = 1;
        return 0;
    }
    land_before_saturation(tr, z1, zs);
    double u[USM_MAX_NU];
    outputs(b, zs, y);
    unscale(b, zs, u);
    tr->end = END_SATURATION;
    tr->end_value = lambda;
    tr->end_type = USM_EVENT_FRICTION_SATURATION;
    emit_event(b, USM_EVENT_FRICTION_SATURATION, lambda, NULL,
                    "F_t / F_n reaches the friction law's supremum %.6g at %s (theta = %.6g rad): "
                    "the rotor speed diverges and no stationary solution exists %s it",
                    fabs(y[USM_STEADY_F_T] / y[USM_STEADY_F_N]), sweep_value_text(b->info, lambda, v),
                    u[0], side(b->dir));
    return 1;
}

/* Scale each unknown by the largest size it has had: the rotor speed may grow
 * by many orders of magnitude towards friction saturation. */
static void rescale(sweep_branch *b, double *z, double *t)
{
    int changed = 0;
    for (int i = 0; i < b->nu; ++i) {
        const double size = fabs(z[i] * b->scale[i]);
        /* the tilt by its own size in both directions: it may fall by decades
         * (theta ~ 1/c_r), and a step measured in the first size would then
         * jump across theta = 0 */
        if (size > b->scale[i] || (i == 0 && size < 0.25 * b->scale[i] && size > 0)) {
            const double f = b->scale[i] / size;
            z[i] *= f;
            t[i] *= f;
            b->scale[i] = size;
            changed = 1;
        }
    }
    if (changed) {
        const double len = sqrt(dot(b, t, t));
        for (int j = 0; j < b->n; ++j)
            t[j] /= len;
    }
}

/* The arc of one accepted step [0, h] to z1: its end (s_end, zend), its events
 * and the grid points on it.  0 or -1. */
static int step_arc(trace *tr, const arc *a, double h, const double *z1, const double *t1,
                    double *s_end, double *zend)
{
    sweep_branch *b = tr->b;
    if (arc_end(tr, a, h, z1, t1, s_end, &tr->end) != 0)
        return -1;
    if (tr->end == END_STOP)
        memcpy(zend, z1, sizeof(double) * (size_t)b->n);
    else if (arc_point(b, a, *s_end, zend) != 0)
        return -1;
    if (arc_events(tr, a, *s_end, zend) != 0 || land_on_grid(tr, a, *s_end, zend) != 0)
        return -1;
    return 0;
}

/* Follow the branch from the solution u0 at lambda0 in direction b->dir until
 * lambda passes tr->stop or the branch ends.  0, or -1 when it is lost. */
static int follow(trace *tr, const double *u0, double lambda0, double h)
{
    sweep_branch *b = tr->b;
    const int nu = b->nu, n = b->n;
    double z[SWEEP_MAX_N], t[SWEEP_MAX_N], z1[SWEEP_MAX_N], t1[SWEEP_MAX_N];
    double e[SWEEP_MAX_N] = {0};
    arc a;
    tr->end = END_STOP;
    for (int i = 0; i < nu; ++i)
        z[i] = u0[i] / b->scale[i];
    z[nu] = lambda0 / b->scale[nu];
    e[nu] = b->dir;
    if (tangent(b, z, e, t) != 0)
        return -1;
    for (long step = 0; step < MAX_STEPS; ++step) {
        for (int j = 0; j < n; ++j)
            z1[j] = z[j] + h * t[j];
        const int its = correct(b, z1, t, dot(b, t, z) + h);
        double turn = -1;
        if (its >= 0 && tangent(b, z1, t, t1) == 0)
            turn = dot(b, t, t1);
        if (turn < COS_MAX_TURN) {
            if ((h *= 0.5) < H_MIN)
                return -1;
            continue;
        }
        memcpy(a.za, z, sizeof z);
        memcpy(a.ta, t, sizeof t);
        double s_end, zend[SWEEP_MAX_N];
        /* A Newton correction inside the arc may fail where the branch curves
         * strongly (a parameter over decades): the step is then retried
         * shorter, with what the failed attempt found dropped. */
        const ptrdiff_t next = tr->next;
        if (step_arc(tr, &a, h, z1, t1, &s_end, zend) != 0) {
            discard(b);
            tr->next = next;
            tr->end = END_STOP;
            if ((h *= 0.5) < H_MIN)
                return -1;
            continue;
        }
        flush(b);
        if (tr->end != END_STOP) {
            if (within(tr, lambda_of(b, zend))) {
                const int rc = report_end(tr, zend);
                flush(b);
                return rc;
            }
            tr->end = END_STOP; /* the branch ends beyond the range asked for */
            return 0;
        }
        if (!within(tr, lambda_of(b, z1)))
            return 0;
        if (check_saturation(tr, z1)) {
            flush(b);
            return 0;
        }
        memcpy(z, z1, sizeof z1);
        memcpy(t, t1, sizeof t1);
        rescale(b, z, t);
        if (its <= 3 && turn > 0.995)
            h = fmin(2.0 * h, H_MAX);
        else if (its >= 6)
            h *= 0.5;
    }
    return -1;
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
    const double h0 = fmin(H_MAX, 0.5 / (double)(n - 1));

    if (i > 0) {
        /* Where does the solution appear?  Follow the branch back to `from`:
         * a fold or range boundary on the way is an event, and grid points
         * the full search missed are landed on. */
        trace back = {b, (ptrdiff_t)i - 1, -1, opt->from, 0, END_STOP, 0, USM_EVENT_FOLD};
        b->dir = -dir;
        follow(&back, start.u, grid[i], h0);
        discard(b);
    }
    for (;;) {
        trace tr = {b, (ptrdiff_t)i + 1, 1, opt->to, 0, END_STOP, 0, USM_EVENT_FOLD};
        b->dir = dir;
        setup_branch(b, start.u);
        if (follow(&tr, start.u, grid[i], h0) == 0) {
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

typedef struct finish_pass {
    const usm_model *m;
    const usm_params *p;
    const usm_sweep_options *opt;
    const usm_param_info *info;
    usm_sweep_point *pts;
} finish_pass;

static void *finish_alloc(void *ctx)
{
    const finish_pass *fp = ctx;
    return usm_steady_alloc(fp->m);
}

static void finish_free(void *state) { usm_steady_free(state); }

/* finish_point's full search and polish for grid point i (pts[i].sol.u holds
 * the branch's root there), a task of the worker pool. */
static int finish_task(void *ctx, void *state, size_t i)
{
    const finish_pass *fp = ctx;
    usm_sweep_point *pt = &fp->pts[i];
    usm_steady *st = state;
    if (!pt->converged || pt->roots != SWEEP_ROOTS_PENDING)
        return 0;
    const int nu = fp->m->nu;
    double u[USM_MAX_NU];
    memcpy(u, pt->sol.u, sizeof u);
    usm_params q = *fp->p;
    *usm_params_field(&q, fp->info) = pt->value;
    const usm_steady_solution *r = NULL;
    int roots = 0;
    if (usm_steady_solve(st, &q, &fp->opt->steady) == USM_OK) {
        roots = (int)usm_steady_count(st);
        for (size_t k = 0; k < usm_steady_count(st) && !r; ++k)
            if (same_unknowns_nu(nu, u, usm_steady_root(st, k)->u))
                r = usm_steady_root(st, k);
    }
    /* the branch's root missed by the search is one more root */
    if (!r)
        roots++;
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
    return 0;
}

int sweep_finish_points(const usm_model *m, const usm_params *p, const usm_sweep_options *opt,
                        usm_sweep_point *pts, size_t n, char msg[USM_MSG_LEN])
{
    finish_pass fp = {m, p, opt, usm_params_find(opt->over), pts};
    pool_job job = {n, opt->threads, &fp, finish_alloc, finish_free, finish_task, NULL};
    return pool_run(&job, msg);
}
