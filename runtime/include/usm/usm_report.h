/* usm_report.h: the paper reproduced (`usm report`): every number the paper
 * publishes beside the one computed, the motor characteristics, stability
 * maps, sensitivities and figures, written into a directory:
 *   report.json   every computed number by name
 *   report.md     rendered from the template data/report/report.md.in
 *   report.html   the same as one self-contained page (figures inline SVG)
 *   *.csv, *.gp   the figures' data and gnuplot scripts (PNG and SVG when
 *                 gnuplot runs: $USM_GNUPLOT, else "gnuplot" on the PATH)
 * The data files (the paper's published values, templates, static gnuplot
 * scripts) are found in $USM_DATA_DIR, else beside the installed command
 * (share/usm), else in the source tree the library was built from.
 *
 * Thread safety: no global mutable state; reports into distinct directories
 * may be written from distinct threads at the same time.
 */
#ifndef USM_REPORT_H
#define USM_REPORT_H

#include "usm.h"
#include "usm_io.h" /* USM_IO_MSG_LEN */
#include "usm_progress.h"

#ifdef __cplusplus
extern "C" {
#endif

/* How the report is computed. */
typedef struct usm_report_options {
    int quick;    /* coarser grids (seconds instead of minutes) */
    int threads;  /* worker threads, 1 to 64 */
    int plots;    /* run gnuplot on the scripts */
    int force;    /* replace files in dir that usm report did not write */
    usm_progress progress; /* the sections as they finish ("sections": the stationary
                              curves, the maps, the non-ideal motors, squeal, the
                              design, the files); {NULL}: silent */
} usm_report_options;

/* quick 0, threads 2, plots 1, force 0, progress silent. */
void usm_report_options_default(usm_report_options *opt);

/* USM_OK when opt is usable, else USM_EINPUT with "FIELD: reason" in msg
 * (threads outside 1 to 64). */
int usm_report_options_check(const usm_report_options *opt, char msg[USM_IO_MSG_LEN]);

/* Whether a report may be written into dir: it does not exist yet, or is a
 * writable directory holding no file of the report's names that an earlier
 * `usm report` did not write (unless opt->force).  Then dir is created (with
 * its parents) and marked as the report's (the file .usm-report, so that an
 * interrupted run is replaced by the next).  A symlink at dir is refused
 * unless opt->force, and then left as it is (usm_report_write replaces the
 * link; nothing is written into its target).  USM_OK, or USM_EINPUT with
 * "DIR: reason" in msg (or as usm_report_options_check). */
int usm_report_prepare_dir(const char *dir, const usm_report_options *opt,
                           char msg[USM_IO_MSG_LEN]);

/* Compute the report at parameters p and write it into dir (prepared by
 * usm_report_prepare_dir).  USM_OK; USM_ENOSOLUTION (no stationary solution
 * at p), USM_EINPUT (bad parameters or options, or another run writing into
 * dir: flock on dir), USM_EFAILED (a numerical failure, a file not written,
 * or the figures not rendered: then the report is still written, without
 * figures); with a one-line msg.  The report is written into a stage beside
 * dir and exchanged with it only when complete, so that dir holds the old
 * report or the new one, never a mix (in place, the old report.md/.html/.json
 * removed first, when dir holds other files or its parent is not writable);
 * every file through usm_io_create (no write through a symlink).  A dir
 * that is a symlink (accepted by usm_report_prepare_dir with force only) is
 * replaced as a link by the new directory, its target never written. */
int usm_report_write(const char *dir, const usm_params *p, const usm_report_options *opt,
                     char msg[USM_IO_MSG_LEN]);

#ifdef __cplusplus
}
#endif

#endif /* USM_REPORT_H */
