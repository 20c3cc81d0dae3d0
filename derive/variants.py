"""The modelling assumptions: the input of the derivation.

A generated model is a base model (MODELS) under a variant (VARIANTS): the
variant's assumptions override the paper's (PAPER).  derive/generate.py turns
every combination into generated/usm_<name>.{h,c}, where <name> is the base
model's name for the paper's variant and "<base>_<variant>" otherwise.
Changing an assumption here and rebuilding regenerates the kernels; the runtime
handles any generated model through its descriptor (usm_model) without code
changes.  See docs/changing-an-assumption.md.

Assumptions and their choices:
  contact          "stick": no slip, rotor speed tied to the stator (2.4), 3 DOF
                   "slip":  rotor angle phi_R free, F_t = mu(v_rel) F_n (5.1), 4 DOF
  friction         (slip only) a name in FRICTION_LAWS: "atan" is the paper's
                   mu0*atan(kappa*v_rel) (5.2); "tanh" is mu0*tanh(kappa*v_rel);
                   "stribeck" is tanh with a decaying static peak (non-monotone)
  twist            "paper": twist angle phi + psi*cos(theta) (2.9)
                   "integrated": twist angle tau with tau' = omega_Z (extra state)
  spring_reference "theta0": F_R = F0 + c_R*(Z - H), Z measured from theta = 0
                   "literal": F_R = F0 + c_R*Z as printed in (2.1)
  stator_inertia   "axisymmetric": I_yy is taken equal to I_xx
                   "general": I_xx, I_yy, I_zz independent
  imperfection     "none" (default): the ideal motor of the paper
                   "driver_stator": the parameters amp_imbalance, phase_error
                   (driver) and mode_split (stator tilt stiffness fixed in the
                   housing) enter the equations of motion; the stationary
                   solution and its kernels are those of the ideal motor
                   (imperfections 0), the only case where it exists
  closure          "bilateral" (default): the rotor rides on the stator at all
                   times (2.3), F_n may take any sign (the paper's model)
                   "unilateral": the contact opens where F_n would turn
                   negative; while open the rotor's axial position is a state
                   of its own, and it closes again by an impact (Newton
                   restitution e_impact, friction impulse at most mu0 times
                   the normal one); see docs/unilateral.md
  coordinates      "euler_zxz" (default): the paper's z-x-z Euler angles
                   "tilt_vector": the stator axis in the frame turning with
                   Omega t and the spin angle phi + psi, regular at theta = 0
                   (docs/coordinates.md); needs the integrated twist
                   law (the paper's twist angle phi + psi cos(theta) needs phi,
                   which is singular at theta = 0); no imperfections
"""

PAPER = {
    "twist": "paper",
    "spring_reference": "theta0",
    "stator_inertia": "axisymmetric",
    "friction": "atan",
}

# Parameters an assumption ties to another: (assumption, choice) ->
# [(parameter, the parameter it equals, the assumption in words)].  Stated here
# only: derive/ emits it for the runtime (usm_param_couplings, each model's
# param_coupling, usm_param_coupled and usm_params_couple in
# generated/usm_contracts.{h,c}) and refuses kernels of such a model that read
# the tied parameter.
COUPLINGS = {
    ("stator_inertia", "axisymmetric"): [("I_yy", "I_xx", "an axisymmetric stator")],
}

# Assumptions PAPER leaves unstated (so the paper's models keep their lists):
# their value in the paper's models, e.g. for the documents' "(paper: none)".
UNSTATED = {"imperfection": "none", "closure": "bilateral", "coordinates": "euler_zxz"}

# Friction laws mu(v_rel) of the slip model, as formulas in v_rel, mu0, kappa.
# The runtime needs mu continuous in v_rel; it may be non-monotone (then
# several rotor speeds can balance one load, and the stationary solver reports
# each of them; see runtime/solve/steady.c).
FRICTION_LAWS = {
    "atan": "mu0*atan(kappa*v_rel)",
    "tanh": "mu0*tanh(kappa*v_rel)",
    # Stribeck peak: a static excess of 50 % over mu0 that decays with slip on
    # the scale 0.01 m/s (written 100*v_rel so the constants stay exact).
    "stribeck": "mu0*tanh(kappa*v_rel)*(1 + exp(-(100*v_rel)**2)/2)",
}

MODELS = {
    "3dof": {"contact": "stick",
             "description": "3-DOF stick model of sections 2-4"},
    "4dof": {"contact": "slip",
             "description": "4-DOF slip model of section 5"},
}

# name -> (assumptions that differ from PAPER, base models, description)
VARIANTS = {
    "paper": ({}, ["3dof", "4dof"],
              "the paper's assumptions (default): twist angle phi + psi cos(theta), "
              "mu = mu0 atan(kappa v_rel)"),
    "twist_integrated": ({"twist": "integrated"}, ["3dof", "4dof"],
                         "twist angle integrated from omega_Z (extra state tau): "
                         "the linearisation is periodic, multipliers independent of t0"),
    "friction_tanh": ({"friction": "tanh"}, ["4dof"],
                      "friction law mu = mu0 tanh(kappa v_rel) instead of (5.2)"),
    "friction_stribeck": ({"friction": "stribeck"}, ["4dof"],
                          "friction law mu = mu0 tanh(kappa v_rel) (1 + 0.5 exp(-(v_rel/0.01)^2)) "
                          "(Stribeck peak; not monotone for kappa above about 114 s/m)"),
    # Last in the list: the kernel tests draw random samples model by model
    # from one stream, and earlier models keep their samples this way.
    # Built on the integrated twist law: the paper's twist angle
    # phi + psi cos(theta) grows with psi = -Omega t / cos(theta), so under it
    # no motion is periodic in (phi - Omega t, theta, rates) (see
    # docs/periodic.md); the integrated twist angle tau is bounded.
    "imperfect": ({"twist": "integrated", "imperfection": "driver_stator"}, ["3dof", "4dof"],
                  "a real motor: driver amplitude imbalance and phase error, stator mode "
                  "split (parameters amp_imbalance, phase_error, mode_split), integrated "
                  "twist law; periodic steady states by `usm periodic`"),
    # After imperfect: its kernels (the closed mode) stay owned by imperfect.
    "imperfect_unilateral": ({"twist": "integrated", "imperfection": "driver_stator",
                              "closure": "unilateral"}, ["3dof", "4dof"],
                             "the variant imperfect with a contact that may open: the rotor "
                             "lifts off where F_n would turn negative and lands again by an "
                             "impact (restitution e_impact); `usm simulate` switches modes"),
    # After imperfect_unilateral: the models in regular coordinates.
    "tilt": ({"twist": "integrated", "coordinates": "tilt_vector"}, ["3dof", "4dof"],
             "twist_integrated in coordinates regular at theta = 0 (stator axis in the frame "
             "turning with Omega t, spin angle phi + psi): the same motor and stationary "
             "solution, better-conditioned equations (docs/coordinates.md)"),
}


def generated_models():
    """(name, base, variant, assumptions, description) of every generated model."""
    out = []
    for variant, (changes, bases, vdesc) in VARIANTS.items():
        for base in bases:
            spec = dict(PAPER, **changes)
            spec["contact"] = MODELS[base]["contact"]
            if spec["contact"] == "stick":
                spec.pop("friction")
            else:
                spec["friction_law"] = FRICTION_LAWS[spec["friction"]]
            name = base if variant == "paper" else f"{base}_{variant}"
            desc = MODELS[base]["description"]
            if variant != "paper":
                desc += f", variant {variant}"
            out.append((name, base, variant, spec, desc))
    return out
