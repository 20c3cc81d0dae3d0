/* robust_args.c: the texts of a robust problem (usm_robust.h) as usm
 * optimize's options and the Python package's arguments give them:
 * --objective yield|NAME|mean:NAME|qNN:NAME and the constraints on the yield
 * and the derived quantities, --vary, --constraint on an optimizer output and
 * --over-range and the other options of robust design; and usm pareto's
 * --objectives A,B. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "usm_io.h"
#include "usm_robust.h"

int usm_robust_objective_parse(usm_robust_problem *rp, const char *text,
                               char msg[USM_IO_MSG_LEN])
{
    const char *name = text;
    if (strncmp(text, "mean:", 5) == 0) {
        rp->stat = USM_ROBUST_STAT_MEAN;
        name = text + 5;
    } else if (text[0] == 'q' && text[1] >= '0' && text[1] <= '9') {
        char *end;
        const double q = strtod(text + 1, &end);
        if (*end != ':' || !(q > 0 && q < 100)) {
            snprintf(msg, USM_IO_MSG_LEN, "objective: \"%s\": a quantile is qNN:NAME with "
                     "0 < NN < 100 (q05:power_out)", text);
            return USM_EINPUT;
        }
        rp->stat = USM_ROBUST_STAT_QUANTILE;
        rp->quantile = q / 100;
        name = end + 1;
    } else
        rp->stat = USM_ROBUST_STAT_NOMINAL;
    rp->objective = usm_robust_quantity_find(name);
    if (rp->objective < 0) {
        snprintf(msg, USM_IO_MSG_LEN, "objective: unknown output \"%s\" (see usm optimize "
                 "--help)", name);
        return USM_EINPUT;
    }
    if (rp->objective == USM_ROBUST_YIELD && rp->stat != USM_ROBUST_STAT_NOMINAL) {
        snprintf(msg, USM_IO_MSG_LEN, "objective: \"%s\": yield takes no statistic", text);
        return USM_EINPUT;
    }
    return USM_OK;
}

int usm_robust_constraint_parse(usm_robust_problem *rp, const char *text,
                                char msg[USM_IO_MSG_LEN])
{
    const char *op = strstr(text, ">=");
    int upper = 0;
    char name[64];
    double value;
    if (!op) {
        op = strstr(text, "<=");
        upper = 1;
    }
    if (!op || op == text || (size_t)(op - text) >= sizeof name)
        return 1;
    snprintf(name, sizeof name, "%.*s", (int)(op - text), text);
    const int k = usm_robust_quantity_find(name);
    if (k < USM_OPT_OUTPUT_COUNT)
        return 1;
    if (usm_parse_number("constraint", op + 2, strlen(op + 2), &value, msg) != USM_OK)
        return USM_EINPUT;
    if (k == USM_ROBUST_YIELD) {
        if (upper || !(value > 0 && value < 1)) {
            snprintf(msg, USM_IO_MSG_LEN, "constraint: yield>=Y with 0 < Y < 1, got \"%s\"",
                     text);
            return USM_EINPUT;
        }
        rp->yield_min = value;
        return USM_OK;
    }
    if (rp->nderived >= USM_ROBUST_MAX_DERIVED) {
        snprintf(msg, USM_IO_MSG_LEN, "constraint: at most %d on derived quantities",
                 USM_ROBUST_MAX_DERIVED);
        return USM_EINPUT;
    }
    rp->derived[rp->nderived++] = (usm_robust_constraint){k, upper, value};
    return USM_OK;
}

/* One objective of a front: [max:|min:]NAME. */
static int pareto_objective(const char *text, int *output, int *minimize, char msg[USM_IO_MSG_LEN])
{
    *minimize = strncmp(text, "min:", 4) == 0;
    if (*minimize || strncmp(text, "max:", 4) == 0)
        text += 4;
    *output = usm_opt_output_find(text);
    if (*output < 0 || usm_opt_output_analytic(*output) != 1) {
        snprintf(msg, USM_IO_MSG_LEN, "objectives: \"%s\": %s (see usm pareto --help)", text,
                 *output < 0 ? "unknown output" : "needs an analytic gradient");
        return USM_EINPUT;
    }
    return USM_OK;
}

