/* The operating envelope: the boundaries of the stationary solution
 * continued in two parameters (usm_envelope.h gives the extended systems).
 *
 * Both the seed lines (one parameter free) and the curves (both free, one
 * defining function more) are zero problems of the continuation engine
 * (usm_cont.h); they share the residual and the defining functions below and
 * differ in which unknowns are free:
 *   line   x = (u, q)       q the line's parameter, the other one fixed
 *   curve  x = (u, a, b)    a, b = px, py or py, px (b the one that moves
 *                           most at the seed: the engine's start holds the
 *                           last unknown fixed)
 * This file keeps the problems, the seeds and the curves; envelope_regions.c
 * the raster and the regions' classes; envelope_result.c the object and the
 * results it holds.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/dense.h"
#include "core/grow.h"
#include "envelope_internal.h"

#define NMAX (USM_MAX_NU + 2)
/* Central differences of g: this fraction of each unknown's scale (g is
 * smooth, its rounding ~1e-16 / 1e-7 relative: ample for Newton, whose
 * solution does not depend on the Jacobian's accuracy). */
#define FD_REL 1e-7
/* Two points of one kind closer than this (the box's sides 1, the unknowns
 * by their scales) lie on one curve. */
#define SAME_TOL 2e-4
/* The box's sides for the stopping tests, this fraction of a side outside:
 * an end is then put onto the side itself (usm_cont_correct_fixed). */
#define BOX_PAD 1e-9
/* A Bogdanov-Takens zero is kept when both multipliers nearest 1 are this
 * close to it (a zero at a jump of the test function leaves one far). */
#define BT_GAP 1e-6
/* The corrector's tolerance on stability curves (scaled unknowns). */
#define STAB_NEWTON_TOL 1e-10
/* Two multiplier pairs within this of the unit circle where a stability
 * curve is lost: the corner of the boundary (a double Hopf point). */
#define CORNER_TOL 1e-3
/* The other leg's seed this far from the corner (the box's sides 1). */
#define CORNER_STEP 2e-3

void usm_envelope_options_default(usm_envelope_options *opt)
{
    memset(opt, 0, sizeof *opt);
    opt->lines = 3;
    opt->nodes = 9;
    opt->h_max = 0.02;
    opt->max_points = 4000;
    opt->stability = 1;
    opt->raster = 120;
    usm_steady_options_default(&opt->steady);
    opt->t0 = 0.0;
    usm_floquet_options_default(&opt->floquet);
    usm_op_options_default(&opt->op);
}

/* ---- the problems ---------------------------------------------------------------- */

/* Sets the two parameters from x (the problem's layout). */
static void set_params(env_problem *pb, const double *x)
{
    const int nu = pb->e->nu;
    double px, py;
    if (pb->kind < 0) {
        px = pb->line_axis == 0 ? x[nu] : pb->fixed;
        py = pb->line_axis == 0 ? pb->fixed : x[nu];
    } else {
        px = pb->swap ? x[nu + 1] : x[nu];
        py = pb->swap ? x[nu] : x[nu + 1];
    }
    *usm_params_field(&pb->p, pb->e->ax[0]) = px;
    *usm_params_field(&pb->p, pb->e->ax[1]) = py;
}

void env_xy(const env_problem *pb, const double *x, double *px, double *py)
{
    const int nu = pb->e->nu;
    if (pb->kind < 0) {
        *px = pb->line_axis == 0 ? x[nu] : pb->fixed;
        *py = pb->line_axis == 0 ? pb->fixed : x[nu];
    } else {
        *px = pb->swap ? x[nu + 1] : x[nu];
        *py = pb->swap ? x[nu] : x[nu + 1];
    }
}

/* Both parameters inside their physical range (Newton must not wander to
 * kappa < 0). */
static int admissible(const env_problem *pb)
{
    for (int k = 0; k < 2; ++k) {
        const double v = usm_params_get(&pb->p, pb->e->ax[k]);
        const usm_constraint c = usm_param_constraints[usm_param_index(pb->e->ax[k])];
        if (!isfinite(v) || (c == USM_CONSTRAINT_POSITIVE && !(v > 0)) ||
            (c == USM_CONSTRAINT_NONNEGATIVE && !(v >= 0)))
            return 0;
    }
    return 1;
}

/* The bordered system's g and its null vectors (v right, w left): the
 * minimally augmented fold function. */
static int fold_function(env_problem *pb, const double *u, double *g, double *v, double *w)
{
    const int nu = pb->e->nu, n1 = nu + 1;
    double A[USM_MAX_NU * USM_MAX_NU], M[(USM_MAX_NU + 1) * (USM_MAX_NU + 1)],
        MT[(USM_MAX_NU + 1) * (USM_MAX_NU + 1)], r[USM_MAX_NU + 1], l[USM_MAX_NU + 1];
    int piv[USM_MAX_NU + 1];
    pb->e->m->steady_jacobian(u, &pb->p, A);
    for (int i = 0; i < n1; ++i)
        for (int j = 0; j < n1; ++j) {
            double a;
            if (i < nu && j < nu)
                a = A[i * nu + j] * pb->uscale[j];
            else if (i < nu)
                a = pb->border_b[i];
            else if (j < nu)
                a = pb->border_c[j];
            else
                a = 0.0;
            M[i * n1 + j] = a;
            MT[j * n1 + i] = a;
        }
    for (int i = 0; i < n1; ++i)
        r[i] = l[i] = i == nu ? 1.0 : 0.0;
    if (usm_lu_factor_dense(n1, M, piv) != 0)
        return -1;
    usm_lu_solve_dense(n1, M, piv, r, 1);
    if (usm_lu_factor_dense(n1, MT, piv) != 0)
        return -1;
    usm_lu_solve_dense(n1, MT, piv, l, 1);
    *g = r[nu];
    if (v)
        for (int j = 0; j < nu; ++j)
            v[j] = r[j];
    if (w)
        for (int j = 0; j < nu; ++j)
            w[j] = l[j];
    return 0;
}

/* det r_u, in the scaled unknowns: its sign changes at a fold (a test on the
 * other curves, where the borders are not kept). */
static double fold_det(env_problem *pb, const double *u)
{
    const int nu = pb->e->nu;
    double A[USM_MAX_NU * USM_MAX_NU];
    int piv[USM_MAX_NU];
    pb->e->m->steady_jacobian(u, &pb->p, A);
    for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nu; ++j)
            A[i * nu + j] *= pb->uscale[j];
    if (usm_lu_factor_dense(nu, A, piv) != 0)
        return 0.0;
    double d = 1.0;
    for (int i = 0; i < nu; ++i)
        d *= A[i * nu + i] * (piv[i] != i ? -1.0 : 1.0);
    return d;
}

double env_defining(env_problem *pb, int kind, const double *x)
{
    const usm_model *m = pb->e->m;
    double y[USM_STEADY_COUNT], g;
    set_params(pb, x);
    switch (kind) {
    case USM_ENVELOPE_TILT_ZERO:
        return x[m->u_theta];
    case USM_ENVELOPE_STALL:
        return m->u_phidot_R >= 0 ? x[m->u_phidot_R] : NAN;
    case USM_ENVELOPE_FRICTION_SATURATION:
        return m->u_phidot_R >= 0 && pb->kind == kind ? x[m->u_phidot_R] - pb->sat_w : NAN;
    case USM_ENVELOPE_STICK_LIMIT:
        m->steady_outputs(x, &pb->p, y);
        return fabs(y[USM_STEADY_F_T]) - pb->p.mu0 * y[USM_STEADY_F_N];
    case USM_ENVELOPE_FOLD:
        return fold_function(pb, x, &g, NULL, NULL) == 0 ? g : NAN;
    case USM_ENVELOPE_STABILITY: {
        usm_steady_solution sol;
        usm_floquet_result fr;
        /* at the axis the Euler angles are singular: no multipliers there */
        if (!(x[m->u_theta] > 0))
            return NAN;
        memset(&sol, 0, sizeof sol);
        memcpy(sol.u, x, sizeof(double) * (size_t)pb->e->nu);
        usm_steady_evaluate(m, &pb->p, &sol);
        if (usm_floquet_compute(pb->e->fl, &pb->p, &sol, pb->e->opt.t0, &pb->e->opt.floquet, &fr) !=
                USM_OK ||
            !isfinite(fr.max_modulus))
            return NAN;
        return fr.max_modulus - 1.0;
    }
    }
    return NAN;
}

