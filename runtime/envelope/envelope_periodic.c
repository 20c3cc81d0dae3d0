/* The operating envelope of the imperfect motor, whose steady motion is a
 * periodic orbit rather than a stationary solution: contact_loss and
 * stick_loss continued in two parameters.
 *
 * The zero problem, k + 1 equations in k + 2 unknowns x = (x0, a, b):
 *   r(x0; px, py) = 0   the orbit's periodicity in the k non-cyclic
 *                       components of the state at t0 (usm_periodic_shoot,
 *                       solve/periodic_internal.h; scaled as the shooting's)
 *   g(x0; px, py) = 0   contact_loss: F_n_min, the least normal force over
 *                       the period; stick_loss (stick models): the largest
 *                       |F_t| - mu0 F_n over it; each the extreme sample
 *                       refined by Brent on its rate, a smooth function of
 *                       (x0, px, py) as the one-parameter sweep's test
 *                       functions are, so that both locate the same zero.
 * Jacobian: the monodromy's block and forward differences in px and py (one
 * period of the state alone each) for r; g's row by forward differences (a
 * shot each), formed once per continuation step and kept for the
 * corrector's iterations there (a chord on one row: Newton then converges
 * linearly, the zero set is r and g's alone).
 *
 * Seeds: a one-parameter periodic sweep (usm_periodic_sweep) along each of
 * the box's four edges; each contact_loss and stick_loss event it locates
 * is a point of a curve crossing that edge.  The curve is continued from it
 * into the box (the edge's parameter held at the start, so that the first
 * point is the event itself) until it leaves the box, where its end is put
 * onto the side (usm_cont_correct_fixed): the seed the sweep of that side
 * found is then dropped as on the curve.  A curve closed inside the box,
 * crossing no edge, is not found.
 *
 * Not yet working (measured, 3dof_imperfect): a seed on the axis
 * mode_split = 0 is lost at the first step (no step down to 1e-5 of the
 * box converges: g appears to have a corner there, as at phase_error = 0,
 * where two equal minima of F_n a period compete); and where two minima
 * nearly compete (contact_loss below phase error 0.26 rad at mode split
 * 2.4 %) Newton converges linearly, 8 iterations a step, and the curve
 * creeps.  tests/envelope/test_envelope_periodic.c (disabled) says what
 * must hold.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/grow.h"
#include "envelope_internal.h"
#include "solve/periodic_internal.h"
#include "usm_periodic_sweep.h"

#define PMAX (USM_MAX_NX + 2)
/* Forward differences of r in the parameters: this fraction of the
 * unknown's scale (the sweep's DLAM: the residual's noise floor ~5e-10 of
 * the scales over it stays below 1e-4 of the column). */
#define FD_REL 1e-5
/* g's row: 1e-5 made Newton linear at a factor 0.3 an iteration (g's
 * curvature over some state scales), 1e-7 converges in 3 or 4 where g's
 * extreme is one peak. */
#define G_FD_REL 1e-7
/* The corrector's tolerance on its update (scaled): the one-parameter
 * sweep's, above the residual's noise floor. */
#define NEWTON_TOL 1e-8
/* Longest step (the box's sides 1): the curves are smooth and each step
 * costs k + 2 shots for g's row. */
#define H_MAX 0.08
/* A seed within this (box's sides 1) of a curve's end of its kind lies on
 * that curve. */
#define SAME_TOL 1e-5
/* The box's sides for the stopping tests, this fraction of a side outside. */
#define BOX_PAD 1e-9
/* Shortest step (scaled): where g has a corner (at phase_error = 0 with a
 * mode split the normal force has two equal minima a period, and F_n_min is
 * their lesser) Newton converges only linearly and the steps would shrink
 * without end; the curve is lost there instead. */
#define H_MIN 1e-5
/* A curve lost within this (box's sides 1) of a side's seed of its kind
 * ends at that seed: the corner lies on the side (the symmetry's axis). */
#define SNAP_TOL 2e-3
/* Grid values of the edges' sweeps (the events do not depend on them). */
#define EDGE_POINTS 3

typedef struct pseed {
    int kind;
    int edge; /* 0 x = lo, 1 x = hi, 2 y = lo, 3 y = hi */
    double x, y;
    double x0[USM_MAX_NX];
} pseed;

