/* usm tolerance: Monte Carlo yield study (the library's usm_tolerance.h);
 * this file parses, calls and writes. */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <jansson.h>

#include "commands.h"
#include "json_out.h"
#include "options.h"
#include "plot_run.h"
#include "usm_tolerance.h"
#ifdef USM_HAVE_MPI
#include "mpi_run.h"
#endif

static void usage(FILE *out)
{
    fprintf(out,
            "usage: usm tolerance --samples N --vary NAME=DIST [--vary ...]\n"
            "                     [--spec OUTPUT>=X | --spec OUTPUT<=X]... [--seed S] [--threads N]\n"
            "                     [--model M] [--variant V] [--params F] [--set N=V]...\n"
            "                     [--out DIR [--force]] [--checkpoint FILE] [--json]\n\n"
            "Monte Carlo tolerance study: N parameter points drawn around the nominal design,\n"
            "at each the stationary solution and its Floquet multipliers; the yield (exists,\n"
            "stable, every spec met) with its 95 %% Wilson interval, quantiles and the Spearman\n"
            "rank correlation of each output with each varied parameter.\n\noptions:\n");
    cli_common_usage(out);
    cli_floquet_usage(out);
    fprintf(out,
            "  --samples N         number of samples (1 ... 1e9)\n"
            "  --vary NAME=DIST    DIST: normal:5%% (sigma relative to the nominal value),\n"
            "                      normal:0.01 (absolute sigma), uniform:2%% (relative\n"
            "                      half-width), uniform:LO:HI; repeatable\n"
            "  --spec OUT>=X, OUT<=X  a bound on theta, rotor_speed, F_n, F_t, max_modulus or\n"
            "                      efficiency (repeatable; rotor_speed < 0 when driving)\n"
            "  --seed S            random seed (default 1); sample i depends only on (S, i)\n"
            "  --threads N         worker threads (default 2)\n"
            "  --out DIR           write DIR/samples.csv, DIR/summary.md, DIR/histograms.png/svg\n"
            "  --force             write into an existing DIR\n"
            "  --checkpoint FILE   keep completed blocks in FILE; rerun to resume\n"
            "  -h, --help          print this help\n\n"
            "Output: summary (Markdown) on stdout; --json: {samples, seed, yield, yield_ci,\n"
            "quantiles, influence, failed, redrawn, exists, stable}.  Under mpirun the samples\n"
            "are shared out over the ranks; the output is the same.\n\n"
            "exit status: 0 done, 1 numerical failure or write error, 2 bad input\n");
}

