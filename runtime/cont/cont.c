/* The continuation engine (usm_cont.h): pseudo-arclength continuation of
 * F(x) = 0, n equations in n + 1 unknowns, with test functions whose zeros
 * are located along the arclength.
 *
 * In scaled coordinates z = x / scale (Keller's bordered system):
 *   tangent    [F_z; c] t = e_{n+1}, c the previous tangent (so c.t > 0: the
 *              orientation is kept through a fold, where F_u alone is singular)
 *   step       predictor z_k + h t_k, corrector Newton on
 *              [F(z); t_k.(z - z_k) - h] = 0
 *   arc        the accepted step as s -> z(s), s in [0, h], each z(s) the
 *              corrector from z_k + s t_k in the hyperplane t_k.(z - z_k) = s
 * A test function's sign change between the ends of a step is located by
 * Brent (core/root.h) on that arc.  The tangent at the end of a step comes
 * from the corrector's last factorisation (the Jacobian one Newton update,
 * <= newton_tol, away); inside a location it is computed afresh.
 */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/dense.h"
#include "core/grow.h"
#include "core/root.h"
#include "usm_cont.h"

typedef struct cont_test {
    usm_cont_test_fn fn;
    void *ctx;
    int flags;
    int branch; /* the built-in branch-point test (fn NULL) */
    double g;   /* value at the current point */
} cont_test;

struct usm_cont {
    int n, N; /* equations, unknowns */
    usm_cont_residual f;
    void *fctx;
    usm_cont_options o;
    double *scale;
    cont_test *tests;
    int ntests;
    size_t testcap;
    /* the branch */
    int started, ended, its;
    long steps;
    double h;
    double *z, *t, *x, *dx; /* current point and tangent (scaled), and unscaled */
    /* the last step's arc */
    double *za, *ta, *zb, s_end; /* start, tangent, end */
    double *xa;                  /* za in the problem's units */
    int have_arc;
    /* events of the last step */
    usm_cont_event *ev;
    double *evbuf; /* 2 N values an event */
    int nev;
    /* work */
    double *A, *LU, *J, *F, *w, *z1, *t1, *g1;
    double *wk; /* 5 N: the locations (usm_cont_arc_locate, locate_events) */
    double *wp; /* 2 N: usm_cont_arc_point, usm_cont_correct_fixed */
    int *piv;
    usm_root *root;
};

void usm_cont_options_default(usm_cont_options *o)
{
    o->h0 = 0.01;
    o->h_min = 1e-13;
    o->h_max = 0.05;
    o->newton_tol = 1e-10;
    o->newton_max = 12;
    o->grow_its = 3;
    o->shrink_its = 6;
    o->cos_max_turn = 0.9;
    o->event_tol = 1e-14;
    o->across_fold = 0;
    o->max_steps = 2000000;
    o->chord = 0;
}

usm_cont *usm_cont_alloc(int n)
{
    if (n < 1 || n > 100000)
        return NULL;
    usm_cont *c = calloc(1, sizeof *c);
    if (!c)
        return NULL;
    const size_t N = (size_t)n + 1;
    c->n = n;
    c->N = (int)N;
    usm_cont_options_default(&c->o);
    c->scale = malloc(N * sizeof(double));
    c->z = calloc(N, sizeof(double));
    c->t = calloc(N, sizeof(double));
    c->x = calloc(N, sizeof(double));
    c->dx = calloc(N, sizeof(double));
    c->za = calloc(N, sizeof(double));
    c->ta = calloc(N, sizeof(double));
    c->zb = calloc(N, sizeof(double));
    c->xa = calloc(N, sizeof(double));
    c->A = calloc(N * N, sizeof(double));
    c->LU = calloc(N * N, sizeof(double));
    c->J = calloc(N * N, sizeof(double));
    c->F = calloc(N, sizeof(double));
    c->w = calloc(N, sizeof(double));
    c->z1 = calloc(N, sizeof(double));
    c->t1 = calloc(N, sizeof(double));
    c->wk = calloc(5 * N, sizeof(double));
    c->wp = calloc(2 * N, sizeof(double));
    c->piv = calloc(N, sizeof(int));
    c->root = usm_root_alloc();
    if (!c->scale || !c->z || !c->t || !c->x || !c->dx || !c->za || !c->ta || !c->zb || !c->xa || !c->A ||
        !c->LU || !c->J || !c->F || !c->w || !c->z1 || !c->t1 || !c->wk || !c->wp || !c->piv || !c->root ||
        usm_cont_add_test(c, NULL, NULL, USM_CONT_TEST_MONITOR) != USM_CONT_FOLD) {
        usm_cont_free(c);
        return NULL;
    }
    for (size_t j = 0; j < N; ++j)
        c->scale[j] = 1.0;
    return c;
}

