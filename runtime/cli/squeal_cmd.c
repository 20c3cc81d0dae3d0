/* usm squeal: what the motor does over one parameter beyond the last periodic
 * orbit: long event-driven runs, their stroboscopic samples, Lyapunov
 * exponents, the kind of motion and the audible lines (usm_squeal_study.h). */
#define _POSIX_C_SOURCE 200809L

#include <stdio.h>
#include <string.h>

#include "commands.h"
#include "diag.h"
#include "options.h"
#include "progress.h"
#include "usm_io.h"
#include "usm_plot.h"
#include "usm_run.h"
#include "usm_squeal_study.h"

/* The variant of base `base` whose contact may open: the default here. */
static const char *default_variant(const char *base)
{
    for (int k = 0; k < USM_NMODELS; ++k)
        if (usm_models[k]->unilateral && usm_models[k]->imperfect &&
            strcmp(usm_models[k]->base, base) == 0)
            return usm_models[k]->variant;
    return "paper";
}

static void usage(FILE *out)
{
    fprintf(out,
            "usage: usm squeal --over NAME --from A --to B [--points N]\n"
            "                  [--model 3dof|4dof] [--variant NAME] [--params FILE.json]\n"
            "                  [--set NAME=VALUE]... [--settle N] [--window N]\n"
            "                  [--lyapunov-periods N] [--power-periods N] [--sensitivities]\n"
            "                  [--no-rest-check] [--rtol R]\n"
            "                  [--out FILE.csv] [--plot PREFIX] [--force] [--json] [--quiet]\n"
            "\n"
            "What the motor does at N values of one parameter, where its periodic orbit\n"
            "may be lost: at each value a long event-driven run (from rest at A, then from\n"
            "the previous value's end state; and from rest again as a check of coexisting\n"
            "attractors), its settled window's stroboscopic samples (once an excitation\n"
            "period: rotor speed, tilt, gap), the largest Lyapunov exponent (tangent\n"
            "vectors through the saltation matrices), the kind of motion (periodic with\n"
            "period k, quasi_periodic with its second frequency, chaotic), mean speed and\n"
            "ripple, impact rate and largest impact velocity, and the audible lines\n"
            "(20 Hz - 20 kHz) of the stator rim's axial velocity at the contact point with\n"
            "their level in dB re 1e-9 m/s.  See docs/squeal.md.\n"
            "\n"
            "options:\n");
    cli_common_usage_variant(out, default_variant("3dof"));
    cli_units_usage(out);
    cli_quiet_usage(out);
    fprintf(out,
            "  --over NAME         the parameter to vary (any of usm steady --help)\n"
            "  --from A, --to B    the range, in the parameter's unit or with a unit (A != B)\n"
            "  --points N          values, 2 to 10000 (default 11)\n"
            "  --settle N          periods before the window (default 400)\n"
            "  --window N          periods of the settled window (default 1024: lines f/N\n"
            "                      apart)\n"
            "  --lyapunov-periods N  periods the exponent is averaged over (default 200,\n"
            "                      after 50 skipped)\n"
            "  --power-periods N   periods of the power account from the window's start:\n"
            "                      the power of excitation, damping, load, friction and\n"
            "                      impacts and the energy balance (default 200; 0: none)\n"
            "  --sensitivities     locate where the stable orbit ends past the origin and\n"
            "                      its derivative in F0, mu0, f, T and m0 (central\n"
            "                      differences; about 10 s of CPU): --json's \"onset\"\n"
            "  --no-rest-check     no second run from rest at each value\n"
            "  --rtol R            the simulation's relative tolerance (default 1e-8)\n"
            "  --out FILE.csv      write the CSV there instead of stdout\n"
            "  --plot PREFIX       the bifurcation diagram (rotor speed and tilt once a\n"
            "                      period over NAME) and the audible lines over NAME\n"
            "                      (coloured by level): PREFIX.csv, .gp, .png, .svg\n"
            "  --force             overwrite --out and the --plot files\n"
            "  -h, --help          print this help\n"
            "\n"
            "Output: CSV (default), one row per value: NAME, motion, period,\n"
            "second_frequency, lyapunov, lyapunov_per_period, rotor_speed_mean,\n"
            "rotor_speed_ripple, theta_mean, open_fraction, impacts_per_period,\n"
            "impact_velocity_max, the three strongest audible lines and levels, the\n"
            "powers [W] and energy_balance_error, rest_motion, coexisting, error, seconds.  --json: {model, over, sound_source,\n"
            "points: [{value, motion, period, lyapunov, lines: [{frequency, level_db}],\n"
            "...}]}.\n"
            "\n"
            "exit status: 0 done, 1 numerical failure or write error, 2 bad input\n");
}

