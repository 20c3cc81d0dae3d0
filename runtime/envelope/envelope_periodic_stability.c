/* The imperfect motor's stability curve: where its periodic orbit's largest
 * non-trivial Floquet multiplier crosses the unit circle, continued in two
 * parameters (the kind `stability`, named as the sweep's stability_change
 * events; usm_envelope.h).
 *
 * The curve is the zero set of k + 1 equations in k + 2 unknowns
 * z = (x0, a, b):
 *   r(x0; px, py) = 0   periodicity in the k non-cyclic components of the
 *                       state x0 at the envelope's t0 (usm_periodic_shoot,
 *                       solve/periodic_internal.h; scaled as the shooting's)
 *   g = max |lambda| - 1 over the non-cyclic multipliers of that orbit's
 *                       monodromy (usm_periodic_shoot_max_modulus), the
 *                       function whose zero the one-parameter sweep locates
 *                       as its stability_change
 * r's rows: the monodromy's block and forward differences in a and b, as
 * contact_loss's (envelope_periodic.c).  g's row by forward differences, a
 * shot each (the multipliers' derivatives would need the second variation),
 * formed once a step and kept for the corrector's iterations there.  The
 * modulus of a simple complex pair is smooth in z, so where the critical
 * multiplier is a pair (Neimark-Sacker) the curve is a smooth curve; the
 * angle is not an unknown: it is read off the pair at each point, and its
 * frequency (usm_squeal_frequency of the orbit's frequency, as the sweep's
 * event's squeal frequency) is the curve's per-point value.
 *
 * Seeds: the stability_change events other than a fold (a real multiplier
 * +1 is the branch's turning point, which the sweep ends at) of the
 * periodic sweeps along the box's four edges (envelope_periodic.c runs them
 * for all the imperfect kinds); each curve is continued from its edge, that
 * edge's parameter held at the start, until it leaves the box, where its end
 * is put onto the side.  A seed of the other side on the curve is dropped.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/grow.h"
#include "envelope_internal.h"
#include "solve/periodic_internal.h"

#define SMAX (USM_MAX_NX + 2)
/* r's forward differences in the parameters, of the box's side (the
 * sweep's, DLAM: above the residual's noise floor over it). */
#define FD_REL 1e-5
/* g's forward differences: the first step G_FD_REL of each unknown's
 * scale, cut by G_FD_SHRINK until g moves by at most G_FD_MOVE over it,
 * and kept for the curve's later steps.  g's noise is ~3e-10 (measured at
 * 2.5 % mode split, F0 1 N); in most unknowns g is linear over 1e-4 of the
 * scale, in the twist rates (psidot, phidot) only below 1e-7 (g moves by
 * 6e3 per scale there, and its difference over 1e-4 has the wrong sign). */
#define G_FD_REL 1e-4
#define G_FD_MOVE 1e-4
#define G_FD_SHRINK 1e-2
#define G_FD_TRIES 3
/* The corrector's tolerance on its update (scaled), of the parameters'
 * values rather than the box's sides: g's noise over its rate (~1.5 per N
 * in F0) is ~2e-10 of F0, which in a box 2e-3 N high is 1e-7 of its side. */
#define NEWTON_TOL 1e-9
/* Longest step (the box's sides 1): the curve is nearly straight. */
#define H_MAX 0.25
#define H_MIN 1e-7
#define BOX_PAD 1e-9

typedef struct sprob {
    usm_envelope *e;
    usm_periodic *w;
    int swap;                 /* 0 z = (x0, px, py), 1 z = (x0, py, px) */
    int k, N;
    int idx[USM_MAX_NX];
    double xfull[USM_MAX_NX]; /* the cyclic components (a gauge) */
    double scale[SMAX];
    double grow[SMAX];
    double gstep[SMAX];       /* g's difference steps, kept along the curve */
    int have_grow;
    int tbox[4];
    usm_cont *c;
} sprob;

static void s_xy(const sprob *pb, const double *z, double *px, double *py)
{
    *px = pb->swap ? z[pb->k + 1] : z[pb->k];
    *py = pb->swap ? z[pb->k] : z[pb->k + 1];
}

