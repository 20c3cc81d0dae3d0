/* usm_periodic.h: periodic steady states of a real motor by shooting.
 *
 * A motor with driver amplitude imbalance, phase error or a stator mode split
 * (parameters amp_imbalance, phase_error, mode_split of the variant
 * "imperfect") has no stationary solution: its steady state is periodic with
 * the excitation period T = 1/f.  In the coordinates y = (phi - Omega t, the
 * other states) with the cyclic ones (psi, phi_R) dropped, the ideal
 * stationary solution is an equilibrium and the real motor's steady state a
  * fixed point of the period map, y(t0 + T) = y(t0).  Newton's method solves
 * it, with the monodromy matrix from the variational equations (CVODES with
 * the generated Jacobians), starting from the ideal stationary solution.  The
 * multipliers of that monodromy are the orbit's Floquet multipliers.
 *
 * Only models with the integrated twist law (m->x_tau >= 0) have periodic
 * orbits in these coordinates: the paper's twist angle phi + psi cos(theta)
 * grows without bound on every motion near the stationary one
 * (docs/periodic.md).
 *
 * Thread safety: one usm_periodic per thread; no global state.
 */
#ifndef USM_PERIODIC_H
#define USM_PERIODIC_H

#include <stdio.h>

#include "usm.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Tolerances of usm_periodic_solve (usm_periodic_options_default). */
typedef struct usm_periodic_options {
    double rtol;     /* CVODES relative tolerance (default 1e-11: the multipliers to
                        about 1e-9; 1e-10 moves them by 5e-8) */
    double tol;      /* Newton: converged when every component of y(t0 + T) - y(t0)
                        is below tol times its scale (default 1e-9; see periodic.c) */
    int max_iter;    /* Newton iterations (default 12) */
    double t0;       /* start of the period [s] (default 0) */
} usm_periodic_options;

/* Fill `opt` with the defaults listed above. */
void usm_periodic_options_default(usm_periodic_options *opt);

/* Number of points at which the orbit is sampled (one period, t0 included,
 * t0 + T excluded). */
#define USM_PERIODIC_SAMPLES 200

/* Columns of one orbit sample: t, the state x (nx), F_n, F_t, rotor speed. */
typedef struct usm_periodic_result {
    int converged;          /* 1 when Newton converged */
    int iterations;         /* Newton iterations used */
    double residual;        /* max_i |y_i(t0 + T) - y_i(t0)| / scale_i at the result */
    double t0, period;      /* [s] */
    int nx;
    double x0[USM_MAX_NX];  /* state at t0 on the orbit */
    usm_floquet_result floquet; /* multipliers of the orbit (cyclic ones flagged) */
    /* over one period: means and harmonics from USM_PERIODIC_SAMPLES samples;
     * extremes located on the orbit (the zero of their time derivative next
     * to the extreme sample, by Brent's method on the re-integrated state:
     * to 1e-9 of a 10^5-sample orbit; docs/periodic.md) */
    double rotor_speed_mean;    /* [1/s], the paper's sign */
    double rotor_speed_ripple;  /* peak to peak [1/s] */
    double F_n_min, F_n_max;    /* [N] */
    double friction_needed_max; /* max |F_t| / F_n (NaN when F_n <= 0 somewhere) */
    double theta_mean, theta_min, theta_max; /* [rad] */
    double theta_harmonic_2;    /* amplitude of the 2 Omega component of theta [rad] */
    double F_n_harmonic_2;      /* amplitude of the 2 Omega component of F_n [N] */
    int contact_open;           /* F_n_min < 0: the bilateral contact of the model is
                                   then not valid (the rotor would lift off) */
    usm_validity validity;      /* USM_VALID: F_n_min > 0 and, for stick models,
                                   friction_needed_max <= mu0 (usm.h) */
    int openings_per_period;    /* the separate stretches of one period with F_n < 0 on
                                   the samples (1 where F_n_min < 0 falls between them): the
                                   times a period the bilateral contact opens, counted on
                                   the orbit (2 for the 2 Omega wobble of a mode split, whose
                                   F_n(t + T/2) = F_n(t)); 0 while it stays closed */
} usm_periodic_result;

/* Shooting solver of one model (opaque). */
typedef struct usm_periodic usm_periodic;

