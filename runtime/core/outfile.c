/* Files that appear whole or not at all (outfile.h). */
#define _GNU_SOURCE /* renameat2 */

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

/* What a directory entry of mode m is, for a message: usm writes regular
 * files only, never into a pipe (the open would block until a reader came,
 * the data go to whoever reads) or a device. */
static const char *not_regular(mode_t m)
{
    return S_ISFIFO(m)   ? "is a named pipe (FIFO)"
           : S_ISCHR(m)  ? "is a character device"
           : S_ISBLK(m)  ? "is a block device"
           : S_ISSOCK(m) ? "is a socket"
                         : "is not a regular file";
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
        if (S_ISDIR(st.st_mode)) {
            snprintf(why, len, "%.900s: is a directory", path);
            return USM_EINPUT;
        }
        if (!S_ISREG(st.st_mode) && !S_ISLNK(st.st_mode)) {
            /* with --force too: replacing a pipe or device node is never what was meant */
            snprintf(why, len, "%.900s: %s; usm writes regular files only (refusing to write "
                     "to it or replace it)", path, not_regular(st.st_mode));
            return USM_EINPUT;
        }
        if (!force) {
            snprintf(why, len, "%.900s: %s", path,
                     S_ISLNK(st.st_mode)
                         ? "is a symbolic link; refusing to write through it (use --force to "
                           "replace the link itself)"
                         : "exists; refusing to overwrite it (use --force)");
            return USM_EINPUT;
        }
        /* force: a symlink is replaced by the new file, whatever it points to */
    } else if (errno != ENOENT) {
        snprintf(why, len, "%.900s: %s", path, strerror(errno));
        return USM_EINPUT;
    }
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
 * run's); a live process's are left alone, and so is anything usm cannot
 * have made: not a regular file, or another user's.  unlinkat removes the
 * name itself, never a symlink's target. */
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
        struct stat st;
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
        if (!dead_pid(num, 0) || fstatat(dirfd(d), n, &st, AT_SYMLINK_NOFOLLOW) != 0 ||
            !S_ISREG(st.st_mode) || st.st_uid != geteuid())
            continue;
        unlinkat(dirfd(d), n, 0);
    }
    closedir(d);
}