static void s_unpack(const sprob *pb, const double *z, double *x0, usm_params *q)
{
    double px, py;
    memcpy(x0, pb->xfull, sizeof(double) * (size_t)pb->e->m->nx);
    for (int a = 0; a < pb->k; ++a)
        x0[pb->idx[a]] = z[a];
    s_xy(pb, z, &px, &py);
    *q = pb->e->p;
    *usm_params_field(q, pb->e->ax[0]) = px;
    *usm_params_field(q, pb->e->ax[1]) = py;
}

/* The column of axis a (0 x, 1 y). */
static int s_axis_col(const sprob *pb, int a) { return pb->k + ((a == 0) == !pb->swap ? 0 : 1); }

/* g at z after a shot there (its samples and monodromy kept in w). */
static double g_at(sprob *pb, const double *z)
{
    double x0[USM_MAX_NX], r[USM_MAX_NX];
    usm_params q;
    s_unpack(pb, z, x0, &q);
    if (usm_periodic_shoot(pb->w, &q, NULL, 0.0, x0, r, NULL) != USM_OK)
        return NAN;
    return usm_periodic_shoot_max_modulus(pb->w) - 1.0;
}

static int s_residual(const double *z, double *F, double *J, void *ctx)
{
    sprob *pb = ctx;
    const int k = pb->k, N = pb->N, ja = k, jb = k + 1;
    double x0[USM_MAX_NX], rb[USM_MAX_NX], Jk[USM_MAX_NX * (USM_MAX_NX + 1)];
    usm_params q;
    for (int j = 0; j < N; ++j)
        if (!isfinite(z[j]))
            return -1;
    s_unpack(pb, z, x0, &q);
    const usm_param_info *pa = pb->e->ax[pb->swap ? 1 : 0], *pbp = pb->e->ax[pb->swap ? 0 : 1];
    if (J) {
        /* b's column first: the state alone keeps nothing */
        const double d = FD_REL * pb->scale[jb];
        usm_params q2 = q;
        *usm_params_field(&q2, pbp) += d;
        if (usm_periodic_shoot_state(pb->w, &q2, x0, rb) != USM_OK ||
            usm_periodic_shoot(pb->w, &q, pa, FD_REL * pb->scale[ja], x0, F, Jk) != USM_OK)
            return -1;
        for (int a = 0; a < k; ++a) {
            for (int b = 0; b <= k; ++b)
                J[a * N + b] = Jk[a * (k + 1) + b];
            J[a * N + jb] = (rb[a] - F[a]) / d;
        }
    } else if (usm_periodic_shoot(pb->w, &q, NULL, 0.0, x0, F, NULL) != USM_OK)
        return -1;
    const double g = usm_periodic_shoot_max_modulus(pb->w) - 1.0;
    if (!isfinite(g))
        return -1;
    F[k] = g;
    if (J) {
        if (!pb->have_grow) {
            double zs[SMAX];
            memcpy(zs, z, sizeof(double) * (size_t)N);
            for (int j = 0; j < N; ++j) {
                double gj;
                for (int tries = 0;; ++tries) {
                    zs[j] = z[j] + pb->gstep[j];
                    gj = g_at(pb, zs);
                    zs[j] = z[j];
                    if (!isfinite(gj))
                        return -1;
                    if (tries == G_FD_TRIES || fabs(gj - g) <= G_FD_MOVE)
                        break;
                    pb->gstep[j] *= G_FD_SHRINK;
                }
                pb->grow[j] = (gj - g) / pb->gstep[j];
            }
            pb->have_grow = 1;
        }
        memcpy(J + k * N, pb->grow, sizeof(double) * (size_t)N);
    }
    return 0;
}

typedef struct sbox {
    const sprob *pb;
    int side; /* 0 x low, 1 x high, 2 y low, 3 y high */
} sbox;

static double s_test_box(const double *z, const double *dz, void *ctx)
{
    (void)dz;
    const sbox *t = ctx;
    const usm_envelope *e = t->pb->e;
    double v[2];
    s_xy(t->pb, z, &v[0], &v[1]);
    const int a = t->side / 2;
    const double pad = BOX_PAD * (e->hi[a] - e->lo[a]);
    return t->side % 2 == 0 ? v[a] - (e->lo[a] - pad) : (e->hi[a] + pad) - v[a];
}

typedef struct sbuf {
    double *xy, *u, *freq;
    size_t n, cap_xy, cap_u, cap_f;
} sbuf;

