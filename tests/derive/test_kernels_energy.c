/* test_kernels_energy: physics checks of the emitted dynamics M(x) x' = f(x, t) that
 * do not use the generator's derivation: every check below evaluates its
 * reference with its own z-x-z kinematics, written out here.  The trajectories
 * are integrated with CVODES (x' = M^-1 f by GSL LU).
 *
 * 1. Energy conservation, every model.  With no damping (d_R = d_r = d_t = 0),
 *    no excitation (m0 = 0), no load (T = 0), no twist spring (c_t = 0: the
 *    paper's twist torque c_t (phi + psi cos theta) e_Z is not conservative,
 *    because the rate of phi + psi cos theta is not omega_Z) and no friction
 *    (mu0 = 0, slip models), the mechanical energy
 *      E = 1/2 omega_K^T diag(I_xx, I_yy, I_zz) omega_K + 1/2 c_r theta^2
 *        + 1/2 M Zdot^2 + F0 Z + 1/2 c_R (Z - H)^2 + 1/2 I_R phidot_R^2
 *    is conserved (stick models: phidot_R = -v_c / R*).  Imperfect models run
 *    with mode_split s = 0.3: their tilt stiffness c_r (1 +- s) about the
 *    housing's X, Y adds 1/2 c_r s theta^2 cos(2 phi) to E.  Models that integrate
 *    the twist angle (state tau, tau' = omega_Z) keep c_t: their twist torque
 *    -c_t tau e_Z has power -c_t tau omega_Z = -d/dt (c_t tau^2 / 2), and
 *    E gains 1/2 c_t tau^2.  The normal force does no net work (the rotor and
 *    the stator's contact point share Zdot), and in stick neither does the
 *    tangential force.
 * 2. Friction work balance, slip models: as 1 but with mu0 > 0 and a rotor
 *    spinning the wrong way, E(t) + W(t) = E(0), W' = F_t v_rel with
 *    F_t = mu(v_rel) F_n (mu from the model's friction kernel: any law of
 *    derive/variants.py), v_rel = v_c + phidot_R R*, and F_n from
 *    the rotor's axial equation M Zddot = F_n - F0 - c_R (Z - H) - d_R Zdot.
 *    (W' >= 0 only while F_n > 0; at these tilts M Zddot swings F_n through
 *    +-1e3 N -- the model keeps contact by assumption -- so W oscillates.)
 * 3. Angular momentum balance, every model, full damped and excited motion
 *    with the paper's parameters: d/dt L_N = M_N in the inertial frame, with
 *      L_N = C_NK diag(I) omega_K,  C_NK = Rz(phi) Rx(theta) Rz(psi),
 *      M_N = M_E - M_R - M_D + r_c x F_c,
 *      M_E = m0 ((1 + e) cos Omega t, (1 - e) sin(Omega t + delta), 0)
 *            (e = amp_imbalance, delta = phase_error: 0.2, 0.3 in imperfect models),
 *      M_R = c_r theta e_x1 + c_t (phi + psi cos theta) e_Z   (or c_t tau e_Z),
 *      M_D = d_r omega_X e_X + d_r omega_Y e_Y + d_t omega_Z e_Z,
 *      r_c = R e_y2 + H e_z2,  F_c = -F_t e_x1 - F_n e_z1,
 *    F_n, F_t from the generated outputs kernel (with x' = M^-1 f).  dL_N/dt is
 *    taken (a) by a 5-point central difference of L_N along the integrated
 *    trajectory (points reached by CVODES steps), and (b) pointwise from x and
 *    x' as C_NK (I omegadot_K + omega_K x I omega_K) (Euler's equations, with
 *    omegadot_K differentiated by hand below).  This checks Euler's equations,
 *    the projection onto the Euler-angle rows, the excitation, restoring and
 *    damping torques, and the contact forces of the outputs kernel.
 *
 * Tolerances are stated where they are checked (ENERGY_TOL, MOMENTUM_FD_TOL,
 * MOMENTUM_PT_TOL).
 *
 * Models in the tilt-vector coordinates (a, b, chi, m->coordinates
 * = 1) are integrated in them; every check reads their states through the
 * Euler angles of the same motion, written out here (euler_view: theta =
 * asin |(a, b)|, phi = Omega t + atan2(a, -b), psi = chi - phi, the rates and
 * accelerations by the chain rule), so the same references apply.
 */
#define _POSIX_C_SOURCE 200809L

#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include <cvodes/cvodes.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_linalg.h>
#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include "usm.h"

#include "check.h"

static const double PI = 3.141592653589793238462643383279502884;

/* Integrator: relative tolerance for every run; absolute tolerances are
 * RTOL times a typical size of each state component. */
#define RTOL 1e-12

/* Energy: the drift of E is the integrator's global error, which grows with
 * the number of steps; it scales with RTOL (worst model, 4dof with
 * integrated twist and friction: 7.6e-7, 4.4e-8, 3.3e-9 for RTOL = 1e-10,
 * 1e-11, 1e-12), so it is integration error, not a non-conservative term in
 * the model.  ENERGY_TOL = 1e5 RTOL = 1e-7 leaves a factor 30 over the worst
 * measured case and still catches any non-conservative term: a torque error of
 * relative size 1e-6 does work of about that size every period (measured: c_t
 * = 1 N m/rad with the paper's twist law instead of 0 drifts by 0.5, tilt
 * damping 1e-4 of the paper's by 1e-3, a friction power 1 % off by 1e-2). */
