/* The power fed into the vibration and the energy balance that checks it
 * (usm_squeal_energy, usm_squeal_study.h; docs/squeal.md "Power").
 *
 * An event-driven integration of its own (CVODES, Adams, as the hybrid
 * shooting's: over a period the motion is not stiff) of the contact modes
 * with the work of every non-conservative force as extra states, so that the
 * works are integrated to the integrator's tolerance, and the mechanical
 * energy E of stator and rotor evaluated at the start, the end and on both
 * sides of every reset.  The resets are the simulation's (the separation
 * kernel; solve/impact.h's rule for an impact and the landing), so the motion
 * is the one the simulation runs.  What the balance checks: E(end) - E(start)
 * equals the sum of the works and of the jumps of E at the resets, each
 * computed from its own formula below, which the generated equations of
 * motion know nothing of: a force left out or a sign wrong in either breaks
 * it by far more than the tolerance.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/cvodes.h"
#include "core/dense.h"
#include "solve/contact_mode.h"
#include "solve/impact.h"
#include "usm_periodic.h"
#include "usm_squeal_study.h"

#define TWO_PI 6.283185307179586476925286766559
#define NY USM_MAX_NY
/* the works integrated: excitation, damping, load, friction (both sides),
   friction on the stator, normal force on the stator */
enum { W_EXC, W_DAMP, W_LOAD, W_FRIC, W_FRIC_STATOR, W_NORMAL_STATOR, NW };
#define MAXZ (NY + NW)

typedef struct energy {
    const usm_model *m;
    const usm_unilateral *u;
    usm_params p;
    usm_mode k[2];
    int mode, n;
    double Omega, T, v_land;
    double scale[MAXZ];
    usm_cvodes cv;
    char msg[USM_MSG_LEN];
} energy;

static int rates(const energy *e, int mode, double t, const double *y, double *ydot)
{
    const usm_mode *k = &e->k[mode];
    const int n = k->n;
    double lu[NY * NY];
    int piv[NY];
    k->mass(y, &e->p, lu);
    for (int i = 0; i < n * n; ++i)
        if (!isfinite(lu[i]))
            return -1;
    if (usm_lu_factor_dense(n, lu, piv) != 0)
        return -1;
    k->rhs(y, t, &e->p, ydot);
    usm_lu_solve_dense(n, lu, piv, ydot, 1);
    for (int i = 0; i < n; ++i)
        if (!isfinite(ydot[i]))
            return -1;
    return 0;
}

/* The powers of the non-conservative forces at (t, y) of the mode into P
 * (NW values; docs/squeal.md "Power"). */
static int powers(const energy *e, int mode, double t, const double *y, double *P)
{
    const usm_model *m = e->m;
    const usm_params *p = &e->p;
    double yd[NY], out[USM_OUT_COUNT];
    if (rates(e, mode, t, y, yd) != 0)
        return -1;
    e->k[mode].outputs(y, yd, t, p, out);
    const double phi = y[m->x_phi], th = y[m->x_theta];
    const double phid = y[m->x_phidot], thd = y[m->x_thetadot], psid = y[m->x_psidot];
    /* the stator's angular velocity in frame A */
    const double wx = thd, wy = -psid * sin(th), wz = phid + psid * cos(th);
    /* the excitation torque m0 ((1 + eps) cos Omega t, (1 - eps) sin(Omega t + delta))
       in the housing frame, turned into frame A */
    const double MX = p->m0 * (1.0 + p->amp_imbalance) * cos(e->Omega * t);
    const double MY = p->m0 * (1.0 - p->amp_imbalance) * sin(e->Omega * t + p->phase_error);
    const double Ex = cos(phi) * MX + sin(phi) * MY, Ey = -sin(phi) * MX + cos(phi) * MY;
    /* the rotor's axial velocity: the crest's while closed, its own while open */
    const double Rs = p->R * cos(th) - p->H * sin(th);
    const double Zd = mode ? y[e->u->y_Z_Rdot] : Rs * thd;
    const double Fn = out[USM_OUT_F_N], Ft = out[USM_OUT_F_T];
    P[W_EXC] = Ex * wx + Ey * wy;
    P[W_DAMP] = -(p->d_r * (wx * wx + wy * wy) + p->d_t * wz * wz + p->d_R * Zd * Zd);
    P[W_LOAD] = p->T * out[USM_OUT_ROTOR_SPEED]; /* -T w_R, w_R = -phidot_R */
    P[W_FRIC] = -Ft * out[USM_OUT_V_REL];
    P[W_FRIC_STATOR] = -Ft * out[USM_OUT_V_C];
    P[W_NORMAL_STATOR] = mode ? 0.0 : -Fn * Rs * thd;
    for (int i = 0; i < NW; ++i)
        if (!isfinite(P[i]))
            return -1;
    return 0;
}

