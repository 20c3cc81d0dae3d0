/* The operating envelope of the imperfect motor, whose steady motion is a
 * periodic orbit rather than a stationary solution: contact_loss and
 * stick_loss continued in two parameters.
 *
 * contact_loss, where the orbit's least F_n is 0, and stick_loss (stick
 * models), where its largest stick excess q = |F_t| - mu0 F_n is 0, are
 * posed alike.  q has two extremes a period, half a period apart and equal
 * to the shot's noise (1e-10 of F_n_max) wherever measured (the orbit's
 * half-period symmetry: the imperfections force at 2 Omega).  One of them
 * is followed, its time t* an unknown: the orbit is shot from t0 = t*, and
 * k + 2 equations in k + 3 unknowns z = (x*, t*, a, b):
 *   r(x*, t*; px, py) = 0   periodicity in the k non-cyclic components of
 *                           the state x* at t* (usm_periodic_shoot,
 *                           solve/periodic_internal.h; scaled as the
 *                           shooting's)
 *   q(x*, t*; p) = 0        (scaled by F_n_max)
 *   dq/dt(x*, t*; p) = 0    its rate along the motion: t* is its extreme
 * Jacobian: the monodromy's block, dr/dt* in closed form (f(x1, t* + T) -
 * B f(x*, t*)), central differences in a and b (two periods of the state
 * alone each); the last two rows by central differences, which need no
 * integration (q and its rate are functions of (x*, t*, p)).  Newton
 * converges in 2 or 3 iterations, on the axes mode_split = 0 and
 * phase_error = 0 too, where the orbit's located extreme as the defining
 * function was lost at the first step (contact_loss) or noisy at 1e-5 of
 * the box (stick_loss).
 *
 * Two things make stick_loss's system regular.  (1) z holds the twist rate
 * w = phidot + psidot cos(theta) (the rate of the twist angle, a state of
 * the model) in phidot's place, scaled as the tilt vector's spin rate
 * (Omega theta).  On the orbit phidot and psidot are +-Omega and w is 1e-7
 * of Omega (0.03 rad/s at the onset on mode_split = 0); F_t follows w
 * (through the twist damping, 1.5e4 F_n_max per Omega, its rate through the
 * twist spring 47 times that), so q is linear over 1e-2 of Omega theta in
 * w, and 1e-4 of Omega in phidot alone, the rows' difference step in the
 * Euler angles, changed w by 700 times its value and flipped F_t's sign:
 * those rows were wrong, which was the singularity seen.  q is not steep;
 * phidot is the wrong unknown.  (2) q's rate by a central difference of
 * 1e-2 rad of Omega t, not F_n's 1e-5: F_t comes from phi'' and psi''
 * (~1e9 rad/s^2) that nearly cancel, so q is rounded to 1e-12 of F_n_max,
 * and over 1e-5 its rate was noisy at 2e-7 of F_n_max Omega, where Newton
 * stalled (periodic_internal.h, usm_periodic_quantity_rate_step).
 *
 * The followed extreme must stay the orbit's global one: at every point the
 * test function (the most extreme other local extreme of q over the orbit
 * against q(t*)) is monitored, the half-period copy of the followed one not
 * counted as another where the orbit has the symmetry.  Where it vanishes
 * (a corner of the boundary) the piece ends (`corner`), is named a
 * codimension-two point (e.g. contact_loss/contact_loss) inside the box,
 * and the other extreme's piece starts there, in the half where the first
 * one is no longer the global.  At a seed where two extremes are equal, the
 * one whose first step keeps it the global one is followed.
 *
 * Seeds: a one-parameter periodic sweep (usm_periodic_sweep) along each of
 * the box's four edges; each contact_loss and stick_loss event it locates
 * is a point of a curve crossing that edge.  The curve is continued from it
 * into the box (the edge's parameter held at the start, so that the first
 * point is the event itself) until it leaves the box, where its end is put
 * onto the side (usm_cont_correct_fixed): the seed the sweep of that side
 * found is then dropped as on the curve.  A curve closed inside the box,
 * crossing no edge, is not found.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/grow.h"
#include "envelope_internal.h"
#include "envelope_periodic_problem.h"
#include "solve/periodic_internal.h"
#include "usm_periodic_sweep.h"

#define PMAX (USM_MAX_NX + 3)
/* r's columns in the parameters, central differences of two shots of the
 * state alone: this fraction of the unknown's scale (truncation 1e-8).  The
 * forward difference against the full shot at 1e-5 had the full shot's
 * other steps in it, 1e-9 of the scales: in a box of 0.02 rad the tangent's
 * phase_error component was then noisy at 3e-3, and at stick_loss's turn
 * the fold's location failed step after step until the curve was lost. */
#define FD_REL 1e-4
/* q's and its rate's rows, central differences: truncation ~1e-8, and the
 * rate's own rounding (~1e-11 of it, a difference along the motion) over
 * this step ~1e-7 of the row. */
#define G_FD_REL 1e-4
/* The central differences along the motion that give q's rate, in radians
 * of Omega t: F_n's as the orbit's located extremes (solve/periodic.c);
 * the stick excess's longer, above its rounding (periodic_internal.h). */
#define RATE_STEP_F_N 1e-5
#define RATE_STEP_STICK 1e-2
/* The corrector's tolerance on its update (scaled): contact_loss's, and
 * stick_loss's, which is relative to the parameters' size where the box is
 * small against them (0.02 rad at 0.65 rad: 3.3e-7 of the side, 1e-8 of
 * the value).  The stick excess's rate and the twist angle's periodicity
 * leave ~1e-9 rad of noise in phase_error; at 1e-8 of such a box's side the
 * corrector failed near stick_loss's turn and the curve was lost. */
