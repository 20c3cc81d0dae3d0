/* Stability maps over two parameters, and the point evaluator (usm_map.h). */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/grid.h"
#include "core/pool_internal.h"
#include "core/progress.h"
#include "core/root.h"
#include "point_worker.h"
#include "usm_map.h"

/* Bisection stops when the bracket is this fraction of the y range. */
#define BISECT_RTOL 1e-7
#define BISECT_MAXIT 60
#define MAX_AXIS_POINTS 100000

/* ---- one point ------------------------------------------------------------------- */

/* The point, the stationary part by the full search (warm == 0), from the
 * given root, or by the warm start from guess (warm == 1). */
static int point_evaluate(usm_steady *s, usm_floquet *f, const usm_params *p,
                          const usm_steady_options *steady_opt, const usm_steady_solution *root,
                          int warm, int floquet, double t0, const usm_floquet_options *floquet_opt,
                          usm_point *out)
{
    memset(out, 0, sizeof *out);
    out->floquet.max_modulus = NAN;
    if (root && !warm) {
        out->sol = *root;
        out->roots = 1;
    } else {
        const int st = warm ? usm_steady_solve_warm(s, p, steady_opt, root)
                            : usm_steady_solve(s, p, steady_opt);
        if (st == USM_EINPUT) {
            snprintf(out->error, USM_MSG_LEN, "%s", usm_steady_message(s));
            return USM_EINPUT;
        }
        if (st != USM_OK || usm_steady_count(s) == 0) {
            snprintf(out->error, USM_MSG_LEN, "%s", usm_steady_message(s));
            return USM_OK;
        }
        out->sol = *usm_steady_root(s, 0);
        out->roots = warm ? 0 : (int)usm_steady_count(s);
    }
    out->exists = 1;
    if (!floquet)
        return USM_OK;
    if (usm_floquet_compute(f, p, &out->sol, t0, floquet_opt, &out->floquet) != USM_OK)
        snprintf(out->error, USM_MSG_LEN, "floquet: %.240s", usm_floquet_message(f));
    else if (!isfinite(out->floquet.max_modulus))
        snprintf(out->error, USM_MSG_LEN, "floquet: the multipliers are not finite");
    else
        out->has_floquet = 1;
    return USM_OK;
}

int usm_point_evaluate(usm_steady *s, usm_floquet *f, const usm_params *p,
                       const usm_steady_options *steady_opt, const usm_steady_solution *root,
                       int floquet, double t0, const usm_floquet_options *floquet_opt,
                       usm_point *out)
{
    return point_evaluate(s, f, p, steady_opt, root, 0, floquet, t0, floquet_opt, out);
}

int usm_point_evaluate_warm(usm_steady *s, usm_floquet *f, const usm_params *p,
                            const usm_steady_options *steady_opt,
                            const usm_steady_solution *guess, int floquet, double t0,
                            const usm_floquet_options *floquet_opt, usm_point *out)
{
    return point_evaluate(s, f, p, steady_opt, guess, 1, floquet, t0, floquet_opt, out);
}

const char *usm_point_op_class_name(usm_point_op_class cls)
{
    switch (cls) {
    case USM_POINT_OP_NOT_EVALUATED:
        return "not_evaluated";
    case USM_POINT_OP_STABLE:
        return "operating_point";
    case USM_POINT_OP_NO_STABLE_ROOT:
        return "no_stable_root";
    case USM_POINT_OP_DOES_NOT_START:
        return "does_not_start";
    case USM_POINT_OP_UNKNOWN:
        return "unknown";
    case USM_POINT_OP_NO_SOLUTION:
        return "no_solution";
    }
    return NULL;
}

