/* periodic_internal.h: what the writers of a periodic orbit (io/periodic_out.c)
 * need of the shooting solver beyond usm_periodic.h.  Not installed; not part
 * of the API. */
#ifndef USM_PERIODIC_INTERNAL_H
#define USM_PERIODIC_INTERNAL_H

#include "usm_periodic.h"

/* The model w solves (usm_periodic_alloc's m). */
const usm_model *usm_periodic_model_of(const usm_periodic *w);

#endif /* USM_PERIODIC_INTERNAL_H */
