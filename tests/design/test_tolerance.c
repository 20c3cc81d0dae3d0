/* The tolerance study (usm_tolerance.h) against independent truth:
 *   - a tight distribution: the median of each output is the nominal point's
 *     value (usm_steady_solve) and the 5..95 % spread is the linear one,
 *     3.29 sqrt(sum (dy/dp_j sigma_j)^2), from the implicit-function
 *     sensitivities (usm_sensitivity_compute, a second method);
 *   - the sign of each Spearman correlation is the sign of that derivative;
 *   - a spec at the nominal value gives a yield of 1/2 (symmetric scatter);
 *   - the confidence interval solves the Wilson score equation and is close
 *     to the exact Clopper-Pearson interval (GSL's beta quantiles);
 *   - the draws: mean and deviation of normal draws; redraws of a uniform
 *     range a quarter of which is unphysical follow the geometric law (1/3
 *     per sample) and leave only physical values;
 *   - determinism over threads, and a checkpointed run stopped after two
 *     blocks and resumed equals an uninterrupted run bit for bit; a
 *     checkpoint of another study is refused;
 *   - parsing of DIST and specs;
 *   - the rule's "drives its load": a 4-DOF study whose load torque scatters
 *     across the stall torque (usm sweep: 4.95e-4 N m; stable and valid up
 *     to friction saturation at 9.46e-4 N m): every sample's good recomputed
 *     from its own row, power_out = -T rotor_speed computed here (the
 *     paper's sign), so good is 0 wherever power_out < 0; `driven` counts
 *     the samples good but for that sign; allow_driven restores the old rule;
 *     a checkpoint of the other rule is refused. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <gsl/gsl_cdf.h>
#include <gsl/gsl_errno.h>

#include "check.h"
#include "usm_design.h"
#include "usm_tolerance.h"

#define N 2000

static usm_tolerance *study(const usm_model *m, const char *const *vary, int nvary,
                            const usm_tolerance_spec *spec)
{
    char msg[USM_MSG_LEN];
    usm_tolerance *t = usm_tolerance_alloc(m);
    for (int j = 0; j < nvary; ++j) {
        usm_tolerance_vary v;
        int ok = usm_tolerance_vary_parse(vary[j], &v, msg) == USM_OK &&
                 usm_tolerance_vary_add(t, &v) == USM_OK;
        CHECK(ok, "vary %s: %s", vary[j], msg);
    }
    if (spec)
        CHECK(usm_tolerance_spec_add(t, spec) == USM_OK, "spec");
    return t;
}

/* All rows of the last run, for bitwise comparison. */
static double *rows_of(const usm_tolerance *t, uint64_t n, int nv)
{
    const size_t w = (size_t)nv + USM_TOL_NOUTPUTS + 2;
    double *r = calloc(n * w, sizeof *r);
    for (uint64_t i = 0; r && i < n; ++i) {
        int good, redraws;
        usm_tolerance_sample(t, i, r + i * w, r + i * w + nv, &good, &redraws);
        r[i * w + w - 2] = good;
        r[i * w + w - 1] = redraws;
    }
    return r;
}

