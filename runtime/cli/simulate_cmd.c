/* usm simulate: start-up transient of the full model (library: usm_simulate.h).
 *
 * Streams the time history as CSV (to --out or stdout), then prints a summary:
 * a table, or one JSON object with --json, on stdout unless the CSV occupies
 * stdout (then on stderr).  Never overwrites a file unless --force. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "commands.h"
#include "diag.h"
#include "options.h"
#include "progress.h"
#include "usm.h"
#include "usm_io.h"
#include "usm_plot.h"
#include "usm_run.h"
#include "usm_simulate.h"
#include "usm_spectrum.h"

/* More rows than anyone can look at; a typo in --rate or --duration. */
#define MAX_ROWS 100000000.0

static void usage(FILE *out)
{
    fprintf(out,
            "usage: usm simulate [--model 3dof|4dof] [--variant NAME] [--params FILE.json]\n"
            "                    [--set NAME=VALUE]...\n"
            "                    --duration S [--from rest|stationary|FILE] [--out FILE.csv]\n"
            "                    [--force] [--quiet] [--rate HZ] [--tilt0 RAD] [--rtol R] [--plot PREFIX]\n"
            "                    [--spectrum PREFIX [--spectrum-periods N]] [--json]\n"
            "\n"
            "Integrate the full nonlinear model M(x) x' = f(x, t) (CVODES, BDF) from the motor\n"
            "at rest, write the time history as CSV and report whether and when the motion\n"
            "settled onto the stationary solution, and which root it settled on (settled_on:\n"
            "a root index of usm steady, \"rest\" when the wobble decays: the run then stops).\n"
            "\n"
            "options:\n");
    cli_common_usage(out);
    cli_units_usage(out);
    cli_quiet_usage(out);
    fprintf(out,
            "  --duration S        simulated time [s] (required)\n"
            "  --from rest         start at rest: tilt tilt0 about the excitation torque's axis,\n"
            "                      zero rates (default); the summary says which tilt\n"
            "  --from stationary   start on the stationary orbit (usm steady's primary root)\n"
            "  --from FILE         start from a state: a CSV with a header naming the state\n"
            "                      variables (its last row is used, so an --out file continues)\n"
            "                      or a JSON object {\"t\": S, \"x\": [...]} or {\"theta\": ..., ...}\n"
            "  --out FILE.csv      write the time history there (default: stdout)\n"
            "  --force             overwrite --out and --plot files that exist\n"
            "  --rate HZ           samples per second (default 10 f; 0: no time history)\n"
            "  --tilt0 RAD         initial tilt when starting at rest, > 0 (default: at rest,\n"
            "                      below every unstable root: 1e-2 of the smallest unstable\n"
            "                      root's tilt, at most 1e-6; docs/operating-point.md)\n"
            "  --rtol R            relative tolerance of the integrator (default 1e-8)\n"
            "  --settle-tol X      relative settling tolerance (default 1e-3)\n"
            "  --settle-periods N  periods the settled state must last (default 100)\n"
            "  --theta-limit RAD   stop as runaway when the tilt reaches it (default 0.5)\n"
            "  --speed-limit W     stop as runaway when |phidot_R| reaches it [1/s] (default 1e4)\n"
            "  --max-steps N       cap on internal integrator steps (default 2000 per period)\n"
            "  --max-twist-growth G  refuse runs the paper's twist law would slow down beyond\n"
            "                      twist growth G (default 400, about 2 s of the paper's motor;\n"
            "                      0: no limit; see docs/simulate.md)\n"
            "  --plot PREFIX       write PREFIX.gp and run gnuplot: PREFIX.png, PREFIX.svg\n"
            "                      (needs --out)\n"
            "  --spectrum PREFIX   amplitude spectrum (Hann window, FFT) of the rotor speed,\n"
            "                      tilt and F_n over the settled part of the run: PREFIX.csv,\n"
            "                      PREFIX.gp, PREFIX.png, PREFIX.svg; its strongest lines in the\n"
            "                      summary (harmonics of f or not; see docs/simulate.md).  The\n"
            "                      time history goes only to --out, not to stdout\n"
            "  --spectrum-periods N  the settled part: the last N whole excitation periods\n"
            "                      (default: the whole periods of the run's second half)\n"
            "  -h, --help          print this help\n"
            "\n"
            "CSV columns: t [s], phi theta psi [rad], phidot thetadot psidot [rad/s],\n"
            "phi_R [rad], phi_Rdot [rad/s], F_n F_t [N], v_rel [m/s], theta_avg [rad],\n"
            "phi_Rdot_avg [rad/s] (means over the last complete excitation period),\n"
            "valid, invalid_reason (false, contact_open where F_n <= 0).\n"
            "\n"
            "exit status: 0 completed (settled or not) or the wobble decayed to rest,\n"
            "             1 stopped early (integrator failure,\n"
            "             runaway, step cap, write error), 2 bad input or an existing output\n"
            "             file, 3 --from stationary without a stationary solution\n");
}

