/* The paper's twist law slows simulations down; usm_sim_run says so.
 *
 * 1. The premise, measured: CVODES' steps for 100 excitation periods on the
 *    stationary orbit grow with the start time t0 under the paper's twist law
 *    (its linearisation grows with psi(t)) and stay the same under the
 *    integrated twist law.  (Step counts, not times: no timed test.)
 * 2. A run that far along warns before integrating (callback and summary),
 *    naming the remedy; the twist_integrated variant does not warn.
 * 3. A long run (10 s) is refused at once (USM_EINPUT, "duration: ..."), unless
 *    max_twist_growth = 0; under twist_integrated it is not refused.  The
 *    duration named in the message separates refused from accepted runs.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>

#include "usm.h"
#include "usm_simulate.h"

#include "check.h"

typedef struct {
    int warnings;        /* calls of the warning callback */
    int warned_first;    /* the warning came before the first sample */
    int samples;
} watch;

static void on_warning(const char *msg, void *data)
{
    watch *w = data;
    (void)msg;
    w->warnings++;
}

/* Stops the run at the first sample: enough to see that it was not refused. */
static int stop_at_first(const usm_sim_sample *smp, void *data)
{
    watch *w = data;
    (void)smp;
    if (w->samples++ == 0)
        w->warned_first = w->warnings > 0;
    return 1;
}

static long steps_from_orbit(usm_sim *s, const usm_params *p, double t0, usm_sim_summary *sum)
{
    usm_sim_options o;
    usm_sim_options_default(&o);
    o.start = USM_SIM_FROM_STATIONARY;
    o.t0 = t0;
    o.duration = 100.0 / p->f;
    o.max_twist_growth = 0;
    const int rc = usm_sim_run(s, p, &o, NULL, sum);
    CHECK(rc == USM_OK, "from the orbit at t0 = %g s: %s", t0, usm_sim_message(s));
    return sum->steps;
}

/* 1 and 2 */
static void check_premise_and_warning(const char *name, int paper_law)
{
    const usm_model *m = usm_model_find(name);
    CHECK(m != NULL, "model %s", name);
    if (!m)
        return;
    CHECK(m->t0_independent == !paper_law, "%s: t0_independent", name);
    usm_params p;
    usm_params_default(&p);
    usm_sim *s = usm_sim_alloc(m);
    usm_sim_summary sum0, sum1;
    const long n0 = steps_from_orbit(s, &p, 0.0, &sum0);
    const long n1 = steps_from_orbit(s, &p, 0.5, &sum1);
    printf("%s: steps for 100 periods on the orbit from t0 = 0: %ld, from t0 = 0.5 s: %ld "
           "(twist growth %.3g, %.3g)\n",
           name, n0, n1, sum0.twist_growth, sum1.twist_growth);
    if (paper_law) {
        CHECK(n1 > 5 * n0, "%s: the steps do not grow with t0 (%ld, %ld)", name, n0, n1);
        CHECK(sum0.twist_growth < USM_SIM_TWIST_GROWTH_WARN &&
                  sum1.twist_growth > USM_SIM_TWIST_GROWTH_WARN,
              "%s: twist growth %g at t0 = 0, %g at 0.5 s", name, sum0.twist_growth,
              sum1.twist_growth);
        CHECK(sum0.warning[0] == '\0', "%s: a warning from t0 = 0: %s", name, sum0.warning);
        CHECK(strstr(sum1.warning, "twist_integrated") != NULL,
              "%s: from t0 = 0.5 s the warning does not name the remedy: '%s'", name,
              sum1.warning);
    } else {
        CHECK(labs(n1 - n0) <= n0 / 10, "%s: the steps change with t0 (%ld, %ld)", name, n0, n1);
        CHECK(sum1.twist_growth == 0 && sum1.warning[0] == '\0', "%s: warned (%g): %s", name,
              sum1.twist_growth, sum1.warning);
    }

    /* the callback comes before the integration */
    watch w = {0, 0, 0};
    usm_sim_callbacks cb = {stop_at_first, NULL, &w, on_warning};
    usm_sim_options o;
    usm_sim_options_default(&o);
    o.start = USM_SIM_FROM_STATIONARY;
    o.t0 = 0.5;
    o.duration = 1e-3;
    o.rate = 1e5;
    const int rc = usm_sim_run(s, &p, &o, &cb, &sum1);
    CHECK(rc == USM_EFAILED && sum1.stop == USM_SIM_STOPPED, "%s: run not stopped by the callback",
          name);
    CHECK(w.warnings == paper_law, "%s: %d warning callbacks", name, w.warnings);
    CHECK(w.warned_first == paper_law, "%s: the warning did not come first", name);
    usm_sim_free(s);
}