void usm_cont_free(usm_cont *c)
{
    if (!c)
        return;
    free(c->scale);
    free(c->tests);
    free(c->z);
    free(c->t);
    free(c->x);
    free(c->dx);
    free(c->za);
    free(c->ta);
    free(c->zb);
    free(c->xa);
    free(c->ev);
    free(c->evbuf);
    free(c->A);
    free(c->LU);
    free(c->J);
    free(c->F);
    free(c->w);
    free(c->z1);
    free(c->t1);
    free(c->g1);
    free(c->wk);
    free(c->wp);
    free(c->piv);
    usm_root_free(c->root);
    free(c);
}

void usm_cont_set_problem(usm_cont *c, usm_cont_residual f, void *ctx)
{
    c->f = f;
    c->fctx = ctx;
}

int usm_cont_set_options(usm_cont *c, const usm_cont_options *o)
{
    if (!(o->h_min > 0) || !(o->h_max >= o->h_min) || !(o->h0 >= o->h_min) ||
        !(o->h0 <= o->h_max) || !(o->newton_tol > 0) || o->newton_max < 1 ||
        !(o->cos_max_turn > -1 && o->cos_max_turn < 1) || !(o->event_tol > 0) ||
        o->max_steps < 1 || !isfinite(o->h_max) || (o->chord != 0 && o->chord != 1))
        return USM_CONT_EUSAGE;
    c->o = *o;
    if (c->started)
        c->h = fmin(fmax(c->h, o->h_min), o->h_max);
    return 0;
}

const usm_cont_options *usm_cont_options_get(const usm_cont *c) { return &c->o; }

static double dot(int N, const double *a, const double *b)
{
    double d = 0;
    for (int j = 0; j < N; ++j)
        d += a[j] * b[j];
    return d;
}

static void normalise(int N, double *t)
{
    const double len = sqrt(dot(N, t, t));
    for (int j = 0; j < N; ++j)
        t[j] /= len;
}

static void unscale(const usm_cont *c, const double *z, double *x)
{
    for (int j = 0; j < c->N; ++j)
        x[j] = z[j] * c->scale[j];
}

static void sync_current(usm_cont *c)
{
    unscale(c, c->z, c->x);
    unscale(c, c->t, c->dx);
}

int usm_cont_set_scale(usm_cont *c, const double *scale)
{
    for (int j = 0; j < c->N; ++j)
        if (!(scale[j] > 0) || !isfinite(scale[j]))
            return USM_CONT_EUSAGE;
    for (int j = 0; j < c->N; ++j) {
        const double r = c->scale[j] / scale[j];
        c->z[j] *= r;
        c->t[j] *= r;
        c->scale[j] = scale[j];
    }
    if (c->started) {
        normalise(c->N, c->t);
        sync_current(c);
    }
    /* the arc was measured in the old coordinates */
    c->have_arc = 0;
    return 0;
}

static int add_test(usm_cont *c, usm_cont_test_fn fn, void *ctx, int flags, int branch)
{
    const int kind = flags & ~USM_CONT_TEST_POINT;
    if ((kind != USM_CONT_TEST_MONITOR && kind != USM_CONT_TEST_STOP) || c->started)
        return USM_CONT_EUSAGE;
    if (usm_grow((void **)&c->tests, &c->testcap, (size_t)c->ntests + 1, sizeof *c->tests) != 0)
        return USM_CONT_EUSAGE;
    c->tests[c->ntests] = (cont_test){fn, ctx, flags, branch, NAN};
    return c->ntests++;
}

int usm_cont_add_test(usm_cont *c, usm_cont_test_fn fn, void *ctx, int flags)
{
    /* fn NULL only for the fold, registered first by usm_cont_alloc */
    if (c->ntests > 0 && !fn)
        return USM_CONT_EUSAGE;
    return add_test(c, fn, ctx, flags, 0);
}

int usm_cont_add_branch_test(usm_cont *c, int flags)
{
    /* it reads the tangent: never USM_CONT_TEST_POINT */
    if (flags != USM_CONT_TEST_MONITOR && flags != USM_CONT_TEST_STOP)
        return USM_CONT_EUSAGE;
    return add_test(c, NULL, NULL, flags, 1);
}

