/* Stationary solutions (paper, section 3 and section 5).
 *
 * Math: on the ansatz (3.1) the frame-A components x1, y1 of Euler's equations
 * give two residuals r(theta, alpha) = 0 (3.5); the slip model adds the rotor's
 * moment balance, with the rotor speed phidot_R as third unknown.
 *
 * Search, from the parameters alone:
 *  1. At fixed tilt theta the x1/y1 rows are linear in (cos alpha, sin alpha)
 *     (the excitation is the only place alpha enters); the generated seed kernel
 *     solves them and returns amplitude_mismatch = cos^2 + sin^2 - 1.  Its sign
 *     changes on a log-spaced theta grid bracket every stationary tilt in the
 *     range; GSL's Brent solver refines each one.
 *  2. Slip model: the rotor balance is monotone in phidot_R for a monotone
 *     friction law; an expanding bracket around 0 finds the sign change, or
 *     shows there is none (the load exceeds what friction can transmit).
 *  3. GSL's hybridsj polishes (theta, alpha[, phidot_R]) on the full residual
 *     with the generated Jacobian.
 * A root is reported only when hybridsj converged and the residual is small.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_multiroots.h>
#include <gsl/gsl_roots.h>

#include "usm.h"

#define MAX_ROOTS 16
#define TWO_PI 6.283185307179586476925286766559

struct usm_steady {
    const usm_model *m;
    usm_params p;
    gsl_multiroot_fdfsolver *solver;
    gsl_root_fsolver *brent;
    gsl_vector *u0;
    size_t count;
    usm_steady_solution roots[MAX_ROOTS];
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
    s->brent = gsl_root_fsolver_alloc(gsl_root_fsolver_brent);
    s->u0 = gsl_vector_alloc((size_t)m->nu);
    if (!s->solver || !s->brent || !s->u0) {
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
    if (s->brent)
        gsl_root_fsolver_free(s->brent);
    if (s->u0)
        gsl_vector_free(s->u0);
    free(s);
}

size_t usm_steady_count(const usm_steady *s) { return s->count; }

const usm_steady_solution *usm_steady_root(const usm_steady *s, size_t i)
{
    return i < s->count ? &s->roots[i] : NULL;
}

const char *usm_steady_message(const usm_steady *s) { return s->msg; }

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

static double mismatch(double theta, void *ctx)
{
    const usm_steady *s = ctx;
    double out[USM_SEED_COUNT];
    s->m->steady_seed(theta, &s->p, out);
    return out[USM_SEED_AMPLITUDE_MISMATCH];
}

/* Residual scale: torques are compared with the excitation amplitude. */
static double residual_scale(const usm_params *p)
{
    return p->m0 > 0 ? p->m0 : 1.0;
}

/* ---- search steps ---------------------------------------------------------- */

static int refine_theta(usm_steady *s, double lo, double hi, double *theta)
{
    gsl_function F = {mismatch, s};
    if (gsl_root_fsolver_set(s->brent, &F, lo, hi) != GSL_SUCCESS)
        return -1;
    for (int it = 0; it < 200; ++it) {
        if (gsl_root_fsolver_iterate(s->brent) != GSL_SUCCESS)
            return -1;
        lo = gsl_root_fsolver_x_lower(s->brent);
        hi = gsl_root_fsolver_x_upper(s->brent);
        if (gsl_root_test_interval(lo, hi, 0.0, 1e-15) == GSL_SUCCESS)
            break;
    }
    *theta = gsl_root_fsolver_root(s->brent);
    return 0;
}

static double rotor_residual(const usm_steady *s, const double *u2, double w)
{
    double u[USM_MAX_NU] = {u2[0], u2[1], w}, r[USM_MAX_NU];
    s->m->steady_residual(u, &s->p, r);
    return r[2];
}

/* Rotor speed bracket for the slip model: the rotor row changes sign between
 * -W and W for some W, unless friction cannot carry the load. */
static int find_rotor_speed(usm_steady *s, double *u)
{
    double W = 1.0;
    for (int k = 0; k < 60; ++k, W *= 2.0) {
        double a = rotor_residual(s, u, -W), b = rotor_residual(s, u, W);
        if (!isfinite(a) || !isfinite(b))
            return -1;
        if ((a < 0) != (b < 0)) {
            double lo = -W, hi = W;
            for (int it = 0; it < 200 && hi - lo > 1e-14 * W; ++it) {
                double mid = 0.5 * (lo + hi), c = rotor_residual(s, u, mid);
                if ((c < 0) == (a < 0))
                    lo = mid;
                else
                    hi = mid;
            }
            u[2] = 0.5 * (lo + hi);
            return 0;
        }
    }
    return -1;
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
    int status = GSL_CONTINUE;
    for (int it = 0; it < 200 && status == GSL_CONTINUE; ++it) {
        status = gsl_multiroot_fdfsolver_iterate(s->solver);
        if (status != GSL_SUCCESS) {
            /* No further progress, or a trial step left the domain (a NaN):
             * near a tilt of 1e-9 rad or a huge rotor speed, xtol can ask for
             * more than rounding allows.  Accept the last iterate only if its
             * residual vanishes. */
            status = gsl_multiroot_test_residual(s->solver->f, 1e-12 * fscale);
            break;
        }
        status = gsl_multiroot_test_delta(s->solver->dx, s->solver->x, 0.0, xtol);
        if (status == GSL_SUCCESS)
            status = gsl_multiroot_test_residual(s->solver->f, 1e-10 * fscale);
    }
    if (status != GSL_SUCCESS)
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
}

