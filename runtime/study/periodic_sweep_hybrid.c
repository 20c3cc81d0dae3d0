/* The periodic sweep past contact loss: the orbits with separation of a
 * unilateral model at the grid points (usm_periodic_sweep.h, "Unilateral
 * models"; docs/unilateral.md).
 *
 * The orbits with separation are followed as a branch by the continuation
 * engine (cont/, usm_cont.h).  The zero problem is the shooting condition of
 * usm_hybrid_solve_from (solve/hybrid_internal.h): the period map from the
 * section time t0 of the branch's first orbit, x(t0 + T) - x(t0) on the
 * non-cyclic components of the state, in those components and the swept
 * parameter; its Jacobian is the monodromy with its saltation matrices less
 * I and a difference in the parameter.  From the last grid point's orbit
 * the engine steps to the next grid value (a stopping test function there,
 * the orbit corrected to the value exactly), and on the way locates, by
 * root finding on the arclength:
 *   - max |lambda| = 1 (largest |multiplier| with saltation): a
 *     stability_change event with the orbit there;
 *   - a change of the mode sequence (the indicator +1 on the branch's
 *     sequence, -1 off it; its sign change located by Brent, which bisects
 *     a step): where the orbit just past it continues the located one (the
 *     map is continuous there), a grazing event, and the branch goes on in
 *     the new sequence; otherwise the branch ends there;
 *   - a fold (dp/ds = 0): the branch ends there.
 * Where the steps shrink to h_min next to a multiplier +1 that is no fold
 * (a branch point) the branch is taken across by the parameter
 * (jump_across); where the section leaves the closed phase it moves
 * (resection).  The events of a step past a grid point wait for the next
 * one.
 * A branch that ends (or whose corrector fails) is lost: the point takes the
 * orbit a start from rest settles on (usm_hybrid_solve), a branch_switch
 * with branch_lost carrying where the branch ended (branch_end) and its last
 * grid orbit, and the branch is followed on from the new orbit.
 *
 * The orbit the motor runs on: where the followed orbit is unstable at a
 * grid point, a start from rest gives the start-up's attractor; when that
 * one is stable the point takes it (branch_switch, with where the followed
 * orbit turned unstable: unstable_from) and the branch continues from it. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/root.h"
#include "periodic_sweep_state.h"
#include "solve/hybrid_internal.h"
#include "usm_cont.h"

static usm_params params_at(const usm_periodic_sweep *s, double v)
{
    usm_params q = s->p;
    *usm_params_field(&q, s->info) = v;
    return q;
}

/* Newton's stop near |lambda| = 1 for the event's orbit: B - I nearly
 * singular there amplifies the map's noise (1e-11) by 1 / (|lambda| - 1),
 * so a residual of 1e-9 may not be reached (measured 1.5e-8 at |lambda| =
 * 1.001); an orbit to 1e-7 moves the multipliers by about that. */
#define STAB_NEWTON_TOL 1e-7
/* The engine's corrector stops at 1e-8 of the state's scales (the noise
 * amplified near a multiplier +1: above); the orbit at a grid point is then
 * finished by usm_hybrid_solve_from to its 1e-9. */
#define CONT_NEWTON_TOL 1e-8
/* The parameter's difference step in the Jacobian, of the range: the map's
 * noise 1e-11 over it is 1e-5 of the column, which moves the tangent only. */
#define DP_REL 1e-6
/* A test function's value at the corrector's point is the one of its last
 * Jacobian (a monodromy) when that lies within this of it (scaled). */
#define CACHE_TOL 1e-7
/* Past a change of the mode sequence: the branch restarts this far (of the
 * range) beyond the located point, and the sequences' orbits meet when the
 * restart's state lies within GRAZE_MEET of it (scaled). */
#define GRAZE_NUDGE 1e-8
#define GRAZE_MEET 1e-4
#define MAX_GRAZINGS 64 /* along one branch */
#define TWIST_SCALE 100.0
#define MAX_JUMPS 16 /* along one branch */
#define MAX_PENDING 16
#define ORBIT_TOL 1e-9 /* usm_hybrid_solve_from's default */

/* The zero problem of one branch and the engine that follows it. */
typedef struct hbranch {
    usm_periodic_sweep *s;
    int nx, nr, idx[USM_MAX_NX]; /* the state; its non-cyclic components: the unknowns */
    double t0, xs[USM_MAX_NX];   /* section time; the state whose cyclic components stay */
    double scale[USM_MAX_NX + 1];
    char seq[USM_HYBRID_MAX_SWITCHES + 1]; /* the branch's mode sequence */
    /* the last map with the monodromy: its point, max |lambda| and that
     * multiplier, sequence */
    int have;
    double xc[USM_MAX_NX + 1], mod, crit[2];
    char seqc[USM_HYBRID_MAX_SWITCHES + 1];
    usm_cont *c;
    int k_seq;
    /* the engine on the branch (live) from one grid point to the next; its
     * events past the last grid point wait (pend) for the grid point after
     * them, and are dropped should the sweep leave the branch there */
    int live, ended; /* ended: the branch ended (or was lost) at end_v */
    double end_v, sense;
    char end[256];
    usm_branch_end_how end_how;
    int npend, jumps, grazings, resections;
    double xs0[USM_MAX_NX + 1], dx0[USM_MAX_NX + 1]; /* the last step's start and direction */
    struct pending {
        int grazing; /* 0: a stability change (at, located, rising) */
        double v;
        usm_hybrid_result at;
        int located, rising;
        char from[USM_HYBRID_MAX_SWITCHES + 1], to[USM_HYBRID_MAX_SWITCHES + 1];
    } pend[MAX_PENDING];
} hbranch;

