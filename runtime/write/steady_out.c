/* Output of a stationary solution and its Floquet multipliers. */
#include "steady_out.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "io/json_out.h"

/* The root the top level describes: the operating point when there is one
 * (and every root's multipliers are known), else root 0. */
static size_t top_root(const usm_steady_report *r)
{
    if (r->op && r->op->index > 0 && r->roots_floquet &&
        (size_t)r->op->index < usm_steady_count(r->steady))
        return (size_t)r->op->index;
    return 0;
}

/* operating_point, operating_point_reason, starts_from_rest, and what the
 * simulation from rest showed */
static void put_operating_point(json_t *obj, const usm_op_result *op, int *ok)
{
    usm_json_put(obj, "operating_point", op->index >= 0 ? json_integer(op->index) : json_null(),
                 ok);
    usm_json_put(obj, "operating_point_reason",
                 op->reason == USM_OP_UNDECIDED ? json_null()
                                                : json_string(usm_op_reason_name(op->reason)),
                 ok);
    usm_json_put(obj, "operating_point_message", json_string(op->message), ok);
    usm_json_put(obj, "starts_from_rest",
                 op->starts_from_rest < 0 ? json_null() : json_boolean(op->starts_from_rest), ok);
    usm_json_put(obj, "start_margin",
                 isfinite(op->start_margin) ? usm_json_real(op->start_margin) : json_null(), ok);
    usm_json_put(obj, "operating_point_ambiguous", json_boolean(op->ambiguous), ok);
    if (op->simulated) {
        const usm_sim_summary *s = &op->sim;
        json_t *fr = json_object();
        int fok = fr != NULL;
        usm_json_put(fr, "duration", usm_json_real(s->t1 - s->t0), &fok);
        usm_json_put(fr, "t_reached", usm_json_real(s->t_reached), &fok);
        usm_json_put(fr, "stop", json_string(usm_sim_stop_name(s->stop)), &fok);
        usm_json_put(fr, "steps", json_integer(s->steps), &fok);
        usm_json_put(fr, "settled_on",
                     s->settled_on >= 0 ? json_integer(s->settled_on)
                     : s->settled_on == USM_SIM_SETTLED_REST ? json_string("rest")
                                                             : json_null(),
                     &fok);
        usm_json_put(fr, "theta_avg_end", usm_json_real(s->theta_avg_end), &fok);
        usm_json_put(fr, "rotor_speed_avg_end", usm_json_real(s->rotor_speed_avg_end), &fok);
        usm_json_put(fr, "wall_time", usm_json_real(op->wall), &fok);
        usm_json_put(fr, "periods", json_integer(s->periods), &fok);
        usm_json_put(fr, "tilt_start", usm_json_real(s->tilt_start), &fok);
        usm_json_put(fr, "start", json_string(s->start_message), &fok);
        usm_json_put(fr, "model", json_string(op->sim_model ? op->sim_model->name : ""), &fok);
        usm_json_put(fr, "reason", json_string(s->reason), &fok);
        if (!fok) {
            json_decref(fr);
            fr = NULL;
        }
        usm_json_put(obj, "from_rest", fr, ok);
    }
}

