/* Stationary solutions (paper, section 3 and section 5).
 *
 * Math: on the ansatz (3.1) the frame-A components x1, y1 of Euler's equations
 * give two residuals r(theta, alpha) = 0 (3.5); the slip model adds the rotor's
 * moment balance, with the rotor speed phidot_R as third unknown.
 *
 * Search, from the parameters alone:
 *  1. Tilt.  At fixed tilt theta the x1/y1 rows are linear in
 *     (m0 cos alpha, m0 sin alpha): the excitation is the only place alpha and
 *     m0 enter.  The generated seed kernel, called with m0 = 1, solves them for
 *     the torque vector A(theta) the excitation must supply; theta is
 *     stationary where |A(theta)| = m0.  The search function is
 *         g(theta) = log |A(theta)| - log m0,
 *     a monotone transform of the kernel's amplitude_mismatch
 *     |A|^2/m0^2 - 1 with the same roots and extrema that neither overflows
 *     nor underflows for extreme m0, c_r, F0.  It is sampled on a log-spaced
 *     grid of the tilt range, refined geometrically towards both ends (cells
 *     halving 30 times, down to ~4e-11 relative).  Every root is then found
 *     by one of two rules:
 *       a. a sign change of g between neighbouring samples: GSL's Brent root
 *          solver refines it;
 *       b. a discrete extremum pointing towards zero (a sample lower than
 *          both neighbours with all three positive, or higher with all three
 *          negative): GSL's Brent minimiser locates the extremum of g between
 *          the neighbours; where it crosses zero the cell pair holds two
 *          roots, bracketed on either side of it; where it touches zero
 *          within 1e-13 the double root is polished from there.
 *     Why nothing is missed: let g be continuous with at most one extremum in
 *     any two neighbouring cells.  A cell holding an odd number of roots shows
 *     a sign change (rule a).  A cell, or a pair of neighbouring cells, whose
 *     ends have the same sign but which holds roots holds an extremum of the
 *     opposite sign between them; being alone in the window, that extremum
 *     makes the sample nearest to it lower (higher) than both neighbours, so
 *     rule b sees it, and the minimiser, started inside the window, finds it.
 *     Limit: two extrema of g within two neighbouring cells (3.9 % in theta
 *     each at the default 500 samples), i.e. features of g narrower than the
 *     grid, can hide a pair of roots, and so can a pair inside one of the
 *     two outermost cells (~4e-11 relative).  A pair closer than about 1e-8
 *     relative (where g's extremum is within rounding of zero: the
 *     resolution of a minimum in floating point is sqrt(eps)) is polished
 *     from the extremum and reported as one root, or, if hybridsj does not
 *     converge at the near-double root, not at all.
 *  2. Rotor speed (slip model).  Given theta, the rotor balance needs the
 *     friction coefficient mu_needed = F_t/F_n of the seed, and
 *     v_rel = v_0 + R* phidot_R is affine in the rotor speed, so every root is
 *     a slip speed with mu(v_rel) = mu_needed.  The friction law is only
 *     assumed continuous with a continuous slope (the generated friction
 *     kernel's): its extrema are located as sign changes of the slope on a
 *     symmetric log grid of |v_rel| (40 samples per decade from
 *     min(1e-12, 1e-6/kappa) to max(1e6, 1e6/kappa) m/s, plus 0; a cell whose
 *     end slopes agree but whose values move against them holds two extrema
 *     and is bisected), each refined by Brent on the slope.  Between
 *     neighbouring extrema (and 0) mu is monotone, so each piece holds at most
 *     one root, bracketed by the values at its ends; the two outer pieces are
 *     assumed monotone beyond the grid and searched by doubling out to
 *     |v_rel| = 1e300 m/s.  Limit: extrema of mu closer than one grid step
 *     (5.9 % in v_rel) that cancel in the slope's sign, and non-monotone
 *     behaviour beyond the grid, are not seen.  The law's supremum and
 *     infimum are taken over the grid, the extrema and the far ends; only
 *     when mu_needed lies outside them does the solver say the load exceeds
 *     what the friction law can transmit.
 *  3. GSL's hybridsj polishes (theta, alpha[, phidot_R]) on the full residual
 *     with the generated Jacobian.  A root is reported only when hybridsj
 *     converged and each residual row is below 1e-10 m0 plus the rounding of
 *     its terms (16 eps sum_j |dr_i/du_j| |u_j|: under a large load the
 *     rotor row's terms are far larger than m0).
 * Each distinct (theta, alpha, phidot_R) is its own root.  Roots are ordered
 * by tilt; roots at the same tilt (several rotor speeds) by increasing
 * |v_rel|, then by increasing phidot_R.
 */
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_min.h>
#include <gsl/gsl_multiroots.h>

#include "core/grow.h"
#include "core/root.h"
#include "usm.h"
#include "steady_cell.h"

#define TWO_PI 6.283185307179586476925286766559
#define END_REFINEMENTS 30      /* halvings of the end cells of the tilt grid */
#define TOUCH_TOL 1e-13         /* |g| of an extremum treated as a double root */
#define V_PER_DECADE 40         /* friction grid density */
#define V_FAR 1e300             /* outermost slip speed searched [m/s] */
#define MAX_BISECT_DEPTH 30     /* subdivision of a friction cell hiding extrema */
#define FAR_CAP 1100            /* kept law values on an outer piece (2^1037 spans V_FAR) */
/* |A|^2 decides g's sign alone between these (no underflow or overflow) and
 * at least Q_MARGIN (relative) away from m0^2 */
#define Q_MIN 1e-290
#define Q_MAX 1e300
#define Q_MARGIN 1e-10

/* A root and its sort key: the refined tilt it was seeded from (shared by the
 * rotor speeds found at one tilt, unlike the polished tilts). */
typedef struct root_entry {
    usm_steady_solution sol;
    double key;
} root_entry;

struct usm_steady {
    const usm_model *m;
    usm_params p;      /* parameters of the current solve */
    usm_params p_unit; /* the same with m0 = 1: the seed returns the torque A(theta) */
    gsl_multiroot_fdfsolver *solver;
    usm_root *root;
    gsl_min_fminimizer *fmin;
    gsl_vector *u0;
    size_t count, cap;
    root_entry *roots;
    /* tilt grid (kept while the options do not change) and its samples in
     * the current solve: the seed's torque components, g where computed */
    double *th, *ca, *sa, *q, *g; /* q = |A|^2 (NaN outside [Q_MIN, Q_MAX]) */
    double *trig;                 /* sin, cos, tan of each th (kept with the grid) */
    unsigned char *gdone;
    signed char *qsign;           /* g's sign from q, 0 when undecided */
    int m2_ok;                    /* m0^2 in [Q_MIN, Q_MAX] */
    size_t grid_cap, ngrid, nsampled;
    double grid_key[3];
    double m2; /* m0^2 */
    usm_steady_warm_outcome warm;
    /* friction law of the current solve (slip model): extrema and 0, ascending */
    double *brk;
    size_t nbrk, brk_cap;
    int law_ready;
    double mu_sup, mu_inf;
    /* The analysis is kept between solves whose friction law is the same:
     * dep[k] = 1 where parameter k enters the law (or the analysis' grid). */
    unsigned char dep[USM_NPARAMS];
    int dep_ready, law_kept;
    usm_params law_p;  /* parameters of the kept analysis */
    /* mu at the doubling points of the two outer pieces (slip_speeds), in
     * order, as far as a solve needed them: they depend on the law alone, and
     * the scan out to V_FAR (~1000 points on a side without a root) was most
     * of a slip model's solve */
    double far_mu[2][FAR_CAP];
    int far_n[2];
    /* running maximum and minimum of far_mu over its first far_tame entries,
     * all finite and at most 1e300 in size (there mu - mu_needed is finite
     * and has the sign of the comparison) */
    double far_max[2][FAR_CAP], far_min[2][FAR_CAP];
    int far_tame[2];
    char msg[USM_MSG_LEN];
};

