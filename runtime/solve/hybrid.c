/* Periodic orbits with separation (usm_periodic.h, "periodic orbits with
 * separation"; docs/unilateral.md).
 *
 * One CVODES integration (Adams, fixed-point iteration: over a period the
 * motion is not stiff, as in periodic.c) carries the state of the current
 * contact mode and its variational matrix Phi (n x nx: the current mode's
 * state against the closed state at the section), z = (x, Phi), with
 *     x' = M^-1 f,   Phi' = M^-1 (df/dx - d(M v)/dx |_{v = x'}) Phi.
 * The guard of the mode (F_n while closed, the gap while open) is located by
 * CVODES' root finding; there the reset (separation, or impact and landing)
 * maps x, the saltation matrix
 *     S = R + (f+ - R f-) g_x^T / (g_x f- + g_t)
 * maps Phi (R the reset's Jacobian; f-, f+ the flows before and after; for
 * the closed guard g(x, t) = F_n(x, x'(x, t)), so g_x = F_n,x + F_n,x' A and
 * g_t = F_n,x' M^-1 df/dt), and the integration restarts in the new mode.
 * The landing rule is the simulation's (simulate.c, usm_simulate.h): the
 * closed mode follows an impact unless the rotor bounces faster than v_land
 * or the closed mode would pull.
 *
 * Error control: absolute tolerances rtol * scale_i for x_i and
 * rtol * scale_i / scale_j for Phi_ij (scales as periodic.c's, and R theta,
 * R theta Omega for the gap and its rate).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/cvodes.h"
#include "core/dense.h"
#include "contact_mode.h"
#include "hybrid_internal.h"
#include "impact.h"
#include "multipliers.h"
#include "usm_periodic.h"
#include "usm_simulate.h"

#define TWO_PI 6.283185307179586476925286766559
#define RIPPLE_SAMPLES 256 /* rotor speed samples a period (and both sides of every switch) */
#define NY USM_MAX_NY
#define MAXZ (NY + NY * USM_MAX_NX)

struct usm_hybrid {
    const usm_model *m;
    const usm_unilateral *u;
    int nx, ny;
    usm_params p;
    double rtol, Omega, T, v_land;
    double map_rtol; /* the integration's: rtol, or ROUGH_RTOL for a cold start's first Jacobian */
    double scale[NY];
    double colscale[USM_MAX_NX]; /* of Phi's columns: the spin coordinates (below) */
    double Bspin[USM_MAX_NX * USM_MAX_NX]; /* the last monodromy in spin coordinates */
    double Phi[USM_MAX_NX * USM_MAX_NX];   /* and as integrated: x rows, spin columns */
    usm_multipliers *mult; /* its eigenvalues (solve/multipliers.h) */
    /* the last converged orbit's B - I on the non-cyclic components (LU),
     * at its section time: Newton's first Jacobian from a nearby start */
    int jc_nr;
    double jc_ts, jc_lu[USM_MAX_NX * USM_MAX_NX];
    int jc_piv[USM_MAX_NX];
    /* the integration */
    int mode, n, ncol; /* mode (0 closed, 1 open), its state length, columns of Phi */
    usm_mode k[2];     /* the kernels of the closed and the open mode */
    usm_cvodes cv;     /* z = [state, Phi row by row], quadrature: the rotor angle */
    /* the last period map */
    double open_total, open_since, vmax;
    int nsamp;                /* > 0: sample the rotor speed (min/max) this often a period */
    double wmin, wmax;
    double *rows;             /* not NULL: the samples' rows too (usm_hybrid_orbit_samples) */
    int nrows, rows_max, rows_lost;
    int nsep, nimp, nslip, nmodes;
    int bounces;       /* impacts with rebound since the last separation */
    double vfirst;     /* their first approach velocity */
    int chatter;       /* a landing after rebounds was met (message set) */
    int long_run;      /* usm_hybrid_lyapunov: a landing after rebounds is a landing (the
                          simulation's rule), not a failure of the period map */
    int half;          /* usm_hybrid_shoot maps half a period (usm_hybrid_shoot_half) */
    /* the last map's impacts (usm_hybrid_shoot_impacts): time, F_n of the
     * closed mode just after, and whether the rotor landed */
    int nimprec;
    double imp_t[USM_HYBRID_MAX_SWITCHES], imp_fn[USM_HYBRID_MAX_SWITCHES];
    int imp_lands[USM_HYBRID_MAX_SWITCHES];
    /* > 0: the map stops just after this impact (usm_hybrid_impact_map),
     * its time into stop_t and the state after (the first nx entries) into
     * the map's x1 */
    int stop_impacts;
    double stop_t;
    int map_half;      /* the current period map's: half, in usm_hybrid_shoot only */
    char seq[USM_HYBRID_MAX_SWITCHES + 1];
    char msg[USM_MSG_LEN];
};

void usm_hybrid_options_default(usm_hybrid_options *opt)
{
    opt->rtol = 1e-11;
    opt->tol = 1e-9;
    opt->max_iter = 12;
    opt->settle = 0.005;
}

const char *usm_hybrid_message(const usm_hybrid *h) { return h->msg; }

void usm_hybrid_free(usm_hybrid *h)
{
    if (!h)
        return;
    usm_cvodes_free(&h->cv);
    usm_multipliers_free(h->mult);
    free(h);
}

usm_hybrid *usm_hybrid_alloc(const usm_model *m)
{
    if (!m || !m->unilateral)
        return NULL;
    usm_hybrid *h = calloc(1, sizeof *h);
    if (!h)
        return NULL;
    h->m = m;
    h->u = m->unilateral;
    h->nx = m->nx;
    h->ny = m->unilateral->ny;
    usm_mode_kernels(m, 0, &h->k[0]);
    usm_mode_kernels(m, 1, &h->k[1]);
    /* the monodromy is integrated in the spin coordinates themselves: the
     * basis of the cyclic directions is that of the identity */
    double I[USM_MAX_NX * USM_MAX_NX] = {0};
    for (int i = 0; i < h->nx; ++i)
        I[i * h->nx + i] = 1.0;
    h->mult = usm_multipliers_alloc(m);
    if (!h->mult || usm_multipliers_basis(h->mult, I) != 0) {
        usm_multipliers_free(h->mult);
        free(h);
        return NULL;
    }
    return h;
}

/* ---- the modes ------------------------------------------------------------------- */

/* LU of the mode's mass matrix at x into lu/piv (core/dense.h: plain loops,
 * a fifth of GSL's cost at these sizes); 0 or -1. */
static int mass_lu(const usm_hybrid *h, int mode, const double *x, double *lu, int *piv)
{
    const usm_mode *k = &h->k[mode];
    const int n = k->n;
    k->mass(x, &h->p, lu);
    for (int i = 0; i < n * n; ++i)
        if (!isfinite(lu[i]))
            return -1;
    return usm_lu_factor_dense(n, lu, piv);
}

/* x' of the mode, and when A is not NULL the flow's Jacobian
 * A = M^-1 (df/dx - d(M v)/dx |_{v = x'}) (n x n) and, when ft is not NULL,
 * M^-1 df/dt.  0 or -1. */
static int rates(const usm_hybrid *h, int mode, double t, const double *x, double *xdot,
                 double *A, double *ft)
{
    const usm_mode *k = &h->k[mode];
    const int n = k->n;
    double lu[NY * NY], Jf[NY * NY], Jm[NY * NY];
    int piv[NY];
    if (mass_lu(h, mode, x, lu, piv) != 0)
        return -1;
    k->rhs(x, t, &h->p, xdot);
    usm_lu_solve_dense(n, lu, piv, xdot, 1);
    if (A) {
        k->jac_rhs(x, t, &h->p, Jf);
        k->jac_mass(x, xdot, &h->p, Jm);
        for (int i = 0; i < n * n; ++i)
            A[i] = Jf[i] - Jm[i];
        usm_lu_solve_dense(n, lu, piv, A, n);
    }
    if (ft) {
        k->rhs_t(x, t, &h->p, ft);
        usm_lu_solve_dense(n, lu, piv, ft, 1);
    }
    for (int i = 0; i < n; ++i)
        if (!isfinite(xdot[i]))
            return -1;
    return 0;
}