/* The multipliers at x, kept for the next call at the same x (a fold curve's
 * two tests read the same ones).  0, or -1 off the axis's side or when the
 * computation fails. */
static int fold_multipliers(env_problem *pb, const double *x, const usm_floquet_result **out)
{
    const usm_model *m = pb->e->m;
    const int n = pb->n + 1;
    if (!(x[m->u_theta] > 0))
        return -1;
    if (pb->fl_valid && memcmp(pb->fl_x, x, sizeof(double) * (size_t)n) == 0) {
        *out = &pb->fl_res;
        return 0;
    }
    usm_steady_solution sol;
    pb->fl_valid = 0;
    set_params(pb, x);
    memset(&sol, 0, sizeof sol);
    memcpy(sol.u, x, sizeof(double) * (size_t)pb->e->nu);
    usm_steady_evaluate(m, &pb->p, &sol);
    if (usm_floquet_compute(pb->e->fl, &pb->p, &sol, pb->e->opt.t0, &pb->e->opt.floquet,
                            &pb->fl_res) != USM_OK)
        return -1;
    memcpy(pb->fl_x, x, sizeof(double) * (size_t)n);
    pb->fl_valid = 1;
    *out = &pb->fl_res;
    return 0;
}

/* The two non-cyclic multipliers nearest 1 (a nearest), their distances. */
static int nearest_one(const usm_floquet_result *fr, int *a, int *b, double *da, double *db)
{
    *a = *b = -1;
    *da = *db = INFINITY;
    for (int k = 0; k < fr->n; ++k) {
        if (fr->cyclic[k])
            continue;
        const double d = hypot(fr->re[k] - 1.0, fr->im[k]);
        if (d < *da) {
            *b = *a;
            *db = *da;
            *a = k;
            *da = d;
        } else if (d < *db) {
            *b = k;
            *db = d;
        }
    }
    return *a >= 0 && *b >= 0 && isfinite(*da) && isfinite(*db) ? 0 : -1;
}

/* The tests of a fold curve that replace the stability function there.  Along
 * a fold one multiplier is 1 (the stationary linearisation's eigenvalue 0),
 * so the stability function is 1 - 1 = 0 up to rounding, and the test would
 * be noise.
 *   Bogdanov-Takens: with lambda_1, lambda_2 the two non-cyclic multipliers
 *   nearest 1, Re(lambda_1 + lambda_2) - 2 is symmetric in the pair (smooth
 *   where the pair is apart from the others) and is lambda_2 - 1 on the
 *   fold: it vanishes where a second multiplier reaches 1, the double
 *   eigenvalue 0.  *gap = |lambda_1 - 1| + |lambda_2 - 1|, which a located
 *   zero must make small (where the third-nearest takes the second's place
 *   the function jumps and changes sign without a zero).
 *   fold/stability (a fold-Hopf point): the largest modulus but that of
 *   lambda_1, minus 1: another multiplier crosses the unit circle on the fold,
 *   where a stability curve ends on it. */
static double fold_test(env_problem *pb, const double *x, int bt, double *gap)
{
    const usm_floquet_result *fr;
    int a, b;
    double da, db;
    if (fold_multipliers(pb, x, &fr) != 0 || nearest_one(fr, &a, &b, &da, &db) != 0)
        return NAN;
    if (gap)
        *gap = da + db;
    if (bt)
        return fr->re[a] + fr->re[b] - 2.0;
    double mx = 0.0;
    for (int k = 0; k < fr->n; ++k)
        if (!fr->cyclic[k] && k != a)
            mx = fmax(mx, hypot(fr->re[k], fr->im[k]));
    return mx - 1.0;
}

/* The residual of both problems: r(u) and, on a curve, g; the Jacobian from
 * the generated r_u, r_p and g's row (analytic for theta and phidot_R,
 * central differences otherwise). */
static int problem_residual(const double *x, double *F, double *Jx, void *ctx)
{
    env_problem *pb = ctx;
    const usm_model *m = pb->e->m;
    const int nu = pb->e->nu, N = pb->n + 1;
    double J[USM_MAX_NU * USM_MAX_NU], Jp[USM_MAX_NU * USM_NPARAMS];
    set_params(pb, x);
    if (!admissible(pb))
        return -1;
    m->steady_residual(x, &pb->p, F);
    if (pb->kind >= 0) {
        F[nu] = env_defining(pb, pb->kind, x);
        if (!isfinite(F[nu]))
            return -1;
    }
    for (int i = 0; i < nu; ++i)
        if (!isfinite(F[i]))
            return -1;
    if (!Jx)
        return 0;
    set_params(pb, x);
    m->steady_jacobian(x, &pb->p, J);
    m->steady_jacobian_params(x, &pb->p, Jp);
    const int cx = pb->e->col[0], cy = pb->e->col[1];
    for (int i = 0; i < nu; ++i) {
        for (int j = 0; j < nu; ++j)
            Jx[i * N + j] = J[i * nu + j];
        if (pb->kind < 0)
            Jx[i * N + nu] = Jp[i * USM_NPARAMS + (pb->line_axis == 0 ? cx : cy)];
        else {
            Jx[i * N + nu] = Jp[i * USM_NPARAMS + (pb->swap ? cy : cx)];
            Jx[i * N + nu + 1] = Jp[i * USM_NPARAMS + (pb->swap ? cx : cy)];
        }
    }
    if (pb->kind < 0)
        return 0;
    double *row = Jx + nu * N;
    if (pb->kind == USM_ENVELOPE_TILT_ZERO || pb->kind == USM_ENVELOPE_STALL ||
        pb->kind == USM_ENVELOPE_FRICTION_SATURATION) {
        const int k = pb->kind == USM_ENVELOPE_TILT_ZERO ? m->u_theta : m->u_phidot_R;
        for (int j = 0; j < N; ++j)
            row[j] = j == k ? 1.0 : 0.0;
        return 0;
    }
    double xp[NMAX];
    memcpy(xp, x, sizeof(double) * (size_t)N);
    for (int j = 0; j < N; ++j) {
        const double h = FD_REL * pb->scale[j];
        xp[j] = x[j] + h;
        const double gp = env_defining(pb, pb->kind, xp);
        xp[j] = x[j] - h;
        const double gm = env_defining(pb, pb->kind, xp);
        xp[j] = x[j];
        if (!isfinite(gp) || !isfinite(gm))
            return -1;
        row[j] = (gp - gm) / (2.0 * h);
    }
    set_params(pb, x);
    return 0;
}

/* ---- test functions -------------------------------------------------------------- */

/* A test of a line or a curve: a defining function (kind >= 0), a box side,
 * the tilt range's top, or the cusp coefficient. */
enum { TEST_KIND = 0, TEST_BOX, TEST_TOP, TEST_CUSP, TEST_BT, TEST_FOLD_HOPF };

