/* The report's section "Design under scatter": on the paper's
 * 3-DOF motor, the Pareto front of speed against efficiency over the drive
 * frequency f and the preload F0 (usm_pareto_run), and the most efficient
 * design with speed >= REPORT_DESIGN_SPEED nominally (usm_optimize) beside
 * the one whose yield under 2 % tilt-stiffness and 1 % frequency scatter is
 * at least 99 % (usm_robust_run).  Kept cheap: fewer samples than the
 * command's defaults (the text says how many). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "report_internal.h"
#include "usm_robust.h"

#define REPORT_DESIGN_POINTS 12      /* front points */
#define REPORT_DESIGN_SPEED 6.0      /* the speed spec [1/s] */
#define REPORT_DESIGN_YIELD 0.99
#define REPORT_DESIGN_SAMPLES 2000   /* CRN samples per design (command: 10^4) */
#define REPORT_DESIGN_VERIFY 10000   /* fresh samples (command: 10^5) */
#define REPORT_DESIGN_EVALS 30       /* designs per COBYLA run (command: 40) */
/* --quick: the front at 6 points, no robust search (about 2 s of CPU, five
 * times the rest of a quick report; the section says so) */
#define QUICK_POINTS 6
static const double F_LO = 34000, F_HI = 42000, P_LO = 0.2, P_HI = 1.0;

typedef struct usm_report_design {
    int ok;
    int points, samples, verify, evals; /* what was used */
    char note[USM_MSG_LEN];
    usm_pareto_result front;
    int front_ok;
    usm_robust_result robust;
    int robust_ok;
    double seconds;
} usm_report_design;

int usm_report_compute_design(usm_report_data *d, char msg[USM_IO_MSG_LEN])
{
    const double t = usm_report_now();
    const usm_model *m = usm_model_find("3dof");
    usm_report_design *g = calloc(1, sizeof *g);
    char why[USM_MSG_LEN];
    if (!g) {
        usm_io_msg(msg, "out of memory");
        return USM_EFAILED;
    }
    d->design = g;
    const int quick = d->opt.quick;
    g->points = quick ? QUICK_POINTS : REPORT_DESIGN_POINTS;
    g->samples = REPORT_DESIGN_SAMPLES;
    g->verify = REPORT_DESIGN_VERIFY;
    g->evals = REPORT_DESIGN_EVALS;
    usm_opt_problem pb;
    usm_opt_problem_init(&pb);
    /* the section's problem is fixed text, but a renamed parameter or output
     * must not leave it silently smaller: a failure ends the section with the
     * library's message */
    if (usm_opt_problem_add_vary(&pb, "f", F_LO, F_HI, why) != USM_OK ||
        usm_opt_problem_add_vary(&pb, "F0", P_LO, P_HI, why) != USM_OK) {
        snprintf(g->note, sizeof g->note, "the design problem: %.200s", why);
        g->seconds = usm_report_now() - t;
        return USM_OK;
    }
    /* fewer starts than the command's 8: the front's ends and the nominal
     * optimum are the same to 1e-5 with them (measured), at a quarter of the cost */
    pb.starts = quick ? 2 : 4;
    const int obj[2] = {USM_OPT_SPEED, USM_SENS_EFFICIENCY}, mn[2] = {0, 0};
    int rc = usm_pareto_run(m, &d->params, &pb, obj, mn, g->points, &g->front, why);
    g->front_ok = rc == USM_OK;
    if (!g->front_ok)
        snprintf(g->note, sizeof g->note, "front: %.200s", why);
    usm_robust_problem rp;
    usm_robust_problem_init(&rp);
    rp.nominal = pb;
    rp.nominal.starts = quick ? 1 : 2;
    rp.objective = USM_SENS_EFFICIENCY;
    rp.yield_min = REPORT_DESIGN_YIELD;
    const int set = usm_opt_problem_add_constraint(&rp.nominal, "speed", 0, REPORT_DESIGN_SPEED,
                                                   why) == USM_OK &&
                    usm_tolerance_vary_parse("c_r=normal:2%", &rp.scatter[0], why) == USM_OK &&
                    usm_tolerance_vary_parse("f=normal:1%", &rp.scatter[1], why) == USM_OK;
    if (!set && !quick) {
        snprintf(g->note, sizeof g->note, "the robust problem: %.200s", why);
        g->seconds = usm_report_now() - t;
        return USM_OK;
    }
    rp.nscatter = 2;
    rp.samples = (uint64_t)g->samples;
    rp.verify_samples = (uint64_t)g->verify;
    rp.max_evals = g->evals;
    rp.threads = d->opt.threads;
    if (!quick) {
        rc = usm_robust_run(m, &d->params, &rp, &g->robust, why);
        g->robust_ok = rc == USM_OK && g->robust.nominal.feasible;
        if (!g->robust_ok && !g->note[0])
            snprintf(g->note, sizeof g->note, "robust optimum: %.200s",
                     why[0] ? why : "no nominal optimum");
    }
    g->ok = g->front_ok && (quick || g->robust_ok);
    g->seconds = usm_report_now() - t;
    return USM_OK;
}

