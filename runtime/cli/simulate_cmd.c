/* usm simulate: start-up transient of the full model (library: usm_simulate.h).
 *
 * Streams the time history as CSV (to --out or stdout), then prints a summary:
 * a table, or one JSON object with --json, on stdout unless the CSV occupies
 * stdout (then on stderr).  Never overwrites a file unless --force. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include <jansson.h>

#include "commands.h"
#include "diag.h"
#include "json_out.h"
#include "options.h"
#include "csv_out.h"
#include "plot_run.h"
#include "usm_io.h"
#include "usm.h"
#include "usm_simulate.h"

/* More rows than anyone can look at; a typo in --rate or --duration. */
#define MAX_ROWS 100000000.0

static void usage(FILE *out)
{
    fprintf(out,
            "usage: usm simulate [--model 3dof|4dof] [--params FILE.json] [--set NAME=VALUE]...\n"
            "                    --duration S [--from rest|stationary|FILE] [--out FILE.csv]\n"
            "                    [--force] [--rate HZ] [--tilt0 RAD] [--rtol R] [--plot PREFIX]\n"
            "                    [--json]\n"
            "\n"
            "Integrate the full nonlinear model M(x) x' = f(x, t) (CVODES, BDF) from the motor\n"
            "at rest, write the time history as CSV and report whether and when the motion\n"
            "settled onto the stationary solution.\n"
            "\n"
            "options:\n");
    cli_common_usage(out);
    fprintf(out,
            "  --duration S        simulated time [s] (required)\n"
            "  --from rest         start at rest: tilt tilt0 about the excitation torque's axis,\n"
            "                      zero rates (default)\n"
            "  --from stationary   start on the stationary orbit (usm steady's primary root)\n"
            "  --from FILE         start from a state: a CSV with a header naming the state\n"
            "                      variables (its last row is used, so an --out file continues)\n"
            "                      or a JSON object {\"t\": S, \"x\": [...]} or {\"theta\": ..., ...}\n"
            "  --out FILE.csv      write the time history there (default: stdout)\n"
            "  --force             overwrite --out and --plot files that exist\n"
            "  --rate HZ           samples per second (default 10 f; 0: no time history)\n"
            "  --tilt0 RAD         initial tilt when starting at rest (default 1e-6)\n"
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
            "  -h, --help          print this help\n"
            "\n"
            "CSV columns: t [s], phi theta psi [rad], phidot thetadot psidot [rad/s],\n"
            "phi_R [rad], phi_Rdot [rad/s], F_n F_t [N], v_rel [m/s], theta_avg [rad],\n"
            "phi_Rdot_avg [rad/s] (means over the last complete excitation period).\n"
            "\n"
            "exit status: 0 completed (settled or not), 1 stopped early (integrator failure,\n"
            "             runaway, step cap, write error), 2 bad input or an existing output\n"
            "             file, 3 --from stationary without a stationary solution\n");
}

typedef struct sim_args {
    cli_common common;
    usm_sim_options opt;
    const char *from_file;
    const char *out;
    const char *plot;
    int force;
    int rate_set;
    int duration_set;
    int help;
} sim_args;

/* ---- parsing ------------------------------------------------------------------ */

static int take_double(int argc, char **argv, int *i, const char *name, double *v, int *taken,
                       char msg[CLI_MSG_LEN])
{
    const char *value;
    int r = cli_option_value(argc, argv, i, name, &value, msg);
    *taken = r == CLI_OPT_TAKEN;
    if (r == CLI_OPT_ERROR)
        return USM_EINPUT;
    if (r == CLI_OPT_TAKEN)
        return cli_parse_double(name, value, v, msg);
    return USM_OK;
}

static int take_string(int argc, char **argv, int *i, const char *name, const char **v,
                       int *taken, char msg[CLI_MSG_LEN])
{
    int r = cli_option_value(argc, argv, i, name, v, msg);
    *taken = r == CLI_OPT_TAKEN;
    if (r == CLI_OPT_ERROR)
        return USM_EINPUT;
    if (r == CLI_OPT_TAKEN && (*v)[0] == '\0') {
        cli_msg(msg, "%s: empty value", name);
        return USM_EINPUT;
    }
    return USM_OK;
}

