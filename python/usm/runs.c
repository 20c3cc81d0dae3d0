/* runs.c: the analyses of the Python module as the usm command runs them
 * (runs.h).  Each function repeats the library calls of its command's run()
 * in runtime/cli/ and writes the result with the same writer, into an
 * in-memory stream instead of stdout; messages carry the command's prefixes. */
#include "runs.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

void usmpy_out_init(usmpy_out *o)
{
    memset(o, 0, sizeof *o);
}

void usmpy_out_free(usmpy_out *o)
{
    free(o->json);
    free(o->rows);
    o->json = NULL;
    o->rows = NULL;
}

static void fail(usmpy_out *o, int status, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(o->msg, sizeof o->msg, fmt, ap);
    va_end(ap);
    o->status = status;
}

/* An in-memory stream for a writer; finish() closes it and keeps the text. */
typedef struct mem {
    FILE *f;
    char *buf;
    size_t len;
} mem;

static int mem_open(mem *m, usmpy_out *o)
{
    m->buf = NULL;
    m->len = 0;
    if (!(m->f = open_memstream(&m->buf, &m->len))) {
        fail(o, USM_EFAILED, "out of memory");
        return -1;
    }
    return 0;
}

/* rc: the writer's return.  The text becomes o->json on success. */
static int mem_finish(mem *m, int rc, usmpy_out *o)
{
    int bad = rc != 0 || ferror(m->f);
    if (fclose(m->f) != 0)
        bad = 1;
    if (bad || !m->buf) {
        free(m->buf);
        fail(o, USM_EFAILED, "out of memory or write error");
        return -1;
    }
    o->json = m->buf;
    o->len = m->len;
    return 0;
}

/* ---- steady (steady_cmd.c) ----------------------------------------------------- */

/* The state of one steady analysis, kept until its JSON is asked for. */
struct usmpy_steady_state {
    const usm_model *model;
    usm_params params;
    usm_steady *s;
    usm_floquet_result *res;
    usm_op_result op;
    int status;       /* USM_OK: roots, multipliers and op; USM_ENOSOLUTION: error */
};

void usmpy_steady_state_free(usmpy_steady_state *st)
{
    if (!st)
        return;
    free(st->res);
    usm_steady_free(st->s);
    free(st);
}

usmpy_steady_state *usmpy_steady_run(const usm_model *model, const usm_params *p, double t0,
                                     const usm_floquet_options *fo, const usm_op_options *opo,
                                     usmpy_out *o)
{
    usm_floquet *fl = NULL;
    const char *bad;
    int status;
    usmpy_steady_state *st = calloc(1, sizeof *st);
    usmpy_out_init(o);
    if (!st || !(st->s = usm_steady_alloc(model))) {
        free(st);
        fail(o, USM_EFAILED, "out of memory");
        return NULL;
    }
    st->model = model;
    st->params = *p;
    p = &st->params;
    status = usm_steady_solve(st->s, p, NULL);
    if (status == USM_ENOSOLUTION) {
        fail(o, USM_ENOSOLUTION, "no stationary solution: %s", usm_steady_message(st->s));
        st->status = USM_ENOSOLUTION; /* --json prints converged = false */
        return st;
    }
    if (status == USM_EINPUT) {
        fail(o, USM_EINPUT, "%s", usm_steady_message(st->s));
        goto fail;
    }
    if (status != USM_OK || usm_steady_count(st->s) == 0) {
        fail(o, USM_EFAILED, "steady: %s", usm_steady_message(st->s));
        goto fail;
    }
    if (!(fl = usm_floquet_alloc(model)) ||
        !(st->res = malloc(usm_steady_count(st->s) * sizeof *st->res))) {
        fail(o, USM_EFAILED, "out of memory");
        goto fail;
    }
    status = usm_floquet_roots(fl, p, st->s, t0, fo, st->res);
    if (status != USM_OK) {
        fail(o, status == USM_EINPUT ? USM_EINPUT : USM_EFAILED, "floquet: %s",
             usm_floquet_message(fl));
        goto fail;
    }
    for (size_t k = 0; k < usm_steady_count(st->s); ++k)
        if ((bad = usm_steady_nonfinite(usm_steady_root(st->s, k), &st->res[k]))) {
            fail(o, USM_EFAILED, "%s", bad);
            goto fail;
        }
    status = usm_operating_point(model, p, st->s, st->res, opo, &st->op);
    if (status != USM_OK) {
        fail(o, status, "%s", st->op.message);
        goto fail;
    }
    usm_floquet_free(fl);
    st->status = o->status = USM_OK;
    return st;
fail:
    usm_floquet_free(fl);
    usmpy_steady_state_free(st);
    return NULL;
}

