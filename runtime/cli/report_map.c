/* Stability map over a 2-D parameter grid, computed by worker threads. */
#define _POSIX_C_SOURCE 200809L

#include "report_map.h"

#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "json_out.h"

/* Bisection stops when the bracket is this fraction of the y range. */
#define BISECT_RTOL 1e-7
#define BISECT_MAXIT 60

const char *report_boundary_name(int kind)
{
    switch (kind) {
    case REPORT_BOUNDARY_EXISTENCE: return "existence";
    case REPORT_BOUNDARY_STABILITY: return "stability";
    case REPORT_BOUNDARY_STICK: return "stick";
    default: return "?";
    }
}

double report_axis_value(const report_axis *a, int i)
{
    if (i <= 0)
        return a->from;
    if (i >= a->points - 1)
        return a->to;
    return a->from + (a->to - a->from) * (double)i / (double)(a->points - 1);
}

int report_axis_check(const report_axis *a, const char *field, char msg[CLI_MSG_LEN])
{
    if (!a->param) {
        cli_msg(msg, "%s: missing parameter name", field);
        return USM_EINPUT;
    }
    if (!(isfinite(a->from) && isfinite(a->to))) {
        cli_msg(msg, "%s-from/%s-to: the range must be finite", field, field);
        return USM_EINPUT;
    }
    if (!(a->to != a->from)) {
        cli_msg(msg, "%s-to: must differ from %s-from (%g)", field, field, a->from);
        return USM_EINPUT;
    }
    if (a->points < 2 || a->points > 100000) {
        cli_msg(msg, "%s-points: need 2 ... 100000 points, got %d", field, a->points);
        return USM_EINPUT;
    }
    return USM_OK;
}

/* ---- one worker ------------------------------------------------------------ */

typedef struct map_shared {
    report_map *map;
    pthread_mutex_t lock;
    int next_column;
    int failed;       /* USM_OK or the first error status */
    char msg[CLI_MSG_LEN];
    /* per column, per kind: boundary points found (at most y.points - 1) */
    report_boundary_point *col_bnd[REPORT_NBOUNDARY];
    int *col_count[REPORT_NBOUNDARY];
    size_t floquet_failures;
} map_shared;

typedef struct map_worker {
    map_shared *sh;
    usm_steady *steady;
    usm_floquet *floquet;
    usm_params p;
    size_t floquet_failures;
} map_worker;

static void fail(map_shared *sh, int status, const char *text)
{
    pthread_mutex_lock(&sh->lock);
    if (sh->failed == USM_OK) {
        sh->failed = status;
        cli_msg(sh->msg, "%s", text);
    }
    pthread_mutex_unlock(&sh->lock);
}

int report_map_eval(usm_steady *s, usm_floquet *f, const usm_params *p, double t0,
                    int want_floquet, report_map_cell *c, char msg[USM_MSG_LEN])
{
    return report_map_eval_opt(s, f, p, t0, NULL, want_floquet, c, msg);
}

int report_map_eval_opt(usm_steady *s, usm_floquet *f, const usm_params *p, double t0,
                        const usm_floquet_options *fopt, int want_floquet, report_map_cell *c,
                        char msg[USM_MSG_LEN])
{
    const usm_steady_solution *sol;
    usm_floquet_result res;
    int st;
    c->exists = c->roots = c->floquet_ok = c->stable = c->stick_admissible = 0;
    c->max_modulus = c->theta = c->rotor_speed = c->mu_used = NAN;
    st = usm_steady_solve(s, p, NULL);
    if (st == USM_EINPUT) {
        snprintf(msg, USM_MSG_LEN, "%s", usm_steady_message(s));
        return USM_EINPUT;
    }
    if (st != USM_OK || usm_steady_count(s) == 0)
        return USM_OK;
    sol = usm_steady_root(s, 0);
    c->exists = 1;
    c->roots = (int)usm_steady_count(s);
    c->theta = sol->theta;
    c->rotor_speed = sol->rotor_speed;
    c->mu_used = sol->mu_used;
    c->stick_admissible = sol->stick_admissible;
    if (want_floquet && usm_floquet_compute(f, p, sol, t0, fopt, &res) == USM_OK &&
        isfinite(res.max_modulus)) {
        c->floquet_ok = 1;
        c->max_modulus = res.max_modulus;
        c->stable = res.stable;
    }
    return USM_OK;
}

