"""Equations of motion of the motor, derived from named modelling assumptions.

Everything the C kernels compute comes out of ``derive_model``: nothing here is
an equation of motion typed by hand; the only inputs are the kinematics of
``kinematics.py``, the force laws of the paper (2.1), (2.2), (2.5), (2.8)-(2.10)
and the assumptions of a variant (``variants.py``).

Rotational equations.  Euler's equations (2.6) hold in the body frame K.  The
mass-matrix form uses them projected on frame A (rows = C_AK * (2.6)): the
solution set is the same (C_AK is orthogonal), and in frame A the stationary
solution is constant, which makes the stationary residuals (3.3)-(3.5) free of
time without any simplification of large expressions.  The linearisation about
a solution is unchanged by such a row rotation, because the rotated residual
vanishes on the solution.
"""
import copy
from dataclasses import dataclass, field
import sympy as sp

from .kinematics import Kinematics, TiltKinematics

# The paper's parameter symbols in ASCII (Appendix A plus f, M, mu0, kappa),
# with SI units.  Their order is the field order of the C struct usm_params.
PARAMETERS = [
    ("m0", "N m", "excitation torque amplitude", "positive"),
    ("T", "N m", "load torque", "any"),
    ("F0", "N", "spring preload", "nonnegative"),
    ("c_R", "N/m", "rotor spring stiffness", "nonnegative"),
    ("d_R", "N s/m", "rotor axial damping", "nonnegative"),
    ("c_t", "N m/rad", "twist stiffness", "nonnegative"),
    ("c_r", "N m/rad", "tilt stiffness", "nonnegative"),
    ("d_t", "N m s/rad", "twist damping", "nonnegative"),
    ("d_r", "N m s/rad", "tilt damping", "nonnegative"),
    ("R", "m", "contact radius at rest", "positive"),
    ("H", "m", "height of the contact plane", "positive"),
    ("I_R", "kg m^2", "rotor moment of inertia", "positive"),
    ("I_xx", "kg m^2", "stator moment of inertia about x", "positive"),
    ("I_yy", "kg m^2", "stator moment of inertia about y", "positive"),
    ("I_zz", "kg m^2", "stator moment of inertia about z", "positive"),
    ("M", "kg", "rotor mass", "nonnegative"),
    ("f", "Hz", "excitation frequency (Omega = 2 pi f)", "positive"),
    ("mu0", "1", "friction law scale", "nonnegative"),
    ("kappa", "s/m", "friction law slope", "positive"),
    # Imperfections of a real motor; they enter only the models
    # whose assumption imperfection is "driver_stator" (variant imperfect).
    ("amp_imbalance", "1", "amplitude imbalance e of the two excitation phases", "any"),
    ("phase_error", "rad", "phase error delta of the second excitation phase", "any"),
    ("mode_split", "1", "tilt stiffness split s: c_r (1 + s) about X, c_r (1 - s) about Y", "any"),
    # Newton's restitution coefficient of the impact that closes an open
    # contact; it enters only the models whose assumption closure
    # is "unilateral".  0: the rotor lands and stays.
    ("e_impact", "1", "restitution coefficient of the rotor's impact on the stator", "unit_interval"),
]
IMPERFECTIONS = ["amp_imbalance", "phase_error", "mode_split"]

P = {name: sp.Symbol(name, real=True) for name, *_ in PARAMETERS}
t = sp.Symbol("t", real=True)
OMEGA = 2 * sp.pi * P["f"]


def solve_linear(expr, x):
    """Root of an expression affine in x.  sympy's solve() would call simplify
    on the whole expression, which costs seconds here for nothing."""
    a = sp.diff(expr, x)
    if x in a.free_symbols:
        raise RuntimeError(f"expression is not linear in {x}")
    return -expr.subs(x, 0) / a


def friction_law(text, v):
    """mu(v_rel) from its formula (derive/variants.py, FRICTION_LAWS), in the
    symbols v_rel, mu0 and kappa."""
    names = {"v_rel": v, "mu0": P["mu0"], "kappa": P["kappa"]}
    expr = sp.sympify(text, locals=names)
    unknown = expr.free_symbols - set(names.values())
    if unknown:
        raise ValueError(f"friction law {text!r} uses unknown symbols {unknown}")
    return expr


def imperfect_excitation_A(kin, Om):
    """Excitation (2.8) of a real driver minus the ideal one, in frame A:
    M_E = m0 [(1 + e) cos(Omega t) e_X + (1 - e) sin(Omega t + delta) e_Y].
    Kept apart from the ideal part so that at e = delta = 0 it is an exact
    zero and the ideal terms keep their simplified form."""
    e, delta, m0 = P["amp_imbalance"], P["phase_error"], P["m0"]
    extra_N = sp.Matrix([m0 * e * sp.cos(Om * t),
                         m0 * ((1 - e) * sp.sin(Om * t + delta) - sp.sin(Om * t)), 0])
    return kin.C_NA.T * extra_N


def mode_split_moment_A(kin, euler):
    """Restoring moment of the split part of the tilt stiffness, in frame A.

    The stiffness is fixed in the housing: c_r (1 + s) about X and c_r (1 - s)
    about Y, acting on the housing-frame tilt vector rho (kinematics.py), so
    its energy is V = c_r/2 [(1 + s) rho_X^2 + (1 - s) rho_Y^2]; the isotropic
    part c_r theta e_x1 is (2.10) as before and this is the rest,
    V_s = c_r s (rho_X^2 - rho_Y^2) / 2.  A restoring moment M_R belongs to a
    potential when its power equals dV/dt for every motion: with
    omega_A = L qdot that is L^T M_R = dV/dq.  L is singular at theta = 0
    (the Euler angles are), so the e_y1 component cos(theta) dV/dphi /
    sin(theta) is written with theta/sin(theta) = 1/sinc(theta), finite there.
    """
    phi_f, theta_f, psi_f = euler
    q = sp.symbols("phi_q theta_q psi_q", real=True)
    to_q = {phi_f: q[0], theta_f: q[1], psi_f: q[2]}
    rho = kin.housing_tilt_vector().xreplace(to_q)
    V = P["c_r"] * P["mode_split"] * (rho[0] ** 2 - rho[1] ** 2) / 2
    g = sp.Matrix([sp.diff(V, c) for c in q])
    rates = [c.diff(t) for c in euler]
    L = kin.omega_A.jacobian(rates).xreplace(to_q)
    M = L.T.LUsolve(g).applyfunc(sp.simplify)
    th = q[1]

    def regular(e):
        if sp.sin(th) not in sp.denom(sp.together(e.rewrite(sp.sin))).atoms(sp.sin):
            return e
        return sp.simplify(e * sp.sin(th) / th) / sp.sinc(th)
    M = M.applyfunc(regular)
    check = (L.T * M - g).applyfunc(lambda e: sp.simplify(e.subs(sp.sinc(th), sp.sin(th) / th)))
    if check != sp.zeros(3, 1) or any(sp.denom(e).subs(th, 0) == 0 for e in M):
        raise RuntimeError(f"mode-split moment is not the potential's: {check.T}, {M.T}")
    return M.xreplace({v: k for k, v in to_q.items()})