static void test_linear_spread(const usm_model *m)
{
    static const char *const vary[] = {"F0=normal:0.5%", "c_t=normal:0.5%", "T=normal:2e-7"};
    static const int outs[] = {USM_TOL_THETA, USM_TOL_ROTOR_SPEED, USM_TOL_F_N,
                               USM_TOL_MAX_MODULUS};
    static const int sens[] = {USM_SENS_THETA, USM_SENS_ROTOR_SPEED, USM_SENS_F_N,
                               USM_SENS_MAX_MODULUS};
    usm_params p;
    usm_tolerance_options opt;
    usm_sensitivity_result sr;
    usm_params_default(&p);
    usm_steady *s = usm_steady_alloc(m);
    usm_sensitivity *se = usm_sensitivity_alloc(m);
    CHECK(usm_steady_solve(s, &p, NULL) == USM_OK, "nominal solve");
    const usm_steady_solution *sol = usm_steady_root(s, 0);
    CHECK(usm_sensitivity_compute(se, &p, sol, 1, &sr) == USM_OK, "sensitivity");
    const double sigma[3] = {0.005 * p.F0, 0.005 * p.c_t, 2e-7};
    const int idx[3] = {(int)(usm_params_find("F0") - usm_param_table),
                        (int)(usm_params_find("c_t") - usm_param_table),
                        (int)(usm_params_find("T") - usm_param_table)};

    /* the spec at the nominal speed: half of a symmetric scatter meets it */
    usm_tolerance_spec spec = {USM_TOL_ROTOR_SPEED, 1, sol->rotor_speed};
    usm_tolerance *t = study(m, vary, 3, &spec);
    usm_tolerance_options_default(&opt);
    opt.samples = N;
    opt.seed = 12345;
    CHECK(usm_tolerance_run(t, &p, &opt) == USM_OK, "run: %s", usm_tolerance_message(t));
    const usm_tolerance_summary *r = usm_tolerance_result(t);
    if (!r) {
        usm_tolerance_free(t);
        usm_steady_free(s);
        usm_sensitivity_free(se);
        return;
    }
    for (size_t o = 0; o < sizeof outs / sizeof outs[0]; ++o) {
        const int k = outs[o];
        double var = 0.0, nominal = sr.value[sens[o]];
        for (int j = 0; j < 3; ++j)
            var += pow(sr.d[sens[o]][idx[j]] * sigma[j], 2);
        const double sd = sqrt(var), spread = r->quantile[k][3] - r->quantile[k][1];
        CHECK(fabs(r->quantile[k][2] - nominal) < 0.2 * sd, "%s: median %.10g, nominal %.10g "
              "(sd %.3g)", usm_tolerance_output_name(k), r->quantile[k][2], nominal, sd);
        CHECK(fabs(spread / (2.0 * 1.6448536269514722 * sd) - 1.0) < 0.1,
              "%s: 5..95 %% spread %.6g, linear %.6g", usm_tolerance_output_name(k), spread,
              2.0 * 1.6448536269514722 * sd);
        for (int j = 0; j < 3; ++j) {
            const double dj = sr.d[sens[o]][idx[j]] * sigma[j], rho = usm_tolerance_influence(t, k, j);
            if (fabs(dj) > 0.3 * sd)
                CHECK(rho * dj > 0 && fabs(rho) > 0.2, "%s vs %s: Spearman %g, derivative %g",
                      usm_tolerance_output_name(k), vary[j], rho, dj);
        }
    }
    CHECK(r->samples == N && r->exists == N && r->stable == N && r->failed == 0,
          "counts: %llu %llu %llu", (unsigned long long)r->exists,
          (unsigned long long)r->stable, (unsigned long long)r->failed);
    CHECK(fabs(r->yield - 0.5) < 3.0 * sqrt(0.25 / N), "yield at the nominal speed: %g",
          r->yield);
    /* Wilson: the bounds solve (phat - b)^2 = z^2 b (1 - b) / n */
    const double z = 1.959963984540054, ph = (double)r->good / N;
    for (int b = 0; b < 2; ++b) {
        const double x = b ? r->yield_hi : r->yield_lo;
        /* the bounds in closed form: the equation's terms are ~5e-4 (z^2 / 4N),
         * so rounding leaves ~1e-19; 1e-12 */
        CHECK(fabs((ph - x) * (ph - x) - z * z * x * (1 - x) / N) < 1e-12,
              "Wilson equation at %g", x);
    }
    /* Clopper-Pearson (exact binomial) differs from Wilson by O(1/n) */
    const double k = (double)r->good;
    const double cp_lo = gsl_cdf_beta_Pinv(0.025, k, N - k + 1),
                 cp_hi = gsl_cdf_beta_Pinv(0.975, k + 1, N - k);
    /* the reference (GSL's beta quantiles) is exact to rounding; the two
     * intervals differ by O(1/N) = 5e-4 at N = 2000: 2e-3 */
    CHECK(fabs(cp_lo - r->yield_lo) < 2e-3 && fabs(cp_hi - r->yield_hi) < 2e-3,
          "CI [%g, %g], Clopper-Pearson [%g, %g]", r->yield_lo, r->yield_hi, cp_lo, cp_hi);
    /* the normal draws */
    double mean = 0, sq = 0, vals[3];
    for (uint64_t i = 0; i < N; ++i) {
        usm_tolerance_sample(t, i, vals, NULL, NULL, NULL);
        mean += vals[1];
        sq += vals[1] * vals[1];
    }
    mean /= N;
    const double dev = sqrt(sq / N - mean * mean);
    CHECK(fabs(mean - p.c_t) < 5 * sigma[1] / sqrt(N) && fabs(dev / sigma[1] - 1) < 0.08,
          "c_t draws: mean %g sd %g", mean, dev);
    usm_tolerance_free(t);
    usm_steady_free(s);
    usm_sensitivity_free(se);
}

