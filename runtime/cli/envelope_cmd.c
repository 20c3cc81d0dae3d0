/* usm envelope: the boundaries of the stationary solution continued in two
 * parameters, the codimension-two points, and the regions between the
 * curves with their operating class (usm_envelope.h). */
#define _POSIX_C_SOURCE 200809L

#include <stdio.h>
#include <string.h>

#include "commands.h"
#include "diag.h"
#include "options.h"
#include "usm.h"
#include "usm_envelope.h"
#include "usm_io.h"
#include "usm_plot.h"
#include "usm_run.h"

static void usage(FILE *out)
{
    fprintf(out,
            "usage: usm envelope --x NAME:LO:HI --y NAME:LO:HI\n"
            "                    [--model 3dof|4dof] [--variant NAME] [--params FILE.json]\n"
            "                    [--set NAME=VALUE]... [--lines N] [--nodes N] [--raster N]\n"
            "                    [--no-stability] [--t0 S] [--floquet-method NAME] [--rtol R]\n"
            "                    [--from-rest [--from-rest-periods N]] [--json]\n"
            "                    [--out FILE.csv] [--plot PREFIX] [--force]\n"
            "\n"
            "The operating envelope over two parameters: every boundary of the stationary\n"
            "solution that crosses the box (tilt_zero, fold, stick_limit, stall, stability,\n"
            "friction_saturation) continued as a curve of the extended system\n"
            "[r = 0; g = 0], the points where two curves meet or a fold curve has its\n"
            "cusp, and the regions between the curves with the operating class `usm map`\n"
            "gives there (docs/envelope.md).\n"
            "\n"
            "options:\n");
    cli_common_usage(out);
    cli_units_usage(out);
    fprintf(out,
            "  --x NAME:LO:HI, --y NAME:LO:HI   the box (LO < HI, SI or with a unit:\n"
            "                      --x f:36kHz:40kHz); two different parameters\n"
            "  --lines N           interior seed lines per direction (default 3)\n"
            "  --nodes N           full searches per seed line (default 9)\n"
            "  --raster N          cells per side of the regions' raster (default 120)\n"
            "  --no-stability      no stability curves (no Floquet multipliers on the way; the\n"
            "                      imperfect motor: nor its orbits' folds)\n"
            "  --t0 S              start of the Floquet period [s] (default 0)\n");
    cli_floquet_usage(out);
    cli_from_rest_usage(out);
    fprintf(out,
            "  --out FILE          write the CSV (or with --json the object) to FILE; an\n"
            "                      existing FILE is kept unless --force is given\n"
            "  --plot PREFIX       also draw the envelope with gnuplot: PREFIX.csv (the\n"
            "                      curves, the regions' cells), PREFIX.gp, PREFIX.png,\n"
            "                      PREFIX.svg; existing files are kept unless --force\n"
            "  --force             overwrite FILE and the --plot files\n"
            "  -h, --help          print this help\n"
            "\n"
            "Output: CSV, header curve,kind,X [unit],Y [unit]: one row per curve point, in\n"
            "order along each curve; then a comment line per codimension-two point and per\n"
            "region.  With --json one object: model, x, y, parameters, curves[] {kind,\n"
            "points [[x, y], ...], ends}, regions[] {class, root, sample [x, y], roots,\n"
            "cells, message}, codim2[] {type, point [x, y], curve, theta}, seeds,\n"
            "seeds_on_traced_curves.\n"
            "\n"
            "exit status: 0 done, 1 numerical failure or write error, 2 bad input\n");
}

typedef struct envelope_args {
    cli_common common;
    usm_envelope_options opt;
    const char *axis_text[2];
    char names[2][256];
    const char *out;
    const char *plot; /* --plot PREFIX, or NULL */
    int force, no_stability;
} envelope_args;

static int init(void *p, char msg[CLI_MSG_LEN])
{
    envelope_args *a = p;
    (void)msg;
    usm_envelope_options_default(&a->opt);
    return USM_OK;
}

static int option(void *p, int argc, char **argv, int *i, char msg[CLI_MSG_LEN])
{
    envelope_args *a = p;
    CLI_TRY(cli_flag_option(argv, i, "--force", &a->force));
    CLI_TRY(cli_flag_option(argv, i, "--no-stability", &a->no_stability));
    CLI_TRY(cli_common_option(&a->common, argc, argv, i, msg));
    CLI_TRY(cli_floquet_option(&a->opt.floquet, argc, argv, i, msg));
    CLI_TRY(cli_from_rest_option(&a->opt.op, argc, argv, i, msg));
    CLI_TRY(cli_int_option(argc, argv, i, "--lines", &a->opt.lines, msg));
    CLI_TRY(cli_int_option(argc, argv, i, "--nodes", &a->opt.nodes, msg));
    CLI_TRY(cli_int_option(argc, argv, i, "--raster", &a->opt.raster, msg));
    CLI_TRY(cli_quantity_option(argc, argv, i, "--t0", "s", &a->opt.t0, msg));
    CLI_TRY(cli_option_value(argc, argv, i, "--x", &a->axis_text[0], msg));
    CLI_TRY(cli_option_value(argc, argv, i, "--y", &a->axis_text[1], msg));
    CLI_TRY(cli_plot_option(argc, argv, i, &a->plot, msg));
    return cli_path_option(argc, argv, i, "--out", "file name", &a->out, msg);
}