double usm_squeal_mechanical_energy(const usm_model *m, const usm_params *p, int open,
                                    const double *y)
{
    const usm_unilateral *u = m->unilateral;
    if (!u)
        return NAN;
    double yy[NY], sj[NY * (NY + 1)], ke = NAN;
    if (open)
        memcpy(yy, y, sizeof(double) * (size_t)u->ny);
    else { /* the closed state with the rotor on the crest (continuous) */
        u->separation(y, p, sj);
        memcpy(yy, sj + u->separation_out.y, sizeof(double) * (size_t)u->ny);
    }
    u->kinetic_energy(yy, p, &ke);
    const double th = yy[m->x_theta], phi = yy[m->x_phi], tw = yy[m->x_tau];
    const double dz = yy[u->y_Z_R] - p->H; /* the spring's length from theta = 0 */
    /* the tilt spring fixed in the housing, c_r (1 + s) about X and c_r (1 - s)
       about Y on the tilt vector theta (cos phi, sin phi); the twist spring on
       the integrated twist angle; the rotor's preloaded spring */
    const double V = 0.5 * p->c_r * th * th * (1.0 + p->mode_split * cos(2.0 * phi)) +
                     0.5 * p->c_t * tw * tw + p->F0 * dz + 0.5 * p->c_R * dz * dz;
    return ke + V;
}

static int cv_rhs(sunrealtype t, N_Vector zv, N_Vector zdot, void *data)
{
    energy *e = data;
    const double *z = N_VGetArrayPointer(zv);
    double *d = N_VGetArrayPointer(zdot);
    if (rates(e, e->mode, t, z, d) != 0 || powers(e, e->mode, t, z, d + e->n) != 0)
        return 1;
    return 0;
}

static int cv_root(sunrealtype t, N_Vector zv, sunrealtype *g, void *data)
{
    energy *e = data;
    const double *z = N_VGetArrayPointer(zv);
    if (e->mode == 1) {
        double gg[1 + NY];
        e->u->guard_open(z, &e->p, gg);
        g[0] = gg[e->u->guard_open_out.gap];
    } else {
        double xd[NY], out[USM_OUT_COUNT];
        if (rates(e, 0, t, z, xd) != 0)
            return -1;
        e->m->outputs(z, xd, t, &e->p, out);
        g[0] = out[USM_OUT_F_N];
    }
    return isfinite(g[0]) ? 0 : -1;
}

static double closed_Fn(void *ctx, double t, const double *y)
{
    const energy *e = ctx;
    double xd[NY], o[USM_OUT_COUNT];
    if (rates(e, 0, t, y, xd) != 0)
        return NAN;
    e->m->outputs(y, xd, t, &e->p, o);
    return o[USM_OUT_F_N];
}

