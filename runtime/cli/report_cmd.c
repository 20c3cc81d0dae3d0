/* usm report: the paper reproduced in DIR/report.md, with figures. */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>

#include "commands.h"
#include "data_dir.h"
#include "diag.h"
#include "options.h"
#include "report.h"
#include "template.h"
#include "usm.h"

static void usage(FILE *out)
{
    fprintf(out,
            "usage: usm report --out DIR [--quick] [--force] [--no-plots] [--threads N]\n"
            "                  [--params FILE.json] [--set NAME=VALUE]...\n"
            "\n"
            "Reproduce the paper: compute the stationary solutions, Floquet multipliers,\n"
            "motor characteristics (speed vs f, T, m0) and stability maps of both models and\n"
            "write DIR/report.md: every published number beside the computed one, the\n"
            "reasons where they differ, and the figures (PNG and SVG, drawn by gnuplot from\n"
            "CSV data and scripts written into DIR as well).\n"
            "\n"
            "options:\n"
            "  --out DIR           output directory (created if missing)\n"
            "  --quick             coarser grids (a few seconds; for tests)\n"
            "  --force             overwrite DIR/report.md and the report's files even if\n"
            "                      they were not written by usm report.  Without it a report\n"
            "                      that usm wrote is replaced, anything else is kept\n"
            "  --no-plots          write data and gnuplot scripts but do not run gnuplot\n"
            "  --threads N         worker threads (default 2)\n"
            "  --params FILE.json  parameter values (default: the paper's)\n"
            "  --set NAME=VALUE    set one parameter (repeatable; applied after --params)\n"
            "  -h, --help          print this help\n"
            "\n"
            "gnuplot is taken from $USM_GNUPLOT, else \"gnuplot\" on the PATH.\n"
            "On success prints the path of report.md.\n"
            "exit status: 0 written, 1 numerical failure or figures not rendered (the\n"
            "             report is still written), 2 bad input or DIR not usable,\n"
            "             3 no stationary solution at the chosen parameters\n");
}

typedef struct report_args {
    cli_common common;
    const char *out;
    int quick, force, plots, threads, help;
} report_args;

static int parse(report_args *a, int argc, char **argv, char msg[CLI_MSG_LEN])
{
    memset(a, 0, sizeof *a);
    cli_common_init(&a->common);
    a->plots = 1;
    a->threads = 2;
    for (int i = 1; i < argc; ++i) {
        const char *value;
        int r;
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            a->help = 1;
            return USM_OK;
        }
        if (strcmp(argv[i], "--quick") == 0) {
            a->quick = 1;
            continue;
        }
        if (strcmp(argv[i], "--force") == 0) {
            a->force = 1;
            continue;
        }
        if (strcmp(argv[i], "--no-plots") == 0) {
            a->plots = 0;
            continue;
        }
        {
            /* The report always covers the paper's two models; --json has no
             * meaning for a directory of files. */
            static const char *const not_here[] = {"--json", "--model", "--variant"};
            for (size_t k = 0; k < sizeof not_here / sizeof not_here[0]; ++k) {
                size_t len = strlen(not_here[k]);
                if (strncmp(argv[i], not_here[k], len) == 0 &&
                    (argv[i][len] == '\0' || argv[i][len] == '=')) {
                    cli_msg(msg, "%s: not an option of usm report (it covers the paper's 3dof "
                                 "and 4dof models; see usm report --help)", not_here[k]);
                    return USM_EINPUT;
                }
            }
        }
        if ((r = cli_common_option(&a->common, argc, argv, &i, msg)) == CLI_OPT_TAKEN)
            continue;
        if (r == CLI_OPT_ERROR)
            return USM_EINPUT;
        if ((r = cli_option_value(argc, argv, &i, "--out", &value, msg)) != CLI_OPT_NOT_MINE) {
            if (r == CLI_OPT_ERROR)
                return USM_EINPUT;
            if (value[0] == '\0') {
                cli_msg(msg, "--out: empty directory name");
                return USM_EINPUT;
            }
            a->out = value;
            continue;
        }
        if ((r = cli_option_value(argc, argv, &i, "--threads", &value, msg)) != CLI_OPT_NOT_MINE) {
            double v;
            if (r == CLI_OPT_ERROR || cli_parse_double("--threads", value, &v, msg) != USM_OK)
                return USM_EINPUT;
            if (v != (double)(int)v || v < 1 || v > 64) {
                cli_msg(msg, "--threads: \"%s\" must be an integer from 1 to 64", value);
                return USM_EINPUT;
            }
            a->threads = (int)v;
            continue;
        }
        if (argv[i][0] == '-')
            cli_msg(msg, "%s: unknown option (see usm report --help)", argv[i]);
        else
            cli_msg(msg, "%s: unexpected argument (see usm report --help)", argv[i]);
        return USM_EINPUT;
    }
    if (!a->out) {
        cli_msg(msg, "--out: missing, the output directory is required");
        return USM_EINPUT;
    }
    return cli_common_finish(&a->common, msg);
}

