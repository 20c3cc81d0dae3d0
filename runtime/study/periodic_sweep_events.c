/* The event names, the event list, value text and stability_change builder
 * (kind, critical multiplier, squeal frequency, text) of a periodic sweep, shared by the
 * bilateral branch (periodic_sweep.c) and the orbits with separation
 * (periodic_sweep_hybrid.c): both append events, neither calls the other for it. */
#include "core/grow.h"
#include "periodic_sweep_state.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char *usm_pevent_name(usm_pevent_type type)
{
    switch (type) {
    case USM_PEVENT_CONTACT_LOSS: return "contact_loss";
    case USM_PEVENT_STICK_LOSS: return "stick_loss";
    case USM_PEVENT_FOLD: return "fold";
    case USM_PEVENT_STABILITY_CHANGE: return "stability_change";
    case USM_PEVENT_FRICTION_SATURATION: return "friction_saturation";
    case USM_PEVENT_CONTACT_REGAINED: return "contact_regained";
    case USM_PEVENT_GRAZING: return "grazing";
    case USM_PEVENT_BRANCH_SWITCH: return "branch_switch";
    }
    return "unknown";
}

const char *usm_crossing_name(usm_crossing_kind kind)
{
    switch (kind) {
    case USM_CROSSING_FOLD: return "fold";
    case USM_CROSSING_PERIOD_DOUBLING: return "period_doubling";
    case USM_CROSSING_NEIMARK_SACKER: return "neimark_sacker";
    case USM_CROSSING_NONE: break;
    }
    return "";
}

const char *usm_branch_end_how_name(usm_branch_end_how how)
{
    switch (how) {
    case USM_BRANCH_END_NEWTON: return "newton_fails";
    case USM_BRANCH_END_FOLD: return "fold";
    case USM_BRANCH_END_SEQUENCE: return "mode_sequence";
    case USM_BRANCH_END_NONE: break;
    }
    return "";
}

usm_periodic_event *psweep_event_add(usm_periodic_sweep *s, usm_pevent_type type, double v,
                                      const usm_periodic_result *orbit, const char *fmt, ...)
{
    if (usm_grow((void **)&s->ev, &s->cap, s->nev + 1, sizeof *s->ev) != 0)
        return NULL;
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
    /* not the limits of validity themselves: at stick_loss, contact_loss and
     * contact_regained the orbit sits on such a boundary, its validity on
     * either side by rounding (and a contact loss past the stick limit
     * would say either reason) */
    if (orbit && type != USM_PEVENT_STICK_LOSS && type != USM_PEVENT_CONTACT_LOSS &&
        type != USM_PEVENT_CONTACT_REGAINED)
        psweep_event_mark(e, orbit->validity);
    return e;
}

void psweep_event_mark(usm_periodic_event *e, usm_validity v)
{
    /* e.g. the 4-DOF Neimark-Sacker point at 8.62 % mode split, where the
     * bilateral orbit's contact has long opened: the text says so, not only
     * the orbit's `valid` */
    if (v == USM_VALID)
        return;
    const size_t len = strlen(e->what);
    snprintf(e->what + len, sizeof e->what - len, "; model invalid: %s", usm_validity_name(v));
}

void psweep_value_text(const usm_periodic_sweep *s, double v, char buf[96])
{
    /* no unit "1" after a ratio */
    snprintf(buf, 96, "%s = %.12g%s%s", s->over, v, strcmp(s->unit, "1") ? " " : "",
             strcmp(s->unit, "1") ? s->unit : "");
}

/* The non-cyclic multiplier of largest modulus, or -1. */
static int critical(const usm_floquet_result *f)
{
    int c = -1;
    for (int i = 0; i < f->n; ++i)
        if (!f->cyclic[i] && (c < 0 || hypot(f->re[i], f->im[i]) > hypot(f->re[c], f->im[c])))
            c = i;
    return c;
}

usm_periodic_event *psweep_stability_add(usm_periodic_sweep *s, double v,
                                         const usm_periodic_result *orbit,
                                         const usm_floquet_result *fl, double period,
                                         const char *subject, int located, int dir_up, int rising)
{
    char vt[96];
    const char *how = located ? "" : " (not located to tolerance: a trial orbit failed)";
    psweep_value_text(s, v, vt);
    const int c = critical(fl);
    const double re = c >= 0 ? fl->re[c] : NAN, im = c >= 0 ? fl->im[c] : NAN;
    const usm_crossing_kind kind = fabs(im) > USM_COMPLEX_PAIR_TOL * hypot(re, im)
                                       ? USM_CROSSING_NEIMARK_SACKER
                                   : re > 0 ? USM_CROSSING_FOLD
                                            : USM_CROSSING_PERIOD_DOUBLING;
    /* the emerging vibration's frequency, of the orbit's period there (a
     * sweep over f changes it) */
    const double squeal = kind == USM_CROSSING_NEIMARK_SACKER
                              ? usm_squeal_frequency(1.0 / period, re, im)
                              : NAN;
    char sq[64] = "";
    if (isfinite(squeal))
        snprintf(sq, sizeof sq, ", squeal frequency %.6g Hz", squeal);
    usm_periodic_event *e = psweep_event_add(
        s, USM_PEVENT_STABILITY_CHANGE, v, orbit,
        "max |lambda| = 1 at %s (%s: critical multiplier %.8f %+.8fi%s): %s %s as %s %s%s", vt,
        usm_crossing_name(kind), re, fabs(im), sq, subject,
        rising ? "loses stability" : "becomes stable", s->over,
        dir_up ? "increases" : "decreases", how);
    if (!e)
        return NULL;
    e->kind = kind;
    e->squeal_frequency = squeal;
    e->multiplier_re = re;
    e->multiplier_im = fabs(im);
    return e;
}
