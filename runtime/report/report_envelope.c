/* The operating envelope (report section "The operating envelope"): the
 * 3-DOF stationary envelope over the excitation frequency f (36-40 kHz) and
 * the preload F0 (0.1-2 N) with start-up from rest, as `usm envelope --x
 * f:36kHz:40kHz --y F0:0.1:2 --from-rest` computes it: the boundaries
 * continued as curves (tilt_zero, which is the start threshold in the 3-DOF
 * model, and the fold), the codimension-two point where they meet, and the
 * regions between them classified as `usm map` classifies a point.  The
 * curves are located to the continuation's tolerance, not to a grid cell;
 * the regions' raster only colours the figure.  --quick: a coarser raster
 * and fewer seed searches (the curves are the same, their seeds fewer). */
#include <math.h>
#include <string.h>

#include "io/data_dir.h"
#include "io/template.h"
#include "report_internal.h"
#include "usm_envelope.h"

int usm_report_compute_envelope(usm_report_data *d, char msg[USM_IO_MSG_LEN])
{
    struct usm_report_envelope *en = &d->envelope;
    const double t0 = usm_report_now();
    const usm_model *m = usm_model_find("3dof");
    usm_envelope_options o;
    memset(en, 0, sizeof *en);
    if (!m) {
        snprintf(en->note, sizeof en->note, "the 3-DOF model is not built");
        return USM_OK;
    }
    if (!(en->e = usm_envelope_alloc(m))) {
        usm_io_msg(msg, "out of memory");
        return USM_EFAILED;
    }
    usm_envelope_options_default(&o);
    o.x = (usm_envelope_axis){"f", 36e3, 40e3};
    o.y = (usm_envelope_axis){"F0", 0.1, 2.0};
    o.op.from_rest = 1;
    if (d->opt.quick) {
        o.raster = 60;
        o.lines = 1;
        o.nodes = 5;
    }
    en->raster = o.raster;
    if (usm_envelope_run(en->e, &d->params, &o) == USM_OK)
        en->ok = 1;
    else
        snprintf(en->note, sizeof en->note, "%.200s", usm_envelope_message(en->e));
    en->seconds = usm_report_now() - t0;
    return USM_OK;
}

void usm_report_envelope_free(usm_report_data *d)
{
    usm_envelope_free(d->envelope.e);
    d->envelope.e = NULL;
}

int usm_report_envelope_write_data(const usm_report_data *d, const char *dir,
                                   char msg[USM_IO_MSG_LEN])
{
    const struct usm_report_envelope *en = &d->envelope;
    const char *name = usm_report_figures[REPORT_FIG_ENVELOPE].name;
    char file[160], src[4096];
    usm_io_file out;
    FILE *f;
    char *text;
    int st;
    if (!en->ok)
        return USM_OK;
    snprintf(file, sizeof file, "%s.csv", name);
    if (!(f = usm_report_open(&out, dir, file, msg)))
        return USM_EFAILED;
    if (usm_envelope_write_plot_csv(en->e, f) != 0) {
        usm_io_msg(msg, "%s/%s: write error", dir, file);
        usm_report_close(&out, msg);
        return USM_EFAILED;
    }
    if ((st = usm_report_close(&out, msg)) != USM_OK)
        return st;
    /* `usm envelope --plot`'s static script behind the values it reads */
    if (usm_data_path("plots/envelope.gp", src, sizeof src) != 0) {
        usm_io_msg(msg, "%s: the report's gnuplot script is not installed (set USM_DATA_DIR)", src);
        return USM_EFAILED;
    }
    if (!(text = usm_template_read(src, msg)))
        return USM_EFAILED;
    snprintf(file, sizeof file, "%s.gp", name);
    if (!(f = usm_report_open(&out, dir, file, msg))) {
        free(text);
        return USM_EFAILED;
    }
    fprintf(f, "prefix = '%s'\nxcol = 'f [Hz]'\nycol = 'F0 [N]'\ncells = %d\n", name, en->raster);
    fputs(text, f);
    free(text);
    return usm_report_close(&out, msg);
}

json_t *usm_report_envelope_json(const usm_report_data *d)
{
    const struct usm_report_envelope *en = &d->envelope;
    json_t *o = json_object();
#define NUM(obj, k, v) json_object_set_new(obj, k, isfinite(v) ? json_real(v) : json_null())
    json_object_set_new(o, "ok", json_boolean(en->ok));
    json_object_set_new(o, "note", json_string(en->note));
    json_object_set_new(o, "model", json_string("3dof"));
    json_object_set_new(o, "x", json_pack("{s:s, s:f, s:f}", "name", "f", "lo", 36e3, "hi", 40e3));
    json_object_set_new(o, "y", json_pack("{s:s, s:f, s:f}", "name", "F0", "lo", 0.1, "hi", 2.0));
    json_object_set_new(o, "from_rest", json_true());
    json_object_set_new(o, "raster", json_integer(en->raster));
    NUM(o, "seconds", en->seconds);
    if (en->ok) {
        json_t *curves = json_array(), *codim2 = json_array(), *regions = json_array();
        for (size_t i = 0; i < usm_envelope_curve_count(en->e); ++i) {
            const usm_envelope_curve *c = usm_envelope_curve_at(en->e, i);
            json_t *co = json_object();
            json_object_set_new(co, "index", json_integer((json_int_t)i));
            json_object_set_new(co, "kind", json_string(usm_envelope_kind_name(c->kind)));
            json_object_set_new(co, "points", json_integer((json_int_t)c->npoints));
            json_object_set_new(co, "start", json_string(usm_envelope_end_name(c->end[0])));
            json_object_set_new(co, "end", json_string(usm_envelope_end_name(c->end[1])));
            json_array_append_new(curves, co);
        }
        for (size_t i = 0; i < usm_envelope_codim2_count(en->e); ++i) {
            const usm_envelope_codim2 *c = usm_envelope_codim2_at(en->e, i);
            json_t *co = json_object();
            json_object_set_new(co, "type", json_string(c->type));
            NUM(co, "f", c->x);
            NUM(co, "f_kHz", c->x / 1e3);
            NUM(co, "F0", c->y);
            json_object_set_new(co, "curve", json_integer((json_int_t)c->curve));
            json_array_append_new(codim2, co);
        }
        for (size_t i = 0; i < usm_envelope_region_count(en->e); ++i) {
            const usm_envelope_region *r = usm_envelope_region_at(en->e, i);
            json_t *ro = json_object();
            json_object_set_new(ro, "index", json_integer((json_int_t)i));
            json_object_set_new(ro, "class", json_string(usm_point_op_class_name(r->cls)));
            NUM(ro, "f", r->x);
            NUM(ro, "f_kHz", r->x / 1e3);
            NUM(ro, "F0", r->y);
            json_object_set_new(ro, "roots", json_integer(r->roots));
            json_object_set_new(ro, "cells", json_integer((json_int_t)r->cells));
            json_array_append_new(regions, ro);
        }
        json_object_set_new(o, "ncurves", json_integer(json_array_size(curves)));
        json_object_set_new(o, "nregions", json_integer(json_array_size(regions)));
        json_object_set_new(o, "curves", curves);
        json_object_set_new(o, "codim2", codim2);
        json_object_set_new(o, "regions", regions);
    }
#undef NUM
    return o;
}
