/* A periodic steady state: its orbit as CSV, the `usm periodic --json`
 * object (usm_periodic.h) and its table for people (usm_io.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/csv_out.h"
#include "io/json_out.h"
#include "solve/periodic_internal.h"
#include "usm_io.h"

/* The state columns of an orbit file: every state an angle or its rate, but
 * the tilt vector's (a, b), components of the stator's unit axis, and their
 * rates. */
static void state_columns(const usm_model *m, usm_csv_column *cols)
{
    for (int i = 0; i < m->nx; ++i) {
        const char *nm = m->state_names[i];
        const size_t len = strlen(nm);
        const int rate = len > 3 && strcmp(nm + len - 3, "dot") == 0;
        const int unit_vector = m->coordinates == 1 && (i == m->x_a || i == m->x_b ||
                                                        i == m->x_adot || i == m->x_bdot);
        cols[i] = (usm_csv_column){nm, unit_vector ? (rate ? "1/s" : "1") : rate ? "rad/s" : "rad"};
    }
}

int usm_periodic_write_orbit_csv(const usm_periodic *w, FILE *out)
{
    const usm_model *m = usm_periodic_model_of(w);
    const int n = m->nx, ncol = n + 4;
    const double *samples = usm_periodic_samples(w);
    usm_csv_column cols[USM_MAX_NX + 4];
    if (!samples)
        return -1;
    cols[0] = (usm_csv_column){"t", "s"};
    state_columns(m, cols + 1);
    cols[n + 1] = (usm_csv_column){"F_n", "N"};
    cols[n + 2] = (usm_csv_column){"F_t", "N"};
    cols[n + 3] = (usm_csv_column){"rotor_speed", "1/s"};
    usm_csv_header(out, cols, ncol);
    for (int k = 0; k < USM_PERIODIC_SAMPLES; ++k) {
        for (int j = 0; j < ncol; ++j)
            usm_csv_num(out, j == 0, samples[k * ncol + j]);
        fputc('\n', out);
    }
    return ferror(out) ? -1 : 0;
}

int usm_periodic_write_json(const usm_periodic *w, const usm_params *p,
                            const usm_periodic_result *r, FILE *out)
{
    json_t *o = json_object();
    int ok = o != NULL;
    usm_json_put(o, "model", json_string(usm_periodic_model_of(w)->name), &ok);
    usm_json_put(o, "parameters", usm_json_params(p), &ok);
    usm_json_put(o, "converged", json_boolean(r != NULL), &ok);
    if (!r) {
        usm_json_put(o, "error", json_string(usm_periodic_message(w)), &ok);
    } else {
        json_t *orbit = usm_json_periodic_result(r);
        ok = ok && orbit && json_object_update(o, orbit) == 0;
        json_decref(orbit);
        if (usm_periodic_model_of(w)->unilateral) {
            /* a contact that may open, and here never does (docs/unilateral.md) */
            usm_json_put(o, "separation_fraction", usm_json_real(0.0), &ok);
            usm_json_put(o, "impacts_per_period", json_integer(0), &ok);
            usm_json_put(o, "impact_velocity_max", usm_json_real(0.0), &ok);
            usm_json_put(o, "mode_sequence", json_string("c"), &ok);
        }
    }
    return usm_json_write(usm_json_finish(o, ok), out);
}

