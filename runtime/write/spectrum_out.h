/* spectrum_out.h: the simulation's spectrum in `usm simulate`'s summary
 * (spectrum_out.c; the CSV writer is public: usm_spectrum.h).  Internal
 * to io/. */
#ifndef USM_SPECTRUM_OUT_H
#define USM_SPECTRUM_OUT_H

#include <stdio.h>

#include <jansson.h>

#include "usm_spectrum.h"

/* The "spectrum" object of `usm simulate --json` (keys: docs/simulate.md);
 * csv: the spectrum's file (or NULL).  NULL when out of memory. */
json_t *usm_json_sim_spectrum(const usm_sim_spectrum_result *r, const char *csv);

/* The spectrum's lines in `usm simulate`'s table. */
void usm_sim_spectrum_write_table(const usm_sim_spectrum_result *r, const char *csv, FILE *out);

#endif /* USM_SPECTRUM_OUT_H */