int usm_point_evaluate_op(usm_steady *s, usm_floquet *f, const usm_model *m,
                          const usm_params *p, double t0, const usm_floquet_options *floquet_opt,
                          const usm_op_options *op_opt, usm_point *out)
{
    const int rc = point_evaluate(s, f, p, NULL, NULL, 0, 0, t0, floquet_opt, out);
    usm_point_op *op = &out->op;
    memset(op, 0, sizeof *op);
    out->has_op = 1;
    op->index = -1;
    op->reason = USM_OP_UNDECIDED;
    op->starts_from_rest = -1;
    if (rc != USM_OK)
        return rc;
    if (!out->exists) {
        op->cls = USM_POINT_OP_NO_SOLUTION;
        snprintf(op->message, USM_MSG_LEN, "no stationary solution");
        return USM_OK;
    }
    const size_t n = usm_steady_count(s);
    usm_floquet_result *fl = malloc(n * sizeof *fl);
    if (!fl) {
        op->cls = USM_POINT_OP_UNKNOWN;
        snprintf(op->message, USM_MSG_LEN, "out of memory");
        snprintf(out->error, USM_MSG_LEN, "out of memory");
        return USM_OK;
    }
    const int fr = usm_floquet_roots(f, p, s, t0, floquet_opt, fl);
    /* root 0's multipliers are those usm_point_evaluate gives */
    if (fr == USM_OK || usm_floquet_message(f)[0] == '\0' ||
        strncmp(usm_floquet_message(f), "root #1 ", 8) != 0) {
        out->floquet = fl[0];
        if (isfinite(out->floquet.max_modulus))
            out->has_floquet = 1;
        else
            snprintf(out->error, USM_MSG_LEN, "floquet: the multipliers are not finite");
    } else
        snprintf(out->error, USM_MSG_LEN, "floquet: %.240s", usm_floquet_message(f));
    if (fr != USM_OK) {
        op->cls = USM_POINT_OP_UNKNOWN;
        snprintf(op->message, USM_MSG_LEN, "multipliers: %.240s", usm_floquet_message(f));
        free(fl);
        return USM_OK;
    }
    for (size_t k = 0; k < n; ++k)
        op->stable_roots += fl[k].stable != 0;
    usm_op_result res;
    const int orc = usm_operating_point(m, p, s, fl, op_opt, &res);
    if (orc == USM_EINPUT) {
        snprintf(out->error, USM_MSG_LEN, "%s", res.message);
        free(fl);
        return USM_EINPUT;
    }
    point_op_classify(op, orc, &res, s, fl, NULL);
    free(fl);
    return USM_OK;
}

/* ---- options ----------------------------------------------------------------------- */

double usm_map_axis_value(const usm_map_axis *a, int i)
{
    return usm_grid_value(a->from, a->to, i, a->points);
}

void usm_map_options_default(usm_map_options *opt)
{
    memset(opt, 0, sizeof *opt);
    opt->x = (usm_map_axis){usm_param_table[USM_P_f].name, 30000.0, 46000.0, 33};
    opt->y = (usm_map_axis){usm_param_table[USM_P_T].name, 0.0, 0.008, 33};
    opt->t0 = 0.0;
    usm_floquet_options_default(&opt->floquet);
    opt->threads = 2;
    opt->boundaries = 1;
    opt->warm_start = 0;
    opt->operating_point = 1;
    usm_op_options_default(&opt->op);
}

const char *usm_map_boundary_name(usm_map_boundary_kind kind)
{
    switch (kind) {
    case USM_MAP_BOUNDARY_EXISTENCE:
        return "existence";
    case USM_MAP_BOUNDARY_STABILITY:
        return "stability";
    case USM_MAP_BOUNDARY_STICK:
        return "stick";
    }
    return "unknown";
}

int usm_map_indicator(usm_map_boundary_kind kind, const usm_point *pt)
{
    switch (kind) {
    case USM_MAP_BOUNDARY_EXISTENCE:
        return pt->exists;
    case USM_MAP_BOUNDARY_STABILITY:
        return pt->has_floquet ? pt->floquet.max_modulus < 1.0 : -1;
    case USM_MAP_BOUNDARY_STICK:
        return pt->exists ? pt->sol.stick_admissible : -1;
    }
    return -1;
}

struct usm_map {
    const usm_model *m;
    usm_params p;
    usm_map_options opt;
    const usm_param_info *xi, *yi;
    usm_map_cell *cells;       /* cells[j * nx + i] */
    usm_map_boundary_point *bnd[USM_MAP_NBOUNDARY];
    size_t nbnd[USM_MAP_NBOUNDARY];
    size_t floquet_failures;
    char msg[USM_MSG_LEN];
    /* during a run: per column and kind, the changes found there */
    usm_map_boundary_point *col_bnd[USM_MAP_NBOUNDARY];
    int *col_count[USM_MAP_NBOUNDARY];
    int *col_failures;
    char *col_msg;             /* per column: why it stopped (USM_EINPUT) */
    progress_meter meter;      /* the grid's points, by column (under the pool's lock) */
};

usm_map *usm_map_alloc(const usm_model *m)
{
    usm_map *map = calloc(1, sizeof *map);
    if (map)
        map->m = m;
    return map;
}

