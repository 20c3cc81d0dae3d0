/* The report's directory (report_dir.h): whether it may be written, the lock
 * that keeps a second run out, and the staging directory that is published
 * whole.
 *
 * Why a staging directory: a report is tens of files computed over seconds
 * to minutes.  Written in place, an interrupted re-run left the old
 * report.md (complete, marked as usm's) beside new data.  Written beside
 * DIR and swapped in with renameat2(RENAME_EXCHANGE), a reader sees the old
 * report or the new one, never a mixture.  Where the swap cannot be used
 * (DIR holds files that are not the report's, DIR is the working directory,
 * or the file system refuses the exchange) the files are moved in one by
 * one, the old report.md/.html/.json removed first and the new ones moved
 * last, so that a complete-looking report is never one of mixed runs. */
#define _GNU_SOURCE /* renameat2 */

#include "report_dir.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "report_internal.h"

#define STAGE_TAG ".usm-new-"
#define LOCK_TAG ".usm-lock"

/* The three outputs: report.md last, since it says a complete report is there. */
static const char *const outputs[] = {"report.json", "report.html", "report.md"};

static int is_output(const char *name)
{
    for (size_t k = 0; k < sizeof outputs / sizeof outputs[0]; ++k)
        if (strcmp(name, outputs[k]) == 0)
            return 1;
    return 0;
}

/* One of the names the report writes (or its manifest). */
static int is_report_file(const char *name)
{
    if (strcmp(name, REPORT_MANIFEST) == 0)
        return 1;
    for (int k = 0; usm_report_files[k]; ++k)
        if (strcmp(name, usm_report_files[k]) == 0)
            return 1;
    return 0;
}

/* mkdir -p */
static int make_dirs(const char *dir, char msg[USM_IO_MSG_LEN])
{
    char path[PATH_MAX];
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
    return USM_OK;
}

/* Split dir into parent and last component (trailing slashes dropped). */
static int split(const char *dir, char parent[PATH_MAX], char name[NAME_MAX + 1],
                 char msg[USM_IO_MSG_LEN])
{
    char path[PATH_MAX];
    size_t len = strlen(dir);
    if (len == 0 || len >= sizeof path) {
        usm_io_msg(msg, "%s: %s", dir, len ? "path too long" : "empty path");
        return USM_EINPUT;
    }
    memcpy(path, dir, len + 1);
    while (len > 1 && path[len - 1] == '/')
        path[--len] = '\0';
    char *slash = strrchr(path, '/');
    const char *base = slash ? slash + 1 : path;
    if (strlen(base) > NAME_MAX) {
        usm_io_msg(msg, "%s: name too long", dir);
        return USM_EINPUT;
    }
    snprintf(name, NAME_MAX + 1, "%s", base);
    if (!slash)
        snprintf(parent, PATH_MAX, ".");
    else if (slash == path)
        snprintf(parent, PATH_MAX, "/");
    else {
        *slash = '\0';
        snprintf(parent, PATH_MAX, "%s", path);
    }
    return USM_OK;
}

static int join(char out[PATH_MAX], const char *a, const char *b)
{
    int n = snprintf(out, PATH_MAX, "%s/%s", a, b);
    return n < 0 || n >= PATH_MAX ? -1 : 0;
}

/* Remove directory path holding only report files; 0, or -1 when something
 * else is in it (then it is left alone). */
static int remove_report_tree(const char *path)
{
    DIR *d = opendir(path);
    struct dirent *e;
    char file[PATH_MAX];
    int foreign = 0;
    if (!d)
        return -1;
    while ((e = readdir(d)) != NULL) {
        if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0)
            continue;
        if (is_report_file(e->d_name) && join(file, path, e->d_name) == 0)
            unlink(file);
        else
            foreign = 1;
    }
    closedir(d);
    return foreign ? -1 : rmdir(path);
}

/* Whether dir holds nothing but the report's files. */
static int only_report_files(const char *dir)
{
    DIR *d = opendir(dir);
    struct dirent *e;
    int only = 1;
    if (!d)
        return 0;
    while (only && (e = readdir(d)) != NULL)
        if (strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0 &&
            !is_report_file(e->d_name))
            only = 0;
    closedir(d);
    return only;
}

/* Whether dir is the working directory or one of its ancestors: swapping it
 * would leave the process (and the user's shell) in a removed directory. */
static int holds_cwd(const char *dir)
{
    char real[PATH_MAX], cwd[PATH_MAX];
    size_t n;
    if (!realpath(dir, real) || !getcwd(cwd, sizeof cwd))
        return 1;
    n = strlen(real);
    return strncmp(cwd, real, n) == 0 && (cwd[n] == '\0' || cwd[n] == '/' || n == 1);
}

