/* params_file.h: parameter files, a JSON object {"NAME": number, ...}. */
#ifndef USM_CLI_PARAMS_FILE_H
#define USM_CLI_PARAMS_FILE_H

#include <stddef.h>

#include "diag.h"
#include "usm.h"

/* Set the parameters named in file `path` in *p (others keep their value).
 * USM_OK, or USM_EINPUT with "PATH[:LINE:COLUMN]: reason" in msg. */
int cli_params_file_read(const char *path, usm_params *p, char msg[CLI_MSG_LEN]);

/* The same on the `len` bytes at `text` (which need not end in NUL); `path`
 * names them in messages.  *p is changed only when the whole text is good.
 * Numbers go through cli_parse_number(), the parser of --set. */
int cli_params_parse(const char *path, const char *text, size_t len, usm_params *p,
                     char msg[CLI_MSG_LEN]);

#endif /* USM_CLI_PARAMS_FILE_H */