#define ENERGY_TOL (1e5 * RTOL)
#define ENERGY_PERIODS 50
#define ENERGY_SAMPLES_PER_PERIOD 20

/* Angular momentum.  Scaled error |dL/dt - M_N| / (|dL/dt| + |M_E| + |M_R|
 * + |M_D| + |r_c x F_c|), i.e. relative to the largest torque in the balance.
 * (a) 5-point central difference with step h = T / MOMENTUM_FD_STEPS, the
 *     points reached by actual steps (stop times): truncation (omega h)^4 / 30
 *     for the fastest motion (the twist mode at sqrt(c_t / I_zz) = 2.8 Omega:
 *     4e-11 for h = T/3000) plus the integration error amplified by
 *     1/(Omega h): L_z holds I_zz (phidot cos theta + psidot), a difference of
 *     two rates of size Omega each known to RTOL, so ~RTOL / (Omega h) = 5e-10;
 *     measured 8e-10 (1.4e-9 with RTOL = 1e-11; up to 5e-7 when the points
 *     were interpolated instead).  MOMENTUM_FD_TOL = 1e-7.
 * (b) pointwise from x and x' = M^-1 f: only rounding in the torques and in
 *     the LU solve of M, whose condition number grows like 1/theta^2 (1e6 at
 *     theta = 1e-3, so up to ~1e6 eps = 2e-10); measured 1e-14.
 *     MOMENTUM_PT_TOL = 1e-9.
 * The contact moment and the excitation are small parts of the balance
 * (|r_c x F_c| ~ 6e-3 N m, m0 = 5e-3 N m against c_r theta ~ 2 .. 10 N m), but
 * well above both tolerances: measured, F_t with the wrong sign gives 1e-2,
 * F_t 1 % too large 5e-5, the excitation with the wrong sign 1e-3, and the
 * misparenthesised F_t = T R*^3 of an earlier generator 6e-3. */
#define MOMENTUM_FD_TOL 1e-7
#define MOMENTUM_PT_TOL 1e-9
#define MOMENTUM_PERIODS 10
#define MOMENTUM_SAMPLES 100
#define MOMENTUM_FD_STEPS 3000

/* ---- SUNDIALS-style return checks ------------------------------------------ */

/* opt 0: function returned a pointer, NULL is an error;
 * opt 1: function returned an int flag, < 0 is an error. */
static int check_retval(const void *returnvalue, const char *funcname, int opt)
{
    if (opt == 0 && returnvalue == NULL) {
        fprintf(stderr, "FAIL: SUNDIALS/GSL error: %s() failed - returned NULL pointer\n",
                funcname);
        return 1;
    }
    if (opt == 1) {
        const int *retval = (const int *)returnvalue;
        if (*retval < 0) {
            fprintf(stderr, "FAIL: SUNDIALS error: %s() failed with retval = %d\n", funcname,
                    *retval);
            return 1;
        }
    }
    return 0;
}

/* ---- small 3-vector / 3x3 helpers ----------------------------------------------- */

typedef struct { double v[3]; } vec3;
typedef struct { double a[3][3]; } mat3;

static vec3 v3(double x, double y, double z)
{
    vec3 r = {{x, y, z}};
    return r;
}

static vec3 vadd(vec3 a, vec3 b)
{
    return v3(a.v[0] + b.v[0], a.v[1] + b.v[1], a.v[2] + b.v[2]);
}

static vec3 vsub(vec3 a, vec3 b)
{
    return v3(a.v[0] - b.v[0], a.v[1] - b.v[1], a.v[2] - b.v[2]);
}

static vec3 vscale(double s, vec3 a)
{
    return v3(s * a.v[0], s * a.v[1], s * a.v[2]);
}

static vec3 vcross(vec3 a, vec3 b)
{
    return v3(a.v[1] * b.v[2] - a.v[2] * b.v[1], a.v[2] * b.v[0] - a.v[0] * b.v[2],
              a.v[0] * b.v[1] - a.v[1] * b.v[0]);
}

static double vnorm(vec3 a)
{
    return sqrt(a.v[0] * a.v[0] + a.v[1] * a.v[1] + a.v[2] * a.v[2]);
}

static mat3 rot_z(double a)
{
    double c = cos(a), s = sin(a);
    mat3 r = {{{c, -s, 0.0}, {s, c, 0.0}, {0.0, 0.0, 1.0}}};
    return r;
}

static mat3 rot_x(double a)
{
    double c = cos(a), s = sin(a);
    mat3 r = {{{1.0, 0.0, 0.0}, {0.0, c, -s}, {0.0, s, c}}};
    return r;
}

static mat3 mmul(mat3 A, mat3 B)
{
    mat3 r;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            r.a[i][j] = A.a[i][0] * B.a[0][j] + A.a[i][1] * B.a[1][j] + A.a[i][2] * B.a[2][j];
    return r;
}

static vec3 mvec(mat3 A, vec3 x)
{
    vec3 r;
    for (int i = 0; i < 3; ++i)
        r.v[i] = A.a[i][0] * x.v[0] + A.a[i][1] * x.v[1] + A.a[i][2] * x.v[2];
    return r;
}

/* ---- the test's own kinematics ---------------------------------------------------- */

/* Where the Euler angles, their rates and the rotor sit in a model's state
 * (the generated indices of the model descriptor). */
typedef struct layout {
    int phi, theta, psi, phidot, thetadot, psidot;
    int phi_R, phi_Rdot; /* -1 in stick models */
    int tau;             /* integrated twist angle, tau' = omega_Z; -1 if the
                            twist angle is the paper's phi + psi cos theta */
    const usm_model *m;  /* its friction kernel: the law mu(v_rel) it assumes */
} layout;