json_t *usm_steady_json(const usm_steady_report *r)
{
    json_t *obj = json_object();
    json_t *roots = json_array();
    int ok = obj && roots;
    size_t n = r->error ? 0 : usm_steady_count(r->steady);

    usm_json_put(obj, "model", json_string(r->model->name), &ok);
    usm_json_put(obj, "parameters", usm_json_params(r->params), &ok);
    usm_json_put(obj, "converged", json_boolean(r->error == NULL), &ok);
    if (r->error)
        usm_json_put(obj, "error", json_string(r->error), &ok);
    else {
        /* The operating point's (else the primary root's) values at top
         * level, so that the common case needs no indexing. */
        json_t *primary = usm_json_root(usm_steady_root(r->steady, top_root(r)));
        if (!primary || json_object_update(obj, primary) != 0)
            ok = 0;
        json_decref(primary);
    }
    for (size_t k = 0; k < n; ++k) {
        json_t *root = usm_json_root(usm_steady_root(r->steady, k));
        /* each root's own multipliers, the keys of the top-level "floquet" */
        if (root && r->roots_floquet) {
            usm_json_put(root, "floquet", usm_json_floquet(&r->roots_floquet[k]), &ok);
            usm_json_put_squeal(root, &r->roots_floquet[k], r->params->f, &ok);
        }
        if (json_array_append_new(roots, root) != 0)
            ok = 0;
    }
    usm_json_put(obj, "roots", roots, &ok);
    if (r->floquet) {
        const usm_floquet_result *fl =
            top_root(r) > 0 ? &r->roots_floquet[top_root(r)] : r->floquet;
        usm_json_put(obj, "floquet", usm_json_floquet(fl), &ok);
        usm_json_put_squeal(obj, fl, r->params->f, &ok);
    }
    if (r->op && !r->error)
        put_operating_point(obj, r->op, &ok);
    return usm_json_finish(obj, ok);
}

/* d: the display units of the table (NULL: SI) */
static void row_in(FILE *out, const usm_display *d, const char *name, double v, const char *si,
                   const char *what)
{
    const char *unit;
    v = usm_display_value(d, si, v, &unit);
    fprintf(out, "  %-17s %-24.10g %-7s %s\n", name, v, unit, what);
}
#define row(out, name, v, unit, what) row_in(out, d, name, v, unit, what)

static void solution(FILE *out, const usm_display *d, const usm_steady_solution *s)
{
    row(out, "theta", s->theta, "rad", "stator tilt");
    row(out, "alpha", s->alpha, "rad", "phase of phi behind the excitation, in [0, 2 pi)");
    row(out, "beta", s->beta, "rad", "phase of psi");
    row(out, "rotor_speed", s->rotor_speed, "1/s", "phidot_R (negative when driving)");
    row(out, "F_n", s->F_n, "N", "normal contact force");
    row(out, "F_t", s->F_t, "N", "tangential contact force");
    row(out, "mu_used", s->mu_used, "1", "F_t / F_n");
    row(out, "v_c", s->v_c, "m/s", "speed of the stator's contact point");
    row(out, "v_rel", s->v_rel, "m/s", "slip velocity");
    row(out, "R_star", s->R_star, "m", "contact radius");
    row(out, "Z", s->Z, "m", "contact height");
    fprintf(out, "  %-17s %-24s %-7s F_t <= %.6g F_n\n", "stick_admissible",
            s->stick_admissible ? "yes" : "no", "", s->mu_stick);
    fprintf(out, "  %-17s %-24s %-7s %s\n", "valid", s->validity == USM_VALID ? "yes" : "no", "",
            s->validity == USM_VALID ? "the model describes the motor here"
                                     : usm_validity_name(s->validity));
    row(out, "residual_norm", s->residual_norm, "N m", "max |r_i| of eq. (3.5)");
    row(out, "power_in", s->power_in, "W", "excitation torque x stator angular velocity");
    row(out, "power_out", s->power_out, "W", "load torque x rotor speed (driving: > 0)");
    row(out, "power_damping", s->power_damping, "W", "dissipated by d_r, d_t, d_R");
    row(out, "power_slip", s->power_slip, "W", "F_t v_rel, lost in the contact");
    if (isfinite(s->efficiency))
        row(out, "efficiency", s->efficiency, "1", "power_out / power_in");
    else
        fprintf(out, "  %-17s %-24s %-7s %s\n", "efficiency", "undefined", "1",
                "power_in <= 0: no power taken in");
}

/* validity: of the root the multipliers belong to; a squeal frequency of a
 * root the model does not describe is a prediction only with this flag */