@dataclass
class Model:
    """A derived model: first-order form and stationary-solution problem."""
    name: str
    assumptions: dict
    states: list            # symbols of x, in order
    state_names: list
    mass: sp.Matrix         # M(x), n x n
    rhs: sp.Matrix          # f(x, t), n
    v: list                 # symbols of the vector v in d(M v)/dx
    outputs: dict           # name -> expression of (x, xdot, t)
    xdot: list              # symbols of xdot used by outputs
    unknowns: list          # stationary unknowns u
    unknown_names: list
    residual: sp.Matrix     # r(u)
    steady_outputs: dict    # name -> expression of u
    steady_state: sp.Matrix  # xbar(t) as function of (u, beta, t)
    steady_rate: sp.Matrix   # d xbar/dt
    seed: dict              # name -> expression of theta (see derive_model)
    friction: object = None  # mu(v) expression in symbol v_rel, slip only
    v_rel: object = None
    tangent_map: sp.Matrix = None  # T(x): dy = T dx, see derive_model
    jac_rhs: sp.Matrix = None      # df/dx
    jac_mass: sp.Matrix = None     # d(M v)/dx
    t0_independent: bool = False   # linearisation about xbar(t) free of t
    steady_power: dict = None      # name -> power on the stationary solution, of u
    floquet_direction: list = None  # [dM, dA] along (du, dt, dp), see derive_model
    direction_symbols: list = None  # (symbol, direction symbol) pairs of that derivative
    cyclic: list = field(default_factory=list)
    equations: dict = field(default_factory=dict)  # for the readable export
    unilateral: dict = None  # closure = unilateral: the open mode, guards, reset


# --------------------------------------------------------------------------
# The derivation in steps.  A variant (derive/variants.py) is a choice for
# each assumption; each choice is a step below, and derive_model composes the
# steps its variant's choices name (the tables CONTACT, TWIST, IMPERFECTION,
# SPRING_REFERENCE, STATOR_INERTIA).  A step reads what the earlier steps put
# in the derivation ``d`` and adds its own quantities; the steps after the
# equations of motion (stationary solution, power, seed, linearisation) hold
# for every variant.

class Derivation:
    """The quantities of one derivation, filled in step by step."""

    def __init__(self, name, assumptions):
        self.name = name
        self.assumptions = dict(assumptions)

    # True in coordinates other than the Euler angles (_derive_regular): there
    # the substitutions of symbols by expressions are structural (xreplace),
    # which gives the same expressions as subs() without its search for
    # matching subexpressions, minutes on the large tilt-vector Jacobians.
    regular = False

    def plain(self, e):
        """q''(t), q'(t), q(t) -> the plain symbols qddot, qdot, q."""
        if self.regular:
            return sp.sympify(e).xreplace(dict(self.subs_lists))
        return e.subs(self.subs_lists)

    def put(self, e, mapping):
        """e with the symbols of mapping replaced at once (simultaneously)."""
        if self.regular:
            return e.xreplace(mapping)
        return e.subs(mapping, simultaneous=True)

    def on_ansatz(self, e):
        """An expression of the motion on the stationary ansatz (3.1)."""
        e = e.subs({c.diff(t, 2): 0 for c in self.coords})
        e = e.subs({c.diff(t): self.rate_bar[c] for c in self.coords})
        return e.subs(self.ansatz)

    def steady(self, e):
        """On the stationary solution: the ansatz with beta from the twisting balance."""
        return self.on_ansatz(e).subs(self.beta, self.beta_expr)


def _choose(table, what, value):
    if value not in table:
        raise ValueError(f"unknown {what} {value!r}")
    return table[value]


# --- kinematics ----------------------------------------------------------------

def euler_coordinates(d, rotor_angle):
    """The generalised coordinates: the stator's z-x-z Euler angles
    (kinematics.py), preceded by the rotor angle phi_R when the rotor turns
    freely (slip contact)."""
    d.phi_f, d.theta_f, d.psi_f = (sp.Function(n, real=True)(t)
                                   for n in ("phi", "theta", "psi"))
    d.kin = Kinematics(t, d.phi_f, d.theta_f, d.psi_f, P["R"], P["H"])
    _coordinates(d, [d.phi_f, d.theta_f, d.psi_f], ["phi", "theta", "psi"], rotor_angle)


def tilt_coordinates(d, rotor_angle):
    """Coordinates regular at theta = 0: the stator axis e_z2 in
    the co-rotating frame C (a, b), the spin angle chi = phi + psi
    (kinematics.py, TiltKinematics), preceded by the rotor angle phi_R when
    the rotor turns freely.  Frame C plays frame A's role: the rows are
    Euler's equations in C, where the ideal motor's equations are free of t."""
    a_f, b_f, chi_f = (sp.Function(n, real=True)(t) for n in ("a", "b", "chi"))
    d.kin = TiltKinematics(t, a_f, b_f, chi_f, P["R"], P["H"], OMEGA)
    d.phi_f = d.psi_f = None
    d.theta_f = d.kin.theta
    _coordinates(d, [a_f, b_f, chi_f], ["a", "b", "chi"], rotor_angle)


# Assumption coordinates: the stator's orientation coordinates.
COORDINATES = {"euler_zxz": euler_coordinates, "tilt_vector": tilt_coordinates}


def _coordinates(d, coords, coord_names, rotor_angle):
    d.coords = list(coords)
    d.coord_names = list(coord_names)
    d.phiR_f = None
    if rotor_angle:
        d.phiR_f = sp.Function("phi_R", real=True)(t)
        d.coords = [d.phiR_f] + d.coords
        d.coord_names = ["phi_R"] + d.coord_names
    d.nq = len(d.coords)
    d.q = [sp.Symbol(n, real=True) for n in d.coord_names]
    d.qd = [sp.Symbol(n + "dot", real=True) for n in d.coord_names]
    d.qdd = [sp.Symbol(n + "ddot", real=True) for n in d.coord_names]
    # q''(t), q'(t), q(t) -> plain symbols, highest order first
    d.subs_lists = ([(c.diff(t, 2), d.qdd[i]) for i, c in enumerate(d.coords)]
                    + [(c.diff(t), d.qd[i]) for i, c in enumerate(d.coords)]
                    + [(c, d.q[i]) for i, c in enumerate(d.coords)])


# --- contact: the normal force -------------------------------------------------

# Assumption spring_reference: the spring length is measured from Z(theta = 0)
# = H, or from Z = 0 as printed in (2.1).
SPRING_REFERENCE = {"theta0": P["H"], "literal": 0}


def normal_force(d, spring_reference):
    """(2.1) with the contact constraint (2.3): the rotor rides on the contact
    point at height Z, F_n = M Z'' + F0 + c_R (Z - Z_ref) + d_R Z'; through the
    named symbols Z, Z', Z'' (the document shows this form)."""
    Z_ref = _choose(SPRING_REFERENCE, "spring reference", spring_reference)
    Z = d.kin.Z
    d.Z_s, d.Zd_s, d.Zdd_s = sp.symbols("Z Zdot Zddot", real=True)
    d.F_n_generic = (P["M"] * d.Zdd_s + P["F0"] + P["c_R"] * (d.Z_s - Z_ref)
                     + P["d_R"] * d.Zd_s)
    d.F_n = d.F_n_generic.subs({d.Zdd_s: Z.diff(t, 2), d.Zd_s: Z.diff(t), d.Z_s: Z},
                               simultaneous=True)