/* ---- CVODES -------------------------------------------------------------------- */

static int cv_rhs(sunrealtype t, N_Vector zv, N_Vector zdot, void *data)
{
    usm_hybrid *h = data;
    const int n = h->n, c = h->ncol;
    const double *z = N_VGetArrayPointer(zv);
    double *d = N_VGetArrayPointer(zdot);
    double A[NY * NY];
    if (rates(h, h->mode, t, z, d, c ? A : NULL, NULL) != 0)
        return 1;
    const double *Phi = z + n;
    double *dPhi = d + n;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < c; ++j) {
            double s = 0;
            for (int k = 0; k < n; ++k)
                s += A[i * n + k] * Phi[k * c + j];
            dPhi[i * c + j] = s;
        }
    return 0;
}

static int cv_quad(sunrealtype t, N_Vector zv, N_Vector qdot, void *data)
{
    usm_hybrid *h = data;
    const double *z = N_VGetArrayPointer(zv);
    double xdot[NY], out[USM_OUT_COUNT];
    if (rates(h, h->mode, t, z, xdot, NULL, NULL) != 0)
        return 1;
    h->k[h->mode].outputs(z, xdot, t, &h->p, out);
    N_VGetArrayPointer(qdot)[0] = out[USM_OUT_ROTOR_SPEED];
    return 0;
}

static int cv_root(sunrealtype t, N_Vector zv, sunrealtype *g, void *data)
{
    usm_hybrid *h = data;
    const double *z = N_VGetArrayPointer(zv);
    if (h->mode == 1) {
        double gg[1 + NY];
        h->u->guard_open(z, &h->p, gg);
        g[0] = gg[h->u->guard_open_out.gap];
    } else {
        double xdot[NY], out[USM_OUT_COUNT];
        if (rates(h, 0, t, z, xdot, NULL, NULL) != 0)
            return -1;
        h->m->outputs(z, xdot, t, &h->p, out);
        g[0] = out[USM_OUT_F_N];
    }
    return isfinite(g[0]) ? 0 : -1;
}

/* A new integrator for the current mode from z at t to t_end, quadrature q0. */
static int setup(usm_hybrid *h, double t, const double *z, double q0, double t_end)
{
    const int n = h->n, c = h->ncol, len = n + n * c;
    double a[MAXZ];
    for (int i = 0; i < n; ++i) {
        a[i] = h->map_rtol * h->scale[i];
        for (int j = 0; j < c; ++j)
            a[n + i * c + j] = h->map_rtol * h->scale[i] / h->colscale[j];
    }
    static const int dir = -1; /* the guards fall through zero */
    const usm_cvodes_spec spec = {.lmm = CV_ADAMS,
                                  .n = len,
                                  .t0 = t,
                                  .y0 = z,
                                  .rhs = cv_rhs,
                                  .data = h,
                                  .max_steps = 200000,
                                  .rtol = h->map_rtol,
                                  .atol_v = a,
                                  .t_stop = t_end,
                                  .nq = 1,
                                  .quad = cv_quad,
                                  .q0 = &q0,
                                  .nroots = 1,
                                  .roots = cv_root,
                                  .root_dir = &dir};
    return usm_cvodes_init(&h->cv, &spec, h->msg);
}

/* ---- the switches ----------------------------------------------------------------- */

static void note_mode(usm_hybrid *h, int mode)
{
    if (h->nmodes < USM_HYBRID_MAX_SWITCHES)
        h->seq[h->nmodes] = mode ? 'o' : 'c';
    h->nmodes++;
    h->seq[h->nmodes < USM_HYBRID_MAX_SWITCHES ? h->nmodes : USM_HYBRID_MAX_SWITCHES] = '\0';
}

/* F_n of the closed mode at y (the impact rule's, solve/impact.h). */
static double closed_Fn(void *ctx, double t, const double *y)
{
    const usm_hybrid *h = ctx;
    double xd[NY], o[USM_OUT_COUNT];
    if (rates(h, 0, t, y, xd, NULL, NULL) != 0)
        return NAN;
    h->m->outputs(y, xd, t, &h->p, o);
    return o[USM_OUT_F_N];
}

/* The guard crossed at t: reset the state and the variational matrix in z
 * (the current mode's layout on entry, the new mode's on return). */
static int switch_at(usm_hybrid *h, double t, double *z)
{
    const int na = h->n, c = h->ncol, nx = h->nx, ny = h->ny;
    double x[NY], fa[NY], A[NY * NY], ft[NY], Gx[NY], Gt = 0.0;
    double xp[NY], R[NY * NY], fb[NY];
    int nb, newmode;
    memcpy(x, z, sizeof(double) * (size_t)na);
    if (rates(h, h->mode, t, x, fa, A, ft) != 0) {
        snprintf(h->msg, USM_MSG_LEN, "the state at the switch at t = %.9g s is singular", t);
        return USM_EFAILED;
    }
    if (h->mode == 0) {
        double gc[1 + 2 * USM_MAX_NX];
        h->u->guard_closed(x, fa, t, &h->p, gc);
        const double *dFn_dx = gc + h->u->guard_closed_out.dF_n_dx;
        const double *dFn_dxdot = gc + h->u->guard_closed_out.dF_n_dxdot;
        for (int j = 0; j < nx; ++j) {
            Gx[j] = dFn_dx[j];
            for (int i = 0; i < nx; ++i)
                Gx[j] += dFn_dxdot[i] * A[i * nx + j];
        }
        for (int i = 0; i < nx; ++i)
            Gt += dFn_dxdot[i] * ft[i];
        double sj[NY * (NY + 1)];
        h->u->separation(x, &h->p, sj);
        memcpy(xp, sj + h->u->separation_out.y, sizeof(double) * (size_t)ny);
        memcpy(R, sj + h->u->separation_out.dy_dx, sizeof(double) * (size_t)(ny * nx));
        nb = ny;
        newmode = 1;
        h->nsep++;
        h->open_since = t;
        h->bounces = 0;
    } else {
        double gg[1 + NY];
        usm_impact_outcome io;
        h->u->guard_open(x, &h->p, gg);
        memcpy(Gx, gg + h->u->guard_open_out.dgap_dy, sizeof(double) * (size_t)ny);
        /* the simulation's rule (solve/impact.h) */
        if (usm_impact_resolve(h->m, &h->p, h->v_land, t, x, closed_Fn, h, xp, R, &io) != 0) {
            snprintf(h->msg, USM_MSG_LEN, "the impact at t = %.9g s gave a state that is not "
                     "finite", t);
            return USM_EFAILED;
        }
        if (!io.impact) {
            /* the rotor grazes and the closed mode would pull it off again:
             * the same mode, no reset, S = I */
            h->n = na;
            return USM_OK;
        }
        h->nimp++;
        if (h->nimprec < USM_HYBRID_MAX_SWITCHES) {
            h->imp_t[h->nimprec] = t;
            h->imp_fn[h->nimprec] = closed_Fn(h, t, xp);
            h->imp_lands[h->nimprec++] = io.lands;
        }
        h->vmax = fmax(h->vmax, io.v);
        h->nslip += io.slipping;
        newmode = !io.lands;
        if (newmode && io.v_after > h->v_land && h->bounces++ == 0)
            h->vfirst = io.v; /* a rebound (not a touch the closed mode would pull off) */
        if (!newmode && h->bounces > 0 && h->long_run)
            h->bounces = 0;
        else if (!newmode && h->bounces > 0) {
            /* a landing after rebounds: at e_impact > 0 every impact throws
             * the rotor off again (gap'+ = -e gap'- > 0), so a contact that
             * closes does so only at the end of an accumulation of ever
             * shorter bounces (Zeno: infinitely many impacts in a finite
             * time), which the landing rule cuts at v_land after a number of
             * bounces that jumps with the state: the period map is not
             * smooth there, and no such orbit is computed */
            snprintf(h->msg, USM_MSG_LEN,
                     "chattering at e_impact = %g: the bounces accumulate (Zeno: %d rebounds from %.3g "
                     "m/s, landing at t = %.9g s below v_land = %.3g m/s); orbits that land "
                     "again at e_impact > 0 are not computed",
                     h->p.e_impact, h->bounces, h->vfirst, t, h->v_land);
            h->chatter = 1;
            return USM_EFAILED;
        }
        nb = newmode ? ny : nx; /* landing: the first nx rows of R */
        if (newmode == 0)
            h->open_total += t - h->open_since;
    }
    if (rates(h, newmode, t, xp, fb, NULL, NULL) != 0) {
        snprintf(h->msg, USM_MSG_LEN, "the state after the switch at t = %.9g s is singular", t);
        return USM_EFAILED;
    }
    double Gdot = Gt;
    for (int j = 0; j < na; ++j)
        Gdot += Gx[j] * fa[j];
    if (!(fabs(Gdot) > 0)) {
        snprintf(h->msg, USM_MSG_LEN, "grazing at t = %.9g s: the guard's rate is 0", t);
        return USM_EFAILED;
    }
    /* saltation S = R + (fb - R fa) Gx^T / Gdot (nb x na), then Phi+ = S Phi- */
    double S[NY * NY], w[NY];
    for (int i = 0; i < nb; ++i) {
        double Rf = 0;
        for (int k = 0; k < na; ++k)
            Rf += R[i * na + k] * fa[k];
        w[i] = (fb[i] - Rf) / Gdot;
    }
    for (int i = 0; i < nb; ++i)
        for (int j = 0; j < na; ++j)
            S[i * na + j] = R[i * na + j] + w[i] * Gx[j];
    double Phi[NY * USM_MAX_NX];
    for (int i = 0; i < nb; ++i)
        for (int j = 0; j < c; ++j) {
            double s = 0;
            for (int k = 0; k < na; ++k)
                s += S[i * na + k] * z[na + k * c + j];
            Phi[i * c + j] = s;
        }
    memcpy(z, xp, sizeof(double) * (size_t)nb);
    memcpy(z + nb, Phi, sizeof(double) * (size_t)(nb * c));
    h->mode = newmode;
    h->n = nb;
    note_mode(h, newmode);
    return USM_OK;
}