static void multipliers(FILE *out, const usm_floquet_result *f, double freq,
                        usm_validity validity)
{
    usm_squeal sq;
    fprintf(out, "\nFloquet multipliers over [t0, t0 + 2 pi / Omega], t0 = %.10g s\n", f->t0);
    fprintf(out, "  %3s %-24s %-24s %-18s\n", "#", "re", "im", "|lambda|");
    for (int k = 0; k < f->n; ++k)
        fprintf(out, "  %3d %-24.15g %-24.15g %-18.10g%s\n", k + 1, f->re[k], f->im[k],
                hypot(f->re[k], f->im[k]), f->cyclic[k] ? " cyclic coordinate" : "");
    fprintf(out, "  max |lambda| (non-cyclic) = %.10g: %s\n", f->max_modulus,
            f->stable ? "stable" : "unstable");
    usm_floquet_squeal(f, freq, &sq);
    if (sq.found)
        fprintf(out, "  squeal frequency = %.8g Hz (%.6f f): the dominant complex pair %.10g "
                     "+-%.10gi (|lambda| %.10g)%s%s\n",
                sq.frequency, sq.frequency / freq, sq.re, sq.im, sq.modulus,
                validity == USM_VALID ? "" : "; MODEL INVALID here: ",
                validity == USM_VALID ? "" : usm_validity_name(validity));
    else
        fprintf(out, "  squeal frequency: none (%s)\n", sq.reason);
    if (f->t0_dependent)
        fprintf(out, "  note: under the paper's twist law the linearisation is not periodic and\n"
                     "  the multipliers depend on t0 (Table 3 uses t0 = 0); --variant\n"
                     "  twist_integrated removes the dependence\n");
}

/* One line per root; with every root's multipliers (fl, or NULL) also its
 * largest modulus and stability, for every count of roots. */
static void other_roots(FILE *out, const usm_display *d, const usm_steady *s,
                        const usm_floquet_result *fl)
{
    const char *ua, *us, *uf;
    char ctheta[32], calpha[32], cspeed[32], cforce[32];
    usm_display_value(d, "rad", 0, &ua);
    usm_display_value(d, "1/s", 0, &us);
    usm_display_value(d, "N", 0, &uf);
    snprintf(ctheta, sizeof ctheta, "theta [%s]", ua);
    snprintf(calpha, sizeof calpha, "alpha [%s]", ua);
    snprintf(cspeed, sizeof cspeed, "rotor_speed [%s]", us);
    snprintf(cforce, sizeof cforce, "F_n [%s]", uf);
    size_t n = usm_steady_count(s);
    if (n < 2 && !fl)
        return;
    if (fl)
        fprintf(out, n == 1 ? "\nthe stationary solution and its stability\n"
                            : "\nall %zu stationary solutions, each with its own stability\n",
                n);
    else
        fprintf(out, "\nall %zu stationary solutions (Floquet multipliers above are of #1)\n", n);
    fprintf(out, "  %3s %-18s %-18s %-18s %-18s %-5s", "#", ctheta, calpha, cspeed,
            cforce, "stick");
    if (fl)
        fprintf(out, " %-14s %s", "max |lambda|", "stability");
    fputc('\n', out);
    for (size_t k = 0; k < n; ++k) {
        const usm_steady_solution *r = usm_steady_root(s, k);
        fprintf(out, "  %3zu %-18.10g %-18.10g %-18.10g %-18.10g %-5s", k + 1,
                usm_display_value(d, "rad", r->theta, NULL),
                usm_display_value(d, "rad", r->alpha, NULL),
                usm_display_value(d, "1/s", r->rotor_speed, NULL),
                usm_display_value(d, "N", r->F_n, NULL), r->stick_admissible ? "yes" : "no");
        if (fl)
            fprintf(out, " %-14.10g %s", fl[k].max_modulus, fl[k].stable ? "stable" : "unstable");
        fputc('\n', out);
    }
}

/* A person should see the 0.005 they typed, not 0.0050000000000000001,
 * without losing any bits.  At least 6 digits, so that 4000 does not print as
 * 4e+03. */
