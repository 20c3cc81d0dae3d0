/* test_kernels_jacobians: every Jacobian-type kernel of every generated model against
 * central finite differences of the kernel it differentiates.
 *
 *   jac_rhs(x, t)        vs  d f(x, t) / dx
 *   jac_mass(x, v)       vs  d (M(x) v) / dx          (v fixed)
 *   steady_jacobian(u)   vs  d r(u) / du
 *   steady_jacobian_params(u)  vs  d r(u; p) / dp   (every usm_params field)
 *   friction(v)[1]       vs  d mu(v) / dv             (models with slip)
 *   linearisation(x, v)  the fused kernel [M, df/dx, d(Mv)/dx]: its Jacobian
 *                        blocks as jac_rhs and jac_mass, its M block vs
 *                        d (M(x) w) / dw of the mass kernel
 *
 * Samples: NSAMPLES random points per model, each with its own parameter set
 * (every default parameter times a log-uniform factor in [1/2, 2]; I_yy kept
 * equal to I_xx, as the axisymmetric-stator models assume), theta log-uniform
 * in [1e-5, 0.3], angles in [-10 pi, 10 pi], phi/psi rates of order
 * Omega = 2 pi f, the tilt rate of order 0.05 Omega, random t.  For the slip
 * models half of the samples put the slip velocity v_rel within a few 1/kappa
 * of zero, where the friction law bends.  The PRNG is splitmix64 with a fixed
 * seed, so every run checks the same points.
 *
 * Step and error measure.  Column j is differenced with
 *     h_j = 1e-6 * xhat_j,   xhat_j = max(|x_j|, s_j)
 * (s_j: a typical size of x_j; theta: 0.1 rad, see THETA_SCALE), central
 * differences at h_j and h_j/2 combined by Richardson extrapolation,
 * (4 D(h/2) - D(h)) / 3, which leaves an O(h^4) truncation error.  In slip
 * models h_j is also capped so that v_rel moves by at most 1e-2/kappa (see
 * slip_step_caps).  Each entry is judged against the size of its row, so that
 * an entry that is small because of cancellation is not asked for more
 * relative accuracy than the row's arithmetic carries:
 *     |J_ad - J_fd|_ij <= TOL * (|J_ij| + S_i / xhat_j),
 *     S_i = max(|g_i(x)|, max_k |J_ik| xhat_k)       (g = f, M v or r;
 *           for M v, |g_i| is replaced by sum_k |M_ik v_k|),
 * i.e. the error, times a typical change xhat_j of x_j, is small against the
 * size of g_i and of every term of its linearisation.  In these units a
 * central difference is off by
 *     truncation  ~ (h_j / L_j)^4 <= 1e-8 with Richardson (L_j: the length on
 *                 which g varies -- 1 rad for angles, |x_j| or more for
 *                 rates, 1/kappa in v_rel for the friction law),
 *     rounding    ~ eps * xhat_j / h_j = 2.2e-16 / 1e-6 = 2.2e-10, times the
 *                 cancellation inside g_i and a factor 3 from Richardson,
 * so a correct kernel is expected at 1e-10 ... 1e-8 (measured:
 * 1.0e-7 worst for the paper's models (4dof steady_jac_params), 3.2e-7 for
 * friction_stribeck, whose Stribeck peak varies on 0.01 m/s, below the 1/kappa
 * on which the slip caps place the steps).  TOL = 1e-6 keeps a factor 10 over
 * the paper's models, 3 over friction_stribeck and 100 or more over the
 * typical entry; a wrong or missing term is of relative size 1e-3 ... 1
 * of the entry's row and fails clearly (a misparenthesised 1/R*^4 in jac_mass
 * of an earlier generator gave 0.37).
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "usm.h"

#include "check.h"

#define NSAMPLES 200
#define TOL 1e-6
#ifndef REL_STEP
#define REL_STEP 1e-6
#endif
/* Difference scale of theta: h = 1e-6 max(theta, 0.1 rad).  The kernels vary
 * with theta on the scale of trig functions (1 rad) and of R* (about 1 rad),
 * not on the scale of theta itself, so a step proportional to a tiny theta
 * only magnifies rounding.  And that rounding is not eps-small: cos(theta) is
 * quantised at eps, and the steady residuals form theta^2-sized terms from it
 * (Omega (cos theta - 1/cos theta) = -Omega sin theta tan theta, and a sum
 * cos theta * that + Omega sin^2 theta that vanishes identically), which
 * carries absolute noise ~eps Omega whatever theta is: measured, the 4dof
 * rotor residual at theta = 4.2e-4 is noisy at 2e-12 of its size.  With
 * s_theta = 1e-3 (h = 1e-9 rad) the worst scaled error was 7.9e-7, with
 * 1e-2 it was 9.1e-8, with 0.1 it is below 5e-8. */
