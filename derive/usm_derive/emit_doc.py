"""The derived equations in the paper's notation: a list of lines, each held
both as typeset LaTeX and as sympy (srepr), rendered as Markdown and LaTeX.

The document is written the way a textbook states a model: contact geometry
(R*, Z, v_c) defined once and used as symbols, the contact and rotor laws, each
torque, Euler's equations in frame A, and then M(x) x' = f(x, t) row by row in
those named quantities.  It is built from the generic pieces of the derivation
(model.py, ``Model.equations``: the force laws with placeholders, the torques,
the kinematics) with R* and Z as functions of theta whose derivatives are
dR*/dtheta = -Z and dZ/dtheta = R*; no equation of motion is typed here.
tests/derive/equations_proof.py proves the lines equal to the compiled kernels.

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
         "tau": r"\chi"}
PARAM_TEX = {"m0": "m_0", "F0": "F_0", "I_xx": "I_{xx}", "I_yy": "I_{yy}", "I_zz": "I_{zz}",
             "mu0": r"\mu_0", "kappa": r"\kappa", "c_R": "c_R", "d_R": "d_R", "c_t": "c_t",
             "c_r": "c_r", "d_t": "d_t", "d_r": "d_r", "I_R": "I_R",
             "amp_imbalance": r"\varepsilon", "phase_error": r"\delta", "mode_split": "s",
             "e_impact": r"e_{\mathrm{impact}}"}
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
        self.used = set()   # names of the symbols in the parsed lines

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
            self.used |= {x.name for x in (lhs.free_symbols | rhs.free_symbols)}
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

    def display(self, key, lhs_tex, rhs_tex, tag=None, rel=None, defines=None):
        """A typeset line; rel: its relation when not '='; defines: the LaTeX of
        the symbol it defines (printed as a comment for tests/derive/equations_symbols.py)."""
        extra = {}
        if rel:
            extra["rel"] = rel
        if defines:
            extra["defines_tex"] = defines
        self._add("display", key, tag, None, rhs_tex, lhs_tex, **extra)


def lhs_key(sym):
    if isinstance(sym, (list, tuple)):
        return ",".join(s.name for s in sym)
    return sym.name


# --------------------------------------------------------------------------
# the model in named quantities

def model_data(m):
    """The document of one model as data (JSON-able): its lines, symbols and
    the keys the proof needs (tests/derive/equations_proof.py), section by section."""
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
    doc.stability()
    doc.validity()
    if getattr(m, "unilateral", None):
        doc.unilateral()
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
        d.text(r"Frames (the paper's Table 1): $N$ inertial with unit vectors $\vec e_X, \vec e_Y, "
               r"\vec e_Z$; $A$ (axes $x_1, y_1, z_1$) turned by $\varphi$ about $\vec e_Z$; $B$ "
               r"(axes $x_2, y_2, z_2$) by $\theta$ about $x_1$; $K$ (the stator body) by $\psi$ "
               r"about $z_2$.  $C_{UV}$ maps the components of a vector in frame $V$ to its "
               r"components in frame $U$.  Vectors are given by their components in frame $A$.",
               "frames")
        d.define(self.Om, 2 * sp.pi * P["f"])
        for key, nm in (("C_NA", "C_{NA}"), ("C_AB", "C_{AB}"), ("C_BK", "C_{BK}")):
            d.define(key, plain(e[key]), lhs_tex=nm)
        d.define("omega_K", tidy(plain(e["omega_K"])), lhs_tex=r"\vec\omega^{\,K}")
        self.om_syms = [names.add("omega_" + a.replace("_", ""), r"\omega_{" + a + "}")
                        for a in AXES]
        self.omega_A = tidy(plain(self.kin.omega_A))
        self.named(self.om_syms, self.omega_A, lhs_tex=r"\vec\omega^{\,A}", key="def:omega_A")
        self.named(self.Rs, R * sp.cos(theta) - H * sp.sin(theta))
        self.named(self.Zs, R * sp.sin(theta) + H * sp.cos(theta), tag="2.3")
        d.define("r_c", plain(self.kin.r_c_A), lhs_tex=r"\vec r_c^{\,A}")
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
        self.vec("M_E", r"\tau_E", tidy(plain(e["M_E_A_t"])), "2.8", r"\vec\tau_E^{\,A}")
        self.vec("M_R", r"\tau_R", plain(e["M_R_A_t"].subs(tw, e["twist_angle"])), "2.9",
                 r"\vec\tau_R^{\,A}")
        self.vec("M_D", r"\tau_D", tidy(plain(e["M_D_A_t"])), "2.10", r"\vec\tau_D^{\,A}")
        M_C = self.nice(plain(e["M_C_A_t"].subs({cs["F_t"]: F_t, cs["F_n"]: F_n})))
        self.vec("M_C", r"\tau_C", M_C, "2.11", r"\vec\tau_C^{\,A} = \vec r_c\times\vec F_c")
        torques = self.torques
        M0 = sp.Matrix(torques["M_E"]) - sp.Matrix(torques["M_R"]) \
            - sp.Matrix(torques["M_D"]) + sp.Matrix(torques["M_C"])
        self.vec("M0", r"\tau", M0, "2.7", r"\vec\tau^{\,A}")
        if self.extra:
            d.text(r"The twist angle $\chi$ is a state of its own, integrated from "
                   r"$\omega_{z_1}$ ($\dot\chi = \omega_{z_1}$); the paper's $\varphi + \psi\cos"
                   r"\theta$ does not enter.", "tau")

    def euler_equations(self):
        d, e, plain = self.d, self.e, self.plain
        d.section("Euler's equations (2.6) in frame A")
        d.text(r"$\vec L = \mathbf{I}\,\vec\omega$ is the stator's angular momentum, "
               r"$\mathbf{I} = \mathrm{diag}(I_{xx}, I_{yy}, I_{zz})$ its inertia tensor in frame $K$.  "
               r"Frame $A$ turns with $\dot\varphi$ about $\vec e_Z$, so the rate of $\vec L$ is "
               r"$\vec G = \dot{\vec L}^{A} + \dot\varphi\,\vec e_Z\times\vec L$, "
               r"$\dot{\vec L}^{A}$ the rate of its components in frame $A$; these rows are "
               r"$C_{AK} = C_{AB} C_{BK}$ times (2.6), the same solutions.", "euler")
        d.define("L_A", tidy(plain(e["L_A"])), lhs_tex=r"\vec L^{A}")
        K = tidy(plain(e["dLdt_A"]))
        self.vec("K", "G", K, None,
                 r"\vec G = \dot{\vec L}^{A} + \dot\varphi\,\vec e_Z\times\vec L")
        nrot = 1 if self.slip else 0
        d.equation("eq:euler", sp.Matrix(self.torques["K"]), sp.Matrix(self.torques["M0"]),
                   row=self.nq + nrot, tag="2.6")

    def equations_of_motion(self):
        d = self.d
        self.paper_eq = "5.3" if self.slip else "4.6"
        d.section(r"Equations of motion $\mathcal{M}(\mathbf{x})\,\dot{\mathbf{x}} = "
                  r"\mathbf{f}(\mathbf{x}, t)$" f" ({self.paper_eq})")
        d.define("qvec", sp.Matrix(self.q).T, lhs_tex=r"\mathbf{q}^{\mathsf{T}}")
        d.define("xvec", sp.Matrix(self.m.states).T, lhs_tex=r"\mathbf{x}^{\mathsf{T}}")
        d.text(r"$\mathbf{q}$ holds the $n_q = %d$ coordinates, $\mathbf{x}$ the state.  "
               r"A superscript ${}^{(0)}$ marks the value of a quantity at zero accelerations "
               r"($\ddot{\mathbf{q}} = 0$); the part proportional to the accelerations is in "
               r"$\mathcal{M}$, whose entries are $\mathcal{M}_{i,j}$ (the identity where not "
               r"given), and $\mathbf{f}_{i}$ are the entries of $\mathbf{f}$."
               % self.nq, "zero")
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
                self.named(s0, sp.Matrix(z), key=f"def:{key}__0", lhs_tex=r"\vec G^{(0)}")
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
                    sym = names.add(f"m_{i + 1}_{nq + j + 1}",
                                    f"\\mathcal{{M}}_{{{i + 1},{nq + j + 1}}}")
                    self.named(sym, mij)
                    msyms[i, nq + j] = sym
            fi = self.nice(-row.subs(self.zero_of))
            sym = names.add(f"f_{i + 1}", f"\\mathbf{{f}}_{{{i + 1}}}")
            self.named(sym, fi)
            fsyms[i] = sym
        for k, rate in enumerate(self.e["extra_rates_t"]):
            i = 2 * nq + k
            msyms[i, i] = 1
            fsyms[i] = self.nice(self.plain(rate)).subs(
                {v: s for s, v in zip(self.om_syms, self.omega_A) if v != 0 and not v.is_Atom})
        d.define("Mass", msyms, lhs_tex=r"\mathcal{M}(\mathbf{x})", key="def:M")
        d.define("fvec", fsyms, lhs_tex=r"\mathbf{f}(\mathbf{x}, t)", key="def:f")
        d.display("display:eom", r"\mathcal{M}(\mathbf{x})\,\dot{\mathbf{x}}",
                  r"\mathbf{f}(\mathbf{x}, t)", tag=self.paper_eq)

    def stationary_solution(self):
        integrated = bool(self.extra)
        if self.slip:
            title = "(3.1)-(3.5), section 5" if integrated else "(3.1)-(3.6), section 5"
        else:
            title = "(3.1)-(3.5), (3.7)" if integrated else "(3.1)-(3.7)"
        self.d.section("Stationary solution " + title)
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
            # the twist state chi is constant on the orbit: its value is the
            # unknown bar chi of the twisting balance (below)
            on[self.extra[0]] = chi
            self.ansatz[self.extra[0].name] = "chi"
        d.text(r"On the orbit $\dot\theta = \dot Z = \ddot Z = 0$ and $\omega_{z_1} = 0$; a bar "
               r"marks a quantity on it.  Frame $A$ turns with $\bar\varphi = \Omega t + \alpha$, "
               r"so the components in frame $A$ are the paper's $X + iY$ combination (3.3) times "
               r"$e^{-i\bar\varphi}$: time drops out, and (3.4) splits into the real residuals "
               r"(3.5a), (3.5b)." + (r"  The twist angle $\chi$ is constant on the orbit, "
                                     r"$\bar\chi$." if self.extra else ""), "orbit")
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
        d.display("display:3.2", r"\bar{\vec G}", r"\bar{\vec\tau}_E - \bar{\vec\tau}_R - "
                  r"\bar{\vec\tau}_D + \bar{\vec\tau}_C", tag="3.2")
        args = self.res_args = (r"\alpha, \bar\theta, \bar{\dot\varphi}_R" if self.slip
                                else r"\alpha, \bar\theta")
        d.display("display:3.4", r"f_1(%s) + i f_2(%s)" % (args, args), "0", tag="3.4",
                  defines="f_1, f_2")
        self.res_keys = []
        if self.slip:
            rr = names.add("f_R", "f_R")
            rot = (self.rotor_eq[0] - self.rotor_eq[1]).xreplace(self.ideal).subs({self.wRd: 0})
            self.named(rr, self.nice_bar(rot.subs(bar_of)), tag="3.5c",
                       lhs_tex=r"f_R(\alpha, \bar\theta, \bar{\dot\varphi}_R)")
            self.res_keys.append(rr.name)
        for k, tag in ((0, "3.5a"), (1, "3.5b")):
            fs = names.add(f"f_{k + 1}bar", f"f_{k + 1}")
            self.named(fs, resid[k], tag=tag, lhs_tex=f"f_{k + 1}({self.res_args})")
            self.res_keys.append(fs.name)

    def twist_lines(self):
        """The twisting balance (the z_1 row) gives the twist angle on the
        orbit, beta follows (3.6); the stick model's rotor speed (3.7)."""
        d, chi, beta, thb = self.d, self.chi, self.beta, self.thb
        solved = (r"The stationary solution: $f_1 = f_2 = 0$"
                  + (r" and $f_R = 0$ ((3.5c) is this document's number: the rotor's balance "
                     r"(2.2) on the orbit, which the paper's section 5 states in words)"
                     if self.slip else "")
                  + r".  The $z_1$ row, the twisting balance, gives the twist angle $\bar\chi$ "
                  r"on the orbit")
        if self.extra:
            d.text(solved + r".  $\psi$ enters none of this model's equations (it is cyclic), so "
                   r"$\beta$, the phase of $\psi$ in (3.1c), is free; by convention the kernels "
                   r"report the $\beta$ for which the paper's twist angle $\varphi + \psi\cos"
                   r"\theta$ equals $\bar\chi$ on the orbit.", "twist")
        else:
            d.text(solved + r", and $\beta$ follows from the twist angle $\varphi + \psi\cos"
                   r"\theta$ of (2.9) (the paper's (3.6) has the sign of $\alpha$ flipped: see "
                   r"the departures from the paper).", "twist")
        if chi not in self.resid[2].free_symbols:
            raise RuntimeError(f"{self.m.name}: twisting balance free of the twist angle")
        chi_expr = self.nice_bar(solve_linear(self.resid[2], chi))
        self.named(chi, chi_expr, lhs_tex=r"\bar\chi")
        beta_expr = self.e["beta_generic"].subs({self.cs["twist"]: chi,
                                                 sp.Symbol("theta", real=True): thb})
        self.named(beta, self.nice_bar(beta_expr), tag=None if self.extra else "3.6")
        self.steady = {"beta": beta.name, "twist": chi.name}
        if not self.slip:
            rs = self.names.add("phidot_R_bar", r"\bar{\dot\varphi}_R")
            self.named(rs, -self.bar_of[self.wR], tag="3.7")
            self.steady["rotor_speed"] = rs.name

    def linearisation(self):
        d, m, e, nq, nextra = self.d, self.m, self.e, self.nq, len(self.extra)
        d.section("Linearisation about the stationary orbit (4.9)")
        d.text(r"$\Delta\mathbf{x} = \mathbf{x} - \bar{\mathbf{x}}(t)$ is the deviation from "
               r"the stationary orbit $\bar{\mathbf{x}}(t)$ of (3.1), $\mathbf{v}$ a vector held "
               r"fixed while differentiating, $\mathbf{1}_{n}$ the $n \times n$ identity; "
               r"$\mathcal{M}_q$ is the block of $\mathcal{M}$ on the accelerations and "
               r"$\mathbf{f}_q$ the matching entries of $\mathbf{f}$.", "linvars")
        d.display("display:def:Mq", r"\mathcal{M}_q",
                  r"\left(\mathcal{M}_{k,l}\right)_{n_q < k, l \le 2 n_q}", defines=r"\mathcal{M}_q")
        d.display("display:def:fq", r"\mathbf{f}_q",
                  r"\left(\mathbf{f}_{n_q + 1}, \dots, \mathbf{f}_{2 n_q}\right)^{\mathsf{T}}",
                  defines=r"\mathbf{f}_q")
        d.display("display:def:J", r"J(t)", defines="J", rhs_tex=
                  r"\frac{\partial\mathbf{f}}{\partial\mathbf{x}} - \frac{\partial "
                  r"(\mathcal{M}\mathbf{v})}{\partial\mathbf{x}}\Big|_{\mathbf{x} = "
                  r"\bar{\mathbf{x}}(t),\ \mathbf{v} = \dot{\bar{\mathbf{x}}}(t)}")

        d.display("display:4.9", r"\mathcal{M}(\bar{\mathbf{x}}(t))\,\Delta\dot{\mathbf{x}}",
                  r"J(t)\,\Delta\mathbf{x}", tag="4.9")
        d.display("display:blocks", r"\mathcal{M}(\bar{\mathbf{x}}(t))", block_mass(nq, nextra))
        d.display("display:A", r"J(t)", block_jacobian(m, nq, nextra))
        if not all(x == 0 for x in list(e["steady_rate"])[nq:2 * nq]):
            raise RuntimeError(f"{m.name}: accelerations on the orbit are not zero")
        if m.t0_independent:
            when = (r"In frame $A$ every entry of $J$ and $\mathcal{M}$ is constant on the orbit: "
                    r"the multipliers do not depend on the start time $t_0$.")
        else:
            ent = ", ".join(r"$\partial f_{%d}/\partial %s$" % (i + 1, self.names.tex[m.states[j]])
                            for i, j in e["A_bar_t_entries"])
            ent = ent.replace(r"\partial f_{", r"\partial \mathbf{f}_{")
            when = (r"In frame $A$ the entries of $J$ are constant on the orbit except "
                    + (ent or r"in $\mathcal{M}$") + r" (changing with $t$ along "
                    r"$\bar{\mathbf{x}}(t)$): the multipliers depend on the start time $t_0$ "
                    r"(the paper's Table " + ("4" if self.slip else "3") + r" is $t_0 = 0$).")
        d.text(r"On the orbit $\ddot{\bar{\mathbf{q}}} = 0$, so the $\partial(\mathcal{M}\mathbf{v})/"
               r"\partial\mathbf{x}$ term vanishes.  " + when, "linear")

    def stability(self):
        """The Floquet problem the runtime solves (section 4 of the paper)."""
        d, m, names = self.d, self.m, self.names
        d.section("Stability: the Floquet problem (section 4)")
        d.text(r"The coefficients of (4.9) are periodic with the period of the excitation.  "
               r"The fundamental matrix $\mathbf{Y}(t)$ starts from the identity at the start "
               r"time $t_0$; after one period it is the monodromy matrix $\mathbf{B}$, whose "
               r"eigenvalues $\lambda_k$ are the Floquet multipliers:", "floquet")
        d.display("display:def:period", r"\mathcal{T}", r"\frac{2\pi}{\Omega}",
                  defines=r"\mathcal{T}")
        d.display("display:def:Y", r"\mathcal{M}(\bar{\mathbf{x}}(t))\,\dot{\mathbf{Y}}(t)",
                  r"J(t)\,\mathbf{Y}(t), \quad \mathbf{Y}(t_0) = \mathbf{1}_{%d}"
                  % len(m.states), defines=r"\mathbf{Y}")
        d.display("display:def:B", r"\mathbf{B}", r"\mathbf{Y}(t_0 + \mathcal{T})",
                  defines=r"\mathbf{B}")
        d.display("display:def:lambda", r"\det(\mathbf{B} - \lambda_k \mathbf{1}_{%d})"
                  % len(m.states), "0", defines=r"\lambda_k")
        cyc = [names.tex[m.states[i]] for i in m.cyclic]
        if cyc:
            which = (r"A cyclic coordinate (one that enters neither $\mathcal{M}$ nor "
                     r"$\mathbf{f}$: here $" + "$, $".join(cyc) + r"$) leaves its column of "
                     r"$\mathbf{B}$ a unit vector and contributes an exact multiplier $1$ "
                     r"(a shift of that coordinate is again a solution); it is set aside.  ")
        else:
            which = (r"No coordinate of this model is cyclic (each enters $\mathcal{M}$ or "
                     r"$\mathbf{f}$), so every multiplier counts.  ")
        d.text(which + r"The stationary solution is asymptotically stable if and only if every "
               r"other multiplier lies inside the unit circle, $|\lambda_k| < 1$ (the paper's "
               r"Tables 3 and 4, with $t_0 = 0$).", "stable")

    def validity(self):
        """Where the model describes the motor: contact and stick."""
        d = self.d
        d.section("Where the model describes the motor: contact and stick")
        d.text(r"The contact is assumed permanent (2.3) and the rotor pressed on the stator, so "
               r"a result describes the motor only while the normal force is positive"
               + (r"; the stick model also needs the friction to carry the tangential force, "
                  r"with the friction coefficient $\mu_0$ of section 5 as the limit"
                  if not self.slip else
                  r" (the slip model's friction law replaces the stick condition)")
               + r".  usm checks this on every stationary solution and marks a result where it "
               r"fails (in JSON: `valid` is false, `invalid_reason` is `contact_open`"
               + ("" if self.slip else r" or `stick_not_admissible`") + ").", "valid")
        d.display("display:contact", r"F_n", "0", rel=">")
        if not self.slip:
            d.display("display:stick", r"|F_t|", r"\mu_0 F_n", rel=r"\le")
        d.section(r"Conditioning near $\theta = 0$")
        d.text(r"The Euler angles are singular at $\theta = 0$: $\varphi$ and $\psi$ then "
               r"turn about the same axis ($\omega_{y_1} = -\dot\psi\sin\theta$ vanishes), "
               r"and $\mathcal{M}(\mathbf{x})$ becomes singular.  On the paper's orbit "
               r"($\bar\theta = 0.81836 \cdot 10^{-4}$) it is nearly so: the 2-norm condition "
               r"number of $\mathcal{M}(\bar{\mathbf{x}})$ is $9.1 \cdot 10^{11}$ (3-DOF model "
               r"with integrated twist, $7 \times 7$; tilt-vector coordinates give "
               r"$5.5 \cdot 10^{7}$) and the entries of the linearisation span about 17 orders "
               r"of magnitude.  Do not invert $\mathcal{M}$ alone: solve with it in balanced "
               r"coordinates, integrate with tight tolerances, and expect the multipliers to "
               r"about 9 to 12 digits in double precision (docs/coordinates.md).", "cond")

    def unilateral(self):
        """closure = unilateral: the two modes, the guards, the resets
        (typeset only; the kernels are checked by tests/solve/test_hybrid_unilateral.c)."""
        d, u = self.d, self.m.unilateral
        tex = dict(self.names.tex)
        tex.update({sp.Symbol(nm, real=True): t_ for nm, t_ in (
            ("Z_R", r"Z_R"), ("Z_Rdot", r"\dot{Z}_R"), ("Z_Rddot", r"\ddot{Z}_R"),
            ("w_R", r"w_R"), ("w_Rdot", r"\dot{w}_R"), ("F_n", r"F_n"), ("F_t", r"F_t"))})
        d.section("Unilateral contact: modes, guards, resets")
        d.text("Closed mode: the equations of motion above, valid while $F_n \\ge 0$. "
               "Open mode: state $\\mathbf{y} = (\\mathbf{x}, " + ", ".join(
                   tex[sp.Symbol(nm, real=True)] for nm in u["new_names"]) + ")$; the rows "
               "below with $F_n = F_t = 0$ (the stator's rows are (2.6) with the contact "
               "forces as symbols; the impact uses their coefficients).", "unilateral:modes")
        rows = u["rows"]
        start = len(rows) - len(u["new_names"]) + 1
        for i in range(start, len(rows)):
            d.display(f"display:open_row{i}", "0", latex(rows[i], tex))
        d.display("display:guard_closed", r"g_{\mathrm{closed}}",
                  r"F_n(\mathbf{x}, \dot{\mathbf{x}}) \searrow 0 \;\Rightarrow\; "
                  r"\text{separation: } \mathbf{y} = (\mathbf{x}, Z(\theta), \dot Z"
                  + (r", v_c/R^*" if "w_R" in u["new_names"] else "") + ")")
        d.display("display:guard_open", r"g_{\mathrm{open}}", latex(u["gap"], tex)
                  + r" \searrow 0 \;\Rightarrow\; \text{impact}")
        d.display("display:impact", r"M_a\,\Delta\mathbf{v}",
                  r"B\,(P_n, P_t)^T, \quad \dot g^+ = -e_{\mathrm{impact}}\,\dot g^-, "
                  r"\quad v_{\mathrm{rel}}^+ = 0 \text{ if } |P_t| \le \mu_0 P_n "
                  r"\text{, else } P_t = \pm\mu_0 P_n")
        d.display("display:gap_rate", r"\dot g", latex(u["contact_velocity"][0], tex))

    def data(self):
        m = self.m
        from .emit_contracts import model_couplings, couplings
        coupled = {}
        for k, i in enumerate(model_couplings(m.assumptions)):
            if i >= 0:
                c = couplings()[i]
                coupled[c[2]] = [c[3], c[4]]
        used = sorted(self.d.used & {s.name for s in P.values()})
        if not self.slip:
            used = sorted(set(used) | {"mu0"})   # the stick check
        if getattr(m, "unilateral", None):
            used = sorted(set(used) | {"e_impact", "mu0"})   # the impact law
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
            "used_parameters": used, "coupled": coupled, "slip": self.slip,
            "twist_integrated": bool(self.extra),
            "unilateral": bool(getattr(m, "unilateral", None)),
            "cyclic": [m.states[i].name for i in m.cyclic],
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
    rows = [r"\mathbf{1}_{%d}" % nq + r" & 0", r"0 & \mathcal{M}_q(\bar{\mathbf{x}}(t))"]
    if nextra:
        rows = [r"\mathbf{1}_{%d} & 0 & 0" % nq, r"0 & \mathcal{M}_q(\bar{\mathbf{x}}(t)) & 0",
                r"0 & 0 & 1"]
    return r"\begin{pmatrix}" + r" \\ ".join(rows) + r"\end{pmatrix}"


