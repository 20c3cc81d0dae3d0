/* Datasheet quantities of a design (usm_robust.h): stall torque, no-load
 * speed, maximum power over load, frequency band width, and any optimizer
 * output judged over an operating range; each from one continuation sweep
 * (usm_sweep.h) and its events. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "usm_map.h"
#include "usm_robust.h"
#include "usm_sweep.h"

static const struct {
    int k;
    const char *name, *unit;
} derived[] = {
    {USM_ROBUST_STALL_TORQUE, "stall_torque", "N m"},
    {USM_ROBUST_NO_LOAD_SPEED, "no_load_speed", "1/s"},
    {USM_ROBUST_MAX_POWER, "max_power", "W"},
    {USM_ROBUST_BAND_WIDTH, "band_width", "Hz"},
    {USM_ROBUST_YIELD, "yield", "1"},
};
#define NDERIVED ((int)(sizeof derived / sizeof derived[0]))

static const char *const range_stat_names[] = {"worst", "mean", "integral"};

const char *usm_robust_quantity_name(int k)
{
    if (k >= 0 && k < USM_OPT_OUTPUT_COUNT)
        return usm_opt_output_name(k);
    for (int i = 0; i < NDERIVED; ++i)
        if (derived[i].k == k)
            return derived[i].name;
    return NULL;
}

const char *usm_robust_quantity_unit(int k)
{
    if (k >= 0 && k < USM_OPT_OUTPUT_COUNT)
        return usm_opt_output_unit(k);
    for (int i = 0; i < NDERIVED; ++i)
        if (derived[i].k == k)
            return derived[i].unit;
    return NULL;
}

int usm_robust_quantity_find(const char *name)
{
    if (!name)
        return -1;
    for (int i = 0; i < NDERIVED; ++i)
        if (strcmp(name, derived[i].name) == 0)
            return derived[i].k;
    return usm_opt_output_find(name);
}

int usm_range_stat_find(const char *name)
{
    for (int i = 0; i < 3; ++i)
        if (name && strcmp(name, range_stat_names[i]) == 0)
            return i;
    return -1;
}

const char *usm_range_stat_name(usm_range_stat s)
{
    return (int)s >= 0 && (int)s < 3 ? range_stat_names[s] : NULL;
}

/* ---- the sweeps ------------------------------------------------------------------- */

static double monitor_power_out(const usm_steady_solution *sol, const usm_params *p, void *ctx)
{
    (void)p;
    (void)ctx;
    return sol->power_out;
}

static double monitor_speed(const usm_steady_solution *sol, const usm_params *p, void *ctx)
{
    (void)p;
    (void)ctx;
    return -sol->rotor_speed;
}

/* A sweep of parameter `param` over [lo, hi] at `points` values, with one
 * monitor (NULL: none), multipliers only when floquet.  NULL with msg on
 * failure. */
static usm_sweep *sweep(const usm_model *m, const usm_params *p, int param, double lo,
                        double hi, int points, const usm_sweep_monitor *mon, int floquet,
                        double t0, char msg[USM_MSG_LEN])
{
    usm_sweep *s = usm_sweep_alloc(m);
    usm_sweep_options o;
    if (!s) {
        snprintf(msg, USM_MSG_LEN, "out of memory");
        return NULL;
    }
    usm_sweep_options_default(&o);
    o.over = usm_param_table[param].name;
    o.from = lo;
    o.to = hi;
    o.points = points;
    o.floquet = floquet;
    o.operating_point = 0;
    o.threads = 1;
    o.t0 = t0;
    o.monitors = mon;
    o.nmonitors = mon ? 1 : 0;
    const int rc = usm_sweep_run(s, p, &o);
    if (rc != USM_OK) {
        snprintf(msg, USM_MSG_LEN, "sweep over %s: %.200s", o.over, usm_sweep_message(s));
        usm_sweep_free(s);
        return NULL;
    }
    return s;
}

