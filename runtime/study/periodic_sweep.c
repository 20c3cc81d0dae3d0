/* Continuation of the periodic orbit in one parameter, with its events
 * (usm_periodic_sweep.h), posed to the continuation engine (cont/,
 * usm_cont.h).
 *
 * The zero problem: the orbit's periodicity r(x0, lambda) = 0 in the
 * non-cyclic components of the state at t0 and the swept parameter
 * (usm_periodic_shoot, solve/periodic_internal.h): its Jacobian the
 * monodromy's non-cyclic block minus I and a forward difference in lambda
 * (one period of the state alone).  The engine works in z = (x0 / the
 * shooting's state scales, lambda / the range), the scales growing with the
 * unknowns (the rotor speed diverges towards friction saturation); it
 * predicts, corrects, controls the step and locates the zeros of the test
 * functions on each step's arc to event_tol in the scaled arclength:
 *   fold              its own (d lambda/ds); the branch ends there
 *   contact           F_n_min, the minimum over the orbit of the normal force
 *   stick             stick models: the maximum over the orbit of
 *                     |F_t| - mu0 F_n (minus the least stick margin), zero
 *                     where friction_needed_max = mu0 and defined where the
 *                     contact opens too
 *   stability         the largest non-cyclic |multiplier| - 1
 * Each extremum over the orbit is the extreme sample refined by Brent on the
 * zero of its time derivative on the re-integrated state (solve/periodic.c,
 * exact_extreme): a smooth function of the orbit, so Brent on the arc finds
 * the same zero whatever the grid.
 * This file keeps what is the sweep's own: the grid values landed on
 * (Newton with lambda fixed, usm_cont_correct_fixed, from the step's chord),
 * the orbits kept for the points and events, the friction saturation
 * (usm_periodic_saturation), and the events' texts.
 */
#include "periodic_sweep_internal.h"
#include "periodic_sweep_state.h"

#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/grid.h"
#include "core/dense.h"
#include "core/grow.h"
#include "usm_cont.h"
#include "solve/periodic_internal.h"

#define H_MAX 0.25 /* longest step in the scaled arclength (lambda: of the range) */
#define H_MIN 1e-9 /* shortest: below it the branch is lost */
/* The forward difference in lambda for the Jacobian's last column, of the
 * range: its error, 1e-5 of the curvature and the residual's noise floor
 * (3e-10 .. 8e-10 of the scales, the twist angle's) over 1e-5, slows
 * Newton's last digits only; the branch is fixed by r alone.  (At 1e-7 the
 * noise made the column 5e-3 wrong and Newton linear at that rate.) */
#define DLAM 1e-5
/* The corrector's tolerance on its update (scaled): above that noise floor,
 * which the default 1e-10 is not (Newton then stalls and the step fails);
 * at 1e-7 an event's orbit was 2.4e-9 off its limit (friction_needed_max
 * against mu0), at 1e-8 4e-10. */
#define NEWTON_TOL 1e-8
/* The chord Newton of a landing: at most this many periods of the state
 * alone, stopping below CHORD_TOL times the shooting's tolerance or at the
 * residual's noise floor (the confirming shot with the variational
 * equations takes other steps, and its residual differs from the state
 * alone's by up to 1e-9 of the scales there). */
#define CHORD_MAX 6
#define CHORD_TOL 0.25
#define NCACHE 4 /* orbits kept (the points a step's tests and events ask for) */
/* Slip models: once friction_needed_max reaches this fraction of the
 * friction law's supremum, the saturation point is computed directly (as the
 * stationary sweep, study/sweep_branch.c). */
#define SAT_TRIGGER 0.999
#define SAT_NEAR 0.99 /* where a lost branch is checked for saturation */


void usm_periodic_sweep_options_default(usm_periodic_sweep_options *opt)
{
    memset(opt, 0, sizeof *opt);
    opt->points = 101;
    opt->event_tol = 1e-11;
    usm_periodic_options_default(&opt->periodic);
}

usm_periodic_sweep *usm_periodic_sweep_alloc(const usm_model *m)
{
    usm_periodic_sweep *s = calloc(1, sizeof *s);
    if (!s)
        return NULL;
    s->m = m;
    if (!(s->w = usm_periodic_alloc(m))) {
        free(s);
        return NULL;
    }
    return s;
}

void usm_periodic_sweep_free(usm_periodic_sweep *s)
{
    if (!s)
        return;
    usm_periodic_free(s->w);
    usm_hybrid_free(s->hy);
    free(s->pts);
    free(s->ev);
    free(s);
}