/* The state x0 of the unknowns x (the spin coordinates w of
 * usm_hybrid_shoot: w[x_phidot] = phidot + psidot), and back. */
static void state_of(const hbranch *b, const double *x, double *xs)
{
    const usm_model *m = b->s->m;
    memcpy(xs, b->xs, sizeof(double) * (size_t)b->nx);
    for (int a = 0; a < b->nr; ++a)
        xs[b->idx[a]] = x[a];
    xs[m->x_phidot] -= xs[m->x_psidot];
}

static void unknowns_of(const hbranch *b, const double *xs, double *x)
{
    const usm_model *m = b->s->m;
    for (int a = 0; a < b->nr; ++a)
        x[a] = xs[b->idx[a]] + (b->idx[a] == m->x_phidot ? xs[m->x_psidot] : 0.0);
}

/* One map with the monodromy at x: F and B - I (J, nr x nr), the cache. */
static int shoot_at(hbranch *b, const double *x, double *F, double *J)
{
    double xs[USM_MAX_NX];
    state_of(b, x, xs);
    const usm_params q = params_at(b->s, x[b->nr]);
    b->have = 0;
    if (usm_hybrid_shoot(b->s->hy, &q, b->t0, xs, NULL, NULL, F, J, &b->mod, b->crit, NULL,
                         b->seqc) !=
        USM_OK)
        return -1;
    memcpy(b->xc, x, sizeof(double) * (size_t)(b->nr + 1));
    b->have = 1;
    return 0;
}

static int residual(const double *x, double *F, double *J, void *ctx)
{
    hbranch *b = ctx;
    const int n = b->nr, N = n + 1;
    double Jx[USM_MAX_NX * USM_MAX_NX], Fp[USM_MAX_NX], xs[USM_MAX_NX];
    if (!J) {
        state_of(b, x, xs);
        const usm_params q = params_at(b->s, x[n]);
        return usm_hybrid_shoot(b->s->hy, &q, b->t0, xs, NULL, NULL, F, NULL, NULL, NULL,
                                NULL, NULL) == USM_OK ? 0 : -1;
    }
    if (shoot_at(b, x, F, Jx) != 0)
        return -1;
    state_of(b, x, xs);
    double dp = DP_REL * b->scale[n];
    usm_params q = params_at(b->s, x[n] + dp);
    if (usm_hybrid_shoot(b->s->hy, &q, b->t0, xs, NULL, NULL, Fp, NULL, NULL, NULL, NULL,
                         NULL) != USM_OK) {
        dp = -dp; /* the parameter's bound just beyond */
        q = params_at(b->s, x[n] + dp);
        if (usm_hybrid_shoot(b->s->hy, &q, b->t0, xs, NULL, NULL, Fp, NULL, NULL, NULL,
                             NULL, NULL) != USM_OK)
            return -1;
    }
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j)
            J[i * N + j] = Jx[i * n + j];
        J[i * N + n] = (Fp[i] - F[i]) / dp;
    }
    return 0;
}

/* The cache at x (the corrector's last Jacobian within CACHE_TOL), else a
 * map with the monodromy there; 0 or -1. */
static int cached(hbranch *b, const double *x)
{
    double F[USM_MAX_NX], J[USM_MAX_NX * USM_MAX_NX];
    int near = b->have;
    for (int j = 0; near && j <= b->nr; ++j)
        near = fabs(x[j] - b->xc[j]) <= CACHE_TOL * b->scale[j];
    return near ? 0 : shoot_at(b, x, F, J);
}

static double stab_test(const double *x, const double *dx, void *ctx)
{
    (void)dx;
    hbranch *b = ctx;
    return cached(b, x) == 0 ? b->mod - 1.0 : NAN;
}

static double seq_test(const double *x, const double *dx, void *ctx)
{
    (void)dx;
    hbranch *b = ctx;
    if (cached(b, x) != 0)
        return NAN;
    return strcmp(b->seqc, b->seq) == 0 ? 1.0 : -1.0;
}

/* The orbit (usm_hybrid_solve_from, to tol) at the branch's point x. */
static int orbit_at(hbranch *b, const double *x, double tol, usm_hybrid_result *out)
{
    double xs[USM_MAX_NX];
    usm_hybrid_options o;
    usm_hybrid_options_default(&o);
    o.tol = tol;
    state_of(b, x, xs);
    const usm_params q = params_at(b->s, x[b->nr]);
    return usm_hybrid_solve_from(b->s->hy, &q, &o, b->t0, xs, out) == USM_OK &&
                   out->nmodes >= 2 ? 0 : -1;
}

