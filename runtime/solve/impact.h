/* impact.h: the rotor reaching the stator (the contact that may open,
 * closure = unilateral; usm_simulate.h "Unilateral contact",
 * docs/unilateral.md), one rule for the event-driven simulation (simulate.c)
 * and the shooting of orbits with separation (hybrid.c), so that both decide
 * alike: a period map whose resets differ from the simulation's would find
 * orbits the motor does not run on.  Internal to libusm; not installed.
 *
 * At a zero of the gap, with the approach velocity v = -gap' of the open
 * state y:
 *   - no impact when the rotor does not approach (v <= 0), or touches slower
 *     than v_land while the closed mode would pull it off at once (F_n < 0):
 *     it grazes and stays off;
 *   - otherwise Newton's impact (the generated impact_stick), or, in slip
 *     models, sliding with |P_t| = mu0 P_n (impact_slide) where sticking
 *     needs |P_t| > mu0 P_n (the stick model sticks regardless, and counts
 *     it);
 *   - the rotor lands (the closed mode follows) unless it leaves faster than
 *     v_land or the closed mode would pull (F_n < 0 after the impact).
 */
#ifndef USM_SOLVE_IMPACT_H
#define USM_SOLVE_IMPACT_H

#include "usm.h"

/* F_n of the closed mode at the open state y (its first nx entries) at t;
 * NaN where it cannot be evaluated. */
typedef double (*usm_impact_fn)(void *ctx, double t, const double *y);

typedef struct usm_impact_outcome {
    int impact;     /* 0: a graze or no approach (y unchanged, nothing else set) */
    double v;       /* approach velocity -gap' before [m/s] */
    double v_after; /* gap' after the impact [m/s] */
    int slide;      /* slip models: the sliding impulse was applied */
    int slipping;   /* stick model: sticking needs more than mu0 P_n */
    int lands;      /* the closed mode follows */
} usm_impact_outcome;

/* Apply the rule to the open state y (ny entries) of model m at t; yplus
 * (ny) receives the state after (y itself without an impact) and, when R is
 * not NULL, R (ny x ny, row-major) the impact's Jacobian dy+/dy.  closed_Fn
 * is called at most twice.  0, or -1 when the state after is not finite. */
int usm_impact_resolve(const usm_model *m, const usm_params *p, double v_land, double t,
                       const double *y, usm_impact_fn closed_Fn, void *ctx, double *yplus,
                       double *R, usm_impact_outcome *o);

#endif /* USM_SOLVE_IMPACT_H */