static void test_redraws(const usm_model *m)
{
    static const char *const vary[] = {"c_t=uniform:-10000:30000"};
    usm_params p;
    usm_tolerance_options opt;
    usm_params_default(&p);
    usm_tolerance *t = study(m, vary, 1, NULL);
    usm_tolerance_options_default(&opt);
    opt.samples = N;
    CHECK(usm_tolerance_run(t, &p, &opt) == USM_OK, "run: %s", usm_tolerance_message(t));
    const usm_tolerance_summary *r = usm_tolerance_result(t);
    if (r) {
        /* failures before success with p = 1/4: mean 1/3, variance 4/9 per sample */
        CHECK(fabs((double)r->redrawn - N / 3.0) < 5.0 * sqrt(N * 4.0 / 9.0), "redrawn %llu",
              (unsigned long long)r->redrawn);
        double mean = 0, v, mn = 1e300;
        for (uint64_t i = 0; i < N; ++i) {
            usm_tolerance_sample(t, i, &v, NULL, NULL, NULL);
            mean += v / N;
            mn = fmin(mn, v);
        }
        CHECK(mn > 0.0 && fabs(mean - 15000.0) < 5.0 * 30000.0 / sqrt(12.0 * N),
              "redrawn c_t: min %g mean %g", mn, mean);
    }
    usm_tolerance_free(t);
}

static void test_determinism_checkpoint(const usm_model *m)
{
    static const char *const vary[] = {"F0=normal:20%", "T=uniform:0:0.012"};
    char dir[] = "/tmp/usm_tolXXXXXX", path[64];
    usm_params p;
    usm_tolerance_options opt;
    const uint64_t n = 1000;
    const size_t bytes = n * (2 + USM_TOL_NOUTPUTS + 2) * sizeof(double);
    usm_params_default(&p);
    usm_tolerance_options_default(&opt);
    opt.samples = n;
    opt.seed = 7;
    opt.threads = 1;
    usm_tolerance *t = study(m, vary, 2, NULL);
    CHECK(usm_tolerance_run(t, &p, &opt) == USM_OK, "run: %s", usm_tolerance_message(t));
    double *ref = rows_of(t, n, 2);
    CHECK(usm_tolerance_result(t)->exists < n && usm_tolerance_result(t)->exists > 0,
          "a study with and without solutions (%llu exist)",
          (unsigned long long)usm_tolerance_result(t)->exists);
    opt.threads = 3;
    CHECK(usm_tolerance_run(t, &p, &opt) == USM_OK, "run 3 threads");
    double *three = rows_of(t, n, 2);
    CHECK(memcmp(ref, three, bytes) == 0, "3 threads differ from 1");

    CHECK(mkdtemp(dir) != NULL, "mkdtemp");
    snprintf(path, sizeof path, "%s/ck", dir);
    opt.checkpoint = path;
    opt.stop_after_blocks = 2;
    opt.threads = 2;
    CHECK(usm_tolerance_run(t, &p, &opt) == USM_EFAILED &&
              strstr(usm_tolerance_message(t), "stopped after 2 block"),
          "stop hook: %s", usm_tolerance_message(t));
    CHECK(access(path, F_OK) == 0, "checkpoint written");
    opt.stop_after_blocks = 0;
    CHECK(usm_tolerance_run(t, &p, &opt) == USM_OK, "resume: %s", usm_tolerance_message(t));
    CHECK(usm_tolerance_result(t) && usm_tolerance_result(t)->resumed_blocks == 2,
          "resumed 2 blocks");
    double *resumed = rows_of(t, n, 2);
    CHECK(memcmp(ref, resumed, bytes) == 0, "resumed run differs from an uninterrupted one");
    opt.seed = 8;
    CHECK(usm_tolerance_run(t, &p, &opt) == USM_EINPUT &&
              strstr(usm_tolerance_message(t), "another study") &&
              strstr(usm_tolerance_message(t), "seed"),
          "mismatch: %s", usm_tolerance_message(t));
    FILE *f = fopen(path, "w");
    fputs("precious\n", f);
    fclose(f);
    CHECK(usm_tolerance_run(t, &p, &opt) == USM_EINPUT &&
              strstr(usm_tolerance_message(t), "not a usm tolerance checkpoint"),
          "foreign file: %s", usm_tolerance_message(t));
    unlink(path);
    snprintf(path, sizeof path, "%s/.ck.usm-lock", dir); /* the lock file, kept by design */
    unlink(path);
    rmdir(dir);
    free(ref);
    free(three);
    free(resumed);
    usm_tolerance_free(t);
}

