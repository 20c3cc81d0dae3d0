/* The periodic sweep past contact loss: the orbits with separation of a
 * unilateral model at the grid points (usm_periodic_sweep.h, "Unilateral
 * models"; docs/unilateral.md).
 *
 * The orbits with separation are followed along the grid as a branch: each
 * point's orbit is Newton's (usm_hybrid_solve_from) from the secant
 * prediction of the branch's last two orbits (the last one's state when
 * there is one, or the two have different section times).  A solution whose
 * separation fraction or mean speed jumps (changes by more than JUMP_GROWTH
 * times the last step's change, and more than JUMP_FRACTION / JUMP_SPEED)
 * has left the branch: near a multiplier +1, B - I is nearly singular and
 * Newton's first step may throw it onto a coexisting orbit.
 * Then, and where Newton fails, paths of 2, 4, 8 substeps (each predicted
 * alike) decide: the orbit at the point is the branch's where two successive
 * paths (the direct step the first) end on the same orbit (a continuous
 * branch, e.g. with a kink where an impact changes from sticking to
 * sliding); if none do, the branch is lost there (it ends, or Newton
 * fails).
 *
 * The orbit the motor runs on: where the followed orbit is unstable, or the
 * branch was lost, usm_hybrid_solve (a simulation from rest, then Newton)
 * gives the start-up's attractor; when that one is stable (or the branch was
 * lost and it does not continue the branch) the point takes it and the
 * branch continues from it: a branch_switch event, with both orbits and,
 * for an unstable one, where it turned unstable (Brent's method on
 * max |lambda| = 1 between its last stable and first unstable point).
 * Wherever the followed orbit's max |lambda| crosses 1 between two grid
 * points of one branch and mode sequence (continued, in either direction),
 * that crossing, located so, is a stability_change event carrying the
 * located orbit (its kind and text as the bilateral ones').  Where
 * the mode sequence changes along the branch, the change is located by
 * bisection on the parameter (the mode sequence of the orbit continued from
 * the bracket's end of the old sequence) to the event tolerance: a grazing
 * where the two sequences' orbits meet there, else the old sequence's
 * branch ended and Newton landed on another orbit (branch_switch). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/root.h"
#include "periodic_sweep_state.h"

#define JUMP_GROWTH 3.0
#define JUMP_FRACTION 2e-3 /* of the period */
#define JUMP_SPEED 1e-3    /* relative */
#define MAX_HALVINGS 3     /* substeps 2, 4, 8 */
#define MAX_BISECT 48
#define SAME_TOL 1e-6    /* same_orbit */
#define GRAZE_GAP 1e-3   /* grazing: the two sequences' orbits meet (fraction, relative speed) */

/* The branch followed: its last two orbits (r[1] the newer). */
typedef struct branch {
    int n;
    double v[2];
    usm_hybrid_result r[2];
} branch;

static void branch_push(branch *b, double v, const usm_hybrid_result *r)
{
    if (b->n > 0) {
        b->v[0] = b->v[1];
        b->r[0] = b->r[1];
    }
    b->v[1] = v;
    b->r[1] = *r;
    b->n = b->n < 2 ? b->n + 1 : 2;
}

static usm_params params_at(const usm_periodic_sweep *s, double v)
{
    usm_params q = s->p;
    *usm_params_field(&q, s->info) = v;
    return q;
}

/* r off the branch (see the header comment): its separation fraction or mean
 * speed changed from the last orbit's by more than JUMP_GROWTH times the
 * last step's change (scaled to the step) and more than JUMP_FRACTION /
 * JUMP_SPEED.  Not the prediction's error: the branches have kinks (an
 * impact changing from sticking to sliding), where the linear prediction
 * is poor at any step while the change per step stays small. */