size_t usm_periodic_sweep_count(const usm_periodic_sweep *s) { return s->npts; }
size_t usm_periodic_sweep_event_count(const usm_periodic_sweep *s) { return s->nev; }
const char *usm_periodic_sweep_message(const usm_periodic_sweep *s) { return s->msg; }
const usm_model *usm_periodic_sweep_model(const usm_periodic_sweep *s) { return s->m; }
const char *usm_periodic_sweep_over(const usm_periodic_sweep *s) { return s->over; }
const char *usm_periodic_sweep_unit(const usm_periodic_sweep *s) { return s->unit; }

const usm_periodic_point *usm_periodic_sweep_point_at(const usm_periodic_sweep *s, size_t i)
{
    return i < s->npts ? &s->pts[i] : NULL;
}

const usm_periodic_event *usm_periodic_sweep_event_at(const usm_periodic_sweep *s, size_t i)
{
    return i < s->nev ? &s->ev[i] : NULL;
}

/* The orbit at parameter value v from the start state x0 (NULL: the ideal
 * motor's). */
static int solve_at(usm_periodic_sweep *s, double v, const double *x0, usm_periodic_result *r)
{
    usm_params q = s->p;
    *usm_params_field(&q, s->info) = v;
    return usm_periodic_solve(s->w, &q, x0, &s->popt, r);
}


/* ---- the problem posed to the engine --------------------------------------------- */

/* One orbit at a point of the branch, with what the tests ask of it: each
 * computed when first asked for (NaN until then; full 0 until r is). */
typedef struct orbit_slot {
    double x[USM_MAX_NX + 1];
    int used, full;
    usm_periodic_result r;
    double q[3]; /* the tests' quantities, Q_* */
} orbit_slot;

enum { Q_FN_MIN, Q_STICK, Q_MODULUS };

typedef struct branch {
    usm_periodic_sweep *s;
    usm_cont *c;
    int k, N;                 /* equations (non-cyclic states), unknowns (k + 1) */
    int idx[USM_MAX_NX];      /* the non-cyclic states */
    double xfull[USM_MAX_NX]; /* the start state: the cyclic components carried */
    double scale[USM_MAX_NX + 1];
    double dlam;
    int shot;                 /* the solver's last shot was at shot_x */
    double shot_x[USM_MAX_NX + 1];
    orbit_slot cache[NCACHE];
    int next_slot;
    int t_contact, t_stick, t_stab; /* the engine's indices of the tests (-1: none) */
    double lu[USM_MAX_NX * USM_MAX_NX]; /* the chord Newton's factored matrix */
    int piv[USM_MAX_NX], have_lu;
} branch;

static int same_x(const branch *b, const double *a, const double *c)
{
    return memcmp(a, c, sizeof(double) * (size_t)b->N) == 0;
}

/* The state at t0 and the parameters of the unknowns x. */
static void unpack(const branch *b, const double *x, double *x0, usm_params *q)
{
    memcpy(x0, b->xfull, sizeof(double) * (size_t)b->s->m->nx);
    for (int a = 0; a < b->k; ++a)
        x0[b->idx[a]] = x[a];
    *q = b->s->p;
    *usm_params_field(q, b->s->info) = x[b->k];
}

/* The swept parameter inside its physical range: a step must not carry the
 * branch to mode_split < 0 or f <= 0. */
static int admissible(const branch *b, double lambda)
{
    char msg[USM_MSG_LEN];
    return isfinite(lambda) &&
           usm_param_check_value(usm_param_index(b->s->info), lambda, msg) == USM_OK;
}

static int chord_factor(branch *b, const double *J);
static int shoot(branch *b, const double *x, double *F, double *J)
{
    double x0[USM_MAX_NX];
    usm_params q;
    b->shot = 0;
    if (!admissible(b, x[b->k]))
        return -1;
    unpack(b, x, x0, &q);
    if (usm_periodic_shoot(b->s->w, &q, b->s->info, b->dlam, x0, F, J) != USM_OK)
        return -1;
    memcpy(b->shot_x, x, sizeof(double) * (size_t)b->N);
    b->shot = 1;
    if (J)
        chord_factor(b, J);
    return 0;
}

/* The engine's residual and Jacobian. */
static int residual(const double *x, double *F, double *J, void *ctx)
{
    return shoot(ctx, x, F, J);
}

/* The slot of the orbit at x on the branch (kept: the tests of one point
 * share it), the solver's last shot at x; NULL when the shot fails. */
