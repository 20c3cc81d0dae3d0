/* Stationary solution and Floquet multipliers, checked against independent truth.
 *
 * 1. The stationary solution found from the reduced residuals (3.5) makes the
 *    full nonlinear equations M(xbar) xbar' - f(xbar, t) vanish at many times t
 *    (the mass/rhs kernels are derived separately from the residual kernels),
 *    each torque row to 1e-6 m0: an error of 1e-3 m0 in one row fails
 *    (tests/derive/mutation.sh).  States are addressed by the generated indices.
 * 2. The two Floquet methods (CVODES on the variational equations; product of
 *    matrix exponentials) agree multiplier by multiplier.
 * 3. Integrating the full nonlinear model (CVODES, BDF) from xbar(0) for 20
 *    periods stays on the orbit.
 * 4. The slip model's cyclic rotor angle: the integrated monodromy's column
 *    of a cyclic coordinate is the unit vector.
 * 5. Parameters without a stationary solution are reported as such.
 * 6. t0: under the integrated twist law the monodromy from t0 = 0 and from
 *    t0 = 100 T agree, and the multipliers equal those of the constant-
 *    coefficient linearisation (one matrix exponential of the frame-A matrix);
 *    under the paper's law the dependence on t0 is reported.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cvodes/cvodes.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_linalg.h>
#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include "usm.h"

#include "check.h"

/* ---- 1. full residual on the orbit ----------------------------------------- */

/* 1 where row i of M x' = f is a balance of torques (the rows of the rates),
 * 0 for the kinematic rows q' = qdot and tau' = omega_Z. */
static int torque_row(const usm_model *m, int i)
{
    if (m->coordinates == 1) /* the tilt vector's rates */
        return i == m->x_adot || i == m->x_bdot || i == m->x_chidot || i == m->x_phi_Rdot;
    return i == m->x_phidot || i == m->x_thetadot || i == m->x_psidot || i == m->x_phi_Rdot;
}

/* Torque rows are judged against the excitation amplitude m0: a correct model
 * leaves only rounding, an error of 1e-3 m0 in one row (tests/derive/mutation.sh)
 * fails by a factor 1000.  The rounding: the twist torque c_t (phi + psi cos
 * theta) is a difference of terms c_t phi and c_t psi that grow with t (about
 * 2e6 N m after 18 periods), so it carries ~eps c_t (|phi| + |psi|); the
 * allowance is 1e-6 m0 plus 64 times that.  (An earlier scale of
 * c_t (|phi| + |psi|) alone let an error of 0.2 % of m0 pass.) */
#define ORBIT_M0_TOL 1e-6
#define ORBIT_KIN_TOL 1e-12

static void check_orbit_residual(const usm_model *m, const usm_params *p,
                                 const usm_steady_solution *sol)
{
    const int n = m->nx;
    double worst_torque = 0, worst_kin = 0;
    for (int k = 0; k < 50; ++k) {
        const double t = (k * 0.37) / p->f; /* spread over ~18 periods */
        double o[2 * USM_MAX_NX], M[USM_MAX_NX * USM_MAX_NX], f[USM_MAX_NX];
        m->steady_state(sol->u, sol->beta, t, p, o);
        m->mass(o, p, M);
        m->rhs(o, t, p, f);
        const double twist_terms =
            m->coordinates == 1 ? p->c_t * (fabs(o[m->x_chi]) + fabs(o[m->x_tau])) :
            p->c_t * (fabs(o[m->x_phi]) + fabs(o[m->x_psi]) + (m->x_tau >= 0 ? fabs(o[m->x_tau]) : 0));
        for (int i = 0; i < n; ++i) {
            double r = -f[i], size = fabs(f[i]);
            for (int j = 0; j < n; ++j) {
                r += M[i * n + j] * o[n + j];
                size = fmax(size, fabs(M[i * n + j] * o[n + j]));
            }
            if (torque_row(m, i))
                worst_torque = fmax(worst_torque, fabs(r) / (ORBIT_M0_TOL * p->m0 +
                                                             64 * 2.22e-16 * twist_terms));
            else /* q' = qdot, tau' = omega_Z: differences of rates of size Omega */
                worst_kin = fmax(worst_kin, fabs(r) / (ORBIT_KIN_TOL * fmax(size, 6.283185307179586 * p->f)));
        }
    }
    printf("%s: full residual on the stationary orbit: torque rows %.2e, kinematic rows %.2e "
           "of their allowance\n", m->name, worst_torque, worst_kin);
    CHECK(worst_torque <= 1, "%s: M xbar' - f does not vanish on the orbit: a torque row is off "
          "by %.3e times %g m0", m->name, worst_torque, ORBIT_M0_TOL);
    CHECK(worst_kin <= 1, "%s: a kinematic row is off on the orbit (%.3e of its allowance)",
          m->name, worst_kin);
}

