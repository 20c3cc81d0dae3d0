/* The report into a directory (usm_report.h): the directory's guard, the
 * computation (report_compute.c, report_map.c), the data files and figures
 * (report_plot.c), report.json (report_json.c), report.md from its template
 * (template.c) and report.html (report_html.c).
 *
 * A report directory is replaced as a whole: the new report is written into
 * a stage beside it (PARENT/.NAME.usm-new-PID), and only when complete the
 * stage and DIR are exchanged (renameat2 RENAME_EXCHANGE, one step) and the
 * old report removed, so that no interruption mixes two runs: a reader sees
 * the old report or the new one.  A DIR that is a symlink is refused
 * without --force; with it the link itself is replaced by the stage (its
 * target is never written).  A DIR holding files that are not the report's
 * (allowed with --force) or a parent that is not writable is written in
 * place instead, its old report.md/.html/.json removed first, so that an
 * interrupted run leaves no complete-looking report beside new data.
 * flock(2) on DIR (on .DIR.usm-lock beside a symlink) makes a second run
 * into the same directory fail at once. */
#define _GNU_SOURCE /* renameat2 */

#include "usm_report.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>

#include "core/outfile.h"
#include "core/progress.h"
#include "io/data_dir.h"
#include "io/io_msg.h"
#include "io/json_out.h"
#include "report_internal.h"
#include "io/template.h"

void usm_report_options_default(usm_report_options *opt)
{
    opt->quick = 0;
    opt->threads = 2;
    opt->plots = 1;
    opt->force = 0;
    opt->progress = (usm_progress){NULL, NULL};
}

/* mkdir -p */
static int make_dir(const char *dir, char msg[USM_IO_MSG_LEN])
{
    char path[4096];
    struct stat st;
    size_t len = strlen(dir);
    if (len >= sizeof path) {
        usm_io_msg(msg, "%s: path too long", dir);
        return USM_EINPUT;
    }
    memcpy(path, dir, len + 1);
    for (size_t i = 1; i <= len; ++i) {
        if (path[i] != '/' && path[i] != '\0')
            continue;
        char c = path[i];
        path[i] = '\0';
        if (mkdir(path, 0777) != 0 && errno != EEXIST) {
            usm_io_msg(msg, "%s: cannot create %s: %s", dir, path, strerror(errno));
            return USM_EINPUT;
        }
        path[i] = c;
    }
    if (stat(dir, &st) != 0 || !S_ISDIR(st.st_mode)) {
        usm_io_msg(msg, "%s: not a directory", dir);
        return USM_EINPUT;
    }
    return USM_OK;
}

/* 1 when the file at path is a regular file (not a symlink: never followed;
 * not a pipe: the open must not block) that starts with the line `marker`. */
