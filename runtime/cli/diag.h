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

/* The run's --json object (usm_run_write_json) on stdout, flushed: USM_OK,
 * or USM_EFAILED after "stdout: write error", reported here once so that
 * main's final check (after clearerr) does not repeat it. */
struct usm_run;
int cli_run_json(const struct usm_run *r);

/* snprintf into a CLI_MSG_LEN buffer. */
void cli_msg(char msg[CLI_MSG_LEN], const char *fmt, ...) CLI_PRINTF(2, 3);

#endif /* USM_CLI_DIAG_H */
