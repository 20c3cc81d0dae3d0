/* The imperfect motor's orbits' critical-multiplier curves in two
 * parameters: `stability` (a complex pair e^{+-i omega} on the unit circle,
 * Neimark-Sacker, or a real multiplier -1) and `fold` (a real multiplier
 * +1: the branch's turning point), named as the sweep's stability_change
 * and fold events (usm_envelope.h).
 *
 * The unknowns z = (x0, [omega], a, b): the k non-cyclic components of the
 * state x0 at the envelope's t0 (the twist rate w = phidot + psidot
 * cos(theta) in phidot's place, scaled as Omega theta, as contact_loss's:
 * envelope_periodic.c), the critical pair's angle omega (Neimark-Sacker
 * only) and both parameters.  The equations:
 *   r(x0; px, py) = 0   periodicity (usm_periodic_shoot, scaled as the
 *                       shooting's)
 *   g(z) = 0            the bordered (minimally augmented) test of R - mu I:
 *       [R - mu I   b] [v]   [0]
 *       [c^H        0] [g] = [1]
 *                       R the monodromy with the cyclic directions deflated
 *                       (usm_periodic_shoot_reduced: in the balanced
 *                       coordinates of the variational integration, where
 *                       it carries the integration's accuracy; the physical
 *                       block of B is rounded to cond(S) eps ~ 1e-5 where
 *                       the tilt is 1e-5 rad).  Neimark-Sacker: mu = e^{i
 *                       omega}, g complex, Re g = Im g = 0 (k + 2 equations
 *                       in k + 3 unknowns); fold mu = +1, period doubling
 *                       mu = -1, g real (k + 1 in k + 2).
 * g vanishes exactly where mu is a multiplier, and is regular there (its
 * derivative -w^H dA v, v and w the bordered system's null vectors) where
 * the multiplier is simple: a regular extended system, unlike the modulus
 * of the largest multiplier minus 1 it replaces, which left the angle out
 * and whose row by differences in phidot (6e3 per scale) the corrector
 * could not use where the rotor speed is near zero.  Borders b, c: the left
 * and right null vectors at the last point (normalised), renewed each step.
 *
 * Rows: r's from the monodromy's block and central differences in the
 * parameters (two shots of the state alone each), as contact_loss's; g's
 * by forward differences, one more shot a column (R at z + h e_j, with the
 * coordinates' balancing held so that both R are in one basis), omega's in
 * closed form (dg/domega = i mu w^H v, no shot).  The costly part (all
 * but the monodromy's block and omega's column) is reused within JAC_REUSE
 * of where it was computed, until the borders change: one Jacobian a step
 * (chord Newton at the predicted point; the tangent at the step's end and
 * the location of the box's side take it), half the curves' time.
 *
 * Seeds: the edge sweeps' stability_change events (neimark_sacker,
 * period_doubling) with their orbits, and their fold events (no orbit
 * there: the orbit of the last event or grid point before the fold on the
 * sweep, Newton on the fold system with the edge's parameter held).  Each
 * curve is continued from its edge until it leaves the box, where its end
 * is put onto the side.  Along a curve: where a stability curve meets a
 * fold (det(R - I) changes sign: "fold/stability"), where a fold curve
 * meets a stability curve (a complex pair's modulus through 1), and where
 * either meets contact_loss (F_n_min) or stick_loss (the stick excess) the
 * point is a codimension-two point.
 */
#include <complex.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/grow.h"
#include "envelope_internal.h"
#include "envelope_periodic_problem.h"
#include "solve/periodic_internal.h"
#include "usm_periodic_sweep.h"

#define SMAX (USM_MAX_NX + 3)
#define NN (USM_MAX_NX * USM_MAX_NX)
/* r's parameter columns, central differences of two shots of the state
 * alone (as envelope_periodic.c's). */
