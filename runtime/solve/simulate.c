/* Transient simulation of M(x) x' = f(x, t) with CVODES (see usm_simulate.h).
 *
 * Events drive the loop: CVode in CV_NORMAL mode is asked for the next sample
 * time or the next end of an excitation period, whichever comes first, so the
 * values handed out are CVODES' interpolants (dense output) and the internal
 * steps are chosen by the error control alone.  Quadratures of theta and of
 * phidot_R give exact period means (and the stick model's rotor angle, which
 * is not a state there).  Root functions find contact events and runaway.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>


#include <cvodes/cvodes.h>
#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include "core/cvode_msg.h"
#include "core/cvodes.h"
#include "core/dense.h"
#include "core/grow.h"
#include "contact_mode.h"
#include "impact.h"
#include "usm_simulate.h"

#define TWO_PI 6.283185307179586476925286766559

/* Root functions, in CVODES' order. */
enum { ROOT_TILT_ZERO, ROOT_TILT_LIMIT, ROOT_SPEED, ROOT_FN, ROOT_STICK, NROOTS };

/* A step count per CVode call (at most one excitation period) that no sane
 * motion needs: the paper's parameters take about 30 to 60; a start at rest
 * below a small unstable root (3e-11 rad at F0 = 1.0 N, f = 38 kHz) circles the
 * axis at some 60,000 a period (docs/operating-point.md). */
#define STEPS_PER_CALL 200000

struct usm_sim {
    const usm_model *m;    /* the model integrated */
    const usm_model *user; /* the model asked for: m, or m in the other coordinates
                              (states in and out are in its layout) */
    int n;
    int iphi, ith, ipsi, irot; /* positions in x (irot = -1: rotor angle not a state) */
    int iphid, ithd, ipsid;    /* positions of their rates */
    int tilt;                  /* 1: the tilt-vector coordinates (m->coordinates) */
    int layout_ok;
    double phi_prev;           /* the samples' phi, for its branch (tilt coordinates) */
    usm_params p;
    usm_sim_options o;
    double Omega, t0, t1;
    /* integrator state z = T x + c + d (t - t0) (see to_x) */
    double c[USM_MAX_NY], d[USM_MAX_NY];
    double ewt_scale[USM_MAX_NY];
    unsigned char ewt_absolute[USM_MAX_NY];
    int nroots;
    /* the contact mode (usm_model.unilateral): 0 closed (the model's kernels,
     * n = nx), 1 open (the open mode's kernels, n = ny) */
    const usm_unilateral *u;  /* NULL: the contact never opens */
    int nx, mode;
    usm_mode k;               /* the current mode's kernels */
    long stats_done[5];  /* steps, rhs, jac, error test and Newton failures of the
                          * integrators of earlier modes (each switch makes a new one) */
    double v_land;       /* a bounce slower than this lands (usm_simulate.h) */
    usm_cvodes cv;        /* BDF, Newton with a dense LU; quadratures int theta, rotor angle */
    /* the LU of the current mass matrix (core/dense.h: at 7 x 7 to 12 x 12
     * GSL's LU, a BLAS call per column, was a quarter of a simulation's time) */
    double lu[USM_MAX_NY * USM_MAX_NY];
    int piv[USM_MAX_NY];
    usm_steady *steady;
    usm_floquet *floquet;  /* the roots' stability, for the start at rest */
    usm_floquet_result *fl;
    size_t fl_cap;
    /* running diagnostics, updated by the root function at every step */
    usm_sim_summary *sum;
    double Fn_min, excess_max;
    int in_open, in_stick;
    double open_since, stick_since;
    /* where it ends (usm_simulate.h): consecutive periods within settle_tol
     * of each root, and of the decay rule */
    long *root_run;
    size_t root_cap;
    long rest_run;
    double rest_prev;
    long trap_run;   /* periods held below rest_fraction trap_ref */
    double trap_ref; /* the smallest root's tilt when that root is unstable, else 0 */
    char msg[USM_MSG_LEN];
};

void usm_sim_options_default(usm_sim_options *opt)
{
    memset(opt, 0, sizeof *opt);
    opt->start = USM_SIM_FROM_REST;
    opt->t0 = 0.0;
    opt->duration = 0.0;
    opt->tilt0 = 0.0;
    opt->rotor_angle0 = 0.0;
    opt->rate = 0.0;
    opt->rtol = 1e-8;
    opt->settle_tol = 1e-3;
    opt->settle_periods = 100;
    opt->theta_limit = 0.5;
    opt->speed_limit = 1e4;
    opt->max_steps = 0;
    opt->max_step = 0.0;
    opt->max_twist_growth = 400.0;
    opt->rest_fraction = 0.1;
}

double usm_sim_default_rate(const usm_params *p)
{
    return 10.0 * p->f;
}

const char *usm_sim_stop_name(usm_sim_stop stop)
{
    switch (stop) {
    case USM_SIM_COMPLETED:
        return "completed";
    case USM_SIM_INTEGRATOR:
        return "integrator";
    case USM_SIM_RUNAWAY_TILT:
        return "runaway_tilt";
    case USM_SIM_TILT_ZERO:
        return "tilt_zero";
    case USM_SIM_RUNAWAY_SPEED:
        return "runaway_speed";
    case USM_SIM_MAX_STEPS:
        return "max_steps";
    case USM_SIM_STOPPED:
        return "stopped";
    case USM_SIM_REST:
        return "rest";
    }
    return "unknown";
}

const char *usm_sim_message(const usm_sim *s) { return s->msg; }

/* The kernels and workspace of contact mode `mode` (0 closed, 1 open). */
static void set_mode(usm_sim *s, int mode)
{
    s->mode = mode;
    usm_mode_kernels(s->m, mode, &s->k);
    s->n = s->k.n;
}

/* Integrate model m (s->user, or s->user in the other coordinates: the same
 * nx, neither of them unilateral). */
static void use_model(usm_sim *s, const usm_model *m)
{
    s->m = m;
    s->n = m->nx;
    s->iphi = m->x_phi;
    s->ith = m->x_theta;
    s->ipsi = m->x_psi;
    s->irot = m->x_phi_R;
    s->iphid = m->x_phidot;
    s->ithd = m->x_thetadot;
    s->ipsid = m->x_psidot;
    s->tilt = 0;
    s->layout_ok = s->iphi >= 0 && s->ith >= 0 && s->ipsi >= 0 && s->iphid >= 0 &&
                   s->ithd >= 0 && s->ipsid >= 0;
    if (m->coordinates == 1) {
        /* the tilt vector (a, b, chi): integrated as it is (regular at theta = 0) */
        s->tilt = 1;
        s->iphi = m->x_a;
        s->ith = m->x_b;
        s->ipsi = m->x_chi;
        s->iphid = m->x_adot;
        s->ithd = m->x_bdot;
        s->ipsid = m->x_chidot;
        s->layout_ok = m->x_a >= 0 && m->x_b >= 0 && m->x_chi >= 0 && m->x_adot >= 0 &&
                       m->x_bdot >= 0 && m->x_chidot >= 0 && m->other_coordinates;
    }
    /* the asked-for model's own indices are read too (x0 in, samples out):
     * a -1 among them is refused by check_options, never used */
    s->layout_ok = s->layout_ok && usm_coords_layout_ok(m) && usm_coords_layout_ok(s->user);
    s->nx = m->nx;
    s->u = m->unilateral;
    set_mode(s, 0);
}

/* Coordinates (docs/coordinates.md): unless the options ask for the
 * model's own, a model with a counterpart in the tilt vector is integrated in
 * it -- the same motion, regular at theta = 0, where the start-up at
 * F0 = 1.4 N, f = 38.8 kHz (wobble decaying to zero) took 108,369 steps in
 * Euler angles and 40,978 in the tilt vector; from rest at the paper's
 * preload 10,253 and 9,901.  States in and out (x0, samples, final_x) stay in
 * the model's own layout. */
static void choose_coordinates(usm_sim *s, const usm_sim_options *o)
{
    const usm_model *r = s->user->other_coordinates;
    use_model(s, !o->own_coordinates && s->user->coordinates == 0 && !s->user->unilateral &&
                             r && r->coordinates == 1 && !r->unilateral && r->nx == s->user->nx
                     ? r : s->user);
}