#define NEWTON_TOL 1e-9
#define NEWTON_TOL_STICK 1e-8
/* Longest step (the box's sides 1). */
#define H_MAX 0.05
/* Shortest step (scaled). */
#define H_MIN 1e-7
/* A seed within this (box's sides 1) of a curve's end of its kind lies on
 * that curve. */
#define SAME_TOL 1e-5
/* The box's sides for the stopping tests, this fraction of a side outside. */
#define BOX_PAD 1e-9
/* Two extremes of q within this (of F_n_max) are equal: the seed lies on a
 * corner, and each is tried. */
#define TIE_REL 1e-6
/* The half-period symmetry holds where q(t + T/2) - q(t) stays within this
 * (of F_n_max) over the samples: the shot's noise is ~1e-10. */
#define SYM_REL 1e-7
/* Extremes of one orbit listed. */
#define MAX_EXT 16
/* Curve pieces from one seed (corners followed). */
#define MAX_PIECES 8
/* Grid values of the edges' sweeps (the events do not depend on them). */
#define EDGE_POINTS 3
/* The edges' sweeps locate their events to this (of the edge): a seed is
 * only a start, each curve's first point is Newton's on its own system with
 * the edge's parameter held, and a seed is matched to a curve's end within
 * SAME_TOL.  The sweep's default 1e-11 cost half the seeds' time (the 4-DOF
 * stability box's edges 3.3 s each, 1.7 s at this) for nothing the
 * envelope reports. */
#define EDGE_EVENT_TOL 1e-7

typedef struct pseed {
    int kind;
    int edge; /* 0 x = lo, 1 x = hi, 2 y = lo, 3 y = hi */
    double x, y;
    double x0[USM_MAX_NX];
    /* stability and fold seeds: the sweep's crossing kind; a fold's x0 is
     * the branch's orbit nearest it, at (sx, sy) */
    int crossing;
    double sx, sy;
} pseed;

typedef struct penv {
    usm_envelope *e;
    usm_periodic *w;
    int kind;
    usm_periodic_quantity which;
    double sign;              /* +1 q's maximum is followed, -1 its minimum */
    int swap;                 /* 0 z = (x*, t*, px, py), 1 z = (x*, t*, py, px) */
    int k, N;                 /* non-cyclic states; unknowns k + 3 */
    int idx[USM_MAX_NX];
    env_twist twist;          /* the twist rate in phidot's place */
    double rate_step;         /* q's rate: its central difference's step */
    double xfull[USM_MAX_NX]; /* the cyclic components (a gauge) */
    double scale[PMAX];
    double gscale, Omega, h_sample;
    int tbox[4], tcorner;
    int skip;                 /* the corner test undefined at the piece's start */
    double start[2];
    double shot_z[PMAX];      /* where w's kept shot is (have_shot_z) */
    int have_shot_z;
    usm_cont *c;
} penv;

static void p_xy(const penv *pb, const double *z, double *px, double *py)
{
    const int j = pb->k + 1;
    *px = pb->swap ? z[j + 1] : z[j];
    *py = pb->swap ? z[j] : z[j + 1];
}

static void p_unpack(const penv *pb, const double *z, double *x0, usm_params *q)
{
    double px, py;
    env_twist_unpack(&pb->twist, pb->e->m, pb->idx, pb->k, pb->xfull, z, x0);
    p_xy(pb, z, &px, &py);
    *q = pb->e->p;
    *usm_params_field(q, pb->e->ax[0]) = px;
    *usm_params_field(q, pb->e->ax[1]) = py;
}

/* The parameter of unknown column j (k + 1 or k + 2). */
static const usm_param_info *col_param(const penv *pb, int j)
{
    return pb->e->ax[(j == pb->k + 1) == !pb->swap ? 0 : 1];
}

/* The column of axis a (0 x, 1 y). */
static int axis_col(const penv *pb, int a)
{
    return pb->k + 1 + ((a == 0) == !pb->swap ? 0 : 1);
}

/* The shot at z (its samples kept in w). */
static int shoot_at(penv *pb, const double *z, double *r)
{
    double x0[USM_MAX_NX];
    usm_params q;
    p_unpack(pb, z, x0, &q);
    usm_periodic_shoot_set_t0(pb->w, z[pb->k]);
    const int rc = usm_periodic_shoot(pb->w, &q, NULL, 0.0, x0, r, NULL) == USM_OK ? 0 : -1;
    pb->have_shot_z = rc == 0;
    memcpy(pb->shot_z, z, sizeof(double) * (size_t)pb->N);
    return rc;
}

/* q and dq/dt at z, scaled (no integration). */
static int q_pair(penv *pb, const double *z, double *g, double *gd)
{
    double x0[USM_MAX_NX];
    usm_params q;
    p_unpack(pb, z, x0, &q);
    if (usm_periodic_quantity_rate_step(pb->w, &q, pb->which, z[pb->k], x0, pb->rate_step, g,
                                        gd) != USM_OK)
        return -1;
    *g /= pb->gscale;
    *gd /= pb->gscale * pb->Omega;
    return 0;
}