#define THETA_SCALE 0.1
/* Parameter columns (steady_jacobian_params) use relative steps 1e-4: the
 * residuals are rational/trig in the parameters on the scale of each
 * parameter itself (Richardson truncation ~ (1e-4)^4), except through the
 * friction law, which the slip caps handle.  With 1e-6 the column d/df of the
 * rotor balance at theta ~ 1e-5 measured the eps*Omega noise above: its
 * signal 2 pi Z tan(theta) h is proportional to theta (scaled error 3e-5;
 * 1e-8 with 1e-4). */
#define PARAM_REL_STEP 1e-4
#define MAX_REPORTS 5 /* failure messages printed per model and kernel */
/* Most columns of any checked Jacobian (states or parameters). */
#define NCOL (USM_MAX_NX > USM_NPARAMS ? USM_MAX_NX : USM_NPARAMS)

static const double PI = 3.141592653589793238462643383279502884;

/* ---- deterministic PRNG (check.h: splitmix64) ----------------------------- */

static uint64_t rng = 0x5eed0f05a1e5ULL;

/* ---- random parameters and states ------------------------------------------- */

static void random_params(usm_params *p)
{
    usm_params_default(p);
    for (int i = 0; i < USM_NPARAMS; ++i) {
        double *v = usm_params_field(p, &usm_param_table[i]);
        if (*v != 0.0) /* the imperfections (0) draw nothing: see below */
            *v *= rng_log_range(&rng, 0.5, 2.0);
    }
    p->I_yy = p->I_xx;
    /* imperfections are 0 by default: give them values (imperfect models),
     * from a stream of their own so that the other samples stay as they were */
    static uint64_t imperfection_stream = 0x1d3a9e57ULL;
    p->amp_imbalance = rng_range(&imperfection_stream, -0.3, 0.3);
    p->phase_error = rng_range(&imperfection_stream, -0.5, 0.5);
    p->mode_split = rng_range(&imperfection_stream, -0.2, 0.2);
}

static double omega_of(const usm_params *p)
{
    return 2.0 * PI * p->f;
}

/* Index of the state/unknown called `name` in `names` (length n), or -1. */
static int index_of(const char *const *names, int n, const char *name)
{
    for (int i = 0; i < n; ++i)
        if (strcmp(names[i], name) == 0)
            return i;
    return -1;
}

/* Contact-point speed v_c = (omega x r_c) . e_x1, written in frame A
 * (independent of the generated code; only used to place samples). */
static double contact_speed(double theta, double phidot, double psidot, const usm_params *p)
{
    double s = sin(theta), c = cos(theta);
    double Rs = p->R * c - p->H * s, Z = p->R * s + p->H * c;
    double wy = -psidot * s, wz = phidot + psidot * c;
    return wy * Z - wz * Rs;
}

static double contact_radius(double theta, const usm_params *p)
{
    return p->R * cos(theta) - p->H * sin(theta);
}

