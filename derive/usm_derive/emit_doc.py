"""The derived equations in the paper's notation: a list of lines, each held
both as typeset LaTeX and as sympy (srepr), rendered as Markdown and LaTeX.

The document is written the way a textbook states a model: contact geometry
(R*, Z, v_c) defined once and used as symbols, the contact and rotor laws, each
torque, Euler's equations in frame A, and then M(x) x' = f(x, t) row by row in
those named quantities.  It is built from the generic pieces of the derivation
(model.py, ``Model.equations``: the force laws with placeholders, the torques,
the kinematics) with R* and Z as functions of theta whose derivatives are
dR*/dtheta = -Z and dZ/dtheta = R*; no equation of motion is typed here.
tests/equations_proof.py proves the lines equal to the compiled kernels.

model_data(m) returns the lines as JSON-able data (one model, in the worker);
render() turns the data into Markdown and LaTeX, marking the lines that differ
from the paper's model of the same base (highlighting driven by the variant's
assumptions in derive/variants.py), and diff documents with those lines only.
"""
import re

import sympy as sp

from .model import IMPERFECTIONS, P, t, solve_linear

# --------------------------------------------------------------------------
# symbols and their typeset names

GREEK = {"phi": r"\varphi", "theta": r"\theta", "psi": r"\psi", "phi_R": r"\varphi_R",
         "tau": r"\tau"}
PARAM_TEX = {"m0": "m_0", "F0": "F_0", "I_xx": "I_{xx}", "I_yy": "I_{yy}", "I_zz": "I_{zz}",
             "mu0": r"\mu_0", "kappa": r"\kappa", "c_R": "c_R", "d_R": "d_R", "c_t": "c_t",
             "c_r": "c_r", "d_t": "d_t", "d_r": "d_r", "I_R": "I_R",
             "amp_imbalance": "e", "phase_error": r"\delta", "mode_split": "s"}
AXES = ["x_1", "y_1", "z_1"]
SMALL = 120  # operations: trigsimp only below this, its cost grows steeply


def _acc(tex, n):
    """\\dot{\\varphi}_R rather than \\dot{\\varphi_R}."""
    mark = {1: r"\dot", 2: r"\ddot"}[n]
    if tex.endswith("_R"):
        return mark + "{" + tex[:-2] + "}_R"
    return mark + "{" + tex + "}"


class RStar(sp.Function):
    """R*(theta) = R cos(theta) - H sin(theta), the contact radius."""
    nargs = 1

    def fdiff(self, argindex=1):
        return -ZC(self.args[0])


class ZC(sp.Function):
    """Z(theta) = R sin(theta) + H cos(theta), the height of the contact point (2.3)."""
    nargs = 1

    def fdiff(self, argindex=1):
        return RStar(self.args[0])


class Names:
    """The document's symbols: sympy Symbol (real) and its LaTeX name."""

    def __init__(self):
        self.tex = {}
        for base, tex in GREEK.items():
            self.add(base, tex)
            self.add(base + "dot", _acc(tex, 1))
            self.add(base + "ddot", _acc(tex, 2))
        for name, sym in P.items():
            self.tex[sym] = PARAM_TEX.get(name) or (
                name if re.fullmatch(r"[A-Za-z](_[A-Za-z]+)?", name)
                else r"\mathrm{" + name.replace("_", r"\_") + "}")

    def add(self, name, tex):
        s = sp.Symbol(name, real=True)
        if s in self.tex and self.tex[s] != tex:
            raise RuntimeError(f"symbol {name} named twice")
        self.tex[s] = tex
        return s

    def table(self):
        return {s.name: tex for s, tex in self.tex.items()}


def latex(e, names):
    return sp.latex(e, symbol_names=names, mat_delim="(", inv_trig_style="full")


# --------------------------------------------------------------------------
# simplification of small pieces

def _ops(e):
    return sp.count_ops(e)


def tidy(e, identities=()):
    """The shortest of a few equivalent forms of a small expression: as is,
    trigsimp'ed, and with the geometric identities (R* cos + Z sin = R ...)
    applied after collecting by the rates and accelerations."""
    e = sp.sympify(e)
    if isinstance(e, sp.MatrixBase):
        return e.applyfunc(lambda x: tidy(x, identities))
    cands = [e]
    if _ops(e) <= SMALL and not e.has(sp.atan, sp.tanh, sp.exp):
        cands.append(_trigsimp(e))
    gens = sorted((g for g in e.free_symbols if g.name.endswith("dot")), key=lambda s: s.name)
    if gens and not e.has(sp.atan, sp.tanh, sp.exp):
        # a polynomial in the rates and accelerations: each coefficient is small
        try:
            poly = sp.Poly(sp.expand(e), *gens)
        except sp.PolynomialError:
            poly = None
        if poly is not None:
            terms = [_small_trigsimp(c) * sp.Mul(*(g**k for g, k in zip(gens, mono)))
                     for mono, c in poly.terms()]
            cands.append(sp.Add(*terms))
            cands.append(sp.collect(sp.Add(*terms), gens))
    for c in list(cands):
        ex = sp.expand(c)
        cands.append(ex)
        for old, new in identities:
            gens = sorted(ex.free_symbols, key=lambda s: s.name)
            rates = [g for g in gens if g.name.endswith("dot") or g.name.endswith("ddot")
                     or g.name.startswith("F_") or g.name.startswith("mu")]
            col = sp.collect(ex, rates) if rates else ex
            cands.append(col.subs(old, new))
    cands += [sp.factor_terms(c) for c in list(cands)]
    return min(cands, key=lambda c: (_ops(c), len(str(c))))


def _trigsimp(c, memo={}):
    """trigsimp, once per expression (the same pieces recur line after line)."""
    if c not in memo:
        memo[c] = sp.trigsimp(c)
    return memo[c]


def _small_trigsimp(c):
    if _ops(c) > SMALL or c.has(sp.atan, sp.tanh, sp.exp):
        return c
    ts = _trigsimp(c)
    return min([c, ts, sp.factor_terms(ts)], key=lambda x: (_ops(x), len(str(x))))


# --------------------------------------------------------------------------
# the document as lines

