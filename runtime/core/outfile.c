/* Files that appear whole or not at all (outfile.h). */
#define _POSIX_C_SOURCE 200809L

#include "outfile.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "usm.h"

#define TMP_MID ".usm-"
#define TMP_END ".part"

/* path's directory ("." when it has none) and its last component. */
static int split(const char *path, char dir[USM_OUTFILE_PATH], const char **base)
{
    const char *slash = strrchr(path, '/');
    if (!slash) {
        snprintf(dir, USM_OUTFILE_PATH, ".");
        *base = path;
        return 0;
    }
    const size_t n = slash == path ? 1 : (size_t)(slash - path);
    if (n >= USM_OUTFILE_PATH)
        return -1;
    memcpy(dir, path, n);
    dir[n] = '\0';
    *base = slash + 1;
    return 0;
}

int usm_outfile_check(const char *path, int force, char *why, size_t len)
{
    char dir[USM_OUTFILE_PATH];
    const char *base;
    struct stat st;
    if (!path[0] || strlen(path) + 64 >= USM_OUTFILE_PATH || split(path, dir, &base) != 0 ||
        !base[0] || strcmp(base, ".") == 0 || strcmp(base, "..") == 0) {
        snprintf(why, len, "%.200s: not usable as a file name", path);
        return USM_EINPUT;
    }
    if (lstat(path, &st) == 0) {
        const char *r = S_ISDIR(st.st_mode) ? "is a directory"
                        : force             ? NULL
                        : S_ISLNK(st.st_mode)
                            ? "is a symbolic link; refusing to write through it (use --force "
                              "to replace the link itself)"
                            : "exists; refusing to overwrite it (use --force)";
        if (r) {
            snprintf(why, len, "%.900s: %s", path, r);
            return USM_EINPUT;
        }
    } else if (errno != ENOENT) {
        snprintf(why, len, "%.900s: %s", path, strerror(errno));
        return USM_EINPUT;
    }
    if (force && stat(path, &st) == 0 && (S_ISCHR(st.st_mode) || S_ISFIFO(st.st_mode)))
        return USM_OK; /* a device or pipe, written as it is */
    if (stat(dir, &st) != 0 || !S_ISDIR(st.st_mode) || access(dir, W_OK | X_OK) != 0) {
        const int e = errno;
        snprintf(why, len, "%.900s: directory %s: %s", path, dir,
                 stat(dir, &st) == 0 && !S_ISDIR(st.st_mode) ? "not a directory" : strerror(e));
        return USM_EINPUT;
    }
    return USM_OK;
}

static int dead_pid(const char *s, int old_too);

/* Remove the temporaries of base in dir whose process is gone (a killed
 * run's); a live process's are left alone. */
static void clean_stale(const char *dir, const char *base)
{
    DIR *d = opendir(dir);
    struct dirent *e;
    const size_t blen = strlen(base);
    if (!d)
        return;
    while ((e = readdir(d))) {
        const char *n = e->d_name;
        const size_t nlen = strlen(n);
        if (n[0] != '.' || nlen < 1 + blen + strlen(TMP_MID) + strlen(TMP_END) + 2 ||
            strncmp(n + 1, base, blen) != 0 ||
            strncmp(n + 1 + blen, TMP_MID, strlen(TMP_MID)) != 0 ||
            strcmp(n + nlen - strlen(TMP_END), TMP_END) != 0)
            continue;
        char num[32];
        const char *at = n + 1 + blen + strlen(TMP_MID);
        const size_t digits = strspn(at, "0123456789");
        if (digits == 0 || digits >= sizeof num || at[digits] != '-')
            continue;
        memcpy(num, at, digits);
        num[digits] = '\0';
        if (!dead_pid(num, 0))
            continue;
        char p[USM_OUTFILE_PATH];
        if (snprintf(p, sizeof p, "%s/%s", dir, n) < (int)sizeof p)
            unlink(p);
    }
    closedir(d);
}

