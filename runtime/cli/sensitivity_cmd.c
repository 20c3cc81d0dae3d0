#define _POSIX_C_SOURCE 200809L /* strtok_r */
/* usm sensitivity: derivatives and elasticities of the primary stationary
 * solution's outputs with respect to every parameter (usm_design.h). */
#include <stdio.h>
#include <string.h>

#include "commands.h"
#include "diag.h"
#include "options.h"
#include "usm_design.h"
#include "usm_io.h"
#include "usm_run.h"

static void usage(FILE *out)
{
    fprintf(out,
            "usage: usm sensitivity [--model 3dof|4dof] [--variant V] [--params FILE.json]\n"
            "                       [--set NAME=VALUE]... [--of NAME,...] [--json]\n"
            "\n"
            "Derivatives dy/dp and elasticities (p/y) dy/dp of the primary stationary\n"
            "solution's outputs y with respect to every parameter p: implicit function\n"
            "theorem on the generated Jacobians; max_modulus by eigenvalue perturbation of\n"
            "the monodromy matrix (exponential method, t0 = 0) with its exact derivative.\n"
            "\n"
            "options:\n");
    cli_common_usage(out);
    fprintf(out, "  --of NAME,...       outputs (default all of the first seven):");
    for (int k = 0; k < USM_SENS_COUNT; ++k)
        fprintf(out, "%s%s", k % 5 == 0 ? "\n                        " : " ",
                usm_sensitivity_output_name(k));
    fprintf(out,
            "\n  -h, --help          print this help\n"
            "\n"
            "The table lists, per output, the parameters by decreasing |elasticity|.\n"
            "Axisymmetric models: the derivative in I_xx moves I_yy with it (I_yy: 0).\n"
            "A derivative that does not exist (a repeated multiplier pair, efficiency at\n"
            "power_in <= 0) is reported as such: \"undefined\" with the reason, null in JSON.\n"
            "\n"
            "exit status: 0 solved, 1 numerical failure, 2 bad input,\n"
            "             3 no stationary solution\n");
}

typedef struct sens_args {
    cli_common common;
    int want[USM_SENS_COUNT];
} sens_args;

static int parse_of(sens_args *a, const char *text, char msg[CLI_MSG_LEN])
{
    char buf[512];
    if (strlen(text) >= sizeof buf || text[0] == '\0') {
        cli_msg(msg, "--of: expected a comma-separated list of outputs");
        return USM_EINPUT;
    }
    memset(a->want, 0, sizeof a->want);
    strcpy(buf, text);
    for (char *save = NULL, *tok = strtok_r(buf, ",", &save); tok;
         tok = strtok_r(NULL, ",", &save)) {
        int k = usm_sensitivity_output_find(tok);
        if (k < 0) {
            cli_msg(msg, "--of: unknown output \"%s\" (see usm sensitivity --help)", tok);
            return USM_EINPUT;
        }
        a->want[k] = 1;
    }
    return USM_OK;
}

static int init(void *p, char msg[CLI_MSG_LEN])
{
    sens_args *a = p;
    (void)msg;
    usm_sensitivity_outputs_default(a->want);
    return USM_OK;
}

static int option(void *p, int argc, char **argv, int *i, char msg[CLI_MSG_LEN])
{
    sens_args *a = p;
    const char *value;
    CLI_TRY(cli_common_option(&a->common, argc, argv, i, msg));
    int r = cli_option_value(argc, argv, i, "--of", &value, msg);
    return r == CLI_OPT_TAKEN && parse_of(a, value, msg) != USM_OK ? CLI_OPT_ERROR : r;
}

static int table(const void *p, const usm_run *r, FILE *out)
{
    const sens_args *a = p;
    usm_sensitivity_write_table(a->common.model, &a->common.params,
                                usm_run_sensitivity_result(r), a->want, out);
    return 0;
}

static int run(void *p)
{
    const sens_args *a = p;
    usm_run *r = usm_run_sensitivity(a->common.model, &a->common.params, a->want);
    int status = cli_run_output(r, a->common.json, 0, table, a);
    usm_run_free(r);
    return status;
}

const cli_command cli_sensitivity = {sizeof(sens_args), usage, init, option, NULL, run, 0, 0};
