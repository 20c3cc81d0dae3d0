/* cvode_msg.h: CVODES' messages turned into the library's (internal).
 *
 * The library never prints: each CVODES object gets an error handler that
 * keeps the last message in a buffer of its owner, and return flags are named
 * with CVodeGetReturnFlagName, whose string is malloc'ed (freed here).
 */
#ifndef USM_CVODE_MSG_H
#define USM_CVODE_MSG_H

#include <stdio.h>
#include <stdlib.h>

#include <cvodes/cvodes.h>

/* The name of CVODES return flag `flag` ("CV_TOO_MUCH_WORK", ...) in buf. */
static inline const char *usm_cvode_flag_name(int flag, char *buf, size_t len)
{
    char *name = CVodeGetReturnFlagName(flag);
    if (name)
        snprintf(buf, len, "%s", name);
    else
        snprintf(buf, len, "CVODES flag %d", flag);
    free(name);
    return buf;
}

#endif /* USM_CVODE_MSG_H */
