/* Orientation coordinates: the models in the tilt-vector
 * coordinates (variant tilt) against their Euler-angle counterparts.
 *
 * 1. The stationary solution: the one found in the tilt-vector model, its
 *    orbit recovered in Euler angles by the library's map (usm_coords_map,
 *    usm_coords_euler_angles), equals the Euler-angle model's to 1e-13
 *    (theta, alpha, rotor speed; the orbit's states at several t, relative to
 *    their size), and the map of the Euler orbit equals the tilt model's own
 *    generated orbit (derived separately, derive/usm_derive/model.py,
 *    regular_orbit).  Both ways the map and the kernels agree to rounding
 *    (measured 2e-16 tilt -> Euler, 2e-15 Euler -> tilt; chi = phi + psi, an
 *    angle, to 1e-13 rad: on the orbit it is alpha + beta = T / c_t ~ 6e-9).
 * 2. A start-up from rest at the paper's preload, simulated in both
 *    coordinate sets at rtol 1e-10 (the Euler-angle model with
 *    own_coordinates = 1): the samples' theta and rotor speed agree to the
 *    integrator's tolerance (measured and asserted below); and the library's
 *    default for the Euler-angle model (integrated in the tilt vector) hands
 *    out the same samples as the tilt model.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "usm.h"
#include "usm_simulate.h"

#include "check.h"

#define TWO_PI 6.283185307179586476925286766559

static double rel(double a, double b) { return fabs(a - b) / fmax(fabs(b), 1e-300); }

/* 1. */
static void check_stationary(const usm_model *e, const usm_params *p, const char *what)
{
    const usm_model *r = e->other_coordinates;
    usm_steady *se = usm_steady_alloc(e), *sr = usm_steady_alloc(r);
    CHECK(usm_steady_solve(se, p, NULL) == USM_OK, "%s %s: steady", e->name, what);
    CHECK(usm_steady_solve(sr, p, NULL) == USM_OK, "%s %s: steady", r->name, what);
    const usm_steady_solution *a = usm_steady_root(se, 0), *b = usm_steady_root(sr, 0);
    double worst = fmax(rel(b->theta, a->theta), fmax(rel(b->alpha, a->alpha),
                                                      rel(b->rotor_speed, a->rotor_speed)));
    const int n = e->nx;
    double worst_orbit = 0, worst_map = 0;
    for (int k = 0; k < 7; ++k) {
        const double t = 0.123 * k / p->f;
        double oe[2 * USM_MAX_NX], orr[2 * USM_MAX_NX], x[USM_MAX_NX], eul[6];
        e->steady_state(a->u, a->beta, t, p, oe);
        r->steady_state(b->u, b->beta, t, p, orr);
        /* tilt -> Euler: the Euler model's state from the tilt model's orbit */
        CHECK(usm_coords_map(r, orr, t, p, oe[e->x_phi], e, x) == USM_OK, "map");
        for (int i = 0; i < n; ++i) {
            const double scale = i == e->x_theta ? a->theta
                                 : i == e->x_thetadot ? a->theta * TWO_PI * p->f
                                                      : fmax(fabs(oe[i]), 1e-300);
            worst_orbit = fmax(worst_orbit, fabs(x[i] - oe[i]) / scale);
        }
        /* the report's quantities from the tilt vector */
        usm_coords_euler_angles(r, orr, t, p, oe[e->x_phi], eul);
        worst_orbit = fmax(worst_orbit, rel(eul[1], a->theta));
        worst_orbit = fmax(worst_orbit, fabs(eul[0] - TWO_PI * p->f * t - a->alpha) /
                                            fabs(a->alpha));
        /* Euler -> tilt: the map of the Euler orbit against the generated one */
        CHECK(usm_coords_map(e, oe, t, p, 0.0, r, x) == USM_OK, "map");
        const double tilt = sin(a->theta), Om = TWO_PI * p->f;
        for (int i = 0; i < n; ++i) {
            const double scale = (i == r->x_a || i == r->x_b) ? tilt
                                 : (i == r->x_adot || i == r->x_bdot) ? tilt * Om
                                 : i == r->x_chidot ? Om
                                 : i == r->x_chi ? fmax(fabs(orr[i]), 1.0) /* an angle */
                                 : fmax(fabs(orr[i]), 1e-300);
            worst_map = fmax(worst_map, fabs(x[i] - orr[i]) / scale);
        }
    }
    printf("%-24s %-14s stationary solution: theta, alpha, rotor speed %.2e; orbit, tilt -> "
           "Euler %.2e; Euler -> tilt %.2e (relative)\n",
           r->name, what, worst, worst_orbit, worst_map);
    /* the same kernels (derive/ shares them): 0 measured; the maps: 2e-16 .. 6e-15 */
    CHECK(worst <= 1e-13, "%s %s: stationary solution differs by %.3e", r->name, what, worst);
    CHECK(worst_orbit <= 1e-13, "%s %s: orbit recovered to %.3e", r->name, what, worst_orbit);
    CHECK(worst_map <= 1e-13, "%s %s: mapped orbit off by %.3e", r->name, what, worst_map);
    usm_steady_free(se);
    usm_steady_free(sr);
}