/* Fill x (and the difference scales s) of model m with a random state. */
static int random_state(const usm_model *m, const usm_params *p, double *x, double *s)
{
    const double W = omega_of(p);
    for (int i = 0; i < m->nx; ++i) {
        const char *nm = m->state_names[i];
        if (strcmp(nm, "theta") == 0) {
            x[i] = rng_log_range(&rng, 1e-5, 0.3);
            s[i] = THETA_SCALE;
        } else if (strcmp(nm, "phi") == 0 || strcmp(nm, "psi") == 0 || strcmp(nm, "phi_R") == 0) {
            x[i] = rng_range(&rng, -10.0 * PI, 10.0 * PI);
            s[i] = 1.0;
        } else if (strcmp(nm, "phidot") == 0 || strcmp(nm, "psidot") == 0) {
            x[i] = W * rng_range(&rng, -2.0, 2.0);
            s[i] = W;
        } else if (strcmp(nm, "thetadot") == 0) {
            x[i] = 0.05 * W * rng_range(&rng, -1.0, 1.0);
            s[i] = 0.05 * W;
        } else if (strcmp(nm, "phi_Rdot") == 0) {
            x[i] = rng_range(&rng, -1000.0, 1000.0);
            s[i] = 100.0;
        } else if (strcmp(nm, "a") == 0 || strcmp(nm, "b") == 0) { /* the tilt vector */
            x[i] = (rng_uniform(&rng) < 0.5 ? -1 : 1) * rng_log_range(&rng, 1e-5, 0.2);
            s[i] = THETA_SCALE;
        } else if (strcmp(nm, "chi") == 0) {
            x[i] = rng_range(&rng, -10.0 * PI, 10.0 * PI);
            s[i] = 1.0;
        } else if (strcmp(nm, "adot") == 0 || strcmp(nm, "bdot") == 0) {
            x[i] = 0.05 * W * rng_range(&rng, -1.0, 1.0);
            s[i] = 0.05 * W;
        } else if (strcmp(nm, "chidot") == 0) {
            x[i] = W * rng_range(&rng, -2.0, 2.0);
            s[i] = W;
        } else if (strcmp(nm, "tau") == 0) { /* integrated twist angle */
            x[i] = rng_range(&rng, -0.1, 0.1);
            s[i] = 0.01;
        } else {
            CHECK(0, "model %s: state %s has no sampling rule in this test", m->name, nm);
            return 1;
        }
    }
    /* Slip models: half of the samples near v_rel = v_c + phidot_R R* = 0. */
    int iR = index_of(m->state_names, m->nx, "phi_Rdot");
    if (iR >= 0 && m->coordinates == 0 && rng_uniform(&rng) < 0.5) {
        int ith = index_of(m->state_names, m->nx, "theta");
        int iph = index_of(m->state_names, m->nx, "phidot");
        int ips = index_of(m->state_names, m->nx, "psidot");
        double vc = contact_speed(x[ith], x[iph], x[ips], p);
        double vrel = rng_range(&rng, -3.0, 3.0) / p->kappa;
        x[iR] = (vrel - vc) / contact_radius(x[ith], p);
    }
    return 0;
}

/* Random stationary unknowns u of model m (and their scales s). */
static int random_unknowns(const usm_model *m, const usm_params *p, double *u, double *s)
{
    int ith = index_of(m->unknown_names, m->nu, "theta");
    for (int i = 0; i < m->nu; ++i) {
        const char *nm = m->unknown_names[i];
        if (strcmp(nm, "theta") == 0) {
            u[i] = rng_log_range(&rng, 1e-5, 0.3);
            s[i] = THETA_SCALE;
        } else if (strcmp(nm, "alpha") == 0) {
            u[i] = rng_range(&rng, 0.0, 2.0 * PI);
            s[i] = 1.0;
        } else if (strcmp(nm, "phidot_R") == 0) {
            s[i] = 10.0;
            u[i] = 0.0; /* set below, needs theta */
        } else {
            CHECK(0, "model %s: unknown %s has no sampling rule in this test", m->name, nm);
            return 1;
        }
    }
    int iR = index_of(m->unknown_names, m->nu, "phidot_R");
    if (iR >= 0) {
        /* On the orbit (3.1) v_c = Omega tan(theta) Z; put v_rel within a few
         * 1/kappa of zero or anywhere in +-10 m/s. */
        double th = u[ith], W = omega_of(p);
        double vc = contact_speed(th, W, -W / cos(th), p);
        double vrel = rng_uniform(&rng) < 0.5 ? rng_range(&rng, -3.0, 3.0) / p->kappa : rng_range(&rng, -10.0, 10.0);
        u[iR] = (vrel - vc) / contact_radius(th, p);
    }
    return 0;
}

