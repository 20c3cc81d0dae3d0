/* test_steady_power: the power balance on stationary solutions.
 *
 * On a stationary solution the stator's kinetic energy and every spring's
 * energy are constant, so the power put in by the excitation must leave as
 * load power, damping and slip:  power_in = power_out + power_damping +
 * power_slip.  The two sides are computed independently:
 *  - left, from the state: the mean over one period (32-point rectangle rule,
 *    exact for the trigonometric integrand) of M_E(t) . omega(t), with the
 *    paper's excitation (2.8) M_E = m0 (cos Omega t, sin Omega t, 0) in frame N
 *    and omega = phidot e_Z + thetadot e_x1 + psidot e_z2 (z-x-z Euler angles)
 *    from the orbit's state (<model>_steady_state);
 *  - right, from the torques: the library's generated power_out,
 *    power_damping and power_slip (usm_steady_evaluate).
 * The balance holds only where the residuals vanish, so it checks the
 * derivation and the root together.  Tolerance 1e-9 relative to power_in.
 * Also: the library's power_in and power_damping equal the state's
 * (1e-12 relative; damping d_r (omega_X^2 + omega_Y^2) + d_t omega_Z^2 + d_R Z'^2),
 * power_out = -T rotor_speed (1e-8), power_slip = F_t v_rel (1e-7: v_rel is a
 * cancellation), efficiency = power_out / power_in.
 * Points: the paper's and 50 random parameter sets (every parameter scaled by
 * a factor in [0.8, 1.25], load T in [0, 2 T_paper], I_yy = I_xx) per model:
 * 3dof, 4dof under both twist laws (paper, integrated).
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <gsl/gsl_errno.h>

#include "check.h"
#include "usm.h"

#define NRANDOM 50
#define NQUAD 32
/* The balance power_in = out + damping + slip from two independent routes
 * (the state's forces over the orbit by NQUAD-point quadrature over the
 * period; the library's torques): measured 8.5e-15
 * (printed at the end): 1e-9.  The other tolerances below: what each pair of
 * expressions delivers, measured (printed at the end as "agreement"). */
#define TOL_BALANCE 1e-9

/* largest relative difference seen: power_in, power_damping, power_out,
 * power_slip, efficiency */
static double agree[5];

static double rel_diff(double a, double b, double scale)
{
    return scale > 0 ? fabs(a - b) / scale : fabs(a - b);
}

static void random_params(uint64_t *state, usm_params *p)
{
    usm_params_default(p);
    const double T0 = p->T;
    for (int i = 0; i < USM_NPARAMS; ++i)
        *usm_params_field(p, &usm_param_table[i]) *= exp(rng_range(state, log(0.8), log(1.25)));
    p->I_yy = p->I_xx;
    p->T = rng_range(state, 0.0, 2.0 * T0);
}

/* Mean excitation and damping power over one period, from the orbit's state. */
static void state_powers(const usm_model *m, const usm_params *p, const usm_steady_solution *s,
                         double *p_in, double *p_damp)
{
    const double W = 2.0 * 3.141592653589793238462643 * p->f, T = 1.0 / p->f;
    double orbit[2 * USM_MAX_NX];
    *p_in = *p_damp = 0;
    for (int k = 0; k < NQUAD; ++k) {
        const double t = k * T / NQUAD;
        m->steady_state(s->u, s->beta, t, p, orbit);
        const double *x = orbit, *xd = orbit + m->nx;
        const double ph = x[m->x_phi], th = x[m->x_theta];
        const double phd = xd[m->x_phi], thd = xd[m->x_theta], psd = xd[m->x_psi];
        /* omega in frame N */
        const double wX = thd * cos(ph) + psd * sin(th) * sin(ph);
        const double wY = thd * sin(ph) - psd * sin(th) * cos(ph);
        const double wZ = phd + psd * cos(th);
        *p_in += p->m0 * (cos(W * t) * wX + sin(W * t) * wY) / NQUAD;
        /* Z = R sin(theta) + H cos(theta): its rate is zero when theta is */
        const double Zd = (p->R * cos(th) - p->H * sin(th)) * thd;
        *p_damp += (p->d_r * (wX * wX + wY * wY) + p->d_t * wZ * wZ + p->d_R * Zd * Zd) / NQUAD;
    }
}

static double worst; /* largest relative imbalance seen */

