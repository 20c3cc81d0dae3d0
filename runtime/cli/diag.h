/* diag.h: the usm command's error messages. */
#ifndef USM_CLI_DIAG_H
#define USM_CLI_DIAG_H

#include <stdio.h>

/* Size of the message buffers the command passes around: room for a library
 * message (USM_MSG_LEN) plus the option or file name that prefixes it. */
#define CLI_MSG_LEN 1024

#if defined(__GNUC__)
#define CLI_PRINTF(fmt, args) __attribute__((format(printf, fmt, args)))
#else
#define CLI_PRINTF(fmt, args)
#endif

/* Print "usm: <message>" as exactly one line on stderr.  Scripts rely on one
 * line per error, so control characters (from file names, option values or
 * library messages) are replaced by spaces. */
void cli_error(const char *fmt, ...) CLI_PRINTF(1, 2);

/* The tail of a command's run (usm_run.h): on a failure its message; then
 * on stdout the --json object (json) or what write prints for people (a
 * table, a CSV), flushed.  flags: CLI_JSON_ON_FAILURE, the run's object
 * also of a failure (and then no message, unless CLI_MESSAGE_ALWAYS).
 * The run's status, or USM_EFAILED after "stdout: write error", reported
 * here once so that main's final check (after clearerr) does not repeat it. */
struct usm_run;
enum { CLI_JSON_ON_FAILURE = 1, CLI_MESSAGE_ALWAYS = 2 };
typedef int (*cli_write)(const void *a, const struct usm_run *r, FILE *out);
int cli_run_output(const struct usm_run *r, int json, int flags, cli_write write, const void *a);

/* The table or CSV of stdout again into a file: usm_plot_csv_write's writer
 * for PREFIX.csv of --plot, with data a cli_csv. */
typedef struct cli_csv {
    cli_write write;
    const void *a;
    const struct usm_run *r;
} cli_csv;
int cli_csv_write(FILE *out, const void *data);

/* The status of usm_plot_render: no gnuplot (USM_ENOSOLUTION) is a warning
 * (the data and script are there to plot later); another failure is msg and
 * USM_EINPUT or USM_EFAILED. */
int cli_plot_status(int rc, const char *msg);

/* Before a long computation: --out (when not NULL) and --plot PREFIX's files
 * (when not NULL) can be written (usm_io_check, usm_plot_csv_check), and
 * PREFIX.csv is not --out's file.  USM_OK, or USM_EINPUT with one line said. */
int cli_check_out_plot(const char *out, const char *plot, int force);

/* snprintf into a CLI_MSG_LEN buffer. */
void cli_msg(char msg[CLI_MSG_LEN], const char *fmt, ...) CLI_PRINTF(2, 3);

#endif /* USM_CLI_DIAG_H */
