/* grow.h: the one way libusm grows an array (internal).
 *
 * A list that grows one element at a time (roots, events, samples, rows)
 * doubles its capacity, so that n appends cost O(n) copies in all.
 */
#ifndef USM_GROW_H
#define USM_GROW_H

#include <stddef.h>

/* Make the array *ptr of *cap elements of elem bytes hold at least need:
 * the capacity doubles (from 16 when 0) until it does, and the array is
 * reallocated once.  0, or -1 when memory is short or the size overflows;
 * then *ptr (still valid, still to be freed) and *cap are as they were.
 * ptr is the address of any object pointer, cast: (void **)&s->items. */
int usm_grow(void **ptr, size_t *cap, size_t need, size_t elem);

#endif /* USM_GROW_H */