#define FD_REL 1e-4
/* g's columns: forward differences of this of each unknown's scale.  R's
 * noise is ~1e-10 (the integration's rtol 1e-11 on the balanced
 * variational equations): 1e-5 of the derivative; with the twist rate as
 * the unknown g is linear over it. */
#define G_FD_REL 1e-5
/* The corrector's tolerance on its update (scaled), of the parameters'
 * values where the box is small against them. */
#define NEWTON_TOL 1e-9
/* Longest step (the box's sides 1): the curves are nearly straight. */
#define H_MAX 0.25
#define H_MIN 1e-7
#define BOX_PAD 1e-9
/* The Jacobian's costly part (r's parameter columns and g's rows: k + 2
 * of its k + 3 shots with the variational equations and its four of the
 * state alone) is reused within this (scaled, max norm) of where it
 * was last computed, the monodromy's block and omega's column always fresh:
 * the tangent at a step's end then takes the corrector's, and the location
 * of the box's side the step's.  Its accuracy sets the corrector's rate
 * only.  In the start, which may come from an orbit away from the curve
 * (the fold's seed), within JAC_REUSE_START: the last iterations. */
#define JAC_REUSE 0.05
#define JAC_REUSE_START 1e-4
/* Codimension-two tests monitored along a curve. */
enum { CT_FOLD, CT_PAIR, CT_CONTACT, CT_STICK, CT_N };

typedef struct sprob {
    usm_envelope *e;
    usm_periodic *w;
    int kind;                 /* USM_ENVELOPE_STABILITY or USM_ENVELOPE_FOLD */
    int ns;                   /* 1: complex pair, omega an unknown */
    double mu_real;           /* real cases: +1 (fold) or -1 (period doubling) */
    int swap;                 /* 0 (.., px, py), 1 (.., py, px) */
    int k, nk, N, neq;
    int idx[USM_MAX_NX];
    env_twist twist;          /* the twist rate in phidot's place */
    double xfull[USM_MAX_NX]; /* the cyclic components (a gauge) */
    double scale[SMAX];
    double complex b[USM_MAX_NX], c[USM_MAX_NX];
    double F_n_scale;
    /* the last shot's point (a test's values from one shot) */
    double shot_z[SMAX];
    int have_shot_z;
    int tbox[4], tcd[CT_N];
    usm_cont *c_;
    /* the Jacobian's costly part (r's parameter columns, g's rows) of the
     * last evaluation at jac_z (have_jac) */
    double jac_z[SMAX], jac[(USM_MAX_NX + 2) * SMAX];
    int have_jac, may_reuse;
} sprob;

static int col_om(const sprob *pb) { return pb->ns ? pb->k : -1; }
static int col_p0(const sprob *pb) { return pb->k + pb->ns; }

static void s_xy(const sprob *pb, const double *z, double *px, double *py)
{
    const int j = col_p0(pb);
    *px = pb->swap ? z[j + 1] : z[j];
    *py = pb->swap ? z[j] : z[j + 1];
}

/* The column of axis a (0 x, 1 y). */
static int s_axis_col(const sprob *pb, int a)
{
    return col_p0(pb) + ((a == 0) == !pb->swap ? 0 : 1);
}

static const usm_param_info *s_col_param(const sprob *pb, int j)
{
    return pb->e->ax[(j == col_p0(pb)) == !pb->swap ? 0 : 1];
}

static void s_unpack(const sprob *pb, const double *z, double *x0, usm_params *q)
{
    double px, py;
    env_twist_unpack(&pb->twist, pb->e->m, pb->idx, pb->k, pb->xfull, z, x0);
    s_xy(pb, z, &px, &py);
    *q = pb->e->p;
    *usm_params_field(q, pb->e->ax[0]) = px;
    *usm_params_field(q, pb->e->ax[1]) = py;
}