int report_map_indicator(int kind, const report_map_cell *c)
{
    switch (kind) {
    case REPORT_BOUNDARY_EXISTENCE: return c->exists;
    case REPORT_BOUNDARY_STABILITY: return c->floquet_ok ? c->max_modulus < 1.0 : -1;
    case REPORT_BOUNDARY_STICK: return c->exists ? c->stick_admissible : -1;
    default: return -1;
    }
}

/* Solve at (x, y) of the map.  USM_OK (cell filled; exists may be 0) or
 * USM_EINPUT (recorded as the map's failure). */
static int eval_point(map_worker *w, double x, double y, int want_floquet, report_map_cell *c)
{
    const report_map *map = w->sh->map;
    char lib[USM_MSG_LEN];
    w->p = map->params;
    *usm_params_field(&w->p, map->x.param) = x;
    *usm_params_field(&w->p, map->y.param) = y;
    c->x = x;
    c->y = y;
    if (report_map_eval_opt(w->steady, w->floquet, &w->p, map->t0, map->floquet, want_floquet, c,
                            lib) != USM_OK) {
        char text[CLI_MSG_LEN];
        cli_msg(text, "at %s = %g, %s = %g: %s", map->x.param->name, x, map->y.param->name, y,
                lib);
        fail(w->sh, USM_EINPUT, text);
        return USM_EINPUT;
    }
    if (want_floquet && c->exists && !c->floquet_ok)
        ++w->floquet_failures;
    return USM_OK;
}

/* Locate the change of `kind` between y = a (indicator ia) and y = b.
 * 1 and *y_out on success, 0 when the indicator became undefined. */
static int bisect(map_worker *w, int kind, double x, double a, int ia, double b, double *y_out)
{
    const report_map *map = w->sh->map;
    const double tol = BISECT_RTOL * fabs(map->y.to - map->y.from);
    report_map_cell c;
    for (int it = 0; it < BISECT_MAXIT && fabs(b - a) > tol; ++it) {
        double m = 0.5 * (a + b);
        int im;
        if (eval_point(w, x, m, kind == REPORT_BOUNDARY_STABILITY, &c) != USM_OK)
            return 0;
        im = report_map_indicator(kind, &c);
        if (im < 0)
            return 0;
        if (im == ia)
            a = m;
        else
            b = m;
    }
    *y_out = 0.5 * (a + b);
    return 1;
}

static void do_column(map_worker *w, int i)
{
    map_shared *sh = w->sh;
    report_map *map = sh->map;
    const int nx = map->x.points, ny = map->y.points;
    const double x = report_axis_value(&map->x, i);
    for (int j = 0; j < ny; ++j)
        if (eval_point(w, x, report_axis_value(&map->y, j), 1, &map->cells[(size_t)j * nx + i]) !=
            USM_OK)
            return;
    if (!map->boundaries)
        return;
    for (int kind = 0; kind < REPORT_NBOUNDARY; ++kind) {
        report_boundary_point *out = sh->col_bnd[kind] + (size_t)i * (size_t)(ny - 1);
        int n = 0;
        for (int j = 0; j + 1 < ny; ++j) {
            const report_map_cell *c0 = &map->cells[(size_t)j * nx + i];
            const report_map_cell *c1 = &map->cells[(size_t)(j + 1) * nx + i];
            int i0 = report_map_indicator(kind, c0), i1 = report_map_indicator(kind, c1);
            double y;
            if (i0 < 0 || i1 < 0 || i0 == i1)
                continue;
            if (bisect(w, kind, x, c0->y, i0, c1->y, &y)) {
                out[n].x = x;
                out[n].y = y;
                out[n].column = i;
                out[n].k = n;
                ++n;
            }
        }
        sh->col_count[kind][i] = n;
    }
}

