/* usm.h: runtime library around the generated ultrasonic-motor kernels.
 *
 * Model (paper: "Modeling and stability analysis for an ultrasonic motor"):
 * the stator of a wobbling-disk motor is a rigid body described by z-x-z Euler
 * angles (phi, theta, psi); the rotor is pressed onto it by a spring and driven
 * through frictional contact.  The generated kernels give the first-order form
 *     M(x) x' = f(x, t),
 * its Jacobians, and the stationary-solution residuals r(u) = 0 with
 * u = (theta, alpha[, phidot_R]) for the ansatz (3.1)
 *     phi = Omega t + alpha,  theta = const,  psi = -Omega t / cos(theta) + beta.
 * This library finds every stationary solution (GSL multiroot) and its Floquet
 * multipliers: eigenvalues of the monodromy matrix over T = 2 pi / Omega of the
 * linearisation  M(xbar) dx' = (df/dx - d(M v)/dx |_{v = xbar'}) dx.
 *
 * Life cycle (GSL style): usm_<thing>_alloc, usm_<thing>_<verb>, usm_<thing>_free.
 * Thread safety: no global mutable state.  Distinct objects may be used from
 * distinct threads at the same time; one object must not be shared without a
 * lock.  The parameter table and model descriptors are read-only.
 *
 * Errors: every GSL and SUNDIALS return code is checked and turned into a
 * status and a message.  GSL's default error handler aborts the process on
 * conditions this library handles itself (a singular matrix, a non-finite
 * function value); applications call gsl_set_error_handler_off() once at start
 * (the usm command does).  The handler is process-global, so the library
 * leaves that choice to the application.
 */
#ifndef USM_H
#define USM_H

#include <stddef.h>

#include "usm_kernels.h"

/* Major version of the kernel generator (derive/generate.py) whose kernels
 * this runtime is written for: the layout of usm_model and usm_params may
 * change with it.  Mixing the runtime with kernels of another major version
 * is refused at build time; regenerate the kernels. */
#define USM_EXPECTED_GENERATOR_MAJOR 2

#if !defined(USM_GENERATOR_VERSION_MAJOR)
#error "usm_kernels.h has no USM_GENERATOR_VERSION_MAJOR: the generated kernels are older than this runtime; regenerate them (python3 derive/generate.py)"
#elif USM_GENERATOR_VERSION_MAJOR != USM_EXPECTED_GENERATOR_MAJOR
#error "the generated kernels come from another generator major version (USM_GENERATOR_VERSION_MAJOR in usm_kernels.h) than this runtime expects (USM_EXPECTED_GENERATOR_MAJOR in usm.h); regenerate them (python3 derive/generate.py)"
#endif

/* Parameters, outputs and constraints by index, the couplings (USM_P_f,
 * usm_param_coupled, ...): generated, so the runtime spells no name. */
#include "usm_contracts.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Status codes; the values are the `usm` command's exit codes. */
enum {
    USM_OK = 0,          /* solved */
    USM_EFAILED = 1,     /* numerical failure (integrator, eigen solver) */
    USM_EINPUT = 2,      /* bad input: the message names the field and reason */
    USM_ENOSOLUTION = 3  /* no stationary solution for these parameters */
};

/* Length of the message buffers used by this API (messages are truncated). */
#define USM_MSG_LEN 256

/* ---- versions -------------------------------------------------------------- */

/* Version of the library, "MAJOR.MINOR.PATCH" (the CMake project version). */
const char *usm_version(void);

/* Version of the generator that wrote the kernels built into the library
 * (USM_GENERATOR_VERSION of the usm_kernels.h it was compiled with). */
const char *usm_generator_version(void);

/* ---- models ---------------------------------------------------------------- */

/* The generated model called `name` ("3dof", "4dof", "4dof_friction_tanh", ...),
 * or NULL. */
const usm_model *usm_model_find(const char *name);

/* Base model `base` ("3dof", "4dof") under variant `variant` ("paper",
 * "twist_integrated", ...; see usm_variants), or NULL if not generated. */
const usm_model *usm_model_variant(const char *base, const char *variant);

/* The variant called `name`, or NULL. */
const usm_variant_info *usm_variant_find(const char *name);

/* ---- orientation coordinates (docs/coordinates.md) ------------------- */

