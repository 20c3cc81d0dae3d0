/* The imperfect motor's curves' unknowns (envelope_periodic_problem.h). */
#include "envelope_periodic_problem.h"

#include <math.h>
#include <string.h>

#include "solve/periodic_internal.h"

void env_twist_setup(env_twist *t, const usm_model *m, const int *idx, int k, const double *sc,
                     double Omega, double *scale)
{
    t->tw = t->th = t->psd = -1;
    for (int a = 0; a < k; ++a) {
        scale[a] = sc[idx[a]];
        if (m->coordinates == 0 && idx[a] == m->x_phidot)
            t->tw = a;
        if (m->coordinates == 0 && idx[a] == m->x_theta)
            t->th = a;
        if (m->coordinates == 0 && idx[a] == m->x_psidot)
            t->psd = a;
    }
    if (t->tw >= 0 && t->th >= 0 && t->psd >= 0)
        /* the twist rate's scale as the tilt vector's spin rate's
         * (solve/periodic.c) */
        scale[t->tw] = Omega * sc[m->x_theta];
    else
        t->tw = -1;
}

void env_twist_unpack(const env_twist *t, const usm_model *m, const int *idx, int k,
                      const double *xfull, const double *z, double *x)
{
    memcpy(x, xfull, sizeof(double) * (size_t)m->nx);
    for (int a = 0; a < k; ++a)
        x[idx[a]] = z[a];
    if (t->tw >= 0)
        x[m->x_phidot] = z[t->tw] - x[m->x_psidot] * cos(x[m->x_theta]);
}

void env_twist_pack(const env_twist *t, const usm_model *m, const int *idx, int k,
                    const double *x, double *z)
{
    for (int a = 0; a < k; ++a)
        z[a] = x[idx[a]];
    if (t->tw >= 0)
        z[t->tw] = x[m->x_phidot] + x[m->x_psidot] * cos(x[m->x_theta]);
}

void env_twist_chain(const env_twist *t, const usm_model *m, const double *x, double *row)
{
    if (t->tw < 0)
        return;
    const double jw = row[t->tw];
    row[t->th] += jw * x[m->x_psidot] * sin(x[m->x_theta]);
    row[t->psd] -= jw * cos(x[m->x_theta]);
}

double env_box_test(const usm_envelope *e, int side, double px, double py, double pad)
{
    const int a = side / 2;
    const double v = a == 0 ? px : py, p = pad * (e->hi[a] - e->lo[a]);
    return side % 2 == 0 ? v - (e->lo[a] - p) : (e->hi[a] + p) - v;
}

int env_end_on_side(const usm_envelope *e, usm_cont *c, const int tbox[4], const int col[2],
                    double *z, int N)
{
    const usm_cont_event *ev = usm_cont_event_at(c, usm_cont_event_count(c) - 1);
    int side = -1;
    for (int sd = 0; ev && sd < 4; ++sd)
        if (ev->test == tbox[sd])
            side = sd;
    if (side < 0)
        return 0;
    const int a = side / 2;
    const double v = side % 2 == 0 ? e->lo[a] : e->hi[a];
    if (usm_cont_correct_fixed(c, z, col[a], v) < 0) {
        memcpy(z, usm_cont_point(c), sizeof(double) * (size_t)N);
        z[col[a]] = v;
    }
    return 1;
}

int env_param_column(usm_periodic *w, const usm_params *q, const usm_param_info *info, double d,
                     const double *x0, int k, double *J, int N, int j)
{
    double rp[USM_MAX_NX], rm[USM_MAX_NX];
    usm_params qp = *q, qm = *q;
    *usm_params_field(&qp, info) += d;
    *usm_params_field(&qm, info) -= d;
    if (usm_periodic_shoot_state(w, &qp, x0, rp) != USM_OK ||
        usm_periodic_shoot_state(w, &qm, x0, rm) != USM_OK)
        return -1;
    for (int a = 0; a < k; ++a)
        J[a * N + j] = (rp[a] - rm[a]) / (2 * d);
    return 0;
}
