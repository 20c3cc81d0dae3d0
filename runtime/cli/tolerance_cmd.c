/* usm tolerance: Monte Carlo yield study (the library's usm_tolerance.h);
 * this file parses, calls and writes. */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

#include "commands.h"
#include "options.h"
#include "progress.h"
#include "usm_plot.h"
#include "usm_run.h"
#include "usm_tolerance.h"
#ifdef USM_HAVE_MPI
#include "usm_mpi.h"
#endif

static double clock_seconds(clockid_t id)
{
    struct timespec ts;
    clock_gettime(id, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void usage(FILE *out)
{
    fputs("usage: usm tolerance --samples N --vary NAME=DIST [--vary ...]\n"
          "         [--spec OUTPUT>=X | --spec OUTPUT<=X]... [--allow-driven]\n"
          "         [--seed S] [--threads N]\n"
          "         [--model M] [--variant V] [--params F] [--set N=V]...\n"
          "         [--floquet-method NAME] [--rtol R] [--from-rest]\n"
          "         [--out DIR [--force]] [--checkpoint FILE] [--json] [--quiet]\n\n"
          "Monte Carlo tolerance study: at N parameter points drawn around the nominal\n"
          "design, the stationary solution and its Floquet multipliers; the yield with its\n"
          "95 % Wilson interval, quantiles, and the Spearman rank correlation of each\n"
          "output with each varied parameter.  A sample is good (counts for the yield) only\n"
          "if its operating point (the stable root the motor runs at) exists, is stable,\n"
          "meets every spec, is valid (the model describes the motor there: contact\n"
          "closed, and for the 3-DOF stick model |F_t| <= mu0 F_n) and the motor drives its\n"
          "load (power_out >= 0, as usm optimize asks), unless --allow-driven.  Where several\n"
          "roots exist the operating point is unknown, and does not count, unless --from-rest.\n"
          "\noptions:\n",
          out);
    cli_common_usage(out);
    cli_floquet_usage(out);
    cli_from_rest_usage(out);
    fputs("  --samples N         number of samples, a whole number 1 ... 1000000000\n"
          "  --vary NAME=DIST    normal:5% (sigma relative to the nominal value), normal:0.01\n"
          "                      (absolute), uniform:2% (relative half-width), uniform:LO:HI;\n"
          "                      absolute values in SI or with a unit: F0=uniform:350mN:450mN\n"
          "  --spec OUT>=X, OUT<=X  a bound on theta, rotor_speed (< 0 when driving), F_n,\n"
          "                      F_t, max_modulus or efficiency (repeatable)\n"
          "  --allow-driven      a sample the load drives backwards (power_out < 0) may be\n"
          "                      good (default: it is not, and is counted as driven)\n"
          "  --seed S            random seed (default 1; 0 to " USM_SEED_MAX_TEXT "); sample i\n"
          "                      depends only on (S, i)\n"
          "  --threads N         worker threads (default 2)\n"
          "  --out DIR           DIR/samples.csv, summary.md, histograms.csv (the figure's\n"
          "                      binned counts), histograms.png/svg (--force: write into an\n"
          "                      existing DIR)\n"
          "  --checkpoint FILE   keep completed blocks in FILE (under mpirun also FILE.R for\n"
          "                      rank R); the same command resumes, with any number of ranks\n",
          out);
    cli_quiet_usage(out);
    fputs("\nOutput: a Markdown summary; --json: {samples, seed, yield, yield_ci, quantiles,\n"
          "influence, failed, redrawn, exists, stable, good, operating_point, invalid,\n"
          "invalid_reasons, driven, timings: {compute, reduce, statistics, output (wall seconds),\n"
          "compute_cpu, output_cpu (CPU seconds)}};\n"
          "samples.csv ends with valid, invalid_reason.  Under mpirun the samples are shared\n"
          "out over the ranks and stay there (statistics by reductions, samples.csv written\n"
          "by every rank with MPI-IO), with the same output.\n"
          "exit status: 0 done, 1 numerical failure or write error, 2 bad input\n", out);
}

typedef struct tol_args {
    cli_common common;
    usm_tolerance_options opt;
    usm_tolerance_vary vary[USM_NPARAMS + 1];
    usm_tolerance_spec spec[64];
    int nvary, nspec, have_samples, force, quiet;
    const char *out;
} tol_args;

/* A whole number in [lo, hi]. */
static int parse_count(const char *field, const char *text, uint64_t lo, uint64_t hi,
                       uint64_t *v, char msg[CLI_MSG_LEN])
{
    char *end;
    errno = 0;
    unsigned long long x = strtoull(text, &end, 10);
    if (!(text[0] >= '0' && text[0] <= '9') || *end || errno || x < lo || x > hi) {
        cli_msg(msg, "%s: \"%s\" must be a whole number from %llu to %llu", field, text,
                (unsigned long long)lo, (unsigned long long)hi);
        return USM_EINPUT;
    }
    *v = x;
    return USM_OK;
}

static int own_option(tol_args *a, int argc, char **argv, int *i, char msg[CLI_MSG_LEN])
{
    const char *v = NULL;
    char lib[USM_MSG_LEN];
    uint64_t n = 0;
    int r = CLI_OPT_NOT_MINE, rc = USM_OK;
    /* each OPT is tried only while no earlier one took or refused the argument */
#define OPT(name) \
    (r == CLI_OPT_NOT_MINE && (r = cli_option_value(argc, argv, i, name, &v, msg)) == CLI_OPT_TAKEN)
    if (OPT("--samples") && (a->have_samples = 1))
        rc = parse_count("--samples", v, 1, USM_TOLERANCE_MAX_SAMPLES, &a->opt.samples, msg);
    else if (OPT("--seed"))
        rc = parse_count("--seed", v, 0, USM_SEED_MAX, &a->opt.seed, msg);
    else if (OPT("--threads") && (rc = parse_count("--threads", v, 1, 64, &n, msg)) == USM_OK)
        a->opt.threads = (int)n;
    else if (OPT("--vary")) {
        char vmsg[USM_IO_MSG_LEN];
        if (a->nvary > USM_NPARAMS)
            rc = USM_EINPUT, cli_msg(msg, "--vary too many");
        else if (usm_tolerance_vary_parse_units("--vary", v, &a->vary[a->nvary++], vmsg) !=
                 USM_OK)
            rc = USM_EINPUT, cli_msg(msg, "%.1000s", vmsg);
    } else if (OPT("--spec") && (a->nspec >= 64 ||
                               usm_tolerance_spec_parse(v, &a->spec[a->nspec++], lib) != USM_OK))
        rc = USM_EINPUT, cli_msg(msg, "--spec %s", a->nspec >= 64 ? "at most 64" : lib);
    else if (OPT("--out"))
        a->out = v;
    else if (OPT("--checkpoint"))
        a->opt.checkpoint = v;
#undef OPT
    if (r != CLI_OPT_TAKEN || rc != USM_OK)
        return rc != USM_OK ? CLI_OPT_ERROR : r;
    if (!v[0] && (v == a->out || v == a->opt.checkpoint))
        cli_msg(msg, "%s: empty file name", v == a->out ? "--out" : "--checkpoint");
    else
        return CLI_OPT_TAKEN;
    return CLI_OPT_ERROR;
}

static int init(void *p, char msg[CLI_MSG_LEN])
{
    tol_args *a = p;
    const char *stop = getenv("USM_TOLERANCE_STOP_AFTER_BLOCKS"); /* test hook, docs/tolerance.md */
    usm_tolerance_options_default(&a->opt);
    if (stop && stop[0] &&
        parse_count("USM_TOLERANCE_STOP_AFTER_BLOCKS", stop, 1, UINT64_MAX,
                    &a->opt.stop_after_blocks, msg))
        return USM_EINPUT;
    return USM_OK;
}

static int option(void *p, int argc, char **argv, int *i, char msg[CLI_MSG_LEN])
{
    tol_args *a = p;
    CLI_TRY(cli_flag_option(argv, i, "--force", &a->force));
    CLI_TRY(cli_flag_option(argv, i, "--allow-driven", &a->opt.allow_driven));
    CLI_TRY(cli_quiet_option(&a->quiet, argc, argv, i));
    CLI_TRY(cli_common_option(&a->common, argc, argv, i, msg));
    CLI_TRY(cli_floquet_option(&a->opt.floquet, argc, argv, i, msg));
    CLI_TRY(cli_from_rest_option(&a->opt.op, argc, argv, i, msg));
    return own_option(a, argc, argv, i, msg);
}

static int finish(void *p, char msg[CLI_MSG_LEN])
{
    tol_args *a = p;
    if (!a->have_samples || a->nvary == 0) {
        cli_msg(msg, "%s: required (see usm tolerance --help)", a->have_samples ? "--vary"
                                                                                : "--samples");
        return USM_EINPUT;
    }
    return cli_common_finish(&a->common, msg);
}

/* Under MPI, samples.csv is written by every rank (usm_tolerance_write_csv_mpi):
 * the ranks other than 0 call it here, rank 0 from write_file (or with NULL,
 * to let them go, when it gives up before). */
static int csv_mpi(const usm_tolerance *t, const char *path, char msg[CLI_MSG_LEN])
{
#ifdef USM_HAVE_MPI
    char why[USM_MSG_LEN];
    const int rc = usm_tolerance_write_csv_mpi(t, path, why);
    if (rc != USM_OK)
        cli_msg(msg, "--out %s", why);
    return rc;
#else
    (void)t, (void)path, (void)msg;
    return USM_EFAILED;
#endif
}

/* DIR/NAME written by `write`, whole or not at all (usm_io_create); USM_OK
 * or a status with msg.  mpi: samples.csv written by all ranks. */
enum { FILE_SAMPLES, FILE_SUMMARY, FILE_HISTOGRAMS };

static int write_file(const char *dir, const char *name, const usm_tolerance *t, int kind,
                      int force, int mpi, char msg[CLI_MSG_LEN])
{
    char path[4096], why[USM_IO_MSG_LEN];
    usm_io_file file;
    int status;
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = usm_io_create(&file, path, force, why, &status);
    if (mpi && kind == FILE_SAMPLES) {
        /* the temporary exists: the ranks write into it, rank 0 commits it */
        if (csv_mpi(t, f ? (file.tmp[0] ? file.tmp : file.path) : NULL, msg) != USM_OK) {
            if (f)
                usm_io_abort(&file);
            else
                cli_msg(msg, "--out %.900s", why);
            return f ? USM_EFAILED : status;
        }
    } else if (f && (kind == FILE_SUMMARY      ? usm_tolerance_write_summary(t, f, "histograms")
                     : kind == FILE_HISTOGRAMS ? usm_tolerance_write_histograms(t, f)
                                               : usm_tolerance_write_csv(t, f)) != 0) {
        usm_io_abort(&file);
        cli_msg(msg, "--out %s: write error", path);
        return USM_EFAILED;
    }
    if (!f || (status = usm_io_commit(&file, why)) != USM_OK) {
        cli_msg(msg, "--out %.900s", why);
        return status;
    }
    return USM_OK;
}

/* DIR: samples.csv, summary.md and histograms.csv written into a stage and renamed to DIR
 * together (a new or empty DIR appears whole or not at all; with --force
 * into a non-empty one, file by file, each whole); then the histograms. */
static int write_out(const tol_args *a, const usm_tolerance *t, int mpi, char msg[CLI_MSG_LEN])
{
    char prefix[4096], csv[4096], bins[4096], why[USM_IO_MSG_LEN];
    usm_io_dir dir;
    int rc = usm_io_dir_create(&dir, a->out, a->force, why);
    if (rc != USM_OK) {
        cli_msg(msg, "--out %.900s", why);
        if (mpi)
            csv_mpi(t, NULL, why); /* the other ranks wait for samples.csv */
        return rc;
    }
    rc = write_file(dir.work, "samples.csv", t, FILE_SAMPLES, a->force, mpi, msg);
    if (rc == USM_OK)
        rc = write_file(dir.work, "summary.md", t, FILE_SUMMARY, a->force, 0, msg);
    /* the figure's counts, binned by the library: gnuplot reads 40 rows, not
     * every sample (3.5 s of a 4.8 s run at 10^5 samples when it did) */
    if (rc == USM_OK)
        rc = write_file(dir.work, "histograms.csv", t, FILE_HISTOGRAMS, a->force, 0, msg);
    if (rc != USM_OK) {
        usm_io_dir_msg(&dir, msg); /* DIR/samples.csv, not the hidden stage's */
        usm_io_dir_abort(&dir);
        return rc;
    }
    if ((rc = usm_io_dir_commit(&dir, why)) != USM_OK) {
        cli_msg(msg, "--out %.900s", why);
        return rc;
    }
    snprintf(prefix, sizeof prefix, "%s/histograms", a->out);
    snprintf(csv, sizeof csv, "%s/samples.csv", a->out);
    snprintf(bins, sizeof bins, "%s/histograms.csv", a->out);
    /* the figure draws the bounds a sample is judged by: the tightest
     * --spec on rotor_speed each way, and on max_modulus (else 1) */
    char lo[32] = "", hi[32] = "", mod[32] = "1";
    double slo = -HUGE_VAL, shi = HUGE_VAL, mhi = 1.0;
    for (int j = 0; j < a->nspec; ++j) {
        const usm_tolerance_spec *s = &a->spec[j];
        if (s->output == USM_TOL_ROTOR_SPEED && s->upper && s->bound < shi)
            shi = s->bound, snprintf(hi, sizeof hi, "%.17g", s->bound);
        else if (s->output == USM_TOL_ROTOR_SPEED && !s->upper && s->bound > slo)
            slo = s->bound, snprintf(lo, sizeof lo, "%.17g", s->bound);
        else if (s->output == USM_TOL_MAX_MODULUS && s->upper && s->bound < mhi)
            mhi = s->bound, snprintf(mod, sizeof mod, "%.17g", s->bound);
    }
    const char *names[5] = {"csv", "bins", "modulus_hi"}, *values[5] = {csv, bins, mod};
    int n = 3;
    if (lo[0])
        names[n] = "speed_lo", values[n++] = lo;
    if (hi[0])
        names[n] = "speed_hi", values[n++] = hi;
    rc = usm_plot_render("tolerance", prefix, names, values, n, msg);
    if (rc == USM_ENOSOLUTION) /* no gnuplot: the data and script are there */
        cli_error("warning: %s", msg);
    return rc == USM_ENOSOLUTION ? USM_OK : rc;
}

/* Before the computation, alike on every rank: DIR new, empty (a killed
 * run's) or --force; not a symlink to nothing nor a file; its parent
 * writable. */
static int check_out(const tol_args *a, char msg[CLI_MSG_LEN])
{
    char why[USM_IO_MSG_LEN];
    if (usm_io_dir_check(a->out, a->force, why) == USM_OK)
        return USM_OK;
    cli_msg(msg, "--out %.900s", why);
    return USM_EINPUT;
}

static int run(void *p)
{
    tol_args *a = p;
    char msg[CLI_MSG_LEN];
    const int rank = a->common.rank, size = a->common.size;
    int status = USM_OK;
    usm_tolerance *t = NULL;
    usm_run *run = NULL;
    if (status == USM_OK && a->out)
        status = check_out(a, msg);
    if (status == USM_OK) {
        usm_tolerance_runner runner = NULL;
        cli_progress bar;
        /* under mpirun the ranks' shares are not one count to draw */
        cli_progress_init(&bar, "usm tolerance", a->quiet || size > 1);
        a->opt.progress = cli_progress_callback(&bar);
#ifdef USM_HAVE_MPI
        if (size > 1)
            runner = usm_tolerance_run_mpi;
#endif
        run = usm_run_tolerance(a->common.model, &a->common.params, a->vary, a->nvary, a->spec,
                                a->nspec, &a->opt, runner);
        cli_progress_end(&bar);
        t = usm_run_tolerance_result(run);
        status = usm_run_status(run);
        /* the library names its fields "vary", "spec" and "checkpoint"; the
         * command's options are --vary, --spec and --checkpoint */
        const char *lib = usm_run_message(run);
        const int option = (status == USM_EINPUT && (strncmp(lib, "vary ", 5) == 0 ||
                                                     strncmp(lib, "spec ", 5) == 0)) ||
                           strncmp(lib, "checkpoint ", 11) == 0;
        cli_msg(msg, "%s%s", option ? "--" : "", lib);
    }
    /* the files first: their time is in --json's timings.output */
    if (status == USM_OK && a->out) {
        const double t0 = clock_seconds(CLOCK_MONOTONIC);
        const double c0 = clock_seconds(CLOCK_PROCESS_CPUTIME_ID);
        if (rank == 0)
            status = write_out(a, t, size > 1, msg);
        else
            status = csv_mpi(t, NULL, msg);
        usm_tolerance_output_seconds_add(t, clock_seconds(CLOCK_MONOTONIC) - t0);
        usm_tolerance_output_cpu_seconds_add(t, clock_seconds(CLOCK_PROCESS_CPUTIME_ID) - c0);
    }
    if (status == USM_OK && rank == 0) {
        if ((a->common.json ? usm_run_write_json(run, stdout)
                           : usm_tolerance_write_summary(t, stdout, NULL)) != 0) {
            cli_msg(msg, "stdout: write error");
            status = USM_EFAILED;
        }
    }
    if (status != USM_OK && rank == 0)
        cli_error("%s", msg);
    usm_run_free(run);
    return status;
}

const cli_command cli_tolerance = {sizeof(tol_args), usage, init, option, finish, run, 1, 0};