def block_jacobian(m, nq, nextra):
    """A = df/dx on the orbit in blocks: position rows (0, I), acceleration rows
    and extra rows, each block named unless it is zero or the identity."""
    groups = [(r"\mathbf{q}", 0, nq), (r"\dot{\mathbf{q}}", nq, 2 * nq)]
    if nextra:
        groups.append((r"\chi", 2 * nq, 2 * nq + nextra))
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
                cells.append(r"\mathbf{1}")
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
    """Inverse of broken(): the plain 'lhs = rhs' text (tests/derive/equations_proof.py)."""
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


ASSUMPTION_WORDS = {
    ("contact", "stick"): r"Stick: the rotor turns with the stator's contact point, without slip "
                          r"(2.4); the rotor angle is not a state (3 degrees of freedom).",
    ("contact", "slip"): r"Slip: the rotor angle $\varphi_R$ is a fourth degree of freedom and the "
                         r"tangential force is $F_t = \mu(v_{\mathrm{rel}}) F_n$ (5.1).",
    ("friction", "atan"): r"The paper's friction law $\mu = \mu_0 \arctan(\kappa v_{\mathrm{rel}})$ "
                          r"(5.2).",
    ("friction", "tanh"): r"The friction law $\mu = \mu_0 \tanh(\kappa v_{\mathrm{rel}})$ in place of "
                          r"the paper's (5.2).",
    ("friction", "stribeck"): r"A friction law with a Stribeck peak, $\mu = \mu_0 \tanh(\kappa "
                              r"v_{\mathrm{rel}})\,(1 + e^{-(100 v_{\mathrm{rel}})^2}/2)$ with "
                              r"$v_{\mathrm{rel}}$ in m/s, in place of the paper's (5.2).",
    ("twist", "paper"): r"The restoring torque of the twist acts on the paper's twist angle "
                        r"$\varphi + \psi\cos\theta$ (2.9).",
    ("twist", "integrated"): r"The restoring torque of the twist acts on a twist angle $\chi$ "
                             r"integrated from the twist rate, $\dot\chi = \omega_{z_1}$ (an extra "
                             r"state), in place of the paper's $\varphi + \psi\cos\theta$.",
    ("spring_reference", "theta0"): r"The spring force is measured from the contact height at "
                                    r"$\theta = 0$: $F_R = F_0 + c_R(Z - Z_0)$, $Z_0 = H$.",
    ("spring_reference", "literal"): r"The spring force as printed in (2.1): $F_R = F_0 + c_R Z$.",
    ("stator_inertia", "axisymmetric"): r"An axisymmetric stator: $I_{yy} = I_{xx}$.",
    ("stator_inertia", "general"): r"Stator inertias $I_{xx}$, $I_{yy}$, $I_{zz}$ independent.",
    ("imperfection", "none"): r"The ideal motor: two excitation phases of equal amplitude in exact "
                              r"quadrature, the same tilt stiffness in every direction.",
    ("imperfection", "driver_stator"): r"A real motor: amplitude imbalance $\varepsilon$ and phase "
                                       r"error $\delta$ of the driver, tilt-stiffness split $s$ of "
                                       r"the stator (parameters below).",
}

