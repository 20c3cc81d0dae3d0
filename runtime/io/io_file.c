/* Output files that appear whole or not at all (usm_io_create, usm_io.h);
 * the mechanism is core/outfile.c's. */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <string.h>
#include <unistd.h>

#include "core/outfile.h"
#include "io_msg.h"
#include "usm.h"

int usm_io_check(const char *path, int force, char msg[USM_IO_MSG_LEN])
{
    return usm_outfile_check(path, force, msg, USM_IO_MSG_LEN);
}

FILE *usm_io_create(usm_io_file *out, const char *path, int force, char msg[USM_IO_MSG_LEN],
                    int *status)
{
    int fd;
    memset(out, 0, sizeof *out);
    out->force = force;
    if (strlen(path) >= sizeof out->path) {
        usm_io_msg(msg, "%.200s: path too long", path);
        *status = USM_EINPUT;
        return NULL;
    }
    strcpy(out->path, path);
    if ((fd = usm_outfile_open(path, force, out->tmp, msg, USM_IO_MSG_LEN, status)) < 0)
        return NULL;
    if (!(out->f = fdopen(fd, "w"))) {
        usm_io_msg(msg, "%s: %s", path, strerror(errno));
        close(fd);
        if (out->tmp[0])
            unlink(out->tmp);
        *status = USM_EFAILED;
        return NULL;
    }
    *status = USM_OK;
    return out->f;
}

int usm_io_commit(usm_io_file *out, char msg[USM_IO_MSG_LEN])
{
    int bad;
    if (!out->f) {
        usm_io_msg(msg, "%s: not open", out->path);
        return USM_EFAILED;
    }
    bad = fflush(out->f) != 0 || ferror(out->f);
    bad |= fclose(out->f) != 0;
    out->f = NULL;
    if (bad) {
        usm_io_msg(msg, "%s: write error", out->path);
        if (out->tmp[0])
            unlink(out->tmp);
        return USM_EFAILED;
    }
    return usm_outfile_place(out->tmp, out->path, out->force, msg, USM_IO_MSG_LEN);
}

void usm_io_abort(usm_io_file *out)
{
    if (!out->f)
        return;
    fclose(out->f);
    out->f = NULL;
    if (out->tmp[0])
        unlink(out->tmp);
}