typedef struct sim_args {
    cli_common common;
    usm_sim_options opt;
    const char *from_file;
    const char *out;
    const char *plot;
    const char *spectrum;
    long spectrum_periods; /* 0: the library's default */
    int force, quiet;
    int rate_set;
    int duration_set;
} sim_args;

/* ---- parsing ------------------------------------------------------------------ */

/* The library's message "FIELD: reason" with FIELD spelled as the option
 * ("settle_tol" becomes "--settle-tol") when it is one. */
static void option_message(const char *lib, char msg[CLI_MSG_LEN])
{
    static const char *const fields[] = {"duration", "rate", "tilt0", "rtol", "settle_tol",
                                         "settle_periods", "theta_limit", "speed_limit",
                                         "max_steps", "max_twist_growth"};
    size_t n = strcspn(lib, ":");
    for (size_t k = 0; k < sizeof fields / sizeof fields[0]; ++k)
        if (strlen(fields[k]) == n && strncmp(lib, fields[k], n) == 0) {
            char opt[32];
            snprintf(opt, sizeof opt, "%s", fields[k]);
            for (char *c = opt; *c; ++c)
                *c = *c == '_' ? '-' : *c;
            cli_msg(msg, "--%s%s", opt, lib + n);
            return;
        }
    cli_msg(msg, "%s", lib);
}

static int init(void *p, char msg[CLI_MSG_LEN])
{
    sim_args *a = p;
    (void)msg;
    usm_sim_options_default(&a->opt);
    return USM_OK;
}

/* --from rest|stationary|FILE */
static void start_option(sim_args *a, const char *sv)
{
    usm_sim_options *o = &a->opt;
    a->from_file = NULL;
    if (strcmp(sv, "rest") == 0)
        o->start = USM_SIM_FROM_REST;
    else if (strcmp(sv, "stationary") == 0)
        o->start = USM_SIM_FROM_STATIONARY;
    else {
        o->start = USM_SIM_FROM_STATE;
        a->from_file = sv;
    }
}

