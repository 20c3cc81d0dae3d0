/* The stability map of the command (usm_report_map.h): computed by the
 * library (usm_map.h), written as CSV and JSON. */
#include "report_map.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "io/csv_out.h"
#include "io/io_msg.h"
#include "io/json_out.h"
#include "usm_map.h"

const char *usm_report_boundary_name(int kind)
{
    return usm_map_boundary_name((usm_map_boundary_kind)kind);
}

/* The library's message with its field named as the command's option:
 * "x-points: ..." becomes "--x-points: ...". */
static void option_message(const char *lib, char msg[USM_IO_MSG_LEN])
{
    if ((lib[0] == 'x' || lib[0] == 'y') && (lib[1] == '-' || lib[1] == ':'))
        usm_io_msg(msg, "--%s", lib);
    else
        usm_io_msg(msg, "%s", lib);
}

void usm_report_map_cell_copy(const usm_map_cell *in, usm_report_map_cell *c)
{
    const usm_point *pt = &in->point;
    c->x = in->x;
    c->y = in->y;
    c->exists = pt->exists;
    c->roots = pt->exists ? pt->roots : 0;
    c->floquet_ok = pt->has_floquet;
    c->max_modulus = pt->has_floquet ? pt->floquet.max_modulus : NAN;
    c->stable = pt->has_floquet && pt->floquet.stable;
    c->theta = pt->exists ? pt->sol.theta : NAN;
    c->rotor_speed = pt->exists ? pt->sol.rotor_speed : NAN;
    c->mu_used = pt->exists ? pt->sol.mu_used : NAN;
    c->stick_admissible = pt->exists && pt->sol.stick_admissible;
    c->validity = pt->exists ? pt->sol.validity : USM_VALID;
    c->power_in = pt->exists ? pt->sol.power_in : NAN;
    c->power_out = pt->exists ? pt->sol.power_out : NAN;
    c->power_damping = pt->exists ? pt->sol.power_damping : NAN;
    c->power_slip = pt->exists ? pt->sol.power_slip : NAN;
    c->efficiency = pt->exists ? pt->sol.efficiency : NAN;
    snprintf(c->error, sizeof c->error, "%s", pt->error);
    const int op = pt->has_op && pt->op.index >= 0;
    c->op_class = pt->has_op ? (int)pt->op.cls : (int)USM_POINT_OP_NOT_EVALUATED;
    c->op_index = op ? pt->op.index : -1;
    c->op_reason = pt->has_op ? (int)pt->op.reason : (int)USM_OP_UNDECIDED;
    c->starts_from_rest = pt->has_op ? pt->op.starts_from_rest : -1;
    c->op_theta = op ? pt->op.sol.theta : NAN;
    c->op_rotor_speed = op ? pt->op.sol.rotor_speed : NAN;
    c->op_max_modulus = op ? pt->op.floquet.max_modulus : NAN;
    snprintf(c->op_message, sizeof c->op_message, "%s", pt->has_op ? pt->op.message : "");
}

void usm_report_map_options(const usm_report_map *map, usm_map_options *opt)
{
    usm_map_options_default(opt);
    opt->x = (usm_map_axis){map->x.name, map->x.from, map->x.to, map->x.points};
    opt->y = (usm_map_axis){map->y.name, map->y.from, map->y.to, map->y.points};
    opt->t0 = map->t0;
    if (map->floquet)
        opt->floquet = *map->floquet;
    opt->threads = map->threads;
    opt->boundaries = map->boundaries;
    if (map->op)
        opt->op = *map->op;
    opt->progress = map->progress;
}

int usm_report_map_fill(usm_report_map *map, const usm_map_cell *cells,
                        usm_map_boundary_point *const bnd[USM_MAP_NBOUNDARY],
                        const size_t nbnd[USM_MAP_NBOUNDARY], size_t floquet_failures,
                        char msg[USM_IO_MSG_LEN])
{
    const size_t n = (size_t)map->x.points * (size_t)map->y.points;
    map->x.param = usm_params_find(map->x.name);
    map->y.param = usm_params_find(map->y.name);
    for (int k = 0; k < USM_REPORT_NBOUNDARY; ++k) {
        map->bnd[k] = NULL;
        map->nbnd[k] = 0;
    }
    if (!(map->cells = calloc(n, sizeof *map->cells))) {
        usm_io_msg(msg, "map: out of memory");
        return USM_EFAILED;
    }
    for (size_t c = 0; c < n; ++c)
        usm_report_map_cell_copy(&cells[c], &map->cells[c]);
    for (int k = 0; k < USM_REPORT_NBOUNDARY; ++k) {
        if (!(map->bnd[k] = malloc((nbnd[k] ? nbnd[k] : 1) * sizeof *map->bnd[k]))) {
            usm_io_msg(msg, "map: out of memory");
            usm_report_map_free(map);
            return USM_EFAILED;
        }
        for (size_t q = 0; q < nbnd[k]; ++q)
            map->bnd[k][q] = (usm_report_boundary_point){bnd[k][q].x, bnd[k][q].y,
                                                         bnd[k][q].column, bnd[k][q].k};
        map->nbnd[k] = nbnd[k];
    }
    map->floquet_failures = floquet_failures;
    return USM_OK;
}