typedef struct squeal_args {
    cli_common common;
    usm_squeal_options opt;
    const char *over, *from_text, *to_text, *out, *plot;
    int have_from, have_to, quiet, force, no_rest, lyap, power, sens;
    int settle, window;
} squeal_args;

static int init(void *p, char msg[CLI_MSG_LEN])
{
    squeal_args *a = p;
    (void)msg;
    usm_squeal_options_default(&a->opt);
    a->opt.points = 11;
    a->settle = (int)a->opt.settle;
    a->window = (int)a->opt.window;
    a->lyap = (int)a->opt.lyapunov_periods;
    a->power = (int)a->opt.power_periods;
    a->common.variant = default_variant(a->common.base);
    return USM_OK;
}

static int option(void *p, int argc, char **argv, int *i, char msg[CLI_MSG_LEN])
{
    squeal_args *a = p;
    int r;
    CLI_TRY(cli_common_option(&a->common, argc, argv, i, msg));
    CLI_TRY(cli_quiet_option(&a->quiet, argc, argv, i));
    CLI_TRY(cli_flag_option(argv, i, "--force", &a->force));
    CLI_TRY(cli_flag_option(argv, i, "--no-rest-check", &a->no_rest));
    CLI_TRY(cli_flag_option(argv, i, "--sensitivities", &a->sens));
    CLI_TRY(cli_option_value(argc, argv, i, "--over", &a->over, msg));
    CLI_TRY(cli_path_option(argc, argv, i, "--out", "value", &a->out, msg));
    CLI_TRY(cli_plot_option(argc, argv, i, &a->plot, msg));
    if ((r = cli_option_value(argc, argv, i, "--from", &a->from_text, msg)) != CLI_OPT_NOT_MINE)
        return a->have_from = 1, r;
    if ((r = cli_option_value(argc, argv, i, "--to", &a->to_text, msg)) != CLI_OPT_NOT_MINE)
        return a->have_to = 1, r;
    CLI_TRY(cli_int_option(argc, argv, i, "--settle", &a->settle, msg));
    CLI_TRY(cli_int_option(argc, argv, i, "--window", &a->window, msg));
    CLI_TRY(cli_int_option(argc, argv, i, "--lyapunov-periods", &a->lyap, msg));
    CLI_TRY(cli_int_option(argc, argv, i, "--power-periods", &a->power, msg));
    CLI_TRY(cli_quantity_option(argc, argv, i, "--rtol", "", &a->opt.rtol, msg));
    return cli_int_option(argc, argv, i, "--points", &a->opt.points, msg);
}

static int finish(void *p, char msg[CLI_MSG_LEN])
{
    squeal_args *a = p;
    if (!a->over || !a->have_from || !a->have_to) {
        cli_msg(msg, "%s: required (see usm squeal --help)",
                !a->over ? "--over" : !a->have_from ? "--from" : "--to");
        return USM_EINPUT;
    }
    const usm_param_info *over = usm_params_find(a->over);
    if (!over) {
        cli_msg(msg, "--over: unknown parameter \"%s\" (see usm steady --help)", a->over);
        return USM_EINPUT;
    }
    if (cli_parse_quantity("--from", over->unit, a->from_text, &a->opt.from, msg) != USM_OK ||
        cli_parse_quantity("--to", over->unit, a->to_text, &a->opt.to, msg) != USM_OK)
        return USM_EINPUT;
    if (a->force && !a->out && !a->plot) {
        cli_msg(msg, "--force: only with --out or --plot (it overwrites their files)");
        return USM_EINPUT;
    }
    if (a->out || a->plot) {
        char files[USM_PLOT_MAX_FILES][USM_IO_PATH_LEN], why[USM_IO_MSG_LEN];
        const char *paths[1 + USM_PLOT_MAX_FILES], *opts[1 + USM_PLOT_MAX_FILES];
        int n = 0;
        if (a->out)
            paths[n] = a->out, opts[n++] = "--out";
        const int m = a->plot ? usm_plot_files(a->plot, 1, files) : 0;
        if (m < 0) {
            cli_msg(msg, "--plot %.200s: path too long", a->plot);
            return USM_EINPUT;
        }
        for (int k = 0; k < m; ++k)
            paths[n] = files[k], opts[n++] = "--plot";
        if (usm_io_check_distinct(paths, opts, n, why) != USM_OK) {
            cli_msg(msg, "%s", why);
            return USM_EINPUT;
        }
        /* refused before the (long) study, not after it */
        if (a->plot && usm_plot_csv_check(a->plot, a->force, msg) != USM_OK)
            return USM_EINPUT;
        if (a->out && usm_io_check(a->out, a->force, why) != USM_OK) {
            cli_msg(msg, "--out %s", why);
            return USM_EINPUT;
        }
    }
    a->opt.over = a->over;
    a->opt.settle = a->settle;
    a->opt.window = a->window;
    a->opt.lyapunov_periods = a->lyap;
    a->opt.power_periods = a->power;
    a->opt.sensitivities = a->sens;
    a->opt.check_rest = !a->no_rest;
    return cli_common_finish(&a->common, msg);
}