static int option(void *p, int argc, char **argv, int *i, char msg[CLI_MSG_LEN])
{
    sim_args *a = p;
    usm_sim_options *o = &a->opt;
    /* numbers: the library checks their ranges (usm_sim_check) */
    static const char *const num_opt[] = {"--duration",    "--rate",         "--tilt0",
                                          "--rtol",        "--settle-tol",   "--theta-limit",
                                          "--speed-limit", "--max-twist-growth", "--settle-periods",
                                          "--max-steps",   "--spectrum-periods"};
    /* the units of --duration, --rate, --tilt0, --theta-limit, --speed-limit */
    static const char *const num_unit[] = {"s", "Hz", "rad", NULL, NULL, "rad",
                                           "1/s", NULL, NULL, NULL, NULL};
    double *const num[] = {&o->duration,    &o->rate,        &o->tilt0,
                           &o->rtol,        &o->settle_tol,  &o->theta_limit,
                           &o->speed_limit, &o->max_twist_growth};
    const char *sv;
    double v;
    int r, which = -1;
    CLI_TRY(cli_common_option(&a->common, argc, argv, i, msg));
    CLI_TRY(cli_flag_option(argv, i, "--force", &a->force));
    CLI_TRY(cli_quiet_option(&a->quiet, argc, argv, i));
    for (int k = 0; k < 11 && which < 0; ++k) {
        if ((r = cli_quantity_option(argc, argv, i, num_opt[k], num_unit[k], &v, msg)) ==
            CLI_OPT_ERROR)
            return r;
        if (r == CLI_OPT_TAKEN)
            which = k;
    }
    if (which >= 0) {
        if (which == 2 && !(v > 0)) {
            /* 0 is the library's start at rest: reached by omitting the option */
            cli_msg(msg, "--tilt0: must be > 0 (omit it for the start at rest, below every "
                         "unstable root)");
            return CLI_OPT_ERROR;
        }
        if (which < 8)
            *num[which] = v;
        else if (v != floor(v) || v < 1 || v > (which == 9 ? 1e15 : 1e8)) {
            cli_msg(msg, "%s: must be a whole number in [1, %.0f]", num_opt[which],
                    which == 9 ? 1e15 : 1e8);
            return CLI_OPT_ERROR;
        } else if (which == 8)
            o->settle_periods = (int)v;
        else if (which == 9)
            o->max_steps = (long)v;
        else
            a->spectrum_periods = (long)v;
        a->duration_set |= which == 0;
        a->rate_set |= which == 1;
        return CLI_OPT_TAKEN;
    }
    if ((r = cli_path_option(argc, argv, i, "--from", "value", &sv, msg)) == CLI_OPT_TAKEN)
        start_option(a, sv);
    if (r != CLI_OPT_NOT_MINE)
        return r;
    CLI_TRY(cli_path_option(argc, argv, i, "--out", "value", &a->out, msg));
    CLI_TRY(cli_path_option(argc, argv, i, "--plot", "value", &a->plot, msg));
    return cli_path_option(argc, argv, i, "--spectrum", "value", &a->spectrum, msg);
}

static int finish(void *p, char msg[CLI_MSG_LEN])
{
    sim_args *a = p;
    usm_sim_options *o = &a->opt;
    if (!a->duration_set) {
        cli_msg(msg, "--duration: missing (the simulated time in seconds)");
        return USM_EINPUT;
    }
    if (a->plot && !a->out) {
        cli_msg(msg, "--plot: needs --out (gnuplot reads the CSV file)");
        return USM_EINPUT;
    }
    if (a->rate_set && o->rate == 0 && (a->out || a->plot)) {
        cli_msg(msg, "--rate 0 writes no time history; drop --out/--plot or give a rate");
        return USM_EINPUT;
    }
    if (a->spectrum_periods && !a->spectrum) {
        cli_msg(msg, "--spectrum-periods: needs --spectrum");
        return USM_EINPUT;
    }
    if (a->spectrum && a->rate_set && o->rate == 0) {
        cli_msg(msg, "--rate 0 records no samples; --spectrum needs a rate (default 10 f)");
        return USM_EINPUT;
    }
    if (a->spectrum && a->plot && strcmp(a->spectrum, a->plot) == 0) {
        cli_msg(msg, "--spectrum: the same PREFIX as --plot (both write PREFIX.gp/.png/.svg)");
        return USM_EINPUT;
    }
    return cli_common_finish(&a->common, msg);
}

/* ---- output ----------------------------------------------------------------- */

typedef struct run_io {
    FILE *csv;
    const usm_display *display; /* --units */
    int csv_failed;         /* a write error on it */
    cli_progress line;     /* of the excitation periods simulated */
    char early_warning[CLI_MSG_LEN]; /* a warning held back until the run ends */
} run_io;