/* A new engine on the branch of the orbit r at v. */
static int branch_begin(hbranch *b, double v, const usm_hybrid_result *r, double *x)
{
    usm_cont_options o;
    double F[USM_MAX_NX], J[USM_MAX_NX * USM_MAX_NX];
    usm_cont_free(b->c);
    b->c = NULL;
    b->live = b->ended = 0;
    b->npend = b->jumps = b->grazings = b->resections = 0;
    b->end_v = NAN;
    snprintf(b->end, sizeof b->end, "Newton fails on its branch");
    b->end_how = USM_BRANCH_END_NEWTON;
    b->nx = r->nx;
    b->t0 = r->t0;
    memcpy(b->xs, r->x0, sizeof(double) * (size_t)r->nx);
    snprintf(b->seq, sizeof b->seq, "%s", r->mode_sequence);
    const usm_params q = params_at(b->s, v);
    b->have = 0;
    if (usm_hybrid_shoot(b->s->hy, &q, b->t0, r->x0, b->idx, &b->nr, F, J, &b->mod, b->crit,
                         b->scale, b->seqc) != USM_OK)
        return -1;
    double sc[USM_MAX_NX + 1];
    /* the twist angle's corrector updates stall at 2e-8 to 5e-8 of its
     * scale (measured, 4-DOF mode split 1.94 %: the map's noise over its
     * weak column), the others' at 1e-9: it is measured at TWIST_SCALE times
     * its scale, so that the corrector's tolerance is above its noise */
    for (int a = 0; a < b->nr; ++a)
        sc[a] = b->scale[b->idx[a]] * (b->idx[a] == b->s->m->x_tau ? TWIST_SCALE : 1.0);
    unknowns_of(b, r->x0, x);
    /* the parameter at its own size, not the sweep's range: the path, and so
     * the events, the same for any range and grid */
    sc[b->nr] = fmax(fabs(v), b->s->range);
    x[b->nr] = v;
    memcpy(b->scale, sc, sizeof sc);
    if (!(b->c = usm_cont_alloc(b->nr)))
        return -2;
    usm_cont_options_default(&o);
    o.newton_tol = CONT_NEWTON_TOL;
    o.newton_max = 8;
    o.h_min = 1e-9;
    o.event_tol = 1e-11;
    usm_cont_set_problem(b->c, residual, b);
    if (usm_cont_set_options(b->c, &o) != 0 || usm_cont_set_scale(b->c, b->scale) != 0 ||
        (b->k_seq = usm_cont_add_test(b->c, seq_test, b, USM_CONT_TEST_STOP)) < 0)
        return -2;
    return 0;
}

/* The orbit a start from rest settles on at v (usm_hybrid_solve); 0 or -1. */
static int solve_cold(usm_periodic_sweep *s, double v, usm_hybrid_result *out)
{
    const usm_params q = params_at(s, v);
    return usm_hybrid_solve(s->hy, &q, NULL, out) == USM_OK && out->nmodes >= 2 ? 0 : -1;
}

/* How a branch_switch came about. */
enum { SW_UNSTABLE, SW_LOST };

/* The branch_switch event at pt: `to` the orbit followed from here, `from`
 * the followed orbit it replaces (SW_UNSTABLE: unstable at pt; SW_LOST: the
 * branch's last orbit, at v_last, and `to` from a start from rest; end says
 * how the branch ended). */
static int switch_event(usm_periodic_sweep *s, const usm_periodic_point *pt,
                        const usm_hybrid_result *to, const usm_hybrid_result *from, int how,
                        double v_last, double unstable_from, const char *end)
{
    char vt[96], vl[96];
    psweep_value_text(s, pt->value, vt);
    psweep_value_text(s, v_last, vl);
    usm_periodic_event *e =
        how == SW_LOST
            ? psweep_event_add(
                  s, USM_PEVENT_BRANCH_SWITCH, pt->value, NULL,
                  "the orbit with separation followed to %s does not continue to %s (%s); "
                  "from a start from rest: %s, max |lambda| %.4f, %.6g 1/s, open %.3f, followed "
                  "on", vl, vt, end, to->mode_sequence, to->floquet.max_modulus,
                  to->rotor_speed_mean, to->separation_fraction)
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
    e->branch_end = NAN;
    return 0;
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
    e->branch_last = e->unstable_from = e->branch_end = NAN;
    return 0;
}


/* The grazing where the followed orbit's mode sequence changes from `from`
 * to `to` at vg (located).  0, or -1 when out of memory. */
static int grazing_event(usm_periodic_sweep *s, double vg, const char *from, const char *to)
{
    char vt[96];
    psweep_value_text(s, vg, vt);
    return psweep_event_add(s, USM_PEVENT_GRAZING, vg, NULL,
                            "the orbit with separation changes its mode sequence from %s to %s "
                            "at %s: an orbit touches a guard tangentially there", from, to,
                            vt) ? 0 : -1;
}

/* Past the change of the mode sequence at the branch's point x (towards
 * v): the orbit just beyond, corrected at its parameter, into x, and its
 * sequence the branch's.  1 when it continues the orbit at x (the two
 * sequences' orbits meet: a grazing), 0 when not (the branch ends). */
