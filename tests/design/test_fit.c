/* The fit of parameters to measured characteristics (usm_fit.h) against
 * independent truth: synthetic data drawn from known parameters with known
 * noise.
 *
 *   test_fit recovery [SETS]  the 95 % intervals of c_r, d_r, kappa contain the
 *                             truth in a fraction of the data sets that a
 *                             binomial(SETS, 0.95) allows (3 sigma), and the
 *                             estimates are unbiased within their standard
 *                             errors
 *   test_fit ident            mu0, kappa (and c_r, I_xx) from speed curves only:
 *                             not identifiable, the combination named; with a
 *                             separating measurement added: identifiable
 *   test_fit starts           started a factor 30 off the truth, the default starts
 *                             (a Sobol sample of the box a factor 100 around the
 *                             start) find the global minimum: the truth within
 *                             its intervals, chi^2 that of the noise
 *   test_fit speed_max        speed_max_frequency: the model's value the located
 *                             maximum of the sweep over f (README's 37452.06 Hz)
 *                             and its Jacobian row against a 10 times larger step
 *   test_fit datasheet        speed curves and a stall torque column: the truth
 *                             recovered, the stall torque's model value the
 *                             datasheet's (usm_robust_quantity_eval) at the
 *                             estimate, its Jacobian row (central differences)
 *                             against differences of a 10 times larger step, and
 *                             mu0, kappa, which the curves alone cannot separate,
 *                             identifiable with it
 *   test_fit data             the reader: units converted, bad files refused
 *                             with one line naming the column and the reason
 *   test_fit measure          prints the time per fit and the identifiable sets
 *                             of speed-frequency, speed-load and both
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <gsl/gsl_errno.h>

#include "check.h"
#include "usm_fit.h"
#include "usm_io.h"
#include "usm_robust.h"
#include "usm_sweep.h"

static double gauss(uint64_t *st)
{
    double u1 = rng_uniform(st), u2 = rng_uniform(st);
    return sqrt(-2.0 * log(1.0 - u1)) * cos(6.283185307179586 * u2);
}

static double cpu(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The measurement plan: speed over f at two loads (nf points each over
 * 37..41 kHz) and speed over T at 38.8 kHz (nt points over 0..Tmax); either
 * part may be empty.  Conditions f and T. */
static usm_fit_data *plan(int nf, int nt, double Tmax, int power)
{
    const int rows = 2 * nf + nt;
    usm_fit_data *d = usm_fit_data_alloc(rows, 2, power ? 2 : 1);
    if (!d)
        return NULL;
    d->cond[0] = USM_P_f;
    d->cond[1] = USM_P_T;
    d->out[0] = USM_FIT_SPEED;
    d->out[1] = USM_SENS_POWER_IN;
    d->has_sigma[0] = d->has_sigma[1] = 1;
    int r = 0;
    for (int c = 0; c < 2; ++c)
        for (int i = 0; i < nf; ++i, ++r) {
            d->x[2 * r] = 37000 + 4000.0 * i / (nf - 1);
            d->x[2 * r + 1] = c ? 1e-4 : 0.0;
        }
    for (int i = 0; i < nt; ++i, ++r) {
        d->x[2 * r] = 38800;
        d->x[2 * r + 1] = Tmax * i / (nt - 1);
    }
    return d;
}

/* y = the model at p (sigma 1, y 0 gives f = model), then noise of relative
 * size rel; sigma = rel |model|.  0, or -1 when the model fails. */