static orbit_slot *slot_at(branch *b, const double *x)
{
    double F[USM_MAX_NX];
    orbit_slot *o = NULL;
    for (int i = 0; i < NCACHE && !o; ++i)
        if (b->cache[i].used && same_x(b, b->cache[i].x, x))
            o = &b->cache[i];
    if (!(b->shot && same_x(b, b->shot_x, x)) && shoot(b, x, F, NULL) != 0)
        return NULL;
    if (o)
        return o;
    o = &b->cache[b->next_slot];
    b->next_slot = (b->next_slot + 1) % NCACHE;
    memcpy(o->x, x, sizeof(double) * (size_t)b->N);
    o->used = 1;
    o->full = 0;
    o->q[0] = o->q[1] = o->q[2] = NAN;
    return o;
}

/* The full orbit at x (the points' and events'), or NULL when its shot or
 * multipliers fail. */
static orbit_slot *orbit_at(branch *b, const double *x)
{
    for (int i = 0; i < NCACHE; ++i)
        if (b->cache[i].used && b->cache[i].full && same_x(b, b->cache[i].x, x))
            return &b->cache[i];
    orbit_slot *o = slot_at(b, x);
    if (!o || usm_periodic_shoot_result(b->s->w, &o->r) != USM_OK)
        return NULL;
    o->full = 1;
    return o;
}

/* A test's quantity at x: of the full orbit where it was formed, else the
 * one extreme (or the multipliers) alone. */
static double quantity(branch *b, const double *x, int q)
{
    for (int i = 0; i < NCACHE; ++i) {
        const orbit_slot *o = &b->cache[i];
        if (o->used && same_x(b, o->x, x) && !isnan(o->q[q]))
            return o->q[q];
        if (o->used && o->full && q != Q_STICK && same_x(b, o->x, x))
            return q == Q_FN_MIN ? o->r.F_n_min : o->r.floquet.max_modulus;
    }
    orbit_slot *o = slot_at(b, x);
    if (!o)
        return NAN;
    usm_periodic *w = b->s->w;
    o->q[q] = q == Q_FN_MIN    ? usm_periodic_shoot_F_n_min(w)
              : q == Q_STICK   ? usm_periodic_shoot_stick_excess(w)
                               : usm_periodic_shoot_max_modulus(w);
    return o->q[q];
}

static double test_contact(const double *x, const double *dx, void *ctx)
{
    (void)dx;
    return quantity(ctx, x, Q_FN_MIN);
}

static double test_stability(const double *x, const double *dx, void *ctx)
{
    (void)dx;
    return quantity(ctx, x, Q_MODULUS) - 1.0;
}

static double test_stick(const double *x, const double *dx, void *ctx)
{
    (void)dx;
    return quantity(ctx, x, Q_STICK);
}

/* Scale each state by the largest size it has had (the rotor speed grows
 * without bound towards friction saturation, and a step measured in its
 * first size would shrink to nothing). */
static int rescale(branch *b, const double *x)
{
    int changed = 0;
    for (int a = 0; a < b->k; ++a)
        if (fabs(x[a]) > b->scale[a]) {
            b->scale[a] = fabs(x[a]);
            changed = 1;
        }
    return changed ? usm_cont_set_scale(b->c, b->scale) : 0;
}

/* The engine and its tests for the orbit r0 at lambda0 (solved by
 * usm_periodic_solve, whose scales the shooting keeps).  0, or -1 when out
 * of memory. */
static int setup(branch *b, usm_periodic_sweep *s, const usm_periodic_sweep_options *opt,
                 size_t npts)
{
    usm_cont_options o;
    double sc[USM_MAX_NX];
    memset(b, 0, sizeof *b);
    b->s = s;
    b->k = usm_periodic_shoot_layout(s->w, b->idx, sc);
    b->N = b->k + 1;
    for (int a = 0; a < b->k; ++a)
        b->scale[a] = sc[b->idx[a]];
    b->scale[b->k] = s->range;
    b->dlam = DLAM * s->range;
    b->t_contact = b->t_stick = b->t_stab = -1;
    if (!(b->c = usm_cont_alloc(b->k)))
        return -1;
    usm_cont_set_problem(b->c, residual, b);
    usm_cont_options_default(&o);
    o.h_max = H_MAX;
    o.h_min = H_MIN;
    o.h0 = fmin(H_MAX, 1.0 / (double)(npts > 1 ? npts - 1 : 1));
    o.event_tol = opt->event_tol;
    o.newton_tol = NEWTON_TOL;
    o.across_fold = 0;
    if (usm_cont_set_options(b->c, &o) != 0 || usm_cont_set_scale(b->c, b->scale) != 0 ||
        (b->t_contact = usm_cont_add_test(b->c, test_contact, b, USM_CONT_TEST_MONITOR | USM_CONT_TEST_POINT)) < 0 ||
        (b->t_stab = usm_cont_add_test(b->c, test_stability, b, USM_CONT_TEST_MONITOR | USM_CONT_TEST_POINT)) < 0)
        return -1;
    /* slip built in: F_t = mu(v) F_n, stick has no meaning */
    if (!s->m->friction &&
        (b->t_stick = usm_cont_add_test(b->c, test_stick, b, USM_CONT_TEST_MONITOR | USM_CONT_TEST_POINT)) < 0)
        return -1;
    return 0;
}