static int past_grazing(hbranch *b, double *x, double v)
{
    const int N = b->nr + 1;
    double xn[USM_MAX_NX + 1];
    memcpy(xn, x, sizeof(double) * (size_t)N);
    xn[b->nr] += (v > x[b->nr] ? 1 : -1) * GRAZE_NUDGE * b->scale[b->nr];
    if (usm_cont_correct_fixed(b->c, xn, b->nr, xn[b->nr]) < 0 || cached(b, xn) != 0 ||
        strcmp(b->seqc, b->seq) == 0)
        return 0;
    for (int a = 0; a < b->nr; ++a)
        if (!(fabs(xn[a] - x[a]) <= GRAZE_MEET * b->scale[a]))
            return 0;
    snprintf(b->seq, sizeof b->seq, "%s", b->seqc);
    memcpy(x, xn, sizeof(double) * (size_t)N);
    return 1;
}

/* Brent's function across a jump (below): max |lambda| - 1 of the orbit at
 * the parameter value q, corrected at it from the linear interpolation of
 * the jump's ends. */
typedef struct jump_ctx {
    hbranch *b;
    const double *xa, *xb;
    double x[USM_MAX_NX + 1];
    usm_hybrid_result at; /* the last trial's orbit */
} jump_ctx;

static double jump_stab(double q, void *ctx)
{
    jump_ctx *j = ctx;
    hbranch *b = j->b;
    const int n = b->nr;
    const double w = (q - j->xa[n]) / (j->xb[n] - j->xa[n]);
    for (int a = 0; a <= n; ++a)
        j->x[a] = j->xa[a] + w * (j->xb[a] - j->xa[a]);
    j->x[n] = q;
    /* Newton on the residual, to STAB_NEWTON_TOL: next to the branch point
     * the corrector's updates stall above its tolerance */
    if (orbit_at(b, j->x, STAB_NEWTON_TOL, &j->at) != 0 ||
        strcmp(j->at.mode_sequence, b->seq) != 0)
        return NAN;
    return j->at.floquet.max_modulus - 1.0;
}

/* Where the engine's steps shrink to h_min next to a multiplier +1 of a
 * branch that goes on through it (a branch point: the tangent is not
 * defined there, and the steps that reach it turn), the branch is taken
 * across it by the parameter: from the last point x (direction dx) to the
 * parameter JUMP_MIN, 10 JUMP_MIN, ... of the range beyond (towards v), the
 * predictor along dx corrected at that value, kept when it lies within
 * JUMP_NEAR of the prediction (scaled) in the branch's sequence, past
 * max |lambda| = 1 when the last point is within JUMP_STAB of it, and where
 * the engine starts again (its tangent defined).  Into x; 0, or -1 when no
 * jump holds.  A stability change across it is located by
 * Brent on the parameter (each trial corrected at its value) into *vs, and
 * *rising says its sense; *vs NaN when there is none. */
#define JUMP_MIN 1e-6
#define JUMP_MAX 1e-1
#define JUMP_NEAR 1e-2
#define JUMP_STAB 1e-3
static int jump_across(hbranch *b, double *x, const double *dx, double v, double *vs,
                       int *rising, usm_hybrid_result *at)
{
    const int n = b->nr;
    double xa[USM_MAX_NX + 1], xb[USM_MAX_NX + 1];
    *vs = NAN;
    memcpy(xa, x, sizeof(double) * (size_t)(n + 1));
    if (cached(b, xa) != 0 || !(fabs(dx[n]) > 0))
        return -1;
    const double ga = b->mod - 1.0, sense = v > xa[n] ? 1 : -1;
    for (double d = JUMP_MIN; d <= JUMP_MAX * 1.01; d *= 10) {
        const double q = fabs(v - xa[n]) < d * b->scale[n] ? v : xa[n] + sense * d * b->scale[n];
        int near = 1;
        /* the tangent next to a branch point is poorly defined: along it
         * while its prediction is not far from the point's, else from it */
        const double hp = (q - xa[n]) / dx[n];
        for (int a = 0; a <= n; ++a)
            xb[a] = xa[a] + (fabs(hp) < JUMP_NEAR ? dx[a] * hp : 0.0);
        xb[n] = q;
        double xp[USM_MAX_NX + 1];
        memcpy(xp, xb, sizeof xp);
        int corrected = usm_cont_correct_fixed(b->c, xb, n, q);
        if (corrected < 0) {
            /* the orbit's own Newton (on the residual, with chord steps),
             * where the corrector's updates do not settle (a kink of the
             * map: its Jacobian jumps) */
            usm_hybrid_result o;
            memcpy(xb, xp, sizeof xp);
            if (orbit_at(b, xb, ORBIT_TOL, &o) == 0) {
                unknowns_of(b, o.x0, xb);
                corrected = 0;
            }
        }
        if (corrected < 0 || cached(b, xb) != 0 || strcmp(b->seqc, b->seq) != 0)
            continue;
        for (int a = 0; a < n && near; ++a)
            near = fabs(xb[a] - xp[a]) <= JUMP_NEAR * b->scale[a];
        if (!near)
            continue;
        const double gb = b->mod - 1.0;
        /* next to |lambda| = 1, across it; the engine goes on from there
         * (its tangent defined) */
        if ((fabs(ga) < JUMP_STAB && !((ga < 0) != (gb < 0))) ||
            usm_cont_start(b->c, xb, (int)sense) != 0)
            continue;
        if (isfinite(ga) && isfinite(gb) && (ga < 0) != (gb < 0)) {
            jump_ctx j = {.b = b, .xa = xa, .xb = xb};
            usm_root *root = usm_root_alloc();
            const usm_root_stop stop = {1e-11 * b->scale[n], 0.0, 100};
            double qs;
            if (root && usm_root_brent(root, jump_stab, &j, xa[n], q, ga, gb, &stop, &qs) == 0 &&
                isfinite(jump_stab(qs, &j))) {
                *at = j.at;
                *vs = qs;
                *rising = ga < 0;
            }
            usm_root_free(root);
        }
        memcpy(x, xb, sizeof(double) * (size_t)(n + 1));
        return 0;
    }
    return -1;
}