/* ---- the bordered system ---------------------------------------------------------- */

/* F(z) into c->F[0..n-1]; with jac, the scaled F_z into rows 0..n-1 of c->A. */
static int eval(usm_cont *c, const double *z, int jac)
{
    const int n = c->n, N = c->N;
    unscale(c, z, c->w);
    if (c->f(c->w, c->F, jac ? c->J : NULL, c->fctx) != 0)
        return -1;
    for (int i = 0; i < n; ++i)
        if (!isfinite(c->F[i]))
            return -1;
    if (!jac)
        return 0;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < N; ++j) {
            const double a = c->J[i * N + j] * c->scale[j];
            if (!isfinite(a))
                return -1;
            c->A[i * N + j] = a;
        }
    return 0;
}

/* usm_lu_factor_dense (the same operations, so the same factors), except
 * that an exactly zero pivot is replaced by DBL_EPSILON times its row's
 * size: the bordered matrix is exactly singular at a branch point, and the
 * locator of its test function lands there exactly when the test is linear
 * in s; the tangent there then comes out along the followed branch instead
 * of the location failing. */
static int lu_factor(int n, double *A, int *piv)
{
    for (int k = 0; k < n; ++k) {
        int p = k;
        for (int i = k + 1; i < n; ++i)
            if (fabs(A[i * n + k]) > fabs(A[p * n + k]))
                p = i;
        if (!isfinite(A[p * n + k]))
            return -1;
        piv[k] = p;
        if (p != k)
            for (int j = 0; j < n; ++j) {
                const double t = A[k * n + j];
                A[k * n + j] = A[p * n + j];
                A[p * n + j] = t;
            }
        if (A[k * n + k] == 0.0) {
            double row = 0;
            for (int j = k + 1; j < n; ++j)
                row = fmax(row, fabs(A[k * n + j]));
            A[k * n + k] = DBL_EPSILON * (row > 0 ? row : 1.0);
        }
        for (int i = k + 1; i < n; ++i) {
            const double l = A[i * n + k] /= A[k * n + k];
            if (l == 0.0)
                continue;
            for (int j = k + 1; j < n; ++j)
                A[i * n + j] -= l * A[k * n + j];
        }
    }
    return 0;
}

/* Factors c->A with its last row replaced by the border b into c->LU. */
static int factor(usm_cont *c, const double *b)
{
    const int n = c->n, N = c->N;
    memcpy(c->LU, c->A, sizeof(double) * (size_t)n * (size_t)N);
    memcpy(c->LU + (size_t)n * (size_t)N, b, sizeof(double) * (size_t)N);
    return lu_factor(N, c->LU, c->piv);
}

static int solve(usm_cont *c, double *x)
{
    usm_lu_solve_dense(c->N, c->LU, c->piv, x, 1);
    for (int j = 0; j < c->N; ++j)
        if (!isfinite(x[j]))
            return -1;
    return 0;
}

/* Newton on [F(z); b.z - b0] = 0 from z, in place.  Iterations, or -1 (z
 * then holds the last iterate). */
static int correct(usm_cont *c, double *z, const double *b, double b0)
{
    const int n = c->n, N = c->N;
    double prev = INFINITY;
    for (int it = 1; it <= c->o.newton_max; ++it) {
        const int jac = !c->o.chord || it == 1;
        if (eval(c, z, jac) != 0 || (jac && factor(c, b) != 0))
            return -1;
        c->F[n] = dot(N, b, z) - b0;
        for (int j = 0; j < N; ++j)
            c->F[j] = -c->F[j];
        if (solve(c, c->F) != 0)
            return -1;
        double norm = 0;
        for (int j = 0; j < N; ++j) {
            z[j] += c->F[j];
            norm = fmax(norm, fabs(c->F[j]));
        }
        if (norm <= c->o.newton_tol)
            return it;
        /* a growing update: the start lies outside Newton's basin; the step
         * control shortens the step instead */
        if (it >= 2 && norm > prev)
            return -1;
        prev = norm;
    }
    return -1;
}

/* The unit tangent from the factorisation in c->LU (border b): b.t > 0. */
static int tangent_from_lu(usm_cont *c, double *t)
{
    for (int j = 0; j < c->N; ++j)
        t[j] = 0.0;
    t[c->n] = 1.0;
    if (solve(c, t) != 0)
        return -1;
    normalise(c->N, t);
    return 0;
}

