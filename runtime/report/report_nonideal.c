/* The non-ideal motor in the report: periodic orbits of
 * the variant "imperfect" along the phase error (0 to 36 degrees) and the
 * mode split (0 to 2.4 %), each alone; past contact loss the orbits with
 * separation of the variant "imperfect_unilateral" (the sweep
 * runs on that model, whose bilateral orbits are those of "imperfect"), followed by the library's periodic
 * sweep (usm_periodic_sweep.h, the computation of `usm sweep --periodic`);
 * the tolerable value, where the contact opens (F_n_min = 0) or stability is
 * lost (max |lambda| = 1), whichever comes first: the sweep's contact_loss or
 * stability_change event on the first grid interval where the quantity
 * changes sign; and one orbit for the figure (usm_periodic.h).
 *
 * Each (model, imperfection) curve is one task of the library's pool
 * (pool_internal.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/grid.h"
#include "core/pool_internal.h"
#include "report_internal.h"
#include "usm_periodic_sweep.h"

#define PI 3.14159265358979323846264338327950

typedef struct per_state {
    usm_periodic_sweep *sweep[REPORT_NMODELS];
    usm_periodic *w[REPORT_NMODELS]; /* the orbit drawn */
} per_state;

typedef struct per_ctx {
    usm_report_data *d;
} per_ctx;

static void state_free(void *state)
{
    per_state *s = state;
    if (!s)
        return;
    for (int k = 0; k < REPORT_NMODELS; ++k) {
        usm_periodic_sweep_free(s->sweep[k]);
        usm_periodic_free(s->w[k]);
    }
    free(s);
}

static void *state_alloc(void *ctx)
{
    per_ctx *c = ctx;
    per_state *s = calloc(1, sizeof *s);
    if (!s)
        return NULL;
    for (int k = 0; k < REPORT_NMODELS; ++k)
        if (!(s->sweep[k] = usm_periodic_sweep_alloc(c->d->nonideal.umodel[k]
                                                         ? c->d->nonideal.umodel[k]
                                                         : c->d->nonideal.model[k])) ||
            !(s->w[k] = usm_periodic_alloc(c->d->nonideal.model[k]))) {
            state_free(s);
            return NULL;
        }
    return s;
}

/* The parameters of a curve: the report's with every imperfection 0 (the
 * sweep sets the one it follows). */
static usm_params curve_params(const usm_params *base)
{
    usm_params p = *base;
    p.amp_imbalance = p.phase_error = p.mode_split = 0.0;
    return p;
}

/* The first root of g (F_n_min, or 1 - max_modulus) on the curve: the first
 * grid interval where g goes from positive to not positive between two
 * converged points; there the sweep's event of that kind (the first in the
 * interval: g > 0 at its start, so it is the crossing downwards). */
static void root_from_sweep(const usm_periodic_sweep *sw, const usm_report_nonideal_curve *cv,
                            int stability, usm_report_nonideal_root *out)
{
    const char *what = stability ? "max |lambda| reaches 1" : "F_n_min reaches 0";
    const usm_pevent_type type = stability ? USM_PEVENT_STABILITY_CHANGE : USM_PEVENT_CONTACT_LOSS;
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
        if (!stability)
            out->openings = pt->openings;
        if (i == 0) {
            out->found = 1;
            out->value = pt->value;
            snprintf(out->note, USM_MSG_LEN, "%s already without imperfection", what);
            return;
        }
        const double a = cv->pt[i - 1].value, b = pt->value;
        for (size_t q = 0; q < usm_periodic_sweep_event_count(sw); ++q) {
            const usm_periodic_event *e = usm_periodic_sweep_event_at(sw, q);
            /* the bilateral orbit's crossing (an orbit with separation's
             * stability_change carries has_hybrid) */
            if (e->type != type || e->has_hybrid || !(e->value >= a && e->value <= b))
                continue;
            out->found = 1;
            out->value = e->value;
            if (strstr(e->what, "not located to tolerance"))
                snprintf(out->note, USM_MSG_LEN,
                         "%s between %s = %.6g and %.6g: not located to tolerance (a trial "
                         "orbit failed)", what, cv->param, a, b);
            return;
        }
        if (g == 0) { /* on the grid point: no sign change for the sweep */
            out->found = 1;
            out->value = b;
            return;
        }
        snprintf(out->note, USM_MSG_LEN, "%s between %s = %.6g and %.6g, not located by the sweep",
                 what, cv->param, a, b);
        return;
    }
    snprintf(out->note, USM_MSG_LEN, "%s: not reached for %s from %g to %g", what, cv->param,
             cv->from, cv->to);
}

/* How far the curve is valid (usm_periodic_result.validity, from 0): the
 * first grid interval from a valid to an invalid orbit, and there the sweep's
 * first stick_loss or contact_loss event (else the last valid grid value). */
