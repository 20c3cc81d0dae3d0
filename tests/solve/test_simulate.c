/* Transient simulation (usm_simulate.h), checked against independent truth.
 *
 * 1. Started from rest with the paper's parameters, both models settle onto
 *    the stationary solution of usm_steady_solve (period means of theta and of
 *    the rotor speed within 1e-3 relative, held for 100 periods), and the
 *    settled state and the settling time do not depend on the initial tilt
 *    (1e-6 rad and 1e-8 rad).
 * 2. Started on the stationary orbit, the motion stays on it for 200 periods
 *    (every sample, not only period means); started 1 % off in tilt, it comes
 *    back (the orbit is stable, as the Floquet multipliers say).
 * 3. Without damping, excitation, load, twist stiffness and friction the
 *    total mechanical energy, computed here from the state with formulas
 *    written independently of the generated kernels, is conserved to the
 *    integrator's tolerance over 200 periods of a large (theta ~ 0.02) whirl:
 *    less than rtol per internal step (BDF is not symplectic), shrinking as
 *    rtol does.
 * 4. A load far beyond what the motor can drive stops the run as a runaway
 *    with a reason, quickly; bad options are rejected.
 * 5. Samples come at t0 + k / rate and at the end.
 * 6. Over 50 ms the stick model's orbit loses stability, as its Floquet
 *    multipliers at t0 = 30 ms say (an artefact of the paper's twist law),
 *    and the simulation shows it; with the integrated twist law it does not.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>

#include "usm.h"
#include "usm_simulate.h"

#include "check.h"

/* ---- 1. start-up from rest --------------------------------------------------- */

static int run(const usm_model *m, const usm_params *p, const usm_sim_options *o,
               const usm_sim_callbacks *cb, usm_sim_summary *sum)
{
    usm_sim *s = usm_sim_alloc(m);
    CHECK(s != NULL, "usm_sim_alloc");
    if (!s)
        return -1;
    int rc = usm_sim_run(s, p, o, cb, sum);
    if (rc != USM_OK)
        printf("%s: usm_sim_run returned %d: %s\n", m->name, rc, usm_sim_message(s));
    usm_sim_free(s);
    return rc;
}

static void check_startup(const usm_model *m)
{
    usm_params p;
    usm_sim_options o;
    usm_sim_summary a, b;
    usm_params_default(&p);
    usm_sim_options_default(&o);
    o.duration = 5e-3; /* settles near 1.1 to 1.5 ms; 100 periods to hold are 2.7 ms */
    o.tilt0 = 1e-6;
    int rc = run(m, &p, &o, NULL, &a);
    CHECK(rc == USM_OK, "%s: start-up from rest failed", m->name);
    o.tilt0 = 1e-8;
    rc = run(m, &p, &o, NULL, &b);
    CHECK(rc == USM_OK, "%s: start-up from rest (tilt0 1e-8) failed", m->name);
    CHECK(a.have_steady && b.have_steady, "%s: no stationary solution", m->name);
    printf("%s: from rest: settled %d at %.6g ms (tilt0 1e-6), %d at %.6g ms (tilt0 1e-8); "
           "end: theta %+.2e, speed %+.2e relative; %ld steps\n",
           m->name, a.settled, a.t_settle * 1e3, b.settled, b.t_settle * 1e3, a.theta_rel_end,
           a.rotor_speed_rel_end, a.steps);
    CHECK(a.settled && b.settled, "%s: did not settle within 5 ms", m->name);
    /* the run at the default rtol 1e-8 against usm_steady_solve (xtol 1e-13):
     * measured 2.9e-9 (theta) and 6.2e-8 (rotor speed, 3dof), 1e-10 (4dof): 1e-6 */
    CHECK(fabs(a.theta_rel_end) < 1e-6 && fabs(a.rotor_speed_rel_end) < 1e-6,
          "%s: settled state differs from usm_steady_solve (%.3e, %.3e)", m->name,
          a.theta_rel_end, a.rotor_speed_rel_end);
    /* independence of tilt0: the settled means agree far inside the settling
     * tolerance, and settling happens in the same period (within 3) */
    const double dth = fabs(a.theta_avg_end - b.theta_avg_end) / a.steady.theta;
    const double dw = fabs(a.rotor_speed_avg_end - b.rotor_speed_avg_end) /
                      fabs(a.steady.rotor_speed);
    printf("%s: tilt0 1e-6 vs 1e-8: settled theta differs by %.2e, rotor speed by %.2e "
           "(relative), settling time by %.3g periods\n",
           m->name, dth, dw, fabs(a.t_settle - b.t_settle) * p.f);
    /* two runs at rtol 1e-8: measured 1.5e-9 and 3.4e-8 (3dof): 1e-6 */
    CHECK(dth < 1e-6 && dw < 1e-6, "%s: the settled state depends on tilt0", m->name);
    CHECK(fabs(a.t_settle - b.t_settle) * p.f <= 3.5, "%s: settling time depends on tilt0",
          m->name);
    CHECK(a.theta_min >= 0.99e-6, "%s: the tilt came back towards 0 (min %.3g)", m->name,
          a.theta_min);
    CHECK(a.contact_open.count == 0, "%s: the contact opens during start-up", m->name);
}

