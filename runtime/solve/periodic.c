/* Periodic steady states by shooting (see usm_periodic.h).
 *
 * Unknowns.  The state x0 at t0 without its cyclic components (psi, phi_R:
 * they appear in neither M nor f, their start values are a free gauge and
 * stay at those of the ideal solution).  In y = (phi - Omega t, the rest) the
 * ideal stationary solution is an equilibrium; the period map takes y(t0) to
 * y(t0 + T), so the equations are, for every non-cyclic i,
 *     r_i = x_i(t0 + T) - x_i(t0) - 2 pi [i = phi] = 0.
 * (The imperfections force frame A at 2 Omega, so an orbit of period T/2 also
 * solves this; T is the period of the issue and of `usm steady`'s multipliers.)
 * In the tilt vector (a, b, chi; variant tilt, docs/coordinates.md) a and b
 * are already in the frame turning with Omega t: no component shifts by 2 pi
 * (m->x_phi is -1 there, which the test i == m->x_phi never matches), and
 * theta, wherever it is reported, is usm_coords_theta of the state.
 *
 * Start: the ideal stationary solution plus its linear forced response
 * (linear_predictor).
 *
 * Newton.  dr/dx0 = B - I on the non-cyclic rows and columns, B the monodromy
 * matrix.  One CVODES integration (Adams, fixed-point iteration: over one
 * period the motion is not stiff, as in floquet.c) carries x and the
 * variational matrix Psi = S Phi S^{-1} together, S = D^{-1} T as in
 * floquet.c: T the generated tangent map at x0, D a balancing of T G T^{-1}.
 * B = S^{-1} Psi S is formed for the Newton step only, in units of the state
 * scales (scale_of); its rounding (cond S ~ 1/theta^2) slows Newton at worst,
 * it does not move the converged orbit, which is fixed by r alone.  The
 * multipliers come from Psi, with the cyclic directions S e_i split off,
 * by floquet.c's code (solve/multipliers.h).
 *
 * Convergence: max_i |r_i| / scale_i <= tol (default 1e-9).  The scales are
 * physical sizes: 1 rad for phi, the ideal tilt for theta, Omega for the
 * angle rates, Omega theta for the tilt rate, m0/c_t for the twist angle (the
 * angle at which the twist spring's torque equals the excitation's), the
 * ideal rotor speed for phidot_R.  The integration's absolute tolerances are
 * rtol times the same scales.  The floor of r is the twist angle's: tau' =
 * phidot + psidot cos(theta) cancels two rates of size Omega, which leaves
 * about 1e-16 rad of noise per period, 2e-10 of m0/c_t (the other components
 * reach 1e-12); tol = 1e-9 sits above it.
 *
 * Extremes over the orbit (exact_extreme): the extreme sample, then the zero
 * of the quantity's time derivative between its neighbours by Brent's method
 * (core/root.h), the state at each trial time re-integrated from the sample
 * before it (a second CVODES instance, the state alone).
 *
 * Friction saturation of slip models (usm_periodic_saturation, for the
 * periodic sweep): the limit orbit at infinite rotor speed, by a bordered
 * Newton in (the stator's state, the parameter); see periodic_internal.h.
 */
#include <complex.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_complex_math.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_linalg.h>
#include <gsl/gsl_matrix.h>

#include "core/cvode_msg.h"
#include "core/cvodes.h"
#include "core/dense.h"
#include "core/root.h"
#include "multipliers.h"
#include "periodic_internal.h"

#define TWO_PI 6.283185307179586476925286766559
#define NN (USM_MAX_NX * USM_MAX_NX)
#define NS USM_PERIODIC_SAMPLES

struct usm_periodic {
    const usm_model *m;
    int n;
    usm_params p;
    double Omega, t0, T;
    double scale[USM_MAX_NX];
    double S[NN], Sinv[NN];
    /* CVODES */
    usm_cvodes cv;  /* the state and its variational equations over a period */
    usm_cvodes cv2; /* the state alone, re-integrated from a sample (the extremes) */
    usm_root *root;
    double rtol;
    /* eigenproblem without the cyclic directions (solve/multipliers.h) */
    usm_multipliers *mult;
    /* the balancing D of the last coordinates(), and whether it is held
     * (usm_periodic_shoot_hold_balance) */
    double bal[USM_MAX_NX];
    int hold_bal, have_bal;
    usm_steady *steady;
    double samples[NS * (USM_MAX_NX + 4)];
    int have_samples;
    /* the last usm_periodic_shoot: its start, monodromy (physical units and
     * Psi) and residual, its samples in `samples` */
    int have_shot;
    double shot_x0[USM_MAX_NX], shot_x1[USM_MAX_NX], shot_B[NN], shot_Psi[NN], shot_res;
    char msg[USM_MSG_LEN];
};

void usm_periodic_options_default(usm_periodic_options *opt)
{
    opt->rtol = 1e-11;
    opt->tol = 1e-9;
    opt->max_iter = 12;
    opt->t0 = 0.0;
}

const char *usm_periodic_message(const usm_periodic *w) { return w->msg; }

const double *usm_periodic_samples(const usm_periodic *w)
{
    return w->have_samples ? w->samples : NULL;
}

const usm_model *usm_periodic_model_of(const usm_periodic *w) { return w->m; }

void usm_periodic_free(usm_periodic *w)
{
    if (!w)
        return;
    usm_cvodes_free(&w->cv2); /* first: it borrows cv's context */
    usm_cvodes_free(&w->cv);
    usm_root_free(w->root);
    usm_multipliers_free(w->mult);
    usm_steady_free(w->steady);
    free(w);
}

static int cv_rhs(sunrealtype tau, N_Vector yv, N_Vector ydot, void *data);
static int cv_rhs_state(sunrealtype tau, N_Vector yv, N_Vector ydot, void *data);

usm_periodic *usm_periodic_alloc(const usm_model *m)
{
    usm_periodic *w = calloc(1, sizeof *w);
    if (!w)
        return NULL;
    w->m = m;
    w->n = m->nx;
    const size_t n = (size_t)w->n, N = n + n * n;
    w->mult = usm_multipliers_alloc(m);
    w->steady = usm_steady_alloc(m);
    w->root = usm_root_alloc();
    /* tolerances after each CVodeReInit (period_map, state_at) */
    usm_cvodes_spec spec = {.lmm = CV_ADAMS, .n = (sunindextype)N, .rhs = cv_rhs, .data = w,
                            .max_steps = 100000};
    if (!w->mult || !w->steady || !w->root || usm_cvodes_init(&w->cv, &spec, w->msg) != USM_OK) {
        usm_periodic_free(w);
        return NULL;
    }
    usm_cvodes_share(&w->cv2, &w->cv);
    spec.n = (sunindextype)n;
    spec.rhs = cv_rhs_state;
    if (usm_cvodes_init(&w->cv2, &spec, w->msg) != USM_OK) {
        usm_periodic_free(w);
        return NULL;
    }
    return w;
}

/* ---- the motion and its variational equations ------------------------------ */