static int setup(energy *e, double t, const double *z, double t_end, double rtol, long steps)
{
    const int len = e->n + NW;
    double a[MAXZ], zz[MAXZ];
    memcpy(zz, z, sizeof(double) * (size_t)e->n);
    memcpy(zz + e->n, z + NY, sizeof(double) * NW);
    for (int i = 0; i < e->n; ++i)
        a[i] = rtol * e->scale[i];
    for (int i = 0; i < NW; ++i)
        a[e->n + i] = rtol * e->scale[NY + i];
    static const int dir = -1; /* the guards fall through zero */
    const usm_cvodes_spec spec = {.lmm = CV_ADAMS,
                                  .n = len,
                                  .t0 = t,
                                  .y0 = zz,
                                  .rhs = cv_rhs,
                                  .data = e,
                                  .max_steps = steps,
                                  .rtol = rtol,
                                  .atol_v = a,
                                  .t_stop = t_end,
                                  .nroots = 1,
                                  .roots = cv_root,
                                  .root_dir = &dir};
    return usm_cvodes_init(&e->cv, &spec, e->msg);
}

/* Scales of the states (as the hybrid shooting's) and of the works: the
 * excitation's work in a period at the tilt theta. */
static void set_scales(energy *e, double theta, double speed)
{
    const usm_model *m = e->m;
    for (int i = 0; i < MAXZ; ++i)
        e->scale[i] = 1.0;
    e->scale[m->x_theta] = theta;
    e->scale[m->x_phidot] = e->scale[m->x_psidot] = e->Omega;
    e->scale[m->x_thetadot] = e->Omega * theta;
    e->scale[m->x_tau] = e->p.m0 / e->p.c_t;
    if (m->x_phi_Rdot >= 0)
        e->scale[m->x_phi_Rdot] = fmax(fabs(speed), e->Omega * theta);
    e->scale[e->u->y_Z_R] = e->p.R * theta;
    e->scale[e->u->y_Z_Rdot] = e->p.R * theta * e->Omega;
    if (e->u->y_w_R >= 0)
        e->scale[e->u->y_w_R] = fmax(fabs(speed), e->Omega * theta);
    for (int i = 0; i < NW; ++i)
        e->scale[NY + i] = e->p.m0 * theta * e->Omega * e->T;
    e->v_land = 0.0;
}