static int whole_number(const char *name, double v, double lo, long *out, char msg[CLI_MSG_LEN])
{
    if (v != floor(v) || v < lo || v > 1e15) {
        cli_msg(msg, "%s: must be a whole number >= %g", name, lo);
        return USM_EINPUT;
    }
    *out = (long)v;
    return USM_OK;
}

static int parse(sim_args *a, int argc, char **argv, char msg[CLI_MSG_LEN])
{
    memset(a, 0, sizeof *a);
    cli_common_init(&a->common);
    usm_sim_options_default(&a->opt);
    for (int i = 1; i < argc; ++i) {
        const char *sv;
        double v;
        int r, taken;
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            a->help = 1;
            return USM_OK;
        }
        if ((r = cli_common_option(&a->common, argc, argv, &i, msg)) == CLI_OPT_TAKEN)
            continue;
        if (r == CLI_OPT_ERROR)
            return USM_EINPUT;
        if (strcmp(argv[i], "--force") == 0) {
            a->force = 1;
            continue;
        }
        if (take_double(argc, argv, &i, "--duration", &a->opt.duration, &taken, msg) != USM_OK)
            return USM_EINPUT;
        if (taken) {
            if (!(a->opt.duration > 0)) {
                cli_msg(msg, "--duration: must be positive, got %g", a->opt.duration);
                return USM_EINPUT;
            }
            a->duration_set = 1;
            continue;
        }
        if (take_double(argc, argv, &i, "--rate", &a->opt.rate, &taken, msg) != USM_OK)
            return USM_EINPUT;
        if (taken) {
            if (!(a->opt.rate >= 0)) {
                cli_msg(msg, "--rate: must be >= 0 samples per second, got %g", a->opt.rate);
                return USM_EINPUT;
            }
            a->rate_set = 1;
            continue;
        }
        if (take_double(argc, argv, &i, "--tilt0", &a->opt.tilt0, &taken, msg) != USM_OK)
            return USM_EINPUT;
        if (taken) {
            if (!(a->opt.tilt0 > 0 && a->opt.tilt0 < 0.5)) {
                cli_msg(msg, "--tilt0: must be in (0, 0.5) rad, got %g", a->opt.tilt0);
                return USM_EINPUT;
            }
            continue;
        }
        if (take_double(argc, argv, &i, "--rtol", &a->opt.rtol, &taken, msg) != USM_OK)
            return USM_EINPUT;
        if (taken) {
            if (!(a->opt.rtol >= 1e-14 && a->opt.rtol <= 1e-3)) {
                cli_msg(msg, "--rtol: must be in [1e-14, 1e-3], got %g", a->opt.rtol);
                return USM_EINPUT;
            }
            continue;
        }
        if (take_double(argc, argv, &i, "--settle-tol", &a->opt.settle_tol, &taken, msg) != USM_OK)
            return USM_EINPUT;
        if (taken) {
            if (!(a->opt.settle_tol > 0 && a->opt.settle_tol < 1)) {
                cli_msg(msg, "--settle-tol: must be in (0, 1), got %g", a->opt.settle_tol);
                return USM_EINPUT;
            }
            continue;
        }
        if (take_double(argc, argv, &i, "--settle-periods", &v, &taken, msg) != USM_OK)
            return USM_EINPUT;
        if (taken) {
            long n;
            if (whole_number("--settle-periods", v, 1, &n, msg) != USM_OK || n > 100000000) {
                cli_msg(msg, "--settle-periods: must be a whole number in [1, 1e8]");
                return USM_EINPUT;
            }
            a->opt.settle_periods = (int)n;
            continue;
        }
        if (take_double(argc, argv, &i, "--theta-limit", &a->opt.theta_limit, &taken, msg) !=
            USM_OK)
            return USM_EINPUT;
        if (taken) {
            if (!(a->opt.theta_limit > 0 && a->opt.theta_limit < 1.5)) {
                cli_msg(msg, "--theta-limit: must be in (0, 1.5) rad, got %g", a->opt.theta_limit);
                return USM_EINPUT;
            }
            continue;
        }
        if (take_double(argc, argv, &i, "--speed-limit", &a->opt.speed_limit, &taken, msg) !=
            USM_OK)
            return USM_EINPUT;
        if (taken) {
            if (!(a->opt.speed_limit > 0)) {
                cli_msg(msg, "--speed-limit: must be positive, got %g", a->opt.speed_limit);
                return USM_EINPUT;
            }
            continue;
        }
        if (take_double(argc, argv, &i, "--max-steps", &v, &taken, msg) != USM_OK)
            return USM_EINPUT;
        if (taken) {
            if (whole_number("--max-steps", v, 1, &a->opt.max_steps, msg) != USM_OK)
                return USM_EINPUT;
            continue;
        }
        if (take_double(argc, argv, &i, "--max-twist-growth", &a->opt.max_twist_growth, &taken,
                        msg) != USM_OK)
            return USM_EINPUT;
        if (taken) {
            if (!(a->opt.max_twist_growth >= 0)) {
                cli_msg(msg, "--max-twist-growth: must be >= 0 (0: no limit), got %g",
                        a->opt.max_twist_growth);
                return USM_EINPUT;
            }
            continue;
        }
        if (take_string(argc, argv, &i, "--from", &sv, &taken, msg) != USM_OK)
            return USM_EINPUT;
        if (taken) {
            a->from_file = NULL;
            if (strcmp(sv, "rest") == 0)
                a->opt.start = USM_SIM_FROM_REST;
            else if (strcmp(sv, "stationary") == 0)
                a->opt.start = USM_SIM_FROM_STATIONARY;
            else {
                a->opt.start = USM_SIM_FROM_STATE;
                a->from_file = sv;
            }
            continue;
        }
        if (take_string(argc, argv, &i, "--out", &a->out, &taken, msg) != USM_OK)
            return USM_EINPUT;
        if (taken)
            continue;
        if (take_string(argc, argv, &i, "--plot", &a->plot, &taken, msg) != USM_OK)
            return USM_EINPUT;
        if (taken)
            continue;
        if (argv[i][0] == '-')
            cli_msg(msg, "%s: unknown option (see usm simulate --help)", argv[i]);
        else
            cli_msg(msg, "%s: unexpected argument (see usm simulate --help)", argv[i]);
        return USM_EINPUT;
    }
    if (!a->duration_set) {
        cli_msg(msg, "--duration: missing (the simulated time in seconds)");
        return USM_EINPUT;
    }
    if (a->plot && !a->out) {
        cli_msg(msg, "--plot: needs --out (gnuplot reads the CSV file)");
        return USM_EINPUT;
    }
    if (a->rate_set && a->opt.rate == 0 && (a->out || a->plot)) {
        cli_msg(msg, "--rate 0 writes no time history; drop --out/--plot or give a rate");
        return USM_EINPUT;
    }
    return cli_common_finish(&a->common, msg);
}