static void *worker_main(void *arg)
{
    map_worker *w = arg;
    map_shared *sh = w->sh;
    for (;;) {
        int i;
        pthread_mutex_lock(&sh->lock);
        i = sh->failed == USM_OK && sh->next_column < sh->map->x.points ? sh->next_column++ : -1;
        pthread_mutex_unlock(&sh->lock);
        if (i < 0)
            break;
        do_column(w, i);
    }
    return NULL;
}

/* ---- driver ------------------------------------------------------------------ */

/* The constraints are signs and I_yy == I_xx, so checking the corners of
 * the grid checks every point of it. */
static int check_corners(const report_map *map, char msg[CLI_MSG_LEN])
{
    for (int c = 0; c < 4; ++c) {
        usm_params p = map->params;
        char lib[USM_MSG_LEN];
        double x = c & 1 ? map->x.to : map->x.from, y = c & 2 ? map->y.to : map->y.from;
        *usm_params_field(&p, map->x.param) = x;
        *usm_params_field(&p, map->y.param) = y;
        if (usm_params_check(&p, map->model, lib) != USM_OK) {
            cli_msg(msg, "at %s = %g, %s = %g: %s", map->x.param->name, x, map->y.param->name, y,
                    lib);
            return USM_EINPUT;
        }
    }
    return USM_OK;
}

static int cmp_boundary(const void *pa, const void *pb)
{
    const report_boundary_point *a = pa, *b = pb;
    if (a->k != b->k)
        return a->k - b->k;
    return a->column - b->column;
}

