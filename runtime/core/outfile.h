/* outfile.h: files that appear whole or not at all (internal; not
 * installed).  The one mechanism behind every single-file output of libusm
 * and the command: usm_io_create/usm_io_commit (io/io_file.c, usm_io.h) and
 * the tolerance checkpoint (write/tolerance_checkpoint.c).
 *
 * A file FINAL is written to a temporary beside it, DIR/.BASE.usm-PID-XXXXXX.part,
 * created with O_CREAT|O_EXCL|O_NOFOLLOW (never through a symlink, never
 * over a file), and renamed over FINAL only when whole.  Without force the
 * rename cannot replace anything (link(2), then unlink of the temporary):
 * a file or symlink that appeared meanwhile is kept and the write refused.
 * With force, rename(2) replaces the directory entry FINAL itself -- a
 * symlink there is replaced, its target is never written.  A pipe, device
 * or socket at FINAL is refused, with force too: usm never opens one for
 * writing (a pipe would block the run until a reader came).  A killed run
 * leaves at most a temporary, which a later usm_outfile_open in the same
 * directory removes once its process is gone.
 *
 * Messages are "PATH: reason" (no option name), into why[len].
 * Thread safety: no global mutable state. */
#ifndef USM_CORE_OUTFILE_H
#define USM_CORE_OUTFILE_H

#include <stddef.h>

#define USM_OUTFILE_PATH 4096

/* USM_OK when a file could be written at path now: its directory exists
 * and is writable, path is neither a directory nor a pipe, device or
 * socket, and (unless force) nothing is there -- neither a file nor a
 * symlink, dangling or not.  Else USM_EINPUT
 * with why.  Called before a computation, so that it does not fail late. */
int usm_outfile_check(const char *path, int force, char *why, size_t len);

/* Create the temporary for path (tmp: USM_OUTFILE_PATH bytes); an fd open
 * for writing, or -1 with why.  *status: USM_OK, USM_EINPUT (path not
 * usable, exists without force, directory missing or not writable) or
 * USM_EFAILED. */
int usm_outfile_open(const char *path, int force, char tmp[USM_OUTFILE_PATH], char *why,
                     size_t len, int *status);

/* Put the closed, complete temporary tmp in place as path; USM_OK, or
 * USM_EINPUT (path appeared meanwhile, without force) / USM_EFAILED with
 * why; the temporary is removed on failure. */
int usm_outfile_place(const char *tmp, const char *path, int force, char *why, size_t len);

/* ---- output directories (io/io_file.c usm_io_dir_*, report/report.c) ---------- */

/* A directory written whole is first a stage beside it: PARENT/.NAME +
 * USM_OUTFILE_STAGE + PID (+ ".old" for a report's old directory while it
 * is swapped out). */
#define USM_OUTFILE_STAGE ".usm-new-"

/* PARENT/.NAME + suffix for the directory path into buf (USM_OUTFILE_PATH
 * bytes); 0, or -1 when too long or path has no last component. */
int usm_outfile_beside(char buf[USM_OUTFILE_PATH], const char *path, const char *suffix);

/* Remove the regular files and symlinks of dir that drop(name) accepts
 * (every one when drop is NULL), then dir itself (kept when anything is
 * left).  dir's last component is never followed: entered only through
 * open(O_DIRECTORY|O_NOFOLLOW) and emptied with unlinkat on that
 * descriptor, so when it is a symlink the link itself is removed and its
 * target's contents stay as they are. */
void usm_outfile_remove_dir(const char *dir, int (*drop)(const char *name));

/* Remove (as usm_outfile_remove_dir) the stages of path whose process is
 * gone: runs that were killed.  Found by their names, so a stage is only
 * entered when it is a real directory of this user's (st_uid): a
 * directory anyone else planted under a stage's name is left alone. */
void usm_outfile_clean_stages(const char *path, int (*drop)(const char *name));

/* The directory (or file) from in place of the symlink link, the link
 * removed (renameat2 RENAME_EXCHANGE, then unlink of the link; without the
 * exchange unlink then rename): --force onto a symlink replaces the link,
 * never writes into its target.  0, or -1 with errno. */
int usm_outfile_replace_link(const char *from, const char *link);

/* Every occurrence of stage in msg (len bytes) replaced by path: a message
 * names the user's path, not the hidden stage its files are written in. */
void usm_outfile_unstage(char *msg, size_t len, const char *stage, const char *path);

/* An exclusive lock for the users of path: flock(2) on the lock file
 * DIR/.BASE.usm-lock beside it (created if missing, never through a
 * symlink; kept, since removing a lock file races), not on path itself,
 * which renames replace.  The descriptor (close it to unlock), or -1 with
 * why and *input = 1 for a refusal of the user's making (another process
 * holds the lock; the lock path is a symlink, a directory or not a regular
 * file; it cannot be created there), *input = 0 for a failure of the
 * system (no space, no descriptors). */
int usm_outfile_lock(const char *path, char *why, size_t len, int *input);

#endif /* USM_CORE_OUTFILE_H */
