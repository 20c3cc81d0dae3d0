/* The non-ideal motor in the report (issue 14, item 4): periodic orbits of
 * the variant "imperfect" (usm_periodic.h) along the phase error (0 to 30
 * degrees) and the mode split (0 to 2 %), each alone; the tolerable value,
 * where the contact opens (F_n_min = 0) or stability is lost (max |lambda| =
 * 1), whichever comes first, located by the Illinois variant of regula falsi
 * on periodic solves; and one orbit for the figure.
 *
 * Each (model, imperfection) curve is one task of the library's pool
 * (pool_internal.h); a curve warm-starts every point from the previous
 * orbits (linear extrapolation of the start state from the last two), and
 * each root's iterates from the orbit at the nearer end of its bracket. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/pool_internal.h"
#include "report_internal.h"

#define PI 3.14159265358979323846264338327950

#define ROOT_MAXEVAL 40

typedef struct per_state {
    usm_periodic *w[REPORT_NMODELS];
} per_state;

typedef struct per_ctx {
    usm_report_data *d;
} per_ctx;

static void *state_alloc(void *ctx)
{
    per_ctx *c = ctx;
    per_state *s = calloc(1, sizeof *s);
    if (!s)
        return NULL;
    for (int k = 0; k < REPORT_NMODELS; ++k)
        if (!(s->w[k] = usm_periodic_alloc(c->d->nonideal.model[k]))) {
            for (int j = 0; j < k; ++j)
                usm_periodic_free(s->w[j]);
            free(s);
            return NULL;
        }
    return s;
}

static void state_free(void *state)
{
    per_state *s = state;
    if (!s)
        return;
    for (int k = 0; k < REPORT_NMODELS; ++k)
        usm_periodic_free(s->w[k]);
    free(s);
}

/* One orbit at imperfection `value` (the others 0), started from x_start
 * (NULL: the library's start from the ideal motor); on failure with a warm
 * start, once more from the ideal start. */
static int solve_at(usm_periodic *w, const usm_params *base, const char *param, double value,
                    const double *x_start, const usm_periodic_options *opt,
                    usm_periodic_result *r, int *solves)
{
    usm_params p = *base;
    char msg[USM_MSG_LEN];
    p.amp_imbalance = p.phase_error = p.mode_split = 0.0;
    if (usm_params_set(&p, param, value, msg) != USM_OK)
        return USM_EINPUT;
    ++*solves;
    int rc = usm_periodic_solve(w, &p, x_start, opt, r);
    if (rc == USM_EFAILED && x_start) {
        ++*solves;
        rc = usm_periodic_solve(w, &p, NULL, opt, r);
    }
    return rc;
}

static double root_function(const usm_periodic_result *r, int stability)
{
    return stability ? 1.0 - r->floquet.max_modulus : r->F_n_min;
}

/* The first root of g (F_n_min, or 1 - max_modulus) on the curve: the first
 * grid interval where g goes from positive to not positive between two
 * converged points, refined by Illinois regula falsi. */
