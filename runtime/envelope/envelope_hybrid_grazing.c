/* Where the orbit with separation's closed phases vanish, continued in two
 * parameters: the curve kind separation_grazing (unilateral models, variant
 * imperfect_unilateral).
 *
 * The orbit lands (a plastic impact) and rests on the stator until F_n
 * falls to 0; as the parameters move, F_n just after the landing falls to 0
 * and the closed phase shrinks to nothing (3-DOF, phase error 0.9135333
 * rad: the two closed phases of the `cococ` orbit, alike by the half-period
 * symmetry, both at once).  Past it the rotor only touches (solve/impact.h:
 * the closed mode would pull) and never rests.
 *
 * Why not the stroboscopic map of the other curves (usm_hybrid_shoot): its
 * section time is fixed and must lie inside a closed phase, and at this
 * boundary there is no closed phase left for it to lie in (its length goes
 * to 0 with F_n after the impact; at 1e-6 rad before the boundary it lasts
 * about 2e-9 s).  No defining function on that map can be regular up to
 * the boundary.  So the section moves with the orbit: it is the impact
 * itself (usm_hybrid_impact_map, solve/hybrid_internal.h), and the map runs
 * from the state just after one impact to the state just after the second
 * impact on (one period of a two-impact orbit).  Unknowns z = (w, ts, a,
 * b): w the non-cyclic state just after the impact (spin coordinates, as
 * envelope_hybrid.c), ts its time, the two parameters (the one held at the
 * seed's edge last).  Equations:
 *   r = x1 - x0 (less 2 pi in phi) on the non-cyclic components (nr)
 *   t1 - ts - T = 0     the second impact a period on
 *   g = F_n(x0, ts)     F_n of the closed mode just after the impact
 * g is the function the landing rule tests, smooth in z on both sides; the
 * map too is smooth to first order across g = 0: the closed phase of length
 * d ~ g / |dF_n/dt| holds the rotor where the open mode would let it move
 * with an acceleration ~ g, a difference O(g^2) in the velocities, and
 * where F_n = 0 the modes' accelerations are equal (no saltation jump).
 * Newton on this system at the 3-DOF boundary: from the orbit at 0.912 rad
 * (g = 0.214 N) to 0.9135333 rad in five iterations, the updates 3.5e-6,
 * 2.6e-8, 5e-10 of the scales, then the map's noise (about 1e-9 rad).
 * The other closed phase's F_n is not watched: a two-impact orbit without
 * the symmetry whose other phase vanishes first is not followed.
 *
 * Jacobian: central differences of maps without the monodromy (2 (nr + 3)
 * maps of a few ms each): the rows include the impact times' dependence,
 * which the monodromy at fixed end time does not carry.
 *
 * Seeds: the edge sweeps' branch_switch events whose branch was lost as
 * its corrector failed ("Newton fails") on an orbit with two closed phases:
 * the last grid orbit of the branch (hybrid_left) is brought to its impact
 * by the impact map; Newton on the extended system with the edge's
 * parameter held gives the curve's first point (the sweep's branch end
 * there is where its corrector failed, as the section left the closed
 * phase: 0.913379 rad before the boundary at 0.9135333, 3-DOF).  The curve
 * is continued into the box and ends at its sides or where the
 * continuation is lost.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/dense.h"
#include "core/grow.h"
#include "envelope_internal.h"
#include "envelope_periodic_problem.h"
#include "solve/hybrid_internal.h"
#include "usm_periodic_sweep.h"

#define GN (USM_MAX_NX + 3)
/* The twist angle's unknown measured at this times its scale
 * (envelope_hybrid.c's TWIST_SCALE) */
#define TWIST_SCALE 100.0
/* Central differences of the map over this (of the unknowns' scales) */
#define FD_STEP 1e-7
/* Newton to the first point: iterations and tolerance (scaled updates) */
#define FIRST_ITER 20
#define FIRST_TOL 1e-10
/* below this the updates are the map's noise where they stop shrinking
 * (measured 5e-10 to 4e-9 of the scales at the 3-DOF boundary) */
