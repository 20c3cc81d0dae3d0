/* usm_simulate.h: transient simulation of the full nonlinear motor model.
 *
 * Math: the generated kernels give M(x) x' = f(x, t).  CVODES integrates the
 * explicit ODE x' = M(x)^{-1} f(x, t) (BDF, dense direct linear solver) with
 * the analytic Jacobian
 *     J = M^{-1} (df/dx - d(M v)/dx |_{v = x'}).
 * The mass matrix is at most 8 x 8 and regular for theta > 0, so solving it in
 * every right-hand side costs less than a DAE formulation (IDA) would, and it
 * keeps CVODES' error control on the state alone (no algebraic components to
 * exclude).  See docs/simulate.md for the choices below.
 *
 *  - Coordinates.  phi and psi grow like +-Omega t and, at the small tilts of
 *    the motor, move almost exactly opposite to each other: a perturbation
 *    of the tilt vector of size e shows up in them as e / theta.  CVODES
 *    therefore works on z = (phi + psi, theta, psi + Omega (t - t0), and the
 *    same for the rates), a constant linear change of variables, with error
 *    weights stated in physical terms (simulate.c, set_scales): the spin
 *    phi + psi is controlled absolutely at rtol * theta_c (theta_c the
 *    stationary tilt), since the twisting torque c_t (phi + psi cos theta)
 *    is a small difference of two large angles.
 *  - Start from rest.  A motor at rest has no tilt, but the contact law is
 *    singular at theta = 0 in every coordinate set (docs/coordinates.md), so
 *    the run starts from theta = tilt0 with zero rates and phi = Omega t0,
 *    psi = -Omega t0: the tilt is a rotation about the axis of the excitation
 *    torque at t0, the twist angle is zero.  Below the smallest unstable
 *    stationary tilt theta_u the motion falls back to the axis where the
 *    preload's moment holds the stator, above it the wobble may grow: a start
 *    above theta_u is not a start at rest.  So tilt0 = 0 (the default) starts
 *    at min(USM_SIM_TILT0_DEFAULT, USM_SIM_REST_START_FRACTION theta_u)
 *    (theta_u from the roots' Floquet multipliers at t0; with multipliers that
 *    fail, every root counts as unstable), and the summary says which start
 *    was used (tilt_start, start_message).  A tilt0 > 0 is used as given; the
 *    message says when it lies at or above theta_u.
 *  - Settling.  At the end of every excitation period T = 1/f the mean tilt and
 *    the mean rotor speed over that period (quadratures) are compared with the
 *    primary stationary solution of usm_steady_solve.  The motion has settled
 *    at t_settle when every period from t_settle to the end is within
 *    settle_tol (relative) in both, and that stretch lasts at least
 *    settle_periods periods.
 *  - Where it ended (settled_on).  The same rule is applied to every root of
 *    usm_steady_solve (the roots of `usm steady`, in its order): the run
 *    settled on root k when the period means of tilt and rotor speed are
 *    within settle_tol (relative) of root k's in every period of the last
 *    settle_periods periods up to the end of a completed run (for root 0
 *    this is `settled`); should two roots qualify (roots closer than
 *    settle_tol), the one nearer at the end wins.  The wobble decayed (the
 *    motor does not start) when, for USM_SIM_REST_PERIODS consecutive
 *    periods, the period-mean tilt is below rest_fraction theta_ref, with
 *    theta_ref the smaller of the start tilt and the smallest stationary tilt
 *    (the start tilt when there is no stationary solution): a tilt 10 times
 *    below where it started and below every stationary tilt, held for 5
 *    periods, is decay, not an approach to a root (the start-ups that reach
 *    a root dip by less than a factor 2).  Or, from rest with the smallest
 *    root unstable (the threshold the wobble must cross to grow), when for
 *    USM_SIM_TRAP_PERIODS consecutive periods the period-mean tilt is below
 *    rest_fraction times that root's tilt (rest_theta_ref then says so): the
 *    motion held near the axis does not die out but circles the apex at a
 *    level of its own (1e-9 .. 1e-8 rad, docs/coordinates.md), which a start
 *    below that level never falls 1/rest_fraction beneath.  The rule asks
 *    nothing of the rotor: under a load the slip model's stopped rotor is
 *    back-driven at the friction law's creep speed
 *    tan(T / (R F0 mu0)) / (kappa R) (0.39 1/s at F0 = 1.1 N) while the
 *    wobble dies out, and the stick model's rotor speed follows the tilt.
 *    The run then stops (USM_SIM_REST) instead of integrating on towards
 *    theta = 0, where the contact law is singular and the steps shrink
 *    without end.  Otherwise the run has not settled (USM_SIM_SETTLED_NONE),
 *    e.g. when it was too short or stopped early.
 *  - The paper's twist law.  Its linearisation grows with psi(t) (the twist
 *    torque's theta-derivative c_t psi sin(theta), psi ~ -Omega t): the fastest
 *    linearised mode gets faster as the run goes on, the steps shorter, and the
 *    cost of a run grows superlinearly with its length (4-DOF, paper's
 *    parameters: 0.1 s simulated in 0.5 s, 2 s in a minute).  The run measures
 *    it by the twist growth
 *        g = c_t max|psi| sin(theta_c) / (I_xx Omega^2)
 *    (max|psi| over the run on the stationary orbit of tilt theta_c; the
 *    stator's stiffness at the excitation frequency in the denominator), 0 for
 *    models whose linearisation does not depend on t (usm_model.t0_independent)
 *    and when no stationary solution exists.  Above USM_SIM_TWIST_GROWTH_WARN
 *    the run warns (usm_sim_summary.warning and the warning callback, before
 *    integrating); above max_twist_growth it is refused (USM_EINPUT).  The
 *    variant twist_integrated has a constant linearisation and scales linearly.
 *  - Unilateral contact (models with usm_model.unilateral, the variant
 *    imperfect_unilateral; docs/unilateral.md).  Closed, the model's own
 *    equations; the contact opens where F_n falls through 0 (located by CVODES'
 *    root finding to its tolerance): the separation map continues in the open
 *    mode, whose state adds the rotor's axial position Z_R and rate (and the
 *    stick model's free rotor speed w_R).  Open, the contact closes where the gap
 *    Z_R - Z(theta) falls through 0: the impact map (Newton's restitution
 *    e_impact; sticking if |P_t| <= mu0 P_n, else sliding with P_t = +-mu0 P_n,
 *    the stick model counting it in impacts_slipping) and then the closed mode,
 *    unless the rotor bounces faster than v_land = sqrt(rtol) R theta_c Omega
 *    or the closed mode would pull (F_n < 0): then it stays open.  Every
 *    switch restarts CVODES from the new state (its order and step history
 *    are lost: the derivative jumps).  Where the contact never opens the run
 *    is the closed model's own, step for step.
 *  - Diagnostics.  Root functions locate, to the integrator's accuracy, where
 *    F_n changes sign (contact would open) and, in the stick model, where
 *    |F_t| crosses mu0 F_n; and stop the run at runaway: theta >= theta_limit,
 *    theta <= 0 (the coordinates' singularity), |phidot_R| >= speed_limit.
 *
 * Life cycle (GSL style): usm_sim_alloc, usm_sim_run (any number of times),
 * usm_sim_free.  Thread safety: no global mutable state; distinct usm_sim
 * objects may run in distinct threads at the same time, one object must not
 * be shared without a lock.  The library never prints: CVODES' messages are
 * captured into the summary's reason.
 */
