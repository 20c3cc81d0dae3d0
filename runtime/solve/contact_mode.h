/* contact_mode.h: the kernels of one contact mode, chosen once (internal to solve/).
 *
 * A contact that may open (usm_model.unilateral) has two modes with states of
 * different length: closed (the model's own kernels, x of length nx) and open
 * (the open mode's kernels, y of length ny, which begins with x).  The
 * solvers that switch modes (simulate.c, hybrid.c) pick the kernels here at
 * each switch and call through the descriptor, never testing the mode at a
 * call.
 */
#ifndef USM_CONTACT_MODE_H
#define USM_CONTACT_MODE_H

#include "usm.h"

typedef struct usm_mode {
    int mode; /* 0 closed, 1 open */
    int n;    /* the state's length: nx closed, ny open */
    void (*mass)(const double *USM_RESTRICT x, const usm_params *USM_RESTRICT p,
                 double *USM_RESTRICT out);
    void (*rhs)(const double *USM_RESTRICT x, double t, const usm_params *USM_RESTRICT p,
                double *USM_RESTRICT out);
    void (*jac_rhs)(const double *USM_RESTRICT x, double t, const usm_params *USM_RESTRICT p,
                    double *USM_RESTRICT out);
    void (*jac_mass)(const double *USM_RESTRICT x, const double *USM_RESTRICT v,
                     const usm_params *USM_RESTRICT p, double *USM_RESTRICT out);
    void (*outputs)(const double *USM_RESTRICT x, const double *USM_RESTRICT xdot, double t,
                    const usm_params *USM_RESTRICT p, double *USM_RESTRICT out);
    /* df/dt explicit in t; NULL for a model without the unilateral descriptor */
    void (*rhs_t)(const double *USM_RESTRICT x, double t, const usm_params *USM_RESTRICT p,
                  double *USM_RESTRICT out);
} usm_mode;

/* The kernels of mode `mode` of model m into k: closed (0) from m itself,
 * open (1) from m->unilateral, which it then needs. */
static inline void usm_mode_kernels(const usm_model *m, int mode, usm_mode *k)
{
    const usm_unilateral *u = m->unilateral;
    k->mode = mode;
    if (mode == 0) {
        k->n = m->nx;
        k->mass = m->mass;
        k->rhs = m->rhs;
        k->jac_rhs = m->jac_rhs;
        k->jac_mass = m->jac_mass;
        k->outputs = m->outputs;
        k->rhs_t = u ? u->closed_rhs_t : NULL;
    } else {
        k->n = u->ny;
        k->mass = u->open_mass;
        k->rhs = u->open_rhs;
        k->jac_rhs = u->open_jac_rhs;
        k->jac_mass = u->open_jac_mass;
        k->outputs = u->open_outputs;
        k->rhs_t = u->open_rhs_t;
    }
}

#endif /* USM_CONTACT_MODE_H */
