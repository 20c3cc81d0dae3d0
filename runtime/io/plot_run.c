/* Running gnuplot on the static scripts of data/plots/ (see plot_run.h). */
#define _POSIX_C_SOURCE 200809L

#include "plot_run.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include "core/outfile.h"
#include "data_dir.h"
#include "template.h"
#include "usm.h"

static int path_in(char *buf, size_t len, const char *dir, const char *stem, const char *ext)
{
    int n = strcmp(dir, ".") == 0 ? snprintf(buf, len, "%s%s", stem, ext)
                                  : snprintf(buf, len, "%s/%s%s", dir, stem, ext);
    return n < 0 || (size_t)n >= len ? -1 : 0;
}

static pid_t spawn(const char *exe, const char *dir, const char *script, int log_fd)
{
    pid_t pid = fork();
    if (pid == 0) {
        int null_fd = open("/dev/null", O_RDONLY);
        if (null_fd >= 0)
            dup2(null_fd, 0);
        dup2(log_fd, 1);
        dup2(log_fd, 2);
        if (chdir(dir) != 0)
            _exit(126);
        execlp(exe, exe, script, (char *)NULL);
        _exit(127);
    }
    return pid;
}

int usm_gnuplot_run(const char *dir, const char *const *stems, int n, int jobs,
                    const char *log_path, char msg[USM_IO_MSG_LEN])
{
    const char *exe = getenv("USM_GNUPLOT");
    char path[4096], script[256], log_tmp[USM_OUTFILE_PATH];
    pid_t *pids = calloc((size_t)n + 1, sizeof *pids);
    int running = 0, next = 0, failed = 0, missing = 0, log_fd;
    int failed_at = -1, ost;
    if (!exe || !exe[0])
        exe = "gnuplot";
    /* the log too appears whole, and replaces a symlink rather than write its target */
    if (!pids || (log_fd = usm_outfile_open(log_path, 1, log_tmp, msg, USM_IO_MSG_LEN, &ost)) < 0) {
        if (!pids)
            usm_io_msg(msg, "%s: out of memory", log_path);
        free(pids);
        return USM_EFAILED;
    }
    for (int i = 0; i < n; ++i) {
        pids[i] = -1;
        /* a previous run's image must not pass for this run's */
        for (int e = 0; e < 2; ++e)
            if (path_in(path, sizeof path, dir, stems[i], e ? ".svg" : ".png") == 0)
                unlink(path);
    }
    fflush(NULL);
    while (next < n || running > 0) {
        int status;
        pid_t pid;
        if (next < n && running < (jobs < 1 ? 1 : jobs)) {
            snprintf(script, sizeof script, "%s.gp", stems[next]);
            if ((pids[next] = spawn(exe, dir, script, log_fd)) < 0) {
                usm_io_msg(msg, "gnuplot: cannot start a process: %s", strerror(errno));
                failed = 1;
                next = n;
                continue;
            }
            ++next;
            ++running;
            continue;
        }
        if ((pid = wait(&status)) < 0) {
            if (errno == EINTR)
                continue;
            break;
        }
        for (int i = 0; i < n; ++i)
            if (pids[i] == pid) {
                --running;
                pids[i] = -1;
                if (WIFEXITED(status) && WEXITSTATUS(status) == 127)
                    missing = 1;
                else if ((!WIFEXITED(status) || WEXITSTATUS(status) != 0) && failed_at < 0)
                    failed_at = i;
            }
    }
    /* the log is put in place even when closing it failed */
    const int log_closed = close(log_fd) == 0;
    const int log_placed = usm_outfile_place(log_tmp, log_path, 1, path, sizeof path) == 0;
    if (!log_closed || !log_placed)
        failed = 1, usm_io_msg(msg, "%.1000s", path);
    if (missing) {
        usm_io_msg(msg, "%s: not found, figures not rendered (install gnuplot-nox, or set "
                     "USM_GNUPLOT; then run the *.gp scripts in %s)", exe, dir);
        free(pids);
        return USM_ENOSOLUTION;
    } else if (failed_at >= 0) {
        usm_io_msg(msg, "gnuplot failed on %s/%s.gp (see %s)", dir, stems[failed_at], log_path);
    } else if (!failed) {
        /* gnuplot may exit 0 without writing (a terminal missing, an edited
         * script): only images that exist count */
        for (int i = 0; i < n && !failed; ++i)
            for (int e = 0; e < 2 && !failed; ++e) {
                struct stat st;
                if (path_in(path, sizeof path, dir, stems[i], e ? ".svg" : ".png") != 0 ||
                    stat(path, &st) != 0 || st.st_size == 0) {
                    usm_io_msg(msg, "%s: gnuplot exited 0 but did not write %s (see %s)", exe,
                            path, log_path);
                    failed = 1;
                }
            }
        free(pids);
        return failed ? USM_EFAILED : USM_OK;
    }
    free(pids);
    return USM_EFAILED;
}

