/* periodic_internal.h: what the writers of a periodic orbit (write/periodic_out.c)
 * need of the shooting solver beyond usm_periodic.h.  Not installed; not part
 * of the API. */
#ifndef USM_PERIODIC_INTERNAL_H
#define USM_PERIODIC_INTERNAL_H

#include "usm_periodic.h"

/* The model w solves (usm_periodic_alloc's m). */
const usm_model *usm_periodic_model_of(const usm_periodic *w);

/* The supremum of the friction law of a slip model, max |mu(+-V)| at a
 * slip velocity V standing for infinity; NaN for a stick model. */
double usm_periodic_friction_supremum(const usm_model *m, const usm_params *p);

/* Friction saturation of a slip model (study/periodic_sweep.c): the value of
 * the parameter `info` at which F_t / F_n reaches the friction law's
 * supremum over the whole orbit and the rotor speed diverges.  There the
 * stator's motion no longer depends on the rotor speed (held at the speed
 * where the slip is 1e15 m/s, as the stationary sweep's saturation point),
 * and the limit is the stator's periodic orbit on which the mean rotor
 * acceleration vanishes: Newton on (the stator's periodicity, the rotor
 * speed's change over the period by the trapezoid rule on the samples) in
 * (the stator's state at t0, the parameter), the monodromy's columns and a
 * forward difference in the parameter.  Started from x_start (an orbit of
 * the branch near saturation) at p's value of the parameter; lambda_scale:
 * the parameter's size (the forward difference's step is 1e-7 of it);
 * converged when the periodicity is within opt->tol of the scales and
 * Newton's last change of the parameter is below lambda_tol.  USM_OK and
 * *lambda, or USM_EINPUT (not a slip model) / USM_EFAILED, the reason in
 * usm_periodic_message.  The samples are not kept (no orbit at infinite
 * speed). */
int usm_periodic_saturation(usm_periodic *w, const usm_params *p, const usm_param_info *info,
                            const double *x_start, double lambda_scale, double lambda_tol,
                            const usm_periodic_options *opt, double *lambda);

#endif /* USM_PERIODIC_INTERNAL_H */
