/* Continuation of the periodic orbit in one parameter, with its events
 * (usm_periodic_sweep.h). */
#include "periodic_sweep_internal.h"
#include "periodic_sweep_state.h"

#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/grid.h"
#include "core/grow.h"
#include "core/root.h"
#include "solve/periodic_internal.h"

/* A trial step is accepted when Newton needed at most this many iterations;
 * more means the prediction was poor, and the next step is halved. */
#define SLOW_NEWTON 4
#define MIN_STEP 1e-7 /* of the range: below it the branch is lost */
#define MAX_LOCATE 60
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

/* Start state at v predicted linearly from the orbits (va, a) and (vb, b). */
static void predict(const usm_periodic_result *a, double va, const usm_periodic_result *b,
                    double vb, double v, double *x)
{
    const double t = (v - vb) / (vb - va);
    for (int i = 0; i < b->nx; ++i)
        x[i] = b->x0[i] + t * (b->x0[i] - a->x0[i]);
}

/* ---- events ------------------------------------------------------------------- */

enum { G_CONTACT, G_STICK, G_STABILITY, NG };

/* The event functions: their zeros are the events (NaN: undefined here). */
static double gfun(const usm_periodic_sweep *s, int k, const usm_periodic_result *r)
{
    switch (k) {
    case G_CONTACT: return r->F_n_min;
    case G_STICK: return r->friction_needed_max - s->p.mu0;
    default: return r->floquet.max_modulus - 1.0;
    }
}

/* One trial orbit of the locator: the parameter value, the orbit, g_k there. */
typedef struct trial {
    double v, g;
    usm_periodic_result r;
} trial;

typedef struct locate_ctx {
    usm_periodic_sweep *s;
    int k;
    usm_root *root;
    trial t[3]; /* the bracket's two ends and the trial being evaluated */
} locate_ctx;

/* The slot of the trial at v, or -1. */
static int trial_at(const locate_ctx *c, double v)
{
    for (int i = 0; i < 3; ++i)
        if (c->t[i].v == v)
            return i;
    return -1;
}

/* g_k at v, the locator's function: the orbit started from the linear
 * interpolation of the states at the ends of the current bracket (NaN when
 * it fails). */
static double trial_g(double v, void *ctx)
{
    locate_ctx *c = ctx;
    double lo, hi, x[USM_MAX_NX];
    usm_root_bracket(c->root, &lo, &hi);
    const int a = trial_at(c, lo), b = trial_at(c, hi);
    if (a < 0 || b < 0 || a == b)
        return NAN;
    trial *t = &c->t[3 - a - b]; /* the slot that is neither end */
    predict(&c->t[a].r, lo, &c->t[b].r, hi, v, x);
    t->v = NAN;
    if (solve_at(c->s, v, x, &t->r) != USM_OK)
        return NAN;
    t->v = v;
    t->g = gfun(c->s, c->k, &t->r);
    return t->g;
}

/* The zero of g_k between (va, ra) and (vb, rb), where g_k changes sign, by
 * Brent's method (the shared locator, core/root.h) to s->tol; every trial
 * orbit starts from the linear interpolation of the bracket's states.  *v
 * and *r: the end of the last bracket of smaller |g|.  0, or -1 when a
 * trial orbit fails (*v, *r then the end of smaller |g| of the last
 * bracket). */
static int locate(usm_periodic_sweep *s, int k, double va, const usm_periodic_result *ra,
                  double vb, const usm_periodic_result *rb, double *v, usm_periodic_result *r,
                  trial *pos)
{
    locate_ctx c;
    c.s = s;
    c.k = k;
    c.root = usm_root_alloc();
    c.t[0].v = va, c.t[0].g = gfun(s, k, ra), c.t[0].r = *ra;
    c.t[1].v = vb, c.t[1].g = gfun(s, k, rb), c.t[1].r = *rb;
    c.t[2].v = NAN;
    const usm_root_stop stop = {s->tol, 0.0, MAX_LOCATE};
    double x, lo = va, hi = vb;
    int rc = -1;
    if (c.root) {
        rc = usm_root_brent(c.root, trial_g, &c, va, vb, c.t[0].g, c.t[1].g, &stop, &x);
        usm_root_bracket(c.root, &lo, &hi);
        usm_root_free(c.root);
    }
    int a = trial_at(&c, lo), b = trial_at(&c, hi);
    if (a < 0 || b < 0) /* not reached: the bracket's ends are trials */
        a = 0, b = 1, rc = -1;
    const trial *best = fabs(c.t[a].g) <= fabs(c.t[b].g) ? &c.t[a] : &c.t[b];
    *v = best->v;
    *r = best->r;
    if (pos)
        *pos = c.t[a].g > 0 ? c.t[a] : c.t[b];
    return rc;
}

