/* report_map.h: the stability map as a jansson value, for the report's
 * report.json (internal; the map's public API: usm_report_map.h). */
#ifndef USM_REPORT_MAP_INTERNAL_H
#define USM_REPORT_MAP_INTERNAL_H

#include <jansson.h>

#include "usm_report_map.h"

/* The `usm map --json` object, or NULL when out of memory. */
json_t *usm_report_map_json(const usm_report_map *map);

#endif /* USM_REPORT_MAP_INTERNAL_H */