/* NAME:LO:HI into the axis, LO and HI in the parameter's unit. */
static int parse_axis(envelope_args *a, int k, char msg[CLI_MSG_LEN])
{
    const char *field = k == 0 ? "--x" : "--y", *text = a->axis_text[k];
    usm_envelope_axis *ax = k == 0 ? &a->opt.x : &a->opt.y;
    char buf[256], *c1, *c2;
    if (!text) {
        cli_msg(msg, "%s: required (NAME:LO:HI)", field);
        return USM_EINPUT;
    }
    snprintf(buf, sizeof buf, "%s", text);
    if (!(c1 = strchr(buf, ':')) || !(c2 = strchr(c1 + 1, ':')) || strchr(c2 + 1, ':')) {
        cli_msg(msg, "%s: \"%s\" is not NAME:LO:HI", field, text);
        return USM_EINPUT;
    }
    *c1 = *c2 = '\0';
    const usm_param_info *info = usm_params_find(buf);
    if (!info) {
        cli_msg(msg, "%s: unknown parameter '%s' (see usm steady --help)", field, buf);
        return USM_EINPUT;
    }
    snprintf(a->names[k], sizeof a->names[k], "%s", buf);
    ax->name = a->names[k];
    if (cli_parse_quantity(field, info->unit, c1 + 1, &ax->lo, msg) != USM_OK ||
        cli_parse_quantity(field, info->unit, c2 + 1, &ax->hi, msg) != USM_OK)
        return USM_EINPUT;
    if (!(ax->lo < ax->hi)) {
        cli_msg(msg, "%s: LO (%s) must be below HI (%s)", field, c1 + 1, c2 + 1);
        return USM_EINPUT;
    }
    return USM_OK;
}

static int finish(void *p, char msg[CLI_MSG_LEN])
{
    envelope_args *a = p;
    if (parse_axis(a, 0, msg) != USM_OK || parse_axis(a, 1, msg) != USM_OK)
        return USM_EINPUT;
    if (strcmp(a->names[0], a->names[1]) == 0) {
        cli_msg(msg, "--y: the same parameter as --x (%s)", a->names[0]);
        return USM_EINPUT;
    }
    a->opt.stability = !a->no_stability;
    return cli_common_finish(&a->common, msg);
}

static int write_csv(const void *p, const usm_run *r, FILE *out)
{
    const envelope_args *a = p;
    cli_shown shown;
    FILE *f = cli_shown_open(&shown, &a->common.display, out);
    int rc = f ? usm_envelope_write_csv(usm_run_envelope_result(r), f) : -1;
    return f && cli_shown_close(&shown) != 0 ? -1 : rc;
}

/* PREFIX.csv in the display units, as the CSV. */
typedef struct plot_data {
    const envelope_args *a;
    const usm_envelope *e;
} plot_data;

static int write_plot_csv(FILE *out, const void *data)
{
    const plot_data *d = data;
    cli_shown shown;
    FILE *f = cli_shown_open(&shown, &d->a->common.display, out);
    int rc = f ? usm_envelope_write_plot_csv(d->e, f) : -1;
    return f && cli_shown_close(&shown) != 0 ? -1 : rc;
}

/* --plot: PREFIX.csv, then gnuplot on data/plots/envelope.gp.  A missing
 * gnuplot is a warning (the CSV and PREFIX.gp are there to plot later). */
static int plot(const envelope_args *a, const usm_run *r)
{
    char msg[CLI_MSG_LEN], xcol[300], ycol[300];
    const plot_data d = {a, usm_run_envelope_result(r)};
    int rc = usm_plot_csv_write(a->plot, a->force, write_plot_csv, &d, msg);
    if (rc != USM_OK) {
        cli_error("%s", msg);
        return rc;
    }
    const char *xu, *yu;
    usm_display_value(&a->common.display, usm_params_find(a->names[0])->unit, 0, &xu);
    usm_display_value(&a->common.display, usm_params_find(a->names[1])->unit, 0, &yu);
    snprintf(xcol, sizeof xcol, "%s [%s]", a->names[0], xu);
    snprintf(ycol, sizeof ycol, "%s [%s]", a->names[1], yu);
    char cells[32];
    snprintf(cells, sizeof cells, "%d", a->opt.raster);
    const char *names[] = {"xcol", "ycol", "cells"}, *values[] = {xcol, ycol, cells};
    rc = usm_plot_render("envelope", a->plot, names, values, 3, msg);
    return cli_plot_status(rc, msg);
}

static int run(void *p)
{
    const envelope_args *a = p;
    char msg[CLI_MSG_LEN];
    int status;
    /* an --out that cannot be written is refused before the computation */
    if (cli_check_out_plot(a->out, a->plot, a->force) != USM_OK)
        return USM_EINPUT;
    usm_run *r = usm_run_envelope(a->common.model, &a->common.params, &a->opt);
    if (!a->out) {
        status = cli_run_output(r, a->common.json, 0, write_csv, a);
        if (status == USM_OK && a->plot)
            status = plot(a, r);
        usm_run_free(r);
        return status;
    }
    status = usm_run_status(r);
    if (status != USM_OK) {
        cli_error("%s", usm_run_message(r));
        usm_run_free(r);
        return status;
    }
    usm_io_file file;
    FILE *out = usm_io_create(&file, a->out, a->force, msg, &status);
    if (!out) {
        cli_error("--out %s", msg);
        usm_run_free(r);
        return status;
    }
    const int wr = a->common.json ? usm_run_write_json(r, out) : write_csv(a, r, out);
    if (wr != 0) {
        usm_io_abort(&file);
        cli_error("--out %s: write error", a->out);
        status = USM_EFAILED;
    } else if ((status = usm_io_commit(&file, msg)) != USM_OK)
        cli_error("--out %s", msg);
    if (status == USM_OK && a->plot)
        status = plot(a, r);
    usm_run_free(r);
    return status;
}

const cli_command cli_envelope = {sizeof(envelope_args), usage, init, option, finish, run, 0, 1};