static void locate_root(usm_periodic *w, const usm_params *p, const usm_report_nonideal *ni,
                        usm_report_nonideal_curve *cv, double (*xs)[USM_MAX_NX], int stability,
                        usm_report_nonideal_root *out)
{
    const char *what = stability ? "max |lambda| reaches 1" : "F_n_min reaches 0";
    memset(out, 0, sizeof *out);
    for (int i = 0; i < cv->points; ++i) {
        const usm_report_nonideal_point *pt = &cv->pt[i];
        if (!pt->converged) {
            snprintf(out->note, USM_MSG_LEN,
                     "%s: not located: no periodic orbit found at %s = %.6g, before any "
                     "crossing", what, cv->param, pt->value);
            return;
        }
        const double g = stability ? 1.0 - pt->max_modulus : pt->F_n_min;
        if (g > 0)
            continue;
        if (i == 0) {
            out->found = 1;
            out->value = pt->value;
            snprintf(out->note, USM_MSG_LEN, "%s already without imperfection", what);
            return;
        }
        /* bracket [a, b]: g(a) > 0, g(b) <= 0 */
        double a = cv->pt[i - 1].value, b = pt->value;
        double ga = stability ? 1.0 - cv->pt[i - 1].max_modulus : cv->pt[i - 1].F_n_min, gb = g;
        double xa[USM_MAX_NX], xb[USM_MAX_NX], fa = ga, fb = gb; /* fa, fb: unscaled */
        int side = 0;
        memcpy(xa, xs[i - 1], sizeof xa);
        memcpy(xb, xs[i], sizeof xb);
        for (int it = 0; it < ROOT_MAXEVAL && fabs(b - a) > ni->root_xtol * (cv->to - cv->from);
             ++it) {
            usm_periodic_result r;
            double c = (a * gb - b * ga) / (gb - ga);
            if (!(c > a && c < b))
                c = 0.5 * (a + b);
            const double *start = c - a < b - c ? xa : xb;
            ++out->evaluations;
            if (solve_at(w, p, cv->param, c, start, &ni->opt, &r, &cv->solves) != USM_OK) {
                snprintf(out->note, USM_MSG_LEN,
                         "%s between %s = %.6g and %.6g, not located: no periodic orbit at "
                         "%.6g (%.120s)", what, cv->param, a, b, c, usm_periodic_message(w));
                return;
            }
            const double gc = root_function(&r, stability);
            if (gc > 0) {
                a = c;
                ga = fa = gc;
                memcpy(xa, r.x0, sizeof xa);
                if (side == -1)
                    gb *= 0.5; /* Illinois: the stale end's value halved */
                side = -1;
            } else {
                b = c;
                gb = fb = gc;
                memcpy(xb, r.x0, sizeof xb);
                if (side == 1)
                    ga *= 0.5;
                side = 1;
            }
            if (gc == 0)
                break;
        }
        out->found = 1;
        out->value = fabs(fa) < fabs(fb) ? a : b;
        if (fabs(b - a) > ni->root_xtol * (cv->to - cv->from) && fb != 0) {
            out->value = 0.5 * (a + b);
            snprintf(out->note, USM_MSG_LEN, "%s: bracket [%.9g, %.9g] after %d solves", what, a,
                     b, out->evaluations);
        }
        return;
    }
    snprintf(out->note, USM_MSG_LEN, "%s: not reached for %s from %g to %g", what, cv->param,
             cv->from, cv->to);
}

/* Task i: model i / REPORT_NIMP, imperfection i % REPORT_NIMP. */
static int curve_task(void *ctx, void *state, size_t i)
{
    usm_report_data *d = ((per_ctx *)ctx)->d;
    per_state *s = state;
    const int k = (int)i / REPORT_NIMP, j = (int)i % REPORT_NIMP;
    usm_report_nonideal_curve *cv = &d->nonideal.curve[k][j];
    usm_periodic *w = s->w[k];
    double(*xs)[USM_MAX_NX] = calloc((size_t)cv->points, sizeof *xs);
    usm_periodic_result r;
    if (!xs)
        return USM_EFAILED;
    for (int q = 0; q < cv->points; ++q) {
        usm_report_nonideal_point *pt = &cv->pt[q];
        double start[USM_MAX_NX];
        const double *x_start = NULL;
        pt->value = cv->from + (cv->to - cv->from) * q / (cv->points - 1);
        if (q >= 2 && cv->pt[q - 1].converged && cv->pt[q - 2].converged) {
            for (int c = 0; c < USM_MAX_NX; ++c)
                start[c] = 2.0 * xs[q - 1][c] - xs[q - 2][c];
            x_start = start;
        } else if (q >= 1 && cv->pt[q - 1].converged)
            x_start = xs[q - 1];
        pt->converged =
            solve_at(w, &d->params, cv->param, pt->value, x_start, &d->nonideal.opt_curve, &r,
                     &cv->solves) == USM_OK;
        if (!pt->converged) {
            pt->speed_mean = pt->ripple = pt->F_n_min = pt->F_n_max = NAN;
            pt->max_modulus = pt->theta_h2 = NAN;
            continue;
        }
        memcpy(xs[q], r.x0, sizeof xs[q]);
        pt->speed_mean = r.rotor_speed_mean;
        pt->ripple = r.rotor_speed_ripple;
        pt->F_n_min = r.F_n_min;
        pt->F_n_max = r.F_n_max;
        pt->max_modulus = r.floquet.max_modulus;
        pt->theta_h2 = r.theta_harmonic_2;
    }
    locate_root(w, &d->params, &d->nonideal, cv, xs, 0, &cv->contact);
    locate_root(w, &d->params, &d->nonideal, cv, xs, 1, &cv->stability);
    cv->tolerable_found = cv->contact.found || cv->stability.found;
    if (cv->contact.found && (!cv->stability.found || cv->contact.value <= cv->stability.value)) {
        cv->tolerable = cv->contact.value;
        cv->tolerable_by = "contact";
    } else if (cv->stability.found) {
        cv->tolerable = cv->stability.value;
        cv->tolerable_by = "stability";
    } else {
        cv->tolerable = NAN;
        cv->tolerable_by = "";
    }
    /* the orbit drawn: the 3-DOF motor at its tolerable value of the
     * imperfection that deforms the tilt vector's path most (the mode split:
     * a phase error leaves it nearly a circle), else at the range's end */
    if (k == REPORT_3DOF && j == d->nonideal.orbit_imp) {
        usm_report_nonideal *ni = &d->nonideal;
        const double v = cv->tolerable_found ? cv->tolerable : cv->to;
        ni->orbit_value = v;
        if (solve_at(w, &d->params, cv->param, v, NULL, &ni->opt, &r, &cv->solves) == USM_OK) {
            const double *smp = usm_periodic_samples(w);
            const int cols = r.nx + 4;
            ni->orbit_ok = 1;
            ni->orbit_nx = r.nx;
            ni->orbit_F_n_min = r.F_n_min;
            ni->orbit_period = r.period;
            for (int q = 0; q < USM_PERIODIC_SAMPLES; ++q)
                memcpy(ni->orbit[q], smp + (size_t)q * (size_t)cols, sizeof(double) * (size_t)cols);
        } else
            snprintf(ni->orbit_note, USM_MSG_LEN, "no periodic orbit at %s = %g: %.150s",
                     cv->param, v, usm_periodic_message(w));
    }
    free(xs);
    return USM_OK;
}

