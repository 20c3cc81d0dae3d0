/* A region's class in a unilateral model where the bilateral orbit's
 * contact opens: the orbit with separation the motor runs on there.
 *
 * In the unilateral variant the contact may open, so `contact_open` (the
 * bilateral orbit's F_n turning negative) is not the motor's state: the
 * motor runs on an orbit with separation.  At the region's sample the
 * orbit a start from rest settles on (usm_hybrid_solve: the start-up's
 * attractor, as `usm periodic` and the periodic sweep's branch_switch find
 * it) is the region's orbit; its class is `separating` where its largest
 * non-cyclic multiplier (with the saltation matrices) lies inside the unit
 * circle, `separating_unstable` where it does not (the start-up lingered
 * near an unstable orbit and no stable one was found), and the message
 * gives its mode sequence, impacts per period, time open, mean rotor speed
 * and that multiplier.  Where no orbit with separation is found the class
 * stays and the message says why.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "envelope_internal.h"

void env_hybrid_classify(usm_envelope *e, usm_envelope_region *r)
{
    usm_hybrid *h = usm_hybrid_alloc(e->m);
    usm_hybrid_result res;
    if (!h)
        return;
    usm_params q = e->p;
    *usm_params_field(&q, e->ax[0]) = r->x;
    *usm_params_field(&q, e->ax[1]) = r->y;
    if (usm_hybrid_solve(h, &q, NULL, &res) == USM_OK && res.converged && res.nmodes >= 2) {
        const double mod = res.floquet.max_modulus;
        snprintf(r->class_name, sizeof r->class_name, "%s",
                 mod < 1.0 ? "separating" : "separating_unstable");
        snprintf(r->message, sizeof r->message,
                 "the orbit with separation from rest: %s, %d impacts per period, open %.4f of "
                 "the period, rotor speed %.6g 1/s, max |lambda| %.9f%s",
                 res.mode_sequence, res.impacts_per_period, res.separation_fraction,
                 res.rotor_speed_mean, mod,
                 res.validity == USM_VALID ? "" : "; an impact needs more than mu0");
        r->roots = 1;
    } else {
        const size_t len = strlen(r->message);
        snprintf(r->message + len, sizeof r->message - len, "; no orbit with separation: %.120s",
                 usm_hybrid_message(h));
    }
    usm_hybrid_free(h);
}