static int pend_add(hbranch *b, int grazing, double v, const usm_hybrid_result *at,
                    int located, int rising, const char *from, const char *to)
{
    if (b->npend >= MAX_PENDING)
        return -1;
    struct pending *e = &b->pend[b->npend++];
    e->grazing = grazing;
    e->v = v;
    if (at)
        e->at = *at;
    e->located = located;
    e->rising = rising;
    snprintf(e->from, sizeof e->from, "%s", from ? from : "");
    snprintf(e->to, sizeof e->to, "%s", to ? to : "");
    return 0;
}

/* The branch's end at x with its reason. */
static void branch_ended(hbranch *b, double v_end, usm_branch_end_how how, const char *fmt,
                         const char *seq)
{
    char vt[96];
    b->ended = 1;
    b->end_how = how;
    b->end_v = v_end;
    psweep_value_text(b->s, v_end, vt);
    snprintf(b->end, sizeof b->end, fmt, vt, seq);
}

/* The branch's section moved to the middle of the longest closed phase of
 * the orbit at x (RESECT_SAMPLES a period): the section time t0 is the first
 * orbit's, and where the closed phases shift along the branch it may leave
 * them, where the period map fails (the contact open at the end of the
 * period: 3-DOF phase error 0.88 rad on, the branch seemed to end at
 * 0.90927 rad, where it goes on to 0.9125).  The engine restarts there (its
 * pending events kept).  0, or -1 when the orbit or the samples fail, the
 * section does not move, or the engine does not start. */
#define RESECT_SAMPLES 200
#define MAX_RESECTIONS 8 /* along one branch */
static int resection(hbranch *b, const double *x)
{
    usm_hybrid_result r, r2;
    const int nx = b->nx, cols = USM_HYBRID_SAMPLE_COLS(nx);
    if (b->resections >= MAX_RESECTIONS || orbit_at(b, x, ORBIT_TOL, &r) != 0)
        return -1;
    const usm_params q = params_at(b->s, x[b->nr]);
    double *rows = malloc(sizeof(double) * (size_t)USM_HYBRID_SAMPLE_ROWS(RESECT_SAMPLES) *
                          (size_t)cols);
    int nrows = 0, best = -1, best_len = 0;
    if (rows && usm_hybrid_orbit_samples(b->s->hy, &q, &r, 0.0, RESECT_SAMPLES, rows, &nrows) ==
                    USM_OK)
        for (int i = 0; i < nrows;) {
            int j = i;
            while (j < nrows && rows[(size_t)j * (size_t)cols + 1] == 0.0)
                ++j;
            if (j - i > best_len) {
                best_len = j - i;
                best = i + (j - i) / 2;
            }
            i = j > i ? j : i + 1;
        }
    double t0 = NAN, x0[USM_MAX_NX];
    if (best >= 0) {
        t0 = rows[(size_t)best * (size_t)cols];
        memcpy(x0, rows + (size_t)best * (size_t)cols + 2, sizeof(double) * (size_t)nx);
    }
    free(rows);
    if (best < 0 || fabs(t0 - b->t0) < 1e-3 * r.period ||
        usm_hybrid_solve_from(b->s->hy, &q, NULL, t0, x0, &r2) != USM_OK || r2.nmodes < 2)
        return -1;
    /* the engine anew from there; its events and counts kept */
    hbranch keep = *b;
    double xn[USM_MAX_NX + 1];
    const int rc = branch_begin(b, x[b->nr], &r2, xn);
    memcpy(b->pend, keep.pend, sizeof b->pend);
    b->npend = keep.npend;
    b->jumps = keep.jumps;
    b->grazings = keep.grazings;
    b->resections = keep.resections + 1;
    b->sense = keep.sense;
    b->live = 1;
    if (rc != 0 || usm_cont_start(b->c, xn, (int)b->sense) != 0)
        return -1;
    return 0;
}

/* The cubic through a step's ends xa, xb with their directions da, db
 * (dx/ds) at the parameter's value v (the chord when hermite is 0), into x. */
static void step_cubic(int n, const double *xa, const double *da, const double *xb,
                       const double *db, int hermite, double v, double *x)
{
    const double dp = xb[n] - xa[n], w = (v - xa[n]) / dp;
    const double h00 = (1 + 2 * w) * (1 - w) * (1 - w), h10 = w * (1 - w) * (1 - w);
    const double h01 = w * w * (3 - 2 * w), h11 = w * w * (w - 1);
    for (int a = 0; a < n; ++a)
        x[a] = hermite ? h00 * xa[a] + h10 * dp * da[a] / da[n] + h01 * xb[a] +
                             h11 * dp * db[a] / db[n]
                       : xa[a] + w * (xb[a] - xa[a]);
    x[n] = v;
}

