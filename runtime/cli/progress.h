/* progress.h: the one progress line of the usm command.
 *
 * A long command (map, tolerance) hands cli_progress_callback() to the
 * library (usm_progress.h) and calls cli_progress_end() as soon as the study
 * returns, before it prints anything else on stderr.  The line
 *   usm map: 480/1089 points (44%)  12.5/s  49 s left
 * is rewritten in place with \r on stderr, only when stderr is a terminal
 * and --quiet was not given, and erased at the end: a terminal keeps no
 * trace of it, and a redirected stderr never gets one.
 */
#ifndef USM_CLI_PROGRESS_H
#define USM_CLI_PROGRESS_H

#include <stdio.h>

#include "options.h"
#include "usm_progress.h"

typedef struct cli_progress {
    const char *name;  /* "usm map" */
    int on;            /* drawing: stderr is a terminal, no --quiet */
    int first;         /* no call yet */
    long done0;        /* done at the first call (resumed work: not in the rate) */
    double t0;         /* monotonic seconds of the first call */
    int width;         /* characters of the line on screen (0: none) */
    long total;        /* cli_progress_fraction: the count a fraction is of */
    const char *what;  /* cli_progress_fraction: what it counts ("points") */
    double last;       /* cli_progress_fraction: monotonic seconds of its last line */
} cli_progress;

/* name: the command as the line starts ("usm map"); quiet: --quiet given. */
void cli_progress_init(cli_progress *p, const char *name, int quiet);

/* The library's callback drawing into p (fn NULL when p is off). */
usm_progress cli_progress_callback(cli_progress *p);

/* For a study that reports a fraction done (usm_sweep_options, a
 * simulation's periods): the line of fraction * p->total p->what, redrawn at
 * most ten times a second but always at the end.  ctx: the cli_progress. */
void cli_progress_fraction(double fraction, void *ctx);

/* Erase the line, if one is on screen. */
void cli_progress_end(cli_progress *p);

/* If argv[*i] is --quiet, set *quiet and return CLI_OPT_TAKEN. */
int cli_quiet_option(int *quiet, int argc, char **argv, int *i);

/* The --quiet line of a usage text. */
void cli_quiet_usage(FILE *out);

#endif /* USM_CLI_PROGRESS_H */
