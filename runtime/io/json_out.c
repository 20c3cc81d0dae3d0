/* JSON output of the usm command. */
#include "json_out.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "csv_out.h"

json_t *usm_json_real(double v)
{
    return isfinite(v) ? json_real(v) : json_null();
}

void usm_json_put(json_t *obj, const char *key, json_t *value, int *ok)
{
    /* json_object_set_new releases `value` even when it fails (also when obj
     * is NULL), so nothing leaks on the way to the final check. */
    if (json_object_set_new(obj, key, value) != 0)
        *ok = 0;
}

static void push(json_t *arr, json_t *value, int *ok)
{
    if (json_array_append_new(arr, value) != 0)
        *ok = 0;
}

json_t *usm_json_finish(json_t *obj, int ok)
{
    if (!ok) {
        json_decref(obj);
        return NULL;
    }
    return obj;
}

json_t *usm_json_params(const usm_params *p)
{
    json_t *obj = json_object();
    int ok = obj != NULL;
    for (int k = 0; k < USM_NPARAMS; ++k)
        usm_json_put(obj, usm_param_table[k].name,
                     usm_json_real(usm_params_get(p, &usm_param_table[k])), &ok);
    return usm_json_finish(obj, ok);
}

json_t *usm_json_root(const usm_steady_solution *s)
{
    json_t *obj = json_object();
    int ok = obj != NULL;
    usm_json_put(obj, "theta", usm_json_real(s->theta), &ok);
    usm_json_put(obj, "alpha", usm_json_real(s->alpha), &ok);
    usm_json_put(obj, "beta", usm_json_real(s->beta), &ok);
    usm_json_put(obj, "rotor_speed", usm_json_real(s->rotor_speed), &ok);
    usm_json_put(obj, "F_n", usm_json_real(s->F_n), &ok);
    usm_json_put(obj, "F_t", usm_json_real(s->F_t), &ok);
    usm_json_put(obj, "v_rel", usm_json_real(s->v_rel), &ok);
    usm_json_put(obj, "stick_admissible", json_boolean(s->stick_admissible), &ok);
    usm_json_put(obj, "mu_used", usm_json_real(s->mu_used), &ok);
    usm_json_put(obj, "v_c", usm_json_real(s->v_c), &ok);
    usm_json_put(obj, "R_star", usm_json_real(s->R_star), &ok);
    usm_json_put(obj, "Z", usm_json_real(s->Z), &ok);
    usm_json_put(obj, "residual_norm", usm_json_real(s->residual_norm), &ok);
    usm_json_put(obj, "power_in", usm_json_real(s->power_in), &ok);
    usm_json_put(obj, "power_out", usm_json_real(s->power_out), &ok);
    usm_json_put(obj, "power_damping", usm_json_real(s->power_damping), &ok);
    usm_json_put(obj, "power_slip", usm_json_real(s->power_slip), &ok);
    usm_json_put(obj, "efficiency", usm_json_real(s->efficiency), &ok); /* null: power_in <= 0 */
    usm_json_put(obj, "valid", json_boolean(s->validity == USM_VALID), &ok);
    usm_json_put(obj, "invalid_reason",
                 s->validity == USM_VALID ? json_null() : json_string(usm_validity_name(s->validity)),
                 &ok);
    return usm_json_finish(obj, ok);
}

json_t *usm_json_floquet(const usm_floquet_result *r)
{
    json_t *obj = json_object();
    json_t *mult = json_array();
    json_t *cyclic = json_array();
    int ok = obj && mult && cyclic;
    for (int k = 0; k < r->n; ++k) {
        json_t *pair = json_array();
        push(pair, usm_json_real(r->re[k]), &ok);
        push(pair, usm_json_real(r->im[k]), &ok);
        push(mult, pair, &ok);
        push(cyclic, json_boolean(r->cyclic[k]), &ok);
    }
    usm_json_put(obj, "t0", usm_json_real(r->t0), &ok);
    usm_json_put(obj, "t0_dependent", json_boolean(r->t0_dependent), &ok);
    usm_json_put(obj, "multipliers", mult, &ok);
    usm_json_put(obj, "cyclic", cyclic, &ok);
    usm_json_put(obj, "max_modulus", usm_json_real(r->max_modulus), &ok);
    usm_json_put(obj, "stable", json_boolean(r->stable), &ok);
    return usm_json_finish(obj, ok);
}

