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