class Doc:
    """Lines of the document.  kind: section | text | def | eq | identity | display.

    def: ``defines`` symbols (component-wise for a matrix) or one matrix name;
    eq: ``row`` (first kernel row of M x' - f that lhs - rhs equals);
    identity: lhs = rhs for any values; display: typeset only (not parsed)."""

    def __init__(self, names):
        self.names = names
        self.lines = []
        self.keys = set()

    def section(self, title):
        self.lines.append({"kind": "section", "text": title, "key": "section:" + title})

    def text(self, s, key):
        self.lines.append({"kind": "text", "text": s, "key": "text:" + key})

    def _add(self, kind, key, tag, lhs, rhs, lhs_tex=None, **extra):
        if key in self.keys:
            raise RuntimeError(f"document line {key} twice")
        self.keys.add(key)
        tex = self.names.tex
        if kind != "display":
            # as the proof reads it back: unevaluated forms such as -(a + b) print
            # differently once parsed, and the typeset line must be the parsed one
            lhs, rhs = (sp.sympify(sp.srepr(x)) for x in (lhs, rhs))
        line = {"kind": kind, "key": key, "tag": tag,
                "lhs_tex": lhs_tex if lhs_tex is not None else latex(lhs, tex),
                "rhs_tex": rhs if isinstance(rhs, str) else latex(rhs, tex)}
        if kind != "display":
            line["lhs"] = sp.srepr(lhs)
            line["rhs"] = sp.srepr(rhs)
        line.update(extra)
        self.lines.append(line)

    def define(self, sym, rhs, tag=None, lhs_tex=None, key=None):
        """sym: a Symbol, a list of Symbols (components of the matrix rhs) or a
        name (the whole matrix)."""
        if isinstance(sym, str):
            lhs, defines = sp.Symbol(sym), sym
        elif isinstance(sym, (list, tuple)):
            lhs, defines = sp.Matrix(sym), [s.name for s in sym]
        else:
            lhs, defines = sym, [sym.name]
        self._add("def", key or ("def:" + (sym if isinstance(sym, str) else lhs_key(sym))),
                  tag, lhs, rhs, lhs_tex, defines=defines)

    def equation(self, key, lhs, rhs, row, tag=None, lhs_tex=None):
        self._add("eq", key, tag, lhs, rhs, lhs_tex, row=row)

    def identity(self, key, lhs, rhs, tag=None, lhs_tex=None):
        self._add("identity", key, tag, lhs, rhs, lhs_tex)

    def display(self, key, lhs_tex, rhs_tex, tag=None):
        self._add("display", key, tag, None, rhs_tex, lhs_tex)


def lhs_key(sym):
    if isinstance(sym, (list, tuple)):
        return ",".join(s.name for s in sym)
    return sym.name


# --------------------------------------------------------------------------
# the model in named quantities

def model_data(m):
    """The document of one model as data (JSON-able): its lines, symbols and
    the keys the proof needs (tests/equations_proof.py), section by section."""
    if m.assumptions.get("coordinates", "euler_zxz") != "euler_zxz":
        from .emit_doc_regular import regular_model_data
        return regular_model_data(m, Doc, Names, latex)
    doc = ModelDocument(m)
    doc.kinematics()
    doc.rotor_and_contact()
    doc.torques_on_stator()
    doc.euler_equations()
    doc.equations_of_motion()
    doc.stationary_solution()
    doc.linearisation()
    return doc.data()


def _shortest(cands):
    return min(cands, key=lambda c: (_ops(c), len(str(c))))