/* The rule with condition 5 (docs/tolerance.md): op, stable, valid, specs,
 * and power_out >= 0 -- recomputed from the row alone. */
static void test_driven(const usm_model *m)
{
    static const char *const vary[] = {"T=uniform:0.0002:0.0008", "F0=normal:5%"};
    char dir[] = "/tmp/usm_drvXXXXXX", path[64];
    usm_params p;
    usm_tolerance_options opt;
    const uint64_t n = 640;
    /* a spec that some driven samples fail (max_modulus grows towards the
     * friction saturation): they are not good for another reason, so not
     * `driven` */
    const usm_tolerance_spec spec = {USM_TOL_MAX_MODULUS, 1, 0.95};
    usm_params_default(&p);
    usm_tolerance_options_default(&opt);
    opt.samples = n;
    opt.seed = 3;
    usm_tolerance *t = study(m, vary, 2, &spec);
    uint64_t good[2] = {0, 0}, driven[2] = {0, 0}, negative = 0;
    for (int allow = 0; allow < 2; ++allow) {
        opt.allow_driven = allow;
        if (!CHECK(usm_tolerance_run(t, &p, &opt) == USM_OK, "run: %s",
                   usm_tolerance_message(t)))
            break;
        const usm_tolerance_summary *r = usm_tolerance_result(t);
        uint64_t want_good = 0, want_driven = 0, wrong = 0, neg = 0;
        for (uint64_t i = 0; i < n; ++i) {
            double val[2], out[USM_TOL_NOUTPUTS];
            int g;
            usm_tolerance_sample(t, i, val, out, &g, NULL);
            /* the paper's signs: phidot_R < 0 when driving, so the power given
             * to the load is -T phidot_R */
            const double power_out = -val[0] * out[USM_TOL_ROTOR_SPEED];
            const int rest = !isnan(out[USM_TOL_OPERATING_POINT]) &&
                             out[USM_TOL_MAX_MODULUS] < 1.0 &&
                             out[USM_TOL_VALIDITY] == (double)USM_VALID &&
                             out[USM_TOL_MAX_MODULUS] <= spec.bound;
            const int want = rest && (allow || power_out >= 0.0);
            neg += !isnan(out[USM_TOL_OPERATING_POINT]) && power_out < 0.0;
            want_good += (uint64_t)want;
            want_driven += (uint64_t)(rest && !want);
            wrong += (uint64_t)(g != want);
            if (g != want && wrong <= 3)
                fprintf(stderr, "sample %llu: T %g rotor_speed %g power_out %g good %d, the "
                        "rule says %d\n", (unsigned long long)i, val[0],
                        out[USM_TOL_ROTOR_SPEED], power_out, g, want);
        }
        CHECK(wrong == 0, "allow_driven %d: %llu samples' good differ from the rule", allow,
              (unsigned long long)wrong);
        CHECK(r->good == want_good && r->driven == want_driven,
              "allow_driven %d: good %llu driven %llu, the rows say %llu and %llu", allow,
              (unsigned long long)r->good, (unsigned long long)r->driven,
              (unsigned long long)want_good, (unsigned long long)want_driven);
        good[allow] = r->good;
        driven[allow] = r->driven;
        negative = neg;
    }
    printf("driven: %llu samples of %llu with power_out < 0; good %llu, driven %llu (good with "
           "allow_driven %llu)\n", (unsigned long long)negative, (unsigned long long)n,
           (unsigned long long)good[0], (unsigned long long)driven[0],
           (unsigned long long)good[1]);
    /* the study crosses the stall torque on both sides, and the spec bites
     * some driven samples (measured: 309 of 640 with power_out < 0, 124 of
     * them driven and within the spec) */
    CHECK(negative > n / 4 && negative < 3 * n / 4 && driven[0] > 0 && driven[0] < negative,
          "power_out < 0 in %llu samples, driven %llu", (unsigned long long)negative,
          (unsigned long long)driven[0]);
    CHECK(driven[1] == 0 && good[1] == good[0] + driven[0],
          "allow_driven: good %llu driven %llu, without: %llu + %llu",
          (unsigned long long)good[1], (unsigned long long)driven[1],
          (unsigned long long)good[0], (unsigned long long)driven[0]);
    /* a checkpoint of one rule is another study for the other */
    CHECK(mkdtemp(dir) != NULL, "mkdtemp");
    snprintf(path, sizeof path, "%s/ck", dir);
    opt.checkpoint = path;
    opt.allow_driven = 0;
    opt.stop_after_blocks = 4;
    CHECK(usm_tolerance_run(t, &p, &opt) == USM_EFAILED, "stop hook: %s",
          usm_tolerance_message(t));
    opt.stop_after_blocks = 0;
    opt.allow_driven = 1;
    CHECK(usm_tolerance_run(t, &p, &opt) == USM_EINPUT &&
              strstr(usm_tolerance_message(t), "allow_driven"),
          "a checkpoint of the other rule: %s", usm_tolerance_message(t));
    /* the same rule resumes to the uninterrupted counts, driven samples and all */
    opt.allow_driven = 0;
    CHECK(usm_tolerance_run(t, &p, &opt) == USM_OK && usm_tolerance_result(t)->good == good[0] &&
              usm_tolerance_result(t)->driven == driven[0] &&
              usm_tolerance_result(t)->resumed_blocks == 4,
          "resumed: %s", usm_tolerance_message(t));
    unlink(path);
    snprintf(path, sizeof path, "%s/.ck.usm-lock", dir); /* the lock file, kept by design */
    unlink(path);
    rmdir(dir);
    usm_tolerance_free(t);
}