static double test_fn(const double *x, const double *dx, void *ctx)
{
    env_test *t = ctx;
    env_problem *pb = t->pb;
    (void)dx;
    switch (t->what) {
    case TEST_KIND:
        if (t->kind == USM_ENVELOPE_FOLD && pb->kind != USM_ENVELOPE_FOLD) {
            set_params(pb, x);
            return fold_det(pb, x);
        }
        return env_defining(pb, t->kind, x);
    case TEST_BOX: {
        double px, py;
        env_xy(pb, x, &px, &py);
        const double v = t->side / 2 == 0 ? px : py;
        const int k = t->side / 2;
        /* a seed on a side (the edges are seed lines) would start at this
         * test's zero, where no zero is looked for: the sides just outside */
        const double pad = BOX_PAD * (pb->e->hi[k] - pb->e->lo[k]);
        return t->side % 2 == 0 ? v - (pb->e->lo[k] - pad) : (pb->e->hi[k] + pad) - v;
    }
    case TEST_TOP:
        return pb->e->opt.steady.theta_max - x[pb->e->m->u_theta];
    case TEST_BT:
    case TEST_FOLD_HOPF:
        return fold_test(pb, x, t->what == TEST_BT, NULL);
    default: {
        /* w' r_uu[v, v] by the second difference of r along v */
        const int nu = pb->e->nu;
        double g, v[USM_MAX_NU], w[USM_MAX_NU], up[USM_MAX_NU], um[USM_MAX_NU], rp[USM_MAX_NU],
            rm[USM_MAX_NU], r0[USM_MAX_NU];
        set_params(pb, x);
        if (fold_function(pb, x, &g, v, w) != 0)
            return NAN;
        double nv = 0;
        for (int j = 0; j < nu; ++j)
            nv += v[j] * v[j];
        nv = sqrt(nv);
        if (!(nv > 0))
            return NAN;
        const double h = 1e-4;
        for (int j = 0; j < nu; ++j) {
            up[j] = x[j] + h * v[j] / nv * pb->uscale[j];
            um[j] = x[j] - h * v[j] / nv * pb->uscale[j];
        }
        pb->e->m->steady_residual(up, &pb->p, rp);
        pb->e->m->steady_residual(um, &pb->p, rm);
        pb->e->m->steady_residual(x, &pb->p, r0);
        double a = 0;
        for (int i = 0; i < nu; ++i)
            a += w[i] * (rp[i] - 2.0 * r0[i] + rm[i]) / (h * h);
        return a;
    }
    }
}

static int add_test(env_problem *pb, int what, int kind, int side, int flags)
{
    if (pb->ntests >= ENV_MAX_TESTS)
        return -1;
    env_test *t = &pb->tests[pb->ntests];
    *t = (env_test){pb, what, kind, side, 0};
    t->index = usm_cont_add_test(pb->cont, test_fn, t, flags);
    if (t->index < 0)
        return -1;
    pb->ntests++;
    return 0;
}

const env_test *env_test_of(const env_problem *pb, int index)
{
    for (int k = 0; k < pb->ntests; ++k)
        if (pb->tests[k].index == index)
            return &pb->tests[k];
    return NULL;
}

/* Whether kind applies to the model (stick_limit: stick models; stall: slip). */
int env_kind_applies(const usm_envelope *e, int kind)
{
    /* the periodic orbit's: envelope_periodic.c */
    if (kind == USM_ENVELOPE_CONTACT_LOSS || kind == USM_ENVELOPE_STICK_LOSS ||
        kind == USM_ENVELOPE_SEPARATION_FOLD || kind == USM_ENVELOPE_SEPARATION_STABILITY ||
        kind == USM_ENVELOPE_SEPARATION_GRAZING)
        return 0;
    if (kind == USM_ENVELOPE_STICK_LIMIT)
        return !e->m->slip;
    if (kind == USM_ENVELOPE_STALL)
        return e->m->slip && e->m->u_phidot_R >= 0;
    if (kind == USM_ENVELOPE_STABILITY)
        return e->opt.stability;
    if (kind == USM_ENVELOPE_FRICTION_SATURATION)
        return e->m->slip && e->m->u_phidot_R >= 0 && e->m->friction;
    return 1;
}

/* The engine of one problem: kind < 0 a line in axis `axis` at `fixed`.
 * Tests: the box (stop), the tilt range's top (stop), theta (stop: the
 * tilt_zero event on a line, the tilt_zero end of a curve), the other
 * kinds (monitor), the cusp on a fold curve. */
static int problem_setup(env_problem *pb, usm_envelope *e, int kind, int axis, double fixed,
                         int swap, const double *scale)
{
    usm_cont_options o;
    memset(pb, 0, sizeof *pb);
    pb->e = e;
    pb->p = e->p;
    pb->kind = kind;
    pb->line_axis = axis;
    pb->fixed = fixed;
    pb->swap = swap;
    pb->n = kind < 0 ? e->nu : e->nu + 1;
    memcpy(pb->scale, scale, sizeof(double) * (size_t)(pb->n + 1));
    memcpy(pb->uscale, scale, sizeof(double) * (size_t)e->nu);
    if (kind < 0) {
        *usm_params_field(&pb->p, e->ax[1 - axis]) = fixed;
    }
    pb->cont = usm_cont_alloc(pb->n);
    if (!pb->cont)
        return -1;
    usm_cont_set_problem(pb->cont, problem_residual, pb);
    usm_cont_options_default(&o);
    o.h_max = e->opt.h_max;
    o.h0 = 0.25 * e->opt.h_max;
    /* a curve that no step of 1e-7 of the box continues is lost: halving
     * further costs a Newton (with its Floquet evaluations) per halving */
    o.h_min = 1e-7;
    /* g of a stability curve scatters by ~5e-12 between points 1e-9 apart
     * along it near the axis (theta = 4e-6 rad in the 3-DOF F0 x T box),
     * and the tilt's scale there is its own size: at 1e-12 the corrector
     * did not converge there and the curve was lost; at 1e-10 its points
     * still agree with the sweep's located events to 2e-12 of the box */
    o.newton_tol = kind == USM_ENVELOPE_STABILITY ? STAB_NEWTON_TOL : 1e-12;
    o.event_tol = 1e-14;
    o.across_fold = 1;
    o.max_steps = e->opt.max_points;
    if (usm_cont_set_options(pb->cont, &o) != 0 || usm_cont_set_scale(pb->cont, pb->scale) != 0)
        return -1;
    int sides = kind < 0 ? 2 : 4;
    for (int s = 0; s < 4; ++s) {
        if (sides == 2 && s / 2 != axis)
            continue;
        if (add_test(pb, TEST_BOX, 0, s, USM_CONT_TEST_STOP) != 0)
            return -1;
    }
    if (add_test(pb, TEST_TOP, 0, 0, USM_CONT_TEST_STOP) != 0)
        return -1;
    if (kind != USM_ENVELOPE_TILT_ZERO &&
        add_test(pb, TEST_KIND, USM_ENVELOPE_TILT_ZERO, 0, USM_CONT_TEST_STOP) != 0)
        return -1;
    for (int k = 1; k < USM_ENVELOPE_NKINDS; ++k) {
        if (k == kind || !env_kind_applies(e, k))
            continue;
        /* the saturation is found by its own rule on a line (a test of the
         * diverging rotor speed would not change sign); on a saturation
         * curve the rotor speed is ~1e15 1/s, where r_u's rotor column
         * vanishes and the others' functions are noise */
        if (k == USM_ENVELOPE_FRICTION_SATURATION || kind == USM_ENVELOPE_FRICTION_SATURATION)
            continue;
        /* a line's fold is the engine's own (dq/ds = 0) */
        if (kind < 0 && k == USM_ENVELOPE_FOLD)
            continue;
        /* at the axis there are no multipliers; on a fold one of them is 1
         * all along, so that the test would be noise */
        if ((kind == USM_ENVELOPE_TILT_ZERO || kind == USM_ENVELOPE_FOLD) &&
            k == USM_ENVELOPE_STABILITY)
            continue;
        if (add_test(pb, TEST_KIND, k, 0, USM_CONT_TEST_MONITOR) != 0)
            return -1;
    }
    if (kind == USM_ENVELOPE_FOLD && add_test(pb, TEST_CUSP, 0, 0, USM_CONT_TEST_MONITOR) != 0)
        return -1;
    /* the stability function is noise on a fold: the Bogdanov-Takens test instead */
    if (kind == USM_ENVELOPE_FOLD && env_kind_applies(e, USM_ENVELOPE_STABILITY) &&
        (add_test(pb, TEST_BT, 0, 0, USM_CONT_TEST_MONITOR | USM_CONT_TEST_POINT) != 0 ||
         add_test(pb, TEST_FOLD_HOPF, 0, 0, USM_CONT_TEST_MONITOR | USM_CONT_TEST_POINT) != 0))
        return -1;
    return 0;
}

