/* The folds of the orbits with separation (unilateral models, variant
 * imperfect_unilateral) continued in two parameters: the curve kind
 * separation_fold, where the orbit with separation has a multiplier +1 (the
 * periodic sweep's `fold` of the followed orbit with separation: its
 * stability_change of kind fold, or the fold its branch ends at); and
 * separation_stability, its period doubling (a multiplier -1: the sweep's
 * stability_change of kind period_doubling of it), the same system with A =
 * B + I on the period map.
 *
 * The orbit is a fixed point of the event-driven map from the section time
 * t0 inside a closed phase (usm_hybrid_shoot, solve/hybrid_internal.h: the
 * monodromy with its saltation matrices, in the spin coordinates w, on the
 * non-cyclic components, so that the cyclic directions are deflated by
 * leaving them out).  The curve is the zero set, in z = (w, a, b) (the
 * parameters last, the one held at the seed's edge last of all), of
 *   r(w; a, b) = 0     the map's fixed point (nr equations)
 *   g(w; a, b) = 0     the minimally augmented fold function of A:
 *                      [As b_; c_' 0] [v; g] = [0; 1]
 * As = D^-1 A D (D the unknowns' scales) and b_, c_ the left and right null
 * vectors of As at the last point (refreshed every step; the zero set does
 * not depend on them).  The real multiplier nearest 1 minus 1 would do as
 * g only where that multiplier stays apart from the others and real: g is
 * smooth in z wherever A has a simple zero eigenvalue, and needs no
 * eigensolver.
 *
 * Which map, and A: an orbit with the half-period symmetry (x(t + T/2) =
 * x(t) on the non-cyclic components: the imperfections force at 2 Omega,
 * and the `cococ` orbits open alike at both F_n minima) is a fixed point of
 * the half map (usm_hybrid_shoot_half), whose multipliers mu are the square
 * roots of the period map's.  A multiplier +1 of the period map is then
 * mu = +1 (A = B_h - I: a fold, the branch turns back) or mu = -1 (A = B_h +
 * I: the symmetry breaks, the branch goes on through it unstable, as at the
 * 4-DOF motor's phase error 0.591655 rad).  At the latter the period map's
 * r has a rank one short (its parameter columns lie in the range of B - I),
 * so its fold system is singular along the whole curve; the half map's is
 * regular.  An orbit without the symmetry uses the period map, A = B - I.
 *
 * Jacobian: r's rows are the monodromy's (less I) and central differences
 * of two maps without the monodromy in each parameter; g's row is
 *   dg/dz_j = -w' D^-1 (dA/dz_j) D v,
 * the second derivative r_zz[Dv, e_j] by one difference of the monodromy
 * along the null vector for all the state's columns at once, and one
 * difference of it in each parameter: four maps with the monodromy a
 * Jacobian, not nr + 2.  Its accuracy sets Newton's rate only: the points
 * solve the system to the corrector's tolerance.  So the corrector is chord
 * Newton after the start, and all but the monodromy's block is reused
 * within JAC_REUSE of where it was computed, until the borders change.
 *
 * Seeds: the edge sweeps' (envelope_periodic.c) stability_change events of
 * kind fold of an orbit with separation (the located orbit is the start)
 * and their branch_switch events whose branch ended at a fold (the branch's
 * last grid orbit, solved again on the way to the fold's located value,
 * halving the distance each time, is the start).  Newton on the extended
 * system with the edge's parameter held gives the curve's first point; the
 * curve is continued into the box and ends at its sides (the end put onto
 * the side), where the mode sequence changes (`lost`: a grazing, where the
 * map is not smooth), or where the continuation is lost.
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

#define HN (USM_MAX_NX + 2)
/* r's parameter columns: central differences of this (of the box's side) */
#define FD_PARAM 1e-5
/* g's row: differences of the monodromy over this (scaled) */
#define FD_G 1e-4
/* The twist angle's unknown measured at this times its scale: its
 * corrector updates stall above the others' (the sweep's TWIST_SCALE) */
