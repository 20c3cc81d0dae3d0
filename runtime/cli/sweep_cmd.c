/* usm sweep: motor characteristics, the stationary solution followed over a
 * range of one parameter by continuation, with its events (fold, stick limit,
 * friction saturation, stability change). */
#define _POSIX_C_SOURCE 200809L

#include <stdio.h>
#include <string.h>

#include "commands.h"
#include "diag.h"
#include "options.h"
#include "progress.h"
#include "usm_io.h"
#include "usm_periodic_sweep.h"
#include "usm_plot.h"
#include "usm_run.h"
#include "usm_sweep.h"

static void usage(FILE *out)
{
    fprintf(out,
            "usage: usm sweep --over NAME --from A --to B [--points N]\n"
            "                 [--model 3dof|4dof] [--variant NAME] [--params FILE.json]\n"
            "                 [--set NAME=VALUE]...\n"
            "                 [--t0 S] [--floquet-method NAME] [--rtol R] [--threads N]\n"
            "                 [--no-floquet] [--json] [--plot PREFIX [--force]] [--quiet]\n"
            "                 [--from-rest [--from-rest-periods N]]\n"
            "                 [--extremum Q]... [--crossing Q=V]...\n"
            "       usm sweep --periodic --over NAME --from A --to B [--points N]\n"
            "                 [--model 3dof|4dof] [--variant NAME] [--params FILE.json]\n"
            "                 [--set NAME=VALUE]... [--json] [--plot PREFIX [--force]] [--quiet]\n"
            "\n"
            "Follow the stationary solution of smallest tilt at A through the parameter\n"
            "range A..B by pseudo-arclength continuation and report it at N equally spaced\n"
            "values, with its Floquet multipliers and the events on the way, each located\n"
            "to tolerance: fold (a turning point of the branch), tilt_zero (the tilt\n"
            "vanishes), range_end (the tilt leaves the searched range), stick_limit (stick\n"
            "models: F_t = mu0 F_n), stall (slip models: the rotor speed passes 0),\n"
            "friction_saturation (slip models: the friction needed reaches the law's\n"
            "supremum), stability_change (the largest multiplier crosses 1), and the\n"
            "maximum, minimum and crossing events of --extremum and --crossing.  At every\n"
            "value also the operating point (the stable root the motor runs at; several\n"
            "roots: unknown unless --from-rest) and operating_point_jump events where it\n"
            "moves to another branch, appears or vanishes between two grid values.\n"
            "\n"
            "options:\n");
    cli_common_usage(out);
    cli_units_usage(out);
    cli_quiet_usage(out);
    fprintf(out,
            "  --over NAME         the parameter to sweep (any of usm steady --help)\n"
            "  --from A, --to B    the range, in the parameter's unit or with a unit: 36kHz\n"
            "                      (A != B; B < A sweeps down)\n"
            "  --points N          grid values, 2 to 1000000 (default 101)\n"
            "  --t0 S              start of the Floquet period [s] (default 0, the paper's)\n"
            "  --threads N         worker threads for the multipliers (default 2)\n"
            "  --no-floquet        skip the multipliers (and the stability events)\n");
    cli_floquet_usage(out);
    cli_from_rest_usage(out);
    fprintf(out,
            "  --extremum Q        events at the maxima and minima of quantity Q along the\n"
            "                      branch (repeatable); Q is one of theta, alpha,\n"
            "                      rotor_speed, speed (= -rotor_speed), F_n, F_t, mu_used, v_rel\n"
            "  --crossing Q=V      an event where quantity Q crosses V (repeatable)\n"
            "  --plot PREFIX       also write the CSV to PREFIX.csv and draw it with gnuplot\n"
            "                      (rotor speed in the driving direction and tilt against\n"
            "                      NAME, the events as labelled lines; with --periodic the\n"
            "                      mean speed and its ripple, F_n_min and max |lambda|):\n"
            "                      PREFIX.gp, PREFIX.png, PREFIX.svg; existing files are\n"
            "                      kept unless --force is given\n"
            "  --force             overwrite the --plot files\n"
            "  --periodic          follow the periodic orbit (usm periodic) instead; implied\n"
            "                      by the variant imperfect.\n"
            "                      Columns: NAME, converged, rotor_speed_mean, rotor_speed_ripple,\n"
            "                      F_n_min, F_n_max, friction_needed_max, theta_mean, theta_min,\n"
            "                      theta_max, theta_harmonic_2, F_n_harmonic_2, max_modulus,\n"
            "                      stable, contact_open, error; events contact_loss, stick_loss,\n"
            "                      fold, stability_change (kind fold, period_doubling,\n"
            "                      neimark_sacker); see docs/periodic.md\n"
            "  -h, --help          print this help\n"
            "\n"
            "Output: CSV (default), header\n"
            "  NAME [unit],theta [rad],alpha [rad],rotor_speed [1/s],F_n [N],F_t [N],\n"
            "  mu_needed [1],max_modulus [1],stable,converged,roots,error,power_in [W],\n"
            "  power_out [W],power_damping [W],power_slip [W],efficiency [1]\n"
            "one row per grid value (empty fields where no solution exists; roots counts\n"
            "the stationary solutions there, the others lie on other branches, which the\n"
            "sweep never jumps to; error says why a point has no solution or why its\n"
            "multipliers failed), then one\n"
            "comment line per event: \"# TYPE at NAME = VALUE: what happens\", and last\n"
            "\"# operating point rule: ...\" (which points a start-up from rest decides).\n"
            "With --json one object {over, model, parameters, operating_point_rule,\n"
            "points[], events[]}; a point\n"
            "has the keys of usm steady --json plus NAME.\n"
            "A progress line is drawn on stderr when it is a terminal.\n"
            "\n"
            "exit status: 0 done (even where points have no solution), 1 numerical\n"
            "             failure or write error, 2 bad input\n");
}