usm_sim *usm_sim_alloc(const usm_model *m)
{
    usm_sim *s = calloc(1, sizeof *s);
    if (!s)
        return NULL;
    s->user = m;
    use_model(s, m);
    set_mode(s, 0);
    s->steady = usm_steady_alloc(m);
    s->floquet = usm_floquet_alloc(m);
    if (!s->steady || !s->floquet) {
        usm_sim_free(s);
        return NULL;
    }
    return s;
}

void usm_sim_free(usm_sim *s)
{
    if (!s)
        return;
    usm_cvodes_free(&s->cv);
    usm_steady_free(s->steady);
    usm_floquet_free(s->floquet);
    free(s->fl);
    free(s->root_run);
    free(s);
}

/* ---- the model in the integrator's coordinates -------------------------------- */

/* The tilt theta of a state x. */
static double theta_of(const usm_sim *s, const double *x)
{
    if (!s->tilt)
        return x[s->ith];
    const double a = x[s->iphi], b = x[s->ith], s2 = a * a + b * b;
    return atan2(sqrt(s2), sqrt(fmax(0.0, 1.0 - s2)));
}

/* z = T x + c + d (t - t0), where T replaces phi by phi + psi and phidot by
 * phidot + psidot (see set_scales for why). */
static void to_x(const usm_sim *s, double t, const double *z, double *x)
{
    const double dt = t - s->t0;
    for (int i = 0; i < s->n; ++i)
        x[i] = z[i] - s->c[i] - s->d[i] * dt;
    if (s->tilt)
        return;
    x[s->iphi] -= x[s->ipsi];
    x[s->iphid] -= x[s->ipsid];
}

static void to_z(const usm_sim *s, double t, const double *x, double *z)
{
    const double dt = t - s->t0;
    double u[USM_MAX_NY];
    memcpy(u, x, sizeof(double) * (size_t)s->n);
    if (!s->tilt) {
        u[s->iphi] += u[s->ipsi];
        u[s->iphid] += u[s->ipsid];
    }
    for (int i = 0; i < s->n; ++i)
        z[i] = u[i] + s->c[i] + s->d[i] * dt;
}

/* z' = T x' + d */
static void to_zdot(const usm_sim *s, const double *xdot, double *zdot)
{
    for (int i = 0; i < s->n; ++i)
        zdot[i] = xdot[i] + s->d[i];
    if (s->tilt)
        return;
    zdot[s->iphi] += xdot[s->ipsi];
    zdot[s->iphid] += xdot[s->ipsid];
}

/* LU of M(x) into s->lu; 0, or -1 when singular or not finite (theta -> 0). */
static int factor_mass(usm_sim *s, const double *x)
{
    const int n = s->n;
    s->k.mass(x, &s->p, s->lu);
    for (int i = 0; i < n * n; ++i)
        if (!isfinite(s->lu[i]))
            return -1;
    return usm_lu_factor_dense(n, s->lu, s->piv);
}

/* x and xdot = M^{-1} f at (t, y).  0, or -1 (recoverable for CVODES). */
static int evaluate(usm_sim *s, double t, const double *y, double *x, double *xdot)
{
    to_x(s, t, y, x);
    if (factor_mass(s, x) != 0)
        return -1;
    s->k.rhs(x, t, &s->p, xdot);
    usm_lu_solve_dense(s->n, s->lu, s->piv, xdot, 1);
    for (int i = 0; i < s->n; ++i)
        if (!isfinite(xdot[i]))
            return -1;
    return 0;
}

static int cv_rhs(sunrealtype t, N_Vector yv, N_Vector ydot, void *data)
{
    usm_sim *s = data;
    double x[USM_MAX_NY], xdot[USM_MAX_NY];
    if (evaluate(s, t, N_VGetArrayPointer(yv), x, xdot) != 0)
        return 1; /* recoverable: CVODES retries with a smaller step */
    to_zdot(s, xdot, N_VGetArrayPointer(ydot));
    return 0;
}

/* x' = T^{-1} (z' - d) */
static void to_xdot(const usm_sim *s, const double *zdot, double *xdot)
{
    for (int i = 0; i < s->n; ++i)
        xdot[i] = zdot[i] - s->d[i];
    if (s->tilt)
        return;
    xdot[s->iphi] -= xdot[s->ipsi];
    xdot[s->iphid] -= xdot[s->ipsid];
}

/* dz'/dz = T (dx'/dx) T^{-1}, dx'/dx = M^{-1} (df/dx - d(M v)/dx |_{v = x'}). */
static int cv_jac(sunrealtype t, N_Vector yv, N_Vector fy, SUNMatrix J, void *data,
                  N_Vector tmp1, N_Vector tmp2, N_Vector tmp3)
{
    usm_sim *s = data;
    const int n = s->n;
    double x[USM_MAX_NY], xdot[USM_MAX_NY];
    double Jf[USM_MAX_NY * USM_MAX_NY], Jm[USM_MAX_NY * USM_MAX_NY], G[USM_MAX_NY * USM_MAX_NY];
    const double *f = N_VGetArrayPointer(fy);
    (void)tmp1;
    (void)tmp2;
    (void)tmp3;
    to_x(s, t, N_VGetArrayPointer(yv), x);
    to_xdot(s, f, xdot);
    if (factor_mass(s, x) != 0)
        return 1;
    s->k.jac_rhs(x, t, &s->p, Jf);
    s->k.jac_mass(x, xdot, &s->p, Jm);
    for (int i = 0; i < n * n; ++i)
        G[i] = Jf[i] - Jm[i];
    usm_lu_solve_dense(n, s->lu, s->piv, G, n);
    /* T^{-1} on the right: column psi -= column phi; T on the left: row phi += row psi */
    for (int k = 0; k < (s->tilt ? 0 : 2); ++k) {
        const int a = k ? s->iphid : s->iphi, b = k ? s->ipsid : s->ipsi;
        for (int i = 0; i < n; ++i)
            G[i * n + b] -= G[i * n + a];
        for (int j = 0; j < n; ++j)
            G[a * n + j] += G[b * n + j];
    }
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const double g = G[i * n + j];
            if (!isfinite(g))
                return 1;
            SM_ELEMENT_D(J, i, j) = g;
        }
    return 0;
}

/* Quadratures: q0 = int theta dt, q1 = int phidot_R dt. */
static int cv_quad(sunrealtype t, N_Vector yv, N_Vector qdot, void *data)
{
    usm_sim *s = data;
    double x[USM_MAX_NY], xdot[USM_MAX_NY], out[USM_OUT_COUNT];
    double *d = N_VGetArrayPointer(qdot);
    if (evaluate(s, t, N_VGetArrayPointer(yv), x, xdot) != 0)
        return 1;
    s->k.outputs(x, xdot, t, &s->p, out);
    d[0] = theta_of(s, x);
    d[1] = out[USM_OUT_ROTOR_SPEED];
    return isfinite(d[1]) ? 0 : 1;
}

/* CVODES evaluates the root functions at the end of every step (and at
 * interpolated points while locating a root), which makes this the place to
 * see extremes at step resolution without stepping one at a time. */
static int cv_roots(sunrealtype t, N_Vector yv, sunrealtype *g, void *data)
{
    usm_sim *s = data;
    double x[USM_MAX_NY], xdot[USM_MAX_NY], out[USM_OUT_COUNT];
    if (evaluate(s, t, N_VGetArrayPointer(yv), x, xdot) != 0)
        return -1;
    s->k.outputs(x, xdot, t, &s->p, out);
    const double theta = theta_of(s, x), Fn = out[USM_OUT_F_N], Ft = out[USM_OUT_F_T];
    const double speed = out[USM_OUT_ROTOR_SPEED];
    g[ROOT_TILT_ZERO] = s->tilt ? 1.0 : theta; /* a singularity of the Euler angles only */
    g[ROOT_TILT_LIMIT] = s->o.theta_limit - theta;
    g[ROOT_SPEED] = s->o.speed_limit - fabs(speed);
    g[ROOT_FN] = Fn;
    if (s->nroots > ROOT_STICK)
        g[ROOT_STICK] = s->p.mu0 * Fn - fabs(Ft);
    if (s->mode == 1) {
        /* open: the guard is the gap; no contact force, nothing to check */
        double gap[1 + USM_MAX_NY];
        s->u->guard_open(x, &s->p, gap);
        g[ROOT_FN] = gap[s->u->guard_open_out.gap];
        if (s->nroots > ROOT_STICK)
            g[ROOT_STICK] = 1.0;
    }
    for (int i = 0; i < s->nroots; ++i)
        if (!isfinite(g[i]))
            return -1;
    s->sum->theta_min = fmin(s->sum->theta_min, theta);
    s->sum->theta_max = fmax(s->sum->theta_max, theta);
    if (s->mode == 0) {
        s->Fn_min = fmin(s->Fn_min, Fn);
        s->excess_max = fmax(s->excess_max, fabs(Ft) - s->p.mu0 * Fn);
    }
    return 0;
}