typedef struct eval_ctx {
    const usm_model *m;
    const usm_params *p;
    double t;
    const double *v; /* jac_mass: the fixed vector */
    const double *u; /* steady_jacobian_params: the fixed unknowns */
    const double *x; /* linearisation's M block: the fixed state */
} eval_ctx;

typedef void (*vec_fn)(const eval_ctx *c, const double *x, double *out);
typedef double (*scalar_fn)(const eval_ctx *c, const double *x);

/* Parameters with the fields taken from the vector x (usm_param_table order). */
static usm_params params_from(const usm_params *p0, const double *x)
{
    usm_params p = *p0;
    for (int k = 0; k < USM_NPARAMS; ++k)
        *usm_params_field(&p, &usm_param_table[k]) = x[k];
    return p;
}

/* Slip velocity v_rel = v_c + phidot_R R* of a state, and on the orbit (3.1)
 * for the stationary unknowns (test's own kinematics). */
static double vrel_of_state(const usm_model *m, const usm_params *p, const double *x, double t)
{
    if (index_of(m->state_names, m->nx, "theta") < 0) {
        /* a tilt-vector state: its Euler-angle twin's kinematics.  The map is
         * the library's, but it only sizes the difference steps: the kernels
         * are still judged by the difference quotients alone. */
        double xe[USM_MAX_NX];
        if (!m->other_coordinates ||
            usm_coords_map(m, x, t, p, 0.0, m->other_coordinates, xe) != USM_OK)
            return 0.0;
        return vrel_of_state(m->other_coordinates, p, xe, t);
    }
    int ith = index_of(m->state_names, m->nx, "theta");
    int iph = index_of(m->state_names, m->nx, "phidot");
    int ips = index_of(m->state_names, m->nx, "psidot");
    int iR = index_of(m->state_names, m->nx, "phi_Rdot");
    return contact_speed(x[ith], x[iph], x[ips], p) + x[iR] * contact_radius(x[ith], p);
}

static double vrel_of_unknowns(const usm_model *m, const usm_params *p, const double *u)
{
    int ith = index_of(m->unknown_names, m->nu, "theta");
    int iR = index_of(m->unknown_names, m->nu, "phidot_R");
    double th = u[ith], W = omega_of(p);
    return contact_speed(th, W, -W / cos(th), p) + u[iR] * contact_radius(th, p);
}

/* Step caps for slip models: the friction law mu0 atan(kappa v_rel) bends on
 * the scale 1/kappa of v_rel, while v_rel = v_c + phidot_R R* is a small
 * difference of terms of size Omega theta Z.  A relative step 1e-6 |x_j| of a
 * rate of size Omega moves v_rel by up to ~0.2/kappa and the difference
 * quotient would measure the curvature of atan, not the kernel.  So column j
 * moves v_rel by at most 1e-2/kappa:  h_j <= 1e-2 / (kappa |dv_rel/dx_j|)
 * (Richardson truncation ~ (1e-2)^4; rounding in v_rel ~ eps |v_c| kappa
 * / 1e-2 <= 1e-9 relative for |v_c| <= 1000 m/s). */
static void slip_step_caps(scalar_fn vrel, const eval_ctx *c, const double *x, const double *s,
                           int n, double rel, double *hmax)
{
    double xp[NCOL];
    for (int j = 0; j < n; ++j) {
        double h = rel * fmax(fabs(x[j]), s[j]);
        memcpy(xp, x, (size_t)n * sizeof *xp);
        xp[j] = x[j] + h;
        double vp = vrel(c, xp);
        xp[j] = x[j] - h;
        double dv = fabs(vp - vrel(c, xp)) / (2.0 * h);
        hmax[j] = dv > 0.0 ? 1e-2 / (c->p->kappa * dv) : INFINITY;
    }
}