static int synthesize(const usm_model *m, const usm_params *p, usm_fit_data *d, double rel,
                      double noise, uint64_t *st)
{
    usm_fit_options o;
    usm_fit_options_default(&o);
    o.nfit = 1;
    o.fit[0] = USM_P_c_r;
    const size_t ny = (size_t)d->nrows * (size_t)d->nout;
    for (size_t i = 0; i < ny; ++i) {
        d->y[i] = 0.0;
        d->sigma[i] = 1.0;
    }
    int n = usm_fit_data_count(d);
    double *f = malloc((size_t)n * sizeof *f), t = log(p->c_r);
    if (!f || usm_fit_residuals(m, p, d, &o, &t, f, NULL) != USM_OK) {
        free(f);
        return -1;
    }
    for (int i = 0; i < n; ++i) {
        d->sigma[i] = rel * fabs(f[i]);
        d->y[i] = f[i] + noise * d->sigma[i] * gauss(st);
    }
    free(f);
    return 0;
}

static void fit_names(const usm_model *m, const char *names, usm_fit_options *o)
{
    char msg[USM_MSG_LEN];
    usm_fit_options_default(o);
    if (usm_fit_parse_names(m, "--fit", names, o, msg) != USM_OK)
        printf("parse: %s\n", msg);
}

/* ---- recovery and coverage ------------------------------------------------------ */

static void recovery(int sets)
{
    const usm_model *m = usm_model_find("4dof");
    usm_params truth;
    usm_params_default(&truth);
    usm_fit_options o;
    fit_names(m, "c_r,d_r,kappa", &o);
    o.starts = 1; /* the truth is near: coverage tests the intervals, not the search */
    o.profile = 0; /* the Jacobian's intervals are the ones tested */
    usm_fit_data *d = plan(8, 8, 2.5e-4, 0);
    uint64_t st = 20261207;
    int covered[3] = {0}, done = 0;
    double zsum[3] = {0};
    double t0 = cpu();
    if (!CHECK(d && m, "setup"))
        return;
    for (int s = 0; s < sets; ++s) {
        usm_fit_result r;
        if (synthesize(m, &truth, d, 0.01, 1.0, &st) != 0) {
            CHECK(0, "synthesize failed");
            break;
        }
        /* start off the truth by 20 %: the fit must move */
        usm_params p = truth;
        p.c_r *= 1.2;
        p.d_r *= 0.8;
        p.kappa *= 1.2;
        int status = usm_fit_run(m, &p, d, &o, &r);
        if (!CHECK(status == USM_OK, "set %d: %s", s, r.message)) {
            usm_fit_result_free(&r);
            continue;
        }
        ++done;
        const double tv[3] = {truth.c_r, truth.d_r, truth.kappa};
        for (int j = 0; j < 3; ++j) {
            covered[j] += r.lo[j] <= tv[j] && tv[j] <= r.hi[j];
            zsum[j] += (log(r.estimate[j]) - log(tv[j])) / r.se_scaled[j];
        }
        if (s == 0)
            CHECK(r.identifiable && r.nflagged == 0 && r.p_value > 1e-4,
                  "set 0: identifiable %d flagged %d p %g", r.identifiable, r.nflagged,
                  r.p_value);
        usm_fit_result_free(&r);
    }
    double per = (cpu() - t0) / (done ? done : 1);
    /* binomial(done, 0.95): 3 standard deviations */
    double sd = sqrt(done * 0.95 * 0.05);
    for (int j = 0; j < 3; ++j) {
        double z = zsum[j] / sqrt(done > 0 ? done : 1); /* mean z times sqrt(N): N(0,1) */
        printf("%s: coverage %d/%d = %.3f, mean standardized error %.3f (z %.2f)\n",
               usm_param_table[o.fit[j]].name, covered[j], done,
               (double)covered[j] / (done ? done : 1), zsum[j] / (done ? done : 1), z);
        CHECK(fabs(covered[j] - 0.95 * done) <= 3 * sd + 1, "%s: coverage %d of %d",
              usm_param_table[o.fit[j]].name, covered[j], done);
        CHECK(fabs(z) < 4, "%s: biased: mean standardized error %g over %d sets",
              usm_param_table[o.fit[j]].name, zsum[j] / done, done);
    }
    printf("%.1f ms CPU per fit (%d points, 3 parameters)\n", 1e3 * per,
           usm_fit_data_count(d));
    usm_fit_data_free(d);
}