/* One monitor per quantity named (usm_sweep_quantity: --extremum, --crossing). */
#define NQUANTITIES USM_SWEEP_MAX_MONITORS

typedef struct sweep_args {
    cli_common common;
    const char *over;
    double from, to, t0;
    int have_from, have_to;
    const char *from_text, *to_text; /* parsed in --over's unit once it is known */
    int points, threads, floquet, force, periodic, quiet;
    int others; /* options of the stationary sweep only, for --periodic's refusal */
    const char *plot; /* --plot PREFIX, or NULL */
    usm_floquet_options floquet_opt;
    usm_op_options op;
    usm_sweep_monitor monitors[NQUANTITIES]; /* one per quantity named */
    int nmonitors;
} sweep_args;

/* The monitor of quantity `name` (added on first use), or NULL with msg. */
static usm_sweep_monitor *monitor_of(sweep_args *a, const char *field, const char *name,
                                     size_t len, char msg[CLI_MSG_LEN])
{
    usm_monitor_fn fn;
    const char *q;
    for (int k = 0; k < a->nmonitors; ++k)
        if (strlen(a->monitors[k].name) == len && strncmp(a->monitors[k].name, name, len) == 0)
            return &a->monitors[k];
    if ((q = usm_sweep_quantity(name, len, &fn)) && a->nmonitors < NQUANTITIES) {
        usm_sweep_monitor *m = &a->monitors[a->nmonitors++];
        memset(m, 0, sizeof *m);
        m->name = q;
        m->fn = fn;
        return m;
    }
    cli_msg(msg, "%s: unknown quantity \"%.*s\" (%s)", field, (int)len, name,
            USM_SWEEP_QUANTITIES);
    return NULL;
}

