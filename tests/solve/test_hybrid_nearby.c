/* An orbit with separation from a nearby start (usm_hybrid_solve_from; docs/unilateral.md,
 * "Cost"): a continuation's next orbit, solved with the solver that solved
 * the last one, begins Newton with that orbit's LU (chord maps without the
 * monodromy) and needs one map with the monodromy, its check and its
 * multipliers (out.iterations 0), at times two; before, always a first map
 * with the monodromy at the start and a second at the converged orbit, or
 * more: 9 maps for the four orbits here, now 4 (measured; at most 6
 * allowed).
 *
 * Independent truth: the same orbit from the same start by a fresh solver
 * (no last orbit: Newton from a map with the monodromy at the start).  Both
 * converge to Newton's 1e-9, so the states agree to about 1e-8 of their
 * scales and the multipliers, the mean speed and the open fraction to far
 * below what the sweeps report.
 *
 * 4-DOF imperfect_unilateral, the stable two-impact orbit from mode split 1.4 % on in
 * steps of 5e-5 (bench/bench_hybrid_cont's branch), four orbits, each
 * from the last one. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "usm.h"
#include "usm_periodic.h"

#define NAME "4dof_imperfect_unilateral"

int main(void)
{
    const usm_model *m = usm_model_find(NAME);
    usm_hybrid *h = m ? usm_hybrid_alloc(m) : NULL;
    usm_params p;
    usm_hybrid_result last;
    if (!CHECK(h != NULL, "no hybrid solver for %s", NAME))
        return 1;
    usm_params_default(&p);
    p.mode_split = 0.014;
    if (!CHECK(usm_hybrid_solve(h, &p, NULL, &last) == USM_OK, "from rest: %s",
               usm_hybrid_message(h)))
        return 1;
    int maps = 0, n = 0;
    for (int k = 1; k <= 4; ++k) {
        usm_hybrid_result r, ref;
        p.mode_split = 0.014 + 5e-5 * k;
        const int rc = usm_hybrid_solve_from(h, &p, NULL, last.t0, last.x0, &r);
        usm_hybrid *fresh = usm_hybrid_alloc(m);
        const int rc_ref = fresh ? usm_hybrid_solve_from(fresh, &p, NULL, last.t0, last.x0, &ref)
                                 : USM_EFAILED;
        usm_hybrid_free(fresh);
        if (!CHECK(rc == USM_OK && rc_ref == USM_OK, "mode split %g: %s", p.mode_split,
                   usm_hybrid_message(h)))
            break;
        double dx = 0;
        for (int i = 0; i < r.nx; ++i)
            dx = fmax(dx, fabs(r.x0[i] - ref.x0[i]) / fmax(fabs(ref.x0[i]), 1e-300));
        const double dl = fabs(r.floquet.max_modulus - ref.floquet.max_modulus);
        const double dw = fabs(r.rotor_speed_mean / ref.rotor_speed_mean - 1);
        const double dopen = fabs(r.separation_fraction - ref.separation_fraction);
        printf("mode split %.5f %%: %s, maps with the monodromy %d (fresh solver %d); against "
               "the fresh solver: state %.2g, max |lambda| %.2g, speed %.2g, open fraction %.2g\n",
               100 * p.mode_split, r.mode_sequence, r.iterations + 1, ref.iterations + 1, dx, dl,
               dw, dopen);
        maps += r.iterations + 1;
        ++n;
        CHECK(strcmp(r.mode_sequence, ref.mode_sequence) == 0, "sequence %s, fresh %s",
              r.mode_sequence, ref.mode_sequence);
        /* measured: state 9e-9 to 1.3e-7 relative (its largest, the twist
         * angle's, whose column is weak), max |lambda|, speed and open
         * fraction 1e-9 to 5e-9 */
        CHECK(dx < 1e-6 && dl < 1e-7 && dw < 1e-8 && dopen < 1e-8,
              "mode split %g: against the fresh solver state %g, max |lambda| %g, speed %g, "
              "open %g", p.mode_split, dx, dl, dw, dopen);
        last = r;
    }
    usm_hybrid_free(h);
    CHECK(n == 4 && maps <= 6, "%d maps with the monodromy for %d orbits, want at most 6 for 4",
          maps, n);
    printf("%s: %d failures\n", __FILE__, failures);
    return failures != 0;
}
