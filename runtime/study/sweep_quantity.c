/* sweep_quantity.c: the quantities of a stationary solution that a sweep's
 * monitors watch by name (usm_sweep_quantity, usm_sweep.h). */
#include <string.h>

#include "usm_sweep.h"

static double q_theta(const usm_steady_solution *s, const usm_params *p, void *c) { (void)p; (void)c; return s->theta; }
static double q_alpha(const usm_steady_solution *s, const usm_params *p, void *c) { (void)p; (void)c; return s->alpha; }
static double q_rotor(const usm_steady_solution *s, const usm_params *p, void *c) { (void)p; (void)c; return s->rotor_speed; }
static double q_speed(const usm_steady_solution *s, const usm_params *p, void *c) { (void)p; (void)c; return -s->rotor_speed; }
static double q_Fn(const usm_steady_solution *s, const usm_params *p, void *c) { (void)p; (void)c; return s->F_n; }
static double q_Ft(const usm_steady_solution *s, const usm_params *p, void *c) { (void)p; (void)c; return s->F_t; }
static double q_mu(const usm_steady_solution *s, const usm_params *p, void *c) { (void)p; (void)c; return s->mu_used; }
static double q_vrel(const usm_steady_solution *s, const usm_params *p, void *c) { (void)p; (void)c; return s->v_rel; }

const char *usm_sweep_quantity(const char *name, size_t len, usm_monitor_fn *fn)
{
    static const struct {
        const char *name;
        usm_monitor_fn fn;
    } quantities[] = {{"theta", q_theta}, {"alpha", q_alpha}, {"rotor_speed", q_rotor},
                      {"speed", q_speed}, {"F_n", q_Fn},       {"F_t", q_Ft},
                      {"mu_used", q_mu},  {"v_rel", q_vrel}};
    for (size_t q = 0; q < sizeof quantities / sizeof quantities[0]; ++q)
        if (strlen(quantities[q].name) == len && strncmp(quantities[q].name, name, len) == 0) {
            if (fn)
                *fn = quantities[q].fn;
            return quantities[q].name;
        }
    return NULL;
}
