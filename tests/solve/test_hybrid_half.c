/* The half map of an orbit with separation (usm_hybrid_shoot_half,
 * runtime/solve/hybrid.c), which the envelope's separation_fold curves use
 * where the orbit has the half-period symmetry.
 *
 * The 4-DOF orbit with separation at 1.94 % mode split (`cococ`: the
 * contact opens alike at both F_n minima of the period) closes under the
 * half map t0 -> t0 + T/2 (phi turned by pi), with the mode sequence `coc`;
 * the period map's monodromy on the non-cyclic components is the square of
 * the half map's (the cyclic coordinates feed no other, and the second half
 * is the first's image), so its largest multiplier is the square of the half
 * map's.  Both against the period map shot over the whole period in one
 * integration.  Before the half map, its F was the period map's and its
 * sequence `cococ`.  Measured: the half map's residual 1.8e-7 of the scales
 * (the twist angle's 9e-14 rad against its scale 5e-7 rad; the others 6e-9
 * at most, against 1e-9 to 1e-10 for the period map), B_h^2 - B 7.5e-7 of
 * B, max |mu|^2 - max |lambda| 4e-7: the symmetry holds to about 1e-7,
 * which bounds what a curve on the half map can claim.
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
    const usm_model *m = usm_model_variant("4dof", "imperfect_unilateral");
    const clock_t c0 = clock();
    usm_params p;
    usm_params_default(&p);
    p.mode_split = 0.0194;
    usm_hybrid *h = usm_hybrid_alloc(m);
    usm_hybrid_result r;
    CHECK(m && h, "model and solver");
    if (!m || !h)
        return 1;
    const int rc = usm_hybrid_solve(h, &p, NULL, &r);
    CHECK(rc == USM_OK && strcmp(r.mode_sequence, "cococ") == 0, "the orbit: %s (%s)",
          rc == USM_OK ? r.mode_sequence : "-", usm_hybrid_message(h));
    if (rc != USM_OK)
        return 1;
    int idx[USM_MAX_NX], nr = 0, nrh = 0;
    double Ff[USM_MAX_NX], Fh[USM_MAX_NX], Jf[USM_MAX_NX * USM_MAX_NX],
        Jh[USM_MAX_NX * USM_MAX_NX], sc[USM_MAX_NX], modf = NAN, modh = NAN;
    char seqf[USM_HYBRID_MAX_SWITCHES + 1], seqh[USM_HYBRID_MAX_SWITCHES + 1];
    CHECK(usm_hybrid_shoot(h, &p, r.t0, r.x0, idx, &nr, Ff, Jf, &modf, NULL, sc, seqf) == USM_OK,
          "the period map: %s", usm_hybrid_message(h));
    usm_hybrid_shoot_half(h, 1);
    CHECK(usm_hybrid_shoot(h, &p, r.t0, r.x0, NULL, &nrh, Fh, Jh, &modh, NULL, NULL, seqh) ==
              USM_OK,
          "the half map: %s", usm_hybrid_message(h));
    usm_hybrid_shoot_half(h, 0);
    CHECK(nrh == nr, "the same components (%d, %d)", nrh, nr);
    CHECK(strcmp(seqh, "coc") == 0, "the half map's sequence: %s", seqh);
    /* rows and columns in the spin coordinates (phidot + psidot, psidot) */
    int ap = -1, as = -1;
    for (int a = 0; a < nr; ++a) {
        ap = idx[a] == m->x_phidot ? a : ap;
        as = idx[a] == m->x_psidot ? a : as;
    }
    CHECK(ap >= 0 && as >= 0, "phidot and psidot among the unknowns");
    if (ap < 0 || as < 0)
        return 1;
    Ff[ap] += Ff[as];
    Fh[ap] += Fh[as];
    double res_f = 0, res_h = 0;
    for (int a = 0; a < nr; ++a) {
        res_f = fmax(res_f, fabs(Ff[a]) / sc[idx[a]]);
        res_h = fmax(res_h, fabs(Fh[a]) / sc[idx[a]]);
    }
    CHECK(res_f <= 1e-8, "the orbit closes under the period map (%.2g)", res_f);
    CHECK(res_h <= 1e-6, "and under the half map (%.2g)", res_h);
    double Bf[USM_MAX_NX * USM_MAX_NX], Bh[USM_MAX_NX * USM_MAX_NX];
    for (int b = 0; b < nr; ++b) {
        Jf[ap * nr + b] += Jf[as * nr + b];
        Jh[ap * nr + b] += Jh[as * nr + b];
    }
    for (int a = 0; a < nr; ++a)
        for (int b = 0; b < nr; ++b) {
            const double s = sc[idx[b]] / sc[idx[a]];
            Bf[a * nr + b] = (Jf[a * nr + b] + (a == b)) * s;
            Bh[a * nr + b] = (Jh[a * nr + b] + (a == b)) * s;
        }
    double diff = 0, size = 0;
    for (int a = 0; a < nr; ++a)
        for (int b = 0; b < nr; ++b) {
            double sq = 0;
            for (int k = 0; k < nr; ++k)
                sq += Bh[a * nr + k] * Bh[k * nr + b];
            diff = fmax(diff, fabs(sq - Bf[a * nr + b]));
            size = fmax(size, fabs(Bf[a * nr + b]));
        }
    CHECK(diff <= 5e-6 * size, "B = B_h^2 on the non-cyclic components, scaled (%.2g of %.3g)",
          diff, size);
    CHECK(fabs(modh * modh - modf) <= 2e-6, "max |mu|^2 %.12f against max |lambda| %.12f",
          modh * modh, modf);
    printf("half map: residual %.2g, |B_h^2 - B| %.2g of %.3g, max |mu|^2 %.12f, max |lambda| "
           "%.12f; CPU %.2f s\n", res_h, diff, size, modh * modh, modf,
           (double)(clock() - c0) / CLOCKS_PER_SEC);
    usm_hybrid_free(h);
    return failures != 0;
}