/* Brent's function for a stability change inside a step: max |lambda| - 1
 * of the orbit at the parameter's value q, Newton (to STAB_NEWTON_TOL) from
 * the step's cubic there plus the cubic's error at the last trial (the
 * cubic misses the orbits of a long step by up to 1e-6, a smooth error: so
 * the trials that close in on the zero start within Newton's tolerance and
 * take one map with the monodromy each, not two), in the branch's
 * sequence. */
typedef struct cubic_ctx {
    hbranch *b;
    const double *xa, *da, *xb, *db;
    double x[USM_MAX_NX + 1], q;
    double err[USM_MAX_NX + 1]; /* the cubic's error at the last trial */
    usm_hybrid_result at;       /* the orbit at q */
} cubic_ctx;

static double cubic_stab(double q, void *ctx)
{
    cubic_ctx *j = ctx;
    hbranch *b = j->b;
    double xc[USM_MAX_NX + 1];
    step_cubic(b->nr, j->xa, j->da, j->xb, j->db, 1, q, xc);
    for (int a = 0; a <= b->nr; ++a)
        j->x[a] = xc[a] + j->err[a];
    j->q = NAN;
    if (orbit_at(b, j->x, STAB_NEWTON_TOL, &j->at) != 0 ||
        strcmp(j->at.mode_sequence, b->seq) != 0)
        return NAN;
    unknowns_of(b, j->at.x0, j->x);
    for (int a = 0; a < b->nr; ++a)
        j->err[a] = j->x[a] - xc[a];
    j->q = q;
    return j->at.floquet.max_modulus - 1.0;
}

/* The stability change inside the last step (max |lambda| - 1 from g0 at
 * its start, b->xs0, to g1 at the engine's point): its parameter value into
 * *v and its orbit into *at; 0, or -1 when it is not located.  Where the
 * critical multiplier is +1 (plus) the branch has a branch point there (B -
 * I singular, the branch going on in the parameter: not a fold), where the
 * arc's corrections fail within about 1e-4 of it (the noise amplified by
 * 1 / (|lambda| - 1)); there Brent on the parameter, each trial an orbit
 * from the step's cubic, comes first; elsewhere Brent on the step's arc.
 * Each is the other's fallback.  (Before, a failed location rejected the
 * step: the engine halved it some 25 times to h_min, about 2 s, before
 * jump_across took the branch across by the same Brent on the parameter.) */
static int stab_in_step(hbranch *b, double g0, double g1, int plus, double *v,
                        usm_hybrid_result *at)
{
    const int n = b->nr;
    const double *xb = usm_cont_point(b->c), *db = usm_cont_direction(b->c);
    const double dp = xb[n] - b->xs0[n];
    /* the cubic in the parameter needs it monotone along the step */
    const int cubic = dp != 0.0 && b->dx0[n] * dp > 0 && db[n] * dp > 0;
    for (int pass = 0; pass < 2; ++pass) {
        if ((pass == 0) != (plus && cubic)) {
            double x[USM_MAX_NX + 1], s;
            if (usm_cont_arc_locate(b->c, stab_test, b, g0, g1, &s, x) == 0 &&
                orbit_at(b, x, STAB_NEWTON_TOL, at) == 0) {
                *v = x[n];
                return 0;
            }
        } else if (cubic) {
            cubic_ctx j = {.b = b, .xa = b->xs0, .da = b->dx0, .xb = xb, .db = db, .q = NAN};
            usm_root *root = usm_root_alloc();
            /* the trials' max |lambda| is good to about 1e-9 (Newton to
             * STAB_NEWTON_TOL), the zero so to about 1e-11 of the
             * parameter's scale at the slopes of 30 to 200 per unit met: a
             * tighter stop only bisects that noise (measured, 4-DOF mode
             * split 1.947 %: seven trials within 1e-13 of each other) */
            const usm_root_stop stop = {1e-10 * b->scale[n], 0.0, 100};
            double q;
            const int ok = root &&
                           usm_root_brent(root, cubic_stab, &j, b->xs0[n], xb[n], g0, g1, &stop,
                                          &q) == 0 &&
                           (j.q == q || isfinite(cubic_stab(q, &j)));
            usm_root_free(root);
            if (ok) {
                *v = q;
                *at = j.at;
                return 0;
            }
        }
    }
    return -1;
}

/* One step of the engine on the branch, its events pending and its end
 * noted (b->ended); a jump across a branch point goes at most to v.  0, or
 * -1 when out of memory. */