#define TWIST_SCALE 100.0
/* The orbit has the half-period symmetry where the half map's residual is
 * below this (of the scales): its orbit is good to 1e-7 or better */
#define SYM_TOL 1e-5
/* The longest step (the box's sides 1) */
#define H_MAX 0.25
/* The corrector's tolerance (scaled; the box's sides 1): the map's noise
 * near a multiplier +1 leaves the updates at ~1e-9, where a tolerance of
 * 1e-9 halved the steps to h_min (the sweep's corrector stops at 1e-8 too) */
#define NEWTON_TOL 1e-8
#define H_MIN 1e-7
#define BOX_PAD 1e-9
/* A seed within this (box's sides 1) of a traced curve's end lies on it */
#define SAME_TOL 1e-5
/* The Jacobian's costly part (r's parameter columns and g's row: three
 * maps with the monodromy and four without) is reused within this (scaled,
 * max norm) of where it was computed, the monodromy's block always fresh:
 * after the start the corrector is chord Newton (one Jacobian a step, at
 * the predicted point) and the tangent at the step's end and the location
 * of the box's side take that one.  In the start (Newton from the seed's
 * orbit) within JAC_REUSE_START only: its last iterations.  Its accuracy
 * sets the corrector's rate only. */
#define JAC_REUSE 0.05
#define JAC_REUSE_START 1e-4
/* Halvings of the distance from a branch's last orbit to its fold */
#define APPROACH_STEPS 10

typedef struct hseed {
    int kind;                    /* separation_fold or separation_stability */
    int edge;                    /* 0 x = lo, 1 x = hi, 2 y = lo, 3 y = hi */
    double x, y;                 /* the fold's located value on the edge */
    double ox, oy;               /* where the start orbit is */
    double t0, x0[USM_MAX_NX];   /* the start orbit (section time, state) */
} hseed;

struct env_hseeds {
    hseed *s;
    size_t n, cap;
};

typedef struct hprob {
    usm_envelope *e;
    usm_hybrid *h;
    int half;                    /* the half map */
    double shift;                /* A = (B - I) + shift I: 0 (mu = +1) or 2 (mu = -1) */
    int swap;                    /* 0 z = (w, px, py), 1 z = (w, py, px) */
    int nr, N, idx[USM_MAX_NX];
    double t0, xs[USM_MAX_NX];   /* section time; the cyclic components */
    double scale[HN];
    double bb[USM_MAX_NX], cc[USM_MAX_NX];
    char seq[USM_HYBRID_MAX_SWITCHES + 1], seqc[USM_HYBRID_MAX_SWITCHES + 1];
    usm_cont *c;
    /* r's parameter columns and g's row of the last Jacobian, at jac_z
     * (have_jac; dropped with the borders) */
    double jac_z[HN], jac[(USM_MAX_NX + 1) * HN];
    int have_jac;
    double reuse_tol;
} hprob;

static void h_xy(const hprob *pb, const double *z, double *px, double *py)
{
    *px = pb->swap ? z[pb->nr + 1] : z[pb->nr];
    *py = pb->swap ? z[pb->nr] : z[pb->nr + 1];
}

static int axis_col(const hprob *pb, int a) { return pb->nr + ((a == 0) == !pb->swap ? 0 : 1); }

/* The state of the unknowns (spin coordinates: w[phidot] = phidot + psidot). */
static void state_of(const hprob *pb, const double *z, double *xs)
{
    const usm_model *m = pb->e->m;
    memcpy(xs, pb->xs, sizeof(double) * (size_t)m->nx);
    for (int a = 0; a < pb->nr; ++a)
        xs[pb->idx[a]] = z[a];
    xs[m->x_phidot] -= xs[m->x_psidot];
}

static void unknowns_of(const hprob *pb, const double *xs, double *z)
{
    const usm_model *m = pb->e->m;
    for (int a = 0; a < pb->nr; ++a)
        z[a] = xs[pb->idx[a]] + (pb->idx[a] == m->x_phidot ? xs[m->x_psidot] : 0.0);
}

