/* hybrid_internal.h: the shooting condition of an orbit with separation as a
 * zero problem, for the continuation engine's sweeps (study/).  Room-private:
 * not installed, not part of the API. */
#ifndef USM_HYBRID_INTERNAL_H
#define USM_HYBRID_INTERNAL_H

#include "usm_periodic.h"

/* The shooting condition of usm_hybrid_solve_from at (p, ts, x0): its scales
 * and v_land set from x0 as that solve sets them, one period map, and into
 * F[a] = x1[i] - x0[i] (less 2 pi in phi) for the non-cyclic components
 * i = idx[a] (a < *nr; idx and *nr filled when not NULL).  With J not NULL
 * the map carries the monodromy with its saltation matrices: J = dF/dw on
 * those components (nr x nr, row-major) in the spin coordinates w of x0
 * (w = x but for w[x_phidot] = phidot + psidot: in x the columns of phidot
 * and psidot are nearly equal and large, their difference carries the
 * multipliers, and B - I is ill-conditioned beyond the map's noise),
 * *max_modulus its largest |lambda| but the cyclic ones, that multiplier
 * (re, im) into crit when not NULL, and the scales of w (nx values) into
 * scale when not NULL.  seq: the map's mode sequence, when not NULL.  USM_OK,
 * or USM_EINPUT / USM_EFAILED (usm_hybrid_message). */
int usm_hybrid_shoot(usm_hybrid *h, const usm_params *p, double ts, const double *x0,
                     int *idx, int *nr, double *F, double *J, double *max_modulus,
                     double crit[2], double *scale, char seq[USM_HYBRID_MAX_SWITCHES + 1]);

/* half 1: usm_hybrid_shoot maps from ts to ts + T / 2 (F = x(ts + T/2) -
 * x(ts) on the non-cyclic components, less pi in phi; the drive's phase turns by pi), J that map's monodromy
 * less I; 0 (the default): the period.  An orbit with the half-period symmetry (the
 * imperfections force at 2 Omega: both openings of a `cococ` orbit alike)
 * is a fixed point of the half map, whose multipliers mu are the roots of
 * the period map's (lambda = mu^2): a multiplier +1 of the period map where
 * the branch goes on is mu = -1, a symmetry-breaking bifurcation, at which
 * the period map's fold system is singular and the half map's is not.  The
 * solve and the period map (usm_hybrid_solve*, usm_hybrid_period_map) are
 * never affected; set it back to 0 before them. */
void usm_hybrid_shoot_half(usm_hybrid *h, int half);

/* The impacts of the last period map (usm_hybrid_shoot's, or any other):
 * their count, and of the first max of them, in order, the time into t, F_n
 * of the closed mode at the state just after the impact into fn (what the
 * landing rule of solve/impact.h tests: the rotor lands where it is >= 0)
 * and whether the rotor landed into lands (each may be NULL).  F_n just
 * after the impact that closes a contact phase is the smooth function that
 * vanishes as that phase shrinks to nothing (envelope_hybrid_grazing.c):
 * its impact is still there, and still the same one in order, on both
 * sides. */
int usm_hybrid_shoot_impacts(const usm_hybrid *h, double *t, double *fn, int *lands, int max);

/* The impact map: from the closed state x0 at ts (the state just after an
 * impact) to the state just after the k-th impact on (the first nx entries
 * of the open or closed state: the same closed coordinates whether the
 * rotor lands or only touches) into x1, its time into *t1, and F_n of the
 * closed mode at (x0, ts) into *fn0 (NULL allowed).  Where F_n
 * of the closed mode at (x0, ts) is negative the rotor leaves at once (a
 * closed phase of length 0).  A section that moves with the orbit's
 * impact: the stroboscopic map of usm_hybrid_shoot needs its fixed section
 * time inside a closed phase, which has none left where the closed phases
 * shrink to nothing.  No monodromy.  USM_OK, or USM_EINPUT / USM_EFAILED
 * (usm_hybrid_message). */
int usm_hybrid_impact_map(usm_hybrid *h, const usm_params *p, double ts, const double *x0,
                          int k, double *x1, double *t1, double *fn0,
                          char seq[USM_HYBRID_MAX_SWITCHES + 1]);

#endif /* USM_HYBRID_INTERNAL_H */
