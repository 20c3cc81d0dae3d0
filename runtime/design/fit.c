/* Parameters identified from measured characteristics (usm_fit.h): the
 * least-squares driver (starts, GSL's Levenberg-Marquardt, profile
 * likelihood).  One evaluation (fit_eval.c) gives the residuals and the
 * Jacobian together; GSL asks for them separately, so the pass of the last
 * point asked for is kept. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <gsl/gsl_blas.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_linalg.h>
#include <gsl/gsl_matrix.h>
#include <gsl/gsl_multifit_nlinear.h>
#include <gsl/gsl_qrng.h>
#include <gsl/gsl_vector.h>

#include "fit_internal.h"
#include "usm_fit.h"


/* ---- options ------------------------------------------------------------------- */

void usm_fit_options_default(usm_fit_options *o)
{
    memset(o, 0, sizeof *o);
    o->starts = 4;
    o->spread = 100.0;
    o->max_iter = 100;
    o->ident_tol = 0.05;
    o->advise = 1;
    o->profile = 1;
    usm_op_options_default(&o->op);
    o->op.from_rest = 1;
}

int usm_fit_parse_names(const usm_model *m, const char *field, const char *text,
                        usm_fit_options *o, char msg[USM_MSG_LEN])
{
    char buf[512];
    if (!text || text[0] == '\0' || strlen(text) >= sizeof buf) {
        snprintf(msg, USM_MSG_LEN, "%s: expected NAME[,NAME...] (parameters to fit)", field);
        return USM_EINPUT;
    }
    strcpy(buf, text);
    o->nfit = 0;
    for (char *save = NULL, *tok = strtok_r(buf, ",", &save); tok;
         tok = strtok_r(NULL, ",", &save)) {
        while (*tok == ' ')
            ++tok;
        const usm_param_info *pi = usm_params_find(tok);
        if (!pi) {
            snprintf(msg, USM_MSG_LEN, "%s: unknown parameter \"%.60s\"", field, tok);
            return USM_EINPUT;
        }
        int k = usm_param_index(pi);
        const usm_param_coupling *c = m ? usm_param_coupled(m, k) : NULL;
        if (c) {
            snprintf(msg, USM_MSG_LEN, "%s: %s equals %s under the assumption of %s: fit %s",
                     field, tok, usm_param_table[c->equals].name, c->because,
                     usm_param_table[c->equals].name);
            return USM_EINPUT;
        }
        for (int j = 0; j < o->nfit; ++j)
            if (o->fit[j] == k) {
                snprintf(msg, USM_MSG_LEN, "%s: %s named twice", field, tok);
                return USM_EINPUT;
            }
        if (o->nfit == USM_NPARAMS) {
            snprintf(msg, USM_MSG_LEN, "%s: too many parameters", field);
            return USM_EINPUT;
        }
        o->fit[o->nfit++] = k;
    }
    if (o->nfit == 0) {
        snprintf(msg, USM_MSG_LEN, "%s: no parameter named", field);
        return USM_EINPUT;
    }
    return USM_OK;
}


int usm_fit_check(const usm_model *m, const usm_params *p, const usm_fit_data *d,
                  const usm_fit_options *o, char msg[USM_MSG_LEN])
{
    if (o->nfit < 1 || o->nfit > USM_NPARAMS) {
        snprintf(msg, USM_MSG_LEN, "fit: no parameter to fit");
        return USM_EINPUT;
    }
    if (o->starts < 1 || o->starts > 100 || o->max_iter < 1 || !(o->ident_tol > 0) ||
        !(o->spread >= 1 && o->spread <= 1e6)) {
        snprintf(msg, USM_MSG_LEN, "fit: starts must be 1..100, spread 1..1e6, max_iter >= 1, "
                 "ident_tol > 0");
        return USM_EINPUT;
    }
    for (int j = 0; j < o->nfit; ++j) {
        int k = o->fit[j];
        if (k < 0 || k >= USM_NPARAMS) {
            snprintf(msg, USM_MSG_LEN, "fit: parameter index %d out of range", k);
            return USM_EINPUT;
        }
        const char *name = usm_param_table[k].name;
        if (m && usm_param_coupled(m, k)) {
            snprintf(msg, USM_MSG_LEN, "%s: tied to %s by the model's assumptions: fit that",
                     name, usm_param_table[usm_param_coupled(m, k)->equals].name);
            return USM_EINPUT;
        }
        for (int c = 0; c < d->ncond; ++c)
            if (d->cond[c] == k) {
                snprintf(msg, USM_MSG_LEN, "%s: is a condition column of the data, it cannot "
                         "also be fitted", name);
                return USM_EINPUT;
            }
        double v = usm_params_get(p, &usm_param_table[k]);
        if (fit_log_scale(k) && !(v > 0)) {
            snprintf(msg, USM_MSG_LEN, "%s: the start value %g must be positive (fitted in log "
                     "scale: --set a positive start)", name, v);
            return USM_EINPUT;
        }
    }
    const int n = usm_fit_data_count(d);
    int all_sigma = 1;
    for (int c = 0; c < d->nout; ++c)
        all_sigma &= d->has_sigma[c];
    if (n < o->nfit || (!all_sigma && n == o->nfit)) {
        snprintf(msg, USM_MSG_LEN, "data: %d measured value%s for %d fitted parameter%s: %s", n,
                 n == 1 ? "" : "s", o->nfit, o->nfit == 1 ? "" : "s",
                 n < o->nfit ? "fewer points than parameters"
                             : "no residual freedom left to estimate sigma (give sigma_ columns "
                               "or more points)");
        return USM_EINPUT;
    }
    return USM_OK;
}