static int off_branch(const branch *b, double v, const usm_hybrid_result *r)
{
    if (b->n < 2 || strcmp(b->r[1].mode_sequence, r->mode_sequence) != 0)
        return 0; /* a new sequence: grazing, which the caller locates */
    const double ts = (v - b->v[1]) / (b->v[1] - b->v[0]), t = fabs(ts);
    const usm_hybrid_result *a = &b->r[0], *c = &b->r[1];
    const double df = fabs(c->separation_fraction - a->separation_fraction) * t;
    const double dw = fabs(c->rotor_speed_mean - a->rotor_speed_mean) * t;
    /* the change, or the secant prediction's error: an orbit past a fold
     * (the branch turns back there) is often no farther from the last one
     * than a step, but on the other side of the prediction (4-DOF mode
     * split 1.93 -> 1.80 %: the speed changes by 2.7 times the last
     * step's change, and its prediction misses by 3.7 times) */
    const double pf = c->separation_fraction + ts * (c->separation_fraction -
                                                     a->separation_fraction);
    const double pw = c->rotor_speed_mean + ts * (c->rotor_speed_mean - a->rotor_speed_mean);
    const double ef = fmax(fabs(r->separation_fraction - c->separation_fraction),
                           fabs(r->separation_fraction - pf));
    const double ew = fmax(fabs(r->rotor_speed_mean - c->rotor_speed_mean),
                           fabs(r->rotor_speed_mean - pw));
    return (ef > JUMP_GROWTH * df && ef > JUMP_FRACTION) ||
           (ew > JUMP_GROWTH * dw && ew > JUMP_SPEED * fabs(c->rotor_speed_mean));
}

/* One Newton solve at v from the branch's prediction (or its last state):
 * 0 an orbit with separation (*jump: off the branch by off_branch), -1 none. */
static int solve_on(usm_periodic_sweep *s, const branch *b, double v, usm_hybrid_result *out,
                    int *jump)
{
    const usm_params q = params_at(s, v);
    const usm_hybrid_result *c = &b->r[1];
    double x[USM_MAX_NX];
    int rc = -1;
    if (b->n == 2 && b->r[0].t0 == c->t0) {
        const double t = (v - b->v[1]) / (b->v[1] - b->v[0]);
        for (int i = 0; i < c->nx; ++i)
            x[i] = c->x0[i] + t * (c->x0[i] - b->r[0].x0[i]);
        rc = usm_hybrid_solve_from(s->hy, &q, NULL, c->t0, x, out);
    }
    if (rc != USM_OK)
        rc = usm_hybrid_solve_from(s->hy, &q, NULL, c->t0, c->x0, out);
    if (rc != USM_OK || out->nmodes < 2)
        return -1;
    *jump = off_branch(b, v, out);
    return 0;
}

/* The same orbit, to Newton's tolerance (1e-9 of the state) and far more. */
static int same_orbit(const usm_hybrid_result *a, const usm_hybrid_result *b)
{
    return strcmp(a->mode_sequence, b->mode_sequence) == 0 &&
           fabs(a->separation_fraction - b->separation_fraction) < SAME_TOL &&
           fabs(a->rotor_speed_mean - b->rotor_speed_mean) < SAME_TOL * fabs(a->rotor_speed_mean);
}

/* Follow the branch b to v; on success b ends with the orbit at v (*out).
 * A step whose orbit jumps (off_branch) or fails is checked by paths of 2,
 * 4, 8 substeps: the orbit at v is accepted where two successive paths (the
 * direct step the first) end on the same orbit, a continuous branch (with a
 * kink, say); otherwise the branch is lost (-1). */
static int follow(usm_periodic_sweep *s, branch *b, double v, usm_hybrid_result *out)
{
    int jump = 0, have;
    usm_hybrid_result prev;
    have = solve_on(s, b, v, out, &jump) == 0;
    if (have && !jump) {
        branch_push(b, v, out);
        return 0;
    }
    prev = *out;
    const double v0 = b->v[1];
    for (int k = 1; k <= MAX_HALVINGS; ++k) {
        const int m = 1 << k;
        branch w = *b;
        int j;
        for (j = 1; j <= m; ++j) {
            const double vj = j == m ? v : v0 + (v - v0) * j / m;
            /* a substep that jumps: the path passed the end of the branch
             * (a fold within the step), not a continuation */
            if (solve_on(s, &w, vj, out, &jump) != 0 || jump)
                break;
            branch_push(&w, vj, out);
        }
        if (j <= m) {
            have = 0;
            continue;
        }
        if (have && same_orbit(out, &prev)) {
            *b = w;
            return 0;
        }
        prev = *out;
        have = 1;
    }
    return -1;
}

/* The bisection's indicator (core/root.h): 1 where the orbit continued from
 * the latest orbit of a's sequence (the bracket's end on that side) has a's
 * sequence, 0 where it has c's. */
typedef struct graze_ctx {
    usm_periodic_sweep *s;
    const char *seq_a, *seq_c;
    usm_hybrid_result lo, hi; /* the last bracket's orbits */
    double vlo, vhi;
} graze_ctx;