static void problem_free(env_problem *pb)
{
    usm_cont_free(pb->cont);
    pb->cont = NULL;
}

/* The unknowns' scales: the tilt by its own size (never below 1e-9 rad:
 * tilt_zero curves keep theta = 0), the phase and rotor speed by at least
 * one, the parameters by the box. */
static void make_scale(const usm_envelope *e, const double *u, int kind, int axis, int swap,
                       double *scale)
{
    const int nu = e->nu;
    for (int i = 0; i < nu; ++i)
        scale[i] = i == e->m->u_theta ? fmax(fabs(u[i]), 1e-9) : fmax(1.0, fabs(u[i]));
    if (kind < 0)
        scale[nu] = e->hi[axis] - e->lo[axis];
    else {
        scale[nu] = e->hi[swap] - e->lo[swap];
        scale[nu + 1] = e->hi[1 - swap] - e->lo[1 - swap];
    }
}

/* The tilt's scale follows its size (it may fall by decades), as the sweep's. */
static int rescale(env_problem *pb, const double *x)
{
    const int k = pb->e->m->u_theta;
    const double size = fabs(x[k]);
    int changed = 0;
    for (int i = 0; i < pb->e->nu; ++i) {
        if (i == k)
            continue;
        if (fabs(x[i]) > pb->scale[i]) {
            pb->scale[i] = fabs(x[i]);
            changed = 1;
        }
    }
    if (size > 1e-9 && (size > pb->scale[k] || size < 0.25 * pb->scale[k])) {
        pb->scale[k] = size;
        changed = 1;
    }
    if (!changed)
        return 0;
    /* the fold's borders are in the scaled unknowns: keep them */
    return usm_cont_set_scale(pb->cont, pb->scale);
}

/* ---- the result's lists ---------------------------------------------------------- */

static int add_seed(usm_envelope *e, int kind, const double *u, double px, double py)
{
    if (usm_grow((void **)&e->seeds, &e->seedcap, e->nseeds + 1, sizeof *e->seeds) != 0)
        return -1;
    env_seed *s = &e->seeds[e->nseeds++];
    memset(s, 0, sizeof *s);
    s->kind = kind;
    memcpy(s->u, u, sizeof(double) * (size_t)e->nu);
    s->x = px;
    s->y = py;
    return 0;
}

static const char *pair_name(int a, int b, char *buf, size_t len)
{
    /* in the order of the kinds, so that both curves name it alike */
    const int lo = a < b ? a : b, hi = a < b ? b : a;
    snprintf(buf, len, "%s/%s", usm_envelope_kind_name((usm_envelope_kind)lo),
             usm_envelope_kind_name((usm_envelope_kind)hi));
    return buf;
}

/* ---- seed lines ------------------------------------------------------------------ */

/* Once F_t / F_n is this close to the friction law's supremum the
 * saturation point is computed directly instead of following the diverging
 * rotor speed (as the sweep). */
#define SAT_TRIGGER 0.999
#define V_HUGE 1e15 /* slip velocity [m/s] that stands for infinity */

/* A slip model's line at x: when F_t / F_n is within SAT_TRIGGER of the
 * friction law's supremum, the saturation point (Newton on [r; phidot_R =
 * W], W the rotor speed of slip velocity V_HUGE) as a seed.  1: the line
 * ends here (seeded), 0: go on, -1: out of memory. */
static int line_saturation(env_problem *pb, const double *x)
{
    usm_envelope *e = pb->e;
    const int r = e->m->u_phidot_R, nu = e->nu;
    double y[USM_STEADY_COUNT], mu[USM_FRICTION_COUNT], xs[NMAX];
    set_params(pb, x);
    e->m->steady_outputs(x, &pb->p, y);
    const double v = y[USM_STEADY_V_REL], w = x[r];
    if (!(fabs(v) > 0) || !(fabs(w) > 0) || !(y[USM_STEADY_F_N] != 0))
        return 0;
    e->m->friction(copysign(V_HUGE, v), &pb->p, mu);
    const double lim = fabs(mu[USM_FRICTION_MU]);
    if (!(lim > 0) || fabs(y[USM_STEADY_F_T] / y[USM_STEADY_F_N]) / lim < SAT_TRIGGER)
        return 0;
    memcpy(xs, x, sizeof(double) * (size_t)(nu + 1));
    xs[r] = w * (V_HUGE / fabs(v));
    if (usm_cont_correct_fixed(pb->cont, xs, r, xs[r]) < 0)
        return 0; /* not yet near enough: the continuation goes on */
    const double q = xs[nu];
    if (q < e->lo[pb->line_axis] || q > e->hi[pb->line_axis])
        return 1; /* beyond the box: nothing more on this line */
    double px, py;
    env_xy(pb, xs, &px, &py);
    return add_seed(e, USM_ENVELOPE_FRICTION_SATURATION, xs, px, py) == 0 ? 1 : -1;
}

/* Follow a line's branch from u0 at q0 in direction dir up to q_stop (or an
 * end), recording every located zero of a defining function as a seed. */
static int follow_line(usm_envelope *e, int axis, double fixed, const double *u0, double q0,
                       int dir, double q_stop)
{
    env_problem pb;
    double scale[NMAX], x[NMAX];
    const int nu = e->nu;
    make_scale(e, u0, -1, axis, 0, scale);
    if (problem_setup(&pb, e, -1, axis, fixed, 0, scale) != 0) {
        problem_free(&pb);
        return -1;
    }
    memcpy(x, u0, sizeof(double) * (size_t)nu);
    x[nu] = q0;
    int rc = 0;
    if (usm_cont_start(pb.cont, x, dir) != 0)
        goto done;
    for (long steps = 0; steps < e->opt.max_points; ++steps) {
        const int st = usm_cont_step(pb.cont);
        if (st != USM_CONT_STEP && st != USM_CONT_END)
            break;
        for (int k = 0; k < usm_cont_event_count(pb.cont); ++k) {
            const usm_cont_event *ev = usm_cont_event_at(pb.cont, k);
            const env_test *t = env_test_of(&pb, ev->test);
            int kind = -1;
            if (ev->test == USM_CONT_FOLD)
                kind = USM_ENVELOPE_FOLD;
            else if (t && t->what == TEST_KIND)
                kind = t->kind;
            if (kind < 0)
                continue;
            double px, py;
            env_xy(&pb, ev->x, &px, &py);
            if (add_seed(e, kind, ev->x, px, py) != 0) {
                rc = -1;
                goto done;
            }
        }
        if (st == USM_CONT_END)
            break;
        const double *xc = usm_cont_point(pb.cont);
        if (env_kind_applies(e, USM_ENVELOPE_FRICTION_SATURATION)) {
            const int sat = line_saturation(&pb, xc);
            if (sat < 0) {
                rc = -1;
                goto done;
            }
            if (sat > 0)
                break;
        }
        /* the next node's full search takes over from there */
        if ((xc[nu] - q_stop) * dir > 0)
            break;
        if (rescale(&pb, xc) != 0)
            break;
    }
done:
    problem_free(&pb);
    return rc;
}