static int load_range(const usm_quantity_options *opt, const char *what, double *lo, double *hi,
                      int *points, char msg[USM_MSG_LEN])
{
    const usm_robust_range *r = &opt->range;
    *lo = 0;
    *hi = USM_ROBUST_T_MAX;
    *points = 21;
    if (r->param >= 0) {
        if (r->param != USM_P_T) {
            snprintf(msg, USM_MSG_LEN, "over-range: %s searches a load range: give T=LO:HI, "
                     "not %s", what, usm_param_table[r->param].name);
            return USM_EINPUT;
        }
        *lo = r->lo;
        *hi = r->hi;
        *points = r->points;
    }
    return USM_OK;
}

static int stall_torque(const usm_model *m, const usm_params *p, const usm_quantity_options *opt,
                        double *value, char msg[USM_MSG_LEN])
{
    double lo, hi;
    int n;
    if (!m->slip) {
        snprintf(msg, USM_MSG_LEN, "stall_torque: model %s keeps stick (the rotor speed is "
                 "kinematic and never stalls); use a slip model (--model 4dof)", m->name);
        return USM_EINPUT;
    }
    if (load_range(opt, "stall_torque", &lo, &hi, &n, msg) != USM_OK)
        return USM_EINPUT;
    usm_sweep *s = sweep(m, p, USM_P_T, lo, hi, n, NULL, 0, opt->t0, msg);
    if (!s)
        return USM_ENOSOLUTION;
    int rc = USM_ENOSOLUTION;
    for (size_t i = 0; i < usm_sweep_event_count(s); ++i) {
        const usm_sweep_event *e = usm_sweep_event_at(s, i);
        if (e->type == USM_EVENT_STALL) {
            *value = e->value;
            rc = USM_OK;
            break;
        }
    }
    if (rc != USM_OK)
        snprintf(msg, USM_MSG_LEN, "stall_torque: no stall between T = %g and %g N m", lo, hi);
    usm_sweep_free(s);
    return rc;
}

static int max_power(const usm_model *m, const usm_params *p, const usm_quantity_options *opt,
                     double *value, char msg[USM_MSG_LEN])
{
    double lo, hi;
    int n;
    if (load_range(opt, "max_power", &lo, &hi, &n, msg) != USM_OK)
        return USM_EINPUT;
    const usm_sweep_monitor mon = {"power_out", monitor_power_out, NULL, 1, 0, {0}};
    usm_sweep *s = sweep(m, p, USM_P_T, lo, hi, n, &mon, 0, opt->t0, msg);
    if (!s)
        return USM_ENOSOLUTION;
    double best = -INFINITY;
    for (size_t i = 0; i < usm_sweep_count(s); ++i) {
        const usm_sweep_point *pt = usm_sweep_point_at(s, i);
        /* only where the model describes the motor (3-DOF: past the stick
         * limit the power of the stick model grows on, but the motor slips) */
        if (pt->converged && pt->sol.validity == USM_VALID && pt->sol.power_out > best)
            best = pt->sol.power_out;
    }
    for (size_t i = 0; i < usm_sweep_event_count(s); ++i) {
        const usm_sweep_event *e = usm_sweep_event_at(s, i);
        if (e->type == USM_EVENT_MAXIMUM && e->has_sol && e->sol.validity == USM_VALID &&
            e->monitor_value > best)
            best = e->monitor_value;
        /* the stick limit, located: where the stick model's power is largest
         * when it grows up to the limit */
        if (e->type == USM_EVENT_STICK_LIMIT && e->has_sol && e->sol.power_out > best)
            best = e->sol.power_out;
    }
    usm_sweep_free(s);
    if (!isfinite(best)) {
        snprintf(msg, USM_MSG_LEN, "max_power: no stationary solution the model holds for "
                 "between T = %g and %g N m", lo, hi);
        return USM_ENOSOLUTION;
    }
    *value = best;
    return USM_OK;
}