static int graze_indicator(double v, void *ctx)
{
    graze_ctx *g = ctx;
    usm_hybrid_result r;
    const usm_params q = params_at(g->s, v);
    if (usm_hybrid_solve_from(g->s->hy, &q, NULL, g->lo.t0, g->lo.x0, &r) != USM_OK ||
        r.nmodes < 2)
        return USM_ROOT_FAILED;
    if (strcmp(r.mode_sequence, g->seq_a) == 0) {
        g->lo = r;
        g->vlo = v;
        return 1;
    }
    if (strcmp(r.mode_sequence, g->seq_c) == 0) {
        g->hi = r;
        g->vhi = v;
        return 0;
    }
    return USM_ROOT_UNDEFINED;
}

/* Where the mode sequence changes from a's (at va) to c's (at vc):
 * usm_root_bisect to the event tolerance; g's lo and hi end as the last
 * bracket's orbits.  1 located, 0 not (a trial failed or met a third
 * sequence). */
static int locate_grazing(usm_periodic_sweep *s, double va, const usm_hybrid_result *a,
                          double vc, const usm_hybrid_result *c, graze_ctx *g)
{
    double x;
    g->s = s;
    g->seq_a = a->mode_sequence;
    g->seq_c = c->mode_sequence;
    g->lo = *a, g->hi = *c, g->vlo = va, g->vhi = vc;
    return usm_root_bisect(graze_indicator, g, va, 1, vc, s->tol, MAX_BISECT, &x) == 1;
}

/* Brent's function (core/root.h) along the followed branch: max |lambda| - 1
 * of the orbit at v, Newton from the bracket's orbits' interpolation, to
 * STAB_NEWTON_TOL: near |lambda| = 1, B - I is nearly singular and
 * amplifies the map's noise (1e-11) by 1 / (|lambda| - 1), so Newton's
 * residual stalls above the default 1e-9 (measured 1.5e-8 at |lambda| =
 * 1.001); an orbit to 1e-7 moves the multipliers by about that. */
#define STAB_NEWTON_TOL 1e-7
#define STAB_CACHE 8
typedef struct stab_ctx {
    usm_periodic_sweep *s;
    usm_root *root;
    int n; /* orbits evaluated; the last STAB_CACHE kept */
    double v[STAB_CACHE];
    usm_hybrid_result r[STAB_CACHE];
} stab_ctx;

static void stab_keep(stab_ctx *c, double v, const usm_hybrid_result *r)
{
    const int k = c->n++ % STAB_CACHE;
    c->v[k] = v;
    c->r[k] = *r;
}

/* The kept orbit at v, or NULL. */
static const usm_hybrid_result *stab_at(const stab_ctx *c, double v)
{
    for (int i = 0; i < c->n && i < STAB_CACHE; ++i)
        if (c->v[i] == v)
            return &c->r[i];
    return NULL;
}

static double stab_fn(double v, void *ctx)
{
    stab_ctx *c = ctx;
    double lo, hi, x[USM_MAX_NX];
    usm_root_bracket(c->root, &lo, &hi);
    const usm_hybrid_result *a = stab_at(c, lo), *b = stab_at(c, hi);
    if (!a || !b || a->t0 != b->t0)
        return NAN;
    /* Newton from the linear interpolation of the bracket's orbits; a result
     * whose separation fraction leaves their span by more than its width
     * jumped to another orbit */
    const double t = (v - lo) / (hi - lo);
    for (int i = 0; i < a->nx; ++i)
        x[i] = a->x0[i] + t * (b->x0[i] - a->x0[i]);
    usm_hybrid_result r;
    usm_hybrid_options o;
    usm_hybrid_options_default(&o);
    o.tol = STAB_NEWTON_TOL;
    const usm_params q = params_at(c->s, v);
    const double fa = a->separation_fraction, fb = b->separation_fraction, w = fabs(fb - fa);
    if (usm_hybrid_solve_from(c->s->hy, &q, &o, a->t0, x, &r) != USM_OK || r.nmodes < 2 ||
        strcmp(r.mode_sequence, a->mode_sequence) != 0 ||
        r.separation_fraction < fmin(fa, fb) - w || r.separation_fraction > fmax(fa, fb) + w)
        return NAN;
    stab_keep(c, v, &r);
    return r.floquet.max_modulus - 1.0;
}

/* The kept orbit at v, else the kept one nearest |lambda| = 1. */
static const usm_hybrid_result *stab_best(const stab_ctx *c, double v)
{
    const usm_hybrid_result *r = stab_at(c, v);
    if (r)
        return r;
    r = &c->r[0];
    for (int i = 1; i < c->n && i < STAB_CACHE; ++i)
        if (fabs(c->r[i].floquet.max_modulus - 1) < fabs(r->floquet.max_modulus - 1))
            r = &c->r[i];
    return r;
}

