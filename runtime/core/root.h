/* root.h: the one bracketing root locator of libusm (internal; not
 * installed).  Every sign change the runtime locates goes through it: the
 * tilt angles, the friction law's extrema and the slip speeds of the
 * stationary solutions (solve/steady.c), the test functions' zeros along
 * a continued branch (cont/cont.c: a sweep's fold, stick limit, stall,
 * monitors), the stability changes along a sweep (study/sweep_stability.c),
 * the start threshold of a sweep's operating-point jump (study/sweep_op.c),
 * the events of the periodic-orbit sweep (study/periodic_sweep.c); a
 * boundary of a map (study/map.c) and the other operating-point jumps, where
 * only a yes/no indicator is known, by its bisection.
 *
 * Brent's method is GSL's gsl_root_fsolver_brent (inverse quadratic
 * interpolation, secant and bisection steps; the bracket always holds the
 * sign change), stopped by gsl_root_test_interval on the bracket:
 * |hi - lo| < epsabs + epsrel min(|lo|, |hi|) (min 0 when lo < 0 < hi).
 *
 * The function: a NaN or infinite value says the evaluation failed, and
 * the locator stops with -1 (GSL's own error handler is never reached).
 */
#ifndef USM_CORE_ROOT_H
#define USM_CORE_ROOT_H

/* f(x, ctx), whose sign change is located. */
typedef double (*usm_root_fn)(double x, void *ctx);

/* When Brent stops. */
typedef struct usm_root_stop {
    double epsabs, epsrel; /* on the bracket, as gsl_root_test_interval */
    int max_iter;          /* iterations; after them the best estimate so far */
} usm_root_stop;

/* A locator: GSL's Brent solver and the state of one location. */
typedef struct usm_root usm_root;

/* NULL when out of memory. */
usm_root *usm_root_alloc(void);
/* NULL is allowed. */
void usm_root_free(usm_root *r);

/* The root of f in the bracket [lo, hi] (either order), where f changes
 * sign, by Brent's method.  flo and fhi are f's values at the ends, known to
 * the caller and not evaluated again: an end where f is 0 is the root; ends
 * of the same sign (or not finite) are -1.  0 and *x, or -1 when the bracket
 * holds no sign change or an evaluation failed. */
int usm_root_brent(usm_root *r, usm_root_fn f, void *ctx, double lo, double hi, double flo,
                   double fhi, const usm_root_stop *stop, double *x);

/* The same where the values at the ends are not known: f is evaluated
 * there first (at lo, then at hi, as GSL's Brent would). */
int usm_root_brent_eval(usm_root *r, usm_root_fn f, void *ctx, double lo, double hi,
                        const usm_root_stop *stop, double *x);

/* During an evaluation of f by usm_root_brent*: the current bracket
 * [*lo, *hi], whose ends are points where f was evaluated (or the ends
 * given); the point being evaluated lies inside it.  For warm starts from
 * the ends' solutions.  After usm_root_brent*: the last bracket (after
 * -1, the one in which the failed evaluation was made). */
void usm_root_bracket(const usm_root *r, double *lo, double *hi);

/* An indicator of a yes/no property at x (e.g. "a stationary solution
 * exists"), where no function value is there to interpolate: 0 or 1, or
 * USM_ROOT_UNDEFINED (the property is undefined at x) or USM_ROOT_FAILED
 * (the evaluation failed). */
typedef int (*usm_root_indicator)(double x, void *ctx);
#define USM_ROOT_UNDEFINED (-1)
#define USM_ROOT_FAILED (-2)

/* Where the indicator changes between a (where it is ia) and b (where it is
 * not), by bisection: the midpoint replaces the end with its indicator
 * value, until |b - a| <= tol or max_iter halvings.  1 and *x the midpoint
 * of the last bracket; 0 when the indicator became undefined; -1 when an
 * evaluation failed. */
int usm_root_bisect(usm_root_indicator f, void *ctx, double a, int ia, double b, double tol,
                    int max_iter, double *x);

#endif /* USM_CORE_ROOT_H */