#ifndef USM_SIMULATE_H
#define USM_SIMULATE_H

#include "usm.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
    USM_SIM_FROM_REST = 0,       /* theta = tilt0, zero rates */
    USM_SIM_FROM_STATIONARY = 1, /* the primary stationary orbit at t0 */
    USM_SIM_FROM_STATE = 2       /* x0 (and rotor_angle0 for the stick model) */
} usm_sim_start;

typedef struct usm_sim_options {
    usm_sim_start start;
    double t0;             /* start time [s] (the excitation is m0 (cos Omega t, sin Omega t)) */
    double duration;       /* [s], > 0 */
    double tilt0;          /* FROM_REST: initial tilt [rad]; 0 (default): at rest, below
                              every unstable root (header comment, "Start from rest") */
    double x0[USM_MAX_NX]; /* FROM_STATE: the state, in the model's state order */
    double rotor_angle0;   /* initial rotor angle phi_R [rad] of the stick model (default 0) */
    double rate;           /* samples per second passed to the callback; 0: none (default) */
    double rtol;           /* relative tolerance (default 1e-8) */
    double settle_tol;     /* relative settling tolerance (default 1e-3) */
    int settle_periods;    /* periods the settled state must last (default 100) */
    double theta_limit;    /* runaway: tilt [rad] (default 0.5) */
    double speed_limit;    /* runaway: |phidot_R| [1/s] (default 1e4) */
    long max_steps;        /* cap on internal steps; 0: 2000 per period + 10^5 (default) */
    double max_step;       /* largest internal step [s]; 0: T / 4 (default), see README */
    double max_twist_growth; /* refuse runs whose twist growth exceeds this (see the
                              * header comment); 0: no limit (default 400: about 2 s
                              * of the paper's motor, a minute of computing) */
    double rest_fraction;  /* the decay rule of settled_on (header comment; default
                              0.1, in [0, 0.5]); 0: never decide that the wobble decayed */
    int own_coordinates;   /* 1: integrate in the model's own orientation coordinates;
                              0 (default): a model with a counterpart in the tilt
                              vector (twist_integrated) is integrated in it, the
                              same motion regular at theta = 0 (docs/coordinates.md); states in and out are the
                              model's either way */
} usm_sim_options;