/* ---- events ------------------------------------------------------------------- */

/* The event of test `test` at the orbit r (value v); before: the test's value
 * at the step's start (rising: > 0 after it, in sweep order).  openings: the
 * times a period the contact opens on the step's open end, at open_v
 * (contact only), counted there, not assumed. */
static int emit_located(usm_periodic_sweep *s, const branch *b, int test, double v,
                        const usm_periodic_result *r, int dir_up, int rising, int openings,
                        double open_v)
{
    char times[32], ot[96];
    psweep_value_text(s, open_v, ot);
    if (openings == 1)
        snprintf(times, sizeof times, "once");
    else if (openings == 2)
        snprintf(times, sizeof times, "twice");
    else
        snprintf(times, sizeof times, "%d times", openings);
    char vt[96];
    psweep_value_text(s, v, vt);
    const char *inc = dir_up ? "increases" : "decreases";
    if (test == b->t_contact)
        return psweep_event_add(s, rising && s->m->unilateral ? USM_PEVENT_CONTACT_REGAINED
                                                       : USM_PEVENT_CONTACT_LOSS, v, r,
                         "F_n_min = 0 at %s: the contact %s %s a period as %s %s (counted on "
                         "the orbit at %s)", vt,
                         rising ? "closes again, where it opened" : "opens", times, s->over, inc,
                         ot)
                   ? 0 : -1;
    if (test == b->t_stick)
        return psweep_event_add(s, USM_PEVENT_STICK_LOSS, v, r,
                         "friction_needed_max = mu0 = %g at %s: stick %s as %s %s", s->p.mu0,
                         vt, rising ? "fails somewhere on the orbit (intermittent slip)"
                                    : "holds again over the whole orbit",
                         s->over, inc)
                   ? 0 : -1;
    return psweep_stability_add(s, v, r, &r->floquet, r->period, "the orbit", 1, dir_up, rising)
               ? 0 : -1;
}

/* The events the engine located in its last step (from xa to xb), in the
 * order of the arclength, which is the sweep's (the branch ends at a fold).
 * 0; 1 when an event's orbit failed (its shot, or its multipliers); -1 when
 * out of memory. */
static int step_events(branch *b, const double *xa, const double *xb, int dir_up)
{
    usm_periodic_sweep *s = b->s;
    for (int i = 0; i < usm_cont_event_count(b->c); ++i) {
        const usm_cont_event *e = usm_cont_event_at(b->c, i);
        if (e->test == USM_CONT_FOLD)
            continue;
        const orbit_slot *o = orbit_at(b, e->x);
        if (!o)
            return 1;
        const usm_periodic_result r = o->r;
        int openings = 0;
        double open_v = NAN;
        if (e->test == b->t_contact) {
            /* at the located orbit F_n_min is 0 to rounding, too close to
             * count its dips: counted on the step's open end */
            const double *xo = e->before < 0 ? xa : xb;
            const orbit_slot *oo = orbit_at(b, xo);
            openings = oo ? oo->r.openings_per_period : 0;
            open_v = xo[b->k];
        }
        if (emit_located(s, b, e->test, e->x[b->k], &r, dir_up, e->before < 0, openings,
                         open_v) != 0)
            return -1;
    }
    return 0;
}

/* The fold that ended the branch at x. */
static int fold_event(usm_periodic_sweep *s, const double *x, int k)
{
    char vt[96];
    psweep_value_text(s, x[k], vt);
    return psweep_event_add(s, USM_PEVENT_FOLD, x[k], NULL,
                            "the branch turns back at %s (d%s/ds = 0 on the pseudo-arclength; "
                            "a real multiplier is +1 there): no orbit on this branch beyond it",
                            vt, s->over)
               ? 0 : -1;
}

/* Friction saturation ahead of the orbit (v, r) of a slip model, between v
 * and `to`: s->sat 1 and s->sat_value when located there, else -1. */
