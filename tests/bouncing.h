/* bouncing.h: the irregular motion the squeal tests start from.
 *
 * The 4-DOF imperfect unilateral motor at 5 % mode split has no stable
 * periodic orbit: its rotor bounces irregularly (docs/squeal.md).  Tests of
 * what the library says about such a motion (its Lyapunov exponent, its
 * energy balance) need a state on the attractor, not on the transient from
 * the default start: bouncing_settle runs 100 excitation periods with
 * usm_sim_run and keeps the last sample.  Header only, like check.h. */
#ifndef USM_TEST_BOUNCING_H
#define USM_TEST_BOUNCING_H

#include <string.h>

#include "check.h"
#include "usm.h"
#include "usm_simulate.h"

typedef struct bouncing_state {
    double t, y[USM_MAX_NY];
    int open; /* the contact is open at t */
} bouncing_state;

static int bouncing_keep_last(const usm_sim_sample *smp, void *data)
{
    bouncing_state *l = data;
    l->t = smp->t;
    l->open = smp->open;
    memcpy(l->y, smp->y, sizeof(double) * (size_t)smp->ny);
    return 0;
}

/* The model 4dof_imperfect_unilateral and its parameters p (the defaults,
 * mode split 5 %) after 100 periods, in *l; 0 when the run failed (a failed
 * CHECK says why). */
static int bouncing_settle(const usm_model **m, usm_params *p, bouncing_state *l)
{
    *m = usm_model_find("4dof_imperfect_unilateral");
    if (!CHECK(*m != NULL, "the variant 4dof_imperfect_unilateral is not built"))
        return 0;
    usm_params_default(p);
    usm_params_set(p, "mode_split", 0.05, NULL);
    usm_sim *s = usm_sim_alloc(*m);
    usm_sim_options o;
    usm_sim_options_default(&o);
    o.duration = 100 / p->f;
    o.rate = p->f;
    const usm_sim_callbacks cb = {bouncing_keep_last, NULL, l, NULL};
    usm_sim_summary sum;
    const int ok = CHECK(usm_sim_run(s, p, &o, &cb, &sum) == USM_OK, "run: %s", usm_sim_message(s));
    usm_sim_free(s);
    return ok;
}

#endif /* USM_TEST_BOUNCING_H */