static int branch_step(hbranch *b, double v)
{
    const int N = b->nr + 1;
    double x[USM_MAX_NX + 1];
    memcpy(b->xs0, usm_cont_point(b->c), sizeof(double) * (size_t)N);
    memcpy(b->dx0, usm_cont_direction(b->c), sizeof(double) * (size_t)N);
    /* max |lambda| - 1 at the step's start (the cache: its corrector's last
     * Jacobian) */
    const double g0 = cached(b, b->xs0) == 0 ? b->mod - 1.0 : NAN;
    const int st = usm_cont_step(b->c);
    /* the last point on the branch, before a failed resection replaces the
     * engine (whose point is then no point of the branch) */
    const double v_last = usm_cont_point(b->c)[b->nr];
    if (st == USM_CONT_LOST && strstr(usm_hybrid_message(b->s->hy), "section") != NULL) {
        /* the last map failed as its section left the closed phase: a new
         * section, and on */
        memcpy(x, usm_cont_point(b->c), sizeof(double) * (size_t)N);
        if (resection(b, x) == 0)
            return 0;
        if (!b->c)
            return -1;
    }
    if (st == USM_CONT_LOST && b->jumps < MAX_JUMPS) {
        double dx[USM_MAX_NX + 1], vs;
        int rising;
        usm_hybrid_result at;
        memcpy(x, usm_cont_point(b->c), sizeof(double) * (size_t)N);
        memcpy(dx, usm_cont_direction(b->c), sizeof(double) * (size_t)N);
        if (jump_across(b, x, dx, v, &vs, &rising, &at) == 0) {
            ++b->jumps;
            return isfinite(vs) ? pend_add(b, 0, vs, &at, 1, rising, NULL, NULL) : 0;
        }
    }
    if (st != USM_CONT_STEP && st != USM_CONT_END) {
        branch_ended(b, v_last, USM_BRANCH_END_NEWTON, "Newton fails on its branch past %s%s",
                     "");
        return 0;
    }
    memcpy(x, usm_cont_point(b->c), sizeof(double) * (size_t)N);
    if (isfinite(g0) && g0 != 0.0 && cached(b, x) == 0 && isfinite(b->mod) &&
        (b->mod == 1.0 || (g0 < 0) != (b->mod < 1.0))) {
        usm_hybrid_result at;
        double vs;
        /* no orbit to report when it fails: the grid points' multipliers
         * say it */
        if (stab_in_step(b, g0, b->mod - 1.0, b->crit[1] == 0.0 && b->crit[0] > 0.0, &vs,
                         &at) == 0 &&
            pend_add(b, 0, vs, &at, 1, g0 < 0, NULL, NULL) != 0)
            return -1;
    }
    if (st == USM_CONT_STEP)
        return 0;
    const usm_cont_event *e = usm_cont_event_at(b->c, usm_cont_event_count(b->c) - 1);
    memcpy(x, usm_cont_point(b->c), sizeof(double) * (size_t)N);
    const double ve = x[b->nr];
    if (e->test == USM_CONT_FOLD) {
        branch_ended(b, ve, USM_BRANCH_END_FOLD, "its branch ends at a fold at %s%s", "");
        return 0;
    }
    char from[USM_HYBRID_MAX_SWITCHES + 1];
    snprintf(from, sizeof from, "%s", b->seq);
    if (b->grazings++ >= MAX_GRAZINGS || !past_grazing(b, x, b->sense * INFINITY) ||
        usm_cont_start(b->c, x, (int)b->sense) != 0) {
        branch_ended(b, ve, USM_BRANCH_END_SEQUENCE,
                     "its branch ends at %s, where its mode sequence %s changes and no "
                     "orbit of another continues it",
                     from);
        return 0;
    }
    return pend_add(b, 1, ve, NULL, 1, 0, from, b->seq);
}

/* The pending events up to v (in the sweep's sense) as the sweep's. */
static int pend_flush(usm_periodic_sweep *s, hbranch *b, double v, double dir,
                      double *unstable_from)
{
    int k = 0, rc = 0;
    for (; k < b->npend && rc == 0 && (b->pend[k].v - v) * b->sense <= 0; ++k) {
        const struct pending *e = &b->pend[k];
        if (e->grazing)
            rc = grazing_event(s, e->v, e->from, e->to);
        else {
            rc = stability_event(s, e->v, &e->at, e->located, dir > 0, e->rising);
            *unstable_from = e->rising ? e->v : NAN;
        }
    }
    memmove(b->pend, b->pend + k, sizeof b->pend[0] * (size_t)(b->npend - k));
    b->npend -= k;
    return rc;
}

/* Follows the branch of the orbit ra at va (the engine's, when it is live
 * from there) to the grid value v, with its stability changes and
 * grazings on the way.  0: *out the orbit at v; 1: the branch is lost before
 * v (*v_end where it ended, NaN when not located; `end` says how); -1: out
 * of memory. */