/* ---- the period map -------------------------------------------------------------- */

/* The rotor speed at (t, z) of the current mode into wmin/wmax, and, when
 * h->rows is set, the sample's row (usm_hybrid_orbit_samples). */
static void sample_speed(usm_hybrid *h, double t, const double *z)
{
    double xdot[NY], out[USM_OUT_COUNT];
    if (rates(h, h->mode, t, z, xdot, NULL, NULL) != 0)
        return;
    h->k[h->mode].outputs(z, xdot, t, &h->p, out);
    h->wmin = fmin(h->wmin, out[USM_OUT_ROTOR_SPEED]);
    h->wmax = fmax(h->wmax, out[USM_OUT_ROTOR_SPEED]);
    if (h->rows && h->nrows >= h->rows_max)
        h->rows_lost = 1;
    else if (h->rows) {
        const int nx = h->nx;
        double *row = h->rows + (size_t)h->nrows++ * (size_t)USM_HYBRID_SAMPLE_COLS(nx);
        double g[1 + NY] = {0};
        if (h->mode)
            h->u->guard_open(z, &h->p, g);
        row[0] = t;
        row[1] = h->mode;
        memcpy(row + 2, z, sizeof(double) * (size_t)nx);
        row[nx + 2] = g[h->u->guard_open_out.gap];
        row[nx + 3] = out[USM_OUT_F_N];
        row[nx + 4] = out[USM_OUT_F_T];
        row[nx + 5] = out[USM_OUT_ROTOR_SPEED];
    }
}

static int period_map(usm_hybrid *h, double ts, const double *x0, double *x1, double *B,
                      double *speed_mean)
{
    const int nx = h->nx;
    double z[MAXZ];
    const double t_end = ts + (h->map_half ? 0.5 : 1.0) * h->T;
    h->mode = 0;
    h->n = nx;
    h->ncol = B ? nx : 0;
    h->open_total = 0;
    h->vmax = 0;
    h->nsep = h->nimp = h->nslip = h->nmodes = 0;
    h->nimprec = 0;
    h->bounces = 0;
    h->seq[0] = '\0';
    note_mode(h, 0);
    memcpy(z, x0, sizeof(double) * (size_t)nx);
    if (h->stop_impacts > 0 && !B && !(closed_Fn(h, ts, x0) >= 0)) {
        /* the section at an impact after which the closed mode would pull:
         * the rotor leaves at once (the touch of solve/impact.h), a closed
         * phase of length 0; the map so goes on smoothly (to first order)
         * from the closed phase that shrinks to nothing as F_n there falls
         * to 0, the modes' accelerations being equal where F_n = 0 */
        double sj[NY * (NY + 1)];
        h->u->separation(x0, &h->p, sj);
        memcpy(z, sj + h->u->separation_out.y, sizeof(double) * (size_t)h->ny);
        h->mode = 1;
        h->n = h->ny;
        h->open_since = ts;
        note_mode(h, 1);
    }
    /* Phi's columns are perturbations in the spin coordinates w = (.., u =
     * phidot + psidot, .., psidot, ..): Phi(ts) = T^-1, the column of psidot
     * moves psidot at fixed spin.  In x the monodromy has two nearly equal
     * columns of size Omega / (Omega theta) whose difference carries the
     * multipliers; integrated this way, each column has its own error
     * control and the difference is never formed. */
    const int ip = h->m->x_phidot, is = h->m->x_psidot;
    for (int i = 0; i < nx * h->ncol; ++i)
        z[nx + i] = 0.0;
    for (int i = 0; i < h->ncol; ++i)
        z[nx + i * nx + i] = 1.0;
    if (h->ncol)
        z[nx + ip * nx + is] = -1.0;
    double q = 0.0, t = ts;
    int rc = setup(h, t, z, q, t_end), ks = 0;
    h->wmin = INFINITY;
    h->wmax = -INFINITY;
    if (h->nsamp > 0)
        sample_speed(h, t, z);
    for (int events = 0; rc == USM_OK; ++events) {
        h->cv.cvmsg[0] = '\0';
        if (t >= t_end) /* a switch at the end of the period */
            break;
        /* sampling: the next sample time (CVODES interpolates there) */
        while (h->nsamp > 0 && ks < h->nsamp && ts + h->T * (ks + 1) / h->nsamp <= t)
            ++ks;
        const double tout = h->nsamp > 0 && ks + 1 < h->nsamp ? ts + h->T * (ks + 1) / h->nsamp
                                                              : t_end;
        const int flag = CVode(h->cv.mem, tout, h->cv.y, &t, CV_NORMAL);
        if (flag < 0) {
            rc = usm_cvodes_fail(&h->cv, "CVode", flag);
            break;
        }
        if (CVodeGetQuad(h->cv.mem, &t, h->cv.q) == CV_SUCCESS)
            q = N_VGetArrayPointer(h->cv.q)[0];
        if (h->nsamp > 0)
            sample_speed(h, t, N_VGetArrayPointer(h->cv.y));
        if (flag != CV_ROOT_RETURN && t < t_end) {
            --events;
            continue;
        }
        if (flag != CV_ROOT_RETURN)
            break;
        if (events > 4 * USM_HYBRID_MAX_SWITCHES) {
            snprintf(h->msg, USM_MSG_LEN, "more than %d contact switches in one period",
                     4 * USM_HYBRID_MAX_SWITCHES);
            rc = USM_EFAILED;
            break;
        }
        memcpy(z, N_VGetArrayPointer(h->cv.y), sizeof(double) * (size_t)(h->n + h->n * h->ncol));
        const int imps = h->nimprec;
        rc = switch_at(h, t, z);
        if (rc == USM_OK && h->stop_impacts > 0 && h->nimprec == h->stop_impacts &&
            imps < h->nimprec) {
            h->stop_t = t;
            memcpy(x1, z, sizeof(double) * (size_t)nx);
            usm_cvodes_release(&h->cv);
            return USM_OK;
        }
        if (rc == USM_OK && h->nmodes > USM_HYBRID_MAX_SWITCHES) {
            /* the mode sequence names the orbit (the sweep compares it):
             * never a truncated one */
            snprintf(h->msg, USM_MSG_LEN, "more than %d contact modes in one period",
                     USM_HYBRID_MAX_SWITCHES);
            rc = USM_EFAILED;
        }
        if (rc == USM_OK)
            rc = setup(h, t, z, q, t_end);
        if (rc == USM_OK && h->nsamp > 0)
            sample_speed(h, t, z);
    }
    if (rc == USM_OK && h->stop_impacts > 0) {
        snprintf(h->msg, USM_MSG_LEN, "fewer than %d impacts from t = %.9g s to %.9g s",
                 h->stop_impacts, ts, t_end);
        rc = USM_EFAILED;
    }
    if (rc == USM_OK && h->mode != 0) {
        snprintf(h->msg, USM_MSG_LEN, "the contact is open at the end of the period (t = %.9g s): "
                 "the section must lie in a closed phase", t);
        rc = USM_EFAILED;
    }
    if (rc == USM_OK) {
        const double *zz = N_VGetArrayPointer(h->cv.y);
        memcpy(x1, zz, sizeof(double) * (size_t)nx);
        if (B) {
            /* x coordinates: B = Phi T (column psidot = Phi's phidot + psidot
             * columns); spin coordinates: T Phi (row phidot += row psidot) */
            const double *Phi = zz + nx;
            memcpy(h->Phi, Phi, sizeof(double) * (size_t)(nx * nx));
            for (int i = 0; i < nx; ++i)
                for (int j = 0; j < nx; ++j) {
                    B[i * nx + j] = Phi[i * nx + j] + (j == is ? Phi[i * nx + ip] : 0.0);
                    h->Bspin[i * nx + j] = Phi[i * nx + j] + (i == ip ? Phi[is * nx + j] : 0.0);
                }
        }
        if (speed_mean)
            *speed_mean = q / h->T;
    }
    usm_cvodes_release(&h->cv);
    return rc;
}