/* ---- identifiability ------------------------------------------------------------ */

static int ident(const usm_model *m, usm_fit_data *d, const char *names, int expect,
                 double ratio)
{
    usm_params p;
    usm_fit_options o;
    usm_fit_result r;
    usm_params_default(&p);
    fit_names(m, names, &o);
    o.starts = 1; /* from the truth: the valley the data leave open, not another regime */
    int status = usm_fit_run(m, &p, d, &o, &r);
    if (!CHECK(status == USM_OK, "%s: %s", names, r.message)) {
        usm_fit_result_free(&r);
        return -1;
    }
    printf("%s: identifiable %d, singular values", names, r.identifiable);
    for (int j = 0; j < r.nfit; ++j)
        printf(" %.3g", r.singular[j]);
    printf(", corr %.4f, estimates", r.nfit > 1 ? r.corr[1] : NAN);
    for (int j = 0; j < r.nfit; ++j)
        printf(" %s = %.4g +- %.2g", usm_param_table[r.fit[j]].name, r.estimate[j], r.se[j]);
    printf(" (%d starts, %d iterations, %d evaluations, %.0f ms)\n", r.starts, r.iterations,
           r.evaluations, 1e3 * r.wall);
    CHECK(r.identifiable == expect, "%s: identifiable %d, expected %d", names, r.identifiable,
          expect);
    /* the profile likelihood differs from the Jacobian's interval where the data
     * leave a direction open (kappa along the valley of mu0 kappa: the sum of
     * squares is not quadratic there), and agrees within 10 % where they
     * determine every parameter */
    if (strcmp(names, "mu0,kappa") == 0)
        for (int j = 0; j < r.nfit; ++j)
            if (expect || j == 1)
                CHECK(r.profiled[j] == !expect, "%s: %s profiled %d [%g, %g] vs [%g, %g]", names,
                      usm_param_table[r.fit[j]].name, r.profiled[j], r.profile_lo[j],
                      r.profile_hi[j], r.lo[j], r.hi[j]);
    if (!expect && CHECK(r.nunidentified == 1, "%s: %d combinations", names, r.nunidentified)) {
        const usm_fit_unidentified *u = &r.unidentified[0];
        /* the direction the data leave open, in log scale: mu0 kappa fixed
         * (d log mu0 = -d log kappa), c_r / I_xx fixed (d log c_r = d log I_xx) */
        CHECK(fabs(u->direction[0] * u->direction[1] - ratio) < 0.15,
              "%s: combination %g, %g; expected the ratio %g", names, u->direction[0],
              u->direction[1], ratio);
        if (CHECK(u->advice, "%s: no advice", names))
            printf("  advice: %s at f = %g, T = %g (score %.3g)\n",
                   usm_fit_output_name(u->advice_output), u->advice_cond[0], u->advice_cond[1],
                   u->advice_score);
    }
    usm_fit_result_free(&r);
    return 0;
}

static void identifiability(void)
{
    const usm_model *m = usm_model_find("4dof");
    usm_params truth;
    uint64_t st = 7;
    usm_params_default(&truth);
    usm_fit_data *curves = plan(10, 0, 0, 0), *both = plan(10, 12, 8.5e-4, 0);
    if (!CHECK(curves && both, "setup"))
        return;
    /* exact data: the fit stays at the truth, where the open direction is the
     * product's (noise would let it drift along the valley) */
    synthesize(m, &truth, curves, 0.01, 0.0, &st);
    synthesize(m, &truth, both, 0.01, 0.0, &st);
    ident(m, curves, "mu0,kappa", 0, -1.0);
    ident(m, curves, "c_r,I_xx", 0, 1.0);
    /* a load sweep past the stall, into the friction law's saturation (the
     * rotor dragged backwards), separates mu0 from kappa */
    ident(m, both, "mu0,kappa", 1, 0.0);
    usm_fit_data_free(curves);
    usm_fit_data_free(both);
}

/* ---- starts far from the truth ------------------------------------------------- */