# --- rotor coupling: stick or slip -----------------------------------------------

def _rotor_balance(d, w_R_generic):
    """The rotor's moment balance (2.2) for its speed w_R in the driving
    direction.  Newton's third law: the stator feels F_c = -F_t e_x1 - F_n e_z1
    (2.5); the rotor feels -F_c at r_c, whose moment about Z is -R* F_t, and the
    load T opposes the driving direction w_R = -phidot_R:
    I_R dw_R/dt = F_t R* - T."""
    d.Ft_s, d.Fn_s = sp.symbols("F_t F_n", real=True)
    d.wRdot_s, d.Rstar_s, d.vc_s, d.wR_s = sp.symbols("wdot_R R_star v_c w_R", real=True)
    d.w_R_generic = w_R_generic(d)
    d.w_R = d.w_R_generic.subs({d.vc_s: d.kin.v_c, d.Rstar_s: d.kin.R_star}, simultaneous=True)
    d.rotor_balance_generic = P["I_R"] * d.wRdot_s - (d.Ft_s * d.Rstar_s - P["T"])  # (2.2)
    d.rotor_balance = d.rotor_balance_generic.subs({d.wRdot_s: d.w_R.diff(t),
                                                    d.Rstar_s: d.kin.R_star})
    d.phiR_rate = -d.w_R


def stick_rotor_coupling(d):
    """No slip (2.4): the rotor turns with the stator's contact point,
    w_R = v_c / R*, and its moment balance (2.2) gives the friction force F_t."""
    _rotor_balance(d, lambda d: d.vc_s / d.Rstar_s)
    d.F_t = solve_linear(d.rotor_balance, d.Ft_s)
    d.v_rel = sp.Integer(0)
    d.v_rel_generic = None
    d.rotor_rows = []
    d.mu_expr, d.v_sym = None, None


def slip_rotor_coupling(d):
    """Slip (5.1): the rotor angle phi_R is free, w_R = -phidot_R; the friction
    force is F_t = mu(v_rel) F_n (friction law) at the slip velocity
    v_rel = v_c - w_R R*, and the rotor's moment balance (2.2) is a row of the
    equations of motion."""
    _rotor_balance(d, lambda d: -d.phiR_f.diff(t))
    d.v_rel_generic = d.vc_s - d.wR_s * d.Rstar_s                   # (5.1)
    d.v_rel = d.v_rel_generic.subs({d.vc_s: d.kin.v_c, d.wR_s: d.w_R, d.Rstar_s: d.kin.R_star},
                                   simultaneous=True)
    d.v_sym = sp.Symbol("v_rel", real=True)
    friction(d, d.assumptions["friction_law"])                       # (5.2)
    d.F_t = d.mu_expr.subs(d.v_sym, d.v_rel) * d.F_n
    d.rotor_rows = [d.rotor_balance.subs(d.Ft_s, d.F_t)]


def friction(d, law):
    """The friction law mu(v_rel) of the slip contact (5.2), from its formula
    (derive/variants.py, FRICTION_LAWS)."""
    d.mu_expr = friction_law(law, d.v_sym)


# Assumption contact: its step, and whether the rotor angle is a coordinate.
CONTACT = {"stick": (stick_rotor_coupling, False), "slip": (slip_rotor_coupling, True)}


# --- the stator: inertia, excitation, twist law, imperfections ----------------------

# Assumption stator_inertia: the moment of inertia I_yy.
STATOR_INERTIA = {"axisymmetric": P["I_xx"], "general": P["I_yy"]}


def stator_momentum(d, stator_inertia):
    """The stator's angular momentum L = I omega in frame A and its rate in
    the rotating frame A, dL/dt + phidot e_Z x L (left side of (2.6))."""
    Iyy = _choose(STATOR_INERTIA, "stator inertia", stator_inertia)
    kin = d.kin
    d.I_A = kin.tensor_in_A_from_K((P["I_xx"], Iyy, P["I_zz"]))
    d.L_A = d.I_A * kin.omega_A
    d.dLdt_A = d.L_A.diff(t) + kin.frame_A_rate.cross(d.L_A)


def excitation(d):
    """The excitation torque (2.8) of the ideal driver, in frame A."""
    Om = OMEGA
    d.M_E_A = (d.kin.C_NA.T * sp.Matrix([P["m0"] * sp.cos(Om * t),
                                         P["m0"] * sp.sin(Om * t), 0])
               ).applyfunc(sp.trigsimp)


def paper_twist(d):
    """The paper's twist angle phi + psi cos(theta) (2.9)."""
    if d.phi_f is None:
        raise RuntimeError("the paper's twist angle phi + psi cos(theta) needs the Euler "
                           "angles phi and psi apart (phi is singular at theta = 0): "
                           "regular coordinates take the integrated twist law")
    d.twist_angle = d.phi_f + d.psi_f * sp.cos(d.theta_f)
    d.extra_states, d.extra_names, d.extra_rates = [], [], []


def integrated_twist(d):
    """The twist angle as a state of its own, tau' = omega_Z."""
    tau = sp.Symbol("tau", real=True)
    d.twist_angle = tau
    d.extra_states, d.extra_names = [tau], ["tau"]
    d.extra_rates = [d.kin.omega_A[2]]


# Assumption twist.
TWIST = {"paper": paper_twist, "integrated": integrated_twist}


def restoring_moment(d):
    """The restoring moment (2.9) of tilt and twist stiffness.  The twist angle
    enters through a placeholder, so that the stationary problem can solve the
    twisting balance for its value whatever the twist law."""
    d.Tw = sp.Symbol("twist", real=True)
    d.M_R_A = P["c_r"] * d.kin.tilt_vector_A + sp.Matrix([0, 0, P["c_t"] * d.Tw])


def no_imperfection(d):
    """The ideal motor of the paper."""


def driver_stator_imperfection(d):
    """A real driver (amplitude imbalance, phase error) and a stator tilt
    stiffness split fixed in the housing, added to the ideal excitation and
    restoring moment."""
    if d.phi_f is None:
        raise RuntimeError("the imperfections are derived in Euler angles only")
    d.M_E_A = d.M_E_A + imperfect_excitation_A(d.kin, OMEGA)
    d.M_R_A = d.M_R_A + mode_split_moment_A(d.kin, d.coords[-3:])


# Assumption imperfection.
IMPERFECTION = {"none": no_imperfection, "driver_stator": driver_stator_imperfection}


def euler_equations(d):
    """Euler's equations (2.6) in frame A with the torques (2.7)-(2.11): the
    stator's rows, with the contact forces and the twist law substituted.
    The stationary quantities use the ideal motor's rows (``stator_generic``):
    the stationary solution (3.1) exists only there."""
    kin = d.kin
    d.ideal = {P[k]: sp.Integer(0) for k in IMPERFECTIONS}
    d.D_A = kin.tensor_in_A_from_N((P["d_r"], P["d_r"], P["d_t"]))
    d.M_D_A = d.D_A * kin.omega_A                                     # (2.10)
    d.F_c_A = -d.Ft_s * kin.e_x1_A - d.Fn_s * sp.Matrix([0, 0, 1])      # (2.5)
    d.M_C_A = kin.r_c_A.cross(d.F_c_A)                                # (2.11)
    stator = d.dLdt_A - (d.M_E_A - d.M_R_A - d.M_D_A + d.M_C_A)       # (2.6), (2.7)
    d.stator_rows = list(stator.subs({d.Ft_s: d.F_t, d.Fn_s: d.F_n, d.Tw: d.twist_angle}))
    d.stator_generic = stator.xreplace(d.ideal)
    d.M_E_A_ideal = d.M_E_A.xreplace(d.ideal)