static void clear(usm_map *map)
{
    free(map->cells);
    map->cells = NULL;
    for (int k = 0; k < USM_MAP_NBOUNDARY; ++k) {
        free(map->bnd[k]);
        free(map->col_bnd[k]);
        free(map->col_count[k]);
        map->bnd[k] = NULL;
        map->col_bnd[k] = NULL;
        map->col_count[k] = NULL;
        map->nbnd[k] = 0;
    }
    free(map->col_failures);
    free(map->col_msg);
    map->col_failures = NULL;
    map->col_msg = NULL;
    map->floquet_failures = 0;
}

void usm_map_free(usm_map *map)
{
    if (!map)
        return;
    clear(map);
    free(map);
}

static int check_axis(usm_map *map, const usm_map_axis *a, const char *field,
                      const usm_param_info **info)
{
    if (!a->name || !(*info = usm_params_find(a->name))) {
        snprintf(map->msg, USM_MSG_LEN, "%s: unknown parameter \"%s\"", field,
                 a->name ? a->name : "(null)");
        return USM_EINPUT;
    }
    if (!(isfinite(a->from) && isfinite(a->to))) {
        snprintf(map->msg, USM_MSG_LEN, "%s-from/%s-to: the range must be finite", field, field);
        return USM_EINPUT;
    }
    if (!isfinite(a->to - a->from)) { /* the grid's spacing would be infinite */
        snprintf(map->msg, USM_MSG_LEN, "%s-from/%s-to: the width to - from overflows (%g to "
                 "%g; at most %g)", field, field, a->from, a->to, DBL_MAX);
        return USM_EINPUT;
    }
    if (!(a->to != a->from)) {
        snprintf(map->msg, USM_MSG_LEN, "%s-to: must differ from %s-from (%g)", field, field,
                 a->from);
        return USM_EINPUT;
    }
    if (a->points < 2 || a->points > MAX_AXIS_POINTS) {
        snprintf(map->msg, USM_MSG_LEN, "%s-points: need 2 ... %d points, got %d", field,
                 MAX_AXIS_POINTS, a->points);
        return USM_EINPUT;
    }
    return USM_OK;
}

/* The constraints are signs and I_yy == I_xx, so checking the corners of the
 * grid checks every point of it. */
static int check_options(usm_map *map, const usm_params *p, const usm_map_options *opt)
{
    char lib[USM_MSG_LEN];
    if (!p || !opt) {
        snprintf(map->msg, USM_MSG_LEN, "%s: must not be NULL", !p ? "params" : "options");
        return USM_EINPUT;
    }
    if (check_axis(map, &opt->x, "x", &map->xi) != USM_OK ||
        check_axis(map, &opt->y, "y", &map->yi) != USM_OK)
        return USM_EINPUT;
    if (map->xi == map->yi) {
        snprintf(map->msg, USM_MSG_LEN, "y: %s must differ from x", map->yi->name);
        return USM_EINPUT;
    }
    if (opt->threads < 1 || opt->threads > POOL_MAX_THREADS) {
        snprintf(map->msg, USM_MSG_LEN, "threads: must be between 1 and %d, got %d",
                 POOL_MAX_THREADS, opt->threads);
        return USM_EINPUT;
    }
    if (!isfinite(opt->t0)) {
        snprintf(map->msg, USM_MSG_LEN, "t0: must be a finite number");
        return USM_EINPUT;
    }
    for (int c = 0; c < 4; ++c) {
        usm_params q = *p;
        const double x = c & 1 ? opt->x.to : opt->x.from, y = c & 2 ? opt->y.to : opt->y.from;
        *usm_params_field(&q, map->xi) = x;
        *usm_params_field(&q, map->yi) = y;
        if (usm_params_check(&q, map->m, lib) != USM_OK || usm_params_check_ideal(&q, lib) != USM_OK) {
            snprintf(map->msg, USM_MSG_LEN, "at %s = %g, %s = %g: %.180s", map->xi->name, x,
                     map->yi->name, y, lib);
            return USM_EINPUT;
        }
    }
    return USM_OK;
}

/* ---- one column (a task of the pool) ---------------------------------------------- */

typedef point_worker worker;

static void *worker_alloc(void *ctx)
{
    const usm_map *map = ctx;
    return point_worker_alloc(map->m);
}

/* Point (x, y); guess: a neighbouring point's primary root for the warm
 * start (map->opt.warm_start), or NULL. */