static usm_params params_of(const hprob *pb, const double *z)
{
    usm_params q = pb->e->p;
    double px, py;
    h_xy(pb, z, &px, &py);
    *usm_params_field(&q, pb->e->ax[0]) = px;
    *usm_params_field(&q, pb->e->ax[1]) = py;
    return q;
}

/* The map at z: F (nr) and, with J, B - I (nr x nr), both in the spin
 * coordinates (usm_hybrid_shoot's rows are x's: the row of phidot becomes
 * that of the spin phidot + psidot, so that J is T (B - I) T^-1 and J +
 * shift I is A, and the rows' scales are the columns').  0 or -1. */
static int shoot(hprob *pb, const double *z, double *F, double *J)
{
    const usm_model *m = pb->e->m;
    const int n = pb->nr;
    double xs[USM_MAX_NX];
    for (int j = 0; j < pb->N; ++j)
        if (!isfinite(z[j]))
            return -1;
    state_of(pb, z, xs);
    const usm_params q = params_of(pb, z);
    if (usm_hybrid_shoot(pb->h, &q, pb->t0, xs, NULL, NULL, F, J, NULL, NULL, NULL,
                         pb->seqc) != USM_OK)
        return -1;
    int ap = -1, as = -1;
    for (int a = 0; a < n; ++a) {
        ap = pb->idx[a] == m->x_phidot ? a : ap;
        as = pb->idx[a] == m->x_psidot ? a : as;
    }
    if (ap >= 0 && as >= 0) {
        F[ap] += F[as];
        for (int b = 0; J && b < n; ++b)
            J[ap * n + b] += J[as * n + b];
    }
    return 0;
}

/* As = D^-1 (J + shift I) D into As (nr x nr). */
static void scaled_A(const hprob *pb, const double *J, double *As)
{
    const int n = pb->nr;
    for (int a = 0; a < n; ++a)
        for (int b = 0; b < n; ++b)
            As[a * n + b] = (J[a * n + b] + (a == b ? pb->shift : 0.0)) * pb->scale[b] /
                            pb->scale[a];
}

/* The bordered systems at As: g, the right null vector v and the left w
 * (scaled; v and w may be NULL).  0 or -1. */
static int bordered(const hprob *pb, const double *As, double *g, double *v, double *w)
{
    const int n = pb->nr, m = n + 1;
    double M[(USM_MAX_NX + 1) * (USM_MAX_NX + 1)], Mt[(USM_MAX_NX + 1) * (USM_MAX_NX + 1)];
    double y[USM_MAX_NX + 1] = {0};
    int piv[USM_MAX_NX + 1];
    for (int a = 0; a < m; ++a)
        for (int b = 0; b < m; ++b) {
            const double val = a < n && b < n ? As[a * n + b]
                               : a < n && b == n ? pb->bb[a]
                               : a == n && b < n ? pb->cc[b]
                                                 : 0.0;
            M[a * m + b] = val;
            Mt[b * m + a] = val;
        }
    if (usm_lu_factor_dense(m, M, piv) != 0)
        return -1;
    y[n] = 1.0;
    usm_lu_solve_dense(m, M, piv, y, 1);
    *g = y[n];
    if (v)
        memcpy(v, y, sizeof(double) * (size_t)n);
    if (w) {
        if (usm_lu_factor_dense(m, Mt, piv) != 0)
            return -1;
        memset(y, 0, sizeof y);
        y[n] = 1.0;
        usm_lu_solve_dense(m, Mt, piv, y, 1);
        memcpy(w, y, sizeof(double) * (size_t)n);
    }
    return isfinite(*g) ? 0 : -1;
}