# --- the same for every variant ------------------------------------------------------

def equations_of_motion(d):
    """The first-order form M(x) x' = f(x, t): the rows are linear in the
    accelerations, M_q qdd = f_q; positions and the extra states have rate
    rows of their own."""
    rows = [d.plain(r) for r in d.rotor_rows + d.stator_rows]
    d.M_q = sp.Matrix(rows).jacobian(d.qdd)
    d.f_q = -sp.Matrix(rows).subs({a: 0 for a in d.qdd})
    nq = d.nq
    n = d.n = 2 * nq + len(d.extra_states)
    d.states = d.q + d.qd + d.extra_states
    d.state_names = d.coord_names + [c + "dot" for c in d.coord_names] + d.extra_names
    mass = sp.zeros(n, n)
    for i in range(nq):
        mass[i, i] = 1
    mass[nq:2 * nq, nq:2 * nq] = d.M_q
    for i in range(len(d.extra_states)):
        mass[2 * nq + i, 2 * nq + i] = 1
    d.mass = mass
    d.rhs = sp.Matrix(d.qd + list(d.f_q) + [d.plain(r) for r in d.extra_rates])
    d.v = [sp.Symbol(f"v{i}", real=True) for i in range(n)]


def motion_outputs(d):
    """Derived quantities along any motion (x, x')."""
    plain, kin = d.plain, d.kin
    d.xdot = [sp.Symbol(nm + "_rate", real=True) for nm in d.state_names]
    xdot_subs = {d.qdd[i]: d.xdot[d.nq + i] for i in range(d.nq)}
    d.outputs = {
        "R_star": plain(kin.R_star),
        "Z": plain(kin.Z),
        "v_c": plain(kin.v_c),
        "F_n": plain(d.F_n).subs(xdot_subs),
        "F_t": plain(d.F_t).subs(xdot_subs),
        "v_rel": plain(d.v_rel),
        "rotor_speed": plain(d.phiR_rate),
    }


def stationary_ansatz(d):
    """The stationary ansatz (3.1): phi = Omega t + alpha, theta constant,
    psi = -Omega t / cos(theta) + beta, and phi_R = phidot_R t when the rotor
    angle is a coordinate; the unknowns u of the stationary problem."""
    Om = OMEGA
    theta_b, alpha, d.beta = sp.symbols("theta alpha beta", real=True)
    d.unknowns = [theta_b, alpha]
    d.unknown_names = ["theta", "alpha"]
    psi_rate = -Om / sp.cos(theta_b)
    d.ansatz = {d.phi_f: Om * t + alpha, d.theta_f: theta_b,
                d.psi_f: psi_rate * t + d.beta}                      # (3.1)
    d.rate_bar = {d.phi_f: Om, d.theta_f: 0, d.psi_f: psi_rate}
    if d.phiR_f is not None:
        wR = sp.Symbol("phidot_R", real=True)
        d.unknowns.append(wR)
        d.unknown_names.append("phidot_R")
        d.ansatz[d.phiR_f] = wR * t
        d.rate_bar[d.phiR_f] = wR


def stationary_residual(d):
    """The residuals (3.3)-(3.5): the x1, y1 rows of Euler's equations on the
    ansatz (and the rotor's row); free of t, or the variant has no stationary
    solution."""
    on_ansatz = d.on_ansatz
    # The stator rows on the ansatz, with the contact forces still symbols:
    # small expressions, so trigsimp turns the cos^2 + sin^2 - 1 terms
    # (omega_Z = 0 on the orbit) into exact zeros instead of rounding noise of
    # size eps*Omega, and halves the operation count.  The contact law is
    # substituted afterwards, so the cost does not depend on it.
    d.stator_steady = [sp.trigsimp(on_ansatz(r)) for r in list(d.stator_generic)[:2]]
    d.contact_bar = {d.Ft_s: on_ansatz(d.F_t), d.Fn_s: on_ansatz(d.F_n)}
    residual_rows = ([on_ansatz(r) for r in d.rotor_rows]
                     + [r.subs(d.contact_bar) for r in d.stator_steady])
    for r in residual_rows:
        if t in r.free_symbols or d.Tw in r.free_symbols:
            raise RuntimeError("stationary residual depends on time: "
                               "the ansatz (3.1) is not a solution of this variant")
    d.residual = sp.Matrix(residual_rows)


def twisting_balance(d):
    """The z1 row on the ansatz: the twist angle on the stationary solution,
    and beta from it (3.6)."""
    on_ansatz, phi_f, psi_f, theta_f = d.on_ansatz, d.phi_f, d.psi_f, d.theta_f
    d.z_row = on_ansatz(list(d.stator_generic)[2].subs(d.contact_bar))
    # small expression: simplification makes omega_Z = 0 on the orbit exact.
    # The contact law is substituted afterwards, as for the stator rows: a
    # friction law with exp() makes simplify() take many minutes otherwise.
    d.twist_bar = sp.simplify(solve_linear(on_ansatz(list(d.stator_generic)[2]), d.Tw)
                              ).subs(d.contact_bar)
    if t in d.twist_bar.free_symbols:
        raise RuntimeError("twisting balance depends on time")
    # beta from the paper's twist angle phi + psi cos(theta) = twist_bar at any
    # t (3.6); under the integrated law tau = twist_bar and psi's phase is free
    # (psi is cyclic), and the same beta is used by convention.
    d.beta_expr = solve_linear(sp.expand(on_ansatz(phi_f + psi_f * sp.cos(theta_f)))
                               - d.twist_bar, d.beta)
    if t in d.beta_expr.free_symbols:
        raise RuntimeError("beta depends on time")


def stationary_outputs(d):
    """Quantities on the stationary solution, (3.7) and section 5."""
    steady, kin, theta_b = d.steady, d.kin, d.unknowns[0]
    d.steady_outputs = {
        "beta": d.beta_expr,
        "rotor_speed": steady(d.phiR_rate),
        "F_n": steady(d.F_n),
        "F_t": steady(d.F_t),
        "v_c": steady(kin.v_c),
        "v_rel": steady(d.v_rel),
        "R_star": kin.R_star.subs(d.theta_f, theta_b),
        "Z": kin.Z.subs(d.theta_f, theta_b),
        "twist": d.twist_bar,
    }