/* ---- output ----------------------------------------------------------------- */

typedef struct run_io {
    FILE *csv;
    int progress;          /* draw a progress bar on stderr */
    double last_draw;      /* wall time of the last redraw */
    int drawn;
    double wall0;
    char early_warning[CLI_MSG_LEN]; /* a warning held back until the run ends */
} run_io;

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The time history's columns (csv_out.h), read back by --from FILE. */
static const usm_csv_column columns[] = {
    {"t", "s"},           {"phi", "rad"},         {"theta", "rad"},    {"psi", "rad"},
    {"phidot", "rad/s"},  {"thetadot", "rad/s"},  {"psidot", "rad/s"}, {"phi_R", "rad"},
    {"phi_Rdot", "rad/s"}, {"F_n", "N"},          {"F_t", "N"},        {"v_rel", "m/s"},
    {"theta_avg", "rad"}, {"phi_Rdot_avg", "rad/s"}};

static void csv_header(FILE *f)
{
    usm_csv_header(f, columns, (int)(sizeof columns / sizeof columns[0]));
}

static int on_sample(const usm_sim_sample *s, void *data)
{
    run_io *io = data;
    FILE *f = io->csv;
    /* shortest exact text: --from FILE continues exactly */
    const double v[] = {s->t, s->phi, s->theta, s->psi, s->phidot, s->thetadot, s->psidot,
                        s->rotor_angle, s->rotor_speed, s->out[USM_OUT_F_N],
                        s->out[USM_OUT_F_T], s->out[USM_OUT_V_REL],
                        s->have_avg ? s->theta_avg : NAN, s->have_avg ? s->rotor_speed_avg : NAN};
    for (size_t k = 0; k < sizeof v / sizeof v[0]; ++k)
        usm_csv_num(f, k == 0, v[k]);
    fputc('\n', f);
    return ferror(f) ? 1 : 0;
}