static void set_scales(usm_hybrid *h, double theta, double speed)
{
    const usm_model *m = h->m;
    for (int j = 0; j < USM_MAX_NX; ++j)
        h->colscale[j] = 1.0;
    for (int i = 0; i < NY; ++i)
        h->scale[i] = 1.0;
    h->scale[m->x_theta] = theta;
    h->scale[m->x_phidot] = h->scale[m->x_psidot] = h->Omega;
    h->scale[m->x_thetadot] = h->Omega * theta;
    h->scale[m->x_tau] = h->p.m0 / h->p.c_t;
    if (m->x_phi_Rdot >= 0)
        h->scale[m->x_phi_Rdot] = fmax(fabs(speed), h->Omega * theta);
    h->scale[h->u->y_Z_R] = h->p.R * theta;
    h->scale[h->u->y_Z_Rdot] = h->p.R * theta * h->Omega;
    if (h->u->y_w_R >= 0)
        h->scale[h->u->y_w_R] = fmax(fabs(speed), h->Omega * theta);
    h->v_land = sqrt(h->rtol) * h->p.R * theta * h->Omega;
    for (int j = 0; j < h->nx; ++j)
        h->colscale[j] = h->scale[j];
    h->colscale[m->x_phidot] = h->Omega * theta; /* the spin */
}

/* The guard of every read of an orientation index here: the orbit with
 * separation is built in the Euler angles (its spin coordinates are phidot,
 * psidot) with the twist angle tau; a model whose descriptor lacks one (-1)
 * is refused instead of indexing a state with it.  The unilateral models are
 * all such; no tilt-vector model has an open mode. */
static int layout_check(usm_hybrid *h)
{
    const usm_model *m = h->m;
    if (m->coordinates == 0 && usm_coords_layout_ok(m) && m->x_tau >= 0 && m->x_tau < m->nx &&
        m->x_phi_Rdot < m->nx)
        return USM_OK;
    snprintf(h->msg, USM_MSG_LEN,
             "model %s: the orbit with separation needs the Euler angles phi, theta, psi, "
             "their rates and the twist angle tau, which its state lacks", m->name);
    return USM_EINPUT;
}

int usm_hybrid_set(usm_hybrid *h, const usm_params *p, double rtol)
{
    char why[USM_MSG_LEN];
    h->msg[0] = '\0';
    if (layout_check(h) != USM_OK)
        return USM_EINPUT;
    if (usm_params_check(p, h->m, why) != USM_OK) {
        snprintf(h->msg, USM_MSG_LEN, "%s", why);
        return USM_EINPUT;
    }
    if (!(p->M > 0)) {
        snprintf(h->msg, USM_MSG_LEN, "M: must be positive for a contact that may open (the "
                 "rotor's axial motion is a state of its own)");
        return USM_EINPUT;
    }
    if (!(rtol >= 1e-14 && rtol <= 1e-3)) {
        snprintf(h->msg, USM_MSG_LEN, "rtol: must be in [1e-14, 1e-3]");
        return USM_EINPUT;
    }
    h->p = *p;
    h->rtol = rtol;
    h->map_rtol = rtol;
    h->Omega = TWO_PI * p->f;
    h->T = 1.0 / p->f;
    if (!(h->scale[h->m->x_theta] > 0))
        set_scales(h, 1e-4, 0.0);
    else
        set_scales(h, h->scale[h->m->x_theta], h->scale[h->m->x_phi_Rdot >= 0 ? h->m->x_phi_Rdot
                                                                              : h->m->x_theta]);
    return USM_OK;
}

int usm_hybrid_period_map(usm_hybrid *h, double ts, const double *x0, double *x1, double *B)
{
    h->msg[0] = '\0';
    if (layout_check(h) != USM_OK)
        return USM_EINPUT;
    return period_map(h, ts, x0, x1, B, NULL);
}

/* Gram-Schmidt of the c tangent columns of z (the current mode's n rows)
 * in the norm |v|^2 = sum (v_i / scale_i)^2 over the non-cyclic rows (a
 * cyclic row feeds no other: it is dropped, the quotient's dynamics are
 * unchanged); their lengths before normalising into r.  0, or -1 when a
 * column vanished or is not finite. */
static int orthonormalise(usm_hybrid *h, double *z, int c, double *r)
{
    const int n = h->n;
    double *Phi = z + n;
    for (int i = 0; i < n; ++i)
        if (i < h->nx && h->m->cyclic[i])
            for (int j = 0; j < c; ++j)
                Phi[i * c + j] = 0.0;
    for (int j = 0; j < c; ++j) {
        for (int l = 0; l < j; ++l) {
            double d = 0;
            for (int i = 0; i < n; ++i)
                d += Phi[i * c + j] * Phi[i * c + l] / (h->scale[i] * h->scale[i]);
            for (int i = 0; i < n; ++i)
                Phi[i * c + j] -= d * Phi[i * c + l];
        }
        double s = 0;
        for (int i = 0; i < n; ++i)
            s += Phi[i * c + j] * Phi[i * c + j] / (h->scale[i] * h->scale[i]);
        s = sqrt(s);
        if (!(s > 0) || !isfinite(s))
            return -1;
        r[j] = s;
        for (int i = 0; i < n; ++i)
            Phi[i * c + j] /= s;
    }
    return 0;
}