/* jansson (2.14) prints a real with a fixed number of digits; 17 read back
 * bit for bit but show 0.005 as 0.0050000000000000001.  So the text passes
 * through this filter, which reprints every real number token outside the
 * strings in the shortest form that reads back to the same double (the CSV's
 * usm_shortest), keeping a "." or an exponent so that it stays a real. */
typedef struct shortest_filter {
    FILE *out;
    int in_string, escaped, failed;
    size_t len;   /* of the number token being collected */
    char num[64];
} shortest_filter;

static void filter_flush(shortest_filter *f)
{
    char buf[40];
    const char *text = f->num;
    f->num[f->len] = '\0';
    if (f->len > 0 && strpbrk(f->num, ".eE")) {
        char *end;
        double v = strtod(f->num, &end);
        if (*end == '\0' && isfinite(v)) {
            char *e;
            usm_shortest(buf, v);
            if (!strpbrk(buf, ".e"))
                strcat(buf, ".0");
            if ((e = strchr(buf, 'e'))) { /* 1e-05 -> 1e-5, 1e+20 -> 1e20, as jansson */
                char *d = e + 1, *src = e + 1;
                if (*src == '+')
                    ++src;
                else if (*src == '-')
                    d = ++src;
                while (*src == '0' && src[1] != '\0')
                    ++src;
                memmove(d, src, strlen(src) + 1);
            }
            text = buf;
        }
    }
    if (f->len > 0 && fputs(text, f->out) == EOF)
        f->failed = 1;
    f->len = 0;
}

static int filter_chunk(const char *buffer, size_t size, void *data)
{
    shortest_filter *f = data;
    size_t run = 0; /* start of the pending pass-through span */
    for (size_t k = 0; k < size; ++k) {
        const char c = buffer[k];
        if (f->in_string) {
            if (f->escaped)
                f->escaped = 0;
            else if (c == '\\')
                f->escaped = 1;
            else if (c == '"')
                f->in_string = 0;
            continue;
        }
        const int starts = c == '-' || (c >= '0' && c <= '9');
        const int goes_on = starts || c == '+' || c == '.' || c == 'e' || c == 'E';
        if ((f->len == 0 && starts) || (f->len > 0 && goes_on)) {
            if (k > run && fwrite(buffer + run, 1, k - run, f->out) != k - run)
                f->failed = 1;
            run = k + 1;
            if (f->len + 1 >= sizeof f->num) { /* not a double's text: as it is */
                f->num[f->len] = '\0';
                if (fputs(f->num, f->out) == EOF)
                    f->failed = 1;
                f->len = 0;
            }
            f->num[f->len++] = c;
            continue;
        }
        if (f->len > 0) {
            filter_flush(f);
        }
        if (c == '"')
            f->in_string = 1;
    }
    if (size > run && fwrite(buffer + run, 1, size - run, f->out) != size - run)
        f->failed = 1;
    return f->failed ? -1 : 0;
}

int usm_json_dumpf(const json_t *value, FILE *out, size_t flags)
{
    shortest_filter f = {out, 0, 0, 0, 0, {0}};
    if (json_dump_callback(value, filter_chunk, &f, flags | JSON_REAL_PRECISION(17)) != 0)
        return -1;
    filter_flush(&f);
    return f.failed ? -1 : 0;
}

int usm_json_print(const json_t *value, FILE *out)
{
    if (usm_json_dumpf(value, out, JSON_INDENT(2) | JSON_PRESERVE_ORDER) != 0)
        return -1;
    return fputc('\n', out) == EOF ? -1 : 0;
}

int usm_json_write(json_t *value, FILE *out)
{
    int rc = value ? usm_json_print(value, out) : -1;
    json_decref(value);
    return rc;
}