#define NOISE_TOL 1e-7
#define H_MAX 0.25
#define H_MIN 1e-7
#define NEWTON_TOL 1e-7
#define BOX_PAD 1e-9
#define SAME_TOL 1e-5
/* Halvings of the distance from the branch's last orbit to its end */
#define APPROACH_STEPS 10

typedef struct gseed {
    int edge;
    double ox, oy;               /* where the start orbit is */
    double vend;                 /* where the sweep's branch ended (its free parameter) */
    double t0, x0[USM_MAX_NX];   /* the start orbit (stroboscopic section) */
} gseed;

struct env_gseeds {
    gseed *s;
    size_t n, cap;
};

typedef struct gprob {
    usm_envelope *e;
    usm_hybrid *h;
    int swap;                    /* 0 z = (w, ts, px, py), 1 z = (w, ts, py, px) */
    int nr, N, idx[USM_MAX_NX];
    double xs[USM_MAX_NX];       /* the cyclic components */
    double scale[GN];
} gprob;

static void g_xy(const gprob *pb, const double *z, double *px, double *py)
{
    *px = pb->swap ? z[pb->nr + 2] : z[pb->nr + 1];
    *py = pb->swap ? z[pb->nr + 1] : z[pb->nr + 2];
}

static int axis_col(const gprob *pb, int a)
{
    return pb->nr + 1 + ((a == 0) == !pb->swap ? 0 : 1);
}

static void state_of(const gprob *pb, const double *z, double *xs)
{
    const usm_model *m = pb->e->m;
    memcpy(xs, pb->xs, sizeof(double) * (size_t)m->nx);
    for (int a = 0; a < pb->nr; ++a)
        xs[pb->idx[a]] = z[a];
    xs[m->x_phidot] -= xs[m->x_psidot];
}

static void unknowns_of(const gprob *pb, const double *xs, double *z)
{
    const usm_model *m = pb->e->m;
    for (int a = 0; a < pb->nr; ++a)
        z[a] = xs[pb->idx[a]] + (pb->idx[a] == m->x_phidot ? xs[m->x_psidot] : 0.0);
}

/* The system's value at z (nr + 2 entries).  0 or -1. */
static int value(gprob *pb, const double *z, double *F)
{
    const usm_model *m = pb->e->m;
    const int n = pb->nr;
    double x0[USM_MAX_NX], x1[USM_MAX_NX], t1, fn, px, py;
    for (int j = 0; j < pb->N; ++j)
        if (!isfinite(z[j]))
            return -1;
    state_of(pb, z, x0);
    usm_params q = pb->e->p;
    g_xy(pb, z, &px, &py);
    *usm_params_field(&q, pb->e->ax[0]) = px;
    *usm_params_field(&q, pb->e->ax[1]) = py;
    if (!(q.f > 0) ||
        usm_hybrid_impact_map(pb->h, &q, z[n], x0, 2, x1, &t1, &fn, NULL) != USM_OK)
        return -1;
    for (int a = 0; a < n; ++a) {
        const int i = pb->idx[a];
        F[a] = x1[i] - x0[i] - (i == m->x_phi ? 6.283185307179586476925286766559 : 0.0) +
               (i == m->x_phidot ? x1[m->x_psidot] - x0[m->x_psidot] : 0.0);
    }
    F[n] = t1 - z[n] - 1.0 / q.f;
    F[n + 1] = fn;
    return 0;
}

static int residual(const double *z, double *F, double *J, void *ctx)
{
    gprob *pb = ctx;
    const int N = pb->N, n = N - 1;
    if (value(pb, z, F) != 0)
        return -1;
    if (!J)
        return 0;
    double zp[GN], Fp[GN], Fm[GN];
    for (int j = 0; j < N; ++j) {
        const double d = FD_STEP * pb->scale[j];
        memcpy(zp, z, sizeof(double) * (size_t)N);
        zp[j] = z[j] + d;
        if (value(pb, zp, Fp) != 0)
            return -1;
        zp[j] = z[j] - d;
        if (value(pb, zp, Fm) != 0)
            return -1;
        for (int a = 0; a < n; ++a)
            J[a * N + j] = (Fp[a] - Fm[a]) / (2 * d);
    }
    return 0;
}

