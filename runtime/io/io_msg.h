/* io_msg.h: messages of the library's file readers and writers (internal).
 * They name a file or a field, so they get more room than USM_MSG_LEN. */
#ifndef USM_IO_MSG_H
#define USM_IO_MSG_H

#include <stdarg.h>
#include <stdio.h>

#include "usm_io.h" /* USM_IO_MSG_LEN, usm_io_create */

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

#endif /* USM_IO_MSG_H */