/* ---- the least-squares driver -------------------------------------------------------- */

static int same_point(const fit_eval *e, const gsl_vector *x)
{
    if (!e->have)
        return 0;
    for (int j = 0; j < e->np; ++j)
        if (gsl_vector_get(x, (size_t)j) != e->t[j])
            return 0;
    return 1;
}

static int ensure(fit_eval *e, const gsl_vector *x)
{
    double t[USM_NPARAMS];
    if (same_point(e, x))
        return GSL_SUCCESS;
    for (int j = 0; j < e->np; ++j)
        t[j] = gsl_vector_get(x, (size_t)j);
    if (fit_eval_at(e, t) != USM_OK) {
        e->failed = 1;
        return GSL_ENOMEM;
    }
    return GSL_SUCCESS;
}

static int lm_f(const gsl_vector *x, void *data, gsl_vector *f)
{
    fit_eval *e = data;
    int st = ensure(e, x);
    if (st != GSL_SUCCESS)
        return st;
    for (int i = 0; i < e->n; ++i)
        gsl_vector_set(f, (size_t)i, e->f[i]);
    return GSL_SUCCESS;
}

static int lm_df(const gsl_vector *x, void *data, gsl_matrix *J)
{
    fit_eval *e = data;
    int st = ensure(e, x);
    if (st != GSL_SUCCESS)
        return st;
    for (int i = 0; i < e->n; ++i)
        for (int j = 0; j < e->np; ++j)
            gsl_matrix_set(J, (size_t)i, (size_t)j, e->J[(size_t)i * (size_t)e->np + (size_t)j]);
    return GSL_SUCCESS;
}

/* One local search from t (replaced by its end); its sum of squares in *chi2. */
static int local_search(fit_eval *e, gsl_multifit_nlinear_workspace *w, double *t, double *chi2,
                        int *iters)
{
    gsl_multifit_nlinear_fdf fdf;
    gsl_vector_view x0 = gsl_vector_view_array(t, (size_t)e->np);
    int info;
    memset(&fdf, 0, sizeof fdf);
    fdf.f = lm_f;
    fdf.df = lm_df;
    fdf.fvv = NULL; /* geodesic acceleration's second directional derivative by differences */
    fdf.n = (size_t)e->n;
    fdf.p = (size_t)e->np;
    fdf.params = e;
    e->failed = 0;
    if (gsl_multifit_nlinear_init(&x0.vector, &fdf, w) != GSL_SUCCESS || e->failed)
        return e->failed ? USM_EFAILED : USM_ENOSOLUTION;
    int st = gsl_multifit_nlinear_driver((size_t)e->o->max_iter, 1e-10, 1e-10, 0.0, NULL, NULL,
                                         &info, w);
    if (e->failed)
        return USM_EFAILED;
    const gsl_vector *x = gsl_multifit_nlinear_position(w);
    for (int j = 0; j < e->np; ++j)
        t[j] = gsl_vector_get(x, (size_t)j);
    *iters += (int)gsl_multifit_nlinear_niter(w);
    (void)st; /* a search stopped at max_iter or unable to improve still has its best point */
    if (fit_eval_at(e, t) != USM_OK)
        return USM_EFAILED;
    *chi2 = e->chi2;
    return isfinite(e->chi2) ? USM_OK : USM_ENOSOLUTION;
}