BODY_WORDS = (
    r"The upper part of the stator is a rigid body turning about a fixed point by the z-x-z Euler "
    r"angles $\varphi$, $\theta$, $\psi$ (the paper's Fig. 5); springs and dampers restrain its "
    r"tilt ($c_r$, $d_r$) and its twist ($c_t$, $d_t$), and a torque of amplitude $m_0$ rotating "
    r"at $\Omega = 2\pi f$ drives it (2.8).  The rotor is a rigid disk (mass $M$, moment of "
    r"inertia $I_R$) turning about $\vec e_Z$, pressed on the stator by a preloaded spring "
    r"($F_0$, $c_R$, $d_R$) and loaded by the torque $T$.  Rotor and stator touch at one point, "
    r"at radius $R$ and height $H$ on the stator, at all times (2.3); the radial contact force "
    r"is neglected (2.5).")


def _assumption_words(assumptions):
    out = []
    for k, v in assumptions.items():
        if k == "friction_law":
            continue
        if (k, v) in ASSUMPTION_WORDS:
            out.append(ASSUMPTION_WORDS[(k, v)])
        elif k == "friction" and "friction_law" in assumptions:
            out.append(f"The friction law `mu = {assumptions['friction_law']}` (`{v}`) in place "
                       "of the paper's (5.2).")
        else:   # an assumption this module has no words for yet
            out.append(f"Assumption `{k}` is `{v}` (derive/variants.py).")
    return out


