/* Motor characteristics: the stationary solution followed in one parameter.
 *
 * This file holds the API of usm_sweep.h: options and their checks, the grid,
 * the result arrays and the order of the work.  The continuation itself is in
 * sweep_branch.c, the Floquet part in sweep_stability.c.
 */
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/grid.h"
#include "core/grow.h"
#include "sweep_branch.h"
#include "sweep_op.h"
#include "sweep_stability.h"

struct usm_sweep {
    const usm_model *m;
    sweep_branch br;
    usm_sweep_point *pts;
    size_t npts, cap;
    double *grid;         /* the grid values, for the tracer */
    unsigned char *settled; /* per point: passed on by the tracer once */
    usm_sweep_event *ev;
    size_t nev, evcap;
    char msg[USM_MSG_LEN];
    const char *op_rule;  /* usm_op_rule_text of the run's options, or NULL */
    /* progress: the continuation's share of the run, then the Floquet part's */
    const usm_sweep_options *opt;
    double progress_split;
    size_t done;          /* grid points settled by the continuation phase */
};

const char *usm_sweep_op_rule(const usm_sweep *s) { return s->op_rule; }

void usm_sweep_options_default(usm_sweep_options *opt)
{
    memset(opt, 0, sizeof *opt);
    opt->over = usm_param_table[USM_P_f].name;
    opt->from = 36000.0;
    opt->to = 39000.0;
    opt->points = 31;
    opt->floquet = 1;
    opt->t0 = 0.0;
    usm_floquet_options_default(&opt->floquet_options);
    opt->threads = 2;
    opt->progress = NULL;
    opt->progress_ctx = NULL;
    usm_steady_options_default(&opt->steady);
    opt->operating_point = 1;
    usm_op_options_default(&opt->op);
}

usm_sweep *usm_sweep_alloc(const usm_model *m)
{
    usm_sweep *s = calloc(1, sizeof *s);
    if (!s)
        return NULL;
    s->m = m;
    if (sweep_branch_alloc(&s->br, m) != 0) {
        usm_sweep_free(s);
        return NULL;
    }
    return s;
}

void usm_sweep_free(usm_sweep *s)
{
    if (!s)
        return;
    sweep_branch_free(&s->br);
    free(s->pts);
    free(s->grid);
    free(s->settled);
    free(s->ev);
    free(s);
}

size_t usm_sweep_count(const usm_sweep *s) { return s->npts; }

const usm_sweep_point *usm_sweep_point_at(const usm_sweep *s, size_t i)
{
    return i < s->npts ? &s->pts[i] : NULL;
}

size_t usm_sweep_event_count(const usm_sweep *s) { return s->nev; }

const usm_sweep_event *usm_sweep_event_at(const usm_sweep *s, size_t i)
{
    return i < s->nev ? &s->ev[i] : NULL;
}

const char *usm_sweep_message(const usm_sweep *s) { return s->msg; }

/* ---- the sink: what the branch tracer and the stability pass find -------------- */

static void progress(const usm_sweep *s, double fraction)
{
    if (s->opt && s->opt->progress)
        s->opt->progress(fmin(1.0, fmax(0.0, fraction)), s->opt->progress_ctx);
}

static void sink_point(void *ctx, size_t i, const usm_steady_solution *sol, int roots,
                       const char *error)
{
    usm_sweep *s = ctx;
    usm_sweep_point *pt = &s->pts[i];
    pt->converged = sol != NULL;
    if (sol)
        pt->sol = *sol;
    pt->roots = roots;
    /* what snprintf "%s" would write, without its format machinery (a
     * fifth of a microsecond a row) */
    const char *nul = error ? memchr(error, '\0', USM_MSG_LEN - 1) : NULL;
    const size_t len = !error ? 0 : nul ? (size_t)(nul - error) : USM_MSG_LEN - 1;
    memcpy(pt->error, error ? error : "", len);
    pt->error[len] = '\0';
    if (!s->settled[i]) {
        s->settled[i] = 1;
        ++s->done;
        progress(s, s->progress_split * (double)s->done / (double)s->npts);
    }
}

static int sink_event(void *ctx, const usm_sweep_event *e)
{
    usm_sweep *s = ctx;
    if (usm_grow((void **)&s->ev, &s->evcap, s->nev + 1, sizeof *s->ev) != 0)
        return -1;
    usm_sweep_event *x = &s->ev[s->nev++];
    *x = *e;
    /* an event on a root the model does not describe says so in its text
     * (the stick model's loss of stability at 3.577 N mm lies past its stick
     * limit, 0.602 N mm); not the stick limit itself, which is that boundary */
    if (x->has_sol && x->type != USM_EVENT_STICK_LIMIT && x->sol.validity != USM_VALID) {
        const size_t len = strlen(x->what);
        snprintf(x->what + len, sizeof x->what - len, "; model invalid: %s",
                 usm_validity_name(x->sol.validity));
    }
    return 0;
}