/* The box of the starts in the fitted scale: a log-scale parameter from its
 * given value divided by o->spread to the value times o->spread, a linear one
 * the given value +- o->spread times its magnitude (at least a thousandth of
 * its range), both clipped into the physical range (usm_param_ranges). */
static void start_box(const fit_eval *e, int j, double *lo, double *hi)
{
    const int k = e->o->fit[j];
    const double v = usm_params_get(&e->base, &usm_param_table[k]), f = e->o->spread;
    const usm_param_range rg = usm_param_ranges[k];
    if (e->log_scale[j]) {
        *lo = log(v / f);
        *hi = log(v * f);
        if (rg.lo > 0 && *lo < log(rg.lo))
            *lo = log(rg.lo);
        if (*hi > log(rg.hi))
            *hi = log(rg.hi);
    } else {
        const double w = f * fmax(fabs(v), 1e-3 * (rg.hi - rg.lo));
        *lo = fmax(v - w, rg.lo);
        *hi = fmin(v + w, rg.hi);
    }
}

/* The candidates of the starts: the first `count` points of the Sobol
 * sequence in as many dimensions as parameters (GSL's gsl_qrng_sobol, the
 * all-zero corner skipped: deterministic, no seed), mapped into the box;
 * row-major count x np in t.  USM_OK or USM_EFAILED. */
static int start_candidates(const fit_eval *e, int count, double *t)
{
    double lo[USM_NPARAMS], hi[USM_NPARAMS], u[USM_NPARAMS];
    gsl_qrng *q = gsl_qrng_alloc(gsl_qrng_sobol, (unsigned)e->np);
    if (!q)
        return USM_EFAILED;
    for (int j = 0; j < e->np; ++j)
        start_box(e, j, &lo[j], &hi[j]);
    gsl_qrng_get(q, u); /* the corner (0, ..., 0) */
    for (int s = 0; s < count; ++s) {
        gsl_qrng_get(q, u);
        for (int j = 0; j < e->np; ++j)
            t[(size_t)s * (size_t)e->np + (size_t)j] = lo[j] + u[j] * (hi[j] - lo[j]);
    }
    gsl_qrng_free(q);
    return USM_OK;
}

/* The starts: the given values, then the start_count - 1 candidates with the
 * lowest sum of squares (evaluated without the Jacobian) among
 * USM_FIT_SCREEN per start, ties kept in the sequence's order.  t holds
 * o->starts x np; *nstarts the starts found (fewer when candidates fail). */
static int choose_starts(fit_eval *e, double *t, int *nstarts)
{
    const int np = e->np, want = e->o->starts - 1, ncand = USM_FIT_SCREEN * want;
    double *cand = NULL, *chi2 = NULL;
    int *order = NULL;
    *nstarts = 1;
    for (int j = 0; j < np; ++j)
        t[j] = e->log_scale[j]
                   ? log(usm_params_get(&e->base, &usm_param_table[e->o->fit[j]]))
                   : usm_params_get(&e->base, &usm_param_table[e->o->fit[j]]);
    if (want < 1)
        return USM_OK;
    cand = malloc((size_t)ncand * (size_t)np * sizeof *cand);
    chi2 = malloc((size_t)ncand * sizeof *chi2);
    order = malloc((size_t)ncand * sizeof *order);
    int st = cand && chi2 && order ? start_candidates(e, ncand, cand) : USM_EFAILED;
    e->no_jacobian = 1;
    for (int s = 0; s < ncand && st == USM_OK; ++s) {
        st = fit_eval_at(e, cand + (size_t)s * (size_t)np);
        chi2[s] = isfinite(e->chi2) ? e->chi2 : INFINITY;
        order[s] = s;
    }
    e->no_jacobian = 0;
    e->have = 0;
    if (st == USM_OK) {
        /* insertion sort: stable, and ncand is small */
        for (int a = 1; a < ncand; ++a)
            for (int b = a; b > 0 && chi2[order[b]] < chi2[order[b - 1]]; --b) {
                int tmp = order[b];
                order[b] = order[b - 1];
                order[b - 1] = tmp;
            }
        for (int s = 0; s < want && isfinite(chi2[order[s]]); ++s, ++*nstarts)
            memcpy(t + (size_t)*nstarts * (size_t)np, cand + (size_t)order[s] * (size_t)np,
                   (size_t)np * sizeof *t);
    }
    free(cand);
    free(chi2);
    free(order);
    return st;
}

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void usm_fit_result_free(usm_fit_result *r)
{
    if (!r)
        return;
    free(r->points);
    r->points = NULL;
    r->npoints = 0;
}