/* The full shot at z (R and the samples kept in w). */
static int s_shoot(sprob *pb, const double *z, double *r, double *Jk)
{
    double x0[USM_MAX_NX], rr[USM_MAX_NX];
    usm_params q;
    s_unpack(pb, z, x0, &q);
    pb->have_shot_z = 0;
    if (usm_periodic_shoot(pb->w, &q, NULL, 0.0, x0, r ? r : rr, Jk) != USM_OK)
        return -1;
    memcpy(pb->shot_z, z, sizeof(double) * (size_t)pb->N);
    pb->have_shot_z = 1;
    return 0;
}

static int s_shot_at(sprob *pb, const double *z)
{
    if (pb->have_shot_z && memcmp(pb->shot_z, z, sizeof(double) * (size_t)pb->N) == 0)
        return 0;
    return s_shoot(pb, z, NULL, NULL);
}

/* Solve A x = y in place (n x n complex, row-major), partial pivoting.  0,
 * or -1 when singular. */
static int csolve(int n, double complex *A, double complex *y)
{
    for (int p = 0; p < n; ++p) {
        int piv = p;
        for (int i = p + 1; i < n; ++i)
            if (cabs(A[i * n + p]) > cabs(A[piv * n + p]))
                piv = i;
        if (A[piv * n + p] == 0)
            return -1;
        if (piv != p) {
            for (int j = 0; j < n; ++j) {
                const double complex t = A[p * n + j];
                A[p * n + j] = A[piv * n + j];
                A[piv * n + j] = t;
            }
            const double complex t = y[p];
            y[p] = y[piv];
            y[piv] = t;
        }
        for (int i = p + 1; i < n; ++i) {
            const double complex f = A[i * n + p] / A[p * n + p];
            if (f == 0)
                continue;
            for (int j = p; j < n; ++j)
                A[i * n + j] -= f * A[p * n + j];
            y[i] -= f * y[p];
        }
    }
    for (int i = n - 1; i >= 0; --i) {
        double complex s = y[i];
        for (int j = i + 1; j < n; ++j)
            s -= A[i * n + j] * y[j];
        y[i] = s / A[i * n + i];
    }
    return 0;
}

/* The bordered system of R - mu I (borders pb->b, pb->c): g, and when v or
 * wl are not NULL the right and left null vectors (nk each; wl from the
 * adjoint system [A^H c; b^H 0]). */
static int bordered(const sprob *pb, const double *R, double complex mu, double complex *g,
                    double complex *v, double complex *wl)
{
    const int n = pb->nk, m = n + 1;
    double complex A[(USM_MAX_NX + 1) * (USM_MAX_NX + 1)], y[USM_MAX_NX + 1];
    for (int pass = 0; pass < (wl ? 2 : 1); ++pass) {
        for (int i = 0; i < n; ++i) {
            for (int j = 0; j < n; ++j) {
                const double complex a = R[i * n + j] - (i == j ? mu : 0);
                if (pass == 0)
                    A[i * m + j] = a;
                else
                    A[j * m + i] = conj(a);
            }
            A[i * m + n] = pass == 0 ? pb->b[i] : pb->c[i];
            A[n * m + i] = pass == 0 ? conj(pb->c[i]) : conj(pb->b[i]);
            y[i] = 0;
        }
        A[n * m + n] = 0;
        y[n] = 1;
        if (csolve(m, A, y) != 0)
            return -1;
        if (pass == 0) {
            *g = y[n];
            if (v)
                memcpy(v, y, sizeof(double complex) * (size_t)n);
        } else
            memcpy(wl, y, sizeof(double complex) * (size_t)n);
    }
    return 0;
}

static double complex s_mu(const sprob *pb, const double *z)
{
    return pb->ns ? cexp(I * z[col_om(pb)]) : pb->mu_real;
}

/* g of the last shot at z (R read from w). */
static int g_of_shot(sprob *pb, const double *z, double complex *g)
{
    double R[NN];
    if (usm_periodic_shoot_reduced(pb->w, R) != pb->nk)
        return -1;
    return bordered(pb, R, s_mu(pb, z), g, NULL, NULL);
}