/* Where the followed orbit's stability changes (max |lambda| = 1) between
 * (va, a) and (vb, b), on either side of 1, by Brent's method to STAB_TOL
 * of the range (the event tolerance is finer than the multipliers' own
 * accuracy, about 1e-6: near |lambda| = 1 they scatter by that, and Newton,
 * B - I nearly singular there, may fail).  1: *v Brent's zero; 0: a failed
 * trial ended it and *v is the last bracket's middle, within 100 STAB_TOL;
 * -1: not located, *v the trial orbit nearest |lambda| = 1.  *at: the
 * trial orbit at *v, else (0, -1) the one nearest |lambda| = 1. */
#define STAB_TOL 1e-6
static int locate_stability(usm_periodic_sweep *s, double va, const usm_hybrid_result *a,
                            double vb, const usm_hybrid_result *b, double *v,
                            usm_hybrid_result *at)
{
    stab_ctx c;
    double x = NAN, lo, hi;
    int rc = 1;
    c.s = s;
    c.n = 0;
    stab_keep(&c, va, a);
    stab_keep(&c, vb, b);
    usm_root *root = c.root = usm_root_alloc();
    const double tol = fmax(s->tol, STAB_TOL * s->range);
    const usm_root_stop stop = {tol, 0.0, MAX_BISECT};
    if (!root || usm_root_brent(root, stab_fn, &c, va, vb, a->floquet.max_modulus - 1.0,
                                b->floquet.max_modulus - 1.0, &stop, &x) != 0) {
        rc = -1;
        if (root) {
            usm_root_bracket(root, &lo, &hi);
            if (fabs(hi - lo) <= 100 * tol)
                rc = 0, x = 0.5 * (lo + hi);
        }
    }
    usm_root_free(root);
    const usm_hybrid_result *r = stab_best(&c, x);
    for (int i = 0; rc < 0 && i < c.n && i < STAB_CACHE; ++i)
        if (&c.r[i] == r)
            x = c.v[i];
    *v = x;
    *at = *r;
    if (rc >= 0 && !stab_at(&c, x)) {
        /* Brent's zero can be an older trial's abscissa than the cache
         * keeps: the orbit there, from the nearest kept one */
        const usm_params q = params_at(s, x);
        usm_hybrid_result rx;
        if (usm_hybrid_solve_from(s->hy, &q, NULL, r->t0, r->x0, &rx) == USM_OK &&
            rx.nmodes >= 2)
            *at = rx;
    }
    return rc;
}

/* The orbit a start from rest settles on at v (usm_hybrid_solve); 0 or -1. */
static int solve_cold(usm_periodic_sweep *s, double v, usm_hybrid_result *out)
{
    const usm_params q = params_at(s, v);
    return usm_hybrid_solve(s->hy, &q, NULL, out) == USM_OK && out->nmodes >= 2 ? 0 : -1;
}

/* How a branch_switch came about. */
enum { SW_UNSTABLE, SW_LOST, SW_ENDS };

/* The branch_switch event at pt: `to` the orbit followed from here, `from`
 * the followed orbit it replaces (SW_UNSTABLE: unstable at pt; SW_LOST: the
 * branch's last orbit, at v_last, and `to` from a start from rest; SW_ENDS:
 * the branch's last orbit of its mode sequence, at v_last, and `to` what
 * Newton from it found at pt). */
