/* The progress callback of the long studies (usm_progress.h), checked on a
 * map and a tolerance study:
 *
 * 1. done never decreases, the last call has done == total, total and the
 *    unit are the same on every call, and no two calls overlap (a trylock
 *    the callback holds while it runs fails if a second one enters);
 * 2. the calls are rate-limited: at most the first, the last and one per
 *    0.1 s of wall time;
 * 3. a resumed tolerance study's first call counts the checkpoint's samples;
 *    a Pareto front counts its points (usm_opt_problem.progress); a robust
 *    search its designs, against a total that may grow when a search starts
 *    again, and ends at the final total;
 * 4. the results are bit for bit those of the same run without a callback.
 */
#define _POSIX_C_SOURCE 200809L
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "usm_map.h"
#include "usm_robust.h"
#include "usm_tolerance.h"

#include "check.h"

typedef struct record {
    pthread_mutex_t inside;
    long calls, first, last, total, decreases, overlaps, total_changes, shrinks;
    char what[32];
} record;

static void record_init(record *r)
{
    memset(r, 0, sizeof *r);
    pthread_mutex_init(&r->inside, NULL);
    r->first = r->last = r->total = -1;
}

static void on_progress(void *ctx, long done, long total, const char *what)
{
    record *r = ctx;
    if (pthread_mutex_trylock(&r->inside) != 0) {
        ++r->overlaps; /* racy by design: any count > 0 is the failure */
        return;
    }
    /* long enough for a second thread to arrive if the study let it */
    nanosleep(&(struct timespec){0, 200000}, NULL);
    if (r->calls == 0) {
        r->first = done;
        r->total = total;
        snprintf(r->what, sizeof r->what, "%s", what);
    } else {
        r->decreases += done < r->last;
        r->total_changes += total != r->total || strcmp(what, r->what) != 0;
        r->shrinks += total < r->total;
        r->total = total;
    }
    r->last = done;
    ++r->calls;
    pthread_mutex_unlock(&r->inside);
}