/* x' = M^{-1} f and, when G is not NULL, G = M^{-1} (df/dx - d(M v)/dx |_{v = x'}).
 * Three kernels, not the fused `linearisation`: it needs x' first, so M would
 * be evaluated twice, and it was measured slower (bench_periodic:
 * one period map 2.5 -> 2.6 ms (3dof), 4.2 -> 4.4 ms (4dof); the last-bit
 * change took 3dof's Newton from 2 to 3 iterations, 7.8 -> 10.8 ms per orbit).
 * Nor in linear_predictor (one evaluation per solve: no measurable change). */
static int motion(const usm_periodic *w, double t, const double *x, double *xdot, double *G)
{
    const int n = w->n;
    double M[NN], Jm[NN];
    int piv[USM_MAX_NX];
    w->m->mass(x, &w->p, M);
    if (usm_lu_factor_dense(n, M, piv) != 0)
        return -1;
    w->m->rhs(x, t, &w->p, xdot);
    usm_lu_solve_dense(n, M, piv, xdot, 1);
    if (G) {
        w->m->jac_rhs(x, t, &w->p, G);
        w->m->jac_mass(x, xdot, &w->p, Jm);
        for (int i = 0; i < n * n; ++i)
            G[i] -= Jm[i];
        usm_lu_solve_dense(n, M, piv, G, n);
        for (int i = 0; i < n * n; ++i)
            if (!isfinite(G[i]))
                return -1;
    }
    for (int i = 0; i < n; ++i)
        if (!isfinite(xdot[i]))
            return -1;
    return 0;
}

/* y = [x (n), Psi column by column (n*n)]; tau = t - t0. */
static int cv_rhs(sunrealtype tau, N_Vector yv, N_Vector ydot, void *data)
{
    usm_periodic *w = data;
    const int n = w->n;
    const double *Y = N_VGetArrayPointer(yv);
    double *D = N_VGetArrayPointer(ydot);
    double G[NN], W[NN], Gs[NN];
    if (motion(w, w->t0 + tau, Y, D, G) != 0)
        return 1; /* recoverable: CVODES retries with a smaller step */
    usm_matmul_dense(n, w->S, G, W);
    usm_matmul_dense(n, W, w->Sinv, Gs);
    const double *Psi = Y + n;
    double *dPsi = D + n;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            double s = 0;
            for (int k = 0; k < n; ++k)
                s += Gs[i * n + k] * Psi[j * n + k];
            dPsi[j * n + i] = s;
        }
    return 0;
}

/* The state alone (the extremes' re-integration from a sample). */
static int cv_rhs_state(sunrealtype tau, N_Vector yv, N_Vector ydot, void *data)
{
    usm_periodic *w = data;
    return motion(w, w->t0 + tau, N_VGetArrayPointer(yv), N_VGetArrayPointer(ydot), NULL) ? 1 : 0;
}

/* S = D^{-1} T(x0), D balancing T G(x0) T^{-1} (as floquet.c), and the basis
 * Qc whose first columns span S e_i for the cyclic i. */
static int coordinates(usm_periodic *w, const double *x0)
{
    const int n = w->n;
    double T[NN], G[NN], W[NN], xdot[USM_MAX_NX], d[USM_MAX_NX];
    w->m->tangent_map(x0, &w->p, T);
    memcpy(w->S, T, sizeof(double) * (size_t)(n * n));
    for (int i = 0; i < n * n; ++i)
        w->Sinv[i] = 0.0;
    for (int i = 0; i < n; ++i)
        w->Sinv[i * n + i] = 1.0;
    if (usm_solve_dense(n, T, w->Sinv) != 0 || motion(w, w->t0, x0, xdot, G) != 0)
        return -1;
    if (w->hold_bal && w->have_bal)
        memcpy(d, w->bal, sizeof(double) * (size_t)n);
    else {
        usm_matmul_dense(n, w->S, G, W);
        usm_matmul_dense(n, W, w->Sinv, G);
        usm_balance_dense(n, G, d);
        memcpy(w->bal, d, sizeof(double) * (size_t)n);
        w->have_bal = 1;
    }
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            w->S[i * n + j] /= d[i];
            w->Sinv[i * n + j] *= d[j];
        }
    return usm_multipliers_basis(w->mult, w->S);
}

/* One sample row: t, x, F_n, F_t, rotor speed. */
static int sample(const usm_periodic *w, double t, const double *x, double *row)
{
    double xdot[USM_MAX_NX], out[USM_OUT_COUNT];
    if (motion(w, t, x, xdot, NULL) != 0)
        return -1;
    w->m->outputs(x, xdot, t, &w->p, out);
    row[0] = t;
    memcpy(row + 1, x, sizeof(double) * (size_t)w->n);
    row[w->n + 1] = out[USM_OUT_F_N];
    row[w->n + 2] = out[USM_OUT_F_T];
    row[w->n + 3] = out[USM_OUT_ROTOR_SPEED];
    return 0;
}

/* Integrate one period from x0: x(t0 + T) into x1, Psi into Psi (row-major),
 * the samples into w->samples. */
static int period_map(usm_periodic *w, const double *x0, double rtol, double *x1, double *Psi)
{
    const int n = w->n;
    int flag;
    char name[32];
    if (coordinates(w, x0) != 0) {
        snprintf(w->msg, USM_MSG_LEN, "the linearisation at the start state is singular or "
                                      "not finite (theta = %g)", usm_coords_theta(w->m, x0));
        return USM_EFAILED;
    }
    usm_cvodes *c = &w->cv;
    double *Y = N_VGetArrayPointer(c->y), *A = N_VGetArrayPointer(c->atol);
    N_VConst(0.0, c->y);
    memcpy(Y, x0, sizeof(double) * (size_t)n);
    for (int i = 0; i < n; ++i) {
        Y[n + i * n + i] = 1.0;
        A[i] = rtol * w->scale[i];
    }
    for (int i = n; i < n + n * n; ++i)
        A[i] = rtol;
    c->cvmsg[0] = '\0';
    int rc;
    if ((rc = usm_cvodes_check(c, "CVodeReInit", CVodeReInit(c->mem, 0.0, c->y))) != USM_OK ||
        (rc = usm_cvodes_check(c, "CVodeSVtolerances", CVodeSVtolerances(c->mem, rtol, c->atol))) !=
            USM_OK ||
        (rc = usm_cvodes_check(c, "CVodeSetStopTime", CVodeSetStopTime(c->mem, w->T))) != USM_OK)
        return rc;
    if (sample(w, w->t0, x0, w->samples) != 0) {
        snprintf(w->msg, USM_MSG_LEN, "the start state is singular (mass matrix)");
        return USM_EFAILED;
    }
    for (int k = 1; k <= NS; ++k) {
        double reached = 0;
        const double tout = k == NS ? w->T : w->T * k / NS;
        flag = CVode(c->mem, tout, c->y, &reached, CV_NORMAL);
        if (flag < 0) {
            snprintf(w->msg, USM_MSG_LEN, "CVODES failed at t = %.6g s of the period: %s%s%.100s",
                     w->t0 + reached, usm_cvode_flag_name(flag, name, sizeof name),
                     c->cvmsg[0] ? " -- " : "", c->cvmsg);
            return USM_EFAILED;
        }
        if (k < NS && sample(w, w->t0 + tout, Y, w->samples + k * (n + 4)) != 0) {
            snprintf(w->msg, USM_MSG_LEN, "the motion became singular at t = %.6g s",
                     w->t0 + tout);
            return USM_EFAILED;
        }
    }
    memcpy(x1, Y, sizeof(double) * (size_t)n);
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
            Psi[i * n + j] = Y[n + j * n + i];
    return USM_OK;
}