static int make_layout(const usm_model *m, layout *L)
{
    L->phi = m->x_phi;
    L->theta = m->x_theta;
    L->psi = m->x_psi;
    L->phidot = m->x_phidot;
    L->thetadot = m->x_thetadot;
    L->psidot = m->x_psidot;
    L->phi_R = m->x_phi_R;
    L->phi_Rdot = m->x_phi_Rdot;
    L->tau = m->x_tau;
    L->m = m;
    if (L->phi_Rdot >= 0 && !m->friction) {
        fprintf(stderr, "FAIL: model %s: slip model without a friction kernel\n", m->name);
        return 1;
    }
    if (L->phi < 0 || L->theta < 0 || L->psi < 0 || L->phidot < 0 || L->thetadot < 0 ||
        L->psidot < 0 || (L->phi_R < 0) != (L->phi_Rdot < 0)) {
        fprintf(stderr, "FAIL: model %s: state layout not understood by this test\n", m->name);
        return 1;
    }
    return 0;
}

/* Body-frame angular velocity of the z-x-z Euler angles. */
static vec3 omega_K(double th, double ps, double phd, double thd, double psd)
{
    return v3(phd * sin(th) * sin(ps) + thd * cos(ps), phd * sin(th) * cos(ps) - thd * sin(ps),
              phd * cos(th) + psd);
}

/* Its time derivative, given the angle accelerations. */
static vec3 omega_K_dot(double th, double ps, double phd, double thd, double psd, double phdd,
                        double thdd, double psdd)
{
    double st = sin(th), ct = cos(th), sp = sin(ps), cp = cos(ps);
    return v3(phdd * st * sp + phd * thd * ct * sp + phd * st * cp * psd + thdd * cp - thd * sp * psd,
              phdd * st * cp + phd * thd * ct * cp - phd * st * sp * psd - thdd * sp - thd * cp * psd,
              phdd * ct - phd * thd * st + psdd);
}

static mat3 C_NK(double ph, double th, double ps)
{
    return mmul(mmul(rot_z(ph), rot_x(th)), rot_z(ps));
}

typedef struct contact {
    double R_star, Z, Zdot, v_c;
} contact;

/* Contact point r_c = R e_y2 + H e_z2 = (0, R*, Z) in frame A, its height rate
 * and the stator's material speed along e_x1, v_c = (omega_A x r_c_A)_x with
 * omega_A = (thetadot, -psidot sin theta, phidot + psidot cos theta). */
static contact contact_of(const layout *L, const double *x, const usm_params *p)
{
    contact c;
    double th = x[L->theta], st = sin(th), ct = cos(th);
    c.R_star = p->R * ct - p->H * st;
    c.Z = p->R * st + p->H * ct;
    c.Zdot = x[L->thetadot] * c.R_star;
    vec3 wA = v3(x[L->thetadot], -x[L->psidot] * st, x[L->phidot] + x[L->psidot] * ct);
    vec3 rA = v3(0.0, c.R_star, c.Z);
    c.v_c = vcross(wA, rA).v[0];
    return c;
}

static double rotor_speed(const layout *L, const double *x, const contact *c)
{
    return L->phi_Rdot >= 0 ? x[L->phi_Rdot] : -c->v_c / c->R_star;
}

static double energy(const layout *L, const double *x, const usm_params *p)
{
    vec3 w = omega_K(x[L->theta], x[L->psi], x[L->phidot], x[L->thetadot], x[L->psidot]);
    contact c = contact_of(L, x, p);
    double wR = rotor_speed(L, x, &c);
    double th = x[L->theta];
    return 0.5 * (p->I_xx * w.v[0] * w.v[0] + p->I_yy * w.v[1] * w.v[1] + p->I_zz * w.v[2] * w.v[2]) +
           0.5 * p->c_r * th * th + 0.5 * p->M * c.Zdot * c.Zdot + p->F0 * c.Z +
           0.5 * p->c_R * (c.Z - p->H) * (c.Z - p->H) + 0.5 * p->I_R * wR * wR +
           (L->tau >= 0 ? 0.5 * p->c_t * x[L->tau] * x[L->tau] : 0.0) +
           /* mode split (imperfect models): c_r (1 + s) about X, c_r (1 - s)
            * about Y on the housing-frame tilt vector theta (cos phi, sin phi) */
           0.5 * p->c_r * p->mode_split * th * th * cos(2.0 * x[L->phi]);
}

/* The friction law mu(v_rel) the model assumes, whatever it is: the model's
 * generated friction kernel (derive/variants.py, FRICTION_LAWS), the law being
 * an input of the model, not something derived.  Checked against its
 * derivative in test_kernels_jacobians. */
static double friction_mu(const layout *L, const usm_params *p, double v_rel)
{
    double mu[2];
    L->m->friction(v_rel, p, mu);
    return mu[0];
}

/* Normal force from the rotor's axial equation (2.1), spring measured from H. */
static double normal_force(const layout *L, const double *x, const double *xdot,
                           const usm_params *p)
{
    contact c = contact_of(L, x, p);
    double thd = x[L->thetadot], thdd = xdot[L->thetadot];
    double Zddot = thdd * c.R_star - thd * thd * c.Z;
    return p->M * Zddot + p->F0 + p->c_R * (c.Z - p->H) + p->d_R * c.Zdot;
}

/* ---- the ODE ------------------------------------------------------------------------ */

