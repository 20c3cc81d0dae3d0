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

int cli_run_output(const usm_run *r, int json, int flags, cli_write write, const void *a)
{
    const int status = usm_run_status(r);
    const int json_anyway = json && (flags & CLI_JSON_ON_FAILURE) && usm_run_has_json(r);
    if (status != USM_OK && (!json_anyway || (flags & CLI_MESSAGE_ALWAYS)))
        cli_error("%s", usm_run_message(r));
    if (status != USM_OK && !json_anyway)
        return status;
    if ((json ? usm_run_write_json(r, stdout) : write(a, r, stdout)) != 0 || fflush(stdout) != 0 ||
        ferror(stdout)) {
        clearerr(stdout);
        cli_error("stdout: write error");
        return USM_EFAILED;
    }
    return status;
}

int cli_csv_write(FILE *out, const void *data)
{
    const cli_csv *c = data;
    return c->write(c->a, c->r, out);
}

int cli_plot_status(int rc, const char *msg)
{
    if (rc == USM_ENOSOLUTION) {
        cli_error("warning: %s", msg);
        return USM_OK;
    }
    if (rc != USM_OK) {
        cli_error("%s", msg);
        return rc == USM_EINPUT ? USM_EINPUT : USM_EFAILED;
    }
    return USM_OK;
}