/* mkdir -p */
static int make_dir(const char *dir, char msg[CLI_MSG_LEN])
{
    char path[4096];
    struct stat st;
    size_t len = strlen(dir);
    if (len >= sizeof path) {
        cli_msg(msg, "--out %s: path too long", dir);
        return USM_EINPUT;
    }
    memcpy(path, dir, len + 1);
    for (size_t i = 1; i <= len; ++i) {
        if (path[i] != '/' && path[i] != '\0')
            continue;
        char c = path[i];
        path[i] = '\0';
        if (mkdir(path, 0777) != 0 && errno != EEXIST) {
            cli_msg(msg, "--out %s: cannot create %s: %s", dir, path, strerror(errno));
            return USM_EINPUT;
        }
        path[i] = c;
    }
    if (stat(dir, &st) != 0 || !S_ISDIR(st.st_mode)) {
        cli_msg(msg, "--out %s: not a directory", dir);
        return USM_EINPUT;
    }
    return USM_OK;
}

/* 1 when the file at path starts with the line `marker`. */
static int starts_with_line(const char *path, const char *marker)
{
    char line[512];
    FILE *f = fopen(path, "r");
    int own = 0;
    if (!f)
        return 0;
    if (fgets(line, sizeof line, f)) {
        line[strcspn(line, "\r\n")] = '\0';
        own = strcmp(line, marker) == 0;
    }
    fclose(f);
    return own;
}

/* DIR/.usm-report, written before any other file of the report. */
static int write_manifest(const char *dir, char msg[CLI_MSG_LEN])
{
    FILE *f = report_open(dir, REPORT_MANIFEST, msg);
    if (!f)
        return USM_EINPUT;
    fprintf(f, "%s\n", REPORT_MANIFEST_MARKER);
    for (int k = 0; report_files[k]; ++k)
        fprintf(f, "%s\n", report_files[k]);
    return report_close(f, dir, REPORT_MANIFEST, msg) == USM_OK ? USM_OK : USM_EINPUT;
}

/* Refuse to overwrite files usm did not write (see --force). */
static int check_dir(const char *dir, int force, char msg[CLI_MSG_LEN])
{
    char path[4096];
    struct stat st;
    if (stat(dir, &st) != 0) {
        if (errno == ENOENT)
            return USM_OK; /* created later */
        cli_msg(msg, "--out %s: %s", dir, strerror(errno));
        return USM_EINPUT;
    }
    if (!S_ISDIR(st.st_mode)) {
        cli_msg(msg, "--out %s: exists and is not a directory", dir);
        return USM_EINPUT;
    }
    if (access(dir, W_OK) != 0) {
        cli_msg(msg, "--out %s: not writable", dir);
        return USM_EINPUT;
    }
    if (force)
        return USM_OK;
    if (report_path(path, sizeof path, dir, "report.md") != 0) {
        cli_msg(msg, "--out %s: path too long", dir);
        return USM_EINPUT;
    }
    if (access(path, F_OK) == 0) {
        if (starts_with_line(path, REPORT_MARKER))
            return USM_OK;
        cli_msg(msg, "--out %s: report.md there was not written by usm report; not "
                     "overwriting it (use --force, or another directory)", dir);
        return USM_EINPUT;
    }
    /* no report.md: a run that was interrupted left its manifest */
    if (report_path(path, sizeof path, dir, REPORT_MANIFEST) == 0 &&
        starts_with_line(path, REPORT_MANIFEST_MARKER))
        return USM_OK;
    for (int k = 0; report_files[k]; ++k) {
        if (report_path(path, sizeof path, dir, report_files[k]) != 0) {
            cli_msg(msg, "--out %s: path too long", dir);
            return USM_EINPUT;
        }
        if (access(path, F_OK) == 0) {
            cli_msg(msg, "--out %s: %s exists and no usm report is there; not overwriting it "
                         "(use --force, or another directory)", dir, report_files[k]);
            return USM_EINPUT;
        }
    }
    return USM_OK;
}

/* report.md's text: data/report/report.md.in rendered with data (free() it). */
static char *render_md(json_t *data, char msg[CLI_MSG_LEN])
{
    char path[4096], *tpl, *md = NULL;
    size_t len = 0;
    FILE *f;
    int st;
    if (cli_data_path("report/report.md.in", path, sizeof path) != 0) {
        cli_msg(msg, "%s: the report's template is not installed (set USM_DATA_DIR)", path);
        return NULL;
    }
    if (!(tpl = cli_template_read(path, msg)))
        return NULL;
    if (!(f = open_memstream(&md, &len))) {
        cli_msg(msg, "out of memory");
        free(tpl);
        return NULL;
    }
    st = cli_template_render(tpl, path, data, f, msg);
    free(tpl);
    if (fclose(f) != 0 || st != USM_OK) {
        if (st == USM_OK)
            cli_msg(msg, "out of memory");
        free(md);
        return NULL;
    }
    return md;
}