/* A solver for model m (not NULL), or NULL when out of memory. */
usm_periodic *usm_periodic_alloc(const usm_model *m);
/* Free w; NULL is allowed. */
void usm_periodic_free(usm_periodic *w);

/* The periodic orbit for parameters p, started from x0 (the state at
 * opt->t0; NULL: the ideal motor's primary stationary solution, imperfections
 * set to 0).  opt may be NULL.  Returns USM_OK (out->converged = 1);
 * USM_EINPUT for bad parameters or options, or for a model without the
 * integrated twist law (no periodic orbit in these coordinates);
 * USM_ENOSOLUTION when x0 is NULL and the ideal motor has no stationary
 * solution to start from (as usm_steady_solve; no claim that no orbit
 * exists); USM_EFAILED when the integration fails or Newton does not
 * converge.  The reason is in usm_periodic_message. */
int usm_periodic_solve(usm_periodic *w, const usm_params *p, const double *x0,
                       const usm_periodic_options *opt, usm_periodic_result *out);

/* The samples of the last converged orbit: USM_PERIODIC_SAMPLES rows of
 * (t, x[0..nx-1], F_n, F_t, rotor_speed), row-major with nx + 4 columns;
 * NULL before a converged solve. */
const double *usm_periodic_samples(const usm_periodic *w);

/* The samples of the last converged orbit as CSV in the project's dialect
 * (header with units: t [s], the states, F_n [N], F_t [N], rotor_speed [1/s]);
 * -1 before a converged solve or on a write error. */
int usm_periodic_write_orbit_csv(const usm_periodic *w, FILE *out);

/* The `usm periodic --json` object and a newline to out: model, parameters
 * p, converged, and either the orbit's keys (r: the result of the last
 * solve of w) or, with r NULL, "error": usm_periodic_message(w) (keys:
 * docs/periodic.md).  0, or -1 on a write error or when out of memory. */
int usm_periodic_write_json(const usm_periodic *w, const usm_params *p,
                            const usm_periodic_result *r, FILE *out);

/* Why the last solve failed, or "".  Owned by w. */
const char *usm_periodic_message(const usm_periodic *w);

/* ---- periodic orbits with separation (docs/unilateral.md) -------------
 *
 * For a model whose contact may open (m->unilateral, the variant
 * imperfect_unilateral).  The orbit is a fixed point of the event-driven
 * period map P: x(ts) -> x(ts + T) with the section time ts inside a closed
 * phase (found from a simulation: the middle of the longest closed stretch
 * of its last period).  One shooting integration carries the state and its
 * variational matrix through every mode; at each switch the variational
 * matrix is multiplied by the saltation matrix
 *     S = R + (f+ - R f-) g_x^T / (dg/dt),
 * R the reset's Jacobian, f-, f+ the flows before and after, g the guard
 * (F_n(x, x'(x, t)) while closed, the gap while open), so the monodromy is
 * Phi_K S_K ... S_1 Phi_0.  Newton on the non-cyclic components as
 * usm_periodic_solve.  The mode sequence is the one the shooting
 * integration meets (from the simulation's state, then each Newton iterate). */

/* Options of usm_hybrid_solve (usm_hybrid_options_default). */
typedef struct usm_hybrid_options {
    double rtol;     /* CVODES relative tolerance (default 1e-11: Newton's tol 1e-9 needs it) */
    double tol;      /* Newton: max |x(ts + T) - x(ts)| / scale (default 1e-9) */
    int max_iter;    /* Newton iterations: period maps with the monodromy, each followed
                        by chord steps (maps without it) while they contract (default 12) */
    double settle;   /* simulated time from rest before shooting [s] (default 0.005): the
                        careful start's; the quick start ends earlier (usm_hybrid_solve) */
} usm_hybrid_options;

/* Fill `opt` with the defaults listed above. */
void usm_hybrid_options_default(usm_hybrid_options *opt);

/* Longest mode sequence reported (usm_hybrid_result.mode_sequence). */
#define USM_HYBRID_MAX_SWITCHES 32