static int on_sample(const usm_sim_sample *s, void *data)
{
    run_io *io = data;
    return io->csv_failed = usm_sim_csv_row_in(s, io->display, io->csv) != 0;
}

/* The message of usm_plot_csv_check / usm_plot_csv_write ("--plot ...") as
 * the option --spectrum's. */
static void spectrum_msg(char msg[CLI_MSG_LEN])
{
    if (strncmp(msg, "--plot", 6) == 0) {
        char tmp[CLI_MSG_LEN];
        snprintf(tmp, sizeof tmp, "--spectrum%.*s", CLI_MSG_LEN - 16, msg + 6);
        snprintf(msg, CLI_MSG_LEN, "%s", tmp);
    }
}

static int spectrum_csv(FILE *out, const void *run)
{
    return usm_run_spectrum_write_csv(run, out);
}

/* The message of a spectrum that the run could not compute (the library's
 * reason: "periods: ..." is the option --spectrum-periods'). */
static void spectrum_error(const char *lib, char msg[CLI_MSG_LEN])
{
    if (strncmp(lib, "periods:", 8) == 0)
        cli_msg(msg, "--spectrum-periods:%s", lib + 8);
    else if (strncmp(lib, "out of memory", 13) == 0)
        cli_msg(msg, "%s", lib);
    else
        cli_msg(msg, "--spectrum: %s", lib);
}

/* --spectrum after the run: PREFIX.csv of the run's spectrum, and PREFIX.gp
 * run by gnuplot.  USM_OK; otherwise msg says why (USM_ENOSOLUTION: no
 * gnuplot, a warning). */
static int spectrum_write(const sim_args *a, const usm_run *run, char msg[CLI_MSG_LEN])
{
    int rc;
    if ((rc = usm_plot_csv_write(a->spectrum, a->force, spectrum_csv, run, msg)) != USM_OK) {
        spectrum_msg(msg);
        return rc;
    }
    char csv[4096], title[256], num[11][32];
    const usm_sim_spectrum_result *r = usm_run_spectrum(run);
    snprintf(csv, sizeof csv, "%s.csv", a->spectrum);
    snprintf(title, sizeof title,
             "usm simulate, model %s: amplitude spectrum over t = %.4g to %.4g ms (%ld periods, "
             "Hann window)", a->common.model->name, r->t_from * 1e3, r->t_to * 1e3, r->periods);
    static const char *const names[] = {"csv", "title", "f", "nh_rotor_speed", "nh_theta",
                                        "nh_F_n", "nh_rotor_speed_amp", "nh_theta_amp",
                                        "nh_F_n_amp", "fmax", "peak_rotor_speed",
                                        "peak_theta", "peak_F_n"};
    const char *values[13] = {csv, title, num[0], num[1], num[2], num[3], num[4], num[5], num[6],
                              num[7], num[8], num[9], num[10]};
    snprintf(num[0], 32, "%.17g", r->f);
    for (int c = 0; c < USM_SPECTRUM_NCHANNELS; ++c) {
        snprintf(num[1 + c], 32, "%.17g", r->have_nonharmonic[c] ? r->nonharmonic[c].frequency : 0.0);
        snprintf(num[4 + c], 32, "%.17g", r->have_nonharmonic[c] ? r->nonharmonic[c].amplitude : 0.0);
        snprintf(num[8 + c], 32, "%.17g", r->peak[c]);
    }
    snprintf(num[7], 32, "%.17g", (double)(r->bins - 1) * r->df);
    rc = usm_plot_render("spectrum", a->spectrum, names, values, 13, msg);
    if (rc != USM_OK)
        spectrum_msg(msg);
    return rc;
}

/* Said before the run starts on a terminal, so that a slow run is not a
 * silent one.  Otherwise held back: a run that stops early says so in exactly
 * one stderr line, and the warning is in the summary either way. */