/* ---- results -------------------------------------------------------------------- */

/* The multipliers from Psi, as floquet.c's (solve/multipliers.h). */
static int multipliers(usm_periodic *w, const double *Psi, usm_floquet_result *f)
{
    if (usm_multipliers_eigen(w->mult, Psi, w->msg) != 0)
        return USM_EFAILED;
    usm_multipliers_result(w->mult, f);
    f->t0 = w->t0;
    f->t0_dependent = 0;
    f->method = USM_FLOQUET_VARIATIONAL;
    return USM_OK;
}

/* ---- the extremes over the orbit ------------------------------------------------ */

/* The quantities whose extremes are reported. */
enum { Q_THETA, Q_F_N, Q_RATIO, Q_SPEED, Q_STICK };

/* Quantity q at the sample row (t, x, F_n, F_t, rotor speed). */
static double sample_quantity(const usm_periodic *w, int q, const double *row)
{
    const int n = w->n;
    switch (q) {
    case Q_THETA: return usm_coords_theta(w->m, row + 1);
    case Q_F_N: return row[n + 1];
    case Q_RATIO: return fabs(row[n + 2]) / row[n + 1];
    /* the friction stick needs beyond what it has: defined where F_n <= 0
     * too, unlike the ratio, with the same zero where F_n > 0 */
    case Q_STICK: return fabs(row[n + 2]) - w->p.mu0 * row[n + 1];
    default: return row[n + 3];
    }
}

/* Quantity q at (t, x), as a sample row would hold it; NaN when the motion
 * is singular there. */
static double quantity(const usm_periodic *w, int q, double t, const double *x)
{
    double row[USM_MAX_NX + 4];
    if (q == Q_THETA)
        return usm_coords_theta(w->m, x);
    if (sample(w, t, x, row) != 0)
        return NAN;
    return sample_quantity(w, q, row);
}

/* The step of the central difference along the motion, in radians of
 * Omega t: truncation (eps Omega)^2 ~ 1e-10 and rounding 1e-16 / (eps
 * Omega) ~ 1e-11 of the rate, which moves the located time by far less than
 * the 1e-5 of T/(4 pi) at which the extreme's value would change by 1e-10. */
#define RATE_STEP 1e-5

/* dq/dt along the motion at (t, x): theta' from the equations of motion
 * (through the chain rule in the tilt vector);
 * the others by the central difference of q along the tangent (x', 1) of
 * the motion, exact to O(eps^2) (no integration). */
static double rate_step(const usm_periodic *w, int q, double t, const double *x, double step)
{
    const int n = w->n;
    double xdot[USM_MAX_NX], xp[USM_MAX_NX], xm[USM_MAX_NX];
    if (motion(w, t, x, xdot, NULL) != 0)
        return NAN;
    if (q == Q_THETA)
        return usm_coords_theta_rate(w->m, x, xdot);
    const double e = step / w->Omega;
    for (int i = 0; i < n; ++i) {
        xp[i] = x[i] + e * xdot[i];
        xm[i] = x[i] - e * xdot[i];
    }
    return (quantity(w, q, t + e, xp) - quantity(w, q, t - e, xm)) / (2.0 * e);
}

static double rate(const usm_periodic *w, int q, double t, const double *x)
{
    return rate_step(w, q, t, x, RATE_STEP);
}

/* The state on the orbit at time t (taken modulo the period into [t0, t0 +
 * T)): re-integrated (the state alone, rtol as the period map) from the
 * last sample at or before it.  0, or -1 when the integration fails. */
static int state_at(usm_periodic *w, double t, double *x)
{
    const int n = w->n, nc = n + 4;
    const double h = w->T / NS;
    double tau = fmod(t - w->t0, w->T), reached = 0;
    if (tau < 0)
        tau += w->T;
    int j = (int)floor(tau / h);
    j = j < 0 ? 0 : j >= NS ? NS - 1 : j;
    while (j > 0 && w->T * j / NS > tau)
        --j;
    const double tj = w->T * j / NS; /* the sample's tout (period_map) */
    const double *row = w->samples + j * nc;
    if (tau - tj <= 1e-6 * h) {
        /* too close for CVODES to start: the first-order Taylor step, whose
         * error (1e-6 h)^2 x''/2 is ~1e-15 of x */
        double xdot[USM_MAX_NX];
        if (motion(w, w->t0 + tj, row + 1, xdot, NULL) != 0)
            return -1;
        for (int i = 0; i < n; ++i)
            x[i] = row[1 + i] + (tau - tj) * xdot[i];
        return 0;
    }
    usm_cvodes *c = &w->cv2;
    double *Y = N_VGetArrayPointer(c->y), *A = N_VGetArrayPointer(c->atol);
    memcpy(Y, row + 1, sizeof(double) * (size_t)n);
    for (int i = 0; i < n; ++i)
        A[i] = w->rtol * w->scale[i];
    /* a failure is the caller's NaN (the extreme is then the sample's) */
    if (CVodeReInit(c->mem, tj, c->y) != CV_SUCCESS ||
        CVodeSVtolerances(c->mem, w->rtol, c->atol) != CV_SUCCESS ||
        CVodeSetStopTime(c->mem, tau) != CV_SUCCESS ||
        CVode(c->mem, tau, c->y, &reached, CV_NORMAL) < 0)
        return -1;
    memcpy(x, Y, sizeof(double) * (size_t)n);
    return 0;
}

typedef struct extreme_ctx {
    usm_periodic *w;
    int q;
    double tk; /* the extreme sample's time */
} extreme_ctx;

/* The locator's function: dq/dt at tk + s (NaN when the re-integration
 * fails). */
static double extreme_rate(double s, void *data)
{
    extreme_ctx *c = data;
    double x[USM_MAX_NX];
    if (state_at(c->w, c->tk + s, x) != 0)
        return NAN;
    return rate(c->w, c->q, c->tk + s, x);
}

/* The extreme of q near sample k located as exact_extreme below says: its time
 * into *t and its value returned (the sample's, at the sample's time, when
 * the location fails or does not improve on it). */
static double extreme_near(usm_periodic *w, int q, double sign, int k, double *t)
{
    const int nc = w->n + 4;
    double best = sample_quantity(w, q, w->samples + k * nc), s, x[USM_MAX_NX];
    const double h = w->T / NS;
    extreme_ctx c = {w, q, w->t0 + w->T * k / NS};
    const usm_root_stop stop = {1e-6 * h, 0.0, 100};
    *t = c.tk;
    if (usm_root_brent_eval(w->root, extreme_rate, &c, -h, h, &stop, &s) == 0 &&
        state_at(w, c.tk + s, x) == 0) {
        const double v = quantity(w, q, c.tk + s, x);
        if (sign * v > sign * best) {
            best = v;
            *t = c.tk + s;
        }
    }
    return best;
}

