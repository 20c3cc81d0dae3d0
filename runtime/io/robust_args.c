/* robust_args.c: the texts of a robust problem (usm_robust.h) as usm
 * optimize's options and the Python package's arguments give them:
 * --objective yield|NAME|mean:NAME|qNN:NAME and the constraints on the yield
 * and the derived quantities; and usm pareto's --objectives A,B. */
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