int env_grazing_seed(usm_envelope *e, int edge, const usm_periodic_event *ev)
{
    const int axis = edge < 2 ? 1 : 0;
    const double fixed = edge < 2 ? (edge == 0 ? e->lo[0] : e->hi[0])
                                  : (edge == 2 ? e->lo[1] : e->hi[1]);
    /* a branch lost as its corrector failed, on an orbit with a closed
     * phase besides the section's */
    if (ev->type != USM_PEVENT_BRANCH_SWITCH || !ev->branch_lost ||
        ev->branch_end_how != USM_BRANCH_END_NEWTON || !ev->hybrid_left.converged ||
        ev->hybrid_left.nmodes < 5 || ev->hybrid_left.impacts_per_period != 2 ||
        !isfinite(ev->branch_last) || !isfinite(ev->branch_end))
        return 0;
    if (!e->gseeds && !(e->gseeds = calloc(1, sizeof *e->gseeds)))
        return -1;
    struct env_gseeds *gs = e->gseeds;
    if (usm_grow((void **)&gs->s, &gs->cap, gs->n + 1, sizeof *gs->s) != 0)
        return -1;
    gseed *s = &gs->s[gs->n++];
    memset(s, 0, sizeof *s);
    s->edge = edge;
    s->ox = axis == 0 ? ev->branch_last : fixed;
    s->oy = axis == 0 ? fixed : ev->branch_last;
    s->vend = ev->branch_end;
    s->t0 = ev->hybrid_left.t0;
    memcpy(s->x0, ev->hybrid_left.x0, sizeof(double) * (size_t)e->m->nx);
    return 0;
}

static int on_curve(const usm_envelope *e, double x, double y)
{
    for (size_t c = 0; c < e->ncurves; ++c) {
        const usm_envelope_curve *cv = &e->curves[c].pub;
        if (cv->kind != USM_ENVELOPE_SEPARATION_GRAZING || cv->npoints == 0)
            continue;
        for (size_t i = 0; i < cv->npoints; ++i) {
            const double *p = cv->xy + 2 * i;
            if (fabs(p[0] - x) <= SAME_TOL * (e->hi[0] - e->lo[0]) &&
                fabs(p[1] - y) <= SAME_TOL * (e->hi[1] - e->lo[1]))
                return 1;
        }
    }
    return 0;
}

typedef struct gtest {
    const gprob *pb;
    int side;
} gtest;

static double test_box(const double *z, const double *dz, void *ctx)
{
    (void)dz;
    const gtest *t = ctx;
    double px, py;
    g_xy(t->pb, z, &px, &py);
    return env_box_test(t->pb->e, t->side, px, py, BOX_PAD);
}

static int push(env_xy_buf *b, const gprob *pb, const double *z)
{
    double px, py;
    g_xy(pb, z, &px, &py);
    return env_xy_push(b, px, py);
}

/* Newton on the extended system with the last unknown (the edge's
 * parameter) held: the curve's first point from z.  0 or -1. */
static int first_point(gprob *pb, double *z)
{
    const int N = pb->N, n = N - 1;
    double F[GN], J[GN * GN], A[GN * GN], y[GN];
    int piv[GN];
    double dn_last = INFINITY;
    for (int it = 0; it < FIRST_ITER; ++it) {
        if (residual(z, F, J, pb) != 0) {
            return -1;
        }
        for (int a = 0; a < n; ++a) {
            for (int b = 0; b < n; ++b)
                A[a * n + b] = J[a * N + b] * pb->scale[b];
            y[a] = -F[a];
        }
        if (usm_lu_factor_dense(n, A, piv) != 0)
            return -1;
        usm_lu_solve_dense(n, A, piv, y, 1);
        double dn = 0;
        for (int b = 0; b < n; ++b) {
            z[b] += y[b] * pb->scale[b];
            dn = fmax(dn, fabs(y[b]));
        }
        if (!isfinite(dn))
            return -1;
        /* converged, or at the map's noise (the updates no longer shrink) */
        if (dn < FIRST_TOL || (dn < NOISE_TOL && dn > 0.5 * dn_last))
            return 0;
        dn_last = dn;
    }
    return -1;
}