static void on_warning(const char *msg, void *data)
{
    run_io *io = data;
    if (io->line.on)
        cli_error("warning: %s", msg);
    else
        snprintf(io->early_warning, sizeof io->early_warning, "%s", msg);
}

static void on_progress(double t, double t0, double t1, void *data)
{
    run_io *io = data;
    cli_progress_fraction((t - t0) / (t1 - t0), &io->line);
}

static void warnings(const usm_sim_summary *s, double mu0)
{
    if (s->unilateral && s->impacts_slipping)
        cli_error("warning: %ld impacts needed a friction impulse above mu0 P_n; the stick model "
                  "sticks regardless and does not describe them (the 4-DOF model does)",
                  s->impacts_slipping);
    if (s->contact_open.count && !s->unilateral)
        cli_error("warning: F_n < 0 (the contact would open; the model assumes it never does) in "
                  "%ld interval%s from t = %.6g s to %.6g s, total %.6g s, min F_n = %.4g N",
                  s->contact_open.count, s->contact_open.count == 1 ? "" : "s",
                  s->contact_open.first, s->contact_open.last, s->contact_open.total,
                  s->contact_open.worst);
    if (s->stick_checked && s->stick_exceeded.count)
        cli_error("warning: |F_t| > mu0 F_n = %g F_n (the stick model needs more friction than "
                  "mu0) in %ld interval%s from t = %.6g s to %.6g s, total %.6g s, max excess "
                  "%.4g N",
                  mu0, s->stick_exceeded.count, s->stick_exceeded.count == 1 ? "" : "s",
                  s->stick_exceeded.first, s->stick_exceeded.last, s->stick_exceeded.total,
                  s->stick_exceeded.worst);
}

/* --out, --plot's and --spectrum's files: one run's outputs, each its own
 * file (--out X.csv --spectrum X would write the spectrum over the time
 * history), refused before the run. */
static int check_outputs(const sim_args *a, char msg[CLI_MSG_LEN])
{
    char files[2][USM_PLOT_MAX_FILES][USM_IO_PATH_LEN], why[USM_IO_MSG_LEN];
    const char *paths[1 + 2 * USM_PLOT_MAX_FILES], *opts[1 + 2 * USM_PLOT_MAX_FILES];
    int n = 0;
    if (a->out)
        paths[n] = a->out, opts[n++] = "--out";
    for (int k = 0; k < 2; ++k) {
        const char *prefix = k ? a->spectrum : a->plot;
        const int m = prefix ? usm_plot_files(prefix, k, files[k]) : 0;
        if (m < 0) {
            cli_msg(msg, "%s %.200s: path too long", k ? "--spectrum" : "--plot", prefix);
            return USM_EINPUT;
        }
        for (int i = 0; i < m; ++i)
            paths[n] = files[k][i], opts[n++] = k ? "--spectrum" : "--plot";
    }
    if (usm_io_check_distinct(paths, opts, n, why) != USM_OK) {
        cli_msg(msg, "%s", why);
        return USM_EINPUT;
    }
    return USM_OK;
}