int usm_report_stage_begin(usm_report_stage *st, const char *dir, char msg[USM_IO_MSG_LEN])
{
    char name[NAME_MAX + 1], lock[PATH_MAX], tmpl[PATH_MAX];
    memset(st, 0, sizeof *st);
    st->lock_fd = -1;
    if (split(dir, st->parent, name, msg) != USM_OK)
        return USM_EINPUT;
    if (strcmp(name, ".") == 0 || strcmp(name, "..") == 0 || strcmp(name, "/") == 0) {
        /* no sibling to stage beside: the report is moved in file by file */
        if (!realpath(dir, st->dir)) {
            usm_io_msg(msg, "%s: %s", dir, strerror(errno));
            return USM_EINPUT;
        }
        if (split(st->dir, st->parent, name, msg) != USM_OK)
            return USM_EINPUT;
    } else {
        snprintf(st->dir, sizeof st->dir, "%s", dir);
    }
    if (make_dirs(st->parent, msg) != USM_OK)
        return USM_EINPUT;
    if (snprintf(lock, sizeof lock, "%s/.%s" LOCK_TAG, st->parent, name) >= (int)sizeof lock ||
        snprintf(tmpl, sizeof tmpl, "%s/.%s" STAGE_TAG "XXXXXX", st->parent, name) >=
            (int)sizeof tmpl) {
        usm_io_msg(msg, "%s: path too long", dir);
        return USM_EINPUT;
    }
    st->lock_fd = open(lock, O_RDWR | O_CREAT | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (st->lock_fd < 0) {
        usm_io_msg(msg, "%s: cannot create the lock %s: %s", dir, lock, strerror(errno));
        return USM_EINPUT;
    }
    /* a run killed a moment ago may leave the lock with a child between fork
     * and exec for an instant: a second's grace, then fail at once */
    int locked = -1;
    for (int tries = 0; tries < 10 && (locked = flock(st->lock_fd, LOCK_EX | LOCK_NB)) != 0;
         ++tries)
        nanosleep(&(struct timespec){0, 100000000L}, NULL);
    if (locked != 0) {
        usm_io_msg(msg, "%s: another usm report is writing it (lock %s)", dir, lock);
        close(st->lock_fd);
        st->lock_fd = -1;
        return USM_EINPUT;
    }
    /* holding the lock, no other run writes DIR: staging directories of
     * interrupted runs are leftovers */
    {
        DIR *d = opendir(st->parent);
        struct dirent *e;
        char prefix[NAME_MAX + 16], path[PATH_MAX];
        snprintf(prefix, sizeof prefix, ".%s" STAGE_TAG, name);
        while (d && (e = readdir(d)) != NULL)
            if (strncmp(e->d_name, prefix, strlen(prefix)) == 0 &&
                strlen(e->d_name) == strlen(prefix) + 6 && join(path, st->parent, e->d_name) == 0)
                remove_report_tree(path);
        if (d)
            closedir(d);
    }
    snprintf(st->stage, sizeof st->stage, "%s", tmpl);
    if (!mkdtemp(st->stage)) {
        usm_io_msg(msg, "%s: cannot create a directory beside it: %s", dir, strerror(errno));
        st->stage[0] = '\0';
        usm_report_stage_end(st);
        return USM_EINPUT;
    }
    chmod(st->stage, 0755 & ~0022); /* mkdtemp's 0700; the report is for reading */
    return USM_OK;
}

/* Move staged file name into dir; one that this run did not write (e.g. no
 * figures) is removed there too, so no file of an earlier run is left. */
static int move_one(usm_report_stage *st, const char *name, char msg[USM_IO_MSG_LEN])
{
    char from[PATH_MAX], to[PATH_MAX];
    struct stat sb;
    if (join(from, st->stage, name) != 0 || join(to, st->dir, name) != 0) {
        usm_io_msg(msg, "%s: path too long", st->dir);
        return USM_EFAILED;
    }
    if (lstat(from, &sb) != 0) {
        unlink(to);
        return USM_OK;
    }
    if (rename(from, to) != 0) {
        usm_io_msg(msg, "%s: %s", to, strerror(errno));
        return USM_EFAILED;
    }
    return USM_OK;
}

/* Move the staged files into the existing dir one by one (see the top): the
 * old outputs removed first, then the manifest, the data and figures, and
 * the outputs last. */
static int publish_by_file(usm_report_stage *st, char msg[USM_IO_MSG_LEN])
{
    char to[PATH_MAX];
    const size_t nout = sizeof outputs / sizeof outputs[0];
    for (size_t k = 0; k < nout; ++k)
        if (join(to, st->dir, outputs[k]) == 0)
            unlink(to);
    if (move_one(st, REPORT_MANIFEST, msg) != USM_OK)
        return USM_EFAILED;
    for (int k = 0; usm_report_files[k]; ++k)
        if (!is_output(usm_report_files[k]) && move_one(st, usm_report_files[k], msg) != USM_OK)
            return USM_EFAILED;
    for (size_t k = 0; k < nout; ++k)
        if (move_one(st, outputs[k], msg) != USM_OK)
            return USM_EFAILED;
    return USM_OK;
}

int usm_report_stage_publish(usm_report_stage *st, char msg[USM_IO_MSG_LEN])
{
    struct stat sb;
    if (lstat(st->dir, &sb) != 0) {
        if (errno == ENOENT && renameat2(AT_FDCWD, st->stage, AT_FDCWD, st->dir,
                                         RENAME_NOREPLACE) == 0) {
            st->stage[0] = '\0';
            return USM_OK;
        }
        if (errno != ENOENT && errno != EINVAL && errno != ENOSYS) {
            usm_io_msg(msg, "%s: %s", st->dir, strerror(errno));
            return USM_EFAILED;
        }
        if (make_dirs(st->dir, msg) != USM_OK)
            return USM_EFAILED;
    } else if (S_ISDIR(sb.st_mode) && only_report_files(st->dir) && !holds_cwd(st->dir) &&
               renameat2(AT_FDCWD, st->stage, AT_FDCWD, st->dir, RENAME_EXCHANGE) == 0) {
        /* the old report is now at the staging name */
        remove_report_tree(st->stage);
        st->stage[0] = '\0';
        return USM_OK;
    }
    return publish_by_file(st, msg);
}

void usm_report_stage_end(usm_report_stage *st)
{
    if (st->stage[0])
        remove_report_tree(st->stage);
    st->stage[0] = '\0';
    if (st->lock_fd >= 0)
        close(st->lock_fd); /* releases the lock */
    st->lock_fd = -1;
}