static int switch_event(usm_periodic_sweep *s, const usm_periodic_point *pt,
                        const usm_hybrid_result *to, const usm_hybrid_result *from, int how,
                        double v_last, double unstable_from)
{
    char vt[96], vl[96];
    psweep_value_text(s, pt->value, vt);
    psweep_value_text(s, v_last, vl);
    usm_periodic_event *e =
        how == SW_LOST
            ? psweep_event_add(
                  s, USM_PEVENT_BRANCH_SWITCH, pt->value, NULL,
                  "the orbit with separation followed to %s does not continue to %s (its "
                  "branch ends, or Newton fails); from a start from rest: %s, max |lambda| "
                  "%.4f, %.6g 1/s, open %.3f, followed on", vl, vt, to->mode_sequence,
                  to->floquet.max_modulus, to->rotor_speed_mean, to->separation_fraction)
        : how == SW_ENDS
            ? psweep_event_add(
                  s, USM_PEVENT_BRANCH_SWITCH, pt->value, NULL,
                  "the %s orbit with separation ends after %s (no grazing: the orbits of the "
                  "two sequences do not meet); at %s another: %s, max |lambda| %.4f, %.6g 1/s, "
                  "followed on", from->mode_sequence, vl, vt, to->mode_sequence,
                  to->floquet.max_modulus, to->rotor_speed_mean)
            : psweep_event_add(
                  s, USM_PEVENT_BRANCH_SWITCH, pt->value, NULL,
                  "the continued orbit with separation is unstable at %s (max |lambda| %.4f, "
                  "speed %.6g 1/s); a start from rest settles on a stable one (%.4f, %.6g 1/s, "
                  "open %.3f): the motor's, followed from here", vt, from->floquet.max_modulus,
                  from->rotor_speed_mean, to->floquet.max_modulus, to->rotor_speed_mean,
                  to->separation_fraction);
    if (!e)
        return -1;
    e->has_hybrid = 1;
    e->hybrid = *to;
    e->hybrid_left = *from;
    psweep_event_mark(e, to->validity);
    e->branch_lost = how != SW_UNSTABLE;
    e->branch_last = how != SW_UNSTABLE ? v_last : pt->value;
    e->unstable_from = how == SW_UNSTABLE ? unstable_from : NAN;
    return 0;
}

/* The mode sequence changed from a's (at va) to c's (at pt) along the
 * branch: a grazing where the two sequences' orbits meet (at the located
 * value their separation fraction and mean speed agree to GRAZE_GAP), else
 * the branch of a's sequence ended in between and Newton landed on another
 * orbit (branch_switch, SW_ENDS).  0 grazing, 1 switch, -1 out of memory. */
static int grazing_event(usm_periodic_sweep *s, double va, const usm_hybrid_result *a,
                         const usm_periodic_point *pt, const usm_hybrid_result *c)
{
    graze_ctx g;
    const int located = locate_grazing(s, va, a, pt->value, c, &g);
    const usm_hybrid_result *lo = &g.lo, *hi = &g.hi;
    const double vlo = g.vlo, vhi = g.vhi;
    const int meet = fabs(lo->separation_fraction - hi->separation_fraction) <= GRAZE_GAP &&
                     fabs(lo->rotor_speed_mean - hi->rotor_speed_mean) <=
                         GRAZE_GAP * fabs(hi->rotor_speed_mean);
    if (located && !meet)
        return switch_event(s, pt, c, lo, SW_ENDS, vlo, NAN) == 0 ? 1 : -1;
    const double vg = 0.5 * (vlo + vhi);
    char vt[96], pa[96], pc[96];
    psweep_value_text(s, vg, vt);
    psweep_value_text(s, vlo, pa);
    psweep_value_text(s, vhi, pc);
    usm_periodic_event *e =
        located ? psweep_event_add(s, USM_PEVENT_GRAZING, vg, NULL,
                                   "the orbit with separation changes its mode sequence from %s "
                                   "to %s at %s: an orbit touches a guard tangentially there",
                                   a->mode_sequence, c->mode_sequence, vt)
                : psweep_event_add(s, USM_PEVENT_GRAZING, vg, NULL,
                                   "the orbit with separation changes its mode sequence from %s "
                                   "to %s between %s and %s (not located to tolerance: a trial "
                                   "orbit failed)", a->mode_sequence, c->mode_sequence, pa, pc);
    return e ? 0 : -1;
}

/* The stability_change of the followed orbit with separation at v (the
 * located orbit `at`): the bilateral events' kind and text
 * (psweep_stability_add), the orbit with separation in `hybrid` (the
 * bilateral orbit there has an open contact: has_orbit 0).  0, or -1 when
 * out of memory. */
static int stability_event(usm_periodic_sweep *s, double v, const usm_hybrid_result *at,
                           int located, int dir_up, int rising)
{
    char subject[48 + USM_HYBRID_MAX_SWITCHES + 1];
    snprintf(subject, sizeof subject, "the followed orbit with separation (%s)",
             at->mode_sequence);
    usm_periodic_event *e = psweep_stability_add(s, v, NULL, &at->floquet, at->period, subject,
                                                 located, dir_up, rising);
    if (!e)
        return -1;
    e->has_hybrid = 1;
    e->hybrid = *at;
    psweep_event_mark(e, at->validity);
    e->branch_last = e->unstable_from = NAN;
    return 0;
}

