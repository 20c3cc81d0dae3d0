/* usm fit: parameters identified from measured characteristics (usm_fit.h):
 * parse, call usm_run_fit, write. */
#include <stdio.h>
#include <string.h>

#include "commands.h"
#include "diag.h"
#include "options.h"
#include "usm_fit.h"
#include "usm_io.h"
#include "usm_plot.h"
#include "usm_run.h"

static void usage(FILE *out)
{
    fprintf(out,
            "usage: usm fit --data FILE.csv --fit NAME[,NAME...]\n"
            "               [--model 3dof|4dof] [--variant V] [--params FILE.json]\n"
            "               [--set NAME=VALUE]... [--starts N] [--units LIST]\n"
            "               [--out FILE.csv] [--plot PREFIX] [--force] [--json]\n"
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
            "                      efficiency, stick_margin, power_out; the datasheet's\n"
            "                      stall_torque [mNm], no_load_speed, max_power,\n"
            "                      speed_max_frequency [kHz]: the f of the speed maximum),\n"
            "                      sigma_OUTPUT\n"
            "  --fit NAME,...      the parameters to fit (their --set/--params values start)\n"
            "  --starts N          starts of the local search (default 4; 1: from the given\n"
            "                      values only): the given values and the best of a Sobol\n"
            "                      sample of the box --spread around them\n"
            "  --spread F          the starts' box: the given values divided and multiplied\n"
            "                      by F (log-scale parameters; default 100), clipped to the\n"
            "                      physical ranges\n"
            "  --out FILE.csv      the residuals per measured value\n"
            "  --plot PREFIX       PREFIX.csv (the residuals) and the figure PREFIX.png/svg:\n"
            "                      measured and model values over the condition with the\n"
            "                      most distinct values, and the residuals (gnuplot)\n"
            "  --force             overwrite the --out and --plot files\n"
            "  -h, --help          print this help\n"
            "\n"
            "exit status: 0 fitted, 1 numerical failure, 2 bad input or data,\n"
            "             3 no start gives a finite sum of squares\n");
}

typedef struct fit_args {
    cli_common common;
    const char *data, *names, *out, *plot;
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
    CLI_TRY(cli_plot_option(argc, argv, i, &a->plot, msg));
    CLI_TRY(cli_int_option(argc, argv, i, "--starts", &a->opt.starts, msg));
    CLI_TRY(cli_quantity_option(argc, argv, i, "--spread", "1", &a->opt.spread, msg));
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
    if (a->force && !a->out && !a->plot) {
        cli_msg(msg, "--force: only with --out or --plot");
        return USM_EINPUT;
    }
    if (a->out && a->plot) { /* one run's outputs: distinct files */
        char files[USM_PLOT_MAX_FILES][USM_IO_PATH_LEN];
        const char *paths[USM_PLOT_MAX_FILES + 1], *opts[USM_PLOT_MAX_FILES + 1];
        int n = usm_plot_files(a->plot, 1, files);
        if (n < 0) {
            cli_msg(msg, "--plot %.200s: path too long", a->plot);
            return USM_EINPUT;
        }
        paths[0] = a->out;
        opts[0] = "--out";
        for (int k = 0; k < n; ++k) {
            paths[k + 1] = files[k];
            opts[k + 1] = "--plot";
        }
        if (usm_io_check_distinct(paths, opts, n + 1, msg) != USM_OK)
            return USM_EINPUT;
    }
    if (a->plot && usm_plot_csv_check(a->plot, a->force, msg) != USM_OK)
        return USM_EINPUT;
    if (a->opt.starts < 1 || a->opt.starts > 100) {
        cli_msg(msg, "--starts: %d is not in 1..100", a->opt.starts);
        return USM_EINPUT;
    }
    if (!(a->opt.spread >= 1 && a->opt.spread <= 1e6)) {
        cli_msg(msg, "--spread: %g is not in 1..1e6", a->opt.spread);
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

static int residuals_csv(FILE *out, const void *p)
{
    const usm_run *r = p;
    return usm_fit_write_csv(usm_run_fit_data(r), usm_run_fit_result(r), out);
}

/* --plot: the residuals' CSV and the figure over the condition with the most
 * distinct values (the curve's axis: f of a speed-frequency curve) */
static int plot(const fit_args *a, const usm_run *r)
{
    char msg[CLI_MSG_LEN], xcol[96] = "row";
    const usm_fit_data *d = usm_run_fit_data(r);
    int rc = usm_plot_csv_write(a->plot, a->force, residuals_csv, r, msg);
    if (rc != USM_OK) {
        cli_error("%s", msg);
        return rc;
    }
    int best = -1, most = 0;
    for (int c = 0; c < d->ncond; ++c) {
        int distinct = 0;
        for (int i = 0; i < d->nrows; ++i) {
            int seen = 0;
            for (int j = 0; j < i && !seen; ++j)
                seen = d->x[(size_t)j * (size_t)d->ncond + (size_t)c] ==
                       d->x[(size_t)i * (size_t)d->ncond + (size_t)c];
            distinct += !seen;
        }
        if (distinct > most) {
            most = distinct;
            best = c;
        }
    }
    if (best >= 0)
        snprintf(xcol, sizeof xcol, "%s [%s]", usm_param_table[d->cond[best]].name,
                 usm_param_table[d->cond[best]].unit);
    const char *names[] = {"xcol"};
    const char *values[] = {xcol};
    return cli_plot_status(usm_plot_render("fit", a->plot, names, values, 1, msg), msg);
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
    if (status == USM_OK && a->plot)
        status = plot(a, r);
    usm_run_free(r);
    return status;
}

const cli_command cli_fit = {sizeof(fit_args), usage, init, option, finish, run, 0, 1};