static int residual(const double *z, double *F, double *J, void *ctx)
{
    penv *pb = ctx;
    const int k = pb->k, N = pb->N, ja = k + 1, jb = k + 2;
    double x0[USM_MAX_NX], ct[USM_MAX_NX];
    double Jk[USM_MAX_NX * (USM_MAX_NX + 1)];
    usm_params q;
    pb->have_shot_z = 0;
    for (int j = 0; j < N; ++j)
        if (!isfinite(z[j]))
            return -1;
    p_unpack(pb, z, x0, &q);
    usm_periodic_shoot_set_t0(pb->w, z[k]);
    if (J) {
        /* the parameters' columns first (the state alone keeps nothing),
         * each from two shots of the state alone: a difference against the
         * full shot, which takes other steps, is noisy at 1e-9 of the
         * scales over the step */
        for (int j = ja; j <= jb; ++j)
            if (env_param_column(pb->w, &q, col_param(pb, j), FD_REL * pb->scale[j], x0, k, J, N,
                                 j) != 0)
                return -1;
        if (usm_periodic_shoot(pb->w, &q, NULL, 0.0, x0, F, Jk) != USM_OK ||
            usm_periodic_shoot_t0_column(pb->w, ct) != USM_OK)
            return -1;
        for (int a = 0; a < k; ++a) {
            for (int b = 0; b < k; ++b)
                J[a * N + b] = Jk[a * (k + 1) + b];
            J[a * N + k] = ct[a];
            env_twist_chain(&pb->twist, pb->e->m, x0, J + a * N);
        }
    } else if (usm_periodic_shoot(pb->w, &q, NULL, 0.0, x0, F, NULL) != USM_OK)
        return -1;
    if (q_pair(pb, z, &F[k], &F[k + 1]) != 0)
        return -1;
    if (J) {
        double zs[PMAX], gp, gdp, gm, gdm;
        memcpy(zs, z, sizeof(double) * (size_t)N);
        for (int j = 0; j < N; ++j) {
            const double d = G_FD_REL * pb->scale[j];
            zs[j] = z[j] + d;
            const int okp = q_pair(pb, zs, &gp, &gdp);
            zs[j] = z[j] - d;
            const int okm = q_pair(pb, zs, &gm, &gdm);
            zs[j] = z[j];
            if (okp != 0 || okm != 0)
                return -1;
            J[k * N + j] = (gp - gm) / (2 * d);
            J[(k + 1) * N + j] = (gdp - gdm) / (2 * d);
        }
    }
    return 0;
}

/* The corner test at z: sign (q(t*) - the most extreme other local extreme
 * of q over the orbit), scaled; positive while the followed extreme is the
 * global one.  An orbit with the half-period symmetry (q(t + T/2) = q(t) to
 * SYM_REL) has each extreme twice, the copy half a period on: that copy is
 * the followed extreme itself, not another.  The other's time into *t_other
 * when not NULL.  NaN when the orbit has no other extreme or the shot
 * fails. */
static double corner_value(penv *pb, const double *z, double *t_other)
{
    double r[USM_MAX_NX], t[MAX_EXT], v[MAX_EXT], g, gd;
    if (shoot_at(pb, z, r) != 0)
        return NAN;
    const int n = usm_periodic_shoot_extremes(pb->w, pb->which, pb->sign, MAX_EXT, t, v);
    const int sym =
        usm_periodic_shoot_half_period_asymmetry(pb->w, pb->which) <= SYM_REL * pb->gscale;
    const double period = pb->h_sample * USM_PERIODIC_SAMPLES;
    for (int i = 0; i < n; ++i) {
        /* the followed extreme sits at t* = t0, the orbit's start */
        const double tau = t[i] - z[pb->k];
        const double dist = fmin(fabs(tau), fabs(period - fabs(tau)));
        if (dist <= 1.5 * pb->h_sample ||
            (sym && fabs(dist - 0.5 * period) <= 1.5 * pb->h_sample))
            continue;
        if (q_pair(pb, z, &g, &gd) != 0)
            return NAN;
        if (t_other)
            *t_other = t[i];
        return pb->sign * (g - v[i] / pb->gscale);
    }
    return NAN;
}

static double test_corner(const double *z, const double *dz, void *ctx)
{
    (void)dz;
    penv *pb = ctx;
    double px, py;
    p_xy(pb, z, &px, &py);
    const usm_envelope *e = pb->e;
    if (pb->skip && fabs(px - pb->start[0]) <= 1e-9 * (e->hi[0] - e->lo[0]) &&
        fabs(py - pb->start[1]) <= 1e-9 * (e->hi[1] - e->lo[1]))
        return NAN;
    return corner_value(pb, z, NULL);
}

typedef struct ptest {
    const penv *pb;
    int side; /* 0 x low, 1 x high, 2 y low, 3 y high */
} ptest;

static double test_box(const double *z, const double *dz, void *ctx)
{
    (void)dz;
    const ptest *t = ctx;
    const penv *pb = t->pb;
    double px, py;
    p_xy(pb, z, &px, &py);
    return env_box_test(pb->e, t->side, px, py, BOX_PAD);
}

static int add_seed(pseed **s, size_t *n, size_t *cap, int kind, int edge, double x, double y,
                    const double *x0, int nx)
{
    if (usm_grow((void **)s, cap, *n + 1, sizeof **s) != 0)
        return -1;
    pseed *d = &(*s)[(*n)++];
    memset(d, 0, sizeof *d);
    d->kind = kind;
    d->edge = edge;
    d->x = d->sx = x;
    d->y = d->sy = y;
    memcpy(d->x0, x0, sizeof(double) * (size_t)nx);
    return 0;
}

/* The events of the sweep along edge `edge`.  USM_OK, or USM_EFAILED when
 * out of memory; a sweep that fails is no seed (the message kept). */
