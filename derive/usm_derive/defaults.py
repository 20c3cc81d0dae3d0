"""The default value of every parameter, where it comes from and why (the
reasons are prose with LaTeX math between $...$, printed in the documents).

The one place these numbers are written: derive/ emits them as
usm_param_defaults (generated/usm_contracts.c), which usm_params_default
(runtime/core/params.c) copies, and as the parameter table of every equations
document (emit_doc.py).  A value is "paper" (Appendix A, Table 5, or the text)
or "chosen" by usm, with the reason; see also docs/cli.md, "Parameters".
"""
from .model import PARAMETERS

TABLE5 = "paper, Appendix A, Table 5"

# name -> (value in the parameter's SI unit, source, reason or remark)
_R, _I_R = 0.005, 7.9522e-9
DEFAULTS = {
    "m0": (0.005, TABLE5, ""),
    "T": (6.46e-5, TABLE5, ""),
    "F0": (0.4, TABLE5, ""),
    "c_R": (4000.0, TABLE5, ""),
    "d_R": (0.1632, TABLE5, ""),
    "c_t": (10000.0, TABLE5, "the table prints the unit Nm; a torque per radian"),
    "c_r": (924.6677, TABLE5, "the table prints the unit Nm; a torque per radian"),
    "d_t": (9.1232e-4, TABLE5, "the table prints the unit Nms"),
    "d_r": (2.3865e-4, TABLE5, "the table prints the unit Nms"),
    "R": (_R, TABLE5, ""),
    "H": (0.003, TABLE5, ""),
    "I_R": (_I_R, TABLE5, ""),
    "I_xx": (1.7109e-8, TABLE5, ""),
    "I_yy": (1.7109e-8, TABLE5, "equal to I_xx under the axisymmetric stator"),
    "I_zz": (2.3120e-8, TABLE5, ""),
    # the same operations as C's double arithmetic: 2.0 * I_R / (R * R)
    "M": (2.0 * _I_R / (_R * _R), "chosen",
          r"not stated; $M = 2 I_R / R^2$, a solid-disk rotor of radius $R$; a scan of $M$ "
          r"over 0 to 0.02 kg fits the paper's Table 3 best at $6.361 \cdot 10^{-4}$ kg (all "
          r"six multipliers within $5 \cdot 10^{-4}$)"),
    "f": (37000.0, "chosen",
          r"not stated; Table 5 is built on 37 kHz: $c_r = I_{xx} (2\pi \cdot 37\,\mathrm{kHz})^2$, "
          r"$d_r$ and $d_t$ are 3 % damping at it, and it gives the paper's tilt "
          r"$\bar\theta = 0.81836 \cdot 10^{-4}$ to five digits"),
    "mu0": (0.3, "paper, section 5 text", "stated with the friction law (5.2), not in Table 5"),
    "kappa": (20.0, "paper, section 5 text", "stated with the friction law (5.2), not in Table 5"),
    "amp_imbalance": (0.0, "chosen", "the ideal motor of the paper; a real motor's value "
                      "enters only the imperfect variant"),
    "phase_error": (0.0, "chosen", "the ideal motor of the paper; a real motor's value "
                    "enters only the imperfect variant"),
    "mode_split": (0.0, "chosen", "the ideal motor of the paper; a real motor's value "
                   "enters only the imperfect variant"),
    "e_impact": (0.0, "chosen", "not in the paper, whose contact never opens: the rotor lands "
                 "and stays (Newton restitution 0); enters only the unilateral variant"),
}


# name -> (lo, hi): the physical range of the parameter in its SI unit, both
# ends included.  Chosen generously, wide around every wobbling-disk motor of
# a few millimetres to a few centimetres (this motor: R = 5 mm, 37 kHz), yet
# narrow enough that a value typed in the wrong unit falls outside it: f = 38
# (meant kHz), F0 = 400 (meant mN), phase_error = 35 (meant deg).  The library
# refuses a value outside (usm_params_set, usm_params_check, the studies'
# ranges and scatters) naming the range and the unit the user likely meant.
# An angle spans one turn, -pi .. pi: a larger one is a value in degrees.
# Four ranges reach far, to the limits the solvers are tested at: d_R to a
# rigid axial dashpot (1e12 N s/m, where the Floquet integrators fail), T to
# +-10 N m and m0 to 100 N m (the folds of the root branch under a load that
# drives the rotor hard, or an excitation far above the paper's), mu0 to 1e4
# (a slip model that emulates the stick model).
_PI = 3.141592653589793
RANGES = {
    "m0": (1e-9, 100.0),
    "T": (-10.0, 10.0),
    "F0": (0.0, 100.0),
    "c_R": (0.0, 1e8),
    "d_R": (0.0, 1e12),
    "c_t": (0.0, 1e7),
    "c_r": (0.0, 1e7),
    "d_t": (0.0, 10.0),
    "d_r": (0.0, 10.0),
    "R": (1e-4, 0.1),
    "H": (1e-5, 0.1),
    "I_R": (1e-14, 1e-2),
    "I_xx": (1e-14, 1e-2),
    "I_yy": (1e-14, 1e-2),
    "I_zz": (1e-14, 1e-2),
    "M": (0.0, 10.0),
    "f": (1e3, 1e6),
    "mu0": (0.0, 1e4),
    "kappa": (1e-3, 1e6),
    "amp_imbalance": (-1.0, 1.0),
    "phase_error": (-_PI, _PI),
    "mode_split": (-1.0, 1.0),
    "e_impact": (0.0, 1.0),
}


def ranges():
    """[(name, unit, lo, hi)] in PARAMETERS order; every default lies inside its range."""
    table = []
    for name, unit, _, value, _, _ in defaults():
        if name not in RANGES:
            raise ValueError(f"derive/usm_derive/defaults.py: no range for {name}")
        lo, hi = RANGES[name]
        if not lo <= value <= hi:
            raise ValueError(f"derive/usm_derive/defaults.py: the default {name} = {value} "
                             f"lies outside its range {lo} .. {hi}")
        table.append((name, unit, lo, hi))
    if set(RANGES) - {row[0] for row in table}:
        raise ValueError(f"a range for unknown {sorted(set(RANGES) - {r[0] for r in table})}")
    return table


# Set while a model is derived and emitted (pipeline.model_files): a model's
# own files must not depend on the defaults, which are not in its digest
# (digests.NOT_IN_MODELS), so that a changed default derives nothing.
IN_MODEL = False


def defaults():
    """[(name, unit, meaning, value, source, reason)] in PARAMETERS order."""
    if IN_MODEL:
        raise RuntimeError("derive/usm_derive/defaults.py read while a model is derived: "
                           "a model's files would depend on a file not in their digest "
                           "(usm_derive/digests.py, NOT_IN_MODELS)")
    missing = [name for name, *_ in PARAMETERS if name not in DEFAULTS]
    extra = [name for name in DEFAULTS if name not in [p[0] for p in PARAMETERS]]
    if missing or extra:
        raise ValueError(f"derive/usm_derive/defaults.py: no default for {missing}, "
                         f"a default for unknown {extra}")
    return [(name, unit, meaning) + DEFAULTS[name] for name, unit, meaning, _ in PARAMETERS]