/* One seed line: the full search at `nodes` values of its parameter, every
 * root followed to the neighbouring nodes. */
static int seed_line(usm_envelope *e, int axis, double fixed)
{
    const int nodes = e->opt.nodes;
    const double lo = e->lo[axis], hi = e->hi[axis];
    for (int i = 0; i < nodes; ++i) {
        const double q = lo + (hi - lo) * i / (nodes - 1);
        usm_params pq = e->p;
        *usm_params_field(&pq, e->ax[axis]) = q;
        *usm_params_field(&pq, e->ax[1 - axis]) = fixed;
        const int rc = usm_steady_solve(e->steady, &pq, &e->opt.steady);
        if (rc == USM_EINPUT) {
            snprintf(e->msg, sizeof e->msg, "%s", usm_steady_message(e->steady));
            return USM_EINPUT;
        }
        if (rc != USM_OK)
            continue;
        const size_t nr = usm_steady_count(e->steady);
        usm_steady_solution *roots = malloc(nr * sizeof *roots);
        if (!roots)
            return USM_EFAILED;
        for (size_t k = 0; k < nr; ++k)
            roots[k] = *usm_steady_root(e->steady, k);
        const double step = (hi - lo) / (nodes - 1);
        for (size_t k = 0; k < nr; ++k) {
            if ((i + 1 < nodes && follow_line(e, axis, fixed, roots[k].u, q, 1, q + step) != 0) ||
                (i > 0 && follow_line(e, axis, fixed, roots[k].u, q, -1, q - step) != 0)) {
                free(roots);
                return USM_EFAILED;
            }
        }
        free(roots);
    }
    return USM_OK;
}

/* ---- curves ---------------------------------------------------------------------- */

typedef struct half {
    double *xy, *u;
    size_t n, capxy, capu;
    usm_envelope_end end;
} half;

static int half_push(half *h, int nu, double px, double py, const double *u)
{
    if (usm_grow((void **)&h->xy, &h->capxy, 2 * (h->n + 1), sizeof(double)) != 0 ||
        usm_grow((void **)&h->u, &h->capu, (size_t)nu * (h->n + 1), sizeof(double)) != 0)
        return -1;
    h->xy[2 * h->n] = px;
    h->xy[2 * h->n + 1] = py;
    memcpy(h->u + (size_t)nu * h->n, u, sizeof(double) * (size_t)nu);
    h->n++;
    return 0;
}

/* Normalised distance of (px, py, u) to the segment a-b of a curve (u by
 * the tilt's size), in units of the tolerance for "on the curve". */
static double seg_dist(const usm_envelope *e, const double *a, const double *b, const double *ua,
                       const double *ub, double px, double py, const double *u)
{
    const double wx = e->hi[0] - e->lo[0], wy = e->hi[1] - e->lo[1];
    const double ax = a[0] / wx, ay = a[1] / wy, bx = b[0] / wx, by = b[1] / wy;
    const double qx = px / wx, qy = py / wy;
    const double dx = bx - ax, dy = by - ay, l2 = dx * dx + dy * dy;
    double t = l2 > 0 ? ((qx - ax) * dx + (qy - ay) * dy) / l2 : 0.0;
    t = fmin(1.0, fmax(0.0, t));
    const double ex = ax + t * dx - qx, ey = ay + t * dy - qy;
    /* the chord is off the curve by its sagitta, ~ l^2 kappa / 8: where the
     * curve turns sharply that is a few per cent of the chord */
    const double tol = fmax(SAME_TOL, 0.05 * sqrt(l2));
    const int k = e->m->u_theta;
    const double th = ua[k] + t * (ub[k] - ua[k]);
    const double dth = fabs(th - u[k]) / fmax(fmax(fabs(u[k]), fabs(th)), 1e-9);
    return fmax(sqrt(ex * ex + ey * ey), (fabs(u[k]) > 1e-12 ? 1e-2 * dth : 0.0)) / tol;
}

/* Whether a seed lies on a curve of its kind already traced. */
static int on_curve(const usm_envelope *e, const env_seed *s)
{
    for (size_t c = 0; c < e->ncurves; ++c) {
        const env_curve *cv = &e->curves[c];
        /* a fold is a stability change too (a multiplier passes 1 there):
         * a stability seed on a fold curve is that fold */
        if ((int)cv->pub.kind != s->kind &&
            !(s->kind == USM_ENVELOPE_STABILITY && cv->pub.kind == USM_ENVELOPE_FOLD))
            continue;
        for (size_t i = 0; i + 1 < cv->pub.npoints || (cv->pub.npoints == 1 && i == 0); ++i) {
            const size_t j = cv->pub.npoints == 1 ? i : i + 1;
            if (seg_dist(e, cv->xy + 2 * i, cv->xy + 2 * j, cv->u + (size_t)e->nu * i,
                         cv->u + (size_t)e->nu * j, s->x, s->y, s->u) < 1.0)
                return 1;
        }
    }
    return 0;
}

/* The fold's borders from the null vectors at x (scaled unknowns): b the
 * left, c the right one, by inverse iteration on r_u. */
static void fold_borders(env_problem *pb, const double *x)
{
    const int nu = pb->e->nu;
    double A[USM_MAX_NU * USM_MAX_NU], AT[USM_MAX_NU * USM_MAX_NU], v[USM_MAX_NU], w[USM_MAX_NU];
    int piv[USM_MAX_NU], pivt[USM_MAX_NU];
    set_params(pb, x);
    pb->e->m->steady_jacobian(x, &pb->p, A);
    for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nu; ++j) {
            A[i * nu + j] *= pb->uscale[j];
            AT[j * nu + i] = A[i * nu + j];
        }
    /* a tiny shift keeps the factorisation of the (nearly) singular matrix */
    double nrm = 0;
    for (int i = 0; i < nu * nu; ++i)
        nrm = fmax(nrm, fabs(A[i]));
    for (int i = 0; i < nu; ++i) {
        A[i * nu + i] += 1e-12 * nrm;
        AT[i * nu + i] += 1e-12 * nrm;
        v[i] = w[i] = 1.0 / sqrt((double)nu) * (1.0 + 0.1 * i);
    }
    if (usm_lu_factor_dense(nu, A, piv) != 0 || usm_lu_factor_dense(nu, AT, pivt) != 0)
        return; /* keep the previous borders */
    for (int it = 0; it < 3; ++it) {
        usm_lu_solve_dense(nu, A, piv, v, 1);
        usm_lu_solve_dense(nu, AT, pivt, w, 1);
        double nv = 0, nw = 0;
        for (int i = 0; i < nu; ++i) {
            nv += v[i] * v[i];
            nw += w[i] * w[i];
        }
        nv = sqrt(nv);
        nw = sqrt(nw);
        if (!(nv > 0 && nw > 0 && isfinite(nv) && isfinite(nw)))
            return;
        for (int i = 0; i < nu; ++i) {
            v[i] /= nv;
            w[i] /= nw;
        }
    }
    /* the signs kept from the previous borders: v and w take their signs
     * from c and b (c'v = b'w = 1), and the cusp coefficient w' r_uu[v, v]
     * must not change sign by a flip of w */
    double sv = 0, sw = 0;
    for (int i = 0; i < nu; ++i) {
        sv += v[i] * pb->border_c[i];
        sw += w[i] * pb->border_b[i];
    }
    for (int i = 0; i < nu; ++i) {
        pb->border_c[i] = sv < 0 ? -v[i] : v[i];
        pb->border_b[i] = sw < 0 ? -w[i] : w[i];
    }
}

/* Which parameter moves most along the curve at the seed (scaled): the
 * tangent from the Jacobian with either parameter held.  0: y last, 1: x. */