static int eval_at(usm_map *map, worker *w, size_t column, double x, double y, int floquet,
                   const usm_steady_solution *guess, usm_point *pt)
{
    usm_params q = map->p;
    *usm_params_field(&q, map->xi) = x;
    *usm_params_field(&q, map->yi) = y;
    /* floquet == 2: a cell of the grid with its operating point */
    const int st =
        floquet == 2 ? usm_point_evaluate_op(w->steady, w->floquet, map->m, &q, map->opt.t0,
                                             &map->opt.floquet, &map->opt.op, pt)
        : map->opt.warm_start
            ? usm_point_evaluate_warm(w->steady, w->floquet, &q, NULL, guess, floquet,
                                      map->opt.t0, &map->opt.floquet, pt)
            : usm_point_evaluate(w->steady, w->floquet, &q, NULL, NULL, floquet, map->opt.t0,
                                 &map->opt.floquet, pt);
    if (st != USM_OK) {
        snprintf(map->col_msg + column * USM_MSG_LEN, USM_MSG_LEN, "at %s = %g, %s = %g: %.180s",
                 map->xi->name, x, map->yi->name, y, pt->error);
        return USM_EINPUT;
    }
    return USM_OK;
}

/* The indicator of one boundary kind at y on the column x. */
typedef struct boundary_fn {
    usm_map *map;
    worker *w;
    size_t column;
    usm_map_boundary_kind kind;
    double x;
} boundary_fn;

static int boundary_indicator(double y, void *ctx)
{
    const boundary_fn *c = ctx;
    usm_point pt;
    if (eval_at(c->map, c->w, c->column, c->x, y, c->kind == USM_MAP_BOUNDARY_STABILITY, NULL,
                &pt) != USM_OK)
        return USM_ROOT_FAILED;
    const int im = usm_map_indicator(c->kind, &pt);
    return im < 0 ? USM_ROOT_UNDEFINED : im;
}

/* The change of `kind` between y = a (indicator ia) and y = b, by the shared
 * locator's bisection (core/root.h: the indicators are yes/no, nothing to
 * interpolate).  1 and *y_out, 0 when the indicator became undefined, -1 on
 * bad input. */
static int bisect(usm_map *map, worker *w, size_t column, usm_map_boundary_kind kind, double x,
                  double a, int ia, double b, double *y_out)
{
    boundary_fn c = {map, w, column, kind, x};
    return usm_root_bisect(boundary_indicator, &c, a, ia, b,
                           BISECT_RTOL * fabs(map->opt.y.to - map->opt.y.from), BISECT_MAXIT,
                           y_out);
}

static int column_task(void *ctx, void *state, size_t i)
{
    usm_map *map = ctx;
    worker *w = state;
    const size_t nx = (size_t)map->opt.x.points, ny = (size_t)map->opt.y.points;
    const double x = usm_map_axis_value(&map->opt.x, (int)i);
    for (size_t j = 0; j < ny; ++j) {
        usm_map_cell *c = &map->cells[j * nx + i];
        c->x = x;
        c->y = usm_map_axis_value(&map->opt.y, (int)j);
        const usm_map_cell *prev = j > 0 ? &map->cells[(j - 1) * nx + i] : NULL;
        if (eval_at(map, w, i, x, c->y, map->opt.operating_point ? 2 : 1,
                    prev && prev->point.exists ? &prev->point.sol : NULL,
                    &c->point) != USM_OK)
            return USM_EINPUT;
        map->col_failures[i] += c->point.exists && !c->point.has_floquet;
    }
    if (!map->opt.boundaries)
        return USM_OK;
    for (int kind = 0; kind < USM_MAP_NBOUNDARY; ++kind) {
        usm_map_boundary_point *out = map->col_bnd[kind] + i * (ny - 1);
        int n = 0;
        for (size_t j = 0; j + 1 < ny; ++j) {
            const usm_map_cell *c0 = &map->cells[j * nx + i], *c1 = &map->cells[(j + 1) * nx + i];
            const int i0 = usm_map_indicator((usm_map_boundary_kind)kind, &c0->point);
            const int i1 = usm_map_indicator((usm_map_boundary_kind)kind, &c1->point);
            double y;
            if (i0 < 0 || i1 < 0 || i0 == i1)
                continue;
            const int rc = bisect(map, w, i, (usm_map_boundary_kind)kind, x, c0->y, i0, c1->y, &y);
            if (rc < 0)
                return USM_EINPUT;
            if (rc > 0) {
                out[n] = (usm_map_boundary_point){x, y, (int)i, n};
                ++n;
            }
        }
        map->col_count[kind][i] = n;
    }
    return USM_OK;
}

/* ---- the run ------------------------------------------------------------------------ */