/* The maximum (sign +1) or minimum (-1) of quantity q over the orbit: the
 * extreme sample k, then the zero of dq/dt between the samples k - 1 and k +
 * 1 by Brent's method (core/root.h) to 1e-6 of the sample spacing (the
 * value's error is quadratic in the time's: (4 pi 1e-6 / 200)^2 ~ 1e-14 of
 * its size; 1e-9 moved the values by 5e-11 at most, the re-integration's
 * noise, and cost 10 % more in a sweep), and q there on the re-integrated
 * state.  The sample's value where the rate does
 * not change sign there (an extreme at a kink) or the location fails. */
static double exact_extreme(usm_periodic *w, int q, double sign)
{
    const int nc = w->n + 4;
    int k = 0;
    double t;
    for (int i = 1; i < NS; ++i)
        if (sign * sample_quantity(w, q, w->samples + i * nc) >
            sign * sample_quantity(w, q, w->samples + k * nc))
            k = i;
    return extreme_near(w, q, sign, k, &t);
}

/* Amplitude of the harmonic `h` (of the excitation frequency) of periodic samples. */
static double harmonic(const double *v, int stride, int h)
{
    double re = 0, im = 0;
    for (int i = 0; i < NS; ++i) {
        re += v[i * stride] * cos(TWO_PI * h * i / NS);
        im -= v[i * stride] * sin(TWO_PI * h * i / NS);
    }
    return 2.0 * hypot(re, im) / NS;
}

static void orbit_outputs(usm_periodic *w, usm_periodic_result *r)
{
    const int n = w->n, nc = n + 4; /* samples: nc columns (usm_periodic_samples) */
    const double *s = w->samples;
    const double *Fn = s + n + 1, *wr = s + n + 3;
    double th[NS], sum_w = 0, sum_th = 0;
    int open = 0;
    for (int i = 0; i < NS; ++i) {
        th[i] = usm_coords_theta(w->m, s + i * nc + 1);
        sum_w += wr[i * nc];
        sum_th += th[i];
        open |= !(Fn[i * nc] > 0.0);
    }
    r->rotor_speed_mean = sum_w / NS; /* trapezoid rule: spectral on a periodic function */
    r->rotor_speed_ripple = exact_extreme(w, Q_SPEED, 1.0) - exact_extreme(w, Q_SPEED, -1.0);
    r->F_n_min = exact_extreme(w, Q_F_N, -1.0);
    r->F_n_max = exact_extreme(w, Q_F_N, 1.0);
    r->contact_open = r->F_n_min < 0.0;
    r->friction_needed_max = open || r->contact_open ? NAN : exact_extreme(w, Q_RATIO, 1.0);
    r->theta_mean = sum_th / NS;
    r->theta_min = exact_extreme(w, Q_THETA, -1.0);
    r->theta_max = exact_extreme(w, Q_THETA, 1.0);
    r->theta_harmonic_2 = harmonic(th, 1, 2);
    r->F_n_harmonic_2 = harmonic(Fn, nc, 2);
    /* the closed-to-open switches around the period (cyclic) */
    r->openings_per_period = 0;
    for (int i = 0; i < NS; ++i)
        r->openings_per_period += Fn[i * nc] < 0.0 && !(Fn[((i + NS - 1) % NS) * nc] < 0.0);
    if (r->openings_per_period == 0 && (r->contact_open || Fn[0] < 0.0))
        r->openings_per_period = 1; /* between two samples, or never closed */
    r->validity = open || !(r->F_n_min > 0.0) ? USM_INVALID_CONTACT_OPEN
                  : !w->m->slip && r->friction_needed_max > w->p.mu0 ? USM_INVALID_STICK
                                                                     : USM_VALID;
}

/* ---- the solver ------------------------------------------------------------------ */

/* b <- A^{-1} b, k x k complex (row-major; a C99 double complex has the layout
 * of a gsl_complex), GSL's LU with partial pivoting; -1 when singular. */
static int complex_solve(int k, double complex *A, double complex *b)
{
    gsl_matrix_complex_view Av = gsl_matrix_complex_view_array((double *)A, (size_t)k, (size_t)k);
    gsl_vector_complex_view bv = gsl_vector_complex_view_array((double *)b, (size_t)k);
    gsl_permutation *perm = gsl_permutation_alloc((size_t)k);
    int sign, status = -1;
    if (!perm)
        return -1;
    if (gsl_linalg_complex_LU_decomp(&Av.matrix, perm, &sign) == GSL_SUCCESS) {
        status = 0;
        for (int c = 0; c < k; ++c)
            if (!(gsl_complex_abs(gsl_matrix_complex_get(&Av.matrix, (size_t)c, (size_t)c)) > 0))
                status = -1;
        if (status == 0 && gsl_linalg_complex_LU_svx(&Av.matrix, perm, &bv.vector) != GSL_SUCCESS)
            status = -1;
    }
    gsl_permutation_free(perm);
    return status;
}

/* Newton's start: the ideal orbit xbar plus the linear forced response at t0.
 * About xbar the linearisation is constant in these coordinates (integrated
 * twist law), dx' = G dx + F(t) with F = M^{-1} (f(p) - f(ideal)) along xbar;
 * harmonic k of F (NPRED samples) gives dx_k = (i k Omega - G)^{-1} F_k on
 * the non-cyclic components.  It leaves an error of second order in the
 * imperfections, so Newton needs one or two steps fewer than from xbar. */
#define NPRED 8
static void linear_predictor(const usm_periodic *w, const usm_params *q,
                             const usm_steady_solution *s, double *x0)
{
    const usm_model *m = w->m;
    const int n = w->n;
    double orbit[2 * USM_MAX_NX], G[NN], Jm[NN], M[NN], xdot[USM_MAX_NX];
    double complex Fk[NPRED / 2][USM_MAX_NX];
    int piv[USM_MAX_NX], idx[USM_MAX_NX], k = 0;
    for (int i = 0; i < n; ++i)
        if (!m->cyclic[i])
            idx[k++] = i;
    const double *xbar = orbit + m->steady_state_out.x;
    m->steady_state(s->u, s->beta, w->t0, q, orbit);
    m->mass(xbar, q, M);
    if (usm_lu_factor_dense(n, M, piv) != 0)
        return;
    m->jac_rhs(xbar, w->t0, q, G);
    m->jac_mass(xbar, orbit + m->steady_state_out.xdot, q, Jm);
    for (int i = 0; i < n * n; ++i)
        G[i] -= Jm[i];
    usm_lu_solve_dense(n, M, piv, G, n);
    memset(Fk, 0, sizeof Fk);
    for (int j = 0; j < NPRED; ++j) {
        const double t = w->t0 + w->T * j / NPRED;
        double f0[USM_MAX_NX];
        m->steady_state(s->u, s->beta, t, q, orbit);
        m->mass(xbar, q, M);
        if (usm_lu_factor_dense(n, M, piv) != 0)
            return;
        m->rhs(xbar, t, &w->p, xdot);
        m->rhs(xbar, t, q, f0);
        for (int i = 0; i < n; ++i)
            xdot[i] -= f0[i];
        usm_lu_solve_dense(n, M, piv, xdot, 1);
        for (int h = 0; h < NPRED / 2; ++h)
            for (int i = 0; i < n; ++i)
                Fk[h][i] += xdot[i] * cexp(-I * TWO_PI * h * j / NPRED) / NPRED;
    }
    double dx[USM_MAX_NX] = {0};
    for (int h = 0; h < NPRED / 2; ++h) {
        double complex A[NN], b[USM_MAX_NX];
        for (int a = 0; a < k; ++a) {
            for (int c = 0; c < k; ++c)
                A[a * k + c] = (a == c ? I * h * w->Omega : 0.0) - G[idx[a] * n + idx[c]];
            b[a] = Fk[h][idx[a]];
        }
        if (complex_solve(k, A, b) != 0)
            return;
        for (int a = 0; a < k; ++a)
            dx[idx[a]] += (h == 0 ? 1.0 : 2.0) * creal(b[a]);
    }
    for (int i = 0; i < n; ++i)
        if (!isfinite(dx[i]))
            return;
    for (int i = 0; i < n; ++i)
        x0[i] += dx[i];
}

