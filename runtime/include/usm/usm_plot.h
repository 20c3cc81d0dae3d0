/* usm_plot.h: `--plot PREFIX` of usm simulate, sweep and map, for any
 * program: the data's CSV file beside a gnuplot script, and gnuplot run on
 * it.  The script is PREFIX.gp: the values the static script
 * data/plots/SCRIPT.gp reads, then that script; gnuplot writes PREFIX.png and
 * PREFIX.svg (a gnuplot that exits 0 without them is a failure).  gnuplot is
 * $USM_GNUPLOT, else "gnuplot" on the PATH.  Existing files are kept unless
 * force; messages name the file and the reason (USM_IO_MSG_LEN bytes).
 *
 * Thread safety: no global mutable state, but usm_plot_render starts gnuplot
 * as a child process and waits for any child (wait(2)): call it from one
 * thread at a time, while the program has no other child process running.
 * The other functions may be called from several threads at once on
 * distinct prefixes.
 */
#ifndef USM_PLOT_H
#define USM_PLOT_H

#include <stdio.h>

#include "usm_io.h" /* USM_IO_MSG_LEN */

#ifdef __cplusplus
extern "C" {
#endif

/* USM_OK when PREFIX is usable, its directory writable, and none of
 * PREFIX.gp/.png/.svg exists, not even as a dangling symlink (or force);
 * USM_EINPUT with "--plot FILE: exists..." otherwise.  Every file is
 * written whole or not at all (usm_io_create), and with force a symlink is
 * replaced, never written through. */
int usm_plot_check(const char *prefix, int force, char msg[USM_IO_MSG_LEN]);

/* `--plot PREFIX` of usm simulate, sweep and map (call usm_plot_check first,
 * then write the data).  Writes PREFIX.gp: the n assignments NAME = VALUE
 * the static script data/plots/SCRIPT.gp reads (prefix = 'PREFIX' always; a
 * value that is a number unquoted, e.g. mu0 = 0.3, else quoted, e.g.
 * csv = 'sweep.csv', xcol = 'T [N m]'), then that script; runs gnuplot on it
 * in the current directory (messages in PREFIX.log): PREFIX.png and
 * PREFIX.svg; `gnuplot PREFIX.gp` re-plots.  USM_OK; USM_ENOSOLUTION when
 * gnuplot is not installed; USM_EFAILED when it failed or did not write an
 * image; USM_EINPUT for a PREFIX that is not usable; with a one-line msg. */
int usm_plot_render(const char *script, const char *prefix, const char *const *names,
                    const char *const *values, int n, char msg[USM_IO_MSG_LEN]);

/* `--plot PREFIX` of usm sweep and usm map: the data file PREFIX.csv beside
 * the files usm_plot_check guards.  USM_OK when none of
 * PREFIX.csv/.gp/.png/.svg exists (or force), else USM_EINPUT with msg;
 * called before the computation. */
int usm_plot_csv_check(const char *prefix, int force, char msg[USM_IO_MSG_LEN]);

/* PREFIX.csv opened for writing by usm_io_create(out, ...) (never replacing
 * a file that appeared since usm_plot_csv_check unless force), or NULL with
 * msg; finish with usm_io_commit(out) or usm_io_abort(out). */
FILE *usm_plot_csv_open(usm_io_file *out, const char *prefix, int force,
                        char msg[USM_IO_MSG_LEN]);

#ifdef __cplusplus
}
#endif

#endif /* USM_PLOT_H */