/* Error weights.  phi and psi are absolute (see usm_simulate.h): their size,
 * |alpha| or a slowly growing psi offset, says nothing about the accuracy the
 * twisting torque needs. */
static int cv_ewt(N_Vector yv, N_Vector ewt, void *data)
{
    const usm_sim *s = data;
    const double *y = N_VGetArrayPointer(yv);
    double *w = N_VGetArrayPointer(ewt);
    for (int i = 0; i < s->n; ++i) {
        const double tol = s->o.rtol * (s->ewt_absolute[i] ? s->ewt_scale[i]
                                                           : fabs(y[i]) + s->ewt_scale[i]);
        w[i] = 1.0 / tol;
    }
    return 0;
}

/* ---- set-up ------------------------------------------------------------------------- */

static int input_error(usm_sim *s, const char *what)
{
    snprintf(s->msg, USM_MSG_LEN, "%s", what);
    return USM_EINPUT;
}

static int check_options(usm_sim *s, const usm_sim_options *o)
{
    if (!s->layout_ok)
        return input_error(s, "model: the state has no phi, theta, psi (or a, b, chi) and "
                              "their rates");
    if (!isfinite(o->t0))
        return input_error(s, "t0: must be a finite number");
    if (!(o->duration > 0) || !isfinite(o->duration))
        return input_error(s, "duration: must be positive (a number of seconds)");
    if (!(o->rate >= 0) || !isfinite(o->rate))
        return input_error(s, "rate: must be >= 0 samples per second");
    if (!(o->rtol >= 1e-14 && o->rtol <= 1e-3))
        return input_error(s, "rtol: must be in [1e-14, 1e-3]");
    if (!(o->settle_tol > 0 && o->settle_tol < 1))
        return input_error(s, "settle_tol: must be in (0, 1)");
    if (o->settle_periods < 1)
        return input_error(s, "settle_periods: must be at least 1");
    if (!(o->rest_fraction >= 0 && o->rest_fraction <= 0.5))
        return input_error(s, "rest_fraction: must be in [0, 0.5] (0: never decide rest)");
    if (!(o->theta_limit > 0 && o->theta_limit < 1.5))
        return input_error(s, "theta_limit: must be in (0, 1.5) rad");
    if (!(o->speed_limit > 0) || !isfinite(o->speed_limit))
        return input_error(s, "speed_limit: must be a positive number");
    if (o->max_steps < 0)
        return input_error(s, "max_steps: must be >= 0");
    if (!(o->max_step >= 0) || !isfinite(o->max_step))
        return input_error(s, "max_step: must be >= 0 seconds");
    if (!(o->max_twist_growth >= 0) || !isfinite(o->max_twist_growth))
        return input_error(s, "max_twist_growth: must be >= 0 (0: no limit)");
    if (o->start == USM_SIM_FROM_REST && !(o->tilt0 >= 0 && o->tilt0 < o->theta_limit))
        return input_error(s, "tilt0: must be >= 0 (0: the start at rest, below every unstable "
                              "root) and below theta_limit");
    if (!isfinite(o->rotor_angle0))
        return input_error(s, "rotor_angle0: must be a finite number");
    if (o->start == USM_SIM_FROM_STATE) {
        for (int i = 0; i < s->n; ++i)
            if (!isfinite(o->x0[i])) {
                snprintf(s->msg, USM_MSG_LEN, "x0: %s is not a finite number", s->user->state_names[i]);
                return USM_EINPUT;
            }
        if (s->user != s->m) {
            const double th0 = o->x0[s->user->x_theta];
            if (!(th0 > 0 && th0 < o->theta_limit))
                return input_error(s, "x0: theta must be > 0 and below theta_limit");
        } else if (s->tilt && !(theta_of(s, o->x0) < o->theta_limit && o->x0[s->iphi] * o->x0[s->iphi] +
                                     o->x0[s->ith] * o->x0[s->ith] < 1))
            return input_error(s, "x0: a^2 + b^2 must be below sin(theta_limit)^2");
        else if (s->tilt && !(theta_of(s, o->x0) > 0))
            return input_error(s, "x0: a^2 + b^2 must be > 0 (theta = 0: the contact point is "
                                  "not defined on the stator's axis, docs/coordinates.md)");
        if (!s->tilt && !(o->x0[s->ith] > 0 && o->x0[s->ith] < o->theta_limit))
            return input_error(s, "x0: theta must be > 0 (the z-x-z angles are singular at 0) "
                                  "and below theta_limit");
    }
    if (o->start != USM_SIM_FROM_REST && o->start != USM_SIM_FROM_STATIONARY &&
        o->start != USM_SIM_FROM_STATE)
        return input_error(s, "start: unknown start");
    return USM_OK;
}

/* usm_params_check demands m0 > 0 because a stationary solution needs the
 * excitation; a transient with the excitation off (ring-down, energy checks)
 * is still a meaningful motion. */
static int check_params(usm_sim *s, const usm_params *p)
{
    usm_params q = *p;
    char why[USM_MSG_LEN];
    if (q.m0 == 0.0)
        q.m0 = 1.0;
    if (usm_params_check(&q, s->m, why) != USM_OK) {
        snprintf(s->msg, USM_MSG_LEN, "%s", why);
        return USM_EINPUT;
    }
    if (s->m->unilateral && !(p->M > 0)) {
        snprintf(s->msg, USM_MSG_LEN, "M: must be positive for a contact that may open (the "
                 "rotor's axial motion is a state of its own), got %g", p->M);
        return USM_EINPUT;
    }
    return USM_OK;
}

int usm_sim_check(usm_sim *s, const usm_params *p, const usm_sim_options *opt)
{
    int rc;
    s->msg[0] = '\0';
    if ((rc = check_options(s, opt)) != USM_OK)
        return rc;
    return check_params(s, p);
}

/* A new integrator for the current mode from state x at time t, quadratures
 * q0 (int theta dt) and q1 (the rotor angle).  A switch of the contact mode
 * restarts the integration (a new state length, a discontinuous derivative). */
static int setup_integrator(usm_sim *s, double t, const double *x0, double q0, double q1)
{
    double y0[USM_MAX_NY];
    const double q[2] = {q0, q1};
    to_z(s, t, x0, y0);
    /* F_n: both ways for the episodes; a unilateral contact opens where F_n
     * falls through 0 and closes where the gap does */
    const int dir[NROOTS] = {-1, -1, -1, s->u ? -1 : 0, 0};
    const usm_cvodes_spec spec = {.lmm = CV_BDF,
                                  .n = s->n,
                                  .t0 = t,
                                  .y0 = y0,
                                  .rhs = cv_rhs,
                                  .jac = cv_jac,
                                  .data = s,
                                  .max_steps = STEPS_PER_CALL,
                                  .rtol = s->o.rtol,
                                  .ewt = cv_ewt,
                                  .t_stop = s->t1,
                                  .nq = 2,
                                  .quad = cv_quad,
                                  .q0 = q,
                                  .nroots = s->nroots,
                                  .roots = cv_roots,
                                  .root_dir = dir};
    usm_cvodes *c = &s->cv;
    int rc;
    if ((rc = usm_cvodes_init(c, &spec, s->msg)) != USM_OK)
        return rc;
    /* every mode is an oscillator with a few percent damping: eigenvalues
     * close to the imaginary axis, where BDF orders 3 to 5 are unstable */
    if ((rc = usm_cvodes_check(c, "CVodeSetStabLimDet", CVodeSetStabLimDet(c->mem, SUNTRUE))) !=
        USM_OK)
        return rc;
    /* Near the stationary orbit z hardly changes, and CVODES would step over
     * hundreds of excitation periods at once: blind to a perturbation that
     * grows from one period to the next (the 3-DOF orbit does, after about
     * 20 ms: docs/simulate.md).  A quarter period keeps it visible. */
    const double hmax = s->o.max_step > 0 ? s->o.max_step : 0.25 / s->p.f;
    if ((rc = usm_cvodes_check(c, "CVodeSetMaxStep", CVodeSetMaxStep(c->mem, hmax))) != USM_OK)
        return rc;
    return usm_cvodes_check(c, "CVodeSetQuadErrCon", CVodeSetQuadErrCon(c->mem, SUNFALSE));
}