/* Store a polished root unless it duplicates one already found. */
static void add_root(usm_steady *s, const double *u)
{
    for (size_t k = 0; k < s->count; ++k)
        if (fabs(s->roots[k].u[0] - u[0]) <= 1e-9 * fabs(u[0]))
            return;
    if (s->count == MAX_ROOTS)
        return;
    usm_steady_solution *sol = &s->roots[s->count++];
    memset(sol, 0, sizeof *sol);
    memcpy(sol->u, u, sizeof(double) * (size_t)s->m->nu);
    usm_steady_evaluate(s->m, &s->p, sol);
}

static int by_theta(const void *a, const void *b)
{
    double ta = ((const usm_steady_solution *)a)->theta;
    double tb = ((const usm_steady_solution *)b)->theta;
    return (ta > tb) - (ta < tb);
}

/* Seed (theta, alpha[, phidot_R]) at a refined tilt, then polish. */
static int root_at(usm_steady *s, double theta, double xtol, int *saturated)
{
    double seed[USM_SEED_COUNT], u[USM_MAX_NU] = {theta, 0, 0};
    s->m->steady_seed(theta, &s->p, seed);
    u[1] = atan2(seed[USM_SEED_SIN_ALPHA], seed[USM_SEED_COS_ALPHA]);
    if (s->m->nu == 3 && find_rotor_speed(s, u) != 0) {
        *saturated = 1;
        return -1;
    }
    if (polish(s, u, xtol) != 0)
        return -1;
    add_root(s, u);
    return 0;
}

int usm_steady_solve(usm_steady *s, const usm_params *p, const usm_steady_options *opt)
{
    usm_steady_options def;
    if (!opt) {
        usm_steady_options_default(&def);
        opt = &def;
    }
    s->count = 0;
    s->msg[0] = '\0';
    if (usm_params_check(p, s->m, s->msg) != USM_OK)
        return USM_EINPUT;
    if (!(opt->theta_min > 0 && opt->theta_max > opt->theta_min && opt->grid >= 2)) {
        snprintf(s->msg, USM_MSG_LEN, "theta range: need 0 < theta_min < theta_max and grid >= 2");
        return USM_EINPUT;
    }
    s->p = *p;
    const double ratio = pow(opt->theta_max / opt->theta_min, 1.0 / (opt->grid - 1));
    double th_prev = opt->theta_min, h_prev = mismatch(th_prev, s);
    double need_min = INFINITY, need_at = th_prev;
    int brackets = 0, saturated = 0;
    for (int i = 1; i < opt->grid; ++i) {
        double th = i == opt->grid - 1 ? opt->theta_max : th_prev * ratio, h = mismatch(th, s);
        if (isfinite(h) && h + 1 >= 0 && sqrt(h + 1) * p->m0 < need_min) {
            need_min = sqrt(h + 1) * p->m0;
            need_at = th;
        }
        if (isfinite(h) && isfinite(h_prev) && (h < 0) != (h_prev < 0)) {
            double theta;
            ++brackets;
            if (refine_theta(s, th_prev, th, &theta) == 0)
                root_at(s, theta, opt->xtol, &saturated);
        }
        th_prev = th;
        h_prev = h;
    }
    qsort(s->roots, s->count, sizeof s->roots[0], by_theta);
    if (s->count > 0)
        return USM_OK;
    if (saturated)
        snprintf(s->msg, USM_MSG_LEN,
                 "the load T = %g N m exceeds what the friction law can transmit "
                 "(mu0 = %g, kappa = %g): no rotor speed balances the rotor",
                 p->T, p->mu0, p->kappa);
    else if (brackets == 0)
        snprintf(s->msg, USM_MSG_LEN,
                 "no tilt theta in [%g, %g] rad balances the excitation: m0 = %g N m, "
                 "but holding any tilt needs at least %.4g N m (at theta = %.3g rad)",
                 opt->theta_min, opt->theta_max, p->m0, need_min, need_at);
    else
        snprintf(s->msg, USM_MSG_LEN,
                 "the stationary equations (3.5) did not converge at the %d bracketed tilt(s)",
                 brackets);
    return USM_ENOSOLUTION;
}

int usm_steady_solve_from(usm_steady *s, const usm_params *p, const double *u0)
{
    double u[USM_MAX_NU];
    s->count = 0;
    s->msg[0] = '\0';
    if (usm_params_check(p, s->m, s->msg) != USM_OK)
        return USM_EINPUT;
    s->p = *p;
    memcpy(u, u0, sizeof(double) * (size_t)s->m->nu);
    int rc = polish(s, u, 1e-13);
    if (rc != 0 || !(u[0] > 0)) {
        snprintf(s->msg, USM_MSG_LEN, "Newton iteration from the given start did not converge");
        return USM_ENOSOLUTION;
    }
    add_root(s, u);
    return USM_OK;
}