static int choose_swap(usm_envelope *e, int kind, const double *u, double px, double py,
                       const double *border_b, const double *border_c)
{
    env_problem pb;
    double scale[NMAX], x[NMAX], J[(USM_MAX_NU + 1) * NMAX];
    const int nu = e->nu, n = nu + 1, N = nu + 2;
    make_scale(e, u, kind, 0, 0, scale);
    memset(&pb, 0, sizeof pb);
    pb.e = e;
    pb.p = e->p;
    pb.kind = kind;
    pb.n = n;
    memcpy(pb.scale, scale, sizeof scale);
    memcpy(pb.uscale, scale, sizeof(double) * (size_t)nu);
    memcpy(pb.border_b, border_b, sizeof pb.border_b);
    memcpy(pb.border_c, border_c, sizeof pb.border_c);
    if (e->m->u_phidot_R >= 0)
        pb.sat_w = u[e->m->u_phidot_R];
    memcpy(x, u, sizeof(double) * (size_t)nu);
    x[nu] = px;
    x[nu + 1] = py;
    double F[USM_MAX_NU + 1];
    if (problem_residual(x, F, J, &pb) != 0)
        return 0;
    /* solve J[:, 0..n-1] t = -J[:, n] (y held: last column y) and the same
     * with x's column last: the larger |last| of the normalised tangent */
    double best[2];
    for (int s = 0; s < 2; ++s) {
        double A[(USM_MAX_NU + 1) * (USM_MAX_NU + 1)], t[USM_MAX_NU + 1];
        int piv[USM_MAX_NU + 1];
        const int keep = s == 0 ? nu : nu + 1, last = s == 0 ? nu + 1 : nu;
        for (int i = 0; i < n; ++i) {
            for (int j = 0; j < nu; ++j)
                A[i * n + j] = J[i * N + j] * scale[j];
            A[i * n + nu] = J[i * N + keep] * scale[keep];
            t[i] = -J[i * N + last] * scale[last];
        }
        if (usm_lu_factor_dense(n, A, piv) != 0) {
            best[s] = 0;
            continue;
        }
        usm_lu_solve_dense(n, A, piv, t, 1);
        double nt = 1.0;
        for (int i = 0; i < n; ++i)
            nt += t[i] * t[i];
        best[s] = isfinite(nt) ? 1.0 / sqrt(nt) : 0.0;
    }
    return best[1] > best[0];
}

/* Follow one half of a curve from the seed x0 (problem layout) in dir. */
static int follow_half(usm_envelope *e, env_problem *pb, const double *x0, int dir, half *h,
                       size_t curve_index)
{
    const int nu = e->nu;
    double px, py;
    char buf[40];
    double far = 0; /* the largest distance from the seed so far (the box's sides 1) */
    h->end = USM_ENVELOPE_END_LOST;
    if (usm_cont_start(pb->cont, x0, dir) != 0)
        return 0;
    const double *xc = usm_cont_point(pb->cont);
    env_xy(pb, xc, &px, &py);
    if (half_push(h, nu, px, py, xc) != 0)
        return -1;
    for (long steps = 0; steps < e->opt.max_points; ++steps) {
        if (pb->kind == USM_ENVELOPE_FOLD)
            fold_borders(pb, usm_cont_point(pb->cont));
        const int st = usm_cont_step(pb->cont);
        if (st != USM_CONT_STEP && st != USM_CONT_END)
            return 0;
        for (int k = 0; k < usm_cont_event_count(pb->cont); ++k) {
            const usm_cont_event *ev = usm_cont_event_at(pb->cont, k);
            const env_test *t = env_test_of(pb, ev->test);
            if (!t || ev->stop)
                continue;
            env_xy(pb, ev->x, &px, &py);
            if (t->what == TEST_CUSP) {
                if (env_add_codim2(e, "cusp", ev->x, px, py, curve_index) != 0)
                    return -1;
            } else if (t->what == TEST_BT) {
                double gap = INFINITY;
                const double g = fold_test(pb, ev->x, 1, &gap);
                if (isfinite(g) && gap <= BT_GAP &&
                    env_add_codim2(e, "bogdanov_takens", ev->x, px, py, curve_index) != 0)
                    return -1;
            } else if (t->what == TEST_FOLD_HOPF) {
                /* on the fold (lambda_1 = 1) another multiplier on the unit
                 * circle; not a jump of the maximum */
                double gap = INFINITY;
                const double g = fold_test(pb, ev->x, 0, &gap);
                if (isfinite(g) && fabs(g) <= BT_GAP &&
                    env_add_codim2(e, pair_name(USM_ENVELOPE_FOLD, USM_ENVELOPE_STABILITY, buf,
                                                sizeof buf),
                                   ev->x, px, py, curve_index) != 0)
                    return -1;
            } else if (t->what == TEST_KIND &&
                       env_add_codim2(e, pair_name(pb->kind, t->kind, buf, sizeof buf), ev->x, px,
                                  py, curve_index) != 0)
                return -1;
        }
        xc = usm_cont_point(pb->cont);
        env_xy(pb, xc, &px, &py);
        if (half_push(h, nu, px, py, xc) != 0)
            return -1;
        if (st == USM_CONT_END) {
            const usm_cont_event *ev =
                usm_cont_event_at(pb->cont, usm_cont_event_count(pb->cont) - 1);
            const env_test *t = ev ? env_test_of(pb, ev->test) : NULL;
            if (t && t->what == TEST_KIND) {
                h->end = USM_ENVELOPE_END_TILT_ZERO;
                if (env_add_codim2(e, pair_name(pb->kind, USM_ENVELOPE_TILT_ZERO, buf, sizeof buf),
                               xc, px, py, curve_index) != 0)
                    return -1;
            } else if (t && t->what == TEST_TOP)
                h->end = USM_ENVELOPE_END_RANGE;
            else {
                h->end = USM_ENVELOPE_END_BOX;
                if (t && t->what == TEST_BOX) {
                    const int k = t->side / 2;
                    const int col = pb->kind < 0 ? nu : (k == 0) == !pb->swap ? nu : nu + 1;
                    double xs[NMAX];
                    memcpy(xs, xc, sizeof(double) * (size_t)(nu + 2));
                    if (usm_cont_correct_fixed(pb->cont, xs, col,
                                               t->side % 2 == 0 ? e->lo[k] : e->hi[k]) >= 0) {
                        env_xy(pb, xs, &px, &py);
                        h->n--;
                        /* a seed on the side, left outwards: the seed alone */
                        const int again =
                            h->n > 0 && fabs(h->xy[2 * h->n - 2] - px) <=
                                            1e-12 * (e->hi[0] - e->lo[0]) &&
                            fabs(h->xy[2 * h->n - 1] - py) <= 1e-12 * (e->hi[1] - e->lo[1]);
                        if (!again && half_push(h, nu, px, py, xs) != 0)
                            return -1;
                    }
                }
            }
            return 0;
        }
        /* back at the seed, after having left it: a closed curve */
        const double dx = (px - h->xy[0]) / (e->hi[0] - e->lo[0]),
                     dy = (py - h->xy[1]) / (e->hi[1] - e->lo[1]), dist = sqrt(dx * dx + dy * dy);
        far = fmax(far, dist);
        if (far > 4.0 * e->opt.h_max) {
            if (dist < 0.5 * e->opt.h_max &&
                fabs(xc[e->m->u_theta] - h->u[e->m->u_theta]) <=
                    1e-3 * fmax(fabs(xc[e->m->u_theta]), 1e-12)) {
                h->end = USM_ENVELOPE_END_CLOSED;
                return 0;
            }
        }
        if (rescale(pb, xc) != 0)
            return 0;
    }
    h->end = USM_ENVELOPE_END_LIMIT;
    return 0;
}

/* The moduli at (px, py) of the pairs (im > 0) nearest the angles ang[0..1]
 * (the stationary root by Newton from u).  0, or -1. */