static void far_starts(void)
{
    const usm_model *m = usm_model_find("4dof");
    usm_params truth;
    usm_params_default(&truth);
    usm_fit_options o;
    fit_names(m, "c_r,d_r,kappa", &o);
    o.profile = 0;
    o.advise = 0;
    usm_fit_data *d = plan(6, 6, 2.5e-4, 0);
    uint64_t st = 4242;
    if (!CHECK(d && m && synthesize(m, &truth, d, 0.01, 1.0, &st) == 0, "setup"))
        return;
    /* a factor 30 off: the resonance c_r / I_xx off by a factor 5.5 in
     * frequency, kappa's friction law far into saturation */
    usm_params p = truth;
    p.c_r *= 30;
    p.d_r /= 30;
    p.kappa *= 30;
    usm_fit_result r;
    double t0 = cpu();
    int status = usm_fit_run(m, &p, d, &o, &r);
    printf("from a factor 30 off: status %d, chi2 %.3g (%d values), %d starts, %d at the best "
           "(start %d), %d evaluations, %.2f s CPU\n", status, r.chi2, usm_fit_data_count(d),
           r.starts, r.starts_at_best, r.best_start, r.evaluations, cpu() - t0);
    if (CHECK(status == USM_OK, "%s", r.message)) {
        const double tv[3] = {truth.c_r, truth.d_r, truth.kappa};
        for (int j = 0; j < 3; ++j) {
            printf("  %s = %.5g in [%.5g, %.5g], truth %.5g\n", usm_param_table[r.fit[j]].name,
                   r.estimate[j], r.lo[j], r.hi[j], tv[j]);
            /* the global minimum of noisy data lies within a few standard errors
             * of the truth; another minimum would be many away */
            CHECK(fabs(log(r.estimate[j] / tv[j])) < 4 * r.se_scaled[j], "%s: %g, truth %g",
                  usm_param_table[r.fit[j]].name, r.estimate[j], tv[j]);
        }
        /* chi^2 of 1 % noise: dof +- a few sqrt(2 dof) */
        CHECK(r.chi2 < r.dof + 5 * sqrt(2.0 * r.dof), "chi2 %g for %d dof", r.chi2, r.dof);
        CHECK(r.starts_at_best >= 1 && r.starts_at_best <= r.starts, "starts at best %d of %d",
              r.starts_at_best, r.starts);
    }
    usm_fit_result_free(&r);
    usm_fit_data_free(d);
}

/* ---- the frequency of the speed maximum measured ---------------------------- */

static double speed_monitor(const usm_steady_solution *sol, const usm_params *p, void *ctx)
{
    (void)p;
    (void)ctx;
    return -sol->rotor_speed;
}

