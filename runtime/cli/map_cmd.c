/* usm map: the largest Floquet multiplier over a 2-D grid of two parameters
 * (a stability map), with the existence, stability and stick boundaries. */
#define _POSIX_C_SOURCE 200809L

#include <stdio.h>
#include <string.h>

#include "commands.h"
#include "diag.h"
#include "options.h"
#include "progress.h"
#include "usm.h"
#include "usm_io.h"
#include "usm_plot.h"
#include "usm_report_map.h"
#include "usm_run.h"
#ifdef USM_HAVE_MPI
#include "usm_mpi.h"
#endif

static void usage(FILE *out)
{
    fprintf(out,
            "usage: usm map [--x NAME --x-from A --x-to B] [--x-points N]\n"
            "               [--y NAME --y-from A --y-to B] [--y-points N]\n"
            "               [--model 3dof|4dof] [--variant NAME] [--params FILE.json]\n"
            "               [--set NAME=VALUE]...\n"
            "               [--t0 S] [--floquet-method NAME] [--rtol R] [--threads N] [--json]\n"
            "               [--from-rest [--from-rest-periods N]]\n"
            "               [--out FILE] [--plot PREFIX] [--force] [--quiet]\n"
            "\n"
            "Stability map: at every point of a grid over two parameters, the stationary\n"
            "solution (full search) and the largest modulus of its Floquet multipliers.\n"
            "Default grid: f from 30000 to 46000 Hz (x, 33 points) times T from 0 to\n"
            "0.008 N m (y, 33 points).  Naming another parameter needs its range.\n"
            "\n"
            "options:\n");
    cli_common_usage(out);
    cli_units_usage(out);
    fprintf(out,
            "  --x NAME, --y NAME  the parameters of the two axes (see usm steady --help)\n"
            "  --x-from A, --x-to B, --y-from A, --y-to B   axis ranges (SI, or with a\n"
            "                      unit: --x-from 30kHz, --y-to 8mNm)\n"
            "  --x-points N, --y-points N   grid points per axis (default 33, at least 2)\n"
            "  --t0 S              start of the Floquet period [s] (default 0, the paper's)\n");
    cli_floquet_usage(out);
    cli_from_rest_usage(out);
    fprintf(out,
            "  --threads N         worker threads (default 2)\n"
            "  --out FILE          write to FILE instead of stdout; an existing FILE is\n"
            "                      kept unless --force is given\n"
            "  --plot PREFIX       also write the CSV to PREFIX.csv and draw the map with\n"
            "                      gnuplot: PREFIX.gp, PREFIX.png, PREFIX.svg; existing\n"
            "                      files are kept unless --force is given\n"
            "  --force             overwrite FILE and the --plot files\n");
    cli_quiet_usage(out);
    fprintf(out,
            "  -h, --help          print this help\n"
            "\n"
            "Output: CSV (default), header\n"
            "  X [unit],Y [unit],exists,roots,max_modulus [1],stable,theta [rad],\n"
            "  rotor_speed [1/s],mu_used [1],stick_admissible,power_in [W],power_out [W],\n"
            "  power_damping [W],power_slip [W],efficiency [1],valid,invalid_reason,\n"
            "  operating_point,op_class,op_reason,starts_from_rest,op_theta [rad],\n"
            "  op_rotor_speed [1/s],op_max_modulus [1]\n"
            "(op_class: operating_point, no_stable_root, does_not_start, unknown --\n"
            "several roots and no --from-rest -- or no_solution; the columns before it are\n"
            "the smallest-tilt root's)\n"
            "one row per grid point, x fastest, an empty field where a value does not\n"
            "exist, true/false for yes/no.  With\n"
            "--json one object: model, parameters, t0, x, y, points[] and boundaries\n"
            "{existence, stability, stick}: [x, y] pairs where, along y, a solution starts\n"
            "or stops existing, |lambda| crosses 1, F_t = mu0 F_n (located by bisection).\n"
            "A point without a solution or whose multipliers fail has its reason in\n"
            "\"error\"; the map goes on.\n"
            "\n"
            "exit status: 0 done, 1 numerical failure or write error, 2 bad input\n");
}

typedef struct map_args {
    cli_common common;
    usm_floquet_options floquet;
    usm_op_options op;
    const char *xname, *yname;
    double xfrom, xto, yfrom, yto;
    int have_xfrom, have_xto, have_yfrom, have_yto;
    int xpoints, ypoints, threads;
    double t0;
    const char *out;
    const char *plot; /* --plot PREFIX, or NULL */
    int force, quiet;
    const char *dbl_text[5]; /* the ranges are parsed once --x and --y are known, in their units */
} map_args;

static const char *const dbl_names[] = {"--x-from", "--x-to", "--y-from", "--y-to", "--t0"};

