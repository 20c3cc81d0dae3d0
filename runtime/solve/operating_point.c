/* The operating point: the stable root the motor reaches from rest
 * (usm_operating_point.h states the definition and the rule). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "usm.h"
#include "usm_operating_point.h"
#include "usm_simulate.h"

const char *usm_op_reason_name(usm_op_reason reason)
{
    switch (reason) {
    case USM_OP_UNDECIDED:
        return "undecided";
    case USM_OP_ONLY_STABLE_ROOT:
        return "only_stable_root";
    case USM_OP_REACHED_FROM_REST:
        return "reached_from_rest";
    case USM_OP_NO_STABLE_ROOT:
        return "no_stable_root";
    case USM_OP_DOES_NOT_START:
        return "does_not_start";
    }
    return NULL;
}

void usm_op_options_default(usm_op_options *opt)
{
    memset(opt, 0, sizeof *opt);
    opt->from_rest = 0;
    opt->periods = 400;
    usm_sim_options_default(&opt->sim);
}

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The simulation from rest; USM_OK (an answer in out->sim) or USM_EINPUT /
 * USM_EFAILED (bad options, out of memory). */
static int simulate_from_rest(const usm_model *m, const usm_params *p, const usm_op_options *opt,
                              usm_op_result *out)
{
    usm_sim_options so = opt->sim;
    so.start = USM_SIM_FROM_REST;
    so.t0 = 0.0;
    so.duration = opt->periods / p->f;
    usm_sim *sim = usm_sim_alloc(m);
    if (!sim) {
        snprintf(out->message, USM_MSG_LEN, "out of memory");
        return USM_EFAILED;
    }
    int rc = usm_sim_run(sim, p, &so, NULL, &out->sim);
    if (rc == USM_EINPUT) {
        snprintf(out->message, USM_MSG_LEN, "from rest: %.200s", usm_sim_message(sim));
        usm_sim_free(sim);
        return USM_EINPUT;
    }
    usm_sim_free(sim);
    out->simulated = 1;
    if (out->sim.settled_on == USM_SIM_SETTLED_REST)
        out->starts_from_rest = 0;
    else if (out->sim.settled_on >= 0)
        out->starts_from_rest = 1;
    return USM_OK;
}

int usm_operating_point(const usm_model *m, const usm_params *p, const usm_steady *s,
                        const usm_floquet_result *fl, const usm_op_options *opt,
                        usm_op_result *out)
{
    usm_op_options def;
    const double t_start = now();
    if (!opt) {
        usm_op_options_default(&def);
        opt = &def;
    }
    memset(out, 0, sizeof *out);
    out->index = -1;
    out->reason = USM_OP_UNDECIDED;
    out->starts_from_rest = -1;
    if (opt->from_rest && !(opt->periods >= 1 && opt->periods <= 1e7)) {
        snprintf(out->message, USM_MSG_LEN, "periods: must be in [1, 1e7], got %g",
                 opt->periods);
        return USM_EINPUT;
    }
    const size_t n = usm_steady_count(s);
    size_t stable = 0;
    for (size_t k = 0; k < n; ++k)
        stable += fl[k].stable != 0;
    if (opt->from_rest) {
        int rc = simulate_from_rest(m, p, opt, out);
        if (rc != USM_OK)
            return rc;
    }
    out->wall = now() - t_start;

    /* rule 1 */
    if (stable == 0) {
        out->reason = USM_OP_NO_STABLE_ROOT;
        snprintf(out->message, USM_MSG_LEN,
                 "no stable stationary solution (%zu root%s, all unstable)", n,
                 n == 1 ? "" : "s");
        return USM_OK;
    }
    /* rule 2 */
    if (!opt->from_rest) {
        if (n == 1) {
            out->index = 0;
            out->reason = USM_OP_ONLY_STABLE_ROOT;
            snprintf(out->message, USM_MSG_LEN, "root #1, the only root, is stable");
        } else
            snprintf(out->message, USM_MSG_LEN,
                     "%zu roots, %zu of them stable: only a simulation from rest tells which "
                     "one the motor reaches (not asked)",
                     n, stable);
        return USM_OK;
    }
    /* rule 3: what the simulation from rest shows */
    const usm_sim_summary *sum = &out->sim;
    if (sum->settled_on == USM_SIM_SETTLED_REST) {
        out->reason = USM_OP_DOES_NOT_START;
        snprintf(out->message, USM_MSG_LEN,
                 "the motor does not start from rest: the wobble decays (tilt below %g of "
                 "%.3g rad by t = %.6g s)",
                 sum->rest_fraction, sum->rest_theta_ref, sum->t_rest);
        return USM_OK;
    }
    if (sum->settled_on < 0) {
        snprintf(out->message, USM_MSG_LEN,
                 "the simulation from rest settled on no root in %g periods (stop: %s%s%.120s)",
                 opt->periods, usm_sim_stop_name(sum->stop), sum->reason[0] ? ": " : "",
                 sum->reason);
        return USM_OK;
    }
    const size_t k = (size_t)sum->settled_on;
    /* the simulation's roots are usm_steady_solve's at the same parameters:
     * the same list as s's when s was solved with the default options */
    if (sum->roots != n || k >= n || usm_steady_root(s, k)->theta != sum->settled_root.theta) {
        snprintf(out->message, USM_MSG_LEN,
                 "the simulation's roots are not these roots (solve them with the default "
                 "options)");
        return USM_OK;
    }
    if (!fl[k].stable) {
        snprintf(out->message, USM_MSG_LEN,
                 "the simulation from rest settled on root #%zu, which the multipliers call "
                 "unstable (max |lambda| %.10g)",
                 k + 1, fl[k].max_modulus);
        return USM_OK;
    }
    out->index = (int)k;
    out->reason = USM_OP_REACHED_FROM_REST;
    snprintf(out->message, USM_MSG_LEN,
             "root #%zu: reached from rest (period means within %g of it for the last %d of "
             "%g periods)",
             k + 1, sum->settle_tol, sum->settle_periods, opt->periods);
    return USM_OK;
}