/* ---- 2. two Floquet methods ------------------------------------------------- */

static void check_floquet_methods(const usm_model *m, const usm_params *p,
                                  const usm_steady_solution *sol, usm_floquet_result *res)
{
    usm_floquet *f = usm_floquet_alloc(m);
    usm_floquet_options o;
    usm_floquet_result r2;
    usm_floquet_options_default(&o);
    o.method = USM_FLOQUET_VARIATIONAL;
    int rc = usm_floquet_compute(f, p, sol, 0.0, &o, res);
    CHECK(rc == USM_OK, "%s: variational Floquet failed: %s", m->name, usm_floquet_message(f));
    o.method = USM_FLOQUET_EXPONENTIAL;
    rc = usm_floquet_compute(f, p, sol, 0.0, &o, &r2);
    CHECK(rc == USM_OK, "%s: exponential Floquet failed: %s", m->name, usm_floquet_message(f));
    /* Both at their default accuracy (CVODES rtol 1e-8, 64 exponentials),
     * multipliers matched by nearest pairs.  Measured against CVODES at rtol
     * 1e-12: the exponential method is within 1.8e-11, CVODES at
     * rtol 1e-8 within 1.3e-7 (4dof_twist_integrated) and it moves by up to
     * 2.1e-7 under a last-bit change of the tilt (its step sequence changes):
     * so 1e-6, 5 times that. */
    const double worst = MULTIPLIERS_DISTANCE(*res, r2);
    printf("%s: Floquet methods differ by at most %.2e\n", m->name, worst);
    CHECK(worst < 1e-6, "%s: Floquet methods disagree by %.3e", m->name, worst);
    /* (the cyclic multipliers themselves are set to 1 by construction; the
     * cyclic column of the integrated monodromy B must be e_i) */
    for (int j = 0; j < m->nx; ++j)
        if (m->cyclic[j])
            for (int i = 0; i < m->nx; ++i)
                /* exact in theory; the well-conditioned coordinates round
                 * it at ~1e-11 in the rate rows, whose entries are ~Omega
                 * (measured: up to 2.4e-11, 3dof_twist_integrated): 1e-9 */
                CHECK(fabs(res->monodromy[i * m->nx + j] - (i == j)) < 1e-9,
                      "%s: monodromy column %d is not e_%d", m->name, j, j);
    usm_floquet_free(f);
}

/* ---- 3. nonlinear integration stays on the orbit ---------------------------- */

typedef struct {
    const usm_model *m;
    const usm_params *p;
} ode_ctx;

static int ode_rhs(sunrealtype t, N_Vector y, N_Vector ydot, void *data)
{
    const ode_ctx *c = data;
    const int n = c->m->nx;
    double M[USM_MAX_NX * USM_MAX_NX];
    c->m->mass(N_VGetArrayPointer(y), c->p, M);
    c->m->rhs(N_VGetArrayPointer(y), t, c->p, N_VGetArrayPointer(ydot));
    gsl_matrix_view Mv = gsl_matrix_view_array(M, (size_t)n, (size_t)n);
    gsl_vector_view fv = gsl_vector_view_array(N_VGetArrayPointer(ydot), (size_t)n);
    gsl_permutation *perm = gsl_permutation_alloc((size_t)n);
    int sign, rc = gsl_linalg_LU_decomp(&Mv.matrix, perm, &sign);
    if (rc == GSL_SUCCESS)
        rc = gsl_linalg_LU_svx(&Mv.matrix, perm, &fv.vector);
    gsl_permutation_free(perm);
    return rc == GSL_SUCCESS ? 0 : 1;
}

