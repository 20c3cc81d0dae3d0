/* Output of a sweep: CSV rows or one JSON object. */
#include "sweep_out.h"

#include <math.h>
#include <string.h>

#include "io/csv_out.h"
#include "io/json_out.h"
#include "steady_out.h"

/* The operating point of a point: operating_point (index into
 * the full search's roots, or null), operating_point_class,
 * operating_point_reason (null when undecided), operating_point_message,
 * starts_from_rest, and operating_point_solution (the root, when there is
 * one, with its floquet). */
static void op_json(json_t *obj, const usm_point_op *op, int *ok)
{
    usm_json_put(obj, "operating_point", op->index >= 0 ? json_integer(op->index) : json_null(),
                 ok);
    usm_json_put(obj, "operating_point_class", json_string(usm_point_op_class_name(op->cls)), ok);
    usm_json_put(obj, "operating_point_reason",
                 op->cls != USM_POINT_OP_NO_SOLUTION && op->reason != USM_OP_UNDECIDED
                     ? json_string(usm_op_reason_name(op->reason))
                     : json_null(),
                 ok);
    usm_json_put(obj, "operating_point_message", json_string(op->message), ok);
    usm_json_put(obj, "starts_from_rest",
                 op->starts_from_rest >= 0 ? json_boolean(op->starts_from_rest) : json_null(), ok);
    if (op->index >= 0) {
        json_t *root = usm_json_root(&op->sol);
        usm_json_put(root, "floquet", usm_json_floquet(&op->floquet), ok);
        usm_json_put(obj, "operating_point_solution", root, ok);
    }
}

/* The operating point's CSV fields, appended last: operating_point, op_class,
 * op_theta [rad], op_rotor_speed [1/s], op_max_modulus [1] (empty when not
 * computed or none). */
static void op_csv(FILE *out, const usm_sweep_point *pt)
{
    const int op = pt->has_op && pt->op.index >= 0;
    if (op)
        fprintf(out, ",%d", pt->op.index);
    else
        fputc(',', out);
    fprintf(out, ",%s", pt->has_op ? usm_point_op_class_name(pt->op.cls) : "");
    usm_csv_num(out, 0, op ? pt->op.sol.theta : NAN);
    usm_csv_num(out, 0, op ? pt->op.sol.rotor_speed : NAN);
    usm_csv_num(out, 0, op ? pt->op.floquet.max_modulus : NAN);
}

/* A point carries the keys of `usm steady --json` for one root, so that a
 * program reading either finds the same names. */
static json_t *point_json(const usm_sweep_point *pt, const usm_model *m, const char *over)
{
    json_t *obj = json_object();
    int ok = obj != NULL;
    usm_json_put(obj, over, usm_json_real(pt->value), &ok);
    usm_json_put(obj, "model", json_string(m->name), &ok);
    usm_json_put(obj, "converged", json_boolean(pt->converged), &ok);
    usm_json_put(obj, "roots", json_integer(pt->roots), &ok);
    if (!pt->converged)
        usm_json_put(obj, "error", json_string(pt->error), &ok);
    else {
        json_t *root = usm_json_root(&pt->sol);
        if (!root || json_object_update(obj, root) != 0)
            ok = 0;
        json_decref(root);
    }
    if (pt->has_floquet)
        usm_json_put(obj, "floquet", usm_json_floquet(&pt->floquet), &ok);
    else if (pt->floquet_error[0])
        usm_json_put(obj, "floquet_error", json_string(pt->floquet_error), &ok);
    if (pt->has_op)
        op_json(obj, &pt->op, &ok);
    return usm_json_finish(obj, ok);
}

static json_t *event_json(const usm_sweep_event *e, const char *over)
{
    json_t *obj = json_object();
    int ok = obj != NULL;
    usm_json_put(obj, "type", json_string(usm_event_name(e->type)), &ok);
    usm_json_put(obj, over, usm_json_real(e->value), &ok);
    usm_json_put(obj, "what", json_string(e->what), &ok);
    if (e->monitor[0]) {
        usm_json_put(obj, "monitor", json_string(e->monitor), &ok);
        usm_json_put(obj, "monitor_value", usm_json_real(e->monitor_value), &ok);
    }
    if (e->has_sol)
        usm_json_put(obj, "solution", usm_json_root(&e->sol), &ok);
    /* beside the event's values, not only inside "solution" (not at the stick
     * limit, the boundary itself) */
    if (e->has_sol && e->type != USM_EVENT_STICK_LIMIT) {
        usm_json_put(obj, "valid", json_boolean(e->sol.validity == USM_VALID), &ok);
        usm_json_put(obj, "invalid_reason",
                     e->sol.validity == USM_VALID ? json_null()
                                                  : json_string(usm_validity_name(e->sol.validity)),
                     &ok);
    }
    return usm_json_finish(obj, ok);
}