void usm_json_put_squeal(json_t *obj, const usm_floquet_result *r, double f, int *ok)
{
    usm_squeal sq;
    usm_floquet_squeal(r, f, &sq);
    usm_json_put(obj, "squeal_frequency", sq.found ? usm_json_real(sq.frequency) : json_null(),
                 ok);
    usm_json_put(obj, "squeal_multiplier", sq.found ? json_pack("[ff]", sq.re, sq.im) : json_null(),
                 ok);
    usm_json_put(obj, "squeal_reason", sq.found ? json_null() : json_string(sq.reason), ok);
}

/* The keys of `usm periodic --json` for one orbit. */
json_t *usm_json_periodic_result(const usm_periodic_result *r)
{
    json_t *o = json_object(), *h = json_object();
    int ok = o && h;
    usm_json_put(o, "rotor_speed_mean", usm_json_real(r->rotor_speed_mean), &ok);
    usm_json_put(o, "rotor_speed_ripple", usm_json_real(r->rotor_speed_ripple), &ok);
    usm_json_put(o, "F_n_min", usm_json_real(r->F_n_min), &ok);
    usm_json_put(o, "F_n_max", usm_json_real(r->F_n_max), &ok);
    usm_json_put(o, "friction_needed_max", usm_json_real(r->friction_needed_max), &ok);
    usm_json_put(o, "theta_mean", usm_json_real(r->theta_mean), &ok);
    usm_json_put(o, "theta_min", usm_json_real(r->theta_min), &ok);
    usm_json_put(o, "theta_max", usm_json_real(r->theta_max), &ok);
    usm_json_put(h, "theta", usm_json_real(r->theta_harmonic_2), &ok);
    usm_json_put(h, "F_n", usm_json_real(r->F_n_harmonic_2), &ok);
    usm_json_put(o, "harmonic_2", h, &ok);
    usm_json_put(o, "floquet", usm_json_floquet(&r->floquet), &ok);
    usm_json_put_squeal(o, &r->floquet, 1.0 / r->period, &ok);
    usm_json_put(o, "contact_open", json_boolean(r->contact_open), &ok);
    usm_json_put(o, "openings_per_period", json_integer(r->openings_per_period), &ok);
    usm_json_put(o, "valid", json_boolean(r->validity == USM_VALID), &ok);
    usm_json_put(o, "invalid_reason",
                 r->validity == USM_VALID ? json_null() : json_string(usm_validity_name(r->validity)),
                 &ok);
    usm_json_put(o, "newton_iterations", json_integer(r->iterations), &ok);
    usm_json_put(o, "residual", usm_json_real(r->residual), &ok);
    return usm_json_finish(o, ok);
}

json_t *usm_json_hybrid_result(const usm_hybrid_result *r)
{
    json_t *o = json_object();
    int ok = o != NULL;
    const int valid = r->validity == USM_VALID;
    usm_json_put(o, "rotor_speed_mean", usm_json_real(r->rotor_speed_mean), &ok);
    usm_json_put(o, "rotor_speed_ripple", usm_json_real(r->rotor_speed_ripple), &ok);
    usm_json_put(o, "floquet", usm_json_floquet(&r->floquet), &ok);
    usm_json_put(o, "separation_fraction", usm_json_real(r->separation_fraction), &ok);
    usm_json_put(o, "separations_per_period", json_integer(r->separations_per_period), &ok);
    usm_json_put(o, "impacts_per_period", json_integer(r->impacts_per_period), &ok);
    usm_json_put(o, "impacts_slipping", json_integer(r->impacts_slipping), &ok);
    usm_json_put(o, "impact_velocity_max", usm_json_real(r->impact_velocity_max), &ok);
    usm_json_put(o, "mode_sequence", json_string(r->mode_sequence), &ok);
    usm_json_put(o, "section_t", usm_json_real(r->t0), &ok);
    usm_json_put(o, "contact_open", json_true(), &ok);
    usm_json_put(o, "valid", json_boolean(valid), &ok);
    usm_json_put(o, "invalid_reason",
                 valid ? json_null() : json_string(usm_validity_name(r->validity)), &ok);
    usm_json_put(o, "newton_iterations", json_integer(r->iterations), &ok);
    usm_json_put(o, "residual", usm_json_real(r->residual), &ok);
    return usm_json_finish(o, ok);
}