void usmpy_steady_json(const usmpy_steady_state *st, usmpy_out *o)
{
    /* designated: fields the report gains stay zero (absent) here */
    usm_steady_report rep = {.model = st->model, .params = &st->params, .steady = st->s};
    mem m;
    usmpy_out_init(o);
    if (st->status == USM_ENOSOLUTION)
        rep.error = usm_steady_message(st->s);
    else {
        rep.floquet = &st->res[0];
        rep.roots_floquet = st->res;
        rep.op = &st->op;
    }
    o->status = USM_OK;
    if (mem_open(&m, o) == 0)
        mem_finish(&m, usm_steady_write_json(&rep, m.f), o);
}

void usmpy_steady(const usm_model *model, const usm_params *p, double t0,
                  const usm_floquet_options *fo, const usm_op_options *opo, usmpy_out *o)
{
    usmpy_steady_state *st = usmpy_steady_run(model, p, t0, fo, opo, o);
    if (st) {
        usmpy_out w;
        usmpy_steady_json(st, &w);
        if (w.status != USM_OK) {
            *o = w;
        } else {
            o->json = w.json;
            o->len = w.len;
        }
        usmpy_steady_state_free(st);
    }
}

/* ---- sweep (sweep_cmd.c run, run_periodic) ----------------------------------------- */

void usmpy_sweep(const usm_model *model, const usm_params *p, const usm_sweep_options *opt,
                 usmpy_out *o)
{
    mem m;
    int status;
    usm_sweep *s = usm_sweep_alloc(model);
    usmpy_out_init(o);
    if (!s) {
        fail(o, USM_EFAILED, "out of memory");
        return;
    }
    status = usm_sweep_run(s, p, opt);
    if (status == USM_EINPUT)
        fail(o, USM_EINPUT, "%s", usm_sweep_message(s));
    else if (status != USM_OK)
        fail(o, USM_EFAILED, "sweep: %s", usm_sweep_message(s));
    else if (mem_open(&m, o) == 0)
        mem_finish(&m, usm_sweep_write_json(s, model, p, opt->over, m.f), o);
    usm_sweep_free(s);
}

void usmpy_periodic_sweep(const usm_model *model, const usm_params *p,
                          const usm_periodic_sweep_options *opt, usmpy_out *o)
{
    mem m;
    int status;
    usm_periodic_sweep *s = usm_periodic_sweep_alloc(model);
    usmpy_out_init(o);
    if (!s) {
        fail(o, USM_EFAILED, "out of memory");
        return;
    }
    status = usm_periodic_sweep_run(s, p, opt);
    if (status != USM_OK)
        fail(o, status == USM_EINPUT ? USM_EINPUT : USM_EFAILED, "sweep: %s",
             usm_periodic_sweep_message(s));
    else if (mem_open(&m, o) == 0)
        mem_finish(&m, usm_periodic_sweep_write_json(s, p, m.f), o);
    usm_periodic_sweep_free(s);
}

/* ---- simulate (simulate_cmd.c run) --------------------------------------------------- */

typedef struct history {
    double *rows;
    size_t n, cap;
    int oom;
} history;

/* One row in the CSV's columns (usm_sim_csv_header, usm_sim_csv_row). */
static int on_sample(const usm_sim_sample *s, void *data)
{
    history *h = data;
    if (h->n == h->cap) {
        size_t cap = h->cap ? 2 * h->cap : 1024;
        double *r = realloc(h->rows, cap * USMPY_SIM_COLUMNS * sizeof *r);
        if (!r) {
            h->oom = 1;
            return 1;
        }
        h->rows = r;
        h->cap = cap;
    }
    double *row = h->rows + h->n * USMPY_SIM_COLUMNS;
    const double v[USMPY_SIM_COLUMNS] = {
        s->t, s->phi, s->theta, s->psi, s->phidot, s->thetadot, s->psidot, s->rotor_angle,
        s->rotor_speed, s->out[USM_OUT_F_N], s->out[USM_OUT_F_T], s->out[USM_OUT_V_REL],
        s->have_avg ? s->theta_avg : NAN, s->have_avg ? s->rotor_speed_avg : NAN,
        (double)s->validity};
    memcpy(row, v, sizeof v);
    h->n++;
    return 0;
}