def _num(v):
    """A value as LaTeX: 8 significant digits, powers of ten as 10^{n}."""
    if v == 0:
        return "0"
    if 1e-3 <= abs(v) < 1e5:
        return "%.8g" % v
    mant, ex = ("%.7e" % v).split("e")
    mant = mant.rstrip("0").rstrip(".")
    return r"%s \cdot 10^{%d}" % (mant, int(ex))


def _unit_tex(u):
    return re.sub(r"\^(\d)", r"$^\1$", u)


def parameter_rows(data, names_tex):
    """[(symbol tex, name, meaning, unit, value tex, source, remark)] of every parameter."""
    from .defaults import TABLE5, defaults
    used = set(data.get("used_parameters", data["parameters"]))
    coupled = data.get("coupled", {})
    rows, notes = [], []
    for name, unit, meaning, value, source, reason in defaults():
        if name not in data["parameters"]:
            continue
        sym = names_tex[name]
        val = "$" + _num(value) + "$"
        src = source
        if name in coupled:
            eq, because = coupled[name]
            val = "$= " + names_tex[eq] + "$"
            src += f"; taken equal to ${names_tex[eq]}$ ({because})"
        elif name not in used:
            src += "; does not enter this model"
        if reason and source != TABLE5:
            for k, (syms, r) in enumerate(notes):
                if r == reason:
                    notes[k] = (syms + [sym], r)
                    break
            else:
                notes.append(([sym], reason))
        rows.append((sym, name, MEANING.get(name, meaning), unit, val, src))
    return rows, notes