static int residual(const double *z, double *F, double *J, void *ctx)
{
    hprob *pb = ctx;
    const int n = pb->nr, N = pb->N;
    double Jx[USM_MAX_NX * USM_MAX_NX], As[USM_MAX_NX * USM_MAX_NX], v[USM_MAX_NX],
        w[USM_MAX_NX], g;
    if (shoot(pb, z, F, Jx) != 0)
        return -1;
    scaled_A(pb, Jx, As);
    if (bordered(pb, As, &g, v, J ? w : NULL) != 0)
        return -1;
    F[n] = g;
    if (!J)
        return 0;
    if (pb->have_jac) {
        double d = 0;
        for (int j = 0; j < N; ++j)
            d = fmax(d, fabs(z[j] - pb->jac_z[j]) / pb->scale[j]);
        if (d <= pb->reuse_tol) {
            for (int a = 0; a <= n; ++a)
                for (int j = 0; j < N; ++j)
                    J[a * N + j] = a < n && j < n ? Jx[a * n + j] : pb->jac[a * N + j];
            return 0;
        }
    }
    double zp[HN], Fp[USM_MAX_NX], Fm[USM_MAX_NX], Jp[USM_MAX_NX * USM_MAX_NX], u[USM_MAX_NX];
    /* r's parameter columns, and g's by the monodromy there */
    for (int j = n; j < N; ++j) {
        const double d = FD_PARAM * pb->scale[j];
        memcpy(zp, z, sizeof(double) * (size_t)N);
        zp[j] = z[j] + d;
        if (shoot(pb, zp, Fp, NULL) != 0)
            return -1;
        zp[j] = z[j] - d;
        if (shoot(pb, zp, Fm, NULL) != 0)
            return -1;
        for (int a = 0; a < n; ++a)
            J[a * N + j] = (Fp[a] - Fm[a]) / (2 * d);
        const double dq = FD_G * pb->scale[j];
        zp[j] = z[j] + dq;
        if (shoot(pb, zp, Fp, Jp) != 0)
            return -1;
        double s = 0;
        for (int a = 0; a < n; ++a) {
            double t = 0;
            for (int b = 0; b < n; ++b)
                t += (Jp[a * n + b] - Jx[a * n + b]) * v[b] * pb->scale[b];
            s += w[a] / pb->scale[a] * t;
        }
        J[n * N + j] = -s / dq;
    }
    for (int a = 0; a < n; ++a)
        for (int b = 0; b < n; ++b)
            J[a * N + b] = Jx[a * n + b];
    /* g's state columns at once: the monodromy's difference along D v */
    for (int b = 0; b < n; ++b)
        u[b] = v[b] * pb->scale[b];
    double vn = 0;
    for (int b = 0; b < n; ++b)
        vn = fmax(vn, fabs(v[b]));
    if (!(vn > 0))
        return -1;
    const double eps = FD_G / vn;
    memcpy(zp, z, sizeof(double) * (size_t)N);
    for (int b = 0; b < n; ++b)
        zp[b] += eps * u[b];
    if (shoot(pb, zp, Fp, Jp) != 0)
        return -1;
    for (int b = 0; b < n; ++b) {
        double s = 0;
        for (int a = 0; a < n; ++a)
            s += w[a] / pb->scale[a] * (Jp[a * n + b] - Jx[a * n + b]);
        J[n * N + b] = -s / eps;
    }
    memcpy(pb->jac, J, sizeof(double) * (size_t)((n + 1) * N));
    memcpy(pb->jac_z, z, sizeof(double) * (size_t)N);
    pb->have_jac = 1;
    return 0;
}

/* The borders refreshed to the null vectors at z (normalised); from
 * inverse iteration on As when init.  0 or -1. */