static void find_saturation(usm_periodic_sweep *s, double v, const usm_periodic_result *r,
                            double to)
{
    usm_params q = s->p;
    double ls = NAN;
    *usm_params_field(&q, s->info) = v;
    const double dir = to > v ? 1.0 : -1.0;
    s->sat = -1;
    /* its Newton sets scales of its own: the branch's shooting keeps its */
    int idx[USM_MAX_NX];
    double scale[USM_MAX_NX];
    usm_periodic_shoot_layout(s->w, idx, scale);
    const int rc = usm_periodic_saturation(s->w, &q, s->info, r->x0, s->range, s->tol, &s->popt,
                                           &ls);
    usm_periodic_shoot_set_scale(s->w, scale);
    if (rc == USM_OK && (ls - v) * dir > 0 && (ls - to) * dir <= 0) {
        s->sat = 1;
        s->sat_value = ls;
    }
}

/* The friction_saturation event at s->sat_value. */
static int emit_saturation(usm_periodic_sweep *s, int dir_up)
{
    char vt[96];
    psweep_value_text(s, s->sat_value, vt);
    return psweep_event_add(s, USM_PEVENT_FRICTION_SATURATION, s->sat_value, NULL,
                     "F_t / F_n reaches the friction law's supremum %.6g over the whole orbit at "
                     "%s: the rotor speed diverges and no periodic orbit exists %s it",
                     usm_periodic_friction_supremum(s->m, &s->p), vt,
                     dir_up ? "above" : "below")
               ? 0 : -1;
}

/* The k x k block of J (k rows of k + 1) factored into b->lu: the chord
 * Newton's matrix.  0, or -1 when singular. */
static int chord_factor(branch *b, const double *J)
{
    const int k = b->k;
    for (int a = 0; a < k; ++a)
        for (int c = 0; c < k; ++c)
            b->lu[a * k + c] = J[a * (k + 1) + c];
    b->have_lu = usm_lu_factor_dense(k, b->lu, b->piv) == 0;
    return b->have_lu ? 0 : -1;
}

/* Newton on the orbit's periodicity with lambda held at x[k], in place from
 * x, to usm_periodic_solve's tolerance on the same residual.  A chord
 * Newton first: the monodromy's block of the last Jacobian formed (at the
 * step's end, or the last point landed on: a step away at most) with one
 * period of the state alone a step, a tenth of a period with the
 * variational equations; then, at the point it accepts, one shot with
 * them, which gives the orbit there and confirms the residual (else full
 * Newton steps from it).  The solver's last shot is at the accepted x, so
 * that the orbit there costs no further period.  Iterations (shots with the
 * monodromy), or -1. */
static int land(branch *b, double *x)
{
    const int k = b->k, N = b->N;
    double F[USM_MAX_NX], J[USM_MAX_NX * (USM_MAX_NX + 1)], x0[USM_MAX_NX];
    usm_params q;
    const double tol = b->s->popt.tol;
    if (!admissible(b, x[k]))
        return -1;
    double prev = INFINITY;
    for (int it = 0; b->have_lu && it < CHORD_MAX; ++it) {
        double res = 0;
        unpack(b, x, x0, &q);
        b->shot = 0;
        if (usm_periodic_shoot_state(b->s->w, &q, x0, F) != USM_OK)
            break;
        for (int a = 0; a < k; ++a)
            res = fmax(res, fabs(F[a]));
        /* converged, or at the residual's noise floor (the twist angle's,
         * 2e-10 .. 1e-9 of the scales), where a step only stirs the noise */
        if (res <= CHORD_TOL * tol || (res <= tol && res > 0.25 * prev))
            break;
        prev = res;
        usm_lu_solve_dense(k, b->lu, b->piv, F, 1);
        for (int a = 0; a < k; ++a)
            x[a] -= F[a];
    }
    for (int it = 0; it <= b->s->popt.max_iter; ++it) {
        double res = 0;
        b->shot = 0;
        unpack(b, x, x0, &q);
        if (usm_periodic_shoot(b->s->w, &q, b->s->info, 0.0, x0, F, J) != USM_OK)
            return -1;
        memcpy(b->shot_x, x, sizeof(double) * (size_t)N);
        b->shot = 1;
        for (int a = 0; a < k; ++a)
            res = fmax(res, fabs(F[a]));
        if (chord_factor(b, J) != 0)
            return -1;
        if (res <= tol)
            return it;
        usm_lu_solve_dense(k, b->lu, b->piv, F, 1);
        for (int a = 0; a < k; ++a)
            x[a] -= F[a];
    }
    return -1;
}

/* The point at lambda = target on the cubic Hermite interpolant of the step
 * from (xa, dxa) to (xb, dxb) in the arclength s in [0, h] (dx: the unit
 * directions, scaled as the engine's, d x/ds of the arc being dx / (ta.tb)
 * at its end): its error is fourth order in the step, where the chord's is
 * second, so Newton lands in one or two periods. */
