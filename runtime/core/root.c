/* The bracketing root locator (see root.h). */
#include "root.h"

#include <math.h>
#include <stdlib.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_roots.h>

struct usm_root {
    gsl_root_fsolver *brent;
    usm_root_fn f;
    void *ctx;
    int failed;           /* an evaluation returned NaN or infinity */
    int ends_known;       /* flo, fhi known: GSL's evaluations at the ends are answered */
    double lo, hi, flo, fhi;
    double blo, bhi;      /* the bracket while f is evaluated */
};

usm_root *usm_root_alloc(void)
{
    usm_root *r = calloc(1, sizeof *r);
    if (!r)
        return NULL;
    if (!(r->brent = gsl_root_fsolver_alloc(gsl_root_fsolver_brent))) {
        free(r);
        return NULL;
    }
    return r;
}

void usm_root_free(usm_root *r)
{
    if (!r)
        return;
    gsl_root_fsolver_free(r->brent);
    free(r);
}

void usm_root_bracket(const usm_root *r, double *lo, double *hi)
{
    *lo = r->blo;
    *hi = r->bhi;
}

/* What GSL evaluates: the known ends' values, else f; a failed evaluation
 * is flagged and answered with 0 (GSL would call its error handler on a
 * value that is not finite), and the locator stops after GSL's step. */
static double evaluate(double x, void *p)
{
    usm_root *r = p;
    if (r->ends_known && (x == r->lo || x == r->hi))
        return x == r->lo ? r->flo : r->fhi;
    if (r->failed)
        return 0.0;
    const double y = r->f(x, r->ctx);
    if (!isfinite(y)) {
        r->failed = 1;
        return 0.0;
    }
    return y;
}

static int brent(usm_root *r, usm_root_fn f, void *ctx, double lo, double hi, double flo,
                 double fhi, int ends_known, const usm_root_stop *stop, double *x)
{
    if (lo > hi) {
        const double t = lo, ft = flo;
        lo = hi, flo = fhi;
        hi = t, fhi = ft;
    }
    r->f = f;
    r->ctx = ctx;
    r->failed = 0;
    r->ends_known = 0;
    r->lo = r->blo = lo;
    r->hi = r->bhi = hi;
    if (!ends_known) {
        /* in GSL's order (lower, then upper); from here on they are known, so
         * that a bracket without a sign change never reaches GSL's error
         * handler */
        flo = evaluate(lo, r);
        if (!r->failed)
            fhi = evaluate(hi, r);
        if (r->failed)
            return -1;
    }
    if (flo == 0.0 || fhi == 0.0) {
        *x = flo == 0.0 ? lo : hi;
        return 0;
    }
    if (!isfinite(flo) || !isfinite(fhi) || (flo < 0) == (fhi < 0))
        return -1;
    r->ends_known = 1;
    r->flo = flo;
    r->fhi = fhi;
    gsl_function F = {evaluate, r};
    if (gsl_root_fsolver_set(r->brent, &F, lo, hi) != GSL_SUCCESS || r->failed)
        return -1;
    for (int it = 0; it < stop->max_iter; ++it) {
        if (gsl_root_fsolver_iterate(r->brent) != GSL_SUCCESS || r->failed)
            return -1;
        lo = r->blo = gsl_root_fsolver_x_lower(r->brent);
        hi = r->bhi = gsl_root_fsolver_x_upper(r->brent);
        if (gsl_root_test_interval(lo, hi, stop->epsabs, stop->epsrel) == GSL_SUCCESS)
            break;
    }
    *x = gsl_root_fsolver_root(r->brent);
    return 0;
}

int usm_root_brent(usm_root *r, usm_root_fn f, void *ctx, double lo, double hi, double flo,
                   double fhi, const usm_root_stop *stop, double *x)
{
    return brent(r, f, ctx, lo, hi, flo, fhi, 1, stop, x);
}

int usm_root_brent_eval(usm_root *r, usm_root_fn f, void *ctx, double lo, double hi,
                        const usm_root_stop *stop, double *x)
{
    return brent(r, f, ctx, lo, hi, 0.0, 0.0, 0, stop, x);
}

int usm_root_bisect(usm_root_indicator f, void *ctx, double a, int ia, double b, double tol,
                    int max_iter, double *x)
{
    for (int it = 0; it < max_iter && fabs(b - a) > tol; ++it) {
        const double m = 0.5 * (a + b);
        const int im = f(m, ctx);
        if (im == USM_ROOT_FAILED)
            return -1;
        if (im == USM_ROOT_UNDEFINED)
            return 0;
        if (im == ia)
            a = m;
        else
            b = m;
    }
    *x = 0.5 * (a + b);
    return 1;
}