/* rising: g_k > 0 after the event (in sweep order). */
/* openings: the times a period the contact opens on the step's open end,
 * at open_v (G_CONTACT only), counted there, not assumed */
static int emit_located(usm_periodic_sweep *s, int k, double v, const usm_periodic_result *r,
                        int located, int dir_up, int rising, int openings, double open_v)
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
    const char *how = located ? "" : " (not located to tolerance: a trial orbit failed)";
    psweep_value_text(s, v, vt);
    const char *inc = dir_up ? "increases" : "decreases";
    if (k == G_CONTACT)
        return psweep_event_add(s, rising && s->m->unilateral ? USM_PEVENT_CONTACT_REGAINED
                                                       : USM_PEVENT_CONTACT_LOSS, v, r,
                         "F_n_min = 0 at %s: the contact %s %s a period as %s %s (counted on "
                         "the orbit at %s)%s", vt,
                         rising ? "closes again, where it opened" : "opens", times, s->over, inc,
                         ot, how)
                   ? 0 : -1;
    if (k == G_STICK)
        return psweep_event_add(s, USM_PEVENT_STICK_LOSS, v, r,
                         "friction_needed_max = mu0 = %g at %s: stick %s as %s %s%s", s->p.mu0,
                         vt, rising ? "fails somewhere on the orbit (intermittent slip)"
                                    : "holds again over the whole orbit",
                         s->over, inc, how)
                   ? 0 : -1;
    return psweep_stability_add(s, v, r, &r->floquet, r->period, "the orbit", located, dir_up,
                                rising)
               ? 0 : -1;
}

/* Events between the accepted orbits (va, ra) and (vb, rb), in sweep order.
 * The contact first: where it opens within the step, friction_needed_max is
 * undefined at that end (it divides by F_n), and stick_loss is looked for
 * between the other end and the located contact loss's closed side (where
 * F_n_min > 0 is tiny and the friction needed large), so that stick loss
 * before a contact loss in the same step is reported, and in its order. */
static int step_events(usm_periodic_sweep *s, double va, const usm_periodic_result *ra, double vb,
                       const usm_periodic_result *rb)
{
    static const int order[NG] = {G_CONTACT, G_STABILITY, G_STICK};
    double vs[NG];
    usm_periodic_result rs[NG];
    int ks[NG], located[NG], rising[NG], opens[NG], n = 0, have_closed = 0;
    double openv[NG];
    trial closed; /* the contact loss's last bracket end with F_n_min > 0 */
    for (int o = 0; o < NG; ++o) {
        const int k = order[o];
        if (k == G_STICK && s->m->friction)
            continue; /* slip built in: F_t = mu(v) F_n, stick has no meaning */
        double v0 = va, v1 = vb;
        const usm_periodic_result *r0 = ra, *r1 = rb;
        double g0 = gfun(s, k, r0), g1 = gfun(s, k, r1);
        if (k == G_STICK && have_closed && isfinite(g0) != isfinite(g1)) {
            if (!isfinite(g0))
                v0 = closed.v, r0 = &closed.r, g0 = closed.g;
            else
                v1 = closed.v, r1 = &closed.r, g1 = closed.g;
            g0 = gfun(s, k, r0), g1 = gfun(s, k, r1);
        }
        if (!isfinite(g0) || !isfinite(g1) || (g0 < 0) == (g1 < 0))
            continue;
        located[n] = locate(s, k, v0, r0, v1, r1, &vs[n], &rs[n],
                            k == G_CONTACT ? &closed : NULL) == 0;
        /* on the step's open end: at the located orbit F_n_min is 0 to rounding,
         * too close to count its dips as openings */
        opens[n] = k == G_CONTACT ? (g0 < 0 ? r0 : r1)->openings_per_period : 0;
        openv[n] = g0 < 0 ? v0 : v1;
        if (k == G_CONTACT)
            have_closed = isfinite(closed.v);
        rising[n] = g1 > 0;
        ks[n++] = k;
    }
    /* in sweep order: by distance from va */
    for (int i = 0; i < n; ++i) {
        int best = i;
        for (int j = i + 1; j < n; ++j)
            if (fabs(vs[j] - va) < fabs(vs[best] - va))
                best = j;
        if (emit_located(s, ks[best], vs[best], &rs[best], located[best], vb > va,
                         rising[best], opens[best], openv[best]) != 0)
            return -1;
        vs[best] = vs[i], rs[best] = rs[i], ks[best] = ks[i], located[best] = located[i];
        rising[best] = rising[i], opens[best] = opens[i], openv[best] = openv[i];
    }
    return 0;
}