def stationary_power(d):
    """Power on the stationary solution, from the same torques and
    forces as the equations of motion: the excitation torque (2.8) and the
    damping torque (2.10) times the stator's angular velocity, the rotor's
    axial damping force times Z', the load times the rotor's speed in its
    driving direction, and the friction force times the slip velocity.  In
    frame A every one of them is constant on the orbit (checked below), so
    the mean over a period is the value itself.  Their balance
    power_in = power_out + power_damping + power_slip is not built in: it
    holds only where the residuals vanish (tests/solve/test_steady_power.c)."""
    kin = d.kin
    power_exprs = {
        "power_in": (d.M_E_A_ideal.T * kin.omega_A)[0],
        "power_out": P["T"] * d.w_R,
        "power_damping": (d.M_D_A.T * kin.omega_A)[0] + P["d_R"] * kin.Z.diff(t) ** 2,
        # F_t stays a symbol through trigsimp (a friction law with exp() makes
        # it take many minutes otherwise); it is constant on the orbit.
        "power_slip": d.Ft_s * d.v_rel,
    }
    d.steady_power = {}
    for key, e in power_exprs.items():
        e = sp.trigsimp(d.steady(e)).subs(d.Ft_s, d.steady(d.F_t))
        if t in e.free_symbols:
            raise RuntimeError(f"{key} depends on time on the stationary solution")
        d.steady_power[key] = e


def stationary_orbit(d):
    """The state on the stationary orbit and its rate, for any t (used by
    Floquet); the extra state (the integrated twist angle) is the twisting
    balance's value."""
    xbar = [d.ansatz[c] for c in d.coords] + [d.rate_bar[c] for c in d.coords]
    xbar_rate = [sp.diff(e, t) for e in xbar]
    for _ in d.extra_states:
        xbar.append(d.twist_bar)
        xbar_rate.append(sp.Integer(0))
    d.steady_state = sp.Matrix(xbar)
    d.steady_rate = sp.Matrix(xbar_rate)


def stationary_seed(d):
    """Seed for the root search: at given theta the stator rows are linear in
    (cos alpha, sin alpha) once the steady contact forces are known; solving
    that 2x2 system gives alpha, and |(cos, sin)| = 1 is a scalar equation in
    theta alone whose sign changes bracket every stationary solution."""
    alpha = d.unknowns[1]
    C, S = sp.symbols("C S", real=True)
    Ft_steady = solve_linear(d.on_ansatz(d.rotor_balance), d.Ft_s)
    Fn_steady = d.on_ansatz(d.F_n)
    lin = [sp.expand(r.subs({d.Ft_s: Ft_steady, d.Fn_s: Fn_steady}))
           .subs({sp.cos(alpha): C, sp.sin(alpha): S}) for r in d.stator_steady]
    for r in lin:
        if alpha in r.free_symbols:
            raise RuntimeError("stator rows are not linear in cos/sin alpha")
    A, bvec = sp.linear_eq_to_matrix(lin, [C, S])
    det = A[0, 0] * A[1, 1] - A[0, 1] * A[1, 0]
    Cs = (bvec[0] * A[1, 1] - A[0, 1] * bvec[1]) / det
    Ss = (A[0, 0] * bvec[1] - bvec[0] * A[1, 0]) / det
    d.seed = {"amplitude_mismatch": Cs**2 + Ss**2 - 1, "cos_alpha": Cs, "sin_alpha": Ss,
              "F_t": Ft_steady, "F_n": Fn_steady}


def tangent_map(d):
    """Well-conditioned perturbation coordinates.  Near theta = 0 a z-x-z
    perturbation (dphi, dtheta, dpsi) is dominated by dphi + dpsi ~ 0 pairs,
    and the linearisation spans ~17 orders of magnitude.  The small-rotation
    vector in frame A, d(rot) = L(theta) dq with L = d(omega_A)/d(qdot), maps
    angles and rates alike to physically comparable components."""
    names = d.coord_names
    L = d.kin.omega_A.applyfunc(d.plain).jacobian([d.qd[names.index(c)]
                                                  for c in ("phi", "theta", "psi")])
    d.tangent_map = sp.eye(d.n)
    e_idx = [names.index(c) for c in ("phi", "theta", "psi")]
    for block in (0, d.nq):
        for a in range(3):
            for b in range(3):
                d.tangent_map[block + e_idx[a], block + e_idx[b]] = L[a, b]


def linearisation(d):
    """Jacobians df/dx and d(M v)/dx; whether the linearisation about the
    stationary orbit depends on time; and its directional derivative along
    (du, dt, dp) for the sensitivity of the Floquet multipliers."""
    states, n = d.states, d.n
    d.jac_rhs = d.rhs.jacobian(states)
    d.jac_mass = (d.mass * sp.Matrix(d.v)).jacobian(states)
    # Does the linearisation about the stationary orbit depend on time?  In
    # frame A it is constant except where an angle enters other than through
    # phi - Omega t (the paper's twist angle phi + psi cos(theta) does).
    on_orbit = dict(zip(states, d.steady_state))
    jac_rhs_ideal, jac_mass_ideal = d.jac_rhs.xreplace(d.ideal), d.jac_mass.xreplace(d.ideal)
    if d.regular:
        A_bar = d.put(jac_rhs_ideal - d.put(jac_mass_ideal, dict(zip(d.v, d.steady_rate))),
                      on_orbit)
        M_bar = d.put(d.mass, on_orbit)
    else:
        A_bar = (jac_rhs_ideal - jac_mass_ideal.subs(dict(zip(d.v, d.steady_rate)))
                 ).subs(on_orbit)
        M_bar = d.mass.subs(on_orbit)
    d.t0_independent = (t not in A_bar.free_symbols and t not in M_bar.free_symbols)
    d.A_bar_t_entries = [(i, j) for i in range(n) for j in range(n)
                         if t in A_bar[i, j].free_symbols]
    # Directional derivative of the linearisation about the orbit: M(xbar)
    # and A = df/dx - d(M v)/dx |_{v = xbar'} as functions of (u, t, p) with
    # beta from the twisting balance, differentiated along (du, dt, dp).  One
    # direction per call keeps this a sum of first derivatives of the
    # linearisation (second derivatives of the equations of motion).
    orbit_beta = {**on_orbit, **dict(zip(d.v, d.steady_rate))}
    orbit_beta = {k: sp.sympify(e).subs(d.beta, d.beta_expr) for k, e in orbit_beta.items()}
    A_full = d.put(jac_rhs_ideal - jac_mass_ideal, orbit_beta)
    M_full = d.put(d.mass, orbit_beta)
    # (the imperfections are 0 here: their directions have no stationary orbit)
    d.dir_vars = list(d.unknowns) + [t] + [P[k] for k, *_ in PARAMETERS]
    d.dir_syms = [sp.Symbol("dir_" + s.name, real=True) for s in d.dir_vars]

    def along(e):
        return sum((sp.diff(e, s) * ds for s, ds in zip(d.dir_vars, d.dir_syms)
                    if s in e.free_symbols), sp.Integer(0))
    d.floquet_direction = [along(e) for e in M_full] + [along(e) for e in A_full]


def cyclic_states(d):
    """The states in neither M nor f (their value does not matter)."""
    d.cyclic = [i for i, s in enumerate(d.states)
                if s not in d.rhs.free_symbols and s not in d.mass.free_symbols]


# --- closure: whether the contact may open ------------------------------

def bilateral_closure(d):
    """The paper's contact (2.3): the rotor rides on the stator's contact
    point at all times, F_n may take any sign."""
    d.unilateral = None