/* The unit tangent at z (on the branch) with b.t > 0, computed afresh. */
static int tangent(usm_cont *c, const double *z, const double *b, double *t)
{
    if (eval(c, z, 1) != 0 || factor(c, b) != 0)
        return -1;
    return tangent_from_lu(c, t);
}

/* det [F_z; t] at z: the branch-point test; NaN when F cannot be
 * evaluated. */
static double bordered_det(usm_cont *c, const double *z, const double *t)
{
    if (eval(c, z, 1) != 0)
        return NAN;
    if (factor(c, t) != 0)
        return NAN;
    double d = 1.0;
    for (int j = 0; j < c->N; ++j) {
        d *= c->LU[(size_t)j * (size_t)c->N + (size_t)j];
        if (c->piv[j] != j)
            d = -d;
    }
    return d;
}

static double test_value(usm_cont *c, int k, const double *z, const double *t, double *x,
                         double *dx)
{
    unscale(c, z, x);
    unscale(c, t, dx);
    if (k == USM_CONT_FOLD)
        return dx[c->n];
    if (c->tests[k].branch)
        return bordered_det(c, z, t);
    return c->tests[k].fn(x, dx, c->tests[k].ctx);
}

/* ---- the arc of the last step --------------------------------------------------------- */

static int arc_point_z(usm_cont *c, double s, double *z, double *t)
{
    const int N = c->N;
    if (s == 0.0)
        memcpy(z, c->za, sizeof(double) * (size_t)N);
    else if (s == c->s_end)
        memcpy(z, c->zb, sizeof(double) * (size_t)N);
    else {
        for (int j = 0; j < N; ++j)
            z[j] = c->za[j] + s * c->ta[j];
        if (correct(c, z, c->ta, dot(N, c->ta, c->za) + s) < 0)
            return -1;
    }
    return t ? tangent(c, z, c->ta, t) : 0;
}

int usm_cont_arc_point(usm_cont *c, double s, double *x, double *dx)
{
    const int N = c->N;
    double *z = c->wp;
    if (!c->have_arc || !(s >= 0.0 && s <= c->s_end) ||
        arc_point_z(c, s, z, dx ? z + N : NULL) != 0)
        return -1;
    unscale(c, z, x);
    if (dx)
        unscale(c, z + N, dx);
    return 0;
}

typedef struct arc_fn {
    usm_cont *c;
    int k;               /* a test function, or -1: fn */
    usm_cont_test_fn fn; /* k = -1 */
    void *ctx;
    double *z, *t, *x, *dx; /* work, N values each */
} arc_fn;

static double arc_value(double s, void *ctx)
{
    arc_fn *a = ctx;
    usm_cont *c = a->c;
    /* a test of the point alone: no tangent (one Jacobian fewer a trial) */
    const int point = a->k > USM_CONT_FOLD && (c->tests[a->k].flags & USM_CONT_TEST_POINT);
    if (arc_point_z(c, s, a->z, point ? NULL : a->t) != 0)
        return NAN; /* the locator stops */
    if (point) {
        unscale(c, a->z, a->x);
        return c->tests[a->k].fn(a->x, NULL, c->tests[a->k].ctx);
    }
    if (a->k >= 0)
        return test_value(c, a->k, a->z, a->t, a->x, a->dx);
    unscale(c, a->z, a->x);
    unscale(c, a->t, a->dx);
    return a->fn(a->x, a->dx, a->ctx);
}

/* The zero on the arc of the function of a (values f0, f1 at the ends):
 * 0 with *s and its point (unscaled) in x, dx; or -1. */
static int arc_zero(arc_fn *a, double f0, double f1, double *s, double *x, double *dx)
{
    usm_cont *c = a->c;
    const usm_root_stop stop = {c->o.event_tol, 0.0, 200};
    if (usm_root_brent(c->root, arc_value, a, 0.0, c->s_end, f0, f1, &stop, s) != 0 ||
        arc_point_z(c, *s, a->z, a->t) != 0)
        return -1;
    unscale(c, a->z, x);
    if (dx)
        unscale(c, a->t, dx);
    return 0;
}

int usm_cont_arc_locate(usm_cont *c, usm_cont_test_fn fn, void *ctx, double f0, double f1,
                        double *s, double *x)
{
    const size_t N = (size_t)c->N;
    double *work = c->wk;
    if (!c->have_arc || !fn)
        return -1;
    arc_fn a = {c, -1, fn, ctx, work, work + N, work + 2 * N, work + 3 * N};
    return arc_zero(&a, f0, f1, s, x, work + 4 * N);
}