static int edge_seeds(usm_envelope *e, int edge, pseed **s, size_t *n, size_t *cap)
{
    const int axis = edge < 2 ? 1 : 0; /* the edge x = const runs along y */
    const double fixed = edge < 2 ? (edge == 0 ? e->lo[0] : e->hi[0])
                                  : (edge == 2 ? e->lo[1] : e->hi[1]);
    usm_params q = e->p;
    *usm_params_field(&q, e->ax[1 - axis]) = fixed;
    usm_periodic_sweep *sw = usm_periodic_sweep_alloc(e->m);
    usm_periodic_sweep_options o;
    if (!sw)
        return USM_EFAILED;
    usm_periodic_sweep_options_default(&o);
    o.over = e->ax[axis]->name;
    o.from = e->lo[axis];
    o.to = e->hi[axis];
    o.points = EDGE_POINTS;
    o.event_tol = EDGE_EVENT_TOL;
    o.periodic.t0 = e->opt.t0;
    int rc = USM_OK;
    if (usm_periodic_sweep_run(sw, &q, &o) != USM_OK) {
        if (!e->msg[0])
            snprintf(e->msg, sizeof e->msg, "the sweep along %s = %g: %.150s",
                     e->ax[1 - axis]->name, fixed, usm_periodic_sweep_message(sw));
    } else
        for (size_t i = 0; i < usm_periodic_sweep_event_count(sw) && rc == USM_OK; ++i) {
            const usm_periodic_event *ev = usm_periodic_sweep_event_at(sw, i);
            if (e->m->unilateral && env_hybrid_seed(e, edge, ev) != 0)
                rc = USM_EFAILED;
            const int kind = ev->type == USM_PEVENT_CONTACT_LOSS  ? USM_ENVELOPE_CONTACT_LOSS
                             : ev->type == USM_PEVENT_STICK_LOSS ? USM_ENVELOPE_STICK_LOSS
                             : ev->type == USM_PEVENT_STABILITY_CHANGE &&
                                     ev->kind != USM_CROSSING_FOLD && e->opt.stability
                                 ? USM_ENVELOPE_STABILITY
                             : ev->type == USM_PEVENT_FOLD && e->opt.stability
                                 ? USM_ENVELOPE_FOLD
                                 : -1;
            const double x = axis == 0 ? ev->value : fixed, y = axis == 0 ? fixed : ev->value;
            if (kind == USM_ENVELOPE_FOLD) {
                /* the fold has no orbit: the branch's orbit nearest it */
                const usm_periodic_result *near = NULL;
                double at = NAN;
                for (size_t j = 0; j < i; ++j) {
                    const usm_periodic_event *ej = usm_periodic_sweep_event_at(sw, j);
                    if (ej->has_orbit && ej->orbit.converged &&
                        !(fabs(ej->value - ev->value) >= fabs(at - ev->value))) {
                        near = &ej->orbit;
                        at = ej->value;
                    }
                }
                for (size_t j = 0; j < usm_periodic_sweep_count(sw); ++j) {
                    const usm_periodic_point *pj = usm_periodic_sweep_point_at(sw, j);
                    if (pj->converged && !(fabs(pj->value - ev->value) >= fabs(at - ev->value))) {
                        near = &pj->orbit;
                        at = pj->value;
                    }
                }
                if (!near)
                    continue;
                if (add_seed(s, n, cap, kind, edge, x, y, near->x0, e->m->nx) != 0) {
                    rc = USM_EFAILED;
                    break;
                }
                (*s)[*n - 1].crossing = USM_CROSSING_FOLD;
                (*s)[*n - 1].sx = axis == 0 ? at : fixed;
                (*s)[*n - 1].sy = axis == 0 ? fixed : at;
                continue;
            }
            if (kind < 0 || !ev->has_orbit)
                continue;
            if (add_seed(s, n, cap, kind, edge, x, y, ev->orbit.x0, e->m->nx) != 0)
                rc = USM_EFAILED;
            else
                (*s)[*n - 1].crossing = ev->kind;
        }
    usm_periodic_sweep_free(sw);
    return rc;
}

static int on_curve(const usm_envelope *e, const pseed *s)
{
    for (size_t c = 0; c < e->ncurves; ++c) {
        const usm_envelope_curve *cv = &e->curves[c].pub;
        if ((int)cv->kind != s->kind || cv->npoints == 0)
            continue;
        for (int end = 0; end < 2; ++end) {
            const double *p = cv->xy + 2 * (end ? cv->npoints - 1 : 0);
            if (fabs(p[0] - s->x) <= SAME_TOL * (e->hi[0] - e->lo[0]) &&
                fabs(p[1] - s->y) <= SAME_TOL * (e->hi[1] - e->lo[1]))
                return 1;
        }
    }
    return 0;
}

typedef struct pbuf {
    double *xy, *u;
    size_t n, cap_xy, cap_u;
} pbuf;

/* A point of the curve: its (x, y) and the orbit's state at the envelope's
 * t0 (the curve's u, as the sweep reports an orbit). */
static int pbuf_push(pbuf *b, penv *pb, const double *z)
{
    const int nx = pb->e->m->nx;
    double x0[USM_MAX_NX], r[USM_MAX_NX];
    usm_params q;
    if (usm_grow((void **)&b->xy, &b->cap_xy, 2 * (b->n + 1), sizeof(double)) != 0 ||
        usm_grow((void **)&b->u, &b->cap_u, (size_t)nx * (b->n + 1), sizeof(double)) != 0)
        return -1;
    p_xy(pb, z, &b->xy[2 * b->n], &b->xy[2 * b->n + 1]);
    p_unpack(pb, z, x0, &q);
    double *u = b->u + (size_t)nx * b->n;
    memcpy(u, x0, sizeof(double) * (size_t)nx);
    /* the corner test's shot at z, when it is the last one */
    if ((pb->have_shot_z && memcmp(pb->shot_z, z, sizeof(double) * (size_t)pb->N) == 0) ||
        shoot_at(pb, z, r) == 0)
        (void)usm_periodic_shoot_state_at(pb->w, pb->e->opt.t0, u);
    b->n++;
    return 0;
}

/* How a piece ended. */
enum { PIECE_OK, PIECE_WRONG, PIECE_NOMEM };

/* One piece of a curve: the extreme at z0 followed from z0 in direction dir
 * of the last unknown, until it leaves the box, meets a corner (*end
 * CORNER, the point into zc and the other extreme's time into *t_other) or
 * is lost.  check: after the first step the followed extreme must be the
 * global one, else PIECE_WRONG (nothing kept). */