/* The start at rest (tilt0 = 0, header comment): at most this tilt [rad] ... */
#define USM_SIM_TILT0_DEFAULT 1e-6
/* ... and at most this fraction of the smallest unstable stationary tilt. */
#define USM_SIM_REST_START_FRACTION 1e-2

/* Consecutive periods the decay rule must hold (see the header comment). */
#define USM_SIM_REST_PERIODS 5
/* Consecutive periods the trapped form of the decay rule must hold. */
#define USM_SIM_TRAP_PERIODS 25

/* usm_sim_summary.settled_on when the wobble decayed: the motor does not start. */
#define USM_SIM_SETTLED_REST (-1)
/* usm_sim_summary.settled_on when the run settled on no root and did not decay. */
#define USM_SIM_SETTLED_NONE (-2)

/* Twist growth above which a run warns that it will slow down (about 0.2 s
 * of the paper's motor under its twist law). */
#define USM_SIM_TWIST_GROWTH_WARN 40.0

/* Defaults: start from rest at t0 = 0, tilt0 = 0 (at rest, below every unstable
 * root), duration 0 (must be set), no samples, the tolerances and limits
 * stated above. */
void usm_sim_options_default(usm_sim_options *opt);

/* The sample rate the clients record a time history at unless told
 * otherwise (usm simulate's --rate, the Python package's rate): 10 samples
 * per excitation period, 10 p->f [1/s], enough to draw the wobble. */
double usm_sim_default_rate(const usm_params *p);

