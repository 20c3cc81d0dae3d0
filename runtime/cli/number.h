/* number.h: the one parser for numbers the user types, on the command line
 * (--set, --t0, ...) and in parameter files, so both accept and reject the
 * same texts with the same words. */
#ifndef USM_CLI_NUMBER_H
#define USM_CLI_NUMBER_H

#include <stddef.h>

#include "diag.h"

/* Parse the `len` characters at `text` as a finite double (strtod syntax,
 * the whole text used, no blanks).  Rejected, with "FIELD: \"text\" reason"
 * in msg and USM_EINPUT: not a number, nan/inf, overflow (|x| > DBL_MAX) and
 * underflow: a nonzero text whose value is below the smallest normal double
 * (DBL_MIN, 2.2e-308), whether it would round to a subnormal or to 0 -- a
 * value that small is a typing mistake, and silently using 0 instead is a
 * wrong answer.  Integers of any size are read as doubles. */
int cli_parse_number(const char *field, const char *text, size_t len, double *out,
                     char msg[CLI_MSG_LEN]);

#endif /* USM_CLI_NUMBER_H */
