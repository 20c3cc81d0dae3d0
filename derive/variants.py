"""The modelling assumptions: the input of the derivation.

Each entry is one model variant that derive/generate.py turns into
generated/usm_<name>.{h,c}.  Changing an assumption here and rebuilding
regenerates the kernels; the runtime handles any variant through its
descriptor (usm_model) without code changes.

Assumptions and their choices:
  contact          "stick": no slip, rotor speed tied to the stator (2.4), 3 DOF
                   "slip":  rotor angle phi_R free, F_t = mu(v_rel) F_n (5.1), 4 DOF
  friction         (slip only) "atan": mu0*atan(kappa*v_rel) (5.2);
                   "tanh": mu0*tanh(kappa*v_rel)
  twist            "paper": twist angle phi + psi*cos(theta) (2.9)
                   "integrated": twist angle tau with tau' = omega_Z (extra state)
  spring_reference "theta0": F_R = F0 + c_R*(Z - H), Z measured from theta = 0
                   "literal": F_R = F0 + c_R*Z as printed in (2.1)
  stator_inertia   "axisymmetric": I_yy is taken equal to I_xx
                   "general": I_xx, I_yy, I_zz independent
"""

PAPER = {
    "twist": "paper",
    "spring_reference": "theta0",
    "stator_inertia": "axisymmetric",
}

VARIANTS = {
    "3dof": dict(PAPER, contact="stick",
                 description="3-DOF stick model of sections 2-4 (paper's default)"),
    "4dof": dict(PAPER, contact="slip", friction="atan",
                 description="4-DOF slip model of section 5, mu = mu0*atan(kappa*v_rel)"),
}