class ModelDocument:
    """The document of one model, built section by section: each method adds
    the lines of one section to ``d`` and the quantities it names to
    ``chain`` (symbol -> its definition in earlier names)."""

    def __init__(self, m):
        self.m = m
        e = self.e = m.equations
        names = self.names = Names()
        self.d = Doc(names)
        self.kin, self.coords, cnames = e["kin"], e["coords"], e["coord_names"]
        self.cnames = cnames
        self.cs = e["contact_symbols"]
        self.slip = m.assumptions["contact"] == "slip"
        self.nq = len(self.coords)
        self.th_f = self.coords[cnames.index("theta")]
        self.q = [sp.Symbol(n, real=True) for n in cnames]
        self.qd = [sp.Symbol(n + "dot", real=True) for n in cnames]
        self.qdd = [sp.Symbol(n + "ddot", real=True) for n in cnames]
        self.theta = self.q[cnames.index("theta")]
        self.to_plain = ([(c.diff(t, 2), self.qdd[i]) for i, c in enumerate(self.coords)]
                         + [(c.diff(t), self.qd[i]) for i, c in enumerate(self.coords)]
                         + [(c, self.q[i]) for i, c in enumerate(self.coords)])
        self.Om = names.add("Omega", r"\Omega")
        self.Rs = names.add("R_star", "R^*")
        self.Zs = self.cs["Z"]
        names.tex[self.Zs] = "Z"
        self.Zd, self.Zdd = names.add("Zdot", r"\dot Z"), names.add("Zddot", r"\ddot Z")
        theta, R, H = self.theta, P["R"], P["H"]
        self.short_f = {RStar(theta): self.Rs, ZC(theta): self.Zs}
        self.identities = [(self.Rs * sp.cos(theta) + self.Zs * sp.sin(theta), R),
                           (self.Zs * sp.cos(theta) - self.Rs * sp.sin(theta), H)]
        self.chain = {}     # every named quantity: symbol -> its definition
        self.torques = {}   # torque name -> its component symbols
        self.zero_of = {}   # symbol -> its value at zero accelerations (a (0) symbol or 0)
        self.bar_of = {}    # symbol -> its value on the stationary orbit
        self.rotor_eq = None
        self.extra = e["extra_states"]

    # --- helpers -------------------------------------------------------------

    def plain(self, x):
        """Function-of-t expression (R*, Z as functions of theta) -> symbols."""
        kin, th_f = self.kin, self.th_f
        x = sp.sympify(x).subs({kin.R_star: RStar(th_f), kin.Z: ZC(th_f)})
        x = x.subs(self.to_plain).subs(P["f"], self.Om / (2 * sp.pi))
        return x.xreplace(self.short_f) if not isinstance(x, sp.MatrixBase) else \
            x.applyfunc(lambda y: y.xreplace(self.short_f))

    def nice(self, x):
        return tidy(x, self.identities)

    def named(self, sym, expr, tag=None, lhs_tex=None, key=None):
        if isinstance(sym, list):
            sym = tuple(sym)
        self.chain[sym] = expr
        self.d.define(sym, expr, tag, lhs_tex, key)
        return sym

    def vec(self, key, tex_name, value, tag, lhs_tex):
        """A named vector (component symbols along x_1, y_1, z_1)."""
        names = self.names
        if "_" in tex_name and "^" not in tex_name:
            base, sub = tex_name.split("_", 1)
            syms = [names.add(f"{key}_{a.replace('_', '')}", f"{base}_{{{sub},{a}}}")
                    for a in AXES]
        else:
            syms = [names.add(f"{key}_{a.replace('_', '')}", tex_name + "_{" + a + "}")
                    for a in AXES]
        self.named(syms, value, tag=tag, lhs_tex=lhs_tex, key="def:" + key)
        self.torques[key] = syms
        return syms

    def depends_on_acc(self, x):
        return bool(sp.sympify(x).free_symbols & (set(self.qdd) | set(self.zero_of)))

    # --- sections --------------------------------------------------------------

    def kinematics(self):
        d, e, names, plain = self.d, self.e, self.names, self.plain
        theta, th_f, R, H = self.theta, self.th_f, P["R"], P["H"]
        d.section("Kinematics: z-x-z Euler angles (Fig. 5, Table 1)")
        d.text(r"Frames: $N$ inertial, $A$ turned by $\varphi$ about $Z$, $B$ by $\theta$ about "
               r"$x_1$, $K$ (body) by $\psi$ about $z_2$; $C_{XY}$ maps components in frame $Y$ "
               r"to components in frame $X$.  Vectors are given by their components in frame "
               r"$A$, $\Omega = 2\pi f$.", "frames")
        d.define(self.Om, 2 * sp.pi * P["f"])
        for key, nm in (("C_NA", "C_{NA}"), ("C_AB", "C_{AB}"), ("C_BK", "C_{BK}")):
            d.define(key, plain(e[key]), lhs_tex=nm)
        d.define("omega_K", tidy(plain(e["omega_K"])), lhs_tex=r"\vec\omega^{\,K}")
        self.om_syms = [names.add("omega_" + a.replace("_", ""), r"\omega_{" + a + "}")
                        for a in AXES]
        self.omega_A = tidy(plain(self.kin.omega_A))
        self.named(self.om_syms, self.omega_A, lhs_tex=r"\vec\omega^{\,A}", key="def:omega_A")
        d.define("r_c", plain(self.kin.r_c_A), lhs_tex=r"\vec r_c^{\,A}")
        self.named(self.Rs, R * sp.cos(theta) - H * sp.sin(theta))
        self.named(self.Zs, R * sp.sin(theta) + H * sp.cos(theta), tag="2.3")
        self.named(self.Zd, plain(ZC(th_f).diff(t)))
        self.named(self.Zdd, self.nice(plain(ZC(th_f).diff(t, 2))))
        kin = self.kin
        self.vc_t = kin.v_c.subs({kin.R_star: RStar(th_f), kin.Z: ZC(th_f)})
        self.v_c = names.add("v_c", "v_c")
        self.named(self.v_c, self.nice(plain(self.vc_t)),
                   lhs_tex=r"v_c = (\vec\omega\times\vec r_c)\cdot\vec e_{x_1}")

    def rotor_and_contact(self):
        d, e, names, cs = self.d, self.e, self.names, self.cs
        d.section("Rotor and contact (2.1)-(2.5)" + (", (5.1), (5.2)" if self.slip else ""))
        self.F_n, self.F_t = cs["F_n"], cs["F_t"]
        self.wR, self.wRd = names.add("w_R", "w_R"), names.add("wdot_R", r"\dot w_R")
        names.add("F_n", "F_n"), names.add("F_t", "F_t")
        self.named(self.F_n, e["F_n_generic"].subs({cs["Zddot"]: self.Zdd, cs["Zdot"]: self.Zd}),
                   tag="2.1")
        d.text(r"$w_R = -\dot\varphi_R$ is the rotor's speed in its driving direction; "
               r"$F_R = F_0 + c_R(Z - Z_0)$ is measured from $Z_0 = Z(\theta = 0) = H$ "
               r"when the spring reference is $\theta = 0$.", "w_R")
        if self.slip:
            self.slip_rotor()
        else:
            self.stick_rotor()

    def stick_rotor(self):
        """(2.4): w_R from v_c and R*, dw_R/dt by the chain rule, F_t from (2.2)."""
        e, cs, names, plain, chain = self.e, self.cs, self.names, self.plain, self.chain
        wR, wRd, v_c = self.wR, self.wRd, self.v_c
        self.named(wR, e["w_R_generic"].subs({cs["v_c"]: v_c, cs["R_star"]: self.Rs}), tag="2.4")
        # the chain rule on the named quantities: dw_R/dt from dv_c/dt and dR*/dt
        vcd = names.add("vdot_c", r"\dot v_c")
        self.named(vcd, self.nice(plain(self.vc_t.diff(t))))
        rates = {v_c: vcd, self.Rs: plain(RStar(self.th_f).diff(t))}
        wrd = sum(sp.diff(chain[wR], s) * r for s, r in rates.items())
        self.named(wRd, _shortest([self.nice(wrd),
                                   self.nice(sp.expand(wrd).subs(chain[wR], wR))]))
        Ft_expr = sp.factor_terms(sp.together(
            solve_linear(e["rotor_balance"], cs["F_t"]).subs(
                {cs["wdot_R"]: wRd, cs["R_star"]: self.Rs})))
        self.named(self.F_t, Ft_expr, tag="2.2")
        self.rotor_eq = None

    def slip_rotor(self):
        """w_R = -phidot_R, the slip velocity (5.1), the friction law (5.2) and
        the rotor's moment balance (2.2) as an equation."""
        e, cs, names, plain = self.e, self.cs, self.names, self.plain
        wR, wRd = self.wR, self.wRd
        wR_gen = e["w_R_generic"]
        self.named(wR, plain(wR_gen))
        self.named(wRd, plain(wR_gen.diff(t)))
        vr = names.add("v_rel", r"v_{\mathrm{rel}}")
        self.named(vr, e["v_rel_generic"].subs({cs["v_c"]: self.v_c, cs["w_R"]: wR,
                                                cs["R_star"]: self.Rs}), tag="5.1")
        mu = names.add("mu", r"\mu")
        self.named(mu, e["friction"].subs(e["v_sym"], vr), tag="5.2")
        self.named(self.F_t, mu * self.F_n, tag="5.1", key="def:F_t")
        rb = e["rotor_balance"].subs({cs["wdot_R"]: wRd, cs["R_star"]: self.Rs})
        self.rotor_eq = (P["I_R"] * wRd, P["I_R"] * wRd - rb)
        self.d.equation("eq:rotor", self.rotor_eq[0], self.rotor_eq[1], row=self.nq, tag="2.2")

    def torques_on_stator(self):
        d, e, cs, plain = self.d, self.e, self.cs, self.plain
        F_t, F_n = self.F_t, self.F_n
        d.section("Torques on the stator, components in frame A (2.5), (2.7)-(2.11)")
        d.display("display:F_c", r"\vec F_c^{\,A}", latex(e["F_c_A"].subs(
            {cs["F_t"]: F_t, cs["F_n"]: F_n}), self.names.tex), tag="2.5")
        tw = cs["twist"]
        self.vec("M_E", "M_E", tidy(plain(e["M_E_A_t"])), "2.8", r"\vec M_E^{\,A}")
        self.vec("M_R", "M_R", plain(e["M_R_A_t"].subs(tw, e["twist_angle"])), "2.9",
                 r"\vec M_R^{\,A}")
        self.vec("M_D", "M_D", tidy(plain(e["M_D_A_t"])), "2.10", r"\vec M_D^{\,A}")
        M_C = self.nice(plain(e["M_C_A_t"].subs({cs["F_t"]: F_t, cs["F_n"]: F_n})))
        self.vec("M_C", "M_C", M_C, "2.11", r"\vec M_C^{\,A} = \vec r_c\times\vec F_c")
        torques = self.torques
        M0 = sp.Matrix(torques["M_E"]) - sp.Matrix(torques["M_R"]) \
            - sp.Matrix(torques["M_D"]) + sp.Matrix(torques["M_C"])
        self.vec("M0", r"M^{(0)}", M0, "2.7", r"\vec M^{(0)}")
        if self.extra:
            d.text(r"The twist angle $\tau$ is a state of its own, integrated from "
                   r"$\omega_{z_1}$.", "tau")

    def euler_equations(self):
        d, e, plain = self.d, self.e, self.plain
        d.section("Euler's equations (2.6) in frame A")
        d.text(r"Frame $A$ turns with $\dot\varphi$ about $Z$, so the rate of the angular "
               r"momentum $\vec L = I\vec\omega$ is $\vec K = \dot{\vec L}^{A} + \dot\varphi\,"
               r"\vec e_Z\times\vec L$; these rows are $C_{AK}$ times (2.6), the same solutions.",
               "euler")
        d.define("L_A", tidy(plain(e["L_A"])), lhs_tex=r"\vec L^{A}")
        K = tidy(plain(e["dLdt_A"]))
        self.vec("K", "K", K, None,
                 r"\vec K = \dot{\vec L}^{A} + \dot\varphi\,\vec e_Z\times\vec L")
        nrot = 1 if self.slip else 0
        d.equation("eq:euler", sp.Matrix(self.torques["K"]), sp.Matrix(self.torques["M0"]),
                   row=self.nq + nrot, tag="2.6")

    def equations_of_motion(self):
        d = self.d
        self.paper_eq = "5.3" if self.slip else "4.6"
        d.section(r"Equations of motion $M(\mathbf{x})\,\dot{\mathbf{x}} = "
                  r"\mathbf{f}(\mathbf{x}, t)$" f" ({self.paper_eq})")
        d.define("xvec", sp.Matrix(self.m.states).T, lhs_tex=r"\mathbf{x}^T")
        d.text(r"A superscript ${}^{(0)}$ marks a quantity at zero accelerations "
               r"($\ddot{\mathbf{q}} = 0$); the rest of it is in $M$.", "zero")
        self.zero_acceleration_names()
        self.mass_and_rhs()

    def zero_acceleration_names(self):
        """Each named quantity that depends on the accelerations gets a (0)
        name for its value at zero accelerations; the contact torque inline,
        K^(0) named component-wise."""
        names, chain, qdd, zero_of = self.names, self.chain, self.qdd, self.zero_of
        for s, expr in list(chain.items()):
            if isinstance(s, (list, tuple)):
                continue
            if self.depends_on_acc(expr):
                z = self.nice(expr.subs({a: 0 for a in qdd}).subs(zero_of))
                if z == 0 or z.is_Atom:
                    zero_of[s] = z
                else:
                    tex0 = names.tex[s]
                    s0 = names.add(s.name + "__0", "{" + tex0 + "}^{(0)}")
                    self.named(s0, z)
                    zero_of[s] = s0
        for s, v in zip(self.torques["M_C"], chain_vec(chain, self.torques["M_C"])):
            if self.depends_on_acc(v):
                zero_of[s] = v.subs({a: 0 for a in qdd}).subs(zero_of)
        for key in ("K",):
            syms = self.torques[key]
            vals = [sp.sympify(chain_vec(chain, syms)[k]) for k in range(3)]
            if any(self.depends_on_acc(v) for v in vals):
                z = [self.nice(v.subs({a: 0 for a in qdd}).subs(zero_of)) for v in vals]
                s0 = [names.add(f"{s.name}__0", "{" + names.tex[s] + "}^{(0)}") for s in syms]
                self.named(s0, sp.Matrix(z), key=f"def:{key}__0",
                           lhs_tex=r"\vec " + key.replace("_", "_{") + ("}" if "_" in key else "")
                           + "^{(0)}")
                for s, z0 in zip(syms, s0):
                    zero_of[s] = z0

    def expand_acc(self, x):
        """Substitute every definition that depends on the accelerations."""
        for _ in range(12):
            y = x.subs({s: v for s, v in flat_chain(self.chain).items()
                        if self.depends_on_acc(v)})
            if y == x:
                return x
            x = y
        raise RuntimeError("definitions do not terminate")

    def mass_and_rhs(self):
        """The rows as the model states them, in named quantities: M(x) entry
        by entry (derivatives in the accelerations), f at zero accelerations."""
        d, names, chain, nq, qd, qdd = self.d, self.names, self.chain, self.nq, self.qd, self.qdd
        n = len(self.m.states)
        rows_named = []
        if self.slip:
            rows_named.append(self.rotor_eq[0] - self.rotor_eq[1])
        rows_named += [k - m0 for k, m0 in zip(self.torques["K"],
                                               chain_vec(chain, self.torques["M0"]))]
        msyms = sp.zeros(n, n)
        for i in range(nq):
            msyms[i, i] = 1
        fsyms = sp.Matrix(qd + [0] * nq + [0] * len(self.extra))
        for k, row in enumerate(rows_named):
            i = nq + k
            full = self.expand_acc(row)
            for j, a in enumerate(qdd):
                mij = self.nice(sp.diff(full, a))
                if mij != 0:
                    sym = names.add(f"m_{i + 1}_{nq + j + 1}", f"m_{{{i + 1},{nq + j + 1}}}")
                    self.named(sym, mij)
                    msyms[i, nq + j] = sym
            fi = self.nice(-row.subs(self.zero_of))
            sym = names.add(f"f_{i + 1}", f"f_{{{i + 1}}}")
            self.named(sym, fi)
            fsyms[i] = sym
        for k, rate in enumerate(self.e["extra_rates_t"]):
            i = 2 * nq + k
            msyms[i, i] = 1
            fsyms[i] = self.nice(self.plain(rate)).subs(
                {v: s for s, v in zip(self.om_syms, self.omega_A) if v != 0 and not v.is_Atom})
        d.define("Mass", msyms, lhs_tex=r"M(\mathbf{x})", key="def:M")
        d.define("fvec", fsyms, lhs_tex=r"\mathbf{f}(\mathbf{x}, t)", key="def:f")
        d.display("display:eom", r"M(\mathbf{x})\,\dot{\mathbf{x}}",
                  r"\mathbf{f}(\mathbf{x}, t)", tag=self.paper_eq)

    def stationary_solution(self):
        self.d.section("Stationary solution (3.1)-(3.7)" + (", section 5" if self.slip else ""))
        self.ideal_motor()
        self.ansatz_lines()
        self.orbit_quantities()
        self.residual_lines()
        self.twist_lines()

    def ideal_motor(self):
        """The imperfections make the residuals depend on t on the ansatz (3.1):
        the stationary solution exists only for the ideal motor, and the kernels
        (steady_residual, steady_outputs, steady_state) are derived at that point."""
        imperfect = self.m.assumptions.get("imperfection", "none") != "none"
        self.ideal = {P[k]: sp.Integer(0) for k in IMPERFECTIONS} if imperfect else {}
        if imperfect:
            imp = [self.names.tex[P[k]] for k in IMPERFECTIONS]
            self.d.text(r"The imperfections make the excitation and the restoring moment depend "
                        r"on $t$ on the ansatz (3.1) in frame $A$: a stationary solution exists "
                        r"only for the ideal motor, $" + " = ".join(imp) + r" = 0$.  Everything "
                        r"in this section, and the orbit of the linearisation below, is at that "
                        r"point; the stationary kernels compute it whatever the values of $"
                        + "$, $".join(imp) + "$.", "ideal")
            self.d.display("display:ideal", " = ".join(imp), "0")

    def nice_bar(self, x):
        """tidy() on the orbit: R and H written through R*, Z where shorter."""
        R, H, thb = P["R"], P["H"], self.thb
        Rb, Zb = self.bar_of.get(self.Rs, self.Rs), self.bar_of.get(self.Zs, self.Zs)
        ids = [(Rb * sp.cos(thb) + Zb * sp.sin(thb), R), (Zb * sp.cos(thb) - Rb * sp.sin(thb), H)]
        best = tidy(x, ids)
        if _ops(x) <= SMALL and not x.has(sp.atan, sp.tanh, sp.exp) and Rb != self.Rs \
                and Zb != self.Zs:
            alt = _trigsimp(x.subs({R: Rb * sp.cos(thb) + Zb * sp.sin(thb),
                                    H: Zb * sp.cos(thb) - Rb * sp.sin(thb)}))
            best = _shortest([best, alt])
        return best

    def ansatz_lines(self):
        """The ansatz (3.1) and its substitution ``on`` (coordinates, rates,
        accelerations on the orbit)."""
        d, names, q, qd, cnames, Om = self.d, self.names, self.q, self.qd, self.cnames, self.Om
        self.thb = thb = names.add("thetabar", r"\bar\theta")
        self.alpha = alpha = names.add("alpha", r"\alpha")
        self.beta = names.add("beta", r"\beta")
        self.chi = chi = names.add("chi", r"\bar\chi")
        self.unknowns = [thb, alpha]
        on = self.on = {self.theta: thb, qd[cnames.index("theta")]: 0,
                        q[cnames.index("phi")]: Om * t + alpha, qd[cnames.index("phi")]: Om,
                        q[cnames.index("psi")]: -Om * t / sp.cos(thb) + self.beta,
                        qd[cnames.index("psi")]: -Om / sp.cos(thb)}
        on.update({a: 0 for a in self.qdd})
        d.define("phibar", Om * t + alpha, lhs_tex=r"\bar\varphi(t)", tag="3.1a")
        self.ansatz = {"phi": "phibar", "theta": "thetabar", "psi": "psibar"}
        d.display("display:ansatz_theta", r"\bar\theta(t)", r"\bar\theta = \mathrm{const}",
                  tag="3.1b")
        d.define("psibar", on[q[cnames.index("psi")]], lhs_tex=r"\bar\psi(t)", tag="3.1c")
        if self.slip:
            wb = names.add("phidotbar_R", r"\bar{\dot\varphi}_R")
            self.unknowns.append(wb)
            on[q[cnames.index("phi_R")]] = wb * t
            on[qd[cnames.index("phi_R")]] = wb
            d.define("phibar_R", wb * t, lhs_tex=r"\bar\varphi_R(t)")
            self.ansatz["phi_R"] = "phibar_R"
        if self.extra:
            on[self.extra[0]] = chi
            d.define("taubar", chi, lhs_tex=r"\bar\tau")
            self.ansatz[self.extra[0].name] = "taubar"
        d.text(r"On the orbit $\dot\theta = \dot Z = \ddot Z = 0$ and $\omega_{z_1} = 0$; a bar "
               r"marks a quantity on it.  Frame $A$ turns with $\bar\varphi = \Omega t + \alpha$, "
               r"so the components in frame $A$ are the paper's $X + iY$ combination (3.3) times "
               r"$e^{-i\bar\varphi}$: time drops out, and (3.4) splits into the real residuals "
               r"(3.5a), (3.5b).", "orbit")
        d.identity("identity:3.3", sp.cos(Om * t + alpha) + sp.I * sp.sin(Om * t + alpha),
                   sp.exp(sp.I * Om * t) * (sp.cos(alpha) + sp.I * sp.sin(alpha)), tag="3.3")

    def orbit_quantities(self):
        """Every named quantity on the orbit: a barred name, or inline when it
        is a torque component or short."""
        names, chain, torques, bar_of = self.names, self.chain, self.torques, self.bar_of
        bar_twist = {self.cs["twist"]: self.chi}
        for s, expr in flat_chain(chain).items():
            if s.name.endswith("__0") or s.name.startswith(("m_", "f_", "M0_", "K_")) \
                    or s in self.om_syms:
                continue
            if s in torques["M_R"]:
                expr = self.plain(self.e["M_R_A_t"])[torques["M_R"].index(s)].subs(bar_twist)
            b = self.nice_bar(expr.xreplace(self.ideal).subs(self.on).subs(bar_of))
            if any(s in torques[k] for k in ("M_E", "M_R", "M_D", "M_C")) or b.is_Atom or \
                    (b.is_Mul and len(b.args) == 2 and b.args[0] == -1 and b.args[1].is_Atom):
                bar_of[s] = b
                continue
            sb = names.add(s.name + "_bar", r"\bar{" + names.tex[s] + "}")
            chain[sb] = b
            self.d.define(sb, b)
            bar_of[s] = sb

    def residual_lines(self):
        """Euler's equations on the orbit: the residuals (3.5a), (3.5b) (and
        the rotor's f_R); the z_1 row is kept for the twisting balance."""
        d, names, torques, bar_of = self.d, self.names, self.torques, self.bar_of
        # K on the orbit: constant in frame A (trigsimp makes omega_Z = 0 exact)
        Kbar = [_trigsimp(chain_vec(self.chain, torques["K"])[k].xreplace(self.ideal)
                          .subs(self.on)) for k in range(3)]
        resid = self.resid = []
        for k in range(3):
            r = Kbar[k] - (bar_of[torques["M_E"][k]] - bar_of[torques["M_R"][k]]
                           - bar_of[torques["M_D"][k]] + bar_of[torques["M_C"][k]])
            resid.append(self.nice_bar(r))
        if t in set().union(*(r.free_symbols for r in resid)):
            # the derivation (model.py) refuses such assumptions: a document without
            # the stationary solution would not be the kernels' model
            raise RuntimeError(f"{self.m.name}: the residuals on the ansatz (3.1) depend on t")
        d.display("display:3.2", r"\bar{\vec K}", r"\bar{\vec M}_E - \bar{\vec M}_R - "
                  r"\bar{\vec M}_D + \bar{\vec M}_C", tag="3.2")
        d.display("display:3.4", r"f_1(\alpha, \bar\theta) + i f_2(\alpha, \bar\theta)", "0",
                  tag="3.4")
        self.res_keys = []
        if self.slip:
            rr = names.add("f_R", "f_R")
            rot = (self.rotor_eq[0] - self.rotor_eq[1]).xreplace(self.ideal).subs({self.wRd: 0})
            self.named(rr, self.nice_bar(rot.subs(bar_of)), lhs_tex=r"f_R(\alpha, \bar\theta, "
                       r"\bar{\dot\varphi}_R)")
            self.res_keys.append(rr.name)
        for k, tag in ((0, "3.5a"), (1, "3.5b")):
            fs = names.add(f"f_{k + 1}bar", f"f_{k + 1}")
            self.named(fs, resid[k], tag=tag, lhs_tex=f"f_{k + 1}(\\alpha, \\bar\\theta)")
            self.res_keys.append(fs.name)

    def twist_lines(self):
        """The twisting balance (the z_1 row) gives the twist angle on the
        orbit, beta follows (3.6); the stick model's rotor speed (3.7)."""
        d, chi, beta, thb = self.d, self.chi, self.beta, self.thb
        d.text(r"The stationary solution: $f_1 = f_2 = 0$" + (r" and $f_R = 0$" if self.slip
                                                               else "")
               + r".  The $z_1$ row, the twisting balance, gives the twist angle "
               r"$\bar\chi$ on the orbit, and $\beta$ follows from the twist angle "
               r"$\varphi + \psi\cos\theta$ of (2.9) (the paper's (3.6) has the sign of "
               r"$\alpha$ flipped).", "twist")
        if chi not in self.resid[2].free_symbols:
            raise RuntimeError(f"{self.m.name}: twisting balance free of the twist angle")
        chi_expr = self.nice_bar(solve_linear(self.resid[2], chi))
        self.named(chi, chi_expr, lhs_tex=r"\bar\chi")
        beta_expr = self.e["beta_generic"].subs({self.cs["twist"]: chi,
                                                 sp.Symbol("theta", real=True): thb})
        self.named(beta, self.nice_bar(beta_expr), tag="3.6")
        self.steady = {"beta": beta.name, "twist": chi.name}
        if not self.slip:
            rs = self.names.add("phidot_R_bar", r"\bar{\dot\varphi}_R")
            self.named(rs, -self.bar_of[self.wR], tag="3.7")
            self.steady["rotor_speed"] = rs.name

    def linearisation(self):
        d, m, e, nq, nextra = self.d, self.m, self.e, self.nq, len(self.extra)
        d.section("Linearisation about the stationary orbit (4.9)")
        d.display("display:4.9", r"M(t)\,\Delta\dot{\mathbf{x}}",
                  r"A(t)\,\Delta\mathbf{x}, \quad "
                  r"M(t) = M(\bar{\mathbf{x}}(t)), \quad A(t) = \frac{\partial\mathbf{f}}"
                  r"{\partial\mathbf{x}} - \frac{\partial (M\mathbf{v})}{\partial\mathbf{x}}"
                  r"\Big|_{\mathbf{v} = \dot{\bar{\mathbf{x}}}}", tag="4.9")
        d.display("display:blocks", r"M(t)", block_mass(nq, nextra))
        d.display("display:A", r"A(t)", block_jacobian(m, nq, nextra))
        if not all(x == 0 for x in list(e["steady_rate"])[nq:2 * nq]):
            raise RuntimeError(f"{m.name}: accelerations on the orbit are not zero")
        if m.t0_independent:
            when = (r"In frame $A$ every entry of $A$ and $M$ is constant on the orbit: the "
                    r"multipliers do not depend on the start time $t_0$.")
        else:
            ent = ", ".join(r"$\partial f_{%d}/\partial %s$" % (i + 1, self.names.tex[m.states[j]])
                            for i, j in e["A_bar_t_entries"])
            when = (r"In frame $A$ the entries of $A$ are constant on the orbit except "
                    + (ent or "in $M$") + r" (changing with $t$ along $\bar{\mathbf{x}}(t)$): "
                    r"the multipliers depend on the start time $t_0$ (the paper's Table 3 is "
                    r"$t_0 = 0$).")
        d.text(r"On the orbit $\ddot{\bar{\mathbf{q}}} = 0$, so the $\partial(M\mathbf{v})/"
               r"\partial\mathbf{x}$ term vanishes.  " + when, "linear")

    def data(self):
        m = self.m
        return {
            "model": m.name,
            "assumptions": m.assumptions,
            "lines": self.d.lines,
            "symbols": self.names.table(),
            "states": [s.name for s in m.states],
            "accelerations": [s.name for s in self.qdd],
            "unknowns": [s.name for s in self.unknowns],
            "parameters": [s.name for s in P.values()],
            "mass": "Mass", "rhs": "fvec", "residual": self.res_keys, "steady": self.steady,
            "ansatz": self.ansatz,
        }