void usm_report_design_free(usm_report_data *d)
{
    if (!d->design)
        return;
    usm_pareto_result_free(&d->design->front);
    free(d->design);
    d->design = NULL;
}

double usm_report_design_seconds(const usm_report_data *d)
{
    return d->design ? d->design->seconds : NAN;
}

static void num(json_t *o, const char *key, double v)
{
    json_object_set_new(o, key, isfinite(v) ? json_real(v) : json_null());
}

static json_t *design_json(const usm_robust_design *r)
{
    json_t *o = json_object();
    if (!o)
        return NULL;
    num(o, "efficiency", r->efficiency);
    num(o, "efficiency_percent", 100 * r->efficiency);
    num(o, "speed", r->speed);
    num(o, "f", r->params.f);
    num(o, "F0", r->params.F0);
    num(o, "max_modulus", r->max_modulus);
    num(o, "power_out_mW", 1e3 * r->power_out);
    num(o, "yield_percent", 100 * r->yield);
    num(o, "yield_lo_percent", 100 * r->yield_lo);
    num(o, "yield_hi_percent", 100 * r->yield_hi);
    num(o, "crn_yield_percent", 100 * r->crn_yield);
    return o;
}

json_t *usm_report_design_json(const usm_report_data *d)
{
    const usm_report_design *g = d->design;
    json_t *o = json_object(), *front = json_array();
    if (!o || !front) {
        json_decref(o);
        json_decref(front);
        return NULL;
    }
    json_object_set_new(o, "ok", json_boolean(g && g->ok));
    json_object_set_new(o, "robust_ok", json_boolean(g && g->robust_ok));
    json_object_set_new(o, "note", json_string(g ? g->note : "not computed"));
    num(o, "speed_spec", REPORT_DESIGN_SPEED);
    num(o, "yield_min_percent", 100 * REPORT_DESIGN_YIELD);
    json_object_set_new(o, "samples", json_integer(g ? g->samples : 0));
    json_object_set_new(o, "verify_samples", json_integer(g ? g->verify : 0));
    json_object_set_new(o, "max_evals", json_integer(g ? g->evals : 0));
    num(o, "f_lo", F_LO);
    num(o, "f_hi", F_HI);
    num(o, "F0_lo", P_LO);
    num(o, "F0_hi", P_HI);
    num(o, "seconds", g ? g->seconds : NAN);
    if (g && g->front_ok)
        for (int i = 0; i < g->front.npoints; ++i) {
            const usm_pareto_point *pt = &g->front.points[i];
            json_t *p = json_object();
            if (!p)
                break;
            num(p, "speed", pt->f[0]);
            num(p, "efficiency_percent", 100 * pt->f[1]);
            num(p, "f", pt->params.f);
            num(p, "F0", pt->params.F0);
            json_object_set_new(p, "active", json_string(pt->nactive ? pt->active[0] : "none"));
            json_array_append_new(front, p);
        }
    json_object_set_new(o, "front", front);
    json_object_set_new(o, "front_points", json_integer((json_int_t)json_array_size(front)));
    if (g && g->robust_ok) {
        const usm_robust_design *r = &g->robust.robust, *n = &g->robust.nominal;
        json_object_set_new(o, "robust", design_json(r));
        json_object_set_new(o, "nominal", design_json(n));
        json_object_set_new(o, "verified", json_boolean(g->robust.verified));
        num(o, "yield_gain_points", 100 * (r->yield - n->yield));
        num(o, "efficiency_cost_percent",
            n->efficiency > 0 ? 100 * (1 - r->efficiency / n->efficiency) : NAN);
        num(o, "speed_margin", r->speed - REPORT_DESIGN_SPEED);
    }
    return o;
}