void usm_steady_options_default(usm_steady_options *opt)
{
    opt->theta_min = 1e-9;
    opt->theta_max = 0.2;
    opt->grid = 500;
    opt->xtol = 1e-13;
}

usm_steady *usm_steady_alloc(const usm_model *m)
{
    usm_steady *s = calloc(1, sizeof *s);
    if (!s)
        return NULL;
    s->m = m;
    s->solver = gsl_multiroot_fdfsolver_alloc(gsl_multiroot_fdfsolver_hybridsj, (size_t)m->nu);
    s->root = usm_root_alloc();
    s->fmin = gsl_min_fminimizer_alloc(gsl_min_fminimizer_brent);
    s->u0 = gsl_vector_alloc((size_t)m->nu);
    if (!s->solver || !s->root || !s->fmin || !s->u0) {
        usm_steady_free(s);
        return NULL;
    }
    return s;
}

void usm_steady_free(usm_steady *s)
{
    if (!s)
        return;
    if (s->solver)
        gsl_multiroot_fdfsolver_free(s->solver);
    usm_root_free(s->root);
    if (s->fmin)
        gsl_min_fminimizer_free(s->fmin);
    if (s->u0)
        gsl_vector_free(s->u0);
    free(s->roots);
    free(s->th);
    free(s->trig);
    free(s->ca);
    free(s->sa);
    free(s->g);
    free(s->gdone);
    free(s->q);
    free(s->qsign);
    free(s->brk);
    free(s);
}

size_t usm_steady_count(const usm_steady *s) { return s->count; }

const usm_steady_solution *usm_steady_root(const usm_steady *s, size_t i)
{
    return i < s->count ? &s->roots[i].sol : NULL;
}

const char *usm_steady_message(const usm_steady *s) { return s->msg; }

/* A number for a message: never "inf" or "nan". */
/* A message of the solver; one that does not fit in USM_MSG_LEN ends in "..."
 * so that a cut is visible rather than silent. */
#if defined(__GNUC__)
__attribute__((format(printf, 2, 3)))
#endif
static void steady_msg(usm_steady *s, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    const int n = vsnprintf(s->msg, USM_MSG_LEN, fmt, ap);
    va_end(ap);
    if (n >= USM_MSG_LEN)
        memcpy(s->msg + USM_MSG_LEN - 4, "...", 4);
}

static const char *fmt_num(char buf[32], double x, const char *fmt)
{
    if (isfinite(x))
        snprintf(buf, 32, fmt, x);
    else if (isnan(x))
        snprintf(buf, 32, "an undefined value");
    else
        snprintf(buf, 32, "%s", x > 0 ? "more than 1.8e308" : "less than -1.8e308");
    return buf;
}

/* ---- GSL adaptors ---------------------------------------------------------- */

static int residual_f(const gsl_vector *u, void *ctx, gsl_vector *r)
{
    const usm_steady *s = ctx;
    double out[USM_MAX_NU];
    s->m->steady_residual(u->data, &s->p, out);
    for (int i = 0; i < s->m->nu; ++i) {
        if (!isfinite(out[i]))
            return GSL_EBADFUNC;
        gsl_vector_set(r, (size_t)i, out[i]);
    }
    return GSL_SUCCESS;
}

static int residual_df(const gsl_vector *u, void *ctx, gsl_matrix *J)
{
    const usm_steady *s = ctx;
    double out[USM_MAX_NU * USM_MAX_NU];
    const int nu = s->m->nu;
    s->m->steady_jacobian(u->data, &s->p, out);
    for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nu; ++j) {
            if (!isfinite(out[i * nu + j]))
                return GSL_EBADFUNC;
            gsl_matrix_set(J, (size_t)i, (size_t)j, out[i * nu + j]);
        }
    return GSL_SUCCESS;
}

static int residual_fdf(const gsl_vector *u, void *ctx, gsl_vector *r, gsl_matrix *J)
{
    int status = residual_f(u, ctx, r);
    return status ? status : residual_df(u, ctx, J);
}

/* |A(theta)|: the excitation torque that holds tilt theta. */
static double needed_torque(const usm_steady *s, double theta)
{
    double out[USM_SEED_COUNT];
    s->m->steady_seed(theta, &s->p_unit, out);
    return hypot(out[USM_SEED_COS_ALPHA], out[USM_SEED_SIN_ALPHA]);
}

/* g(theta) = log |A(theta)| - log m0 (NaN or infinite where A is). */
static double tilt_g(double theta, void *ctx)
{
    const usm_steady *s = ctx;
    return log(needed_torque(s, theta)) - log(s->p.m0);
}

/* sign * g(exp(x)): the minimiser works in log theta, like the grid. */
typedef struct extremum_ctx {
    usm_steady *s;
    double sign;
} extremum_ctx;

static double tilt_g_log(double x, void *ctx)
{
    const extremum_ctx *c = ctx;
    return c->sign * tilt_g(exp(x), c->s);
}

/* Residual scale: torques are compared with the excitation amplitude. */
static double residual_scale(const usm_params *p)
{
    return p->m0 > 0 ? p->m0 : 1.0;
}

/* ---- one-dimensional root refinement ---------------------------------------- */

/* Root of f in [lo, hi] where f changes sign (a zero end is the root), by
 * the shared locator (core/root.h).  exact: flo and fhi are f's own values
 * at the ends, bit for bit, and are not evaluated again; else (values from
 * another computation of the same quantity) f is evaluated there afresh. */
static int refine_root(usm_steady *s, usm_root_fn f, void *ctx, double lo, double hi,
                       double flo, double fhi, int exact, double *root)
{
    static const usm_root_stop stop = {DBL_MIN, 1e-15, 200};
    if (flo == 0) {
        *root = lo;
        return 0;
    }
    if (fhi == 0) {
        *root = hi;
        return 0;
    }
    return exact ? usm_root_brent(s->root, f, ctx, lo, hi, flo, fhi, &stop, root)
                 : usm_root_brent_eval(s->root, f, ctx, lo, hi, &stop, root);
}

/* ---- friction law (slip model) --------------------------------------------- */

static double law_mu(const usm_steady *s, double v)
{
    double out[USM_FRICTION_COUNT];
    s->m->friction(v, &s->p, out);
    return out[USM_FRICTION_MU];
}

static double law_slope(double v, void *ctx)
{
    const usm_steady *s = ctx;
    double out[USM_FRICTION_COUNT];
    s->m->friction(v, &s->p, out);
    return out[USM_FRICTION_SLOPE];
}

typedef struct gap_ctx {
    const usm_steady *s;
    double mu_needed;
} gap_ctx;

static double mu_gap(double v, void *ctx)
{
    const gap_ctx *c = ctx;
    return law_mu(c->s, v) - c->mu_needed;
}

static int sgn(double x) { return (x > 0) - (x < 0); }