# meanings that name the parameter's symbol, written with the document's symbols
MEANING = {
    "f": r"excitation frequency, $\Omega = 2\pi f$",
    "amp_imbalance": "amplitude imbalance of the two excitation phases",
    "phase_error": "phase error of the second excitation phase",
    "mode_split": r"tilt stiffness split: $c_r(1 + s)$ about $\vec e_X$, $c_r(1 - s)$ about "
                  r"$\vec e_Y$",
}


NOTATION = [
    (r"t", "time"),
    (r"\varphi, \theta, \psi", r"Euler angles of the stator: about $\vec e_Z$, then about $x_1$ "
                               r"(the tilt), then about $z_2$"),
    (r"\varphi_R", r"rotor angle about $\vec e_Z$"),
    (r"\vec e_X, \vec e_Y, \vec e_Z", r"unit vectors of the inertial frame $N$"),
    (r"\vec e_{x_1}, \vec e_{y_1}, \vec e_{z_1}", r"unit vectors of frame $A$"),
    (r"\vec\omega", "angular velocity of the stator"),
    (r"\vec F_c", r"contact force on the stator, normal part $F_n$, tangential part $F_t$"),
    (r"\alpha, \beta", r"phase angles of the stationary solution (3.1), radians in $[0, 2\pi)$"),
    (r"\bar\theta", "tilt of the stationary solution (3.1b)"),
    (r"\bar\chi", "twist angle on the stationary orbit, from the twisting balance"),
    (r"n_q", r"number of coordinates $\mathbf{q}$"),
    (r"t_0", "start time of the Floquet integration"),
    (r"\mathbf{v}", "a vector held fixed while differentiating (4.9)"),
    (r"e, i, \pi", "Euler's number, the imaginary unit, pi"),
]
NOTATION_SLIP = [(r"\bar{\dot\varphi}_R", "rotor speed of the stationary solution (unknown)")]
NOTATION_TWIST = [(r"\chi", r"twist angle, a state: $\dot\chi = \omega_{z_1}$")]
# the unilateral contact's section (closure = unilateral)
NOTATION_UNILATERAL = [
    (r"Z_R", r"height of the rotor's contact face, a state while the contact is open"),
    (r"\mathbf{y}", r"state of the open mode: $\mathbf{x}$ with the rotor's own coordinates"),
    (r"g", r"gap between the rotor's face and the stator's highest point (open mode)"),
    (r"g_{\mathrm{closed}}, g_{\mathrm{open}}", r"guard functions: the contact opens where "
                                              r"$g_{\mathrm{closed}} = F_n$ falls through 0, "
                                              r"closes where $g_{\mathrm{open}} = g$ does"),
    (r"M_a", r"mass matrix of the impact (the velocity rows of $\mathcal{M}$ with the rotor's)"),
    (r"B", r"directions in which the normal and tangential impulses act"),
    (r"P_n, P_t", r"normal and tangential impulse at the impact"),
    (r"v_{\mathrm{rel}}", r"relative tangential velocity of rotor and stator at the contact"),
]

