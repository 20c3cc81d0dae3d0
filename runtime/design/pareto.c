/* The Pareto front of two optimizer outputs (usm_robust.h) by the
 * epsilon-constraint method: usm_optimize_run on obj[0] with obj[1] bounded,
 * the bound stepped between the two single optima, each step warm-started
 * from its neighbour's design; dominated points dropped. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "core/progress.h"
#include "usm_robust.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Does a dominate b (both objectives oriented: larger is better)? */
static int dominates(const double a[2], const double b[2])
{
    return a[0] >= b[0] && a[1] >= b[1] && (a[0] > b[0] || a[1] > b[1]);
}

static int cmp_f1(const void *x, const void *y)
{
    const usm_pareto_point *a = x, *b = y;
    return (a->f[1] > b->f[1]) - (a->f[1] < b->f[1]);
}

/* One optimization of obj[0] under pb (with the epsilon bound added by the
 * caller), warm-started at `start` (NULL: pb's lattice).  1 and *pt when
 * feasible, 0 when not, -1 on failure (msg). */
static int solve(usm_optimize *o, const usm_params *p, const usm_opt_problem *pb, int objective,
                 int minimize, const int obj[2], const double *start, usm_opt_result *r,
                 usm_pareto_point *pt, char msg[USM_MSG_LEN])
{
    usm_opt_problem q = *pb;
    q.objective = objective;
    q.minimize = minimize;
    q.no_flat = 1;
    q.progress = (usm_progress){NULL, NULL}; /* the front reports, not each optimization */
    if (start) {
        q.has_start = 1;
        q.starts = 1;
        memcpy(q.start, start, sizeof q.start);
    }
    const int rc = usm_optimize_run(o, p, &q, r);
    if (rc == USM_ENOSOLUTION)
        return 0;
    if (rc != USM_OK) {
        snprintf(msg, USM_MSG_LEN, "%s", usm_optimize_message(o));
        return -1;
    }
    for (int i = 0; i < 2; ++i)
        pt->f[i] = usm_opt_output_value(obj[i], &r->sol, &r->params, r->floquet.max_modulus);
    pt->params = r->params;
    pt->nactive = r->nactive;
    memcpy(pt->active, r->active, sizeof pt->active);
    return 1;
}

