/* The envelope object: its life cycle, the results it holds (curves,
 * codimension-two points, regions) with their accessors, and the names of
 * the kinds and ends.  Below every computing file of the room (envelope.c,
 * envelope_periodic*.c, envelope_regions.c), which store into it through
 * env_add_codim2 and read the names.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/grow.h"
#include "envelope_internal.h"

const char *usm_envelope_kind_name(usm_envelope_kind kind)
{
    static const char *const names[] = {"tilt_zero", "fold",      "stick_limit",
                                        "stall",     "stability", "friction_saturation",
                                        "contact_loss", "stick_loss", "separation_fold",
                                        "separation_stability", "separation_grazing"};
    return (unsigned)kind < USM_ENVELOPE_NKINDS ? names[kind] : NULL;
}

const char *usm_envelope_end_name(usm_envelope_end end)
{
    static const char *const names[] = {"box", "tilt_zero", "range_end", "closed", "lost",
                                        "max_points", "corner"};
    return (unsigned)end <= USM_ENVELOPE_END_CORNER ? names[end] : NULL;
}

int env_add_codim2(usm_envelope *e, const char *type, const double *u, double px, double py,
                      size_t curve)
{
    /* found from both curves that meet: once */
    for (size_t k = 0; k < e->ncodim2; ++k) {
        const usm_envelope_codim2 *c = &e->codim2[k];
        if (fabs(c->x - px) <= 1e-6 * (e->hi[0] - e->lo[0]) &&
            fabs(c->y - py) <= 1e-6 * (e->hi[1] - e->lo[1]))
            return 0;
    }
    if (usm_grow((void **)&e->codim2, &e->codim2cap, e->ncodim2 + 1, sizeof *e->codim2) != 0)
        return -1;
    usm_envelope_codim2 *c = &e->codim2[e->ncodim2++];
    memset(c, 0, sizeof *c);
    snprintf(c->type, sizeof c->type, "%s", type);
    c->x = px;
    c->y = py;
    c->curve = curve;
    memcpy(c->u, u, sizeof(double) * (size_t)e->nu);
    return 0;
}

usm_envelope *usm_envelope_alloc(const usm_model *m)
{
    usm_envelope *e = calloc(1, sizeof *e);
    if (!e)
        return NULL;
    e->m = m;
    e->nu = m->nu;
    e->steady = usm_steady_alloc(m);
    e->fl = usm_floquet_alloc(m);
    if (!e->steady || !e->fl) {
        usm_envelope_free(e);
        return NULL;
    }
    return e;
}

void env_clear_result(usm_envelope *e)
{
    for (size_t c = 0; c < e->ncurves; ++c) {
        free(e->curves[c].xy);
        free(e->curves[c].u);
        free(e->curves[c].freq);
    }
    e->ncurves = e->nseeds = e->ncodim2 = e->nregions = 0;
    e->seeds_dropped = 0;
    free(e->label);
    e->label = NULL;
}

void usm_envelope_free(usm_envelope *e)
{
    if (!e)
        return;
    env_clear_result(e);
    free(e->curves);
    free(e->seeds);
    free(e->codim2);
    free(e->regions);
    usm_steady_free(e->steady);
    usm_floquet_free(e->fl);
    free(e);
}

const char *usm_envelope_message(const usm_envelope *e) { return e->msg; }
size_t usm_envelope_curve_count(const usm_envelope *e) { return e->ncurves; }
const usm_envelope_curve *usm_envelope_curve_at(const usm_envelope *e, size_t i)
{
    return i < e->ncurves ? &e->curves[i].pub : NULL;
}
size_t usm_envelope_codim2_count(const usm_envelope *e) { return e->ncodim2; }
const usm_envelope_codim2 *usm_envelope_codim2_at(const usm_envelope *e, size_t i)
{
    return i < e->ncodim2 ? &e->codim2[i] : NULL;
}
void usm_envelope_seed_counts(const usm_envelope *e, size_t *found, size_t *dropped)
{
    *found = e->nseeds;
    *dropped = e->seeds_dropped;
}

int env_xy_push(env_xy_buf *b, double px, double py)
{
    if (usm_grow((void **)&b->xy, &b->cap, 2 * (b->n + 1), sizeof(double)) != 0)
        return -1;
    b->xy[2 * b->n] = px;
    b->xy[2 * b->n + 1] = py;
    b->n++;
    return 0;
}

int env_keep_xy_curve(usm_envelope *e, int kind, env_xy_buf *b, usm_envelope_end e0,
                      usm_envelope_end e1)
{
    if (b->n < 2) {
        free(b->xy);
        memset(b, 0, sizeof *b);
        return 0;
    }
    if (usm_grow((void **)&e->curves, &e->curvecap, e->ncurves + 1, sizeof *e->curves) != 0)
        return -1;
    env_curve *cv = &e->curves[e->ncurves++];
    memset(cv, 0, sizeof *cv);
    cv->xy = b->xy;
    cv->pub.kind = (usm_envelope_kind)kind;
    cv->pub.npoints = b->n;
    cv->pub.xy = cv->xy;
    cv->pub.end[0] = e0;
    cv->pub.end[1] = e1;
    memset(b, 0, sizeof *b);
    return 0;
}