static int follow(usm_periodic_sweep *s, hbranch *b, double va, const usm_hybrid_result *ra,
                  double v, double dir, usm_hybrid_result *out, double *v_end, char end[256],
                  usm_branch_end_how *end_how, double *unstable_from)
{
    double x[USM_MAX_NX + 1];
    *v_end = NAN;
    if (!b->live) {
        const int rc = branch_begin(b, va, ra, x);
        if (rc != 0) {
            snprintf(end, 256, "%s", b->end);
            *end_how = b->end_how;
            return rc == -2 ? -1 : 1;
        }
        b->sense = v > va ? 1 : -1;
        b->live = 1;
        if (usm_cont_start(b->c, x, (int)b->sense) != 0)
            branch_ended(b, va, USM_BRANCH_END_NEWTON, "Newton fails on its branch at %s%s", "");
    }
    const int n = b->nr;
    /* steps until the branch passes v or ends */
    for (;;) {
        const double *xa;
        const double s_end = usm_cont_step_arc(b->c, &xa);
        const double pb = usm_cont_point(b->c)[n];
        if (b->ended && (b->end_v - v) * b->sense <= 0)
            break;
        if ((pb - v) * b->sense >= 0) {
            /* the grid point: on the last step's arc (or the point itself),
             * corrected at v */
            const double *xb = usm_cont_point(b->c);
            memcpy(x, xb, sizeof(double) * (size_t)(n + 1));
            if (xa && s_end > 0 && (xa[n] - v) * b->sense < 0) {
                /* the cubic through the step's ends with their directions
                 * (an arc point would cost a correction more; the chord
                 * alone missed the orbit by 1e-4, Hermite's by 1e-8) */
                const double *db = usm_cont_direction(b->c), *da = b->dx0;
                const int hermite = memcmp(xa, b->xs0, sizeof(double) * (size_t)(n + 1)) == 0 &&
                                    fabs(da[n]) > 0 && fabs(db[n]) > 0;
                step_cubic(n, xa, da, xb, db, hermite, v, x);
            }
            x[n] = v;
            if (pend_flush(s, b, v, dir, unstable_from) != 0)
                return -1;
            /* the orbit's own Newton (chord steps: maps without the
             * monodromy) from there; else from the arc's point corrected */
            if (orbit_at(b, x, ORBIT_TOL, out) == 0 && strcmp(out->mode_sequence, b->seq) == 0)
                return 0;
            if (xa && s_end > 0 &&
                usm_cont_arc_point(b->c, (v - xa[n]) / (pb - xa[n]) * s_end, x, NULL) == 0 &&
                usm_cont_correct_fixed(b->c, x, n, v) >= 0 && orbit_at(b, x, ORBIT_TOL, out) == 0)
                return 0;
            branch_ended(b, v, USM_BRANCH_END_NEWTON, "Newton fails on its branch at %s%s", "");
            break;
        }
        if (b->ended)
            break;
        if (branch_step(b, v) != 0)
            return -1;
    }
    if (pend_flush(s, b, b->end_v, dir, unstable_from) != 0)
        return -1;
    *v_end = b->end_v;
    snprintf(end, 256, "%s", b->end);
    *end_how = b->end_how;
    b->live = 0;
    return 1;
}

int psweep_separating(usm_periodic_sweep *s, double dir)
{
    if (!s->hy && !(s->hy = usm_hybrid_alloc(s->m)))
        return -1;
    hbranch b;
    memset(&b, 0, sizeof b);
    b.s = s;
    /* the followed orbit (have) at vl, or a branch lost at a point without
     * any orbit since (gone), its end at v_end */
    int have = 0, gone = 0, rc = 0;
    double vl = NAN, v_end = NAN, unstable_from = NAN;
    usm_hybrid_result rl, alt, r;
    char end[256] = "";
    usm_branch_end_how end_how = USM_BRANCH_END_NONE;
    for (size_t i = 0; i < s->npts && rc == 0; ++i) {
        usm_periodic_point *pt = &s->pts[i];
        pt->separating = pt->switched = 0;
        if (pt->converged ? !pt->orbit.contact_open : !have && !gone) {
            have = gone = 0; /* the contact closes: no orbit with separation to follow */
            b.live = 0;
            continue;
        }
        int on = 0;
        if (have) {
            const int f = follow(s, &b, vl, &rl, pt->value, dir, &r, &v_end, end, &end_how,
                                  &unstable_from);
            if (f < 0) {
                rc = -1;
                break;
            }
            on = f == 0;
        }
        const int lost = (have || gone) && !on;
        if (!on && solve_cold(s, pt->value, &r) != 0) {
            /* a converged point keeps its bilateral orbit (contact_open) and
             * says why there is no orbit with separation in `error` */
            const size_t len = strlen(pt->error);
            snprintf(pt->error + len, sizeof pt->error - len, "%sno orbit with separation: %.100s",
                     len ? "; " : "", usm_hybrid_message(s->hy)[0]
                                          ? usm_hybrid_message(s->hy)
                                          : "the contact does not open on it");
            gone = have || gone;
            have = 0;
            continue;
        }
        pt->separating = 1;
        pt->hybrid = r;
        if (!on || !(r.floquet.max_modulus >= 1))
            unstable_from = NAN;
        if (lost) {
            if (switch_event(s, pt, &r, &rl, SW_LOST, vl, NAN, end) != 0) {
                rc = -1;
                break;
            }
            s->ev[s->nev - 1].branch_end = v_end;
            s->ev[s->nev - 1].branch_end_how = end_how;
            pt->switched = 1;
            b.live = 0;
        } else if (on && !(r.floquet.max_modulus < 1) && solve_cold(s, pt->value, &alt) == 0 &&
                   alt.floquet.max_modulus < 1) {
            if (switch_event(s, pt, &alt, &r, SW_UNSTABLE, pt->value, unstable_from, "") != 0) {
                rc = -1;
                break;
            }
            pt->hybrid = r = alt;
            pt->switched = 1;
            b.live = 0; /* the events past pt on the left branch are not the motor's */
        }
        have = 1;
        gone = 0;
        vl = pt->value;
        rl = r;
    }
    usm_cont_free(b.c);
    if (rc != 0)
        return rc;
    /* every event in sweep order (insertion sort: stable, few events) */
    for (size_t i = 1; i < s->nev; ++i)
        for (size_t j = i; j > 0 && dir * (s->ev[j].value - s->ev[j - 1].value) < 0; --j) {
            usm_periodic_event t = s->ev[j];
            s->ev[j] = s->ev[j - 1];
            s->ev[j - 1] = t;
        }
    return 0;
}