/* Said before the run starts on a terminal, so that a slow run is not a
 * silent one.  Otherwise held back: a run that stops early says so in exactly
 * one stderr line, and the warning is in the summary either way. */
static void on_warning(const char *msg, void *data)
{
    run_io *io = data;
    if (io->progress)
        cli_error("warning: %s", msg);
    else
        snprintf(io->early_warning, sizeof io->early_warning, "%s", msg);
}

static void on_progress(double t, double t0, double t1, void *data)
{
    run_io *io = data;
    const double w = now();
    if (!io->progress || (w - io->last_draw < 0.1 && t < t1))
        return;
    const double frac = (t - t0) / (t1 - t0);
    const int width = 40, fill = (int)(frac * width);
    char bar[64];
    for (int k = 0; k < width; ++k)
        bar[k] = k < fill ? '#' : '.';
    bar[width] = '\0';
    fprintf(stderr, "\rusm simulate [%s] %3.0f%%  t = %-12.6g s  %6.1f s", bar, 100 * frac, t,
            w - io->wall0);
    fflush(stderr);
    io->last_draw = w;
    io->drawn = 1;
}

static const char *start_text(const sim_args *a, char *buf, size_t len)
{
    switch (a->opt.start) {
    case USM_SIM_FROM_REST:
        snprintf(buf, len, "rest (tilt0 = %g rad about the excitation axis, zero rates)",
                 a->opt.tilt0);
        break;
    case USM_SIM_FROM_STATIONARY:
        snprintf(buf, len, "the stationary orbit");
        break;
    case USM_SIM_FROM_STATE:
        snprintf(buf, len, "the state in %s", a->from_file);
        break;
    }
    return buf;
}

static void episodes_line(FILE *out, const char *what, const usm_sim_episodes *e,
                          const char *worst_what, const char *unit)
{
    fprintf(out, "  %-22s %ld interval%s, first from t = %.6g s, last until t = %.6g s, total "
                 "%.6g s; %s %.4g %s\n",
            what, e->count, e->count == 1 ? "" : "s", e->first, e->last, e->total, worst_what,
            e->worst, unit);
}

