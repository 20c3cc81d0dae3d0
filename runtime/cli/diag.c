/* The usm command's error messages. */
#include "diag.h"

#include <stdarg.h>
#include <stdio.h>

#include "usm_run.h"

void cli_error(const char *fmt, ...)
{
    char line[CLI_MSG_LEN];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    for (char *c = line; *c; ++c)
        if ((unsigned char)*c < 0x20 || *c == 0x7f)
            *c = ' ';
    fprintf(stderr, "usm: %s\n", line);
}

void cli_msg(char msg[CLI_MSG_LEN], const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, CLI_MSG_LEN, fmt, ap);
    va_end(ap);
}

int cli_run_json(const usm_run *r)
{
    if (usm_run_write_json(r, stdout) != 0 || fflush(stdout) != 0 || ferror(stdout)) {
        clearerr(stdout);
        cli_error("stdout: write error");
        return USM_EFAILED;
    }
    return USM_OK;
}