def flat_chain(chain):
    out = {}
    for s, v in chain.items():
        if isinstance(s, (list, tuple)):
            for k, c in enumerate(s):
                out[c] = v[k]
        else:
            out[s] = v
    return out


def chain_vec(chain, syms):
    for s, v in chain.items():
        if isinstance(s, (list, tuple)) and list(s) == list(syms):
            return v
    raise KeyError(syms)


def block_mass(nq, nextra):
    rows = [r"I_{%d}" % nq + r" & 0", r"0 & M_q(\bar{\mathbf{x}}(t))"]
    if nextra:
        rows = [r"I_{%d} & 0 & 0" % nq, r"0 & M_q(\bar{\mathbf{x}}(t)) & 0", r"0 & 0 & 1"]
    return r"\begin{pmatrix}" + r" \\ ".join(rows) + r"\end{pmatrix}"


def block_jacobian(m, nq, nextra):
    """A = df/dx on the orbit in blocks: position rows (0, I), acceleration rows
    and extra rows, each block named unless it is zero or the identity."""
    groups = [(r"\mathbf{q}", 0, nq), (r"\dot{\mathbf{q}}", nq, 2 * nq)]
    if nextra:
        groups.append((r"\tau", 2 * nq, 2 * nq + nextra))
    rowgroups = [(r"\dot{\mathbf{q}}", 0, nq), (r"\mathbf{f}_{q}", nq, 2 * nq)]
    if nextra:
        rowgroups.append((r"\omega_{z_1}", 2 * nq, 2 * nq + nextra))
    jac = m.jac_rhs
    rows = []
    for rname, r0, r1 in rowgroups:
        cells = []
        for cname, c0, c1 in groups:
            block = jac[r0:r1, c0:c1]
            if all(x == 0 for x in block):
                cells.append("0")
            elif block == sp.eye(r1 - r0) and r1 - r0 == c1 - c0:
                cells.append("I")
            else:
                cells.append(r"\frac{\partial %s}{\partial %s}" % (rname, cname))
        rows.append(" & ".join(cells))
    return r"\begin{pmatrix}" + r" \\ ".join(rows) + r"\end{pmatrix}_{\bar{\mathbf{x}}(t)}"


