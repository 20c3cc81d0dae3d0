/* check.h: the assertion of the C tests.  CHECK(cond, fmt, ...) counts and
 * reports a failure with its place and keeps going, so one run shows every
 * failing check; main() returns failures != 0. */
#ifndef USM_TEST_CHECK_H
#define USM_TEST_CHECK_H

#include <stdio.h>

static int failures;

#define CHECK(cond, ...)                                                                           \
    do {                                                                                           \
        if (!(cond)) {                                                                             \
            ++failures;                                                                            \
            printf("FAIL %s:%d: ", __FILE__, __LINE__);                                            \
            printf(__VA_ARGS__);                                                                   \
            printf("\n");                                                                          \
        }                                                                                          \
    } while (0)

#endif /* USM_TEST_CHECK_H */
