/* optimize_json.h: JSON pieces the optimizer's writers share (optimize_out.c;
 * robust_out.c).  Not installed. */
#ifndef USM_IO_OPTIMIZE_JSON_H
#define USM_IO_OPTIMIZE_JSON_H

#include <jansson.h>

#include "usm_optimize.h"

/* ["text", ...] of n texts; *ok = 0 when out of memory. */
json_t *usm_opt_json_strings(int n, const char (*text)[USM_OPT_TEXT_LEN], int *ok);
/* {NAME: value} of pb's varied parameters in p; *ok = 0 when out of memory. */
json_t *usm_opt_json_varied(const usm_opt_problem *pb, const usm_params *p, int *ok);

#endif /* USM_IO_OPTIMIZE_JSON_H */