int usm_cont_correct_fixed(usm_cont *c, double *x, int k, double value)
{
    const int N = c->N;
    if (k < 0 || k >= N)
        return -1;
    double *z = c->wp, *b = c->wp + N;
    for (int j = 0; j < N; ++j) {
        z[j] = x[j] / c->scale[j];
        b[j] = j == k ? 1.0 : 0.0;
    }
    const int its = correct(c, z, b, value / c->scale[k]);
    if (its >= 0)
        unscale(c, z, x);
    return its;
}

static int start_tests(usm_cont *c);

/* ---- branch switching ----------------------------------------------------------------- */

/* The eigenvector of the smallest eigenvalue of the symmetric m x m matrix
 * S (destroyed) into v, by cyclic Jacobi (V: m x m work); the eigenvalue. */
static double smallest_eigvec(int m, double *S, double *V, double *v)
{
    for (int i = 0; i < m; ++i)
        for (int j = 0; j < m; ++j)
            V[i * m + j] = i == j ? 1.0 : 0.0;
    for (int sweep = 0; sweep < 60; ++sweep) {
        double off = 0, diag = 0;
        for (int i = 0; i < m; ++i) {
            diag += S[i * m + i] * S[i * m + i];
            for (int j = i + 1; j < m; ++j)
                off += S[i * m + j] * S[i * m + j];
        }
        if (off <= 1e-32 * diag || off == 0.0)
            break;
        for (int p = 0; p < m; ++p)
            for (int q = p + 1; q < m; ++q) {
                const double apq = S[p * m + q];
                if (apq == 0.0)
                    continue;
                const double theta = (S[q * m + q] - S[p * m + p]) / (2.0 * apq);
                const double tt = (theta >= 0 ? 1.0 : -1.0) / (fabs(theta) + sqrt(theta * theta + 1.0));
                const double cs = 1.0 / sqrt(tt * tt + 1.0), sn = tt * cs;
                for (int k = 0; k < m; ++k) { /* columns p, q */
                    const double skp = S[k * m + p], skq = S[k * m + q];
                    S[k * m + p] = cs * skp - sn * skq;
                    S[k * m + q] = sn * skp + cs * skq;
                }
                for (int k = 0; k < m; ++k) { /* rows p, q */
                    const double spk = S[p * m + k], sqk = S[q * m + k];
                    S[p * m + k] = cs * spk - sn * sqk;
                    S[q * m + k] = sn * spk + cs * sqk;
                }
                for (int k = 0; k < m; ++k) {
                    const double vkp = V[k * m + p], vkq = V[k * m + q];
                    V[k * m + p] = cs * vkp - sn * vkq;
                    V[k * m + q] = sn * vkp + cs * vkq;
                }
            }
    }
    int best = 0;
    for (int i = 1; i < m; ++i)
        if (S[i * m + i] < S[best * m + best])
            best = i;
    for (int k = 0; k < m; ++k)
        v[k] = V[k * m + best];
    return S[best * m + best];
}

/* psi' (F_z(z + e v) - F_z(z - e v)) / (2 e): the row psi' F_zz[v, .] into
 * row (N values); A: n x N work.  0 or -1. */
static int second_derivative_row(usm_cont *c, const double *z, const double *v, const double *psi,
                                 double *zw, double *A, double *row)
{
    const int n = c->n, N = c->N;
    const double e = 1e-5;
    for (int j = 0; j < N; ++j)
        zw[j] = z[j] + e * v[j];
    if (eval(c, zw, 1) != 0)
        return -1;
    memcpy(A, c->A, sizeof(double) * (size_t)n * (size_t)N);
    for (int j = 0; j < N; ++j)
        zw[j] = z[j] - e * v[j];
    if (eval(c, zw, 1) != 0)
        return -1;
    for (int j = 0; j < N; ++j) {
        double r = 0;
        for (int i = 0; i < n; ++i)
            r += psi[i] * (A[i * N + j] - c->A[i * N + j]);
        row[j] = r / (2.0 * e);
    }
    return 0;
}

/* The other branch's tangent tau and phi (scaled, unit) at the branch point
 * z with the followed branch's unit tangent t1 (scaled).  USM_CONT_ABE,
 * USM_CONT_PERPENDICULAR or USM_CONT_LOST. */