static int pair_moduli(usm_envelope *e, const double *u, double px, double py, const double *ang,
                       double *mod)
{
    usm_params q = e->p;
    usm_floquet_result fr;
    *usm_params_field(&q, e->ax[0]) = px;
    *usm_params_field(&q, e->ax[1]) = py;
    if (usm_steady_solve_from(e->steady, &q, u) != USM_OK)
        return -1;
    const usm_steady_solution *sol = usm_steady_root(e->steady, 0);
    if (!(sol->theta > 0) || usm_floquet_compute(e->fl, &q, sol, e->opt.t0, &e->opt.floquet,
                                                 &fr) != USM_OK)
        return -1;
    for (int j = 0; j < 2; ++j) {
        double best = INFINITY;
        mod[j] = NAN;
        for (int k = 0; k < fr.n; ++k) {
            if (fr.cyclic[k] || !(fr.im[k] > 0))
                continue;
            const double d = fabs(atan2(fr.im[k], fr.re[k]) - ang[j]);
            if (d < best) {
                best = d;
                mod[j] = hypot(fr.re[k], fr.im[k]);
            }
        }
        if (!isfinite(mod[j]))
            return -1;
    }
    return 0;
}

/* Where a stability curve is lost at the point (px, py, u) and two pairs of
 * multipliers are on the unit circle there, the boundary max |lambda| = 1
 * has a corner: the curve of the first pair (the one at 1 at the point
 * `before`, a few steps back) gives way to that of the second.  The
 * second's leg leaves along |lambda_b| = 1 to the side where |lambda_a| < 1;
 * its seed is CORNER_STEP along it, the stationary root by Newton from u.
 * 1 with the seed in (su, *sx, *sy), 2 a corner whose other leg leaves the
 * box at once, 0 when the point is no corner, -1 when an evaluation failed. */
static int stability_corner(usm_envelope *e, const double *u, double px, double py,
                            const double *ub, double bx, double by, double *su, double *sx,
                            double *sy)
{
    usm_params q = e->p;
    usm_steady_solution sol;
    usm_floquet_result fr;
    double ang[2], modb[2], g[2][2];
    int np = 0;
    *usm_params_field(&q, e->ax[0]) = px;
    *usm_params_field(&q, e->ax[1]) = py;
    memset(&sol, 0, sizeof sol);
    memcpy(sol.u, u, sizeof(double) * (size_t)e->nu);
    usm_steady_evaluate(e->m, &q, &sol);
    if (!(sol.theta > 0) ||
        usm_floquet_compute(e->fl, &q, &sol, e->opt.t0, &e->opt.floquet, &fr) != USM_OK)
        return 0;
    for (int k = 0; k < fr.n && np < 3; ++k)
        if (!fr.cyclic[k] && fr.im[k] > 0 &&
            fabs(hypot(fr.re[k], fr.im[k]) - 1.0) <= CORNER_TOL) {
            if (np < 2)
                ang[np] = atan2(fr.im[k], fr.re[k]);
            np++;
        }
    if (np != 2)
        return 0;
    /* a = the pair that was at 1 on the way in */
    if (pair_moduli(e, ub, bx, by, ang, modb) != 0)
        return -1;
    if (modb[1] > modb[0]) {
        const double t = ang[0];
        ang[0] = ang[1];
        ang[1] = t;
    }
    const double w[2] = {e->hi[0] - e->lo[0], e->hi[1] - e->lo[1]}, h = 1e-6;
    for (int k = 0; k < 2; ++k) {
        double mp[2], mm[2];
        const double dx = k == 0 ? h * w[0] : 0, dy = k == 1 ? h * w[1] : 0;
        if (pair_moduli(e, u, px + dx, py + dy, ang, mp) != 0 ||
            pair_moduli(e, u, px - dx, py - dy, ang, mm) != 0)
            return -1;
        for (int j = 0; j < 2; ++j)
            g[j][k] = (mp[j] - mm[j]) / (2 * h);
    }
    /* along |lambda_b| = 1, to where |lambda_a| falls */
    double t[2] = {-g[1][1], g[1][0]};
    const double nt = hypot(t[0], t[1]);
    if (!(nt > 0))
        return -1;
    if (t[0] * g[0][0] + t[1] * g[0][1] > 0) {
        t[0] = -t[0];
        t[1] = -t[1];
    }
    *sx = px + CORNER_STEP * t[0] / nt * w[0];
    *sy = py + CORNER_STEP * t[1] / nt * w[1];
    if (*sx < e->lo[0] || *sx > e->hi[0] || *sy < e->lo[1] || *sy > e->hi[1])
        return 2;
    *usm_params_field(&q, e->ax[0]) = *sx;
    *usm_params_field(&q, e->ax[1]) = *sy;
    if (usm_steady_solve_from(e->steady, &q, u) != USM_OK)
        return -1;
    memcpy(su, usm_steady_root(e->steady, 0)->u, sizeof(double) * (size_t)e->nu);
    return 1;
}