int usm_report_map_run(usm_report_map *map, char msg[USM_IO_MSG_LEN])
{
    usm_map_options opt;
    usm_map_cell *cells = NULL;
    usm_map_boundary_point *bnd[USM_MAP_NBOUNDARY] = {NULL};
    size_t nbnd[USM_MAP_NBOUNDARY] = {0};
    int status;
    usm_map *lib = usm_map_alloc(map->model);
    map->cells = NULL;
    for (int k = 0; k < USM_REPORT_NBOUNDARY; ++k) {
        map->bnd[k] = NULL;
        map->nbnd[k] = 0;
    }
    map->floquet_failures = 0;
    if (!lib) {
        usm_io_msg(msg, "map: out of memory");
        return USM_EFAILED;
    }
    usm_report_map_options(map, &opt);
    if ((status = usm_map_run(lib, &map->params, &opt)) != USM_OK) {
        if (status == USM_EINPUT)
            option_message(usm_map_message(lib), msg);
        else
            usm_io_msg(msg, "map: %s", usm_map_message(lib));
        usm_map_free(lib);
        return status;
    }
    /* the library's result as arrays, the form a map gathered elsewhere has */
    const size_t nx = (size_t)map->x.points, ny = (size_t)map->y.points;
    int ok = (cells = malloc(nx * ny * sizeof *cells)) != NULL;
    for (size_t j = 0; ok && j < ny; ++j)
        for (size_t i = 0; i < nx; ++i)
            cells[j * nx + i] = *usm_map_cell_at(lib, (int)i, (int)j);
    for (int k = 0; ok && k < USM_MAP_NBOUNDARY; ++k) {
        nbnd[k] = usm_map_boundary_count(lib, (usm_map_boundary_kind)k);
        ok = (bnd[k] = malloc((nbnd[k] ? nbnd[k] : 1) * sizeof *bnd[k])) != NULL;
        for (size_t q = 0; ok && q < nbnd[k]; ++q)
            bnd[k][q] = *usm_map_boundary_at(lib, (usm_map_boundary_kind)k, q);
    }
    if (!ok) {
        usm_io_msg(msg, "map: out of memory");
        status = USM_EFAILED;
    } else
        status = usm_report_map_fill(map, cells, bnd, nbnd, usm_map_floquet_failures(lib), msg);
    free(cells);
    for (int k = 0; k < USM_MAP_NBOUNDARY; ++k)
        free(bnd[k]);
    usm_map_free(lib);
    return status;
}

void usm_report_map_free(usm_report_map *map)
{
    free(map->cells);
    map->cells = NULL;
    for (int k = 0; k < USM_REPORT_NBOUNDARY; ++k) {
        free(map->bnd[k]);
        map->bnd[k] = NULL;
        map->nbnd[k] = 0;
    }
}

/* ---- output ------------------------------------------------------------------ */

/* The two axis columns of a header, "f [Hz],T [N m]". */
static void axis_header(const usm_report_map *map, usm_csv_column cols[2])
{
    cols[0] = (usm_csv_column){map->x.param->name, map->x.param->unit};
    cols[1] = (usm_csv_column){map->y.param->name, map->y.param->unit};
}