/* The start orbit brought towards where the sweep's branch ended: solved
 * again (stroboscopic, usm_hybrid_solve_from) at the values halving the
 * distance, each from the last, the last that converges into (t0, x0) at
 * (*ox, *oy).  Newton on the extended system from the branch's last grid
 * orbit, far from the boundary (F_n after the impact 0.55 N at 3-DOF 0.90
 * rad), may find another zero of it (0.8537 rad there); from 0.9125 rad on
 * it converges to the boundary. */
static void approach(gprob *pb, const gseed *s, double *t0, double *x0, double *ox, double *oy)
{
    usm_envelope *e = pb->e;
    const int axis = s->edge < 2 ? 1 : 0;
    const double vo = axis == 0 ? s->ox : s->oy;
    usm_hybrid_result r;
    *t0 = s->t0;
    memcpy(x0, s->x0, sizeof(double) * (size_t)e->m->nx);
    *ox = s->ox;
    *oy = s->oy;
    usm_hybrid_shoot_half(pb->h, 0);
    for (int k = 1; k <= APPROACH_STEPS; ++k) {
        usm_params q = e->p;
        const double val = s->vend + (vo - s->vend) * ldexp(1.0, -k);
        *usm_params_field(&q, e->ax[0]) = axis == 0 ? val : s->ox;
        *usm_params_field(&q, e->ax[1]) = axis == 0 ? s->oy : val;
        if (usm_hybrid_solve_from(pb->h, &q, NULL, *t0, x0, &r) != USM_OK ||
            r.impacts_per_period != 2)
            break;
        memcpy(x0, r.x0, sizeof(double) * (size_t)e->m->nx);
        *(axis == 0 ? ox : oy) = val;
    }
}

/* The curve through seed s, from its edge into the box.  0, or -1 when out
 * of memory. */