CONVENTIONS = (
    r"$\dot X$ is the time derivative of $X$, $\bar X$ its value on the stationary orbit (3.1), "
    r"$\Delta X$ a deviation from it, $X^{(0)}$ its value at zero accelerations; "
    r"$X_{x_1}, X_{y_1}, X_{z_1}$ (or $X_{E,x_1}, \dots$ for $\vec X_E$) are the components of a "
    r"vector $\vec X$ in frame $A$, and $\vec X^{A}$ the vector given by them.  "
    r"Symbols renamed against the paper, so that none has two meanings: the mass matrix is "
    r"$\mathcal{M}$ (the paper's bold $M$; $M$ is the rotor mass), the torques are "
    r"$\vec\tau_E, \vec\tau_R, \vec\tau_D, \vec\tau_C$ and their sum $\vec\tau$ (the paper's "
    r"$\vec M_E, \dots$ and (2.7)), $\vec G$ the rate of the angular momentum, $J(t)$ the matrix of "
    r"(4.9) (the paper's $A(t)$; $A$ names a frame), $\mathcal{T}$ the period (the paper's $T$, "
    r"also its load torque), $\mathbf{B}$ the monodromy matrix as in the paper.")


def departures(data, changes, description):
    """[(equation, the paper, this document, evidence)] for this model."""
    a = data["assumptions"]
    slip, integrated = data.get("slip"), data.get("twist_integrated")
    rows = []
    if a.get("spring_reference") == "theta0":
        rows.append(("(2.1)", r"$F_R = F_0 + c_R Z$",
                     r"$F_R = F_0 + c_R(Z - Z_0)$, $Z_0 = H$, the height at $\theta = 0$",
                     r"read literally, $F_n \approx 12.4$ N and no stationary solution exists; "
                     r"with $Z_0 = H$ the paper's $\bar\theta = 0.81836 \cdot 10^{-4}$ comes out "
                     r"to five digits"))
    rows.append(("(2.2), (2.4)", r"$I_R \ddot\varphi_R = F_t R^* - T$ with (2.4) as printed",
                 r"$I_R \dot w_R = F_t R^* - T$, $w_R = -\dot\varphi_R$ the rotor's speed in "
                 r"its driving direction",
                 r"Newton's third law with the force on the stator (2.5); read literally "
                 r"together, (2.2) and (2.4) flip the sign of the rotor inertia the stator "
                 r"feels and Table 3 is not reproduced; as here its multipliers agree to about "
                 r"$5 \cdot 10^{-4}$"))
    if slip:
        rows.append(("(5.1)", r"$v_{\mathrm{rel}} = v_c - \omega_R R^*$",
                     r"$v_{\mathrm{rel}} = v_c - w_R R^*$, $w_R = -\dot\varphi_R$",
                     r"the paper's own stationary rotor speed, $\dot\varphi_R = -10.34$ 1/s, "
                     r"is negative: the rotor turns in $-\vec e_Z$ (Fig. 8: against the "
                     r"contact point), and this sign reproduces it and Table 4"))
    if integrated:
        rows.append(("(3.6)", r"$\beta = (T + c_t\alpha)/(c_t\cos\bar\theta)$",
                     r"not used: $\psi$ is cyclic, $\beta$ is free; reported by convention",
                     r"$\psi$ enters no equation of this model"))
    else:
        rows.append(("(3.6)", r"$\beta = (T + c_t\alpha)/(c_t\cos\bar\theta)$",
                     r"$\beta = (T/c_t - \alpha)/\cos\bar\theta$",
                     r"the twisting balance $c_t(\alpha + \beta\cos\bar\theta) = T$; it gives "
                     r"$\beta = -5.1256$, the paper's 4-DOF $\beta = -5.12$; its 3-DOF "
                     r"$-1.98$ is $\pi - 5.1256$, a branch modulo $\pi$"))
    if not slip:
        rows.append(("(3.7)", r"$\dot\varphi_R = H\bar\theta\Omega/R$ (small $\bar\theta$)",
                     r"$\bar{\dot\varphi}_R = -\bar w_R$, exact, from (2.4); negative",
                     r"the rotor turns against the contact point (Fig. 8); $-11.42$ 1/s at the "
                     r"paper's parameters; the paper's 4-DOF speed $-10.34$ 1/s is negative too"))
    rows.append(("(3.5)", r"$\alpha = 5.16$ degrees, $\beta = -1.98$ degrees (3-DOF)",
                 r"radians in $[0, 2\pi)$: $\alpha = 5.1256$",
                 r"the stator's equations on the orbit are the same in both models, and the "
                 r"paper's 4-DOF section gives $\alpha = 5.12$, $\beta = -5.12$: 5.16 is a "
                 r"misprint of 5.126, in radians"))
    if integrated:
        rows.append(("(4.9)", "periodic coefficients",
                     r"constant in frame $A$: the multipliers do not depend on $t_0$",
                     r"the twist angle $\chi$ is bounded on the orbit (variant)"))
    else:
        rows.append(("(4.9)", "periodic coefficients",
                     r"constant in frame $A$ but for $\partial\mathbf{f}/\partial\theta$ through "
                     r"$\bar\psi(t)$, which grows with $t$: the multipliers depend on $t_0$",
                     r"$t_0 = 0$ reproduces the paper's Table " + ("4" if slip else "3")))
    rows.append(("Table 5", r"$c_t$, $c_r$ in Nm; $d_t$, $d_r$ in Nms",
                 "N m/rad and N m s/rad", "torques per radian and per radian/s in (2.9), (2.10)"))
    rows.append(("Table 5", r"no rotor mass, no excitation frequency",
                 r"$M = 2 I_R/R^2$, $f = 37$ kHz (chosen)", "the parameter table's notes"))
    if slip:
        rows.append(("Table 4", r"$\lambda_{1,2} = 0.2616 \pm 0.4934i$",
                     r"about $0.2648 \pm 0.5010i$ (not reproduced)",
                     r"same angle, modulus 1.5 \% larger; every other multiplier of Tables 3 "
                     r"and 4 agrees to about $5 \cdot 10^{-4}$"))
    for k, v, p in changes:
        rows.append(("variant", f"`{k} = {p}`", f"`{k} = {v}`", description))
    return rows