void usmpy_simulate(const usm_model *model, const usm_params *p, const usm_sim_options *opt,
                    usmpy_out *o)
{
    usm_sim_summary sum;
    usm_sim_callbacks cb = {NULL, NULL, NULL, NULL};
    history h = {NULL, 0, 0, 0};
    mem m;
    int rc;
    usm_sim *s = usm_sim_alloc(model);
    usmpy_out_init(o);
    if (!s) {
        fail(o, USM_EFAILED, "out of memory");
        return;
    }
    if (usm_sim_check(s, p, opt) != USM_OK) {
        fail(o, USM_EINPUT, "%s", usm_sim_message(s));
        goto done;
    }
    cb.sample = opt->rate > 0 ? on_sample : NULL;
    cb.data = &h;
    struct timespec w0, w1;
    clock_gettime(CLOCK_MONOTONIC, &w0);
    rc = usm_sim_run(s, p, opt, &cb, &sum);
    clock_gettime(CLOCK_MONOTONIC, &w1);
    if (h.oom) {
        fail(o, USM_EFAILED, "out of memory");
        goto done;
    }
    if (rc == USM_EINPUT || rc == USM_ENOSOLUTION) {
        fail(o, rc, "%s", usm_sim_message(s));
        goto done;
    }
    usm_sim_report rep = {.model = model, .params = p, .opt = opt, .summary = &sum,
                          .wall = (double)(w1.tv_sec - w0.tv_sec) +
                                  1e-9 * (double)(w1.tv_nsec - w0.tv_nsec)};
    o->status = rc;
    if (rc != USM_OK)
        snprintf(o->msg, sizeof o->msg, "%s", usm_sim_message(s));
    if (mem_open(&m, o) == 0 && mem_finish(&m, usm_sim_write_json(&rep, m.f), o) == 0) {
        o->rows = h.rows;
        o->nrows = h.n;
        o->ncols = USMPY_SIM_COLUMNS;
        h.rows = NULL;
    }
done:
    free(h.rows);
    usm_sim_free(s);
}

/* ---- periodic (periodic_cmd.c) --------------------------------------------------------- */

void usmpy_periodic(const usm_model *model, const usm_params *p, usmpy_out *o)
{
    usm_periodic_result r;
    mem m;
    usm_periodic *w = usm_periodic_alloc(model);
    usmpy_out_init(o);
    if (!w) {
        fail(o, USM_EFAILED, "out of memory");
        return;
    }
    int status = usm_periodic_solve(w, p, NULL, NULL, &r);
    if (status == USM_EINPUT) {
        fail(o, USM_EINPUT, "%s", usm_periodic_message(w));
    } else {
        if (status != USM_OK)
            fail(o, status == USM_ENOSOLUTION ? USM_ENOSOLUTION : USM_EFAILED, "periodic: %s",
                 usm_periodic_message(w));
        else
            o->status = USM_OK;
        /* --json prints the object with "error" on a failure too */
        if (mem_open(&m, o) == 0)
            mem_finish(&m, usm_periodic_write_json(w, p, status ? NULL : &r, m.f), o);
    }
    usm_periodic_free(w);
}

/* ---- sensitivity (sensitivity_cmd.c) --------------------------------------------------- */

void usmpy_sensitivity(const usm_model *model, const usm_params *p, const int want[USM_SENS_COUNT],
                       usmpy_out *o)
{
    usm_sensitivity_result res;
    usm_sensitivity *sens = NULL;
    mem m;
    int status;
    usm_steady *s = usm_steady_alloc(model);
    usmpy_out_init(o);
    if (!s) {
        fail(o, USM_EFAILED, "out of memory");
        return;
    }
    status = usm_steady_solve(s, p, NULL);
    if (status == USM_ENOSOLUTION) {
        fail(o, USM_ENOSOLUTION, "no stationary solution: %s", usm_steady_message(s));
        goto done;
    }
    if (status == USM_EINPUT) {
        fail(o, USM_EINPUT, "%s", usm_steady_message(s));
        goto done;
    }
    if (status != USM_OK || usm_steady_count(s) == 0) {
        fail(o, USM_EFAILED, "steady: %s", usm_steady_message(s));
        goto done;
    }
    if (!(sens = usm_sensitivity_alloc(model))) {
        fail(o, USM_EFAILED, "out of memory");
        goto done;
    }
    status = usm_sensitivity_compute(sens, p, usm_steady_root(s, 0), want[USM_SENS_MAX_MODULUS],
                                     &res);
    if (status != USM_OK) {
        fail(o, status == USM_EINPUT ? USM_EINPUT : USM_EFAILED, "sensitivity: %s",
             usm_sensitivity_message(sens));
        goto done;
    }
    o->status = USM_OK;
    if (mem_open(&m, o) == 0)
        mem_finish(&m, usm_sensitivity_write_json(model, p, &res, want, m.f), o);
done:
    usm_sensitivity_free(sens);
    usm_steady_free(s);
}

