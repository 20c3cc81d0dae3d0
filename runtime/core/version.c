/* Versions of the library and of the generator of its kernels.  usm.h refuses
 * to compile against kernels of another generator major version. */
#include "usm.h"

#ifndef USM_VERSION
#define USM_VERSION "unknown" /* CMake defines it; a bare `gcc -c` does not */
#endif

const char *usm_version(void) { return USM_VERSION; }

const char *usm_generator_version(void) { return USM_GENERATOR_VERSION; }