typedef struct ode {
    const usm_model *m;
    usm_params p;
    layout L;
    int n;        /* model states */
    int tilt;     /* 1: the model's state is the tilt vector (a, b, chi), L the
                     Euler angles of its counterpart (euler_view) */
    int work;     /* 1: one more state, the friction work W, W' = F_t v_rel */
    double M[USM_MAX_NX * USM_MAX_NX], f[USM_MAX_NX];
    gsl_permutation *perm;
    long nrhs;
    int lu_failed;
} ode;

/* x' = M(x)^-1 f(x, t); 0 or -1 (singular M). */
static int solve_xdot(ode *d, const double *x, double t, double *xdot)
{
    int n = d->n, signum;
    d->m->mass(x, &d->p, d->M);
    d->m->rhs(x, t, &d->p, d->f);
    gsl_matrix_view Mv = gsl_matrix_view_array(d->M, (size_t)n, (size_t)n);
    gsl_vector_view fv = gsl_vector_view_array(d->f, (size_t)n);
    gsl_vector_view xv = gsl_vector_view_array(xdot, (size_t)n);
    if (gsl_linalg_LU_decomp(&Mv.matrix, d->perm, &signum) != GSL_SUCCESS ||
        gsl_linalg_LU_solve(&Mv.matrix, d->perm, &fv.vector, &xv.vector) != GSL_SUCCESS) {
        d->lu_failed = 1;
        return -1;
    }
    for (int i = 0; i < n; ++i)
        if (!isfinite(xdot[i])) {
            d->lu_failed = 1;
            return -1;
        }
    return 0;
}

/* The state x (and x', if given) of a tilt-vector model as the Euler angles of
 * the same motion at time t, in the layout L (a copy for Euler-angle models).
 * a + i b = sin(theta) exp(i (phi - Omega t - pi/2)), chi = phi + psi. */
static void euler_view(const ode *d, const double *x, const double *xd, double t, double *xe,
                       double *xde)
{
    const int n = d->n;
    memcpy(xe, x, sizeof(double) * (size_t)n);
    if (xd)
        memcpy(xde, xd, sizeof(double) * (size_t)n);
    if (!d->tilt)
        return;
    const usm_model *m = d->m;
    const layout *L = &d->L;
    const double W = 2.0 * PI * d->p.f;
    const double a = x[m->x_a], b = x[m->x_b], ad = x[m->x_adot], bd = x[m->x_bdot];
    const double s2 = a * a + b * b, s = sqrt(s2), c = sqrt(1.0 - s2);
    const double pr = a * ad + b * bd, sd = pr / s, q = a * bd - b * ad;
    const double ph = W * t + atan2(a, -b), phd = W + q / s2;
    const double th = atan2(s, c), thd = sd / c;
    xe[L->phi] = ph;
    xe[L->theta] = th;
    xe[L->psi] = x[m->x_chi] - ph;
    xe[L->phidot] = phd;
    xe[L->thetadot] = thd;
    xe[L->psidot] = x[m->x_chidot] - phd;
    if (!xd)
        return;
    const double add = xd[m->x_adot], bdd = xd[m->x_bdot];
    const double prd = ad * ad + bd * bd + a * add + b * bdd, sdd = (prd - sd * sd) / s;
    const double qd = a * bdd - b * add, phdd = (qd * s2 - 2.0 * q * pr) / (s2 * s2);
    xde[L->phi] = phd;
    xde[L->theta] = thd;
    xde[L->psi] = x[m->x_chidot] - phd;
    xde[L->phidot] = phdd;
    xde[L->thetadot] = sdd / c + s * sd * sd / (c * c * c);
    xde[L->psidot] = xd[m->x_chidot] - phdd;
}

/* The inverse for a start state given in Euler angles: x in place. */
static void from_euler(const ode *d, double *x, double t)
{
    if (!d->tilt)
        return;
    const usm_model *m = d->m;
    const layout *L = &d->L;
    const double W = 2.0 * PI * d->p.f;
    const double ph = x[L->phi], th = x[L->theta], ps = x[L->psi], phd = x[L->phidot],
                 thd = x[L->thetadot], psd = x[L->psidot];
    const double al = ph - W * t;
    x[m->x_a] = sin(th) * sin(al);
    x[m->x_b] = -sin(th) * cos(al);
    x[m->x_chi] = ph + ps;
    x[m->x_adot] = cos(th) * thd * sin(al) + sin(th) * cos(al) * (phd - W);
    x[m->x_bdot] = -cos(th) * thd * cos(al) + sin(th) * sin(al) * (phd - W);
    x[m->x_chidot] = phd + psd;
}

static int ode_rhs(sunrealtype t, N_Vector y, N_Vector ydot, void *user_data)
{
    ode *d = user_data;
    const double *x = N_VGetArrayPointer(y);
    double *xd = N_VGetArrayPointer(ydot);
    d->nrhs++;
    if (solve_xdot(d, x, t, xd))
        return -1;
    if (d->work) {
        double xe[USM_MAX_NX], xde[USM_MAX_NX];
        euler_view(d, x, xd, t, xe, xde);
        contact c = contact_of(&d->L, xe, &d->p);
        double v_rel = c.v_c + xe[d->L.phi_Rdot] * c.R_star;
        double F_t = friction_mu(&d->L, &d->p, v_rel) * normal_force(&d->L, xe, xde, &d->p);
        xd[d->n] = F_t * v_rel;
    }
    return 0;
}

typedef struct integrator {
    SUNContext ctx;
    N_Vector y, atol;
    SUNMatrix A;
    SUNLinearSolver LS;
    void *mem;
} integrator;