int usm_report_map_write_csv(const usm_report_map *map, FILE *out)
{
    const int nx = map->x.points, ny = map->y.points;
    usm_csv_column cols[] = {{NULL, NULL},          {NULL, NULL},
                             {"exists", NULL},      {"roots", NULL},
                             {"max_modulus", "1"},  {"stable", NULL},
                             {"theta", "rad"},      {"rotor_speed", "1/s"},
                             {"mu_used", "1"},      {"stick_admissible", NULL},
                             {"power_in", "W"},     {"power_out", "W"},
                             {"power_damping", "W"}, {"power_slip", "W"},
                             {"efficiency", "1"},   {"valid", NULL},
                             {"invalid_reason", NULL}, {"operating_point", NULL},
                             {"op_class", NULL},    {"op_reason", NULL},
                             {"starts_from_rest", NULL}, {"op_theta", "rad"},
                             {"op_rotor_speed", "1/s"}, {"op_max_modulus", "1"}};
    axis_header(map, cols);
    usm_csv_header(out, cols, (int)(sizeof cols / sizeof cols[0]));
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            const usm_report_map_cell *c = &map->cells[(size_t)j * nx + i];
            char buf[32];
            usm_csv_num(out, 1, c->x);
            usm_csv_num(out, 0, c->y);
            usm_csv_bool(out, 0, c->exists);
            snprintf(buf, sizeof buf, "%d", c->roots);
            usm_csv_text(out, 0, buf);
            usm_csv_num(out, 0, c->max_modulus);
            if (c->floquet_ok)
                usm_csv_bool(out, 0, c->stable);
            else
                fputc(',', out); /* not known */
            usm_csv_num(out, 0, c->theta);
            usm_csv_num(out, 0, c->rotor_speed);
            usm_csv_num(out, 0, c->mu_used);
            if (c->exists)
                usm_csv_bool(out, 0, c->stick_admissible);
            else
                fputc(',', out);
            usm_csv_num(out, 0, c->power_in);
            usm_csv_num(out, 0, c->power_out);
            usm_csv_num(out, 0, c->power_damping);
            usm_csv_num(out, 0, c->power_slip);
            usm_csv_num(out, 0, c->efficiency);
            usm_csv_validity(out, c->exists, c->validity);
            if (c->op_index >= 0) {
                snprintf(buf, sizeof buf, "%d", c->op_index);
                usm_csv_text(out, 0, buf);
            } else
                fputc(',', out);
            usm_csv_text(out, 0, usm_point_op_class_name((usm_point_op_class)c->op_class));
            if (c->op_reason != USM_OP_UNDECIDED)
                usm_csv_text(out, 0, usm_op_reason_name((usm_op_reason)c->op_reason));
            else
                fputc(',', out);
            if (c->starts_from_rest >= 0)
                usm_csv_bool(out, 0, c->starts_from_rest);
            else
                fputc(',', out);
            usm_csv_num(out, 0, c->op_theta);
            usm_csv_num(out, 0, c->op_rotor_speed);
            usm_csv_num(out, 0, c->op_max_modulus);
            fputc('\n', out);
        }
    return ferror(out) ? -1 : 0;
}

int usm_report_map_write_boundary_csv(const usm_report_map *map, int kind, FILE *out)
{
    const usm_report_boundary_point *b = map->bnd[kind];
    const size_t n = map->nbnd[kind];
    usm_csv_column cols[2];
    axis_header(map, cols);
    usm_csv_header(out, cols, 2);
    for (size_t q = 0; q < n; ++q) {
        if (q > 0 && b[q].k != b[q - 1].k)
            fputs("\n\n", out); /* next block (gnuplot index) */
        else if (q > 0 && b[q].column != b[q - 1].column + 1)
            fputc('\n', out); /* a gap: columns without this change */
        usm_csv_num(out, 1, b[q].x);
        usm_csv_num(out, 0, b[q].y);
        fputc('\n', out);
    }
    return ferror(out) ? -1 : 0;
}

static json_t *axis_json(const usm_report_axis *a)
{
    json_t *obj = json_object();
    int ok = obj != NULL;
    usm_json_put(obj, "name", json_string(a->param->name), &ok);
    usm_json_put(obj, "from", usm_json_real(a->from), &ok);
    usm_json_put(obj, "to", usm_json_real(a->to), &ok);
    usm_json_put(obj, "points", json_integer(a->points), &ok);
    return usm_json_finish(obj, ok);
}