int usm_squeal_energy(const usm_model *m, const usm_params *p, double t0, int open,
                      const double *y0, long periods, double rtol, usm_squeal_power *out,
                      char *msg)
{
    memset(out, 0, sizeof *out);
    msg[0] = '\0';
    if (!m->unilateral || m->x_tau < 0 || m->x_phi < 0) {
        snprintf(msg, USM_MSG_LEN, "model: %s has no contact that may open", m->name);
        return USM_EINPUT;
    }
    if (periods < 1 || !(rtol >= 1e-14 && rtol <= 1e-3)) {
        snprintf(msg, USM_MSG_LEN, periods < 1 ? "periods: must be at least 1"
                                               : "rtol: must be in [1e-14, 1e-3]");
        return USM_EINPUT;
    }
    energy e;
    memset(&e, 0, sizeof e);
    e.m = m;
    e.u = m->unilateral;
    e.p = *p;
    e.Omega = TWO_PI * p->f;
    e.T = 1.0 / p->f;
    usm_mode_kernels(m, 0, &e.k[0]);
    usm_mode_kernels(m, 1, &e.k[1]);
    e.mode = open ? 1 : 0;
    e.n = open ? e.u->ny : m->nx;
    const int iw = m->x_phi_Rdot >= 0 ? m->x_phi_Rdot : e.u->y_w_R;
    set_scales(&e, fabs(y0[m->x_theta]), iw >= 0 && (iw < m->nx || open) ? y0[iw] : 0.0);
    /* the simulation's landing threshold (usm_simulate.h "Unilateral contact") */
    e.v_land = sqrt(rtol) * p->R * fabs(y0[m->x_theta]) * e.Omega;
    double z[MAXZ] = {0};
    memcpy(z, y0, sizeof(double) * (size_t)e.n);
    const double t_end = t0 + (double)periods * e.T;
    const long steps = 5000 * periods + 100000;
    out->energy_start = usm_squeal_mechanical_energy(m, p, e.mode, z);
    double t = t0, jumps = 0.0;
    long events = 0;
    int rc = setup(&e, t, z, t_end, rtol, steps);
    while (rc == USM_OK && t < t_end) {
        e.cv.cvmsg[0] = '\0';
        const int flag = CVode(e.cv.mem, t_end, e.cv.y, &t, CV_NORMAL);
        if (flag < 0) {
            rc = usm_cvodes_fail(&e.cv, "CVode", flag);
            break;
        }
        const double *zz = N_VGetArrayPointer(e.cv.y);
        memcpy(z, zz, sizeof(double) * (size_t)e.n);
        memcpy(z + NY, zz + e.n, sizeof(double) * NW);
        if (flag != CV_ROOT_RETURN)
            break;
        if (++events > 4L * USM_HYBRID_MAX_SWITCHES * (periods + 1)) {
            snprintf(e.msg, USM_MSG_LEN, "more than %d contact switches a period (t = %.9g s)",
                     4 * USM_HYBRID_MAX_SWITCHES, t);
            rc = USM_EFAILED;
            break;
        }
        const double before = usm_squeal_mechanical_energy(m, p, e.mode, z);
        double yp[NY];
        int newmode = e.mode;
        if (e.mode == 0) { /* separation: the rotor leaves the crest */
            double sj[NY * (NY + 1)];
            e.u->separation(z, p, sj);
            memcpy(yp, sj + e.u->separation_out.y, sizeof(double) * (size_t)e.u->ny);
            newmode = 1;
            out->separations++;
        } else {
            usm_impact_outcome io;
            if (usm_impact_resolve(m, p, e.v_land, t, z, closed_Fn, &e, yp, NULL, &io) != 0) {
                snprintf(e.msg, USM_MSG_LEN, "the impact at t = %.9g s gave a state that is "
                         "not finite", t);
                rc = USM_EFAILED;
                break;
            }
            if (io.impact) {
                out->impacts++;
                newmode = !io.lands;
            }
        }
        e.mode = newmode;
        e.n = newmode ? e.u->ny : m->nx;
        memcpy(z, yp, sizeof(double) * (size_t)e.n);
        const double after = usm_squeal_mechanical_energy(m, p, e.mode, z);
        jumps += after - before;
        rc = setup(&e, t, z, t_end, rtol, steps);
    }
    usm_cvodes_free(&e.cv);
    if (rc != USM_OK) {
        snprintf(msg, USM_MSG_LEN, "%s", e.msg);
        return rc;
    }
    out->energy_end = usm_squeal_mechanical_energy(m, p, e.mode, z);
    const double dur = t - t0;
    out->periods = periods;
    out->duration = dur;
    out->excitation = z[NY + W_EXC] / dur;
    out->damping = z[NY + W_DAMP] / dur;
    out->load = z[NY + W_LOAD] / dur;
    out->friction = z[NY + W_FRIC] / dur;
    out->friction_stator = z[NY + W_FRIC_STATOR] / dur;
    out->friction_rotor = (z[NY + W_FRIC] - z[NY + W_FRIC_STATOR]) / dur;
    out->normal_stator = z[NY + W_NORMAL_STATOR] / dur;
    out->impacts_power = jumps / dur;
    const double sum = z[NY + W_EXC] + z[NY + W_DAMP] + z[NY + W_LOAD] + z[NY + W_FRIC] + jumps;
    const double turnover = fabs(z[NY + W_EXC]) + fabs(z[NY + W_DAMP]) + fabs(z[NY + W_LOAD]) +
                            fabs(z[NY + W_FRIC]) + fabs(jumps);
    out->balance_error = turnover > 0
                             ? fabs(out->energy_end - out->energy_start - sum) / turnover
                             : NAN;
    return USM_OK;
}
