/* The impact map of the orbits with separation (usm_hybrid_impact_map,
 * solve/hybrid_internal.h: the section at a landing impact, on which the
 * envelope's separation_grazing curve rests), against the stroboscopic
 * period map and solver (usm_hybrid_shoot, usm_hybrid_solve_from).
 *
 * 3-DOF motor, phase error 0.905 then 0.912 rad (the `cococ` orbit, two
 * landings a period): from the stroboscopic orbit the impact map to the
 * first impact gives the state just after it; from there, over two impacts,
 * the map returns to that state (to 1e-8 of the scales: both maps solve one
 * orbit, the stroboscopic to its tolerance) one period later (to 1e-9 of the
 * period), and F_n there equals what the stroboscopic map recorded at that
 * landing (usm_hybrid_shoot_impacts; to 1e-7: the two integrations take
 * their own steps, the landing times 1e-10 of the period apart).
 */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "solve/hybrid_internal.h"
#include "usm.h"
#include "usm_periodic.h"

#include "check.h"

int main(void)
{
    const clock_t c0 = clock();
    const usm_model *m = usm_model_variant("3dof", "imperfect_unilateral");
    usm_params p;
    usm_params_default(&p);
    usm_hybrid *h = usm_hybrid_alloc(m);
    usm_hybrid_result r;
    CHECK(m && h, "model and solver");
    p.phase_error = 0.905;
    CHECK(usm_hybrid_solve(h, &p, NULL, &r) == USM_OK, "orbit at 0.905: %s",
          usm_hybrid_message(h));
    p.phase_error = 0.912;
    const usm_hybrid_result r0 = r;
    CHECK(usm_hybrid_solve_from(h, &p, NULL, r0.t0, r0.x0, &r) == USM_OK &&
              strcmp(r.mode_sequence, "cococ") == 0,
          "orbit at 0.912: %s (%s)", usm_hybrid_message(h), r.mode_sequence);
    /* the stroboscopic map's landings */
    double F[USM_MAX_NX], sc[USM_MAX_NX], J[USM_MAX_NX * USM_MAX_NX], ti[4], fi[4];
    int idx[USM_MAX_NX], nr = 0, li[4];
    CHECK(usm_hybrid_shoot(h, &p, r.t0, r.x0, idx, &nr, F, J, NULL, NULL, sc, NULL) == USM_OK,
          "stroboscopic map");
    const int ni = usm_hybrid_shoot_impacts(h, ti, fi, li, 4);
    CHECK(ni == 2 && li[0] && li[1], "two landings (%d)", ni);
    double x1[USM_MAX_NX], x2[USM_MAX_NX], t1, t2, fn0 = NAN;
    char seq[USM_HYBRID_MAX_SWITCHES + 1];
    CHECK(usm_hybrid_impact_map(h, &p, r.t0, r.x0, 1, x1, &t1, NULL, seq) == USM_OK,
          "to the first impact: %s", usm_hybrid_message(h));
    CHECK(fabs(t1 - ti[0]) <= 1e-9 * r.period, "the same landing: %.15g %.15g", t1, ti[0]);
    CHECK(usm_hybrid_impact_map(h, &p, t1, x1, 2, x2, &t2, &fn0, seq) == USM_OK,
          "over two impacts: %s", usm_hybrid_message(h));
    CHECK(strcmp(seq, "cococ") == 0, "sequence %s", seq);
    CHECK(fabs(t2 - t1 - r.period) <= 1e-9 * r.period, "a period on: %.3g of it",
          (t2 - t1 - r.period) / r.period);
    double worst = 0;
    for (int a = 0; a < nr; ++a) {
        const int i = idx[a];
        /* phidot in the spin phidot + psidot, as the scales are */
        const double d = x2[i] - x1[i] - (i == m->x_phi ? 6.283185307179586 : 0.0) +
                         (i == m->x_phidot ? x2[m->x_psidot] - x1[m->x_psidot] : 0.0);
        worst = fmax(worst, fabs(d) / sc[i]);
    }
    CHECK(worst <= 1e-8, "returns to its state: %.3g of the scales", worst);
    CHECK(fabs(fn0 - fi[0]) <= 1e-7 * fabs(fi[0]) && fn0 > 0.1,
          "F_n after the landing %.12g, stroboscopic %.12g", fn0, fi[0]);
    printf("returns to %.2g of the scales; F_n after the landing %.9g N; %.2f s CPU\n", worst,
           fi[0], (double)(clock() - c0) / CLOCKS_PER_SEC);
    usm_hybrid_free(h);
    return failures != 0;
}