/* The stator's Euler angles (phi, theta, psi) and their rates from the state x
 * of model m at time t, in either coordinate set (m->coordinates): copied for
 * the z-x-z Euler angles; from the tilt vector (a, b, chi) by
 * theta = asin(sqrt(a^2 + b^2)) in [0, pi/2), phi = Omega t + atan2(a, -b)
 * taken within pi of phi_near (the branch: pass the previous value along a
 * motion), psi = chi - phi.  At theta = 0 phi is undefined (this returns
 * phi_near there) and phidot, thetadot are not finite.  Omega = 2 pi p->f.
 * USM_OK, or USM_EINPUT (euler all NaN) when m lacks its orientation indices
 * (usm_coords_layout_ok). */
int usm_coords_euler_angles(const usm_model *m, const double *x, double t,
                            const usm_params *p, double phi_near, double euler[6]);

/* The time derivatives (phidot, thetadot, psidot, phiddot, thetaddot, psiddot)
 * of the Euler angles along a motion of model m in state x with rate xdot
 * (either coordinate set; the chain rule for the tilt vector, singular at
 * theta = 0). */
int usm_coords_euler_rates(const usm_model *m, const double *x, const double *xdot,
                           const usm_params *p, double edot[6]);

/* 1 when every orientation index of m's coordinate set (x_phi ... x_psidot for
 * the Euler angles, x_a ... x_chidot for the tilt vector) is a state of m,
 * else 0.  The functions of this section return USM_EINPUT (the angles NaN)
 * or NaN for a model without them instead of reading outside x; code that
 * reads those indices itself checks this first. */
int usm_coords_layout_ok(const usm_model *m);

/* The stator tilt theta [rad] of the state x of model m in either coordinate
 * set: x[m->x_theta], or asin(sqrt(a^2 + b^2)) from the tilt vector (0 on the
 * axis, where the Euler angles are singular).  NaN when m has neither layout
 * or a^2 + b^2 >= 1. */
double usm_coords_theta(const usm_model *m, const double *x);

/* d theta/dt [rad/s] along a motion through x with rate xdot (either set; in
 * the tilt vector (a a' + b b') / (sin theta cos theta)).  NaN where it does
 * not exist: at a = b = 0 (theta has a kink there), or as usm_coords_theta. */
double usm_coords_theta_rate(const usm_model *m, const double *x, const double *xdot);

/* x_to (the state of model `to`) from x_from (the state of model `from`) at
 * time t, where `to` is `from` itself or from->other_coordinates (the same
 * assumptions in the other coordinate set): the same motion.  Every state but
 * the stator's orientation (phi_R, its rate, tau) is copied.  phi_near as for
 * usm_coords_euler_angles.  USM_OK, or USM_EINPUT when the two models are not
 * such a pair or either lacks its orientation indices (usm_coords_layout_ok). */
int usm_coords_map(const usm_model *from, const double *x_from, double t,
                   const usm_params *p, double phi_near, const usm_model *to, double *x_to);

/* ---- parameters ------------------------------------------------------------ */

/* The paper's parameters: Appendix A, f = 37000 Hz, M = 2 I_R / R^2,
 * mu0 = 0.3, kappa = 20 s/m. */
void usm_params_default(usm_params *p);

/* Table entry of the parameter called `name`, or NULL. */
const usm_param_info *usm_params_find(const char *name);

/* Address of the field described by `info` inside `p`. */
double *usm_params_field(usm_params *p, const usm_param_info *info);

/* Value of the field described by `info` in `p`. */
double usm_params_get(const usm_params *p, const usm_param_info *info);

/* Set parameter `name` to `value`.  Returns USM_OK, or USM_EINPUT with a
 * message naming the parameter and the reason in msg (unknown name, value not
 * finite, of the wrong sign or outside the parameter's range:
 * usm_param_check_value). */
int usm_params_set(usm_params *p, const char *name, double value, char msg[USM_MSG_LEN]);

/* Check value v of parameter k (USM_P_<name>) alone: finite, of its sign
 * (usm_param_constraints) and inside its physical range (usm_param_ranges,
 * derive/usm_derive/defaults.py, docs/cli.md "Parameters"; generous for this
 * motor class, so that a value outside is one typed in the wrong unit).
 * USM_OK, or USM_EINPUT with "NAME: reason", or for a value outside the
 * range "f = 38 Hz is outside 1 kHz..1 MHz (...); did you mean 38 kHz?"
 * (the unit of the table that brings the number into the range; an angle
 * outside -pi..pi is one in degrees). */
