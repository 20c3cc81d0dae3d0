/* Output files (usm_io_create, usm_io.h). */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <fcntl.h>
#include <string.h>
#include <unistd.h>

#include "io_msg.h"
#include "usm.h"

FILE *usm_io_create(const char *path, int force, char msg[USM_IO_MSG_LEN], int *status)
{
    int fd = open(path, O_WRONLY | O_CREAT | (force ? O_TRUNC : O_EXCL), 0666);
    FILE *f;
    *status = USM_EINPUT;
    if (fd < 0) {
        if (errno == EEXIST)
            usm_io_msg(msg, "%s: exists; refusing to overwrite it (use --force)", path);
        else
            usm_io_msg(msg, "%s: %s", path, strerror(errno));
        return NULL;
    }
    if (!(f = fdopen(fd, "w"))) {
        usm_io_msg(msg, "%s: %s", path, strerror(errno));
        close(fd);
        *status = USM_EFAILED;
        return NULL;
    }
    *status = USM_OK;
    return f;
}