static int branch_tangent_z(usm_cont *c, const double *z, const double *t1, double *tau, double *phi)
{
    const int n = c->n, N = c->N;
    const size_t NN = (size_t)N * (size_t)N;
    double *mem = malloc(sizeof(double) * (4 * NN + 4 * (size_t)N));
    if (!mem)
        return USM_CONT_LOST;
    double *A0 = mem, *S = A0 + NN, *V = S + NN, *A = V + NN;
    double *psi = A + NN, *zw = psi + N, *r1 = zw + N, *r2 = r1 + N;
    int method = USM_CONT_LOST;
    if (eval(c, z, 1) != 0)
        goto out;
    memcpy(A0, c->A, sizeof(double) * (size_t)n * (size_t)N);
    /* phi: the null vector of F_z orthogonal to t1, the smallest eigenvector
     * of F_z'F_z + sigma t1 t1' (t1 itself lifted to sigma) */
    double sigma = 1.0;
    for (int i = 0; i < n * N; ++i)
        sigma += A0[i] * A0[i];
    for (int j = 0; j < N; ++j)
        for (int k = 0; k < N; ++k) {
            double s = sigma * t1[j] * t1[k];
            for (int i = 0; i < n; ++i)
                s += A0[i * N + j] * A0[i * N + k];
            S[j * N + k] = s;
        }
    const double lambda = smallest_eigvec(N, S, V, phi);
    /* a regular point: F_z has rank n, phi's eigenvalue of the size of the
     * Jacobian's squared singular values, not a rounding error's */
    if (!(lambda <= 1e-12 * sigma))
        goto out;
    const double pt = dot(N, phi, t1);
    for (int j = 0; j < N; ++j)
        phi[j] -= pt * t1[j];
    normalise(N, phi);
    /* psi: the left null vector of F_z, the smallest eigenvector of F_z F_z' */
    for (int i = 0; i < n; ++i)
        for (int k = 0; k < n; ++k)
            S[i * n + k] = dot(N, A0 + i * N, A0 + k * N);
    smallest_eigvec(n, S, V, psi);
    if (second_derivative_row(c, z, t1, psi, zw, A, r1) != 0 ||
        second_derivative_row(c, z, phi, psi, zw, A, r2) != 0)
        goto out;
    /* a a^2 + 2 b a b + c b^2 = 0 in (alpha, beta); alpha = 1, beta = 0 is
     * (up to the location's error) the followed branch */
    const double qa = dot(N, r1, t1), qb = 0.5 * (dot(N, r1, phi) + dot(N, r2, t1)),
                 qc = dot(N, r2, phi);
    const double disc = qb * qb - qa * qc;
    if (disc > 0 && qb * qb > 1e-12 * (qa * qa + qc * qc)) {
        /* the small root beta/alpha (the followed branch) by the stable
         * formula, the other as the sum of the roots minus it */
        const double r_small = -qa / (qb + copysign(sqrt(disc), qb));
        const double al = qc, be = -2.0 * qb - qc * r_small;
        for (int j = 0; j < N; ++j)
            tau[j] = al * t1[j] + be * phi[j];
        normalise(N, tau);
        method = USM_CONT_ABE;
    } else {
        memcpy(tau, phi, sizeof(double) * (size_t)N);
        method = USM_CONT_PERPENDICULAR;
    }
out:
    free(mem);
    return method;
}

/* x, dx in the problem's units to z, unit t (scaled) */
static void scale_in(const usm_cont *c, const double *x, const double *dx, double *z, double *t)
{
    for (int j = 0; j < c->N; ++j) {
        z[j] = x[j] / c->scale[j];
        t[j] = dx[j] / c->scale[j];
    }
    normalise(c->N, t);
}

int usm_cont_branch_tangent(usm_cont *c, const double *x, const double *dx, double *tau,
                            double *phi)
{
    const int N = c->N;
    if (!c->f)
        return USM_CONT_EUSAGE;
    double *mem = malloc(sizeof(double) * 4 * (size_t)N);
    if (!mem)
        return USM_CONT_LOST;
    double *z = mem, *t1 = z + N, *ts = t1 + N, *ph = ts + N;
    scale_in(c, x, dx, z, t1);
    const int method = branch_tangent_z(c, z, t1, ts, ph);
    if (method >= 0) {
        unscale(c, ts, tau);
        if (phi)
            unscale(c, ph, phi);
    }
    free(mem);
    return method;
}