int usm_param_check_value(int k, double v, char msg[USM_MSG_LEN]);

/* Check that every value is finite and physical for model m (NULL: any model),
 * each inside its range (usm_param_check_value):
 * positive inertias, radii, frequency; non-negative stiffnesses and damping;
 * the axisymmetric-stator assumption's I_yy == I_xx; H, R such that the
 * contact radius is positive.  USM_OK or USM_EINPUT with "NAME: reason". */
int usm_params_check(const usm_params *p, const usm_model *m, char msg[USM_MSG_LEN]);

/* USM_OK when the motor is ideal (amp_imbalance, phase_error and mode_split
 * all 0), the only case with a stationary solution; otherwise USM_EINPUT with
 * "NAME: must be 0 here ..." in msg.  usm_params_check also demands this of
 * every model whose m->imperfect is 0 (|amp_imbalance| <= 1, |mode_split| < 1
 * always). */
int usm_params_check_ideal(const usm_params *p, char msg[USM_MSG_LEN]);

/* ---- stationary solution --------------------------------------------------- */

/* Whether the model describes the motor at a solution (docs/library.md,
 * "Validity"): the contact must be closed (F_n > 0; on a periodic orbit
 * F_n_min > 0), and a stick model (m->slip == 0) needs the stick to be
 * admissible (|F_t| <= mu0 F_n; on an orbit friction_needed_max <= mu0).
 * Past these limits the equations still have solutions, but the motor does
 * something else (the rotor lifts off, the contact slips). */
typedef enum {
    USM_VALID = 0,
    USM_INVALID_CONTACT_OPEN = 1,  /* F_n <= 0 (F_n_min <= 0 on an orbit) */
    USM_INVALID_STICK = 2          /* stick model past the stick limit */
} usm_validity;

/* "" for USM_VALID, "contact_open", "stick_not_admissible" (the JSON
 * invalid_reason and the CSV column of that name). */
const char *usm_validity_name(usm_validity v);

/* One stationary solution: the unknowns and the quantities derived from them. */
typedef struct usm_steady_solution {
    double u[USM_MAX_NU];  /* the unknowns (theta, alpha[, phidot_R]) */
    double theta;          /* tilt [rad] */
    double alpha;          /* phase of phi relative to the excitation [rad], in [0, 2 pi) */
    double beta;           /* phase of psi [rad], from the twisting balance */
    double rotor_speed;    /* phidot_R [1/s], the paper's sign (negative when driving) */
    double F_n, F_t;       /* contact forces [N] */
    double v_c, v_rel;     /* contact-point speed, slip velocity [m/s] */
    double R_star, Z;      /* contact radius and height [m] */
    double mu_used;        /* F_t / F_n */
    double mu_stick;       /* friction coefficient of the stick check */
    int stick_admissible;  /* F_t <= mu_stick * F_n */
    double residual_norm;  /* max |r_i(u)| [N m] at the returned root */
    /* Power on the stationary solution [W] (generated <model>_steady_power;
     * constant along the orbit, so also the mean over a period): */
    double power_in;       /* excitation torque times the stator's angular velocity */
    double power_out;      /* load torque times rotor speed in the driving direction,
                              -T * rotor_speed; positive when the motor drives the load */
    double power_damping;  /* dissipated by d_r, d_t (and d_R, zero on the orbit) */
    double power_slip;     /* F_t * v_rel (slip models; 0 in the stick model) */
    double efficiency;     /* power_out / power_in; NaN when power_in <= 0 (no power
                              taken in: the ratio means nothing) */
    usm_validity validity; /* USM_VALID when the model describes the motor here:
                              F_n > 0 and, for stick models, stick_admissible */
} usm_steady_solution;

/* Where and how usm_steady_solve searches (usm_steady_options_default). */
typedef struct usm_steady_options {
    double theta_min, theta_max; /* tilt range searched [rad] (default 1e-9 .. 0.2) */
    int grid;                    /* log-spaced samples of the range (default 500) */
    double xtol;                 /* relative tolerance on the unknowns (default 1e-13) */
} usm_steady_options;

/* Fill `opt` with the defaults listed above. */
void usm_steady_options_default(usm_steady_options *opt);

/* Solver of the stationary solutions of one model, with its workspace and the
 * roots found by the last solve (opaque). */
typedef struct usm_steady usm_steady;