/* ---- the run ------------------------------------------------------------------------ */

typedef struct run_state {
    const usm_sim_callbacks *cb;
    double T;                 /* excitation period */
    long k, k_last;           /* next sample index, last regular sample index */
    double dt_sample;
    int final_sample;         /* one more sample at t1 */
    long j;                   /* next period end: t0 + j T */
    double q_prev[2];         /* quadratures at the previous period end */
    int have_avg;
    double theta_avg, speed_avg;
    double open_prev;         /* time open up to the previous period end */
    double last_out;          /* end of the last period outside the tolerance */
    long in_tol_run;          /* consecutive periods inside, at the end */
    int rest;                 /* the decay rule was met at the last period end */
} run_state;

static double sample_time(const usm_sim *s, const run_state *r)
{
    if (r->dt_sample <= 0)
        return INFINITY;
    if (r->k <= r->k_last)
        return fmin(s->t0 + (double)r->k * r->dt_sample, s->t1);
    return r->k == r->k_last + 1 && r->final_sample ? s->t1 : INFINITY;
}

static double period_end(const usm_sim *s, const run_state *r)
{
    const double t = s->t0 + (double)r->j * r->T;
    return t <= s->t1 ? t : INFINITY;
}

static int emit_sample(usm_sim *s, run_state *r, double t, const double *y, const double *q)
{
    double x[USM_MAX_NY], xdot[USM_MAX_NY];
    usm_sim_sample smp;
    memset(&smp, 0, sizeof smp);
    if (evaluate(s, t, y, x, xdot) != 0) {
        /* the state CVODES accepted is always evaluable; keep going with rates */
        to_x(s, t, y, x);
        for (int i = 0; i < s->n; ++i)
            xdot[i] = NAN;
    }
    s->k.outputs(x, xdot, t, &s->p, smp.out);
    smp.t = t;
    smp.nx = s->nx; /* the open mode's y begins with x */
    smp.open = s->mode;
    if (s->mode == 1) {
        double gap[1 + USM_MAX_NY];
        s->u->guard_open(x, &s->p, gap);
        smp.gap = gap[s->u->guard_open_out.gap];
    }
    smp.x = x;
    smp.xdot = xdot;
    double xu[USM_MAX_NX], xdu[USM_MAX_NX];
    if (s->user != s->m) { /* the asked-for model's layout (the Euler angles) */
        const usm_model *u = s->user;
        double ed[6];
        usm_coords_map(s->m, x, t, &s->p, s->phi_prev, u, xu);
        for (int i = 0; i < u->nx; ++i) /* the other states' rates, by name */
            for (int j = 0; j < s->n; ++j)
                if (strcmp(u->state_names[i], s->m->state_names[j]) == 0)
                    xdu[i] = xdot[j];
        usm_coords_euler_rates(s->m, x, xdot, &s->p, ed);
        const int idx[6] = {u->x_phi, u->x_theta, u->x_psi, u->x_phidot, u->x_thetadot,
                            u->x_psidot};
        for (int k = 0; k < 6; ++k)
            xdu[idx[k]] = ed[k];
        smp.x = xu;
        smp.xdot = xdu;
    }
    smp.y = smp.x;
    smp.ny = s->user == s->m ? s->n : s->user->nx;
    double e[6];
    usm_coords_euler_angles(s->m, x, t, &s->p, s->phi_prev, e);
    s->phi_prev = e[0];
    smp.phi = e[0];
    smp.theta = e[1];
    smp.psi = e[2];
    smp.phidot = e[3];
    smp.thetadot = e[4];
    smp.psidot = e[5];
    smp.rotor_angle = s->irot >= 0 ? x[s->irot] : q[1];
    smp.rotor_speed = smp.out[USM_OUT_ROTOR_SPEED];
    smp.have_avg = r->have_avg;
    smp.theta_avg = r->theta_avg;
    smp.rotor_speed_avg = r->speed_avg;
    smp.validity = s->mode == 1 ? USM_VALID /* the unilateral model describes it */
                   : !(smp.out[USM_OUT_F_N] > 0) ? USM_INVALID_CONTACT_OPEN
                   : !s->m->slip && fabs(smp.out[USM_OUT_F_T]) > s->p.mu0 * smp.out[USM_OUT_F_N]
                       ? USM_INVALID_STICK
                       : USM_VALID;
    s->sum->samples++;
    if (r->cb && r->cb->sample)
        return r->cb->sample(&smp, r->cb->data);
    return 0;
}

static double rel_diff(double v, double ref)
{
    return (v - ref) / fmax(fabs(ref), 1e-300);
}

static void end_of_period(usm_sim *s, run_state *r, double t, const double *q)
{
    usm_sim_summary *sum = s->sum;
    r->theta_avg = (q[0] - r->q_prev[0]) / r->T;
    r->speed_avg = (q[1] - r->q_prev[1]) / r->T;
    r->q_prev[0] = q[0];
    r->q_prev[1] = q[1];
    r->have_avg = 1;
    sum->periods++;
    sum->theta_avg_end = r->theta_avg;
    sum->rotor_speed_avg_end = r->speed_avg;
    if (s->u) {
        /* the time open in this period, the window of rotor_speed_avg_end */
        const double open = sum->contact_open.total + (s->in_open ? t - s->open_since : 0.0);
        sum->open_fraction_end = (open - r->open_prev) / r->T;
        r->open_prev = open;
    }
    if (sum->have_steady) {
        sum->theta_rel_end = rel_diff(r->theta_avg, sum->steady.theta);
        sum->rotor_speed_rel_end = rel_diff(r->speed_avg, sum->steady.rotor_speed);
        if (fabs(sum->theta_rel_end) <= sum->settle_tol &&
            fabs(sum->rotor_speed_rel_end) <= sum->settle_tol)
            r->in_tol_run++;
        else {
            r->in_tol_run = 0;
            r->last_out = t;
        }
    }
    /* every root, by the rule of root 0 (usm_simulate.h, "Where it ended") */
    for (size_t k = 0; k < sum->roots; ++k) {
        const usm_steady_solution *root = usm_steady_root(s->steady, k);
        if (fabs(rel_diff(r->theta_avg, root->theta)) <= sum->settle_tol &&
            fabs(rel_diff(r->speed_avg, root->rotor_speed)) <= sum->settle_tol)
            s->root_run[k]++;
        else
            s->root_run[k] = 0;
    }
    /* the decay rule: on the tilt alone (usm_simulate.h: a loaded slip
     * model's rotor creeps backwards while the wobble dies out) */
    if (sum->rest_fraction > 0) {
        const double lim = sum->rest_fraction * sum->rest_theta_ref;
        if (r->theta_avg < lim)
            s->rest_run++;
        else
            s->rest_run = 0;
        /* held far below an unstable smallest root: trapped at the axis */
        if (s->trap_ref > 0 && r->theta_avg < sum->rest_fraction * s->trap_ref)
            s->trap_run++;
        else
            s->trap_run = 0;
        s->rest_prev = r->theta_avg;
        if (s->rest_run >= USM_SIM_REST_PERIODS || s->trap_run >= USM_SIM_TRAP_PERIODS) {
            r->rest = 1;
            sum->t_rest = t;
            if (s->rest_run < USM_SIM_REST_PERIODS)
                sum->rest_theta_ref = s->trap_ref;
        }
    }
}

/* Where the run ended (usm_simulate.h): the root whose settling stretch
 * reaches the end of a completed run, the nearest at the end should several;
 * rest when the decay rule stopped it; otherwise none. */
static int settled_on(const usm_sim *s, const run_state *r, int rc)
{
    const usm_sim_summary *sum = s->sum;
    if (r->rest)
        return USM_SIM_SETTLED_REST;
    if (rc != USM_OK || sum->stop != USM_SIM_COMPLETED)
        return USM_SIM_SETTLED_NONE;
    int best = USM_SIM_SETTLED_NONE;
    double best_d = INFINITY;
    for (size_t k = 0; k < sum->roots; ++k) {
        if (s->root_run[k] < sum->settle_periods)
            continue;
        const usm_steady_solution *root = usm_steady_root(s->steady, k);
        const double d = fmax(fabs(rel_diff(r->theta_avg, root->theta)),
                              fabs(rel_diff(r->speed_avg, root->rotor_speed)));
        if (d < best_d) {
            best_d = d;
            best = (int)k;
        }
    }
    return best;
}

