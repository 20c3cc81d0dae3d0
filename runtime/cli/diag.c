/* The usm command's error messages. */
#include "diag.h"

#include <stdarg.h>
#include <stdio.h>

#include "usm_io.h"
#include "usm_plot.h"
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

int cli_check_out_plot(const char *out, const char *plot, int force)
{
    char msg[CLI_MSG_LEN];
    if (out && usm_io_check(out, force, msg) != USM_OK) {
        cli_error("--out %s", msg);
        return USM_EINPUT;
    }
    if (plot && usm_plot_csv_check(plot, force, msg) != USM_OK) {
        cli_error("%s", msg);
        return USM_EINPUT;
    }
    if (out && plot) {
        char files[USM_PLOT_MAX_FILES][USM_IO_PATH_LEN];
        const char *paths[1 + USM_PLOT_MAX_FILES] = {out};
        const char *opts[1 + USM_PLOT_MAX_FILES] = {"--out"};
        const int m = usm_plot_files(plot, 1, files);
        for (int i = 0; i < m; ++i)
            paths[1 + i] = files[i], opts[1 + i] = "--plot";
        if (m < 0 || usm_io_check_distinct(paths, opts, 1 + m, msg) != USM_OK) {
            cli_error("%s", m < 0 ? "--plot: path too long" : msg);
            return USM_EINPUT;
        }
    }
    return USM_OK;
}