/* One point of the time history. */
typedef struct usm_sim_sample {
    double t;                 /* [s] */
    int nx;
    const double *x;          /* the state, model order (usm_model.state_names) */
    const double *xdot;       /* its time derivative */
    double phi, theta, psi;   /* z-x-z Euler angles [rad] */
    double phidot, thetadot, psidot; /* [rad/s] */
    double rotor_angle;       /* phi_R [rad] */
    double rotor_speed;       /* phidot_R [1/s], the paper's sign (negative when driving) */
    double out[USM_OUT_COUNT];/* the model's outputs (USM_OUT_*) */
    int have_avg;             /* 0 before the first complete excitation period */
    double theta_avg;         /* mean tilt over the last complete period [rad] */
    double rotor_speed_avg;   /* mean phidot_R over the last complete period [1/s] */
    usm_validity validity;    /* USM_VALID, or the contact open (F_n <= 0), or in the
                               * stick model |F_t| > mu0 F_n (the model does not
                               * describe the motor at this instant); a unilateral
                               * model's open contact is valid (it describes it) */
    int open;                 /* unilateral model: 1 while the contact is open */
    double gap;               /* Z_R - Z(theta) [m] while open, 0 while closed */
    int ny;                   /* length of y */
    const double *y;          /* the current mode's state: x while closed; while open
                               * the open mode's (usm_model.unilateral->ny: x, then the
                               * rotor's axial states), the start of usm_hybrid_lyapunov */
} usm_sim_sample;

typedef struct usm_sim_callbacks {
    /* Called at t0 + k / rate and at the end; non-zero stops the run. */
    int (*sample)(const usm_sim_sample *s, void *data);
    /* Called at the end of every excitation period (for progress bars). */
    void (*progress)(double t, double t0, double t1, void *data);
    void *data;
    /* Called before integrating with a warning about the run (the text of
     * usm_sim_summary.warning); NULL: none.  Last, so that positional
     * initialisers of the members above stay valid. */
    void (*warning)(const char *msg, void *data);
} usm_sim_callbacks;

/* Time intervals where a contact condition is violated. */
typedef struct usm_sim_episodes {
    long count;      /* separate intervals */
    double first;    /* start of the first [s] */
    double last;     /* end of the last [s] (the end of the run if still violated) */
    double total;    /* total time [s] */
    double worst;    /* F_n < 0: most negative F_n [N]; stick: largest |F_t| - mu0 F_n [N] */
} usm_sim_episodes;

typedef enum {
    USM_SIM_COMPLETED = 0,
    USM_SIM_INTEGRATOR = 1,     /* CVODES failed (flag in `reason`) */
    USM_SIM_RUNAWAY_TILT = 2,   /* theta >= theta_limit */
    USM_SIM_TILT_ZERO = 3,      /* theta <= 0: the Euler angles' singularity */
    USM_SIM_RUNAWAY_SPEED = 4,  /* |phidot_R| >= speed_limit */
    USM_SIM_MAX_STEPS = 5,      /* max_steps internal steps used */
    USM_SIM_STOPPED = 6,        /* the sample callback asked to stop */
    USM_SIM_REST = 7            /* the wobble decayed (settled_on: USM_SIM_SETTLED_REST) */
} usm_sim_stop;

/* "completed", "integrator", "runaway_tilt", "tilt_zero", "runaway_speed",
 * "max_steps", "stopped", "rest" */
const char *usm_sim_stop_name(usm_sim_stop stop);

