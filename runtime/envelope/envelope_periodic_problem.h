/* envelope_periodic_problem.h: what the imperfect motor's curves
 * (envelope_periodic.c: contact_loss, stick_loss; envelope_periodic_stability.c:
 * stability, fold) share about their unknowns: the orbit's state at the
 * shooting's start with the twist rate in phidot's place, and the box.
 * Internal to libusm; not installed. */
#ifndef USM_ENVELOPE_PERIODIC_PROBLEM_H
#define USM_ENVELOPE_PERIODIC_PROBLEM_H

#include "envelope_internal.h"

/* The k non-cyclic components of the state (usm_periodic_shoot_layout's
 * idx) as unknowns, in the Euler-angle models with the twist rate w =
 * phidot + psidot cos(theta) in phidot's place.  On the orbit phidot and
 * psidot are +-Omega and w is 1e-7 of Omega near the stall: quantities that
 * follow w (F_t, the multipliers) are steep in phidot alone (a step of 1e-4
 * of Omega changes w by 700 times its value) and mild in w, scaled as the
 * tilt vector's spin rate Omega theta. */
typedef struct env_twist {
    int tw, th, psd; /* the columns of w (phidot's), theta and psidot; tw -1: the state as it is */
} env_twist;

/* The columns for model m from the layout (idx, k) and, when they exist,
 * w's scale Omega * theta_scale into scale[tw].  scale: the unknowns'
 * scales, the state's filled from sc (usm_periodic_shoot_layout's). */
void env_twist_setup(env_twist *t, const usm_model *m, const int *idx, int k, const double *sc,
                     double Omega, double *scale);

/* The state x (nx values, the cyclic ones from xfull) of the unknowns z
 * (its first k), and back. */
void env_twist_unpack(const env_twist *t, const usm_model *m, const int *idx, int k,
                      const double *xfull, const double *z, double *x);
void env_twist_pack(const env_twist *t, const usm_model *m, const int *idx, int k,
                    const double *x, double *z);

/* The chain rule of phidot = w - psidot cos(theta) on row `row` of J (N
 * columns) whose entries are derivatives by the state's components, at the
 * state x. */
void env_twist_chain(const env_twist *t, const usm_model *m, const double *x, double *row);

/* Column j of the periodicity's rows (k of them, J with N columns) in the
 * parameter `info`: the central difference over +-d of two shots of the
 * state alone at x0 (a difference against the full shot, which takes other
 * steps, is noisy at 1e-9 of the scales over the step).  Before the full
 * shot: the state alone keeps nothing.  0, or -1 when a shot fails. */
int env_param_column(usm_periodic *w, const usm_params *q, const usm_param_info *info, double d,
                     const double *x0, int k, double *J, int N, int j);

/* The box's stopping test for side `side` (0 x low, 1 x high, 2 y low, 3 y
 * high) at (px, py): positive inside, with the pad outside the box. */
double env_box_test(const usm_envelope *e, int side, double px, double py, double pad);

/* Where one of the box's side tests (tbox: the engine's test indices, sides
 * as env_box_test's) is the event that ended the continuation c: its point z
 * (N unknowns) put onto that side, by Newton with the side's parameter
 * (column col[a] for axis a) held at the side's value; where Newton fails,
 * the located point (within the pad of the side) with the value set.  1
 * when a side ended it, else 0 (z untouched). */
int env_end_on_side(const usm_envelope *e, usm_cont *c, const int tbox[4], const int col[2],
                    double *z, int N);

#endif /* USM_ENVELOPE_PERIODIC_PROBLEM_H */