static int s_residual(const double *z, double *F, double *J, void *ctx)
{
    sprob *pb = ctx;
    const int k = pb->k, N = pb->N;
    double x0[USM_MAX_NX];
    double Jk[USM_MAX_NX * (USM_MAX_NX + 1)];
    usm_params q;
    for (int j = 0; j < N; ++j)
        if (!isfinite(z[j]))
            return -1;
    s_unpack(pb, z, x0, &q);
    int reuse = 0;
    if (J && pb->have_jac) {
        double d = 0;
        for (int j = 0; j < N; ++j)
            d = fmax(d, fabs(z[j] - pb->jac_z[j]) / pb->scale[j]);
        reuse = d <= (pb->may_reuse ? JAC_REUSE : JAC_REUSE_START);
    }
    if (J && reuse) {
        for (int j = col_p0(pb); j <= col_p0(pb) + 1; ++j)
            for (int a = 0; a < k; ++a)
                J[a * N + j] = pb->jac[a * N + j];
    } else if (J) {
        /* the parameters' columns first (the state alone keeps nothing) */
        for (int j = col_p0(pb); j <= col_p0(pb) + 1; ++j)
            if (env_param_column(pb->w, &q, s_col_param(pb, j), FD_REL * pb->scale[j], x0, k, J,
                                 N, j) != 0)
                return -1;
    }
    if (s_shoot(pb, z, F, J ? Jk : NULL) != 0)
        return -1;
    double R[NN];
    double complex g, v[USM_MAX_NX], wl[USM_MAX_NX];
    if (usm_periodic_shoot_reduced(pb->w, R) != pb->nk ||
        bordered(pb, R, s_mu(pb, z), &g, J ? v : NULL, J ? wl : NULL) != 0 || !isfinite(creal(g)) ||
        !isfinite(cimag(g)))
        return -1;
    F[k] = creal(g);
    if (pb->ns)
        F[k + 1] = cimag(g);
    if (!J)
        return 0;
    for (int a = 0; a < k; ++a) {
        for (int b = 0; b < k; ++b)
            J[a * N + b] = Jk[a * (k + 1) + b];
        if (pb->ns)
            J[a * N + col_om(pb)] = 0.0;
        env_twist_chain(&pb->twist, pb->e->m, x0, J + a * N);
    }
    /* g's columns: R at z + h e_j in the same coordinates */
    double zs[SMAX];
    int rc = 0;
    if (reuse) {
        for (int i = k; i < pb->neq; ++i)
            for (int j = 0; j < N; ++j)
                J[i * N + j] = pb->jac[i * N + j];
        goto omega;
    }
    memcpy(zs, z, sizeof(double) * (size_t)N);
    usm_periodic_shoot_hold_balance(pb->w, 1);
    for (int j = 0; j < N && rc == 0; ++j) {
        if (j == col_om(pb))
            continue;
        const double h = G_FD_REL * pb->scale[j];
        double complex gj;
        zs[j] = z[j] + h;
        rc = s_shoot(pb, zs, NULL, NULL) != 0 || g_of_shot(pb, zs, &gj) != 0 ? -1 : 0;
        zs[j] = z[j];
        if (rc == 0) {
            J[k * N + j] = creal(gj - g) / h;
            if (pb->ns)
                J[(k + 1) * N + j] = cimag(gj - g) / h;
        }
    }
    usm_periodic_shoot_hold_balance(pb->w, 0);
    if (rc != 0)
        return -1;
    memcpy(pb->jac, J, sizeof(double) * (size_t)(pb->neq * N));
    memcpy(pb->jac_z, z, sizeof(double) * (size_t)N);
    pb->have_jac = 1;
omega:
    if (pb->ns) {
        /* dA/domega = -i mu I: dg = -w^H dA v / (w^H b) with the adjoint's
         * normalisation c^H... here w solves [A^H c; b^H 0][w; .] = [0; 1],
         * so dg/domega = i mu (w^H v) */
        double complex s = 0;
        for (int i = 0; i < pb->nk; ++i)
            s += conj(wl[i]) * v[i];
        const double complex dg = I * s_mu(pb, z) * s;
        J[k * N + col_om(pb)] = creal(dg);
        J[(k + 1) * N + col_om(pb)] = cimag(dg);
    }
    return 0;
}