typedef struct penv {
    usm_envelope *e;
    usm_periodic *w;
    int kind;
    int swap;                 /* 0 x = (x0, px, py), 1 x = (x0, py, px) */
    int k, N;                 /* equations - 1 (the periodicity's), unknowns k + 2 */
    int idx[USM_MAX_NX];
    double xfull[USM_MAX_NX];
    double scale[PMAX];
    double gscale;
    double grow[PMAX];        /* g's row, scaled as the equations */
    int have_grow;
    int tbox[4];
    usm_cont *c;
} penv;

static void p_xy(const penv *pb, const double *x, double *px, double *py)
{
    *px = pb->swap ? x[pb->k + 1] : x[pb->k];
    *py = pb->swap ? x[pb->k] : x[pb->k + 1];
}

static void p_unpack(const penv *pb, const double *x, double *x0, usm_params *q)
{
    double px, py;
    memcpy(x0, pb->xfull, sizeof(double) * (size_t)pb->e->m->nx);
    for (int a = 0; a < pb->k; ++a)
        x0[pb->idx[a]] = x[a];
    p_xy(pb, x, &px, &py);
    *q = pb->e->p;
    *usm_params_field(q, pb->e->ax[0]) = px;
    *usm_params_field(q, pb->e->ax[1]) = py;
}

/* g after a shot of w. */
static double p_g(penv *pb)
{
    return pb->kind == USM_ENVELOPE_CONTACT_LOSS ? usm_periodic_shoot_F_n_min(pb->w)
                                                 : usm_periodic_shoot_stick_excess(pb->w);
}

/* g at x alone (a shot). */
static int g_at(penv *pb, const double *x, double *g)
{
    double x0[USM_MAX_NX], r[USM_MAX_NX];
    usm_params q;
    p_unpack(pb, x, x0, &q);
    if (usm_periodic_shoot(pb->w, &q, NULL, 0.0, x0, r, NULL) != USM_OK)
        return -1;
    *g = p_g(pb);
    return isfinite(*g) ? 0 : -1;
}

/* The parameter of unknown column j (k or k + 1). */
static const usm_param_info *col_param(const penv *pb, int j)
{
    return pb->e->ax[(j == pb->k) == !pb->swap ? 0 : 1];
}

static int residual(const double *x, double *F, double *J, void *ctx)
{
    penv *pb = ctx;
    const int k = pb->k, N = pb->N;
    double x0[USM_MAX_NX], rb[USM_MAX_NX], Jk[USM_MAX_NX * (USM_MAX_NX + 1)];
    usm_params q;
    for (int j = 0; j < N; ++j)
        if (!isfinite(x[j]))
            return -1;
    p_unpack(pb, x, x0, &q);
    if (J) {
        /* the second parameter's column first: the state alone keeps nothing */
        const int j2 = k + 1;
        const double d = FD_REL * pb->scale[j2];
        usm_params q2 = q;
        *usm_params_field(&q2, col_param(pb, j2)) += d;
        if (usm_periodic_shoot_state(pb->w, &q2, x0, rb) != USM_OK)
            return -1;
        if (usm_periodic_shoot(pb->w, &q, col_param(pb, k), FD_REL * pb->scale[k], x0, F, Jk) !=
            USM_OK)
            return -1;
        for (int a = 0; a < k; ++a) {
            for (int b = 0; b <= k; ++b)
                J[a * N + b] = Jk[a * (k + 1) + b];
            J[a * N + j2] = (rb[a] - F[a]) / d;
        }
    } else if (usm_periodic_shoot(pb->w, &q, NULL, 0.0, x0, F, NULL) != USM_OK)
        return -1;
    const double g = p_g(pb);
    if (!isfinite(g))
        return -1;
    F[k] = g / pb->gscale;
    if (J) {
        if (!pb->have_grow) {
            double xs[PMAX];
            memcpy(xs, x, sizeof(double) * (size_t)N);
            for (int j = 0; j < N; ++j) {
                double gj;
                const double d = G_FD_REL * pb->scale[j];
                xs[j] = x[j] + d;
                const int rc = g_at(pb, xs, &gj);
                xs[j] = x[j];
                if (rc != 0)
                    return -1;
                pb->grow[j] = (gj - g) / d / pb->gscale;
            }
            pb->have_grow = 1;
            /* the shots of the row replaced the kept one: x's again */
            if (usm_periodic_shoot(pb->w, &q, NULL, 0.0, x0, rb, NULL) != USM_OK)
                return -1;
        }
        memcpy(J + k * N, pb->grow, sizeof(double) * (size_t)N);
    }
    return 0;
}