typedef struct tol_args {
    cli_common common;
    usm_tolerance_options opt;
    usm_tolerance_vary vary[USM_NPARAMS + 1];
    usm_tolerance_spec spec[64];
    int nvary, nspec, have_samples, force, help;
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

static int option(tol_args *a, int argc, char **argv, int *i, char msg[CLI_MSG_LEN])
{
    const char *v;
    char lib[USM_MSG_LEN];
    uint64_t n;
    int r;
#define OPT(name) ((r = cli_option_value(argc, argv, i, name, &v, msg)) == CLI_OPT_TAKEN)
    if (OPT("--samples")) {
        a->have_samples = 1;
        return parse_count("--samples", v, 1, USM_TOLERANCE_MAX_SAMPLES, &a->opt.samples, msg);
    } else if (r == CLI_OPT_NOT_MINE && OPT("--seed")) {
        return parse_count("--seed", v, 0, UINT64_MAX, &a->opt.seed, msg);
    } else if (r == CLI_OPT_NOT_MINE && OPT("--threads")) {
        r = parse_count("--threads", v, 1, 64, &n, msg);
        a->opt.threads = (int)n;
        return r;
    } else if (r == CLI_OPT_NOT_MINE && OPT("--vary")) {
        if (a->nvary > USM_NPARAMS || usm_tolerance_vary_parse(v, &a->vary[a->nvary++], lib)) {
            cli_msg(msg, "--vary %s", a->nvary > USM_NPARAMS ? "too many" : lib);
            return USM_EINPUT;
        }
    } else if (r == CLI_OPT_NOT_MINE && OPT("--spec")) {
        if (a->nspec >= 64 || usm_tolerance_spec_parse(v, &a->spec[a->nspec++], lib)) {
            cli_msg(msg, "--spec %s", a->nspec >= 64 ? "at most 64" : lib);
            return USM_EINPUT;
        }
    } else if (r == CLI_OPT_NOT_MINE && OPT("--out")) {
        a->out = v;
    } else if (r == CLI_OPT_NOT_MINE && OPT("--checkpoint")) {
        a->opt.checkpoint = v;
    }
#undef OPT
    if (r == CLI_OPT_ERROR)
        return USM_EINPUT;
    if (r == CLI_OPT_NOT_MINE) {
        cli_msg(msg, "%s: %s (see usm tolerance --help)", argv[*i],
                argv[*i][0] == '-' ? "unknown option" : "unexpected argument");
        return USM_EINPUT;
    }
    if ((a->out && !a->out[0]) || (a->opt.checkpoint && !a->opt.checkpoint[0])) {
        cli_msg(msg, "%s: empty file name", a->out && !a->out[0] ? "--out" : "--checkpoint");
        return USM_EINPUT;
    }
    return USM_OK;
}

static int parse(tol_args *a, int argc, char **argv, char msg[CLI_MSG_LEN])
{
    const char *stop = getenv("USM_TOLERANCE_STOP_AFTER_BLOCKS"); /* test hook, docs/tolerance.md */
    memset(a, 0, sizeof *a);
    cli_common_init(&a->common);
    usm_tolerance_options_default(&a->opt);
    if (stop && stop[0] &&
        parse_count("USM_TOLERANCE_STOP_AFTER_BLOCKS", stop, 1, UINT64_MAX,
                    &a->opt.stop_after_blocks, msg))
        return USM_EINPUT;
    for (int i = 1; i < argc; ++i) {
        int r;
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            a->help = 1;
            return USM_OK;
        }
        if (strcmp(argv[i], "--force") == 0) {
            a->force = 1;
            continue;
        }
        if ((r = cli_common_option(&a->common, argc, argv, &i, msg)) == CLI_OPT_NOT_MINE &&
            (r = cli_floquet_option(&a->opt.floquet, argc, argv, &i, msg)) == CLI_OPT_NOT_MINE)
            r = option(a, argc, argv, &i, msg) == USM_OK ? CLI_OPT_TAKEN : CLI_OPT_ERROR;
        if (r == CLI_OPT_ERROR)
            return USM_EINPUT;
    }
    if (!a->have_samples || a->nvary == 0) {
        cli_msg(msg, "%s: required (see usm tolerance --help)", a->have_samples ? "--vary"
                                                                                : "--samples");
        return USM_EINPUT;
    }
    return cli_common_finish(&a->common, msg);
}

static json_t *result_json(const usm_tolerance *t)
{
    const usm_tolerance_summary *s = usm_tolerance_result(t);
    static const char *const qk[5] = {"p1", "p5", "p50", "p95", "p99"};
    json_t *o = json_object(), *q = json_object(), *inf = json_object();
    int ok = o && q && inf;
    cli_json_put(o, "samples", json_integer((json_int_t)s->samples), &ok);
    cli_json_put(o, "seed", json_integer((json_int_t)s->seed), &ok);
    cli_json_put(o, "yield", cli_json_real(s->yield), &ok);
    cli_json_put(o, "yield_ci", json_pack("[ff]", s->yield_lo, s->yield_hi), &ok);
    for (int k = 0; k < USM_TOL_NNUMERIC; ++k) {
        json_t *qo = json_object(), *io = json_object();
        cli_json_put(qo, "count", json_integer((json_int_t)s->count[k]), &ok);
        for (int l = 0; l < 5; ++l)
            cli_json_put(qo, qk[l], cli_json_real(s->quantile[k][l]), &ok);
        for (int j = 0; j < usm_tolerance_vary_count(t); ++j)
            cli_json_put(io, usm_tolerance_vary_at(t, j)->param->name,
                         cli_json_real(usm_tolerance_influence(t, k, j)), &ok);
        cli_json_put(q, usm_tolerance_output_name(k), qo, &ok);
        cli_json_put(inf, usm_tolerance_output_name(k), io, &ok);
    }
    cli_json_put(o, "quantiles", q, &ok);
    cli_json_put(o, "influence", inf, &ok);
    cli_json_put(o, "failed", json_integer((json_int_t)s->failed), &ok);
    cli_json_put(o, "redrawn", json_integer((json_int_t)s->redrawn), &ok);
    cli_json_put(o, "exists", json_integer((json_int_t)s->exists), &ok);
    cli_json_put(o, "stable", json_integer((json_int_t)s->stable), &ok);
    if (!ok)
        json_decref(o);
    return ok ? o : NULL;
}

