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
from dataclasses import dataclass, field
import sympy as sp

from .kinematics import Kinematics

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
    # Imperfections of a real motor (issue 14); they enter only the models
    # whose assumption imperfection is "driver_stator" (variant imperfect).
    ("amp_imbalance", "1", "amplitude imbalance e of the two excitation phases", "any"),
    ("phase_error", "rad", "phase error delta of the second excitation phase", "any"),
    ("mode_split", "1", "tilt stiffness split s: c_r (1 + s) about X, c_r (1 - s) about Y", "any"),
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


def derive_model(name, assumptions):
    """The Model of one variant: assumptions as in derive/variants.py."""
    contact = assumptions["contact"]
    twist = assumptions["twist"]
    spring_reference = assumptions["spring_reference"]
    inertia = assumptions["stator_inertia"]
    p = P
    R, H = p["R"], p["H"]

    phi_f, theta_f, psi_f = (sp.Function(n, real=True)(t)
                             for n in ("phi", "theta", "psi"))
    kin = Kinematics(t, phi_f, theta_f, psi_f, R, H)
    coords = [phi_f, theta_f, psi_f]
    coord_names = ["phi", "theta", "psi"]
    if contact == "slip":
        phiR_f = sp.Function("phi_R", real=True)(t)
        coords = [phiR_f] + coords
        coord_names = ["phi_R"] + coord_names
    nq = len(coords)

    q = [sp.Symbol(n, real=True) for n in coord_names]
    qd = [sp.Symbol(n + "dot", real=True) for n in coord_names]
    qdd = [sp.Symbol(n + "ddot", real=True) for n in coord_names]
    # q''(t), q'(t), q(t) -> plain symbols, highest order first
    subs_lists = ([(c.diff(t, 2), qdd[i]) for i, c in enumerate(coords)]
                  + [(c.diff(t), qd[i]) for i, c in enumerate(coords)]
                  + [(c, q[i]) for i, c in enumerate(coords)])

    def plain(e):
        return e.subs(subs_lists)

    # --- rotor, (2.1)-(2.5): contact forces in terms of the stator motion ----
    Z, R_star, v_c = kin.Z, kin.R_star, kin.v_c
    Z_ref = {"theta0": H, "literal": 0}[spring_reference]
    # (2.1), (2.3) through named symbols Z, Z', Z'' (the document shows this form)
    Z_s, Zd_s, Zdd_s = sp.symbols("Z Zdot Zddot", real=True)
    F_n_generic = p["M"] * Zdd_s + p["F0"] + p["c_R"] * (Z_s - Z_ref) + p["d_R"] * Zd_s
    F_n = F_n_generic.subs({Zdd_s: Z.diff(t, 2), Zd_s: Z.diff(t), Z_s: Z}, simultaneous=True)
    # Newton's third law: the stator feels F_c = -F_t e_x1 - F_n e_z1 (2.5);
    # the rotor feels -F_c at r_c, whose moment about Z is -R* F_t, and the load
    # T opposes the driving direction w_R = -phidot_R.  Moment balance (2.2):
    #   I_R dw_R/dt = F_t R* - T.
    Ft_s, Fn_s = sp.symbols("F_t F_n", real=True)
    wRdot_s, Rstar_s, vc_s, wR_s = sp.symbols("wdot_R R_star v_c w_R", real=True)
    if contact == "stick":
        w_R_generic = vc_s / Rstar_s                                  # (2.4)
    elif contact == "slip":
        w_R_generic = -phiR_f.diff(t)
    else:
        raise ValueError(f"unknown contact law {contact!r}")
    w_R = w_R_generic.subs({vc_s: v_c, Rstar_s: R_star}, simultaneous=True)
    rotor_balance_generic = p["I_R"] * wRdot_s - (Ft_s * Rstar_s - p["T"])  # (2.2)
    rotor_balance = rotor_balance_generic.subs({wRdot_s: w_R.diff(t), Rstar_s: R_star})
    phiR_rate = -w_R
    if contact == "stick":
        F_t = solve_linear(rotor_balance, Ft_s)
        v_rel = sp.Integer(0)
        rotor_rows = []
        mu_expr, v_sym = None, None
    else:
        v_rel_generic = vc_s - wR_s * Rstar_s                         # (5.1)
        v_rel = v_rel_generic.subs({vc_s: v_c, wR_s: w_R, Rstar_s: R_star}, simultaneous=True)
        v_sym = sp.Symbol("v_rel", real=True)
        mu_expr = friction_law(assumptions["friction_law"], v_sym)    # (5.2)
        F_t = mu_expr.subs(v_sym, v_rel) * F_n
        rotor_rows = [rotor_balance.subs(Ft_s, F_t)]

    # --- stator, (2.6)-(2.11) in frame A ------------------------------------
    Iyy = p["I_xx"] if inertia == "axisymmetric" else p["I_yy"]
    I_A = kin.tensor_in_A_from_K((p["I_xx"], Iyy, p["I_zz"]))
    L_A = I_A * kin.omega_A
    dLdt_A = L_A.diff(t) + kin.frame_A_rate.cross(L_A)
    Om = OMEGA
    M_E_A = (kin.C_NA.T * sp.Matrix([p["m0"] * sp.cos(Om * t),
                                     p["m0"] * sp.sin(Om * t), 0])
             ).applyfunc(sp.trigsimp)                                 # (2.8)
    extra_states, extra_names, extra_rates = [], [], []
    if twist == "paper":
        twist_angle = phi_f + psi_f * sp.cos(theta_f)                # (2.9)
    elif twist == "integrated":
        tau = sp.Symbol("tau", real=True)
        twist_angle = tau
        extra_states, extra_names = [tau], ["tau"]
        extra_rates = [kin.omega_A[2]]                    # tau' = omega_Z
    else:
        raise ValueError(f"unknown twist law {twist!r}")
    # The twist angle enters through a placeholder, so that the stationary
    # problem can solve the twisting balance for its value whatever the law.
    Tw = sp.Symbol("twist", real=True)
    M_R_A = sp.Matrix([p["c_r"] * theta_f, 0, p["c_t"] * Tw])
    imperfection = assumptions.get("imperfection", "none")
    if imperfection == "driver_stator":
        M_E_A = M_E_A + imperfect_excitation_A(kin, Om)
        M_R_A = M_R_A + mode_split_moment_A(kin, coords[-3:])
    elif imperfection != "none":
        raise ValueError(f"unknown imperfection {imperfection!r}")
    # The ideal motor: the stationary solution (3.1) exists only there, so
    # every stationary quantity below is derived with the imperfections at 0.
    ideal = {P[k]: sp.Integer(0) for k in IMPERFECTIONS}
    D_A = kin.tensor_in_A_from_N((p["d_r"], p["d_r"], p["d_t"]))
    M_D_A = D_A * kin.omega_A                                         # (2.10)
    F_c_A = sp.Matrix([-Ft_s, 0, -Fn_s])                              # (2.5)
    M_C_A = kin.r_c_A.cross(F_c_A)                                    # (2.11)
    stator_generic = dLdt_A - (M_E_A - M_R_A - M_D_A + M_C_A)         # (2.6), (2.7)
    stator_rows = list(stator_generic.subs({Ft_s: F_t, Fn_s: F_n, Tw: twist_angle}))
    stator_generic = stator_generic.xreplace(ideal)
    M_E_A_ideal = M_E_A.xreplace(ideal)

    rows = [plain(r) for r in rotor_rows + stator_rows]
    # rows are linear in the accelerations: M_q qdd = f_q
    M_q = sp.Matrix(rows).jacobian(qdd)
    f_q = -sp.Matrix(rows).subs({a: 0 for a in qdd})

    n = 2 * nq + len(extra_states)
    states = q + qd + extra_states
    state_names = coord_names + [c + "dot" for c in coord_names] + extra_names
    mass = sp.zeros(n, n)
    for i in range(nq):
        mass[i, i] = 1
    mass[nq:2 * nq, nq:2 * nq] = M_q
    for i in range(len(extra_states)):
        mass[2 * nq + i, 2 * nq + i] = 1
    rhs = sp.Matrix(qd + list(f_q) + [plain(r) for r in extra_rates])
    v = [sp.Symbol(f"v{i}", real=True) for i in range(n)]

    # --- derived output quantities along any motion ---------------------------
    xdot = [sp.Symbol(nm + "_rate", real=True) for nm in state_names]
    xdot_subs = {}
    for i in range(nq):
        xdot_subs[qdd[i]] = xdot[nq + i]
    outputs = {
        "R_star": plain(R_star),
        "Z": plain(Z),
        "v_c": plain(v_c),
        "F_n": plain(F_n).subs(xdot_subs),
        "F_t": plain(F_t).subs(xdot_subs),
        "v_rel": plain(v_rel),
        "rotor_speed": plain(phiR_rate),
    }

    # --- stationary solution, (3.1)-(3.7) and section 5 ------------------------
    theta_b, alpha, beta = sp.symbols("theta alpha beta", real=True)
    unknowns = [theta_b, alpha]
    unknown_names = ["theta", "alpha"]
    psi_rate = -Om / sp.cos(theta_b)
    ansatz = {phi_f: Om * t + alpha, theta_f: theta_b,
              psi_f: psi_rate * t + beta}                              # (3.1)
    rate_bar = {phi_f: Om, theta_f: 0, psi_f: psi_rate}
    if contact == "slip":
        wR = sp.Symbol("phidot_R", real=True)
        unknowns.append(wR)
        unknown_names.append("phidot_R")
        ansatz[phiR_f] = wR * t
        rate_bar[phiR_f] = wR

    def on_ansatz(e):
        e = e.subs({c.diff(t, 2): 0 for c in coords})
        e = e.subs({c.diff(t): rate_bar[c] for c in coords})
        return e.subs(ansatz)

    # The stator rows on the ansatz, with the contact forces still symbols:
    # small expressions, so trigsimp turns the cos^2 + sin^2 - 1 terms
    # (omega_Z = 0 on the orbit) into exact zeros instead of rounding noise of
    # size eps*Omega, and halves the operation count.  The contact law is
    # substituted afterwards, so the cost does not depend on it.
    stator_steady = [sp.trigsimp(on_ansatz(r)) for r in list(stator_generic)[:2]]
    contact_bar = {Ft_s: on_ansatz(F_t), Fn_s: on_ansatz(F_n)}
    residual_rows = ([on_ansatz(r) for r in rotor_rows]
                     + [r.subs(contact_bar) for r in stator_steady])
    for r in residual_rows:
        if t in r.free_symbols or Tw in r.free_symbols:
            raise RuntimeError("stationary residual depends on time: "
                               "the ansatz (3.1) is not a solution of this variant")
    residual = sp.Matrix(residual_rows)
    z_row = on_ansatz(list(stator_generic)[2].subs(contact_bar))
    # Twisting balance (Z row): the twist angle on the stationary solution.
    # small expression: simplification makes omega_Z = 0 on the orbit exact.
    # The contact law is substituted afterwards, as for the stator rows: a
    # friction law with exp() makes simplify() take many minutes otherwise.
    twist_bar = sp.simplify(solve_linear(on_ansatz(list(stator_generic)[2]), Tw)).subs(contact_bar)
    if t in twist_bar.free_symbols:
        raise RuntimeError("twisting balance depends on time")
    # beta from the paper's twist angle phi + psi cos(theta) = twist_bar at any
    # t (3.6); under the integrated law tau = twist_bar and psi's phase is free
    # (psi is cyclic), and the same beta is used by convention.
    beta_expr = solve_linear(sp.expand(on_ansatz(phi_f + psi_f * sp.cos(theta_f)))
                             - twist_bar, beta)
    if t in beta_expr.free_symbols:
        raise RuntimeError("beta depends on time")

    def steady(e):
        return on_ansatz(e).subs(beta, beta_expr)

    steady_outputs = {
        "beta": beta_expr,
        "rotor_speed": steady(phiR_rate),
        "F_n": steady(F_n),
        "F_t": steady(F_t),
        "v_c": steady(v_c),
        "v_rel": steady(v_rel),
        "R_star": R_star.subs(theta_f, theta_b),
        "Z": Z.subs(theta_f, theta_b),
        "twist": twist_bar,
    }

    # Power on the stationary solution (issue 13), from the same torques and
    # forces as the equations of motion: the excitation torque (2.8) and the
    # damping torque (2.10) times the stator's angular velocity, the rotor's
    # axial damping force times Z', the load times the rotor's speed in its
    # driving direction, and the friction force times the slip velocity.  In
    # frame A every one of them is constant on the orbit (checked below), so
    # the mean over a period is the value itself.  Their balance
    # power_in = power_out + power_damping + power_slip is not built in: it
    # holds only where the residuals vanish (tests/test_power.c).
    power_exprs = {
        "power_in": (M_E_A_ideal.T * kin.omega_A)[0],
        "power_out": p["T"] * w_R,
        "power_damping": (M_D_A.T * kin.omega_A)[0] + p["d_R"] * Z.diff(t) ** 2,
        # F_t stays a symbol through trigsimp (a friction law with exp() makes
        # it take many minutes otherwise); it is constant on the orbit.
        "power_slip": Ft_s * v_rel,
    }
    steady_power = {}
    for key, e in power_exprs.items():
        e = sp.trigsimp(steady(e)).subs(Ft_s, steady(F_t))
        if t in e.free_symbols:
            raise RuntimeError(f"{key} depends on time on the stationary solution")
        steady_power[key] = e

    # State on the stationary orbit and its rate, for any t (used by Floquet).
    xbar = [ansatz[c] for c in coords] + [rate_bar[c] for c in coords]
    xbar_rate = [sp.diff(e, t) for e in xbar]
    if twist == "integrated":
        xbar.append(twist_bar)
        xbar_rate.append(sp.Integer(0))
    steady_state = sp.Matrix(xbar)
    steady_rate = sp.Matrix(xbar_rate)

    # Seed for the root search: at given theta the stator rows are linear in
    # (cos alpha, sin alpha) once the steady contact forces are known; solving
    # that 2x2 system gives alpha, and |(cos, sin)| = 1 is a scalar equation in
    # theta alone whose sign changes bracket every stationary solution.
    C, S = sp.symbols("C S", real=True)
    Ft_steady = solve_linear(on_ansatz(rotor_balance), Ft_s)
    Fn_steady = on_ansatz(F_n)
    lin = [sp.expand(r.subs({Ft_s: Ft_steady, Fn_s: Fn_steady}))
           .subs({sp.cos(alpha): C, sp.sin(alpha): S}) for r in stator_steady]
    for r in lin:
        if alpha in r.free_symbols:
            raise RuntimeError("stator rows are not linear in cos/sin alpha")
    A, bvec = sp.linear_eq_to_matrix(lin, [C, S])
    det = A[0, 0] * A[1, 1] - A[0, 1] * A[1, 0]
    Cs = (bvec[0] * A[1, 1] - A[0, 1] * bvec[1]) / det
    Ss = (A[0, 0] * bvec[1] - bvec[0] * A[1, 0]) / det
    seed = {"amplitude_mismatch": Cs**2 + Ss**2 - 1, "cos_alpha": Cs, "sin_alpha": Ss,
            "F_t": Ft_steady, "F_n": Fn_steady}

    # Well-conditioned perturbation coordinates.  Near theta = 0 a z-x-z
    # perturbation (dphi, dtheta, dpsi) is dominated by dphi + dpsi ~ 0 pairs,
    # and the linearisation spans ~17 orders of magnitude.  The small-rotation
    # vector in frame A, d(rot) = L(theta) dq with L = d(omega_A)/d(qdot), maps
    # angles and rates alike to physically comparable components.
    L = kin.omega_A.applyfunc(plain).jacobian([qd[coord_names.index(c)]
                                              for c in ("phi", "theta", "psi")])
    tangent_map = sp.eye(n)
    e_idx = [coord_names.index(c) for c in ("phi", "theta", "psi")]
    for block in (0, nq):
        for a in range(3):
            for b in range(3):
                tangent_map[block + e_idx[a], block + e_idx[b]] = L[a, b]

    jac_rhs = rhs.jacobian(states)
    jac_mass = (mass * sp.Matrix(v)).jacobian(states)
    # Does the linearisation about the stationary orbit depend on time?  In
    # frame A it is constant except where an angle enters other than through
    # phi - Omega t (the paper's twist angle phi + psi cos(theta) does).
    on_orbit = dict(zip(states, steady_state))
    jac_rhs_ideal, jac_mass_ideal = jac_rhs.xreplace(ideal), jac_mass.xreplace(ideal)
    A_bar = (jac_rhs_ideal - jac_mass_ideal.subs(dict(zip(v, steady_rate)))).subs(on_orbit)
    t0_independent = t not in A_bar.free_symbols and t not in mass.subs(on_orbit).free_symbols
    A_bar_t_entries = [(i, j) for i in range(n) for j in range(n) if t in A_bar[i, j].free_symbols]

    # Directional derivative of the linearisation about the orbit, for the
    # sensitivity of the Floquet multipliers (issue 13): M(xbar) and
    # A = df/dx - d(M v)/dx |_{v = xbar'} as functions of (u, t, p) with beta
    # from the twisting balance, differentiated along (du, dt, dp).  One
    # direction per call keeps this a sum of first derivatives of the
    # linearisation (second derivatives of the equations of motion).
    orbit_beta = {**on_orbit, **dict(zip(v, steady_rate))}
    orbit_beta = {k: sp.sympify(e).subs(beta, beta_expr) for k, e in orbit_beta.items()}
    A_full = (jac_rhs_ideal - jac_mass_ideal).subs(orbit_beta, simultaneous=True)
    M_full = mass.subs(orbit_beta, simultaneous=True)
    # (the imperfections are 0 here: their directions have no stationary orbit)
    dir_vars = list(unknowns) + [t] + [P[k] for k, *_ in PARAMETERS]
    dir_syms = [sp.Symbol("dir_" + s.name, real=True) for s in dir_vars]

    def along(e):
        return sum((sp.diff(e, s) * ds for s, ds in zip(dir_vars, dir_syms)
                    if s in e.free_symbols), sp.Integer(0))
    floquet_direction = [along(e) for e in M_full] + [along(e) for e in A_full]

    cyclic = []
    for i, s in enumerate(states):
        if s not in rhs.free_symbols and s not in mass.free_symbols:
            cyclic.append(i)

    # Pieces for the readable export (derive/usm_derive/emit_doc.py).
    equations = {
        "C_NA": kin.C_NA, "C_AB": kin.C_AB, "C_BK": kin.C_BK,
        "omega_K": kin.omega_K.applyfunc(plain), "omega_A": kin.omega_A.applyfunc(plain),
        "r_c_A": kin.r_c_A.applyfunc(plain), "R_star": plain(R_star), "Z": plain(Z),
        "v_c": plain(v_c), "F_n": plain(F_n), "F_t": plain(F_t), "v_rel": plain(v_rel),
        "w_R": plain(w_R), "rotor_rows": [plain(r) for r in rotor_rows],
        "rotor_balance": rotor_balance_generic, "F_t_generic": solve_linear(rotor_balance_generic, Ft_s),
        "friction": mu_expr, "v_sym": v_sym,
        "I_A": I_A.applyfunc(plain), "L_A": L_A.applyfunc(plain),
        "M_E_A": M_E_A.applyfunc(plain), "M_R_A": M_R_A.applyfunc(plain).subs(Tw, plain(twist_angle)),
        "M_D_A": M_D_A.applyfunc(plain), "M_C_A": M_C_A,
        "extra_rates": [plain(r) for r in extra_rates], "extra_names": extra_names,
        "M_q": M_q, "f_q": f_q, "residual": residual, "beta": beta_expr,
        "twist": twist_bar, "qdd": qdd, "qd": qd, "q": q,
        "rotor_speed_bar": steady_outputs["rotor_speed"], "v_rel_bar": steady_outputs["v_rel"],
        "beta_generic": solve_linear(sp.expand(on_ansatz(phi_f + psi_f * sp.cos(theta_f))) - Tw,
                                     beta),
        "twist_display": sp.simplify(solve_linear(
            z_row.subs(steady_outputs["v_rel"], v_sym) if v_sym is not None else z_row, Tw)),
        "ansatz": {c_name: ansatz[c] for c_name, c in zip(coord_names, coords)},
        # The generic pieces of the derivation, for the document's named form
        # (derive/usm_derive/emit_doc.py): functions of t, placeholders kept.
        "kin": kin, "coords": coords, "coord_names": coord_names, "F_n_generic": F_n_generic,
        "w_R_generic": w_R_generic, "v_rel_generic": v_rel_generic if contact == "slip" else None,
        "contact_symbols": {"F_t": Ft_s, "F_n": Fn_s, "Z": Z_s, "Zdot": Zd_s, "Zddot": Zdd_s,
                            "wdot_R": wRdot_s, "R_star": Rstar_s, "v_c": vc_s, "w_R": wR_s,
                            "twist": Tw},
        "stator_generic": stator_generic, "dLdt_A": dLdt_A, "F_c_A": F_c_A,
        "M_E_A_t": M_E_A, "M_R_A_t": M_R_A, "M_D_A_t": M_D_A, "M_C_A_t": M_C_A,
        "twist_angle": twist_angle, "extra_states": extra_states, "extra_rates_t": extra_rates,
        "steady_rate": steady_rate, "t0_independent": t0_independent,
        "A_bar_t_entries": A_bar_t_entries,
    }
    return Model(name=name, assumptions=dict(assumptions), states=states,
                 state_names=state_names, mass=mass, rhs=rhs, v=v,
                 outputs=outputs, xdot=xdot, unknowns=unknowns,
                 unknown_names=unknown_names, residual=residual,
                 steady_outputs=steady_outputs, steady_state=steady_state,
                 steady_rate=steady_rate, seed=seed, friction=mu_expr,
                 v_rel=v_sym, tangent_map=tangent_map, jac_rhs=jac_rhs,
                 jac_mass=jac_mass, t0_independent=t0_independent, cyclic=cyclic, equations=equations,
                 steady_power=steady_power, floquet_direction=floquet_direction,
                 direction_symbols=list(zip(dir_vars, dir_syms)))