typedef struct ptest {
    const penv *pb;
    int side; /* 0 x low, 1 x high, 2 y low, 3 y high */
} ptest;

static double test_box(const double *x, const double *dx, void *ctx)
{
    (void)dx;
    const ptest *t = ctx;
    const penv *pb = t->pb;
    double v[2];
    p_xy(pb, x, &v[0], &v[1]);
    const int a = t->side / 2;
    const usm_envelope *e = pb->e;
    const double pad = BOX_PAD * (e->hi[a] - e->lo[a]);
    return t->side % 2 == 0 ? v[a] - (e->lo[a] - pad) : (e->hi[a] + pad) - v[a];
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
    d->x = x;
    d->y = y;
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
    o.periodic.t0 = e->opt.t0;
    int rc = USM_OK;
    if (usm_periodic_sweep_run(sw, &q, &o) != USM_OK) {
        if (!e->msg[0])
            snprintf(e->msg, sizeof e->msg, "the sweep along %s = %g: %.150s",
                     e->ax[1 - axis]->name, fixed, usm_periodic_sweep_message(sw));
    } else
        for (size_t i = 0; i < usm_periodic_sweep_event_count(sw) && rc == USM_OK; ++i) {
            const usm_periodic_event *ev = usm_periodic_sweep_event_at(sw, i);
            const int kind = ev->type == USM_PEVENT_CONTACT_LOSS  ? USM_ENVELOPE_CONTACT_LOSS
                             : ev->type == USM_PEVENT_STICK_LOSS ? USM_ENVELOPE_STICK_LOSS
                                                                 : -1;
            if (kind < 0 || !ev->has_orbit)
                continue;
            const double x = axis == 0 ? ev->value : fixed, y = axis == 0 ? fixed : ev->value;
            if (add_seed(s, n, cap, kind, edge, x, y, ev->orbit.x0, e->m->nx) != 0)
                rc = USM_EFAILED;
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

static int pbuf_push(pbuf *b, const penv *pb, const double *x)
{
    const int nx = pb->e->m->nx;
    double x0[USM_MAX_NX];
    usm_params q;
    if (usm_grow((void **)&b->xy, &b->cap_xy, 2 * (b->n + 1), sizeof(double)) != 0 ||
        usm_grow((void **)&b->u, &b->cap_u, (size_t)nx * (b->n + 1), sizeof(double)) != 0)
        return -1;
    p_xy(pb, x, &b->xy[2 * b->n], &b->xy[2 * b->n + 1]);
    p_unpack(pb, x, x0, &q);
    memcpy(b->u + (size_t)nx * b->n, x0, sizeof(double) * (size_t)nx);
    b->n++;
    return 0;
}

/* The curve through seed s, from its edge into the box to where it leaves
 * it.  0, or -1 when out of memory. */
static int trace(usm_envelope *e, penv *pb, const pseed *s, const pseed *all, size_t nall)
{
    const usm_model *m = e->m;
    usm_periodic_result r;
    usm_periodic_options po;
    usm_params q = e->p;
    pbuf b = {0};
    int rc = 0;
    usm_envelope_end end = USM_ENVELOPE_END_LOST;
    *usm_params_field(&q, e->ax[0]) = s->x;
    *usm_params_field(&q, e->ax[1]) = s->y;
    usm_periodic_options_default(&po);
    po.t0 = e->opt.t0;
    /* the shooting's scales and t0 are those of the last solve: the seed's */
    if (usm_periodic_solve(pb->w, &q, s->x0, &po, &r) != USM_OK)
        return 0;
    double sc[USM_MAX_NX];
    memset(pb->tbox, 0, sizeof pb->tbox);
    pb->kind = s->kind;
    /* the edge's parameter held at the start: the last unknown */
    pb->swap = s->edge < 2 ? 1 : 0;
    pb->k = usm_periodic_shoot_layout(pb->w, pb->idx, sc);
    pb->N = pb->k + 2;
    memcpy(pb->xfull, r.x0, sizeof(double) * (size_t)m->nx);
    for (int a = 0; a < pb->k; ++a)
        pb->scale[a] = sc[pb->idx[a]];
    pb->scale[pb->k] = e->hi[pb->swap] - e->lo[pb->swap];
    pb->scale[pb->k + 1] = e->hi[1 - pb->swap] - e->lo[1 - pb->swap];
    pb->gscale = fmax(fabs(r.F_n_max), 1e-300);
    pb->have_grow = 0;
    if (!(pb->c = usm_cont_alloc(pb->k + 1)))
        return -1;
    ptest tests[4];
    usm_cont_options o;
    usm_cont_options_default(&o);
    o.h0 = 0.25 * H_MAX;
    o.h_max = H_MAX;
    o.h_min = H_MIN;
    /* g's row by differences makes Newton linear (a factor 0.3 an
     * iteration where the stick excess's peak is shallow): the step grows
     * up to 5 iterations and shrinks from 9 */
    o.newton_max = 10;
    o.grow_its = 5;
    o.shrink_its = 9;
    o.newton_tol = NEWTON_TOL;
    o.event_tol = 1e-10;
    o.across_fold = 1;
    o.max_steps = 20 * e->opt.max_points;
    usm_cont_set_problem(pb->c, residual, pb);
    if (usm_cont_set_options(pb->c, &o) != 0 || usm_cont_set_scale(pb->c, pb->scale) != 0) {
        rc = -1;
        goto done;
    }
    for (int side = 0; side < 4; ++side) {
        tests[side].pb = pb;
        tests[side].side = side;
        if ((pb->tbox[side] = usm_cont_add_test(pb->c, test_box, &tests[side],
                                                USM_CONT_TEST_STOP | USM_CONT_TEST_POINT)) < 0) {
            rc = -1;
            goto done;
        }
    }
    double x[PMAX];
    for (int a = 0; a < pb->k; ++a)
        x[a] = r.x0[pb->idx[a]];
    x[pb->k] = pb->swap ? s->y : s->x;
    x[pb->k + 1] = pb->swap ? s->x : s->y;
    /* into the box: the held parameter away from its edge */
    const int dir = s->edge % 2 == 0 ? 1 : -1;
    if (usm_cont_start(pb->c, x, dir) != 0)
        goto done;
    if (pbuf_push(&b, pb, usm_cont_point(pb->c)) != 0) {
        rc = -1;
        goto done;
    }
    for (long steps = 0; steps < e->opt.max_points; ++steps) {
        pb->have_grow = 0;
        const int st = usm_cont_step(pb->c);
        if (st != USM_CONT_STEP && st != USM_CONT_END)
            break;
        const double *xc = usm_cont_point(pb->c);
        if (st == USM_CONT_END) {
            const usm_cont_event *ev =
                usm_cont_event_at(pb->c, usm_cont_event_count(pb->c) - 1);
            int side = -1;
            for (int sd = 0; ev && sd < 4; ++sd)
                if (ev->test == pb->tbox[sd])
                    side = sd;
            double xs[PMAX];
            memcpy(xs, xc, sizeof(double) * (size_t)pb->N);
            end = USM_ENVELOPE_END_BOX;
            if (side >= 0) {
                const int a = side / 2;
                const int col = (a == 0) == !pb->swap ? pb->k : pb->k + 1;
                pb->have_grow = 0;
                if (usm_cont_correct_fixed(pb->c, xs, col, side % 2 == 0 ? e->lo[a] : e->hi[a]) <
                    0)
                    memcpy(xs, xc, sizeof(double) * (size_t)pb->N);
            }
            if (pbuf_push(&b, pb, xs) != 0)
                rc = -1;
            break;
        }
        if (pbuf_push(&b, pb, xc) != 0) {
            rc = -1;
            break;
        }
        if (steps + 1 == e->opt.max_points)
            end = USM_ENVELOPE_END_LIMIT;
    }
    /* lost at a corner of g: the side's seed of this kind ends the curve */
    if (rc == 0 && end == USM_ENVELOPE_END_LOST && b.n > 0) {
        const double *last = b.xy + 2 * (b.n - 1);
        for (size_t i = 0; i < nall; ++i) {
            const pseed *t = &all[i];
            if (t == s || t->kind != s->kind ||
                hypot((t->x - last[0]) / (e->hi[0] - e->lo[0]),
                      (t->y - last[1]) / (e->hi[1] - e->lo[1])) > SNAP_TOL)
                continue;
            if (usm_grow((void **)&b.xy, &b.cap_xy, 2 * (b.n + 1), sizeof(double)) != 0 ||
                usm_grow((void **)&b.u, &b.cap_u, (size_t)m->nx * (b.n + 1), sizeof(double)) != 0) {
                rc = -1;
                goto done;
            }
            b.xy[2 * b.n] = t->x;
            b.xy[2 * b.n + 1] = t->y;
            memcpy(b.u + (size_t)m->nx * b.n, t->x0, sizeof(double) * (size_t)m->nx);
            b.n++;
            end = USM_ENVELOPE_END_BOX;
            break;
        }
    }
    /* lost at its start (the seed at such a corner): another seed's curve */
    if (rc == 0 && end == USM_ENVELOPE_END_LOST && b.n < 2)
        goto done;
    if (rc == 0 && b.n > 0) {
        if (usm_grow((void **)&e->curves, &e->curvecap, e->ncurves + 1, sizeof *e->curves) != 0) {
            rc = -1;
            goto done;
        }
        env_curve *cv = &e->curves[e->ncurves++];
        memset(cv, 0, sizeof *cv);
        cv->xy = b.xy;
        cv->u = b.u;
        b.xy = b.u = NULL;
        cv->pub.kind = (usm_envelope_kind)s->kind;
        cv->pub.npoints = b.n;
        cv->pub.xy = cv->xy;
        cv->pub.u = cv->u;
        cv->pub.nu = m->nx;
        cv->pub.end[0] = USM_ENVELOPE_END_BOX;
        cv->pub.end[1] = end;
    }
done:
    free(b.xy);
    free(b.u);
    usm_cont_free(pb->c);
    pb->c = NULL;
    return rc;
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
            if (trace(e, &pb, &s[i], s, n) != 0) {
                snprintf(e->msg, sizeof e->msg, "out of memory for the curves");
                rc = USM_EFAILED;
            }
        }
    if (rc == USM_OK && e->ncurves == 0 && sweep_msg[0])
        snprintf(e->msg, sizeof e->msg, "%s", sweep_msg);
    free(s);
    usm_periodic_free(pb.w);
    return rc;
}

int env_periodic_classify(usm_envelope *e, usm_envelope_region *r)
{
    usm_periodic *w = usm_periodic_alloc(e->m);
    usm_periodic_options po;
    usm_periodic_result res;
    usm_params q = e->p;
    if (!w) {
        snprintf(e->msg, sizeof e->msg, "out of memory for the orbits");
        return USM_EFAILED;
    }
    *usm_params_field(&q, e->ax[0]) = r->x;
    *usm_params_field(&q, e->ax[1]) = r->y;
    usm_periodic_options_default(&po);
    po.t0 = e->opt.t0;
    r->root = -1;
    r->roots = 0;
    r->cls = USM_POINT_OP_NOT_EVALUATED;
    if (usm_periodic_solve(w, &q, NULL, &po, &res) != USM_OK) {
        snprintf(r->class_name, sizeof r->class_name, "no_orbit");
        snprintf(r->message, sizeof r->message, "%s", usm_periodic_message(w));
    } else {
        r->roots = 1;
        const char *name = res.validity == USM_INVALID_CONTACT_OPEN ? "contact_open"
                           : res.validity == USM_INVALID_STICK     ? "stick_lost"
                           : e->m->friction                        ? "contact_closed"
                                                                   : "stick_admissible";
        snprintf(r->class_name, sizeof r->class_name, "%s", name);
        snprintf(r->message, sizeof r->message,
                 "the periodic orbit: F_n_min %.6g N, friction_needed_max %.6g", res.F_n_min,
                 res.friction_needed_max);
    }
    usm_periodic_free(w);
    return USM_OK;
}
