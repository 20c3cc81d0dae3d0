/* The power account of the squeal study (usm_squeal_energy): the energy
 * balance closes.
 *
 * Independent truth: a conserved quantity.  The change of the mechanical
 * energy of stator and rotor (kinetic energy from the generated kernel,
 * potentials of the three springs written out) over a run equals the work of
 * the excitation, the dampers, the load and friction, integrated as states
 * from their own formulas, plus the energy the impacts take; neither side
 * is computed from the equations of motion, which only move the state.  A
 * force left out or of the wrong sign would leave an error of order one, an
 * energy or a reset wrong by a fraction of a power share.  Checked on a
 * periodic orbit with separation (3-DOF phase error 0.6 rad: there the
 * mean powers also sum to zero, the orbit's energy repeating) and on the
 * irregular bouncing of the 4-DOF motor at 5 % mode split (impacts every
 * other period, a positive Lyapunov exponent). */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "bouncing.h"
#include "check.h"
#include "usm.h"
#include "usm_periodic.h"
#include "usm_simulate.h"
#include "usm_squeal_study.h"

static void show(const char *what, const usm_squeal_power *w)
{
    printf("%s: %ld periods, %ld separations, %ld impacts; power [W]: excitation %.6g, damping "
           "%.6g, load %.6g, friction %.6g (stator %.6g, rotor %.6g), normal on the stator "
           "%.6g, impacts %.6g; E %.9g -> %.9g J; balance error %.2e\n",
           what, w->periods, w->separations, w->impacts, w->excitation, w->damping, w->load,
           w->friction, w->friction_stator, w->friction_rotor, w->normal_stator,
           w->impacts_power, w->energy_start, w->energy_end, w->balance_error);
}

static void check_periodic(void)
{
    const usm_model *m = usm_model_find("3dof_imperfect_unilateral");
    usm_hybrid *h = usm_hybrid_alloc(m);
    usm_params p;
    usm_hybrid_result r;
    usm_params_default(&p);
    usm_params_set(&p, "phase_error", 0.6, NULL);
    const int rc = usm_hybrid_solve(h, &p, NULL, &r);
    usm_hybrid_free(h);
    if (!CHECK(rc == USM_OK && r.converged, "no orbit at phase error 0.6"))
        return;
    usm_squeal_power w;
    char msg[USM_MSG_LEN];
    CHECK(usm_squeal_energy(m, &p, r.t0, 0, r.x0, 20, 1e-9, &w, msg) == USM_OK, "energy: %s", msg);
    show("3-DOF phase error 0.6 rad (orbit)", &w);
    CHECK(w.balance_error < 1e-6, "balance error %.3g", w.balance_error);
    CHECK(w.impacts == 2 * 20 && w.separations == 2 * 20, "%ld impacts, %ld separations, want "
          "%d each (the orbit's %d a period)", w.impacts, w.separations, 2 * 20,
          r.impacts_per_period);
    /* over whole periods of the orbit the energy repeats: the powers sum to 0 */
    const double sum = w.excitation + w.damping + w.load + w.friction + w.impacts_power;
    CHECK(fabs(sum) < 1e-6 * w.excitation, "powers sum to %.3g W on the orbit", sum);
    CHECK(fabs(w.energy_end - w.energy_start) < 1e-6 * fabs(w.energy_start), "E %.9g -> %.9g",
          w.energy_start, w.energy_end);
    CHECK(w.excitation > 0 && w.damping < 0 && w.friction <= 0 && w.impacts_power < 0,
          "the signs: the driver feeds, dampers, friction and impacts take (friction 0 in the "
          "stick model: no slip)");
    /* the normal force's power on the stator goes to the rotor's axial motion:
       not a loss of its own, but not zero either */
    CHECK(w.normal_stator != 0.0, "no normal power");
}

static void check_irregular(void)
{
    const usm_model *m;
    usm_params p;
    bouncing_state l;
    if (!bouncing_settle(&m, &p, &l))
        return;
    usm_squeal_power w;
    char msg[USM_MSG_LEN];
    CHECK(usm_squeal_energy(m, &p, l.t, l.open, l.y, 60, 1e-9, &w, msg) == USM_OK, "energy: %s",
          msg);
    show("4-DOF mode split 5 % (irregular)", &w);
    CHECK(w.impacts >= 10, "only %ld impacts", w.impacts);
    CHECK(w.balance_error < 1e-6, "balance error %.3g", w.balance_error);
    /* bad input: one clear message */
    const usm_model *closed = usm_model_find("4dof");
    CHECK(usm_squeal_energy(closed, &p, 0, 0, l.y, 10, 1e-9, &w, msg) == USM_EINPUT &&
          strncmp(msg, "model:", 6) == 0, "closed model: %s", msg);
    CHECK(usm_squeal_energy(m, &p, 0, 0, l.y, 0, 1e-9, &w, msg) == USM_EINPUT &&
          strncmp(msg, "periods:", 8) == 0, "periods 0: %s", msg);
}

int main(void)
{
    const clock_t c0 = clock();
    check_periodic();
    check_irregular();
    printf("%.2f s CPU\n%s: %d failures\n", (double)(clock() - c0) / CLOCKS_PER_SEC, __FILE__,
           failures);
    return failures != 0;
}