int usm_hybrid_write_orbit_csv(const usm_model *m, const usm_params *p,
                               const usm_hybrid_result *r, double rtol, int n, FILE *out,
                               char *msg)
{
    const int nx = m->nx, ncol = USM_HYBRID_SAMPLE_COLS(nx);
    if (!(n >= 2 && n <= USM_HYBRID_MAX_SAMPLES)) {
        snprintf(msg, USM_MSG_LEN, "samples: must be 2 to %d", USM_HYBRID_MAX_SAMPLES);
        return USM_EINPUT;
    }
    usm_hybrid *h = usm_hybrid_alloc(m);
    double *rows = malloc(sizeof(double) * (size_t)ncol * (size_t)USM_HYBRID_SAMPLE_ROWS(n));
    int nrows = 0, rc = h && rows ? usm_hybrid_orbit_samples(h, p, r, rtol, n, rows, &nrows)
                                  : USM_EFAILED;
    if (rc != USM_OK)
        snprintf(msg, USM_MSG_LEN, "%s", h && rows ? usm_hybrid_message(h) : "out of memory");
    usm_hybrid_free(h);
    if (rc == USM_OK) {
        usm_csv_column cols[USM_HYBRID_SAMPLE_COLS(USM_MAX_NX)];
        cols[0] = (usm_csv_column){"t", "s"};
        cols[1] = (usm_csv_column){"open", "1"};
        state_columns(m, cols + 2);
        cols[nx + 2] = (usm_csv_column){"gap", "m"};
        cols[nx + 3] = (usm_csv_column){"F_n", "N"};
        cols[nx + 4] = (usm_csv_column){"F_t", "N"};
        cols[nx + 5] = (usm_csv_column){"rotor_speed", "1/s"};
        usm_csv_header(out, cols, ncol);
        for (int k = 0; k < nrows; ++k) {
            for (int j = 0; j < ncol; ++j)
                usm_csv_num(out, j == 0, rows[(size_t)k * (size_t)ncol + (size_t)j]);
            fputc('\n', out);
        }
        if (ferror(out)) {
            snprintf(msg, USM_MSG_LEN, "write error");
            rc = USM_EFAILED;
        }
    }
    free(rows);
    return rc;
}

int usm_hybrid_write_json(const usm_model *m, const usm_params *p, const usm_hybrid_result *r,
                          const char *error, FILE *out)
{
    json_t *o = json_object();
    int ok = o != NULL;
    usm_json_put(o, "model", json_string(m->name), &ok);
    usm_json_put(o, "parameters", usm_json_params(p), &ok);
    usm_json_put(o, "converged", json_boolean(r != NULL), &ok);
    if (!r) {
        usm_json_put(o, "error", json_string(error ? error : ""), &ok);
    } else {
        json_t *orbit = usm_json_hybrid_result(r);
        ok = ok && orbit && json_object_update(o, orbit) == 0;
        json_decref(orbit);
    }
    return usm_json_write(usm_json_finish(o, ok), out);
}

