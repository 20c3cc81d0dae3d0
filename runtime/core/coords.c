/* States between the two orientation coordinate sets.
 *
 * The z-x-z Euler angles (phi, theta, psi) and the tilt vector (a, b, chi) of
 * derive/usm_derive/kinematics.py (TiltKinematics): the stator axis e_z2 in
 * the frame turning with Omega t about Z and the spin angle,
 *     a = sin(theta) sin(phi - Omega t),  b = -sin(theta) cos(phi - Omega t),
 *     chi = phi + psi,
 * and their time derivatives by the chain rule.  This is the definition of the
 * coordinates (TiltKinematics.from_euler), not an equation of motion; the test
 * coords_map checks it against the generated stationary orbits of both sets. */
#include <math.h>
#include <string.h>

#include "usm.h"

#define TWO_PI 6.283185307179586476925286766559

/* The six orientation indices of m's coordinate set, in the order
 * (phi, theta, psi, rates) or (a, b, chi, rates); 0 when one of them is not a
 * state of m (a descriptor's -1 for an absent state must never index x). */
static int orientation(const usm_model *m, int idx[6])
{
    if (!m || (m->coordinates != 0 && m->coordinates != 1))
        return 0;
    const int e[6] = {m->x_phi, m->x_theta, m->x_psi, m->x_phidot, m->x_thetadot, m->x_psidot};
    const int r[6] = {m->x_a, m->x_b, m->x_chi, m->x_adot, m->x_bdot, m->x_chidot};
    for (int k = 0; k < 6; ++k) {
        idx[k] = m->coordinates == 0 ? e[k] : r[k];
        if (idx[k] < 0 || idx[k] >= m->nx)
            return 0;
    }
    return 1;
}

int usm_coords_layout_ok(const usm_model *m)
{
    int idx[6];
    return orientation(m, idx);
}

double usm_coords_theta(const usm_model *m, const double *x)
{
    int idx[6];
    if (!orientation(m, idx))
        return NAN;
    if (m->coordinates == 0)
        return x[idx[1]];
    const double a = x[idx[0]], b = x[idx[1]], s2 = a * a + b * b;
    if (!(s2 < 1.0))
        return NAN;
    return atan2(sqrt(s2), sqrt(1.0 - s2));
}

double usm_coords_theta_rate(const usm_model *m, const double *x, const double *xdot)
{
    int idx[6];
    if (!orientation(m, idx))
        return NAN;
    if (m->coordinates == 0)
        return xdot[idx[1]];
    const double a = x[idx[0]], b = x[idx[1]], s2 = a * a + b * b;
    if (!(s2 > 0.0 && s2 < 1.0))
        return NAN;
    return (a * xdot[idx[0]] + b * xdot[idx[1]]) / (sqrt(s2) * sqrt(1.0 - s2));
}

int usm_coords_euler_angles(const usm_model *m, const double *x, double t,
                            const usm_params *p, double phi_near, double e[6])
{
    int idx[6];
    if (!orientation(m, idx)) {
        for (int k = 0; k < 6; ++k)
            e[k] = NAN;
        return USM_EINPUT;
    }
    if (m->coordinates == 0) {
        e[0] = x[m->x_phi];
        e[1] = x[m->x_theta];
        e[2] = x[m->x_psi];
        e[3] = x[m->x_phidot];
        e[4] = x[m->x_thetadot];
        e[5] = x[m->x_psidot];
        return USM_OK;
    }
    const double Omega = TWO_PI * p->f;
    const double a = x[m->x_a], b = x[m->x_b], ad = x[m->x_adot], bd = x[m->x_bdot];
    const double s2 = a * a + b * b, s = sqrt(s2), c = sqrt(fmax(0.0, 1.0 - s2));
    double phi = phi_near;
    if (s > 0) {
        phi = Omega * t + atan2(a, -b);
        phi += TWO_PI * nearbyint((phi_near - phi) / TWO_PI);
    }
    e[0] = phi;
    e[1] = atan2(s, c);
    e[2] = x[m->x_chi] - phi;
    e[3] = Omega + (a * bd - b * ad) / s2;
    e[4] = (a * ad + b * bd) / (s * c);
    e[5] = x[m->x_chidot] - e[3];
    return USM_OK;
}

