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
        if (stat(path, &st) != 0)
            usm_io_msg(msg, "%s: a symbolic link to nothing; refusing to write through it", path);
        else if (!S_ISDIR(st.st_mode))
            usm_io_msg(msg, "%s: exists and is not a directory", path);
        else if ((empty = dir_empty(path)) < 0 || access(path, W_OK | X_OK) != 0)
            usm_io_msg(msg, "%s: %s", path, strerror(errno));
        else if (!empty && !force)
            usm_io_msg(msg, "%s: exists (use --force to write into it)", path);
        else
            return USM_OK;
        return USM_EINPUT;
    }
    if (errno != ENOENT) {
        usm_io_msg(msg, "%s: %s", path, strerror(errno));
        return USM_EINPUT;
    }
    snprintf(parent, sizeof parent, "%s", path);
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
    /* a non-empty directory (force): in place */
    if (stat(path, &st) == 0 && dir_empty(path) == 0)
        return USM_OK;
    usm_outfile_clean_stages(path, NULL);
    snprintf(suffix, sizeof suffix, "%s%ld", USM_OUTFILE_STAGE, (long)getpid());
    if (usm_outfile_beside(out->stage, path, suffix) != 0) {
        usm_io_msg(msg, "%.200s: path too long", path);
        return USM_EINPUT;
    }
    usm_outfile_remove_dir(out->stage, NULL); /* of a run with our pid, long gone */
    if (mkdir(out->stage, 0777) != 0) {
        usm_io_msg(msg, "%s: %s", out->stage, strerror(errno));
        out->stage[0] = '\0';
        return USM_EFAILED;
    }
    out->work = out->stage;
    return USM_OK;
}

int usm_io_dir_commit(usm_io_dir *out, char msg[USM_IO_MSG_LEN])
{
    if (!out->stage[0])
        return USM_OK;
    /* rename(2) replaces only an empty directory: a DIR filled meanwhile is kept */
    if (rename(out->stage, out->path) != 0) {
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