static int add_break(usm_steady *s, double v)
{
    if (usm_grow((void **)&s->brk, &s->brk_cap, s->nbrk + 1, sizeof *s->brk) != 0)
        return -1;
    s->brk[s->nbrk++] = v;
    return 0;
}

static void note_mu(usm_steady *s, double mu)
{
    if (isfinite(mu)) {
        s->mu_sup = fmax(s->mu_sup, mu);
        s->mu_inf = fmin(s->mu_inf, mu);
    }
}

/* Extrema of mu in the cell [a, b] (slope signs da, db, values ma, mb). */
static int scan_cell(usm_steady *s, double a, double b, double ma, double mb, int da, int db,
                     int depth)
{
    if (da != 0 && db != 0 && da != db) {
        double e;
        if (refine_root(s, law_slope, s, a, b, law_slope(a, s), law_slope(b, s), 1, &e) == 0) {
            note_mu(s, law_mu(s, e));
            return add_break(s, e);
        }
        return 0;
    }
    /* Equal end slopes, but the values move against them: an even number of
     * extrema inside; bisect until they separate. */
    const int dir = da ? da : db;
    if (dir == 0 || sgn(mb - ma) != -dir || depth >= MAX_BISECT_DEPTH)
        return 0;
    const double c = 0.5 * (a + b), mc = law_mu(s, c);
    const int dc = sgn(law_slope(c, s));
    note_mu(s, mc);
    if (scan_cell(s, a, c, ma, mc, da, dc ? dc : da, depth + 1) != 0)
        return -1;
    return scan_cell(s, c, b, mc, mb, dc ? dc : db, db, depth + 1);
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The monotone pieces of the friction law: its extrema and 0, ascending, and
 * the law's supremum and infimum.  Depends only on the parameters. */
static int friction_analyse(usm_steady *s)
{
    s->nbrk = 0;
    s->far_n[0] = s->far_n[1] = 0;
    s->far_tame[0] = s->far_tame[1] = 0;
    s->mu_sup = -INFINITY;
    s->mu_inf = INFINITY;
    const double kappa = s->p.kappa;
    const double v_lo = fmin(1e-12, 1e-6 / kappa), v_hi = fmax(1e6, 1e6 / kappa);
    const int n = (int)ceil(log10(v_hi / v_lo) * V_PER_DECADE);
    const double step = log(v_hi / v_lo) / n;
    for (int side = -1; side <= 1; side += 2) {
        /* from 0 outwards: 0, v_lo, ..., v_hi on this side */
        double a = 0, ma = law_mu(s, 0);
        int da = sgn(law_slope(0, s));
        note_mu(s, ma);
        for (int i = 0; i <= n; ++i) {
            const double b = side * v_lo * exp(step * i), mb = law_mu(s, b);
            const int db = sgn(law_slope(b, s));
            note_mu(s, mb);
            if (isfinite(ma) && isfinite(mb)) {
                /* scan in increasing v_rel */
                int rc = side > 0 ? scan_cell(s, a, b, ma, mb, da, db, 0)
                                  : scan_cell(s, b, a, mb, ma, db, da, 0);
                if (rc != 0)
                    return -1;
            }
            a = b;
            ma = mb;
            if (db != 0)
                da = db;
        }
        note_mu(s, law_mu(s, side * V_FAR));
    }
    if (add_break(s, 0.0) != 0)
        return -1;
    qsort(s->brk, s->nbrk, sizeof *s->brk, cmp_double);
    s->law_ready = 1;
    s->law_kept = 1;
    s->law_p = s->p;
    return 0;
}

/* Which parameters the friction law depends on, by probing the generated
 * kernel: parameter k is a dependency when changing it changes a bit of the
 * law's value or slope at any of 200 slip speeds from 1e-15 to 1e9 m/s of
 * either sign, at the actual parameters or at a generic positive point (so
 * that a factor that happens to vanish, mu0 = 0, does not hide kappa).  The
 * law is a closed-form expression in the parameters, so one that enters it
 * changes it at generic points.  A non-finite value anywhere makes every
 * parameter a dependency (the analysis is then never reused).  kappa sets
 * the analysis' grid and is always one. */
static void friction_deps(usm_steady *s)
{
    double v[200];
    for (int i = 0; i < 100; ++i) {
        v[2 * i] = pow(10.0, -15.0 + 24.0 * i / 99.0) * (1.0 + 0.013 * i);
        v[2 * i + 1] = -v[2 * i] * 1.07;
    }
    usm_params base[2];
    base[0] = base[1] = s->p;
    for (int k = 0; k < USM_NPARAMS; ++k)
        *usm_params_field(&base[1], &usm_param_table[k]) = 0.7317 + 0.1193 * k;
    memset(s->dep, 0, sizeof s->dep);
    for (int b = 0; b < 2; ++b) {
        double ref[200][USM_FRICTION_COUNT];
        for (int i = 0; i < 200; ++i) {
            s->m->friction(v[i], &base[b], ref[i]);
            if (!isfinite(ref[i][USM_FRICTION_MU]) || !isfinite(ref[i][USM_FRICTION_SLOPE])) {
                memset(s->dep, 1, sizeof s->dep);
                s->dep_ready = 1;
                return;
            }
        }
        for (int k = 0; k < USM_NPARAMS; ++k) {
            usm_params q = base[b];
            double *f = usm_params_field(&q, &usm_param_table[k]);
            *f = *f * 1.371 + 0.0917;
            for (int i = 0; i < 200 && !s->dep[k]; ++i) {
                double out[USM_FRICTION_COUNT];
                s->m->friction(v[i], &q, out);
                s->dep[k] = memcmp(out, ref[i], sizeof out) != 0;
            }
        }
    }
    s->dep[USM_P_kappa] = 1;
    s->dep_ready = 1;
}

/* Whether the kept friction analysis holds for the current parameters. */
static int law_still_holds(usm_steady *s)
{
    if (!s->law_kept || !s->m->friction)
        return 0;
    if (!s->dep_ready)
        friction_deps(s);
    for (int k = 0; k < USM_NPARAMS; ++k) {
        const usm_param_info *info = &usm_param_table[k];
        if (s->dep[k] && usm_params_get(&s->p, info) != usm_params_get(&s->law_p, info))
            return 0;
    }
    return 1;
}

/* Every slip speed v with mu(v) = mu_needed: at most one per monotone piece. */
static int slip_speeds(usm_steady *s, double mu_needed, double *v, int vmax)
{
    gap_ctx c = {s, mu_needed};
    int nv = 0;
    for (size_t j = 0; j + 1 < s->nbrk && nv < vmax; ++j) {
        double lo = s->brk[j], hi = s->brk[j + 1], flo = mu_gap(lo, &c), fhi = mu_gap(hi, &c);
        if (!isfinite(flo) || !isfinite(fhi) || sgn(flo) * sgn(fhi) > 0)
            continue;
        if (refine_root(s, mu_gap, &c, lo, hi, flo, fhi, 1, &v[nv]) == 0)
            ++nv;
    }
    /* the outer pieces, monotone out to +-V_FAR */
    for (int side = -1; side <= 1 && nv < vmax; side += 2) {
        const double b = side < 0 ? s->brk[0] : s->brk[s->nbrk - 1];
        const double fb = mu_gap(b, &c);
        if (!isfinite(fb))
            continue;
        if (fb == 0) {
            v[nv++] = b;
            continue;
        }
        double d = fmax(fabs(b), 1e-12), prev = b, fprev = fb;
        const int si = side > 0;
        /* the kept values first, in a tight loop: skip those the loop below
         * would pass over (finite, of fb's sign); doubling is exact, so d
         * and x are those of the loop */
        const double *mk = s->far_mu[si];
        int k = 0;
        if (fabs(mu_needed) <= 1e300) {
            /* among the tame entries: the first with mk >= mu_needed (fb < 0)
             * or mk <= mu_needed (fb > 0), by bisection on the running
             * extremum; the loops below go on from there */
            const double *ext = fb > 0 ? s->far_min[si] : s->far_max[si];
            int lo = 0, hi = s->far_tame[si]; /* the answer lies in [lo, hi] */
            while (lo < hi) {
                const int mid = lo + (hi - lo) / 2;
                if (fb > 0 ? ext[mid] <= mu_needed : ext[mid] >= mu_needed)
                    hi = mid;
                else
                    lo = mid + 1;
            }
            k = lo;
        }
        if (fb > 0)
            while (k < s->far_n[si] && mk[k] - mu_needed > 0 && isfinite(mk[k] - mu_needed))
                ++k;
        else
            while (k < s->far_n[si] && mk[k] - mu_needed < 0 && isfinite(mk[k] - mu_needed))
                ++k;
        if (k > 0) {
            prev = b + side * ldexp(d, k - 1);
            fprev = mk[k - 1] - mu_needed;
            d = ldexp(d, k);
        }
        for (; fabs(b) + d <= V_FAR; ++k) {
            const double x = b + side * d;
            double mx;
            if (k < s->far_n[si])
                mx = s->far_mu[si][k];
            else {
                mx = law_mu(s, x);
                if (k == s->far_n[si] && k < FAR_CAP) {
                    s->far_mu[si][k] = mx;
                    s->far_n[si] = k + 1;
                    if (k == s->far_tame[si] && fabs(mx) <= 1e300) {
                        s->far_max[si][k] = k > 0 ? fmax(s->far_max[si][k - 1], mx) : mx;
                        s->far_min[si][k] = k > 0 ? fmin(s->far_min[si][k - 1], mx) : mx;
                        s->far_tame[si] = k + 1;
                    }
                }
            }
            const double fx = mx - mu_needed; /* = mu_gap(x, &c), bit for bit */
            if (!isfinite(fx))
                break;
            if (sgn(fx) != sgn(fb)) {
                double lo = side < 0 ? x : prev, hi = side < 0 ? prev : x;
                double flo = side < 0 ? fx : fprev, fhi = side < 0 ? fprev : fx;
                if (refine_root(s, mu_gap, &c, lo, hi, flo, fhi, 1, &v[nv]) == 0)
                    ++nv;
                break;
            }
            prev = x;
            fprev = fx;
            d *= 2.0;
        }
    }
    return nv;
}

/* ---- polishing and storing roots ------------------------------------------- */

/* The residual at x vanishes: each row within `base` plus the rounding of its
 * terms, estimated as 16 eps sum_j |dr_i/du_j| |u_j| (the residual cannot be
 * resolved better than a last-bit change of the unknowns moves it; this
 * matters where a row's terms are much larger than m0, e.g. the rotor row
 * of the slip model under a large load). */
static int residual_vanishes(const usm_steady *s, const gsl_vector *x, const gsl_vector *f,
                             double base)
{
    const int nu = s->m->nu;
    double J[USM_MAX_NU * USM_MAX_NU];
    s->m->steady_jacobian(x->data, &s->p, J);
    for (int i = 0; i < nu; ++i) {
        double floor = 0;
        for (int j = 0; j < nu; ++j)
            floor += fabs(J[i * nu + j]) * fabs(gsl_vector_get(x, (size_t)j));
        const double tol = base + 16 * DBL_EPSILON * (isfinite(floor) ? floor : 0);
        if (!(fabs(gsl_vector_get(f, (size_t)i)) <= tol))
            return 0;
    }
    return 1;
}

static int polish(usm_steady *s, double *u, double xtol)
{
    const size_t nu = (size_t)s->m->nu;
    gsl_multiroot_function_fdf fdf = {residual_f, residual_df, residual_fdf, nu, s};
    for (size_t i = 0; i < nu; ++i)
        gsl_vector_set(s->u0, i, u[i]);
    if (gsl_multiroot_fdfsolver_set(s->solver, &fdf, s->u0) != GSL_SUCCESS)
        return -1;
    const double fscale = residual_scale(&s->p);
    int ok = 0;
    for (int it = 0; it < 200; ++it) {
        if (gsl_multiroot_fdfsolver_iterate(s->solver) != GSL_SUCCESS) {
            /* No further progress, or a trial step left the domain (a NaN):
             * near a tilt of 1e-9 rad or a huge rotor speed, xtol can ask for
             * more than rounding allows.  Accept the last iterate only if its
             * residual vanishes. */
            ok = residual_vanishes(s, s->solver->x, s->solver->f, 1e-12 * fscale);
            break;
        }
        /* converged: the step is below xtol and the residual small, or the
         * residual is at rounding level (then the step is rounding noise and
         * xtol may be out of reach) */
        if ((gsl_multiroot_test_delta(s->solver->dx, s->solver->x, 0.0, xtol) == GSL_SUCCESS &&
             residual_vanishes(s, s->solver->x, s->solver->f, 1e-10 * fscale)) ||
            residual_vanishes(s, s->solver->x, s->solver->f, 1e-12 * fscale)) {
            ok = 1;
            break;
        }
    }
    if (!ok)
        return -1;
    for (size_t i = 0; i < nu; ++i)
        u[i] = gsl_vector_get(s->solver->x, i);
    return 0;
}

void usm_steady_evaluate(const usm_model *m, const usm_params *p, usm_steady_solution *sol)
{
    double y[USM_STEADY_COUNT], r[USM_MAX_NU];
    sol->u[1] = fmod(sol->u[1], TWO_PI);
    if (sol->u[1] < 0)
        sol->u[1] += TWO_PI;
    m->steady_outputs(sol->u, p, y);
    m->steady_residual(sol->u, p, r);
    sol->theta = sol->u[0];
    sol->alpha = sol->u[1];
    sol->beta = y[USM_STEADY_BETA];
    sol->rotor_speed = y[USM_STEADY_ROTOR_SPEED];
    sol->F_n = y[USM_STEADY_F_N];
    sol->F_t = y[USM_STEADY_F_T];
    sol->v_c = y[USM_STEADY_V_C];
    sol->v_rel = y[USM_STEADY_V_REL];
    sol->R_star = y[USM_STEADY_R_STAR];
    sol->Z = y[USM_STEADY_Z];
    sol->mu_used = sol->F_t / sol->F_n;
    sol->mu_stick = p->mu0;
    sol->stick_admissible = sol->F_n > 0 && fabs(sol->F_t) <= sol->mu_stick * sol->F_n;
    sol->residual_norm = 0;
    for (int i = 0; i < m->nu; ++i)
        sol->residual_norm = fmax(sol->residual_norm, fabs(r[i]));
    double pw[USM_POWER_COUNT];
    m->steady_power(sol->u, p, pw);
    sol->power_in = pw[USM_POWER_POWER_IN];
    sol->power_out = pw[USM_POWER_POWER_OUT];
    sol->power_damping = pw[USM_POWER_POWER_DAMPING];
    sol->power_slip = pw[USM_POWER_POWER_SLIP];
    sol->efficiency = sol->power_in > 0 ? sol->power_out / sol->power_in : NAN;
    sol->validity = !(sol->F_n > 0)                        ? USM_INVALID_CONTACT_OPEN
                    : !m->slip && !sol->stick_admissible ? USM_INVALID_STICK
                                                           : USM_VALID;
}

const char *usm_validity_name(usm_validity v)
{
    return v == USM_INVALID_CONTACT_OPEN ? "contact_open"
           : v == USM_INVALID_STICK      ? "stick_not_admissible"
                                         : "";
}

/* Same root: the same tilt and the same rotor speed (the slip model's third
 * unknown; 0 in both for the stick model), to 1e-9 relative. */
static int same_root(const usm_steady_solution *a, const double *u, int nu)
{
    if (!(fabs(a->u[0] - u[0]) <= 1e-9 * fabs(u[0])))
        return 0;
    if (nu < 3)
        return 1;
    double wscale = fabs(a->v_c / a->R_star); /* the rotor speed without slip */
    if (!isfinite(wscale))
        wscale = 0;
    return fabs(a->u[2] - u[2]) <= 1e-9 * (fabs(a->u[2]) + fabs(u[2]) + wscale);
}

/* Store a polished root unless it duplicates one already found. */
static int add_root(usm_steady *s, const double *u, double key)
{
    for (size_t k = 0; k < s->count; ++k)
        if (same_root(&s->roots[k].sol, u, s->m->nu))
            return 0;
    if (usm_grow((void **)&s->roots, &s->cap, s->count + 1, sizeof *s->roots) != 0)
        return -1;
    root_entry *e = &s->roots[s->count++];
    memset(e, 0, sizeof *e);
    memcpy(e->sol.u, u, sizeof(double) * (size_t)s->m->nu);
    usm_steady_evaluate(s->m, &s->p, &e->sol);
    e->key = key;
    return 0;
}

static int by_tilt(const void *a, const void *b)
{
    const root_entry *x = a, *y = b;
    if (x->key != y->key)
        return (x->key > y->key) - (x->key < y->key);
    double vx = fabs(x->sol.v_rel), vy = fabs(y->sol.v_rel);
    if (vx != vy)
        return (vx > vy) - (vx < vy);
    return (x->sol.rotor_speed > y->sol.rotor_speed) - (x->sol.rotor_speed < y->sol.rotor_speed);
}

/* What the search saw, for the message when no root converged. */
typedef struct search_notes {
    int tilts;            /* tilts refined */
    int saturated;        /* tilts without a rotor speed because mu_needed is
                             outside the friction law's range */
    double sat_theta, sat_mu; /* the first of them */
    int no_contact;       /* tilts without a rotor speed because F_n = 0 there */
    int oom;
} search_notes;

/* v_rel as a function of the rotor speed at (theta, alpha). */
static double slip_at(const usm_steady *s, double theta, double alpha, double w)
{
    double u[USM_MAX_NU] = {theta, alpha, w}, y[USM_STEADY_COUNT];
    s->m->steady_outputs(u, &s->p, y);
    return y[USM_STEADY_V_REL];
}

/* The rotor speed with slip v at (theta, alpha): v_rel is affine in it. */
static int rotor_speed_for(const usm_steady *s, double theta, double alpha, double v, double *w)
{
    const double v0 = slip_at(s, theta, alpha, 0.0);
    double W = 1.0, slope = 0.5 * (slip_at(s, theta, alpha, W) - slip_at(s, theta, alpha, -W));
    if (isfinite(slope) && slope != 0 && isfinite(v0) && fabs(v0 / slope) > 1.0) {
        W = fabs(v0 / slope);
        slope = 0.5 * (slip_at(s, theta, alpha, W) - slip_at(s, theta, alpha, -W)) / W;
    }
    if (!isfinite(slope) || slope == 0 || !isfinite(v0))
        return -1;
    double x = (v - v0) / slope;
    x += (v - slip_at(s, theta, alpha, x)) / slope; /* one correction for rounding */
    if (!isfinite(x))
        return -1;
    *w = x;
    return 0;
}

/* Seed (theta, alpha[, phidot_R]) at a refined tilt, then polish every root
 * there (the slip model: one per slip speed balancing the rotor). */
static int roots_at(usm_steady *s, double theta, double xtol, search_notes *notes)
{
    double seed[USM_SEED_COUNT], u[USM_MAX_NU] = {theta, 0, 0};
    s->m->steady_seed(theta, &s->p_unit, seed);
    u[1] = atan2(seed[USM_SEED_SIN_ALPHA], seed[USM_SEED_COS_ALPHA]);
    ++notes->tilts;
    if (s->m->nu < 3) {
        if (polish(s, u, xtol) == 0 && add_root(s, u, theta) != 0)
            notes->oom = 1;
        return 0;
    }
    if (!s->m->friction)
        return -1;
    if (!s->law_ready && friction_analyse(s) != 0) {
        notes->oom = 1;
        return -1;
    }
    const double F_t = seed[USM_SEED_F_T], F_n = seed[USM_SEED_F_N];
    if (F_n == 0) {
        ++notes->no_contact;
        return 0;
    }
    const double mu_needed = F_t / F_n;
    double v[64];
    const int nv = isfinite(mu_needed) ? slip_speeds(s, mu_needed, v, 64) : 0;
    if (nv == 0 && !isnan(mu_needed)) {
        if (!(mu_needed >= s->mu_inf && mu_needed <= s->mu_sup)) {
            if (notes->saturated++ == 0) {
                notes->sat_theta = theta;
                notes->sat_mu = mu_needed;
            }
        }
    }
    for (int k = 0; k < nv; ++k) {
        double uk[USM_MAX_NU] = {theta, u[1], 0};
        if (rotor_speed_for(s, theta, u[1], v[k], &uk[2]) != 0)
            continue;
        if (polish(s, uk, xtol) == 0 && add_root(s, uk, theta) != 0)
            notes->oom = 1;
    }
    return 0;
}

/* ---- the tilt search -------------------------------------------------------- */

/* The tilt grid: log-spaced, each end cell halved END_REFINEMENTS times.  It
 * depends on the options alone and is kept between solves. */
static int tilt_grid(usm_steady *s, const usm_steady_options *opt, size_t *n)
{
    if (s->ngrid > 0 && s->grid_key[0] == opt->theta_min && s->grid_key[1] == opt->theta_max &&
        s->grid_key[2] == (double)opt->grid) {
        *n = s->ngrid;
        return 0;
    }
    s->ngrid = 0;
    const size_t need = (size_t)opt->grid + 2 * END_REFINEMENTS;
    if (need > s->grid_cap) {
        /* eight arrays of one capacity: each grown from the same one */
        void **arr[] = {(void **)&s->th, (void **)&s->ca, (void **)&s->sa, (void **)&s->g,
                        (void **)&s->gdone, (void **)&s->q, (void **)&s->qsign,
                        (void **)&s->trig};
        const size_t elem[] = {sizeof *s->th, sizeof *s->ca, sizeof *s->sa, sizeof *s->g,
                               sizeof *s->gdone, sizeof *s->q, sizeof *s->qsign,
                               3 * sizeof *s->trig};
        size_t cap = s->grid_cap;
        for (size_t k = 0; k < sizeof elem / sizeof elem[0]; ++k) {
            cap = s->grid_cap;
            if (usm_grow(arr[k], &cap, need, elem[k]) != 0)
                return -1;
        }
        s->grid_cap = cap;
    }
    const double l0 = log(opt->theta_min), l1 = log(opt->theta_max);
    const double dl = (l1 - l0) / (opt->grid - 1);
    size_t k = 0;
    s->th[k++] = opt->theta_min;
    for (int j = END_REFINEMENTS; j >= 1; --j)
        s->th[k++] = exp(l0 + ldexp(dl, -j));
    for (int i = 1; i < opt->grid - 1; ++i)
        s->th[k++] = exp(l0 + dl * i);
    for (int j = 1; j <= END_REFINEMENTS; ++j)
        s->th[k++] = exp(l1 - ldexp(dl, -j));
    s->th[k++] = opt->theta_max;
    /* drop repeated tilts (grid = 2: both refinements start at the middle) */
    size_t m = 1;
    for (size_t i = 1; i < k; ++i)
        if (s->th[i] > s->th[m - 1])
            s->th[m++] = s->th[i];
    /* the seed's sin, cos and tan of each tilt, computed as its kernel does
     * (steady_seed_trig then equals steady_seed bit for bit; tested) */
    for (size_t i = 0; i < m; ++i) {
        s->trig[3 * i] = sin(s->th[i]);
        s->trig[3 * i + 1] = cos(s->th[i]);
        s->trig[3 * i + 2] = tan(s->th[i]);
    }
    *n = s->ngrid = m;
    s->grid_key[0] = opt->theta_min;
    s->grid_key[1] = opt->theta_max;
    s->grid_key[2] = (double)opt->grid;
    return 0;
}

/* Samples 0..k of the grid: the seed's torque components.  g itself (two
 * logarithms and a hypot, most of a sample's cost) is computed only where a
 * decision of the search needs more than its sign (sample_g). */
static void sample_to(usm_steady *s, size_t k)
{
    /* locals: the stores below could alias the fields for the compiler */
    void (*const seed)(double, const double *USM_RESTRICT, const usm_params *USM_RESTRICT,
                       double *USM_RESTRICT) = s->m->steady_seed_trig;
    const usm_params *const pu = &s->p_unit;
    const double *const th = s->th, *const trig = s->trig;
    double *const ca = s->ca, *const sa = s->sa, *const qv = s->q;
    unsigned char *const gdone = s->gdone;
    signed char *const qsign = s->qsign;
    const double m2_lo = s->m2 * (1 - Q_MARGIN), m2_hi = s->m2 * (1 + Q_MARGIN);
    const int m2_ok = s->m2_ok;
    double out[USM_SEED_COUNT];
    for (size_t i = s->nsampled; i <= k; ++i) {
        seed(th[i], trig + 3 * i, pu, out);
        const double a = out[USM_SEED_COS_ALPHA], b = out[USM_SEED_SIN_ALPHA];
        const double q = a * a + b * b;
        const int q_ok = (q >= Q_MIN) & (q <= Q_MAX);
        ca[i] = a;
        sa[i] = b;
        qv[i] = q_ok ? q : NAN;
        gdone[i] = 0;
        /* g's sign from |A|^2 alone where it is at least Q_MARGIN from
         * m0^2: log and hypot are correct to a few ulps, so the sign cannot
         * differ there (the margin is 5e-11 in g, beyond log's rounding at
         * any |log m0| < 709); 0: undecided, see sample_sign */
        qsign[i] = !m2_ok || !q_ok ? 0 : q < m2_lo ? -1 : q > m2_hi ? 1 : 0;
    }
    if (k + 1 > s->nsampled)
        s->nsampled = k + 1;
}

/* g at sample i exactly as tilt_g computes it; NaN where not finite. */
static double sample_g(usm_steady *s, size_t i)
{
    if (!s->gdone[i]) {
        const double g = log(hypot(s->ca[i], s->sa[i])) - log(s->p.m0);
        s->g[i] = isfinite(g) ? g : NAN;
        s->gdone[i] = 1;
    }
    return s->g[i];
}

/* |A|^2 at sample i when it is a normal number far from overflow, else NaN. */
static double sample_q(const usm_steady *s, size_t i) { return s->q[i]; }

/* The sign of g at sample i: -1 (g < 0), +1 (g >= 0), 2 (not finite). */
static int sample_sign(usm_steady *s, size_t i)
{
    if (s->qsign[i])
        return s->qsign[i];
    const double g = sample_g(s, i);
    return isnan(g) ? 2 : g < 0 ? -1 : 1;
}

/* Whether rule b can fire at sample i (1 < i + 1 < n), decided from |A|^2
 * where that is certain: the rule needs g[i] strictly beyond both
 * neighbours on the side away from zero, and log and hypot being monotone to
 * within a few ulps, that needs |A|^2 at i within 1e-13 of the neighbours'
 * or beyond them; only then are the exact g computed.  *sign: +1 for a
 * minimum of positive g, -1 for a maximum of negative g. */
static int rule_b(usm_steady *s, size_t i, double *sign)
{
    const int a = sample_sign(s, i - 1), b = sample_sign(s, i), c = sample_sign(s, i + 1);
    if (a == 2 || b == 2 || c == 2 || a != b || b != c)
        return 0; /* rule b needs three finite samples of one sign */
    const double qa = sample_q(s, i - 1), qb = sample_q(s, i), qc = sample_q(s, i + 1);
    if (!isnan(qa) && !isnan(qb) && !isnan(qc)) {
        if (b > 0 && !(qb <= qa * (1 + 1e-13) && qb <= qc * (1 + 1e-13)))
            return 0;
        if (b < 0 && !(qb >= qa * (1 - 1e-13) && qb >= qc * (1 - 1e-13)))
            return 0;
    }
    const double ga = sample_g(s, i - 1), gb = sample_g(s, i), gc = sample_g(s, i + 1);
    if (isnan(ga) || isnan(gb) || isnan(gc))
        return 0;
    if (gb > 0 && gb < ga && gb < gc)
        *sign = 1.0;
    else if (gb < 0 && gb > ga && gb > gc)
        *sign = -1.0;
    else
        return 0;
    return 1;
}

/* The extremum of g in (th[j-1], th[j+1]) around the discrete one at th[j]:
 * its tilt and g there.  sign = +1 for a minimum, -1 for a maximum. */
static int locate_extremum(usm_steady *s, size_t j, double sign, double *theta, double *gext)
{
    extremum_ctx c = {s, sign};
    gsl_function F = {tilt_g_log, &c};
    double a = log(s->th[j - 1]), x = log(s->th[j]), b = log(s->th[j + 1]);
    if (gsl_min_fminimizer_set_with_values(s->fmin, &F, x, sign * sample_g(s, j), a,
                                           sign * sample_g(s, j - 1), b,
                                           sign * sample_g(s, j + 1)) != GSL_SUCCESS)
        return -1;
    for (int it = 0; it < 100; ++it) {
        if (gsl_min_fminimizer_iterate(s->fmin) != GSL_SUCCESS)
            return -1;
        if (gsl_min_fminimizer_f_minimum(s->fmin) < 0) /* crosses zero: enough */
            break;
        a = gsl_min_fminimizer_x_lower(s->fmin);
        b = gsl_min_fminimizer_x_upper(s->fmin);
        if (gsl_min_test_interval(a, b, 1e-10, 0.0) == GSL_SUCCESS)
            break;
    }
    *theta = exp(gsl_min_fminimizer_x_minimum(s->fmin));
    *gext = sign * gsl_min_fminimizer_f_minimum(s->fmin);
    return 0;
}

/* What one pass of the search saw. */
typedef struct scan_state {
    search_notes notes;
    int brackets;
    /* the refined extrema of g, which bound the torque needed over the range */
    double ext_min, ext_min_at, ext_max, ext_max_at;
} scan_state;

/* Refine the root of g in [lo, hi] (g changes sign) and solve there. */
static void tilt_root(usm_steady *s, double lo, double hi, double glo, double ghi, double xtol,
                      scan_state *sc)
{
    double theta;
    ++sc->brackets;
    /* glo, ghi from the grid's samples: tilt_g evaluates the ends again */
    if (refine_root(s, tilt_g, s, lo, hi, glo, ghi, 0, &theta) == 0)
        roots_at(s, theta, xtol, &sc->notes);
}

/* Step i of the search (0 <= i < n - 1): rule a on the cell [th[i], th[i+1]],
 * then rule b at sample i.  Roots found get keys in [th[i-1], th[i+1]]. */
static void search_step(usm_steady *s, size_t i, double xtol, scan_state *sc)
{
    sample_to(s, i + 1);
    const double *th = s->th;
    const int si = sample_sign(s, i), sj = sample_sign(s, i + 1);
    /* rule a: a sign change in the cell */
    if (si != 2 && sj != 2 && si != sj)
        tilt_root(s, th[i], th[i + 1], sample_g(s, i), sample_g(s, i + 1), xtol, sc);
    if (i == 0)
        return;
    /* rule b: a discrete extremum pointing towards zero */
    double sign;
    if (!rule_b(s, i, &sign))
        return;
    double te, ge;
    if (locate_extremum(s, i, sign, &te, &ge) != 0)
        return;
    const double nt = needed_torque(s, te);
    if (sign > 0 && nt < sc->ext_min) {
        sc->ext_min = nt;
        sc->ext_min_at = te;
    }
    if (sign < 0 && nt > sc->ext_max) {
        sc->ext_max = nt;
        sc->ext_max_at = te;
    }
    if (sign * ge < 0) {
        tilt_root(s, th[i - 1], te, sample_g(s, i - 1), ge, xtol, sc);
        tilt_root(s, te, th[i + 1], ge, sample_g(s, i + 1), xtol, sc);
    } else if (fabs(ge) <= TOUCH_TOL) {
        ++sc->brackets;
        roots_at(s, te, xtol, &sc->notes);
    }
}

/* Whether step i (0 < i, samples up to i + 1 taken) certainly does nothing,
 * decided from the signs of |A|^2 - m0^2 alone, as search_step and rule_b
 * decide it: samples i and i + 1 of one sign (no rule a), and sample i - 1 of
 * the other sign or |A|^2 at i not a discrete extremum towards zero (no rule
 * b).  Most steps; search_step runs the others. */
static int quiet_step(const usm_steady *s, size_t i)
{
    const signed char *qs = s->qsign;
    const int b = qs[i];
    if (i == 0 || b == 0 || qs[i + 1] != b || qs[i - 1] == 0)
        return 0;
    if (qs[i - 1] != b)
        return 1;
    const double qa = s->q[i - 1], qb = s->q[i], qc = s->q[i + 1];
    if (b > 0)
        return !(qb <= qa * (1 + 1e-13) && qb <= qc * (1 + 1e-13));
    return !(qb >= qa * (1 - 1e-13) && qb >= qc * (1 - 1e-13));
}

/* Check the options and parameters, keep them, and lay out the grid. */
static int search_setup(usm_steady *s, const usm_params *p, const usm_steady_options *opt,
                        size_t *n)
{
    s->count = 0;
    s->msg[0] = '\0';
    s->nsampled = 0;
    s->warm = USM_WARM_NONE;
    if (usm_params_check(p, s->m, s->msg) != USM_OK || usm_params_check_ideal(p, s->msg) != USM_OK)
        return USM_EINPUT;
    if (!(opt->theta_min > 0 && opt->theta_max > opt->theta_min && isfinite(opt->theta_max) &&
          opt->grid >= 2)) {
        snprintf(s->msg, USM_MSG_LEN, "theta range: need 0 < theta_min < theta_max and grid >= 2");
        return USM_EINPUT;
    }
    s->p = *p;
    s->p_unit = *p;
    s->p_unit.m0 = 1.0;
    s->m2 = p->m0 * p->m0;
    s->m2_ok = s->m2 >= Q_MIN && s->m2 <= Q_MAX;
    s->law_ready = law_still_holds(s);
    if (tilt_grid(s, opt, n) != 0) {
        snprintf(s->msg, USM_MSG_LEN, "out of memory");
        return USM_EFAILED;
    }
    return USM_OK;
}

/* The search over steps [0, n - 1), or, with primary_only, until the
 * primary root is settled: once a root is found with a key < th[i] after
 * step i, no later step can find one with a smaller key.  USM_OK, or a
 * status with the message of the search that found nothing. */
static int search_run(usm_steady *s, const usm_params *p, const usm_steady_options *opt, size_t n,
                      int primary_only)
{
    scan_state sc = {{0}, 0, INFINITY, NAN, -INFINITY, NAN};
    double min_key = INFINITY;
    if (!primary_only)
        sample_to(s, n - 1); /* every sample is needed: in one pass */
    for (size_t i = 0; i + 1 < n; ++i) {
        const size_t before = s->count;
        if (primary_only)
            sample_to(s, i + 1);
        if (!quiet_step(s, i))
            search_step(s, i, opt->xtol, &sc);
        for (size_t k = before; k < s->count; ++k)
            min_key = fmin(min_key, s->roots[k].key);
        if (primary_only && s->count > 0 && min_key < s->th[i])
            break;
    }
    if (sc.notes.oom) {
        s->count = 0;
        snprintf(s->msg, USM_MSG_LEN, "out of memory");
        return USM_EFAILED;
    }
    if (s->count > 0) {
        qsort(s->roots, s->count, sizeof s->roots[0], by_tilt);
        return USM_OK;
    }
    /* nothing found: every step ran; the torque needed over the range, for
     * the message */
    char b1[32], b2[32];
    double need_min = sc.ext_min, need_min_at = sc.ext_min_at;
    double need_max = sc.ext_max, need_max_at = sc.ext_max_at;
    size_t finite = 0;
    sample_to(s, n - 1);
    for (size_t i = 0; i < n; ++i) {
        if (isnan(sample_g(s, i)))
            continue;
        const double na = hypot(s->ca[i], s->sa[i]);
        ++finite;
        if (na < need_min) {
            need_min = na;
            need_min_at = s->th[i];
        }
        if (na > need_max) {
            need_max = na;
            need_max_at = s->th[i];
        }
    }
    const search_notes notes = sc.notes;
    const int brackets = sc.brackets;
    if (brackets > 0 && notes.tilts > 0 && notes.saturated == notes.tilts) {
        char b3[32], b4[32];
        steady_msg(s,
                 "the load T = %g N m exceeds what the friction law can transmit "
                 "(mu0 = %g, kappa = %g): at the stationary tilt %.6g rad it needs "
                 "F_t/F_n = %s, outside the law's range [%s, %s]: no rotor speed "
                 "balances the rotor",
                 p->T, p->mu0, p->kappa, notes.sat_theta, fmt_num(b1, notes.sat_mu, "%.6g"),
                 fmt_num(b3, s->mu_inf, "%.6g"), fmt_num(b4, s->mu_sup, "%.6g"));
    } else if (brackets > 0 && notes.tilts > 0 && notes.no_contact == notes.tilts)
        snprintf(s->msg, USM_MSG_LEN,
                 "the contact force F_n vanishes at the stationary tilt(s): friction "
                 "cannot transmit the load T = %g N m",
                 p->T);
    else if (brackets > 0)
        snprintf(s->msg, USM_MSG_LEN,
                 "the stationary equations (3.5) did not converge at the %d bracketed tilt(s)",
                 brackets);
    else if (finite == 0)
        snprintf(s->msg, USM_MSG_LEN,
                 "no tilt theta in [%g, %g] rad can be evaluated: the torque needed to hold "
                 "it is not finite in double precision anywhere in the range (a parameter "
                 "is too large or too small)",
                 opt->theta_min, opt->theta_max);
    else if (need_min > p->m0)
        snprintf(s->msg, USM_MSG_LEN,
                 "no tilt theta in [%g, %g] rad balances the excitation: m0 = %g N m, "
                 "but holding any tilt needs at least %s N m (at theta = %.3g rad)",
                 opt->theta_min, opt->theta_max, p->m0, fmt_num(b1, need_min, "%.4g"),
                 need_min_at);
    else if (need_max < p->m0)
        steady_msg(s,
                 "no tilt theta in [%g, %g] rad balances the excitation: m0 = %g N m "
                 "exceeds the at most %s N m that any tilt in the range holds (at theta = "
                 "%.3g rad); a stationary tilt, if any, lies outside the range",
                 opt->theta_min, opt->theta_max, p->m0, fmt_num(b2, need_max, "%.4g"),
                 need_max_at);
    else
        snprintf(s->msg, USM_MSG_LEN,
                 "no tilt theta in [%g, %g] rad balances the excitation: the torque needed "
                 "is not finite at %zu of the %zu tilts sampled",
                 opt->theta_min, opt->theta_max, n - finite, n);
    return USM_ENOSOLUTION;
}

int usm_steady_solve(usm_steady *s, const usm_params *p, const usm_steady_options *opt)
{
    usm_steady_options def;
    if (!opt) {
        usm_steady_options_default(&def);
        opt = &def;
    }
    size_t n;
    const int st = search_setup(s, p, opt, &n);
    return st != USM_OK ? st : search_run(s, p, opt, n, 0);
}

int usm_steady_solve_warm(usm_steady *s, const usm_params *p, const usm_steady_options *opt,
                          const usm_steady_solution *guess)
{
    usm_steady_options def;
    if (!opt) {
        usm_steady_options_default(&def);
        opt = &def;
    }
    size_t n;
    int st = search_setup(s, p, opt, &n);
    if (st != USM_OK)
        return st;
    /* Newton from the guess: which root the neighbouring point's continues */
    double u[USM_MAX_NU];
    int newton = 0;
    if (guess) {
        memcpy(u, guess->u, sizeof(double) * (size_t)s->m->nu);
        newton = polish(s, u, opt->xtol) == 0 && u[0] >= opt->theta_min && u[0] <= opt->theta_max;
    }
    /* The search below and at its tilt decides whether it is the primary:
     * Newton alone cannot tell which root it converged to. */
    st = search_run(s, p, opt, n, 1);
    if (st != USM_OK) {
        s->warm = newton ? USM_WARM_OTHER_ROOT : USM_WARM_NEWTON_FAILED;
        return st;
    }
    s->count = 1;
    if (!newton)
        s->warm = USM_WARM_NEWTON_FAILED;
    else if (same_root(&s->roots[0].sol, u, s->m->nu))
        s->warm = USM_WARM_CONFIRMED;
    else
        s->warm = USM_WARM_OTHER_ROOT;
    return USM_OK;
}

usm_steady_warm_outcome usm_steady_warm(const usm_steady *s) { return s->warm; }

int usm_steady_solve_from(usm_steady *s, const usm_params *p, const double *u0)
{
    double u[USM_MAX_NU];
    s->count = 0;
    s->msg[0] = '\0';
    s->warm = USM_WARM_NONE;
    if (usm_params_check(p, s->m, s->msg) != USM_OK || usm_params_check_ideal(p, s->msg) != USM_OK)
        return USM_EINPUT;
    s->p = *p;
    s->p_unit = *p;
    s->p_unit.m0 = 1.0;
    memcpy(u, u0, sizeof(double) * (size_t)s->m->nu);
    int rc = polish(s, u, 1e-13);
    if (rc != 0 || !(u[0] > 0)) {
        snprintf(s->msg, USM_MSG_LEN, "Newton iteration from the given start did not converge");
        return USM_ENOSOLUTION;
    }
    if (add_root(s, u, u[0]) != 0) {
        s->count = 0;
        snprintf(s->msg, USM_MSG_LEN, "out of memory");
        return USM_EFAILED;
    }
    return USM_OK;
}

int usm_steady_friction_range(usm_steady *s, const usm_params *p, double *mu_inf, double *mu_sup)
{
    s->count = 0;
    s->msg[0] = '\0';
    s->law_ready = 0;
    if (usm_params_check(p, s->m, s->msg) != USM_OK || usm_params_check_ideal(p, s->msg) != USM_OK)
        return USM_EINPUT;
    if (!s->m->friction) {
        snprintf(s->msg, USM_MSG_LEN, "model: %s has no friction law (stick contact)", s->m->name);
        return USM_EINPUT;
    }
    s->p = *p;
    s->p_unit = *p;
    s->p_unit.m0 = 1.0;
    if (friction_analyse(s) != 0) {
        snprintf(s->msg, USM_MSG_LEN, "out of memory");
        return USM_EFAILED;
    }
    *mu_inf = s->mu_inf;
    *mu_sup = s->mu_sup;
    return USM_OK;
}

/* The root the full search gives near u (solve/steady_cell.h): the search's
 * own refinement of the grid cell holding u's tilt (Brent on g between the
 * cell's ends, which it evaluates afresh, then the polish of each root at
 * that tilt), so the bits are those of usm_steady_solve wherever that cell's
 * sign change is how the search finds the root. */
int usm_steady_solve_cell(usm_steady *s, const usm_params *p, const usm_steady_options *opt,
                          const double *u)
{
    size_t n;
    int st = search_setup(s, p, opt, &n);
    if (st != USM_OK)
        return st;
    const double *th = s->th;
    if (!(u[0] >= th[0] && u[0] <= th[n - 1]))
        return USM_ENOSOLUTION;
    size_t lo = 0, hi = n - 1; /* th[lo] <= u[0] <= th[hi] */
    while (hi - lo > 1) {
        const size_t mid = lo + (hi - lo) / 2;
        if (th[mid] <= u[0])
            lo = mid;
        else
            hi = mid;
    }
    const double glo = tilt_g(th[lo], s), ghi = tilt_g(th[hi], s);
    if (!(glo < 0 && ghi > 0) && !(glo > 0 && ghi < 0))
        return USM_ENOSOLUTION;
    scan_state sc = {{0}, 0, INFINITY, NAN, -INFINITY, NAN};
    tilt_root(s, th[lo], th[hi], glo, ghi, opt->xtol, &sc);
    if (sc.notes.oom) {
        s->count = 0;
        return USM_EFAILED;
    }
    return s->count > 0 ? USM_OK : USM_ENOSOLUTION;
}
