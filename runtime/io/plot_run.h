/* plot_run.h: running gnuplot on the static scripts of data/plots/ (the
 * report's figures, `usm sweep --plot PREFIX`, `usm map --plot PREFIX`).
 *
 * gnuplot is $USM_GNUPLOT, else "gnuplot" on the PATH.  Every script NAME.gp
 * must write NAME.png and NAME.svg (images of an earlier run are deleted
 * first): a gnuplot that exits 0 without them is a failure too. */
#ifndef USM_PLOT_RUN_H
#define USM_PLOT_RUN_H

#include <stdio.h>

#include "io_msg.h"

/* Run gnuplot on STEM.gp for each of the n stems (up to `jobs` at a time)
 * in directory dir, its messages written to log_path; then require
 * dir/STEM.png and dir/STEM.svg.  USM_OK; USM_ENOSOLUTION when gnuplot is
 * not installed; USM_EFAILED when it failed or did not write an image; with
 * a one-line msg. */
int usm_gnuplot_run(const char *dir, const char *const *stems, int n, int jobs,
                    const char *log_path, char msg[USM_IO_MSG_LEN]);

/* USM_OK when PREFIX is usable and none of PREFIX.gp/.png/.svg exists (or
 * force); USM_EINPUT with "--plot FILE: exists..." otherwise. */
int usm_plot_check(const char *prefix, int force, char msg[USM_IO_MSG_LEN]);

/* `--plot PREFIX` of usm simulate, sweep and map (call usm_plot_check first,
 * then write the data).  Writes PREFIX.gp: the n assignments NAME = VALUE
 * the static script data/plots/SCRIPT.gp reads (prefix = 'PREFIX' always; a
 * value that is a number unquoted, e.g. mu0 = 0.3, else quoted, e.g.
 * csv = 'sweep.csv', xcol = 'T [N m]'), then that script; runs gnuplot on it
 * in the current directory (messages in PREFIX.log): PREFIX.png and
 * PREFIX.svg; `gnuplot PREFIX.gp` re-plots.  Returns as usm_gnuplot_run, or
 * USM_EINPUT for a PREFIX that is not usable, with a one-line msg. */
int usm_plot_render(const char *script, const char *prefix, const char *const *names,
                    const char *const *values, int n, char msg[USM_IO_MSG_LEN]);

/* `--plot PREFIX` of usm sweep and usm map: the data file PREFIX.csv beside
 * the files usm_plot_check guards.  usm_plot_csv_check: USM_OK when none of
 * PREFIX.csv/.gp/.png/.svg exists (or force), else USM_EINPUT with msg;
 * called before the computation.  usm_plot_csv_open: PREFIX.csv opened for
 * writing (never replacing a file that appeared meanwhile unless force), or
 * NULL with msg. */
int usm_plot_csv_check(const char *prefix, int force, char msg[USM_IO_MSG_LEN]);
FILE *usm_plot_csv_open(const char *prefix, int force, char msg[USM_IO_MSG_LEN]);

#endif /* USM_PLOT_RUN_H */