static int run_piece(penv *pb, const double *z0, int dir, int check, pbuf *b,
                     usm_envelope_end *end, double *zc, double *t_other)
{
    usm_envelope *e = pb->e;
    const int N = pb->N;
    int rc = PIECE_OK;
    ptest tests[4];
    usm_cont_options o;
    *end = USM_ENVELOPE_END_LOST;
    if (!(pb->c = usm_cont_alloc(N - 1)))
        return PIECE_NOMEM;
    usm_cont_options_default(&o);
    o.h0 = 0.2 * H_MAX;
    o.h_max = H_MAX;
    o.h_min = H_MIN;
    o.newton_max = 8;
    o.grow_its = 3;
    o.shrink_its = 6;
    o.newton_tol = NEWTON_TOL;
    if (pb->which == USM_PERIODIC_Q_STICK_EXCESS) {
        double rel = 1.0;
        for (int a = 0; a < 2; ++a)
            rel = fmax(rel, fmax(fabs(e->lo[a]), fabs(e->hi[a])) / (e->hi[a] - e->lo[a]));
        o.newton_tol = NEWTON_TOL_STICK * rel;
    }
    o.event_tol = 1e-10;
    o.across_fold = 1;
    o.max_steps = 20 * e->opt.max_points;
    usm_cont_set_problem(pb->c, residual, pb);
    if (usm_cont_set_options(pb->c, &o) != 0 || usm_cont_set_scale(pb->c, pb->scale) != 0) {
        rc = PIECE_NOMEM;
        goto done;
    }
    for (int side = 0; side < 4; ++side) {
        tests[side].pb = pb;
        tests[side].side = side;
        if ((pb->tbox[side] = usm_cont_add_test(pb->c, test_box, &tests[side],
                                                USM_CONT_TEST_STOP | USM_CONT_TEST_POINT)) < 0) {
            rc = PIECE_NOMEM;
            goto done;
        }
    }
    pb->tcorner = -1;
    if ((pb->tcorner = usm_cont_add_test(pb->c, test_corner, pb,
                                                   USM_CONT_TEST_STOP | USM_CONT_TEST_POINT)) < 0) {
        rc = PIECE_NOMEM;
        goto done;
    }
    p_xy(pb, z0, &pb->start[0], &pb->start[1]);
    /* at a corner (two extremes equal) the test has no sign at the start */
    const double c0 = corner_value(pb, z0, NULL);
    pb->skip = !(fabs(c0) > TIE_REL);
    if (usm_cont_start(pb->c, z0, dir) != 0)
        goto done;
    const size_t n_before = b->n;
    if (pbuf_push(b, pb, usm_cont_point(pb->c)) != 0) {
        rc = PIECE_NOMEM;
        goto done;
    }
    for (long steps = 0; steps < e->opt.max_points; ++steps) {
        const int st = usm_cont_step(pb->c);
        if (st != USM_CONT_STEP && st != USM_CONT_END)
            break;
        const double *zc_ = usm_cont_point(pb->c);
        if (steps == 0 && check && corner_value(pb, zc_, NULL) < 0) {
            b->n = n_before;
            rc = PIECE_WRONG;
            goto done;
        }
        if (st == USM_CONT_END) {
            const usm_cont_event *ev =
                usm_cont_event_at(pb->c, usm_cont_event_count(pb->c) - 1);
            double zs[PMAX];
            memcpy(zs, zc_, sizeof(double) * (size_t)N);
            if (ev && ev->test == pb->tcorner) {
                *end = USM_ENVELOPE_END_CORNER;
                memcpy(zc, zs, sizeof(double) * (size_t)N);
                if (isnan(corner_value(pb, zs, t_other)))
                    *end = USM_ENVELOPE_END_LOST;
            } else {
                const int col[2] = {axis_col(pb, 0), axis_col(pb, 1)};
                *end = USM_ENVELOPE_END_BOX;
                env_end_on_side(e, pb->c, pb->tbox, col, zs, N);
            }
            if (pbuf_push(b, pb, zs) != 0)
                rc = PIECE_NOMEM;
            break;
        }
        if (pbuf_push(b, pb, zc_) != 0) {
            rc = PIECE_NOMEM;
            break;
        }
        if (steps + 1 == e->opt.max_points)
            *end = USM_ENVELOPE_END_LIMIT;
    }
done:
    usm_cont_free(pb->c);
    pb->c = NULL;
    return rc;
}

/* The curve's points in b, kept as a curve of the envelope (b emptied). */
static int keep_curve(usm_envelope *e, int kind, pbuf *b, usm_envelope_end e0,
                      usm_envelope_end e1)
{
    if (b->n < 2) {
        b->n = 0;
        return 0;
    }
    if (usm_grow((void **)&e->curves, &e->curvecap, e->ncurves + 1, sizeof *e->curves) != 0)
        return -1;
    env_curve *cv = &e->curves[e->ncurves++];
    memset(cv, 0, sizeof *cv);
    cv->xy = b->xy;
    cv->u = b->u;
    cv->pub.kind = (usm_envelope_kind)kind;
    cv->pub.npoints = b->n;
    cv->pub.xy = cv->xy;
    cv->pub.u = cv->u;
    cv->pub.nu = e->m->nx;
    cv->pub.end[0] = e0;
    cv->pub.end[1] = e1;
    memset(b, 0, sizeof *b);
    return 0;
}

/* z for the extreme at time t of the last shot (the parameters px, py). */
static int z_at_extreme(penv *pb, double t, double px, double py, double *z)
{
    double x[USM_MAX_NX];
    if (usm_periodic_shoot_state_at(pb->w, t, x) != USM_OK)
        return -1;
    env_twist_pack(&pb->twist, pb->e->m, pb->idx, pb->k, x, z);
    z[pb->k] = t;
    z[axis_col(pb, 0)] = px;
    z[axis_col(pb, 1)] = py;
    return 0;
}