int usm_hybrid_lyapunov(usm_hybrid *h, double t0, int open, const double *y0, long skip,
                        long periods, usm_hybrid_lyapunov_result *out)
{
    const int nx = h->nx, c = USM_HYBRID_LYAPUNOV_COUNT;
    memset(out, 0, sizeof *out);
    h->msg[0] = '\0';
    if (layout_check(h) != USM_OK)
        return USM_EINPUT;
    if (skip < 0 || periods < 1) {
        snprintf(h->msg, USM_MSG_LEN, "periods: must be at least 1 (and skip at least 0)");
        return USM_EINPUT;
    }
    h->mode = open ? 1 : 0;
    h->n = open ? h->ny : nx;
    h->ncol = c;
    h->nsamp = 0;
    h->open_total = 0;
    h->vmax = 0;
    h->nsep = h->nimp = h->nslip = h->nmodes = 0;
    h->bounces = 0;
    h->long_run = 1;
    const int iw = h->m->x_phi_Rdot >= 0 ? h->m->x_phi_Rdot : h->u->y_w_R;
    set_scales(h, fabs(y0[h->m->x_theta]),
               iw >= 0 && (iw < nx || open) ? y0[iw] : 0.0);
    for (int j = 0; j < c; ++j)
        h->colscale[j] = 1.0; /* unit columns in the scaled norm */
    double z[MAXZ], r[USM_HYBRID_LYAPUNOV_COUNT];
    memcpy(z, y0, sizeof(double) * (size_t)h->n);
    /* fixed start directions (a run is reproducible): every row, then rows
     * of alternating sign, each in units of its scale */
    for (int i = 0; i < h->n; ++i)
        for (int j = 0; j < c; ++j)
            z[h->n + i * c + j] = h->scale[i] * (j == 0 ? 1.0 : (i % 2 ? -1.0 : 1.0) / (1 + i));
    int rc = USM_OK;
    if (orthonormalise(h, z, c, r) != 0) {
        snprintf(h->msg, USM_MSG_LEN, "the start state has no non-cyclic direction");
        rc = USM_EINPUT;
    }
    double sum[USM_HYBRID_LYAPUNOV_COUNT] = {0};
    double t = t0;
    long k;
    for (k = 0; rc == USM_OK && k < skip + periods; ++k) {
        const double t_end = t0 + (double)(k + 1) * h->T;
        rc = setup(h, t, z, 0.0, t_end);
        for (int events = 0; rc == USM_OK && t < t_end; ++events) {
            h->cv.cvmsg[0] = '\0';
            const int flag = CVode(h->cv.mem, t_end, h->cv.y, &t, CV_NORMAL);
            if (flag < 0) {
                rc = usm_cvodes_fail(&h->cv, "CVode", flag);
                break;
            }
            memcpy(z, N_VGetArrayPointer(h->cv.y), sizeof(double) * (size_t)(h->n + h->n * c));
            if (flag != CV_ROOT_RETURN)
                break;
            if (events > 4 * USM_HYBRID_MAX_SWITCHES) {
                snprintf(h->msg, USM_MSG_LEN, "more than %d contact switches in one period "
                         "(t = %.9g s)", 4 * USM_HYBRID_MAX_SWITCHES, t);
                rc = USM_EFAILED;
                break;
            }
            rc = switch_at(h, t, z);
            if (rc == USM_OK)
                rc = setup(h, t, z, 0.0, t_end);
        }
        usm_cvodes_release(&h->cv);
        if (rc != USM_OK)
            break;
        t = t_end;
        if (orthonormalise(h, z, c, r) != 0) {
            snprintf(h->msg, USM_MSG_LEN, "the tangent vectors vanished at t = %.9g s", t);
            rc = USM_EFAILED;
            break;
        }
        if (k >= skip)
            for (int j = 0; j < c; ++j)
                sum[j] += log(r[j]);
    }
    h->long_run = 0;
    out->periods = k > skip ? k - skip : 0;
    for (int j = 0; j < c; ++j)
        out->exponents[j] = out->periods > 0 ? sum[j] / ((double)out->periods * h->T) : NAN;
    out->separations = h->nsep;
    out->impacts = h->nimp;
    out->impact_velocity_max = h->vmax;
    out->t_end = t;
    out->open_end = h->mode;
    out->n_end = h->n;
    memcpy(out->y_end, z, sizeof(double) * (size_t)h->n);
    /* the period maps' column scales again */
    set_scales(h, h->scale[h->m->x_theta], iw >= 0 ? h->scale[iw] : 0.0);
    return rc;
}

int usm_hybrid_orbit_samples(usm_hybrid *h, const usm_params *p, const usm_hybrid_result *r,
                             double rtol, int n, double *rows, int *nrows)
{
    usm_hybrid_options o;
    usm_hybrid_options_default(&o);
    *nrows = 0;
    h->msg[0] = '\0';
    if (!(n >= 2 && n <= USM_HYBRID_MAX_SAMPLES)) {
        snprintf(h->msg, USM_MSG_LEN, "samples: must be 2 to %d", USM_HYBRID_MAX_SAMPLES);
        return USM_EINPUT;
    }
    if (!r->converged || r->nx != h->nx) {
        snprintf(h->msg, USM_MSG_LEN, "the orbit: %s", r->converged ? "of another model"
                                                                     : "not converged");
        return USM_EINPUT;
    }
    int rc = usm_hybrid_set(h, p, rtol == 0 ? o.rtol : rtol);
    if (rc != USM_OK)
        return rc;
    /* the orbit's own scales (the solve's, but for its start's theta) */
    set_scales(h, r->x0[h->m->x_theta], r->rotor_speed_mean);
    double x1[USM_MAX_NX];
    h->rows = rows;
    h->nrows = h->rows_lost = 0;
    h->rows_max = USM_HYBRID_SAMPLE_ROWS(n);
    h->nsamp = n;
    rc = period_map(h, r->t0, r->x0, x1, NULL, NULL);
    h->nsamp = 0;
    h->rows = NULL;
    *nrows = h->nrows;
    if (rc == USM_OK && h->rows_lost) {
        snprintf(h->msg, USM_MSG_LEN, "more switches and touches in the period than rows");
        rc = USM_EFAILED;
    }
    if (rc == USM_OK && strcmp(h->seq, r->mode_sequence) != 0) {
        /* another tolerance (the landing threshold), or not this orbit */
        snprintf(h->msg, USM_MSG_LEN, "the sampled period's modes %.40s are not the orbit's %.40s "
                 "(solved at another rtol?)", h->seq, r->mode_sequence);
        rc = USM_EFAILED;
    }
    return rc;
}

/* ---- the start: a simulation ---------------------------------------------------- */

#define SAMPLES_PER_PERIOD 50
/* The quick start (usm_hybrid_solve): the simulation's tolerance, and its
 * early end once the period means of tilt and rotor speed changed by less
 * than CALM_TOL (relative; the rotor speed's at least to 1e-2 1/s) in
 * CALM_PERIODS consecutive periods.  Measured (bench/bench_hybrid, 3-DOF 35
 * deg, 4-DOF 30 deg): the start-up ends after about 50 of the 185 periods of
 * settle, 25 to 35 ms of the old 230 to 280 ms, and Newton needs one map
 * with the monodromy and three chord steps more. */
#define QUICK_RTOL 1e-5
#define CALM_TOL 3e-4
#define CALM_PERIODS 5
#define NSAMP (2 * SAMPLES_PER_PERIOD) /* two periods */
typedef struct {
    int n, nx;
    double t[NSAMP], x[NSAMP][USM_MAX_NX];
    int open[NSAMP];
    /* the early end: period means seen, the last ones, the calm periods */
    double stol;
    int speriods;
    double theta_avg, speed_avg, w_floor;
    int calm, stopped;
} ring_t;

static int keep_sample(const usm_sim_sample *s, void *data)
{
    ring_t *r = data;
    const int k = r->n % NSAMP;
    r->t[k] = s->t;
    r->open[k] = s->open;
    memcpy(r->x[k], s->x, sizeof(double) * (size_t)r->nx);
    r->n++;
    if (s->have_avg && (s->theta_avg != r->theta_avg || s->rotor_speed_avg != r->speed_avg)) {
        /* a new period's means: calm when both moved by less than stol */
        const double dth = fabs(s->theta_avg - r->theta_avg) / fabs(s->theta_avg);
        const double dw = fabs(s->rotor_speed_avg - r->speed_avg) /
                          fmax(fabs(s->rotor_speed_avg), r->w_floor);
        r->calm = dth < r->stol && dw < r->stol ? r->calm + 1 : 0;
        r->theta_avg = s->theta_avg;
        r->speed_avg = s->rotor_speed_avg;
        if (r->calm >= r->speriods && r->n >= NSAMP) {
            r->stopped = 1;
            return 1;
        }
    }
    return 0;
}

