/* What a fit reports (usm_fit.h): the covariance and intervals from the
 * Jacobian at the minimum, chi^2, the residuals, and the identifiability
 * from the singular values of the Jacobian with unit-norm columns (the
 * collinearity of the parameters' effects on the data, independent of
 * their units and of the noise), with the measurement that would separate
 * what the data do not. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_cdf.h>
#include <gsl/gsl_linalg.h>
#include <gsl/gsl_matrix.h>
#include <gsl/gsl_vector.h>

#include "fit_internal.h"

/* A singular value below this fraction of the largest is a direction of
 * no information at all: its variance is infinite. */
#define SINGULAR_FLOOR 1e-12

/* SVD of the n x np matrix A (row-major): singular values s (descending) and
 * right vectors V (np x np, column k the k-th).  USM_OK or USM_EFAILED. */
static int svd(const double *A, int n, int np, double *s, double *V)
{
    gsl_matrix *U = gsl_matrix_alloc((size_t)n, (size_t)np);
    gsl_matrix *Vm = gsl_matrix_alloc((size_t)np, (size_t)np);
    gsl_vector *S = gsl_vector_alloc((size_t)np), *work = gsl_vector_alloc((size_t)np);
    int st = USM_EFAILED;
    if (U && Vm && S && work) {
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < np; ++j)
                gsl_matrix_set(U, (size_t)i, (size_t)j, A[(size_t)i * (size_t)np + (size_t)j]);
        if (gsl_linalg_SV_decomp(U, Vm, S, work) == 0) {
            for (int j = 0; j < np; ++j) {
                s[j] = gsl_vector_get(S, (size_t)j);
                for (int k = 0; k < np; ++k)
                    V[j * np + k] = gsl_matrix_get(Vm, (size_t)j, (size_t)k);
            }
            st = USM_OK;
        }
    }
    gsl_matrix_free(U);
    gsl_matrix_free(Vm);
    gsl_vector_free(S);
    gsl_vector_free(work);
    return st;
}

/* The separating measurement of one undetermined direction w (fitted
 * scale): among the outputs that can be measured on a motor (speed,
 * power_in, theta) at the data's conditions and at conditions beyond them
 * (each condition moved half its span past its extremes, or halved and
 * doubled where the data hold it constant; never across 0 when the data
 * stay on one side), the one whose relative change
 * along w, |sum_j dln y/dt_j w_j|, is largest: measured to a given relative
 * precision it adds the most information along w.  Pairs the data hold
 * already are skipped. */