static int ideal_start(usm_periodic *w, const usm_params *p, double *x0, double *theta,
                       double *speed)
{
    usm_params q = *p;
    q.amp_imbalance = q.phase_error = q.mode_split = 0.0;
    int rc = usm_steady_solve(w->steady, &q, NULL);
    if (rc != USM_OK) {
        snprintf(w->msg, USM_MSG_LEN,
                 "no start: the ideal motor (imperfections 0) has no stationary solution (%.150s)",
                 usm_steady_message(w->steady));
        return rc == USM_EINPUT || rc == USM_ENOSOLUTION ? rc : USM_EFAILED;
    }
    const usm_steady_solution *s = usm_steady_root(w->steady, 0);
    double orbit[2 * USM_MAX_NX];
    w->m->steady_state(s->u, s->beta, w->t0, &q, orbit);
    memcpy(x0, orbit + w->m->steady_state_out.x, sizeof(double) * (size_t)w->n);
    if (usm_params_check_ideal(p, w->msg) != USM_OK) {
        w->msg[0] = '\0';
        linear_predictor(w, &q, s, x0);
    }
    *theta = s->theta;
    *speed = s->rotor_speed;
    return USM_OK;
}

/* The guard of every read of an orientation index below: a model whose
 * descriptor lacks one (-1) is refused here instead of indexing x with it. */
static int layout_check(usm_periodic *w)
{
    const usm_model *m = w->m;
    if (usm_coords_layout_ok(m) && m->x_tau >= 0 && m->x_tau < m->nx &&
        m->x_phi_Rdot < m->nx)
        return USM_OK;
    snprintf(w->msg, USM_MSG_LEN,
             "model %s: its state lacks the stator's orientation (phi, theta, psi or a, b, chi, "
             "with their rates) or the twist angle tau, which the shooting needs", m->name);
    return USM_EINPUT;
}

/* theta > 0 (in the tilt vector: 0 < a^2 + b^2 < 1): the contact point is
 * singular on the axis in both coordinate sets (docs/coordinates.md). */
static int admissible(const usm_model *m, const double *x)
{
    return usm_coords_theta(m, x) > 0;
}

/* The state scales (see the top of this file).  In the tilt vector (a, b)
 * are the tilt itself (scale theta), their rates Omega theta; the spin rate
 * chidot = phidot + psidot is what the rotor speed and the twist spring see,
 * of size Omega theta^2 on the orbit: stated as the tilt rates, Omega theta
 * (simulate.c weights it so too).  That is tighter than the Euler angles'
 * Omega on phidot and psidot apart, and within reach: no cancellation forms
 * it here, the residual of the stationary orbit's period map is 2e-12
 * (3dof) and 4e-11 (4dof) of the scales at rtol 1e-11.  Needs
 * usm_coords_layout_ok(m) and m->x_tau >= 0 (checked by the callers). */
static void set_scales(usm_periodic *w, double theta, double speed)
{
    const usm_model *m = w->m;
    for (int i = 0; i < w->n; ++i)
        w->scale[i] = 1.0;
    if (m->coordinates == 1) {
        w->scale[m->x_a] = w->scale[m->x_b] = theta;
        w->scale[m->x_adot] = w->scale[m->x_bdot] = w->scale[m->x_chidot] = w->Omega * theta;
    } else {
        w->scale[m->x_theta] = theta;
        w->scale[m->x_phidot] = w->scale[m->x_psidot] = w->Omega;
        w->scale[m->x_thetadot] = w->Omega * theta;
    }
    w->scale[m->x_tau] = w->p.m0 / w->p.c_t;
    if (!(w->scale[m->x_tau] > 0 && isfinite(w->scale[m->x_tau])))
        w->scale[m->x_tau] = theta;
    if (m->x_phi_Rdot >= 0)
        w->scale[m->x_phi_Rdot] = fmax(fabs(speed), w->Omega * theta);
}