static int cmp_double(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static int band_width(const usm_model *m, const usm_params *p, const usm_quantity_options *opt,
                      double *value, char msg[USM_MSG_LEN])
{
    const usm_robust_range *r = &opt->range;
    if (r->param != USM_P_f) {
        snprintf(msg, USM_MSG_LEN, "over-range: band_width needs the frequency range "
                 "f=LO:HI");
        return USM_EINPUT;
    }
    if (!isfinite(opt->band_threshold)) {
        snprintf(msg, USM_MSG_LEN, "band-threshold: band_width needs the speed threshold [1/s]");
        return USM_EINPUT;
    }
    usm_sweep_monitor mon = {"speed", monitor_speed, NULL, 0, 1, {opt->band_threshold}};
    usm_sweep *s = sweep(m, p, USM_P_f, r->lo, r->hi, r->points, &mon, 0, opt->t0, msg);
    if (!s)
        return USM_ENOSOLUTION;
    /* the cuts: the ends and every crossing; a piece counts when its grid
     * values lie above the threshold (no grid value inside: the state after
     * the last crossing, flipped) */
    const size_t ne = usm_sweep_event_count(s), np = usm_sweep_count(s);
    double *cut = malloc((ne + 2) * sizeof *cut);
    if (!cut) {
        usm_sweep_free(s);
        snprintf(msg, USM_MSG_LEN, "out of memory");
        return USM_EFAILED;
    }
    size_t nc = 0;
    const double a = fmin(r->lo, r->hi), b = fmax(r->lo, r->hi);
    cut[nc++] = a;
    for (size_t i = 0; i < ne; ++i) {
        const usm_sweep_event *e = usm_sweep_event_at(s, i);
        if (e->type == USM_EVENT_CROSSING && e->value > a && e->value < b)
            cut[nc++] = e->value;
    }
    cut[nc++] = b;
    qsort(cut, nc, sizeof *cut, cmp_double);
    double width = 0;
    int above = -1;
    for (size_t c = 0; c + 1 < nc; ++c) {
        int state = -1;
        for (size_t i = 0; i < np && state < 0; ++i) {
            const usm_sweep_point *pt = usm_sweep_point_at(s, i);
            if (pt->value > cut[c] && pt->value < cut[c + 1])
                state = pt->converged && pt->sol.validity == USM_VALID &&
                        -pt->sol.rotor_speed >= opt->band_threshold;
        }
        if (state < 0) /* no grid value inside: the ends' grid values, else flip */
            for (size_t i = 0; i < np && state < 0; ++i) {
                const usm_sweep_point *pt = usm_sweep_point_at(s, i);
                if ((c == 0 && pt->value == cut[0]) || (c + 2 == nc && pt->value == cut[nc - 1]))
                    state = pt->converged && pt->sol.validity == USM_VALID &&
                            -pt->sol.rotor_speed >= opt->band_threshold;
            }
        if (state < 0)
            state = above < 0 ? 0 : !above;
        if (state)
            width += cut[c + 1] - cut[c];
        above = state;
    }
    free(cut);
    usm_sweep_free(s);
    *value = width;
    return USM_OK;
}

/* Output k at the operating point of p. */
static int at_op(const usm_model *m, const usm_params *p, int k, double t0, double *value,
                 char msg[USM_MSG_LEN])
{
    usm_steady *st = usm_steady_alloc(m);
    usm_floquet *fl = usm_floquet_alloc(m);
    usm_floquet_options fo;
    usm_op_options oo;
    usm_point pt;
    int rc = USM_EFAILED;
    usm_floquet_options_default(&fo);
    usm_op_options_default(&oo);
    if (!st || !fl)
        snprintf(msg, USM_MSG_LEN, "out of memory");
    else if (usm_point_evaluate_op(st, fl, m, p, t0, &fo, &oo, &pt) != USM_OK) {
        snprintf(msg, USM_MSG_LEN, "%s", pt.error);
        rc = USM_EINPUT;
    } else if (pt.op.index < 0) {
        snprintf(msg, USM_MSG_LEN, "no operating point: %.200s", pt.op.message);
        rc = USM_ENOSOLUTION;
    } else {
        *value = usm_opt_output_value(k, &pt.op.sol, p, pt.op.floquet.max_modulus);
        rc = isnan(*value) ? USM_ENOSOLUTION : USM_OK;
        if (rc != USM_OK)
            snprintf(msg, USM_MSG_LEN, "%s: not defined here", usm_opt_output_name(k));
    }
    usm_steady_free(st);
    usm_floquet_free(fl);
    return rc;
}

/* Output k over the range (worst, mean or integral along the sweep's grid). */
static int over_range(const usm_model *m, const usm_params *p, int k,
                      const usm_quantity_options *opt, int larger_better, double *value,
                      char msg[USM_MSG_LEN])
{
    const usm_robust_range *r = &opt->range;
    const int fl = k == USM_SENS_MAX_MODULUS || k == USM_OPT_MARGIN;
    usm_sweep *s = sweep(m, p, r->param, r->lo, r->hi, r->points, NULL, fl, opt->t0, msg);
    if (!s)
        return USM_ENOSOLUTION;
    double worst = larger_better ? INFINITY : -INFINITY, integral = 0, prev = NAN, prevx = NAN;
    int rc = USM_OK;
    for (size_t i = 0; i < usm_sweep_count(s); ++i) {
        const usm_sweep_point *pt = usm_sweep_point_at(s, i);
        usm_params q = *p;
        *usm_params_field(&q, &usm_param_table[r->param]) = pt->value;
        const double y = pt->converged && (!fl || pt->has_floquet)
                             ? usm_opt_output_value(k, &pt->sol, &q, fl ? pt->floquet.max_modulus
                                                                        : NAN)
                             : NAN;
        if (isnan(y)) {
            snprintf(msg, USM_MSG_LEN, "over-range: %s not defined at %s = %g (%.120s)",
                     usm_opt_output_name(k), usm_param_table[r->param].name, pt->value,
                     pt->converged ? "no multipliers" : pt->error);
            rc = USM_ENOSOLUTION;
            break;
        }
        worst = larger_better ? fmin(worst, y) : fmax(worst, y);
        if (i > 0)
            integral += 0.5 * (y + prev) * (pt->value - prevx);
        prev = y;
        prevx = pt->value;
    }
    usm_sweep_free(s);
    if (rc != USM_OK)
        return rc;
    if (r->stat == USM_RANGE_WORST)
        *value = worst;
    else if (r->stat == USM_RANGE_INTEGRAL)
        *value = integral;
    else
        *value = integral / (r->hi - r->lo);
    return USM_OK;
}

int usm_robust_quantity_eval(const usm_model *m, const usm_params *p, int k,
                             const usm_quantity_options *opt, int larger_better, double *value,
                             char msg[USM_MSG_LEN])
{
    *value = NAN;
    msg[0] = '\0';
    const usm_robust_range *r = &opt->range;
    if (r->param >= 0 && (r->param >= USM_NPARAMS || !(r->lo != r->hi) || !isfinite(r->lo) ||
                          !isfinite(r->hi) || r->points < 2 || r->points > 100000)) {
        snprintf(msg, USM_MSG_LEN, "over-range: NAME=LO:HI with LO != HI and 2 .. 100000 points");
        return USM_EINPUT;
    }
    switch (k) {
    case USM_ROBUST_STALL_TORQUE:
        return stall_torque(m, p, opt, value, msg);
    case USM_ROBUST_MAX_POWER:
        return max_power(m, p, opt, value, msg);
    case USM_ROBUST_BAND_WIDTH:
        return band_width(m, p, opt, value, msg);
    case USM_ROBUST_NO_LOAD_SPEED: {
        usm_params q = *p;
        *usm_params_field(&q, &usm_param_table[USM_P_T]) = 0;
        return at_op(m, &q, USM_OPT_SPEED, opt->t0, value, msg);
    }
    default:
        break;
    }
    if (k < 0 || k >= USM_OPT_OUTPUT_COUNT) {
        snprintf(msg, USM_MSG_LEN, "quantity: %d unknown", k);
        return USM_EINPUT;
    }
    if (r->param >= 0)
        return over_range(m, p, k, opt, larger_better, value, msg);
    return at_op(m, p, k, opt->t0, value, msg);
}