static int trace(usm_envelope *e, gprob *pb, const gseed *s)
{
    const usm_model *m = e->m;
    const int axis = s->edge < 2 ? 1 : 0;
    double F[GN], Jx[USM_MAX_NX * USM_MAX_NX], sc[USM_MAX_NX], z0[GN];
    double x1[USM_MAX_NX], t1;
    int rc = 0;
    usm_cont *c = NULL;
    env_xy_buf b = {0};
    double ts, xa[USM_MAX_NX], ox, oy;
    approach(pb, s, &ts, xa, &ox, &oy);
    usm_params q = e->p;
    *usm_params_field(&q, e->ax[0]) = ox;
    *usm_params_field(&q, e->ax[1]) = oy;
    /* the layout and the scales at the start orbit; then its state just
     * after its first impact */
    usm_hybrid_shoot_half(pb->h, 0);
    if (usm_hybrid_shoot(pb->h, &q, ts, xa, pb->idx, &pb->nr, F, Jx, NULL, NULL, sc, NULL) !=
            USM_OK ||
        usm_hybrid_impact_map(pb->h, &q, ts, xa, 1, x1, &t1, NULL, NULL) != USM_OK) {
        return 0;
    }
    memcpy(pb->xs, x1, sizeof(double) * (size_t)m->nx);
    pb->N = pb->nr + 3;
    pb->swap = s->edge < 2 ? 1 : 0;
    for (int a = 0; a < pb->nr; ++a)
        pb->scale[a] = sc[pb->idx[a]] * (pb->idx[a] == m->x_tau ? TWIST_SCALE : 1.0);
    pb->scale[pb->nr] = 1.0 / q.f;
    for (int a = 0; a < 2; ++a)
        pb->scale[axis_col(pb, a)] = e->hi[a] - e->lo[a];
    unknowns_of(pb, x1, z0);
    z0[pb->nr] = t1;
    z0[axis_col(pb, 0)] = ox;
    z0[axis_col(pb, 1)] = oy;
    if (first_point(pb, z0) != 0) {
        return 0;
    }
    {
        double px, py;
        g_xy(pb, z0, &px, &py);
        const double v = axis == 0 ? px : py;
        if (v < e->lo[axis] || v > e->hi[axis] || on_curve(e, px, py))
            return 0;
    }
    usm_cont_options o;
    gtest tests[4];
    int tbox[4];
    if (!(c = usm_cont_alloc(pb->N - 1)))
        return -1;
    usm_cont_options_default(&o);
    o.h0 = 0.5 * e->opt.h_max;
    o.h_max = fmin(H_MAX, 2.5 * e->opt.h_max);
    o.h_min = H_MIN;
    o.newton_max = 8;
    double rel = 1.0;
    for (int a = 0; a < 2; ++a)
        rel = fmax(rel, fmax(fabs(e->lo[a]), fabs(e->hi[a])) / (e->hi[a] - e->lo[a]));
    o.newton_tol = NEWTON_TOL * rel;
    o.event_tol = 1e-10;
    o.across_fold = 1;
    o.max_steps = 20 * e->opt.max_points;
    usm_cont_set_problem(c, residual, pb);
    if (usm_cont_set_options(c, &o) != 0 || usm_cont_set_scale(c, pb->scale) != 0) {
        rc = -1;
        goto done;
    }
    for (int side = 0; side < 4; ++side) {
        tests[side].pb = pb;
        tests[side].side = side;
        if ((tbox[side] = usm_cont_add_test(c, test_box, &tests[side],
                                            USM_CONT_TEST_STOP | USM_CONT_TEST_POINT)) < 0) {
            rc = -1;
            goto done;
        }
    }
    if (usm_cont_start(c, z0, s->edge % 2 == 0 ? 1 : -1) != 0) {
        goto done;
    }
    if (push(&b, pb, usm_cont_point(c)) != 0) {
        rc = -1;
        goto done;
    }
    usm_envelope_end end = USM_ENVELOPE_END_LOST;
    for (long steps = 0; steps < e->opt.max_points; ++steps) {
        const int st = usm_cont_step(c);
        if (st != USM_CONT_STEP && st != USM_CONT_END)
            break;
        double zs[GN];
        memcpy(zs, usm_cont_point(c), sizeof(double) * (size_t)pb->N);
        if (st == USM_CONT_END) {
            const int col[2] = {axis_col(pb, 0), axis_col(pb, 1)};
            if (env_end_on_side(e, c, tbox, col, zs, pb->N))
                end = USM_ENVELOPE_END_BOX;
            if (push(&b, pb, zs) != 0)
                rc = -1;
            break;
        }
        if (push(&b, pb, zs) != 0) {
            rc = -1;
            break;
        }
        if (steps + 1 == e->opt.max_points)
            end = USM_ENVELOPE_END_LIMIT;
    }
    if (rc == 0 && env_keep_xy_curve(e, USM_ENVELOPE_SEPARATION_GRAZING, &b, USM_ENVELOPE_END_BOX, end) != 0)
        rc = -1;
done:
    free(b.xy);
    usm_cont_free(c);
    return rc;
}

int env_grazing_curves(usm_envelope *e, int run)
{
    struct env_gseeds *gs = e->gseeds;
    int rc = USM_OK;
    e->gseeds = NULL;
    if (!gs)
        return USM_OK;
    if (run) {
        gprob pb;
        memset(&pb, 0, sizeof pb);
        pb.e = e;
        if (!(pb.h = usm_hybrid_alloc(e->m)))
            rc = USM_EFAILED;
        e->nseeds += gs->n;
        for (size_t i = 0; i < gs->n && rc == USM_OK; ++i)
            if (trace(e, &pb, &gs->s[i]) != 0)
                rc = USM_EFAILED;
        usm_hybrid_free(pb.h);
        if (rc != USM_OK)
            snprintf(e->msg, sizeof e->msg, "out of memory for the curves");
    }
    free(gs->s);
    free(gs);
    return rc;
}