static void integrator_free(integrator *in)
{
    if (in->mem)
        CVodeFree(&in->mem);
    if (in->LS)
        SUNLinSolFree(in->LS);
    if (in->A)
        SUNMatDestroy(in->A);
    if (in->y)
        N_VDestroy(in->y);
    if (in->atol)
        N_VDestroy(in->atol);
    if (in->ctx)
        SUNContext_Free(&in->ctx);
}

/* Set up CVODES (Adams-Moulton, Newton with a dense difference-quotient
 * Jacobian) for d from state y0 (length n + work) at t0. */
static int integrator_init(integrator *in, ode *d, const double *y0, double t0)
{
    memset(in, 0, sizeof *in);
    const int N = d->n + d->work;
    const double W = 2.0 * PI * d->p.f;
    int retval = SUNContext_Create(NULL, &in->ctx);
    if (check_retval(&retval, "SUNContext_Create", 1))
        return 1;
    in->y = N_VNew_Serial(N, in->ctx);
    if (check_retval(in->y, "N_VNew_Serial", 0))
        return 1;
    in->atol = N_VNew_Serial(N, in->ctx);
    if (check_retval(in->atol, "N_VNew_Serial", 0))
        return 1;
    double *y = N_VGetArrayPointer(in->y), *at = N_VGetArrayPointer(in->atol);
    memcpy(y, y0, (size_t)N * sizeof *y);
    /* typical sizes: angles 1 rad, theta 0.01 rad, rates Omega (tilt rate
     * 0.01 Omega), rotor speed 10 1/s, work 1e-3 J */
    const layout *L = &d->L;
    for (int i = 0; i < N; ++i)
        at[i] = RTOL;
    at[L->theta] = RTOL * 1e-2;
    at[L->phidot] = at[L->psidot] = RTOL * W;
    if (d->tilt) { /* a, b: the tilt; their rates: the tilt rate; chidot as phidot */
        at[d->m->x_a] = at[d->m->x_b] = RTOL * 1e-2;
        at[d->m->x_adot] = at[d->m->x_bdot] = RTOL * 1e-2 * W;
        at[d->m->x_chi] = RTOL;
        at[d->m->x_chidot] = RTOL * W;
    }
    at[L->thetadot] = RTOL * 1e-2 * W;
    if (L->phi_Rdot >= 0)
        at[L->phi_Rdot] = RTOL * 10.0;
    if (L->tau >= 0)
        at[L->tau] = RTOL * 1e-4;
    if (d->work)
        at[d->n] = RTOL * 1e-3;

    in->mem = CVodeCreate(CV_ADAMS, in->ctx);
    if (check_retval(in->mem, "CVodeCreate", 0))
        return 1;
    retval = CVodeInit(in->mem, ode_rhs, t0, in->y);
    if (check_retval(&retval, "CVodeInit", 1))
        return 1;
    retval = CVodeSVtolerances(in->mem, RTOL, in->atol);
    if (check_retval(&retval, "CVodeSVtolerances", 1))
        return 1;
    retval = CVodeSetUserData(in->mem, d);
    if (check_retval(&retval, "CVodeSetUserData", 1))
        return 1;
    retval = CVodeSetMaxNumSteps(in->mem, 2000000);
    if (check_retval(&retval, "CVodeSetMaxNumSteps", 1))
        return 1;
    in->A = SUNDenseMatrix(N, N, in->ctx);
    if (check_retval(in->A, "SUNDenseMatrix", 0))
        return 1;
    in->LS = SUNLinSol_Dense(in->y, in->A, in->ctx);
    if (check_retval(in->LS, "SUNLinSol_Dense", 0))
        return 1;
    retval = CVodeSetLinearSolver(in->mem, in->LS, in->A);
    if (check_retval(&retval, "CVodeSetLinearSolver", 1))
        return 1;
    return 0;
}

/* Advance to tout; state copied to x.  land = 0: CV_NORMAL, i.e. dense output
 * interpolated at tout; land = 1: a stop time at tout, so that x is the end of
 * an actual step (the Adams interpolant between steps is less smooth than
 * the steps themselves: differencing it at T/3000 gave errors up to 5e-7). */
static int integrator_to(integrator *in, double tout, double *x, int N, int land)
{
    sunrealtype t;
    int retval;
    if (land) {
        retval = CVodeSetStopTime(in->mem, tout);
        if (check_retval(&retval, "CVodeSetStopTime", 1))
            return 1;
    }
    retval = CVode(in->mem, tout, in->y, &t, CV_NORMAL);
    if (check_retval(&retval, "CVode", 1))
        return 1;
    memcpy(x, N_VGetArrayPointer(in->y), (size_t)N * sizeof *x);
    return 0;
}

static long integrator_steps(integrator *in)
{
    long nst = 0;
    int retval = CVodeGetNumSteps(in->mem, &nst);
    if (check_retval(&retval, "CVodeGetNumSteps", 1))
        return -1;
    return nst;
}

static int ode_init(ode *d, const usm_model *m, const usm_params *p, int work)
{
    memset(d, 0, sizeof *d);
    d->m = m;
    d->p = *p;
    d->n = m->nx;
    d->work = work;
    d->tilt = m->coordinates == 1;
    if (make_layout(d->tilt ? m->other_coordinates : m, &d->L))
        return 1;
    d->L.m = m;
    d->perm = gsl_permutation_alloc((size_t)m->nx);
    if (check_retval(d->perm, "gsl_permutation_alloc", 0))
        return 1;
    return 0;
}

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* A tilted, spinning start away from theta = 0, where the Euler angles are
 * singular: theta = 0.03, a tilt rate, phi and psi rates near the stationary
 * +Omega / -Omega (so the stator wobbles at the excitation frequency). */