typedef struct usm_hybrid_result {
    int converged, iterations;  /* iterations: maps with the monodromy (max_iter) */
    double residual;            /* as usm_periodic_result's */
    double t0, period;          /* the section time ts and T [s] */
    int nx;
    double x0[USM_MAX_NX];      /* closed state at ts on the orbit */
    usm_floquet_result floquet; /* multipliers of the monodromy with saltation matrices */
    double rotor_speed_mean;    /* [1/s], the paper's sign */
    double rotor_speed_ripple;  /* peak to peak over the period [1/s]: 256 samples
                                   and both sides of every switch */
    double separation_fraction; /* time open per period / T */
    int separations_per_period, impacts_per_period;
    int impacts_slipping;       /* stick model: impacts per period needing more than mu0 */
    usm_validity validity;      /* USM_VALID, or USM_INVALID_STICK in the stick model where
                                   an impact needs more than mu0 (impacts_slipping > 0) */
    double impact_velocity_max; /* largest approach velocity -gap' [m/s] */
    int nmodes;                 /* modes in mode_sequence (the switches + 1) */
    char mode_sequence[USM_HYBRID_MAX_SWITCHES + 1]; /* 'c' closed, 'o' open, from ts */
} usm_hybrid_result;

/* Hybrid shooting solver of one unilateral model (opaque). */
typedef struct usm_hybrid usm_hybrid;

/* A solver for model m (m->unilateral not NULL), or NULL (out of memory or
 * not a unilateral model). */
usm_hybrid *usm_hybrid_alloc(const usm_model *m);
/* Free h; NULL is allowed. */
void usm_hybrid_free(usm_hybrid *h);

/* The periodic orbit with separation for parameters p: a simulation from
 * rest gives the section time and the start, then Newton.  First the quick
 * start (rtol 1e-5, ended once the period means of tilt and rotor speed
 * changed by less than 3e-4 in 5 consecutive periods, at most opt->settle);
 * should Newton fail from it or find an unstable orbit (a start-up may
 * linger near a weakly unstable orbit: calm there is not settled), the
 * careful start (rtol 1e-8 over the whole opt->settle), whose orbit is the
 * result (the quick one's, unstable, should the careful one fail).
 * USM_OK (out->converged), USM_EINPUT (bad parameters or options),
 * USM_EFAILED (integration or Newton failed; usm_hybrid_message). */
int usm_hybrid_solve(usm_hybrid *h, const usm_params *p, const usm_hybrid_options *opt,
                     usm_hybrid_result *out);

/* The same from a given start: the closed state x_start at the section time
 * ts (e.g. a neighbouring orbit's x0 and t0, for continuation), no
 * simulation.  Returns as usm_hybrid_solve. */
int usm_hybrid_solve_from(usm_hybrid *h, const usm_params *p, const usm_hybrid_options *opt,
                          double ts, const double *x_start, usm_hybrid_result *out);

/* The event-driven period map from the closed state x0 at ts: x1 = x(ts + T)
 * and, when B is not NULL, the monodromy dx1/dx0 (nx x nx, row-major, with
 * the saltation matrices).  USM_OK or USM_EFAILED (the end in an open phase,
 * an integration failure).  Uses p and rtol of the last usm_hybrid_solve or
 * usm_hybrid_set. */
int usm_hybrid_period_map(usm_hybrid *h, double ts, const double *x0, double *x1, double *B);

/* Lyapunov exponents computed by usm_hybrid_lyapunov. */
#define USM_HYBRID_LYAPUNOV_COUNT 2

/* The outcome of usm_hybrid_lyapunov. */
typedef struct usm_hybrid_lyapunov_result {
    double exponents[USM_HYBRID_LYAPUNOV_COUNT]; /* the largest two [1/s] (NaN: none) */
    long periods;               /* periods averaged over (after the skipped ones) */
    long separations, impacts;  /* over the whole run */
    double impact_velocity_max; /* [m/s] */
    double t_end;               /* where the run ended [s] */
    int open_end, n_end;        /* its mode (1 open) and state length */
    double y_end[USM_MAX_NY];   /* its state */
} usm_hybrid_lyapunov_result;