int usm_outfile_open(const char *path, int force, char tmp[USM_OUTFILE_PATH], char *why,
                     size_t len, int *status)
{
    char dir[USM_OUTFILE_PATH];
    const char *base;
    struct timespec ts;
    struct stat st;
    *status = usm_outfile_check(path, force, why, len);
    if (*status != USM_OK)
        return -1;
    /* a device or pipe (--force --out /dev/null): written as it is, nothing to place */
    if (force && stat(path, &st) == 0 && (S_ISCHR(st.st_mode) || S_ISFIFO(st.st_mode))) {
        const int fd = open(path, O_WRONLY | O_NOCTTY | O_CLOEXEC);
        tmp[0] = '\0';
        if (fd < 0) {
            snprintf(why, len, "%.900s: %s", path, strerror(errno));
            *status = USM_EINPUT;
        }
        return fd;
    }
    split(path, dir, &base);
    clean_stale(dir, base);
    clock_gettime(CLOCK_REALTIME, &ts);
    uint64_t r = (uint64_t)ts.tv_nsec ^ ((uint64_t)ts.tv_sec << 20) ^ (uint64_t)(uintptr_t)tmp;
    for (int attempt = 0; attempt < 100; ++attempt) {
        r = r * 6364136223846793005ULL + 1442695040888963407ULL;
        const int n = snprintf(tmp, USM_OUTFILE_PATH, "%.*s.%s%s%ld-%06llx%s",
                               (int)(base - path), path, base, TMP_MID,
                               (long)getpid(), (unsigned long long)(r >> 40), TMP_END);
        if (n < 0 || n >= USM_OUTFILE_PATH) {
            snprintf(why, len, "%.200s: path too long", path);
            *status = USM_EINPUT;
            return -1;
        }
        const int fd = open(tmp, O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
        if (fd >= 0)
            return fd;
        if (errno != EEXIST) {
            snprintf(why, len, "%.900s: %s", path, strerror(errno));
            *status = errno == ENOSPC || errno == EIO ? USM_EFAILED : USM_EINPUT;
            return -1;
        }
    }
    snprintf(why, len, "%.900s: no temporary name free", path);
    *status = USM_EFAILED;
    return -1;
}

int usm_outfile_place(const char *tmp, const char *path, int force, char *why, size_t len)
{
    int status = USM_OK;
    if (!tmp[0])
        return USM_OK; /* a device, written in place */
    if (force) {
        if (rename(tmp, path) != 0) {
            snprintf(why, len, "%.900s: %s", path, strerror(errno));
            status = errno == EISDIR ? USM_EINPUT : USM_EFAILED;
        }
    } else if (link(tmp, path) != 0) {
        /* link(2) never replaces: a name that appeared meanwhile is kept */
        if (errno == EEXIST) {
            snprintf(why, len, "%.900s: appeared while computing; refusing to overwrite it "
                     "(use --force)", path);
            status = USM_EINPUT;
        } else if ((errno == EPERM || errno == ENOTSUP || errno == EOPNOTSUPP ||
                    errno == EMLINK) && access(path, F_OK) != 0 && errno == ENOENT) {
            /* a file system without hard links: the check, then the rename */
            struct stat st;
            if (lstat(path, &st) == 0) {
                snprintf(why, len, "%.900s: appeared while computing; refusing to overwrite "
                         "it (use --force)", path);
                status = USM_EINPUT;
            } else if (rename(tmp, path) != 0) {
                snprintf(why, len, "%.900s: %s", path, strerror(errno));
                status = USM_EFAILED;
            } else
                return USM_OK;
        } else {
            snprintf(why, len, "%.900s: %s", path, strerror(errno));
            status = USM_EFAILED;
        }
    }
    if (status != USM_OK || !force)
        unlink(tmp);
    return status;
}

int usm_outfile_lock(const char *path, char *why, size_t len, int *busy)
{
    char dir[USM_OUTFILE_PATH], lock[USM_OUTFILE_PATH];
    const char *base;
    int fd;
    *busy = 0;
    if (split(path, dir, &base) != 0 ||
        snprintf(lock, sizeof lock, "%.*s.%s.usm-lock", (int)(base - path), path, base) >=
            (int)sizeof lock) {
        snprintf(why, len, "%.200s: path too long", path);
        return -1;
    }
    if ((fd = open(lock, O_RDWR | O_CREAT | O_NOFOLLOW | O_CLOEXEC, 0666)) < 0) {
        snprintf(why, len, "%.900s: %s", lock, strerror(errno));
        return -1;
    }
    if (flock(fd, LOCK_EX | LOCK_NB) != 0) {
        *busy = errno == EWOULDBLOCK;
        snprintf(why, len, "%.900s: %s", path,
                 *busy ? "another run is using it (wait for it to end, or use another file)"
                       : strerror(errno));
        close(fd);
        return -1;
    }
    return fd;
}

/* ---- output directories -------------------------------------------------------------- */

/* Whether the text at s is PID followed by end ("" or ".old") and that
 * process is gone (ours is alive). */
static int dead_pid(const char *s, int old_too)
{
    char *end;
    const long pid = strtol(s, &end, 10);
    return pid > 0 && (*end == '\0' || (old_too && strcmp(end, ".old") == 0)) &&
           pid != (long)getpid() && kill((pid_t)pid, 0) != 0 && errno == ESRCH;
}

int usm_outfile_beside(char buf[USM_OUTFILE_PATH], const char *path, const char *suffix)
{
    size_t n = strlen(path);
    while (n > 1 && path[n - 1] == '/')
        --n;
    size_t plen = n;
    while (plen > 0 && path[plen - 1] != '/')
        --plen;
    const int w = snprintf(buf, USM_OUTFILE_PATH, "%.*s.%.*s%s", (int)plen, path,
                           (int)(n - plen), path + plen, suffix);
    return n == plen || w < 0 || w >= USM_OUTFILE_PATH ? -1 : 0;
}

void usm_outfile_remove_dir(const char *dir, int (*drop)(const char *name))
{
    DIR *d = opendir(dir);
    struct dirent *e;
    if (!d)
        return;
    while ((e = readdir(d)))
        if (strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0 &&
            (!drop || drop(e->d_name)))
            unlinkat(dirfd(d), e->d_name, 0);
    closedir(d);
    rmdir(dir);
}

void usm_outfile_clean_stages(const char *path, int (*drop)(const char *name))
{
    char prefix[USM_OUTFILE_PATH], parent[USM_OUTFILE_PATH], p[USM_OUTFILE_PATH];
    if (usm_outfile_beside(prefix, path, USM_OUTFILE_STAGE) != 0)
        return;
    const char *slash = strrchr(prefix, '/');
    const char *base = slash ? slash + 1 : prefix;
    if (slash)
        snprintf(parent, sizeof parent, "%.*s", slash == prefix ? 1 : (int)(slash - prefix),
                 prefix);
    else
        snprintf(parent, sizeof parent, ".");
    DIR *d = opendir(parent);
    struct dirent *e;
    if (!d)
        return;
    while ((e = readdir(d)))
        if (strncmp(e->d_name, base, strlen(base)) == 0 &&
            dead_pid(e->d_name + strlen(base), 1) &&
            snprintf(p, sizeof p, "%s/%s", parent, e->d_name) < (int)sizeof p)
            usm_outfile_remove_dir(p, drop);
    closedir(d);
}