static void start_state(const ode *d, double *x, double rotor)
{
    const double W = 2.0 * PI * d->p.f;
    const layout *L = &d->L;
    memset(x, 0, (size_t)(d->n + d->work) * sizeof *x);
    x[L->phi] = 0.4;
    x[L->theta] = 0.03;
    x[L->psi] = -0.7;
    x[L->phidot] = 1.02 * W;
    x[L->thetadot] = 0.1 * W * 0.03;
    x[L->psidot] = -0.99 * W;
    if (L->phi_Rdot >= 0) {
        x[L->phi_R] = 0.0;
        x[L->phi_Rdot] = rotor;
    }
    if (L->tau >= 0)
        x[L->tau] = 1e-4; /* c_t tau = 1 N m */
}

/* ---- 1 and 2: energy ----------------------------------------------------------------- */

static int energy_run(const usm_model *m, int friction)
{
    usm_params p;
    usm_params_default(&p);
    p.d_R = p.d_r = p.d_t = 0.0;
    p.m0 = 0.0;
    p.T = 0.0;
    if (m->x_tau < 0)
        p.c_t = 0.0; /* the paper's twist torque is not conservative */
    if (!friction)
        p.mu0 = 0.0;
    if (m->imperfect)
        p.mode_split = 0.3; /* conservative: E gains its potential (energy()) */
    ode d;
    integrator in;
    if (ode_init(&d, m, &p, friction))
        return 1;
    double x[USM_MAX_NX + 1];
    /* with friction: the rotor turns at +1000 1/s against the contact point's
     * drive (-11 1/s at the stationary orbit), so slip does work */
    start_state(&d, x, friction ? 1000.0 : -11.0);
    from_euler(&d, x, 0.0);
    const int N = d.n + d.work;
    double xe[USM_MAX_NX];
    double t0 = now();
    if (integrator_init(&in, &d, x, 0.0)) {
        integrator_free(&in);
        gsl_permutation_free(d.perm);
        return 1;
    }
    euler_view(&d, x, NULL, 0.0, xe, NULL);
    const double E0 = energy(&d.L, xe, &p), T = 1.0 / p.f;
    double worst = 0.0, th_min = INFINITY, th_max = 0.0, t_worst = 0.0, W_max = 0.0;
    int fail = 0;
    const int nout = ENERGY_PERIODS * ENERGY_SAMPLES_PER_PERIOD;
    for (int k = 1; k <= nout && !fail; ++k) {
        double t = T * (double)k / ENERGY_SAMPLES_PER_PERIOD;
        if (integrator_to(&in, t, x, N, 0)) {
            fail = 1;
            break;
        }
        double Wk = friction ? x[d.n] : 0.0;
        euler_view(&d, x, NULL, t, xe, NULL);
        double e = fabs(energy(&d.L, xe, &p) + Wk - E0) / E0;
        if (e > worst) {
            worst = e;
            t_worst = t;
        }
        th_min = fmin(th_min, xe[d.L.theta]);
        th_max = fmax(th_max, xe[d.L.theta]);
        W_max = fmax(W_max, fabs(Wk));
    }
    long nst = integrator_steps(&in);
    double secs = now() - t0;
    integrator_free(&in);
    gsl_permutation_free(d.perm);
    if (fail || d.lu_failed) {
        fprintf(stderr, "FAIL: model %s: integration failed%s\n", m->name,
                d.lu_failed ? " (singular mass matrix)" : "");
        return 1;
    }
    printf("%-22s %-22s E0 %.6e J  max|E+W-E0|/E0 %.3e at t = %.3e s  (tol %.0e)  "
           "theta in [%.4f, %.4f]  %ld steps  %.2f s\n",
           m->name, friction ? "energy + friction work" : "energy", E0, worst, t_worst,
           ENERGY_TOL, th_min, th_max, nst, secs);
    if (friction)
        printf("      friction work max|W| = %.6e J = %.3e E0 (the balance is non-trivial)\n", W_max,
               W_max / E0);
    if (th_min < 1e-3) {
        fprintf(stderr, "FAIL: model %s: the test's trajectory came within %.2e of theta = 0\n",
                m->name, th_min);
        return 1;
    }
    if (friction && !(W_max > 1e3 * ENERGY_TOL * E0)) {
        fprintf(stderr, "FAIL: model %s: friction did too little work (%.3e J) to test the balance\n",
                m->name, W_max);
        return 1;
    }
    if (!(worst <= ENERGY_TOL)) {
        fprintf(stderr,
                "FAIL: model %s: %s not conserved: relative drift %.3e > %.0e (worst at t = %.6e s)\n",
                m->name, friction ? "E + friction work" : "energy", worst, ENERGY_TOL, t_worst);
        return 1;
    }
    return 0;
}

/* ---- 3: angular momentum ------------------------------------------------------------ */

static vec3 L_N(const usm_params *p, const layout *L, const double *x)
{
    vec3 w = omega_K(x[L->theta], x[L->psi], x[L->phidot], x[L->thetadot], x[L->psidot]);
    vec3 Lk = v3(p->I_xx * w.v[0], p->I_yy * w.v[1], p->I_zz * w.v[2]);
    return mvec(C_NK(x[L->phi], x[L->theta], x[L->psi]), Lk);
}

typedef struct torques {
    vec3 E, R, D, C, total;
} torques;