/* The branch ends after (va, ra): a fold if a real multiplier was approaching
 * +1 ((mu - 1)^2 is linear in the parameter near a turning point, so its
 * zero is extrapolated from the last two orbits). */
static int branch_end(usm_periodic_sweep *s, double vp, const usm_periodic_result *rp, int have_p,
                      double va, const usm_periodic_result *ra)
{
    if (!have_p)
        return 0;
    double ga = INFINITY, gp = INFINITY;
    for (int i = 0; i < ra->floquet.n; ++i)
        if (!ra->floquet.cyclic[i] && ra->floquet.im[i] == 0.0 && ra->floquet.re[i] > 0)
            ga = fmin(ga, (ra->floquet.re[i] - 1) * (ra->floquet.re[i] - 1));
    for (int i = 0; i < rp->floquet.n; ++i)
        if (!rp->floquet.cyclic[i] && rp->floquet.im[i] == 0.0 && rp->floquet.re[i] > 0)
            gp = fmin(gp, (rp->floquet.re[i] - 1) * (rp->floquet.re[i] - 1));
    if (!(ga < 0.01 && gp > ga))
        return 0;
    const double vf = va - ga * (va - vp) / (ga - gp);
    char vt[96];
    psweep_value_text(s, vf, vt);
    return psweep_event_add(s, USM_PEVENT_FOLD, vf, NULL,
                     "the branch turns back near %s: a real multiplier reaches +1 (extrapolated "
                     "from the last two orbits; natural-parameter continuation stops here)", vt)
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
    if (usm_periodic_saturation(s->w, &q, s->info, r->x0, s->range, s->tol, &s->popt, &ls) ==
            USM_OK &&
        (ls - v) * dir > 0 && (ls - to) * dir <= 0) {
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
    const int slip = s->m->friction != NULL && s->m->x_phi_Rdot >= 0;
    const double mu_sup = slip ? usm_periodic_friction_supremum(s->m, p) : NAN;
    if (usm_grow((void **)&s->pts, &s->pts_cap, (size_t)opt->points, sizeof *s->pts) != 0) {
        snprintf(s->msg, sizeof s->msg, "out of memory");
        return USM_EFAILED;
    }
    const int n = opt->points;
    const double hmax = (opt->to - opt->from) / (n - 1);
    usm_periodic_result ra, rp, rb;
    double x[USM_MAX_NX];
    int rc = solve_at(s, opt->from, NULL, &ra);
    if (rc != USM_OK) {
        char why[USM_MSG_LEN];
        snprintf(why, sizeof why, "%s", usm_periodic_message(s->w));
        snprintf(s->msg, sizeof s->msg, "no orbit at %s = %.12g: %.180s", s->over, opt->from, why);
        return rc == USM_EINPUT ? USM_EINPUT : USM_EFAILED;
    }
    rp = ra; /* unused before a second orbit (have_p) */
    double va = opt->from, vp = va, h = hmax;
    int have_p = 0, lost = 0;
    char lost_why[USM_MSG_LEN] = "";
    memset(&s->pts[0], 0, sizeof s->pts[0]);
    s->pts[0].value = va;
    s->pts[0].converged = 1;
    s->pts[0].orbit = ra;
    s->npts = 1;
    for (int i = 1; i < n; ++i) {
        /* the grid value as typed, the last exactly `to` (core/grid.h) */
        const double target = usm_grid_value(opt->from, opt->to, i, n);
        usm_periodic_point *pt = &s->pts[i];
        memset(pt, 0, sizeof *pt);
        pt->value = target;
        if (!lost && s->sat == 1 && (target - s->sat_value) * (opt->to - opt->from) >= 0) {
            lost = 1; /* the branch ends at the saturation located ahead */
            if (emit_saturation(s, opt->to > opt->from) != 0)
                goto oom;
        }
        while (!lost && va != target) {
            const double vb = fabs(target - va) <= fabs(h) * (1 + 1e-12) ? target : va + h;
            const double *x0 = ra.x0;
            if (have_p) {
                predict(&rp, vp, &ra, va, vb, x);
                x0 = x;
            }
            rc = solve_at(s, vb, x0, &rb);
            if (rc != USM_OK || rb.iterations > SLOW_NEWTON) {
                if (rc != USM_OK)
                    snprintf(lost_why, sizeof lost_why, "%s", usm_periodic_message(s->w));
                else
                    snprintf(lost_why, sizeof lost_why, "Newton needs %d iterations",
                             rb.iterations);
                h *= 0.5;
                if (fabs(h) < MIN_STEP * s->range) {
                    lost = 1;
                    /* a branch lost near the friction law's supremum: the
                     * saturation, if it lies within a grid spacing ahead */
                    if (slip && s->sat != 1 && ra.friction_needed_max >= SAT_NEAR * mu_sup) {
                        find_saturation(s, va, &ra, opt->to);
                        if (s->sat == 1 && fabs(s->sat_value - va) > fabs(hmax))
                            s->sat = -1;
                    }
                    if (s->sat == 1 ? emit_saturation(s, opt->to > opt->from) != 0
                                    : branch_end(s, vp, &rp, have_p, va, &ra) != 0)
                        goto oom;
                }
                continue;
            }
            if (step_events(s, va, &ra, vb, &rb) != 0)
                goto oom;
            vp = va, rp = ra, have_p = 1;
            va = vb, ra = rb;
            if (slip && s->sat == 0 && rb.friction_needed_max >= SAT_TRIGGER * mu_sup)
                find_saturation(s, va, &ra, opt->to);
            if (rb.iterations <= 2 && fabs(2 * h) <= fabs(hmax))
                h *= 2;
        }
        if (lost && s->sat == 1 && (target - s->sat_value) * (opt->to - opt->from) >= 0) {
            char vt[96];
            psweep_value_text(s, s->sat_value, vt);
            snprintf(pt->error, sizeof pt->error,
                     "no orbit beyond friction_saturation at %s: the rotor speed diverges", vt);
        } else if (lost) {
            char why[USM_MSG_LEN];
            snprintf(why, sizeof why, "%s", lost_why);
            snprintf(pt->error, sizeof pt->error,
                     "no orbit: the continuation lost the branch after %s = %.12g (the step fell "
                     "below %g of the range; last try: %.80s)",
                     s->over, va, MIN_STEP, why);
        } else {
            pt->converged = 1;
            pt->orbit = ra;
        }
        s->npts = (size_t)i + 1;
        if (opt->progress)
            opt->progress((double)i / (n - 1), opt->progress_ctx);
    }
    if (s->m->unilateral && psweep_separating(s, opt->to - opt->from) != 0)
        goto oom;
    return USM_OK;
oom:
    snprintf(s->msg, sizeof s->msg, "out of memory");
    return USM_EFAILED;
}