int usm_report_compute_nonideal(usm_report_data *d, char msg[USM_IO_MSG_LEN])
{
    usm_report_nonideal *ni = &d->nonideal;
    const double t = usm_report_now();
    /* quick: 7 points (5 degrees, 1/3 %); full: 21 (1.5 degrees, 0.1 %) */
    const int points = d->opt.quick ? 7 : 21;
    static const char *const param[REPORT_NIMP] = {"phase_error", "mode_split"};
    static const double to[REPORT_NIMP] = {30.0 * PI / 180.0, 0.02};
    per_ctx ctx = {d};
    char pmsg[USM_MSG_LEN];
    memset(ni, 0, sizeof *ni);
    ni->orbit_imp = REPORT_IMP_SPLIT;
    /* The curves' points with looser tolerances than usm periodic's (the
     * orbit's numbers to about 1e-7, the multipliers to about 1e-6: far below
     * what the figures show) at half the cost per orbit; the roots and the
     * orbit drawn with usm periodic's own, to 1e-9 of the range.  --quick:
     * everything with the looser ones, the roots to 1e-6 of the range. */
    usm_periodic_options_default(&ni->opt);
    ni->opt_curve = ni->opt;
    ni->opt_curve.rtol = 1e-9;
    ni->opt_curve.tol = 1e-7;
    ni->root_xtol = d->opt.quick ? 1e-6 : 1e-9;
    if (d->opt.quick)
        ni->opt = ni->opt_curve;
    for (int k = 0; k < REPORT_NMODELS; ++k) {
        const usm_model *m = d->model[k].model;
        ni->model[k] = m ? usm_model_variant(m->base, "imperfect") : NULL;
        if (!ni->model[k]) {
            snprintf(ni->note, USM_MSG_LEN, "the variant imperfect of %s is not built",
                     m ? m->base : "?");
            return USM_OK;
        }
        ni->theta_ideal[k] = d->model[k].sol.theta;
        for (int j = 0; j < REPORT_NIMP; ++j) {
            usm_report_nonideal_curve *cv = &ni->curve[k][j];
            cv->param = param[j];
            cv->from = 0.0;
            cv->to = to[j];
            cv->points = points;
        }
    }
    if (ni->model[REPORT_3DOF]->x_phi < 0 || ni->model[REPORT_3DOF]->x_theta < 0) {
        snprintf(ni->note, USM_MSG_LEN, "the 3-DOF model has no phi or theta state");
        return USM_OK;
    }
    ni->orbit_x_phi = ni->model[REPORT_3DOF]->x_phi;
    ni->orbit_x_theta = ni->model[REPORT_3DOF]->x_theta;
    pool_job job = {(size_t)(REPORT_NMODELS * REPORT_NIMP), d->opt.threads, &ctx, state_alloc,
                    state_free, curve_task, NULL};
    if (pool_run(&job, pmsg) != USM_OK) {
        usm_io_msg(msg, "the non-ideal motor: %s", pmsg[0] ? pmsg : "out of memory");
        return USM_EFAILED;
    }
    ni->ok = 1;
    ni->seconds = usm_report_now() - t;
    return USM_OK;
}

int usm_report_figure_count(const usm_report_data *d)
{
    if (!d->nonideal.ok)
        return REPORT_FIG_NONIDEAL;
    return d->nonideal.orbit_ok ? REPORT_NFIGURES : REPORT_FIG_ORBIT;
}