static void episode_begin(int *inside, double *since, usm_sim_episodes *e, double t)
{
    if (*inside)
        return;
    *inside = 1;
    *since = t;
    if (e->count++ == 0)
        e->first = t;
}

static void episode_end(int *inside, double since, usm_sim_episodes *e, double t)
{
    if (!*inside)
        return;
    *inside = 0;
    e->last = t;
    e->total += t - since;
}

static void callback_stop(usm_sim *s, double t)
{
    s->sum->stop = USM_SIM_STOPPED;
    snprintf(s->sum->reason, USM_MSG_LEN, "stopped by the sample callback at t = %.9g s", t);
}

/* Accumulate the integrator's counters (before it is replaced). */
static void bank_stats(usm_sim *s)
{
    long v[5] = {0, 0, 0, 0, 0};
    CVodeGetNumSteps(s->cv.mem, &v[0]);
    CVodeGetNumRhsEvals(s->cv.mem, &v[1]);
    CVodeGetNumJacEvals(s->cv.mem, &v[2]);
    CVodeGetNumErrTestFails(s->cv.mem, &v[3]);
    CVodeGetNumNonlinSolvConvFails(s->cv.mem, &v[4]);
    for (int k = 0; k < 5; ++k)
        s->stats_done[k] += v[k];
}

/* Continue in mode `mode` from state x (that mode's layout) at t. */
static int switch_mode(usm_sim *s, int mode, double t, const double *x, const double *q)
{
    if (s->cv.mem)
        bank_stats(s);
    set_mode(s, mode);
    int rc = setup_integrator(s, t, x, q[0], q[1]);
    if (rc != USM_OK) {
        s->sum->stop = USM_SIM_INTEGRATOR;
        snprintf(s->sum->reason, USM_MSG_LEN, "after a contact switch at t = %.9g s: %.200s", t,
                 s->msg);
    }
    return rc;
}

/* The contact opens (closed mode, F_n fell through 0) at t: the separation
 * map, the open mode.  x: the closed state. */
static int separate(usm_sim *s, double t, const double *x, const double *q)
{
    double yx[USM_MAX_NY * (USM_MAX_NY + 1)];
    s->u->separation(x, &s->p, yx);
    s->sum->separations++;
    episode_begin(&s->in_open, &s->open_since, &s->sum->contact_open, t);
    /* no contact force while open: the stick check rests until it closes */
    episode_end(&s->in_stick, s->stick_since, &s->sum->stick_exceeded, t);
    return switch_mode(s, 1, t, yx + s->u->separation_out.y, q);
}

/* F_n of the closed mode at state x (which must be evaluable); NAN if not.
 * Ft: F_t there. */
static double closed_Fn(usm_sim *s, double t, const double *x, double *Ft)
{
    double xdot[USM_MAX_NY], out[USM_OUT_COUNT];
    const int mode = s->mode;
    double Fn = NAN;
    *Ft = NAN;
    set_mode(s, 0);
    if (factor_mass(s, x) == 0) {
        s->k.rhs(x, t, &s->p, xdot);
        usm_lu_solve_dense(s->n, s->lu, s->piv, xdot, 1);
        s->k.outputs(x, xdot, t, &s->p, out);
        Fn = out[USM_OUT_F_N];
        *Ft = out[USM_OUT_F_T];
    }
    set_mode(s, mode);
    return Fn;
}

static double closed_Fn_at(void *ctx, double t, const double *y)
{
    double Ft;
    return closed_Fn(ctx, t, y, &Ft);
}

/* The rotor reaches the stator (open mode, the gap fell through 0) at t:
 * the impact rule shared with the shooting (solve/impact.h).  yv: the open
 * state. */
static int impact(usm_sim *s, double t, const double *yv, const double *q)
{
    double out[USM_MAX_NY];
    usm_sim_summary *sum = s->sum;
    usm_impact_outcome o;
    if (usm_impact_resolve(s->m, &s->p, s->v_land, t, yv, closed_Fn_at, s, out, NULL, &o) != 0) {
        sum->stop = USM_SIM_INTEGRATOR;
        snprintf(sum->reason, USM_MSG_LEN, "the impact at t = %.9g s gave a state that is "
                 "not finite", t);
        return USM_EFAILED;
    }
    if (!o.impact)
        return switch_mode(s, 1, t, yv, q);
    sum->impacts++;
    sum->impact_velocity_max = fmax(sum->impact_velocity_max, o.v);
    sum->impacts_slipping += o.slipping;
    if (!o.lands)
        return switch_mode(s, 1, t, out, q);
    episode_end(&s->in_open, s->open_since, &sum->contact_open, t);
    double Ft;
    const double Fn = closed_Fn(s, t, out, &Ft);
    if (s->nroots > ROOT_STICK && s->p.mu0 * Fn - fabs(Ft) < 0)
        episode_begin(&s->in_stick, &s->stick_since, &sum->stick_exceeded, t);
    return switch_mode(s, 0, t, out, q);
}

/* A root was located at t: record contact events; decide about runaway. */
static int handle_roots(usm_sim *s, double t, const double *y, const double *q)
{
    int found[NROOTS] = {0};
    double x[USM_MAX_NY], xdot[USM_MAX_NY], out[USM_OUT_COUNT];
    usm_sim_summary *sum = s->sum;
    CVodeGetRootInfo(s->cv.mem, found);
    if (!s->u && found[ROOT_FN] < 0)
        episode_begin(&s->in_open, &s->open_since, &sum->contact_open, t);
    else if (!s->u && found[ROOT_FN] > 0)
        episode_end(&s->in_open, s->open_since, &sum->contact_open, t);
    if (s->nroots > ROOT_STICK) {
        if (found[ROOT_STICK] < 0)
            episode_begin(&s->in_stick, &s->stick_since, &sum->stick_exceeded, t);
        else if (found[ROOT_STICK] > 0)
            episode_end(&s->in_stick, s->stick_since, &sum->stick_exceeded, t);
    }
    if (evaluate(s, t, y, x, xdot) == 0)
        s->k.outputs(x, xdot, t, &s->p, out);
    else
        out[USM_OUT_ROTOR_SPEED] = NAN;
    if (found[ROOT_TILT_ZERO]) {
        sum->stop = USM_SIM_TILT_ZERO;
        snprintf(sum->reason, USM_MSG_LEN,
                 "the tilt reached 0 at t = %.9g s (theta = %.3g rad): the z-x-z Euler angles "
                 "are singular there (a variant in the tilt vector, e.g. twist_integrated, "
                 "is regular there)",
                 t, theta_of(s, x));
        return 1;
    }
    if (found[ROOT_TILT_LIMIT]) {
        sum->stop = USM_SIM_RUNAWAY_TILT;
        snprintf(sum->reason, USM_MSG_LEN,
                 "runaway: the tilt reached theta_limit = %.6g rad at t = %.9g s "
                 "(theta = %.6g rad); the model is meant for small tilts",
                 s->o.theta_limit, t, theta_of(s, x));
        return 1;
    }
    if (found[ROOT_SPEED]) {
        const double w = out[USM_OUT_ROTOR_SPEED];
        sum->stop = USM_SIM_RUNAWAY_SPEED;
        snprintf(sum->reason, USM_MSG_LEN,
                 "runaway: |rotor speed| reached speed_limit = %.6g 1/s at t = %.9g s "
                 "(phidot_R = %.6g 1/s, %s)",
                 s->o.speed_limit, t, w,
                 w > 0 ? "running backwards: the load overcomes the drive"
                       : "in the driving direction");
        return 1;
    }
    if (s->u && found[ROOT_FN]) {
        /* a unilateral contact: the guard of the current mode was crossed */
        double xs[USM_MAX_NY];
        to_x(s, t, y, xs);
        if ((s->mode == 0 ? separate(s, t, xs, q) : impact(s, t, xs, q)) != USM_OK)
            return 1;
    }
    return 0;
}

/* The start at rest (usm_simulate.h, "Start from rest"): sum->tilt_start,
 * theta_unstable and start_message.  USM_OK, or USM_EFAILED when out of
 * memory. */
