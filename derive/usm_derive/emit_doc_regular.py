"""The equations document of a model in regular coordinates (assumption coordinates = tilt_vector; derive/usm_derive/model.py,
_derive_regular).

The Euler-angle documents (emit_doc.py, ModelDocument) state the rows in the
paper's named quantities; in the tilt-vector coordinates the rows are the same
physics in other variables, and this document states them as the derivation
made them: the kinematics of the coordinates, the contact quantities, then
M(x) and f(x, t) entry by entry through common subexpressions q_k, and the
stationary problem (the Euler angles' own) with its orbit mapped into the
coordinates.  Every line is sympy (srepr) as well as LaTeX, so
tests/derive/equations_proof.py checks it against the compiled kernels like the
others.
"""
import sympy as sp

from .model import P


# A line longer than this many LaTeX characters has its long pieces named
# (split_long): a product or a function argument cannot be broken across lines.
LONG = 160


def split_long(x, new_symbol, define, latex_of):
    """x with every long non-atomic piece (a term's factor, a function's
    argument) replaced by a new symbol defined before it, recursively, so that
    no line needs more than about LONG characters of LaTeX."""
    if x.is_Atom or len(latex_of(x)) <= LONG:
        return x
    args = []
    for a in x.args:
        a = split_long(a, new_symbol, define, latex_of)
        if not a.is_Atom and len(latex_of(a)) > LONG // 3 and not a.is_Number:
            sym = new_symbol()
            define(sym, a)
            a = sym
        args.append(a)
    return x.func(*args)