/* The curve through seed s, from its edge into the box, its pieces from
 * corner to corner, to where it leaves the box.  0, or -1 when out of
 * memory. */
static int trace(usm_envelope *e, penv *pb, const pseed *s)
{
    const usm_model *m = e->m;
    usm_periodic_result r;
    usm_periodic_options po;
    usm_params q = e->p;
    pbuf b = {0};
    *usm_params_field(&q, e->ax[0]) = s->x;
    *usm_params_field(&q, e->ax[1]) = s->y;
    usm_periodic_options_default(&po);
    po.t0 = e->opt.t0;
    /* the shooting's scales are those of the last solve: the seed's */
    if (usm_periodic_solve(pb->w, &q, s->x0, &po, &r) != USM_OK)
        return 0;
    double sc[USM_MAX_NX], rr[USM_MAX_NX], t[MAX_EXT], v[MAX_EXT];
    pb->kind = s->kind;
    pb->which = s->kind == USM_ENVELOPE_CONTACT_LOSS ? USM_PERIODIC_Q_F_N
                                                     : USM_PERIODIC_Q_STICK_EXCESS;
    pb->sign = s->kind == USM_ENVELOPE_CONTACT_LOSS ? -1.0 : 1.0;
    /* the edge's parameter held at the start: the last unknown */
    pb->swap = s->edge < 2 ? 1 : 0;
    pb->k = usm_periodic_shoot_layout(pb->w, pb->idx, sc);
    pb->N = pb->k + 3;
    memcpy(pb->xfull, r.x0, sizeof(double) * (size_t)m->nx);
    pb->Omega = 2.0 * 3.14159265358979323846 / r.period;
    pb->h_sample = r.period / USM_PERIODIC_SAMPLES;
    env_twist_setup(&pb->twist, m, pb->idx, pb->k, sc, pb->Omega, pb->scale);
    pb->scale[pb->k] = 1.0 / pb->Omega;
    pb->rate_step = pb->which == USM_PERIODIC_Q_F_N ? RATE_STEP_F_N : RATE_STEP_STICK;
    pb->gscale = fmax(fabs(r.F_n_max), 1e-300);
    for (int a = 0; a < 2; ++a)
        pb->scale[axis_col(pb, a)] = e->hi[a] - e->lo[a];
    usm_periodic_shoot_set_t0(pb->w, e->opt.t0);
    pb->have_shot_z = 0;
    if (usm_periodic_shoot(pb->w, &q, NULL, 0.0, r.x0, rr, NULL) != USM_OK)
        return 0;
    const int next = usm_periodic_shoot_extremes(pb->w, pb->which, pb->sign, MAX_EXT, t, v);
    double zc[PMAX], z0[PMAX], t_other = 0;
    usm_envelope_end end = USM_ENVELOPE_END_LOST, e0 = USM_ENVELOPE_END_BOX;
    int rc = PIECE_WRONG;
    /* into the box: the held parameter away from its edge */
    const int dir = s->edge % 2 == 0 ? 1 : -1;
    /* the extremes tied with the global one, each tried */
    for (int i = 0; i < next && rc == PIECE_WRONG; ++i) {
        if (pb->sign * (v[0] - v[i]) > TIE_REL * pb->gscale)
            break;
        /* the seed's shot again: a piece shoots from other start times */
        usm_periodic_shoot_set_t0(pb->w, e->opt.t0);
        pb->have_shot_z = 0;
        if (i > 0 && usm_periodic_shoot(pb->w, &q, NULL, 0.0, r.x0, rr, NULL) != USM_OK)
            break;
        if (z_at_extreme(pb, t[i], s->x, s->y, z0) != 0)
            continue;
        rc = run_piece(pb, z0, dir, 1, &b, &end, zc, &t_other);
    }
    for (int piece = 1; rc == PIECE_OK; ++piece) {
        if (keep_curve(e, s->kind, &b, e0, end) != 0) {
            rc = PIECE_NOMEM;
            break;
        }
        if (end != USM_ENVELOPE_END_CORNER || piece >= MAX_PIECES)
            break;
        double px, py, r2[USM_MAX_NX];
        p_xy(pb, zc, &px, &py);
        /* inside the box: two pieces of one boundary meet at an angle */
        if (px > e->lo[0] + 1e-6 * (e->hi[0] - e->lo[0]) &&
            px < e->hi[0] - 1e-6 * (e->hi[0] - e->lo[0]) &&
            py > e->lo[1] + 1e-6 * (e->hi[1] - e->lo[1]) &&
            py < e->hi[1] - 1e-6 * (e->hi[1] - e->lo[1])) {
            char type[40];
            /* no stationary unknowns: the orbit is the curves' u */
            const double none[USM_MAX_NU] = {0};
            snprintf(type, sizeof type, "%s/%s", usm_envelope_kind_name(s->kind),
                     usm_envelope_kind_name(s->kind));
            if (env_add_codim2(e, type, none, px, py, e->ncurves - 1) != 0) {
                rc = PIECE_NOMEM;
                break;
            }
        }
        /* the other extreme's piece, in the half where it is the global one */
        e0 = USM_ENVELOPE_END_CORNER;
        rc = PIECE_WRONG;
        const int swap0 = pb->swap;
        for (int tryno = 0; tryno < 4 && rc == PIECE_WRONG; ++tryno) {
            pb->swap = tryno < 2 ? swap0 : !swap0;
            const double sa = pb->scale[pb->k + 1];
            if (tryno == 2) { /* the parameters' scales follow their columns */
                pb->scale[pb->k + 1] = pb->scale[pb->k + 2];
                pb->scale[pb->k + 2] = sa;
            }
            double zt[PMAX];
            memcpy(zt, zc, sizeof(double) * (size_t)(pb->k + 1));
            zt[axis_col(pb, 0)] = px;
            zt[axis_col(pb, 1)] = py;
            if (shoot_at(pb, zt, r2) != 0 || z_at_extreme(pb, t_other, px, py, z0) != 0)
                break;
            rc = run_piece(pb, z0, tryno % 2 == 0 ? 1 : -1, 1, &b, &end, zc, &t_other);
        }
    }
    free(b.xy);
    free(b.u);
    return rc == PIECE_NOMEM ? -1 : 0;
}