static int simulate(sim_args *a, usm_sim *s)
{
    char msg[CLI_MSG_LEN];
    const usm_params *p = &a->common.params;
    usm_sim_summary sum;
    run_io io;
    usm_sim_callbacks cb;
    int status = USM_OK, rc;
    FILE *summary_out;
    usm_io_file csv_file;

    if (!a->rate_set)
        a->opt.rate = usm_sim_default_rate(p);
    if (a->opt.start == USM_SIM_FROM_STATE && (rc = usm_sim_read_start(a->from_file, a->common.model, &a->opt, msg)) != USM_OK) {
        cli_error("--from %s", msg);
        return rc;
    }
    if (usm_sim_check(s, p, &a->opt) != USM_OK) {
        option_message(usm_sim_message(s), msg);
        cli_error("%s", msg);
        return USM_EINPUT;
    }
    if (a->opt.rate * a->opt.duration > MAX_ROWS) {
        cli_error("--rate: %g samples per second for %g s would write %.3g rows (at most %.0g)",
                  a->opt.rate, a->opt.duration, a->opt.rate * a->opt.duration, MAX_ROWS);
        return USM_EINPUT;
    }
    if (check_outputs(a, msg) != USM_OK ||
        (a->plot && usm_plot_check(a->plot, a->force, msg) != USM_OK)) {
        cli_error("%s", msg);
        return USM_EINPUT;
    }
    memset(&io, 0, sizeof io);
    io.display = &a->common.display;
    if (a->spectrum) {
        usm_sim_spectrum_options so;
        char lib[USM_MSG_LEN];
        usm_sim_spectrum_options_default(&so);
        so.f = p->f;
        so.periods = a->spectrum_periods;
        so.rate = a->opt.rate;
        if (usm_sim_spectrum_check(&so, a->opt.duration, lib) != USM_OK) {
            if (strncmp(lib, "periods:", 8) == 0)
                cli_error("--spectrum-periods:%s", lib + 8);
            else
                cli_error("--spectrum: %s", lib);
            return USM_EINPUT;
        }
        if (usm_plot_csv_check(a->spectrum, a->force, msg) != USM_OK) {
            spectrum_msg(msg);
            cli_error("%s", msg);
            return USM_EINPUT;
        }
    }
    if (a->opt.rate > 0) {
        if (a->out) {
            if (!(io.csv = usm_io_create(&csv_file, a->out, a->force, msg, &status))) {
                cli_error("--out %s", msg);
                return status;
            }
        } else if (!a->spectrum)
            io.csv = stdout;
        if (io.csv)
            usm_sim_csv_header_in(&a->common.display, io.csv);
    }
    summary_out = io.csv == stdout ? stderr : stdout;
    cli_progress_init(&io.line, "usm simulate", a->quiet);
    io.line.total = lround(a->opt.duration * p->f);
    io.line.what = "periods";
    cb.sample = io.csv ? on_sample : NULL;
    cb.progress = on_progress;
    cb.data = &io;
    cb.warning = on_warning;

    /* the run, its spectrum and its summary: the library's (usm_run.h) */
    usm_run *run = usm_run_simulate(a->common.model, p, &a->opt, &cb,
                                    a->spectrum ? a->spectrum_periods : -1);
    rc = run ? usm_run_status(run) : USM_EFAILED;
    cli_progress_end(&io.line);
    if (io.csv && io.csv != stdout) {
        /* the history up to a numerical stop is data; bad input or no start, none */
        if (rc == USM_EINPUT || rc == USM_ENOSOLUTION)
            usm_io_abort(&csv_file);
        else if (usm_io_commit(&csv_file, msg) != USM_OK && rc == USM_OK) {
            cli_error("--out %s", msg);
            rc = USM_EFAILED;
        }
    } else if (io.csv && (fflush(stdout) != 0 || ferror(stdout))) {
        clearerr(stdout);
        cli_error("stdout: write error");
        usm_run_free(run);
        return USM_EFAILED;
    }
    if (!usm_run_has_json(run)) {
        cli_error("%s", usm_run_message(run));
        usm_run_free(run);
        return rc;
    }
    usm_sim_report rep;
    usm_run_sim_report(run, &rep);
    rep.from_file = a->from_file;
    rep.out = a->out;
    sum = *rep.summary;
    rep.summary = &sum;
    if (sum.stop == USM_SIM_STOPPED && io.csv_failed)
        snprintf(sum.reason, sizeof sum.reason, "write error on the CSV output at t = %.9g s",
                 sum.t_reached);
    /* the run's spectrum (also of a run that stopped early): its files */
    char spec_msg[CLI_MSG_LEN] = "";
    int spec_rc = USM_OK;
    char spec_csv[4096];
    if (usm_run_spectrum(run)) {
        spec_rc = spectrum_write(a, run, spec_msg);
        if (spec_rc != USM_OK && spec_rc != USM_ENOSOLUTION && rc == USM_OK)
            rc = USM_EFAILED;
        snprintf(spec_csv, sizeof spec_csv, "%s.csv", a->spectrum);
        rep.spectrum_csv = spec_csv;
    } else if (a->spectrum) {
        spectrum_error(usm_run_spectrum_error(run) ? usm_run_spectrum_error(run) : "none",
                       spec_msg);
        rep.spectrum_error = spec_msg;
    }
    if (!a->common.json)
        usm_sim_write_table_in(&rep, &a->common.display, summary_out);
    else if (usm_sim_write_json(&rep, summary_out) != 0) {
        cli_error("cannot write the JSON summary");
        rc = USM_EFAILED;
    }
    fflush(summary_out);
    if (rc == USM_OK) {
        if (io.early_warning[0])
            cli_error("warning: %s", io.early_warning);
        warnings(&sum, p->mu0);
    } else /* one line; the warnings are in the summary too */
        cli_error("stopped at t = %.9g s: %s%s%s%s", sum.t_reached, sum.reason,
                  sum.contact_open.count || (sum.stick_checked && sum.stick_exceeded.count)
                      ? " (contact warnings: see the summary)"
                      : "",
                  io.early_warning[0] ? "; warning: " : "", io.early_warning);
    if (a->plot && sum.samples > 0) {
        char title[256], num[7][32];
        static const char *const names[] = {"csv",         "title",     "stick",   "mu0",
                                            "have_steady", "theta_bar", "speed_bar",
                                            "settled",     "t_settle",  "rate_unit",
                                            "angle_unit"};
        const usm_display *d = &a->common.display;
        const char *values[11] = {a->out, title,  num[0], num[1], num[2], num[3],
                                  num[4], num[5], num[6], NULL,   NULL};
        usm_display_value(d, "rad/s", 0, &values[9]);
        usm_display_value(d, "rad", 0, &values[10]);
        snprintf(num[0], 32, "%d", sum.stick_checked);
        snprintf(num[1], 32, "%.17g", p->mu0);
        snprintf(num[2], 32, "%d", sum.have_steady);
        snprintf(num[3], 32, "%.17g",
                 sum.have_steady ? usm_display_value(d, "rad", sum.steady.theta, NULL) : 0.0);
        snprintf(num[4], 32, "%.17g",
                 sum.have_steady ? usm_display_value(d, "1/s", sum.steady.rotor_speed, NULL) : 0.0);
        snprintf(num[5], 32, "%d", sum.settled);
        snprintf(num[6], 32, "%.17g", sum.settled ? sum.t_settle : 0.0);
        if (sum.settled)
            snprintf(title, sizeof title, "usm simulate, model %s: settled at t = %.4g ms",
                     a->common.model->name, sum.t_settle * 1e3);
        else
            snprintf(title, sizeof title,
                     "usm simulate, model %s: not settled (period means within %g of the "
                     "stationary solution for %d periods)",
                     a->common.model->name, sum.settle_tol, sum.settle_periods);
        int prc = usm_plot_render("simulate", a->plot, names, values, 11, msg);
        if (prc == USM_ENOSOLUTION)
            cli_error("warning: %s", msg);
        else if (prc != USM_OK) {
            cli_error("%s", msg);
            if (rc == USM_OK)
                rc = USM_EFAILED;
        }
    }
    if (spec_msg[0])
        cli_error("%s%s", spec_rc == USM_ENOSOLUTION ? "warning: " : "", spec_msg);
    usm_run_free(run);
    return rc == USM_OK ? USM_OK : USM_EFAILED;
}

static int run(void *p)
{
    sim_args *a = p;
    usm_sim *s = usm_sim_alloc(a->common.model);
    if (!s) {
        cli_error("out of memory");
        return USM_EFAILED;
    }
    int rc = simulate(a, s);
    usm_sim_free(s);
    return rc;
}

const cli_command cli_simulate = {sizeof(sim_args), usage, init, option, finish, run, 0, 1};