/* The largest Lyapunov exponents of the motion from the state y0 at t0
 * (open: 1 when the contact is open there and y0 is the open mode's state
 * of usm_model.unilateral->ny, else the closed state of nx): the state and
 * USM_HYBRID_LYAPUNOV_COUNT tangent vectors integrated together for
 * skip + periods excitation periods, the vectors mapped by the saltation
 * matrix at every switch (the period map's, but a landing after rebounds
 * lands, as in the simulation), and at the end of every period made
 * orthonormal again (Gram-Schmidt in the norm of the state's scales, the
 * cyclic rows dropped: their multipliers 1 are the symmetry's, not the
 * motion's); exponent j is the mean of the log of column j's growth over the
 * last `periods` periods, divided by T.  On a periodic orbit with real
 * dominant multiplier exponent 0 tends to ln(max |lambda|) / T.  Uses p and
 * rtol of the last usm_hybrid_set.  USM_OK; USM_EINPUT (periods < 1, skip <
 * 0); USM_EFAILED (integration failure; out holds what was averaged). */
int usm_hybrid_lyapunov(usm_hybrid *h, double t0, int open, const double *y0, long skip,
                        long periods, usm_hybrid_lyapunov_result *out);

/* Set parameters and tolerance for usm_hybrid_period_map without solving. */
int usm_hybrid_set(usm_hybrid *h, const usm_params *p, double rtol);

/* Columns of an orbit sample: t [s], open (0 closed, 1 open), the first nx
 * states of the current mode (the closed state x; in the open mode the same
 * coordinates of y), gap [m] (0 while closed), F_n [N], F_t [N] (0 while
 * open), rotor_speed [1/s]. */
#define USM_HYBRID_SAMPLE_COLS(nx) ((nx) + 6)
/* Most samples a period (usm_hybrid_orbit_samples's n). */
#define USM_HYBRID_MAX_SAMPLES 100000
/* Rows room for n samples a period: the n + 1 times and both sides of every
 * root the period map may meet (4 USM_HYBRID_MAX_SWITCHES + 1: switches and
 * touches without impact). */
#define USM_HYBRID_SAMPLE_ROWS(n) ((n) + 1 + 2 * (4 * USM_HYBRID_MAX_SWITCHES + 1))

/* One period of the converged orbit with separation r of this model (from
 * r->x0 at r->t0) for parameters p at rtol (0: the default, 1e-11; give the
 * solve's: the landing threshold depends on it): samples at the n + 1 times
 * t0 + k T / n (k = 0 .. n) and on both sides of every switch, in time
 * order, into rows (room for USM_HYBRID_SAMPLE_ROWS(n) rows of
 * USM_HYBRID_SAMPLE_COLS(nx) columns, row-major); their number in *nrows.
 * Afterwards h holds p, rtol and the orbit's scales, as after
 * usm_hybrid_set.  USM_OK; USM_EINPUT (n, p, rtol, r not converged or of
 * another model); USM_EFAILED (usm_hybrid_message), also where the sampled
 * period's mode sequence is not r's. */
int usm_hybrid_orbit_samples(usm_hybrid *h, const usm_params *p, const usm_hybrid_result *r,
                             double rtol, int n, double *rows, int *nrows);

/* Why the last call failed, or "".  Owned by h. */
const char *usm_hybrid_message(const usm_hybrid *h);

/* The orbit with separation r of model m at parameters p as CSV (`usm
 * periodic --orbit`): the header with units (t [s], open [1], the states,
 * gap [m], F_n [N], F_t [N], rotor_speed [1/s]) and the rows of
 * usm_hybrid_orbit_samples with n samples a period, at rtol (0: the
 * default).  USM_OK, or USM_EINPUT/USM_EFAILED with msg (USM_MSG_LEN
 * bytes). */
int usm_hybrid_write_orbit_csv(const usm_model *m, const usm_params *p,
                               const usm_hybrid_result *r, double rtol, int n, FILE *out,
                               char *msg);

/* The `usm periodic --json` object of an orbit with separation of model m
 * (keys: docs/unilateral.md), or with r NULL "converged": false and "error":
 * error.  0, or -1 on a write error or when out of memory. */
int usm_hybrid_write_json(const usm_model *m, const usm_params *p, const usm_hybrid_result *r,
                          const char *error, FILE *out);

#ifdef __cplusplus
}
#endif

#endif /* USM_PERIODIC_H */