int usm_cont_switch_branch(usm_cont *c, const double *x, const double *dx, int dir, double h)
{
    const int n = c->n, N = c->N;
    if (!c->f || (dir != 1 && dir != -1))
        return USM_CONT_EUSAGE;
    if (!(h > 0))
        h = c->o.h0;
    double *mem = malloc(sizeof(double) * 6 * (size_t)N);
    if (!mem)
        return USM_CONT_LOST;
    double *z0 = mem, *t1 = z0 + N, *tau = t1 + N, *phi = tau + N, *z = phi + N, *t = z + N;
    int rc = USM_CONT_LOST;
    scale_in(c, x, dx, z0, t1);
    if (branch_tangent_z(c, z0, t1, tau, phi) < 0)
        goto out;
    int lead = n; /* the component whose sign dir gives */
    if (fabs(tau[n]) < 1e-8)
        for (int j = 0; j < n; ++j)
            if (lead == n || fabs(tau[j]) > fabs(tau[lead]))
                lead = j;
    if ((tau[lead] < 0) == (dir > 0))
        for (int j = 0; j < N; ++j)
            tau[j] = -tau[j];
    /* phi.(z - z0) is second order in the distance along the followed
     * branch and first order along the new one */
    const double pt = dot(N, phi, tau);
    if (pt < 0)
        for (int j = 0; j < N; ++j)
            phi[j] = -phi[j];
    for (int j = 0; j < N; ++j)
        z[j] = z0[j] + h * tau[j];
    if (correct(c, z, phi, dot(N, phi, z0) + h * fabs(pt)) < 0 || tangent(c, z, tau, t) != 0)
        goto out;
    c->started = c->ended = 0;
    c->have_arc = 0;
    c->nev = 0;
    c->its = 0;
    c->steps = 0;
    memcpy(c->z, z, sizeof(double) * (size_t)N);
    memcpy(c->t, t, sizeof(double) * (size_t)N);
    c->h = c->o.h0;
    if (start_tests(c) != 0)
        goto out;
    c->started = 1;
    rc = 0;
out:
    free(mem);
    return rc;
}

/* ---- following the branch ------------------------------------------------------------- */

static int is_stop(const usm_cont *c, int k)
{
    return k == USM_CONT_FOLD ? !c->o.across_fold
                              : (c->tests[k].flags & ~USM_CONT_TEST_POINT) == USM_CONT_TEST_STOP;
}

static int start_tests(usm_cont *c)
{
    const size_t N = (size_t)c->N;
    free(c->ev);
    free(c->evbuf);
    free(c->g1);
    c->ev = calloc((size_t)c->ntests, sizeof *c->ev);
    c->evbuf = calloc(2 * N * (size_t)c->ntests, sizeof(double));
    c->g1 = calloc((size_t)c->ntests, sizeof(double));
    if (!c->ev || !c->evbuf || !c->g1)
        return -1;
    for (int k = 0; k < c->ntests; ++k)
        c->tests[k].g = test_value(c, k, c->z, c->t, c->x, c->dx);
    sync_current(c);
    return 0;
}

int usm_cont_start(usm_cont *c, const double *x0, int dir)
{
    const int N = c->N, n = c->n;
    if (!c->f || (dir != 1 && dir != -1))
        return USM_CONT_EUSAGE;
    c->started = c->ended = 0;
    c->have_arc = 0;
    c->nev = 0;
    c->its = 0;
    c->steps = 0;
    for (int j = 0; j < N; ++j)
        c->z[j] = x0[j] / c->scale[j];
    double *e = c->t1;
    for (int j = 0; j < N; ++j)
        e[j] = j == n ? 1.0 : 0.0;
    if (correct(c, c->z, e, c->z[n]) < 0)
        return USM_CONT_LOST;
    e[n] = dir;
    if (tangent(c, c->z, e, c->t) != 0)
        return USM_CONT_LOST;
    c->h = c->o.h0;
    if (start_tests(c) != 0)
        return USM_CONT_LOST;
    c->started = 1;
    return 0;
}

static int event_cmp(const void *a, const void *b)
{
    const usm_cont_event *ea = a, *eb = b;
    return ea->s < eb->s ? -1 : ea->s > eb->s ? 1 : ea->test - eb->test;
}

/* The zeros of the test functions in the arc just taken (c->g1 their values
 * at its end).  0, or -1 when a location failed. */