static int rest_start(usm_sim *s)
{
    usm_sim_summary *sum = s->sum;
    const size_t n = sum->roots;
    size_t k_u = 0;
    int fl_ok = 0;
    sum->theta_unstable = 0.0;
    if (n > 0) {
        if (usm_grow((void **)&s->fl, &s->fl_cap, n, sizeof *s->fl) != 0) {
            snprintf(s->msg, USM_MSG_LEN, "out of memory");
            return USM_EFAILED;
        }
        fl_ok = usm_floquet_roots(s->floquet, &s->p, s->steady, 0.0, NULL, s->fl) == USM_OK;
        for (size_t k = 0; k < n; ++k) {
            const double th = usm_steady_root(s->steady, k)->theta;
            if ((!fl_ok || !s->fl[k].stable) &&
                (sum->theta_unstable == 0.0 || th < sum->theta_unstable)) {
                sum->theta_unstable = th;
                k_u = k;
            }
        }
    }
    const double th_u = sum->theta_unstable;
    if (n > 0 && th_u == usm_steady_root(s->steady, 0)->theta)
        s->trap_ref = th_u;
    char root[96] = "";
    if (th_u > 0)
        snprintf(root, sizeof root, "root #%zu at %.4g rad%s", k_u + 1, th_u,
                 fl_ok ? "" : ", the multipliers having failed");
    if (s->o.tilt0 > 0) {
        sum->tilt_start = s->o.tilt0;
        if (th_u > 0 && s->o.tilt0 >= th_u)
            snprintf(sum->start_message, USM_MSG_LEN,
                     "tilt0 = %.4g rad as given: at or above the smallest unstable tilt (%s), "
                     "so not a start at rest (omit tilt0 for one)",
                     s->o.tilt0, root);
        else
            snprintf(sum->start_message, USM_MSG_LEN, "tilt0 = %.4g rad as given%s%s%s",
                     s->o.tilt0, th_u > 0 ? ", below the smallest unstable tilt (" : "", root,
                     th_u > 0 ? ")" : "");
        return USM_OK;
    }
    if (th_u > 0 && USM_SIM_REST_START_FRACTION * th_u < USM_SIM_TILT0_DEFAULT) {
        sum->tilt_start = USM_SIM_REST_START_FRACTION * th_u;
        snprintf(sum->start_message, USM_MSG_LEN,
                 "at rest: tilt0 = %.4g rad, %g of the smallest unstable tilt (%s)",
                 sum->tilt_start, USM_SIM_REST_START_FRACTION, root);
    } else {
        sum->tilt_start = USM_SIM_TILT0_DEFAULT;
        if (th_u > 0)
            snprintf(sum->start_message, USM_MSG_LEN,
                     "at rest: tilt0 = %g rad, below %g of the smallest unstable tilt (%s)",
                     USM_SIM_TILT0_DEFAULT, USM_SIM_REST_START_FRACTION, root);
        else
            snprintf(sum->start_message, USM_MSG_LEN,
                     "at rest: tilt0 = %g rad (no unstable stationary solution to stay below)",
                     USM_SIM_TILT0_DEFAULT);
    }
    if (!(sum->tilt_start < s->o.theta_limit)) {
        snprintf(s->msg, USM_MSG_LEN, "tilt0: the start at rest, %g rad, is not below "
                 "theta_limit", sum->tilt_start);
        return USM_EINPUT;
    }
    return USM_OK;
}

/* Initial state from the options; USM_OK, or USM_ENOSOLUTION. */
static int initial_state(usm_sim *s, double *x0, double *rotor_angle0)
{
    const int n = s->n;
    const usm_sim_options *o = &s->o;
    memset(x0, 0, sizeof(double) * (size_t)n);
    *rotor_angle0 = o->rotor_angle0;
    switch (o->start) {
    case USM_SIM_FROM_REST:
        /* tilt about the excitation torque's axis at t0, twist angle zero */
        if (s->tilt) { /* the same state, mapped from the Euler angles */
            const usm_model *e = s->m->other_coordinates;
            double xe[USM_MAX_NX] = {0};
            xe[e->x_phi] = s->Omega * o->t0;
            xe[e->x_psi] = -s->Omega * o->t0;
            xe[e->x_theta] = s->sum->tilt_start;
            if (e->x_phi_R >= 0)
                xe[e->x_phi_R] = o->rotor_angle0;
            usm_coords_map(e, xe, o->t0, &s->p, 0.0, s->m, x0);
            break;
        }
        x0[s->iphi] = s->Omega * o->t0;
        x0[s->ipsi] = -s->Omega * o->t0;
        x0[s->ith] = s->sum->tilt_start;
        if (s->irot >= 0)
            x0[s->irot] = o->rotor_angle0;
        break;
    case USM_SIM_FROM_STATIONARY: {
        double orbit[2 * USM_MAX_NY];
        if (!s->sum->have_steady) {
            snprintf(s->msg, USM_MSG_LEN, "no stationary solution to start from: %.200s",
                     s->sum->steady_message);
            return USM_ENOSOLUTION;
        }
        s->m->steady_state(s->sum->steady.u, s->sum->steady.beta, o->t0, &s->p, orbit);
        memcpy(x0, orbit + s->m->steady_state_out.x, sizeof(double) * (size_t)n);
        if (s->irot >= 0)
            x0[s->irot] += o->rotor_angle0;
        break;
    }
    case USM_SIM_FROM_STATE:
        if (usm_coords_map(s->user, o->x0, o->t0, &s->p, 0.0, s->m, x0) != USM_OK)
            return USM_EINPUT;
        break;
    }
    return USM_OK;
}

/* Coordinates and error weights of the integrator.
 *
 * In z-x-z angles a small physical perturbation of the tilt vector
 * perpendicular to the nodal line is a change of phi or psi of size
 * (perturbation / theta), with phi and psi moving opposite to each other; the
 * spin phi + psi (twist, omega_Z) is what the stiff twist spring and the rotor
 * speed see.  So CVODES works on
 *     z = (phi + psi, theta, psi + Omega (t - t0) - psi(t0), and the rates
 *          phidot + psidot, thetadot, psidot + Omega)    [+ phi_R, phi_Rdot, tau]
 * and its error weights are stated physically, with theta_c the stationary
 * tilt (or the initial one if larger):
 *   phi + psi:       rtol * theta_c           (absolute: the twisting torque
 *                                              c_t (phi + psi cos theta) needs it)
 *   psi:             rtol * 1 rad              (absolute: theta * dpsi is a tilt
 *                                              error of rtol * theta)
 *   theta, phi_R:    rtol * (|.| + theta_c)
 *   phidot + psidot: rtol * theta_c * Omega   (absolute: the rotor speed is
 *                                              about (phidot + psidot) + Omega theta H / R)
 *   psidot + Omega:  rtol * (|.| + Omega)
 *   thetadot, phi_Rdot: rtol * (|.| + theta_c * Omega)
 *   tau (integrated twist angle of the twist_integrated variants): as phi + psi
 * Weighting phi and psi separately either lets the twist wander (relative
 * weights on angles that grow like Omega t) or forces CVODES to resolve
 * perturbations of the nodal line's direction of 1e-11 rad (absolute weights
 * on each), which cost a factor of 30 in steps. */