static int write_csv(const void *p, const usm_run *r, FILE *out)
{
    const squeal_args *a = p;
    cli_shown shown;
    FILE *f = cli_shown_open(&shown, &a->common.display, out);
    int rc = !f ? -1 : usm_squeal_write_csv(usm_run_squeal_result(r), f);
    return f && cli_shown_close(&shown) != 0 ? -1 : rc;
}

/* --out: the CSV into its file, whole or not at all */
static int write_out(const void *p, const usm_run *r, FILE *out)
{
    const squeal_args *a = p;
    char msg[USM_IO_MSG_LEN];
    int status;
    usm_io_file file;
    (void)out;
    FILE *f = usm_io_create(&file, a->out, a->force, msg, &status);
    if (!f) {
        cli_error("--out %s", msg);
        return -1;
    }
    if (write_csv(p, r, f) != 0) {
        usm_io_abort(&file);
        cli_error("--out %s: write error", a->out);
        return -1;
    }
    if (usm_io_commit(&file, msg) != USM_OK) {
        cli_error("--out %s", msg);
        return -1;
    }
    return 0;
}

static int plot_csv(FILE *out, const void *data)
{
    return usm_squeal_write_plot_csv(data, out);
}

/* --plot: PREFIX.csv, then gnuplot on data/plots/squeal_study.gp; a missing
 * gnuplot is a warning (the CSV and PREFIX.gp are there to plot later). */
static int plot(const squeal_args *a, const usm_run *r)
{
    char msg[CLI_MSG_LEN], xcol[128];
    const usm_param_info *info = usm_params_find(a->over);
    int rc = usm_plot_csv_write(a->plot, a->force, plot_csv, usm_run_squeal_result(r), msg);
    if (rc != USM_OK) {
        cli_error("%s", msg);
        return rc;
    }
    snprintf(xcol, sizeof xcol, "%s [%s]", a->over, info && info->unit[0] ? info->unit : "1");
    const char *names[] = {"xcol"};
    const char *values[] = {xcol};
    rc = usm_plot_render("squeal_study", a->plot, names, values, 1, msg);
    return cli_plot_status(rc, msg);
}

static int run(void *p)
{
    squeal_args *a = p;
    cli_progress progress;
    cli_progress_init(&progress, "usm squeal", a->quiet);
    progress.total = a->opt.points;
    progress.what = "points";
    a->opt.progress = progress.on ? cli_progress_fraction : NULL;
    a->opt.progress_ctx = &progress;
    usm_run *r = usm_run_squeal(a->common.model, &a->common.params, &a->opt);
    cli_progress_end(&progress);
    int status;
    if (a->out && !a->common.json && r && usm_run_status(r) == USM_OK)
        status = write_out(a, r, stdout) == 0 ? USM_OK : USM_EFAILED;
    else
        status = cli_run_output(r, a->common.json, 0, write_csv, a);
    if (status == USM_OK && a->out && a->common.json && write_out(a, r, stdout) != 0)
        status = USM_EFAILED;
    if (status == USM_OK && a->plot)
        status = plot(a, r);
    usm_run_free(r);
    return status;
}

const cli_command cli_squeal = {sizeof(squeal_args), usage, init, option, finish, run, 0, 1};
