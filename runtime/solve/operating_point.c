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
#include "core/dense.h"

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

const char *usm_op_rule_text(const usm_op_options *o)
{
    const int fr = o ? o->from_rest : 0;
    if (fr == USM_OP_FROM_REST_ALWAYS)
        return "every point with a stable root is decided by a start-up from rest, below every "
               "unstable root";
    if (fr)
        return "ambiguous points (several roots with a stable one, or one stable root while the "
               "preload holds the stator at rest) are decided by a start-up from rest, below "
               "every unstable root; the others without a simulation";
    return "ambiguous points (several roots with a stable one, or one stable root while the "
           "preload holds the stator at rest) are not simulated: their operating point is "
           "unknown (--from-rest simulates them); the others are decided without a simulation";
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

/* The stationary residuals at theta = 0 as functions of v = (alpha,
 * [phidot_R,] m0): the model's own kernel, the tilt fixed at 0. */
static int residual_at_rest(const usm_model *m, const usm_params *p, const double *v, double *r)
{
    double u[8] = {0};
    usm_params q = *p;
    int j = 0;
    for (int i = 0; i < m->nu; ++i)
        u[i] = i == m->u_theta ? 0.0 : v[j++];
    q.m0 = v[j];
    m->steady_residual(u, &q, r);
    for (int i = 0; i < m->nu; ++i)
        if (!isfinite(r[i]))
            return -1;
    return 0;
}

int usm_op_start_margin(const usm_model *m, const usm_params *p, double *margin)
{
    const int n = m->nu;
    if (n < 2 || n > 8 || m->u_theta < 0)
        return USM_ENOSOLUTION;
    /* the scale of the moments: the excitation and the preload's moment */
    const double scale = fmax(p->m0, p->R * p->F0);
    for (int seed = 0; seed < 8; ++seed) {
        double v[8] = {0}, r[8], J[64], rp[8];
        int piv[8];
        /* alpha around the circle, the rotor at rest, m0 the preload's moment */
        v[0] = 6.283185307179586 * seed / 8.0;
        v[n - 1] = hypot(p->R * p->F0, p->H * p->T / p->R);
        for (int it = 0; it < 60; ++it) {
            if (residual_at_rest(m, p, v, r) != 0)
                break;
            double rn = 0.0;
            for (int i = 0; i < n; ++i)
                rn = fmax(rn, fabs(r[i]));
            if (rn <= 1e-13 * scale && v[n - 1] > 0) {
                *margin = p->m0 / v[n - 1] - 1.0;
                return USM_OK;
            }
            /* central differences: three unknowns, a kernel call each way */
            int bad = 0;
            for (int j = 0; j < n && !bad; ++j) {
                const double h = 1e-7 * fmax(fabs(v[j]), j == n - 1 ? scale : 1.0);
                double vp[8], vm[8], rm[8];
                memcpy(vp, v, sizeof vp);
                memcpy(vm, v, sizeof vm);
                vp[j] += h;
                vm[j] -= h;
                bad = residual_at_rest(m, p, vp, rp) != 0 || residual_at_rest(m, p, vm, rm) != 0;
                for (int i = 0; i < n && !bad; ++i)
                    J[i * n + j] = (rp[i] - rm[i]) / (2 * h);
            }
            if (bad || usm_lu_factor_dense(n, J, piv) != 0)
                break;
            usm_lu_solve_dense(n, J, piv, r, 1);
            for (int i = 0; i < n; ++i)
                v[i] -= r[i];
        }
    }
    return USM_ENOSOLUTION;
}

/* The model to simulate from rest (usm_operating_point.h): m, or its
 * twist_integrated variant in the tilt vector when m is the paper's variant
 * in Euler angles and the variant's roots are s's. */
static const usm_model *sim_model(const usm_model *m, const usm_params *p, const usm_steady *s)
{
    if (m->coordinates != 0 || m->other_coordinates || m->unilateral || m->imperfect ||
        strcmp(m->variant, "paper") != 0)
        return m;
    const usm_model *c = usm_model_variant(m->base, "twist_integrated");
    if (!c || !c->other_coordinates || c->other_coordinates->coordinates != 1)
        return m;
    usm_steady *sc = usm_steady_alloc(c);
    int same = sc && usm_steady_solve(sc, p, NULL) == USM_OK &&
               usm_steady_count(sc) == usm_steady_count(s);
    for (size_t k = 0; same && k < usm_steady_count(s); ++k) {
        const usm_steady_solution *a = usm_steady_root(s, k), *b = usm_steady_root(sc, k);
        same = fabs(a->theta - b->theta) <= 1e-9 * a->theta &&
               fabs(a->rotor_speed - b->rotor_speed) <= 1e-9 * fmax(fabs(a->rotor_speed), 1e-6);
    }
    usm_steady_free(sc);
    return same ? c : m;
}

/* The simulation from rest; USM_OK (an answer in out->sim) or USM_EINPUT /
 * USM_EFAILED (bad options, out of memory). */
static int simulate_from_rest(const usm_model *m, const usm_params *p, const usm_steady *s,
                              const usm_op_options *opt, usm_op_result *out)
{
    usm_sim_options so = opt->sim;
    so.start = USM_SIM_FROM_REST;
    so.t0 = 0.0;
    so.duration = opt->periods / p->f;
    out->sim_model = sim_model(m, p, s);
    usm_sim *sim = usm_sim_alloc(out->sim_model);
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
    out->start_margin = NAN;
    if (opt->from_rest < 0 || opt->from_rest > USM_OP_FROM_REST_ALWAYS) {
        snprintf(out->message, USM_MSG_LEN, "from_rest: must be 0, 1 or %d, got %d",
                 USM_OP_FROM_REST_ALWAYS, opt->from_rest);
        return USM_EINPUT;
    }
    if (opt->from_rest && !(opt->periods >= 1 && opt->periods <= 1e7)) {
        snprintf(out->message, USM_MSG_LEN, "periods: must be in [1, 1e7], got %g",
                 opt->periods);
        return USM_EINPUT;
    }
    const size_t n = usm_steady_count(s);
    size_t stable = 0;
    for (size_t k = 0; k < n; ++k)
        stable += fl[k].stable != 0;
    double margin;
    if (usm_op_start_margin(m, p, &margin) == USM_OK)
        out->start_margin = margin;
    const int in_doubt = !(out->start_margin > 0);
    out->ambiguous = stable > 0 && (n > 1 || in_doubt);
    if (stable > 0 && (opt->from_rest == USM_OP_FROM_REST_ALWAYS ||
                       (opt->from_rest && out->ambiguous))) {
        int rc = simulate_from_rest(m, p, s, opt, out);
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
    if (!out->ambiguous && !out->simulated) {
        out->index = 0;
        out->reason = USM_OP_ONLY_STABLE_ROOT;
        snprintf(out->message, USM_MSG_LEN,
                 "root #1, the only root, is stable, and the excitation overcomes the "
                 "preload's moment at rest (start margin %.3g)",
                 out->start_margin);
        return USM_OK;
    }
    if (!out->simulated) {
        if (n > 1)
            snprintf(out->message, USM_MSG_LEN,
                     "%zu roots, %zu of them stable: only a start-up from rest tells which one "
                     "the motor reaches, and it was skipped",
                     n, stable);
        else
            snprintf(out->message, USM_MSG_LEN,
                     "one stable root, but at rest the preload's moment holds the stator "
                     "(start margin %.3g): only a start-up from rest tells whether the motor "
                     "starts, and it was skipped",
                     out->start_margin);
        return USM_OK;
    }
    /* rule 3: what the simulation from rest shows */
    const usm_sim_summary *sum = &out->sim;
    if (sum->settled_on == USM_SIM_SETTLED_REST) {
        out->reason = USM_OP_DOES_NOT_START;
        snprintf(out->message, USM_MSG_LEN,
                 "the motor does not start from rest: the wobble decays (period-mean tilt "
                 "held below %g of %.3g rad by t = %.6g s)",
                 sum->rest_fraction, sum->rest_theta_ref, sum->t_rest);
        return USM_OK;
    }
    if (sum->settled_on < 0) {
        /* the whole reason: the message holds it (USM_MSG_LEN) when the
         * simulation's own reason is short enough, else its cause alone */
        const double done = sum->periods;
        int len = snprintf(out->message, USM_MSG_LEN,
                           "the start-up from rest settled on no root after %.0f of %g "
                           "periods (stop: %s%s%s)",
                           done, opt->periods, usm_sim_stop_name(sum->stop),
                           sum->reason[0] ? ": " : "", sum->reason);
        if (len >= USM_MSG_LEN)
            snprintf(out->message, USM_MSG_LEN,
                     "the start-up from rest settled on no root after %.0f of %g periods "
                     "(stop: %s; the simulation's summary has the whole reason)",
                     done, opt->periods, usm_sim_stop_name(sum->stop));
        return USM_OK;
    }
    const size_t k = (size_t)sum->settled_on;
    /* the simulation's roots are usm_steady_solve's at the same parameters:
     * the same list as s's when s was solved with the default options */
    if (sum->roots != n || k >= n ||
        fabs(usm_steady_root(s, k)->theta - sum->settled_root.theta) >
            1e-9 * usm_steady_root(s, k)->theta) {
        snprintf(out->message, USM_MSG_LEN,
                 "the simulation's roots are not these roots (solve them with the default "
                 "options)");
        return USM_OK;
    }
    if (!fl[k].stable) {
        snprintf(out->message, USM_MSG_LEN,
                 "the start-up from rest settled on root #%zu, which the multipliers call "
                 "unstable (max |lambda| %.10g)",
                 k + 1, fl[k].max_modulus);
        return USM_OK;
    }
    out->index = (int)k;
    out->reason = USM_OP_REACHED_FROM_REST;
    snprintf(out->message, USM_MSG_LEN,
             "root #%zu: reached from rest (period means within %g of it for the last %d of "
             "%.0f periods)",
             k + 1, sum->settle_tol, sum->settle_periods, (double)sum->periods);
    return USM_OK;
}
