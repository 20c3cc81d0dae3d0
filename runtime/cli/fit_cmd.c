/* usm fit: parameters identified from measured characteristics (usm_fit.h):
 * parse, call usm_run_fit, write. */
#include <stdio.h>
#include <string.h>

#include "commands.h"
#include "diag.h"
#include "options.h"
#include "usm_fit.h"
#include "usm_io.h"
#include "usm_run.h"

static void usage(FILE *out)
{
    fprintf(out,
            "usage: usm fit --data FILE.csv --fit NAME[,NAME...]\n"
            "               [--model 3dof|4dof] [--variant V] [--params FILE.json]\n"
            "               [--set NAME=VALUE]... [--starts N] [--units LIST]\n"
            "               [--out FILE.csv [--force]] [--json]\n"
            "\n"
            "Fit the parameters NAME,... to measured characteristics: weighted least\n"
            "squares (Levenberg-Marquardt with geodesic acceleration) on the analytic\n"
            "sensitivities, each measurement at the motor's operating point, parameters\n"
            "of non-negative range in log scale, several starts.  Reports estimates,\n"
            "standard errors, 95 %% intervals, correlations, chi^2 and its p-value, the\n"
            "residuals, and which combinations the data cannot determine, with the\n"
            "measurement that would.  docs/fit.md.\n"
            "\n"
            "options:\n");
    cli_common_usage(out);
    cli_units_usage(out);
    fprintf(out,
            "  --data FILE.csv     the measurements: columns named by parameter (the\n"
            "                      conditions: f [kHz], T [mNm], ...) and by output (speed\n"
            "                      [rpm], rotor_speed, power_in [W], theta, F_n, F_t,\n"
            "                      efficiency, stick_margin, power_out), sigma_OUTPUT\n"
            "  --fit NAME,...      the parameters to fit (their --set/--params values start)\n"
            "  --starts N          starts of the local search (default 4; 1: from the given\n"
            "                      values only)\n"
            "  --out FILE.csv      the residuals per measured value\n"
            "  --force             overwrite --out\n"
            "  -h, --help          print this help\n"
            "\n"
            "exit status: 0 fitted, 1 numerical failure, 2 bad input or data,\n"
            "             3 no start gives a finite sum of squares\n");
}

typedef struct fit_args {
    cli_common common;
    const char *data, *names, *out;
    int force;
    usm_fit_options opt;
} fit_args;

static int init(void *p, char msg[CLI_MSG_LEN])
{
    fit_args *a = p;
    (void)msg;
    usm_fit_options_default(&a->opt);
    return USM_OK;
}

static int option(void *p, int argc, char **argv, int *i, char msg[CLI_MSG_LEN])
{
    fit_args *a = p;
    CLI_TRY(cli_flag_option(argv, i, "--force", &a->force));
    CLI_TRY(cli_common_option(&a->common, argc, argv, i, msg));
    CLI_TRY(cli_path_option(argc, argv, i, "--data", "file name", &a->data, msg));
    CLI_TRY(cli_path_option(argc, argv, i, "--out", "file name", &a->out, msg));
    CLI_TRY(cli_int_option(argc, argv, i, "--starts", &a->opt.starts, msg));
    return cli_option_value(argc, argv, i, "--fit", &a->names, msg);
}

static int finish(void *p, char msg[CLI_MSG_LEN])
{
    fit_args *a = p;
    if (!a->data || !a->names) {
        cli_msg(msg, "%s: required (usm fit --data FILE.csv --fit NAME[,NAME...])",
                a->data ? "--fit" : "--data");
        return USM_EINPUT;
    }
    if (a->force && !a->out) {
        cli_msg(msg, "--force: only with --out");
        return USM_EINPUT;
    }
    if (a->opt.starts < 1 || a->opt.starts > 100) {
        cli_msg(msg, "--starts: %d is not in 1..100", a->opt.starts);
        return USM_EINPUT;
    }
    return cli_common_finish(&a->common, msg);
}

static int table(const void *p, const usm_run *r, FILE *out)
{
    const fit_args *a = p;
    usm_fit_write_table(a->common.model, usm_run_fit_data(r), usm_run_fit_result(r),
                        &a->common.display, out);
    return 0;
}

static int write_out(const fit_args *a, const usm_run *r, char msg[CLI_MSG_LEN])
{
    usm_io_file file;
    int status;
    FILE *f = usm_io_create(&file, a->out, a->force, msg, &status);
    if (!f)
        return status;
    if (usm_fit_write_csv(usm_run_fit_data(r), usm_run_fit_result(r), f) != 0) {
        usm_io_abort(&file);
        cli_msg(msg, "%s: write error", a->out);
        return USM_EFAILED;
    }
    return usm_io_commit(&file, msg);
}

static int run(void *p)
{
    const fit_args *a = p;
    const cli_common *c = &a->common;
    char msg[CLI_MSG_LEN];
    /* an --out that cannot be written fails now, not after the fit */
    if (a->out && usm_io_check(a->out, a->force, msg) != USM_OK) {
        cli_error("--out %s", msg);
        return USM_EINPUT;
    }
    usm_run *r = usm_run_fit(c->model, &c->params, a->data, NULL, 0, a->names, &a->opt);
    int status = usm_run_status(r);
    if (status == USM_OK && a->out && (status = write_out(a, r, msg)) != USM_OK)
        cli_error("--out %s", msg);
    else
        status = cli_run_output(r, c->json, 0, table, a);
    usm_run_free(r);
    return status;
}

const cli_command cli_fit = {sizeof(fit_args), usage, init, option, finish, run, 0, 1};
