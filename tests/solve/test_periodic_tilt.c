/* test_periodic_tilt: the shooting solver (usm_periodic.h) in the tilt-vector
 * coordinates (variant tilt: a, b, chi; docs/coordinates.md) against the same
 * motor in the Euler angles (variant twist_integrated), for both bases.
 *
 * The two variants are one motor under one set of assumptions in two
 * coordinate sets, and the change of coordinates is a diffeomorphism away
 * from theta = 0, so the periodic orbits must be the same motion and carry
 * the same Floquet multipliers.  At two points (the paper's; T = 0 and
 * f = 38.5 kHz), each solve started 1e-6 of the state scales away from the
 * stationary orbit (so Newton has to work in each coordinate set):
 *
 * 1. Both converge (before the tilt vector was handled the solver wrote its
 *    theta scale into scale[-1], the period, and failed after 100,000 steps).
 * 2. The tilt orbit's start state, mapped to the Euler angles by
 *    usm_coords_map, equals the twist_integrated orbit's to 1e-9 of the
 *    state scales (theta; the rates Omega; the tilt rate Omega theta; tau
 *    m0/c_t; the rotor speed itself).
 * 3. Mean rotor speed, theta mean/min/max and F_n min/max agree to 1e-9
 *    relative (the ideal orbit is the stationary solution: theta and F_n
 *    constant, so this also checks the extremes' coordinate-aware theta).
 * 4. The multipliers, as sets (nearest pairs), agree to 2e-8 between the two
 *    orbits and with usm_floquet's on the tilt model (its matrix exponential,
 *    within 1e-10 of the extended-precision reference): each orbit's are
 *    within 3e-9 .. 8e-9 of it at the default rtol 1e-11 (test_periodic's
 *    bound, 2e-8, for the same reason).
 * 5. The guard: a model descriptor whose orientation index is -1 (a copy of
 *    the tilt model with x_a = -1; of the Euler model with x_theta = -1) is
 *    refused by usm_periodic_solve with USM_EINPUT and a message, never read
 *    at x[-1]; usm_coords_theta is NaN and usm_coords_euler_angles
 *    USM_EINPUT for it.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "usm.h"
#include "usm_periodic.h"

#include "check.h"

#define TWO_PI 6.283185307179586476925286766559

/* the Euler-angle scales of runtime/solve/periodic.c */
static void euler_scales(const usm_model *m, const usm_params *p, double theta, double speed,
                         double *scale)
{
    const double W = TWO_PI * p->f;
    for (int i = 0; i < m->nx; ++i)
        scale[i] = 1.0;
    scale[m->x_theta] = theta;
    scale[m->x_phidot] = scale[m->x_psidot] = W;
    scale[m->x_thetadot] = W * theta;
    scale[m->x_tau] = p->m0 / p->c_t;
    if (m->x_phi_Rdot >= 0)
        scale[m->x_phi_Rdot] = fabs(speed);
}

/* the perturbed start: the stationary orbit at t0 = 0 plus 1e-6 of each
 * non-cyclic state's scale, alternating in sign */
static void start_of(const usm_model *m, const usm_params *p, const usm_steady_solution *s,
                     double *x)
{
    double orbit[2 * USM_MAX_NX];
    const double W = TWO_PI * p->f, th = s->theta;
    m->steady_state(s->u, s->beta, 0.0, p, orbit);
    for (int i = 0; i < m->nx; ++i) {
        double sc = 1.0;
        if (m->coordinates == 1)
            sc = i == m->x_a || i == m->x_b ? th
                 : i == m->x_adot || i == m->x_bdot || i == m->x_chidot ? W * th : 1.0;
        else
            sc = i == m->x_theta ? th
                 : i == m->x_phidot || i == m->x_psidot ? W
                 : i == m->x_thetadot ? W * th : 1.0;
        if (i == m->x_tau)
            sc = p->m0 / p->c_t;
        if (i == m->x_phi_Rdot)
            sc = fabs(s->rotor_speed);
        x[i] = orbit[i] + (m->cyclic[i] ? 0.0 : 1e-6 * sc * (i % 2 ? 1.0 : -1.0));
    }
}

