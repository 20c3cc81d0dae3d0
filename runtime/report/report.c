/* The report into a directory (usm_report.h): the directory's guard, the
 * computation (report_compute.c, report_map.c), the data files and figures
 * (report_plot.c), report.json (report_json.c), report.md from its template
 * (template.c) and report.html (report_html.c). */
#define _POSIX_C_SOURCE 200809L

#include "usm_report.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>

#include "io/data_dir.h"
#include "io/io_msg.h"
#include "io/json_out.h"
#include "report_dir.h"
#include "report_internal.h"
#include "io/template.h"

void usm_report_options_default(usm_report_options *opt)
{
    opt->quick = 0;
    opt->threads = 2;
    opt->plots = 1;
    opt->force = 0;
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
static int write_manifest(const char *dir, char msg[USM_IO_MSG_LEN])
{
    FILE *f = usm_report_open(dir, REPORT_MANIFEST, msg);
    if (!f)
        return USM_EINPUT;
    fprintf(f, "%s\n", REPORT_MANIFEST_MARKER);
    for (int k = 0; usm_report_files[k]; ++k)
        fprintf(f, "%s\n", usm_report_files[k]);
    return usm_report_close(f, dir, REPORT_MANIFEST, msg) == USM_OK ? USM_OK : USM_EINPUT;
}

/* Refuse to overwrite files usm did not write (see --force). */
static int check_dir(const char *dir, int force, char msg[USM_IO_MSG_LEN])
{
    char path[4096];
    struct stat st;
    if (stat(dir, &st) != 0) {
        if (errno == ENOENT)
            return USM_OK; /* created later */
        usm_io_msg(msg, "%s: %s", dir, strerror(errno));
        return USM_EINPUT;
    }
    if (!S_ISDIR(st.st_mode)) {
        usm_io_msg(msg, "%s: exists and is not a directory", dir);
        return USM_EINPUT;
    }
    if (access(dir, W_OK) != 0) {
        usm_io_msg(msg, "%s: not writable", dir);
        return USM_EINPUT;
    }
    if (force)
        return USM_OK;
    if (usm_report_path(path, sizeof path, dir, "report.md") != 0) {
        usm_io_msg(msg, "%s: path too long", dir);
        return USM_EINPUT;
    }
    if (access(path, F_OK) == 0) {
        if (starts_with_line(path, REPORT_MARKER))
            return USM_OK;
        usm_io_msg(msg, "%s: report.md there was not written by usm report; not "
                     "overwriting it (use --force, or another directory)", dir);
        return USM_EINPUT;
    }
    /* no report.md: a run that was interrupted left its manifest */
    if (usm_report_path(path, sizeof path, dir, REPORT_MANIFEST) == 0 &&
        starts_with_line(path, REPORT_MANIFEST_MARKER))
        return USM_OK;
    for (int k = 0; usm_report_files[k]; ++k) {
        if (usm_report_path(path, sizeof path, dir, usm_report_files[k]) != 0) {
            usm_io_msg(msg, "%s: path too long", dir);
            return USM_EINPUT;
        }
        if (access(path, F_OK) == 0) {
            usm_io_msg(msg, "%s: %s exists and no usm report is there; not overwriting it "
                         "(use --force, or another directory)", dir, usm_report_files[k]);
            return USM_EINPUT;
        }
    }
    return USM_OK;
}

/* report.md's text: data/report/report.md.in rendered with data (free() it). */
static char *render_md(json_t *data, char msg[USM_IO_MSG_LEN])
{
    char path[4096], *tpl, *md = NULL;
    size_t len = 0;
    FILE *f;
    int st;
    if (usm_data_path("report/report.md.in", path, sizeof path) != 0) {
        usm_io_msg(msg, "%s: the report's template is not installed (set USM_DATA_DIR)", path);
        return NULL;
    }
    if (!(tpl = usm_template_read(path, msg)))
        return NULL;
    if (!(f = open_memstream(&md, &len))) {
        usm_io_msg(msg, "out of memory");
        free(tpl);
        return NULL;
    }
    st = usm_template_render(tpl, path, data, f, msg);
    free(tpl);
    if (fclose(f) != 0 || st != USM_OK) {
        if (st == USM_OK)
            usm_io_msg(msg, "out of memory");
        free(md);
        return NULL;
    }
    return md;
}

/* DIR/name through a temporary file, renamed when complete: report.json
 * (data), report.html (md as HTML) or report.md (md). */
static int write_output(json_t *data, const char *md, const char *dir, const char *name,
                        char msg[USM_IO_MSG_LEN])
{
    char tmp[4096], path[4096];
    FILE *f;
    int fd, bad;
    if (usm_report_path(path, sizeof path, dir, name) != 0 ||
        usm_report_path(tmp, sizeof tmp, dir, ".report.XXXXXX") != 0) {
        usm_io_msg(msg, "%s: path too long", dir);
        return USM_EFAILED;
    }
    if ((fd = mkstemp(tmp)) < 0 || !(f = fdopen(fd, "w"))) {
        usm_io_msg(msg, "%s: %s", tmp, strerror(errno));
        if (fd >= 0) {
            close(fd);
            unlink(tmp);
        }
        return USM_EFAILED;
    }
    fchmod(fd, 0644);
    if (strcmp(name, "report.json") == 0)
        bad = usm_json_dumpf(data, f, JSON_INDENT(2)) != 0 ||
              fputc('\n', f) == EOF;
    else if (strcmp(name, "report.html") == 0)
        bad = usm_report_html_write(md, dir, f) != 0;
    else
        bad = fputs(md, f) == EOF;
    if (ferror(f) | (fclose(f) != 0) | bad) {
        usm_io_msg(msg, "%s: write error", path);
        unlink(tmp);
        return USM_EFAILED;
    }
    if (rename(tmp, path) != 0) {
        usm_io_msg(msg, "%s: %s", path, strerror(errno));
        unlink(tmp);
        return USM_EFAILED;
    }
    return USM_OK;
}

int usm_report_options_check(const usm_report_options *opt, char msg[USM_IO_MSG_LEN])
{
    if (!(opt->threads >= 1 && opt->threads <= 64)) {
        usm_io_msg(msg, "threads: %d: must be an integer from 1 to 64", opt->threads);
        return USM_EINPUT;
    }
    return USM_OK;
}

int usm_report_prepare_dir(const char *dir, const usm_report_options *opt,
                           char msg[USM_IO_MSG_LEN])
{
    if (usm_report_options_check(opt, msg) != USM_OK)
        return USM_EINPUT;
    return check_dir(dir, opt->force, msg);
}

/* Every occurrence of path `from` in msg replaced by `to` (messages name the
 * final directory, not the staging one). */
static void replace_path(char msg[USM_IO_MSG_LEN], const char *from, const char *to)
{
    char out[USM_IO_MSG_LEN];
    size_t n = 0, flen = strlen(from), tlen = strlen(to);
    const char *s = msg;
    if (flen == 0)
        return;
    while (*s && n + 1 < sizeof out) {
        if (strncmp(s, from, flen) == 0 && n + tlen < sizeof out) {
            memcpy(out + n, to, tlen);
            n += tlen;
            s += flen;
        } else {
            out[n++] = *s++;
        }
    }
    out[n] = '\0';
    memcpy(msg, out, n + 1);
}

/* The report into the staging directory dir (usm_report_write).  *written
 * is set once the outputs are there, so that the report is published even
 * when only its figures failed. */
static int write_into(const char *dir, const char *final_dir, const usm_params *p,
                      const usm_report_options *opt, int *written, char msg[USM_IO_MSG_LEN])
{
    usm_report_data *d;
    char plot_note[USM_IO_MSG_LEN] = "";
    int status, plots_ok = 0;
    double t;

    *written = 0;
    if (write_manifest(dir, msg) != USM_OK)
        return USM_EFAILED;
    if (!(d = calloc(1, sizeof *d))) {
        usm_io_msg(msg, "out of memory");
        return USM_EFAILED;
    }
    if (usm_report_paper_load(&d->paper, msg) != USM_OK) {
        free(d);
        return USM_EFAILED;
    }
    d->params = *p;
    d->opt = *opt;
    status = usm_report_compute(d, msg);
    if (status == USM_OK)
        status = usm_report_compute_maps(d, msg);
    if (status == USM_OK)
        status = usm_report_compute_nonideal(d, msg);
    if (status == USM_OK)
        status = usm_report_write_data(d, dir, msg);
    if (status != USM_OK) {
        usm_report_data_free(d);
        free(d);
        return status == USM_EINPUT || status == USM_ENOSOLUTION ? status : USM_EFAILED;
    }
    t = usm_report_now();
    if (opt->plots && usm_report_run_gnuplot(dir, opt->threads, usm_report_figure_count(d),
                                          plot_note) == USM_OK)
        plots_ok = 1;
    d->seconds[3] = usm_report_now() - t;
    if (final_dir)
        replace_path(plot_note, dir, final_dir); /* the note is read after publishing */
    d->opt.plots = plots_ok; /* the report links figures only when they exist */
    {
        /* report.md last: its marker says a complete report is there */
        static const char *const outputs[] = {"report.json", "report.html", "report.md"};
        json_t *data = usm_report_json(d, plots_ok || !opt->plots, plot_note);
        char *md = NULL;
        /* report.json before the rendering: when the template fails, the
         * values it was given are there to see */
        status = data ? write_output(data, NULL, dir, outputs[0], msg) : USM_EFAILED;
        if (!data)
            usm_io_msg(msg, "out of memory");
        if (status == USM_OK && !(md = render_md(data, msg)))
            status = USM_EFAILED;
        for (size_t k = 1; status == USM_OK && k < sizeof outputs / sizeof outputs[0]; ++k)
            status = write_output(data, md, dir, outputs[k], msg);
        free(md);
        json_decref(data);
    }
    usm_report_data_free(d);
    free(d);
    if (status != USM_OK)
        return USM_EFAILED;
    *written = 1;
    if (opt->plots && !plots_ok) {
        usm_io_msg(msg, "%s", plot_note);
        return USM_EFAILED;
    }
    return USM_OK;
}

int usm_report_write(const char *dir, const usm_params *p, const usm_report_options *opt,
                     char msg[USM_IO_MSG_LEN])
{
    usm_report_stage st;
    int status, written;
    if (usm_report_options_check(opt, msg) != USM_OK)
        return USM_EINPUT;
    if (usm_report_stage_begin(&st, dir, msg) != USM_OK)
        return USM_EINPUT;
    status = write_into(st.stage, dir, p, opt, &written, msg);
    replace_path(msg, st.stage, dir);
    if (written) {
        char pmsg[USM_IO_MSG_LEN];
        if (usm_report_stage_publish(&st, pmsg) != USM_OK) {
            usm_io_msg(msg, "%s", pmsg);
            status = USM_EFAILED;
        }
    }
    usm_report_stage_end(&st);
    return status;
}