/* A point: (x, y), the orbit's state at t0 and the critical multiplier's
 * frequency (NaN where it is real). */
static int s_push(sbuf *b, sprob *pb, const double *z)
{
    const int nx = pb->e->m->nx;
    double x0[USM_MAX_NX], r[USM_MAX_NX];
    usm_params q;
    if (usm_grow((void **)&b->xy, &b->cap_xy, 2 * (b->n + 1), sizeof(double)) != 0 ||
        usm_grow((void **)&b->u, &b->cap_u, (size_t)nx * (b->n + 1), sizeof(double)) != 0 ||
        usm_grow((void **)&b->freq, &b->cap_f, b->n + 1, sizeof(double)) != 0)
        return -1;
    s_xy(pb, z, &b->xy[2 * b->n], &b->xy[2 * b->n + 1]);
    s_unpack(pb, z, x0, &q);
    memcpy(b->u + (size_t)nx * b->n, x0, sizeof(double) * (size_t)nx);
    double f = NAN;
    usm_periodic_result res;
    if (usm_periodic_shoot(pb->w, &q, NULL, 0.0, x0, r, NULL) == USM_OK &&
        usm_periodic_shoot_result(pb->w, &res) == USM_OK) {
        const usm_floquet_result *fl = &res.floquet;
        int c = -1;
        for (int i = 0; i < fl->n; ++i)
            if (!fl->cyclic[i] &&
                (c < 0 || hypot(fl->re[i], fl->im[i]) > hypot(fl->re[c], fl->im[c])))
                c = i;
        if (c >= 0 && fabs(fl->im[c]) > USM_COMPLEX_PAIR_TOL * hypot(fl->re[c], fl->im[c]))
            f = usm_squeal_frequency(1.0 / res.period, fl->re[c], fl->im[c]);
    }
    b->freq[b->n] = f;
    b->n++;
    return 0;
}

/* The curve from z0, the last unknown moving in direction dir, to where it
 * leaves the box; its points into b.  0, or -1 when out of memory. */
static int s_run(sprob *pb, const double *z0, int dir, sbuf *b, usm_envelope_end *end)
{
    usm_envelope *e = pb->e;
    const int N = pb->N;
    int rc = 0;
    sbox tests[4];
    usm_cont_options o;
    *end = USM_ENVELOPE_END_LOST;
    if (!(pb->c = usm_cont_alloc(N - 1)))
        return -1;
    usm_cont_options_default(&o);
    o.h0 = 0.5 * H_MAX;
    o.h_max = H_MAX;
    o.h_min = H_MIN;
    o.newton_max = 8;
    o.grow_its = 3;
    o.shrink_its = 6;
    o.newton_tol = NEWTON_TOL;
    for (int a = 0; a < 2; ++a)
        o.newton_tol = fmax(o.newton_tol, NEWTON_TOL * 0.5 * fabs(e->lo[a] + e->hi[a]) /
                                              (e->hi[a] - e->lo[a]));
    o.event_tol = 1e-10;
    o.across_fold = 1;
    o.max_steps = 20 * e->opt.max_points;
    usm_cont_set_problem(pb->c, s_residual, pb);
    if (usm_cont_set_options(pb->c, &o) != 0 || usm_cont_set_scale(pb->c, pb->scale) != 0) {
        rc = -1;
        goto done;
    }
    for (int side = 0; side < 4; ++side) {
        tests[side].pb = pb;
        tests[side].side = side;
        if ((pb->tbox[side] = usm_cont_add_test(pb->c, s_test_box, &tests[side],
                                                USM_CONT_TEST_STOP | USM_CONT_TEST_POINT)) < 0) {
            rc = -1;
            goto done;
        }
    }
    pb->have_grow = 0;
    if (usm_cont_start(pb->c, z0, dir) != 0) {
        goto done;
    }
    if (s_push(b, pb, usm_cont_point(pb->c)) != 0) {
        rc = -1;
        goto done;
    }
    for (long steps = 0; steps < e->opt.max_points; ++steps) {
        pb->have_grow = 0;
        const int st = usm_cont_step(pb->c);
        if (st != USM_CONT_STEP && st != USM_CONT_END)
            break;
        double zs[SMAX];
        memcpy(zs, usm_cont_point(pb->c), sizeof(double) * (size_t)N);
        if (st == USM_CONT_END) {
            const usm_cont_event *ev =
                usm_cont_event_at(pb->c, usm_cont_event_count(pb->c) - 1);
            int side = -1;
            for (int sd = 0; ev && sd < 4; ++sd)
                if (ev->test == pb->tbox[sd])
                    side = sd;
            *end = USM_ENVELOPE_END_BOX;
            if (side >= 0) {
                const int a = side / 2;
                const double v = side % 2 == 0 ? e->lo[a] : e->hi[a];
                pb->have_grow = 0;
                /* where Newton with the side's value held fails, the located
                 * point (within BOX_PAD of the side) put onto it */
                if (usm_cont_correct_fixed(pb->c, zs, s_axis_col(pb, a), v) < 0) {
                    memcpy(zs, usm_cont_point(pb->c), sizeof(double) * (size_t)N);
                    zs[s_axis_col(pb, a)] = v;
                }
            }
            rc = s_push(b, pb, zs);
            break;
        }
        if ((rc = s_push(b, pb, zs)) != 0)
            break;
        if (steps + 1 == e->opt.max_points)
            *end = USM_ENVELOPE_END_LIMIT;
    }
done:
    usm_cont_free(pb->c);
    pb->c = NULL;
    return rc;
}