int usm_periodic_solve(usm_periodic *w, const usm_params *p, const double *x_start,
                       const usm_periodic_options *opt, usm_periodic_result *out)
{
    usm_periodic_options def;
    const usm_model *m = w->m;
    const int n = w->n;
    int rc;
    if (!opt) {
        usm_periodic_options_default(&def);
        opt = &def;
    }
    memset(out, 0, sizeof *out);
    w->msg[0] = '\0';
    w->have_samples = w->have_shot = 0;
    if (m->x_tau < 0) {
        snprintf(w->msg, USM_MSG_LEN,
                 "model %s: the paper's twist angle phi + psi cos(theta) grows without bound "
                 "near the stationary motion, so no motion is periodic in (phi - Omega t, "
                 "theta, rates); use the variant imperfect, twist_integrated or tilt", m->name);
        return USM_EINPUT;
    }
    if ((rc = layout_check(w)) != USM_OK)
        return rc;
    if (usm_params_check(p, m, w->msg) != USM_OK)
        return USM_EINPUT;
    if (!(opt->rtol >= 1e-14 && opt->rtol <= 1e-6) || !(opt->tol > 0 && opt->tol < 1) ||
        opt->max_iter < 1 || !isfinite(opt->t0)) {
        snprintf(w->msg, USM_MSG_LEN, "options: need rtol in [1e-14, 1e-6], tol in (0, 1), "
                                      "max_iter >= 1 and a finite t0");
        return USM_EINPUT;
    }
    w->p = *p;
    w->Omega = TWO_PI * p->f;
    w->T = 1.0 / p->f;
    w->t0 = opt->t0;
    w->rtol = opt->rtol;
    double x0[USM_MAX_NX], x1[USM_MAX_NX], Psi[NN], theta = 0, speed = 0;
    rc = ideal_start(w, p, x0, &theta, &speed);
    if (x_start) {
        if (rc != USM_OK) { /* the scales only: take them from the given start */
            theta = usm_coords_theta(m, x_start);
            speed = m->x_phi_Rdot >= 0 ? x_start[m->x_phi_Rdot] : 0.0;
        }
        memcpy(x0, x_start, sizeof(double) * (size_t)n);
        w->msg[0] = '\0';
    } else if (rc != USM_OK)
        return rc;
    if (!(theta > 0 && isfinite(theta))) {
        snprintf(w->msg, USM_MSG_LEN, "start: theta must be positive, got %g", theta);
        return USM_EINPUT;
    }
    set_scales(w, theta, speed);
    out->t0 = w->t0;
    out->period = w->T;
    out->nx = n;
    for (int it = 0;; ++it) {
        if ((rc = period_map(w, x0, opt->rtol, x1, Psi)) != USM_OK)
            return rc;
        /* residual and Newton matrix on the non-cyclic components, in units of the scales */
        int idx[USM_MAX_NX], k = 0;
        double r[USM_MAX_NX], J[NN], res = 0;
        for (int i = 0; i < n; ++i)
            if (!m->cyclic[i]) {
                idx[k] = i;
                r[k] = (x1[i] - x0[i] - (i == m->x_phi ? TWO_PI : 0.0)) / w->scale[i];
                res = fmax(res, fabs(r[k]));
                ++k;
            }
        out->iterations = it;
        out->residual = res;
        if (!isfinite(res)) {
            snprintf(w->msg, USM_MSG_LEN, "the period map is not finite");
            return USM_EFAILED;
        }
        if (res <= opt->tol) {
            memcpy(out->x0, x0, sizeof(double) * (size_t)n);
            /* B = S^{-1} Psi S for the record (multipliers from Psi) */
            double W[NN];
            usm_matmul_dense(n, w->Sinv, Psi, W);
            usm_matmul_dense(n, W, w->S, out->floquet.monodromy);
            if ((rc = multipliers(w, Psi, &out->floquet)) != USM_OK)
                return rc;
            out->converged = 1;
            w->have_samples = 1;
            orbit_outputs(w, out);
            return USM_OK;
        }
        if (it >= opt->max_iter) {
            snprintf(w->msg, USM_MSG_LEN,
                     "Newton did not converge in %d iterations (residual %.3g of the state "
                     "scales; tolerance %.3g)", opt->max_iter, res, opt->tol);
            return USM_EFAILED;
        }
        double W[NN], B[NN];
        usm_matmul_dense(n, w->Sinv, Psi, W);
        usm_matmul_dense(n, W, w->S, B);
        int piv[USM_MAX_NX];
        for (int a = 0; a < k; ++a)
            for (int b = 0; b < k; ++b)
                J[a * k + b] = (B[idx[a] * n + idx[b]] - (a == b)) * w->scale[idx[b]] /
                               w->scale[idx[a]];
        if (usm_lu_factor_dense(k, J, piv) != 0) {
            snprintf(w->msg, USM_MSG_LEN,
                     "the Newton matrix B - I is singular: a multiplier is 1 (a fold of the "
                     "orbit branch)");
            return USM_EFAILED;
        }
        usm_lu_solve_dense(k, J, piv, r, 1);
        for (int a = 0; a < k; ++a)
            x0[idx[a]] -= r[a] * w->scale[idx[a]];
        if (!admissible(m, x0)) {
            snprintf(w->msg, USM_MSG_LEN, "Newton left the admissible states (%s)",
                     m->coordinates == 1 ? "a^2 + b^2 not in (0, 1): theta = 0, where the "
                                           "contact point is singular, or beyond pi/2"
                                         : "theta <= 0");
            return USM_EFAILED;
        }
    }
}

/* ---- friction saturation ----------------------------------------------------------- */

/* The slip velocity [m/s] that stands for infinity (as the stationary sweep's,
 * study/sweep_branch.c): the friction law equals its supremum there to
 * rounding. */
#define V_HUGE 1e15

double usm_periodic_friction_supremum(const usm_model *m, const usm_params *p)
{
    double mp[USM_FRICTION_COUNT], mm[USM_FRICTION_COUNT];
    if (!m->friction)
        return NAN;
    m->friction(V_HUGE, p, mp);
    m->friction(-V_HUGE, p, mm);
    return fmax(fabs(mp[USM_FRICTION_MU]), fabs(mm[USM_FRICTION_MU]));
}

/* The residuals of the saturated orbit (see usm_periodic_saturation) after a
 * period map from x0 with the samples in w: the stator's periodicity in
 * units of the scales, and for the rotor speed the change the mean rotor
 * acceleration makes over the period (the trapezoid rule on the samples:
 * spectral once the stator is periodic), in units of sw.  0 or -1. */
static int saturation_residual(usm_periodic *w, const double *x0, const double *x1, double sw,
                               double *r)
{
    const usm_model *m = w->m;
    const int n = w->n, nc = n + 4, iw = m->x_phi_Rdot;
    int k = 0;
    for (int i = 0; i < n; ++i) {
        if (m->cyclic[i])
            continue;
        if (i != iw) {
            r[k++] = (x1[i] - x0[i] - (i == m->x_phi ? TWO_PI : 0.0)) / w->scale[i];
            continue;
        }
        double sum = 0, xdot[USM_MAX_NX];
        for (int j = 0; j < NS; ++j) {
            const double *row = w->samples + j * nc;
            if (motion(w, row[0], row + 1, xdot, NULL) != 0)
                return -1;
            sum += xdot[iw];
        }
        r[k++] = sum * (w->T / NS) / sw;
    }
    return 0;
}