/* Whether a run of `duration` from rest is accepted: it starts (and is
 * stopped by the callback at its first sample) or is refused. */
static int accepted(usm_sim *s, const usm_params *p, double duration, double max_growth)
{
    watch w = {0, 0, 0};
    usm_sim_callbacks cb = {stop_at_first, NULL, &w, on_warning};
    usm_sim_options o;
    usm_sim_summary sum;
    usm_sim_options_default(&o);
    o.duration = duration;
    o.rate = 1e5;
    if (max_growth >= 0)
        o.max_twist_growth = max_growth;
    const int rc = usm_sim_run(s, p, &o, &cb, &sum);
    if (rc == USM_EINPUT)
        return 0;
    CHECK(rc == USM_EFAILED && sum.stop == USM_SIM_STOPPED, "duration %g: rc %d, stop %s", duration,
          rc, usm_sim_stop_name(sum.stop));
    return 1;
}

/* 3 */
static void check_refusal(void)
{
    usm_params p;
    usm_params_default(&p);
    const usm_model *m = usm_model_find("4dof"), *mi = usm_model_find("4dof_twist_integrated");
    usm_sim *s = usm_sim_alloc(m), *si = usm_sim_alloc(mi);
    CHECK(!accepted(s, &p, 10.0, -1), "4dof: a 10 s run is not refused");
    const char *msg = usm_sim_message(s);
    printf("4dof, 10 s: %s\n", msg);
    CHECK(strncmp(msg, "duration: ", 10) == 0 && strstr(msg, "twist_integrated"),
          "4dof: the refusal does not name the field and the remedy: %s", msg);
    const char *after = strstr(msg, "after ");
    const double d_max = after ? atof(after + 6) : NAN;
    CHECK(d_max > 0.5 && d_max < 10, "4dof: no duration in the message");
    if (d_max > 0) {
        /* the message's 3 digits: 1 % either side */
        CHECK(accepted(s, &p, 0.99 * d_max, -1), "4dof: %g s refused", 0.99 * d_max);
        CHECK(!accepted(s, &p, 1.01 * d_max, -1), "4dof: %g s accepted", 1.01 * d_max);
    }
    CHECK(accepted(s, &p, 10.0, 0), "4dof: a 10 s run refused with max_twist_growth = 0");
    CHECK(accepted(si, &p, 10.0, -1), "4dof_twist_integrated: a 10 s run refused: %s",
          usm_sim_message(si));
    usm_sim_options o;
    usm_sim_summary sum;
    usm_sim_options_default(&o);
    o.duration = 1.0;
    o.max_twist_growth = -1;
    CHECK(usm_sim_run(s, &p, &o, NULL, &sum) == USM_EINPUT, "max_twist_growth -1 accepted");
    usm_sim_free(s);
    usm_sim_free(si);
}

int main(void)
{
    gsl_set_error_handler_off();
    check_premise_and_warning("4dof", 1);
    check_premise_and_warning("4dof_twist_integrated", 0);
    check_refusal();
    if (failures)
        printf("%d failure(s)\n", failures);
    return failures != 0;
}
