/* The envelope's JSON (`usm envelope --json`) and CSV (usm_envelope.h).  The
 * CSV's comment lines are in SI units, named: --units converts columns only. */
#include <stdio.h>

#include "envelope/envelope_internal.h"
#include "io/csv_out.h"
#include "io/json_out.h"

static json_t *pair(double a, double b)
{
    json_t *p = json_array();
    if (p && (json_array_append_new(p, usm_json_real(a)) != 0 ||
              json_array_append_new(p, usm_json_real(b)) != 0)) {
        json_decref(p);
        return NULL;
    }
    return p;
}

static json_t *axis_json(const usm_envelope *e, int k)
{
    json_t *a = json_object();
    int ok = a != NULL;
    usm_json_put(a, "name", json_string(e->ax[k]->name), &ok);
    usm_json_put(a, "unit", json_string(e->ax[k]->unit), &ok);
    usm_json_put(a, "lo", usm_json_real(e->lo[k]), &ok);
    usm_json_put(a, "hi", usm_json_real(e->hi[k]), &ok);
    return usm_json_finish(a, ok);
}

static json_t *curve_json(const usm_envelope_curve *c)
{
    json_t *o = json_object(), *pts = json_array(), *ends = json_array();
    int ok = o && pts && ends;
    for (size_t i = 0; ok && i < c->npoints; ++i)
        ok = json_array_append_new(pts, pair(c->xy[2 * i], c->xy[2 * i + 1])) == 0;
    for (int k = 0; ok && k < 2; ++k)
        ok = json_array_append_new(ends, json_string(usm_envelope_end_name(c->end[k]))) == 0;
    usm_json_put(o, "kind", json_string(usm_envelope_kind_name(c->kind)), &ok);
    usm_json_put(o, "points", pts, &ok);
    usm_json_put(o, "ends", ends, &ok);
    return usm_json_finish(o, ok);
}

int usm_envelope_write_json(const usm_envelope *e, const usm_model *m, FILE *out)
{
    json_t *o = json_object(), *curves = json_array(), *regions = json_array(),
           *codim2 = json_array();
    int ok = o && curves && regions && codim2;
    for (size_t i = 0; ok && i < e->ncurves; ++i)
        ok = json_array_append_new(curves, curve_json(&e->curves[i].pub)) == 0;
    for (size_t i = 0; ok && i < e->nregions; ++i) {
        const usm_envelope_region *r = &e->regions[i];
        json_t *ro = json_object();
        int rok = ro != NULL;
        usm_json_put(ro, "class", json_string(r->class_name), &rok);
        usm_json_put(ro, "root", r->root >= 0 ? json_integer(r->root) : json_null(), &rok);
        usm_json_put(ro, "sample", pair(r->x, r->y), &rok);
        usm_json_put(ro, "roots", json_integer(r->roots), &rok);
        usm_json_put(ro, "cells", json_integer((json_int_t)r->cells), &rok);
        usm_json_put(ro, "message", json_string(r->message), &rok);
        ok = json_array_append_new(regions, usm_json_finish(ro, rok)) == 0;
    }
    for (size_t i = 0; ok && i < e->ncodim2; ++i) {
        const usm_envelope_codim2 *c = &e->codim2[i];
        json_t *co = json_object();
        int cok = co != NULL;
        usm_json_put(co, "type", json_string(c->type), &cok);
        usm_json_put(co, "point", pair(c->x, c->y), &cok);
        usm_json_put(co, "curve", json_integer((json_int_t)c->curve), &cok);
        usm_json_put(co, "theta", usm_json_real(c->u[e->m->u_theta]), &cok);
        ok = json_array_append_new(codim2, usm_json_finish(co, cok)) == 0;
    }
    usm_json_put(o, "model", json_string(m->name), &ok);
    usm_json_put(o, "x", axis_json(e, 0), &ok);
    usm_json_put(o, "y", axis_json(e, 1), &ok);
    usm_json_put(o, "parameters", usm_json_params(&e->p), &ok);
    usm_json_put(o, "curves", curves, &ok);
    usm_json_put(o, "regions", regions, &ok);
    usm_json_put(o, "codim2", codim2, &ok);
    usm_json_put(o, "seeds", json_integer((json_int_t)e->nseeds), &ok);
    usm_json_put(o, "seeds_on_traced_curves", json_integer((json_int_t)e->seeds_dropped), &ok);
    return usm_json_write(usm_json_finish(o, ok), out);
}