static void table(FILE *out, const sim_args *a, const usm_sim_summary *s, double wall)
{
    char buf[512];
    const double T = 1.0 / a->common.params.f;
    fprintf(out, "usm simulate: model %s from %s\n", a->common.model->name,
            start_text(a, buf, sizeof buf));
    fprintf(out, "  %-22s [%.9g, %.9g] s (%ld excitation periods of %.6g s)\n", "interval", s->t0,
            s->t1, s->periods, T);
    fprintf(out, "  %-22s %s%s%s\n", "stop", usm_sim_stop_name(s->stop), s->reason[0] ? ": " : "",
            s->reason);
    fprintf(out, "  %-22s %.9g s\n", "reached", s->t_reached);
    fprintf(out, "  %-22s %ld steps, %ld f evaluations, %ld Jacobians, %.3g s wall, rtol %g\n",
            "integrator", s->steps, s->rhs_evals, s->jac_evals, wall, a->opt.rtol);
    fprintf(out, "  %-22s [%.6g, %.6g] rad\n", "tilt range", s->theta_min, s->theta_max);
    if (s->have_steady)
        fprintf(out, "  %-22s theta = %.10g rad, rotor speed = %.10g 1/s\n", "stationary solution",
                s->steady.theta, s->steady.rotor_speed);
    else
        fprintf(out, "  %-22s none (%s): settling is not defined\n", "stationary solution",
                s->steady_message);
    if (s->periods > 0) {
        fprintf(out, "  %-22s theta = %.10g rad, rotor speed = %.10g 1/s\n", "last period mean",
                s->theta_avg_end, s->rotor_speed_avg_end);
        if (s->have_steady)
            fprintf(out, "  %-22s theta %+.3e, rotor speed %+.3e (relative to stationary)\n",
                    "difference at the end", s->theta_rel_end, s->rotor_speed_rel_end);
    }
    if (s->settled)
        fprintf(out,
                "  %-22s yes, at t = %.6g s (%.0f periods after the start); period means of "
                "theta and rotor speed within %g of stationary from then to the end (%ld "
                "periods)\n",
                "settled", s->t_settle, (s->t_settle - s->t0) / T, s->settle_tol,
                s->periods - (long)floor((s->t_settle - s->t0) / T + 0.5));
    else if (s->have_steady)
        fprintf(out,
                "  %-22s no (tolerance %g relative, held for %d periods to the end of the run)\n",
                "settled", s->settle_tol, s->settle_periods);
    if (s->contact_open.count)
        episodes_line(out, "F_n < 0 (contact opens)", &s->contact_open, "most negative F_n", "N");
    if (s->stick_checked && s->stick_exceeded.count)
        episodes_line(out, "|F_t| > mu0 F_n", &s->stick_exceeded, "largest |F_t| - mu0 F_n", "N");
}

static json_t *episodes_json(const usm_sim_episodes *e, const char *worst_key)
{
    json_t *o = json_object();
    int ok = o != NULL;
    usm_json_put(o, "count", json_integer(e->count), &ok);
    if (e->count) {
        usm_json_put(o, "first", usm_json_real(e->first), &ok);
        usm_json_put(o, "last", usm_json_real(e->last), &ok);
        usm_json_put(o, "total", usm_json_real(e->total), &ok);
        usm_json_put(o, worst_key, usm_json_real(e->worst), &ok);
    }
    if (!ok) {
        json_decref(o);
        return NULL;
    }
    return o;
}