/* The section: the middle of the longest closed stretch among the last
 * samples (SAMPLES_PER_PERIOD per period over two periods). */
static int start_from_simulation(usm_hybrid *h, const usm_hybrid_options *o, int quick,
                                 double *ts, double *x0, double *speed)
{
    usm_sim *s = usm_sim_alloc(h->m);
    usm_sim_options so;
    usm_sim_summary sum;
    ring_t *r = calloc(1, sizeof *r);
    if (!s || !r) {
        usm_sim_free(s);
        free(r);
        snprintf(h->msg, USM_MSG_LEN, "out of memory");
        return USM_EFAILED;
    }
    usm_sim_options_default(&so);
    so.duration = o->settle;
    so.rate = SAMPLES_PER_PERIOD * h->p.f;
    /* a start near the orbit: Newton does the rest */
    so.rtol = quick ? QUICK_RTOL : 1e-8;
    r->nx = h->nx;
    r->stol = quick ? CALM_TOL : 0.0;
    r->speriods = CALM_PERIODS;
    r->w_floor = 1e-2;
    r->theta_avg = r->speed_avg = NAN;
    usm_sim_callbacks cb = {keep_sample, NULL, r, NULL};
    int rc = usm_sim_run(s, &h->p, &so, &cb, &sum);
    if (r->stopped && sum.stop == USM_SIM_STOPPED)
        rc = USM_OK; /* settled enough for Newton: the early end */
    if (rc != USM_OK)
        snprintf(h->msg, USM_MSG_LEN, "the simulation to start from failed: %.200s",
                 usm_sim_message(s));
    usm_sim_free(s);
    if (rc == USM_OK && r->n < NSAMP) {
        snprintf(h->msg, USM_MSG_LEN, "settle: too short for two periods of samples");
        rc = USM_EINPUT;
    }
    if (rc == USM_OK) {
        int best = -1, best_len = 0;
        for (int i = 0; i < NSAMP;) {
            const int k0 = (r->n + i) % NSAMP;
            if (r->open[k0]) {
                ++i;
                continue;
            }
            int j = i;
            while (j < NSAMP && !r->open[(r->n + j) % NSAMP])
                ++j;
            if (j - i > best_len) {
                best_len = j - i;
                best = i + (j - i) / 2;
            }
            i = j;
        }
        if (best < 0) {
            snprintf(h->msg, USM_MSG_LEN, "the contact stays open in the simulation: no section "
                     "in a closed phase%s", h->p.e_impact > 0 ? " (the rotor bounces on the "
                     "stator without landing: such orbits of impacts only are not computed)" : "");
            rc = USM_EFAILED;
        } else {
            const int k = (r->n + best) % NSAMP;
            *ts = r->t[k];
            memcpy(x0, r->x[k], sizeof(double) * (size_t)h->nx);
            *speed = sum.rotor_speed_avg_end;
        }
    }
    free(r);
    return rc;
}

/* ---- Newton and the multipliers -------------------------------------------------- */

/* The multipliers: the eigenvalues of the monodromy in the coordinates
 * (spin phidot + psidot, psidot) for phidot (in x the monodromy has two
 * nearly equal columns of size Omega / (Omega theta) whose difference
 * carries the multipliers, and an eigensolver loses 1e-5 of them to it;
 * T B T^-1 has the same eigenvalues), by the path of every monodromy
 * (solve/multipliers.h), balanced before QR: unbalanced, GSL's eigensolver
 * lost up to 1.6e-6 of the multipliers whose condition number is about 300
 * (4-DOF, phase error 30 deg: against test_hybrid_unilateral's reference in
 * extended precision, and jumping between 3e-8 and 1.5e-6 with rtol). */
static int multipliers(usm_hybrid *h, const double *B, usm_floquet_result *f)
{
    if (usm_multipliers_eigen(h->mult, h->Bspin, h->msg) != 0)
        return USM_EFAILED;
    memset(f, 0, sizeof *f);
    usm_multipliers_result(h->mult, f);
    memcpy(f->monodromy, B, sizeof(double) * (size_t)(h->nx * h->nx));
    return USM_OK;
}

static int newton(usm_hybrid *h, const usm_hybrid_options *opt, double ts, double *x0,
                  int rough, usm_hybrid_result *out);

static int check_start(usm_hybrid *h, const usm_params *p, const usm_hybrid_options *opt,
                       usm_hybrid_result *out)
{
    int rc;
    memset(out, 0, sizeof *out);
    memset(h->scale, 0, sizeof h->scale);
    h->chatter = 0;
    if ((rc = usm_hybrid_set(h, p, opt->rtol)) != USM_OK)
        return rc;
    if (!(opt->tol > 0) || opt->max_iter < 1 || !(opt->settle > 0) || !isfinite(opt->settle)) {
        snprintf(h->msg, USM_MSG_LEN, "options: tol > 0, max_iter >= 1 and settle > 0 needed");
        return USM_EINPUT;
    }
    return USM_OK;
}

int usm_hybrid_solve(usm_hybrid *h, const usm_params *p, const usm_hybrid_options *opt,
                     usm_hybrid_result *out)
{
    usm_hybrid_options def;
    int rc;
    if (!opt) {
        usm_hybrid_options_default(&def);
        opt = &def;
    }
    if ((rc = check_start(h, p, opt, out)) != USM_OK)
        return rc;
    double ts, x0[USM_MAX_NX], speed;
    /* quick: the start-up at rtol 1e-5, ended once calm; Newton's chord
     * steps take it from there.  Should Newton fail from it, or converge to
     * an unstable orbit (a start-up lingers near a weakly unstable orbit,
     * and calm there is not settled: 4-DOF mode split 2 %), the careful
     * start: the whole settle at rtol 1e-8. */
    usm_hybrid_result first;
    int have_first = 0;
    for (int quick = 1; quick >= 0; --quick) {
        if ((rc = start_from_simulation(h, opt, quick, &ts, x0, &speed)) == USM_OK) {
            set_scales(h, x0[h->m->x_theta], speed);
            rc = newton(h, opt, ts, x0, 1, out);
        }
        if ((rc == USM_OK && (!quick || out->floquet.max_modulus < 1)) || h->chatter)
            break; /* chattering: a careful start would meet it again */
        if (rc == USM_OK) { /* unstable: kept should the careful start fail */
            first = *out;
            have_first = 1;
        }
    }
    if (rc != USM_OK && have_first) {
        *out = first;
        h->msg[0] = '\0';
        rc = USM_OK;
    }
    return rc;
}

int usm_hybrid_solve_from(usm_hybrid *h, const usm_params *p, const usm_hybrid_options *opt,
                          double ts, const double *x_start, usm_hybrid_result *out)
{
    usm_hybrid_options def;
    double x0[USM_MAX_NX];
    int rc;
    if (!opt) {
        usm_hybrid_options_default(&def);
        opt = &def;
    }
    if ((rc = check_start(h, p, opt, out)) != USM_OK)
        return rc;
    memcpy(x0, x_start, sizeof(double) * (size_t)h->nx);
    if (!isfinite(ts) || !(x0[h->m->x_theta] > 0)) {
        snprintf(h->msg, USM_MSG_LEN, "x0: theta must be > 0 and ts finite");
        return USM_EINPUT;
    }
    const int ird = h->m->x_phi_Rdot;
    set_scales(h, x0[h->m->x_theta], ird >= 0 ? x0[ird] : h->Omega * x0[h->m->x_theta]);
    return newton(h, opt, ts, x0, 0, out);
}

/* The residual r = x1 - x0 (less 2 pi in phi) on the non-cyclic components
 * and its largest scaled entry. */