static void hermite_at(const branch *b, const double *xa, const double *dxa, const double *xb,
                       const double *dxb, double h, double target, double *x)
{
    const int N = b->N, k = b->k;
    double cab = 0, m0[USM_MAX_NX + 1], m1[USM_MAX_NX + 1];
    for (int j = 0; j < N; ++j)
        cab += dxa[j] / b->scale[j] * (dxb[j] / b->scale[j]);
    for (int j = 0; j < N; ++j) {
        m0[j] = h * dxa[j];
        m1[j] = cab > 0.5 ? h * dxb[j] / cab : xb[j] - xa[j];
    }
    /* lambda(u) = target, u = s / h in [0, 1]: bisection, then the point */
    double lo = 0, hi = 1, u = 0.5;
    const double dir = xb[k] > xa[k] ? 1.0 : -1.0;
    for (int it = 0; it < 60; ++it) {
        u = 0.5 * (lo + hi);
        const double h00 = (1 + 2 * u) * (1 - u) * (1 - u), h10 = u * (1 - u) * (1 - u),
                     h01 = u * u * (3 - 2 * u), h11 = u * u * (u - 1);
        const double l = h00 * xa[k] + h10 * m0[k] + h01 * xb[k] + h11 * m1[k];
        if ((l - target) * dir < 0)
            lo = u;
        else
            hi = u;
    }
    const double h00 = (1 + 2 * u) * (1 - u) * (1 - u), h10 = u * (1 - u) * (1 - u),
                 h01 = u * u * (3 - 2 * u), h11 = u * u * (u - 1);
    for (int j = 0; j < N; ++j)
        x[j] = h00 * xa[j] + h10 * m0[j] + h01 * xb[j] + h11 * m1[j];
    x[k] = target;
}

/* The grid values g[next], g[next + 1], ... reached by the last step (from
 * xa to xb, directions dxa and dxb), landed on: Newton with lambda held
 * (land) from the step's Hermite interpolant at the value, or from the arc's
 * point at the value's share where that fails.  Each point's orbit into
 * s->pts.  *next advanced past them.  0, or -1 when a landing failed. */
static int land_on_grid(branch *b, const usm_periodic_sweep_options *opt, const double *xa,
                        const double *dxa, double s_end, const double *xb, const double *dxb,
                        int *next)
{
    usm_periodic_sweep *s = b->s;
    const int n = opt->points, k = b->k;
    const double dir = opt->to > opt->from ? 1.0 : -1.0, la = xa[k], lb = xb[k];
    while (*next < n) {
        const double target = usm_grid_value(opt->from, opt->to, *next, n);
        double x[USM_MAX_NX + 1];
        if ((target - lb) * dir > 0)
            break;
        hermite_at(b, xa, dxa, xb, dxb, s_end, target, x);
        int its = land(b, x);
        if (its < 0) {
            const double w = lb != la ? fmin(fmax((target - la) / (lb - la), 0.0), 1.0) : 1.0;
            if (usm_cont_arc_point(b->c, w * s_end, x, NULL) != 0)
                return -1;
            x[k] = target;
            if ((its = land(b, x)) < 0)
                return -1;
        }
        const orbit_slot *o = orbit_at(b, x);
        if (!o)
            return -1;
        usm_periodic_point *pt = &s->pts[*next];
        memset(pt, 0, sizeof *pt);
        pt->value = target;
        pt->converged = 1;
        pt->orbit = o->r;
        pt->orbit.iterations = its;
        s->npts = (size_t)*next + 1;
        if (opt->progress)
            opt->progress((double)*next / (n - 1), opt->progress_ctx);
        ++*next;
    }
    return 0;
}

/* The grid points from `next` on have no orbit: why. */
static void mark_beyond(usm_periodic_sweep *s, const usm_periodic_sweep_options *opt, int next,
                        const char *why)
{
    for (int i = next; i < opt->points; ++i) {
        usm_periodic_point *pt = &s->pts[i];
        memset(pt, 0, sizeof *pt);
        pt->value = usm_grid_value(opt->from, opt->to, i, opt->points);
        snprintf(pt->error, sizeof pt->error, "%s", why);
        s->npts = (size_t)i + 1;
        if (opt->progress)
            opt->progress((double)i / (opt->points - 1), opt->progress_ctx);
    }
}

/* Follow the branch from the orbit r0 at `from` to `to`: the grid points
 * landed on, the events located, the end (fold, friction saturation, lost)
 * said.  0, or -1 when out of memory. */