typedef struct usm_sim_summary {
    usm_sim_stop stop;
    char reason[USM_MSG_LEN];   /* why the run stopped early ("" when completed) */
    double t0, t1;              /* requested interval [s] */
    double t_reached;           /* [s] */
    double final_x[USM_MAX_NX]; /* state at t_reached */
    double final_rotor_angle;   /* phi_R at t_reached [rad] */
    long steps, rhs_evals, jac_evals, error_test_fails, newton_fails;
    long samples;               /* calls of the sample callback */
    double theta_min, theta_max;/* over every internal step [rad] */
    /* the stationary solution the motion is compared with */
    int have_steady;
    usm_steady_solution steady;
    char steady_message[USM_MSG_LEN]; /* why there is none */
    /* settling (see the header comment) */
    double settle_tol;
    int settle_periods;
    long periods;               /* complete excitation periods integrated */
    int settled;
    double t_settle;            /* [s]; meaningful when settled */
    double theta_avg_end, rotor_speed_avg_end; /* means over the last complete period */
    double theta_rel_end, rotor_speed_rel_end; /* (mean - stationary) / |stationary| */
    /* contact diagnostics */
    usm_sim_episodes contact_open;   /* F_n < 0 */
    int stick_checked;               /* stick model: |F_t| > mu0 F_n is checked */
    usm_sim_episodes stick_exceeded; /* |F_t| > mu0 F_n */
    /* the paper's twist law (see the header comment) */
    double twist_growth;        /* g of this run; 0 when it does not apply */
    char warning[USM_MSG_LEN];  /* "" or why the run will slow down, with the remedy */
    /* where it ended (see the header comment) */
    int settled_on;             /* the root index k (0: the primary; the index into
                                   `usm steady --json`'s roots), USM_SIM_SETTLED_REST or
                                   USM_SIM_SETTLED_NONE */
    size_t roots;               /* stationary solutions compared with */
    usm_steady_solution settled_root; /* root settled_on, when settled_on >= 0 */
    /* a unilateral contact (usm_model.unilateral; "Unilateral contact" above) */
    int unilateral;             /* 1: the model's contact may open */
    long separations;           /* closed -> open switches (F_n fell through 0) */
    long impacts;               /* landings of the rotor (the gap fell through 0) */
    long impacts_slipping;      /* stick model: impacts whose sticking impulse exceeded
                                   mu0 P_n (the stick assumption fails there) */
    double impact_velocity_max; /* largest normal approach velocity -gap' [m/s] */
    double open_fraction;       /* time open / time integrated */
    int final_open;             /* 1: open at t_reached (final_x: its first nx states) */
    double rest_fraction;       /* of the options */
    double rest_theta_ref;      /* theta_ref of the decay rule [rad] */
    double t_rest;              /* [s] when the decay rule was met; NaN otherwise */
    double open_fraction_end;   /* unilateral: time open in the last complete excitation
                                   period / T (the window of rotor_speed_avg_end: on a
                                   settled run the orbit's separation fraction, which
                                   open_fraction, over the whole run with its start-up,
                                   is not); 0 before the first complete period */
    double tilt_start;          /* FROM_REST: the start tilt used [rad] (tilt0, or the one
                                   tilt0 = 0 chose); 0 for the other starts */
    double theta_unstable;      /* the smallest unstable stationary tilt [rad]; 0: none */
    char start_message[USM_MSG_LEN]; /* FROM_REST: which start was used and why */
} usm_sim_summary;

/* A transient simulation of one model: integrator workspace and the
 * message of the last run (opaque). */
typedef struct usm_sim usm_sim;

/* A simulation of model m (not NULL), or NULL when out of memory. */
usm_sim *usm_sim_alloc(const usm_model *m);
/* Free s; NULL is allowed. */
void usm_sim_free(usm_sim *s);

/* Check parameters p and options opt for a run of s's model as usm_sim_run
 * does before integrating: USM_OK, or USM_EINPUT with "FIELD: reason" in
 * usm_sim_message, FIELD an option's member name (duration, rtol, ...) or a
 * parameter's. */
int usm_sim_check(usm_sim *s, const usm_params *p, const usm_sim_options *opt);

/* Integrate over [t0, t0 + duration].  Returns USM_OK when the interval was
 * completed (settled or not) or the wobble decayed (stop USM_SIM_REST: the
 * motor does not start, a decided end), USM_EFAILED when the run stopped early
 * (integrator failure, runaway, step cap, callback), USM_EINPUT for bad
 * parameters or options and for a run beyond max_twist_growth (message
 * "duration: ..."), USM_ENOSOLUTION for FROM_STATIONARY without a
 * stationary solution.  The summary is filled in every case but USM_EINPUT;
 * usm_sim_message repeats its reason.  cb and opt may be NULL. */
int usm_sim_run(usm_sim *s, const usm_params *p, const usm_sim_options *opt,
                const usm_sim_callbacks *cb, usm_sim_summary *sum);

/* The reason of the last run's outcome (see usm_sim_run).  Owned by s; valid
 * until the next run or usm_sim_free. */
/* Why the last usm_sim_run did not return USM_OK ("" otherwise). */
const char *usm_sim_message(const usm_sim *s);

#ifdef __cplusplus
}
#endif

#endif /* USM_SIMULATE_H */