static int check_point(const usm_model *m, usm_steady *st, const usm_params *p, const char *what)
{
    if (usm_steady_solve(st, p, NULL) != USM_OK)
        return 0;
    const usm_steady_solution *s = usm_steady_root(st, 0);
    double p_in, p_damp;
    state_powers(m, p, s, &p_in, &p_damp);
    const double rhs = s->power_out + s->power_damping + s->power_slip;
    if (fabs(p_in - rhs) / fabs(p_in) > worst)
        worst = fabs(p_in - rhs) / fabs(p_in);
    CHECK(p_in > 0, "%s %s: power_in from the state %g is not positive", m->name, what, p_in);
    CHECK(fabs(p_in - rhs) <= TOL_BALANCE * fabs(p_in),
          "%s %s: balance: power_in (state) %.15g != out + damping + slip (torques) %.15g "
          "(rel %.2e)", m->name, what, p_in, rhs, fabs(p_in - rhs) / fabs(p_in));
    agree[0] = fmax(agree[0], rel_diff(s->power_in, p_in, fabs(p_in)));
    agree[1] = fmax(agree[1], rel_diff(s->power_damping, p_damp, fabs(p_damp)));
    agree[2] = fmax(agree[2], rel_diff(s->power_out, -p->T * s->rotor_speed, fabs(s->power_out)));
    if (m->slip)
        agree[3] = fmax(agree[3], rel_diff(s->power_slip, s->F_t * s->v_rel, fabs(s->power_slip)));
    agree[4] = fmax(agree[4], rel_diff(s->efficiency, s->power_out / s->power_in, 1.0));
    /* quadrature and the library's closed form: measured 2.9e-15 (power_in),
     * 1.2e-15 (power_damping): 1e-12 */
    CHECK(fabs(s->power_in - p_in) <= 1e-12 * fabs(p_in),
          "%s %s: power_in: library %.15g, state %.15g", m->name, what, s->power_in, p_in);
    CHECK(fabs(s->power_damping - p_damp) <= 1e-12 * fabs(p_damp) + 1e-300,
          "%s %s: power_damping: library %.15g, state %.15g", m->name, what, s->power_damping,
          p_damp);
    /* two generated expressions of the rotor speed (v_c / R* has a cancellation):
     * measured (printed) 1e-10: 1e-8 */
    CHECK(fabs(s->power_out + p->T * s->rotor_speed) <= 1e-8 * fabs(s->power_out) + 1e-300,
          "%s %s: power_out %.15g != -T rotor_speed %.15g", m->name, what, s->power_out,
          -p->T * s->rotor_speed);
    if (!m->slip)
        CHECK(s->power_slip == 0, "%s %s: power_slip %g in the stick model", m->name, what,
              s->power_slip);
    else
        /* v_rel = v_c - w_R R* is a cancellation (slip << v_c): measured
         * (printed) 2.1e-9: 1e-7 */
        CHECK(fabs(s->power_slip - s->F_t * s->v_rel) <= 1e-7 * fabs(s->power_slip) + 1e-300,
              "%s %s: power_slip %.15g != F_t v_rel %.15g", m->name, what, s->power_slip,
              s->F_t * s->v_rel);
    /* the same quotient: measured 0 */
    CHECK(fabs(s->efficiency - s->power_out / s->power_in) <= 1e-15 + 1e-14 * fabs(s->efficiency),
          "%s %s: efficiency %.15g != power_out / power_in", m->name, what, s->efficiency);
    return 1;
}

int main(void)
{
    gsl_set_error_handler_off();
    const char *names[] = {"3dof", "4dof", "3dof_twist_integrated", "4dof_twist_integrated"};
    for (size_t k = 0; k < sizeof names / sizeof names[0]; ++k) {
        const usm_model *m = usm_model_find(names[k]);
        CHECK(m != NULL, "model %s missing", names[k]);
        if (!m)
            continue;
        usm_steady *st = usm_steady_alloc(m);
        usm_params p;
        usm_params_default(&p);
        CHECK(check_point(m, st, &p, "paper"), "%s: no solution at the paper's point", m->name);
        uint64_t rng = 0x9013e5ULL + k;
        int done = 0, tries = 0;
        char what[64];
        while (done < NRANDOM && tries < 20 * NRANDOM) {
            random_params(&rng, &p);
            snprintf(what, sizeof what, "random point %d", tries++);
            done += check_point(m, st, &p, what);
        }
        CHECK(done == NRANDOM, "%s: only %d of %d random points have a stationary solution",
              m->name, done, NRANDOM);
        printf("%s: balance checked at the paper's point and %d random points (%d tried)\n",
               m->name, done, tries);
        usm_steady_free(st);
    }
    printf("largest relative imbalance %.3g (tolerance %g)\n", worst, TOL_BALANCE);
    printf("agreement: power_in %.2g, power_damping %.2g, power_out %.2g, power_slip %.2g, "
           "efficiency %.2g\n", agree[0], agree[1], agree[2], agree[3], agree[4]);
    if (failures)
        printf("%d failures\n", failures);
    return failures != 0;
}