static int fail(usm_fit_result *out, int status, const char *fmt, const char *arg)
{
    out->status = status;
    snprintf(out->message, sizeof out->message, fmt, arg);
    return status;
}

/* ---- profile likelihood --------------------------------------------------------------- */

/* The sum of squares minimized over every fitted parameter but j, with j
 * held at the fitted-scale value z, started from the estimate t.  NaN when
 * z leaves the parameter's range or no finite minimum is found. */
static double profile_chi2(const usm_model *m, const usm_fit_data *d, const usm_fit_options *o,
                           const fit_eval *full, const double *t, int j, double z, int *evals)
{
    const int k = o->fit[j];
    const double v = full->log_scale[j] ? exp(z) : z;
    const usm_param_range rg = usm_param_ranges[k];
    if (!(v >= rg.lo && v <= rg.hi) || (full->log_scale[j] && !(v > 0)))
        return NAN;
    usm_params p;
    fit_params_at(full, t, &p);
    *usm_params_field(&p, &usm_param_table[k]) = v;
    usm_fit_options so = *o;
    double ts[USM_NPARAMS], chi2 = NAN;
    so.nfit = 0;
    for (int i = 0; i < o->nfit; ++i)
        if (i != j) {
            ts[so.nfit] = t[i];
            so.fit[so.nfit++] = o->fit[i];
        }
    fit_eval e;
    if (fit_eval_init(&e, m, &p, d, &so) == USM_OK) {
        if (so.nfit == 0) {
            if (fit_eval_at(&e, ts) == USM_OK)
                chi2 = e.chi2;
        } else {
            gsl_multifit_nlinear_parameters fp = gsl_multifit_nlinear_default_parameters();
            fp.trs = gsl_multifit_nlinear_trs_lmaccel;
            gsl_multifit_nlinear_workspace *w =
                gsl_multifit_nlinear_alloc(gsl_multifit_nlinear_trust, &fp, (size_t)e.n,
                                           (size_t)e.np);
            int iters = 0;
            if (w && local_search(&e, w, ts, &chi2, &iters) != USM_OK)
                chi2 = NAN;
            gsl_multifit_nlinear_free(w);
        }
    }
    *evals += e.evaluations;
    fit_eval_free(&e);
    return chi2;
}

/* Each end of each interval checked against the profile likelihood: the
 * profile's deviation at the Jacobian's end, g = sqrt(dchi2) / (q s) - 1
 * (0 for a quadratic sum of squares), decides; where |g| > 0.1 the end is
 * located by bisection in sqrt(dchi2) after stepping out by doubling. */
static void profile(const usm_model *m, const usm_fit_data *d, const usm_fit_options *o,
                    const fit_eval *e, const double *t, usm_fit_result *out)
{
    const double level = out->quantile * out->sigma_scale;
    for (int j = 0; j < out->nfit; ++j) {
        out->profiled[j] = 0;
        out->profile_lo[j] = out->lo[j];
        out->profile_hi[j] = out->hi[j];
        const double h = out->quantile * out->se_scaled[j];
        if (!isfinite(h) || !(h > 0) || !isfinite(level))
            continue;
        for (int side = -1; side <= 1; side += 2) {
            double a = 0, b = h, c2 = profile_chi2(m, d, o, e, t, j, t[j] + side * h,
                                                   &out->evaluations);
            double r = sqrt(fmax(c2 - out->chi2, 0)) / level; /* 1 for a quadratic */
            if (isfinite(r) && fabs(r - 1) <= 0.1)
                continue;
            out->profiled[j] = 1;
            double end = INFINITY;
            if (!isfinite(r) || r < 1) { /* flatter: step out until the level is passed */
                a = h;
                for (int k = 0; k < 8 && !(isfinite(r) && r >= 1); ++k) {
                    a = b;
                    b *= 2;
                    c2 = profile_chi2(m, d, o, e, t, j, t[j] + side * b, &out->evaluations);
                    r = sqrt(fmax(c2 - out->chi2, 0)) / level;
                    if (!isfinite(c2))
                        break;
                }
            }
            if (isfinite(r) && r >= 1) {
                for (int k = 0; k < 12; ++k) {
                    double mid = 0.5 * (a + b);
                    c2 = profile_chi2(m, d, o, e, t, j, t[j] + side * mid, &out->evaluations);
                    r = sqrt(fmax(c2 - out->chi2, 0)) / level;
                    if (isfinite(r) && r >= 1)
                        b = mid;
                    else
                        a = mid;
                }
                end = t[j] + side * b;
                end = e->log_scale[j] ? exp(end) : end;
            } else
                end = side < 0 ? (e->log_scale[j] ? 0.0 : -INFINITY) : INFINITY;
            if (side < 0)
                out->profile_lo[j] = end;
            else
                out->profile_hi[j] = end;
        }
    }
}