static int follow(usm_periodic_sweep *s, const usm_periodic_sweep_options *opt,
                  const usm_periodic_result *r0)
{
    branch *b = calloc(1, sizeof *b);
    const int dir_up = opt->to > opt->from;
    const double dir = dir_up ? 1.0 : -1.0;
    const int slip = s->m->friction != NULL && s->m->x_phi_Rdot >= 0;
    const double mu_sup = slip ? usm_periodic_friction_supremum(s->m, &s->p) : NAN;
    int rc = -1, next = 1;
    char why[USM_MSG_LEN], vt[96];
    if (!b || setup(b, s, opt, (size_t)opt->points) != 0)
        goto done;
    double x[USM_MAX_NX + 1];
    memcpy(b->xfull, r0->x0, sizeof(double) * (size_t)s->m->nx);
    for (int a = 0; a < b->k; ++a)
        x[a] = r0->x0[b->idx[a]];
    x[b->k] = opt->from;
    if (usm_cont_start(b->c, x, dir_up ? 1 : -1) != 0) {
        snprintf(why, sizeof why, "no orbit: the continuation could not start from %s = %.12g "
                 "(%.100s)", s->over, opt->from, usm_periodic_message(s->w));
        mark_beyond(s, opt, next, why);
        rc = 0;
        goto done;
    }
    for (;;) {
        double dxa[USM_MAX_NX + 1], dxb[USM_MAX_NX + 1];
        memcpy(dxa, usm_cont_direction(b->c), sizeof(double) * (size_t)b->N);
        const int st = usm_cont_step(b->c);
        if (st == USM_CONT_LOST) {
            const double *xl = usm_cont_point(b->c);
            const orbit_slot *o = orbit_at(b, xl);
            /* a branch lost near the friction law's supremum: the
             * saturation, if it lies ahead within the range */
            if (slip && s->sat != 1 && o && o->r.friction_needed_max >= SAT_NEAR * mu_sup) {
                find_saturation(s, xl[b->k], &o->r, opt->to);
                b->shot = 0;
            }
            if (s->sat == 1) {
                if (emit_saturation(s, dir_up) != 0)
                    goto done;
                psweep_value_text(s, s->sat_value, vt);
                snprintf(why, sizeof why,
                         "no orbit beyond friction_saturation at %s: the rotor speed diverges", vt);
            } else
                snprintf(why, sizeof why,
                         "no orbit: the continuation lost the branch after %s = %.12g (no step "
                         "above %g of the scaled arclength converged; last: %.60s)",
                         s->over, xl[b->k], H_MIN, usm_periodic_message(s->w));
            mark_beyond(s, opt, next, why);
            break;
        }
        if (st != USM_CONT_STEP && st != USM_CONT_END)
            goto done;
        const double *xa0;
        const double s_end = usm_cont_step_arc(b->c, &xa0);
        double xa[USM_MAX_NX + 1], xb[USM_MAX_NX + 1];
        memcpy(xa, xa0, sizeof(double) * (size_t)b->N);
        memcpy(xb, usm_cont_point(b->c), sizeof(double) * (size_t)b->N);
        memcpy(dxb, usm_cont_direction(b->c), sizeof(double) * (size_t)b->N);
        /* the events, then the grid: within (from, to) only */
        const int beyond = (xb[b->k] - opt->to) * dir > 0;
        const int ev = step_events(b, xa, xb, dir_up);
        if (ev < 0)
            goto done;
        if (ev > 0) {
            snprintf(why, sizeof why, "no orbit: the orbit of an event after %s = %.12g failed "
                     "(%.100s)", s->over, xa[b->k], usm_periodic_message(s->w));
            mark_beyond(s, opt, next, why);
            break;
        }
        if (beyond) {
            /* events past `to` were emitted: take them back */
            while (s->nev > 0 && (s->ev[s->nev - 1].value - opt->to) * dir > 0)
                s->nev--;
        }
        if (land_on_grid(b, opt, xa, dxa, s_end, xb, dxb, &next) != 0) {
            snprintf(why, sizeof why, "no orbit: the landing on the grid value failed after "
                     "%s = %.12g (%.100s)", s->over, xa[b->k], usm_periodic_message(s->w));
            mark_beyond(s, opt, next, why);
            break;
        }
        /* the saturation located ahead ends the branch where it lies */
        if (s->sat == 1 && next < opt->points &&
            (usm_grid_value(opt->from, opt->to, next, opt->points) - s->sat_value) * dir >= 0) {
            if (emit_saturation(s, dir_up) != 0)
                goto done;
            psweep_value_text(s, s->sat_value, vt);
            snprintf(why, sizeof why,
                     "no orbit beyond friction_saturation at %s: the rotor speed diverges", vt);
            mark_beyond(s, opt, next, why);
            break;
        }
        if (st == USM_CONT_END) {
            if (!beyond) {
                if (fold_event(s, xb, b->k) != 0)
                    goto done;
                psweep_value_text(s, xb[b->k], vt);
                snprintf(why, sizeof why, "no orbit on the branch beyond the fold at %s", vt);
                mark_beyond(s, opt, next, why);
            }
            break;
        }
        if (next >= opt->points)
            break;
        if (slip && s->sat == 0) {
            const orbit_slot *o = orbit_at(b, xb);
            if (o && o->r.friction_needed_max >= SAT_TRIGGER * mu_sup) {
                find_saturation(s, xb[b->k], &o->r, opt->to);
                b->shot = 0;
            }
        }
        if (rescale(b, xb) != 0)
            goto done;
    }
    rc = 0;
done:
    if (b)
        usm_cont_free(b->c);
    free(b);
    return rc;
}