/* The borders renewed from the null vectors at z (after a shot there). */
static void renew_borders(sprob *pb, const double *z)
{
    double R[NN];
    double complex g, v[USM_MAX_NX], wl[USM_MAX_NX];
    if (s_shot_at(pb, z) != 0 || usm_periodic_shoot_reduced(pb->w, R) != pb->nk ||
        bordered(pb, R, s_mu(pb, z), &g, v, wl) != 0)
        return;
    double nv = 0, nw = 0;
    for (int i = 0; i < pb->nk; ++i) {
        nv += creal(v[i] * conj(v[i]));
        nw += creal(wl[i] * conj(wl[i]));
    }
    if (!(nv > 0) || !(nw > 0) || !isfinite(nv) || !isfinite(nw))
        return;
    /* g is another function with other borders: its rows are redone */
    pb->have_jac = 0;
    for (int i = 0; i < pb->nk; ++i) {
        pb->c[i] = v[i] / sqrt(nv);
        pb->b[i] = wl[i] / sqrt(nw);
    }
}

/* The multipliers of the last shot (the reduced R's eigenvalues). */
static int shot_multipliers(sprob *pb, usm_floquet_result *fl)
{
    return usm_periodic_shoot_multipliers(pb->w, fl) == USM_OK ? 0 : -1;
}

typedef struct sbox {
    sprob *pb;
    int what; /* 0..3 a side of the box (0 x low, 1 x high, 2 y low, 3 y high); 4 + CT_* */
} sbox;

/* det(R - I) = prod (lambda_i - 1) over the non-cyclic multipliers: it
 * changes sign where a real multiplier passes +1 (a pair contributes
 * |lambda - 1|^2 > 0), continuously. */
static double det_fold(sprob *pb)
{
    usm_floquet_result fl;
    if (shot_multipliers(pb, &fl) != 0)
        return NAN;
    double complex d = 1.0;
    for (int i = 0; i < fl.n; ++i)
        if (!fl.cyclic[i])
            d *= fl.re[i] - 1.0 + I * fl.im[i];
    return creal(d);
}

static double s_test(const double *z, const double *dz, void *ctx)
{
    (void)dz;
    const sbox *t = ctx;
    sprob *pb = t->pb;
    const usm_envelope *e = pb->e;
    if (t->what < 4) {
        double px, py;
        s_xy(pb, z, &px, &py);
        return env_box_test(e, t->what, px, py, BOX_PAD);
    }
    if (s_shot_at(pb, z) != 0)
        return NAN;
    switch (t->what - 4) {
    case CT_FOLD:
        return det_fold(pb);
    case CT_PAIR: {
        usm_floquet_result fl;
        if (shot_multipliers(pb, &fl) != 0)
            return NAN;
        double m = -INFINITY;
        for (int i = 0; i < fl.n; ++i)
            if (!fl.cyclic[i] && fl.im[i] > USM_COMPLEX_PAIR_TOL * hypot(fl.re[i], fl.im[i]))
                m = fmax(m, hypot(fl.re[i], fl.im[i]));
        return isfinite(m) ? m - 1.0 : NAN;
    }
    case CT_CONTACT:
        return usm_periodic_shoot_F_n_min(pb->w) / pb->F_n_scale;
    case CT_STICK:
        return usm_periodic_shoot_stick_excess(pb->w) / pb->F_n_scale;
    }
    return NAN;
}