static json_t *summary_json(const sim_args *a, const usm_sim_summary *s, double wall)
{
    const usm_model *m = a->common.model;
    json_t *o = json_object(), *fs = json_object(), *x = json_array(), *names = json_array();
    int ok = o && fs && x && names;
    const char *start[] = {"rest", "stationary", "file"};
    usm_json_put(o, "model", json_string(m->name), &ok);
    usm_json_put(o, "parameters", usm_json_params(&a->common.params), &ok);
    usm_json_put(o, "start", json_string(start[a->opt.start]), &ok);
    if (a->opt.start == USM_SIM_FROM_REST)
        usm_json_put(o, "tilt0", usm_json_real(a->opt.tilt0), &ok);
    if (a->from_file)
        usm_json_put(o, "from", json_string(a->from_file), &ok);
    usm_json_put(o, "out", a->out ? json_string(a->out) : json_null(), &ok);
    usm_json_put(o, "rate", usm_json_real(a->opt.rate), &ok);
    usm_json_put(o, "rtol", usm_json_real(a->opt.rtol), &ok);
    usm_json_put(o, "t0", usm_json_real(s->t0), &ok);
    usm_json_put(o, "t1", usm_json_real(s->t1), &ok);
    usm_json_put(o, "t_reached", usm_json_real(s->t_reached), &ok);
    usm_json_put(o, "completed", json_boolean(s->stop == USM_SIM_COMPLETED), &ok);
    usm_json_put(o, "stop", json_string(usm_sim_stop_name(s->stop)), &ok);
    if (s->reason[0])
        usm_json_put(o, "reason", json_string(s->reason), &ok);
    usm_json_put(o, "steps", json_integer(s->steps), &ok);
    usm_json_put(o, "rhs_evals", json_integer(s->rhs_evals), &ok);
    usm_json_put(o, "jac_evals", json_integer(s->jac_evals), &ok);
    usm_json_put(o, "error_test_fails", json_integer(s->error_test_fails), &ok);
    usm_json_put(o, "newton_fails", json_integer(s->newton_fails), &ok);
    usm_json_put(o, "twist_growth", usm_json_real(s->twist_growth), &ok);
    if (s->warning[0])
        usm_json_put(o, "warning", json_string(s->warning), &ok);
    usm_json_put(o, "samples", json_integer(s->samples), &ok);
    usm_json_put(o, "wall_time", usm_json_real(wall), &ok);
    usm_json_put(o, "periods", json_integer(s->periods), &ok);
    usm_json_put(o, "theta_min", usm_json_real(s->theta_min), &ok);
    usm_json_put(o, "theta_max", usm_json_real(s->theta_max), &ok);
    if (s->have_steady)
        usm_json_put(o, "stationary", usm_json_root(&s->steady), &ok);
    else {
        usm_json_put(o, "stationary", json_null(), &ok);
        usm_json_put(o, "stationary_error", json_string(s->steady_message), &ok);
    }
    usm_json_put(o, "settle_tol", usm_json_real(s->settle_tol), &ok);
    usm_json_put(o, "settle_periods", json_integer(s->settle_periods), &ok);
    usm_json_put(o, "settled", json_boolean(s->settled), &ok);
    usm_json_put(o, "t_settle", s->settled ? usm_json_real(s->t_settle) : json_null(), &ok);
    if (s->periods > 0) {
        usm_json_put(o, "theta_avg_end", usm_json_real(s->theta_avg_end), &ok);
        usm_json_put(o, "rotor_speed_avg_end", usm_json_real(s->rotor_speed_avg_end), &ok);
        if (s->have_steady) {
            usm_json_put(o, "theta_rel_end", usm_json_real(s->theta_rel_end), &ok);
            usm_json_put(o, "rotor_speed_rel_end", usm_json_real(s->rotor_speed_rel_end), &ok);
        }
    }
    usm_json_put(o, "contact_open", episodes_json(&s->contact_open, "min_F_n"), &ok);
    if (s->stick_checked)
        usm_json_put(o, "stick_exceeded", episodes_json(&s->stick_exceeded, "max_excess"), &ok);
    for (int i = 0; i < m->nx && ok; ++i) {
        ok = ok && json_array_append_new(x, usm_json_real(s->final_x[i])) == 0;
        ok = ok && json_array_append_new(names, json_string(m->state_names[i])) == 0;
    }
    usm_json_put(fs, "t", usm_json_real(s->t_reached), &ok);
    usm_json_put(fs, "x", x, &ok);
    usm_json_put(fs, "names", names, &ok);
    usm_json_put(fs, "phi_R", usm_json_real(s->final_rotor_angle), &ok);
    usm_json_put(o, "final_state", fs, &ok);
    if (!ok) {
        json_decref(o);
        return NULL;
    }
    return o;
}