static int monitor_option(sweep_args *a, int crossing, const char *value, char msg[CLI_MSG_LEN])
{
    const char *field = crossing ? "--crossing" : "--extremum";
    const char *eq = crossing ? strchr(value, '=') : NULL;
    if (crossing && !eq) {
        cli_msg(msg, "--crossing: \"%s\" must be QUANTITY=VALUE", value);
        return CLI_OPT_ERROR;
    }
    usm_sweep_monitor *m = monitor_of(a, field, value, eq ? (size_t)(eq - value) : strlen(value), msg);
    if (!m)
        return CLI_OPT_ERROR;
    if (!crossing) {
        m->extrema = 1;
        return CLI_OPT_TAKEN;
    }
    double level;
    if (cli_parse_double(field, eq + 1, &level, msg) != USM_OK)
        return CLI_OPT_ERROR;
    if (m->nlevels == USM_SWEEP_MAX_LEVELS) {
        cli_msg(msg, "--crossing: at most %d levels per quantity", USM_SWEEP_MAX_LEVELS);
        return CLI_OPT_ERROR;
    }
    m->levels[m->nlevels++] = level;
    return CLI_OPT_TAKEN;
}

static int init(void *p, char msg[CLI_MSG_LEN])
{
    sweep_args *a = p;
    (void)msg;
    a->points = 101;
    a->threads = 2;
    a->floquet = 1;
    usm_floquet_options_default(&a->floquet_opt);
    usm_op_options_default(&a->op);
    return USM_OK;
}

static int option(void *p, int argc, char **argv, int *i, char msg[CLI_MSG_LEN])
{
    sweep_args *a = p;
    const char *value;
    int r, no_floquet = 0;
    CLI_TRY(cli_common_option(&a->common, argc, argv, i, msg));
    if ((r = cli_floquet_option(&a->floquet_opt, argc, argv, i, msg)) == CLI_OPT_NOT_MINE)
        r = cli_from_rest_option(&a->op, argc, argv, i, msg);
    if (r == CLI_OPT_NOT_MINE && (r = cli_flag_option(argv, i, "--no-floquet", &no_floquet)))
        a->floquet = 0;
    if (r == CLI_OPT_NOT_MINE && (r = cli_int_option(argc, argv, i, "--threads", &a->threads, msg)))
        a->others = 1;
    if (r != CLI_OPT_NOT_MINE) {
        a->others |= r == CLI_OPT_TAKEN;
        return r;
    }
    CLI_TRY(cli_flag_option(argv, i, "--periodic", &a->periodic));
    CLI_TRY(cli_flag_option(argv, i, "--force", &a->force));
    CLI_TRY(cli_quiet_option(&a->quiet, argc, argv, i));
    CLI_TRY(cli_plot_option(argc, argv, i, &a->plot, msg));
    CLI_TRY(cli_option_value(argc, argv, i, "--over", &a->over, msg));
    if ((r = cli_option_value(argc, argv, i, "--from", &a->from_text, msg)) != CLI_OPT_NOT_MINE)
        return a->have_from = 1, r;
    if ((r = cli_option_value(argc, argv, i, "--to", &a->to_text, msg)) != CLI_OPT_NOT_MINE)
        return a->have_to = 1, r;
    if ((r = cli_option_value(argc, argv, i, "--extremum", &value, msg)) != CLI_OPT_NOT_MINE)
        return r == CLI_OPT_TAKEN ? monitor_option(a, 0, value, msg) : r;
    if ((r = cli_option_value(argc, argv, i, "--crossing", &value, msg)) != CLI_OPT_NOT_MINE)
        return r == CLI_OPT_TAKEN ? monitor_option(a, 1, value, msg) : r;
    CLI_TRY(cli_quantity_option(argc, argv, i, "--t0", "s", &a->t0, msg));
    return cli_int_option(argc, argv, i, "--points", &a->points, msg);
}

