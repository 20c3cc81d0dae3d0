/* The paper's motor identified (report section 3): the published numbers
 * that are outputs of the 4-DOF model at its stated point -- the tilt
 * theta and the rotor speed of Sec. 5 -- taken as measurements (sigma half
 * a unit of the last printed digit) and the resonance's parameters fitted
 * to them by usm_fit_run: c_r alone (the interval the paper's numbers allow)
 * and c_r with I_xx (whether the two numbers separate them).  The Fig. 9
 * maximum "near 36.8 kHz" is set against it: the maximum's frequency scales
 * with the resonance sqrt(c_r / I_xx), so 36.8 kHz asks for c_r times
 * (36.8 / f_max)^2 at the same I_xx; the located refit then fits c_r (and
 * c_r with I_xx) to the three numbers together, Fig. 9's maximum as the
 * measured output speed_max_frequency (sigma 50 Hz, half a unit of the
 * printed 36.8 kHz), whose chi^2 says whether one parameter set explains
 * them all.  One row, a few dozen operating points and sweeps: tens of
 * milliseconds. */
#include <math.h>
#include <string.h>

#include "report_internal.h"
#include "usm_fit.h"

/* The fit of names to the Sec. 5 values; 0 with *r filled, -1 (note set). */
/* fmax: 0 without Fig. 9's maximum, -1 with it, > 0 with it and at most
 * fmax iterations */
static int fit_paper(const usm_report_data *d, const char *names, int fmax, usm_fit_result *r,
                     char note[USM_MSG_LEN])
{
    const usm_model *m = usm_model_find("4dof");
    usm_fit_options o;
    usm_fit_data *fd = usm_fit_data_alloc(1, 1, fmax ? 3 : 2);
    char msg[USM_MSG_LEN];
    memset(r, 0, sizeof *r);
    if (!m || !fd) {
        usm_fit_data_free(fd);
        snprintf(note, USM_MSG_LEN, "out of memory");
        return -1;
    }
    fd->cond[0] = USM_P_f;
    fd->x[0] = d->params.f;
    fd->out[0] = USM_SENS_THETA;
    fd->out[1] = USM_SENS_ROTOR_SPEED;
    fd->has_sigma[0] = fd->has_sigma[1] = 1;
    /* the printed digits: 0.81836e-4 rad and -10.34 1/s */
    fd->y[0] = d->paper.theta4.value;
    fd->sigma[0] = 0.5e-9;
    fd->y[1] = d->paper.speed4.value;
    fd->sigma[1] = 0.005;
    if (fmax) { /* "near 36.8 kHz": half a unit of the last printed digit */
        fd->out[2] = USM_FIT_SPEED_MAX_FREQUENCY;
        fd->has_sigma[2] = 1;
        fd->y[2] = d->paper.f_max.value;
        fd->sigma[2] = 50.0;
    }
    usm_fit_options_default(&o);
    o.starts = 1; /* from the paper's own parameters */
    o.advise = 0;
    o.profile = !fmax; /* a profile of sweeps costs a second; the Jacobian's interval suffices */
    if (fmax > 0)
        o.max_iter = fmax;
    int st = usm_fit_parse_names(m, "fit", names, &o, msg);
    if (st == USM_OK)
        st = usm_fit_run(m, &d->params, fd, &o, r);
    usm_fit_data_free(fd);
    if (st != USM_OK) {
        snprintf(note, USM_MSG_LEN, "%s: %.200s", names, st == USM_EINPUT ? msg : r->message);
        usm_fit_result_free(r);
        return -1;
    }
    return 0;
}