static void check_stays_on_orbit(const usm_model *m, const usm_params *p,
                                 const usm_steady_solution *sol)
{
    const int n = m->nx;
    SUNContext ctx;
    ode_ctx c = {m, p};
    double o[2 * USM_MAX_NX];
    SUNContext_Create(NULL, &ctx);
    N_Vector y = N_VNew_Serial(n, ctx);
    m->steady_state(sol->u, sol->beta, 0.0, p, o);
    memcpy(N_VGetArrayPointer(y), o, sizeof(double) * (size_t)n);
    void *cv = CVodeCreate(CV_BDF, ctx);
    SUNMatrix A = SUNDenseMatrix(n, n, ctx);
    SUNLinearSolver LS = SUNLinSol_Dense(y, A, ctx);
    CHECK(cv && A && LS, "CVODES allocation");
    CHECK(CVodeInit(cv, ode_rhs, 0.0, y) == CV_SUCCESS, "CVodeInit");
    CHECK(CVodeSStolerances(cv, 1e-11, 1e-15) == CV_SUCCESS, "CVodeSStolerances");
    CHECK(CVodeSetUserData(cv, &c) == CV_SUCCESS, "CVodeSetUserData");
    CHECK(CVodeSetLinearSolver(cv, LS, A) == CVLS_SUCCESS, "CVodeSetLinearSolver");
    CHECK(CVodeSetMaxNumSteps(cv, 1000000) == CV_SUCCESS, "CVodeSetMaxNumSteps");
    const double T = 1.0 / p->f;
    double worst_theta = 0, worst_speed = 0, t = 0;
    int checked = 0;
    for (int k = 1; k <= 20; ++k) {
        int flag = CVode(cv, k * T, y, &t, CV_NORMAL);
        CHECK(flag >= 0, "%s: CVode failed at t = %g: %s", m->name, t, CVodeGetReturnFlagName(flag));
        if (flag < 0)
            break;
        const double *x = N_VGetArrayPointer(y);
        m->steady_state(sol->u, sol->beta, t, p, o);
        const int ir = m->x_phi_Rdot;
        double ex[6], eo[6]; /* theta of either coordinate set */
        usm_coords_euler_angles(m, x, t, p, 0.0, ex);
        usm_coords_euler_angles(m, o, t, p, 0.0, eo);
        worst_theta = fmax(worst_theta, fabs(ex[1] - eo[1]) / sol->theta);
        if (ir >= 0)
            worst_speed = fmax(worst_speed, fabs(x[ir] - o[ir]) / fabs(sol->rotor_speed));
        ++checked;
    }
    CHECK(checked == 20, "%s: integration stopped after %d periods", m->name, checked);
    printf("%s: 20 periods from xbar(0): theta drift %.2e, rotor speed drift %.2e (relative)\n",
           m->name, worst_theta, worst_speed);
    /* CVODES at rtol 1e-11 from xbar(0) delivers: theta 1.7e-9
     * (3dof: the paper's twist torque is a difference of terms that grow with
     * t), 2e-11 elsewhere, the rotor speed 1.5e-10; so 1e-7, 60 times the
     * largest (it was 1e-5). */
    CHECK(worst_theta < 1e-7, "%s: tilt leaves the stationary orbit (%.3e)", m->name, worst_theta);
    CHECK(worst_speed < 1e-7, "%s: rotor speed leaves the orbit (%.3e)", m->name, worst_speed);
    CVodeFree(&cv);
    SUNLinSolFree(LS);
    SUNMatDestroy(A);
    N_VDestroy(y);
    SUNContext_Free(&ctx);
}

/* ---- 5. no solution --------------------------------------------------------- */