static int finish(void *p, char msg[CLI_MSG_LEN])
{
    sweep_args *a = p;
    if (!a->over || !a->have_from || !a->have_to) {
        cli_msg(msg, "%s: required (see usm sweep --help)",
                !a->over ? "--over" : !a->have_from ? "--from" : "--to");
        return USM_EINPUT;
    }
    {
        const usm_param_info *over = usm_params_find(a->over);
        const char *unit = over ? over->unit : NULL;
        /* --from and --to are read in --over's unit: an unknown name is the fault */
        if (!over) {
            cli_msg(msg, "--over: unknown parameter \"%s\" (see usm steady --help)", a->over);
            return USM_EINPUT;
        }
        if (cli_parse_quantity("--from", unit, a->from_text, &a->from, msg) != USM_OK ||
            cli_parse_quantity("--to", unit, a->to_text, &a->to, msg) != USM_OK)
            return USM_EINPUT;
    }
    if (a->force && !a->plot) {
        cli_msg(msg, "--force: only with --plot (it overwrites the --plot files)");
        return USM_EINPUT;
    }
    if (cli_common_finish(&a->common, msg) != USM_OK)
        return USM_EINPUT;
    a->periodic |= a->common.model->imperfect;
    if (a->periodic && (a->others || a->nmonitors > 0 || a->t0 != 0.0)) {
        cli_msg(msg, "--periodic (or the variant imperfect): --no-floquet, --t0, --threads, "
                     "--extremum, --crossing, --from-rest and the Floquet options are for the "
                     "stationary sweep only");
        return USM_EINPUT;
    }
    /* refused before the (long) sweep, not after it */
    return a->plot ? usm_plot_csv_check(a->plot, a->force, msg) : USM_OK;
}

/* ---- run ---------------------------------------------------------------------- */

static int write_csv(const void *p, const usm_run *r, FILE *out)
{
    const sweep_args *a = p;
    cli_shown shown;
    FILE *f = cli_shown_open(&shown, &a->common.display, out);
    int rc = !f ? -1
             : a->periodic ? usm_periodic_sweep_csv(usm_run_periodic_sweep_result(r), f)
                           : usm_sweep_csv(usm_run_sweep_result(r), a->over, a->floquet, f);
    return f && cli_shown_close(&shown) != 0 ? -1 : rc;
}

/* The events of a sweep as the word lists its gnuplot script reads (names,
 * values), for labelled lines. */
typedef struct plot_events {
    char names[1024], values[1024];
} plot_events;

/* Append one event; -1 when the lists are full (the rest are left out). */
static int plot_event_add(plot_events *ev, const char *name, double value)
{
    const size_t ln = strlen(ev->names), lx = strlen(ev->values);
    if (ln + 64 >= sizeof ev->names || lx + 32 >= sizeof ev->values)
        return -1;
    /* each word followed by its space: one value alone must not read as a
     * number, which the script's word() refuses ("non-STRING argument") */
    snprintf(ev->names + ln, sizeof ev->names - ln, "%s ", name);
    snprintf(ev->values + lx, sizeof ev->values - lx, "%.17g ", value);
    return 0;
}

/* The label of event i: its name, and on a root or orbit the model does not
 * describe ":model_invalid:" and the reason; its value in *x. */
static void event_label(const sweep_args *a, const usm_run *r, size_t i, char name[64], double *x)
{
    usm_validity v = USM_VALID;
    if (a->periodic) {
        const usm_periodic_event *e = usm_periodic_sweep_event_at(usm_run_periodic_sweep_result(r), i);
        const int limit = e->type == USM_PEVENT_CONTACT_LOSS ||
                          e->type == USM_PEVENT_STICK_LOSS || e->type == USM_PEVENT_CONTACT_REGAINED;
        v = limit ? USM_VALID
            : e->has_hybrid ? e->hybrid.validity
            : e->has_orbit ? e->orbit.validity : USM_VALID;
        snprintf(name, 64, "%s", usm_pevent_name(e->type));
        *x = e->value;
    } else {
        const usm_sweep_event *e = usm_sweep_event_at(usm_run_sweep_result(r), i);
        if (e->has_sol && e->type != USM_EVENT_STICK_LIMIT)
            v = e->sol.validity;
        snprintf(name, 64, "%s", usm_event_name(e->type));
        *x = e->value;
    }
    if (v != USM_VALID)
        snprintf(name + strlen(name), 64 - strlen(name), ":model_invalid:%s", usm_validity_name(v));
}

