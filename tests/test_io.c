/* test_io: the library's readers and writers (usm_io.h) give back exactly
 * what was computed.
 *
 * Truth: the values in memory that were written.
 *  - usm_steady_write_json: every root's theta, alpha, rotor_speed, F_n and
 *    the Floquet multipliers read back bit for bit (17 digits);
 *  - usm_sim_csv_row + usm_sim_read_start: a run's time history read back
 *    gives its last sample's state and rotor angle bit for bit, so a run
 *    continued from the file starts where the first one stopped; likewise the
 *    JSON summary's final_state (usm_sim_write_json) against
 *    usm_sim_summary.final_x;
 *  - usm_params_read_file: the values of a file; a malformed file is
 *    USM_EINPUT naming PATH:LINE:COLUMN and leaves the parameters unchanged.
 */
#define _POSIX_C_SOURCE 200809L /* mkstemp, fdopen */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>
#include <jansson.h>

#include "check.h"
#include "usm.h"
#include "usm_io.h"
#include "usm_simulate.h"

typedef struct last_sample {
    FILE *csv;
    int nx;
    double x[USM_MAX_NX], rotor_angle, t;
} last_sample;

static int on_sample(const usm_sim_sample *s, void *data)
{
    last_sample *l = data;
    l->nx = s->nx;
    memcpy(l->x, s->x, sizeof(double) * (size_t)s->nx);
    l->rotor_angle = s->rotor_angle;
    l->t = s->t;
    return usm_sim_csv_row(s, l->csv) != 0;
}

static void steady_json(void)
{
    const usm_model *m = usm_model_find("3dof");
    usm_steady *st = usm_steady_alloc(m);
    usm_floquet *fl = usm_floquet_alloc(m);
    usm_floquet_result fr;
    usm_params p;
    usm_params_default(&p);
    CHECK(st && fl && usm_steady_solve(st, &p, NULL) == USM_OK &&
              usm_floquet_compute(fl, &p, usm_steady_root(st, 0), 0.0, NULL, &fr) == USM_OK,
          "steady: no solution at the paper's parameters");
    FILE *f = tmpfile();
    usm_steady_report rep = {m, &p, st, NULL, &fr, NULL, NULL};
    CHECK(f && usm_steady_write_json(&rep, f) == 0, "usm_steady_write_json failed");
    rewind(f);
    json_error_t err;
    json_t *o = json_loadf(f, 0, &err);
    CHECK(o != NULL, "steady JSON does not parse: %s", err.text);
    json_t *roots = json_object_get(o, "roots");
    CHECK(json_array_size(roots) == usm_steady_count(st), "roots: %zu, want %zu",
          json_array_size(roots), usm_steady_count(st));
    for (size_t k = 0; k < json_array_size(roots) && k < usm_steady_count(st); ++k) {
        const usm_steady_solution *s = usm_steady_root(st, k);
        json_t *r = json_array_get(roots, k);
        CHECK(json_real_value(json_object_get(r, "theta")) == s->theta &&
                  json_real_value(json_object_get(r, "alpha")) == s->alpha &&
                  json_real_value(json_object_get(r, "rotor_speed")) == s->rotor_speed &&
                  json_real_value(json_object_get(r, "F_n")) == s->F_n,
              "root %zu: values do not read back exactly", k);
    }
    json_t *mult = json_object_get(json_object_get(o, "floquet"), "multipliers");
    CHECK((int)json_array_size(mult) == fr.n, "multipliers: %zu, want %d", json_array_size(mult),
          fr.n);
    for (int k = 0; k < fr.n && k < (int)json_array_size(mult); ++k) {
        json_t *z = json_array_get(mult, (size_t)k);
        CHECK(json_number_value(json_array_get(z, 0)) == fr.re[k] &&
                  json_number_value(json_array_get(z, 1)) == fr.im[k],
              "multiplier %d does not read back exactly", k);
    }
    json_decref(o);
    if (f)
        fclose(f);
    usm_floquet_free(fl);
    usm_steady_free(st);
}