static double mono(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void check_record(const char *name, const record *r, long total, long first,
                         const char *what, double seconds)
{
    CHECK(r->calls >= 2, "%s: %ld call(s)", name, r->calls);
    CHECK(r->first == first, "%s: first done %ld, expected %ld", name, r->first, first);
    CHECK(r->last == total && r->total == total, "%s: ends at %ld of %ld, expected %ld", name,
          r->last, r->total, total);
    CHECK(r->decreases == 0, "%s: done decreased %ld time(s)", name, r->decreases);
    CHECK(r->total_changes == 0, "%s: total or unit changed", name);
    CHECK(strcmp(r->what, what) == 0, "%s: unit \"%s\", expected \"%s\"", name, r->what, what);
    CHECK(r->overlaps == 0, "%s: %ld overlapping call(s)", name, r->overlaps);
    CHECK(r->calls <= 2 + (long)(seconds / 0.1) + 1, "%s: %ld calls in %.2f s", name, r->calls,
          seconds);
}

static int same_cell(const usm_map_cell *a, const usm_map_cell *b)
{
    const usm_point *p = &a->point, *q = &b->point;
    return a->x == b->x && a->y == b->y && p->exists == q->exists && p->roots == q->roots &&
           p->has_floquet == q->has_floquet &&
           memcmp(&p->sol.theta, &q->sol.theta, sizeof p->sol.theta) == 0 &&
           memcmp(&p->floquet.max_modulus, &q->floquet.max_modulus, sizeof(double)) == 0 &&
           p->op.cls == q->op.cls && p->op.index == q->op.index &&
           strcmp(p->error, q->error) == 0;
}

static void test_map(void)
{
    usm_params p;
    usm_map_options o;
    record r;
    usm_params_default(&p);
    usm_map_options_default(&o);
    o.x = (usm_map_axis){"f", 34000, 40000, 12};
    o.y = (usm_map_axis){"T", 0, 0.008, 7};
    o.threads = 2;
    usm_map *plain = usm_map_alloc(usm_model_find("3dof"));
    usm_map *watched = usm_map_alloc(usm_model_find("3dof"));
    CHECK(usm_map_run(plain, &p, &o) == USM_OK, "map: %s", usm_map_message(plain));
    record_init(&r);
    o.progress = (usm_progress){on_progress, &r};
    const double t0 = mono();
    CHECK(usm_map_run(watched, &p, &o) == USM_OK, "map: %s", usm_map_message(watched));
    check_record("map", &r, 12 * 7, 0, "points", mono() - t0);
    int differ = 0;
    for (int j = 0; j < 7; ++j)
        for (int i = 0; i < 12; ++i)
            differ += !same_cell(usm_map_cell_at(plain, i, j), usm_map_cell_at(watched, i, j));
    CHECK(differ == 0, "map: %d cell(s) differ with the callback", differ);
    for (int k = 0; k < USM_MAP_NBOUNDARY; ++k) {
        const size_t n = usm_map_boundary_count(plain, (usm_map_boundary_kind)k);
        CHECK(n == usm_map_boundary_count(watched, (usm_map_boundary_kind)k),
              "map: boundary %d count differs", k);
        for (size_t q = 0; q < n; ++q)
            CHECK(memcmp(usm_map_boundary_at(plain, (usm_map_boundary_kind)k, q),
                         usm_map_boundary_at(watched, (usm_map_boundary_kind)k, q),
                         sizeof(usm_map_boundary_point)) == 0,
                  "map: boundary %d point %zu differs", k, q);
    }
    usm_map_free(plain);
    usm_map_free(watched);
}

static usm_tolerance *study(const usm_model *m)
{
    static const char *const vary[] = {"F0=normal:20%", "T=uniform:0:0.012"};
    char msg[USM_MSG_LEN];
    usm_tolerance *t = usm_tolerance_alloc(m);
    for (int j = 0; j < 2; ++j) {
        usm_tolerance_vary v;
        CHECK(usm_tolerance_vary_parse(vary[j], &v, msg) == USM_OK &&
                  usm_tolerance_vary_add(t, &v) == USM_OK,
              "vary %s: %s", vary[j], msg);
    }
    return t;
}

static double *rows_of(const usm_tolerance *t, uint64_t n)
{
    const size_t w = 2 + USM_TOL_NOUTPUTS + 2;
    double *r = calloc(n * w, sizeof *r);
    for (uint64_t i = 0; r && i < n; ++i) {
        int good, redraws;
        usm_tolerance_sample(t, i, r + i * w, r + i * w + 2, &good, &redraws);
        r[i * w + w - 2] = good;
        r[i * w + w - 1] = redraws;
    }
    return r;
}

static void test_tolerance(void)
{
    const usm_model *m = usm_model_find("3dof");
    const uint64_t n = 8000;
    const size_t bytes = n * (2 + USM_TOL_NOUTPUTS + 2) * sizeof(double);
    usm_params p;
    usm_tolerance_options opt;
    record r;
    char dir[] = "/tmp/usm_progressXXXXXX", path[64];
    usm_params_default(&p);
    usm_tolerance_options_default(&opt);
    opt.samples = n;
    opt.seed = 3;
    opt.threads = 2;
    usm_tolerance *t = study(m);
    CHECK(usm_tolerance_run(t, &p, &opt) == USM_OK, "run: %s", usm_tolerance_message(t));
    double *plain = rows_of(t, n);
    const uint64_t good = usm_tolerance_result(t)->good;

    record_init(&r);
    opt.progress = (usm_progress){on_progress, &r};
    double t0 = mono();
    CHECK(usm_tolerance_run(t, &p, &opt) == USM_OK, "run: %s", usm_tolerance_message(t));
    check_record("tolerance", &r, (long)n, 0, "samples", mono() - t0);
    double *watched = rows_of(t, n);
    CHECK(plain && watched && memcmp(plain, watched, bytes) == 0,
          "tolerance: the samples differ with the callback");
    CHECK(usm_tolerance_result(t)->good == good, "tolerance: good %llu, expected %llu",
          (unsigned long long)usm_tolerance_result(t)->good, (unsigned long long)good);
    free(watched);

    /* resumed: the checkpoint's blocks are done before the first call */
    CHECK(mkdtemp(dir) != NULL, "mkdtemp");
    snprintf(path, sizeof path, "%s/ck", dir);
    opt.checkpoint = path;
    opt.stop_after_blocks = 3;
    opt.progress = (usm_progress){NULL, NULL};
    CHECK(usm_tolerance_run(t, &p, &opt) == USM_EFAILED, "stop hook: %s",
          usm_tolerance_message(t));
    opt.stop_after_blocks = 0;
    record_init(&r);
    opt.progress = (usm_progress){on_progress, &r};
    t0 = mono();
    CHECK(usm_tolerance_run(t, &p, &opt) == USM_OK, "resume: %s", usm_tolerance_message(t));
    check_record("resumed tolerance", &r, (long)n, 3 * USM_TOLERANCE_BLOCK, "samples",
                 mono() - t0);
    double *resumed = rows_of(t, n);
    CHECK(plain && resumed && memcmp(plain, resumed, bytes) == 0,
          "tolerance: the resumed samples differ");
    free(resumed);
    free(plain);
    unlink(path);
    rmdir(dir);
    usm_tolerance_free(t);
}

static void test_pareto(void)
{
    const usm_model *m = usm_model_find("3dof");
    const int obj[2] = {USM_OPT_SPEED, USM_SENS_EFFICIENCY}, minimize[2] = {0, 0};
    char msg[USM_MSG_LEN];
    usm_params p;
    usm_opt_problem pb;
    usm_pareto_result plain, watched;
    record r;
    usm_params_default(&p);
    usm_opt_problem_init(&pb);
    CHECK(usm_opt_problem_add_vary(&pb, "F0", 0.3, 0.6, msg) == USM_OK, "vary: %s", msg);
    CHECK(usm_pareto_run(m, &p, &pb, obj, minimize, 6, &plain, msg) == USM_OK, "pareto: %s",
          msg);
    record_init(&r);
    pb.progress = (usm_progress){on_progress, &r};
    const double t0 = mono();
    CHECK(usm_pareto_run(m, &p, &pb, obj, minimize, 6, &watched, msg) == USM_OK, "pareto: %s",
          msg);
    check_record("pareto", &r, 6, 0, "front points", mono() - t0);
    int same = plain.npoints == watched.npoints && plain.computed == watched.computed;
    for (int i = 0; same && i < plain.npoints; ++i)
        same = memcmp(plain.points[i].f, watched.points[i].f, sizeof plain.points[i].f) == 0;
    CHECK(same, "pareto: the front differs with the callback");
    usm_pareto_result_free(&plain);
    usm_pareto_result_free(&watched);
}

static void test_robust(void)
{
    const usm_model *m = usm_model_find("3dof");
    char msg[USM_MSG_LEN];
    usm_params p;
    usm_robust_problem rp;
    usm_robust_result *plain = malloc(sizeof *plain), *watched = malloc(sizeof *watched);
    record r;
    usm_params_default(&p);
    usm_robust_problem_init(&rp);
    CHECK(usm_opt_problem_add_vary(&rp.nominal, "f", 34000, 42000, msg) == USM_OK, "%s", msg);
    CHECK(usm_opt_problem_add_vary(&rp.nominal, "F0", 0.2, 1.0, msg) == USM_OK, "%s", msg);
    CHECK(usm_opt_problem_add_constraint(&rp.nominal, "speed", 0, 6.0, msg) == USM_OK, "%s", msg);
    rp.objective = USM_SENS_EFFICIENCY;
    rp.yield_min = 0.99;
    CHECK(usm_tolerance_vary_parse("c_r=normal:2%", &rp.scatter[0], msg) == USM_OK &&
              usm_tolerance_vary_parse("f=normal:1%", &rp.scatter[1], msg) == USM_OK,
          "%s", msg);
    rp.nscatter = 2;
    rp.samples = 600;
    rp.verify_samples = 1200;
    rp.max_evals = 6;
    rp.nominal.starts = 1; /* the nominal optimum is not what is checked here */
    CHECK(usm_robust_run(m, &p, &rp, plain, msg) == USM_OK, "robust: %s", msg);
    record_init(&r);
    rp.nominal.progress = (usm_progress){on_progress, &r};
    const double t0 = mono();
    CHECK(usm_robust_run(m, &p, &rp, watched, msg) == USM_OK, "robust: %s", msg);
    const double seconds = mono() - t0;
    CHECK(r.calls >= 2 && r.first == 0 && r.last == r.total && r.total > 0,
          "robust: %ld calls, first %ld, last %ld of %ld", r.calls, r.first, r.last, r.total);
    CHECK(r.decreases == 0 && r.shrinks == 0 && r.overlaps == 0 && strcmp(r.what, "designs") == 0,
          "robust: %ld decreases, %ld shrinks, %ld overlaps, unit %s", r.decreases, r.shrinks,
          r.overlaps, r.what);
    /* the designs and the 2 x 2 designs' worth of verification samples */
    CHECK(r.total >= watched->evaluations + 4, "robust: total %ld for %d designs", r.total,
          watched->evaluations);
    CHECK(r.calls <= 3 + (long)(seconds / 0.1) + 1, "robust: %ld calls in %.2f s", r.calls,
          seconds);
    CHECK(plain->evaluations == watched->evaluations &&
              memcmp(&plain->robust.value, &watched->robust.value, sizeof(double)) == 0 &&
              memcmp(&plain->robust.yield, &watched->robust.yield, sizeof(double)) == 0 &&
              memcmp(&plain->robust.params, &watched->robust.params, sizeof(usm_params)) == 0,
          "robust: the optimum differs with the callback");
    free(plain);
    free(watched);
}

int main(void)
{
    test_map();
    test_tolerance();
    test_pareto();
    test_robust();
    if (failures)
        printf("%d check(s) failed\n", failures);
    else
        printf("progress: all checks passed\n");
    return failures != 0;
}
