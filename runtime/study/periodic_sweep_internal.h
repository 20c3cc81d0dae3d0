/* periodic_sweep_internal.h: what the writers of a periodic sweep
 * (write/periodic_sweep_out.c) need of it beyond usm_periodic_sweep.h.  Not
 * installed; not part of the API. */
#ifndef USM_PERIODIC_SWEEP_INTERNAL_H
#define USM_PERIODIC_SWEEP_INTERNAL_H

#include "usm_periodic_sweep.h"

/* The model s sweeps (usm_periodic_sweep_alloc's m). */
const usm_model *usm_periodic_sweep_model(const usm_periodic_sweep *s);
/* The swept parameter's name and unit, as the last run was given them. */
const char *usm_periodic_sweep_over(const usm_periodic_sweep *s);
const char *usm_periodic_sweep_unit(const usm_periodic_sweep *s);

#endif /* USM_PERIODIC_SWEEP_INTERNAL_H */
