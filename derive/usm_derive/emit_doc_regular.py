"""The equations document of a model in regular coordinates (issue 21,
assumption coordinates = tilt_vector; derive/usm_derive/model.py,
_derive_regular).

The Euler-angle documents (emit_doc.py, ModelDocument) state the rows in the
paper's named quantities; in the tilt-vector coordinates the rows are the same
physics in other variables, and this document states them as the derivation
made them: the kinematics of the coordinates, the contact quantities, then
M(x) and f(x, t) entry by entry through common subexpressions q_k, and the
stationary problem (the Euler angles' own) with its orbit mapped into the
coordinates.  Every line is sympy (srepr) as well as LaTeX, so
tests/equations_proof.py checks it against the compiled kernels like the
others.
"""
import sympy as sp

from .model import P, t


def regular_model_data(m, Doc, Names):
    e = m.equations
    names = Names()
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

    d.section("Kinematics: tilt-vector coordinates (issue 21)")
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
    d.define("e_z2", show(e["e_z2"]), lhs_tex=r"\vec e_{z_2}^{\,C}")
    d.define("C_tilt", show(e["C_tilt"]), lhs_tex=r"C_{\mathrm{tilt}}")
    d.define("omega_C", show(e["omega"]), lhs_tex=r"\vec\omega^{\,C}")
    d.define("r_c", show(e["r_c"]), lhs_tex=r"\vec r_c^{\,C}")
    for key, tex, tag in (("R_star", "R^*", None), ("Z", "Z", "2.3"),
                          ("v_c", r"v_c = (\vec\omega\times\vec r_c)\cdot\vec e_{x_1}", None)):
        d.define(names.add(key, tex.split(" ")[0]), show(e[key]), tag=tag, lhs_tex=tex)
    d.section("Rotor, contact and equations of motion (2.1)-(2.6)"
              + (", (5.1)-(5.3)" if e["slip"] else ", (4.6)"))
    d.define("xvec", sp.Matrix(m.states).T, lhs_tex=r"\mathbf{x}^T")
    d.text(r"The force laws of the Euler-angle document in these coordinates "
           r"($w_R = -\dot\varphi_R$ the rotor's speed in its driving direction), and the rows "
           r"$M(\mathbf{x})\,\dot{\mathbf{x}} = \mathbf{f}(\mathbf{x}, t)$: Euler's "
           r"equations (2.6) in frame $C$, $\dot{\vec L}^{C} + \Omega\,\vec e_Z\times\vec L = "
           r"\vec M_E - \vec M_R - \vec M_D + \vec M_C$ with the torques (2.8)-(2.11) (the "
           r"restoring moment $c_r\theta\,\vec e_{x_1}$ written $c_r (\vec e_Z\times"
           r"\vec e_{z_2})/\mathrm{sinc}\,\theta$)"
           + (r", preceded by the rotor's moment balance (2.2)" if e["slip"] else "")
           + r"; the positions and the twist angle $\tau$ ($\dot\tau = \omega_Z$) have rate "
           r"rows of their own.  All of them are stated through common subexpressions $q_k$.",
           "rows")
    n = len(m.states)
    contact = [(names.add("F_n", "F_n"), e["F_n"], "2.1"),
               (names.add("w_R", "w_R"), e["w_R"], "5.1" if e["slip"] else "2.4"),
               (names.add("F_t", "F_t"), e["F_t"], "5.1" if e["slip"] else "2.2")]
    exprs = [show(x) for _, x, _ in contact] + \
        [x.subs(to_om) for x in list(m.mass) + list(m.rhs)]
    syms = (names.add(f"q{k}", f"q_{{{k}}}") for k in range(100000))
    repl, reduced = sp.cse(exprs, symbols=syms, order="none")
    for s_, x in repl:
        d.define(s_, x)
    for (sym, _, tag), x in zip(contact, reduced):
        d.define(sym, x, tag=tag)
    reduced = reduced[len(contact):]
    d.define("Mass", sp.Matrix(n, n, reduced[:n * n]), lhs_tex=r"M(\mathbf{x})", key="def:M")
    d.define("fvec", sp.Matrix(reduced[n * n:]), lhs_tex=r"\mathbf{f}(\mathbf{x}, t)",
             key="def:f")
    d.display("display:eom", r"M(\mathbf{x})\,\dot{\mathbf{x}}", r"\mathbf{f}(\mathbf{x}, t)")

    d.section("Stationary solution (3.1)-(3.7)" + (", section 5" if e["slip"] else ""))
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
    res_keys = []
    for k, r in enumerate(m.residual):
        s = names.add(f"f_{k + 1}bar", f"f_{{{k + 1}}}")
        d.define(s, on(r), tag="3.5" if k < 2 or not e["slip"] else None)
        res_keys.append(s.name)
    d.define(beta, on(m.steady_outputs["beta"]), tag="3.6")
    tw = names.add("taubar", r"\bar\tau")
    d.define(tw, on(m.steady_outputs["twist"]))
    steady = {"beta": beta.name, "twist": tw.name}
    if not e["slip"]:
        rs = names.add("phidot_R_bar", r"\bar{\dot\varphi}_R")
        d.define(rs, on(m.steady_outputs["rotor_speed"]), tag="3.7")
        steady["rotor_speed"] = rs.name
    ansatz = {}
    sub_beta = {b: beta for b in beta_in}
    for i, st in enumerate(m.states):
        if st.name.endswith("dot"):
            continue
        key = st.name + "bar"
        if st.name == "tau":
            ansatz["tau"] = tw.name
            continue
        sym = names.add(key, r"\bar{" + names.tex.get(st, st.name) + "}")
        d.define(sym, on(m.steady_state[i].xreplace(sub_beta)), tag="3.1")
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