int usm_pareto_objectives_parse(const char *text, int output[2], int minimize[2],
                                char msg[USM_IO_MSG_LEN])
{
    char first[64];
    const char *comma = strchr(text, ',');
    if (!comma || (size_t)(comma - text) >= sizeof first || strchr(comma + 1, ',')) {
        snprintf(msg, USM_IO_MSG_LEN, "objectives: expected A,B (two outputs), got \"%.200s\"",
                 text);
        return USM_EINPUT;
    }
    snprintf(first, sizeof first, "%.*s", (int)(comma - text), text);
    if (pareto_objective(first, &output[0], &minimize[0], msg) != USM_OK ||
        pareto_objective(comma + 1, &output[1], &minimize[1], msg) != USM_OK)
        return USM_EINPUT;
    if (output[0] == output[1]) {
        snprintf(msg, USM_IO_MSG_LEN, "objectives: two different outputs needed");
        return USM_EINPUT;
    }
    return USM_OK;
}

int usm_opt_vary_parse(usm_opt_problem *pb, const char *text, char msg[USM_IO_MSG_LEN])
{
    char name[64], lo_text[64];
    const char *eq = strchr(text, '='), *colon = eq ? strchr(eq, ':') : NULL;
    double lo, hi;
    if (!eq || !colon || eq == text || (size_t)(eq - text) >= sizeof name ||
        (size_t)(colon - eq - 1) >= sizeof lo_text) {
        snprintf(msg, USM_IO_MSG_LEN, "vary: expected NAME=LO:HI, got \"%.900s\"", text);
        return USM_EINPUT;
    }
    snprintf(name, sizeof name, "%.*s", (int)(eq - text), text);
    snprintf(lo_text, sizeof lo_text, "%.*s", (int)(colon - eq - 1), eq + 1);
    const usm_param_info *info = usm_params_find(name);
    if (!info) {
        snprintf(msg, USM_IO_MSG_LEN, "vary: unknown parameter \"%s\"", name);
        return USM_EINPUT;
    }
    if (usm_parse_quantity("vary", info->unit, lo_text, strlen(lo_text), &lo, msg) != USM_OK ||
        usm_parse_quantity("vary", info->unit, colon + 1, strlen(colon + 1), &hi, msg) != USM_OK)
        return USM_EINPUT;
    return usm_opt_problem_add_vary(pb, name, lo, hi, msg);
}

int usm_opt_constraint_parse(usm_opt_problem *pb, const char *text, char msg[USM_IO_MSG_LEN])
{
    const char *op = strstr(text, ">=");
    int upper = 0;
    char name[64];
    double value;
    if (!op) {
        op = strstr(text, "<=");
        upper = 1;
    }
    if (!op || op == text || (size_t)(op - text) >= sizeof name) {
        snprintf(msg, USM_IO_MSG_LEN, "constraint: expected OUTPUT>=X or OUTPUT<=X, got "
                 "\"%.900s\"", text);
        return USM_EINPUT;
    }
    snprintf(name, sizeof name, "%.*s", (int)(op - text), text);
    /* NAME, rootR.NAME (NAME checked here, R by usm_opt_problem_add_constraint)
     * or roots */
    const int per_root = strncmp(name, "root", 4) == 0;
    const char *dot = per_root ? strchr(name, '.') : NULL;
    const char *bare = dot ? dot + 1 : name;
    if ((!per_root || dot) && usm_opt_output_find(bare) < 0) {
        char list[512];
        usm_opt_output_list(list, sizeof list);
        snprintf(msg, USM_IO_MSG_LEN, "constraint: unknown output \"%s\" (one of: %s)", name,
                 list);
        return USM_EINPUT;
    }
    if (usm_parse_number("constraint", op + 2, strlen(op + 2), &value, msg) != USM_OK)
        return USM_EINPUT;
    return usm_opt_problem_add_constraint(pb, name, upper, value, msg);
}

int usm_robust_range_parse(usm_robust_range *r, const char *text, char msg[USM_IO_MSG_LEN])
{
    char buf[160], *eq, *c1, *c2;
    snprintf(buf, sizeof buf, "%s", text);
    eq = strchr(buf, '=');
    c1 = eq ? strchr(eq + 1, ':') : NULL;
    c2 = c1 ? strchr(c1 + 1, ':') : NULL;
    if (!eq || !c1) {
        snprintf(msg, USM_IO_MSG_LEN, "over-range: expected NAME=LO:HI[:N], got \"%.900s\"",
                 text);
        return USM_EINPUT;
    }
    *eq = *c1 = '\0';
    if (c2)
        *c2 = '\0';
    const usm_param_info *info = usm_params_find(buf);
    if (!info) {
        snprintf(msg, USM_IO_MSG_LEN, "over-range: unknown parameter \"%s\"", buf);
        return USM_EINPUT;
    }
    if (usm_parse_quantity("over-range", info->unit, eq + 1, strlen(eq + 1), &r->lo, msg) !=
            USM_OK ||
        usm_parse_quantity("over-range", info->unit, c1 + 1, strlen(c1 + 1), &r->hi, msg) !=
            USM_OK)
        return USM_EINPUT;
    if (c2) {
        double n;
        if (usm_parse_number("over-range", c2 + 1, strlen(c2 + 1), &n, msg) != USM_OK)
            return USM_EINPUT;
        if (n != floor(n) || n < -2147483648.0 || n > 2147483647.0) {
            snprintf(msg, USM_IO_MSG_LEN, "over-range: \"%s\" must be an integer", c2 + 1);
            return USM_EINPUT;
        }
        r->points = (int)n;
    }
    if (!(r->lo < r->hi) || r->points < 2 || r->points > 100000) {
        snprintf(msg, USM_IO_MSG_LEN, "over-range: needs LO < HI and 2 <= N <= 100000");
        return USM_EINPUT;
    }
    r->param = usm_param_index(info);
    return USM_OK;
}