def _block_inverse(A):
    """Inverse of a matrix whose nonzero pattern is block diagonal (after a
    permutation): each connected block by its adjugate, without simplification
    (A's entries are placeholder symbols here, so the formulas stay small)."""
    n = A.shape[0]
    seen, inv = set(), sp.zeros(n, n)
    for i in range(n):
        if i in seen:
            continue
        block, todo = [], [i]
        while todo:
            k = todo.pop()
            if k in block:
                continue
            block.append(k)
            todo += [j for j in range(n) if j not in block and (A[k, j] != 0 or A[j, k] != 0)]
        block.sort()
        seen |= set(block)
        sub = A.extract(block, block)
        si = sub.inv(method="ADJ") if len(block) > 1 else sp.Matrix([[1 / sub[0, 0]]])
        for a, ia in enumerate(block):
            for b, ib in enumerate(block):
                inv[ia, ib] = si[a, b]
    return inv


def _placeholders(mat, stem):
    """A matrix of the same shape whose nonzero entries are fresh symbols,
    and the map symbol -> entry."""
    out, back = sp.zeros(*mat.shape), {}
    for i in range(mat.shape[0]):
        for j in range(mat.shape[1]):
            if mat[i, j] != 0:
                s = sp.Symbol(f"{stem}_{i}_{j}", real=True)
                out[i, j], back[s] = s, mat[i, j]
    return out, back


def _total_jacobian(exprs, y, back):
    """d exprs / d y where exprs are written in the placeholders of ``back``
    (symbol -> expression of y): the chain rule through the placeholders, so
    that no large expression is differentiated."""
    syms = list(back)
    D = sp.Matrix([[sp.diff(back[s], v) for v in y] for s in syms])
    rows = []
    for e in exprs:
        direct = [sp.diff(e, v) for v in y]
        through = [sp.diff(e, s) for s in syms]
        rows.append([direct[j] + sum((through[k] * D[k, j] for k in range(len(syms))
                                      if through[k] != 0 and D[k, j] != 0), sp.Integer(0))
                     for j in range(len(y))])
    return sp.Matrix(rows)


def unilateral_closure(d):
    """The contact may open.  Two modes:

    closed: the model above (the rotor rides on the contact point, (2.3));
      it holds while F_n >= 0; its guard is F_n = 0 (F_n falling).
    open:   the rotor's axial position Z_R and rate are states of their own:
      M Z_R'' + F0 + c_R (Z_R - Z_ref) + d_R Z_R' = 0 (2.1 with F_n = 0); the
      stator's rows (2.6) with F_n = F_t = 0; the rotor's moment balance (2.2)
      with F_t = 0 (the load T alone decelerates it), its speed w_R a state of
      its own in the stick model.  It holds while the gap Z_R - Z(theta) >= 0;
      its guard is gap = 0 (gap falling).
    separation (closed -> open): y = (x, Z(theta), Z', w_R(x)): continuous.
    impact (open, gap = 0, gap' < 0): impulses P_n (normal) and P_t
      (tangential) act on stator and rotor as the forces F_n, F_t do:
      M_a dv = B (P_n, P_t), M_a the open mode's mass matrix of the
      accelerations, B their force coefficients.  The contact velocities
      (gap', v_rel) = G v change by W P, W = G M_a^-1 B; Newton's law
      gap'+ = -e gap'- with, first, sticking v_rel+ = 0 (P from W); if then
      |P_t| > mu0 P_n, sliding P_t = s mu0 P_n (s the sign of the sticking
      P_t) with the normal law alone.
    """
    kin, plain = d.kin, d.plain
    stick = d.phiR_f is None
    Z_R, Z_Rd, Z_Rdd = sp.symbols("Z_R Z_Rdot Z_Rddot", real=True)
    new, new_names = [Z_R, Z_Rd], ["Z_R", "Z_Rdot"]
    acc_new = [Z_Rdd]
    if stick:
        w_R, w_Rd = sp.symbols("w_R w_Rdot", real=True)
        new.append(w_R)
        new_names.append("w_R")
        acc_new.append(w_Rd)
    n = d.n
    y = list(d.states) + new
    ny = len(y)
    # the open mode's rows with the contact forces as symbols (B comes out of them)
    stator = d.dLdt_A - (d.M_E_A - d.M_R_A - d.M_D_A + d.M_C_A)                  # (2.6)
    rows = [plain(r) for r in _rotor_rows_forces(d)] if not stick else []
    rows += [plain(r) for r in stator.subs(d.Tw, d.twist_angle)]
    rows.append(d.F_n_generic.subs({d.Zdd_s: Z_Rdd, d.Zd_s: Z_Rd, d.Z_s: Z_R},
                                   simultaneous=True) - d.Fn_s)                # (2.1)
    if stick:
        rows.append(P["I_R"] * w_Rd - (d.Ft_s * plain(kin.R_star) - P["T"]))    # (2.2)
    rows = sp.Matrix(rows)
    acc = list(d.qdd) + acc_new
    forces = [d.Fn_s, d.Ft_s]
    M_a = rows.jacobian(acc)
    B = -rows.jacobian(forces)
    for e in list(M_a) + list(B):
        if set(acc + forces) & e.free_symbols:
            raise RuntimeError("open-mode rows are not linear in the accelerations and forces")
    f_a = -rows.subs({a: 0 for a in acc + forces})
    # positions of the velocities in y (the rows of the accelerations)
    nq = d.nq
    pos = [nq + i for i in range(nq)] + [n + 1] + ([n + 2] if stick else [])
    mass = sp.eye(ny)
    rhs = sp.Matrix(list(d.qd) + [0] * nq + [plain(r) for r in d.extra_rates] + [Z_Rd, 0]
                    + ([0] if stick else []))
    for i, pi in enumerate(pos):
        for j, pj in enumerate(pos):
            mass[pi, pj] = M_a[i, j]
        rhs[pi] = f_a[i]
    v = [sp.Symbol(f"v{i}", real=True) for i in range(ny)]
    # outputs along an open motion, in the order of OUTPUT_NAMES
    w_open = w_R if stick else plain(d.w_R)
    v_rel = plain(kin.v_c) - w_open * plain(kin.R_star)
    outputs = {"R_star": plain(kin.R_star), "Z": plain(kin.Z), "v_c": plain(kin.v_c),
               "F_n": sp.Integer(0), "F_t": sp.Integer(0), "v_rel": v_rel,
               "rotor_speed": -w_open}
    ydot = [sp.Symbol(nm + "_rate", real=True) for nm in d.state_names + new_names]
    # guards
    F_n = d.outputs["F_n"]
    gap = Z_R - plain(kin.Z)
    gap_rate = Z_Rd - plain(kin.Z.diff(t))
    # separation: the rotor leaves the contact point with its position and rates
    sep = sp.Matrix(list(d.states) + [plain(kin.Z), plain(kin.Z.diff(t))]
                    + ([plain(d.w_R)] if stick else []))
    # impact: placeholders for M_a, B, G keep the formulas small
    vel = [y[p_] for p_ in pos]
    cv = sp.Matrix([gap_rate, v_rel])
    G = cv.jacobian(vel)
    if (cv - G * sp.Matrix(vel)).applyfunc(sp.expand) != sp.zeros(2, 1):
        raise RuntimeError("contact velocities are not linear in the velocities")
    Mp, back = _placeholders(M_a, "m")
    Bp, bb = _placeholders(B, "b")
    Gp, gb = _placeholders(G, "g")
    back.update(bb)
    back.update(gb)
    Minv_B = _block_inverse(Mp) * Bp
    W = Gp * Minv_B
    u = Gp * sp.Matrix(vel)
    e = P["e_impact"]
    s_sym = sp.Symbol("s", real=True)
    detW = W[0, 0] * W[1, 1] - W[0, 1] * W[1, 0]
    rhs_stick = sp.Matrix([-(1 + e) * u[0], -u[1]])
    P_stick = sp.Matrix([(W[1, 1] * rhs_stick[0] - W[0, 1] * rhs_stick[1]) / detW,
                         (W[0, 0] * rhs_stick[1] - W[1, 0] * rhs_stick[0]) / detW])
    Pn_slide = -(1 + e) * u[0] / (W[0, 0] + s_sym * P["mu0"] * W[0, 1])
    P_slide = sp.Matrix([Pn_slide, s_sym * P["mu0"] * Pn_slide])

    def after(Pvec):
        dv = Minv_B * Pvec
        out = list(y)
        for i, p_ in enumerate(pos):
            out[p_] = y[p_] + dv[i]
        return out + list(Pvec)
    impact_stick = after(P_stick)
    impact_slide = after(P_slide)
    jac_stick = _total_jacobian(impact_stick[:ny], y, back)
    jac_slide = _total_jacobian(impact_slide[:ny], y, back)
    fill = {k: v_ for k, v_ in back.items()}
    impact_stick = [sp.sympify(x_).xreplace(fill) for x_ in impact_stick]
    impact_slide = [sp.sympify(x_).xreplace(fill) for x_ in impact_slide]
    jac_stick = jac_stick.xreplace(fill)
    jac_slide = jac_slide.xreplace(fill)
    # kinetic energy of the open state: the stator's (I_A from its principal
    # moments, independent of the rows above), the rotor's axial and turning
    omega = kin.omega_A.applyfunc(plain)
    kinetic = ((omega.T * d.I_A.applyfunc(plain) * omega)[0] / 2 + P["M"] * Z_Rd ** 2 / 2
               + P["I_R"] * w_open ** 2 / 2)
    d.unilateral = {
        "states": y, "state_names": d.state_names + new_names, "new_names": new_names,
        "ny": ny, "mass": mass, "rhs": rhs, "v": v,
        "jac_rhs": rhs.jacobian(y), "jac_mass": (mass * sp.Matrix(v)).jacobian(y),
        "outputs": outputs, "ydot": ydot,
        "guard_closed": F_n, "guard_closed_grad": [sp.diff(F_n, s_) for s_ in d.states]
        + [sp.diff(F_n, s_) for s_ in d.xdot],
        "gap": gap, "gap_grad": [sp.diff(gap, s_) for s_ in y],
        "contact_velocity": [gap_rate, v_rel],
        "contact_velocity_grad": list(cv.jacobian(y)),
        "separation": sep, "separation_jac": sep.jacobian(d.states),
        "impact_stick": impact_stick, "impact_slide": impact_slide, "s": s_sym,
        "impact_stick_jac": jac_stick, "impact_slide_jac": jac_slide,
        "kinetic": kinetic,
        # explicit time derivatives of f (the excitation), for the guards' rates
        "closed_rhs_t": d.rhs.diff(t), "open_rhs_t": rhs.diff(t),
        # for the documents
        "rows": rows, "acc": acc, "forces": forces, "Z_R": Z_R,
    }