static double vrel_state_fn(const eval_ctx *c, const double *x)
{
    return vrel_of_state(c->m, c->p, x, c->t);
}

static double vrel_unknowns_fn(const eval_ctx *c, const double *u)
{
    return vrel_of_unknowns(c->m, c->p, u);
}

static double vrel_params_fn(const eval_ctx *c, const double *x)
{
    usm_params p = params_from(c->p, x);
    return vrel_of_unknowns(c->m, &p, c->u);
}

/* ---- functions to difference ------------------------------------------------ */

static void eval_rhs(const eval_ctx *c, const double *x, double *out)
{
    c->m->rhs(x, c->t, c->p, out);
}

static void eval_mass_v(const eval_ctx *c, const double *x, double *out)
{
    double M[USM_MAX_NX * USM_MAX_NX];
    int n = c->m->nx;
    c->m->mass(x, c->p, M);
    for (int i = 0; i < n; ++i) {
        double acc = 0.0;
        for (int j = 0; j < n; ++j)
            acc += M[i * n + j] * c->v[j];
        out[i] = acc;
    }
}

/* M(x) w at the fixed state c->x, as a function of w: d(M w)/dw = M. */
static void eval_mass_w(const eval_ctx *c, const double *w, double *out)
{
    double M[USM_MAX_NX * USM_MAX_NX];
    int n = c->m->nx;
    c->m->mass(c->x, c->p, M);
    for (int i = 0; i < n; ++i) {
        double acc = 0.0;
        for (int j = 0; j < n; ++j)
            acc += M[i * n + j] * w[j];
        out[i] = acc;
    }
}

static void eval_residual(const eval_ctx *c, const double *u, double *out)
{
    c->m->steady_residual(u, c->p, out);
}

static void eval_residual_params(const eval_ctx *c, const double *x, double *out)
{
    usm_params p = params_from(c->p, x);
    c->m->steady_residual(c->u, &p, out);
}

/* Sum of |M_ij v_j| per row: a size of M v that ignores cancellation. */
static void mass_v_size(const eval_ctx *c, const double *x, double *out)
{
    double M[USM_MAX_NX * USM_MAX_NX];
    int n = c->m->nx;
    c->m->mass(x, c->p, M);
    for (int i = 0; i < n; ++i) {
        double acc = 0.0;
        for (int j = 0; j < n; ++j)
            acc += fabs(M[i * n + j] * c->v[j]);
        out[i] = acc;
    }
}

/* ---- comparison ---------------------------------------------------------------- */

typedef struct stats {
    double worst;      /* largest scaled error */
    int worst_sample, worst_i, worst_j;
    double worst_ad, worst_fd;
    long entries;      /* entries compared */
    int failures;      /* entries above TOL */
} stats;

static void print_vec(const char *label, const char *const *names, const double *x, int n)
{
    fprintf(stderr, "      %s:", label);
    for (int k = 0; k < n; ++k)
        fprintf(stderr, " %s=%.17g", names ? names[k] : "", x[k]);
    fprintf(stderr, "\n");
}

/* Compare J_ad (m x n, row-major) with central differences of g at x.
 * gsize (may be NULL) gives a cancellation-free size of g_i; else |g_i|. */
