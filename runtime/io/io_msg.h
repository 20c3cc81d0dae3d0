/* io_msg.h: messages of the library's file readers and writers (internal).
 * They name a file or a field, so they get more room than USM_MSG_LEN. */
#ifndef USM_IO_MSG_H
#define USM_IO_MSG_H

#include <stdarg.h>
#include <stdio.h>

#include "usm_io.h" /* USM_IO_MSG_LEN */

#if defined(__GNUC__)
#define USM_IO_PRINTF(fmt, args) __attribute__((format(printf, fmt, args)))
#else
#define USM_IO_PRINTF(fmt, args)
#endif

/* snprintf into a USM_IO_MSG_LEN buffer. */
static inline void usm_io_msg(char msg[USM_IO_MSG_LEN], const char *fmt, ...) USM_IO_PRINTF(2, 3);
static inline void usm_io_msg(char msg[USM_IO_MSG_LEN], const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, USM_IO_MSG_LEN, fmt, ap);
    va_end(ap);
}

/* Create the file at path for writing, never replacing one that exists
 * unless force (the check and the creation are one step: O_EXCL).  NULL with
 * "PATH: reason" in msg and *status USM_EINPUT (exists, cannot be created) or
 * USM_EFAILED. */
FILE *usm_io_create(const char *path, int force, char msg[USM_IO_MSG_LEN], int *status);

#endif /* USM_IO_MSG_H */