int env_periodic_curves(usm_envelope *e)
{
    pseed *s = NULL;
    size_t n = 0, cap = 0;
    int rc = USM_OK;
    penv pb;
    memset(&pb, 0, sizeof pb);
    pb.e = e;
    if (!(pb.w = usm_periodic_alloc(e->m))) {
        snprintf(e->msg, sizeof e->msg, "out of memory for the orbits");
        return USM_EFAILED;
    }
    for (int edge = 0; edge < 4 && rc == USM_OK; ++edge)
        rc = edge_seeds(e, edge, &s, &n, &cap);
    e->nseeds = n;
    /* a failed edge sweep is said only when no curve is found */
    char sweep_msg[USM_MSG_LEN];
    snprintf(sweep_msg, sizeof sweep_msg, "%s", e->msg);
    e->msg[0] = '\0';
    for (int kind = USM_ENVELOPE_CONTACT_LOSS; kind <= USM_ENVELOPE_STICK_LOSS && rc == USM_OK;
         ++kind)
        for (size_t i = 0; i < n && rc == USM_OK; ++i) {
            if (s[i].kind != kind)
                continue;
            if (on_curve(e, &s[i])) {
                e->seeds_dropped++;
                continue;
            }
            if (trace(e, &pb, &s[i]) != 0) {
                snprintf(e->msg, sizeof e->msg, "out of memory for the curves");
                rc = USM_EFAILED;
            }
        }
    /* the orbit's multipliers, stability and fold: envelope_periodic_stability.c */
    for (size_t i = 0; i < n && rc == USM_OK; ++i)
        if ((s[i].kind == USM_ENVELOPE_STABILITY || s[i].kind == USM_ENVELOPE_FOLD) &&
            (on_curve(e, &s[i]) ? (e->seeds_dropped++, 0)
                                : env_periodic_stability_trace(e, pb.w, s[i].edge, s[i].crossing,
                                                               s[i].sx, s[i].sy, s[i].x0) != 0)) {
            snprintf(e->msg, sizeof e->msg, "out of memory for the curves");
            rc = USM_EFAILED;
        }
    /* the folds of the orbits with separation: envelope_hybrid.c */
    if (env_hybrid_curves(e, rc == USM_OK) != USM_OK)
        rc = USM_EFAILED;
    if (rc == USM_OK && e->ncurves == 0 && sweep_msg[0])
        snprintf(e->msg, sizeof e->msg, "%s", sweep_msg);
    free(s);
    usm_periodic_free(pb.w);
    return rc;
}

/* A region's orbit: where the ideal motor's start finds none (the 4-DOF
 * motor above F0 ~ 1 N, where the ideal motor has no stationary solution
 * while the imperfect one's orbits exist), the start is an orbit the
 * envelope knows: the curves' points hold the orbit's state at t0. */
#define CLS_NEAR_CURVES 3
/* the continuation in one parameter from a side of the box: first step,
 * and the smallest before it is given up */
#define CLS_STEP0 0.125
#define CLS_STEP_MIN (1.0 / 256.0)

static int cls_solve(usm_periodic *w, const usm_envelope *e, double x, double y, const double *x0,
                     const usm_periodic_options *po, usm_periodic_result *res)
{
    usm_params q = e->p;
    *usm_params_field(&q, e->ax[0]) = x;
    *usm_params_field(&q, e->ax[1]) = y;
    return usm_periodic_solve(w, &q, x0, po, res) == USM_OK ? 0 : -1;
}

/* From (x, y) where the ideal start finds an orbit to the sample (rx, ry)
 * along a straight line, each step from the last orbit, halved where the
 * solve fails.  0 with the orbit in res, or -1. */
static int cls_continue(usm_periodic *w, const usm_envelope *e, double x, double y, double rx,
                        double ry, const usm_periodic_options *po, usm_periodic_result *res)
{
    if (cls_solve(w, e, x, y, NULL, po, res) != 0)
        return -1;
    double s = 0.0, h = CLS_STEP0, x0[USM_MAX_NX];
    memcpy(x0, res->x0, sizeof(double) * (size_t)e->m->nx);
    while (s < 1.0) {
        const double t = fmin(1.0, s + h);
        if (cls_solve(w, e, x + t * (rx - x), y + t * (ry - y), x0, po, res) == 0) {
            s = t;
            memcpy(x0, res->x0, sizeof(double) * (size_t)e->m->nx);
            h = fmin(2.0 * h, CLS_STEP0);
        } else if ((h *= 0.5) < CLS_STEP_MIN)
            return -1;
    }
    return 0;
}

/* The orbit at the sample (rx, ry): started from the nearest points of the
 * CLS_NEAR_CURVES nearest curves (distance in the box's sides), else from
 * the ideal motor, else continued from the four sides through the sample.
 * *how says which; 0 with the orbit in res, or -1. */