int usm_fit_run(const usm_model *m, const usm_params *p, const usm_fit_data *d,
                const usm_fit_options *o, usm_fit_result *out)
{
    fit_eval e;
    gsl_multifit_nlinear_workspace *w = NULL;
    double t0 = now(), best[USM_NPARAMS], best_chi2 = INFINITY;
    int status;
    memset(out, 0, sizeof *out);
    if ((status = usm_fit_check(m, p, d, o, out->message)) != USM_OK) {
        out->status = status;
        return status;
    }
    if (fit_eval_init(&e, m, p, d, o) != USM_OK) {
        fit_eval_free(&e);
        return fail(out, USM_EFAILED, "%s", "out of memory");
    }
    out->nfit = o->nfit;
    for (int j = 0; j < o->nfit; ++j) {
        out->fit[j] = o->fit[j];
        out->log_scale[j] = e.log_scale[j];
        out->start[j] = usm_params_get(p, &usm_param_table[o->fit[j]]);
    }
    gsl_multifit_nlinear_parameters fp = gsl_multifit_nlinear_default_parameters();
    fp.trs = gsl_multifit_nlinear_trs_lmaccel;
    if (!(w = gsl_multifit_nlinear_alloc(gsl_multifit_nlinear_trust, &fp, (size_t)e.n,
                                         (size_t)e.np))) {
        fit_eval_free(&e);
        return fail(out, USM_EFAILED, "%s", "out of memory");
    }
    double *starts = malloc((size_t)o->starts * (size_t)e.np * sizeof *starts), chi2s[100];
    int nstarts = 0;
    status = starts ? choose_starts(&e, starts, &nstarts) : USM_EFAILED;
    if (status == USM_OK)
        status = USM_ENOSOLUTION;
    for (int s = 0; s < nstarts && status != USM_EFAILED; ++s) {
        double t[USM_NPARAMS], chi2 = INFINITY;
        memcpy(t, starts + (size_t)s * (size_t)e.np, (size_t)e.np * sizeof *t);
        int st = local_search(&e, w, t, &chi2, &out->iterations);
        out->starts++;
        chi2s[s] = st == USM_OK ? chi2 : INFINITY;
        if (st == USM_EFAILED) {
            status = USM_EFAILED;
            break;
        }
        if (st == USM_OK && chi2 < best_chi2) {
            best_chi2 = chi2;
            memcpy(best, t, sizeof t);
            out->best_start = s;
            status = USM_OK;
        }
    }
    /* a start reached the best minimum when its sum of squares is the best's
     * within 1e-6 of it (and 1e-9 per value: an exact fit's is 0) */
    for (int s = 0; s < out->starts && status == USM_OK; ++s)
        out->starts_at_best += chi2s[s] <= best_chi2 + 1e-6 * best_chi2 + 1e-9 * e.n;
    free(starts);
    gsl_multifit_nlinear_free(w);
    if (status == USM_OK)
        status = fit_eval_at(&e, best);
    if (status == USM_OK)
        status = fit_statistics(&e, best, out);
    out->evaluations = e.evaluations;
    if (status == USM_OK && o->profile)
        profile(m, d, o, &e, best, out);
    if (status != USM_OK && !out->message[0])
        fail(out, status, "%s", status == USM_EFAILED ? "out of memory"
                                                        : "no start gives a finite sum of squares");
    fit_eval_free(&e);
    out->status = status;
    out->wall = now() - t0;
    return status;
}
