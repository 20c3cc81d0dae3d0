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

/* ---- the shooting problem posed to a continuation (study/periodic_sweep.c) ----
 *
 * The zero problem of the orbit: r(x0, lambda) = 0, r_a = (x_i(t0 + T) -
 * x_i(t0) - 2 pi [i = phi]) / scale_i over the k non-cyclic components i,
 * in the unknowns (those components of x0, the parameter lambda).  The
 * scales, tolerances and t0 are those of the last usm_periodic_solve of w
 * (its start orbit), held fixed so that r is one function along a branch. */

/* The non-cyclic components' indices (k of them) into idx and the state
 * scales (nx values) into scale; returns k. */
int usm_periodic_shoot_layout(const usm_periodic *w, int *idx, double *scale);

/* The state scales (nx values, as usm_periodic_shoot_layout gives them)
 * restored: a solve in between (usm_periodic_saturation) sets its own. */
void usm_periodic_shoot_set_scale(usm_periodic *w, const double *scale);

/* r at (x0 (nx values; the cyclic ones carried), p) into r (k values) and,
 * when J is not NULL, its Jacobian (k rows of k + 1, row-major, physical
 * units): the non-cyclic block of the monodromy minus I, scaled as r, then
 * dr/dlambda of the parameter `info` by a forward difference of step dlam
 * (one period of the state alone; dlam 0: not formed, the column 0, for a
 * Newton with the parameter held).  The period map at (x0, p), its samples
 * and monodromy are kept for usm_periodic_shoot_result and
 * usm_periodic_shoot_stick_excess.  USM_OK, or USM_EFAILED (reason in
 * usm_periodic_message). */
int usm_periodic_shoot(usm_periodic *w, const usm_params *p, const usm_param_info *info,
                       double dlam, const double *x0, double *r, double *J);

/* r alone at (x0, p), one period of the state without its variational
 * equations (a tenth of usm_periodic_shoot's cost): for a chord Newton.
 * Nothing is kept (usm_periodic_shoot_result then fails).  USM_OK or
 * USM_EFAILED. */
int usm_periodic_shoot_state(usm_periodic *w, const usm_params *p, const double *x0, double *r);

/* The orbit of the last usm_periodic_shoot as usm_periodic_solve reports
 * it (multipliers, extremes, validity; residual the shot's, iterations 0),
 * converged set: the caller says it is on the branch.  USM_OK, or
 * USM_EFAILED (no shot, or the eigenproblem failed). */
int usm_periodic_shoot_result(usm_periodic *w, usm_periodic_result *out);

/* The largest |F_t| - mu0 F_n over the orbit of the last shot, located on
 * the orbit as its other extremes (the extreme sample, then the zero of the
 * rate between its neighbours by Brent on the re-integrated state): the
 * friction the stick needs beyond what it has; its zero is
 * friction_needed_max = mu0 where F_n > 0, and it stays defined where the
 * contact opens.  NaN without a shot. */
double usm_periodic_shoot_stick_excess(usm_periodic *w);

/* Of the last shot's orbit alone, as usm_periodic_shoot_result reports them
 * (F_n_min; floquet.max_modulus) for a tenth of its cost: a continuation's
 * test functions.  NaN without a shot or when the eigenproblem fails. */
double usm_periodic_shoot_F_n_min(usm_periodic *w);
double usm_periodic_shoot_max_modulus(usm_periodic *w);

/* The monodromy of the last shot with the cyclic directions deflated: the
 * block R of Qc^T Psi Qc (solve/multipliers.h) in the balanced coordinates
 * of the variational integration, nk x nk row-major (nk the non-cyclic
 * multipliers, returned; -1 without a shot).  Its eigenvalues are the
 * multipliers; unlike the physical B (rounded to cond(S) eps, ~1e-5 where
 * the tilt is 1e-5 rad) it carries the integration's accuracy, for the
 * envelope's bordered systems on R - mu I. */
int usm_periodic_shoot_reduced(usm_periodic *w, double *R);

/* The multipliers of the last shot alone (usm_periodic_shoot_result's
 * floquet without the orbit's outputs and extremes).  USM_OK, or
 * USM_EFAILED without a shot or when the eigensolver fails. */