def _md_table(head, rows):
    out = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    out += ["| " + " | ".join(c.replace("|", "/") for c in r) + " |" for r in rows]
    return out + [""]


def _tex_table(label, spec, head, rows):
    out = [r"{\small\setlength{\tabcolsep}{4pt}", f"% table {label}",
           r"\begin{longtable}{" + spec + "}",
           " & ".join(r"\textbf{" + h + "}" for h in head) + r" \\ \hline", r"\endhead"]
    out += [" & ".join(_escape_text(c) for c in r) + r" \\" for r in rows]
    return out + [r"\end{longtable}}", ""]


def _front(data, description, changes, diff):
    """(markdown lines, LaTeX lines) of the front matter: what the model is, in words,
    its parameters, the notation and the departures from the paper."""
    model = data["model"]
    names_tex = data["symbols"]
    intro = (f"Model {model}: {description}.  Equations of motion, stationary solution and "
             f"stability of the ultrasonic motor of the paper \"Modeling and stability analysis "
             f"for an ultrasonic motor\", derived by usm; equation numbers are the paper's.")
    words = [BODY_WORDS] + _assumption_words(data["assumptions"])
    if changes and not diff:
        words.append("Lines marked \"changed by the variant\" differ from the paper's model.")
    rows, notes = parameter_rows(data, names_tex)
    prow = [(f"${sym}$", f"`{name}`", meaning, unit, val, src)
            for sym, name, meaning, unit, val, src in rows]
    pnote = "The values the paper's Table 5 does not give: " + "; ".join(
        ", ".join(f"${x}$" for x in syms) + ": " + reason
        for syms, reason in notes) + "."
    notation = NOTATION + (NOTATION_SLIP if data.get("slip") else []) + \
        (NOTATION_TWIST if data.get("twist_integrated") else []) + \
        (NOTATION_UNILATERAL if data.get("unilateral") else [])
    listed = {x.strip() for sym, _ in notation for x in sym.split(",")}
    for st in data["states"]:   # coordinates of another model (not the Euler angles)
        tx = names_tex.get(st, "")
        if st in data.get("accelerations", []) or "dot" in st or not tx or tx in listed:
            continue
        notation.append((tx, r"a coordinate of the state $\mathbf{x}$ of this model"))
        listed.add(tx)
    nrow = [(f"${sym}$", what) for sym, what in notation]
    drow = departures(data, changes, description)
    md = [p + "" for p in [intro, ""] ]
    md += ["## The model in words", ""] + [f"- {w}" for w in words] + [""]
    md += ["## Parameters", ""]
    md += _md_table(["symbol", "name", "meaning", "unit", "default", "source"],
                    [(a, b, c, d.replace("^2", "²"), e, f) for a, b, c, d, e, f in prow])
    md += [pnote, ""]
    md += ["## Notation", ""] + _md_table(["symbol", "meaning"], nrow) + [CONVENTIONS, ""]
    md += ["## Departures from the paper", ""]
    md += _md_table(["where", "the paper", "this document", "evidence"], drow)
    tex = [_escape_text(intro), "", r"\subsection*{The model in words}", r"\begin{itemize}"]
    tex += [r"\item " + _escape_text(w) for w in words] + [r"\end{itemize}"]
    tex += [r"\subsection*{Parameters}"]
    tex += _tex_table("parameters", r"@{}p{0.07\textwidth} p{0.15\textwidth} p{0.20\textwidth} "
                      r"p{0.11\textwidth} p{0.13\textwidth} p{0.22\textwidth}@{}",
                      ["symbol", "name", "meaning", "unit", "default", "source"],
                      [(a, b, c, _unit_tex(d), e, f) for a, b, c, d, e, f in prow])
    tex += [_escape_text(pnote), ""]
    tex += [r"\subsection*{Notation}"]
    tex += _tex_table("notation", r"@{}p{0.22\textwidth} p{0.70\textwidth}@{}", ["symbol", "meaning"], nrow)
    tex += [_escape_text(CONVENTIONS), ""]
    tex += [r"\subsection*{Departures from the paper}"]
    tex += _tex_table("departures", r"@{}p{0.08\textwidth} p{0.23\textwidth} "
                      r"p{0.26\textwidth} p{0.37\textwidth}@{}",
                      ["where", "the paper", "this document", "evidence"], drow)
    return md, tex