static int locate_events(usm_cont *c)
{
    const size_t N = (size_t)c->N;
    double *work = c->wk;
    c->nev = 0;
    for (int k = 0; k < c->ntests; ++k) {
        const double g0 = c->tests[k].g, g1 = c->g1[k];
        if (!isfinite(g0) || !isfinite(g1) || g0 == 0.0 || (g1 != 0.0 && (g0 < 0) == (g1 < 0)))
            continue;
        usm_cont_event *e = &c->ev[c->nev];
        double *x = c->evbuf + 2 * N * (size_t)c->nev;
        arc_fn a = {c, k, NULL, NULL, work, work + N, x, x + N};
        if (arc_zero(&a, g0, g1, &e->s, x, x + N) != 0)
            return -1;
        e->test = k;
        e->stop = is_stop(c, k);
        e->before = g0;
        e->x = x;
        e->dx = x + N;
        c->nev++;
    }
    qsort(c->ev, (size_t)c->nev, sizeof *c->ev, event_cmp);
    return 0;
}

int usm_cont_step(usm_cont *c)
{
    const int N = c->N;
    if (!c->started || c->ended)
        return USM_CONT_EUSAGE;
    if (++c->steps > c->o.max_steps)
        return USM_CONT_LOST;
    for (;;) {
        double *z1 = c->z1, *t1 = c->t1;
        for (int j = 0; j < N; ++j)
            z1[j] = c->z[j] + c->h * c->t[j];
        const int its = correct(c, z1, c->t, dot(N, c->t, c->z) + c->h);
        double turn = -1;
        /* after chord iterations the factorisation is the predictor's: the
         * tangent afresh */
        if (its >= 0 && (c->o.chord ? tangent(c, z1, c->t, t1) : tangent_from_lu(c, t1)) == 0)
            turn = dot(N, c->t, t1);
        int ok = turn >= c->o.cos_max_turn;
        if (ok) {
            memcpy(c->za, c->z, sizeof(double) * (size_t)N);
            memcpy(c->ta, c->t, sizeof(double) * (size_t)N);
            memcpy(c->zb, z1, sizeof(double) * (size_t)N);
            c->s_end = c->h;
            c->have_arc = 1;
            unscale(c, c->za, c->xa);
            for (int k = 0; k < c->ntests && ok; ++k)
                c->g1[k] = test_value(c, k, z1, t1, c->x, c->dx);
            /* a location that fails inside the arc (a correction off the
             * branch where it curves strongly): the step is retried shorter */
            ok = ok && locate_events(c) == 0;
        }
        if (!ok) {
            c->have_arc = 0;
            c->nev = 0;
            sync_current(c);
            if ((c->h *= 0.5) < c->o.h_min)
                return USM_CONT_LOST;
            continue;
        }
        c->its = its;
        for (int k = 0; k < c->nev; ++k)
            if (c->ev[k].stop) {
                const usm_cont_event *e = &c->ev[k];
                c->nev = k + 1;
                c->s_end = e->s;
                for (int j = 0; j < N; ++j) {
                    c->z[j] = e->x[j] / c->scale[j];
                    c->t[j] = e->dx[j] / c->scale[j];
                }
                memcpy(c->zb, c->z, sizeof(double) * (size_t)N);
                sync_current(c);
                c->ended = 1;
                return USM_CONT_END;
            }
        memcpy(c->z, z1, sizeof(double) * (size_t)N);
        memcpy(c->t, t1, sizeof(double) * (size_t)N);
        for (int k = 0; k < c->ntests; ++k)
            c->tests[k].g = c->g1[k];
        sync_current(c);
        if (its <= c->o.grow_its && turn > 0.995)
            c->h = fmin(2.0 * c->h, c->o.h_max);
        else if (its >= c->o.shrink_its)
            c->h = fmax(0.5 * c->h, c->o.h_min);
        return USM_CONT_STEP;
    }
}

const double *usm_cont_point(const usm_cont *c) { return c->x; }

const double *usm_cont_direction(const usm_cont *c) { return c->dx; }

double usm_cont_step_length(const usm_cont *c) { return c->h; }

int usm_cont_iterations(const usm_cont *c) { return c->its; }

int usm_cont_event_count(const usm_cont *c) { return c->nev; }

const usm_cont_event *usm_cont_event_at(const usm_cont *c, int k)
{
    return k >= 0 && k < c->nev ? &c->ev[k] : NULL;
}

double usm_cont_step_arc(const usm_cont *c, const double **x_start)
{
    if (x_start)
        *x_start = c->have_arc ? c->xa : NULL;
    return c->have_arc ? c->s_end : 0.0;
}