def regular_model_data(m, Doc, Names, latex):
    e = m.equations
    names = Names()
    # chi is the spin angle here; the integrated twist angle, which the
    # Euler-angle documents call chi after the paper, is tau
    for nm, tex in (("tau", r"\tau"), ("taudot", r"\dot\tau"), ("tauddot", r"\ddot\tau")):
        names.tex[sp.Symbol(nm, real=True)] = tex
    for nm, tex in (("a", "a"), ("b", "b"), ("chi", r"\chi")):
        names.add(nm, tex)
        names.add(nm + "dot", r"\dot{" + tex + "}")
        names.add(nm + "ddot", r"\ddot{" + tex + "}")
    d = Doc(names)
    plain = e["plain"]
    Om = names.add("Omega", r"\Omega")
    to_om = {P["f"]: Om / (2 * sp.pi)}

    def show(x):
        return sp.sympify(plain(x)).subs(to_om)

    d.section("Kinematics: tilt-vector coordinates")
    d.text(r"Frames: $N$ inertial, $C$ turned by $\Omega t$ about $Z$.  The stator axis "
           r"$\vec e_{z_2}$ has the components $(a, b, \sqrt{1 - a^2 - b^2})$ in $C$ "
           r"($a + i b = \sin\theta\, e^{i(\varphi - \Omega t - \pi/2)}$ in the paper's Euler "
           r"angles), and $\chi = \varphi + \psi$ is the spin angle: the orientation is "
           r"$C_{\mathrm{tilt}}(a, b)$ followed by a turn $\chi$ about $Z$, with "
           r"$C_{\mathrm{tilt}} = I + K + K^2/(1 + \cos\theta)$, $K = [\vec e_Z\times"
           r"\vec e_{z_2}]_\times$ (no division by $\sin\theta$).  Vectors are given by their "
           r"components in frame $C$, $\Omega = 2\pi f$.  The contact point stays singular at "
           r"$\theta = 0$: $\vec e_{x_1}$ is the unit vector of $\vec e_Z\times\vec e_{z_2}$ "
           r"(docs/coordinates.md).", "frames")
    d.define(Om, 2 * sp.pi * P["f"])
    d.define("e_z2", show(e["e_z2"]), lhs_tex=r"\vec e_{z_2}")
    d.define(names.add("Z", "Z"), show(e["Z"]), tag="2.3")
    d.text(r"The angular velocity is $\vec\omega = \Omega(\vec e_Z - \vec e_{z_2}) + "
           r"\mathrm{vee}(\dot C_{\mathrm{tilt}} C_{\mathrm{tilt}}^T) + \dot\chi\,\vec e_{z_2}$ "
           r"(components in $C$), the contact point $\vec r_c = R\,\vec e_{y_2} + H\,\vec e_{z_2}$ "
           r"with $\vec e_{y_2} = \vec e_{z_2}\times\vec e_{x_1}$, $R^* = \vec r_c\cdot"
           r"\vec e_{y_1}$, $v_c = (\vec\omega\times\vec r_c)\cdot\vec e_{x_1}$; the force laws "
           r"(2.1)-(2.5)" + (r", (5.1), (5.2)" if e["slip"] else "") + r" are the Euler-angle "
           r"document's ($w_R = -\dot\varphi_R$ the rotor's speed in its driving direction), "
           r"written out in these coordinates inside $M$ and $\mathbf{f}$ below.", "kinematics")
    d.section("Equations of motion $M(\\mathbf{x})\\,\\dot{\\mathbf{x}} = "
              "\\mathbf{f}(\\mathbf{x}, t)$" + (" (5.3)" if e["slip"] else " (4.6)"))
    d.define("xvec", sp.Matrix(m.states).T, lhs_tex=r"\mathbf{x}^T")
    d.text(r"The rows are Euler's equations (2.6) in frame $C$, $\dot{\vec L}^{C} + \Omega\,"
           r"\vec e_Z\times\vec L = \vec M_E - \vec M_R - \vec M_D + \vec M_C$ with the torques "
           r"(2.8)-(2.11) (the restoring moment $c_r\theta\,\vec e_{x_1}$ written $c_r (\vec e_Z"
           r"\times\vec e_{z_2})/\mathrm{sinc}\,\theta$)"
           + (r", preceded by the rotor's moment balance (2.2)" if e["slip"] else "")
           + r"; the positions and the twist angle $\tau$ ($\dot\tau = \omega_Z$) have rate "
           r"rows of their own.  They are stated through common subexpressions $q_k$.", "rows")
    n = len(m.states)
    exprs = [x.subs(to_om) for x in list(m.mass) + list(m.rhs)]
    syms = (names.add(f"q{k}", f"q_{{{k}}}") for k in range(100000))
    repl, reduced = sp.cse(exprs, symbols=syms, order="none")
    extra = (names.add(f"r{k}", f"r_{{{k}}}") for k in range(100000))

    def short(x):
        return split_long(x, lambda: next(extra), d.define, lambda y: latex(y, names.tex))
    for s_, x in repl:
        d.define(s_, short(x))
    reduced = [short(x) for x in reduced]
    Mred, fred = reduced[:n * n], reduced[n * n:]
    msyms = sp.zeros(n, n)
    for i in range(n):
        for j in range(n):
            x = Mred[i * n + j]
            if x.is_Number:
                msyms[i, j] = x
            else:
                sym = names.add(f"m_{i + 1}_{j + 1}", f"m_{{{i + 1},{j + 1}}}")
                d.define(sym, x)
                msyms[i, j] = sym
    fsyms = []
    for i, x in enumerate(fred):
        if x.is_Atom:
            fsyms.append(x)
        else:
            sym = names.add(f"f_{i + 1}", f"f_{{{i + 1}}}")
            d.define(sym, x)
            fsyms.append(sym)
    d.define("Mass", msyms, lhs_tex=r"M(\mathbf{x})", key="def:M")
    d.define("fvec", sp.Matrix(fsyms), lhs_tex=r"\mathbf{f}(\mathbf{x}, t)", key="def:f")
    d.display("display:eom", r"M(\mathbf{x})\,\dot{\mathbf{x}}", r"\mathbf{f}(\mathbf{x}, t)")

    d.section("Stationary solution (3.1)-(3.5)" + (", section 5" if e["slip"] else ", (3.7)"))
    d.text(r"The stationary problem is the Euler angles' (document of model "
           + e["euler_name"].replace("_", r"\_")
           + r"): the same unknowns, residuals, $\beta$ and twist angle, here written out; "
           r"its orbit (3.1) in these coordinates is constant in $a$, $b$ (the stator axis "
           r"turns with $\Omega t$) and the spin angle grows at "
           r"$\Omega(1 - 1/\cos\bar\theta)$.", "steady")
    bars = {}
    for u, nm in zip(m.unknowns, m.unknown_names):
        tex = {"theta": r"\bar\theta", "alpha": r"\alpha", "phidot_R": r"\bar{\dot\varphi}_R"}[nm]
        bars[u] = names.add({"theta": "thetabar", "alpha": "alpha",
                             "phidot_R": "phidotbar_R"}[nm], tex)
    beta_in = [x for x in m.steady_state.free_symbols if x.name == "beta"]
    beta = names.add("beta", r"\beta")

    def on(x):
        return sp.sympify(x).xreplace(bars).subs(to_om)
    # everything on the orbit through common subexpressions g_k
    items = [("res", k, r) for k, r in enumerate(m.residual)]
    items += [("beta", 0, m.steady_outputs["beta"]), ("twist", 0, m.steady_outputs["twist"])]
    if not e["slip"]:
        items.append(("speed", 0, m.steady_outputs["rotor_speed"]))
    sub_beta = {b: beta for b in beta_in}
    pos = [(i, st) for i, st in enumerate(m.states)
           if not st.name.endswith("dot") and st.name != "tau"]
    items += [("ansatz", i, m.steady_state[i].xreplace(sub_beta)) for i, _ in pos]
    gsyms = (names.add(f"g{k}", f"g_{{{k}}}") for k in range(100000))
    grepl, gred = sp.cse([on(x) for _, _, x in items], symbols=gsyms, order="none")
    res_keys = []
    for s_, x in grepl:
        d.define(s_, short(x))
    gred = [short(x) for x in gred]
    red = {(kind, k): x for (kind, k, _), x in zip(items, gred)}
    for k in range(len(m.residual)):
        sym = names.add(f"f_{k + 1}bar", f"f_{{{k + 1}}}")
        d.define(sym, red[("res", k)], tag="3.5" if k < 2 or not e["slip"] else None)
        res_keys.append(sym.name)
    # beta is a convention under the integrated twist law (psi is cyclic): no (3.6)
    d.define(beta, red[("beta", 0)])
    tw = names.add("taubar", r"\bar\tau")
    d.define(tw, red[("twist", 0)])
    steady = {"beta": beta.name, "twist": tw.name}
    if not e["slip"]:
        rs = names.add("phidot_R_bar", r"\bar{\dot\varphi}_R")
        d.define(rs, red[("speed", 0)], tag="3.7")
        steady["rotor_speed"] = rs.name
    ansatz = {"tau": tw.name} if "tau" in [st.name for st in m.states] else {}
    for i, st in pos:
        sym = names.add(st.name + "bar", r"\bar{" + names.tex.get(st, st.name) + "}")
        d.define(sym, red[("ansatz", i)], tag="3.1")
        ansatz[st.name] = sym.name
    return {
        "model": m.name,
        "assumptions": m.assumptions,
        "lines": d.lines,
        "symbols": names.table(),
        "states": [s.name for s in m.states],
        "accelerations": [s.name + "ddot" for s in m.states[:len(e["coords"])]],
        "unknowns": [bars[u].name for u in m.unknowns],
        "parameters": [s.name for s in P.values()],
        "mass": "Mass", "rhs": "fvec", "residual": res_keys, "steady": steady,
        "ansatz": ansatz,
    }