int env_periodic_stability_trace(usm_envelope *e, usm_periodic *w, int edge, double x, double y,
                                 const double *x0)
{
    const usm_model *m = e->m;
    usm_periodic_result r;
    usm_periodic_options po;
    usm_params q = e->p;
    sprob pb;
    sbuf b;
    memset(&pb, 0, sizeof pb);
    memset(&b, 0, sizeof b);
    pb.e = e;
    pb.w = w;
    *usm_params_field(&q, e->ax[0]) = x;
    *usm_params_field(&q, e->ax[1]) = y;
    usm_periodic_options_default(&po);
    po.t0 = e->opt.t0;
    /* the shooting's scales are those of the last solve: the seed's */
    if (usm_periodic_solve(w, &q, x0, &po, &r) != USM_OK)
        return 0;
    usm_periodic_shoot_set_t0(w, e->opt.t0);
    double sc[USM_MAX_NX], z0[SMAX];
    /* the edge's parameter held at the start: the last unknown */
    pb.swap = edge < 2 ? 1 : 0;
    pb.k = usm_periodic_shoot_layout(w, pb.idx, sc);
    pb.N = pb.k + 2;
    memcpy(pb.xfull, r.x0, sizeof(double) * (size_t)m->nx);
    for (int a = 0; a < pb.k; ++a) {
        pb.scale[a] = sc[pb.idx[a]];
        z0[a] = r.x0[pb.idx[a]];
    }
    for (int a = 0; a < 2; ++a)
        pb.scale[s_axis_col(&pb, a)] = e->hi[a] - e->lo[a];
    for (int j = 0; j < pb.N; ++j)
        pb.gstep[j] = G_FD_REL * pb.scale[j];
    z0[s_axis_col(&pb, 0)] = x;
    z0[s_axis_col(&pb, 1)] = y;
    usm_envelope_end end = USM_ENVELOPE_END_LOST;
    /* into the box: the held parameter away from its edge */
    int rc = s_run(&pb, z0, edge % 2 == 0 ? 1 : -1, &b, &end);
    if (rc == 0 && b.n >= 2) {
        if (usm_grow((void **)&e->curves, &e->curvecap, e->ncurves + 1, sizeof *e->curves) != 0)
            rc = -1;
        else {
            env_curve *cv = &e->curves[e->ncurves++];
            memset(cv, 0, sizeof *cv);
            cv->xy = b.xy;
            cv->u = b.u;
            cv->freq = b.freq;
            cv->pub.kind = USM_ENVELOPE_STABILITY;
            cv->pub.npoints = b.n;
            cv->pub.xy = cv->xy;
            cv->pub.u = cv->u;
            cv->pub.frequency = cv->freq;
            cv->pub.nu = m->nx;
            cv->pub.end[0] = USM_ENVELOPE_END_BOX;
            cv->pub.end[1] = end;
            return 0;
        }
    }
    free(b.xy);
    free(b.u);
    free(b.freq);
    return rc;
}