int usm_report_compute_paper_fit(usm_report_data *d, char msg[USM_IO_MSG_LEN])
{
    usm_report_paper_fit *pf = &d->paper_fit;
    const double t0 = usm_report_now();
    usm_fit_result r;
    (void)msg;
    memset(pf, 0, sizeof *pf);
    if (fit_paper(d, "c_r", 0, &r, pf->note) == 0) {
        pf->ok = 1;
        pf->c_r = r.estimate[0];
        pf->c_r_se = r.se[0];
        pf->c_r_lo = r.profiled[0] ? r.profile_lo[0] : r.lo[0];
        pf->c_r_hi = r.profiled[0] ? r.profile_hi[0] : r.hi[0];
        pf->chi2 = r.chi2;
        usm_fit_result_free(&r);
    }
    if (pf->ok && fit_paper(d, "c_r,I_xx", 0, &r, pf->note) == 0) {
        pf->pair_ok = 1;
        pf->pair_identifiable = r.identifiable;
        pf->pair_corr = r.corr[1];
        pf->pair_singular = r.singular[1];
        pf->pair_c_r = r.estimate[0];
        pf->pair_I_xx = r.estimate[1];
        if (r.nunidentified > 0) {
            pf->pair_dir[0] = r.unidentified[0].direction[0];
            pf->pair_dir[1] = r.unidentified[0].direction[1];
        }
        usm_fit_result_free(&r);
    }
    const usm_report_located *fm = &d->f_max[REPORT_4DOF];
    if (pf->ok && fm->ok && fm->value > 0) {
        pf->fmax_ok = 1;
        pf->fmax_model = fm->value;
        pf->fmax_c_r = d->params.c_r * pow(d->paper.f_max.value / fm->value, 2);
        pf->fmax_sigmas = pf->c_r_se > 0 ? (pf->fmax_c_r - pf->c_r) / pf->c_r_se : NAN;
    }
    if (pf->ok && fit_paper(d, "c_r", -1, &r, pf->note) == 0) {
        pf->loc_ok = 1;
        pf->loc_c_r = r.estimate[0];
        pf->loc_c_r_se = r.se[0];
        pf->loc_chi2 = r.chi2;
        pf->loc_dof = r.dof;
        pf->loc_p = r.p_value;
        for (int i = 0; i < r.npoints; ++i) {
            const usm_fit_point *pt = &r.points[i];
            if (pt->output == USM_FIT_SPEED_MAX_FREQUENCY) {
                pf->loc_fmax = pt->model;
                pf->loc_fmax_res = pt->residual;
            } else if (pt->output == USM_SENS_THETA)
                pf->loc_theta_res = pt->residual;
            else
                pf->loc_speed_res = pt->residual;
        }
        usm_fit_result_free(&r);
    }
    /* c_r with I_xx against all three: only whether the pair is determined,
     * from the Jacobian's singular values after two iterations (the search
     * would walk along the open direction c_r / I_xx = const for a second of
     * sweeps without changing that answer) */
    if (pf->loc_ok && fit_paper(d, "c_r,I_xx", 2, &r, pf->note) == 0) {
        pf->loc_pair_ok = 1;
        pf->loc_pair_identifiable = r.identifiable;
        pf->loc_pair_singular = r.singular[1];
        usm_fit_result_free(&r);
    }
    pf->seconds = usm_report_now() - t0;
    return USM_OK;
}

json_t *usm_report_paper_fit_json(const usm_report_data *d)
{
    const usm_report_paper_fit *pf = &d->paper_fit;
    json_t *o = json_object();
#define NUM(k, v) json_object_set_new(o, k, isfinite(v) ? json_real(v) : json_null())
    json_object_set_new(o, "ok", json_boolean(pf->ok));
    json_object_set_new(o, "note", json_string(pf->note));
    NUM("c_r", pf->c_r);
    NUM("c_r_se", pf->c_r_se);
    NUM("c_r_lo", pf->c_r_lo);
    NUM("c_r_hi", pf->c_r_hi);
    NUM("c_r_paper", d->params.c_r);
    NUM("c_r_rel", pf->ok ? pf->c_r / d->params.c_r - 1 : NAN);
    NUM("chi2", pf->chi2);
    json_object_set_new(o, "pair_ok", json_boolean(pf->pair_ok));
    json_object_set_new(o, "pair_identifiable", json_boolean(pf->pair_identifiable));
    NUM("pair_corr", pf->pair_corr);
    NUM("pair_singular", pf->pair_singular);
    NUM("pair_c_r", pf->pair_c_r);
    NUM("pair_I_xx", pf->pair_I_xx);
    NUM("pair_dir_c_r", pf->pair_dir[0]);
    NUM("pair_dir_I_xx", pf->pair_dir[1]);
    json_object_set_new(o, "fmax_ok", json_boolean(pf->fmax_ok));
    NUM("fmax_model_kHz", pf->fmax_model / 1e3);
    NUM("fmax_paper_kHz", d->paper.f_max.value / 1e3);
    NUM("fmax_c_r", pf->fmax_c_r);
    NUM("fmax_c_r_rel", pf->fmax_ok ? pf->fmax_c_r / d->params.c_r - 1 : NAN);
    NUM("fmax_sigmas", pf->fmax_sigmas);
    json_object_set_new(o, "loc_ok", json_boolean(pf->loc_ok));
    NUM("loc_c_r", pf->loc_c_r);
    NUM("loc_c_r_se", pf->loc_c_r_se);
    NUM("loc_c_r_rel", pf->loc_ok ? pf->loc_c_r / d->params.c_r - 1 : NAN);
    NUM("loc_chi2", pf->loc_chi2);
    json_object_set_new(o, "loc_dof", json_integer(pf->loc_dof));
    NUM("loc_p", pf->loc_p);
    json_object_set_new(o, "loc_consistent", json_boolean(pf->loc_ok && pf->loc_p >= 0.05));
    NUM("loc_fmax_kHz", pf->loc_fmax / 1e3);
    NUM("loc_theta_res", pf->loc_theta_res);
    NUM("loc_speed_res", pf->loc_speed_res);
    NUM("loc_fmax_res", pf->loc_fmax_res);
    json_object_set_new(o, "loc_pair_ok", json_boolean(pf->loc_pair_ok));
    json_object_set_new(o, "loc_pair_identifiable", json_boolean(pf->loc_pair_identifiable));
    NUM("loc_pair_singular", pf->loc_pair_singular);
    NUM("seconds", pf->seconds);
#undef NUM
    return o;
}
