/* The simulation's amplitude spectrum: its CSV (usm_spectrum.h) and its part
 * of `usm simulate`'s summary (spectrum_out.h). */
#include "spectrum_out.h"

#include <math.h>
#include <stdio.h>

#include "io/csv_out.h"
#include "io/json_out.h"

int usm_sim_spectrum_write_csv(const usm_sim_spectrum *s, const usm_sim_spectrum_result *r,
                               FILE *out)
{
    const double *amp[USM_SPECTRUM_NCHANNELS];
    usm_csv_column cols[2 + USM_SPECTRUM_NCHANNELS] = {{"frequency", "Hz"}, {"order", "1"}};
    for (int c = 0; c < USM_SPECTRUM_NCHANNELS; ++c) {
        if (!(amp[c] = usm_sim_spectrum_amplitudes(s, c)))
            return -1;
        cols[2 + c] = (usm_csv_column){usm_spectrum_channel_name(c),
                                       usm_spectrum_channel_unit(c)};
    }
    usm_csv_header(out, cols, 2 + USM_SPECTRUM_NCHANNELS);
    for (size_t k = 1; k < r->bins; ++k) {
        const double fk = (double)k * r->df;
        usm_csv_num(out, 1, fk);
        usm_csv_num(out, 0, fk / r->f);
        for (int c = 0; c < USM_SPECTRUM_NCHANNELS; ++c)
            usm_csv_num(out, 0, amp[c][k]);
        fputc('\n', out);
    }
    return ferror(out) ? -1 : 0;
}

static json_t *line_json(const usm_spectrum_line *l)
{
    json_t *o = json_object();
    int ok = o != NULL;
    usm_json_put(o, "frequency", usm_json_real(l->frequency), &ok);
    usm_json_put(o, "amplitude", usm_json_real(l->amplitude), &ok);
    usm_json_put(o, "order", usm_json_real(l->order), &ok);
    usm_json_put(o, "harmonic", json_boolean(l->harmonic > 0), &ok);
    usm_json_put(o, "harmonic_number", l->harmonic > 0 ? json_integer(l->harmonic) : json_null(),
                 &ok);
    usm_json_put(o, "folded_frequency", usm_json_real(l->folded), &ok);
    return usm_json_finish(o, ok);
}

json_t *usm_json_sim_spectrum(const usm_sim_spectrum_result *r, const char *csv)
{
    json_t *o = json_object(), *ch = json_object();
    int ok = o && ch;
    usm_json_put(o, "csv", csv ? json_string(csv) : json_null(), &ok);
    usm_json_put(o, "window", json_string("hann"), &ok);
    usm_json_put(o, "f", usm_json_real(r->f), &ok);
    usm_json_put(o, "t_from", usm_json_real(r->t_from), &ok);
    usm_json_put(o, "t_to", usm_json_real(r->t_to), &ok);
    usm_json_put(o, "periods", json_integer(r->periods), &ok);
    usm_json_put(o, "samples", json_integer((json_int_t)r->samples), &ok);
    usm_json_put(o, "recorded", json_integer((json_int_t)r->recorded), &ok);
    usm_json_put(o, "resampled", json_boolean(r->resampled), &ok);
    usm_json_put(o, "dt", usm_json_real(r->dt), &ok);
    usm_json_put(o, "resolution", usm_json_real(r->df), &ok);
    usm_json_put(o, "seconds", usm_json_real(r->seconds), &ok);
    for (int c = 0; c < USM_SPECTRUM_NCHANNELS; ++c) {
        json_t *co = json_object(), *lines = json_array();
        int cok = co && lines;
        usm_json_put(co, "unit", json_string(usm_spectrum_channel_unit(c)), &cok);
        usm_json_put(co, "parasitic_rms", usm_json_real(r->parasitic_rms[c]), &cok);
        usm_json_put(co, "peak", usm_json_real(r->peak[c]), &cok);
        usm_json_put(co, "empty", json_boolean(!(r->peak[c] > 0)), &cok);
        for (size_t q = 0; q < r->nlines[c] && cok; ++q)
            if (json_array_append_new(lines, line_json(&r->lines[c][q])) != 0)
                cok = 0;
        usm_json_put(co, "lines", lines, &cok);
        usm_json_put(co, "strongest_nonharmonic",
                     r->have_nonharmonic[c] ? line_json(&r->nonharmonic[c]) : json_null(), &cok);
        if (!cok) {
            json_decref(co);
            co = NULL;
        }
        usm_json_put(ch, usm_spectrum_channel_name(c), co, &ok);
    }
    usm_json_put(o, "channels", ch, &ok);
    return usm_json_finish(o, ok);
}

static void line_text(FILE *out, const usm_spectrum_line *l, double f, const char *unit,
                      const char *mark)
{
    fprintf(out, "    %s%12.6g Hz (%8.5f f)  amplitude %-11.4g %-4s", mark, l->frequency, l->order,
            l->amplitude, unit);
    if (l->harmonic > 0)
        fprintf(out, " harmonic %d f\n", l->harmonic);
    else
        fprintf(out, " not a harmonic: folded %.6g Hz (%.5f f)\n", l->folded, l->folded / f);
}

void usm_sim_spectrum_write_table(const usm_sim_spectrum_result *r, const char *csv, FILE *out)
{
    fprintf(out, "  %-22s %s%sHann window over the last %ld excitation periods, t in [%.6g, "
                 "%.6g] s: %zu samples%s, resolution %.6g Hz (%.3g s)\n",
            "spectrum", csv ? csv : "", csv ? ": " : "", r->periods, r->t_from, r->t_to,
            r->samples, r->resampled ? " (resampled by a cubic spline: the spline's error shows as weak image "
                           "lines; a --rate that is a multiple of f avoids it)"
                         : "", r->df, r->seconds);
    for (int c = 0; c < USM_SPECTRUM_NCHANNELS; ++c) {
        const char *unit = usm_spectrum_channel_unit(c);
        if (!(r->peak[c] > 0)) {
            fprintf(out, "  %s [%s]: constant over the window (zero after its mean): an empty "
                         "spectrum, no line\n",
                    usm_spectrum_channel_name(c), unit);
            continue;
        }
        fprintf(out, "  %s [%s]: not repeating with the excitation period (RMS) %.4g %s; "
                     "strongest lines\n",
                usm_spectrum_channel_name(c), unit, r->parasitic_rms[c], unit);
        for (size_t q = 0; q < r->nlines[c]; ++q)
            line_text(out, &r->lines[c][q], r->f, unit, "  ");
        if (r->have_nonharmonic[c]) {
            fprintf(out, "    strongest line that is not a harmonic of f:\n");
            line_text(out, &r->nonharmonic[c], r->f, unit, "  ");
        } else
            fprintf(out, "    every line is a harmonic of f\n");
    }
}