int usm_envelope_write_csv(const usm_envelope *e, FILE *out)
{
    const usm_csv_column cols[] = {{"curve", NULL}, {"kind", NULL}, {e->ax[0]->name, e->ax[0]->unit},
                                   {e->ax[1]->name, e->ax[1]->unit}};
    usm_csv_header(out, cols, 4);
    for (size_t c = 0; c < e->ncurves; ++c) {
        const usm_envelope_curve *cv = &e->curves[c].pub;
        for (size_t i = 0; i < cv->npoints; ++i) {
            fprintf(out, "%zu", c);
            usm_csv_text(out, 0, usm_envelope_kind_name(cv->kind));
            usm_csv_num(out, 0, cv->xy[2 * i]);
            usm_csv_num(out, 0, cv->xy[2 * i + 1]);
            fputc('\n', out);
        }
    }
    char bx[32], by[32];
    for (size_t k = 0; k < e->ncodim2; ++k)
        fprintf(out, "# codim2 %s at %s = %s %s, %s = %s %s\n", e->codim2[k].type,
                e->ax[0]->name, usm_shortest(bx, e->codim2[k].x), e->ax[0]->unit, e->ax[1]->name,
                usm_shortest(by, e->codim2[k].y), e->ax[1]->unit);
    for (size_t k = 0; k < e->nregions; ++k) {
        const usm_envelope_region *r = &e->regions[k];
        fprintf(out, "# region %zu %s", k, r->class_name);
        if (r->root >= 0) /* numbered from 1 as in every table for people; JSON's is 0-based */
            fprintf(out, " root #%d", r->root + 1);
        fprintf(out, " sample %s = %s %s, %s = %s %s (%zu cells)\n", e->ax[0]->name,
                usm_shortest(bx, r->x), e->ax[0]->unit, e->ax[1]->name, usm_shortest(by, r->y),
                e->ax[1]->unit, r->cells);
    }
    return ferror(out) ? -1 : 0;
}

/* The data of `usm envelope --plot`: the curves' rows with a blank line
 * after each curve (gnuplot draws each as a line of its own), the raster's
 * cells as rows of kind "region:CLASS" (the region's class, its root after
 * '#'), the regions' samples as "sample:CLASS" and the codimension-two
 * points as "codim2:TYPE". */
int usm_envelope_write_plot_csv(const usm_envelope *e, FILE *out)
{
    const usm_csv_column cols[] = {{"curve", NULL}, {"kind", NULL}, {e->ax[0]->name, e->ax[0]->unit},
                                   {e->ax[1]->name, e->ax[1]->unit}};
    char kind[64];
    usm_csv_header(out, cols, 4);
    for (size_t c = 0; c < e->ncurves; ++c) {
        const usm_envelope_curve *cv = &e->curves[c].pub;
        for (size_t i = 0; i < cv->npoints; ++i) {
            fprintf(out, "%zu", c);
            usm_csv_text(out, 0, usm_envelope_kind_name(cv->kind));
            usm_csv_num(out, 0, cv->xy[2 * i]);
            usm_csv_num(out, 0, cv->xy[2 * i + 1]);
            fputc('\n', out);
        }
        fputc('\n', out);
    }
    const int R = e->opt.raster;
    for (int j = 0; e->label && j < R; ++j)
        for (int i = 0; i < R; ++i) {
            const int l = e->label[j * R + i];
            if (l < 0)
                continue;
            const usm_envelope_region *r = &e->regions[l];
            snprintf(kind, sizeof kind, "region:%s", r->class_name);
            fputs("-1", out);
            usm_csv_text(out, 0, kind);
            usm_csv_num(out, 0, e->lo[0] + (e->hi[0] - e->lo[0]) * (i + 0.5) / R);
            usm_csv_num(out, 0, e->lo[1] + (e->hi[1] - e->lo[1]) * (j + 0.5) / R);
            fputc('\n', out);
        }
    for (size_t k = 0; k < e->nregions; ++k) {
        const usm_envelope_region *r = &e->regions[k];
        if (r->root >= 0)
            snprintf(kind, sizeof kind, "sample:%s #%d", r->class_name,
                     r->root + 1);
        else
            snprintf(kind, sizeof kind, "sample:%s", r->class_name);
        fputs("-1", out);
        usm_csv_text(out, 0, kind);
        usm_csv_num(out, 0, r->x);
        usm_csv_num(out, 0, r->y);
        fputc('\n', out);
    }
    for (size_t k = 0; k < e->ncodim2; ++k) {
        snprintf(kind, sizeof kind, "codim2:%s", e->codim2[k].type);
        fputs("-1", out);
        usm_csv_text(out, 0, kind);
        usm_csv_num(out, 0, e->codim2[k].x);
        usm_csv_num(out, 0, e->codim2[k].y);
        fputc('\n', out);
    }
    return ferror(out) ? -1 : 0;
}