int usm_outfile_open(const char *path, int force, char tmp[USM_OUTFILE_PATH], char *why,
                     size_t len, int *status)
{
    char dir[USM_OUTFILE_PATH];
    const char *base;
    struct timespec ts;
    *status = usm_outfile_check(path, force, why, len);
    if (*status != USM_OK)
        return -1;
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

int usm_outfile_lock(const char *path, char *why, size_t len, int *input)
{
    char dir[USM_OUTFILE_PATH], lock[USM_OUTFILE_PATH];
    const char *base;
    struct stat st;
    int fd;
    *input = 1;
    if (split(path, dir, &base) != 0 ||
        snprintf(lock, sizeof lock, "%.*s.%s.usm-lock", (int)(base - path), path, base) >=
            (int)sizeof lock) {
        snprintf(why, len, "%.200s: path too long", path);
        return -1;
    }
    /* O_NONBLOCK: a pipe planted there must not hang the run */
    if ((fd = open(lock, O_RDWR | O_CREAT | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC, 0666)) < 0) {
        const int e = errno;
        const char *r = e == ELOOP    ? "is a symbolic link, not followed (remove it)"
                        : e == EISDIR ? "is a directory (remove it)"
                                      : strerror(e);
        *input = !(e == ENOSPC || e == EIO || e == EMFILE || e == ENFILE || e == ENOMEM);
        snprintf(why, len, "%.900s: its lock file %s%s%s", path, lock + (base - path),
                 e == ELOOP || e == EISDIR ? " " : ": ", r);
        return -1;
    }
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        const int bad = errno;
        snprintf(why, len, "%.900s: its lock file %s %s (remove it)", path, lock + (base - path),
                 fstat(fd, &st) != 0 ? strerror(bad) : not_regular(st.st_mode));
        close(fd);
        return -1;
    }
    if (flock(fd, LOCK_EX | LOCK_NB) != 0) {
        const int busy = errno == EWOULDBLOCK;
        *input = busy;
        snprintf(why, len, "%.900s: %s", path,
                 busy ? "another run is using it (wait for it to end, or use another file)"
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

/* Remove the directory name in the directory open at pfd, as
 * usm_outfile_remove_dir.  Entered only through a descriptor opened with
 * O_DIRECTORY|O_NOFOLLOW, so a symlink is never followed (its target's
 * contents stay as they are): a symlink is itself removed, another kind of
 * file left.  mine: only a directory of ours (st_uid), for a stage found by
 * its name rather than made by this run. */
static void remove_dir_at(int pfd, const char *name, int (*drop)(const char *name), int mine)
{
    struct stat st;
    const int fd = openat(pfd, name, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    if (fd < 0) {
        if (fstatat(pfd, name, &st, AT_SYMLINK_NOFOLLOW) == 0 && S_ISLNK(st.st_mode))
            unlinkat(pfd, name, 0);
        return;
    }
    DIR *d = fstat(fd, &st) == 0 && (!mine || st.st_uid == geteuid()) ? fdopendir(fd) : NULL;
    struct dirent *e;
    if (!d) {
        close(fd);
        return;
    }
    /* usm puts regular files there (and the temporaries that become them); a
     * symlink is unlinked as a name, a directory or pipe is not usm's */
    while ((e = readdir(d)))
        if (strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0 &&
            (!drop || drop(e->d_name)) &&
            fstatat(dirfd(d), e->d_name, &st, AT_SYMLINK_NOFOLLOW) == 0 &&
            (S_ISREG(st.st_mode) || S_ISLNK(st.st_mode)))
            unlinkat(dirfd(d), e->d_name, 0);
    closedir(d);
    unlinkat(pfd, name, AT_REMOVEDIR); /* fails, keeping it, when anything is left */
}

/* Open path's parent directory (its last component in *base); -1 when
 * path has none. */
static int open_parent(const char *path, char parent[USM_OUTFILE_PATH], const char **base)
{
    size_t n = strlen(path);
    while (n > 1 && path[n - 1] == '/')
        --n;
    if (n >= USM_OUTFILE_PATH)
        return -1;
    memcpy(parent, path, n);
    parent[n] = '\0';
    char *slash = strrchr(parent, '/');
    if (!slash) {
        *base = parent;
        return open(".", O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    }
    *slash = '\0';
    *base = slash + 1;
    if (!**base)
        return -1;
    return open(slash == parent ? "/" : parent, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
}

void usm_outfile_remove_dir(const char *dir, int (*drop)(const char *name))
{
    char buf[USM_OUTFILE_PATH];
    const char *base;
    const int pfd = open_parent(dir, buf, &base);
    if (pfd < 0)
        return;
    if (strcmp(base, ".") != 0 && strcmp(base, "..") != 0)
        remove_dir_at(pfd, base, drop, 0);
    close(pfd);
}

void usm_outfile_clean_stages(const char *path, int (*drop)(const char *name))
{
    char prefix[USM_OUTFILE_PATH], buf[USM_OUTFILE_PATH];
    const char *base;
    if (usm_outfile_beside(prefix, path, USM_OUTFILE_STAGE) != 0)
        return;
    const int pfd = open_parent(prefix, buf, &base);
    DIR *d = pfd < 0 ? NULL : fdopendir(pfd);
    struct dirent *e;
    if (!d) {
        if (pfd >= 0)
            close(pfd);
        return;
    }
    const size_t blen = strlen(base);
    while ((e = readdir(d)))
        if (strncmp(e->d_name, base, blen) == 0 && dead_pid(e->d_name + blen, 1))
            remove_dir_at(dirfd(d), e->d_name, drop, 1);
    closedir(d);
}

int usm_outfile_replace_link(const char *from, const char *link)
{
    struct stat st;
    if (renameat2(AT_FDCWD, from, AT_FDCWD, link, RENAME_EXCHANGE) == 0) {
        if (lstat(from, &st) == 0 && S_ISLNK(st.st_mode)) {
            unlink(from); /* the link, now at from: a name only, its target untouched */
            return 0;
        }
        /* not a link any more (replaced meanwhile): put both back, refuse */
        renameat2(AT_FDCWD, from, AT_FDCWD, link, RENAME_EXCHANGE);
        errno = EEXIST;
        return -1;
    }
    /* a file system without the exchange: a moment without the name */
    if (lstat(link, &st) != 0 || !S_ISLNK(st.st_mode)) {
        errno = EEXIST;
        return -1;
    }
    if (unlink(link) != 0)
        return -1;
    return rename(from, link);
}

void usm_outfile_unstage(char *msg, size_t len, const char *stage, const char *path)
{
    char out[USM_OUTFILE_PATH];
    size_t o = 0;
    const size_t fl = strlen(stage), tl = strlen(path);
    if (!fl || len == 0)
        return;
    for (const char *s = msg; *s && o + 1 < sizeof out && o + 1 < len;) {
        if (strncmp(s, stage, fl) == 0 && o + tl + 1 < sizeof out && o + tl + 1 < len) {
            memcpy(out + o, path, tl);
            o += tl;
            s += fl;
        } else
            out[o++] = *s++;
    }
    out[o] = '\0';
    memcpy(msg, out, o + 1);
}