/* x: the Euler angles (euler_view); xm, xmdot: the model's own state and rate */
static torques M_N(const usm_model *m, const usm_params *p, const layout *L, const double *x,
                   const double *xm, const double *xmdot, double t)
{
    torques q;
    const double W = 2.0 * PI * p->f;
    double ph = x[L->phi], th = x[L->theta], ps = x[L->psi];
    mat3 C = C_NK(ph, th, ps), CA = rot_z(ph);
    vec3 wN = mvec(C, omega_K(th, ps, x[L->phidot], x[L->thetadot], x[L->psidot]));
    vec3 e_x1 = mvec(CA, v3(1.0, 0.0, 0.0)), e_Z = v3(0.0, 0.0, 1.0);
    /* a real driver (imperfect models; e = delta = 0 otherwise) */
    q.E = v3(p->m0 * (1.0 + p->amp_imbalance) * cos(W * t),
             p->m0 * (1.0 - p->amp_imbalance) * sin(W * t + p->phase_error), 0.0);
    double twist = L->tau >= 0 ? x[L->tau] : ph + ps * cos(th);
    q.R = vadd(vscale(p->c_r * th, e_x1), vscale(p->c_t * twist, e_Z));
    q.D = v3(p->d_r * wN.v[0], p->d_r * wN.v[1], p->d_t * wN.v[2]);
    double out[USM_OUT_COUNT];
    m->outputs(xm, xmdot, t, p, out);
    vec3 rc = mvec(mmul(CA, rot_x(th)), v3(0.0, p->R, p->H)); /* R e_y2 + H e_z2 */
    vec3 Fc = mvec(CA, v3(-out[USM_OUT_F_T], 0.0, -out[USM_OUT_F_N]));
    q.C = vcross(rc, Fc);
    q.total = vadd(vsub(vsub(q.E, q.R), q.D), q.C);
    return q;
}

/* dL_N/dt from x and x' (Euler): C_NK (I omegadot_K + omega_K x I omega_K). */
static vec3 L_N_dot(const usm_params *p, const layout *L, const double *x, const double *xdot)
{
    double th = x[L->theta], ps = x[L->psi];
    vec3 w = omega_K(th, ps, x[L->phidot], x[L->thetadot], x[L->psidot]);
    vec3 wd = omega_K_dot(th, ps, x[L->phidot], x[L->thetadot], x[L->psidot], xdot[L->phidot],
                          xdot[L->thetadot], xdot[L->psidot]);
    vec3 Iw = v3(p->I_xx * w.v[0], p->I_yy * w.v[1], p->I_zz * w.v[2]);
    vec3 Iwd = v3(p->I_xx * wd.v[0], p->I_yy * wd.v[1], p->I_zz * wd.v[2]);
    return mvec(C_NK(x[L->phi], th, ps), vadd(Iwd, vcross(w, Iw)));
}

static double torque_scale(vec3 dL, const torques *q)
{
    return vnorm(dL) + vnorm(q->E) + vnorm(q->R) + vnorm(q->D) + vnorm(q->C);
}