# --------------------------------------------------------------------------
# rendering

WIDTH = 72  # estimated visible characters of a display line


def _visible(tex):
    s = re.sub(r"\\(left|right|mathrm|operatorname|vec|bar|quad|,)\b", "", tex)
    s = re.sub(r"\\(cos|sin|tan|exp|atan|tanh|operatorname\{atan\})", "xxx", s)
    s = re.sub(r"\\[A-Za-z]+", "x", s)
    s = re.sub(r"\^\{([^{}]*)\}", lambda mm: "x" * max(1, len(mm.group(1)) // 2), s)
    s = re.sub(r"\\frac\{([^{}]*)\}\{([^{}]*)\}",
               lambda mm: "x" * max(len(mm.group(1)), len(mm.group(2))), s)
    return len(re.sub(r"[{}_ ]", "", s))


def _split_points(tex):
    """Positions of top-level ' + ' and ' - ' in a LaTeX expression."""
    depth, out, i = 0, [], 0
    while i < len(tex):
        c = tex[i]
        if tex.startswith(r"\left", i):
            depth += 1
            i += 5
            continue
        if tex.startswith(r"\right", i):
            depth -= 1
            i += 6
            continue
        if c == "{":
            depth += 1
        elif c == "}":
            depth -= 1
        elif depth == 0 and tex[i:i + 3] in (" + ", " - ") and i > 0:
            out.append(i)
        i += 1
    return out


def broken(lhs_tex, rhs_tex):
    """The display body: lhs = rhs, broken at top-level + and - when long."""
    if _visible(lhs_tex) + _visible(rhs_tex) <= WIDTH or r"\begin{" in rhs_tex:
        return f"{lhs_tex} = {rhs_tex}", False
    points = _split_points(rhs_tex)
    chunks, start = [], 0
    limit = max(WIDTH - _visible(lhs_tex), 40)
    last = 0
    for p in points + [len(rhs_tex)]:
        if _visible(rhs_tex[start:p]) > limit and last > start:
            chunks.append(rhs_tex[start:last])
            start = last
            limit = WIDTH - 6
        last = p
    chunks.append(rhs_tex[start:])
    if len(chunks) == 1:
        return f"{lhs_tex} = {rhs_tex}", False
    body = (r"\begin{aligned}" + f"{lhs_tex} &= {chunks[0]}" + "".join(
        r"\\ &\quad " + c.lstrip() for c in chunks[1:]) + r"\end{aligned}")
    return body, True


def unbreak(body):
    """Inverse of broken(): the plain 'lhs = rhs' text (tests/equations_proof.py)."""
    if not body.startswith(r"\begin{aligned}"):
        return body
    body = body[len(r"\begin{aligned}"):-len(r"\end{aligned}")]
    return body.replace(r"\\ &\quad ", " ").replace(" &= ", " = ", 1)


def _escape_text(s):
    """Prose: math between $...$ kept, the rest escaped for LaTeX."""
    parts = s.split("$")
    for i in range(0, len(parts), 2):
        code = parts[i].split("`")
        for k in range(len(code)):
            code[k] = (code[k].replace("\\", r"\textbackslash{}").replace("_", r"\_")
                       .replace("&", r"\&").replace("%", r"\%").replace("#", r"\#"))
            if k % 2:
                code[k] = r"\texttt{" + code[k] + "}"
        parts[i] = "".join(code)
    return "$".join(parts)


def changed_lines(data, paper):
    """Keys of the lines of ``data`` whose content differs from the paper's
    model of the same base, and the keys of the paper's lines it lacks."""
    if paper is None or paper is data:
        return set(), []

    def content(line):
        return (line.get("lhs_tex"), line.get("rhs_tex"), line.get("text"), line.get("tag"))
    ref = {ln["key"]: content(ln) for ln in paper["lines"]}
    mine = {ln["key"] for ln in data["lines"]}
    changed = {ln["key"] for ln in data["lines"]
               if ln["kind"] != "section" and ref.get(ln["key"]) != content(ln)}
    removed = [ln["key"] for ln in paper["lines"] if ln["key"] not in mine
               and ln["kind"] not in ("section", "text")]
    return changed, removed


def _assumption_note(changes):
    return ", ".join(f"`{k} = {v}` (paper: `{p}`)" for k, v, p in changes)


def render(data, description, paper=None, changes=(), diff=False):
    """(markdown, latex) of a model's document; with diff=True only the lines
    that differ from ``paper`` (the paper's model of the same base)."""
    changed, removed = changed_lines(data, paper)
    note = _assumption_note(changes)
    title = f"Equations of the {data['model']} model" + (
        " (differences from the paper's model)" if diff else "")
    pre = [f"Model {data['model']}: {description}.",
           "Assumptions (derive/variants.py): " + ", ".join(
               f"`{k} = {v}`" for k, v in data["assumptions"].items() if k != "friction_law")
           + ".",
           "Generated by derive/generate.py from the same derivation as the C kernels; "
           "tests/equations_proof.py parses every line back and checks "
           r"$M(\mathbf{x})$, $\mathbf{f}(\mathbf{x}, t)$, Euler's equations, the residuals "
           r"and $\beta$ against the compiled kernels.  Equation numbers are the paper's."]
    if changes:
        pre.append(f"Highlighted: the lines that differ from the paper's model ({note}).")
    tags = [ln["tag"] for ln in data["lines"] if ln.get("tag")]
    pre.append("Paper equations: " + ", ".join(f"({tg})" for tg in dict.fromkeys(tags)) + ".")
    md = [f"# {title}", ""] + [p + "  " for p in pre] + [""]
    tex = [r"\documentclass[10pt]{article}",
           r"\usepackage[a4paper,margin=18mm]{geometry}",
           r"\usepackage{amsmath,amssymb}",
           r"\usepackage[dvipsnames]{xcolor}",
           r"\allowdisplaybreaks",
           r"\setcounter{MaxMatrixCols}{12}",
           r"\setlength{\parindent}{0pt}",
           r"\sloppy",
           r"\begin{document}",
           r"\section*{" + _escape_text(title) + "}"]
    tex += [_escape_text(p) + r"\\" for p in pre[:-1]] + [_escape_text(pre[-1]), ""]
    pending = None
    shown = 0
    for ln in data["lines"]:
        if ln["kind"] == "section":
            pending = ln["text"]
            if not diff:
                md += [f"## {pending}", ""]
                tex += [r"\subsection*{" + _escape_text(pending) + "}"]
                pending = None
            continue
        hi = ln["key"] in changed
        if diff and not hi:
            continue
        if pending is not None:
            md += [f"## {pending}", ""]
            tex += [r"\subsection*{" + _escape_text(pending) + "}"]
            pending = None
        shown += 1
        if ln["kind"] == "text":
            md += [("> " if hi and not diff else "") + ln["text"], ""]
            tex += [(r"{\color{BrickRed}" + _escape_text(ln["text"]) + "}") if hi and not diff
                    else _escape_text(ln["text"]), ""]
            continue
        body, _ = broken(ln["lhs_tex"], ln["rhs_tex"])
        tag = ln.get("tag")
        if hi and not diff:
            md += [f"> **Changed by the variant** ({note}):", ""]
            tex += [r"\noindent{\color{BrickRed}$\blacktriangleright$ changed by the variant ("
                    + _escape_text(note) + r"):}", r"\begingroup\color{BrickRed}"]
        md += ["$$", body + (f" \\tag{{{tag}}}" if tag else ""), "$$", ""]
        tex += [f"% line {ln['key']}",
                r"\begin{equation*}" + body + (f"\\tag{{{tag}}}" if tag else "")
                + r"\end{equation*}"]
        if hi and not diff:
            tex += [r"\endgroup"]
    if diff:
        if not changes:
            md += ["The paper's model: no differences.", ""]
            tex += ["The paper's model: no differences.", ""]
        elif removed:
            gone = "Lines of the paper's model not in this one: " + ", ".join(
                k.split(":", 1)[1] for k in removed) + "."
            md += [gone, ""]
            tex += [_escape_text(gone), ""]
    tex += [r"\end{document}"]
    return "\n".join(md).rstrip() + "\n", "\n".join(tex) + "\n"


# --------------------------------------------------------------------------
# the documents for `usm equations`

def _c_lines(text):
    out = []
    for line in text.split("\n")[:-1]:
        esc = line.replace("\\", "\\\\").replace('"', '\\"')
        out.append(f'    "{esc}",')
    return "\n".join(out)


def equations_c(docs, banner):
    """generated/usm_equations.c: the documents as line arrays for `usm equations`
    (one string per line: ISO C guarantees only 4095 characters per literal)."""
    c = banner + '#include <stddef.h>\n\n#include "usm_equations.h"\n\n'
    entries = []
    for k, (model, fmt, text) in enumerate(docs):
        c += f"static const char *const doc{k}[] = {{\n{_c_lines(text)}\n    NULL}};\n\n"
        entries.append(f'    {{"{model}", "{fmt}", doc{k}}},')
    c += ("const usm_equation_doc usm_equation_docs[USM_NEQUATION_DOCS] = {\n"
          + "\n".join(entries) + "\n};\n")
    return c


def equations_h(ndocs, banner):
    """generated/usm_equations.h: the declaration of the documents.  Not part of
    the library (libusm): only the `usm` command links usm_equations.c."""
    return (banner + "#ifndef USM_EQUATIONS_H\n#define USM_EQUATIONS_H\n\n"
            '#ifdef __cplusplus\nextern "C" {\n#endif\n\n'
            "/* The derived equations of every model as Markdown and LaTeX documents\n"
            "   (also generated/usm_<model>_equations.{md,tex}), and the same with only\n"
            "   the lines that differ from the paper's model (formats \"markdown-diff\",\n"
            "   \"latex-diff\"); lines end at NULL. */\n"
            "typedef struct usm_equation_doc {\n    const char *model;\n"
            "    const char *format; /* \"markdown\", \"latex\", \"markdown-diff\", "
            "\"latex-diff\" */\n"
            "    const char *const *lines;\n} usm_equation_doc;\n"
            f"#define USM_NEQUATION_DOCS {ndocs}\n"
            "extern const usm_equation_doc usm_equation_docs[USM_NEQUATION_DOCS];\n"
            '\n#ifdef __cplusplus\n}\n#endif\n\n#endif /* USM_EQUATIONS_H */\n')