static void sink_progress(void *ctx, double fraction)
{
    usm_sweep *s = ctx;
    progress(s, s->progress_split + (1.0 - s->progress_split) * fraction);
}

/* ---- options ------------------------------------------------------------------ */

static int check_options(usm_sweep *s, const usm_params *p, const usm_sweep_options *opt)
{
    const usm_param_info *info;
    if (!opt || !p) {
        snprintf(s->msg, USM_MSG_LEN, "%s: must not be NULL", !opt ? "options" : "params");
        return USM_EINPUT;
    }
    if (!opt->over || !(info = usm_params_find(opt->over))) {
        snprintf(s->msg, USM_MSG_LEN, "over: unknown parameter \"%s\"",
                 opt->over ? opt->over : "(null)");
        return USM_EINPUT;
    }
    if (!isfinite(opt->from) || !isfinite(opt->to)) {
        snprintf(s->msg, USM_MSG_LEN, "%s: must be a finite number",
                 !isfinite(opt->from) ? "from" : "to");
        return USM_EINPUT;
    }
    if (opt->to == opt->from) {
        snprintf(s->msg, USM_MSG_LEN, "to: must differ from from (%g)", opt->from);
        return USM_EINPUT;
    }
    if (!isfinite(opt->to - opt->from)) { /* the steps would be infinite */
        snprintf(s->msg, USM_MSG_LEN, "from, to: the width to - from overflows (%g to %g; "
                 "at most %g)", opt->from, opt->to, DBL_MAX);
        return USM_EINPUT;
    }
    /* both ends inside the parameter's range, named in its unit (38 meant in kHz) */
    for (int end = 0; end < 2; ++end) {
        char why[USM_MSG_LEN];
        if (usm_param_check_value(usm_param_index(info), end ? opt->to : opt->from, why) !=
            USM_OK) {
            snprintf(s->msg, USM_MSG_LEN, "%.200s (the sweep's %s)", why, end ? "to" : "from");
            return USM_EINPUT;
        }
    }
    if (opt->points < 2 || opt->points > SWEEP_MAX_POINTS) {
        snprintf(s->msg, USM_MSG_LEN, "points: must be at least 2 and at most %d, got %d",
                 SWEEP_MAX_POINTS, opt->points);
        return USM_EINPUT;
    }
    if (opt->operating_point && opt->op.from_rest &&
        !(opt->op.periods >= 1 && opt->op.periods <= 1e7)) {
        snprintf(s->msg, USM_MSG_LEN, "from-rest-periods: must be in [1, 1e7], got %g",
                 opt->op.periods);
        return USM_EINPUT;
    }
    if (opt->threads < 1 || opt->threads > SWEEP_MAX_THREADS) {
        snprintf(s->msg, USM_MSG_LEN, "threads: must be between 1 and %d, got %d", SWEEP_MAX_THREADS,
                 opt->threads);
        return USM_EINPUT;
    }
    if (opt->nmonitors < 0 || opt->nmonitors > USM_SWEEP_MAX_MONITORS ||
        (opt->nmonitors > 0 && !opt->monitors)) {
        snprintf(s->msg, USM_MSG_LEN, "monitors: need 0 to %d of them, got %d",
                 USM_SWEEP_MAX_MONITORS, opt->nmonitors);
        return USM_EINPUT;
    }
    for (int k = 0; k < opt->nmonitors; ++k) {
        const usm_sweep_monitor *mo = &opt->monitors[k];
        if (!mo->name || !mo->name[0] || strlen(mo->name) > 31 || strpbrk(mo->name, " \t\n") ||
            !mo->fn || mo->nlevels < 0 || mo->nlevels > USM_SWEEP_MAX_LEVELS) {
            snprintf(s->msg, USM_MSG_LEN,
                     "monitors[%d]: need a name (1 to 31 characters, no spaces), a function "
                     "and 0 to %d levels",
                     k, USM_SWEEP_MAX_LEVELS);
            return USM_EINPUT;
        }
        for (int l = 0; l < mo->nlevels; ++l)
            if (!isfinite(mo->levels[l])) {
                snprintf(s->msg, USM_MSG_LEN, "monitors[%d] (%s): level %d must be a finite number",
                         k, mo->name, l);
                return USM_EINPUT;
            }
    }
    if (!isfinite(opt->t0)) {
        snprintf(s->msg, USM_MSG_LEN, "t0: must be a finite number");
        return USM_EINPUT;
    }
    if (!(opt->steady.theta_min > 0 && opt->steady.theta_max > opt->steady.theta_min &&
          opt->steady.grid >= 2 && opt->steady.xtol > 0)) {
        snprintf(s->msg, USM_MSG_LEN,
                 "steady: need 0 < theta_min < theta_max, grid >= 2 and xtol > 0");
        return USM_EINPUT;
    }
    return USM_OK;
}