static void speed_max(void)
{
    const usm_model *m = usm_model_find("4dof");
    usm_params truth;
    usm_params_default(&truth);
    usm_fit_data *d = usm_fit_data_alloc(1, 0, 1);
    if (!CHECK(d && m, "setup"))
        return;
    d->out[0] = usm_fit_output_find("speed_max_frequency");
    CHECK(d->out[0] == USM_FIT_SPEED_MAX_FREQUENCY && usm_fit_output_is_datasheet(d->out[0]) &&
              strcmp(usm_fit_output_unit(d->out[0]), "Hz") == 0,
          "speed_max_frequency: %d", d->out[0]);
    d->y[0] = 0.0; /* the residual is the model's value */
    d->sigma[0] = 1.0;
    d->has_sigma[0] = 1;
    /* the sweep the command runs (usm sweep --over f --from 30000 --to 46000
     * --extremum speed, its default 101 points), independent of the fit's grid */
    usm_sweep *s = usm_sweep_alloc(m);
    usm_sweep_options so;
    usm_sweep_options_default(&so);
    const usm_sweep_monitor mon = {"speed", speed_monitor, NULL, 1, 0, {0}};
    so.over = "f";
    so.from = 30000;
    so.to = 46000;
    so.points = 101;
    so.floquet = 0;
    so.monitors = &mon;
    so.nmonitors = 1;
    double swept = NAN;
    if (CHECK(s && usm_sweep_run(s, &truth, &so) == USM_OK, "sweep"))
        for (size_t i = 0; i < usm_sweep_event_count(s); ++i)
            if (usm_sweep_event_at(s, i)->type == USM_EVENT_MAXIMUM)
                swept = usm_sweep_event_at(s, i)->value;
    usm_sweep_free(s);
    usm_fit_options o;
    fit_names(m, "c_r,I_xx", &o);
    double f[1], J[2], fp[1], fm[1];
    double t[2] = {log(truth.c_r), log(truth.I_xx)};
    if (CHECK(usm_fit_residuals(m, &truth, d, &o, t, f, J) == USM_OK, "residuals")) {
        printf("speed maximum: fit %.6f Hz, sweep %.6f Hz\n", f[0], swept);
        CHECK(fabs(f[0] / 37452.06 - 1) <= 1e-6, "speed maximum %.6f Hz, README's 37452.06", f[0]);
        CHECK(fabs(f[0] / swept - 1) <= 1e-6, "speed maximum %.6f Hz, the sweep's %.6f", f[0],
              swept);
        /* the Jacobian row against differences of a 10 times larger step; the
         * resonance sqrt(c_r / I_xx) says about +f/2 and -f/2 */
        for (int j = 0; j < 2; ++j) {
            double tp[2] = {t[0], t[1]}, tm[2] = {t[0], t[1]}, h = 1e-2;
            tp[j] += h;
            tm[j] -= h;
            usm_fit_residuals(m, &truth, d, &o, tp, fp, NULL);
            usm_fit_residuals(m, &truth, d, &o, tm, fm, NULL);
            double fd = (fp[0] - fm[0]) / (2 * h);
            printf("  d f_max / d log %s: %.6g Hz (differences of 1e-2: %.6g)\n",
                   usm_param_table[o.fit[j]].name, J[j], fd);
            CHECK(fabs(J[j] - fd) <= 1e-3 * fabs(fd), "d f_max / d log %s: %g vs %g",
                  usm_param_table[o.fit[j]].name, J[j], fd);
            CHECK(fabs(fabs(fd) / (0.5 * f[0]) - 1) < 0.2, "d f_max / d log %s: %g, not near f/2",
                  usm_param_table[o.fit[j]].name, fd);
        }
    }
    usm_fit_data_free(d);
}

/* ---- a datasheet quantity measured ------------------------------------------ */