typedef struct sbuf {
    double *xy, *u, *freq;
    size_t n, cap_xy, cap_u, cap_f;
} sbuf;

/* A point: (x, y), the orbit's state at t0 and, on a Neimark-Sacker curve,
 * the pair's frequency f omega / 2 pi as the sweep's squeal frequency. */
static int s_push(sbuf *b, sprob *pb, const double *z)
{
    const int nx = pb->e->m->nx;
    double x0[USM_MAX_NX];
    usm_params q;
    if (usm_grow((void **)&b->xy, &b->cap_xy, 2 * (b->n + 1), sizeof(double)) != 0 ||
        usm_grow((void **)&b->u, &b->cap_u, (size_t)nx * (b->n + 1), sizeof(double)) != 0 ||
        usm_grow((void **)&b->freq, &b->cap_f, b->n + 1, sizeof(double)) != 0)
        return -1;
    s_xy(pb, z, &b->xy[2 * b->n], &b->xy[2 * b->n + 1]);
    s_unpack(pb, z, x0, &q);
    memcpy(b->u + (size_t)nx * b->n, x0, sizeof(double) * (size_t)nx);
    double f = NAN;
    if (pb->ns) {
        const double om = fabs(remainder(z[col_om(pb)], 2.0 * 3.14159265358979323846));
        f = usm_squeal_frequency(q.f, cos(om), sin(om));
    }
    b->freq[b->n] = f;
    b->n++;
    return 0;
}

static void codim2_events(sprob *pb, size_t curve)
{
    static const char *other[CT_N] = {NULL, NULL, "contact_loss", "stick_loss"};
    for (int i = 0; i < usm_cont_event_count(pb->c_); ++i) {
        const usm_cont_event *ev = usm_cont_event_at(pb->c_, i);
        for (int t = 0; t < CT_N; ++t) {
            if (pb->tcd[t] < 0 || ev->test != pb->tcd[t])
                continue;
            char type[40];
            const double none[USM_MAX_NU] = {0};
            double px, py;
            s_xy(pb, ev->x, &px, &py);
            /* where fold and stability meet: one name from either curve */
            if (t == CT_FOLD || t == CT_PAIR)
                snprintf(type, sizeof type, "fold/stability");
            else
                snprintf(type, sizeof type, "%s/%s", usm_envelope_kind_name(pb->kind),
                         other[t]);
            (void)env_add_codim2(pb->e, type, none, px, py, curve);
        }
    }
}

/* The curve from z0, the last unknown moving in direction dir, to where it
 * leaves the box; its points into b.  0, or -1 when out of memory. */
