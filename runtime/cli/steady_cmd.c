/* usm steady: every stationary solution of a model and the Floquet
 * multipliers of each (the top level: the primary one, smallest tilt). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "commands.h"
#include "diag.h"
#include "options.h"
#include "usm_io.h"
#include "usm.h"
#include "usm_operating_point.h"

static void usage(FILE *out)
{
    fprintf(out,
            "usage: usm steady [--model 3dof|4dof] [--variant NAME] [--params FILE.json]\n"
            "                  [--set NAME=VALUE]... [--t0 S] [--floquet-method NAME] [--rtol R]\n"
            "                  [--from-rest [--from-rest-periods N]] [--json]\n"
            "\n"
            "Find every stationary solution (paper, eq. 3.1) and the Floquet multipliers of\n"
            "each; the summary at the top is the one with the smallest tilt.\n"
            "\n"
            "options:\n");
    cli_common_usage(out);
    fprintf(out,
            "  --t0 S              start of the Floquet period [s] (default 0, the paper's)\n"
            "  --from-rest         simulate the start-up from rest to find the operating point\n"
            "                      (the stable root the motor reaches) where several roots exist\n"
            "  --from-rest-periods N  length of that simulation in excitation periods\n"
            "                      (default 400)\n");
    cli_floquet_usage(out);
    fprintf(out,
            "  -h, --help          print this help\n"
            "\n"
            "parameters (SI units; defaults from the paper, Appendix A):\n");
    {
        usm_params def;
        int width = 0;
        usm_params_default(&def);
        for (int k = 0; k < USM_NPARAMS; ++k)
            if ((int)strlen(usm_param_table[k].name) > width)
                width = (int)strlen(usm_param_table[k].name);
        for (int k = 0; k < USM_NPARAMS; ++k) {
            const usm_param_info *info = &usm_param_table[k];
            fprintf(out, "  %-*s %-12.7g %-10s %s\n", width, info->name,
                    usm_params_get(&def, info), info->unit, info->description);
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
    int help;
} steady_args;

static int parse(steady_args *a, int argc, char **argv, char msg[CLI_MSG_LEN])
{
    cli_common_init(&a->common);
    usm_floquet_options_default(&a->floquet);
    usm_op_options_default(&a->op);
    a->t0 = 0.0;
    a->help = 0;
    for (int i = 1; i < argc; ++i) {
        const char *value;
        int r;
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            a->help = 1;
            return USM_OK;
        }
        if ((r = cli_common_option(&a->common, argc, argv, &i, msg)) == CLI_OPT_TAKEN)
            continue;
        if (r == CLI_OPT_ERROR)
            return USM_EINPUT;
        if ((r = cli_floquet_option(&a->floquet, argc, argv, &i, msg)) == CLI_OPT_TAKEN)
            continue;
        if (r == CLI_OPT_ERROR)
            return USM_EINPUT;
        if ((r = cli_from_rest_option(&a->op, argc, argv, &i, msg)) == CLI_OPT_TAKEN)
            continue;
        if (r == CLI_OPT_ERROR)
            return USM_EINPUT;
        if ((r = cli_option_value(argc, argv, &i, "--t0", &value, msg)) == CLI_OPT_ERROR)
            return USM_EINPUT;
        if (r == CLI_OPT_TAKEN) {
            if (cli_parse_quantity("--t0", "s", value, &a->t0, msg) != USM_OK)
                return USM_EINPUT;
            continue;
        }
        if (argv[i][0] == '-')
            cli_msg(msg, "%s: unknown option (see usm steady --help)", argv[i]);
        else
            cli_msg(msg, "%s: unexpected argument (see usm steady --help)", argv[i]);
        return USM_EINPUT;
    }
    return cli_common_finish(&a->common, msg);
}

static int emit_json(const usm_steady_report *rep)
{
    int rc = usm_steady_write_json(rep, stdout);
    /* Flush here so that a write error is reported once, by this function,
     * and main's final check (after clearerr) does not repeat it. */
    if (rc != 0 || fflush(stdout) != 0 || ferror(stdout)) {
        clearerr(stdout);
        cli_error("stdout: write error");
        return USM_EFAILED;
    }
    return USM_OK;
}

static int run(const steady_args *a)
{
    const cli_common *c = &a->common;
    usm_steady_report rep = {c->model, &c->params, NULL, NULL, NULL, NULL, NULL};
    usm_floquet_result *res = NULL;
    usm_op_result op;
    usm_floquet *fl = NULL;
    const char *bad;
    int status;
    usm_steady *s = usm_steady_alloc(c->model);
    if (!s) {
        cli_error("out of memory");
        return USM_EFAILED;
    }
    rep.steady = s;
    status = usm_steady_solve(s, &c->params, NULL);
    if (status == USM_ENOSOLUTION) {
        rep.error = usm_steady_message(s);
        if (c->json) {
            int rc = emit_json(&rep);
            status = rc != USM_OK ? rc : status;
        } else
            cli_error("no stationary solution: %s", rep.error);
        goto done;
    }
    if (status == USM_EINPUT) {
        cli_error("%s", usm_steady_message(s));
        goto done;
    }
    if (status != USM_OK || usm_steady_count(s) == 0) {
        cli_error("steady: %s", usm_steady_message(s));
        status = USM_EFAILED;
        goto done;
    }
    if (!(fl = usm_floquet_alloc(c->model))) {
        cli_error("out of memory");
        status = USM_EFAILED;
        goto done;
    }
    if (!(res = malloc(usm_steady_count(s) * sizeof *res))) {
        cli_error("out of memory");
        status = USM_EFAILED;
        goto done;
    }
    /* every root's multipliers; the top level keeps describing root 0 */
    status = usm_floquet_roots(fl, &c->params, s, a->t0, &a->floquet, res);
    if (status != USM_OK) {
        cli_error("floquet: %s", usm_floquet_message(fl));
        status = status == USM_EINPUT ? USM_EINPUT : USM_EFAILED;
        goto done;
    }
    for (size_t k = 0; k < usm_steady_count(s); ++k)
        /* "never NaN in the output": a non-finite value is a numerical failure */
        if ((bad = usm_steady_nonfinite(usm_steady_root(s, k), &res[k]))) {
            cli_error("%s", bad);
            status = USM_EFAILED;
            goto done;
        }
    rep.floquet = &res[0];
    rep.roots_floquet = res;
    /* the operating point: cheap where one root is stable, a simulation from
     * rest where asked (usm_operating_point.h) */
    status = usm_operating_point(c->model, &c->params, s, res, &a->op, &op);
    if (status != USM_OK) {
        cli_error("%s", op.message);
        goto done;
    }
    rep.op = &op;
    if (c->json)
        status = emit_json(&rep);
    else
        usm_steady_table(&rep, stdout);
done:
    free(res);
    if (fl)
        usm_floquet_free(fl);
    usm_steady_free(s);
    return status;
}

int cli_steady_main(int argc, char **argv)
{
    steady_args a;
    char msg[CLI_MSG_LEN];
    if (parse(&a, argc, argv, msg) != USM_OK) {
        cli_error("%s", msg);
        return USM_EINPUT;
    }
    if (a.help) {
        usage(stdout);
        return USM_OK;
    }
    return run(&a);
}