int usm_pareto_run(const usm_model *m, const usm_params *p, const usm_opt_problem *pb,
                   const int obj[2], const int minimize[2], int points,
                   usm_pareto_result *res, char msg[USM_MSG_LEN])
{
    const double t_start = now();
    memset(res, 0, sizeof *res);
    msg[0] = '\0';
    if (points < 2 || points > USM_PARETO_MAX_POINTS) {
        snprintf(msg, USM_MSG_LEN, "points: must be 2 to %d", USM_PARETO_MAX_POINTS);
        return USM_EINPUT;
    }
    for (int i = 0; i < 2; ++i)
        if (usm_opt_output_analytic(obj[i]) != 1) {
            snprintf(msg, USM_MSG_LEN, "objectives: %s: each needs an analytic gradient",
                     usm_opt_output_name(obj[i]) ? usm_opt_output_name(obj[i]) : "?");
            return USM_EINPUT;
        }
    if (obj[0] == obj[1]) {
        snprintf(msg, USM_MSG_LEN, "objectives: two different outputs needed");
        return USM_EINPUT;
    }
    if (pb->ncons >= USM_OPT_MAX_CONSTRAINTS) {
        snprintf(msg, USM_MSG_LEN, "constraint: at most %d besides the front's own",
                 USM_OPT_MAX_CONSTRAINTS - 1);
        return USM_EINPUT;
    }
    {
        usm_opt_problem q = *pb;
        q.objective = obj[0];
        if (usm_opt_problem_check(&q, m, p, msg) != USM_OK)
            return USM_EINPUT;
    }
    usm_optimize *o = usm_optimize_alloc(m);
    usm_opt_result *r = malloc(sizeof *r);
    usm_pareto_point *all = malloc((size_t)points * sizeof *all);
    usm_pareto_point anchor[2];
    int status = USM_OK, n = 0;
    if (!o || !r || !all) {
        snprintf(msg, USM_MSG_LEN, "out of memory");
        status = USM_EFAILED;
        goto done;
    }
    progress_meter meter;
    progress_start(&meter, &pb->progress, points, 0, "front points");
    /* the two single optima bound the front */
    for (int i = 0; i < 2; ++i) {
        const int got = solve(o, p, pb, obj[i], minimize[i], obj, NULL, r, &anchor[i], msg);
        res->computed++;
        progress_add(&meter, 1);
        if (got <= 0) {
            if (got == 0)
                snprintf(msg, USM_MSG_LEN, "no feasible design for %s alone: %.200s",
                         usm_opt_output_name(obj[i]), usm_optimize_message(o));
            status = got == 0 ? USM_ENOSOLUTION : USM_EFAILED;
            goto done;
        }
    }
    all[n++] = anchor[0];
    /* half of the levels on obj[1] (obj[0] optimized), half on obj[0]
     * (obj[1] optimized): a front steep in one of them is still covered */
    const int levels = points - 2, nb = (levels + 1) / 2;
    for (int role = 0; role < 2; ++role) {
        const int opt_k = role, eps_k = 1 - role; /* optimize obj[opt_k], bound obj[eps_k] */
        const int nl = role == 0 ? nb : levels - nb;
        const double e0 = anchor[opt_k].f[eps_k], e1 = anchor[eps_k].f[eps_k];
        double start[USM_NPARAMS];
        for (int j = 0; j < pb->nvary; ++j)
            start[j] = usm_params_get(&anchor[opt_k].params, &usm_param_table[pb->vary[j]]);
        for (int i = 1; i <= nl; ++i) {
            usm_opt_problem q = *pb;
            const double eps = e0 + (e1 - e0) * (double)i / (double)(nl + 1);
            q.cons[q.ncons++] = (usm_opt_constraint){obj[eps_k], minimize[eps_k], eps, 0};
            usm_pareto_point pt;
            int got = solve(o, p, &q, obj[opt_k], minimize[opt_k], obj, start, r, &pt, msg);
            res->computed++;
            if (got == 0) { /* the warm start failed: the lattice's starts */
                got = solve(o, p, &q, obj[opt_k], minimize[opt_k], obj, NULL, r, &pt, msg);
                res->computed++;
            }
            if (got < 0) {
                status = USM_EFAILED;
                goto done;
            }
            progress_add(&meter, 1);
            if (got == 0)
                continue;
            all[n++] = pt;
            for (int j = 0; j < pb->nvary; ++j)
                start[j] = usm_params_get(&pt.params, &usm_param_table[pb->vary[j]]);
        }
    }
    all[n++] = anchor[1];
    /* drop the dominated points and the repeated ones */
    res->points = malloc((size_t)n * sizeof *res->points);
    if (!res->points) {
        snprintf(msg, USM_MSG_LEN, "out of memory");
        status = USM_EFAILED;
        goto done;
    }
    for (int i = 0; i < n; ++i) {
        double a[2] = {minimize[0] ? -all[i].f[0] : all[i].f[0],
                       minimize[1] ? -all[i].f[1] : all[i].f[1]};
        int keep = 1;
        for (int k = 0; k < n && keep; ++k) {
            const double b[2] = {minimize[0] ? -all[k].f[0] : all[k].f[0],
                                 minimize[1] ? -all[k].f[1] : all[k].f[1]};
            if (dominates(b, a) || (k < i && b[0] == a[0] && b[1] == a[1]))
                keep = 0;
        }
        if (keep)
            res->points[res->npoints++] = all[i];
    }
    qsort(res->points, (size_t)res->npoints, sizeof *res->points, cmp_f1);
done:
    res->seconds = now() - t_start;
    free(all);
    free(r);
    usm_optimize_free(o);
    if (status != USM_OK)
        usm_pareto_result_free(res);
    return status;
}

void usm_pareto_result_free(usm_pareto_result *res)
{
    if (!res)
        return;
    free(res->points);
    res->points = NULL;
    res->npoints = 0;
}