static void set_scales(usm_sim *s, const double *x0)
{
    const int irotd = s->m->x_phi_Rdot, itau = s->m->x_tau;
    double theta_c = s->sum->have_steady ? s->sum->steady.theta : 1e-4;
    theta_c = fmax(theta_c, theta_of(s, x0));
    memset(s->c, 0, sizeof s->c);
    memset(s->d, 0, sizeof s->d);
    if (s->tilt) {
        /* (a, b): the tilt itself, absolute rtol * theta_c; chi as phi + psi
         * above; the rates absolute rtol * theta_c * Omega (chidot as
         * phidot + psidot), the rest as below */
        for (int i = 0; i < s->n; ++i) {
            s->ewt_scale[i] = theta_c;
            s->ewt_absolute[i] = 0;
        }
        const int absolute[6] = {s->iphi, s->ith, s->ipsi, s->iphid, s->ithd, s->ipsid};
        for (int k = 0; k < 6; ++k)
            s->ewt_absolute[absolute[k]] = 1;
        s->ewt_scale[s->iphid] = s->ewt_scale[s->ithd] = s->ewt_scale[s->ipsid] =
            theta_c * s->Omega;
        if (irotd >= 0)
            s->ewt_scale[irotd] = theta_c * s->Omega;
        if (itau >= 0)
            s->ewt_absolute[itau] = 1;
        return;
    }
    s->c[s->ipsi] = -x0[s->ipsi];
    s->d[s->ipsi] = s->Omega;
    s->c[s->ipsid] = s->Omega;
    for (int i = 0; i < s->n; ++i) {
        s->ewt_scale[i] = theta_c;
        s->ewt_absolute[i] = 0;
    }
    s->ewt_absolute[s->iphi] = 1;
    s->ewt_absolute[s->ipsi] = 1;
    s->ewt_scale[s->ipsi] = 1.0;
    s->ewt_absolute[s->iphid] = 1;
    s->ewt_scale[s->iphid] = theta_c * s->Omega;
    s->ewt_scale[s->ithd] = theta_c * s->Omega;
    s->ewt_scale[s->ipsid] = s->Omega;
    if (irotd >= 0)
        s->ewt_scale[irotd] = theta_c * s->Omega;
    if (itau >= 0) /* an integrated twist angle: what the twist spring sees */
        s->ewt_absolute[itau] = 1;
    if (s->u) {
        /* an open contact: the gap is a fraction of R theta_c, its rate of
         * R theta_c Omega; the stick model's free rotor speed as phi_Rdot */
        s->ewt_absolute[s->u->y_Z_R] = 1;
        s->ewt_scale[s->u->y_Z_R] = s->p.R * theta_c;
        s->ewt_absolute[s->u->y_Z_Rdot] = 1;
        s->ewt_scale[s->u->y_Z_Rdot] = s->p.R * theta_c * s->Omega;
        if (s->u->y_w_R >= 0) {
            s->ewt_absolute[s->u->y_w_R] = 0;
            s->ewt_scale[s->u->y_w_R] = theta_c * s->Omega;
        }
    }
}

static void collect_stats(usm_sim *s)
{
    long v;
    usm_sim_summary *sum = s->sum;
    const long *done = s->stats_done;
    if (CVodeGetNumSteps(s->cv.mem, &v) == CV_SUCCESS)
        sum->steps = v + done[0];
    if (CVodeGetNumRhsEvals(s->cv.mem, &v) == CV_SUCCESS)
        sum->rhs_evals = v + done[1];
    if (CVodeGetNumJacEvals(s->cv.mem, &v) == CV_SUCCESS)
        sum->jac_evals = v + done[2];
    if (CVodeGetNumErrTestFails(s->cv.mem, &v) == CV_SUCCESS)
        sum->error_test_fails = v + done[3];
    if (CVodeGetNumNonlinSolvConvFails(s->cv.mem, &v) == CV_SUCCESS)
        sum->newton_fails = v + done[4];
}

/* Why CVODES gave up, where it is the model's own motion: a tilt far below
 * the stationary one circles the axis ever faster (the paper's contact point
 * makes the contact height a cone at theta = 0; docs/coordinates.md), so the
 * steps per period grow without bound.  Appended to the reason. */
static void cone_hint(usm_sim *s, double t, const double *y)
{
    double x[USM_MAX_NY];
    to_x(s, t, y, x);
    const double theta = theta_of(s, x);
    const double theta_c = s->sum->have_steady ? s->sum->steady.theta : 1e-4;
    if (!(theta < 1e-3 * theta_c))
        return;
    const size_t n = strlen(s->sum->reason);
    snprintf(s->sum->reason + n, USM_MSG_LEN - n,
             " (tilt %.2g rad: it circles the axis, where the contact is a cone; "
             "docs/coordinates.md)", theta);
}

static int integrate(usm_sim *s, run_state *r)
{
    usm_sim_summary *sum = s->sum;
    double *y = N_VGetArrayPointer(s->cv.y);
    double q[2] = {0.0, s->o.rotor_angle0};
    double t = s->t0;
    const long max_steps = s->o.max_steps > 0
                               ? s->o.max_steps
                               : 2000 * (long)ceil((s->t1 - s->t0) / r->T) + 100000;

    if (r->dt_sample > 0) {
        if (emit_sample(s, r, t, y, q) != 0) {
            callback_stop(s, t);
            return USM_EFAILED;
        }
        r->k = 1;
    }
    for (;;) {
        const double ts = sample_time(s, r), tp = period_end(s, r);
        const double tout = fmin(fmin(ts, tp), s->t1);
        s->cv.cvmsg[0] = '\0';
        /* a contact switch that landed on tout restarted the integrator there:
         * the state at tout is at hand */
        int flag = tout <= t ? CV_SUCCESS : CVode(s->cv.mem, tout, s->cv.y, &t, CV_NORMAL);
        sum->t_reached = t;
        if (flag < 0) {
            char name[32];
            sum->stop = USM_SIM_INTEGRATOR;
            snprintf(sum->reason, USM_MSG_LEN, "CVODES failed at t = %.9g s: %s%s%.140s", t,
                     usm_cvode_flag_name(flag, name, sizeof name), s->cv.cvmsg[0] ? " -- " : "",
                     s->cv.cvmsg);
            cone_hint(s, t, y);
            return USM_EFAILED;
        }
        if (CVodeGetQuad(s->cv.mem, &t, s->cv.q) == CV_SUCCESS)
            memcpy(q, N_VGetArrayPointer(s->cv.q), sizeof q);
        if (flag == CV_ROOT_RETURN) {
            if (handle_roots(s, t, y, q))
                return USM_EFAILED;
            y = N_VGetArrayPointer(s->cv.y); /* a contact switch makes a new integrator */
            continue;
        }
        if (tout == tp) {
            end_of_period(s, r, t, q);
            r->j++;
            if (r->cb && r->cb->progress)
                r->cb->progress(t, s->t0, s->t1, r->cb->data);
            if (r->rest) {
                sum->stop = USM_SIM_REST;
                snprintf(sum->reason, USM_MSG_LEN,
                         "the wobble decayed: the period-mean tilt %.3g rad fell below %g of "
                         "%.3g rad (%s) for %ld periods by t = %.9g s; the motor does not start",
                         r->theta_avg, sum->rest_fraction, sum->rest_theta_ref,
                         s->rest_run >= USM_SIM_REST_PERIODS ? "the start tilt or the smallest "
                                                               "root's"
                                                             : "the unstable smallest root's",
                         s->rest_run >= USM_SIM_REST_PERIODS ? s->rest_run : s->trap_run, t);
                return USM_OK;
            }
        }
        if (tout == ts) {
            if (emit_sample(s, r, t, y, q) != 0) {
                callback_stop(s, t);
                return USM_EFAILED;
            }
            r->k++;
        }
        if (tout >= s->t1)
            return USM_OK;
        long nst = 0;
        if (CVodeGetNumSteps(s->cv.mem, &nst) == CV_SUCCESS && nst + s->stats_done[0] >= max_steps) {
            nst += s->stats_done[0];
            sum->stop = USM_SIM_MAX_STEPS;
            snprintf(sum->reason, USM_MSG_LEN,
                     "step cap: %ld internal steps used by t = %.9g s (max_steps); "
                     "the motion needs far more work than a motor start-up",
                     nst, t);
            cone_hint(s, t, y);
            return USM_EFAILED;
        }
    }
}

/* The paper's twist law (usm_simulate.h): the twist growth g of the run from
 * x0, on the stationary orbit, and what to say about it.  USM_OK, or
 * USM_EINPUT when g exceeds max_twist_growth. */
static int check_twist_growth(usm_sim *s, const double *x0, const usm_sim_callbacks *cb)
{
    usm_sim_summary *sum = s->sum;
    if (s->m->t0_independent || !sum->have_steady)
        return USM_OK;
    const double th = sum->steady.theta, d = s->t1 - s->t0;
    /* psi runs at -Omega / cos(theta) on the orbit */
    const double psi0 = x0[s->ipsi], psi1 = psi0 - s->Omega * d / cos(th);
    const double stiffness = s->p.I_xx * s->Omega * s->Omega;
    const double g = s->p.c_t * fmax(fabs(psi0), fabs(psi1)) * sin(th) / stiffness;
    sum->twist_growth = g;
    if (s->o.max_twist_growth > 0 && g > s->o.max_twist_growth) {
        /* the duration after which |psi| reaches the limit's value */
        const double psi_max = s->o.max_twist_growth * stiffness / (s->p.c_t * sin(th));
        const double d_max = fmax(0.0, (psi_max - fabs(psi0)) * cos(th) / s->Omega);
        snprintf(s->msg, USM_MSG_LEN,
                 "duration: the paper's twist law would slow this run down superlinearly (its "
                 "linearisation grows with psi(t): twist growth %.3g by the end, above "
                 "max_twist_growth = %g after %.3g s); use the variant twist_integrated",
                 g, s->o.max_twist_growth, d_max);
        return USM_EINPUT;
    }
    if (g > USM_SIM_TWIST_GROWTH_WARN) {
        snprintf(sum->warning, USM_MSG_LEN,
                 "the paper's twist law slows this run down superlinearly (its linearisation "
                 "grows with psi(t): twist growth %.3g by the end); the variant "
                 "twist_integrated scales linearly",
                 g);
        if (cb && cb->warning)
            cb->warning(sum->warning, cb->data);
    }
    return USM_OK;
}