def _rotor_rows_forces(d):
    """The rotor's moment balance (2.2) with F_t a symbol (slip models)."""
    return [d.rotor_balance]


# Assumption closure.
CLOSURE = {"bilateral": bilateral_closure, "unilateral": unilateral_closure}


def document_pieces(d):
    """Pieces for the readable export (derive/usm_derive/emit_doc.py)."""
    kin, plain = d.kin, d.plain
    phi_f, theta_f, psi_f = d.phi_f, d.theta_f, d.psi_f
    z_row = d.z_row
    return {
        "C_NA": kin.C_NA, "C_AB": kin.C_AB, "C_BK": kin.C_BK,
        "omega_K": kin.omega_K.applyfunc(plain), "omega_A": kin.omega_A.applyfunc(plain),
        "r_c_A": kin.r_c_A.applyfunc(plain), "R_star": plain(kin.R_star), "Z": plain(kin.Z),
        "v_c": plain(kin.v_c), "F_n": plain(d.F_n), "F_t": plain(d.F_t),
        "v_rel": plain(d.v_rel),
        "w_R": plain(d.w_R), "rotor_rows": [plain(r) for r in d.rotor_rows],
        "rotor_balance": d.rotor_balance_generic,
        "F_t_generic": solve_linear(d.rotor_balance_generic, d.Ft_s),
        "friction": d.mu_expr, "v_sym": d.v_sym,
        "I_A": d.I_A.applyfunc(plain), "L_A": d.L_A.applyfunc(plain),
        "M_E_A": d.M_E_A.applyfunc(plain),
        "M_R_A": d.M_R_A.applyfunc(plain).subs(d.Tw, plain(d.twist_angle)),
        "M_D_A": d.M_D_A.applyfunc(plain), "M_C_A": d.M_C_A,
        "extra_rates": [plain(r) for r in d.extra_rates], "extra_names": d.extra_names,
        "M_q": d.M_q, "f_q": d.f_q, "residual": d.residual, "beta": d.beta_expr,
        "twist": d.twist_bar, "qdd": d.qdd, "qd": d.qd, "q": d.q,
        "rotor_speed_bar": d.steady_outputs["rotor_speed"],
        "v_rel_bar": d.steady_outputs["v_rel"],
        "beta_generic": solve_linear(sp.expand(d.on_ansatz(phi_f + psi_f * sp.cos(theta_f)))
                                     - d.Tw, d.beta),
        "twist_display": sp.simplify(solve_linear(
            z_row.subs(d.steady_outputs["v_rel"], d.v_sym) if d.v_sym is not None else z_row,
            d.Tw)),
        "ansatz": {c_name: d.ansatz[c] for c_name, c in zip(d.coord_names, d.coords)},
        # The generic pieces of the derivation, for the document's named form
        # (derive/usm_derive/emit_doc.py): functions of t, placeholders kept.
        "kin": kin, "coords": d.coords, "coord_names": d.coord_names,
        "F_n_generic": d.F_n_generic,
        "w_R_generic": d.w_R_generic, "v_rel_generic": d.v_rel_generic,
        "contact_symbols": {"F_t": d.Ft_s, "F_n": d.Fn_s, "Z": d.Z_s, "Zdot": d.Zd_s,
                            "Zddot": d.Zdd_s, "wdot_R": d.wRdot_s, "R_star": d.Rstar_s,
                            "v_c": d.vc_s, "w_R": d.wR_s, "twist": d.Tw},
        "stator_generic": d.stator_generic, "dLdt_A": d.dLdt_A, "F_c_A": d.F_c_A,
        "M_E_A_t": d.M_E_A, "M_R_A_t": d.M_R_A, "M_D_A_t": d.M_D_A, "M_C_A_t": d.M_C_A,
        "twist_angle": d.twist_angle, "extra_states": d.extra_states,
        "extra_rates_t": d.extra_rates,
        "steady_rate": d.steady_rate, "t0_independent": d.t0_independent,
        "A_bar_t_entries": d.A_bar_t_entries,
    }