static int cls_orbit(usm_periodic *w, const usm_envelope *e, double rx, double ry,
                     const usm_periodic_options *po, usm_periodic_result *res, const char **how,
                     char *why, size_t whylen)
{
    const int nx = e->m->nx;
    size_t best[CLS_NEAR_CURVES], pt[CLS_NEAR_CURVES];
    double dist[CLS_NEAR_CURVES];
    int nb = 0;
    for (size_t c = 0; c < e->ncurves; ++c) {
        const env_curve *cv = &e->curves[c];
        if (!cv->u || cv->pub.nu != nx)
            continue;
        double d = INFINITY;
        size_t j = 0;
        for (size_t i = 0; i < cv->pub.npoints; ++i) {
            const double dx = (cv->xy[2 * i] - rx) / (e->hi[0] - e->lo[0]),
                         dy = (cv->xy[2 * i + 1] - ry) / (e->hi[1] - e->lo[1]);
            if (hypot(dx, dy) < d) {
                d = hypot(dx, dy);
                j = i;
            }
        }
        int at = nb < CLS_NEAR_CURVES ? nb++ : CLS_NEAR_CURVES;
        while (at > 0 && dist[at - 1] > d) {
            if (at < CLS_NEAR_CURVES) {
                best[at] = best[at - 1];
                pt[at] = pt[at - 1];
                dist[at] = dist[at - 1];
            }
            --at;
        }
        if (at < CLS_NEAR_CURVES) {
            best[at] = c;
            pt[at] = j;
            dist[at] = d;
        }
    }
    for (int i = 0; i < nb; ++i)
        if (cls_solve(w, e, rx, ry, e->curves[best[i]].u + (size_t)nx * pt[i], po, res) == 0) {
            *how = "started from the nearest curve's orbit";
            return 0;
        } else if (i == 0)
            snprintf(why, whylen, "from the nearest curve's orbit: %s", usm_periodic_message(w));
    if (cls_solve(w, e, rx, ry, NULL, po, res) == 0) {
        *how = "started from the ideal motor";
        return 0;
    }
    if (nb == 0)
        snprintf(why, whylen, "from the ideal motor: %s", usm_periodic_message(w));
    const double from[4][2] = {
        {rx, e->lo[1]}, {rx, e->hi[1]}, {e->lo[0], ry}, {e->hi[0], ry}};
    for (int i = 0; i < 4; ++i)
        if (cls_continue(w, e, from[i][0], from[i][1], rx, ry, po, res) == 0) {
            *how = "continued from the box's side";
            return 0;
        }
    return -1;
}

int env_periodic_classify(usm_envelope *e, usm_envelope_region *r)
{
    usm_periodic *w = usm_periodic_alloc(e->m);
    usm_periodic_options po;
    usm_periodic_result res;
    if (!w) {
        snprintf(e->msg, sizeof e->msg, "out of memory for the orbits");
        return USM_EFAILED;
    }
    usm_periodic_options_default(&po);
    po.t0 = e->opt.t0;
    r->root = -1;
    r->roots = 0;
    r->cls = USM_POINT_OP_NOT_EVALUATED;
    const char *how = "";
    char why[USM_MSG_LEN] = "";
    if (cls_orbit(w, e, r->x, r->y, &po, &res, &how, why, sizeof why) != 0) {
        snprintf(r->class_name, sizeof r->class_name, "no_orbit");
        snprintf(r->message, sizeof r->message,
                 "no orbit started from the curves' orbits, the ideal motor or continued from "
                 "the box's sides; %.150s",
                 why);
    } else {
        r->roots = 1;
        /* the largest non-cyclic multiplier; where the orbit is unstable
         * through a complex pair with the contact closed, the closed-contact
         * squeal (docs/squeal.md).  Where the contact opens or the stick is
         * lost the model does not describe the motor: those classes stand. */
        const usm_floquet_result *fl = &res.floquet;
        int c = -1;
        for (int i = 0; i < fl->n; ++i)
            if (!fl->cyclic[i] &&
                (c < 0 || hypot(fl->re[i], fl->im[i]) > hypot(fl->re[c], fl->im[c])))
                c = i;
        const double mod = c >= 0 ? hypot(fl->re[c], fl->im[c]) : NAN;
        const int unstable = c >= 0 && mod > 1.0;
        const int pair = unstable && fabs(fl->im[c]) > USM_COMPLEX_PAIR_TOL * mod;
        const char *name = res.validity == USM_INVALID_CONTACT_OPEN ? "contact_open"
                           : res.validity == USM_INVALID_STICK     ? "stick_lost"
                           : pair                                  ? "squeal"
                           : unstable                              ? "unstable"
                           : e->m->friction                        ? "contact_closed"
                                                                   : "stick_admissible";
        snprintf(r->class_name, sizeof r->class_name, "%s", name);
        if (pair && res.validity == USM_VALID)
            snprintf(r->message, sizeof r->message,
                     "the periodic orbit (%s): squeal at %.6f Hz, |lambda| %.9f; F_n_min %.6g N, "
                     "friction_needed_max %.6g",
                     how, usm_squeal_frequency(1.0 / res.period, fl->re[c], fl->im[c]), mod,
                     res.F_n_min, res.friction_needed_max);
        else
            snprintf(r->message, sizeof r->message,
                     "the periodic orbit (%s): largest multiplier %.9g%+.9gi (|lambda| %.9f); "
                     "F_n_min %.6g N, friction_needed_max %.6g",
                     how, c >= 0 ? fl->re[c] : NAN, c >= 0 ? fl->im[c] : NAN, mod, res.F_n_min,
                     res.friction_needed_max);
    }
    /* the unilateral model's orbit with separation: envelope_hybrid_regions.c */
    if (e->m->unilateral && (strcmp(r->class_name, "contact_open") == 0 ||
                             strcmp(r->class_name, "no_orbit") == 0))
        env_hybrid_classify(e, r);
    usm_periodic_free(w);
    return USM_OK;
}