int usm_periodic_saturation(usm_periodic *w, const usm_params *p, const usm_param_info *info,
                            const double *x_start, double lambda_scale, double lambda_tol,
                            const usm_periodic_options *opt, double *lambda)
{
    const usm_model *m = w->m;
    const int n = w->n, iw = m->x_phi_Rdot;
    usm_periodic_options def;
    if (!opt) {
        usm_periodic_options_default(&def);
        opt = &def;
    }
    w->msg[0] = '\0';
    w->have_samples = w->have_shot = 0;
    if (!m->friction || iw < 0 || m->x_tau < 0) {
        snprintf(w->msg, USM_MSG_LEN, "model %s: no friction law to saturate", m->name);
        return USM_EINPUT;
    }
    int rc = layout_check(w);
    if (rc != USM_OK)
        return rc;
    w->p = *p;
    double *field = usm_params_field(&w->p, info);
    double lam = *field;
    w->Omega = TWO_PI * p->f;
    w->T = 1.0 / p->f;
    w->t0 = opt->t0;
    w->rtol = opt->rtol;
    double x0[USM_MAX_NX], x1[USM_MAX_NX], xdot[USM_MAX_NX], out[USM_OUT_COUNT], Psi[NN];
    memcpy(x0, x_start, sizeof(double) * (size_t)n);
    if (motion(w, w->t0, x0, xdot, NULL) != 0)
        return USM_EFAILED;
    m->outputs(x0, xdot, w->t0, &w->p, out);
    const double v = out[USM_OUT_V_REL], theta = usm_coords_theta(m, x0);
    if (!(fabs(v) > 0) || !(fabs(x0[iw]) > 0) || !(theta > 0)) {
        snprintf(w->msg, USM_MSG_LEN, "saturation: no slip to start from");
        return USM_EFAILED;
    }
    /* the rotor speed at which the slip velocity is V_HUGE (the slip is
     * dominated by the rotor's speed there), held fixed: the stator's motion
     * no longer depends on it */
    const double W = x0[iw] * (V_HUGE / fabs(v));
    x0[iw] = W;
    set_scales(w, theta, fabs(W));
    const double sw = w->Omega * theta; /* the rotor speed's change over a period */
    int idx[USM_MAX_NX], k = 0;
    for (int i = 0; i < n; ++i)
        if (!m->cyclic[i])
            idx[k++] = i;
    for (int it = 0; it <= 2 * opt->max_iter; ++it) {
        double r[USM_MAX_NX], r2[USM_MAX_NX], J[NN], B[NN], Wm[NN], res = 0;
        *field = lam;
        rc = period_map(w, x0, opt->rtol, x1, Psi);
        if (rc != USM_OK)
            return rc;
        if (saturation_residual(w, x0, x1, sw, r) != 0)
            return USM_EFAILED;
        for (int a = 0; a < k; ++a)
            res = fmax(res, fabs(r[a]));
        usm_matmul_dense(n, w->Sinv, Psi, Wm);
        usm_matmul_dense(n, Wm, w->S, B);
        /* the parameter's column by a forward difference */
        const double dl = 1e-7 * lambda_scale;
        *field = lam + dl;
        if ((rc = period_map(w, x0, opt->rtol, x1, Psi)) != USM_OK)
            return rc;
        if (saturation_residual(w, x0, x1, sw, r2) != 0)
            return USM_EFAILED;
        *field = lam;
        /* columns: the non-cyclic states but the rotor speed (held), then lambda;
         * the rotor speed's row: d(omega(T))/dx_j = d(int omega' dt)/dx_j */
        for (int a = 0; a < k; ++a) {
            const int i = idx[a];
            const double si = i == iw ? sw : w->scale[i];
            int c = 0;
            for (int b = 0; b < k; ++b) {
                const int j = idx[b];
                if (j == iw)
                    continue;
                J[a * k + c++] = (B[i * n + j] - (i == j)) * w->scale[j] / si;
            }
            J[a * k + c] = (r2[a] - r[a]) / dl * lambda_scale;
        }
        int piv[USM_MAX_NX];
        if (!isfinite(res) || usm_lu_factor_dense(k, J, piv) != 0) {
            snprintf(w->msg, USM_MSG_LEN, "saturation: the bordered Newton matrix is singular or "
                                          "not finite");
            return USM_EFAILED;
        }
        usm_lu_solve_dense(k, J, piv, r, 1);
        int c = 0;
        for (int b = 0; b < k; ++b)
            if (idx[b] != iw)
                x0[idx[b]] -= r[c++] * w->scale[idx[b]];
        const double dlam = r[c] * lambda_scale;
        lam -= dlam;
        if (!admissible(m, x0) || !isfinite(lam)) {
            snprintf(w->msg, USM_MSG_LEN, "saturation: Newton left the admissible states");
            return USM_EFAILED;
        }
        if (res <= opt->tol && fabs(dlam) <= lambda_tol) {
            *lambda = lam;
            *field = lam;
            return USM_OK;
        }
    }
    snprintf(w->msg, USM_MSG_LEN, "saturation: Newton did not converge");
    return USM_EFAILED;
}

/* ---- the shooting problem for a continuation ---------------------------------------- */

int usm_periodic_shoot_layout(const usm_periodic *w, int *idx, double *scale)
{
    int k = 0;
    for (int i = 0; i < w->n; ++i) {
        scale[i] = w->scale[i];
        if (!w->m->cyclic[i])
            idx[k++] = i;
    }
    return k;
}

void usm_periodic_shoot_set_scale(usm_periodic *w, const double *scale)
{
    memcpy(w->scale, scale, sizeof(double) * (size_t)w->n);
}

/* w's parameters, period and frequency from p. */
static void set_params(usm_periodic *w, const usm_params *p)
{
    w->p = *p;
    w->Omega = TWO_PI * p->f;
    w->T = 1.0 / p->f;
}

/* The state alone over one period from x0 (the integration of state_at):
 * x(t0 + T) into x1, no samples.  0, or -1. */
static int period_map_state(usm_periodic *w, const double *x0, double *x1)
{
    const int n = w->n;
    usm_cvodes *c = &w->cv2;
    double *Y = N_VGetArrayPointer(c->y), *A = N_VGetArrayPointer(c->atol), reached = 0;
    memcpy(Y, x0, sizeof(double) * (size_t)n);
    for (int i = 0; i < n; ++i)
        A[i] = w->rtol * w->scale[i];
    if (CVodeReInit(c->mem, 0.0, c->y) != CV_SUCCESS ||
        CVodeSVtolerances(c->mem, w->rtol, c->atol) != CV_SUCCESS ||
        CVodeSetStopTime(c->mem, w->T) != CV_SUCCESS ||
        CVode(c->mem, w->T, c->y, &reached, CV_NORMAL) < 0)
        return -1;
    memcpy(x1, Y, sizeof(double) * (size_t)n);
    for (int i = 0; i < n; ++i)
        if (!isfinite(x1[i]))
            return -1;
    return 0;
}

/* r_a = (x1_i - x0_i - 2 pi [i = phi]) / scale_i over the non-cyclic i. */
static void shoot_residual(const usm_periodic *w, const double *x0, const double *x1, double *r)
{
    int k = 0;
    for (int i = 0; i < w->n; ++i)
        if (!w->m->cyclic[i]) {
            r[k++] = (x1[i] - x0[i] - (i == w->m->x_phi ? TWO_PI : 0.0)) / w->scale[i];
        }
}

int usm_periodic_shoot(usm_periodic *w, const usm_params *p, const usm_param_info *info,
                       double dlam, const double *x0, double *r, double *J)
{
    const usm_model *m = w->m;
    const int n = w->n;
    double x1[USM_MAX_NX], Psi[NN];
    int idx[USM_MAX_NX], k = 0;
    w->have_shot = 0;
    w->have_samples = 0;
    if (!admissible(m, x0)) {
        snprintf(w->msg, USM_MSG_LEN, "the state left the admissible ones (theta <= 0)");
        return USM_EFAILED;
    }
    for (int i = 0; i < n; ++i)
        if (!m->cyclic[i])
            idx[k++] = i;
    if (J && dlam != 0.0) {
        /* the parameter's column first: the state-alone map at the moved
         * parameter would overwrite nothing of the map at p kept below */
        usm_params q = *p;
        double r2[USM_MAX_NX];
        *usm_params_field(&q, info) += dlam;
        set_params(w, &q);
        if (period_map_state(w, x0, x1) != 0) {
            snprintf(w->msg, USM_MSG_LEN, "the period map at the moved parameter failed");
            return USM_EFAILED;
        }
        shoot_residual(w, x0, x1, r2);
        for (int a = 0; a < k; ++a)
            J[a * (k + 1) + k] = r2[a];
    }
    set_params(w, p);
    int rc = period_map(w, x0, w->rtol, x1, Psi);
    if (rc != USM_OK)
        return rc;
    shoot_residual(w, x0, x1, r);
    for (int a = 0; a < k; ++a)
        if (!isfinite(r[a])) {
            snprintf(w->msg, USM_MSG_LEN, "the period map is not finite");
            return USM_EFAILED;
        }
    double W[NN];
    usm_matmul_dense(n, w->Sinv, Psi, W);
    usm_matmul_dense(n, W, w->S, w->shot_B);
    memcpy(w->shot_Psi, Psi, sizeof Psi);
    memcpy(w->shot_x0, x0, sizeof(double) * (size_t)n);
    memcpy(w->shot_x1, x1, sizeof(double) * (size_t)n);
    w->shot_res = 0;
    for (int a = 0; a < k; ++a)
        w->shot_res = fmax(w->shot_res, fabs(r[a]));
    if (J)
        for (int a = 0; a < k; ++a) {
            for (int b = 0; b < k; ++b)
                J[a * (k + 1) + b] = (w->shot_B[idx[a] * n + idx[b]] - (a == b)) / w->scale[idx[a]];
            J[a * (k + 1) + k] = dlam != 0.0 ? (J[a * (k + 1) + k] - r[a]) / dlam : 0.0;
        }
    w->have_shot = 1;
    return USM_OK;
}