int psweep_separating(usm_periodic_sweep *s, double dir)
{
    if (!s->hy && !(s->hy = usm_hybrid_alloc(s->m)))
        return -1;
    branch b, gone;
    double unstable_from = NAN; /* where the followed orbit turned unstable */
    b.n = gone.n = 0; /* gone: a branch lost at a point without any orbit since */
    for (size_t i = 0; i < s->npts; ++i) {
        usm_periodic_point *pt = &s->pts[i];
        pt->separating = pt->switched = 0;
        if (pt->converged ? !pt->orbit.contact_open : b.n == 0 && gone.n == 0) {
            b.n = gone.n = 0; /* the contact closes: no orbit with separation to follow */
            continue;
        }
        const branch before = b.n ? b : gone;
        usm_hybrid_result r, alt;
        int on = b.n > 0 && follow(s, &b, pt->value, &r) == 0;
        int lost = before.n > 0 && !on;
        if (!on && solve_cold(s, pt->value, &r) != 0) {
            /* a converged point keeps its bilateral orbit (contact_open) and
             * says why there is no orbit with separation in `error` */
            const size_t len = strlen(pt->error);
            snprintf(pt->error + len, sizeof pt->error - len, "%sno orbit with separation: %.100s",
                     len ? "; " : "", usm_hybrid_message(s->hy)[0]
                                          ? usm_hybrid_message(s->hy)
                                          : "the contact does not open on it");
            if (before.n)
                gone = before;
            b.n = 0;
            continue;
        }
        if (lost && b.n == 2 && strcmp(b.r[1].mode_sequence, r.mode_sequence) == 0 &&
            !off_branch(&b, pt->value, &r)) {
            /* Newton failed from the branch, but the start from rest found an
             * orbit that continues it (its sequence, no jump) */
            lost = 0;
            on = 1;
            branch_push(&b, pt->value, &r);
        }
        pt->separating = 1;
        pt->hybrid = r;
        gone.n = 0;
        /* where the followed orbit's stability changed since the last
         * point (the same branch and mode sequence), located: a
         * stability_change, and where it turned unstable (unstable_from) */
        const double m0 = before.n ? before.r[1].floquet.max_modulus : NAN;
        const double m1 = r.floquet.max_modulus;
        if (!on || m1 < 1)
            unstable_from = NAN;
        if (on && before.n && strcmp(before.r[1].mode_sequence, r.mode_sequence) == 0 &&
            isfinite(m0) && isfinite(m1) && (m0 < 1) != (m1 < 1)) {
            double vx;
            usm_hybrid_result at;
            const int located = locate_stability(s, before.v[1], &before.r[1], pt->value, &r,
                                                 &vx, &at);
            if (m1 >= 1)
                unstable_from = located >= 0 ? vx : NAN;
            if (stability_event(s, vx, &at, located == 1, dir > 0, m1 >= 1) != 0)
                return -1;
        }
        if (lost) {
            if (switch_event(s, pt, &r, &before.r[1], SW_LOST, before.v[1], NAN) != 0)
                return -1;
            pt->switched = 1;
            b.n = 0;
            branch_push(&b, pt->value, &r);
        } else if (on && !(r.floquet.max_modulus < 1) && solve_cold(s, pt->value, &alt) == 0 &&
                   alt.floquet.max_modulus < 1) {
            if (switch_event(s, pt, &alt, &r, SW_UNSTABLE, pt->value, unstable_from) != 0)
                return -1;
            pt->hybrid = alt;
            pt->switched = 1;
            b.n = 0;
            branch_push(&b, pt->value, &alt);
        } else if (on && strcmp(before.r[1].mode_sequence, r.mode_sequence) != 0) {
            const int g = grazing_event(s, before.v[1], &before.r[1], pt, &r);
            if (g < 0)
                return -1;
            if (g == 1) { /* another branch from here */
                pt->switched = 1;
                b.n = 0;
                branch_push(&b, pt->value, &r);
            }
        }
        if (!on && !lost)
            branch_push(&b, pt->value, &r); /* the first orbit of a branch */
    }
    /* every event in sweep order (insertion sort: stable, few events) */
    for (size_t i = 1; i < s->nev; ++i)
        for (size_t j = i; j > 0 && dir * (s->ev[j].value - s->ev[j - 1].value) < 0; --j) {
            usm_periodic_event t = s->ev[j];
            s->ev[j] = s->ev[j - 1];
            s->ev[j - 1] = t;
        }
    return 0;
}