static int momentum_run(const usm_model *m)
{
    usm_params p;
    usm_params_default(&p);
    if (m->imperfect) {
        p.amp_imbalance = 0.2;
        p.phase_error = 0.3;
    }
    ode d;
    integrator in;
    if (ode_init(&d, m, &p, 0))
        return 1;
    const double W = 2.0 * PI * p.f, T = 1.0 / p.f, th0 = 0.005;
    double x[USM_MAX_NX], xdot[USM_MAX_NX];
    const layout *L = &d.L;
    /* Near the stationary orbit (alpha = 5.1256, beta = -alpha + T/c_t, the
     * paper's values) but tilted 60 times more, so the wobble, the twist
     * oscillation and the decay of both are all in the balance. */
    memset(x, 0, sizeof x);
    x[L->phi] = 5.1256;
    x[L->theta] = th0;
    x[L->psi] = -5.1256 + p.T / p.c_t;
    x[L->phidot] = W;
    x[L->thetadot] = 0.0;
    x[L->psidot] = -W / cos(th0);
    if (L->phi_Rdot >= 0)
        x[L->phi_Rdot] = -11.0;
    if (L->tau >= 0)
        x[L->tau] = p.T / p.c_t;
    from_euler(&d, x, 0.0);
    double t0 = now();
    if (integrator_init(&in, &d, x, 0.0)) {
        integrator_free(&in);
        gsl_permutation_free(d.perm);
        return 1;
    }
    const double h = T / MOMENTUM_FD_STEPS;
    double worst_fd = 0.0, worst_pt = 0.0, t_fd = 0.0, t_pt = 0.0, scale_min = INFINITY,
           scale_max = 0.0, th_min = INFINITY, th_max = 0.0;
    vec3 worst_C = v3(0, 0, 0), worst_E = v3(0, 0, 0);
    int fail = 0;
    for (int k = 0; k < MOMENTUM_SAMPLES && !fail; ++k) {
        double tk = MOMENTUM_PERIODS * T * ((double)k + 0.5) / MOMENTUM_SAMPLES;
        static const int offs[5] = {-2, -1, 0, 1, 2};
        vec3 Ls[5];
        double xk[USM_MAX_NX];
        for (int s = 0; s < 5; ++s) {
            double xs[USM_MAX_NX];
            if (integrator_to(&in, tk + offs[s] * h, xs, d.n, 1)) {
                fail = 1;
                break;
            }
            double xse[USM_MAX_NX];
            euler_view(&d, xs, NULL, tk + offs[s] * h, xse, NULL);
            Ls[s] = L_N(&p, L, xse);
            if (offs[s] == 0)
                memcpy(xk, xs, sizeof xk);
        }
        if (fail)
            break;
        if (solve_xdot(&d, xk, tk, xdot)) {
            fail = 1;
            break;
        }
        /* (a) 5-point central difference along the trajectory */
        vec3 dL_fd = vscale(1.0 / (12.0 * h),
                            vadd(vsub(Ls[0], vscale(8.0, Ls[1])), vsub(vscale(8.0, Ls[3]), Ls[4])));
        /* (b) pointwise, Euler's equations with x' = M^-1 f */
        double xe[USM_MAX_NX], xde[USM_MAX_NX];
        euler_view(&d, xk, xdot, tk, xe, xde);
        vec3 dL_pt = L_N_dot(&p, L, xe, xde);
        torques q = M_N(m, &p, L, xe, xk, xdot, tk);
        double sc = torque_scale(dL_pt, &q);
        double e_fd = vnorm(vsub(dL_fd, q.total)) / sc;
        double e_pt = vnorm(vsub(dL_pt, q.total)) / sc;
        scale_min = fmin(scale_min, sc);
        scale_max = fmax(scale_max, sc);
        th_min = fmin(th_min, xe[L->theta]);
        th_max = fmax(th_max, xe[L->theta]);
        if (e_fd > worst_fd) {
            worst_fd = e_fd;
            t_fd = tk;
        }
        if (e_pt > worst_pt) {
            worst_pt = e_pt;
            t_pt = tk;
            worst_C = q.C;
            worst_E = q.E;
        }
        if (!(e_fd <= MOMENTUM_FD_TOL) || !(e_pt <= MOMENTUM_PT_TOL)) {
            fprintf(stderr,
                    "FAIL: model %s: dL_N/dt != M_N at t = %.9e s: scaled error %.3e "
                    "(difference of the trajectory, tol %.0e), %.3e (pointwise, tol %.0e)\n"
                    "      dL/dt (difference) = (%.9e, %.9e, %.9e)\n"
                    "      dL/dt (pointwise)  = (%.9e, %.9e, %.9e)\n"
                    "      M_N                = (%.9e, %.9e, %.9e)\n"
                    "      M_E (%.3e, %.3e, %.3e) M_R (%.3e, %.3e, %.3e) M_D (%.3e, %.3e, %.3e) "
                    "r_c x F_c (%.3e, %.3e, %.3e)\n",
                    m->name, tk, e_fd, MOMENTUM_FD_TOL, e_pt, MOMENTUM_PT_TOL, dL_fd.v[0],
                    dL_fd.v[1], dL_fd.v[2], dL_pt.v[0], dL_pt.v[1], dL_pt.v[2], q.total.v[0],
                    q.total.v[1], q.total.v[2], q.E.v[0], q.E.v[1], q.E.v[2], q.R.v[0], q.R.v[1],
                    q.R.v[2], q.D.v[0], q.D.v[1], q.D.v[2], q.C.v[0], q.C.v[1], q.C.v[2]);
            fprintf(stderr, "      state:");
            for (int i = 0; i < d.n; ++i)
                fprintf(stderr, " %s=%.17g", m->state_names[i], xk[i]);
            fprintf(stderr, "\n");
            fail = 1;
        }
    }
    long nst = integrator_steps(&in);
    double secs = now() - t0;
    integrator_free(&in);
    gsl_permutation_free(d.perm);
    if (d.lu_failed)
        fprintf(stderr, "FAIL: model %s: singular mass matrix\n", m->name);
    printf("%-22s %-22s max scaled |dL/dt - M_N|: %.3e by differences of the trajectory "
           "(tol %.0e, at t = %.3e s), %.3e pointwise (tol %.0e, at t = %.3e s)\n"
           "      torque scale %.3e .. %.3e N m, |r_c x F_c| %.3e, |M_E| %.3e; theta in "
           "[%.5f, %.5f]; %ld steps  %.2f s\n",
           m->name, "angular momentum", worst_fd, MOMENTUM_FD_TOL, t_fd, worst_pt, MOMENTUM_PT_TOL,
           t_pt, scale_min, scale_max, vnorm(worst_C), vnorm(worst_E), th_min, th_max, nst, secs);
    return fail || d.lu_failed;
}

/* Usage: test_kernels_energy [energy|momentum]  (default: both) */
int main(int argc, char **argv)
{
    int do_energy = 1, do_momentum = 1;
    if (argc > 1) {
        do_energy = strcmp(argv[1], "energy") == 0;
        do_momentum = strcmp(argv[1], "momentum") == 0;
        if (argc > 2 || (!do_energy && !do_momentum)) {
            fprintf(stderr, "usage: %s [energy|momentum]\n", argv[0]);
            return 2;
        }
    }
    gsl_set_error_handler_off();
    for (int i = 0; i < USM_NMODELS; ++i) {
        const usm_model *m = usm_models[i];
        if (do_energy) {
            CHECK(energy_run(m, 0) == 0, "%s: energy balance", m->name);
            if (m->x_phi_Rdot >= 0)
                CHECK(energy_run(m, 1) == 0, "%s: energy and friction work", m->name);
        }
        if (do_momentum)
            CHECK(momentum_run(m) == 0, "%s: angular momentum balance", m->name);
    }
    if (failures) {
        printf("test_kernels_energy: FAILED (%d checks)\n", failures);
        return 1;
    }
    printf("test_kernels_energy: ok\n");
    return 0;
}