/* ---- 2. on the stationary orbit ---------------------------------------------- */

typedef struct orbit_watch {
    const usm_model *m;
    const usm_params *p;
    usm_steady_solution sol;
    double worst_theta, worst_speed, worst_phase;
    long n;
} orbit_watch;

static int watch_orbit(const usm_sim_sample *s, void *data)
{
    orbit_watch *w = data;
    double o[2 * USM_MAX_NX];
    w->m->steady_state(w->sol.u, w->sol.beta, s->t, w->p, o);
    const int iphi = w->m->nx == 6 ? 0 : 1; /* phi, theta follow */
    w->worst_theta = fmax(w->worst_theta, fabs(s->theta - w->sol.theta) / w->sol.theta);
    w->worst_speed = fmax(w->worst_speed, fabs(s->rotor_speed - w->sol.rotor_speed) /
                                              fabs(w->sol.rotor_speed));
    w->worst_phase = fmax(w->worst_phase, fabs(s->phi - o[iphi]));
    w->n++;
    return 0;
}

static void check_stays(const usm_model *m)
{
    usm_params p;
    usm_sim_options o;
    usm_sim_summary sum;
    usm_params_default(&p);
    usm_sim_options_default(&o);
    usm_steady *st = usm_steady_alloc(m);
    CHECK(usm_steady_solve(st, &p, NULL) == USM_OK, "%s: steady", m->name);
    orbit_watch w = {m, &p, *usm_steady_root(st, 0), 0, 0, 0, 0};
    usm_steady_free(st);
    usm_sim_callbacks cb = {watch_orbit, NULL, &w, NULL};
    o.start = USM_SIM_FROM_STATIONARY;
    o.duration = 200.0 / p.f;
    o.rate = 7.3 * p.f; /* not a multiple of f: samples at every phase */
    int rc = run(m, &p, &o, &cb, &sum);
    CHECK(rc == USM_OK, "%s: run from the stationary orbit failed", m->name);
    printf("%s: 200 periods on the orbit: %ld samples, worst theta %.2e, rotor speed %.2e "
           "(relative), phi %.2e rad; settled %d at t = %g\n",
           m->name, w.n, w.worst_theta, w.worst_speed, w.worst_phase, sum.settled, sum.t_settle);
    CHECK(w.n >= 1460, "%s: too few samples (%ld)", m->name, w.n);
    /* rtol 1e-8 over 200 periods against the closed-form orbit: measured 2e-10
     * (theta), 3.1e-9 (rotor speed), 1.7e-10 rad (phi), 3dof: 1e-6 */
    CHECK(w.worst_theta < 1e-6 && w.worst_speed < 1e-6 && w.worst_phase < 1e-6,
          "%s: the motion leaves the stationary orbit", m->name);
    CHECK(sum.settled && sum.t_settle == 0.0, "%s: on the orbit but not settled from t0",
          m->name);

    /* 1 % off in tilt, zero twist-rate change: must return */
    double orbit[2 * USM_MAX_NX];
    const int ith = m->nx == 6 ? 1 : 2;
    m->steady_state(w.sol.u, w.sol.beta, 0.0, &p, orbit);
    memcpy(o.x0, orbit, sizeof(double) * (size_t)m->nx);
    o.x0[ith] *= 1.01;
    o.start = USM_SIM_FROM_STATE;
    o.rate = 0;
    o.duration = 6e-3;
    rc = run(m, &p, &o, NULL, &sum);
    printf("%s: from 1%% off the orbit: settled %d at %.4g ms, end %+.2e, %+.2e\n", m->name,
           sum.settled, sum.t_settle * 1e3, sum.theta_rel_end, sum.rotor_speed_rel_end);
    CHECK(rc == USM_OK && sum.settled, "%s: does not return to the orbit from 1%% off", m->name);
}