static int init(void *p, char msg[CLI_MSG_LEN])
{
    map_args *a = p;
    (void)msg;
    usm_floquet_options_default(&a->floquet);
    usm_op_options_default(&a->op);
    usm_map_options def; /* the library's default grid */
    usm_map_options_default(&def);
    a->xpoints = def.x.points;
    a->ypoints = def.y.points;
    a->threads = 2;
    return USM_OK;
}

static int option(void *p, int argc, char **argv, int *i, char msg[CLI_MSG_LEN])
{
    map_args *a = p;
    int *dbl_flag[] = {&a->have_xfrom, &a->have_xto, &a->have_yfrom, &a->have_yto, NULL};
    const char *value;
    int r;
    CLI_TRY(cli_flag_option(argv, i, "--force", &a->force));
    CLI_TRY(cli_quiet_option(&a->quiet, argc, argv, i));
    CLI_TRY(cli_common_option(&a->common, argc, argv, i, msg));
    CLI_TRY(cli_floquet_option(&a->floquet, argc, argv, i, msg));
    CLI_TRY(cli_from_rest_option(&a->op, argc, argv, i, msg));
    for (size_t k = 0; k < sizeof dbl_names / sizeof dbl_names[0]; ++k) {
        if ((r = cli_option_value(argc, argv, i, dbl_names[k], &value, msg)) == CLI_OPT_ERROR)
            return r;
        if (r == CLI_OPT_TAKEN) {
            if (!dbl_flag[k] && cli_parse_quantity(dbl_names[k], "s", value, &a->t0, msg))
                return CLI_OPT_ERROR;
            a->dbl_text[k] = value;
            if (dbl_flag[k])
                *dbl_flag[k] = 1;
            return r;
        }
    }
    CLI_TRY(cli_int_option(argc, argv, i, "--x-points", &a->xpoints, msg));
    CLI_TRY(cli_int_option(argc, argv, i, "--y-points", &a->ypoints, msg));
    CLI_TRY(cli_int_option(argc, argv, i, "--threads", &a->threads, msg));
    CLI_TRY(cli_option_value(argc, argv, i, "--x", &a->xname, msg));
    CLI_TRY(cli_option_value(argc, argv, i, "--y", &a->yname, msg));
    CLI_TRY(cli_plot_option(argc, argv, i, &a->plot, msg));
    return cli_path_option(argc, argv, i, "--out", "file name", &a->out, msg);
}

static int finish(void *p, char msg[CLI_MSG_LEN])
{
    map_args *a = p;
    double *dbl_dest[] = {&a->xfrom, &a->xto, &a->yfrom, &a->yto};
    for (int k = 0; k < 4; ++k) {
        const char *name = k < 2 ? a->xname : a->yname;
        const usm_param_info *axis =
            usm_params_find(name ? name : usm_param_table[k < 2 ? USM_P_f : USM_P_T].name);
        if (a->dbl_text[k] &&
            cli_parse_quantity(dbl_names[k], axis ? axis->unit : NULL, a->dbl_text[k], dbl_dest[k],
                               msg) != USM_OK)
            return USM_EINPUT;
    }
    return cli_common_finish(&a->common, msg);
}

/* An axis from the options: the default parameter has a default range,
 * another one needs --?-from and --?-to.  The library checks the values. */
static int make_axis(usm_report_axis *ax, const char *field, const char *name,
                     const usm_map_axis *def, int have_from, double from, int have_to,
                     double to, int points, char msg[CLI_MSG_LEN])
{
    const char *n = name ? name : def->name;
    if (strcmp(n, def->name) != 0 && !(have_from && have_to) && usm_params_find(n)) {
        cli_msg(msg, "%s-%s: required when %s is not %s (the range of %s)", field,
                have_from ? "to" : "from", field, def->name, n);
        return USM_EINPUT;
    }
    ax->name = n;
    ax->from = have_from ? from : def->from;
    ax->to = have_to ? to : def->to;
    ax->points = points;
    return USM_OK;
}

/* The map's CSV in the display units (--units). */
typedef struct map_csv {
    const usm_report_map *map;
    const usm_display *d;
} map_csv;

static int write_map_csv(FILE *out, const void *data)
{
    const map_csv *c = data;
    cli_shown shown;
    FILE *f = cli_shown_open(&shown, c->d, out);
    int rc = f ? usm_report_map_write_csv(c->map, f) : -1;
    return f && cli_shown_close(&shown) != 0 ? -1 : rc;
}

/* --plot: PREFIX.csv, then gnuplot on data/plots/map.gp.  A missing gnuplot
 * is a warning (the CSV and PREFIX.gp are there to plot later). */