static int refresh_borders(hprob *pb, const double *z, int init)
{
    const int n = pb->nr;
    double F[USM_MAX_NX], Jx[USM_MAX_NX * USM_MAX_NX], As[USM_MAX_NX * USM_MAX_NX];
    double v[USM_MAX_NX], w[USM_MAX_NX], g;
    if (shoot(pb, z, F, Jx) != 0)
        return -1;
    scaled_A(pb, Jx, As);
    if (init) {
        double LU[USM_MAX_NX * USM_MAX_NX], LUt[USM_MAX_NX * USM_MAX_NX];
        int piv[USM_MAX_NX], pivt[USM_MAX_NX];
        for (int a = 0; a < n; ++a)
            for (int b = 0; b < n; ++b)
                LUt[b * n + a] = LU[a * n + b] = As[a * n + b];
        if (usm_lu_factor_dense(n, LU, piv) != 0 || usm_lu_factor_dense(n, LUt, pivt) != 0)
            return -1;
        for (int a = 0; a < n; ++a)
            v[a] = w[a] = 1.0;
        for (int it = 0; it < 4; ++it) {
            double nv = 0, nw = 0;
            usm_lu_solve_dense(n, LU, piv, v, 1);
            usm_lu_solve_dense(n, LUt, pivt, w, 1);
            for (int a = 0; a < n; ++a) {
                nv += v[a] * v[a];
                nw += w[a] * w[a];
            }
            if (!(nv > 0) || !(nw > 0) || !isfinite(nv) || !isfinite(nw))
                return -1;
            for (int a = 0; a < n; ++a) {
                v[a] /= sqrt(nv);
                w[a] /= sqrt(nw);
            }
        }
    } else if (bordered(pb, As, &g, v, w) != 0)
        return -1;
    double nv = 0, nw = 0;
    for (int a = 0; a < n; ++a) {
        nv += v[a] * v[a];
        nw += w[a] * w[a];
    }
    if (!(nv > 0) || !(nw > 0))
        return -1;
    for (int a = 0; a < n; ++a) {
        pb->cc[a] = v[a] / sqrt(nv);
        pb->bb[a] = w[a] / sqrt(nw);
    }
    /* g is another function with other borders */
    pb->have_jac = 0;
    return 0;
}

/* The smallest singular value of As + s I (s as shift), estimated by
 * inverse iteration: which multiplier (+1 or -1 of the half map) is the
 * critical one.  Infinity when it fails. */
static double sigma_min(const hprob *pb, const double *J, double shift)
{
    hprob t = *pb;
    const int n = pb->nr;
    double As[USM_MAX_NX * USM_MAX_NX], y[USM_MAX_NX];
    int piv[USM_MAX_NX];
    t.shift = shift;
    scaled_A(&t, J, As);
    if (usm_lu_factor_dense(n, As, piv) != 0)
        return 0.0;
    for (int a = 0; a < n; ++a)
        y[a] = 1.0 / sqrt((double)n);
    double growth = 0;
    for (int it = 0; it < 4; ++it) {
        usm_lu_solve_dense(n, As, piv, y, 1);
        double ny = 0;
        for (int a = 0; a < n; ++a)
            ny += y[a] * y[a];
        ny = sqrt(ny);
        if (!(ny > 0) || !isfinite(ny))
            return INFINITY;
        growth = ny;
        for (int a = 0; a < n; ++a)
            y[a] /= ny;
    }
    return 1.0 / growth;
}