int usm_sim_run(usm_sim *s, const usm_params *p, const usm_sim_options *opt,
                const usm_sim_callbacks *cb, usm_sim_summary *sum)
{
    usm_sim_options def;
    double x0[USM_MAX_NY], rotor_angle0;
    run_state r;
    int rc;
    if (!opt) {
        usm_sim_options_default(&def);
        opt = &def;
    }
    s->msg[0] = '\0';
    choose_coordinates(s, opt);
    if ((rc = check_options(s, opt)) != USM_OK || (rc = check_params(s, p)) != USM_OK)
        return rc;
    s->p = *p;
    s->o = *opt;
    s->Omega = TWO_PI * p->f;
    s->t0 = opt->t0;
    s->t1 = opt->t0 + opt->duration;
    s->nroots = s->m->friction ? ROOT_STICK : NROOTS; /* stick check only without a friction law */
    s->sum = sum;
    memset(sum, 0, sizeof *sum);
    sum->stop = USM_SIM_COMPLETED;
    sum->t0 = s->t0;
    sum->t1 = s->t1;
    sum->t_reached = s->t0;
    sum->settle_tol = opt->settle_tol;
    sum->settle_periods = opt->settle_periods;
    sum->theta_min = INFINITY;
    sum->theta_max = -INFINITY;
    sum->stick_checked = s->nroots > ROOT_STICK;
    s->Fn_min = INFINITY;
    s->excess_max = -INFINITY;
    s->in_open = s->in_stick = 0;

    sum->settled_on = USM_SIM_SETTLED_NONE;
    sum->rest_fraction = opt->rest_fraction;
    sum->t_rest = NAN;
    if (usm_steady_solve(s->steady, p, NULL) == USM_OK && usm_steady_count(s->steady) > 0) {
        sum->have_steady = 1;
        sum->steady = *usm_steady_root(s->steady, 0);
        sum->roots = usm_steady_count(s->steady);
    } else
        snprintf(sum->steady_message, USM_MSG_LEN, "%s", usm_steady_message(s->steady));
    if (usm_grow((void **)&s->root_run, &s->root_cap, sum->roots, sizeof *s->root_run) != 0) {
        snprintf(s->msg, USM_MSG_LEN, "out of memory");
        return USM_EFAILED;
    }
    for (size_t k = 0; k < sum->roots; ++k)
        s->root_run[k] = 0;
    s->rest_run = 0;
    s->rest_prev = INFINITY;
    s->trap_run = 0;
    s->trap_ref = 0.0;

    if (opt->start == USM_SIM_FROM_REST && (rc = rest_start(s)) != USM_OK)
        return rc;
    if ((rc = initial_state(s, x0, &rotor_angle0)) != USM_OK ||
        (rc = check_twist_growth(s, x0, cb)) != USM_OK)
        return rc;
    set_scales(s, x0);
    sum->rest_theta_ref = fabs(theta_of(s, x0));
    s->phi_prev = s->tilt ? s->Omega * s->o.t0 : 0.0; /* the branch of phi in the samples */
    if (s->tilt && s->o.start == USM_SIM_FROM_STATE && s->user->coordinates == 0)
        s->phi_prev = s->o.x0[s->user->x_phi];
    if (sum->have_steady)
        sum->rest_theta_ref = fmin(sum->rest_theta_ref, sum->steady.theta);
    if (s->user == s->m)
        memcpy(sum->final_x, x0, sizeof(double) * (size_t)s->nx);
    else
        usm_coords_map(s->m, x0, s->t0, &s->p, s->phi_prev, s->user, sum->final_x);
    /* a bounce slower than this lands: sqrt(rtol) of the contact point's speed scale */
    s->v_land = sqrt(opt->rtol) * p->R * s->ewt_scale[s->ithd];
    sum->final_rotor_angle = s->irot >= 0 ? x0[s->irot] : rotor_angle0;

    set_mode(s, 0);
    memset(s->stats_done, 0, sizeof s->stats_done);
    sum->unilateral = s->u != NULL;
    if ((rc = setup_integrator(s, s->t0, x0, 0.0, rotor_angle0)) != USM_OK)
        goto done;
    {
        double g[NROOTS];
        if (cv_roots(s->t0, s->cv.y, g, s) != 0) {
            snprintf(s->msg, USM_MSG_LEN,
                     "the initial state is not valid: the mass matrix is singular or a value "
                     "is not finite");
            rc = USM_EINPUT;
            goto done;
        }
        if (g[ROOT_FN] < 0 && s->u) {
            /* a unilateral contact that pulls at the start opens at once */
            const double q0[2] = {0.0, rotor_angle0};
            if (separate(s, s->t0, x0, q0) != USM_OK) {
                snprintf(s->msg, USM_MSG_LEN, "%s", sum->reason);
                rc = USM_EFAILED;
                goto done;
            }
        } else if (g[ROOT_FN] < 0)
            episode_begin(&s->in_open, &s->open_since, &sum->contact_open, s->t0);
        if (s->nroots > ROOT_STICK && g[ROOT_STICK] < 0)
            episode_begin(&s->in_stick, &s->stick_since, &sum->stick_exceeded, s->t0);
        if (g[ROOT_SPEED] <= 0) {
            snprintf(s->msg, USM_MSG_LEN, "the initial rotor speed is beyond speed_limit");
            rc = USM_EINPUT;
            goto done;
        }
    }

    memset(&r, 0, sizeof r);
    r.cb = cb;
    r.T = 1.0 / p->f;
    r.j = 1;
    r.last_out = s->t0;
    r.q_prev[0] = 0.0;
    r.q_prev[1] = rotor_angle0;
    if (opt->rate > 0) {
        r.dt_sample = 1.0 / opt->rate;
        r.k_last = (long)floor(opt->duration * opt->rate * (1 + 1e-12));
        r.final_sample = (s->t1 - (s->t0 + (double)r.k_last * r.dt_sample)) > 1e-9 * r.dt_sample;
    }
    rc = integrate(s, &r);
    collect_stats(s);
    {
        double x[USM_MAX_NY];
        to_x(s, sum->t_reached, N_VGetArrayPointer(s->cv.y), x);
        if (s->user == s->m)
            memcpy(sum->final_x, x, sizeof(double) * (size_t)s->nx);
        else
            usm_coords_map(s->m, x, sum->t_reached, &s->p, s->phi_prev, s->user, sum->final_x);
        sum->final_open = s->mode;
        sum->final_rotor_angle = s->irot >= 0 ? x[s->irot] : N_VGetArrayPointer(s->cv.q)[1];
    }
    episode_end(&s->in_open, s->open_since, &sum->contact_open, sum->t_reached);
    episode_end(&s->in_stick, s->stick_since, &sum->stick_exceeded, sum->t_reached);
    if (sum->contact_open.count) /* a unilateral contact opens at F_n = 0 */
        sum->contact_open.worst = s->u ? 0.0 : s->Fn_min;
    if (sum->stick_exceeded.count)
        sum->stick_exceeded.worst = s->excess_max;
    if (s->u && sum->t_reached > s->t0)
        sum->open_fraction = sum->contact_open.total / (sum->t_reached - s->t0);
    sum->settled = sum->have_steady && rc == USM_OK && sum->stop == USM_SIM_COMPLETED &&
                   r.in_tol_run >= opt->settle_periods;
    sum->settled_on = settled_on(s, &r, rc);
    if (sum->settled_on >= 0)
        sum->settled_root = *usm_steady_root(s->steady, (size_t)sum->settled_on);
    sum->t_settle = sum->settled ? r.last_out : NAN;
    if (rc != USM_OK)
        snprintf(s->msg, USM_MSG_LEN, "%s", sum->reason);
done:
    usm_cvodes_release(&s->cv);
    return rc;
}