static void datasheet(void)
{
    const usm_model *m = usm_model_find("4dof");
    usm_params truth;
    usm_params_default(&truth);
    const int nf = 6, ns = 2;
    usm_fit_data *d = usm_fit_data_alloc(2 * nf + ns, 2, 2);
    uint64_t st = 99;
    if (!CHECK(d && m, "setup"))
        return;
    d->cond[0] = USM_P_f;
    d->cond[1] = USM_P_T;
    d->out[0] = USM_FIT_SPEED;
    d->out[1] = usm_fit_output_find("stall_torque");
    d->has_sigma[0] = d->has_sigma[1] = 1;
    CHECK(d->out[1] == USM_FIT_STALL_TORQUE && usm_fit_output_is_datasheet(d->out[1]) &&
              strcmp(usm_fit_output_unit(d->out[1]), "N m") == 0,
          "stall_torque: %d", d->out[1]);
    for (int r = 0; r < 2 * nf; ++r) {
        d->x[2 * r] = 37000 + 4000.0 * (r % nf) / (nf - 1);
        d->x[2 * r + 1] = r < nf ? 0.0 : 1e-4;
    }
    /* the stall torque at two frequencies (the row's T is not used) */
    for (int r = 2 * nf; r < 2 * nf + ns; ++r) {
        d->x[2 * r] = r == 2 * nf ? 38800 : 39500;
        d->x[2 * r + 1] = 0.0;
    }
    /* speed only in the curves' rows, stall torque only in its rows */
    if (!CHECK(synthesize(m, &truth, d, 0.01, 0.0, &st) == 0, "synthesize"))
        return;
    for (int r = 0; r < d->nrows; ++r)
        d->y[2 * r + (r < 2 * nf)] = d->sigma[2 * r + (r < 2 * nf)] = NAN;
    const double y0 = d->y[2 * 2 * nf + 1];
    printf("stall torque at 38.8 kHz: %.6g N m\n", y0);
    usm_quantity_options qo;
    memset(&qo, 0, sizeof qo);
    qo.range.param = -1;
    qo.band_threshold = NAN;
    char msg[USM_MSG_LEN];
    double direct = NAN;
    usm_params q = truth;
    q.f = 38800;
    usm_robust_quantity_eval(m, &q, USM_ROBUST_STALL_TORQUE, &qo, 1, &direct, msg);
    CHECK(fabs(y0 - direct) <= 1e-12 * fabs(direct) && direct > 0,
          "stall torque %g, datasheet %g", y0, direct);
    /* the Jacobian row of the stall torque against a 10 times larger step */
    usm_fit_options o;
    fit_names(m, "mu0,kappa", &o);
    const int n = usm_fit_data_count(d);
    double *f = malloc((size_t)n * sizeof *f), *J = malloc((size_t)n * 2 * sizeof *J),
           *fp = malloc((size_t)n * sizeof *fp), *fm = malloc((size_t)n * sizeof *fm);
    double t[2] = {log(truth.mu0), log(truth.kappa)};
    if (f && J && fp && fm &&
        CHECK(usm_fit_residuals(m, &truth, d, &o, t, f, J) == USM_OK, "residuals")) {
        for (int j = 0; j < 2; ++j) {
            double tp[2] = {t[0], t[1]}, tm[2] = {t[0], t[1]}, h = 1e-2;
            tp[j] += h;
            tm[j] -= h;
            usm_fit_residuals(m, &truth, d, &o, tp, fp, NULL);
            usm_fit_residuals(m, &truth, d, &o, tm, fm, NULL);
            double fd = (fp[n - 2] - fm[n - 2]) / (2 * h);
            printf("  d stall / d log %s: %.6g (differences of 1e-2: %.6g)\n",
                   usm_param_table[o.fit[j]].name, J[(size_t)(n - 2) * 2 + (size_t)j], fd);
            CHECK(fabs(J[(size_t)(n - 2) * 2 + (size_t)j] - fd) <= 1e-3 * fabs(fd) + 1e-6,
                  "d stall / d log %s: %g vs %g", usm_param_table[o.fit[j]].name,
                  J[(size_t)(n - 2) * 2 + (size_t)j], fd);
        }
    }
    free(f);
    free(J);
    free(fp);
    free(fm);
    /* mu0 and kappa from the curves and the stall torque, started 20 % off */
    usm_fit_result r;
    usm_params p = truth;
    p.mu0 *= 1.2;
    p.kappa *= 0.8;
    o.starts = 1;
    o.profile = 0;
    o.advise = 0;
    double c0 = cpu();
    int status = usm_fit_run(m, &p, d, &o, &r);
    printf("mu0,kappa with the stall torque: status %d, identifiable %d, singular values %.3g "
           "%.3g, %d evaluations, %.2f s CPU\n", status, r.identifiable, r.singular[0],
           r.singular[1], r.evaluations, cpu() - c0);
    if (CHECK(status == USM_OK, "%s", r.message)) {
        CHECK(r.identifiable, "mu0,kappa not identifiable with the stall torque");
        const double tv[2] = {truth.mu0, truth.kappa};
        for (int j = 0; j < 2; ++j)
            CHECK(fabs(r.estimate[j] / tv[j] - 1) < 1e-4, "%s: %g, truth %g",
                  usm_param_table[r.fit[j]].name, r.estimate[j], tv[j]);
        CHECK(r.nflagged == 0, "%d flagged", r.nflagged);
    }
    usm_fit_result_free(&r);
    usm_fit_data_free(d);
}

