/* Output files that appear whole or not at all (usm_io_create, usm_io.h);
 * the mechanism is core/outfile.c's. */
#define _POSIX_C_SOURCE 200809L

#include <dirent.h>
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/outfile.h"
#include "io_msg.h"
#include "usm.h"

int usm_io_check(const char *path, int force, char msg[USM_IO_MSG_LEN])
{
    return usm_outfile_check(path, force, msg, USM_IO_MSG_LEN);
}

FILE *usm_io_create(usm_io_file *out, const char *path, int force, char msg[USM_IO_MSG_LEN],
                    int *status)
{
    int fd;
    memset(out, 0, sizeof *out);
    out->force = force;
    if (strlen(path) >= sizeof out->path) {
        usm_io_msg(msg, "%.200s: path too long", path);
        *status = USM_EINPUT;
        return NULL;
    }
    strcpy(out->path, path);
    if ((fd = usm_outfile_open(path, force, out->tmp, msg, USM_IO_MSG_LEN, status)) < 0)
        return NULL;
    if (!(out->f = fdopen(fd, "w"))) {
        usm_io_msg(msg, "%s: %s", path, strerror(errno));
        close(fd);
        if (out->tmp[0])
            unlink(out->tmp);
        *status = USM_EFAILED;
        return NULL;
    }
    *status = USM_OK;
    return out->f;
}

int usm_io_commit(usm_io_file *out, char msg[USM_IO_MSG_LEN])
{
    int bad;
    if (!out->f) {
        usm_io_msg(msg, "%s: not open", out->path);
        return USM_EFAILED;
    }
    bad = fflush(out->f) != 0 || ferror(out->f);
    bad |= fclose(out->f) != 0;
    out->f = NULL;
    if (bad) {
        usm_io_msg(msg, "%s: write error", out->path);
        if (out->tmp[0])
            unlink(out->tmp);
        return USM_EFAILED;
    }
    return usm_outfile_place(out->tmp, out->path, out->force, msg, USM_IO_MSG_LEN);
}

void usm_io_abort(usm_io_file *out)
{
    if (!out->f)
        return;
    fclose(out->f);
    out->f = NULL;
    if (out->tmp[0])
        unlink(out->tmp);
}

/* Whether a and b name one file (usm_io_check_distinct). */
static int same_file(const char *a, const char *b)
{
    const char *sa = strrchr(a, '/'), *sb = strrchr(b, '/');
    const char *ba = sa ? sa + 1 : a, *bb = sb ? sb + 1 : b;
    char da[USM_IO_PATH_LEN], db[USM_IO_PATH_LEN];
    struct stat x, y;
    if (strcmp(ba, bb) != 0)
        return 0;
    snprintf(da, sizeof da, "%.*s", sa ? (sa == a ? 1 : (int)(sa - a)) : 1, sa ? a : ".");
    snprintf(db, sizeof db, "%.*s", sb ? (sb == b ? 1 : (int)(sb - b)) : 1, sb ? b : ".");
    if (stat(da, &x) == 0 && stat(db, &y) == 0)
        return x.st_dev == y.st_dev && x.st_ino == y.st_ino;
    return strcmp(da, db) == 0;
}

int usm_io_check_distinct(const char *const *paths, const char *const *options, int n,
                          char msg[USM_IO_MSG_LEN])
{
    for (int i = 0; i < n; ++i)
        for (int j = i + 1; j < n; ++j)
            if (same_file(paths[i], paths[j])) {
                usm_io_msg(msg, "%s %.400s and %s %.400s are the same file (one would replace "
                           "the other)", options[i], paths[i], options[j], paths[j]);
                return USM_EINPUT;
            }
    return USM_OK;
}

/* ---- output directories ---------------------------------------------------------- */

/* Whether dir is a directory with no entry (1), has entries (0), or cannot
 * be read (-1). */
static int dir_empty(const char *dir)
{
    DIR *d = opendir(dir);
    struct dirent *e;
    int empty = 1;
    if (!d)
        return -1;
    while (empty && (e = readdir(d)))
        empty = strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0;
    closedir(d);
    return empty;
}