int usm_periodic_shoot_state(usm_periodic *w, const usm_params *p, const double *x0, double *r)
{
    double x1[USM_MAX_NX];
    w->have_shot = 0;
    w->have_samples = 0;
    if (!admissible(w->m, x0)) {
        snprintf(w->msg, USM_MSG_LEN, "the state left the admissible ones (theta <= 0)");
        return USM_EFAILED;
    }
    set_params(w, p);
    if (period_map_state(w, x0, x1) != 0) {
        snprintf(w->msg, USM_MSG_LEN, "the period map of the state failed");
        return USM_EFAILED;
    }
    shoot_residual(w, x0, x1, r);
    return USM_OK;
}

int usm_periodic_shoot_result(usm_periodic *w, usm_periodic_result *out)
{
    if (!w->have_shot)
        return USM_EFAILED;
    memset(out, 0, sizeof *out);
    out->t0 = w->t0;
    out->period = w->T;
    out->nx = w->n;
    out->residual = w->shot_res;
    memcpy(out->x0, w->shot_x0, sizeof(double) * (size_t)w->n);
    memcpy(out->floquet.monodromy, w->shot_B, sizeof(double) * (size_t)(w->n * w->n));
    int rc = multipliers(w, w->shot_Psi, &out->floquet);
    if (rc != USM_OK)
        return rc;
    out->converged = 1;
    w->have_samples = 1;
    orbit_outputs(w, out);
    return USM_OK;
}

double usm_periodic_shoot_stick_excess(usm_periodic *w)
{
    return w->have_shot ? exact_extreme(w, Q_STICK, 1.0) : NAN;
}

double usm_periodic_shoot_F_n_min(usm_periodic *w)
{
    return w->have_shot ? exact_extreme(w, Q_F_N, -1.0) : NAN;
}

int usm_periodic_shoot_multipliers(usm_periodic *w, usm_floquet_result *f)
{
    if (!w->have_shot)
        return USM_EFAILED;
    return multipliers(w, w->shot_Psi, f);
}

void usm_periodic_shoot_hold_balance(usm_periodic *w, int hold) { w->hold_bal = hold != 0; }

int usm_periodic_shoot_reduced(usm_periodic *w, double *R)
{
    if (!w->have_shot)
        return -1;
    return usm_multipliers_reduced(w->mult, w->shot_Psi, R);
}

double usm_periodic_shoot_max_modulus(usm_periodic *w)
{
    usm_floquet_result f;
    if (!w->have_shot || multipliers(w, w->shot_Psi, &f) != USM_OK)
        return NAN;
    return f.max_modulus;
}

/* ---- an extreme's time as an unknown (the envelope's contact_loss and stick_loss) ---- */

static int quantity_code(usm_periodic_quantity which)
{
    return which == USM_PERIODIC_Q_STICK_EXCESS ? Q_STICK : Q_F_N;
}

void usm_periodic_shoot_set_t0(usm_periodic *w, double t0) { w->t0 = t0; }


int usm_periodic_shoot_t0_column(usm_periodic *w, double *col)
{
    const int n = w->n;
    double f0[USM_MAX_NX], f1[USM_MAX_NX];
    if (!w->have_shot || motion(w, w->t0, w->shot_x0, f0, NULL) != 0 ||
        motion(w, w->t0 + w->T, w->shot_x1, f1, NULL) != 0)
        return USM_EFAILED;
    int k = 0;
    for (int i = 0; i < n; ++i) {
        if (w->m->cyclic[i])
            continue;
        double s = f1[i];
        for (int j = 0; j < n; ++j)
            s -= w->shot_B[i * n + j] * f0[j];
        col[k++] = s / w->scale[i];
    }
    return USM_OK;
}

int usm_periodic_quantity_rate(usm_periodic *w, const usm_params *p, usm_periodic_quantity which,
                               double t, const double *x, double *value, double *dvalue)
{
    const int q = quantity_code(which);
    set_params(w, p);
    *value = quantity(w, q, t, x);
    if (dvalue)
        *dvalue = rate(w, q, t, x);
    return isfinite(*value) && (!dvalue || isfinite(*dvalue)) ? USM_OK : USM_EFAILED;
}

int usm_periodic_quantity_rate_step(usm_periodic *w, const usm_params *p,
                                    usm_periodic_quantity which, double t, const double *x,
                                    double step, double *value, double *dvalue)
{
    const int q = quantity_code(which);
    if (!(step > 0 && step < 1))
        return USM_EFAILED;
    set_params(w, p);
    *value = quantity(w, q, t, x);
    *dvalue = rate_step(w, q, t, x, step);
    return isfinite(*value) && isfinite(*dvalue) ? USM_OK : USM_EFAILED;
}

int usm_periodic_shoot_extremes(usm_periodic *w, usm_periodic_quantity which, double sign,
                                int max, double *t, double *v)
{
    const int nc = w->n + 4, q = quantity_code(which);
    int count = 0;
    if (!w->have_shot)
        return -1;
    for (int i = 0; i < NS && count < max; ++i) {
        const double a = sign * sample_quantity(w, q, w->samples + ((i + NS - 1) % NS) * nc);
        const double b = sign * sample_quantity(w, q, w->samples + i * nc);
        const double c = sign * sample_quantity(w, q, w->samples + ((i + 1) % NS) * nc);
        /* >= on one side only: a plateau of two equal samples is one extreme */
        if (!(b >= a && b > c))
            continue;
        double ti;
        const double vi = extreme_near(w, q, sign, i, &ti);
        /* into [t0, t0 + T) */
        double tau = fmod(ti - w->t0, w->T);
        if (tau < 0)
            tau += w->T;
        int j = count++;
        for (; j > 0 && sign * v[j - 1] < sign * vi; --j) {
            t[j] = t[j - 1];
            v[j] = v[j - 1];
        }
        t[j] = w->t0 + tau;
        v[j] = vi;
    }
    return count;
}

int usm_periodic_shoot_state_at(usm_periodic *w, double t, double *x)
{
    return w->have_shot && state_at(w, t, x) == 0 ? USM_OK : USM_EFAILED;
}

double usm_periodic_shoot_half_period_asymmetry(usm_periodic *w, usm_periodic_quantity which)
{
    const int nc = w->n + 4, q = quantity_code(which);
    double d = 0;
    if (!w->have_shot || NS % 2 != 0)
        return NAN;
    for (int i = 0; i < NS / 2; ++i)
        d = fmax(d, fabs(sample_quantity(w, q, w->samples + i * nc) -
                         sample_quantity(w, q, w->samples + (i + NS / 2) * nc)));
    return d;
}