static void compare(const char *model, const char *kernel, const char *const *names, int sample,
                    const eval_ctx *c, vec_fn g, vec_fn gsize, int rows, int n, const double *x,
                    const double *s, double rel, const double *hmax, const double *J_ad,
                    stats *st)
{
    double Jfd[USM_MAX_NX * NCOL], xhat[NCOL], xp[NCOL], gp[USM_MAX_NX], gm[USM_MAX_NX],
        g0[USM_MAX_NX], S[USM_MAX_NX];
    for (int j = 0; j < n; ++j) {
        xhat[j] = fmax(fabs(x[j]), s[j]);
        /* D(h) and D(h/2), Richardson-combined: (4 D(h/2) - D(h)) / 3. */
        double D[2][USM_MAX_NX];
        for (int r = 0; r < 2; ++r) {
            double h = fmin(rel * xhat[j], hmax ? hmax[j] : INFINITY) / (r ? 2.0 : 1.0);
            memcpy(xp, x, (size_t)n * sizeof *xp);
            xp[j] = x[j] + h;
            double hp = xp[j] - x[j]; /* the steps actually taken */
            g(c, xp, gp);
            xp[j] = x[j] - h;
            double hm = x[j] - xp[j];
            g(c, xp, gm);
            for (int i = 0; i < rows; ++i)
                D[r][i] = (gp[i] - gm[i]) / (hp + hm);
        }
        for (int i = 0; i < rows; ++i)
            Jfd[i * n + j] = (4.0 * D[1][i] - D[0][i]) / 3.0;
    }
    if (gsize)
        gsize(c, x, g0);
    else
        g(c, x, g0);
    for (int i = 0; i < rows; ++i) {
        double row = fabs(g0[i]);
        for (int k = 0; k < n; ++k)
            row = fmax(row, fmax(fabs(J_ad[i * n + k]), fabs(Jfd[i * n + k])) * xhat[k]);
        S[i] = row;
    }
    for (int i = 0; i < rows; ++i) {
        for (int j = 0; j < n; ++j) {
            double ad = J_ad[i * n + j], fd = Jfd[i * n + j];
            double diff = fabs(ad - fd);
            double scale = fmax(fabs(ad), fabs(fd)) + S[i] / xhat[j];
            double err = scale > 0.0 ? diff / scale : (diff == 0.0 ? 0.0 : INFINITY);
            if (!(err <= TOL) || !isfinite(ad)) {
                if (st->failures < MAX_REPORTS) {
                    fprintf(stderr,
                            "FAIL: model %s, kernel %s, entry (%d,%d) [d row %d / d %s]: analytic "
                            "%.10g, central difference %.10g, scaled error %.3g > %.1g (sample %d)\n",
                            model, kernel, i, j, i, names ? names[j] : "?", ad, fd, err, TOL,
                            sample);
                    print_vec("at", names, x, n);
                }
                st->failures++;
                if (!isfinite(err))
                    err = INFINITY;
            }
            st->entries++;
            if (err > st->worst || (st->worst_sample < 0)) {
                st->worst = err;
                st->worst_sample = sample;
                st->worst_i = i;
                st->worst_j = j;
                st->worst_ad = ad;
                st->worst_fd = fd;
            }
        }
    }
}

static void stats_init(stats *st)
{
    memset(st, 0, sizeof *st);
    st->worst_sample = -1;
}

static int report(const char *model, const char *kernel, const stats *st)
{
    printf("%-24s %-17s entries %6ld  worst scaled error %.3e", model, kernel, st->entries, st->worst);
    if (st->worst_sample >= 0)
        printf("  at (%d,%d) sample %d (analytic %.6g, fd %.6g)", st->worst_i, st->worst_j,
               st->worst_sample, st->worst_ad, st->worst_fd);
    printf("  %s\n", st->failures ? "FAILED" : "ok");
    CHECK(st->entries > 0, "model %s, kernel %s: no entry compared", model, kernel);
    CHECK(st->failures == 0, "model %s, kernel %s: %d entries out of tolerance", model, kernel,
          st->failures);
    return st->failures;
}

/* ---- per model ------------------------------------------------------------------ */

static const char *param_names[USM_NPARAMS];

/* Difference scales of v: its own entries (M w is linear in w). */
static const double *sv_of(const double *v, int n, double *sv)
{
    for (int i = 0; i < n; ++i)
        sv[i] = fabs(v[i]) > 0.0 ? fabs(v[i]) : 1.0;
    return sv;
}