int report_map_run(report_map *map, char msg[CLI_MSG_LEN])
{
    const size_t nx = (size_t)map->x.points, ny = (size_t)map->y.points;
    map_shared sh;
    map_worker *workers = NULL;
    pthread_t *tids = NULL;
    int nthreads = map->threads < 1 ? 1 : map->threads, started = 0, status = USM_OK;

    map->cells = NULL;
    for (int k = 0; k < REPORT_NBOUNDARY; ++k) {
        map->bnd[k] = NULL;
        map->nbnd[k] = 0;
    }
    map->floquet_failures = 0;
    if (report_axis_check(&map->x, "--x", msg) != USM_OK ||
        report_axis_check(&map->y, "--y", msg) != USM_OK)
        return USM_EINPUT;
    if (map->x.param == map->y.param) {
        cli_msg(msg, "--y %s: must differ from --x", map->y.param->name);
        return USM_EINPUT;
    }
    if (check_corners(map, msg) != USM_OK)
        return USM_EINPUT;
    if ((size_t)nthreads > nx)
        nthreads = (int)nx;

    memset(&sh, 0, sizeof sh);
    sh.map = map;
    sh.failed = USM_OK;
    if (pthread_mutex_init(&sh.lock, NULL) != 0) {
        cli_msg(msg, "map: cannot create a mutex");
        return USM_EFAILED;
    }
    map->cells = calloc(nx * ny, sizeof *map->cells);
    workers = calloc((size_t)nthreads, sizeof *workers);
    tids = calloc((size_t)nthreads, sizeof *tids);
    int ok = map->cells && workers && tids;
    for (int k = 0; k < REPORT_NBOUNDARY && ok; ++k) {
        sh.col_bnd[k] = calloc(nx * (ny - 1), sizeof *sh.col_bnd[k]);
        sh.col_count[k] = calloc(nx, sizeof *sh.col_count[k]);
        ok = sh.col_bnd[k] && sh.col_count[k];
    }
    for (int t = 0; t < nthreads && ok; ++t) {
        workers[t].sh = &sh;
        workers[t].steady = usm_steady_alloc(map->model);
        workers[t].floquet = usm_floquet_alloc(map->model);
        ok = workers[t].steady && workers[t].floquet;
    }
    if (!ok) {
        cli_msg(msg, "map: out of memory");
        status = USM_EFAILED;
        goto done;
    }
    /* Worker 0 runs on this thread; the others on their own. */
    for (int t = 1; t < nthreads; ++t) {
        if (pthread_create(&tids[t], NULL, worker_main, &workers[t]) != 0)
            break;
        started = t;
    }
    worker_main(&workers[0]);
    for (int t = 1; t <= started; ++t)
        pthread_join(tids[t], NULL);
    if (sh.failed != USM_OK) {
        cli_msg(msg, "%s", sh.msg);
        status = sh.failed;
        goto done;
    }
    for (int t = 0; t < nthreads; ++t)
        map->floquet_failures += workers[t].floquet_failures;
    for (int k = 0; k < REPORT_NBOUNDARY && map->boundaries; ++k) {
        size_t n = 0;
        for (size_t i = 0; i < nx; ++i)
            n += (size_t)sh.col_count[k][i];
        map->bnd[k] = malloc((n ? n : 1) * sizeof *map->bnd[k]);
        if (!map->bnd[k]) {
            cli_msg(msg, "map: out of memory");
            status = USM_EFAILED;
            goto done;
        }
        n = 0;
        for (size_t i = 0; i < nx; ++i)
            for (int c = 0; c < sh.col_count[k][i]; ++c)
                map->bnd[k][n++] = sh.col_bnd[k][i * (ny - 1) + (size_t)c];
        qsort(map->bnd[k], n, sizeof *map->bnd[k], cmp_boundary);
        map->nbnd[k] = n;
    }
done:
    for (int t = 0; workers && t < nthreads; ++t) {
        if (workers[t].steady)
            usm_steady_free(workers[t].steady);
        if (workers[t].floquet)
            usm_floquet_free(workers[t].floquet);
    }
    for (int k = 0; k < REPORT_NBOUNDARY; ++k) {
        free(sh.col_bnd[k]);
        free(sh.col_count[k]);
    }
    free(workers);
    free(tids);
    pthread_mutex_destroy(&sh.lock);
    if (status != USM_OK)
        report_map_free(map);
    return status;
}

void report_map_free(report_map *map)
{
    free(map->cells);
    map->cells = NULL;
    for (int k = 0; k < REPORT_NBOUNDARY; ++k) {
        free(map->bnd[k]);
        map->bnd[k] = NULL;
        map->nbnd[k] = 0;
    }
}

/* ---- output ------------------------------------------------------------------ */

static void put_num(FILE *out, double v)
{
    if (isfinite(v))
        fprintf(out, "%.10g", v);
    else
        fputs("nan", out);
}

int report_map_write_csv(const report_map *map, FILE *out)
{
    const int nx = map->x.points, ny = map->y.points;
    fprintf(out, "%s,%s,exists,roots,max_modulus,stable,theta,rotor_speed,mu_used,stick_admissible\n",
            map->x.param->name, map->y.param->name);
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            const report_map_cell *c = &map->cells[(size_t)j * nx + i];
            put_num(out, c->x);
            fputc(',', out);
            put_num(out, c->y);
            fprintf(out, ",%d,%d,", c->exists, c->roots);
            put_num(out, c->max_modulus);
            fprintf(out, ",%d,", c->floquet_ok ? c->stable : 0);
            put_num(out, c->theta);
            fputc(',', out);
            put_num(out, c->rotor_speed);
            fputc(',', out);
            put_num(out, c->mu_used);
            fprintf(out, ",%d\n", c->exists ? c->stick_admissible : 0);
        }
    return ferror(out) ? -1 : 0;
}