/* Every grid value, not only the ends: the range may cross a bound (f from
 * -1 to 1) and a message naming the point beats a silent gap.  On the grid
 * setup_points worked out (each value costs a few conversions to find its
 * shortest decimal form: worked out once). */
static int check_grid(usm_sweep *s, const usm_params *p, const usm_sweep_options *opt)
{
    const usm_param_info *info = usm_params_find(opt->over);
    char lib[USM_MSG_LEN];
    usm_params q = *p;
    for (int i = 0; i < opt->points; ++i) {
        *usm_params_field(&q, info) = s->grid[i];
        if (usm_params_check(&q, s->m, lib) != USM_OK || usm_params_check_ideal(&q, lib) != USM_OK) {
            snprintf(s->msg, USM_MSG_LEN, "%.190s (sweep point %d of %d)", lib, i + 1,
                     opt->points);
            return USM_EINPUT;
        }
    }
    return USM_OK;
}

static int setup_points(usm_sweep *s, const usm_sweep_options *opt)
{
    const size_t n = (size_t)opt->points;
    /* three arrays of one capacity: each grown from the same one */
    size_t cap_grid = s->cap, cap_settled = s->cap;
    if (usm_grow((void **)&s->grid, &cap_grid, n, sizeof *s->grid) != 0 ||
        usm_grow((void **)&s->settled, &cap_settled, n, sizeof *s->settled) != 0 ||
        usm_grow((void **)&s->pts, &s->cap, n, sizeof *s->pts) != 0) {
        snprintf(s->msg, USM_MSG_LEN, "out of memory for %zu sweep points", n);
        return USM_EFAILED;
    }
    s->npts = n;
    memset(s->pts, 0, n * sizeof *s->pts);
    memset(s->settled, 0, n);
    /* 36000..39000 in 301 points gives 36010, not 36009.999999999993, and
     * the ends are from and to exactly (core/grid.h) */
    usm_grid_fill(opt->from, opt->to, (long)n, s->grid);
    for (size_t i = 0; i < n; ++i)
        s->pts[i].value = s->grid[i];
    return USM_OK;
}

/* Events in sweep order, whatever phase found them. */
static int by_position(const void *a, const void *b)
{
    const usm_sweep_event *x = a, *y = b;
    return (x->value > y->value) - (x->value < y->value);
}

int usm_sweep_run(usm_sweep *s, const usm_params *p, const usm_sweep_options *opt)
{
    int status;
    s->npts = 0;
    s->nev = 0;
    s->msg[0] = '\0';
    s->opt = NULL;
    if ((status = check_options(s, p, opt)) != USM_OK)
        return status;
    if ((status = setup_points(s, opt)) != USM_OK)
        return status;
    if ((status = check_grid(s, p, opt)) != USM_OK) {
        s->npts = 0;
        return status;
    }
    s->opt = opt;
    s->op_rule = opt->operating_point ? usm_op_rule_text(&opt->op) : NULL;
    s->done = 0;
    s->progress_split = opt->floquet ? 0.05 : 1.0;
    progress(s, 0.0);
    const sweep_sink sink = {s, sink_point, sink_event, sink_progress};
    /* the full search at each grid point (its root count, and the root bit
     * for bit as usm_steady_solve gives it) does not steer the continuation:
     * it runs afterwards, on the workers */
    s->br.defer = 1;
    status = sweep_trace_grid(&s->br, p, opt, s->grid, s->npts, &sink, s->msg);
    if (status == USM_OK)
        for (size_t i = 0; i < s->npts; ++i)
            if (!s->settled[i]) /* beyond a trace's reach: a branch that was lost */
                sink_point(s, i, NULL, 0, "not reached by the continuation");
    if (status == USM_OK)
        status = sweep_finish_points(s->m, p, opt, s->pts, s->npts, s->msg);
    if (status == USM_OK && opt->floquet) {
        status = sweep_floquet_points(s->m, p, opt, s->pts, s->npts, &sink, s->msg);
        if (status == USM_OK)
            status = sweep_stability_events(s->m, p, opt, s->pts, s->npts, &sink, s->msg);
        if (status == USM_OK && opt->operating_point)
            status = sweep_operating_points(s->m, p, opt, s->pts, s->npts, &sink, s->msg);
    }
    if (s->nev > 1) {
        qsort(s->ev, s->nev, sizeof *s->ev, by_position);
        if (opt->to < opt->from)
            for (size_t i = 0, j = s->nev - 1; i < j; ++i, --j) {
                usm_sweep_event t = s->ev[i];
                s->ev[i] = s->ev[j];
                s->ev[j] = t;
            }
    }
    if (status == USM_OK)
        progress(s, 1.0);
    s->opt = NULL;
    return status;
}