static double residual(const usm_hybrid *h, const int *idx, int nr, const double *x0,
                       const double *x1, double *r)
{
    double res = 0;
    for (int a = 0; a < nr; ++a) {
        const int i = idx[a];
        r[a] = x1[i] - x0[i] - (i == h->m->x_phi ? TWO_PI : 0.0);
        res = fmax(res, fabs(r[a]) / h->scale[i]);
    }
    return res;
}

/* Newton on x(ts + T) - x(ts) with chord steps: each map with the monodromy
 * (6.5 ms, 4-DOF) is followed by steps with its LU and maps without it (1.3
 * ms) while they contract the residual at least by CHORD_RATE (or reach
 * opt->tol); the orbit's multipliers come from a map with the monodromy at
 * the converged state.  From a start near the last converged orbit of this
 * solver (same section time; a continuation's next point) the chord steps
 * begin with that orbit's LU instead of a first map with the monodromy: the
 * next orbit is then one map with the monodromy (its check and its
 * multipliers) and the chord maps (measured, bench/bench_hybrid_cont 4-DOF
 * steps of 5e-5: 2.4 maps with the monodromy an orbit before, 1 to 2 now);
 * where they do not contract, Newton goes on as without it from the best
 * iterate.  rough (a cold start, 1e-4 off the orbit): the first
 * map with the monodromy at ROUGH_RTOL and without the ripple samples (2 ms
 * instead of 6.5): its errors of 1e-7 in the step are far below the step's
 * own quadratic error, the chord maps and the last map run at opt->rtol.
 * opt->max_iter counts the maps with the monodromy (out->iterations). */
#define ROUGH_RTOL 1e-7
#define CHORD_RATE 0.25
#define CHORD_MAX 8
#define CHORD_NOISE 10.0
/* The chord steps with the last orbit's LU go on while they halve the
 * residual: a map without the monodromy costs a fifth of one with it, and
 * the first step from a zero-order start contracts by 0.2 to 0.3 only
 * (measured), the noise floor near opt->tol by about 0.5. */
#define REUSE_RATE 0.5
/* Converged by chord maps within this (scaled) of the last map with the
 * monodromy, the orbit takes that map's multipliers and period statistics
 * instead of one more map with the monodromy: they move by about that
 * (relative), a tenth of what Newton's tolerance leaves open near a
 * multiplier 0.9, and the confirming map's residual agreed only to its own
 * noise (CHORD_NOISE) anyway.  Met where the chord maps stall at their
 * noise, 2e-9 to 7e-9, just above opt->tol: the Newton step from the map
 * with the monodromy is then about 1e-8. */
#define REUSE_B_STEP 1e-8

/* What a period map leaves in h of its orbit (the orbit's statistics). */
typedef struct map_stats {
    double open_total, vmax, wmin, wmax;
    int nsep, nimp, nslip, nmodes;
    char seq[USM_HYBRID_MAX_SWITCHES + 1];
} map_stats;

static void stats_keep(const usm_hybrid *h, map_stats *st)
{
    st->open_total = h->open_total;
    st->vmax = h->vmax;
    st->wmin = h->wmin;
    st->wmax = h->wmax;
    st->nsep = h->nsep;
    st->nimp = h->nimp;
    st->nslip = h->nslip;
    st->nmodes = h->nmodes;
    memcpy(st->seq, h->seq, sizeof st->seq);
}

static void stats_restore(usm_hybrid *h, const map_stats *st)
{
    h->open_total = st->open_total;
    h->vmax = st->vmax;
    h->wmin = st->wmin;
    h->wmax = st->wmax;
    h->nsep = st->nsep;
    h->nimp = st->nimp;
    h->nslip = st->nslip;
    h->nmodes = st->nmodes;
    memcpy(h->seq, st->seq, sizeof st->seq);
}

static int newton(usm_hybrid *h, const usm_hybrid_options *opt, double ts, double *x0,
                  int rough, usm_hybrid_result *out)
{
    const int nx = h->nx;
    int rc;
    double x1[USM_MAX_NX], B[USM_MAX_NX * USM_MAX_NX];
    int idx[USM_MAX_NX], nr = 0;
    for (int i = 0; i < nx; ++i)
        if (!h->m->cyclic[i])
            idx[nr++] = i;
    double res = INFINITY, mean = NAN;
    int it;
    if (!rough && h->jc_nr == nr && fabs(ts - h->jc_ts) <= 1e-9 * h->T) {
        double r[USM_MAX_NX], xt[USM_MAX_NX], rt[USM_MAX_NX], rest;
        h->nsamp = 0;
        if (period_map(h, ts, x0, x1, NULL, NULL) == USM_OK) {
            res = residual(h, idx, nr, x0, x1, r);
            for (int c = 0; c < CHORD_MAX && res > opt->tol; ++c) {
                usm_lu_solve_dense(nr, h->jc_lu, h->jc_piv, r, 1);
                memcpy(xt, x0, sizeof xt);
                for (int a = 0; a < nr; ++a)
                    xt[idx[a]] -= r[a];
                if (period_map(h, ts, xt, x1, NULL, NULL) != USM_OK ||
                    !((rest = residual(h, idx, nr, xt, x1, rt)) <= REUSE_RATE * res ||
                      rest <= opt->tol))
                    break; /* x0 the best iterate */
                memcpy(x0, xt, sizeof xt);
                memcpy(r, rt, sizeof rt);
                res = rest;
            }
        }
        /* the map with the monodromy below confirms a converged x0 */
        if (!(res <= opt->tol))
            res = INFINITY;
    }
    /* every map with the monodromy samples the rotor speed for the ripple
     * (the converged one's counts): the samples are CVODES' interpolants,
     * its steps the same */
    map_stats st;
    double xB[USM_MAX_NX];
    int from_B = 0; /* converged near the last map with the monodromy: its multipliers */
    for (it = 0; it <= opt->max_iter && !from_B; ++it) {
        double r[USM_MAX_NX];
        int rough_map = rough && it == 0;
        h->nsamp = rough_map ? 0 : RIPPLE_SAMPLES;
        if (rough_map)
            h->map_rtol = fmax(h->rtol, ROUGH_RTOL);
        rc = period_map(h, ts, x0, x1, B, &mean);
        h->map_rtol = h->rtol;
        if (rc != USM_OK && rough_map) {
            /* a failure (chattering: its bounces counted at the loose
             * tolerance) is judged at opt->rtol */
            rough_map = 0;
            h->chatter = 0;
            h->nsamp = RIPPLE_SAMPLES;
            rc = period_map(h, ts, x0, x1, B, &mean);
        }
        h->nsamp = 0;
        if (rc != USM_OK)
            return rc;
        stats_keep(h, &st);
        memcpy(xB, x0, sizeof xB);
        const double res_b = residual(h, idx, nr, x0, x1, r);
        /* converged by a chord map: this map (other steps, as the monodromy
         * is in the error control) agrees to its integration noise */
        if (res <= opt->tol && res_b <= CHORD_NOISE * opt->tol)
            break;
        res = res_b;
        if ((res <= opt->tol && !rough_map) || it == opt->max_iter)
            break;
        double J[USM_MAX_NX * USM_MAX_NX];
        int piv[USM_MAX_NX];
        for (int a = 0; a < nr; ++a)
            for (int b = 0; b < nr; ++b)
                J[a * nr + b] = B[idx[a] * nx + idx[b]] - (a == b);
        if (usm_lu_factor_dense(nr, J, piv) != 0) {
            snprintf(h->msg, USM_MSG_LEN, "Newton: B - I is singular");
            return USM_EFAILED;
        }
        /* the Newton step, then chord steps with the same LU */
        for (int c = 0; c <= CHORD_MAX; ++c) {
            usm_lu_solve_dense(nr, J, piv, r, 1);
            double xt[USM_MAX_NX], rt[USM_MAX_NX];
            memcpy(xt, x0, sizeof xt);
            for (int a = 0; a < nr; ++a)
                xt[idx[a]] -= r[a];
            if (c == CHORD_MAX) { /* the last step: the next map has the monodromy */
                memcpy(x0, xt, sizeof xt);
                break;
            }
            double rest;
            if (period_map(h, ts, xt, x1, NULL, NULL) != USM_OK || !((rest = residual(h, idx, nr, xt, x1, rt)) <= CHORD_RATE * res ||
                                   rest <= opt->tol)) {
                memcpy(x0, xt, sizeof xt); /* a Newton step that did not contract enough */
                break;
            }
            memcpy(x0, xt, sizeof xt);
            memcpy(r, rt, sizeof rt);
            res = rest;
            if (res <= opt->tol) {
                /* the map with the monodromy confirms it, unless this one
                 * lies within REUSE_B_STEP */
                double step = 0;
                for (int a = 0; a < nr; ++a)
                    step = fmax(step, fabs(x0[idx[a]] - xB[idx[a]]) / h->scale[idx[a]]);
                from_B = !rough_map && step <= REUSE_B_STEP;
                break;
            }
        }
    }
    if (from_B) {
        --it; /* the loop's increment: `it` maps with the monodromy before */
        stats_restore(h, &st);
    }
    out->iterations = it;
    out->residual = res;
    out->t0 = ts;
    out->period = h->T;
    out->nx = nx;
    memcpy(out->x0, x0, sizeof(double) * (size_t)nx);
    if (!(res <= opt->tol)) {
        snprintf(h->msg, USM_MSG_LEN, "Newton did not converge in %d iterations (residual %.3g)",
                 opt->max_iter, res);
        return USM_EFAILED;
    }
    if ((rc = multipliers(h, B, &out->floquet)) != USM_OK)
        return rc;
    h->jc_nr = 0;
    for (int a = 0; a < nr; ++a)
        for (int b = 0; b < nr; ++b)
            h->jc_lu[a * nr + b] = B[idx[a] * nx + idx[b]] - (a == b);
    if (usm_lu_factor_dense(nr, h->jc_lu, h->jc_piv) == 0) {
        h->jc_nr = nr;
        h->jc_ts = ts;
    }
    out->rotor_speed_ripple = h->wmax - h->wmin; /* of the converged map */
    out->floquet.t0 = ts;
    out->converged = 1;
    out->rotor_speed_mean = mean;
    out->separation_fraction = h->open_total / h->T;
    out->separations_per_period = h->nsep;
    out->impacts_per_period = h->nimp;
    out->impacts_slipping = h->nslip;
    /* the stick model does not describe an impact that needs more than mu0 */
    out->validity = h->m->slip || h->nslip == 0 ? USM_VALID : USM_INVALID_STICK;
    out->impact_velocity_max = h->vmax;
    out->nmodes = h->nmodes;
    memcpy(out->mode_sequence, h->seq, sizeof h->seq);
    return USM_OK;
}