/* A solver for model m (not NULL), or NULL when out of memory. */
usm_steady *usm_steady_alloc(const usm_model *m);
/* Free s and its roots; NULL is allowed. */
void usm_steady_free(usm_steady *s);

/* Find every stationary solution in the tilt range: every tilt, and for the
 * slip model every rotor speed that balances the rotor there (a non-monotone
 * friction law can have several); runtime/solve/steady.c states the search's
 * argument and its resolution limit.  USM_OK when at least one root
 * converged; USM_ENOSOLUTION (with a reason in usm_steady_message) when none
 * exists; USM_EINPUT for bad parameters; USM_EFAILED when out of memory.
 * opt may be NULL. */
int usm_steady_solve(usm_steady *s, const usm_params *p, const usm_steady_options *opt);

/* Polish a single root from a starting guess (continuation): Newton/hybridsj
 * from u0 only, no search.  USM_OK or USM_ENOSOLUTION.  The root may be any
 * root near u0, not necessarily the primary: use usm_steady_solve_warm for
 * the primary. */
int usm_steady_solve_from(usm_steady *s, const usm_params *p, const double *u0);

/* What the warm start of the last usm_steady_solve_warm did. */
typedef enum {
    USM_WARM_NONE = 0,          /* the last solve was not a warm start */
    USM_WARM_CONFIRMED = 1,     /* Newton from the guess converged to the primary root */
    USM_WARM_OTHER_ROOT = 2,    /* Newton converged to another root (another branch): the
                                   primary was returned all the same */
    USM_WARM_NEWTON_FAILED = 3  /* Newton did not converge in the tilt range */
} usm_steady_warm_outcome;

/* The primary root only (root 0 of usm_steady_solve, bit for bit, or the
 * same status and message when there is none), warm-started from `guess`
 * (typically the primary root at a neighbouring parameter point: the
 * previous point of a sweep or map column, or the nominal point of a Monte
 * Carlo study; NULL: no Newton step).  Newton (hybridsj on the generated
 * residual and Jacobian) from guess->u says which root the guess continues;
 * the primary is then settled by the full search's own steps run in
 * increasing tilt up to that root and stopped there: Newton alone cannot
 * tell whether a root of lower tilt, the one the full search would return,
 * exists.  The steps below it only sample the search function's sign from
 * the squared torque (runtime/solve/steady.c), so the cost is that of the search
 * up to the root's tilt, without the roots above it.  usm_steady_count is 1
 * after USM_OK; usm_steady_warm says whether Newton's root was the primary
 * (a different branch, or no convergence, changes nothing in the result).
 * opt may be NULL.  Thread safety: as usm_steady_solve. */
int usm_steady_solve_warm(usm_steady *s, const usm_params *p, const usm_steady_options *opt,
                          const usm_steady_solution *guess);

/* The outcome of the last usm_steady_solve_warm (USM_WARM_NONE after any other solve). */
usm_steady_warm_outcome usm_steady_warm(const usm_steady *s);

/* Number of roots found by the last solve (0 before any). */
size_t usm_steady_count(const usm_steady *s);
/* Root i, NULL when out of range.  Roots are ordered by increasing tilt;
 * roots at the same tilt (slip model, several rotor speeds) by increasing
 * |v_rel|, then by increasing phidot_R.  Root 0 is the primary root. */
const usm_steady_solution *usm_steady_root(const usm_steady *s, size_t i);
/* Why the last solve failed, or "" after success.  Owned by s; valid until
 * the next solve or usm_steady_free. */
const char *usm_steady_message(const usm_steady *s);

/* Range of the slip model's friction law mu(v_rel) over all slip speeds, as
 * the solver sees it (its grid, extrema and far ends; runtime/solve/steady.c): no
 * rotor speed balances a load needing F_t/F_n outside [*mu_inf, *mu_sup].
 * The supremum of a non-monotone law can be an interior peak, not the value
 * at large slip.  USM_OK, USM_EINPUT (bad parameters, or a stick model: no
 * friction law; message in usm_steady_message) or USM_EFAILED (out of
 * memory).  Clears the roots of the last solve. */
int usm_steady_friction_range(usm_steady *s, const usm_params *p, double *mu_inf, double *mu_sup);

/* Fill the derived quantities of `sol` from sol->u (used by the solver and by
 * callers that solve the residuals themselves). */
void usm_steady_evaluate(const usm_model *m, const usm_params *p, usm_steady_solution *sol);

/* ---- Floquet multipliers --------------------------------------------------- */

