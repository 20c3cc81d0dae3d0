/* The rotor reaching the stator: one rule for simulation and shooting
 * (impact.h). */
#include "impact.h"

#include <math.h>
#include <string.h>

int usm_impact_resolve(const usm_model *m, const usm_params *p, double v_land, double t,
                       const double *y, usm_impact_fn closed_Fn, void *ctx, double *yplus,
                       double *R, usm_impact_outcome *o)
{
    const usm_unilateral *u = m->unilateral;
    const int ny = u->ny;
    double cv[2 + 2 * USM_MAX_NY], out[USM_MAX_NY + 2];
    memset(o, 0, sizeof *o);
    u->contact_velocity(y, p, cv);
    o->v = -cv[u->contact_velocity_out.gap_rate];
    if (!(o->v > 0) || (o->v <= v_land && closed_Fn(ctx, t, y) < 0)) {
        memcpy(yplus, y, sizeof(double) * (size_t)ny);
        return 0;
    }
    o->impact = 1;
    u->impact_stick(y, p, out);
    const double Pn = out[u->impact_out.P_n], Pt = out[u->impact_out.P_t];
    if (fabs(Pt) > p->mu0 * Pn) {
        if (m->slip) {
            o->slide = 1;
            u->impact_slide(y, Pt > 0 ? 1.0 : -1.0, p, out);
            if (R)
                u->impact_slide_jac(y, Pt > 0 ? 1.0 : -1.0, p, R);
        } else
            o->slipping = 1;
    }
    if (!o->slide && R)
        u->impact_stick_jac(y, p, R);
    const double *after = out + u->impact_out.y;
    for (int i = 0; i < ny; ++i)
        if (!isfinite(after[i]))
            return -1;
    memcpy(yplus, after, sizeof(double) * (size_t)ny);
    u->contact_velocity(yplus, p, cv);
    o->v_after = cv[u->contact_velocity_out.gap_rate];
    o->lands = !(o->v_after > v_land) && closed_Fn(ctx, t, yplus) >= 0;
    return 0;
}