void usm_hybrid_shoot_half(usm_hybrid *h, int half) { h->half = half != 0; }

int usm_hybrid_impact_map(usm_hybrid *h, const usm_params *p, double ts, const double *x0,
                          int k, double *x1, double *t1, double *fn0,
                          char seq[USM_HYBRID_MAX_SWITCHES + 1])
{
    usm_hybrid_options o;
    usm_hybrid_result unused;
    int rc;
    usm_hybrid_options_default(&o);
    if ((rc = check_start(h, p, &o, &unused)) != USM_OK)
        return rc;
    if (!isfinite(ts) || !(x0[h->m->x_theta] > 0) || k < 1 || k > USM_HYBRID_MAX_SWITCHES) {
        snprintf(h->msg, USM_MSG_LEN, "x0: theta must be > 0, ts finite and k in [1, %d]",
                 USM_HYBRID_MAX_SWITCHES);
        return USM_EINPUT;
    }
    const int ird = h->m->x_phi_Rdot;
    set_scales(h, x0[h->m->x_theta], ird >= 0 ? x0[ird] : h->Omega * x0[h->m->x_theta]);
    h->nsamp = 0;
    h->map_half = 0;
    h->stop_impacts = k;
    if (fn0)
        *fn0 = closed_Fn(h, ts, x0);
    /* the k-th impact comes about k / 2 periods on (two a period): room for
     * it to come late */
    const double T = h->T;
    h->T = (0.5 * k + 1.0) * T;
    rc = period_map(h, ts, x0, x1, NULL, NULL);
    h->T = T;
    h->stop_impacts = 0;
    if (rc != USM_OK)
        return rc;
    if (t1)
        *t1 = h->stop_t;
    if (seq)
        memcpy(seq, h->seq, sizeof h->seq);
    return USM_OK;
}

int usm_hybrid_shoot_impacts(const usm_hybrid *h, double *t, double *fn, int *lands, int max)
{
    const int n = h->nimprec < max ? h->nimprec : max;
    for (int k = 0; k < n; ++k) {
        if (t)
            t[k] = h->imp_t[k];
        if (fn)
            fn[k] = h->imp_fn[k];
        if (lands)
            lands[k] = h->imp_lands[k];
    }
    return h->nimprec;
}

/* The continuation engine's zero problem (hybrid_internal.h): the map of
 * usm_hybrid_solve_from's Newton at the same scales, so that a point the
 * engine converges is one that solve converges at once. */
int usm_hybrid_shoot(usm_hybrid *h, const usm_params *p, double ts, const double *x0,
                     int *idx, int *nr, double *F, double *J, double *max_modulus,
                     double crit[2], double *scale, char seq[USM_HYBRID_MAX_SWITCHES + 1])
{
    usm_hybrid_options o;
    usm_hybrid_result unused;
    const int nx = h->nx;
    int rc, id[USM_MAX_NX], n = 0;
    usm_hybrid_options_default(&o);
    if ((rc = check_start(h, p, &o, &unused)) != USM_OK)
        return rc;
    if (!isfinite(ts) || !(x0[h->m->x_theta] > 0)) {
        snprintf(h->msg, USM_MSG_LEN, "x0: theta must be > 0 and ts finite");
        return USM_EINPUT;
    }
    const int ird = h->m->x_phi_Rdot;
    set_scales(h, x0[h->m->x_theta], ird >= 0 ? x0[ird] : h->Omega * x0[h->m->x_theta]);
    for (int i = 0; i < nx; ++i)
        if (!h->m->cyclic[i])
            id[n++] = i;
    double x1[USM_MAX_NX], B[USM_MAX_NX * USM_MAX_NX];
    h->nsamp = 0;
    h->map_half = h->half;
    rc = period_map(h, ts, x0, x1, J ? B : NULL, NULL);
    h->map_half = 0;
    if (rc != USM_OK)
        return rc;
    residual(h, id, n, x0, x1, F);
    /* half a period on, phi has turned by pi (the drive's phase) */
    for (int a = 0; h->half && a < n; ++a)
        if (id[a] == h->m->x_phi)
            F[a] += 0.5 * TWO_PI;
    if (J) {
        /* Phi - dx0/dw (x0 = T^-1 w: phidot = u - psidot) */
        usm_floquet_result f;
        const int ip = h->m->x_phidot, is = h->m->x_psidot;
        for (int a = 0; a < n; ++a)
            for (int b = 0; b < n; ++b)
                J[a * n + b] = h->Phi[id[a] * nx + id[b]] - (a == b) +
                               (id[a] == ip && id[b] == is);
        if ((rc = multipliers(h, B, &f)) != USM_OK)
            return rc;
        if (max_modulus)
            *max_modulus = f.max_modulus;
        if (crit) {
            int k = -1;
            for (int i = 0; i < f.n; ++i)
                if (!f.cyclic[i] &&
                    (k < 0 || hypot(f.re[i], f.im[i]) > hypot(f.re[k], f.im[k])))
                    k = i;
            crit[0] = k >= 0 ? f.re[k] : NAN;
            crit[1] = k >= 0 ? f.im[k] : NAN;
        }
        if (scale)
            memcpy(scale, h->colscale, sizeof(double) * (size_t)nx);
    }
    if (idx)
        memcpy(idx, id, sizeof(int) * (size_t)n);
    if (nr)
        *nr = n;
    if (seq)
        memcpy(seq, h->seq, sizeof h->seq);
    return USM_OK;
}