int usm_periodic_shoot_multipliers(usm_periodic *w, usm_floquet_result *f);

/* Hold (1) or release (0) the balancing of the shots' coordinates: held, a
 * shot keeps the diagonal scaling D of the last one (D is a power of two a
 * component and jumps between neighbouring states), so that R of nearby
 * shots is in one smooth basis and its differences are derivatives. */
void usm_periodic_shoot_hold_balance(usm_periodic *w, int hold);

/* ---- an extreme's time as an unknown (runtime/envelope/envelope_periodic.c) ----
 *
 * Where F_n has two equal minima a period (a symmetry of the imperfections)
 * their lesser has a corner in the parameters; each minimum alone is smooth.
 * Posed with the shooting's start time t0 at the extreme's time t*, the
 * extreme is F_n(x0, t0) with dF_n/dt(x0, t0) = 0: both functions of the
 * unknowns without an integration, and r of (x0, t0, p). */

typedef enum {
    USM_PERIODIC_Q_F_N = 0,          /* the normal force */
    USM_PERIODIC_Q_STICK_EXCESS = 1  /* |F_t| - mu0 F_n */
} usm_periodic_quantity;

/* The shooting's start time (usm_periodic_solve sets it from its options;
 * usm_periodic_shoot reads it). */
void usm_periodic_shoot_set_t0(usm_periodic *w, double t0);

/* dr/dt0 at the last shot (k values, scaled as r): f(x1, t0 + T) - B f(x0,
 * t0) on the non-cyclic rows, f the vector field and B the monodromy, the
 * closed form of moving the start time with x0 held.  USM_OK, or
 * USM_EFAILED without a shot. */
int usm_periodic_shoot_t0_column(usm_periodic *w, double *col);

/* The quantity and, when dvalue is not NULL, its time derivative along the
 * motion (the central difference along the vector field, as the orbit's
 * extremes are located) at the state x at time t, parameters p.  Sets w's
 * parameters: a later usm_periodic_shoot_state_at needs the shot's.  USM_OK
 * or USM_EFAILED (the motion is singular there). */
int usm_periodic_quantity_rate(usm_periodic *w, const usm_params *p, usm_periodic_quantity which,
                               double t, const double *x, double *value, double *dvalue);

/* The same with the central difference's step given, in radians of Omega
 * t (usm_periodic_quantity_rate's is 1e-5): where the quantity is formed
 * with cancellation its rounding over 1e-5 swamps the rate.  The stick
 * excess takes F_t from the accelerations phi'' and psi'' (~1e9 rad/s^2
 * each) that nearly cancel, so it is rounded to ~1e-12 of F_n_max per ulp
 * of the state: its rate is noisy at 1e-7 of F_n_max Omega over 1e-5, at
 * 1e-10 over 1e-2, where the truncation error is 4e-8 (it moves the
 * extreme's time by as much, and its value by 1e-15).  USM_OK, or
 * USM_EFAILED (the motion is singular there, or step not in (0, 1)). */
int usm_periodic_quantity_rate_step(usm_periodic *w, const usm_params *p,
                                    usm_periodic_quantity which, double t, const double *x,
                                    double step, double *value, double *dvalue);

/* The local maxima (sign +1) or minima (-1) of the quantity over the last
 * shot's orbit, each sample extreme (cyclic) located as the orbit's extremes
 * are: their times in [t0, t0 + T) into t and values into v, the most
 * extreme first, at most max.  The count, or -1 without a shot. */
int usm_periodic_shoot_extremes(usm_periodic *w, usm_periodic_quantity which, double sign,
                                int max, double *t, double *v);

/* The largest |q(t + T/2) - q(t)| over the last shot's samples: where it
 * is at the integration's noise the orbit has the half-period symmetry of
 * the excitation (the imperfections force at 2 Omega), and each extreme of
 * q recurs half a period later with the same value.  NaN without a shot. */
double usm_periodic_shoot_half_period_asymmetry(usm_periodic *w, usm_periodic_quantity which);

/* The state of the last shot's orbit at time t (any: taken modulo the
 * period), re-integrated from the sample before it.  USM_OK or USM_EFAILED. */
int usm_periodic_shoot_state_at(usm_periodic *w, double t, double *x);

#endif /* USM_PERIODIC_INTERNAL_H */