/* 2. */
#define NSAMP 64
typedef struct run {
    double theta[NSAMP + 2], speed[NSAMP + 2];
    int n;
} run;

static int sample(const usm_sim_sample *s, void *data)
{
    run *r = data;
    if (r->n < NSAMP + 2) {
        r->theta[r->n] = s->theta;
        r->speed[r->n] = s->rotor_speed;
        r->n++;
    }
    return 0;
}

static long start_up(const usm_model *m, const usm_params *p, double rtol, double duration,
                     run *out, int own)
{
    usm_sim *s = usm_sim_alloc(m);
    usm_sim_options o;
    usm_sim_options_default(&o);
    o.own_coordinates = own; /* 1: the Euler-angle model in Euler angles */
    o.duration = duration;
    o.rate = NSAMP / duration;
    o.rtol = rtol;
    o.settle_periods = 1000000; /* the whole duration */
    usm_sim_summary sum;
    usm_sim_callbacks cb = {sample, NULL, out, NULL};
    memset(out, 0, sizeof *out);
    int rc = usm_sim_run(s, p, &o, &cb, &sum);
    CHECK(rc == USM_OK, "%s: simulate: %s", m->name, usm_sim_message(s));
    usm_sim_free(s);
    return sum.steps;
}

static void check_start_up(const usm_model *e, const usm_params *p)
{
    const usm_model *r = e->other_coordinates;
    const double duration = 1e-3, rtol = 1e-10;
    static run a, b;
    long na = start_up(e, p, rtol, duration, &a, 1), nb = start_up(r, p, rtol, duration, &b, 1);
    static run c;
    start_up(e, p, rtol, duration, &c, 0);
    double dc = 0;
    for (int k = 0; k < b.n && k < c.n; ++k)
        dc = fmax(dc, fabs(c.theta[k] - b.theta[k]) + fabs(c.speed[k] - b.speed[k]));
    CHECK(c.n == b.n && dc == 0, "%s by default: %d samples, %.3e from the tilt model's", e->name,
          c.n, dc);
    CHECK(a.n == b.n && a.n > NSAMP / 2, "%s: %d and %d samples", e->name, a.n, b.n);
    double th_max = 0, w_max = 0, dth = 0, dw = 0;
    for (int k = 0; k < a.n && k < b.n; ++k) {
        th_max = fmax(th_max, fabs(a.theta[k]));
        w_max = fmax(w_max, fabs(a.speed[k]));
    }
    for (int k = 0; k < a.n && k < b.n; ++k) {
        dth = fmax(dth, fabs(a.theta[k] - b.theta[k]) / th_max);
        dw = fmax(dw, fabs(a.speed[k] - b.speed[k]) / w_max);
    }
    printf("%-24s start-up from rest, %g s at rtol %g: theta differs by %.2e of its maximum, "
           "rotor speed by %.2e (%ld steps in Euler angles, %ld in the tilt vector)\n",
           r->name, duration, rtol, dth, dw, na, nb);
    /* two integrations of the same motion to rtol 1e-10 along 37 periods of
     * the start-up: measured 7.8e-9 (4dof) .. 2.0e-8 (3dof) of the maxima;
     * 1e-6 = 1e4 rtol (a model error shows as 4e-2: the contact force's
     * direction once taken in the wrong frame) */
    CHECK(dth <= 1e4 * rtol && dw <= 1e4 * rtol,
          "%s: start-ups differ: theta %.3e, speed %.3e", r->name, dth, dw);
}

int main(void)
{
    int pairs = 0;
    for (int k = 0; k < USM_NMODELS; ++k) {
        const usm_model *e = usm_models[k];
        if (e->coordinates != 0 || !e->other_coordinates)
            continue;
        ++pairs;
        CHECK(e->other_coordinates->other_coordinates == e, "%s: pair", e->name);
        usm_params p;
        usm_params_default(&p);
        check_stationary(e, &p, "paper");
        p.T = 0.0;
        check_stationary(e, &p, "T = 0");
        usm_params_default(&p);
        p.f = 38500;
        check_stationary(e, &p, "f = 38.5 kHz");
        usm_params_default(&p);
        check_start_up(e, &p);
    }
    CHECK(pairs >= 2, "%d model pairs in both coordinate sets", pairs);
    if (failures)
        printf("%d failure(s)\n", failures);
    return failures != 0;
}