static int starts_with_line(const char *path, const char *marker)
{
    char line[512];
    struct stat st;
    const int fd = open(path, O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
    FILE *f = fd >= 0 && fstat(fd, &st) == 0 && S_ISREG(st.st_mode) ? fdopen(fd, "r") : NULL;
    int own = 0;
    if (!f) {
        if (fd >= 0)
            close(fd);
        return 0;
    }
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
    usm_io_file out;
    FILE *f = usm_report_open(&out, dir, REPORT_MANIFEST, msg);
    if (!f)
        return USM_EINPUT;
    fprintf(f, "%s\n", REPORT_MANIFEST_MARKER);
    for (int k = 0; usm_report_files[k]; ++k)
        fprintf(f, "%s\n", usm_report_files[k]);
    return usm_report_close(&out, msg) == USM_OK ? USM_OK : USM_EINPUT;
}

/* Refuse to overwrite files usm did not write (see --force). */
static int check_dir(const char *dir, int force, char msg[USM_IO_MSG_LEN])
{
    char path[4096];
    struct stat st;
    if (lstat(dir, &st) != 0) {
        if (errno == ENOENT)
            return USM_OK; /* created later */
        usm_io_msg(msg, "%s: %s", dir, strerror(errno));
        return USM_EINPUT;
    }
    if (S_ISLNK(st.st_mode)) {
        /* with --force the link itself is replaced by the new report's directory */
        if (force)
            return USM_OK;
        usm_io_msg(msg, "%s: is a symbolic link; refusing to write through it (use --force to "
                   "replace the link itself)", dir);
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

/* DIR/name through a temporary file, renamed when complete (usm_io_create): report.json
 * (data), report.html (md as HTML) or report.md (md). */
static int write_output(json_t *data, const char *md, const char *dir, const char *name,
                        char msg[USM_IO_MSG_LEN])
{
    usm_io_file out;
    FILE *f = usm_report_open(&out, dir, name, msg);
    int bad;
    if (!f)
        return USM_EFAILED;
    if (strcmp(name, "report.json") == 0)
        bad = usm_json_dumpf(data, f, JSON_INDENT(2)) != 0 ||
              fputc('\n', f) == EOF;
    else if (strcmp(name, "report.html") == 0)
        bad = usm_report_html_write(md, dir, f) != 0;
    else
        bad = fputs(md, f) == EOF;
    if (bad) {
        usm_io_abort(&out);
        usm_io_msg(msg, "%s/%s: write error", dir, name);
        return USM_EFAILED;
    }
    return usm_report_close(&out, msg);
}

/* ---- the directory replaced as a whole ------------------------------------------- */

/* Whether name is one of the report's files, its manifest, or a usm temporary. */
static int report_name(const char *name)
{
    const size_t n = strlen(name);
    if (strcmp(name, REPORT_MANIFEST) == 0 ||
        (name[0] == '.' && strstr(name, ".usm-") && n > 5 && strcmp(name + n - 5, ".part") == 0))
        return 1;
    for (int k = 0; usm_report_files[k]; ++k)
        if (strcmp(name, usm_report_files[k]) == 0)
            return 1;
    return 0;
}

/* Whether dir holds nothing but regular files of report names (so that it
 * may be replaced as a whole); 0 when it cannot be read. */
static int only_report_files(const char *dir)
{
    DIR *d = opendir(dir);
    struct dirent *e;
    int only = d != NULL;
    while (only && (e = readdir(d))) {
        struct stat st;
        if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0)
            continue;
        only = report_name(e->d_name) && fstatat(dirfd(d), e->d_name, &st, AT_SYMLINK_NOFOLLOW) == 0 &&
               (S_ISREG(st.st_mode) || S_ISLNK(st.st_mode));
    }
    if (d)
        closedir(d);
    return only;
}

/* Whether dir is a symlink (with --force: replaced by the new directory). */
static int is_link(const char *dir)
{
    struct stat st;
    return lstat(dir, &st) == 0 && S_ISLNK(st.st_mode);
}

/* Lock dir for this run: a descriptor (close it to unlock), or -1 with msg
 * when another run holds it.  A symlink is not followed: the lock is then
 * the file .DIR.usm-lock beside it. */
static int lock_dir(const char *dir, char msg[USM_IO_MSG_LEN])
{
    if (is_link(dir)) {
        char why[USM_IO_MSG_LEN];
        int input;
        const int fd = usm_outfile_lock(dir, why, sizeof why, &input);
        if (fd < 0)
            usm_io_msg(msg, "--out %s", why);
        return fd;
    }
    const int fd = open(dir, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    if (fd < 0) {
        usm_io_msg(msg, "--out %s: %s", dir, strerror(errno));
        return -1;
    }
    if (flock(fd, LOCK_EX | LOCK_NB) != 0) {
        usm_io_msg(msg, "--out %s: %s", dir,
                   errno == EWOULDBLOCK ? "another usm report is writing there (wait for it, "
                                          "or use another directory)"
                                        : strerror(errno));
        close(fd);
        return -1;
    }
    return fd;
}

/* A stage for dir (stage: 4096 bytes), when dir can be replaced as a whole
 * (a symlink always is: the link, never its target); 0 with the stage made,
 * else -1 (write in place). */
static int make_stage(const char *dir, char *stage, char msg[USM_IO_MSG_LEN])
{
    char suffix[64];
    struct stat st;
    snprintf(suffix, sizeof suffix, "%s%ld", USM_OUTFILE_STAGE, (long)getpid());
    if (lstat(dir, &st) != 0 ||
        !(S_ISLNK(st.st_mode) || (S_ISDIR(st.st_mode) && only_report_files(dir))) ||
        usm_outfile_beside(stage, dir, suffix) != 0)
        return -1;
    const mode_t mode = S_ISLNK(st.st_mode) ? 0777 : st.st_mode & 07777;
    usm_outfile_remove_dir(stage, report_name); /* a stage of a run with our pid, long gone */
    if (mkdir(stage, mode) != 0)
        return -1;
    if (!S_ISLNK(st.st_mode))
        chmod(stage, mode);
    if (write_manifest(stage, msg) != USM_OK) {
        usm_outfile_remove_dir(stage, report_name);
        return -1;
    }
    return 0;
}

/* The complete stage in place of dir, the old report removed. */
static int swap_in(const char *dir, const char *stage, char msg[USM_IO_MSG_LEN])
{
    char old[4096];
    if (is_link(dir)) {
        if (usm_outfile_replace_link(stage, dir) == 0)
            return USM_OK;
        usm_io_msg(msg, "%s: cannot replace the symbolic link: %s", dir, strerror(errno));
        return USM_EFAILED;
    }
    if (renameat2(AT_FDCWD, stage, AT_FDCWD, dir, RENAME_EXCHANGE) == 0) {
        usm_outfile_remove_dir(stage, report_name); /* now the old report */
        return USM_OK;
    }
    /* a file system without the exchange: two renames (between them no DIR) */
    if (snprintf(old, sizeof old, "%s.old", stage) >= (int)sizeof old || rename(dir, old) != 0 ||
        rename(stage, dir) != 0) {
        usm_io_msg(msg, "%s: cannot put the new report in place: %s (it is in %s)", dir,
                   strerror(errno), stage);
        return USM_EFAILED;
    }
    usm_outfile_remove_dir(old, report_name);
    return USM_OK;
}

/* In place: the old report's marker files go first, so that an interrupted
 * run does not leave them beside new data. */
static void remove_old_report(const char *dir)
{
    static const char *const names[] = {"report.md", "report.html", "report.json"};
    char path[4096];
    for (size_t k = 0; k < sizeof names / sizeof names[0]; ++k)
        if (usm_report_path(path, sizeof path, dir, names[k]) == 0)
            unlink(path);
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
    if (check_dir(dir, opt->force, msg) != USM_OK)
        return USM_EINPUT;
    if (is_link(dir)) /* --force: the link is replaced, nothing written into its target */
        return USM_OK;
    if (make_dir(dir, msg) != USM_OK || write_manifest(dir, msg) != USM_OK)
        return USM_EINPUT;
    return USM_OK;
}

int usm_report_write(const char *dir, const usm_params *p, const usm_report_options *opt,
                     char msg[USM_IO_MSG_LEN])
{
    usm_report_data *d;
    char plot_note[USM_IO_MSG_LEN] = "", stage[4096];
    int status, plots_ok = 0, lock, staged = 0;
    const char *w = dir; /* where the files are written: the stage, or dir */
    double t;

    if (usm_report_options_check(opt, msg) != USM_OK)
        return USM_EINPUT;
    /* one run per directory, refused before computing */
    if ((lock = lock_dir(dir, msg)) < 0)
        return USM_EINPUT;
    if (!(d = calloc(1, sizeof *d))) {
        usm_io_msg(msg, "out of memory");
        close(lock);
        return USM_EFAILED;
    }
    if (usm_report_paper_load(&d->paper, msg) != USM_OK) {
        free(d);
        close(lock);
        return USM_EFAILED;
    }
    d->params = *p;
    d->opt = *opt;
    int (*const section[])(usm_report_data *, char *) = {
        usm_report_compute, usm_report_compute_maps, usm_report_compute_nonideal,
        usm_report_compute_squeal, usm_report_compute_design, usm_report_compute_paper_fit,
        usm_report_compute_envelope};
    const long nsection = (long)(sizeof section / sizeof section[0]);
    progress_meter meter; /* the files are the last section */
    progress_start(&meter, &opt->progress, nsection + 1, 0, "sections");
    status = USM_OK;
    for (long k = 0; k < nsection && status == USM_OK; ++k)
        if ((status = section[k](d, msg)) == USM_OK)
            progress_add(&meter, 1);
    if (status == USM_OK) {
        usm_outfile_clean_stages(dir, report_name);
        if (is_link(dir) && !opt->force) { /* appeared since usm_report_prepare_dir */
            usm_io_msg(msg, "%s: is a symbolic link; refusing to write through it (use --force "
                       "to replace the link itself)", dir);
            status = USM_EINPUT;
        } else if (make_stage(dir, stage, msg) == 0)
            staged = 1, w = stage;
        else if (is_link(dir)) {
            usm_io_msg(msg, "%s: cannot make the directory that replaces the symbolic link: %s",
                       dir, strerror(errno));
            status = USM_EFAILED;
        } else
            remove_old_report(dir);
        if (status == USM_OK)
            status = usm_report_write_data(d, w, msg);
        if (status == USM_OK) /* the sections' own data files */
            status = usm_report_squeal_write_data(d, w, msg);
        if (status == USM_OK)
            status = usm_report_envelope_write_data(d, w, msg);
    }
    if (status != USM_OK) {
        usm_report_design_free(d);
        usm_report_envelope_free(d);
        usm_report_data_free(d);
        free(d);
        if (staged) {
            usm_outfile_unstage(msg, USM_IO_MSG_LEN, stage, dir);
            usm_outfile_remove_dir(stage, report_name); /* the old report stays as it was */
        }
        close(lock);
        return status == USM_EINPUT || status == USM_ENOSOLUTION ? status : USM_EFAILED;
    }
    t = usm_report_now();
    if (opt->plots && usm_report_run_gnuplot(w, opt->threads, usm_report_figure_count(d),
                                          plot_note) == USM_OK)
        plots_ok = 1;
    if (staged) /* gnuplot's messages outlive the stage */
        usm_outfile_unstage(plot_note, sizeof plot_note, stage, dir);
    d->seconds[3] = usm_report_now() - t;
    d->opt.plots = plots_ok; /* the report links figures only when they exist */
    {
        /* report.md last: its marker says a complete report is there */
        static const char *const outputs[] = {"report.json", "report.html", "report.md"};
        json_t *data = usm_report_json(d, plots_ok || !opt->plots, plot_note);
        char *md = NULL;
        /* report.json before the rendering: when the template fails, the
         * values it was given are there to see */
        status = data ? write_output(data, NULL, w, outputs[0], msg) : USM_EFAILED;
        if (!data)
            usm_io_msg(msg, "out of memory");
        if (status == USM_OK && !(md = render_md(data, msg)))
            status = USM_EFAILED;
        for (size_t k = 1; status == USM_OK && k < sizeof outputs / sizeof outputs[0]; ++k)
            status = write_output(data, md, w, outputs[k], msg);
        free(md);
        json_decref(data);
    }
    usm_report_design_free(d);
    usm_report_envelope_free(d);
    usm_report_data_free(d);
    free(d);
    /* complete (report.md written last): the stage replaces dir as a whole */
    if (staged && status == USM_OK)
        status = swap_in(dir, stage, msg);
    else if (staged) {
        usm_outfile_unstage(msg, USM_IO_MSG_LEN, stage, dir);
        usm_outfile_remove_dir(stage, report_name);
    }
    close(lock);
    if (status != USM_OK)
        return USM_EFAILED;
    progress_add(&meter, 1);
    if (opt->plots && !plots_ok) {
        usm_io_msg(msg, "%s", plot_note);
        return USM_EFAILED;
    }
    return USM_OK;
}