static double rel(double a, double b, double size) { return fabs(a - b) / size; }

static void compare(const char *base, const char *label, const usm_params *p)
{
    const usm_model *me = usm_model_variant(base, "twist_integrated");
    const usm_model *mt = usm_model_variant(base, "tilt");
    if (!CHECK(me && mt && mt->other_coordinates == me, "%s: models missing", base))
        return;
    usm_steady *st = usm_steady_alloc(mt);
    if (!CHECK(st && usm_steady_solve(st, p, NULL) == USM_OK, "%s %s: no stationary solution",
               base, label)) {
        usm_steady_free(st);
        return;
    }
    const usm_steady_solution sol = *usm_steady_root(st, 0);
    usm_steady_free(st);

    usm_periodic *we = usm_periodic_alloc(me), *wt = usm_periodic_alloc(mt);
    usm_periodic_result re, rt;
    double xe[USM_MAX_NX], xt[USM_MAX_NX];
    start_of(me, p, &sol, xe);
    start_of(mt, p, &sol, xt);
    int rce = usm_periodic_solve(we, p, xe, NULL, &re);
    int rct = usm_periodic_solve(wt, p, xt, NULL, &rt);
    CHECK(rce == USM_OK, "%s %s twist_integrated: %s", base, label, usm_periodic_message(we));
    CHECK(rct == USM_OK, "%s %s tilt: %s", base, label, usm_periodic_message(wt));
    if (rce != USM_OK || rct != USM_OK) {
        usm_periodic_free(we);
        usm_periodic_free(wt);
        return;
    }
    CHECK(rt.iterations >= 1, "%s %s: Newton did not move from the perturbed start", base, label);

    /* 2. the same start state */
    double scale[USM_MAX_NX], xm[USM_MAX_NX], worst = 0;
    euler_scales(me, p, sol.theta, sol.rotor_speed, scale);
    CHECK(usm_coords_map(mt, rt.x0, 0.0, p, re.x0[me->x_phi], me, xm) == USM_OK, "map");
    for (int i = 0; i < me->nx; ++i)
        if (!me->cyclic[i]) {
            const double d = fabs(xm[i] - re.x0[i]) / scale[i];
            worst = fmax(worst, d);
            CHECK(d <= 1e-9, "%s %s: the orbits' %s differ by %.3g of its scale", base, label,
                  me->state_names[i], d);
        }

    /* 3. the orbit's quantities */
    const double sp = fabs(re.rotor_speed_mean), th = re.theta_mean, fn = re.F_n_max;
    const double q[][3] = {
        {rel(rt.rotor_speed_mean, re.rotor_speed_mean, sp), 0, 0},
        {rel(rt.theta_mean, re.theta_mean, th), rel(rt.theta_min, re.theta_min, th),
         rel(rt.theta_max, re.theta_max, th)},
        {rel(rt.F_n_min, re.F_n_min, fn), rel(rt.F_n_max, re.F_n_max, fn), 0},
    };
    double dq = 0;
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
            dq = fmax(dq, q[a][b]);
    CHECK(dq <= 1e-9, "%s %s: rotor speed, theta or F_n differ by %.3g relative", base, label,
          dq);
    CHECK(rt.validity == re.validity && rt.contact_open == re.contact_open,
          "%s %s: validity differs", base, label);

    /* 4. the multipliers */
    usm_floquet *f = usm_floquet_alloc(mt);
    usm_floquet_result fr;
    const int rcf = f ? usm_floquet_compute(f, p, &sol, 0.0, NULL, &fr) : USM_EFAILED;
    usm_floquet_free(f);
    const double d_orbits = MULTIPLIERS_DISTANCE(rt.floquet, re.floquet);
    CHECK(d_orbits <= 2e-8, "%s %s: the orbits' multipliers differ by %.3g", base, label,
          d_orbits);
    double d_te = NAN, d_ee = NAN;
    if (CHECK(rcf == USM_OK, "%s %s: usm_floquet failed", base, label)) {
        d_te = MULTIPLIERS_DISTANCE(rt.floquet, fr);
        d_ee = MULTIPLIERS_DISTANCE(re.floquet, fr);
        CHECK(d_te <= 2e-8, "%s %s: the tilt orbit's multipliers are %.3g from usm_floquet's",
              base, label, d_te);
    }
    int cyc_t = 0, cyc_e = 0;
    for (int i = 0; i < rt.floquet.n; ++i)
        cyc_t += rt.floquet.cyclic[i];
    for (int i = 0; i < re.floquet.n; ++i)
        cyc_e += re.floquet.cyclic[i];
    CHECK(cyc_t == cyc_e && rt.floquet.n == re.floquet.n, "%s %s: cyclic multipliers %d and %d",
          base, label, cyc_t, cyc_e);
    printf("%s %s: tilt %d / Euler %d Newton iterations; start states within %.1e of the "
           "scales, quantities %.1e; multipliers: orbits %.1e apart, tilt %.1e and Euler %.1e "
           "from usm_floquet\n",
           base, label, rt.iterations, re.iterations, worst, dq, d_orbits, d_te, d_ee);
    usm_periodic_free(we);
    usm_periodic_free(wt);
}