static void column_done(void *ctx, size_t i)
{
    usm_map *map = ctx;
    (void)i;
    progress_add(&map->meter, (long)map->opt.y.points);
}

static int cmp_boundary(const void *pa, const void *pb)
{
    const usm_map_boundary_point *a = pa, *b = pb;
    if (a->k != b->k)
        return a->k - b->k;
    return a->column - b->column;
}

static int collect_boundaries(usm_map *map)
{
    const size_t nx = (size_t)map->opt.x.points, ny = (size_t)map->opt.y.points;
    for (int k = 0; k < USM_MAP_NBOUNDARY; ++k) {
        size_t n = 0;
        for (size_t i = 0; i < nx; ++i)
            n += (size_t)map->col_count[k][i];
        if (!(map->bnd[k] = malloc((n ? n : 1) * sizeof *map->bnd[k])))
            return -1;
        n = 0;
        for (size_t i = 0; i < nx; ++i)
            for (int c = 0; c < map->col_count[k][i]; ++c)
                map->bnd[k][n++] = map->col_bnd[k][i * (ny - 1) + (size_t)c];
        qsort(map->bnd[k], n, sizeof *map->bnd[k], cmp_boundary);
        map->nbnd[k] = n;
    }
    return 0;
}

int usm_map_run(usm_map *map, const usm_params *p, const usm_map_options *opt)
{
    clear(map);
    map->msg[0] = '\0';
    if (check_options(map, p, opt) != USM_OK)
        return USM_EINPUT;
    map->p = *p;
    map->opt = *opt;
    const size_t nx = (size_t)opt->x.points, ny = (size_t)opt->y.points;
    int ok = (map->cells = calloc(nx * ny, sizeof *map->cells)) != NULL &&
             (map->col_failures = calloc(nx, sizeof *map->col_failures)) != NULL &&
             (map->col_msg = calloc(nx, USM_MSG_LEN)) != NULL;
    for (int k = 0; k < USM_MAP_NBOUNDARY && ok; ++k)
        ok = (map->col_bnd[k] = calloc(nx * (ny - 1), sizeof *map->col_bnd[k])) != NULL &&
             (map->col_count[k] = calloc(nx, sizeof *map->col_count[k])) != NULL;
    if (!ok) {
        clear(map);
        snprintf(map->msg, USM_MSG_LEN, "out of memory for a %zu x %zu map", nx, ny);
        return USM_EFAILED;
    }
    progress_start(&map->meter, &opt->progress, (long)(nx * ny), 0, "points");
    pool_job job = {nx, opt->threads, map, worker_alloc, point_worker_free, column_task,
                    column_done};
    int status = pool_run(&job, map->msg);
    if (status == USM_EINPUT)
        for (size_t i = 0; i < nx; ++i)
            if (map->col_msg[i * USM_MSG_LEN]) {
                snprintf(map->msg, USM_MSG_LEN, "%s", map->col_msg + i * USM_MSG_LEN);
                break;
            }
    if (status == USM_OK && opt->boundaries && collect_boundaries(map) != 0) {
        snprintf(map->msg, USM_MSG_LEN, "out of memory for the boundaries");
        status = USM_EFAILED;
    }
    for (size_t i = 0; status == USM_OK && i < nx; ++i)
        map->floquet_failures += (size_t)map->col_failures[i];
    if (status != USM_OK) {
        char keep[USM_MSG_LEN];
        memcpy(keep, map->msg, USM_MSG_LEN);
        clear(map);
        memcpy(map->msg, keep, USM_MSG_LEN);
    }
    return status;
}

const usm_map_cell *usm_map_cell_at(const usm_map *map, int i, int j)
{
    if (!map->cells || i < 0 || j < 0 || i >= map->opt.x.points || j >= map->opt.y.points)
        return NULL;
    return &map->cells[(size_t)j * (size_t)map->opt.x.points + (size_t)i];
}

size_t usm_map_boundary_count(const usm_map *map, usm_map_boundary_kind kind)
{
    return (int)kind >= 0 && kind < USM_MAP_NBOUNDARY ? map->nbnd[kind] : 0;
}

const usm_map_boundary_point *usm_map_boundary_at(const usm_map *map,
                                                  usm_map_boundary_kind kind, size_t q)
{
    return usm_map_boundary_count(map, kind) > q ? &map->bnd[kind][q] : NULL;
}

size_t usm_map_floquet_failures(const usm_map *map) { return map->floquet_failures; }

const char *usm_map_message(const usm_map *map) { return map->msg; }
