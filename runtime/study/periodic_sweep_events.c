/* The event list and value text of a periodic sweep, shared by the bilateral
 * branch (periodic_sweep.c) and the orbits with separation
 * (periodic_sweep_hybrid.c): both append events, neither calls the other for it. */
#include "periodic_sweep_state.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

usm_periodic_event *psweep_event_add(usm_periodic_sweep *s, usm_pevent_type type, double v,
                                      const usm_periodic_result *orbit, const char *fmt, ...)
{
    if (s->nev == s->cap) {
        size_t cap = s->cap ? 2 * s->cap : 8;
        usm_periodic_event *e = realloc(s->ev, cap * sizeof *e);
        if (!e)
            return NULL;
        s->ev = e;
        s->cap = cap;
    }
    usm_periodic_event *e = &s->ev[s->nev++];
    memset(e, 0, sizeof *e);
    e->type = type;
    e->value = v;
    e->squeal_frequency = NAN;
    if (orbit) {
        e->has_orbit = 1;
        e->orbit = *orbit;
    }
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(e->what, sizeof e->what, fmt, ap);
    va_end(ap);
    return e;
}

void psweep_value_text(const usm_periodic_sweep *s, double v, char buf[96])
{
    /* no unit "1" after a ratio */
    snprintf(buf, 96, "%s = %.12g%s%s", s->over, v, strcmp(s->unit, "1") ? " " : "",
             strcmp(s->unit, "1") ? s->unit : "");
}