int usm_periodic_sweep_run(usm_periodic_sweep *s, const usm_params *p,
                           const usm_periodic_sweep_options *opt)
{
    s->msg[0] = '\0';
    s->npts = s->nev = 0;
    if (!opt || !opt->over) {
        snprintf(s->msg, sizeof s->msg, "over: the parameter to sweep is missing");
        return USM_EINPUT;
    }
    if (!(s->info = usm_params_find(opt->over))) {
        snprintf(s->msg, sizeof s->msg, "over: unknown parameter \"%.60s\"", opt->over);
        return USM_EINPUT;
    }
    s->unit = s->info->unit;
    snprintf(s->over, sizeof s->over, "%s", opt->over);
    if (!isfinite(opt->from) || !isfinite(opt->to) || opt->from == opt->to) {
        snprintf(s->msg, sizeof s->msg, "from, to: must be finite and different");
        return USM_EINPUT;
    }
    if (!isfinite(opt->to - opt->from)) { /* the steps would be infinite: no end */
        snprintf(s->msg, sizeof s->msg, "from, to: the width to - from overflows (%g to %g; "
                 "at most %g)", opt->from, opt->to, DBL_MAX);
        return USM_EINPUT;
    }
    /* both ends inside the parameter's range, named in its unit (36 meant in deg) */
    for (int end = 0; end < 2; ++end) {
        char why[USM_MSG_LEN];
        if (usm_param_check_value(usm_param_index(s->info), end ? opt->to : opt->from, why) !=
            USM_OK) {
            snprintf(s->msg, sizeof s->msg, "%.200s (the sweep's %s)", why, end ? "to" : "from");
            return USM_EINPUT;
        }
    }
    if (opt->points < 2 || opt->points > 1000000) {
        snprintf(s->msg, sizeof s->msg, "points: %d, must be 2 to 1000000", opt->points);
        return USM_EINPUT;
    }
    if (!(opt->event_tol > 0 && opt->event_tol < 1e-2)) {
        snprintf(s->msg, sizeof s->msg, "event_tol: must be in (0, 0.01)");
        return USM_EINPUT;
    }
    /* the far end's parameters refused now, not after a long continuation */
    usm_params q = *p;
    *usm_params_field(&q, s->info) = opt->to;
    if (usm_params_check(&q, s->m, s->msg) != USM_OK)
        return USM_EINPUT;
    s->p = *p;
    s->popt = opt->periodic;
    s->range = fabs(opt->to - opt->from);
    s->tol = opt->event_tol * s->range;
    s->sat = 0;
    if (usm_grow((void **)&s->pts, &s->pts_cap, (size_t)opt->points, sizeof *s->pts) != 0) {
        snprintf(s->msg, sizeof s->msg, "out of memory");
        return USM_EFAILED;
    }
    usm_periodic_result r0;
    int rc = solve_at(s, opt->from, NULL, &r0);
    if (rc != USM_OK) {
        char why[USM_MSG_LEN];
        snprintf(why, sizeof why, "%s", usm_periodic_message(s->w));
        snprintf(s->msg, sizeof s->msg, "no orbit at %s = %.12g: %.180s", s->over, opt->from, why);
        return rc == USM_EINPUT ? USM_EINPUT : USM_EFAILED;
    }
    memset(&s->pts[0], 0, sizeof s->pts[0]);
    s->pts[0].value = opt->from;
    s->pts[0].converged = 1;
    s->pts[0].orbit = r0;
    s->npts = 1;
    if (follow(s, opt, &r0) != 0)
        goto oom;
    if (s->m->unilateral && psweep_separating(s, opt->to - opt->from) != 0)
        goto oom;
    return USM_OK;
oom:
    snprintf(s->msg, sizeof s->msg, "out of memory");
    return USM_EFAILED;
}