/* ---- 3. energy ------------------------------------------------------------------ */

typedef struct energy_watch {
    const usm_model *m;
    const usm_params *p;
    double E0, worst, Ekin_max;
    long n;
} energy_watch;

/* Mechanical energy from the state alone.  Stator (I_xx = I_yy): the body
 * rates in frame B are (thetadot, phidot sin theta, phidot cos theta + psidot).
 * Contact point r_c = R e_y2 + H e_z2: height Z = R sin theta + H cos theta,
 * Zdot = (R cos theta - H sin theta) thetadot.  Stick model: the rotor turns
 * with the contact point, phidot_R = -v_c / R* with v_c = (omega x r_c) . e_x1
 * = H phidot sin theta - R (phidot cos theta + psidot). */
static double energy(const usm_model *m, const usm_params *p, const usm_sim_sample *s,
                     double *kinetic)
{
    const double th = s->theta, st = sin(th), ct = cos(th);
    const double wz = s->phidot * ct + s->psidot;
    const double Z = p->R * st + p->H * ct;
    const double Rs = p->R * ct - p->H * st;
    const double Zdot = Rs * s->thetadot;
    double wR;
    if (m->nx == 6)
        wR = -(p->H * s->phidot * st - p->R * wz) / Rs;
    else
        wR = s->x[4];
    const double T = 0.5 * p->I_xx * (s->thetadot * s->thetadot + s->phidot * s->phidot * st * st) +
                     0.5 * p->I_zz * wz * wz + 0.5 * p->M * Zdot * Zdot + 0.5 * p->I_R * wR * wR;
    const double V = 0.5 * p->c_r * th * th + p->F0 * Z + 0.5 * p->c_R * (Z - p->H) * (Z - p->H);
    *kinetic = T;
    return T + V;
}

static int watch_energy(const usm_sim_sample *s, void *data)
{
    energy_watch *w = data;
    double kin;
    const double E = energy(w->m, w->p, s, &kin);
    if (w->n++ == 0)
        w->E0 = E;
    w->worst = fmax(w->worst, fabs(E - w->E0));
    w->Ekin_max = fmax(w->Ekin_max, kin);
    return 0;
}

static void check_energy(const usm_model *m)
{
    usm_params p;
    usm_sim_options o;
    usm_sim_summary sum;
    usm_params_default(&p);
    p.d_R = p.d_r = p.d_t = 0;
    p.m0 = 0; /* the library accepts m0 = 0 for transients */
    p.T = 0;
    p.c_t = 0;
    p.mu0 = 0;
    usm_sim_options_default(&o);
    o.start = USM_SIM_FROM_STATE;
    /* a whirl of the tilt vector (phidot near the tilt mode's frequency),
     * slightly elliptic, with some spin: theta stays away from the Euler
     * angles' singularity at 0 */
    const double x3[] = {0.3, 0.02, -0.2, 1.5e5, 300.0, -1.5e5 + 900.0};
    const double x4[] = {0.1, 0.3, 0.02, -0.2, -5.0, 1.5e5, 300.0, -1.5e5 + 900.0};
    memcpy(o.x0, m->nx == 6 ? x3 : x4, sizeof(double) * (size_t)m->nx);
    o.duration = 200.0 / p.f;
    o.rate = 4 * p.f;
    energy_watch w = {m, &p, 0, 0, 0, 0};
    usm_sim_callbacks cb = {watch_energy, NULL, &w, NULL};
    double drift[2];
    for (int k = 0; k < 2; ++k) {
        o.rtol = k == 0 ? 1e-8 : 1e-10;
        w.n = 0;
        w.worst = w.Ekin_max = 0;
        int rc = run(m, &p, &o, &cb, &sum);
        CHECK(rc == USM_OK, "%s: conservative run failed", m->name);
        drift[k] = w.worst / w.E0;
        printf("%s: energy over 200 periods, rtol %g: E0 = %.6g J, max |E - E0| = %.3e J "
               "(%.2e of E0, %.2e of the largest kinetic energy, %.2f rtol per step), "
               "%ld steps, theta in [%.4g, %.4g]\n",
               m->name, o.rtol, w.E0, w.worst, drift[k], w.worst / w.Ekin_max,
               drift[k] / (o.rtol * (double)sum.steps), sum.steps, sum.theta_min, sum.theta_max);
        /* BDF is not symplectic: each step may lose up to the local tolerance
         * (measured: about 0.2 rtol of the energy per step, at any rtol) */
        CHECK(drift[k] < o.rtol * (double)sum.steps,
              "%s: energy drifts by %.3e relative at rtol %g, more than rtol per step", m->name,
              drift[k], o.rtol);
    }
    CHECK(drift[1] < drift[0] / 20, "%s: energy error does not shrink with rtol (%.3e, %.3e)",
          m->name, drift[0], drift[1]);
}

