/* fit_internal.h: the evaluation of a fit's residuals (fit_eval.c), used by
 * the least-squares driver (fit.c) and the statistics (fit_stats.c). */
#ifndef USM_FIT_INTERNAL_H
#define USM_FIT_INTERNAL_H

#include "usm_fit.h"

typedef struct fit_eval {
    const usm_model *m;
    usm_params base;
    const usm_fit_data *d;
    const usm_fit_options *o;
    int n, np;
    int log_scale[USM_NPARAMS];
    int sigma_given;           /* every output has its sigma column */
    usm_steady *s;
    usm_floquet *fl;
    usm_sensitivity *sens;
    usm_floquet_result *res;   /* one per root */
    size_t res_cap;
    int *idx;                  /* measured value i: its index into d->y */
    double *w;                 /* its sigma (given) or its output's RMS */
    /* the last evaluated point t and its results */
    int have, failed, evaluations;
    int no_jacobian;           /* 1: residuals only (the starts' screening) */
    double t[USM_NPARAMS];
    double *f, *J, *model, chi2;
    const char **reason;       /* per value: "" or why it is flagged */
} fit_eval;

/* Whether parameter k is fitted in log scale: its range allows no negative value. */
int fit_log_scale(int k);

int fit_eval_init(fit_eval *e, const usm_model *m, const usm_params *p, const usm_fit_data *d,
                  const usm_fit_options *o);
void fit_eval_free(fit_eval *e);
/* e's base with the fitted parameters at t (fitted scale). */
void fit_params_at(const fit_eval *e, const double *t, usm_params *p);
/* The operating point of parameters p (coupled here): *sol NULL with *reason
 * when there is none; else *sol, its sensitivities in *sr (sr may be NULL) and
 * *reason "" or the validity's name.  USM_OK, or USM_EFAILED (out of memory). */
int fit_point(fit_eval *e, usm_params *p, const usm_steady_solution **sol,
              usm_sensitivity_result *sr, const char **reason);
/* Residuals, Jacobian, model values and reasons at t (fitted scale). */
int fit_eval_at(fit_eval *e, const double *t);
/* The result's statistics from e evaluated at the estimate t (fit_stats.c). */
int fit_statistics(fit_eval *e, const double *t, usm_fit_result *out);

#endif /* USM_FIT_INTERNAL_H */