/* A run's outputs read back as the start of the next run. */
static void sim_round_trip(const char *model)
{
    const usm_model *m = usm_model_find(model);
    usm_sim *sim = usm_sim_alloc(m);
    usm_sim_options opt, back;
    usm_sim_summary sum;
    usm_params p;
    char csv_path[] = "/tmp/usm-test-io-XXXXXX", msg[USM_IO_MSG_LEN];
    last_sample last = {0};
    usm_params_default(&p);
    usm_sim_options_default(&opt);
    opt.duration = 20.0 / p.f;
    opt.rate = 2.0 * p.f + 0.5; /* not on the period grid: the last row is the end's */
    int fd = mkstemp(csv_path);
    last.csv = fd >= 0 ? fdopen(fd, "w") : NULL;
    CHECK(sim && last.csv, "%s: set-up failed", model);
    if (!sim || !last.csv)
        return;
    usm_sim_csv_header(last.csv);
    usm_sim_callbacks cb = {on_sample, NULL, &last, NULL};
    CHECK(usm_sim_run(sim, &p, &opt, &cb, &sum) == USM_OK, "%s: run: %s", model,
          usm_sim_message(sim));
    CHECK(fclose(last.csv) == 0, "%s: CSV not written", model);
    CHECK(last.t == sum.t_reached, "%s: the last row is at t = %.17g, the run ended at %.17g",
          model, last.t, sum.t_reached);

    usm_sim_options_default(&back);
    CHECK(usm_sim_read_start(csv_path, m, &back, msg) == USM_OK, "%s: CSV: %s", model, msg);
    CHECK(back.t0 == last.t, "%s: CSV t0 %.17g, want %.17g", model, back.t0, last.t);
    /* the stick model's rotor angle is no state variable: read apart */
    CHECK(m->slip || back.rotor_angle0 == last.rotor_angle,
          "%s: CSV rotor angle %.17g, want %.17g", model, back.rotor_angle0, last.rotor_angle);
    for (int i = 0; i < m->nx; ++i)
        CHECK(back.x0[i] == last.x[i], "%s: CSV %s = %.17g, want %.17g", model,
              m->state_names[i], back.x0[i], last.x[i]);

    char json_path[] = "/tmp/usm-test-io-XXXXXX";
    fd = mkstemp(json_path);
    FILE *jf = fd >= 0 ? fdopen(fd, "w") : NULL;
    usm_sim_report rep = {m, &p, &opt, NULL, csv_path, &sum, 0.0};
    CHECK(jf && usm_sim_write_json(&rep, jf) == 0 && fclose(jf) == 0, "%s: JSON not written",
          model);
    usm_sim_options_default(&back);
    CHECK(usm_sim_read_start(json_path, m, &back, msg) == USM_OK, "%s: JSON: %s", model, msg);
    CHECK(back.t0 == sum.t_reached && (m->slip || back.rotor_angle0 == sum.final_rotor_angle),
          "%s: JSON t0 %.17g / rotor angle %.17g", model, back.t0, back.rotor_angle0);
    for (int i = 0; i < m->nx; ++i)
        CHECK(back.x0[i] == sum.final_x[i], "%s: JSON %s = %.17g, want %.17g", model,
              m->state_names[i], back.x0[i], sum.final_x[i]);
    /* the state of another model is refused, naming the file */
    const usm_model *other = usm_model_find(strcmp(model, "3dof") ? "3dof" : "4dof");
    CHECK(usm_sim_read_start(json_path, other, &back, msg) == USM_EINPUT &&
              strstr(msg, json_path) != NULL,
          "%s: JSON of another model accepted (\"%s\")", model, msg);
    remove(csv_path);
    remove(json_path);
    usm_sim_free(sim);
}

static void params_file(void)
{
    char path[] = "/tmp/usm-test-io-XXXXXX", msg[USM_IO_MSG_LEN];
    usm_params p, q;
    int fd = mkstemp(path);
    FILE *f = fd >= 0 ? fdopen(fd, "w") : NULL;
    CHECK(f != NULL, "params: temporary file");
    if (!f)
        return;
    fputs("{\n  \"f\": 36000.5,\n  \"T\": 1.25e-4\n}\n", f);
    fclose(f);
    usm_params_default(&p);
    q = p;
    CHECK(usm_params_read_file(path, &p, msg) == USM_OK, "params: %s", msg);
    CHECK(p.f == 36000.5 && p.T == 1.25e-4, "params: f %.17g, T %.17g", p.f, p.T);
    CHECK(p.m0 == q.m0 && p.mu0 == q.mu0, "params: a parameter not in the file changed");
    f = fopen(path, "w");
    fputs("{\n  \"f\": 36000.5,\n  \"T\": nan\n}\n", f);
    fclose(f);
    q = p;
    CHECK(usm_params_read_file(path, &p, msg) == USM_EINPUT, "params: a NaN accepted");
    char where[sizeof path + 8];
    snprintf(where, sizeof where, "%s:3:", path);
    CHECK(strstr(msg, where) == msg, "params: message \"%s\" does not start with %s", msg, where);
    CHECK(memcmp(&p, &q, sizeof p) == 0, "params: a bad file changed the parameters");
    remove(path);
}

int main(void)
{
    gsl_set_error_handler_off();
    steady_json();
    sim_round_trip("3dof");
    sim_round_trip("4dof");
    params_file();
    if (failures)
        printf("%d failures\n", failures);
    return failures != 0;
}
