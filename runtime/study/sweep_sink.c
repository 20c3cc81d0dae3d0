/* The names of a sweep's events and values (sweep_sink.h). */
#include <stdio.h>
#include <string.h>

#include "sweep_sink.h"

const char *usm_event_name(usm_event_type type)
{
    switch (type) {
    case USM_EVENT_FOLD:
        return "fold";
    case USM_EVENT_STICK_LIMIT:
        return "stick_limit";
    case USM_EVENT_FRICTION_SATURATION:
        return "friction_saturation";
    case USM_EVENT_STABILITY_CHANGE:
        return "stability_change";
    case USM_EVENT_TILT_ZERO:
        return "tilt_zero";
    case USM_EVENT_RANGE_END:
        return "range_end";
    case USM_EVENT_STALL:
        return "stall";
    case USM_EVENT_MAXIMUM:
        return "maximum";
    case USM_EVENT_MINIMUM:
        return "minimum";
    case USM_EVENT_CROSSING:
        return "crossing";
    case USM_EVENT_OPERATING_POINT_JUMP:
        return "operating_point_jump";
    }
    return "unknown";
}

const char *sweep_value_text(const usm_param_info *info, double value, char buf[64])
{
    const int unit = strcmp(info->unit, "1") != 0; /* a dimensionless value reads better bare */
    snprintf(buf, 64, "%s = %.10g%s%s", info->name, value, unit ? " " : "", unit ? info->unit : "");
    return buf;
}
