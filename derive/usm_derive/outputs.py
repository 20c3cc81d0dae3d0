"""The kernels' outputs: their names in the order of the C arrays (the enums
USM_OUT_*, USM_STEADY_*, ... of usm_kernels.h) and their units (the tables of
usm_contracts.h).  Read by emit_model (the kernels) and emit_contracts (the
tables), so that both state the same order once."""

OUTPUT_NAMES = ["R_star", "Z", "v_c", "F_n", "F_t", "v_rel", "rotor_speed"]
STEADY_NAMES = ["beta", "rotor_speed", "F_n", "F_t", "v_c", "v_rel", "R_star", "Z", "twist"]
SEED_NAMES = ["amplitude_mismatch", "cos_alpha", "sin_alpha", "F_t", "F_n"]
POWER_NAMES = ["power_in", "power_out", "power_damping", "power_slip"]
# Stationary quantities whose derivatives the sensitivities need.
DESIGN_NAMES = ["rotor_speed", "F_n", "F_t"] + POWER_NAMES

# Units of the outputs of the kernels, by name (the enums of usm_kernels.h).
OUTPUT_UNITS = {
    "R_star": "m", "Z": "m", "v_c": "m/s", "F_n": "N", "F_t": "N", "v_rel": "m/s",
    "rotor_speed": "1/s", "beta": "rad", "twist": "rad",
    "amplitude_mismatch": "1", "cos_alpha": "1", "sin_alpha": "1",
    "power_in": "W", "power_out": "W", "power_damping": "W", "power_slip": "W",
}