static int advise(fit_eval *e, const double *t, usm_fit_unidentified *u)
{
    static const int outputs[] = {USM_FIT_SPEED, USM_SENS_POWER_IN, USM_SENS_THETA};
    const usm_fit_data *d = e->d;
    double lo[USM_FIT_MAX_COLUMNS], hi[USM_FIT_MAX_COLUMNS];
    usm_params pt;
    fit_params_at(e, t, &pt);
    for (int c = 0; c < d->ncond; ++c) {
        lo[c] = INFINITY;
        hi[c] = -INFINITY;
        for (int r = 0; r < d->nrows; ++r) {
            double x = d->x[(size_t)r * (size_t)d->ncond + (size_t)c];
            lo[c] = fmin(lo[c], x);
            hi[c] = fmax(hi[c], x);
        }
    }
    u->advice = 0;
    u->advice_score = 0;
    /* candidate v: the row r itself (v = 0) or its condition c moved */
    for (int r = 0; r < d->nrows; ++r)
        for (int v = 0; v <= 2 * d->ncond; ++v) {
            double x[USM_FIT_MAX_COLUMNS];
            for (int c = 0; c < d->ncond; ++c)
                x[c] = d->x[(size_t)r * (size_t)d->ncond + (size_t)c];
            if (v > 0) {
                int c = (v - 1) / 2, up = (v - 1) % 2;
                double span = hi[c] - lo[c], xc = x[c];
                if (span > 0) {
                    if (up ? xc != hi[c] : xc != lo[c])
                        continue;
                    xc += (up ? 0.5 : -0.5) * span;
                } else {
                    if (xc == 0)
                        continue;
                    xc *= up ? 2.0 : 0.5;
                }
                char msg[USM_MSG_LEN];
                /* a condition the data hold on one side of 0 (a load that brakes)
                 * stays there: the other side is another experiment */
                if ((lo[c] >= 0 && xc < 0) || (hi[c] <= 0 && xc > 0) ||
                    usm_param_check_value(d->cond[c], xc, msg) != USM_OK)
                    continue;
                x[c] = xc;
            }
            usm_params p = pt;
            for (int c = 0; c < d->ncond; ++c)
                *usm_params_field(&p, &usm_param_table[d->cond[c]]) = x[c];
            const usm_steady_solution *sol;
            const char *reason;
            usm_sensitivity_result sr;
            if (fit_point(e, &p, &sol, &sr, &reason) != USM_OK)
                return USM_EFAILED;
            if (!sol || reason[0])
                continue;
            for (size_t q = 0; q < sizeof outputs / sizeof outputs[0]; ++q) {
                int k = outputs[q];
                if (v == 0) { /* the row itself: only outputs the data do not hold there */
                    int held = 0;
                    for (int c = 0; c < d->nout; ++c)
                        held |= (d->out[c] == k ||
                                 (k == USM_FIT_SPEED && d->out[c] == USM_SENS_ROTOR_SPEED)) &&
                                !isnan(d->y[(size_t)r * (size_t)d->nout + (size_t)c]);
                    if (held)
                        continue;
                }
                double y = usm_fit_output_value(k, sol, &p);
                if (!(fabs(y) > 0) || !isfinite(y))
                    continue;
                double g = 0;
                int ok = 1;
                for (int j = 0; j < e->np; ++j) {
                    int pk = e->o->fit[j];
                    double dy = k == USM_FIT_SPEED ? -sr.d[USM_SENS_ROTOR_SPEED][pk]
                                                   : sr.defined[k] ? sr.d[k][pk] : NAN;
                    if (e->log_scale[j])
                        dy *= usm_params_get(&p, &usm_param_table[pk]);
                    ok &= isfinite(dy);
                    g += dy * u->direction[j];
                }
                double score = fabs(g / y);
                if (ok && score > u->advice_score) {
                    u->advice = 1;
                    u->advice_score = score;
                    u->advice_output = k;
                    memcpy(u->advice_cond, x, sizeof x);
                }
            }
        }
    return USM_OK;
}

