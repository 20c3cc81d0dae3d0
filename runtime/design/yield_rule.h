/* yield_rule.h: the one rule by which a sample counts for a yield, shared by
 * both yields of usm -- the Monte Carlo study (tolerance.c, and the checks
 * and counts of its rows in tolerance_rows.c) and the common-random-numbers
 * yield of robust design (yield.c) -- so that the two cannot drift.  Not
 * installed; not part of the API. */
#ifndef USM_YIELD_RULE_H
#define USM_YIELD_RULE_H

/* Whether a sample is good: its operating point exists (op), is stable
 * (max_modulus < 1; NaN, failed multipliers, is not), the model describes
 * the motor there (valid: usm_validity is USM_VALID), it meets every spec
 * (meets_specs, judged by the caller on its own outputs) and the motor
 * drives its load: power_out >= 0, where power_out is the stationary
 * solution's (usm_steady_solution, from the model's steady_power kernel:
 * positive when the motor drives the load; at T = 0 it is 0, which counts as
 * driving), the rule of usm optimize's constraint "drives" -- unless
 * allow_driven (usm optimize's --allow-driven).  *driven (may be NULL): 1
 * when the sample meets every other part of the rule but the load drives
 * its rotor backwards (power_out < 0), so that this alone keeps it from
 * counting; 0 otherwise. */
static inline int yield_sample_good(int op, double max_modulus, int valid, int meets_specs,
                                    double power_out, int allow_driven, int *driven)
{
    const int rest = op && max_modulus < 1.0 && valid && meets_specs;
    const int drives = allow_driven || power_out >= 0.0;
    if (driven)
        *driven = rest && !drives;
    return rest && drives;
}

#endif /* USM_YIELD_RULE_H */