static void parameters(FILE *out, const usm_display *d, const usm_params *p)
{
    char buf[32];
    usm_params def;
    usm_params_default(&def);
    int width = 0; /* the longest name (amp_imbalance): the columns stay aligned */
    for (int k = 0; k < USM_NPARAMS; ++k)
        if ((int)strlen(usm_param_table[k].name) > width)
            width = (int)strlen(usm_param_table[k].name);
    fprintf(out, "\nparameters (* differs from the default)\n");
    for (int k = 0; k < USM_NPARAMS; ++k) {
        const usm_param_info *info = &usm_param_table[k];
        const double v = usm_params_get(p, info);
        const char *unit;
        const double shown = usm_display_value(d, info->unit, v, &unit);
        fprintf(out, "  %-*s %c %-24s %-10s %s\n", width, info->name,
                v != usm_params_get(&def, info) ? '*' : ' ', usm_shortest(buf, shown), unit,
                info->description);
    }
}

/* The operating point in words: first, since it is the answer. */
static void operating_point(FILE *out, const usm_op_result *op, size_t n)
{
    fprintf(out, "\noperating point      ");
    if (op->index >= 0)
        fprintf(out, "root #%d of %zu (%s)\n", op->index + 1, n, usm_op_reason_name(op->reason));
    else
        fprintf(out, "none (%s)\n", usm_op_reason_name(op->reason));
    fprintf(out, "  %s\n", op->message);
    if (isfinite(op->start_margin))
        fprintf(out, "  start margin:      %.6g (m0 over the excitation that keeps the stator at "
                     "theta = 0, minus 1: %s)\n",
                op->start_margin,
                op->start_margin > 0 ? "the excitation overcomes the preload's moment at rest"
                                     : "the preload's moment holds the stator at rest");
    fprintf(out, "  starts from rest:  %s\n",
            op->starts_from_rest > 0    ? "yes"
            : op->starts_from_rest == 0 ? "no: the wobble decays"
            : op->simulated             ? "not decided by the simulation"
            : op->ambiguous             ? "not simulated (--no-from-rest)"
            : op->reason == USM_OP_NO_STABLE_ROOT ? "not simulated: no stable root to reach"
                                        : "not simulated: not needed (one stable root, and the "
                                          "excitation overcomes the preload at rest)");
    if (op->simulated) {
        fprintf(out, "  start:             %s%s%s\n", op->sim.start_message,
                op->sim_model ? ", simulated as " : "", op->sim_model ? op->sim_model->name : "");
        fprintf(out, "  from rest:         %ld steps, %ld periods to t = %.6g s (stop: %s), %.3g s\n",
                op->sim.steps, op->sim.periods, op->sim.t_reached,
                usm_sim_stop_name(op->sim.stop), op->wall);
        if (op->sim.settled_on < 0 && op->sim.settled_on != USM_SIM_SETTLED_REST &&
            op->sim.reason[0] && !strstr(op->message, op->sim.reason))
            fprintf(out, "  why:               %s\n", op->sim.reason);
    }
}

void usm_steady_table(const usm_steady_report *r, FILE *out)
{
    usm_steady_table_in(r, NULL, out);
}

void usm_steady_table_in(const usm_steady_report *r, const usm_display *d, FILE *out)
{
    const size_t top = top_root(r), n = usm_steady_count(r->steady);
    const int is_op = r->op && r->op->index >= 0 && (size_t)r->op->index == top;
    fprintf(out, "model %s: %s\n", r->model->name, r->model->description);
    if (r->op)
        operating_point(out, r->op, n);
    if (is_op)
        fprintf(out, "\nstationary solution #%zu of %zu: the operating point\n", top + 1, n);
    else
        fprintf(out, "\nstationary solution #%zu of %zu (smallest tilt%s)\n", top + 1, n,
                !r->roots_floquet          ? ""
                : !r->roots_floquet[top].stable ? "; unstable: not an operating point"
                : r->op                    ? "; not the operating point"
                                           : "");
    solution(out, d, usm_steady_root(r->steady, top));
    if (r->floquet)
        multipliers(out, top > 0 ? &r->roots_floquet[top] : r->floquet, r->params->f,
                    usm_steady_root(r->steady, top)->validity);
    other_roots(out, d, r->steady, r->roots_floquet);
    parameters(out, d, r->params);
}

int usm_steady_write_json(const usm_steady_report *r, FILE *out)
{
    return usm_json_write(usm_steady_json(r), out);
}
