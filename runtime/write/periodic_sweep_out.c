/* The periodic sweep's points and events as CSV and JSON
 * (usm_periodic_sweep.h). */
#include <stdio.h>

#include "io/csv_out.h"
#include "io/json_out.h"
#include "study/periodic_sweep_internal.h"

int usm_periodic_sweep_csv(const usm_periodic_sweep *s, FILE *out)
{
    const char *over = usm_periodic_sweep_over(s);
    const usm_model *m = usm_periodic_sweep_model(s);
    fprintf(out, "%s [%s],converged,rotor_speed_mean [1/s],rotor_speed_ripple [1/s],F_n_min [N],"
                 "F_n_max [N],friction_needed_max [1],theta_mean [rad],theta_min [rad],"
                 "theta_max [rad],theta_harmonic_2 [rad],F_n_harmonic_2 [N],max_modulus [1],"
                 "stable,contact_open,error,valid,invalid_reason%s\n",
            over, usm_periodic_sweep_unit(s),
            m->unilateral ? ",separating,separation_fraction [1],impacts_per_period,"
                            "impact_velocity_max [m/s],mode_sequence" : "");
    for (size_t i = 0; i < usm_periodic_sweep_count(s); ++i) {
        const usm_periodic_point *pt = usm_periodic_sweep_point_at(s, i);
        const usm_periodic_result *r = &pt->orbit;
        char buf[32];
        fputs(usm_shortest(buf, pt->value), out);
        if (pt->separating) {
            /* the orbit with separation: its speed, multipliers and contact */
            const usm_hybrid_result *h = &pt->hybrid;
            const int valid = h->validity == USM_VALID;
            usm_csv_bool(out, 0, 1);
            usm_csv_num(out, 0, h->rotor_speed_mean);
            usm_csv_num(out, 0, h->rotor_speed_ripple);
            fputs(",,,,,,,,", out); /* F_n_min to F_n_harmonic_2: the bilateral orbit's */
            usm_csv_num(out, 0, h->floquet.max_modulus);
            usm_csv_bool(out, 0, h->floquet.stable);
            usm_csv_bool(out, 0, 1);
            fputc(',', out);
            usm_csv_validity(out, 1, valid ? USM_VALID : USM_INVALID_STICK);
            usm_csv_bool(out, 0, 1);
            usm_csv_num(out, 0, h->separation_fraction);
            fprintf(out, ",%d", h->impacts_per_period);
            usm_csv_num(out, 0, h->impact_velocity_max);
            usm_csv_text(out, 0, h->mode_sequence);
            fputc('\n', out);
            continue;
        }
        usm_csv_bool(out, 0, pt->converged);
        if (!pt->converged) {
            fputs(",,,,,,,,,,,,,,", out);
            usm_csv_text(out, 0, pt->error);
            usm_csv_validity(out, 0, USM_VALID);
            if (m->unilateral)
                fputs(",false,,,,", out);
            fputc('\n', out);
            continue;
        }
        const double v[] = {r->rotor_speed_mean, r->rotor_speed_ripple, r->F_n_min, r->F_n_max,
                            r->friction_needed_max, r->theta_mean, r->theta_min, r->theta_max,
                            r->theta_harmonic_2, r->F_n_harmonic_2, r->floquet.max_modulus};
        for (size_t k = 0; k < sizeof v / sizeof v[0]; ++k)
            usm_csv_num(out, 0, v[k]);
        usm_csv_bool(out, 0, r->floquet.stable);
        usm_csv_bool(out, 0, r->contact_open);
        fputc(',', out);
        usm_csv_validity(out, 1, r->validity);
        if (m->unilateral) /* the contact does not open here, or no orbit with separation */
            fputs(r->contact_open ? ",false,,,," : ",false,0,0,0,c", out);
        fputc('\n', out);
    }
    for (size_t i = 0; i < usm_periodic_sweep_event_count(s); ++i) {
        const usm_periodic_event *e = usm_periodic_sweep_event_at(s, i);
        char buf[32];
        fprintf(out, "# %s%s%s%s at %s = %s: %s\n", usm_pevent_name(e->type),
                e->kind ? " (" : "", usm_crossing_name(e->kind), e->kind ? ")" : "", over,
                usm_shortest(buf, e->value), e->what);
    }
    return ferror(out) ? -1 : 0;
}