json_t *usm_report_map_json(const usm_report_map *map)
{
    const size_t n = (size_t)map->x.points * (size_t)map->y.points;
    json_t *obj = json_object(), *pts = json_array(), *bnds = json_object();
    int ok = obj && pts && bnds;
    usm_json_put(obj, "model", json_string(map->model->name), &ok);
    usm_json_put(obj, "parameters", usm_json_params(&map->params), &ok);
    usm_json_put(obj, "t0", usm_json_real(map->t0), &ok);
    usm_json_put(obj, "x", axis_json(&map->x), &ok);
    usm_json_put(obj, "y", axis_json(&map->y), &ok);
    usm_json_put(obj, "operating_point_rule", json_string(usm_op_rule_text(map->op)), &ok);
    for (size_t q = 0; q < n && ok; ++q) {
        const usm_report_map_cell *c = &map->cells[q];
        json_t *pt = json_object();
        ok = pt != NULL;
        usm_json_put(pt, "x", usm_json_real(c->x), &ok);
        usm_json_put(pt, "y", usm_json_real(c->y), &ok);
        usm_json_put(pt, "exists", json_boolean(c->exists), &ok);
        usm_json_put(pt, "roots", json_integer(c->roots), &ok);
        if (c->exists) {
            usm_json_put(pt, "theta", usm_json_real(c->theta), &ok);
            usm_json_put(pt, "rotor_speed", usm_json_real(c->rotor_speed), &ok);
            usm_json_put(pt, "mu_used", usm_json_real(c->mu_used), &ok);
            usm_json_put(pt, "stick_admissible", json_boolean(c->stick_admissible), &ok);
            usm_json_put(pt, "power_in", usm_json_real(c->power_in), &ok);
            usm_json_put(pt, "power_out", usm_json_real(c->power_out), &ok);
            usm_json_put(pt, "power_damping", usm_json_real(c->power_damping), &ok);
            usm_json_put(pt, "power_slip", usm_json_real(c->power_slip), &ok);
            usm_json_put(pt, "efficiency", usm_json_real(c->efficiency), &ok); /* null: power_in <= 0 */
            usm_json_put(pt, "valid", json_boolean(c->validity == USM_VALID), &ok);
            usm_json_put(pt, "invalid_reason",
                         c->validity == USM_VALID ? json_null()
                                                  : json_string(usm_validity_name(c->validity)),
                         &ok);
        }
        if (c->floquet_ok) {
            usm_json_put(pt, "max_modulus", usm_json_real(c->max_modulus), &ok);
            usm_json_put(pt, "stable", json_boolean(c->stable), &ok);
        }
        if (c->error[0])
            usm_json_put(pt, "error", json_string(c->error), &ok);
        if (c->op_class != USM_POINT_OP_NOT_EVALUATED) {
            usm_json_put(pt, "operating_point",
                         c->op_index >= 0 ? json_integer(c->op_index) : json_null(), &ok);
            usm_json_put(pt, "operating_point_class",
                         json_string(usm_point_op_class_name((usm_point_op_class)c->op_class)),
                         &ok);
            usm_json_put(pt, "operating_point_reason",
                         c->op_reason != USM_OP_UNDECIDED
                             ? json_string(usm_op_reason_name((usm_op_reason)c->op_reason))
                             : json_null(),
                         &ok);
            usm_json_put(pt, "operating_point_message", json_string(c->op_message), &ok);
            usm_json_put(pt, "starts_from_rest",
                         c->starts_from_rest >= 0 ? json_boolean(c->starts_from_rest)
                                                  : json_null(),
                         &ok);
            if (c->op_index >= 0) {
                usm_json_put(pt, "op_theta", usm_json_real(c->op_theta), &ok);
                usm_json_put(pt, "op_rotor_speed", usm_json_real(c->op_rotor_speed), &ok);
                usm_json_put(pt, "op_max_modulus", usm_json_real(c->op_max_modulus), &ok);
            }
        }
        if (json_array_append_new(pts, pt) != 0)
            ok = 0;
    }
    for (int k = 0; k < USM_REPORT_NBOUNDARY && ok; ++k) {
        json_t *arr = json_array();
        ok = arr != NULL;
        for (size_t q = 0; q < map->nbnd[k] && ok; ++q) {
            json_t *pair = json_pack("[f,f]", map->bnd[k][q].x, map->bnd[k][q].y);
            if (!pair || json_array_append_new(arr, pair) != 0)
                ok = 0;
        }
        usm_json_put(bnds, usm_report_boundary_name(k), arr, &ok);
    }
    usm_json_put(obj, "points", pts, &ok);
    pts = NULL;
    usm_json_put(obj, "boundaries", bnds, &ok);
    bnds = NULL;
    return usm_json_finish(obj, ok);
}

int usm_report_map_write_json(const usm_report_map *map, FILE *out)
{
    return usm_json_write(usm_report_map_json(map), out);
}