/* --plot: PREFIX.csv, then gnuplot on data/plots/sweep.gp (sweep_periodic.gp
 * with --periodic), the events as word lists for their labelled lines.  A
 * missing gnuplot is a warning (the CSV and PREFIX.gp are there to plot later). */
static int plot(const sweep_args *a, const usm_run *r)
{
    char msg[CLI_MSG_LEN], xcol[128], name[64];
    const usm_param_info *info = usm_params_find(a->over);
    const cli_csv csv = {write_csv, a, r};
    int rc = usm_plot_csv_write(a->plot, a->force, cli_csv_write, &csv, msg);
    if (rc != USM_OK) {
        cli_error("%s", msg);
        return rc;
    }
    /* the header's first column (sweep_out.c), in the display units as the CSV */
    const usm_display *d = &a->common.display;
    const char *xunit, *speed_unit, *angle_unit;
    usm_display_value(d, info ? info->unit : "", 0, &xunit);
    usm_display_value(d, "1/s", 0, &speed_unit);
    usm_display_value(d, "rad", 0, &angle_unit);
    snprintf(xcol, sizeof xcol, "%s [%s]", a->over, xunit);
    plot_events ev = {"", ""};
    const size_t n = a->periodic ? usm_periodic_sweep_event_count(usm_run_periodic_sweep_result(r))
                                 : usm_sweep_event_count(usm_run_sweep_result(r));
    double x;
    for (size_t i = 0; i < n; ++i) {
        event_label(a, r, i, name, &x);
        if (plot_event_add(&ev, name, usm_display_value(d, info ? info->unit : "", x, NULL)) != 0)
            break;
    }
    const char *names[] = {"xcol", "events", "event_x", "speed_unit", "angle_unit"};
    const char *values[] = {xcol, ev.names, ev.values, speed_unit, angle_unit};
    rc = usm_plot_render(a->periodic ? "sweep_periodic" : "sweep", a->plot, names, values, 5, msg);
    return cli_plot_status(rc, msg);
}

/* --periodic: the orbit's continuation (usm_periodic_sweep.h). */
static usm_run *run_periodic(const sweep_args *a, cli_progress *progress)
{
    usm_periodic_sweep_options opt;
    usm_periodic_sweep_options_default(&opt);
    opt.over = a->over;
    opt.from = a->from;
    opt.to = a->to;
    opt.points = a->points;
    opt.progress = progress->on ? cli_progress_fraction : NULL;
    opt.progress_ctx = progress;
    return usm_run_periodic_sweep(a->common.model, &a->common.params, &opt);
}

static usm_run *run_stationary(const sweep_args *a, cli_progress *progress)
{
    usm_sweep_options opt;
    usm_sweep_options_default(&opt);
    opt.over = a->over;
    opt.from = a->from;
    opt.to = a->to;
    opt.points = a->points;
    opt.floquet = a->floquet;
    opt.floquet_options = a->floquet_opt;
    opt.t0 = a->t0;
    opt.threads = a->threads;
    opt.monitors = a->monitors;
    opt.nmonitors = a->nmonitors;
    opt.op = a->op;
    opt.progress = progress->on ? cli_progress_fraction : NULL;
    opt.progress_ctx = progress;
    return usm_run_sweep(a->common.model, &a->common.params, &opt);
}

static int run(void *p)
{
    const sweep_args *a = p;
    cli_progress progress;
    cli_progress_init(&progress, "usm sweep", a->quiet);
    progress.total = a->points;
    progress.what = "points";
    usm_run *r = a->periodic ? run_periodic(a, &progress) : run_stationary(a, &progress);
    cli_progress_end(&progress);
    int status = cli_run_output(r, a->common.json, 0, write_csv, a);
    if (status == USM_OK && a->plot)
        status = plot(a, r);
    usm_run_free(r);
    return status;
}

const cli_command cli_sweep = {sizeof(sweep_args), usage, init, option, finish, run, 0, 1};