/* A sample count: a whole number in the range robust design takes. */
static int parse_count(const char *field, const char *value, uint64_t *out,
                       char msg[USM_IO_MSG_LEN])
{
    double v;
    if (usm_parse_number(field, value, strlen(value), &v, msg) != USM_OK)
        return USM_EINPUT;
    if (!(v >= (double)USM_ROBUST_MIN_SAMPLES && v <= (double)USM_ROBUST_MAX_SAMPLES) ||
        v != floor(v)) {
        snprintf(msg, USM_IO_MSG_LEN, "%s: a whole number %llu to %llu, got \"%.800s\"", field,
                 (unsigned long long)USM_ROBUST_MIN_SAMPLES,
                 (unsigned long long)USM_ROBUST_MAX_SAMPLES, value);
        return USM_EINPUT;
    }
    *out = (uint64_t)v;
    return USM_OK;
}

static int parse_int(const char *field, const char *value, int *out, char msg[USM_IO_MSG_LEN])
{
    double v;
    if (usm_parse_number(field, value, strlen(value), &v, msg) != USM_OK)
        return USM_EINPUT;
    if (v != floor(v) || v < -2147483648.0 || v > 2147483647.0) {
        snprintf(msg, USM_IO_MSG_LEN, "%s: \"%.800s\" must be an integer", field, value);
        return USM_EINPUT;
    }
    *out = (int)v;
    return USM_OK;
}

int usm_robust_option_parse(usm_robust_problem *rp, const char *name, const char *value,
                            char msg[USM_IO_MSG_LEN])
{
    if (strcmp(name, "scatter") == 0) {
        if (rp->nscatter >= USM_ROBUST_MAX_SCATTER) {
            snprintf(msg, USM_IO_MSG_LEN, "scatter: at most %d", USM_ROBUST_MAX_SCATTER);
            return USM_EINPUT;
        }
        if (usm_tolerance_vary_parse_units("scatter:", value, &rp->scatter[rp->nscatter], msg) !=
            USM_OK)
            return USM_EINPUT;
        rp->nscatter++;
        return USM_OK;
    }
    if (strcmp(name, "samples") == 0)
        return parse_count(name, value, &rp->samples, msg);
    if (strcmp(name, "verify-samples") == 0)
        return parse_count(name, value, &rp->verify_samples, msg);
    if (strcmp(name, "seed") == 0) {
        double v;
        if (usm_parse_number(name, value, strlen(value), &v, msg) != USM_OK)
            return USM_EINPUT;
        if (!(v >= 0 && v <= (double)USM_SEED_MAX) || v != floor(v)) {
            snprintf(msg, USM_IO_MSG_LEN, "seed: a whole number 0 to %llu, got \"%.800s\"",
                     (unsigned long long)USM_SEED_MAX, value);
            return USM_EINPUT;
        }
        rp->seed = (uint64_t)v;
        return USM_OK;
    }
    if (strcmp(name, "threads") == 0)
        return parse_int(name, value, &rp->threads, msg);
    if (strcmp(name, "max-evals") == 0)
        return parse_int(name, value, &rp->max_evals, msg);
    if (strcmp(name, "over-range") == 0)
        return usm_robust_range_parse(&rp->qopt.range, value, msg);
    if (strcmp(name, "range-stat") == 0) {
        const int s = usm_range_stat_find(value);
        if (s < 0) {
            snprintf(msg, USM_IO_MSG_LEN, "range-stat: one of worst, mean, integral, got "
                     "\"%.800s\"", value);
            return USM_EINPUT;
        }
        rp->qopt.range.stat = (usm_range_stat)s;
        return USM_OK;
    }
    if (strcmp(name, "band-threshold") == 0)
        return usm_parse_number(name, value, strlen(value), &rp->qopt.band_threshold, msg);
    return 1;
}