int env_hybrid_seed(usm_envelope *e, int edge, const usm_periodic_event *ev)
{
    const int axis = edge < 2 ? 1 : 0; /* the edge x = const runs along y */
    const double fixed = edge < 2 ? (edge == 0 ? e->lo[0] : e->hi[0])
                                  : (edge == 2 ? e->lo[1] : e->hi[1]);
    double v, vo;
    const usm_hybrid_result *r;
    int kind = USM_ENVELOPE_SEPARATION_FOLD;
    if (env_grazing_seed(e, edge, ev) != 0)
        return -1;
    if (!ev->has_hybrid)
        return 0;
    if (ev->type == USM_PEVENT_STABILITY_CHANGE && ev->kind == USM_CROSSING_FOLD) {
        v = vo = ev->value;
        r = &ev->hybrid;
    } else if (ev->type == USM_PEVENT_STABILITY_CHANGE &&
               ev->kind == USM_CROSSING_PERIOD_DOUBLING && e->opt.stability) {
        v = vo = ev->value;
        r = &ev->hybrid;
        kind = USM_ENVELOPE_SEPARATION_STABILITY;
    } else if (ev->type == USM_PEVENT_BRANCH_SWITCH && ev->branch_lost &&
               ev->branch_end_how == USM_BRANCH_END_FOLD && isfinite(ev->branch_end)) {
        v = ev->branch_end;
        vo = ev->branch_last;
        r = &ev->hybrid_left;
    } else
        return 0;
    if (!r->converged || !isfinite(v) || !isfinite(vo))
        return 0;
    if (!e->hseeds && !(e->hseeds = calloc(1, sizeof *e->hseeds)))
        return -1;
    struct env_hseeds *hs = e->hseeds;
    if (usm_grow((void **)&hs->s, &hs->cap, hs->n + 1, sizeof *hs->s) != 0)
        return -1;
    hseed *s = &hs->s[hs->n++];
    memset(s, 0, sizeof *s);
    s->kind = kind;
    s->edge = edge;
    s->x = axis == 0 ? v : fixed;
    s->y = axis == 0 ? fixed : v;
    s->ox = axis == 0 ? vo : fixed;
    s->oy = axis == 0 ? fixed : vo;
    s->t0 = r->t0;
    memcpy(s->x0, r->x0, sizeof(double) * (size_t)e->m->nx);
    return 0;
}

static int on_curve(const usm_envelope *e, const hseed *s)
{
    for (size_t c = 0; c < e->ncurves; ++c) {
        const usm_envelope_curve *cv = &e->curves[c].pub;
        if ((int)cv->kind != s->kind || cv->npoints == 0)
            continue;
        for (size_t i = 0; i < cv->npoints; i += cv->npoints - 1 > 0 ? cv->npoints - 1 : 1) {
            const double *p = cv->xy + 2 * i;
            if (fabs(p[0] - s->x) <= SAME_TOL * (e->hi[0] - e->lo[0]) &&
                fabs(p[1] - s->y) <= SAME_TOL * (e->hi[1] - e->lo[1]))
                return 1;
        }
    }
    return 0;
}

typedef struct htest {
    const hprob *pb;
    int side;
} htest;

static double test_box(const double *z, const double *dz, void *ctx)
{
    (void)dz;
    const htest *t = ctx;
    double px, py;
    h_xy(t->pb, z, &px, &py);
    return env_box_test(t->pb->e, t->side, px, py, BOX_PAD);
}

static int push(env_xy_buf *b, const hprob *pb, const double *z)
{
    double px, py;
    h_xy(pb, z, &px, &py);
    return env_xy_push(b, px, py);
}

/* The start orbit of seed s (at (ox, oy)) brought to the fold's value: from
 * the branch's last orbit, solved again at the values halving the distance
 * to the fold (each from the last), the last that converges.  Its state
 * into x0 and its value of the free parameter into *v.  0 or -1. */
static int approach(hprob *pb, const hseed *s, double *x0, double *v)
{
    usm_envelope *e = pb->e;
    const int axis = s->edge < 2 ? 1 : 0;
    const double vf = axis == 0 ? s->x : s->y, vo = axis == 0 ? s->ox : s->oy;
    usm_hybrid_result r;
    memcpy(x0, s->x0, sizeof(double) * (size_t)e->m->nx);
    *v = vo;
    if (vf == vo)
        return 0;
    usm_hybrid_shoot_half(pb->h, 0);
    for (int k = 1; k <= APPROACH_STEPS; ++k) {
        usm_params q = e->p;
        const double val = vf + (vo - vf) * ldexp(1.0, -k);
        *usm_params_field(&q, e->ax[0]) = axis == 0 ? val : s->x;
        *usm_params_field(&q, e->ax[1]) = axis == 0 ? s->y : val;
        if (usm_hybrid_solve_from(pb->h, &q, NULL, s->t0, x0, &r) != USM_OK || r.nmodes < 2)
            break;
        memcpy(x0, r.x0, sizeof(double) * (size_t)e->m->nx);
        *v = val;
    }
    return 0;
}