static int plot(const map_args *a, const usm_report_map *map)
{
    char msg[CLI_MSG_LEN], xcol[128], ycol[128];
    const map_csv csv = {map, &a->common.display};
    int rc = usm_plot_csv_write(a->plot, a->force, write_map_csv, &csv, msg);
    if (rc != USM_OK) {
        cli_error("%s", msg);
        return rc;
    }
    /* the header's first two columns (report_map.c) */
    const char *xu, *yu;
    usm_display_value(csv.d, map->x.param->unit, 0, &xu);
    usm_display_value(csv.d, map->y.param->unit, 0, &yu);
    snprintf(xcol, sizeof xcol, "%s [%s]", map->x.param->name, xu);
    snprintf(ycol, sizeof ycol, "%s [%s]", map->y.param->name, yu);
    const char *names[] = {"xcol", "ycol", "mcol"}, *values[] = {xcol, ycol, "op_max_modulus [1]"};
    rc = usm_plot_render("map", a->plot, names, values, 3, msg);
    return cli_plot_status(rc, msg);
}

/* The map's memory: the run's, or the gathered map's (MPI). */
static void map_free(usm_report_map *map, usm_run *run)
{
    if (run)
        usm_run_free(run);
    else
        usm_report_map_free(map);
}

static int run(void *p)
{
    const map_args *a = p;
    usm_report_map map;
    char msg[CLI_MSG_LEN];
    FILE *out = stdout;
    usm_io_file file;
    int status;
    usm_run *run = NULL;           /* one process: the library's run of the map */
    const usm_report_map *res = &map; /* the map written (the run's, or gathered) */

    memset(&map, 0, sizeof map);
    usm_map_options def; /* the library's default grid */
    usm_map_options_default(&def);
    if (make_axis(&map.x, "--x", a->xname, &def.x, a->have_xfrom, a->xfrom, a->have_xto, a->xto,
                  a->xpoints, msg) != USM_OK ||
        make_axis(&map.y, "--y", a->yname, &def.y, a->have_yfrom, a->yfrom, a->have_yto, a->yto,
                  a->ypoints, msg) != USM_OK) {
        cli_error("%s", msg);
        return USM_EINPUT;
    }
    map.model = a->common.model;
    map.params = a->common.params;
    map.t0 = a->t0;
    map.floquet = &a->floquet;
    map.op = &a->op;
    map.threads = a->threads;
    map.boundaries = a->common.json;
    /* Refuse an --out that cannot be written before the (long) computation. */
    if (cli_check_out_plot(a->out, a->plot, a->force) != USM_OK)
        return USM_EINPUT;
#ifdef USM_HAVE_MPI
    if (a->common.size > 1) { /* the ranks share the columns; rank 0 gathers the map */
        usm_map_options opt;
        usm_map_gathered g;
        usm_report_map_options(&map, &opt);
        status = usm_map_run_mpi(map.model, &map.params, &opt, &g);
        if (a->common.rank != 0)
            return status;
        if (status != USM_OK)
            cli_msg(msg, "%s%s", g.msg[0] == 'x' || g.msg[0] == 'y' ? "--" : "map: ", g.msg);
        else
            status = usm_report_map_fill(&map, g.cells, g.bnd, g.nbnd, g.floquet_failures, msg);
        usm_map_gathered_free(&g);
    } else
#endif
    {
        usm_map_options opt;
        cli_progress bar;
        cli_progress_init(&bar, "usm map", a->quiet);
        map.progress = cli_progress_callback(&bar);
        usm_report_map_options(&map, &opt);
        run = usm_run_map(map.model, &map.params, &opt);
        cli_progress_end(&bar);
        status = usm_run_status(run);
        cli_msg(msg, "%s", usm_run_message(run));
        res = usm_run_map_result(run);
    }
    if (status != USM_OK) {
        cli_error("%s", msg);
        usm_run_free(run);
        return status;
    }
    if (a->out && !(out = usm_io_create(&file, a->out, a->force, msg, &status))) {
        cli_error("--out %s", msg);
        map_free(&map, run);
        return status;
    }
    if (a->common.json) {
        if (usm_report_map_write_json(res, out) != 0)
            status = USM_EFAILED;
    } else {
        const map_csv csv = {res, &a->common.display};
        if (write_map_csv(out, &csv) != 0)
            status = USM_EFAILED;
    }
    if (out != stdout) {
        if (status != USM_OK) {
            usm_io_abort(&file);
            cli_error("--out %s: write error", a->out);
        } else if ((status = usm_io_commit(&file, msg)) != USM_OK)
            cli_error("--out %s", msg);
    } else if (fflush(stdout) != 0 || ferror(stdout)) {
        clearerr(stdout);
        cli_error("stdout: write error");
        status = USM_EFAILED;
    }
    if (status == USM_OK && a->plot)
        status = plot(a, res);
    if (res->floquet_failures > 0 && status == USM_OK)
        fprintf(stderr, "usm: map: the Floquet computation failed at %zu point(s) (max_modulus nan)\n",
                res->floquet_failures);
    map_free(&map, run);
    return status;
}

const cli_command cli_map = {sizeof(map_args), usage, init, option, finish, run, 1, 1};