int fit_statistics(fit_eval *e, const double *t, usm_fit_result *out)
{
    const int n = e->n, np = e->np;
    double s[USM_NPARAMS], V[USM_NPARAMS * USM_NPARAMS], cov[USM_NPARAMS * USM_NPARAMS];
    double *A = malloc((size_t)n * (size_t)np * sizeof *A);
    if (!A)
        return USM_EFAILED;
    out->chi2 = e->chi2;
    out->dof = n - np;
    out->sigma_estimated = !e->sigma_given;
    double s2 = 1.0;
    if (out->sigma_estimated) {
        s2 = out->dof > 0 ? e->chi2 / out->dof : NAN;
        out->p_value = NAN;
        out->quantile = out->dof > 0 ? gsl_cdf_tdist_Pinv(0.975, out->dof) : NAN;
    } else {
        out->p_value = out->dof > 0 ? gsl_cdf_chisq_Q(e->chi2, out->dof) : NAN;
        out->quantile = gsl_cdf_ugaussian_Pinv(0.975);
    }
    out->sigma_scale = sqrt(s2);
    /* covariance in the fitted scale: s^2 V S^-2 V^T */
    memcpy(A, e->J, (size_t)n * (size_t)np * sizeof *A);
    if (svd(A, n, np, s, V) != USM_OK) {
        free(A);
        snprintf(out->message, sizeof out->message, "fit: the singular value decomposition failed");
        return USM_EFAILED;
    }
    for (int a = 0; a < np; ++a)
        for (int b = 0; b < np; ++b) {
            double c = 0;
            for (int k = 0; k < np; ++k) {
                double va = V[a * np + k], vb = V[b * np + k];
                if (s[k] > SINGULAR_FLOOR * s[0])
                    c += va * vb / (s[k] * s[k]);
                else if (va != 0 && vb != 0)
                    c += (va * vb > 0 ? INFINITY : -INFINITY);
            }
            cov[a * np + b] = s2 * c;
        }
    for (int j = 0; j < np; ++j) {
        double se = sqrt(cov[j * np + j]), z = t[j];
        double q = out->quantile * se;
        out->se_scaled[j] = se;
        if (e->log_scale[j]) {
            out->estimate[j] = exp(z);
            out->se[j] = out->estimate[j] * se;
            out->lo[j] = exp(z - q);
            out->hi[j] = exp(z + q);
        } else {
            out->estimate[j] = z;
            out->se[j] = se;
            out->lo[j] = z - q;
            out->hi[j] = z + q;
        }
    }
    for (int a = 0; a < np; ++a)
        for (int b = 0; b < np; ++b)
            out->corr[a * np + b] =
                a == b ? 1.0 : cov[a * np + b] / sqrt(cov[a * np + a] * cov[b * np + b]);
    /* identifiability: the Jacobian with unit-norm columns */
    double norm[USM_NPARAMS];
    for (int j = 0; j < np; ++j) {
        norm[j] = 0;
        for (int i = 0; i < n; ++i)
            norm[j] += e->J[(size_t)i * (size_t)np + (size_t)j] * e->J[(size_t)i * (size_t)np + (size_t)j];
        norm[j] = sqrt(norm[j]);
    }
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < np; ++j)
            A[(size_t)i * (size_t)np + (size_t)j] =
                norm[j] > 0 ? e->J[(size_t)i * (size_t)np + (size_t)j] / norm[j] : 0.0;
    int st = svd(A, n, np, s, V);
    free(A);
    if (st != USM_OK) {
        snprintf(out->message, sizeof out->message, "fit: the singular value decomposition failed");
        return USM_EFAILED;
    }
    out->nunidentified = 0;
    for (int k = 0; k < np; ++k) {
        out->singular[k] = s[k];
        if (s[k] >= e->o->ident_tol)
            continue;
        usm_fit_unidentified *u = &out->unidentified[out->nunidentified++];
        double big = 0;
        u->singular_value = s[k];
        for (int j = 0; j < np; ++j) {
            u->direction[j] = norm[j] > 0 ? V[j * np + k] / norm[j] : V[j * np + k];
            if (fabs(u->direction[j]) > fabs(big))
                big = u->direction[j];
        }
        for (int j = 0; j < np; ++j) {
            u->direction[j] = big != 0 ? u->direction[j] / big : 0.0;
            if (u->direction[j] == 0)
                u->direction[j] = 0.0; /* never -0 */
        }
        if (e->o->advise && advise(e, t, u) != USM_OK)
            return USM_EFAILED;
    }
    out->identifiable = out->nunidentified == 0;
    /* the points at the estimate (advise evaluated other points: again at t) */
    if (out->nunidentified && e->o->advise && fit_eval_at(e, t) != USM_OK)
        return USM_EFAILED;
    out->points = calloc((size_t)n, sizeof *out->points);
    if (!out->points)
        return USM_EFAILED;
    out->npoints = n;
    out->nflagged = 0;
    for (int i = 0; i < n; ++i) {
        usm_fit_point *pt = &out->points[i];
        pt->row = e->idx[i] / e->d->nout;
        pt->column = e->idx[i] % e->d->nout;
        pt->output = e->d->out[pt->column];
        pt->measured = e->d->y[e->idx[i]];
        pt->model = e->model[i];
        pt->sigma = e->w[i] * out->sigma_scale;
        pt->residual = (pt->model - pt->measured) / pt->sigma;
        snprintf(pt->reason, sizeof pt->reason, "%s", e->reason[i] ? e->reason[i] : "");
        pt->flagged = pt->reason[0] != '\0';
        out->nflagged += pt->flagged;
    }
    return USM_OK;
}