int usm_plot_check(const char *prefix, int force, char msg[USM_IO_MSG_LEN])
{
    static const char *const ext[] = {".gp", ".png", ".svg", ".log"}; /* gnuplot's messages too */
    char path[4096], why[USM_IO_MSG_LEN];
    if (prefix[0] == '\0' || strchr(prefix, '\n') || strlen(prefix) + 70 > sizeof path) {
        usm_io_msg(msg, "--plot: \"%.200s\" is not usable as a file prefix", prefix);
        return USM_EINPUT;
    }
    {
        const char *slash = strrchr(prefix, '/'), *base = slash ? slash + 1 : prefix;
        struct stat st;
        if (!base[0] || strcmp(base, ".") == 0 || strcmp(base, "..") == 0 ||
            (stat(prefix, &st) == 0 && S_ISDIR(st.st_mode))) {
            usm_io_msg(msg, "--plot %.900s: names a directory, not a file prefix (PREFIX.gp, "
                       "PREFIX.png, ... are written beside it: give DIR/NAME)", prefix);
            return USM_EINPUT;
        }
    }
    /* lstat, not stat: a dangling symlink is refused too */
    for (size_t k = 0; k < sizeof ext / sizeof ext[0]; ++k) {
        snprintf(path, sizeof path, "%s%s", prefix, ext[k]);
        if (usm_outfile_check(path, force, why, sizeof why) != USM_OK) {
            usm_io_msg(msg, "--plot %.1000s", why);
            return USM_EINPUT;
        }
    }
    return USM_OK;
}

/* A gnuplot value: a number as it is, anything else single-quoted ('' is
 * one quote inside). */
static void value(FILE *f, const char *s)
{
    char *end;
    double v = s[0] && !isspace((unsigned char)s[0]) ? strtod(s, &end) : NAN;
    if (isfinite(v) && *end == '\0') {
        fputs(s, f);
        return;
    }
    fputc('\'', f);
    for (; *s; ++s) {
        if (*s == '\'')
            fputc('\'', f);
        fputc(*s == '\n' ? ' ' : *s, f);
    }
    fputc('\'', f);
}

int usm_plot_render(const char *script, const char *prefix, const char *const *names,
                    const char *const *values, int n, char msg[USM_IO_MSG_LEN])
{
    char src[4096], name[256], out[4096], log[4096], why[USM_IO_MSG_LEN];
    char *text;
    usm_io_file gp;
    FILE *f;
    int st;
    if (usm_plot_check(prefix, 1, msg) != USM_OK)
        return USM_EINPUT;
    snprintf(name, sizeof name, "plots/%s.gp", script);
    if (usm_data_path(name, src, sizeof src) != 0) {
        usm_io_msg(msg, "--plot %s: %s: the gnuplot script is not installed (set USM_DATA_DIR)",
                prefix, src);
        return USM_EFAILED;
    }
    if (!(text = usm_template_read(src, msg)))
        return USM_EFAILED;
    snprintf(out, sizeof out, "%s.gp", prefix);
    if (!(f = usm_io_create(&gp, out, 1, why, &st))) {
        usm_io_msg(msg, "--plot %.1000s", why);
        free(text);
        return st;
    }
    fputs("# written by usm (--plot): the values, then the static script ", f);
    fprintf(f, "%s.gp;\n# re-plot: gnuplot ", script);
    value(f, out);
    fputs("\nprefix = ", f);
    value(f, prefix);
    fputc('\n', f);
    for (int k = 0; k < n; ++k) {
        fprintf(f, "%s = ", names[k]);
        value(f, values[k]);
        fputc('\n', f);
    }
    fputs(text, f);
    free(text);
    if ((st = usm_io_commit(&gp, why)) != USM_OK) {
        usm_io_msg(msg, "--plot %.1000s", why);
        return st;
    }
    snprintf(log, sizeof log, "%s.log", prefix);
    {
        const char *stems[1] = {prefix};
        return usm_gnuplot_run(".", stems, 1, 1, log, msg);
    }
}

int usm_plot_files(const char *prefix, int csv,
                   char files[USM_PLOT_MAX_FILES][USM_IO_PATH_LEN])
{
    static const char *const ext[] = {".csv", ".gp", ".png", ".svg", ".log"};
    int n = 0;
    for (size_t k = csv ? 0 : 1; k < sizeof ext / sizeof ext[0]; ++k) {
        const int w = snprintf(files[n++], USM_IO_PATH_LEN, "%s%s", prefix, ext[k]);
        if (w < 0 || w >= USM_IO_PATH_LEN)
            return -1;
    }
    return n;
}

int usm_plot_csv_check(const char *prefix, int force, char msg[USM_IO_MSG_LEN])
{
    char path[4096], why[USM_IO_MSG_LEN];
    if (usm_plot_check(prefix, force, msg) != USM_OK)
        return USM_EINPUT;
    snprintf(path, sizeof path, "%s.csv", prefix);
    if (usm_outfile_check(path, force, why, sizeof why) != USM_OK) {
        usm_io_msg(msg, "--plot %.1000s", why);
        return USM_EINPUT;
    }
    return USM_OK;
}

int usm_plot_csv_write(const char *prefix, int force, int (*write)(FILE *out, const void *data),
                       const void *data, char msg[USM_IO_MSG_LEN])
{
    char path[4096], why[USM_IO_MSG_LEN];
    usm_io_file file;
    int status;
    snprintf(path, sizeof path, "%s.csv", prefix);
    FILE *f = usm_io_create(&file, path, force, why, &status);
    if (!f) {
        usm_io_msg(msg, "--plot %.1000s", why);
        return USM_EINPUT;
    }
    if (write(f, data) != 0) {
        usm_io_abort(&file);
        usm_io_msg(msg, "--plot %.1000s: write error", path);
        return USM_EFAILED;
    }
    if (usm_io_commit(&file, why) != USM_OK) {
        usm_io_msg(msg, "--plot %.1000s", why);
        return USM_EFAILED;
    }
    return USM_OK;
}