/* 5. a descriptor with a -1 orientation index is refused, not read */
static void guard(const usm_model *model, int which)
{
    usm_model bad = *model;
    if (which)
        bad.x_a = -1;
    else
        bad.x_theta = -1;
    usm_params p;
    usm_params_default(&p);
    double x[USM_MAX_NX] = {0}, e[6];
    usm_periodic *w = usm_periodic_alloc(&bad);
    usm_periodic_result r;
    if (CHECK(w != NULL, "alloc")) {
        const int rc = usm_periodic_solve(w, &p, NULL, NULL, &r);
        CHECK(rc == USM_EINPUT && strstr(usm_periodic_message(w), "lacks"),
              "%s without %s: rc %d, %s", model->name, which ? "x_a" : "x_theta", rc,
              usm_periodic_message(w));
    }
    usm_periodic_free(w);
    CHECK(!usm_coords_layout_ok(&bad) && isnan(usm_coords_theta(&bad, x)) &&
              usm_coords_euler_angles(&bad, x, 0.0, &p, 0.0, e) == USM_EINPUT && isnan(e[1]),
          "%s: the coordinate functions read a -1 index", model->name);
    CHECK(usm_coords_layout_ok(model), "%s: its own layout refused", model->name);
}

int main(void)
{
    usm_params p;
    usm_params_default(&p);
    compare("3dof", "paper's point", &p);
    compare("4dof", "paper's point", &p);
    p.T = 0.0;
    p.f = 38500.0;
    compare("3dof", "T = 0, f = 38.5 kHz", &p);
    compare("4dof", "T = 0, f = 38.5 kHz", &p);
    guard(&usm_model_3dof_tilt, 1);
    guard(&usm_model_4dof_tilt, 1);
    guard(&usm_model_3dof_twist_integrated, 0);
    /* theta of the tilt vector: 0 on the axis, its rate undefined there */
    double x[USM_MAX_NX] = {0}, xd[USM_MAX_NX] = {0};
    CHECK(usm_coords_theta(&usm_model_3dof_tilt, x) == 0.0 &&
              isnan(usm_coords_theta_rate(&usm_model_3dof_tilt, x, xd)),
          "theta on the axis");
    x[usm_model_3dof_tilt.x_a] = 0.6;
    x[usm_model_3dof_tilt.x_b] = 0.8;
    CHECK(isnan(usm_coords_theta(&usm_model_3dof_tilt, x)), "a^2 + b^2 = 1 accepted");
    return failures != 0;
}
