/* The shooting posed with the start time as an unknown (solve/periodic.c,
 * periodic_internal.h: what the envelope's contact_loss curves are made
 * of), against finite differences and the orbit itself.
 *
 * 1. dr/dt0 in closed form (f(x1, t0 + T) - B f(x0, t0)) against central
 *    differences of the period map in t0 with x0 held (to 1e-3: the
 *    differences themselves spread by 1e-4 between steps).
 * 2. dF_n/dt at a state of the orbit (usm_periodic_quantity_rate) against
 *    central differences of F_n along the orbit's re-integrated states.
 * 3. The orbit shot from a minimum's time: its residual is the orbit's
 *    (periodic to the shooting's tolerance), F_n's rate there is ~0, and
 *    the minimum recurs half a period later with the same value (the
 *    half-period symmetry the envelope's corner test relies on).
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "solve/periodic_internal.h"
#include "usm.h"

#include "check.h"

int main(void)
{
    const usm_model *m = usm_model_variant("3dof", "imperfect");
    usm_periodic *w = usm_periodic_alloc(m);
    usm_params p;
    usm_periodic_result res;
    usm_params_default(&p);
    p.phase_error = 0.4;
    p.mode_split = 0.01;
    if (!CHECK(usm_periodic_solve(w, &p, NULL, NULL, &res) == USM_OK, "solve: %s",
               usm_periodic_message(w)))
        return 1;
    const double T = res.period, Omega = 2 * 3.14159265358979323846 / T;
    int idx[USM_MAX_NX];
    double scale[USM_MAX_NX], r[USM_MAX_NX], col[USM_MAX_NX];
    const int k = usm_periodic_shoot_layout(w, idx, scale);

    /* 1: the orbit's state at t1 = 0.3 T, displaced off it, so that the
     * column is not only -(B - I) f */
    const double t1 = 0.3 * T;
    double x1[USM_MAX_NX];
    usm_periodic_shoot_set_t0(w, 0.0);
    CHECK(usm_periodic_shoot(w, &p, NULL, 0.0, res.x0, r, NULL) == USM_OK, "shot");
    CHECK(usm_periodic_shoot_state_at(w, t1, x1) == USM_OK, "state at t1");
    for (int a = 0; a < k; ++a)
        x1[idx[a]] += 1e-3 * scale[idx[a]];
    usm_periodic_shoot_set_t0(w, t1);
    CHECK(usm_periodic_shoot(w, &p, NULL, 0.0, x1, r, NULL) == USM_OK, "shot at t1");
    CHECK(usm_periodic_shoot_t0_column(w, col) == USM_OK, "t0 column");
    /* the difference converged in its step: the largest change between
     * steps 1e-3 and 1e-4 (of T / 2 pi) bounds its error */
    double dif[2][USM_MAX_NX], worst = 0, size = 0, spread = 0;
    for (int s = 0; s < 2; ++s) {
        const double h = (s == 0 ? 1e-3 : 1e-4) / Omega;
        double rp[USM_MAX_NX], rm[USM_MAX_NX];
        usm_periodic_shoot_set_t0(w, t1 + h);
        CHECK(usm_periodic_shoot_state(w, &p, x1, rp) == USM_OK, "shot at t1 + h");
        usm_periodic_shoot_set_t0(w, t1 - h);
        CHECK(usm_periodic_shoot_state(w, &p, x1, rm) == USM_OK, "shot at t1 - h");
        for (int a = 0; a < k; ++a)
            dif[s][a] = (rp[a] - rm[a]) / (2 * h);
    }
    for (int a = 0; a < k; ++a) {
        worst = fmax(worst, fabs(col[a] - dif[1][a]));
        spread = fmax(spread, fabs(dif[0][a] - dif[1][a]));
        size = fmax(size, fabs(col[a]));
    }
    printf("dr/dt0: closed form against central differences %.2e of its size %.3g (the "
           "differences' spread %.2e)\n", worst / size, size, spread / size);
    /* both ~1e-4: the differences' spread between the two steps (the
     * period map's noise, ~1e-10 of the scales, over a step of 1e-4 rad,
     * and truncation at 1e-3) is as large as their distance to the closed
     * form; a wrong term would be of the column's size */
    CHECK(worst <= 1e-3 * size, "dr/dt0: %.3g of %.3g", worst, size);

    /* 2 and 3: the minima of F_n over the orbit */
    double t[8], v[8], x[USM_MAX_NX];
    usm_periodic_shoot_set_t0(w, 0.0);
    CHECK(usm_periodic_shoot(w, &p, NULL, 0.0, res.x0, r, NULL) == USM_OK, "shot");
    const int n = usm_periodic_shoot_extremes(w, USM_PERIODIC_Q_F_N, -1.0, 8, t, v);
    printf("F_n minima: %d, %.12g N at %.6f T, %.12g N at %.6f T; F_n_min %.12g N\n", n, v[0],
           t[0] / T, n > 1 ? v[1] : NAN, n > 1 ? t[1] / T : NAN, res.F_n_min);
    if (CHECK(n == 2, "F_n: %d minima, not 2", n)) {
        CHECK(fabs(v[0] - v[1]) <= 1e-9 * res.F_n_max, "the minima %.12g and %.12g", v[0], v[1]);
        const double dt = fabs(t[1] - t[0]);
        CHECK(fabs(dt - 0.5 * T) <= 1e-6 * T, "the minima %.6f T apart", dt / T);
        CHECK(fabs(v[0] - res.F_n_min) <= 1e-9 * res.F_n_max, "the least minimum %.12g, "
              "F_n_min %.12g", v[0], res.F_n_min);
    }
    CHECK(usm_periodic_shoot_half_period_asymmetry(w, USM_PERIODIC_Q_F_N) <=
              1e-8 * res.F_n_max,
          "half-period asymmetry %.3g N",
          usm_periodic_shoot_half_period_asymmetry(w, USM_PERIODIC_Q_F_N));
    /* dF_n/dt at 0.1 T against F_n along the orbit */
    const double ta = 0.1 * T, e = 1e-3 / Omega;
    double fa, ra, fp, fm, xp[USM_MAX_NX], xm[USM_MAX_NX];
    CHECK(usm_periodic_shoot_state_at(w, ta, x) == USM_OK &&
              usm_periodic_shoot_state_at(w, ta + e, xp) == USM_OK &&
              usm_periodic_shoot_state_at(w, ta - e, xm) == USM_OK,
          "states along the orbit");
    CHECK(usm_periodic_quantity_rate(w, &p, USM_PERIODIC_Q_F_N, ta, x, &fa, &ra) == USM_OK &&
              usm_periodic_quantity_rate(w, &p, USM_PERIODIC_Q_F_N, ta + e, xp, &fp, NULL) ==
                  USM_OK &&
              usm_periodic_quantity_rate(w, &p, USM_PERIODIC_Q_F_N, ta - e, xm, &fm, NULL) ==
                  USM_OK,
          "F_n along the orbit");
    const double fd = (fp - fm) / (2 * e);
    printf("dF_n/dt at 0.1 T: %.10g N/s, along the orbit %.10g (%.1e)\n", ra, fd,
           fabs(ra / fd - 1));
    CHECK(fabs(ra / fd - 1) <= 1e-6, "dF_n/dt %.10g, along the orbit %.10g", ra, fd);
    /* the orbit shot from its minimum's time */
    if (n >= 1) {
        double xs[USM_MAX_NX], g, gd, res_t = 0;
        CHECK(usm_periodic_shoot_state_at(w, t[0], xs) == USM_OK, "state at the minimum");
        usm_periodic_shoot_set_t0(w, t[0]);
        CHECK(usm_periodic_shoot(w, &p, NULL, 0.0, xs, r, NULL) == USM_OK, "shot at t*");
        for (int a = 0; a < k; ++a)
            res_t = fmax(res_t, fabs(r[a]));
        CHECK(usm_periodic_quantity_rate(w, &p, USM_PERIODIC_Q_F_N, t[0], xs, &g, &gd) == USM_OK,
              "F_n at t*");
        printf("shot from t* = %.6f T: residual %.2e, F_n %.12g N, dF_n/dt %.3g N/s "
               "(%.1e of F_n_max Omega)\n",
               t[0] / T, res_t, g, gd, fabs(gd) / (res.F_n_max * Omega));
        CHECK(res_t <= 1e-8, "the orbit from t*: residual %.3g", res_t);
        CHECK(fabs(g - v[0]) <= 1e-9 * res.F_n_max, "F_n(t*) %.12g, the minimum %.12g", g, v[0]);
        CHECK(fabs(gd) <= 1e-6 * res.F_n_max * Omega, "dF_n/dt(t*) %.3g", gd);
    }
    usm_periodic_free(w);
    return failures != 0;
}