static int s_run(sprob *pb, const double *z0, int dir, sbuf *b, usm_envelope_end *end)
{
    usm_envelope *e = pb->e;
    const int N = pb->N;
    int rc = 0;
    sbox tests[4 + CT_N];
    usm_cont_options o;
    *end = USM_ENVELOPE_END_LOST;
    if (!(pb->c_ = usm_cont_alloc(N - 1)))
        return -1;
    usm_cont_options_default(&o);
    o.h0 = H_MAX;
    /* the Jacobian costs k + 1 full shots, F one: factored once a
     * correction along the curve (the start, from an orbit away from the
     * fold, takes Newton) */
    o.chord = 0;
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
    usm_cont_set_problem(pb->c_, s_residual, pb);
    if (usm_cont_set_options(pb->c_, &o) != 0 || usm_cont_set_scale(pb->c_, pb->scale) != 0) {
        rc = -1;
        goto done;
    }
    for (int t = 0; t < 4 + CT_N; ++t) {
        tests[t].pb = pb;
        tests[t].what = t;
        int *slot = t < 4 ? &pb->tbox[t] : &pb->tcd[t - 4];
        *slot = -1;
        if (t >= 4) {
            const int ct = t - 4;
            /* a stability curve watches the fold's test, a fold curve a
             * pair's; both the contact's and, in stick models, the stick's */
            if ((ct == CT_FOLD && pb->kind != USM_ENVELOPE_STABILITY) ||
                (ct == CT_PAIR && pb->kind != USM_ENVELOPE_FOLD) ||
                /* the stick excess is a stick model's (the sweep's stick_loss) */
                (ct == CT_STICK && e->m->slip))
                continue;
        }
        if ((*slot = usm_cont_add_test(pb->c_, s_test, &tests[t],
                                       (t < 4 ? USM_CONT_TEST_STOP : USM_CONT_TEST_MONITOR) |
                                           USM_CONT_TEST_POINT)) < 0) {
            rc = -1;
            goto done;
        }
    }
    pb->may_reuse = 0;
    if (usm_cont_start(pb->c_, z0, dir) != 0)
        goto done;
    pb->may_reuse = 1;
    o.chord = 1;
    if (usm_cont_set_options(pb->c_, &o) != 0) {
        rc = -1;
        goto done;
    }
    if (s_push(b, pb, usm_cont_point(pb->c_)) != 0) {
        rc = -1;
        goto done;
    }
    renew_borders(pb, usm_cont_point(pb->c_));
    for (long steps = 0; steps < e->opt.max_points; ++steps) {
        const int st = usm_cont_step(pb->c_);
        if (st != USM_CONT_STEP && st != USM_CONT_END)
            break;
        codim2_events(pb, e->ncurves);
        double zs[SMAX];
        memcpy(zs, usm_cont_point(pb->c_), sizeof(double) * (size_t)N);
        if (st == USM_CONT_END) {
            const int col[2] = {s_axis_col(pb, 0), s_axis_col(pb, 1)};
            *end = USM_ENVELOPE_END_BOX;
            env_end_on_side(e, pb->c_, pb->tbox, col, zs, N);
            rc = s_push(b, pb, zs);
            break;
        }
        if ((rc = s_push(b, pb, zs)) != 0)
            break;
        renew_borders(pb, zs);
        if (steps + 1 == e->opt.max_points)
            *end = USM_ENVELOPE_END_LIMIT;
    }
done:
    usm_cont_free(pb->c_);
    pb->c_ = NULL;
    return rc;
}

/* The critical multiplier of the orbit of the last shot: the largest
 * non-cyclic pair (ns), else the real one nearest mu_real; its eigenvector
 * seeds the borders by inverse iteration. */
static int seed_borders(sprob *pb, const double *z)
{
    double R[NN];
    usm_floquet_result fl;
    if (s_shot_at(pb, z) != 0 || shot_multipliers(pb, &fl) != 0 ||
        usm_periodic_shoot_reduced(pb->w, R) != pb->nk)
        return -1;
    int c = -1;
    for (int i = 0; i < fl.n; ++i) {
        if (fl.cyclic[i])
            continue;
        const int pair = fabs(fl.im[i]) > USM_COMPLEX_PAIR_TOL * hypot(fl.re[i], fl.im[i]);
        if (pb->ns ? pair && fl.im[i] > 0 &&
                         (c < 0 || fabs(hypot(fl.re[i], fl.im[i]) - 1) <
                                       fabs(hypot(fl.re[c], fl.im[c]) - 1))
                   : !pair && (c < 0 || fabs(fl.re[i] - pb->mu_real) <
                                            fabs(fl.re[c] - pb->mu_real)))
            c = i;
    }
    if (c < 0)
        return -1;
    const double complex lam = fl.re[c] + I * (pb->ns ? fl.im[c] : 0.0);
    const int n = pb->nk;
    /* inverse iteration on R - lam I (shifted off the exact eigenvalue) for
     * v, on its adjoint for w */
    for (int pass = 0; pass < 2; ++pass) {
        double complex x[USM_MAX_NX];
        for (int i = 0; i < n; ++i)
            x[i] = 1.0 + 0.1 * i;
        for (int it = 0; it < 3; ++it) {
            double complex A[NN];
            for (int i = 0; i < n; ++i)
                for (int j = 0; j < n; ++j) {
                    const double complex a = R[i * n + j] - (i == j ? lam * (1 + 1e-10) : 0);
                    if (pass == 0)
                        A[i * n + j] = a;
                    else
                        A[j * n + i] = conj(a);
                }
            if (csolve(n, A, x) != 0)
                return -1;
            double nx = 0;
            for (int i = 0; i < n; ++i)
                nx += creal(x[i] * conj(x[i]));
            nx = sqrt(nx);
            if (!(nx > 0) || !isfinite(nx))
                return -1;
            for (int i = 0; i < n; ++i)
                x[i] /= nx;
        }
        for (int i = 0; i < n; ++i)
            (pass == 0 ? pb->c : pb->b)[i] = x[i];
    }
    if (pb->ns)
        return atan2(fl.im[c], fl.re[c]) > 0 ? 0 : -1;
    return 0;
}