/* Trace the curve through seed s (both directions) and append it. */
static int trace_curve(usm_envelope *e, const env_seed *s)
{
    const int nu = e->nu;
    env_problem pb;
    double scale[NMAX], x0[NMAX];
    half h[2];
    memset(h, 0, sizeof h);
    double bb[USM_MAX_NU] = {0}, cc[USM_MAX_NU] = {0};
    if (s->kind == USM_ENVELOPE_FOLD) {
        env_problem tmp;
        double xs[NMAX];
        make_scale(e, s->u, s->kind, 0, 0, scale);
        memset(&tmp, 0, sizeof tmp);
        tmp.e = e;
        tmp.p = e->p;
        tmp.kind = s->kind;
        memcpy(tmp.uscale, scale, sizeof(double) * (size_t)nu);
        memcpy(xs, s->u, sizeof(double) * (size_t)nu);
        xs[nu] = s->x;
        xs[nu + 1] = s->y;
        fold_borders(&tmp, xs);
        memcpy(bb, tmp.border_b, sizeof bb);
        memcpy(cc, tmp.border_c, sizeof cc);
    }
    const int swap = choose_swap(e, s->kind, s->u, s->x, s->y, bb, cc);
    make_scale(e, s->u, s->kind, 0, swap, scale);
    if (problem_setup(&pb, e, s->kind, -1, 0.0, swap, scale) != 0) {
        problem_free(&pb);
        return -1;
    }
    memcpy(pb.border_b, bb, sizeof bb);
    memcpy(pb.border_c, cc, sizeof cc);
    if (e->m->u_phidot_R >= 0)
        pb.sat_w = s->u[e->m->u_phidot_R];
    memcpy(x0, s->u, sizeof(double) * (size_t)nu);
    x0[nu] = swap ? s->y : s->x;
    x0[nu + 1] = swap ? s->x : s->y;
    int rc = 0;
    const size_t index = e->ncurves;
    for (int d = 0; d < 2 && rc == 0; ++d) {
        memcpy(pb.scale, scale, sizeof scale);
        usm_cont_set_scale(pb.cont, pb.scale);
        rc = follow_half(e, &pb, x0, d == 0 ? 1 : -1, &h[d], index);
        if (d == 0 && h[0].end == USM_ENVELOPE_END_CLOSED)
            break;
    }
    problem_free(&pb);
    /* a stability curve lost at a corner: named, and the other leg seeded */
    int ncorner = 0;
    env_seed corner[2];
    for (int d = 0; d < 2 && rc == 0; ++d) {
        if (s->kind != USM_ENVELOPE_STABILITY || h[d].end != USM_ENVELOPE_END_LOST || h[d].n < 6)
            continue;
        const size_t i = h[d].n - 1, j = h[d].n - 6;
        env_seed *c = &corner[ncorner];
        memset(c, 0, sizeof *c);
        const int k = stability_corner(e, h[d].u + (size_t)nu * i, h[d].xy[2 * i],
                                       h[d].xy[2 * i + 1], h[d].u + (size_t)nu * j, h[d].xy[2 * j],
                                       h[d].xy[2 * j + 1], c->u, &c->x, &c->y);
        if (k <= 0)
            continue;
        char buf[40];
        h[d].end = USM_ENVELOPE_END_CORNER;
        c->kind = USM_ENVELOPE_STABILITY;
        /* a corner met again (from its other leg): its legs are traced */
        int known = 0;
        for (size_t q = 0; q < e->ncodim2; ++q)
            known |= strcmp(e->codim2[q].type, "stability/stability") == 0 &&
                     fabs(e->codim2[q].x - h[d].xy[2 * i]) <= 1e-4 * (e->hi[0] - e->lo[0]) &&
                     fabs(e->codim2[q].y - h[d].xy[2 * i + 1]) <= 1e-4 * (e->hi[1] - e->lo[1]);
        if (!known && k == 1)
            ncorner++;
        if (!known && env_add_codim2(e, pair_name(s->kind, s->kind, buf, sizeof buf),
                                     h[d].u + (size_t)nu * i, h[d].xy[2 * i], h[d].xy[2 * i + 1],
                                     e->ncurves) != 0)
            rc = -1;
    }
    if (rc == 0 && h[0].n + h[1].n > 0) {
        env_curve cv;
        memset(&cv, 0, sizeof cv);
        const size_t n0 = h[0].n, n1 = h[1].n > 0 ? h[1].n - 1 : 0; /* the seed once */
        const size_t n = n0 + n1;
        cv.xy = malloc(2 * n * sizeof(double));
        cv.u = malloc((size_t)nu * n * sizeof(double));
        if (!cv.xy || !cv.u ||
            usm_grow((void **)&e->curves, &e->curvecap, e->ncurves + 1, sizeof *e->curves) != 0) {
            free(cv.xy);
            free(cv.u);
            rc = -1;
        } else {
            size_t k = 0;
            for (size_t i = n1; i >= 1; --i, ++k) { /* the second half reversed, seed excluded */
                memcpy(cv.xy + 2 * k, h[1].xy + 2 * i, 2 * sizeof(double));
                memcpy(cv.u + (size_t)nu * k, h[1].u + (size_t)nu * i, (size_t)nu * sizeof(double));
            }
            for (size_t i = 0; i < n0; ++i, ++k) {
                memcpy(cv.xy + 2 * k, h[0].xy + 2 * i, 2 * sizeof(double));
                memcpy(cv.u + (size_t)nu * k, h[0].u + (size_t)nu * i, (size_t)nu * sizeof(double));
            }
            cv.pub.kind = (usm_envelope_kind)s->kind;
            cv.pub.npoints = n;
            cv.pub.xy = cv.xy;
            cv.pub.u = cv.u;
            cv.pub.nu = nu;
            cv.pub.end[0] = h[1].n > 0 ? h[1].end : h[0].end;
            cv.pub.end[1] = h[0].end;
            if (h[0].end == USM_ENVELOPE_END_CLOSED)
                cv.pub.end[0] = USM_ENVELOPE_END_CLOSED;
            e->curves[e->ncurves++] = cv;
        }
    }
    for (int d = 0; d < 2; ++d) {
        free(h[d].xy);
        free(h[d].u);
    }
    /* the other leg of each corner, traced at once: its seed lies within a
     * chord's sagitta tolerance of this curve, so on_curve would drop it */
    for (int k = 0; k < ncorner && rc == 0; ++k)
        rc = trace_curve(e, &corner[k]);
    return rc;
}

/* ---- the run --------------------------------------------------------------------- */

static int check_options(usm_envelope *e, const usm_params *p, const usm_envelope_options *o)
{
    const usm_envelope_axis *axes[2] = {&o->x, &o->y};
    const char *fields[2] = {"x", "y"};
    for (int k = 0; k < 2; ++k) {
        if (!axes[k]->name) {
            snprintf(e->msg, sizeof e->msg, "%s: no parameter given", fields[k]);
            return USM_EINPUT;
        }
        if (!(e->ax[k] = usm_params_find(axes[k]->name))) {
            snprintf(e->msg, sizeof e->msg, "%s: unknown parameter '%s'", fields[k],
                     axes[k]->name);
            return USM_EINPUT;
        }
        if (!(isfinite(axes[k]->lo) && isfinite(axes[k]->hi) && axes[k]->lo < axes[k]->hi)) {
            snprintf(e->msg, sizeof e->msg, "%s: the range %s %g .. %g needs LO < HI", fields[k],
                     axes[k]->name, axes[k]->lo, axes[k]->hi);
            return USM_EINPUT;
        }
        e->lo[k] = axes[k]->lo;
        e->hi[k] = axes[k]->hi;
        e->col[k] = usm_param_index(e->ax[k]);
    }
    if (e->ax[0] == e->ax[1]) {
        snprintf(e->msg, sizeof e->msg, "y: the same parameter as x (%s)", o->x.name);
        return USM_EINPUT;
    }
    if (o->lines < 0 || o->lines > 100 || o->nodes < 2 || o->nodes > 1000 ||
        !(o->h_max > 0 && o->h_max <= 0.5) || o->max_points < 10 || o->raster < 4 ||
        o->raster > 2000) {
        snprintf(e->msg, sizeof e->msg,
                 "options: lines 0..100, nodes 2..1000, h_max in (0, 0.5], max_points >= 10, "
                 "raster 4..2000");
        return USM_EINPUT;
    }
    /* every corner must be a valid parameter point */
    for (int c = 0; c < 4; ++c) {
        usm_params q = *p;
        *usm_params_field(&q, e->ax[0]) = c & 1 ? e->hi[0] : e->lo[0];
        *usm_params_field(&q, e->ax[1]) = c & 2 ? e->hi[1] : e->lo[1];
        char msg[USM_MSG_LEN];
        if (usm_params_check(&q, e->m, msg) != USM_OK) {
            snprintf(e->msg, sizeof e->msg, "%s", msg);
            return USM_EINPUT;
        }
    }
    return USM_OK;
}

int usm_envelope_run(usm_envelope *e, const usm_params *p, const usm_envelope_options *opt)
{
    env_clear_result(e);
    e->msg[0] = '\0';
    e->opt = *opt;
    e->p = *p;
    int rc = check_options(e, p, opt);
    if (rc != USM_OK)
        return rc;
    if (e->m->imperfect) {
        rc = env_periodic_curves(e);
        return rc != USM_OK ? rc : env_regions(e);
    }
    /* seed lines: the edges and `lines` interior lines, both directions */
    for (int axis = 0; axis < 2; ++axis) {
        const int other = 1 - axis;
        for (int j = 0; j < opt->lines + 2; ++j) {
            const double fixed =
                e->lo[other] + (e->hi[other] - e->lo[other]) * j / (opt->lines + 1);
            rc = seed_line(e, axis, fixed);
            if (rc != USM_OK) {
                if (!e->msg[0])
                    snprintf(e->msg, sizeof e->msg, "out of memory for the seeds");
                return rc;
            }
        }
    }
    /* the kinds in order: folds before the stability changes they explain */
    for (int kind = 0; kind < USM_ENVELOPE_NKINDS; ++kind)
        for (size_t k = 0; k < e->nseeds; ++k) {
            if (e->seeds[k].kind != kind)
                continue;
            if (on_curve(e, &e->seeds[k])) {
                e->seeds_dropped++;
                continue;
            }
            if (trace_curve(e, &e->seeds[k]) != 0) {
                snprintf(e->msg, sizeof e->msg, "out of memory for the curves");
                return USM_EFAILED;
            }
        }
    return env_regions(e);
}