static int check_model(const usm_model *m)
{
    stats s_rhs, s_mass, s_steady, s_params, s_fric, s_lin_m, s_lin_f, s_lin_mv;
    stats_init(&s_lin_m);
    stats_init(&s_lin_f);
    stats_init(&s_lin_mv);
    stats_init(&s_params);
    stats_init(&s_rhs);
    stats_init(&s_mass);
    stats_init(&s_steady);
    stats_init(&s_fric);
    const int n = m->nx, nu = m->nu;
    int bad = 0;

    for (int k = 0; k < NSAMPLES; ++k) {
        usm_params p;
        random_params(&p);
        if (!m->imperfect) /* an ideal model refuses imperfections */
            p.amp_imbalance = p.phase_error = p.mode_split = 0.0;
        char msg[USM_MSG_LEN];
        if (!CHECK(usm_params_check(&p, m, msg) == USM_OK, "random parameters rejected: %s",
                   msg))
            return 1;
        double x[USM_MAX_NX], s[USM_MAX_NX], v[USM_MAX_NX], J[USM_MAX_NX * NCOL];
        if (random_state(m, &p, x, s))
            return 1;
        /* v: a random "x'" -- rates in the angle slots, accelerations in the
         * rate slots (M v is linear in v, only the mix matters). */
        const double W = omega_of(&p);
        for (int i = 0; i < n; ++i) {
            const char *nm = m->state_names[i];
            double sc = strstr(nm, "dot") ? W * W : W;
            if (strncmp(nm, "theta", 5) == 0)
                sc *= 0.05;
            if (strncmp(nm, "phi_R", 5) == 0)
                sc = strstr(nm, "dot") ? 1e5 : 1e3;
            v[i] = sc * rng_range(&rng, -1.0, 1.0);
        }
        eval_ctx c = {m, &p, rng_range(&rng, 0.0, 100.0 / p.f), v, NULL, x};
        double hx[USM_MAX_NX], hu[USM_MAX_NU];
        const int slip = index_of(m->state_names, n, "phi_Rdot") >= 0;
        if (slip)
            slip_step_caps(vrel_state_fn, &c, x, s, n, REL_STEP, hx);

        m->jac_rhs(x, c.t, &p, J);
        compare(m->name, "jac_rhs", m->state_names, k, &c, eval_rhs, NULL, n, n, x, s, REL_STEP,
                slip ? hx : NULL, J, &s_rhs);

        m->jac_mass(x, v, &p, J);
        compare(m->name, "jac_mass", m->state_names, k, &c, eval_mass_v, mass_v_size, n, n, x, s,
                REL_STEP, slip ? hx : NULL, J, &s_mass);

        /* the fused kernel: [M, df/dx, d(Mv)/dx]; its Jacobian blocks against
         * the same differences as above, its M block against differences in
         * v of the mass kernel's M(x) v (linear in v: only rounding) */
        double L[3 * USM_MAX_NX * USM_MAX_NX], sv[USM_MAX_NX];
        m->linearisation(x, v, c.t, &p, L);
        compare(m->name, "linearisation M", m->state_names, k, &c, eval_mass_w, NULL, n, n, v,
                sv_of(v, n, sv), REL_STEP, NULL, L, &s_lin_m);
        compare(m->name, "linearisation df", m->state_names, k, &c, eval_rhs, NULL, n, n, x, s,
                REL_STEP, slip ? hx : NULL, L + n * n, &s_lin_f);
        compare(m->name, "linearisation dMv", m->state_names, k, &c, eval_mass_v, mass_v_size, n,
                n, x, s, REL_STEP, slip ? hx : NULL, L + 2 * n * n, &s_lin_mv);

        double u[USM_MAX_NU], su[USM_MAX_NU];
        if (random_unknowns(m, &p, u, su))
            return 1;
        const int uslip = index_of(m->unknown_names, nu, "phidot_R") >= 0;
        if (uslip)
            slip_step_caps(vrel_unknowns_fn, &c, u, su, nu, REL_STEP, hu);
        m->steady_jacobian(u, &p, J);
        compare(m->name, "steady_jacobian", m->unknown_names, k, &c, eval_residual, NULL, nu, nu, u,
                su, REL_STEP, uslip ? hu : NULL, J, &s_steady);

        if (m->steady_jacobian_params) {
            /* d r / d p at the same u: every field, relative steps */
            double xp[USM_NPARAMS], sp[USM_NPARAMS], hp[USM_NPARAMS];
            for (int q = 0; q < USM_NPARAMS; ++q) {
                xp[q] = usm_params_get(&p, &usm_param_table[q]);
                sp[q] = fabs(xp[q]) > 0.0 ? fabs(xp[q]) : 1.0;
            }
            c.u = u;
            if (uslip)
                slip_step_caps(vrel_params_fn, &c, xp, sp, USM_NPARAMS, PARAM_REL_STEP, hp);
            m->steady_jacobian_params(u, &p, J);
            compare(m->name, "steady_jac_params", param_names, k, &c, eval_residual_params, NULL, nu,
                    USM_NPARAMS, xp, sp, PARAM_REL_STEP, uslip ? hp : NULL, J, &s_params);
        }

        if (m->friction) {
            /* d mu / d v_rel, v_rel within +-10/kappa */
            double vr = rng_range(&rng, -10.0, 10.0) / p.kappa, out[2], op[2], om[2];
            double h = REL_STEP * fmax(fabs(vr), 1.0 / p.kappa);
            m->friction(vr, &p, out);
            m->friction(vr + h, &p, op);
            m->friction(vr - h, &p, om);
            double fd = (op[0] - om[0]) / ((vr + h) - (vr - h));
            /* row scale: |mu| and the slope times the step scale */
            double xhat = fmax(fabs(vr), 1.0 / p.kappa);
            double scale = fmax(fabs(out[1]), fabs(fd)) + fmax(fabs(out[0]) / xhat, fabs(out[1]));
            double err = fabs(out[1] - fd) / scale;
            s_fric.entries++;
            if (err > s_fric.worst || s_fric.worst_sample < 0) {
                s_fric.worst = err;
                s_fric.worst_sample = k;
                s_fric.worst_ad = out[1];
                s_fric.worst_fd = fd;
            }
            if (!(err <= TOL)) {
                if (s_fric.failures < MAX_REPORTS)
                    fprintf(stderr,
                            "FAIL: model %s, kernel friction, entry (1,0) [dmu/dv_rel] at "
                            "v_rel=%.17g: analytic %.10g, central difference %.10g, scaled error "
                            "%.3g > %.1g (sample %d)\n",
                            m->name, vr, out[1], fd, err, TOL, k);
                s_fric.failures++;
            }
        }
    }
    bad += report(m->name, "jac_rhs", &s_rhs);
    bad += report(m->name, "jac_mass", &s_mass);
    bad += report(m->name, "linearisation M", &s_lin_m);
    bad += report(m->name, "linearisation df", &s_lin_f);
    bad += report(m->name, "linearisation dMv", &s_lin_mv);
    bad += report(m->name, "steady_jacobian", &s_steady);
    if (m->steady_jacobian_params)
        bad += report(m->name, "steady_jac_params", &s_params);
    if (m->friction)
        bad += report(m->name, "friction slope", &s_fric);
    return bad;
}

int main(void)
{
    int entries_failed = 0;
    printf("Jacobian kernels vs central differences: %d samples per model, tolerance %.0e "
           "(scaled error, see the comment at the top)\n",
           NSAMPLES, TOL);
    for (int q = 0; q < USM_NPARAMS; ++q)
        param_names[q] = usm_param_table[q].name;
    for (int i = 0; i < USM_NMODELS; ++i)
        entries_failed += check_model(usm_models[i]);
    if (failures || entries_failed) {
        printf("test_kernels_jacobians: FAILED (%d checks, %d entries out of tolerance)\n", failures,
               entries_failed);
        return 1;
    }
    printf("test_kernels_jacobians: ok\n");
    return 0;
}
