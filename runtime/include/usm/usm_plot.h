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
 * PREFIX.gp/.png/.svg/.log exists, not even as a dangling symlink (or force);
 * USM_EINPUT with "--plot FILE: exists..." otherwise.  PREFIX names files,
 * so a PREFIX whose last component is empty, "." or "..", or that is an
 * existing directory ("--plot ." would write the hidden ..gp; "--plot dir"
 * means files in dir, which PREFIX does not do) is refused: "--plot PREFIX:
 * names a directory...".  Every file is
 * written whole or not at all (usm_io_create), and with force a symlink is
 * replaced, never written through. */
int usm_plot_check(const char *prefix, int force, char msg[USM_IO_MSG_LEN]);

/* The most files one PREFIX names (usm_plot_files). */
#define USM_PLOT_MAX_FILES 5

/* The files `--plot PREFIX` writes into files[0..]: PREFIX.csv when csv
 * (usm sweep, map, simulate --spectrum), then PREFIX.gp, .png, .svg and
 * .log; their count, or -1 when PREFIX is too long.  For
 * usm_io_check_distinct against a run's other outputs. */
int usm_plot_files(const char *prefix, int csv,
                   char files[USM_PLOT_MAX_FILES][USM_IO_PATH_LEN]);

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

/* PREFIX.csv written whole by write(out, data) (0, or -1 on a write error)
 * through usm_io_create / usm_io_commit: never replacing a file that
 * appeared since usm_plot_csv_check unless force, never half-written.
 * USM_OK; USM_EINPUT when the file cannot be created, USM_EFAILED on a write
 * error; with a one-line msg starting "--plot ". */
int usm_plot_csv_write(const char *prefix, int force, int (*write)(FILE *out, const void *data),
                       const void *data, char msg[USM_IO_MSG_LEN]);

#ifdef __cplusplus
}
#endif

#endif /* USM_PLOT_H */