int report_map_write_boundary_csv(const report_map *map, int kind, FILE *out)
{
    const report_boundary_point *b = map->bnd[kind];
    const size_t n = map->nbnd[kind];
    fprintf(out, "%s,%s\n", map->x.param->name, map->y.param->name);
    for (size_t q = 0; q < n; ++q) {
        if (q > 0 && b[q].k != b[q - 1].k)
            fputs("\n\n", out); /* next block (gnuplot index) */
        else if (q > 0 && b[q].column != b[q - 1].column + 1)
            fputc('\n', out); /* a gap: columns without this change */
        put_num(out, b[q].x);
        fputc(',', out);
        put_num(out, b[q].y);
        fputc('\n', out);
    }
    return ferror(out) ? -1 : 0;
}

static json_t *axis_json(const report_axis *a)
{
    json_t *obj = json_object();
    int ok = obj != NULL;
    cli_json_put(obj, "name", json_string(a->param->name), &ok);
    cli_json_put(obj, "from", cli_json_real(a->from), &ok);
    cli_json_put(obj, "to", cli_json_real(a->to), &ok);
    cli_json_put(obj, "points", json_integer(a->points), &ok);
    if (!ok) {
        json_decref(obj);
        return NULL;
    }
    return obj;
}

json_t *report_map_json(const report_map *map)
{
    const size_t n = (size_t)map->x.points * (size_t)map->y.points;
    json_t *obj = json_object(), *pts = json_array(), *bnds = json_object();
    int ok = obj && pts && bnds;
    cli_json_put(obj, "model", json_string(map->model->name), &ok);
    cli_json_put(obj, "parameters", cli_json_params(&map->params), &ok);
    cli_json_put(obj, "t0", cli_json_real(map->t0), &ok);
    cli_json_put(obj, "x", axis_json(&map->x), &ok);
    cli_json_put(obj, "y", axis_json(&map->y), &ok);
    for (size_t q = 0; q < n && ok; ++q) {
        const report_map_cell *c = &map->cells[q];
        json_t *pt = json_object();
        ok = pt != NULL;
        cli_json_put(pt, "x", cli_json_real(c->x), &ok);
        cli_json_put(pt, "y", cli_json_real(c->y), &ok);
        cli_json_put(pt, "exists", json_boolean(c->exists), &ok);
        cli_json_put(pt, "roots", json_integer(c->roots), &ok);
        if (c->exists) {
            cli_json_put(pt, "theta", cli_json_real(c->theta), &ok);
            cli_json_put(pt, "rotor_speed", cli_json_real(c->rotor_speed), &ok);
            cli_json_put(pt, "mu_used", cli_json_real(c->mu_used), &ok);
            cli_json_put(pt, "stick_admissible", json_boolean(c->stick_admissible), &ok);
        }
        if (c->floquet_ok) {
            cli_json_put(pt, "max_modulus", cli_json_real(c->max_modulus), &ok);
            cli_json_put(pt, "stable", json_boolean(c->stable), &ok);
        }
        if (json_array_append_new(pts, pt) != 0)
            ok = 0;
    }
    for (int k = 0; k < REPORT_NBOUNDARY && ok; ++k) {
        json_t *arr = json_array();
        ok = arr != NULL;
        for (size_t q = 0; q < map->nbnd[k] && ok; ++q) {
            json_t *pair = json_pack("[f,f]", map->bnd[k][q].x, map->bnd[k][q].y);
            if (!pair || json_array_append_new(arr, pair) != 0)
                ok = 0;
        }
        cli_json_put(bnds, report_boundary_name(k), arr, &ok);
    }
    cli_json_put(obj, "points", pts, &ok);
    pts = NULL;
    cli_json_put(obj, "boundaries", bnds, &ok);
    bnds = NULL;
    if (!ok) {
        json_decref(obj);
        return NULL;
    }
    return obj;
}