json_t *usm_sweep_json(const usm_sweep *s, const usm_model *m, const usm_params *p,
                       const char *over)
{
    json_t *obj = json_object();
    json_t *points = json_array();
    json_t *events = json_array();
    int ok = obj && points && events;
    usm_json_put(obj, "over", json_string(over), &ok);
    usm_json_put(obj, "model", json_string(m->name), &ok);
    usm_json_put(obj, "parameters", usm_json_params(p), &ok);
    for (size_t i = 0; i < usm_sweep_count(s); ++i)
        if (json_array_append_new(points, point_json(usm_sweep_point_at(s, i), m, over)) != 0)
            ok = 0;
    for (size_t i = 0; i < usm_sweep_event_count(s); ++i)
        if (json_array_append_new(events, event_json(usm_sweep_event_at(s, i), over)) != 0)
            ok = 0;
    if (usm_sweep_op_rule(s))
        usm_json_put(obj, "operating_point_rule", json_string(usm_sweep_op_rule(s)), &ok);
    usm_json_put(obj, "points", points, &ok);
    usm_json_put(obj, "events", events, &ok);
    return usm_json_finish(obj, ok);
}

/* An empty field rather than "nan": spreadsheets and numpy read it as missing. */
static void field(FILE *out, double v, const char *fmt)
{
    fputc(',', out);
    if (isfinite(v))
        fprintf(out, fmt, v);
}

/* A text field, quoted (RFC 4180) when it holds a separator or a quote. */
static void csv_text(FILE *out, const char *text)
{
    if (!strpbrk(text, ",\"\n")) {
        fputs(text, out);
        return;
    }
    fputc('"', out);
    for (const char *c = text; *c; ++c) {
        if (*c == '"')
            fputc('"', out);
        fputc(*c == '\n' ? ' ' : *c, out);
    }
    fputc('"', out);
}

int usm_sweep_csv(const usm_sweep *s, const char *over, int floquet, FILE *out)
{
    const usm_param_info *info = usm_params_find(over);
    fprintf(out, "%s [%s],theta [rad],alpha [rad],rotor_speed [1/s],F_n [N],F_t [N],"
                 "mu_needed [1],max_modulus [1],stable,converged,roots,error,"
                 "power_in [W],power_out [W],power_damping [W],power_slip [W],efficiency [1],"
                 "valid,invalid_reason,operating_point,op_class,op_theta [rad],"
                 "op_rotor_speed [1/s],op_max_modulus [1]\n",
            over, info ? info->unit : "");
    for (size_t i = 0; i < usm_sweep_count(s); ++i) {
        const usm_sweep_point *pt = usm_sweep_point_at(s, i);
        char buf[32];
        /* every bit of the swept value: `usm steady --set` reproduces the row */
        fputs(usm_shortest(buf, pt->value), out);
        if (!pt->converged) {
            fprintf(out, ",,,,,,,,,false,%d,", pt->roots);
            csv_text(out, pt->error);
            fputs(",,,,,,,", out);
            op_csv(out, pt);
            fputc('\n', out);
            continue;
        }
        const usm_steady_solution *r = &pt->sol;
        field(out, r->theta, "%.12g");
        field(out, r->alpha, "%.12g");
        field(out, r->rotor_speed, "%.12g");
        field(out, r->F_n, "%.12g");
        field(out, r->F_t, "%.12g");
        field(out, r->mu_used, "%.12g");
        if (floquet && pt->has_floquet) {
            field(out, pt->floquet.max_modulus, "%.12g");
            fprintf(out, ",%s", pt->floquet.stable ? "true" : "false");
        } else
            fputs(",,", out);
        fprintf(out, ",true,%d,", pt->roots);
        csv_text(out, pt->floquet_error);
        /* appended last: scripts reading the columns above by position keep working */
        usm_csv_num(out, 0, r->power_in);
        usm_csv_num(out, 0, r->power_out);
        usm_csv_num(out, 0, r->power_damping);
        usm_csv_num(out, 0, r->power_slip);
        usm_csv_num(out, 0, r->efficiency); /* empty: power_in <= 0 */
        usm_csv_validity(out, 1, r->validity);
        op_csv(out, pt);
        fputc('\n', out);
    }
    for (size_t i = 0; i < usm_sweep_event_count(s); ++i) {
        const usm_sweep_event *e = usm_sweep_event_at(s, i);
        char buf[32];
        fprintf(out, "# %s at %s = %s: %s\n", usm_event_name(e->type), over,
                usm_shortest(buf, e->value), e->what);
    }
    if (usm_sweep_op_rule(s))
        fprintf(out, "# operating point rule: %s\n", usm_sweep_op_rule(s));
    return ferror(out) ? -1 : 0;
}

int usm_sweep_write_json(const usm_sweep *s, const usm_model *m, const usm_params *p,
                         const char *over, FILE *out)
{
    return usm_json_write(usm_sweep_json(s, m, p, over), out);
}