/* How the monodromy matrix is computed. */
typedef enum {
    USM_FLOQUET_VARIATIONAL = 0, /* CVODES on the variational equations (the independent check) */
    USM_FLOQUET_EXPONENTIAL = 1, /* product of balanced matrix exponentials, frame A, midpoint
                                    rule with Richardson extrapolation (`steps`) */
    USM_FLOQUET_MAGNUS = 2,      /* sixth-order Magnus integrator on the coefficients, which are
                                    affine in t (the paper's twist law) or constant (one
                                    exponential); balanced Pade exponentials */
    USM_FLOQUET_AUTO = 3         /* the default: the fastest method with 10 correct digits
                                    (MAGNUS; bench/usm_bench measures it against CVODES) */
} usm_floquet_method;

/* Name of a method: "variational", "exponential", "magnus", "auto" (NULL if unknown). */
const char *usm_floquet_method_name(usm_floquet_method method);

/* The method called `name` (as usm_floquet_method_name).  USM_OK, or
 * USM_EINPUT with "NAME: unknown Floquet method (known: ...)" in msg. */
int usm_floquet_method_from_name(const char *name, usm_floquet_method *method,
                                 char msg[USM_MSG_LEN]);

/* Method and tolerances of usm_floquet_compute (usm_floquet_options_default). */
/* The most sub-intervals per period of the exponential Floquet method. */
#define USM_FLOQUET_MAX_STEPS 1000000

typedef struct usm_floquet_options {
    usm_floquet_method method; /* default USM_FLOQUET_AUTO */
    double rtol, atol;   /* CVODES tolerances in the scaled coordinates (default 1e-8, 1e-12);
                            the Magnus method takes its number of steps from rtol */
    int steps;           /* exponential method: sub-intervals per period (default 64;
                            1 .. USM_FLOQUET_MAX_STEPS) */
} usm_floquet_options;

/* Fill `opt` with the defaults listed above. */
void usm_floquet_options_default(usm_floquet_options *opt);

/* Floquet multipliers of one stationary solution and its monodromy matrix. */
typedef struct usm_floquet_result {
    int n;                              /* number of multipliers (= nx) */
    double re[USM_MAX_NX], im[USM_MAX_NX];
    int cyclic[USM_MAX_NX];             /* 1: the multiplier 1 of a cyclic coordinate */
    double max_modulus;                 /* largest |lambda| excluding cyclic ones */
    int stable;                         /* max_modulus < 1 */
    double t0;                          /* start time of the period [s] */
    int t0_dependent;                   /* 1: this model's multipliers depend on t0
                                           (the paper's twist law; see README) */
    double monodromy[USM_MAX_NX * USM_MAX_NX]; /* row-major n x n */
    usm_floquet_method method;          /* the method used (never USM_FLOQUET_AUTO) */
} usm_floquet_result;

/* Floquet solver of one model: integrator and eigen-solver workspace (opaque). */
typedef struct usm_floquet usm_floquet;

/* A Floquet solver for model m (not NULL), or NULL when out of memory.  It
 * computes in the coordinates usm_floquet_coordinates(m) (the result's
 * monodromy is in those). */
usm_floquet *usm_floquet_alloc(const usm_model *m);

/* The model whose orientation coordinates the Floquet solver uses for m: m
 * itself, or m->other_coordinates where those give more correct digits (the
 * tilt vector for the stick model's twist_integrated variant; measured in
 * docs/coordinates.md).  The same motor and stationary solution either way. */
const usm_model *usm_floquet_coordinates(const usm_model *m);
/* Free f; NULL is allowed. */
void usm_floquet_free(usm_floquet *f);

/* Multipliers of the stationary solution `sol` over [t0, t0 + T].  The paper's
 * Table 3 uses t0 = 0 with alpha in [0, 2 pi) (see README: the paper's twist law
 * makes the linearisation depend on t0).  opt may be NULL.  Sorted by
 * decreasing modulus.  USM_OK, USM_EFAILED (message in usm_floquet_message),
 * or USM_EINPUT for bad options or a motor that is not ideal (an imperfection
 * non-zero: see usm_params_check_ideal; its orbit is usm_periodic_solve's). */
int usm_floquet_compute(usm_floquet *f, const usm_params *p, const usm_steady_solution *sol,
                        double t0, const usm_floquet_options *opt, usm_floquet_result *out);