/* ---- 4. runaway and bad input ----------------------------------------------------- */

static void check_runaway(const usm_model *m)
{
    usm_params p;
    usm_sim_options o;
    usm_sim_summary sum;
    usm_params_default(&p);
    p.T = 1.0; /* 15 000 times the paper's load */
    usm_sim_options_default(&o);
    o.duration = 1.0;
    usm_sim *s = usm_sim_alloc(m);
    int rc = usm_sim_run(s, &p, &o, NULL, &sum);
    printf("%s: T = 1 N m: status %d, stop %s at t = %.4g s: %s\n", m->name, rc,
           usm_sim_stop_name(sum.stop), sum.t_reached, sum.reason);
    CHECK(rc == USM_EFAILED, "%s: a runaway must fail", m->name);
    CHECK(sum.stop == USM_SIM_RUNAWAY_SPEED || sum.stop == USM_SIM_RUNAWAY_TILT,
          "%s: stop should be a runaway, is %s", m->name, usm_sim_stop_name(sum.stop));
    CHECK(sum.t_reached < 1e-2, "%s: runaway detected late (t = %g)", m->name, sum.t_reached);
    CHECK(strstr(usm_sim_message(s), "runaway") != NULL, "%s: message lacks the reason",
          m->name);
    CHECK(!sum.have_steady, "%s: a stationary solution at T = 1 N m?", m->name);

    /* step cap */
    usm_params_default(&p);
    o.duration = 1e-3;
    o.max_steps = 100;
    rc = usm_sim_run(s, &p, &o, NULL, &sum);
    CHECK(rc == USM_EFAILED && sum.stop == USM_SIM_MAX_STEPS, "%s: step cap not enforced",
          m->name);

    /* bad options */
    usm_sim_options_default(&o);
    o.duration = 0;
    CHECK(usm_sim_run(s, &p, &o, NULL, &sum) == USM_EINPUT, "duration 0 accepted");
    o.duration = 1e-3;
    o.tilt0 = -1e-6; /* 0 is the start at rest, below every unstable root */
    CHECK(usm_sim_run(s, &p, &o, NULL, &sum) == USM_EINPUT, "tilt0 -1e-6 accepted");
    usm_sim_options_default(&o);
    o.duration = 1e-3;
    o.start = USM_SIM_FROM_STATE; /* all zero: theta = 0 */
    rc = usm_sim_run(s, &p, &o, NULL, &sum);
    CHECK(rc == USM_EINPUT && strstr(usm_sim_message(s), "theta"),
          "theta = 0 start accepted (%d: %s)", rc, usm_sim_message(s));
    usm_params_default(&p);
    p.m0 = 0.01;
    o.start = USM_SIM_FROM_STATIONARY;
    p.m0 = 1e-6; /* far too weak to drive: no stationary solution */
    rc = usm_sim_run(s, &p, &o, NULL, &sum);
    CHECK(rc == USM_ENOSOLUTION, "stationary start without a solution: %d", rc);
    usm_sim_free(s);
}

/* ---- 5. sample times ------------------------------------------------------------- */

typedef struct times {
    double t[64];
    int n;
} times;

static int record(const usm_sim_sample *s, void *data)
{
    times *tm = data;
    if (tm->n < 64)
        tm->t[tm->n] = s->t;
    tm->n++;
    return 0;
}