def _equations(d, coordinates):
    """The equations of motion, assumption by assumption, in the order of the
    paper; ``coordinates`` is the step of the assumption coordinates."""
    assumptions = d.assumptions
    rotor_coupling, rotor_angle = _choose(CONTACT, "contact law", assumptions["contact"])
    twist = _choose(TWIST, "twist law", assumptions["twist"])
    imperfection = _choose(IMPERFECTION, "imperfection",
                           assumptions.get("imperfection", "none"))
    coordinates(d, rotor_angle)
    normal_force(d, assumptions["spring_reference"])
    rotor_coupling(d)            # stick, or slip with its friction law
    stator_momentum(d, assumptions["stator_inertia"])
    excitation(d)
    twist(d)
    restoring_moment(d)
    imperfection(d)
    euler_equations(d)
    equations_of_motion(d)
    motion_outputs(d)


# Derivations that models share, kept for the rest of one run (one process):
# a model whose contact may open is its bilateral model's derivation plus the
# closure, and the tilt models take the stationary problem of the Euler
# angles of the same assumptions.  (prefix key, stage) -> a Derivation; a
# stage is a shallow copy, and the later steps only add attributes, so a
# kept stage is never changed by its users.  derive/generate.py derives the
# models of one base model in one process so that these are found.
_SHARED = {}


def _shared_key(assumptions):
    """The assumptions the derivation depends on before the closure."""
    return tuple(sorted((k, v) for k, v in assumptions.items() if k != "closure"))


def _copy(d, name, assumptions):
    e = copy.copy(d)
    e.name, e.assumptions = name, dict(assumptions)
    return e


def _derive_euler(name, assumptions, stationary_only=False):
    """The derivation in the paper's z-x-z Euler angles (with stationary_only,
    up to the stationary problem: what _derive_regular takes from it)."""
    key = _shared_key(assumptions)
    linearised = _SHARED.get((key, "linearised"))
    if linearised is None:
        stationary = _SHARED.get((key, "stationary"))
        if stationary is None:
            d = Derivation(name, assumptions)
            _equations(d, euler_coordinates)
            # what every variant derives from them
            stationary_ansatz(d)
            stationary_residual(d)
            twisting_balance(d)
            stationary_outputs(d)
            stationary_power(d)
            stationary_orbit(d)
            stationary_seed(d)
            _SHARED[(key, "stationary")] = _copy(d, name, assumptions)
        else:
            d = _copy(stationary, name, assumptions)
        if stationary_only:
            return d
        tangent_map(d)
        linearisation(d)
        cyclic_states(d)
        # the document reads nothing the closure adds
        d.document = document_pieces(d)
        _SHARED[(key, "linearised")] = _copy(d, name, assumptions)
    else:
        if stationary_only:
            return _copy(linearised, name, assumptions)
        d = _copy(linearised, name, assumptions)
    _choose(CLOSURE, "closure", assumptions.get("closure", "bilateral"))(d)
    return d


# --- regular coordinates: the stationary problem of the Euler angles ----------------

def _derive_regular(name, assumptions, coordinates):
    """The derivation in coordinates other than the Euler angles.
    The equations of motion are derived in them from the same kinematics and
    force laws; the stationary problem (unknowns theta, alpha, phidot_R, its
    residuals, seed, outputs and power) is the Euler angles' own, derived
    alongside, and its orbit is mapped into the new coordinates
    (``regular_orbit``).  So the stationary solution of both coordinate sets
    is one and the same, and the tests check that the mapped orbit solves the
    new equations (tests/solve/test_steady_floquet.c, kernel residual)."""
    if assumptions.get("closure", "bilateral") != "bilateral":
        raise RuntimeError("the unilateral contact is derived in Euler angles only")
    euler = {k: v for k, v in assumptions.items() if k != "coordinates"}
    e = _derive_euler(name, euler, stationary_only=True)
    d = Derivation(name, assumptions)
    d.regular = True
    _equations(d, coordinates)
    d.euler = e
    for key in ("unknowns", "unknown_names", "residual", "steady_outputs", "steady_power",
                "seed", "beta", "beta_expr", "twist_bar"):
        setattr(d, key, getattr(e, key))
    regular_orbit(d, e)
    d.tangent_map = sp.eye(d.n)   # the coordinates are regular: no tangent map needed
    linearisation(d)
    cyclic_states(d)
    bilateral_closure(d)
    kin = d.kin
    d.document = {"plain": d.plain, "coords": d.coords, "slip": d.phiR_f is not None,
                  "euler_name": _euler_name(name), "e_z2": kin.e_z2, "C_tilt": kin.C_tilt,
                  "omega": kin.omega_A, "r_c": kin.r_c_A, "R_star": kin.R_star, "Z": kin.Z,
                  "v_c": kin.v_c, "F_n": d.F_n, "w_R": d.w_R, "F_t": d.F_t}
    return d


def _euler_name(name):
    import variants
    models = variants.generated_models()
    spec = {m[0]: m[3] for m in models}.get(name, {})
    rest = {k: v for k, v in spec.items() if k != "coordinates"}
    return next((m[0] for m in models if m[3] == rest), "?")


def regular_orbit(d, e):
    """The stationary orbit xbar(t) and its rate in the regular coordinates:
    the Euler angles' orbit (3.1) mapped through the kinematics
    (TiltKinematics.from_euler), simplified entry by entry (small)."""
    mapped = d.kin.from_euler(e.kin, OMEGA, t)
    if e.phiR_f is not None:
        mapped = [e.phiR_f] + mapped
    pos = [sp.simplify(e.on_ansatz(c)) for c in mapped]
    vel = [sp.simplify(e.on_ansatz(c.diff(t))) for c in mapped]
    xbar = pos + vel + [d.twist_bar for _ in d.extra_states]
    d.steady_state = sp.Matrix(xbar)
    d.steady_rate = sp.Matrix([sp.simplify(sp.diff(x, t)) for x in xbar])


def derive_model(name, assumptions):
    """The Model of one variant: assumptions as in derive/variants.py, each
    choice a step of the tables above, applied in the order of the paper."""
    coordinates = _choose(COORDINATES, "coordinates",
                          assumptions.get("coordinates", "euler_zxz"))
    if coordinates is euler_coordinates:
        d = _derive_euler(name, assumptions)
    else:
        d = _derive_regular(name, assumptions, coordinates)
    return Model(name=name, assumptions=dict(assumptions), states=d.states,
                 state_names=d.state_names, mass=d.mass, rhs=d.rhs, v=d.v,
                 outputs=d.outputs, xdot=d.xdot, unknowns=d.unknowns,
                 unknown_names=d.unknown_names, residual=d.residual,
                 steady_outputs=d.steady_outputs, steady_state=d.steady_state,
                 steady_rate=d.steady_rate, seed=d.seed, friction=d.mu_expr,
                 v_rel=d.v_sym, tangent_map=d.tangent_map, jac_rhs=d.jac_rhs,
                 jac_mass=d.jac_mass, t0_independent=d.t0_independent, cyclic=d.cyclic,
                 equations=d.document, steady_power=d.steady_power,
                 floquet_direction=d.floquet_direction,
                 direction_symbols=list(zip(d.dir_vars, d.dir_syms)),
                 unilateral=d.unilateral)