static void valid_from_sweep(const usm_periodic_sweep *sw, const usm_report_nonideal_curve *cv,
                             usm_report_nonideal_root *out)
{
    memset(out, 0, sizeof *out);
    for (int i = 0; i < cv->points; ++i) {
        const usm_report_nonideal_point *pt = &cv->pt[i];
        if (!pt->converged || pt->validity == USM_VALID)
            continue;
        out->found = 1;
        out->value = pt->value;
        snprintf(out->note, USM_MSG_LEN, "%s", usm_validity_name(pt->validity));
        if (i == 0 || !cv->pt[i - 1].converged)
            return;
        const double a = cv->pt[i - 1].value, b = pt->value;
        out->value = a;
        for (size_t q = 0; q < usm_periodic_sweep_event_count(sw); ++q) {
            const usm_periodic_event *e = usm_periodic_sweep_event_at(sw, q);
            if ((e->type == USM_PEVENT_STICK_LOSS || e->type == USM_PEVENT_CONTACT_LOSS) &&
                e->value >= fmin(a, b) && e->value <= fmax(a, b)) {
                out->value = e->value;
                snprintf(out->note, USM_MSG_LEN, "%s", e->type == USM_PEVENT_STICK_LOSS
                                                           ? "stick_loss" : "contact_loss");
                return;
            }
        }
        return;
    }
}