/* The curve through seed s, from its edge into the box.  0, or -1 when out
 * of memory. */
static int trace(usm_envelope *e, hprob *pb, const hseed *s)
{
    const usm_model *m = e->m;
    const int axis = s->edge < 2 ? 1 : 0;
    double x0[USM_MAX_NX], vfree, F[USM_MAX_NX + 1], J[USM_MAX_NX * USM_MAX_NX];
    double sc[USM_MAX_NX], z0[HN];
    int rc = 0;
    env_xy_buf b = {0};
    pb->have_jac = 0;
    memset(pb->bb, 0, sizeof pb->bb);
    memset(pb->cc, 0, sizeof pb->cc);
    pb->t0 = s->t0;
    approach(pb, s, x0, &vfree);
    memcpy(pb->xs, x0, sizeof(double) * (size_t)m->nx);
    /* the layout and the scales of the spin coordinates at the start */
    pb->swap = s->edge < 2 ? 1 : 0;
    usm_params q = e->p;
    *usm_params_field(&q, e->ax[axis]) = vfree;
    *usm_params_field(&q, e->ax[1 - axis]) = axis == 0 ? s->y : s->x;
    usm_hybrid_shoot_half(pb->h, 0);
    if (usm_hybrid_shoot(pb->h, &q, pb->t0, x0, pb->idx, &pb->nr, F, J, NULL, NULL, sc,
                         pb->seq) != USM_OK)
        return 0;
    pb->N = pb->nr + 2;
    for (int a = 0; a < pb->nr; ++a)
        pb->scale[a] = sc[pb->idx[a]] * (pb->idx[a] == m->x_tau ? TWIST_SCALE : 1.0);
    for (int a = 0; a < 2; ++a)
        pb->scale[axis_col(pb, a)] = e->hi[a] - e->lo[a];
    unknowns_of(pb, x0, z0);
    z0[axis_col(pb, axis)] = vfree;
    z0[axis_col(pb, 1 - axis)] = axis == 0 ? s->y : s->x;
    /* the half map where the orbit has the symmetry; then the multiplier
     * nearer the unit circle's +1 or -1 */
    double Fh[USM_MAX_NX], res = 0;
    usm_hybrid_shoot_half(pb->h, 1);
    const int okh = shoot(pb, z0, Fh, J) == 0;
    for (int a = 0; okh && a < pb->nr; ++a)
        res = fmax(res, fabs(Fh[a]) / pb->scale[a]);
    /* a multiplier -1 of the period map: A = B + I on it (r is regular there,
     * B - I invertible; on the half map it would be a pair +-i) */
    pb->half = okh && res <= SYM_TOL && s->kind == USM_ENVELOPE_SEPARATION_FOLD;
    pb->shift = s->kind == USM_ENVELOPE_SEPARATION_STABILITY ? 2.0 : 0.0;
    if (pb->half)
        pb->shift = sigma_min(pb, J, 2.0) < sigma_min(pb, J, 0.0) ? 2.0 : 0.0;
    else
        usm_hybrid_shoot_half(pb->h, 0);
    if (pb->half)
        memcpy(pb->seq, pb->seqc, sizeof pb->seq);
    if (refresh_borders(pb, z0, 1) != 0)
        return 0;
    usm_cont_options o;
    htest tests[4];
    if (!(pb->c = usm_cont_alloc(pb->N - 1)))
        return -1;
    usm_cont_options_default(&o);
    o.h0 = 0.5 * e->opt.h_max;
    /* the envelope's longest step (default 0.02) as the other periodic
     * curves take it, 2.5 times: the curves of orbits are smooth and each
     * point costs some 16 maps with the monodromy */
    o.h_max = fmin(H_MAX, 2.5 * e->opt.h_max);
    o.h_min = H_MIN;
    o.newton_max = 8;
    /* relative to the parameters' size where the box is small against them
     * (envelope_periodic.c's stick_loss alike): the map's noise near the
     * multiplier leaves ~1e-10 of the mode split (1.95 %) in the updates, and
     * at 1e-8 of a side of 0.015 % the steps shrank to h_min */
    double rel = 1.0;
    for (int a = 0; a < 2; ++a)
        rel = fmax(rel, fmax(fabs(e->lo[a]), fabs(e->hi[a])) / (e->hi[a] - e->lo[a]));
    o.newton_tol = NEWTON_TOL * rel;
    o.event_tol = 1e-10;
    o.across_fold = 1;
    o.max_steps = 20 * e->opt.max_points;
    usm_cont_set_problem(pb->c, residual, pb);
    if (usm_cont_set_options(pb->c, &o) != 0 || usm_cont_set_scale(pb->c, pb->scale) != 0) {
        rc = -1;
        goto done;
    }
    int tbox[4];
    for (int side = 0; side < 4; ++side) {
        tests[side].pb = pb;
        tests[side].side = side;
        if ((tbox[side] = usm_cont_add_test(pb->c, test_box, &tests[side],
                                            USM_CONT_TEST_STOP | USM_CONT_TEST_POINT)) < 0) {
            rc = -1;
            goto done;
        }
    }
    /* into the box: the held parameter away from its edge */
    pb->reuse_tol = JAC_REUSE_START;
    if (usm_cont_start(pb->c, z0, s->edge % 2 == 0 ? 1 : -1) != 0)
        goto done;
    pb->reuse_tol = JAC_REUSE;
    o.chord = 1;
    if (usm_cont_set_options(pb->c, &o) != 0) {
        rc = -1;
        goto done;
    }
    if (push(&b, pb, usm_cont_point(pb->c)) != 0) {
        rc = -1;
        goto done;
    }
    usm_envelope_end end = USM_ENVELOPE_END_LOST;
    for (long steps = 0; steps < e->opt.max_points; ++steps) {
        const int st = usm_cont_step(pb->c);
        if (st != USM_CONT_STEP && st != USM_CONT_END)
            break;
        double zs[HN];
        memcpy(zs, usm_cont_point(pb->c), sizeof(double) * (size_t)pb->N);
        /* a change of the mode sequence: the map is not smooth past it */
        if (shoot(pb, zs, F, NULL) != 0 || strcmp(pb->seqc, pb->seq) != 0)
            break;
        if (st == USM_CONT_END) {
            const int col[2] = {axis_col(pb, 0), axis_col(pb, 1)};
            if (env_end_on_side(e, pb->c, tbox, col, zs, pb->N))
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
        /* the borders at the new point: the next step's g */
        if (refresh_borders(pb, zs, 0) != 0)
            break;
    }
    if (rc == 0 && env_keep_xy_curve(e, s->kind, &b, USM_ENVELOPE_END_BOX, end) != 0)
        rc = -1;
done:
    free(b.xy);
    usm_cont_free(pb->c);
    pb->c = NULL;
    usm_hybrid_shoot_half(pb->h, 0);
    return rc;
}

int env_hybrid_curves(usm_envelope *e, int run)
{
    struct env_hseeds *hs = e->hseeds;
    int rc = env_grazing_curves(e, run);
    e->hseeds = NULL;
    if (!hs)
        return rc;
    if (run) {
        hprob pb;
        memset(&pb, 0, sizeof pb);
        pb.e = e;
        if (!(pb.h = usm_hybrid_alloc(e->m)))
            rc = USM_EFAILED;
        e->nseeds += hs->n;
        for (size_t i = 0; i < hs->n && rc == USM_OK; ++i) {
            if (on_curve(e, &hs->s[i])) {
                e->seeds_dropped++;
                continue;
            }
            if (trace(e, &pb, &hs->s[i]) != 0)
                rc = USM_EFAILED;
        }
        usm_hybrid_free(pb.h);
        if (rc != USM_OK)
            snprintf(e->msg, sizeof e->msg, "out of memory for the curves");
    }
    free(hs->s);
    free(hs);
    return rc;
}