def _appendix(data, changes):
    flags = ", ".join(f"`{k} = {v}`" for k, v in data["assumptions"].items()
                      if k != "friction_law")
    lines = [f"Assumptions as derive/variants.py spells them: {flags}."]
    if changes:
        lines.append("Changed against the paper's model: " + _assumption_note(changes) + ".")
    lines += [f"Generated by derive/generate.py (files generated/usm_{data['model']}.c, "
              f"generated/usm_{data['model']}_equations.md, .tex, .json) from the same "
              "derivation as the C kernels; tests/derive/equations_proof.py parses every line back "
              "and checks the mass matrix, the right-hand side, Euler's equations, the residuals "
              "and beta against the compiled kernels; tests/derive/equations_symbols.py checks that "
              "every symbol is defined and every parameter is in the table.",
              "Paper equations: " + ", ".join(
                  f"({tg})" for tg in dict.fromkeys(
                      ln["tag"] for ln in data["lines"] if ln.get("tag"))) + "."]
    md = ["## Appendix: assumptions as code flags, files", ""] + [x + "  " for x in lines] + [""]
    tex = [r"\subsection*{Appendix: assumptions as code flags, files}"]
    tex += [_escape_text(x) + r"\\" for x in lines[:-1]] + [_escape_text(lines[-1]), ""]
    return md, tex


def _body(ln):
    if ln.get("rel"):
        return f"{ln['lhs_tex']} {ln['rel']} {ln['rhs_tex']}"
    return broken(ln["lhs_tex"], ln["rhs_tex"])[0]


def _eq(ln, md, tex, comment=True):
    body, tag = _body(ln), ln.get("tag")
    md += ["$$", body + (f" \\tag{{{tag}}}" if tag else ""), "$$", ""]
    if comment:
        if ln.get("defines_tex"):
            tex.append(f"% defines {ln['defines_tex']}")
        tex.append(f"% line {ln['key']}")
    tex.append(r"\begin{equation*}" + body + (f"\\tag{{{tag}}}" if tag else "")
               + r"\end{equation*}")


def render(data, description, paper=None, changes=(), diff=False):
    """(markdown, latex) of a model's document; with diff=True only the lines
    that differ from ``paper`` (the paper's model of the same base), each
    after the paper's version it replaces."""
    changed, removed = changed_lines(data, paper)
    note = _assumption_note(changes)
    title = f"Equations of the {data['model']} model" + (
        " (differences from the paper's model)" if diff else "")
    md = [f"# {title}", ""]
    tex = [r"\documentclass[10pt]{article}",
           r"\usepackage[a4paper,margin=18mm]{geometry}",
           r"\usepackage{amsmath,amssymb,longtable}",
           r"\usepackage[dvipsnames]{xcolor}",
           r"\allowdisplaybreaks",
           r"\setcounter{MaxMatrixCols}{12}",
           r"\setlength{\parindent}{0pt}",
           r"\sloppy",
           r"\begin{document}",
           r"\section*{" + _escape_text(title) + "}"]
    if diff:
        intro = (f"Model {data['model']}: {description}.  Each line that differs from the "
                 f"paper's model of the same base, after the paper's version it replaces"
                 + (f" ({note})" if note else "") + ".")
        md += [intro, ""]
        tex += [_escape_text(intro), ""]
    else:
        fm, ft = _front(data, description, changes, diff)
        md += fm
        tex += ft
    old = {ln["key"]: ln for ln in (paper or {}).get("lines", [])}
    pending = None
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
        if diff:
            _diff_pair(old.get(ln["key"]), ln, md, tex)
            continue
        if ln["kind"] == "text":
            md += [("> " if hi else "") + ln["text"], ""]
            tex += [(r"{\color{BrickRed}" + _escape_text(ln["text"]) + "}") if hi
                    else _escape_text(ln["text"]), ""]
            continue
        if hi:
            md += [f"> **Changed by the variant** ({note}):", ""]
            tex += [r"\noindent{\color{BrickRed}$\blacktriangleright$ changed by the variant ("
                    + _escape_text(note) + r"):}", r"\begingroup\color{BrickRed}"]
        _eq(ln, md, tex)
        if hi:
            tex += [r"\endgroup"]
    if diff:
        if not changes:
            md += ["The paper's model: no differences.", ""]
            tex += ["The paper's model: no differences.", ""]
        elif removed:
            md += ["## Lines of the paper's model that this model does not have", ""]
            tex += [r"\subsection*{Lines of the paper's model that this model does not have}"]
            for k in removed:
                _diff_pair(old[k], None, md, tex)
    else:
        am, at = _appendix(data, changes)
        md += am
        tex += at
    tex += [r"\end{document}"]
    return "\n".join(md).rstrip() + "\n", "\n".join(tex) + "\n"


def _diff_pair(old, new, md, tex):
    """The paper's version of a line, then this model's (either may be absent)."""
    kind = (new or old)["kind"]
    if kind == "text":
        for label, ln in (("Paper's model, text", old), ("This model, text", new)):
            md += [f"**{label}:** " + (ln["text"] if ln else "(none)"), ""]
            tex += [r"\textbf{" + label + r":} " + (_escape_text(ln["text"]) if ln
                                                   else "(none)"), ""]
        return
    for label, ln in (("Paper's model", old), ("This model", new)):
        md += [f"**{label}:**" + ("" if ln else " (none)"), ""]
        tex += [r"\textbf{" + label + r":}" + ("" if ln else " (none)"), ""]
        if ln:
            _eq(ln, md, tex, comment=False)


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
