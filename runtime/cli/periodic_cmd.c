/* usm periodic: the periodic steady state of a real motor by shooting
 * (library: usm_periodic.h).  Never overwrites --orbit unless --force. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <string.h>

#include "commands.h"
#include "diag.h"
#include "options.h"
#include "usm_io.h"
#include "usm_periodic.h"
#include "usm_run.h"

/* The default variant of base `base`: the one of a real motor (m->imperfect),
 * whose integrated twist law has a periodic orbit; "paper" if none. */
static const char *default_variant(const char *base)
{
    for (int k = 0; k < USM_NMODELS; ++k)
        if (usm_models[k]->imperfect && strcmp(usm_models[k]->base, base) == 0)
            return usm_models[k]->variant;
    return "paper";
}

static void usage(FILE *out)
{
    fprintf(out,
            "usage: usm periodic [--model M] [--variant V] [--params F] [--set N=V]...\n"
            "                    [--orbit FILE.csv [--force]] [--json]\n"
            "\n"
            "The periodic steady state of a motor with driver amplitude imbalance\n"
            "(amp_imbalance), phase error (phase_error [rad]) and stator mode split\n"
            "(mode_split): shooting over one excitation period from the ideal stationary\n"
            "solution, with its Floquet multipliers.  The variant needs the integrated\n"
            "twist law (the paper's has no periodic orbit): imperfect,\n"
            "imperfect_unilateral, twist_integrated or tilt (twist_integrated in the tilt\n"
            "vector; docs/coordinates.md).\n"
            "\n"
            "options:\n");
    cli_common_usage_variant(out, default_variant("3dof"));
    cli_units_usage(out);
    fprintf(out,
            "  --orbit FILE.csv    write one period at %d points: t, state, F_n, F_t, rotor speed\n"
            "                      (an orbit with separation: t, open, state, gap, F_n, F_t,\n"
            "                      rotor speed, at %d + 1 points and both sides of every switch)\n"
            "  --force             overwrite --orbit if it exists\n"
            "  -h, --help          print this help\n"
            "\n"
            "exit status: 0 solved, 1 numerical failure (Newton or integrator; --json still\n"
            "             prints converged=false), 2 bad input or a twist law without\n"
            "             periodic orbit, 3 no stationary solution of the ideal motor to\n"
            "             start from (as usm steady)\n",
            USM_PERIODIC_SAMPLES, USM_PERIODIC_SAMPLES);
}

typedef struct periodic_args {
    cli_common common;
    const char *orbit;
    int force;
} periodic_args;

static int init(void *p, char msg[CLI_MSG_LEN])
{
    periodic_args *a = p;
    (void)msg;
    /* default_variant; --variant overrides it */
    a->common.variant = default_variant(a->common.base);
    return USM_OK;
}

static int option(void *p, int argc, char **argv, int *i, char msg[CLI_MSG_LEN])
{
    periodic_args *a = p;
    CLI_TRY(cli_flag_option(argv, i, "--force", &a->force));
    CLI_TRY(cli_common_option(&a->common, argc, argv, i, msg));
    return cli_option_value(argc, argv, i, "--orbit", &a->orbit, msg);
}

static int finish(void *p, char msg[CLI_MSG_LEN])
{
    periodic_args *a = p;
    if (a->force && !a->orbit) {
        cli_msg(msg, "--force: only with --orbit");
        return USM_EINPUT;
    }
    return cli_common_finish(&a->common, msg);
}

/* --orbit: the orbit's CSV; with separation (h) USM_PERIODIC_SAMPLES a
 * period and both sides of every switch */
static int write_orbit(const periodic_args *a, const usm_run *run, char msg[CLI_MSG_LEN])
{
    usm_io_file file;
    int status;
    char lib[USM_MSG_LEN];
    const usm_hybrid_result *h = usm_run_hybrid_result(run);
    cli_shown shown;
    FILE *out = usm_io_create(&file, a->orbit, a->force, msg, &status);
    if (!out)
        return status;
    FILE *f = cli_shown_open(&shown, &a->common.display, out);
    if (!f) {
        usm_io_abort(&file);
        cli_msg(msg, "%s: out of memory", a->orbit);
        return USM_EFAILED;
    }
    /* the solve's tolerance: usm_run_periodic's default */
    if (h && (status = usm_hybrid_write_orbit_csv(a->common.model, &a->common.params, h, 0.0,
                                                  USM_PERIODIC_SAMPLES, f, lib)) != USM_OK) {
        cli_shown_close(&shown);
        usm_io_abort(&file);
        cli_msg(msg, "%s: %s", a->orbit, lib);
        return status;
    }
    int bad = !h && usm_periodic_write_orbit_csv(usm_run_periodic_solver(run), f) != 0;
    bad |= cli_shown_close(&shown) != 0; /* converts what either writer wrote */
    if (bad) {
        usm_io_abort(&file);
        cli_msg(msg, "%s: write error", a->orbit);
        return USM_EFAILED;
    }
    return usm_io_commit(&file, msg);
}

static int write_table(const void *p, const usm_run *run, FILE *out)
{
    const periodic_args *a = p;
    const usm_hybrid_result *h = usm_run_hybrid_result(run);
    if (h)
        usm_hybrid_write_table(a->common.model, h, &a->common.display, out);
    else
        usm_periodic_write_table(a->common.model, usm_run_periodic_result(run),
                                 &a->common.display, out);
    return 0;
}

static int run(void *p)
{
    const periodic_args *a = p;
    char msg[CLI_MSG_LEN];
    /* an --orbit that cannot be written fails now, not after the shooting */
    if (a->orbit && usm_io_check(a->orbit, a->force, msg) != USM_OK) {
        cli_error("--orbit %s", msg);
        return USM_EINPUT;
    }
    usm_run *run = usm_run_periodic(a->common.model, &a->common.params);
    int status = usm_run_status(run);
    if (status == USM_OK && a->orbit && (status = write_orbit(a, run, msg)) != USM_OK)
        cli_error("--orbit %s", msg);
    else /* the --json object with "error" on a failure too */
        status = cli_run_output(run, a->common.json, CLI_JSON_ON_FAILURE, write_table, a);
    usm_run_free(run);
    return status;
}

const cli_command cli_periodic = {sizeof(periodic_args), usage, init, option, finish, run, 0, 1};
