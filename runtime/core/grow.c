/* grow.c: the one way libusm grows an array (core/grow.h). */
#include "core/grow.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

int usm_grow(void **ptr, size_t *cap, size_t need, size_t elem)
{
    if (need <= *cap)
        return 0;
    size_t n = *cap ? *cap : 16;
    while (n < need) {
        if (n > SIZE_MAX / 2)
            return -1;
        n *= 2;
    }
    if (elem == 0 || n > SIZE_MAX / elem)
        return -1;
    /* through memcpy: *ptr is a double * or a struct's pointer, not a void * */
    void *old, *p;
    memcpy(&old, ptr, sizeof old);
    if (!(p = realloc(old, n * elem)))
        return -1;
    memcpy(ptr, &p, sizeof p);
    *cap = n;
    return 0;
}
