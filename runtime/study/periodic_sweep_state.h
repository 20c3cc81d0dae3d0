/* periodic_sweep_state.h: the state of a periodic sweep, shared by the files
 * of study/ that run it (periodic_sweep.c: the bilateral branch and its
 * events; periodic_sweep_hybrid.c: the orbits with separation past contact
 * loss).  Room-private: not installed, not for the writers. */
#ifndef USM_PERIODIC_SWEEP_STATE_H
#define USM_PERIODIC_SWEEP_STATE_H

#include "usm_periodic_sweep.h"

struct usm_periodic_sweep {
    const usm_model *m;
    usm_periodic *w;
    usm_periodic_point *pts;
    size_t npts, pts_cap;
    usm_periodic_event *ev;
    size_t nev, cap;
    const usm_param_info *info;
    const char *unit;
    char over[32];
    usm_params p;
    usm_periodic_options popt;
    double range, tol;
    int sat;            /* friction saturation: 0 not looked for, 1 located ahead, -1 not found */
    double sat_value;   /* its parameter value when sat = 1 */
    usm_hybrid *hy;     /* unilateral models: the orbits with separation */
    char msg[USM_MSG_LEN];
};

/* Append an event (value v, orbit NULL or the orbit there, `what` from fmt,
 * ending in "; model invalid: REASON" where the orbit is not valid, but for
 * the validity limits stick_loss, contact_loss, contact_regained); NULL
 * when out of memory. */
usm_periodic_event *psweep_event_add(usm_periodic_sweep *s, usm_pevent_type type, double v,
                                      const usm_periodic_result *orbit, const char *fmt, ...);
/* Say in e's `what` that the model does not describe the motor on the orbit
 * it carries (validity v not USM_VALID): "; model invalid: REASON". */
void psweep_event_mark(usm_periodic_event *e, usm_validity v);
/* Append the stability_change event at v (max |lambda| = 1): its kind from
 * the critical multiplier of fl (the non-cyclic one of largest modulus:
 * +1 fold, -1 period_doubling, a complex pair, |Im| > USM_COMPLEX_PAIR_TOL
 * |lambda|, neimark_sacker with its squeal frequency of 1 / period), the
 * text naming `subject` ("the orbit", ...) that loses stability (rising:
 * max |lambda| > 1 after the event in sweep order) or becomes stable;
 * orbit as psweep_event_add's; located 0 says the location failed.  NULL
 * when out of memory.  Shared by the bilateral branch and the orbits with
 * separation. */
usm_periodic_event *psweep_stability_add(usm_periodic_sweep *s, double v,
                                         const usm_periodic_result *orbit,
                                         const usm_floquet_result *fl, double period,
                                         const char *subject, int located, int dir_up,
                                         int rising);
/* "NAME = VALUE UNIT" of the swept parameter at v. */
void psweep_value_text(const usm_periodic_sweep *s, double v, char buf[96]);

/* Unilateral models, after the bilateral branch: the orbits with separation
 * at the grid points and their events (branch_switch, grazing,
 * stability_change), then every
 * event in sweep order (dir: to - from).  0, or -1 when out of memory. */
int psweep_separating(usm_periodic_sweep *s, double dir);

#endif /* USM_PERIODIC_SWEEP_STATE_H */