static json_t *sweep_json(const usm_periodic_sweep *s, const usm_params *p)
{
    const char *over = usm_periodic_sweep_over(s);
    json_t *obj = json_object(), *points = json_array(), *events = json_array();
    int ok = obj && points && events;
    usm_json_put(obj, "over", json_string(over), &ok);
    usm_json_put(obj, "model", json_string(usm_periodic_sweep_model(s)->name), &ok);
    usm_json_put(obj, "periodic", json_true(), &ok);
    usm_json_put(obj, "parameters", usm_json_params(p), &ok);
    for (size_t i = 0; ok && i < usm_periodic_sweep_count(s); ++i) {
        const usm_periodic_point *pt = usm_periodic_sweep_point_at(s, i);
        const usm_model *m = usm_periodic_sweep_model(s);
        /* a unilateral model's point past contact loss: the orbit with separation */
        json_t *o = pt->separating ? usm_json_hybrid_result(&pt->hybrid)
                    : pt->converged ? usm_json_periodic_result(&pt->orbit)
                                    : json_object();
        int pok = o != NULL;
        if (m->unilateral)
            usm_json_put(o, "separating", json_boolean(pt->separating), &pok);
        if (m->unilateral && pt->converged && !pt->separating && !pt->orbit.contact_open) {
            /* as usm periodic says of an orbit that never opens */
            usm_json_put(o, "separation_fraction", usm_json_real(0.0), &pok);
            usm_json_put(o, "impacts_per_period", json_integer(0), &pok);
            usm_json_put(o, "impact_velocity_max", usm_json_real(0.0), &pok);
            usm_json_put(o, "mode_sequence", json_string("c"), &pok);
        }
        usm_json_put(o, over, usm_json_real(pt->value), &pok);
        usm_json_put(o, "converged", json_boolean(pt->converged || pt->separating), &pok);
        if (!pt->converged && !pt->separating)
            usm_json_put(o, "error", json_string(pt->error), &pok);
        else if (!pt->separating && pt->error[0]) /* why no orbit with separation */
            usm_json_put(o, "separation_error", json_string(pt->error), &pok);
        if (!pok || json_array_append_new(points, o) != 0)
            ok = 0;
    }
    for (size_t i = 0; ok && i < usm_periodic_sweep_event_count(s); ++i) {
        const usm_periodic_event *e = usm_periodic_sweep_event_at(s, i);
        json_t *o = json_object();
        int eok = o != NULL;
        usm_json_put(o, "type", json_string(usm_pevent_name(e->type)), &eok);
        if (e->kind) {
            usm_json_put(o, "kind", json_string(usm_crossing_name(e->kind)), &eok);
            json_t *mu = json_pack("[ff]", e->multiplier_re, e->multiplier_im);
            usm_json_put(o, "multiplier", mu, &eok);
            if (e->kind == USM_CROSSING_NEIMARK_SACKER)
                usm_json_put(o, "squeal_frequency", usm_json_real(e->squeal_frequency), &eok);
        }
        usm_json_put(o, over, usm_json_real(e->value), &eok);
        usm_json_put(o, "what", json_string(e->what), &eok);
        /* beside squeal_frequency and the multiplier, not only inside "orbit":
         * a value of an orbit the model does not describe carries its flag */
        if ((e->has_orbit || e->has_hybrid) && e->type != USM_PEVENT_CONTACT_LOSS &&
            e->type != USM_PEVENT_STICK_LOSS && e->type != USM_PEVENT_CONTACT_REGAINED) {
            /* (not at a limit of validity itself: there the orbit is on either side
             * by rounding, as psweep_event_add says) */
            const usm_validity v = e->has_hybrid ? e->hybrid.validity : e->orbit.validity;
            usm_json_put(o, "valid", json_boolean(v == USM_VALID), &eok);
            usm_json_put(o, "invalid_reason",
                         v == USM_VALID ? json_null() : json_string(usm_validity_name(v)), &eok);
        }
        if (e->has_orbit)
            usm_json_put(o, "orbit", usm_json_periodic_result(&e->orbit), &eok);
        /* branch_switch: the orbit followed, the one left; stability_change
         * of an orbit with separation: the located orbit */
        if (e->has_hybrid)
            usm_json_put(o, "orbit", usm_json_hybrid_result(&e->hybrid), &eok);
        if (e->has_hybrid && e->type == USM_PEVENT_BRANCH_SWITCH) {
            usm_json_put(o, "branch_lost", json_boolean(e->branch_lost), &eok);
            if (e->branch_lost) { /* the branch's last orbit, and where */
                usm_json_put(o, "last_orbit", usm_json_hybrid_result(&e->hybrid_left), &eok);
                usm_json_put(o, "last_value", usm_json_real(e->branch_last), &eok);
                /* located on the branch (null where it could not be) */
                usm_json_put(o, "branch_end", usm_json_real(e->branch_end), &eok);
                usm_json_put(o, "branch_end_how",
                             json_string(usm_branch_end_how_name(e->branch_end_how)), &eok);
            } else {
                usm_json_put(o, "unstable_orbit", usm_json_hybrid_result(&e->hybrid_left),
                             &eok);
                usm_json_put(o, "unstable_from", usm_json_real(e->unstable_from), &eok);
            }
        }
        if (!eok || json_array_append_new(events, o) != 0)
            ok = 0;
    }
    usm_json_put(obj, "points", points, &ok);
    usm_json_put(obj, "events", events, &ok);
    return usm_json_finish(obj, ok);
}

int usm_periodic_sweep_write_json(const usm_periodic_sweep *s, const usm_params *p, FILE *out)
{
    return usm_json_write(sweep_json(s, p), out);
}