/* Task i: model i / REPORT_NIMP, imperfection i % REPORT_NIMP. */
static int curve_task(void *ctx, void *state, size_t i)
{
    usm_report_data *d = ((per_ctx *)ctx)->d;
    per_state *s = state;
    const int k = (int)i / REPORT_NIMP, j = (int)i % REPORT_NIMP;
    usm_report_nonideal_curve *cv = &d->nonideal.curve[k][j];
    usm_periodic_sweep *sw = s->sweep[k];
    usm_periodic *w = s->w[k];
    const usm_params base = curve_params(&d->params);
    usm_periodic_sweep_options opt;
    usm_periodic_result r;
    usm_periodic_sweep_options_default(&opt);
    opt.over = cv->param;
    opt.from = cv->from;
    opt.to = cv->to;
    opt.points = cv->points;
    opt.event_tol = d->nonideal.root_xtol;
    opt.periodic = d->nonideal.opt;
    /* no orbit at the start (or bad input): every point without an orbit,
     * which the roots' notes say */
    const int swept = usm_periodic_sweep_run(sw, &base, &opt) == USM_OK;
    for (int q = 0; q < cv->points; ++q) {
        usm_report_nonideal_point *pt = &cv->pt[q];
        const usm_periodic_point *sp = swept ? usm_periodic_sweep_point_at(sw, (size_t)q) : NULL;
        pt->value = sp ? sp->value : usm_grid_value(cv->from, cv->to, q, cv->points);
        pt->converged = sp && sp->converged;
        if (!pt->converged) {
            pt->speed_mean = pt->ripple = pt->F_n_min = pt->F_n_max = NAN;
            pt->max_modulus = pt->theta_h2 = NAN;
            pt->separating = 0;
            pt->sep_speed_mean = pt->sep_ripple = pt->sep_max_modulus = NAN;
            pt->sep_fraction = pt->impact_velocity_max = NAN;
            pt->validity = USM_VALID;
            continue;
        }
        pt->speed_mean = sp->orbit.rotor_speed_mean;
        pt->ripple = sp->orbit.rotor_speed_ripple;
        pt->F_n_min = sp->orbit.F_n_min;
        pt->openings = sp->orbit.openings_per_period;
        pt->F_n_max = sp->orbit.F_n_max;
        pt->max_modulus = sp->orbit.floquet.max_modulus;
        pt->theta_h2 = sp->orbit.theta_harmonic_2;
        pt->validity = sp->orbit.validity;
        pt->sep_speed_mean = pt->sep_ripple = pt->sep_max_modulus = NAN;
        pt->sep_fraction = pt->impact_velocity_max = NAN;
        pt->separating = sp->separating;
        if (sp->separating) {
            const usm_hybrid_result *hy = &sp->hybrid;
            pt->sep_speed_mean = hy->rotor_speed_mean;
            pt->sep_ripple = hy->rotor_speed_ripple;
            pt->sep_max_modulus = hy->floquet.max_modulus;
            pt->sep_fraction = hy->separation_fraction;
            pt->sep_validity = hy->validity;
            pt->impact_velocity_max = hy->impact_velocity_max;
        }
    }
    /* past contact loss: how far the stable orbits with separation drive the
     * load (their mean rotor speed has the ideal motor's sign, that of the
     * first point), their largest impact velocity; the unstable ones counted
     * apart.  Where the continued orbit turned unstable and a start from
     * rest settles on a stable one, the sweep switched to that (the motor's:
     * branch_switch), and these are its numbers */
    cv->sep_points = 0;
    cv->sep_drives_all = 1;
    cv->sep_drives_to = cv->sep_impact_max = cv->sep_impact_at = NAN;
    cv->sep_unstable = 0;
    cv->sep_unstable_from = cv->sep_unstable_to = cv->sep_modulus_max = NAN;
    cv->sep_switches = 0;
    cv->sep_switch_at = cv->sep_switch_modulus = cv->sep_switch_unstable_from = NAN;
    for (size_t q = 0; swept && q < usm_periodic_sweep_event_count(sw); ++q) {
        const usm_periodic_event *e = usm_periodic_sweep_event_at(sw, q);
        if (e->type != USM_PEVENT_BRANCH_SWITCH)
            continue;
        if (cv->sep_switches++ == 0) {
            cv->sep_switch_at = e->value;
            cv->sep_switch_modulus = e->branch_lost ? NAN : e->hybrid_left.floquet.max_modulus;
            cv->sep_switch_unstable_from = e->branch_lost ? NAN : e->unstable_from;
        }
    }
    for (int q = 0; q < cv->points; ++q) {
        const usm_report_nonideal_point *pt = &cv->pt[q];
        if (!pt->separating)
            continue;
        cv->sep_points++;
        if (!(pt->sep_max_modulus <= cv->sep_modulus_max))
            cv->sep_modulus_max = pt->sep_max_modulus;
        if (!(pt->sep_max_modulus < 1.0)) { /* unstable, or no multipliers: not the motor's */
            if (cv->sep_unstable++ == 0)
                cv->sep_unstable_from = pt->value;
            cv->sep_unstable_to = pt->value;
            continue; /* its speed and impacts are not what the motor does */
        }
        const int drives = cv->pt[0].converged && pt->sep_speed_mean * cv->pt[0].speed_mean > 0;
        if (drives && cv->sep_drives_all)
            cv->sep_drives_to = pt->value;
        else
            cv->sep_drives_all = 0;
        if (!(pt->impact_velocity_max <= cv->sep_impact_max)) {
            cv->sep_impact_max = pt->impact_velocity_max;
            cv->sep_impact_at = pt->value;
        }
    }
    root_from_sweep(sw, cv, 0, &cv->contact);
    root_from_sweep(sw, cv, 1, &cv->stability);
    valid_from_sweep(sw, cv, &cv->valid_to);
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
        usm_params p = base;
        char pmsg[USM_MSG_LEN];
        if (usm_params_set(&p, cv->param, v, pmsg) == USM_OK &&
            usm_periodic_solve(w, &p, NULL, &ni->opt, &r) == USM_OK) {
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
    return USM_OK;
}

int usm_report_compute_nonideal(usm_report_data *d, char msg[USM_IO_MSG_LEN])
{
    usm_report_nonideal *ni = &d->nonideal;
    const double t = usm_report_now();
    /* to 36 degrees and 2.4 %, past the contact loss (28.7 / 23.2 degrees,
     * 1.64 / 1.33 %), where the unilateral model's orbits with separation
     * continue the curves: 25 points (1.5 degrees, 0.1 %).  Quick: 7 points
     * to 30 degrees and 1.8 % (5 degrees, 0.3 %), still past both contact
     * losses but short of the orbits with separation's folds (33.9 degrees,
     * 1.91 % for the 4-DOF model), whose location cost half the report */
    const int points = d->opt.quick ? 7 : 25;
    static const char *const param[REPORT_NIMP] = {"phase_error", "mode_split"};
    static const double to_full[REPORT_NIMP] = {36.0 * PI / 180.0, 0.024};
    static const double to_quick[REPORT_NIMP] = {30.0 * PI / 180.0, 0.018};
    const double *to = d->opt.quick ? to_quick : to_full;
    per_ctx ctx = {d};
    char pmsg[USM_MSG_LEN];
    memset(ni, 0, sizeof *ni);
    ni->orbit_imp = REPORT_IMP_SPLIT;
    /* The orbits with usm periodic's tolerances, the roots to 1e-9 of the
     * range.  --quick: looser tolerances (CVODES rtol 1e-9, Newton 1e-7: the
     * orbit's numbers to about 1e-7, the multipliers to about 1e-6, far below
     * what the figures show) at half the cost per orbit, the roots to 1e-6
     * of the range. */
    usm_periodic_options_default(&ni->opt);
    ni->root_xtol = d->opt.quick ? 1e-6 : 1e-9;
    if (d->opt.quick) {
        ni->opt.rtol = 1e-9;
        ni->opt.tol = 1e-7;
    }
    for (int k = 0; k < REPORT_NMODELS; ++k) {
        const usm_model *m = d->model[k].model;
        ni->model[k] = m ? usm_model_variant(m->base, "imperfect") : NULL;
        ni->umodel[k] = m ? usm_model_variant(m->base, "imperfect_unilateral") : NULL;
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
    if (!d->nonideal.orbit_ok)
        return REPORT_FIG_ORBIT;
    if (!d->squeal.motion.ok)
        return REPORT_FIG_SQUEAL_MOTION;
    if (!d->squeal.ok)
        return REPORT_FIG_SQUEAL;
    return d->envelope.ok ? REPORT_NFIGURES : REPORT_FIG_ENVELOPE;
}