/* ---- measures (not a ctest test: printed for docs/fit.md) ------------------------- */

static void measure(void)
{
    const usm_model *m = usm_model_find("4dof");
    usm_params truth;
    uint64_t st = 11;
    usm_params_default(&truth);
    /* time per fit: 3 parameters, 48 points (2 x 16 speed-frequency + 16 speed-load), the
     * default starts, 1 % noise, started 20 % off */
    usm_fit_data *d = plan(16, 16, 5e-4, 0);
    usm_fit_options o;
    usm_fit_result r;
    fit_names(m, "c_r,d_r,kappa", &o);
    synthesize(m, &truth, d, 0.01, 1.0, &st);
    usm_params p = truth;
    p.c_r *= 1.2;
    p.d_r *= 0.8;
    p.kappa *= 1.2;
    double t0 = cpu();
    int status = usm_fit_run(m, &p, d, &o, &r);
    printf("time per fit: %d points, 3 parameters, %d starts: %.3f s CPU (%d evaluations, "
           "status %d)\n", usm_fit_data_count(d), r.starts, cpu() - t0, r.evaluations, status);
    usm_fit_result_free(&r);
    o.starts = 1;
    t0 = cpu();
    status = usm_fit_run(m, &p, d, &o, &r);
    printf("  1 start: %.3f s CPU\n", cpu() - t0);
    usm_fit_result_free(&r);
    usm_fit_data_free(d);
    /* identifiable sets: every pair and triple of six parameters, exact data */
    static const int cand[] = {USM_P_c_r, USM_P_d_r, USM_P_I_xx, USM_P_mu0, USM_P_kappa, USM_P_m0};
    const int nc = 6;
    usm_fit_data *sets[3] = {plan(10, 0, 0, 0), plan(0, 16, 5e-4, 0), plan(10, 16, 5e-4, 0)};
    const char *label[3] = {"speed-frequency (2 loads)", "speed-load (38.8 kHz)", "both"};
    for (int k = 0; k < 3; ++k) {
        synthesize(m, &truth, sets[k], 0.01, 0.0, &st);
        printf("%s, %d points: identifiable sets:", label[k], usm_fit_data_count(sets[k]));
        for (int mask = 1; mask < (1 << nc); ++mask) {
            int n = __builtin_popcount((unsigned)mask);
            if (n < 2 || n > 3)
                continue;
            usm_fit_options_default(&o);
            o.starts = 1;
            o.advise = 0;
            for (int j = 0; j < nc; ++j)
                if (mask & (1 << j))
                    o.fit[o.nfit++] = cand[j];
            if (usm_fit_run(m, &truth, sets[k], &o, &r) == USM_OK && r.identifiable) {
                printf(" {");
                for (int j = 0; j < o.nfit; ++j)
                    printf("%s%s", j ? "," : "", usm_param_table[o.fit[j]].name);
                printf("}");
            }
            usm_fit_result_free(&r);
        }
        printf("\n");
        usm_fit_data_free(sets[k]);
    }
}

int main(int argc, char **argv)
{
    gsl_set_error_handler_off();
    const char *what = argc > 1 ? argv[1] : "recovery";
    if (strcmp(what, "recovery") == 0)
        recovery(argc > 2 ? atoi(argv[2]) : 60);
    else if (strcmp(what, "ident") == 0)
        identifiability();
    else if (strcmp(what, "starts") == 0)
        far_starts();
    else if (strcmp(what, "speed_max") == 0)
        speed_max();
    else if (strcmp(what, "datasheet") == 0)
        datasheet();
    else if (strcmp(what, "measure") == 0)
        measure();
    else {
        printf("unknown test %s\n", what);
        return 2;
    }
    printf("%d failure(s)\n", failures);
    return failures != 0;
}
