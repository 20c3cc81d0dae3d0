/* usm steady: every stationary solution of a model and the Floquet
 * multipliers of each (the top level: the primary one, smallest tilt). */
#include <stdio.h>
#include <string.h>

#include "commands.h"
#include "diag.h"
#include "options.h"
#include "usm_io.h"
#include "usm.h"
#include "usm_operating_point.h"
#include "usm_run.h"

static void usage(FILE *out)
{
    fprintf(out,
            "usage: usm steady [--model 3dof|4dof] [--variant NAME] [--params FILE.json]\n"
            "                  [--set NAME=VALUE]... [--t0 S] [--floquet-method NAME] [--rtol R]\n"
            "                  [--no-from-rest | --from-rest-periods N] [--json]\n"
            "\n"
            "Find every stationary solution (paper, eq. 3.1), the Floquet multipliers of\n"
            "each, and the operating point: the stable root the motor reaches from rest.\n"
            "The summary at the top is the operating point (else the root with the\n"
            "smallest tilt, said so).\n"
            "\n"
            "options:\n");
    cli_common_usage(out);
    cli_units_usage(out);
    fprintf(out,
            "  --t0 S              start of the Floquet period [s] (default 0, the paper's)\n"
            "  --no-from-rest      skip the start-up simulation: an ambiguous point then has\n"
            "                      no operating point (undecided).  By default a point is\n"
            "                      simulated from rest (below every unstable root) only when\n"
            "                      it is ambiguous: several roots with a stable one, or one\n"
            "                      stable root while the preload's moment holds the stator at\n"
            "                      rest (start margin <= 0); 0.1 .. 2 s.  --from-rest is\n"
            "                      accepted (the default)\n"
            "  --from-rest-periods N  length of that simulation in excitation periods\n"
            "                      (default 400)\n");
    cli_floquet_usage(out);
    fprintf(out,
            "  -h, --help          print this help\n"
            "\n"
            "a value outside its range is refused as one typed in the wrong unit (docs/cli.md)\n"
            "parameters (SI units; defaults from the paper, Appendix A; range):\n");
    {
        usm_params def;
        int width = 0;
        usm_params_default(&def);
        for (int k = 0; k < USM_NPARAMS; ++k)
            if ((int)strlen(usm_param_table[k].name) > width)
                width = (int)strlen(usm_param_table[k].name);
        for (int k = 0; k < USM_NPARAMS; ++k) {
            const usm_param_info *info = &usm_param_table[k];
            char range[48];
            snprintf(range, sizeof range, "%g..%g", usm_param_ranges[k].lo,
                     usm_param_ranges[k].hi);
            fprintf(out, "  %-*s %-12.7g %-10s %-18s %s\n", width, info->name,
                    usm_params_get(&def, info), info->unit, range, info->description);
        }
    }
    /* the units table of usm_parse_quantity, one line per SI unit in use */
    fprintf(out, "\nunits a value may be typed in (--set f=37.5kHz, phase_error=10deg;\n"
                 "also --from/--to, --x-from.., --vary and strings in --params files):\n");
    for (int k = 0; k < USM_NPARAMS; ++k) {
        const char *unit = usm_param_table[k].unit;
        char known[256];
        int seen = 0;
        for (int j = 0; j < k; ++j)
            seen |= strcmp(usm_param_table[j].unit, unit) == 0;
        if (!seen && usm_units_accepted(unit, known, sizeof known) > 0)
            fprintf(out, "  %-10s %s\n", unit, known);
    }
    fprintf(out,
            "\n"
            "exit status: 0 solved, 1 numerical failure, 2 bad input,\n"
            "             3 no stationary solution (--json still prints converged=false)\n");
}

typedef struct steady_args {
    cli_common common;
    usm_floquet_options floquet;
    usm_op_options op;
    double t0;
} steady_args;

static int init(void *p, char msg[CLI_MSG_LEN])
{
    steady_args *a = p;
    (void)msg;
    usm_floquet_options_default(&a->floquet);
    usm_op_options_default(&a->op);
    a->op.from_rest = 1; /* one point: decide it */
    return USM_OK;
}

static int option(void *p, int argc, char **argv, int *i, char msg[CLI_MSG_LEN])
{
    steady_args *a = p;
    CLI_TRY(cli_common_option(&a->common, argc, argv, i, msg));
    CLI_TRY(cli_floquet_option(&a->floquet, argc, argv, i, msg));
    CLI_TRY(cli_from_rest_option(&a->op, argc, argv, i, msg));
    return cli_quantity_option(argc, argv, i, "--t0", "s", &a->t0, msg);
}

static int table(const void *p, const usm_run *r, FILE *out)
{
    (void)p;
    usm_steady_table_in(usm_run_steady_report(r), &((const cli_common *)p)->display, out);
    return 0;
}

static int run(void *p)
{
    const steady_args *a = p;
    const cli_common *c = &a->common;
    usm_run *r = usm_run_steady(c->model, &c->params, a->t0, &a->floquet, &a->op);
    /* also converged = false (no stationary solution: exit 3, no message) */
    int status = cli_run_output(r, c->json, CLI_JSON_ON_FAILURE, table, a);
    usm_run_free(r);
    return status;
}

const cli_command cli_steady = {sizeof(steady_args), usage, init, option, NULL, run, 0, 1};