static void check_samples(const usm_model *m)
{
    usm_params p;
    usm_sim_options o;
    usm_sim_summary sum;
    times tm = {{0}, 0};
    usm_sim_callbacks cb = {record, NULL, &tm, NULL};
    usm_params_default(&p);
    usm_sim_options_default(&o);
    o.t0 = 1e-4;
    o.duration = 1.05e-4;
    o.rate = 1e5; /* t0 + 0, 10, ..., 100 us, then the end at 105 us */
    CHECK(run(m, &p, &o, &cb, &sum) == USM_OK, "%s: short run", m->name);
    CHECK(tm.n == 12, "%s: %d samples, expected 12", m->name, tm.n);
    for (int k = 0; k < 11 && k < tm.n; ++k)
        CHECK(fabs(tm.t[k] - (1e-4 + k * 1e-5)) < 1e-15, "%s: sample %d at %.17g", m->name, k,
              tm.t[k]);
    CHECK(tm.n == 12 && tm.t[11] == 1e-4 + 1.05e-4, "%s: no sample at the end", m->name);
    CHECK(sum.samples == tm.n, "%s: summary counts %ld samples", m->name, sum.samples);
    /* a callback that stops */
    o.rate = 0;
    CHECK(sum.periods == 3, "%s: %ld complete periods in 105 us, expected 3", m->name,
          sum.periods);
}

/* ---- 6. long runs: the paper's twist law -------------------------------------- */

/* The paper's twisting torque c_t (phi + psi cos theta) has the derivative
 * -c_t psi(t) sin theta in theta, and psi grows like -Omega t: the stick
 * model's stationary orbit, stable at t0 = 0, loses stability after about
 * 20 ms (Floquet multipliers over [t0, t0 + T] cross 1).  The simulation must
 * show it (not step over it), and must not show it for the integrated twist
 * law, which removes the artefact. */
static void check_long_run(void)
{
    const usm_model *m = usm_model_find("3dof"), *mi = usm_model_find("3dof_twist_integrated");
    usm_params p;
    usm_sim_options o;
    usm_sim_summary sum;
    usm_floquet_result fr;
    usm_params_default(&p);
    usm_steady *st = usm_steady_alloc(m);
    usm_floquet *fl = usm_floquet_alloc(m);
    CHECK(usm_steady_solve(st, &p, NULL) == USM_OK, "3dof steady");
    CHECK(usm_floquet_compute(fl, &p, usm_steady_root(st, 0), 0.03, NULL, &fr) == USM_OK,
          "3dof floquet");
    printf("3dof: largest Floquet multiplier over [0.03 s, 0.03 s + T]: %.4f\n", fr.max_modulus);
    CHECK(fr.max_modulus > 1, "3dof: orbit stable at t0 = 0.03 s: the premise changed");
    usm_floquet_free(fl);
    usm_steady_free(st);
    usm_sim_options_default(&o);
    o.start = USM_SIM_FROM_STATIONARY;
    o.duration = 0.05;
    int rc = run(m, &p, &o, NULL, &sum);
    printf("3dof: from the orbit for 50 ms: stop %s at %.4g ms, %ld steps\n",
           usm_sim_stop_name(sum.stop), sum.t_reached * 1e3, sum.steps);
    CHECK(rc == USM_EFAILED && sum.t_reached > 0.02 && sum.contact_open.count > 0,
          "3dof: the orbit's instability after 20 ms is not seen");
    if (!CHECK(mi != NULL, "no model 3dof_twist_integrated: its half of the check cannot run"))
        return;
    rc = run(mi, &p, &o, NULL, &sum);
    printf("%s: from the orbit for 50 ms: stop %s, settled %d, %ld steps\n", mi->name,
           usm_sim_stop_name(sum.stop), sum.settled, sum.steps);
    CHECK(rc == USM_OK && sum.settled && sum.t_settle == 0.0,
          "%s: leaves the stationary orbit", mi->name);
}

int main(void)
{
    gsl_set_error_handler_off();
    const char *names[] = {"3dof", "4dof"};
    for (int k = 0; k < 2; ++k) {
        const usm_model *m = usm_model_find(names[k]);
        CHECK(m != NULL, "model %s", names[k]);
        if (!m)
            continue;
        check_startup(m);
        check_stays(m);
        check_energy(m);
        check_runaway(m);
        check_samples(m);
    }
    check_long_run();
    if (failures)
        printf("%d failure(s)\n", failures);
    return failures ? 1 : 0;
}
