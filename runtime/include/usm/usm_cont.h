/* usm_cont.h: the continuation engine of libusm.  One branch of solutions of
 * a zero problem F(x) = 0, n equations in n + 1 unknowns x = (u, p) (the
 * parameter p last), is followed by pseudo-arclength continuation, and the
 * zeros of test functions along it are located by root finding on the
 * arclength.  The problem supplies F and its n x (n + 1) Jacobian through a
 * callback; the engine owns the predictor, the corrector, the step control
 * and the events.  docs/numerics.md ("The continuation engine") gives the
 * method.
 *
 * Life cycle (GSL style): usm_cont_alloc, usm_cont_set_problem, any number
 * of usm_cont_add_test, usm_cont_start, usm_cont_step until it says the
 * branch ended or was lost, usm_cont_free.
 *
 * Thread safety: a usm_cont is used by one thread at a time; distinct
 * engines are independent (the callbacks must be, too).
 */
#ifndef USM_CONT_H
#define USM_CONT_H

#ifdef __cplusplus
extern "C" {
#endif

/* F(x) into F[0..n-1] and, when J is not NULL, dF/dx into J (n rows of n + 1,
 * row-major; the parameter's column last).  0, or non-zero when x lies
 * outside the problem's domain or the evaluation failed: the corrector then
 * fails and the step is retried shorter. */
typedef int (*usm_cont_residual)(const double *x, double *F, double *J, void *ctx);

/* A test function at the point x of the branch, whose direction there is
 * dx = dx/ds (the unit tangent in the engine's scaled coordinates, given in
 * the problem's units: dx[i] = t[i] * scale[i]).  A NaN says it is undefined
 * at x: no zero is looked for where either end of a step is NaN. */
typedef double (*usm_cont_test_fn)(const double *x, const double *dx, void *ctx);

/* The built-in test function: the fold, dp/ds (the parameter's component of
 * the tangent).  Its index among the test functions is 0. */
#define USM_CONT_FOLD 0

/* Flags of a test function. */
#define USM_CONT_TEST_MONITOR 0 /* its zeros are events; the branch goes on */
#define USM_CONT_TEST_STOP 1    /* the branch ends at its first zero */
/* Or'ed to either: the test reads the point alone, never dx, so that the
 * trials of its location skip the tangent (one Jacobian each); it is called
 * with dx NULL there. */
#define USM_CONT_TEST_POINT 2

/* What usm_cont_step returns (besides a usage error, USM_CONT_EUSAGE). */
#define USM_CONT_STEP 0    /* a step was accepted; the branch goes on */
#define USM_CONT_END 1     /* the branch ended at a stopping zero in this step */
#define USM_CONT_LOST (-1) /* no step longer than h_min converged */
#define USM_CONT_EUSAGE (-2)

/* The engine's settings.  Step lengths are in the scaled arclength
 * (sum of (dx[i] / scale[i])^2 = ds^2). */
typedef struct usm_cont_options {
    double h0, h_min, h_max; /* first, shortest and longest step */
    double newton_tol;       /* the corrector stops when max |dz| <= this (scaled) */
    int newton_max;          /* corrector iterations */
    int grow_its;            /* the step doubles when the corrector took <= this many */
    int shrink_its;          /* and halves when it took >= this many */
    double cos_max_turn;     /* successive tangents at most this far apart (cosine);
                              * a sharper turn halves the step */
    double event_tol;        /* zeros are located to this in s (absolute, scaled) */
    int across_fold;         /* 1: the branch is followed around a fold (a fold is an
                              * event); 0: the branch ends at the fold */
    long max_steps;          /* usm_cont_step calls after which the branch is lost */
    int chord;               /* 1: the corrector factors the Jacobian once, at its first
                              * iterate, and reuses it (modified Newton: one Jacobian a
                              * correction, more iterations; the tangent at a step's end
                              * then takes one more): for a Jacobian that costs much more
                              * than F.  0 (default): Newton, the tangent from its last
                              * factorisation */
} usm_cont_options;

/* A located zero of a test function inside the last step. */
typedef struct usm_cont_event {
    int test;          /* index: USM_CONT_FOLD or what usm_cont_add_test returned */
    int stop;          /* 1: the branch ended here */
    double s;          /* arclength from the start of the step */
    double before;     /* the test function's value at the start of the step */
    const double *x;   /* the point, n + 1 values; valid until the next step */
    const double *dx;  /* the direction there, as for usm_cont_test_fn */
} usm_cont_event;

/* The engine itself (opaque). */
typedef struct usm_cont usm_cont;

/* Defaults: h0 0.01, h_min 1e-13, h_max 0.05, newton_tol 1e-10, newton_max
 * 12, grow_its 3, shrink_its 6, cos_max_turn 0.9, event_tol 1e-14,
 * across_fold 0, max_steps 2000000, chord 0. */
void usm_cont_options_default(usm_cont_options *o);

/* An engine for n equations in n + 1 unknowns (n >= 1), default options and
 * unit scales; NULL when out of memory or n < 1. */
usm_cont *usm_cont_alloc(int n);

/* NULL is allowed. */
void usm_cont_free(usm_cont *c);

/* The problem's residual and Jacobian with its user data. */
void usm_cont_set_problem(usm_cont *c, usm_cont_residual f, void *ctx);

/* The options (copied).  0, or USM_CONT_EUSAGE when one is out of range. */
int usm_cont_set_options(usm_cont *c, const usm_cont_options *o);

/* The options in force. */
const usm_cont_options *usm_cont_options_get(const usm_cont *c);

/* The size of each unknown (n + 1 positive values): the engine works in
 * z = x / scale, so that the arclength and the corrector's tolerance weigh
 * the unknowns alike.  May be called between steps (the current point and
 * tangent are carried over).  0, or USM_CONT_EUSAGE for a scale not positive
 * and finite. */
int usm_cont_set_scale(usm_cont *c, const double *scale);

/* Registers a test function; its index (>= 1), or USM_CONT_EUSAGE when
 * flags is unknown or out of memory.  Before usm_cont_start. */
int usm_cont_add_test(usm_cont *c, usm_cont_test_fn fn, void *ctx, int flags);

/* Starts the branch at x0 (n + 1 values): corrects it onto the branch with
 * the parameter held at x0[n], then takes the tangent so that dp/ds has the
 * sign of dir (+1 or -1).  0, or USM_CONT_LOST when the correction or the
 * tangent fails (x0 too far from a solution, or a fold at x0). */
int usm_cont_start(usm_cont *c, const double *x0, int dir);

/* One step along the branch: predictor, corrector, step control (a failed
 * step is retried at half the length), then the test functions' zeros in
 * the step.  USM_CONT_STEP, USM_CONT_END (the current point is the stopping
 * zero) or USM_CONT_LOST; USM_CONT_EUSAGE before usm_cont_start or after the
 * branch ended. */
int usm_cont_step(usm_cont *c);

/* The current point (n + 1 values) and its direction dx/ds. */
const double *usm_cont_point(const usm_cont *c);
/* The direction dx/ds at the current point, as for usm_cont_test_fn. */
const double *usm_cont_direction(const usm_cont *c);

/* The length of the next step (scaled arclength). */
double usm_cont_step_length(const usm_cont *c);

/* Corrector iterations of the last accepted step. */
int usm_cont_iterations(const usm_cont *c);

/* The zeros located in the last step, in the order of s. */
int usm_cont_event_count(const usm_cont *c);
/* Event k of the last step, 0 <= k < usm_cont_event_count; NULL otherwise. */
const usm_cont_event *usm_cont_event_at(const usm_cont *c, int k);

/* The last step as an arc: s_end its length (up to the stopping zero when
 * the branch ended in it).  *x_start: its first point. */
double usm_cont_step_arc(const usm_cont *c, const double **x_start);

/* The point of the last step's arc at arclength s in [0, s_end]: the
 * predictor at s corrected onto the branch in the hyperplane normal to the
 * step's first tangent.  With dx not NULL, the direction there.  0, or -1
 * when the correction fails. */
int usm_cont_arc_point(usm_cont *c, double s, double *x, double *dx);

/* A zero of fn on the last step's arc, where its values at the ends, f0 at
 * s = 0 and f1 at s_end, differ in sign, located by Brent on s to
 * event_tol; the point into x (n + 1 values) and its s into *s.  0, or -1
 * when the values do not bracket a zero or an evaluation failed.  For a
 * problem's own conditions along a step (a grid value of the parameter). */
int usm_cont_arc_locate(usm_cont *c, usm_cont_test_fn fn, void *ctx, double f0, double f1,
                        double *s, double *x);

/* ---- branch points ------------------------------------------------------------------
 * A simple branch point is where two branches cross: dF/dx has a null space
 * of dimension two there, and the bordered Jacobian [dF/dx; t] (t the unit
 * tangent) is singular.  Its determinant, oriented by the tangent, changes
 * sign across the branch point and not across a fold (the bordered matrix
 * stays regular there), so it is the test function. */

/* Registers the branch-point test function, det [dF/dz; t] in the scaled
 * coordinates (one Jacobian and one factorisation a point more); flags
 * USM_CONT_TEST_MONITOR or USM_CONT_TEST_STOP.  Its index (>= 1), or
 * USM_CONT_EUSAGE.  Before usm_cont_start. */
int usm_cont_add_branch_test(usm_cont *c, int flags);

/* What usm_cont_branch_tangent says it used. */
#define USM_CONT_ABE 0           /* the algebraic branching equation */
#define USM_CONT_PERPENDICULAR 1 /* the null vector orthogonal to the followed branch */

/* The tangent of the other branch at a branch point x (n + 1 values, e.g. a
 * branch-point event's x) where the followed branch has the direction dx
 * (its dx): the null space of dF/dx there, {t, phi} with phi orthogonal to
 * t, and on it the algebraic branching equation
 *   psi' F_xx[a t + b phi, a t + b phi] = 0   (psi the left null vector),
 * a quadratic in (a, b) with one root along t; the other root is the
 * answer, in the problem's units like dx (tau[i] = tau_scaled[i] * scale[i]),
 * with dtau/ds's sign left to the caller.  Where the equation does not
 * separate two real roots (F_xx by central differences of the Jacobian is
 * degenerate there), phi itself ("perpendicular tangent").
 * USM_CONT_ABE, USM_CONT_PERPENDICULAR, or USM_CONT_LOST when dF/dx has no
 * two-dimensional null space at x (not a branch point) or an evaluation
 * failed.  phi into phi when not NULL (problem's units too). */
int usm_cont_branch_tangent(usm_cont *c, const double *x, const double *dx, double *tau,
                            double *phi);

/* Starts the other branch at the branch point x, dx (as for
 * usm_cont_branch_tangent): the predictor x + h tau (h in the scaled
 * arclength; h <= 0: the option h0) corrected onto the branch in the
 * hyperplane normal to phi, which the followed branch meets only at the
 * branch point, so that the corrector cannot fall back onto it.  dir picks the
 * half: +1 the one along which the parameter grows, -1 the other; where
 * the new branch leaves with |dp/ds| < 1e-8 (a pitchfork's), the half
 * along which the unknown with the largest tangent component grows.  The
 * engine then follows that branch as after usm_cont_start (test functions
 * restarted, the step h0).  0, USM_CONT_LOST, or USM_CONT_EUSAGE (dir not
 * +-1, no problem set). */
int usm_cont_switch_branch(usm_cont *c, const double *x, const double *dx, int dir, double h);

/* Newton on [F(x) = 0; x[k] = value] from x, in place: the point of the
 * branch where unknown k (the parameter: k = n) has the given value.  The
 * corrector's iterations, or -1 when Newton fails (x unchanged then). */
int usm_cont_correct_fixed(usm_cont *c, double *x, int k, double value);

#ifdef __cplusplus
}
#endif

#endif /* USM_CONT_H */