static void test_parse(void)
{
    static const char *const good[] = {"c_t=normal:5%", "F0=normal:0.01", "T=uniform:2%",
                                       "T=uniform:-1e-3:2e-3"};
    static const char *const bad[] = {"c_t", "nosuch=normal:5%", "c_t=gauss:5%", "c_t=normal:",
                                      "c_t=normal:-5%", "c_t=normal:0", "c_t=uniform:0.1",
                                      "c_t=uniform:2:1", "c_t=normal:1:2", "c_t=normal:5%%",
                                      "c_t=normal:nan", "=normal:5%"};
    static const char *const sgood[] = {"rotor_speed<=-10", "max_modulus>=0.5"};
    static const char *const sbad[] = {"rotor_speed=-10", "speed<=1", "stable>=1",
                                       "theta<=x", "theta<=", "<=1", "theta<1"};
    char msg[USM_MSG_LEN];
    usm_tolerance_vary v;
    usm_tolerance_spec s;
    for (size_t k = 0; k < sizeof good / sizeof good[0]; ++k)
        CHECK(usm_tolerance_vary_parse(good[k], &v, msg) == USM_OK, "%s: %s", good[k], msg);
    CHECK(usm_tolerance_vary_parse("c_t=normal:5%", &v, msg) == USM_OK && v.relative &&
              fabs(v.width - 0.05) < 1e-16, "5%% is 0.05 relative"); /* 5 / 100: rounding */
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; ++k)
        CHECK(usm_tolerance_vary_parse(bad[k], &v, msg) == USM_EINPUT && msg[0],
              "%s accepted", bad[k]);
    for (size_t k = 0; k < sizeof sgood / sizeof sgood[0]; ++k)
        CHECK(usm_tolerance_spec_parse(sgood[k], &s, msg) == USM_OK, "%s: %s", sgood[k], msg);
    for (size_t k = 0; k < sizeof sbad / sizeof sbad[0]; ++k)
        CHECK(usm_tolerance_spec_parse(sbad[k], &s, msg) == USM_EINPUT && msg[0],
              "%s accepted", sbad[k]);
}

int main(void)
{
    gsl_set_error_handler_off();
    const usm_model *m = usm_model_find("3dof");
    test_parse();
    test_linear_spread(m);
    test_redraws(m);
    test_determinism_checkpoint(m);
    test_driven(usm_model_find("4dof"));
    printf("%s (%d failures)\n", failures ? "FAIL" : "ok", failures);
    return failures != 0;
}