int env_periodic_stability_trace(usm_envelope *e, usm_periodic *w, int edge, int crossing,
                                 double x, double y, const double *x0)
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
    pb.kind = crossing == USM_CROSSING_FOLD ? USM_ENVELOPE_FOLD : USM_ENVELOPE_STABILITY;
    pb.ns = crossing == USM_CROSSING_NEIMARK_SACKER;
    pb.mu_real = crossing == USM_CROSSING_PERIOD_DOUBLING ? -1.0 : 1.0;
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
    pb.nk = pb.k;
    pb.N = pb.k + pb.ns + 2;
    pb.neq = pb.N - 1;
    memcpy(pb.xfull, r.x0, sizeof(double) * (size_t)m->nx);
    env_twist_setup(&pb.twist, m, pb.idx, pb.k, sc, 2.0 * 3.14159265358979323846 / r.period,
                    pb.scale);
    pb.F_n_scale = fmax(fabs(r.F_n_max), 1e-300);
    if (pb.ns)
        pb.scale[col_om(&pb)] = 1.0;
    for (int a = 0; a < 2; ++a)
        pb.scale[s_axis_col(&pb, a)] = e->hi[a] - e->lo[a];
    env_twist_pack(&pb.twist, m, pb.idx, pb.k, r.x0, z0);
    z0[s_axis_col(&pb, 0)] = x;
    z0[s_axis_col(&pb, 1)] = y;
    if (pb.ns)
        z0[col_om(&pb)] = 0.0;
    pb.have_shot_z = 0;
    {
        /* omega from the seed's pair, then the borders */
        usm_floquet_result fl;
        if (s_shot_at(&pb, z0) != 0 || shot_multipliers(&pb, &fl) != 0)
            return 0;
        if (pb.ns) {
            int c = -1;
            for (int i = 0; i < fl.n; ++i)
                if (!fl.cyclic[i] && fl.im[i] > USM_COMPLEX_PAIR_TOL * hypot(fl.re[i], fl.im[i]) &&
                    (c < 0 || fabs(hypot(fl.re[i], fl.im[i]) - 1) <
                                  fabs(hypot(fl.re[c], fl.im[c]) - 1)))
                    c = i;
            if (c < 0)
                return 0;
            z0[col_om(&pb)] = atan2(fl.im[c], fl.re[c]);
            pb.have_shot_z = 0;
        }
        if (seed_borders(&pb, z0) != 0)
            return 0;
    }
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
            cv->pub.kind = (usm_envelope_kind)pb.kind;
            cv->pub.npoints = b.n;
            cv->pub.xy = cv->xy;
            cv->pub.u = cv->u;
            if (pb.kind == USM_ENVELOPE_STABILITY) {
                cv->freq = b.freq;
                cv->pub.frequency = cv->freq;
            } else
                free(b.freq);
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
