/* plot_run.h: running gnuplot on the static scripts of data/plots/ (the
 * report's figures; `--plot PREFIX` of usm sweep, map and simulate: usm_plot.h).
 *
 * gnuplot is $USM_GNUPLOT, else "gnuplot" on the PATH.  Every script NAME.gp
 * must write NAME.png and NAME.svg (images of an earlier run are deleted
 * first): a gnuplot that exits 0 without them is a failure too. */
#ifndef USM_PLOT_RUN_H
#define USM_PLOT_RUN_H

#include "io_msg.h"
#include "usm_plot.h"

/* Run gnuplot on STEM.gp for each of the n stems (up to `jobs` at a time)
 * in directory dir, its messages written to log_path; then require
 * dir/STEM.png and dir/STEM.svg.  USM_OK; USM_ENOSOLUTION when gnuplot is
 * not installed; USM_EFAILED when it failed or did not write an image; with
 * a one-line msg. */
int usm_gnuplot_run(const char *dir, const char *const *stems, int n, int jobs,
                    const char *log_path, char msg[USM_IO_MSG_LEN]);

#endif /* USM_PLOT_RUN_H */