static void warnings(const usm_sim_summary *s, double mu0)
{
    if (s->contact_open.count)
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

/* Open --out: refuse to replace an existing file unless --force (O_EXCL
 * makes the check and the creation one step). */
static FILE *open_out(const char *path, int force, char msg[CLI_MSG_LEN], int *status)
{
    int fd = open(path, O_WRONLY | O_CREAT | (force ? O_TRUNC : O_EXCL), 0666);
    FILE *f;
    if (fd < 0) {
        if (errno == EEXIST) {
            cli_msg(msg, "--out %s: exists; refusing to overwrite it (use --force)", path);
            *status = USM_EINPUT;
        } else {
            cli_msg(msg, "--out %s: %s", path, strerror(errno));
            *status = USM_EINPUT;
        }
        return NULL;
    }
    if (!(f = fdopen(fd, "w"))) {
        cli_msg(msg, "--out %s: %s", path, strerror(errno));
        close(fd);
        *status = USM_EFAILED;
    }
    return f;
}

static int run(sim_args *a)
{
    char msg[CLI_MSG_LEN];
    const usm_params *p = &a->common.params;
    usm_sim_summary sum;
    run_io io;
    usm_sim_callbacks cb;
    int status = USM_OK, rc;
    FILE *summary_out;
    double wall;
    usm_sim *s;

    if (!a->rate_set)
        a->opt.rate = 10.0 * p->f;
    if (a->opt.rate * a->opt.duration > MAX_ROWS) {
        cli_error("--rate: %g samples per second for %g s would write %.3g rows (at most %.0g)",
                  a->opt.rate, a->opt.duration, a->opt.rate * a->opt.duration, MAX_ROWS);
        return USM_EINPUT;
    }
    if (a->opt.start == USM_SIM_FROM_STATE && (rc = usm_sim_read_start(a->from_file, a->common.model, &a->opt, msg)) != USM_OK) {
        cli_error("--from %s", msg);
        return rc;
    }
    if (a->plot && usm_plot_check(a->plot, a->force, msg) != USM_OK) {
        cli_error("%s", msg);
        return USM_EINPUT;
    }
    memset(&io, 0, sizeof io);
    if (a->opt.rate > 0) {
        if (a->out) {
            if (!(io.csv = open_out(a->out, a->force, msg, &status))) {
                cli_error("%s", msg);
                return status;
            }
        } else
            io.csv = stdout;
        csv_header(io.csv);
    }
    summary_out = io.csv == stdout ? stderr : stdout;
    io.progress = isatty(STDERR_FILENO);
    io.wall0 = io.last_draw = now();
    cb.sample = io.csv ? on_sample : NULL;
    cb.progress = on_progress;
    cb.data = &io;
    cb.warning = on_warning;

    if (!(s = usm_sim_alloc(a->common.model))) {
        cli_error("out of memory");
        if (io.csv && io.csv != stdout)
            fclose(io.csv);
        return USM_EFAILED;
    }
    rc = usm_sim_run(s, p, &a->opt, &cb, &sum);
    wall = now() - io.wall0;
    if (io.drawn)
        fprintf(stderr, "\r%*s\r", 96, "");
    if (io.csv && io.csv != stdout) {
        if (fclose(io.csv) != 0 && rc == USM_OK) {
            cli_error("--out %s: write error", a->out);
            rc = USM_EFAILED;
        }
    } else if (io.csv && (fflush(stdout) != 0 || ferror(stdout))) {
        clearerr(stdout);
        cli_error("stdout: write error");
        usm_sim_free(s);
        return USM_EFAILED;
    }
    if (rc == USM_EINPUT || rc == USM_ENOSOLUTION) {
        cli_error("%s", usm_sim_message(s));
        usm_sim_free(s);
        return rc;
    }
    if (sum.stop == USM_SIM_STOPPED && io.csv)
        snprintf(sum.reason, sizeof sum.reason, "write error on the CSV output at t = %.9g s",
                 sum.t_reached);
    if (a->common.json) {
        json_t *obj = summary_json(a, &sum, wall);
        if (!obj || usm_json_print(obj, summary_out) != 0) {
            cli_error("cannot write the JSON summary");
            rc = USM_EFAILED;
        }
        json_decref(obj);
    } else
        table(summary_out, a, &sum, wall);
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
                                            "settled",     "t_settle"};
        const char *values[9] = {a->out, title,  num[0], num[1], num[2],
                                 num[3], num[4], num[5], num[6]};
        snprintf(num[0], 32, "%d", sum.stick_checked);
        snprintf(num[1], 32, "%.17g", p->mu0);
        snprintf(num[2], 32, "%d", sum.have_steady);
        snprintf(num[3], 32, "%.17g", sum.have_steady ? sum.steady.theta : 0.0);
        snprintf(num[4], 32, "%.17g", sum.have_steady ? sum.steady.rotor_speed : 0.0);
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
        int prc = usm_plot_render("simulate", a->plot, names, values, 9, msg);
        if (prc == USM_ENOSOLUTION)
            cli_error("warning: %s", msg);
        else if (prc != USM_OK) {
            cli_error("%s", msg);
            if (rc == USM_OK)
                rc = USM_EFAILED;
        }
    }
    usm_sim_free(s);
    return rc == USM_OK ? USM_OK : USM_EFAILED;
}

int cli_simulate_main(int argc, char **argv)
{
    sim_args a;
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