static void check_no_solution(const usm_model *m, const char *field, double value,
                              const char *expect)
{
    usm_params p;
    usm_params_default(&p);
    char msg[USM_MSG_LEN];
    CHECK(usm_params_set(&p, field, value, msg) == USM_OK, "set %s", field);
    usm_steady *s = usm_steady_alloc(m);
    int rc = usm_steady_solve(s, &p, NULL);
    printf("%s with %s = %g: status %d, \"%s\"\n", m->name, field, value, rc, usm_steady_message(s));
    CHECK(rc == USM_ENOSOLUTION, "%s: %s = %g should have no stationary solution", m->name, field,
          value);
    CHECK(strstr(usm_steady_message(s), expect) != NULL, "message lacks \"%s\"", expect);
    CHECK(usm_steady_count(s) == 0, "roots reported although none exists");
    usm_steady_free(s);
}

/* ---- 0. the paper's stationary values make the residuals vanish ------------- */

/* The paper gives theta = 0.81836e-4 (5 digits) and alpha = 5.126 rad (read as
 * radians, see docs/model.md).  At those values each residual must be no larger than
 * what half a unit in their last digits can change it by. */
static void check_paper_point(const usm_model *m, const usm_params *p)
{
    if (!CHECK(m->nu == 2, "%s: %d stationary unknowns, the paper's point gives 2", m->name, m->nu))
        return;
    const double u[2] = {0.81836e-4, 5.126}, du[2] = {0.5e-9, 0.5e-3};
    double r[2], J[4];
    m->steady_residual(u, p, r);
    m->steady_jacobian(u, p, J);
    for (int i = 0; i < 2; ++i) {
        const double allowed = fabs(J[2 * i]) * du[0] + fabs(J[2 * i + 1]) * du[1];
        printf("%s: residual %d at the paper's (theta, alpha) = %.3e N m (paper precision %.3e)\n",
               m->name, i, r[i], allowed);
        CHECK(fabs(r[i]) <= allowed, "%s: residual %d = %.3e exceeds the paper's precision %.3e",
              m->name, i, r[i], allowed);
    }
}

/* ---- 5b. roots near the end of the stick branch ------------------------------ */

/* Near T = 7.6375 mN m the stick solution's tilt falls towards 1e-9 rad, where
 * the default xtol asks for more than rounding gives; a solution that exists
 * must still be found (the bisection of the sweep's fold test relies on it). */
static void check_small_tilt_roots(const usm_model *m)
{
    usm_params p;
    usm_params_default(&p);
    usm_steady *s = usm_steady_alloc(m);
    int missed = 0, found = 0;
    for (int k = 0; k < 200; ++k) {
        p.T = 7.63745e-3 + k * (7.637530e-3 - 7.63745e-3) / 199;
        int rc = usm_steady_solve(s, &p, NULL);
        found += rc == USM_OK;
        /* a root exists up to the fold at 7.6375336 mN m: every T here has one */
        missed += rc != USM_OK;
    }
    printf("%s: T in [7.63745, 7.63753] mN m: %d of 200 solved\n", m->name, found);
    CHECK(missed == 0, "%s: %d existing stationary solutions not found near the fold", m->name,
          missed);
    usm_steady_free(s);
}

/* ---- 6. start-time dependence ---------------------------------------------- */

static double max_abs(const double *a, int n)
{
    double m = 0;
    for (int i = 0; i < n; ++i)
        m = fmax(m, fabs(a[i]));
    return m;
}

