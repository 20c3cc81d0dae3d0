/* Where the library's data files are (see data_dir.h). */
#define _POSIX_C_SOURCE 200809L

#include "data_dir.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#ifndef USM_SOURCE_DATA_DIR
#define USM_SOURCE_DATA_DIR "data"
#endif

static int try_path(char *buf, size_t len, const char *dir, const char *sub, const char *name)
{
    int n = snprintf(buf, len, "%s%s/%s", dir, sub, name);
    return n >= 0 && (size_t)n < len && access(buf, R_OK) == 0 ? 0 : -1;
}

int usm_data_path(const char *name, char *buf, size_t len)
{
    const char *env = getenv("USM_DATA_DIR");
    char exe[4096];
    ssize_t n;
    if (env && env[0] && try_path(buf, len, env, "", name) == 0)
        return 0;
    n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    if (n > 0) {
        char *slash;
        exe[n] = '\0';
        if ((slash = strrchr(exe, '/')) != NULL) {
            *slash = '\0';
            if (try_path(buf, len, exe, "/../share/usm", name) == 0)
                return 0;
        }
    }
#ifdef USM_INSTALL_DATA_DIR
    /* a program linked with the installed library, wherever it lives */
    if (try_path(buf, len, USM_INSTALL_DATA_DIR, "", name) == 0)
        return 0;
#endif
    return try_path(buf, len, USM_SOURCE_DATA_DIR, "", name);
}