int usm_io_dir_check(const char *path, int force, char msg[USM_IO_MSG_LEN])
{
    char parent[USM_IO_PATH_LEN];
    struct stat st;
    if (!path[0] || strlen(path) + 64 >= USM_IO_PATH_LEN) {
        usm_io_msg(msg, "%.200s: not usable as a directory name", path);
        return USM_EINPUT;
    }
    if (lstat(path, &st) == 0) {
        int empty;
        if (S_ISLNK(st.st_mode)) {
            /* with force the link itself is replaced by the new directory (commit) */
            if (!force) {
                usm_io_msg(msg, "%s: is a symbolic link; refusing to write through it (use "
                           "--force to replace the link itself)", path);
                return USM_EINPUT;
            }
        } else if (!S_ISDIR(st.st_mode)) {
            usm_io_msg(msg, "%s: exists and is not a directory", path);
            return USM_EINPUT;
        } else if ((empty = dir_empty(path)) < 0 || access(path, W_OK | X_OK) != 0) {
            usm_io_msg(msg, "%s: %s", path, strerror(errno));
            return USM_EINPUT;
        } else if (!empty && !force) {
            usm_io_msg(msg, "%s: exists (use --force to write into it)", path);
            return USM_EINPUT;
        } else
            return USM_OK;
    } else if (errno != ENOENT) {
        usm_io_msg(msg, "%s: %s", path, strerror(errno));
        return USM_EINPUT;
    }
    snprintf(parent, sizeof parent, "%s", path);
    size_t n = strlen(parent);
    while (n > 1 && parent[n - 1] == '/')
        parent[--n] = '\0';
    char *slash = strrchr(parent, '/');
    if (slash)
        slash[slash == parent] = '\0';
    else
        snprintf(parent, sizeof parent, ".");
    if (access(parent, W_OK | X_OK) != 0) {
        usm_io_msg(msg, "%s: %s", path, strerror(errno));
        return USM_EINPUT;
    }
    return USM_OK;
}

int usm_io_dir_create(usm_io_dir *out, const char *path, int force, char msg[USM_IO_MSG_LEN])
{
    char suffix[64];
    struct stat st;
    int status;
    memset(out, 0, sizeof *out);
    if ((status = usm_io_dir_check(path, force, msg)) != USM_OK)
        return status;
    snprintf(out->path, sizeof out->path, "%s", path);
    out->work = out->path;
    /* a non-empty directory (force): in place; never a symlink's target */
    if (lstat(path, &st) == 0 && S_ISDIR(st.st_mode) && dir_empty(path) == 0)
        return USM_OK;
    out->replace_link = force && lstat(path, &st) == 0 && S_ISLNK(st.st_mode);
    usm_outfile_clean_stages(path, NULL);
    snprintf(suffix, sizeof suffix, "%s%ld", USM_OUTFILE_STAGE, (long)getpid());
    if (usm_outfile_beside(out->stage, path, suffix) != 0) {
        usm_io_msg(msg, "%.200s: path too long", path);
        return USM_EINPUT;
    }
    usm_outfile_remove_dir(out->stage, NULL); /* of a run with our pid, long gone */
    if (mkdir(out->stage, 0777) != 0) {
        const int e = errno;
        usm_io_msg(msg, "%s: %s", path,
                   e == EEXIST ? "the name of its stage is taken by something usm did not make"
                               : strerror(e));
        out->stage[0] = '\0';
        return e == ENOSPC || e == EIO ? USM_EFAILED : USM_EINPUT;
    }
    out->work = out->stage;
    return USM_OK;
}

void usm_io_dir_msg(const usm_io_dir *out, char msg[USM_IO_MSG_LEN])
{
    if (out->stage[0])
        usm_outfile_unstage(msg, USM_IO_MSG_LEN, out->stage, out->path);
}

int usm_io_dir_commit(usm_io_dir *out, char msg[USM_IO_MSG_LEN])
{
    struct stat st;
    if (!out->stage[0])
        return USM_OK;
    /* a symlink at path (allowed with force only, usm_io_dir_check): the link
     * itself is replaced, its target never written; one that appeared
     * meanwhile is kept (rename fails, below) */
    if (out->replace_link && lstat(out->path, &st) == 0 && S_ISLNK(st.st_mode)) {
        if (usm_outfile_replace_link(out->stage, out->path) != 0) {
            const int e = errno;
            usm_io_msg(msg, "%s: cannot replace the symbolic link: %s", out->path, strerror(e));
            usm_outfile_remove_dir(out->stage, NULL);
            out->stage[0] = '\0';
            return USM_EFAILED;
        }
    } else if (rename(out->stage, out->path) != 0) {
        /* rename(2) replaces only an empty directory: a DIR filled meanwhile is kept */
        const int e = errno;
        usm_io_msg(msg, "%s: %s", out->path,
                   e == ENOTEMPTY || e == EEXIST || e == ENOTDIR
                       ? "appeared while computing; refusing to replace it (use --force)"
                       : strerror(e));
        usm_outfile_remove_dir(out->stage, NULL);
        out->stage[0] = '\0';
        return e == ENOTEMPTY || e == EEXIST || e == ENOTDIR ? USM_EINPUT : USM_EFAILED;
    }
    out->stage[0] = '\0';
    out->work = out->path;
    return USM_OK;
}

void usm_io_dir_abort(usm_io_dir *out)
{
    if (out->stage[0])
        usm_outfile_remove_dir(out->stage, NULL);
    out->stage[0] = '\0';
}
