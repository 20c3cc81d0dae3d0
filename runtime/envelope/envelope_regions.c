/* The regions between the envelope's curves: the box rastered, the cells a
 * curve crosses removed, the rest split into 4-connected regions, each
 * classified at its cell farthest from the curves and the box's sides by
 * usm_point_evaluate_op, the function `usm map` classifies its cells with,
 * so that the two cannot disagree at a point. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/grow.h"
#include "envelope_internal.h"

/* Samples per cell side along a curve's segment, so that no crossed cell is
 * skipped. */
#define SEG_SAMPLES 4.0

static int cell_of(const usm_envelope *e, double x, double y, int *i, int *j)
{
    const int R = e->opt.raster;
    const double fx = (x - e->lo[0]) / (e->hi[0] - e->lo[0]),
                 fy = (y - e->lo[1]) / (e->hi[1] - e->lo[1]);
    if (!(fx >= 0 && fx <= 1 && fy >= 0 && fy <= 1))
        return -1;
    *i = fx >= 1 ? R - 1 : (int)(fx * R);
    *j = fy >= 1 ? R - 1 : (int)(fy * R);
    return 0;
}

static void mark_curves(usm_envelope *e, int *label)
{
    const int R = e->opt.raster;
    for (size_t c = 0; c < e->ncurves; ++c) {
        const usm_envelope_curve *cv = &e->curves[c].pub;
        for (size_t k = 0; k < cv->npoints; ++k) {
            const double *a = cv->xy + 2 * k, *b = k + 1 < cv->npoints ? a + 2 : a;
            const double dx = (b[0] - a[0]) / (e->hi[0] - e->lo[0]) * R,
                         dy = (b[1] - a[1]) / (e->hi[1] - e->lo[1]) * R;
            const int ns = 1 + (int)(SEG_SAMPLES * sqrt(dx * dx + dy * dy));
            for (int s = 0; s <= ns; ++s) {
                int i, j;
                const double t = (double)s / ns;
                if (cell_of(e, a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), &i, &j) == 0)
                    label[j * R + i] = -1;
            }
        }
    }
}

static int classify(usm_envelope *e, usm_envelope_region *r)
{
    if (e->m->imperfect)
        return env_periodic_classify(e, r);
    usm_point pt;
    usm_params q = e->p;
    *usm_params_field(&q, e->ax[0]) = r->x;
    *usm_params_field(&q, e->ax[1]) = r->y;
    const int rc = usm_point_evaluate_op(e->steady, e->fl, e->m, &q, e->opt.t0, &e->opt.floquet,
                                         &e->opt.op, &pt);
    if (rc != USM_OK) {
        snprintf(e->msg, sizeof e->msg, "%s", pt.error);
        return rc;
    }
    r->cls = pt.op.cls;
    snprintf(r->class_name, sizeof r->class_name, "%s", usm_point_op_class_name(r->cls));
    r->root = pt.op.index;
    r->roots = pt.exists ? pt.roots : 0;
    snprintf(r->message, sizeof r->message, "%s", pt.op.message);
    return USM_OK;
}

int env_regions(usm_envelope *e)
{
    const int R = e->opt.raster;
    const size_t nc = (size_t)R * (size_t)R;
    int *label = malloc(nc * sizeof *label), *dist = malloc(nc * sizeof *dist),
        *queue = malloc(nc * sizeof *queue);
    int rc = USM_OK;
    if (!label || !dist || !queue) {
        rc = USM_EFAILED;
        goto done;
    }
    for (size_t k = 0; k < nc; ++k)
        label[k] = -2; /* not yet visited */
    mark_curves(e, label);
    /* distance (in cells, 4-neighbour steps) to a curve's cell or the box's side */
    size_t head = 0, tail = 0;
    for (int j = 0; j < R; ++j)
        for (int i = 0; i < R; ++i) {
            const int k = j * R + i;
            const int border = 1 + (int)fmin(fmin(i, R - 1 - i), fmin(j, R - 1 - j));
            dist[k] = label[k] == -1 ? 0 : border;
            if (label[k] == -1)
                queue[tail++] = k;
        }
    static const int di[4] = {1, -1, 0, 0}, dj[4] = {0, 0, 1, -1};
    while (head < tail) {
        const int k = queue[head++], i = k % R, j = k / R;
        for (int d = 0; d < 4; ++d) {
            const int ii = i + di[d], jj = j + dj[d];
            if (ii < 0 || jj < 0 || ii >= R || jj >= R)
                continue;
            const int kk = jj * R + ii;
            if (dist[kk] > dist[k] + 1) {
                dist[kk] = dist[k] + 1;
                queue[tail++] = kk;
            }
        }
    }
    /* the regions: flood fill of the unmarked cells */
    for (size_t start = 0; start < nc; ++start) {
        if (label[start] != -2)
            continue;
        const int id = (int)e->nregions;
        if (usm_grow((void **)&e->regions, &e->regioncap, e->nregions + 1, sizeof *e->regions) !=
            0) {
            rc = USM_EFAILED;
            goto done;
        }
        usm_envelope_region *r = &e->regions[e->nregions++];
        memset(r, 0, sizeof *r);
        head = tail = 0;
        queue[tail++] = (int)start;
        label[start] = id;
        int best = (int)start;
        while (head < tail) {
            const int k = queue[head++], i = k % R, j = k / R;
            r->cells++;
            if (dist[k] > dist[best])
                best = k;
            for (int d = 0; d < 4; ++d) {
                const int ii = i + di[d], jj = j + dj[d];
                if (ii < 0 || jj < 0 || ii >= R || jj >= R)
                    continue;
                const int kk = jj * R + ii;
                if (label[kk] == -2) {
                    label[kk] = id;
                    queue[tail++] = kk;
                }
            }
        }
        r->x = e->lo[0] + (e->hi[0] - e->lo[0]) * ((best % R) + 0.5) / R;
        r->y = e->lo[1] + (e->hi[1] - e->lo[1]) * ((best / R) + 0.5) / R;
        if ((rc = classify(e, r)) != USM_OK)
            goto done;
    }
    e->label = label;
    label = NULL;
done:
    if (rc == USM_EFAILED && !e->msg[0])
        snprintf(e->msg, sizeof e->msg, "out of memory for the regions");
    free(label);
    free(dist);
    free(queue);
    return rc;
}

size_t usm_envelope_region_count(const usm_envelope *e) { return e->nregions; }

const usm_envelope_region *usm_envelope_region_at(const usm_envelope *e, size_t i)
{
    return i < e->nregions ? &e->regions[i] : NULL;
}

int usm_envelope_region_of(const usm_envelope *e, double x, double y)
{
    int i, j;
    if (!e->label || cell_of(e, x, y, &i, &j) != 0)
        return -1;
    const int l = e->label[j * e->opt.raster + i];
    return l >= 0 ? l : -1;
}
