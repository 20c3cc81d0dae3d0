/* usm_design.h: design answers on a stationary solution:
 * parameter sensitivities of the stationary outputs and of the largest
 * Floquet modulus.  (Power and efficiency are fields of usm_steady_solution.)
 *
 * Stationary outputs: implicit function theorem on the generated residual
 * Jacobians, du/dp = -(dr/du)^-1 dr/dp, then dy/dp = dy/du du/dp + dy/dp|_u
 * with the generated <model>_steady_design_jacobian.
 *
 * max_modulus: eigenvalue perturbation d(lambda) = w^T dB v / (w^T v) of the
 * monodromy matrix B computed exactly as usm_floquet_compute's exponential
 * method (product of matrix exponentials at the sub-interval midpoints, frame
 * A, 64 and 128 sub-intervals, Richardson; one exponential when the model's
 * linearisation is constant, t0_independent), over [t0, t0 + T] with t0 = 0
 * unless usm_sensitivity_set_t0 says otherwise.  dB is the exact
 * derivative of that product: the Frechet derivative of each exponential in
 * the direction of its exponent's derivative, which comes from the generated
 * <model>_floquet_direction (second derivatives of the equations of motion)
 * and the implicit-function du/dp.  Used in adjoint form: one pair of block
 * exponentials per sub-interval serves every parameter.  Chosen over CVODES
 * forward sensitivities because the derivative is then exact for the method
 * (finite differences of the solver agree to rounding, not to integrator
 * tolerance) and costs no ODE solve per parameter.
 *
 * Axisymmetric models (I_yy taken equal to I_xx): the derivative in I_xx moves
 * I_yy with it; the one in I_yy is 0.
 *
 * Thread safety: no global mutable state; distinct usm_sensitivity objects may
 * be used from distinct threads at the same time, one object must not be
 * shared without a lock.
 */
#ifndef USM_DESIGN_H
#define USM_DESIGN_H

#include "usm.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The outputs whose derivatives usm_sensitivity_compute gives. */
enum {
    USM_SENS_THETA = 0,        /* tilt [rad] */
    USM_SENS_ROTOR_SPEED = 1,  /* phidot_R [1/s] */
    USM_SENS_F_N = 2,          /* normal contact force [N] */
    USM_SENS_F_T = 3,          /* tangential contact force [N] */
    USM_SENS_EFFICIENCY = 4,   /* power_out / power_in */
    USM_SENS_STICK_MARGIN = 5, /* mu0 F_n - F_t [N] */
    USM_SENS_MAX_MODULUS = 6,  /* largest non-cyclic Floquet modulus (from t0, default 0) */
    USM_SENS_POWER_IN = 7,     /* [W] */
    USM_SENS_POWER_OUT = 8,    /* [W] */
    USM_SENS_COUNT = 9
};

/* Name of output k ("theta", "rotor_speed", ...), NULL when out of range. */
const char *usm_sensitivity_output_name(int k);
/* Index of the output called `name`, or -1. */
int usm_sensitivity_output_find(const char *name);
/* The outputs reported unless the client names others (usm sensitivity's
 * --of, the Python package's of=None): the first seven, theta .. max_modulus;
 * power_in and power_out are asked for by name. */
void usm_sensitivity_outputs_default(int want[USM_SENS_COUNT]);

/* Sub-intervals of the exponential product (as usm_floquet_options_default). */
#define USM_SENSITIVITY_STEPS 64

/* Values and derivatives d[k][j] = d(output k)/d(parameter j), j in usm_params
 * field order.  defined[k] = 0 where output k's derivative does not exist or
 * was not asked for; why[k] says which (e.g. a repeated multiplier). */
typedef struct usm_sensitivity_result {
    double value[USM_SENS_COUNT];
    double d[USM_SENS_COUNT][USM_NPARAMS];
    int defined[USM_SENS_COUNT];
    char why[USM_SENS_COUNT][USM_MSG_LEN];
    double multiplier_re, multiplier_im; /* the multiplier of largest modulus */
} usm_sensitivity_result;

/* Workspace of one model (opaque). */
typedef struct usm_sensitivity usm_sensitivity;

/* Workspace for model m (not NULL), or NULL when out of memory. */
usm_sensitivity *usm_sensitivity_alloc(const usm_model *m);
/* Free s; NULL is allowed. */
void usm_sensitivity_free(usm_sensitivity *s);

/* Sensitivities of the stationary solution `sol` (a root of usm_steady_solve
 * for p).  floquet = 0 skips max_modulus.  USM_OK; USM_EFAILED (message in
 * usm_sensitivity_message) when the residual Jacobian is singular (a fold:
 * du/dp does not exist) or an exponential or eigen problem fails.  An
 * undefined single derivative (efficiency at power_in <= 0, a repeated
 * multiplier) is not a failure: defined[k] = 0 and why[k] says so.
 * USM_EINPUT for a model with imperfections (m->imperfect: its stationary
 * solution is the ideal motor's; use the variant twist_integrated). */
int usm_sensitivity_compute(usm_sensitivity *s, const usm_params *p,
                            const usm_steady_solution *sol, int floquet,
                            usm_sensitivity_result *out);
/* The value alone: the largest non-cyclic Floquet modulus of `sol` as
 * usm_sensitivity_compute computes it (the function it differentiates).
 * USM_OK or USM_EFAILED. */
int usm_sensitivity_max_modulus(usm_sensitivity *s, const usm_params *p,
                                const usm_steady_solution *sol, double *value);
/* The start t0 [s] of the Floquet period of max_modulus for the following
 * computes (default 0, the paper's convention; usm_floquet_compute's t0).
 * Derivatives are taken at fixed t0: d/df moves the period's end, not its
 * start.  Only the paper's twist law depends on it (usm_floquet_result's
 * t0_dependent). */
void usm_sensitivity_set_t0(usm_sensitivity *s, double t0);
/* Why the last compute failed, or "". */
const char *usm_sensitivity_message(const usm_sensitivity *s);

/* The elasticity (p_j / y) dy/dp_j of output k in parameter j (the relative
 * change of y per relative change of p_j): NaN where the derivative is
 * undefined or y = 0; exactly 0 (never -0) where dy/dp_j = 0. */
double usm_sensitivity_elasticity(const usm_params *p, const usm_sensitivity_result *r, int k,
                                  int j);

#ifdef __cplusplus
}
#endif

#endif /* USM_DESIGN_H */