/* Why the last usm_floquet_compute failed, or "" after success.  Owned by f;
 * valid until the next compute or usm_floquet_free. */
const char *usm_floquet_message(const usm_floquet *f);

/* Multipliers of every root of the last solve of s (usm_steady_count(s) of
 * them, in root order): out[k] is exactly what usm_floquet_compute gives for
 * usm_steady_root(s, k) with the same t0 and opt, so out[0] describes the
 * primary root.  out has room for usm_steady_count(s) results; nothing is
 * computed when s has no roots.  The cost is that of one root per root (each
 * a monodromy over one period; docs/library.md, "Floquet methods").  USM_OK
 * when every root's multipliers were computed; otherwise the status of the
 * first root that failed (roots before it are filled, those after it are
 * not), with "root #K (theta = ...): reason" in usm_floquet_message (K counted
 * from 1, as `usm steady` numbers the roots).  Thread safety: as
 * usm_floquet_compute (f and s are used, not shared). */
int usm_floquet_roots(usm_floquet *f, const usm_params *p, const usm_steady *s, double t0,
                      const usm_floquet_options *opt, usm_floquet_result *out);

/* ---- the squeal frequency (solve/squeal.c) --------------------------
 *
 * A Floquet multiplier lambda of a motion of period T = 1/f (a stationary
 * solution's multipliers are over one excitation period too) is exp(mu T)
 * with mu = sigma + i omega: a perturbation along its eigenvector vibrates at
 * omega / (2 pi) = f arg(lambda) / (2 pi) + k f for any integer k, and with
 * either sign.  Its lines in a spectrum are at k f +- f_s, and the one
 * representative used here is the folded f_s = f |arg(lambda)| / (2 pi) in
 * [0, f/2] (arg in (-pi, pi]): for lambda = -0.9348 + 0.3552i, f = 37 kHz,
 * f_s = 0.44217 f = 16.360 kHz.  A real multiplier gives 0 (lambda > 0) or f/2
 * (lambda < 0): no new frequency but a drift or a period doubling.
 *
 * A multiplier is one member of a complex pair when |Im lambda| >
 * USM_COMPLEX_PAIR_TOL |lambda| (the rule by which usm_periodic_sweep calls a
 * stability change neimark_sacker); the dominant complex pair is the complex
 * pair of largest modulus among the non-cyclic multipliers (the first in
 * usm_floquet_result order on a tie), whether or not it is the largest
 * multiplier overall: it is the oscillatory mode that decays slowest, and
 * the one that becomes the squeal when it crosses the unit circle. */
#define USM_COMPLEX_PAIR_TOL 1e-6

/* f |arg(re + i im)| / (2 pi) [Hz] in [0, f/2], the folded frequency above;
 * NaN when f or the multiplier is not finite, f <= 0, or re = im = 0. */
double usm_squeal_frequency(double f, double re, double im);

/* The dominant complex pair of a set of multipliers and its frequency. */
typedef struct usm_squeal {
    int found;           /* 1: there is a complex pair */
    int index;           /* the pair's member with im > 0 in r->re/im (-1 when none) */
    double re, im;       /* the pair re +- im i, im > 0 (NaN when none) */
    double modulus;      /* |lambda| (NaN when none) */
    double frequency;    /* usm_squeal_frequency(f, re, im) [Hz] (NaN when none) */
    char reason[USM_MSG_LEN]; /* "" when found, else why there is none */
} usm_squeal;

/* The dominant complex pair of r (above) for a motion of frequency f [Hz]
 * (period 1/f).  USM_OK (out->found says whether there is one, out->reason
 * why not); USM_EINPUT when f is not finite and positive (message in
 * out->reason).  Thread safe (no state). */
int usm_floquet_squeal(const usm_floquet_result *r, double f, usm_squeal *out);

/* The guard of the "never NaN in the output" promise on a stationary
 * solution and its multipliers (the usm command's and the Python package's
 * steady): NULL when theta, alpha, beta, rotor_speed, F_n, F_t, v_c, v_rel,
 * R_star, Z, mu_used, every multiplier and max_modulus are finite, else a
 * static message ("steady: the stationary solution has a non-finite value",
 * "floquet: a multiplier is not finite", "floquet: the largest modulus is
 * not finite"): a numerical failure. */
const char *usm_steady_nonfinite(const usm_steady_solution *s, const usm_floquet_result *f);

#ifdef __cplusplus
}
#endif

#endif /* USM_H */