/* DIR/NAME written by `write`; USM_OK or USM_EFAILED with msg. */
static int write_file(const char *dir, const char *name, const usm_tolerance *t, int summary,
                      char msg[CLI_MSG_LEN])
{
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "w");
    int bad = !f || (summary ? usm_tolerance_write_summary(t, f, "histograms")
                             : usm_tolerance_write_csv(t, f)) != 0;
    if (!f || (fclose(f) != 0) | bad) {
        cli_msg(msg, "--out %s: write error%s%s", path, f ? "" : ": ", f ? "" : strerror(errno));
        return USM_EFAILED;
    }
    return USM_OK;
}

static int write_out(const tol_args *a, const usm_tolerance *t, char msg[CLI_MSG_LEN])
{
    char prefix[4096], csv[4096];
    int rc = write_file(a->out, "samples.csv", t, 0, msg);
    if (rc == USM_OK)
        rc = write_file(a->out, "summary.md", t, 1, msg);
    if (rc != USM_OK)
        return rc;
    snprintf(prefix, sizeof prefix, "%s/histograms", a->out);
    snprintf(csv, sizeof csv, "%s/samples.csv", a->out);
    const char *names[] = {"csv"}, *values[] = {csv};
    rc = cli_plot_render("tolerance", prefix, names, values, 1, msg);
    if (rc == USM_ENOSOLUTION) /* no gnuplot: the data and script are there */
        cli_error("warning: %s", msg);
    return rc == USM_ENOSOLUTION ? USM_OK : rc;
}

int cli_tolerance_main(int argc, char **argv)
{
    tol_args a;
    char msg[CLI_MSG_LEN];
    int rank = 0, size = 1, status;
    usm_tolerance *t = NULL;
    (void)size;
#ifdef USM_HAVE_MPI
    if (usm_mpi_launched() && usm_mpi_start(&rank, &size, msg) != USM_OK) {
        cli_error("mpi: %s", msg);
        return USM_EFAILED;
    }
#endif
    if ((status = parse(&a, argc, argv, msg)) == USM_OK && a.help) {
        if (rank == 0)
            usage(stdout);
        return USM_OK;
    }
    if (status == USM_OK && a.out && rank == 0 && mkdir(a.out, 0777) != 0 &&
        !(errno == EEXIST && a.force)) {
        cli_msg(msg, "--out %s: %s", a.out, errno == EEXIST ? "exists (use --force to write "
                "into it)" : strerror(errno));
        status = USM_EINPUT;
    }
    if (status == USM_OK && !(t = usm_tolerance_alloc(a.common.model))) {
        cli_msg(msg, "out of memory");
        status = USM_EFAILED;
    }
    for (int j = 0; status == USM_OK && j < a.nvary + a.nspec; ++j)
        if ((j < a.nvary ? usm_tolerance_vary_add(t, &a.vary[j])
                         : usm_tolerance_spec_add(t, &a.spec[j - a.nvary])) != USM_OK) {
            cli_msg(msg, "--%s %s", j < a.nvary ? "vary" : "spec", usm_tolerance_message(t));
            status = USM_EINPUT;
        }
    if (status == USM_OK) {
#ifdef USM_HAVE_MPI
        if (size > 1)
            status = usm_tolerance_run_mpi(t, &a.common.params, &a.opt);
        else
#endif
            status = usm_tolerance_run(t, &a.common.params, &a.opt);
        if (status != USM_OK)
            cli_msg(msg, "%s", usm_tolerance_message(t));
    }
    if (status == USM_OK && rank == 0) {
        json_t *o = a.common.json ? result_json(t) : NULL;
        if (a.common.json ? !o || cli_json_print(o, stdout) != 0
                          : usm_tolerance_write_summary(t, stdout, NULL) != 0) {
            cli_msg(msg, "stdout: write error");
            status = USM_EFAILED;
        }
        json_decref(o);
        if (status == USM_OK && a.out)
            status = write_out(&a, t, msg);
    }
    if (status != USM_OK && rank == 0)
        cli_error("%s", msg);
    usm_tolerance_free(t);
    return status;
}