/* ---- map (map_cmd.c) --------------------------------------------------------------------- */

void usmpy_map(const usm_model *model, const usm_params *p, const usm_map_options *opt,
               usmpy_out *o)
{
    usm_report_map map;
    mem m;
    int status;
    usmpy_out_init(o);
    memset(&map, 0, sizeof map);
    map.model = model;
    map.params = *p;
    map.x.name = opt->x.name;
    map.x.from = opt->x.from;
    map.x.to = opt->x.to;
    map.x.points = opt->x.points;
    map.y.name = opt->y.name;
    map.y.from = opt->y.from;
    map.y.to = opt->y.to;
    map.y.points = opt->y.points;
    map.t0 = opt->t0;
    map.floquet = &opt->floquet;
    map.op = &opt->op;
    map.threads = opt->threads;
    map.boundaries = 1; /* as --json */
    status = usm_report_map_run(&map, o->msg);
    if (status != USM_OK) {
        o->status = status;
        return;
    }
    o->status = USM_OK;
    if (mem_open(&m, o) == 0)
        mem_finish(&m, usm_report_map_write_json(&map, m.f), o);
    usm_report_map_free(&map);
}

/* ---- optimize (optimize_cmd.c) --------------------------------------------------------------- */

void usmpy_optimize(const usm_model *model, const usm_params *p, const usm_opt_problem *pb,
                    usmpy_out *o)
{
    mem m;
    usmpy_out_init(o);
    usm_optimize *opt = usm_optimize_alloc(model);
    usm_opt_result *res = malloc(sizeof *res);
    if (!opt || !res) {
        fail(o, USM_EFAILED, "out of memory");
    } else {
        int status = usm_optimize_run(opt, p, pb, res);
        if (status == USM_ENOSOLUTION || status == USM_OK) {
            if (status == USM_ENOSOLUTION)
                fail(o, USM_ENOSOLUTION, "%s", usm_optimize_message(opt));
            else
                o->status = USM_OK;
            if (mem_open(&m, o) == 0)
                mem_finish(&m, usm_optimize_write_json(opt, model, pb, res, m.f), o);
        } else
            fail(o, status == USM_EINPUT ? USM_EINPUT : USM_EFAILED, "optimize: %s",
                 usm_optimize_message(opt));
    }
    free(res);
    usm_optimize_free(opt);
}

/* ---- tolerance (tolerance_cmd.c) ------------------------------------------------------------- */

void usmpy_tolerance(const usm_model *model, const usm_params *p, const usm_tolerance_vary *vary,
                     int nvary, const usm_tolerance_spec *spec, int nspec,
                     const usm_tolerance_options *opt, usmpy_out *o)
{
    mem m;
    int status = USM_OK;
    usmpy_out_init(o);
    usm_tolerance *t = usm_tolerance_alloc(model);
    if (!t) {
        fail(o, USM_EFAILED, "out of memory");
        return;
    }
    for (int j = 0; status == USM_OK && j < nvary + nspec; ++j)
        if ((j < nvary ? usm_tolerance_vary_add(t, &vary[j])
                       : usm_tolerance_spec_add(t, &spec[j - nvary])) != USM_OK) {
            fail(o, USM_EINPUT, "%s %s", j < nvary ? "vary" : "spec", usm_tolerance_message(t));
            status = USM_EINPUT;
        }
    if (status == USM_OK && (status = usm_tolerance_run(t, p, opt)) != USM_OK)
        fail(o, status, "%s", usm_tolerance_message(t));
    if (status == USM_OK) {
        size_t cols = (size_t)nvary + USM_TOL_NOUTPUTS + 2;
        size_t rows = (size_t)opt->samples;
        o->status = USM_OK;
        if (!(o->rows = malloc(rows * cols * sizeof *o->rows))) {
            fail(o, USM_EFAILED, "out of memory");
        } else {
            o->nrows = rows;
            o->ncols = cols;
            for (size_t i = 0; i < rows; ++i) {
                double *r = o->rows + i * cols;
                int good = 0, redraws = 0;
                usm_tolerance_sample(t, i, r, r + nvary, &good, &redraws);
                r[cols - 2] = good;
                r[cols - 1] = redraws;
            }
            if (mem_open(&m, o) == 0)
                mem_finish(&m, usm_tolerance_write_json(t, m.f), o);
        }
    }
    usm_tolerance_free(t);
}