static void check_t0(const usm_model *m, const usm_params *p, const usm_steady_solution *sol)
{
    const int n = m->nx;
    const double T = 1.0 / p->f;
    usm_floquet *f = usm_floquet_alloc(m);
    usm_floquet_options o;
    usm_floquet_result r0, r100, rexp;
    usm_floquet_options_default(&o);
    o.rtol = 1e-12;
    o.atol = 1e-16;
    CHECK(usm_floquet_compute(f, p, sol, 0.0, &o, &r0) == USM_OK, "%s: t0 = 0", m->name);
    CHECK(usm_floquet_compute(f, p, sol, 100 * T, &o, &r100) == USM_OK, "%s: t0 = 100 T", m->name);
    /* entry-wise in the monodromy's own scale (its entries span many decades) */
    double scale = max_abs(r0.monodromy, n * n), dB = 0;
    for (int i = 0; i < n * n; ++i)
        dB = fmax(dB, fabs(r0.monodromy[i] - r100.monodromy[i]) / scale);
    const double dl = MULTIPLIERS_DISTANCE(r0, r100);
    printf("%s: t0 = 0 vs 100 T: monodromy differs by %.2e (relative), multipliers by %.2e\n",
           m->name, dB, dl);
    if (m->t0_independent) {
        /* What the two runs deliver: the same method on the same
         * M(theta) (it does not depend on the angles), only the angles' rounding
         * at t0 = 100 T differs: monodromy 9.7e-14 of its scale, multipliers
         * 4.3e-14 (matched by nearest pairs), so 1e-10 (a last-bit change of
         * the kernels moves both runs alike, by up to 1.8e-8). */
        CHECK(dB < 1e-10, "%s: monodromy depends on t0 (%.3e)", m->name, dB);
        CHECK(dl < 1e-10, "%s: multipliers depend on t0 (%.3e)", m->name, dl);
        /* constant coefficients: a single exponential is exact */
        o.method = USM_FLOQUET_EXPONENTIAL;
        o.steps = 1;
        CHECK(usm_floquet_compute(f, p, sol, 0.0, &o, &rexp) == USM_OK, "%s: expm", m->name);
        const double de = MULTIPLIERS_DISTANCE(r0, rexp);
        printf("%s: constant-coefficient exp(T A) vs variational: %.2e\n", m->name, de);
        /* measured 1.8e-13 (4dof_twist_integrated): one exponential is exact
         * here, the default method at rtol 1e-12 is within 4e-11 of CVODES at
         * rtol 1e-12 (tests/solve/test_floquet_methods.c): 1e-10 */
        CHECK(de < 1e-10, "%s: constant-coefficient multipliers differ (%.3e)", m->name, de);
    } else {
        /* the paper's law: a real, visible dependence (psi(t) in the twist
         * term); measured 1.2e-3 (4dof) to 5.2e-2 (3dof), against the 1e-13
         * of the integrated law above */
        CHECK(dl > 1e-4, "%s: expected a t0 dependence, got %.3e", m->name, dl);
    }
    usm_floquet_free(f);
}

int main(void)
{
    gsl_set_error_handler_off();
    for (int k = 0; k < USM_NMODELS; ++k) {
        const usm_model *m = usm_models[k];
        usm_params p;
        usm_params_default(&p);
        if (strcmp(m->name, "3dof") == 0)
            check_paper_point(m, &p);
        usm_steady *s = usm_steady_alloc(m);
        int rc = usm_steady_solve(s, &p, NULL);
        CHECK(rc == USM_OK, "%s: no stationary solution at the paper's parameters: %s", m->name,
              usm_steady_message(s));
        if (rc != USM_OK)
            continue;
        const usm_steady_solution *sol = usm_steady_root(s, 0);
        check_orbit_residual(m, &p, sol);
        usm_floquet_result res;
        check_floquet_methods(m, &p, sol, &res);
        check_stays_on_orbit(m, &p, sol);
        check_t0(m, &p, sol);
        usm_steady_free(s);
    }
    const usm_model *m3 = usm_model_find("3dof"), *m4 = usm_model_find("4dof");
    CHECK(m3 && m4, "models 3dof and 4dof exist");
    check_small_tilt_roots(m3);
    check_no_solution(m3, "m0", 1e-4, "m0");
    /* beyond mu_max = mu0*pi/2: T > 0.47*0.4 N*5 mm = 0.95 N mm */
    check_no_solution(m4, "T", 2e-3, "friction");
    if (failures)
        printf("%d failure(s)\n", failures);
    return failures ? 1 : 0;
}