void usm_periodic_write_table(const usm_model *m, const usm_periodic_result *r,
                              const usm_display *d, FILE *out)
{
    const char *us, *ua;
    const double w = usm_display_value(d, "1/s", r->rotor_speed_mean, &us);
    const double th = usm_display_value(d, "rad", r->theta_mean, &ua);
    const int valid = r->validity == USM_VALID;
    fprintf(out, "model %s: periodic orbit (%d Newton iterations, residual %.3g)\n", m->name,
            r->iterations, r->residual);
    /* first, not only in its own line below: every value that follows is of
     * an orbit the model does not describe */
    if (!valid)
        fprintf(out, "  MODEL INVALID on this orbit (%s): the values below are the model's "
                "beyond its validity, not the motor's\n", usm_validity_name(r->validity));
    fprintf(out, "  rotor speed        mean %.10g %s, ripple (peak to peak) %.6g %s\n", w, us,
            usm_display_value(d, "1/s", r->rotor_speed_ripple, NULL), us);
    fprintf(out, "  theta              mean %.10g %s, min %.10g, max %.10g, 2 Omega amplitude "
            "%.6g\n", th, ua, usm_display_value(d, "rad", r->theta_min, NULL),
            usm_display_value(d, "rad", r->theta_max, NULL),
            usm_display_value(d, "rad", r->theta_harmonic_2, NULL));
    fprintf(out, "  F_n                min %.10g N, max %.10g N, 2 Omega amplitude %.6g N\n",
            r->F_n_min, r->F_n_max, r->F_n_harmonic_2);
    if (r->contact_open)
        fprintf(out, "  CONTACT OPENS      %d time%s a period (F_n < 0 on the orbit): the "
                "bilateral-contact model is not valid\n",
                r->openings_per_period, r->openings_per_period == 1 ? "" : "s");
    if (isfinite(r->friction_needed_max))
        fprintf(out, "  friction needed    max |F_t|/F_n %.6g\n", r->friction_needed_max);
    else
        fprintf(out, "  friction needed    undefined (F_n <= 0 on the orbit)\n");
    fprintf(out, "  valid              %s\n",
            valid ? "yes: the model describes the motor on this orbit"
                  : usm_validity_name(r->validity));
    fprintf(out, "  Floquet multipliers (max |lambda| %.10g, %s):\n", r->floquet.max_modulus,
            r->floquet.stable ? "stable" : "UNSTABLE");
    for (int i = 0; i < r->floquet.n; ++i)
        fprintf(out, "    %+.10f %+.10fi%s\n", r->floquet.re[i], r->floquet.im[i],
                r->floquet.cyclic[i] ? "  (cyclic coordinate)" : "");
    usm_squeal sq;
    usm_floquet_squeal(&r->floquet, 1.0 / r->period, &sq);
    if (sq.found)
        fprintf(out, "  squeal frequency   %.8g Hz (%.6f f): the dominant complex pair %.10f "
                "+-%.10fi (|lambda| %.10g)%s%s\n",
                sq.frequency, sq.frequency * r->period, sq.re, sq.im, sq.modulus,
                valid ? "" : "; MODEL INVALID here: ",
                valid ? "" : usm_validity_name(r->validity));
    else
        fprintf(out, "  squeal frequency   none: %s\n", sq.reason);
}

void usm_hybrid_write_table(const usm_model *m, const usm_hybrid_result *r,
                            const usm_display *d, FILE *out)
{
    const char *us;
    const double w = usm_display_value(d, "1/s", r->rotor_speed_mean, &us);
    fprintf(out, "usm periodic: model %s, an orbit with separation (period %.10g s, section at "
            "t = %.10g s)\n", m->name, r->period, r->t0);
    fprintf(out, "  converged in %d Newton iterations, residual %.3g\n", r->iterations,
            r->residual);
    fprintf(out, "  rotor speed mean      %.10g %s\n", w, us);
    fprintf(out, "  rotor speed ripple    %.6g %s (peak to peak)\n",
            usm_display_value(d, "1/s", r->rotor_speed_ripple, NULL), us);
    fprintf(out, "  mode sequence         %s (c closed, o open; from the section)\n",
            r->mode_sequence);
    fprintf(out, "  separation fraction   %.6f of the period\n", r->separation_fraction);
    fprintf(out, "  per period            %d separations, %d impacts (%d needing more than "
            "mu0)\n", r->separations_per_period, r->impacts_per_period, r->impacts_slipping);
    fprintf(out, "  impact velocity max   %.6g m/s\n", r->impact_velocity_max);
    fprintf(out, "  valid                 %s\n",
            r->validity == USM_VALID
                ? "yes: the model (contact that may open) describes the motor on this orbit"
                : r->validity == USM_INVALID_STICK
                    ? "no: stick_not_admissible (an impact needs more friction than mu0: the "
                      "stick model does not describe it)"
                    : usm_validity_name(r->validity));
    fprintf(out, "  Floquet multipliers (with saltation matrices; max |lambda| %.10g, %s):\n",
            r->floquet.max_modulus, r->floquet.stable ? "stable" : "UNSTABLE");
    for (int i = 0; i < r->floquet.n; ++i)
        fprintf(out, "    %+.10f %+.10fi%s\n", r->floquet.re[i], r->floquet.im[i],
                r->floquet.cyclic[i] ? "  (cyclic coordinate)" : "");
}