int usm_coords_euler_rates(const usm_model *m, const double *x, const double *xdot,
                           const usm_params *p, double ed[6])
{
    int idx[6];
    if (!orientation(m, idx)) {
        for (int k = 0; k < 6; ++k)
            ed[k] = NAN;
        return USM_EINPUT;
    }
    if (m->coordinates == 0) {
        ed[0] = xdot[m->x_phi];
        ed[1] = xdot[m->x_theta];
        ed[2] = xdot[m->x_psi];
        ed[3] = xdot[m->x_phidot];
        ed[4] = xdot[m->x_thetadot];
        ed[5] = xdot[m->x_psidot];
        return USM_OK;
    }
    const double Omega = TWO_PI * p->f;
    const double a = x[m->x_a], b = x[m->x_b], ad = x[m->x_adot], bd = x[m->x_bdot];
    const double add = xdot[m->x_adot], bdd = xdot[m->x_bdot];
    const double s2 = a * a + b * b, s = sqrt(s2), c = sqrt(fmax(0.0, 1.0 - s2));
    const double pr = a * ad + b * bd, sd = pr / s, q = a * bd - b * ad;
    const double prd = ad * ad + bd * bd + a * add + b * bdd, sdd = (prd - sd * sd) / s;
    const double qd = a * bdd - b * add;
    ed[0] = Omega + q / s2;
    ed[1] = sd / c;
    ed[2] = x[m->x_chidot] - ed[0];
    ed[3] = (qd * s2 - 2.0 * q * pr) / (s2 * s2);
    ed[4] = sdd / c + s * sd * sd / (c * c * c);
    ed[5] = xdot[m->x_chidot] - ed[3];
    return USM_OK;
}

/* the tilt-vector coordinates from the Euler angles e = (phi, theta, psi, rates) */
static void tilt_from_euler(const double e[6], double t, double Omega, double y[6])
{
    const double al = e[0] - Omega * t, st = sin(e[1]), ct = cos(e[1]);
    const double sa = sin(al), ca = cos(al), ald = e[3] - Omega;
    y[0] = st * sa;
    y[1] = -st * ca;
    y[2] = e[0] + e[2];
    y[3] = ct * e[4] * sa + st * ca * ald;
    y[4] = -ct * e[4] * ca + st * sa * ald;
    y[5] = e[3] + e[5];
}

int usm_coords_map(const usm_model *from, const double *x_from, double t,
                   const usm_params *p, double phi_near, const usm_model *to, double *x_to)
{
    if (to == from) {
        memcpy(x_to, x_from, sizeof(double) * (size_t)from->nx);
        return USM_OK;
    }
    if (from->other_coordinates != to || to->nx != from->nx || !usm_coords_layout_ok(from) ||
        !usm_coords_layout_ok(to))
        return USM_EINPUT;
    /* the states other than the orientation, by name */
    for (int i = 0; i < to->nx; ++i)
        for (int j = 0; j < from->nx; ++j)
            if (strcmp(to->state_names[i], from->state_names[j]) == 0)
                x_to[i] = x_from[j];
    double e[6];
    if (usm_coords_euler_angles(from, x_from, t, p, phi_near, e) != USM_OK)
        return USM_EINPUT;
    if (to->coordinates == 0) {
        const int idx[6] = {to->x_phi, to->x_theta, to->x_psi,
                            to->x_phidot, to->x_thetadot, to->x_psidot};
        for (int k = 0; k < 6; ++k)
            x_to[idx[k]] = e[k];
    } else {
        double y[6];
        const int idx[6] = {to->x_a, to->x_b, to->x_chi, to->x_adot, to->x_bdot, to->x_chidot};
        tilt_from_euler(e, t, TWO_PI * p->f, y);
        for (int k = 0; k < 6; ++k)
            x_to[idx[k]] = y[k];
    }
    return USM_OK;
}