/* DIR/name through a temporary file, renamed when complete: report.json
 * (data), report.html (md as HTML) or report.md (md). */
static int write_output(json_t *data, const char *md, const char *dir, const char *name,
                        char msg[CLI_MSG_LEN])
{
    char tmp[4096], path[4096];
    FILE *f;
    int fd, bad;
    if (report_path(path, sizeof path, dir, name) != 0 ||
        report_path(tmp, sizeof tmp, dir, ".report.XXXXXX") != 0) {
        cli_msg(msg, "--out %s: path too long", dir);
        return USM_EFAILED;
    }
    if ((fd = mkstemp(tmp)) < 0 || !(f = fdopen(fd, "w"))) {
        cli_msg(msg, "%s: %s", tmp, strerror(errno));
        if (fd >= 0) {
            close(fd);
            unlink(tmp);
        }
        return USM_EFAILED;
    }
    fchmod(fd, 0644);
    if (strcmp(name, "report.json") == 0)
        bad = json_dumpf(data, f, JSON_INDENT(2) | JSON_REAL_PRECISION(17)) != 0 ||
              fputc('\n', f) == EOF;
    else if (strcmp(name, "report.html") == 0)
        bad = report_html_write(md, dir, f) != 0;
    else
        bad = fputs(md, f) == EOF;
    if (ferror(f) | (fclose(f) != 0) | bad) {
        cli_msg(msg, "%s: write error", path);
        unlink(tmp);
        return USM_EFAILED;
    }
    if (rename(tmp, path) != 0) {
        cli_msg(msg, "%s: %s", path, strerror(errno));
        unlink(tmp);
        return USM_EFAILED;
    }
    return USM_OK;
}

int cli_report_main(int argc, char **argv)
{
    report_args a;
    report_data *d;
    char msg[CLI_MSG_LEN], plot_note[CLI_MSG_LEN] = "";
    int status, plots_ok = 0;
    double t;

    if (parse(&a, argc, argv, msg) != USM_OK) {
        cli_error("%s", msg);
        return USM_EINPUT;
    }
    if (a.help) {
        usage(stdout);
        return USM_OK;
    }
    if (check_dir(a.out, a.force, msg) != USM_OK || make_dir(a.out, msg) != USM_OK ||
        write_manifest(a.out, msg) != USM_OK) {
        cli_error("%s", msg);
        return USM_EINPUT;
    }
    if (report_paper_load(msg) != USM_OK) {
        cli_error("%s", msg);
        return USM_EFAILED;
    }
    if (!(d = calloc(1, sizeof *d))) {
        cli_error("out of memory");
        return USM_EFAILED;
    }
    d->params = a.common.params;
    d->opt.quick = a.quick;
    d->opt.threads = a.threads;
    d->opt.plots = a.plots;
    status = report_compute(d, msg);
    if (status == USM_OK)
        status = report_compute_maps(d, msg);
    if (status == USM_OK)
        status = report_write_data(d, a.out, msg);
    if (status != USM_OK) {
        cli_error("%s", msg);
        report_data_free(d);
        free(d);
        return status == USM_EINPUT || status == USM_ENOSOLUTION ? status : USM_EFAILED;
    }
    t = report_now();
    if (a.plots) {
        if (report_run_gnuplot(a.out, a.threads, plot_note) == USM_OK)
            plots_ok = 1;
    }
    d->seconds[3] = report_now() - t;
    d->opt.plots = plots_ok; /* the report links figures only when they exist */
    {
        /* report.md last: its marker says a complete report is there */
        static const char *const outputs[] = {"report.json", "report.html", "report.md"};
        json_t *data = report_json(d, plots_ok || !a.plots, plot_note);
        char *md = data ? render_md(data, msg) : NULL;
        status = md ? USM_OK : USM_EFAILED;
        if (!data)
            cli_msg(msg, "out of memory");
        for (size_t k = 0; status == USM_OK && k < sizeof outputs / sizeof outputs[0]; ++k)
            status = write_output(data, md, a.out, outputs[k], msg);
        free(md);
        json_decref(data);
    }
    report_data_free(d);
    free(d);
    if (status != USM_OK) {
        cli_error("%s", msg);
        return USM_EFAILED;
    }
    if (a.plots && !plots_ok) {
        cli_error("%s", plot_note);
        return USM_EFAILED;
    }
    printf("%s/report.md\n", a.out);
    return USM_OK;
}
