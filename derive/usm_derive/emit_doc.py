"""The derived equations in the paper's notation, as Markdown and LaTeX.

Only small pieces are simplified (trigsimp of kinematic vectors, torques and
mass-matrix entries); the right-hand side f is stated through its definition
f = -E(q, qdot, 0, t) rather than expanded, so the document stays readable.
Equation numbers are the paper's where one exists.
"""
import sympy as sp

from .model import P, t

OMEGA_SYM = sp.Symbol("Omega", positive=True)

GREEK = {"phi": r"\varphi", "theta": r"\theta", "psi": r"\psi", "phi_R": r"\varphi_R"}
PARAM_TEX = {"m0": "m_0", "F0": "F_0", "I_xx": "I_{xx}", "I_yy": "I_{yy}", "I_zz": "I_{zz}",
             "mu0": r"\mu_0", "kappa": r"\kappa", "c_R": "c_R", "d_R": "d_R", "c_t": "c_t",
             "c_r": "c_r", "d_t": "d_t", "d_r": "d_r", "I_R": "I_R",
             "amp_imbalance": "e", "phase_error": r"\delta", "mode_split": "s"}


def _dot(tex, n):
    """\\dot{\\varphi}_R rather than \\dot{\\varphi_R}."""
    acc = r"\dot" if n == 1 else r"\ddot"
    if tex.endswith("_R"):
        return acc + "{" + tex[:-2] + "}_R"
    return acc + "{" + tex + "}"


def symbol_names():
    names = {}
    for base, tex in GREEK.items():
        names[sp.Symbol(base, real=True)] = tex
        names[sp.Symbol(base + "dot", real=True)] = _dot(tex, 1)
        names[sp.Symbol(base + "ddot", real=True)] = _dot(tex, 2)
    for name, sym in P.items():
        names[sym] = PARAM_TEX.get(name, name)
    names.update({sp.Symbol("tau", real=True): r"\tau", sp.Symbol("v_rel", real=True): r"v_{rel}",
                  sp.Symbol("F_t", real=True): "F_t", sp.Symbol("F_n", real=True): "F_n",
                  sp.Symbol("alpha", real=True): r"\alpha", sp.Symbol("beta", real=True): r"\beta",
                  sp.Symbol("phidot_R", real=True): r"\dot{\varphi}_R", OMEGA_SYM: r"\Omega",
                  sp.Symbol("wdot_R", real=True): r"\dot w_R", sp.Symbol("twist", real=True): r"\chi", sp.Symbol("R_star", real=True): "R^*"})
    return names


def _functions_to_symbols(e):
    """Euler-angle functions of t (used by the rotation matrices) as symbols."""
    subs = {}
    for name in GREEK:
        subs[sp.Function(name, real=True)(t)] = sp.Symbol(name, real=True)
    return e.subs(subs)


SMALL = 80  # operations: trigsimp only below this, its cost grows steeply


def _simplify_small(e):
    if e.has(sp.atan, sp.tanh) or sp.count_ops(e) > SMALL:
        return e
    return sp.trigsimp(e)


def prepare(e, simplify=True):
    e = _functions_to_symbols(sp.sympify(e)).subs(P["f"], OMEGA_SYM / (2 * sp.pi))
    if simplify:
        e = e.applyfunc(_simplify_small) if isinstance(e, sp.MatrixBase) else _simplify_small(e)
    return e


class Doc:
    """Collects numbered equations and renders them as Markdown or LaTeX."""

    def __init__(self):
        self.items = []   # ("section", title) | ("text", s) | ("eq", tag, lhs, rhs)
        self.names = symbol_names()

    def tex(self, e):
        return sp.latex(e, symbol_names=self.names, mat_delim="(")

    def section(self, title):
        self.items.append(("section", title))

    def text(self, s):
        self.items.append(("text", s))

    def eq(self, tag, lhs, rhs, simplify=True):
        rhs_tex = rhs if isinstance(rhs, str) else self.tex(prepare(rhs, simplify))
        self.items.append(("eq", tag, lhs, rhs_tex))

    def tags(self):
        return [it[1] for it in self.items if it[0] == "eq"]

    def markdown(self, title, preamble):
        out = [f"# {title}", ""] + preamble + ["", "Equations: " + ", ".join(
            f"({tag})" for tag in self.tags()), ""]
        for it in self.items:
            if it[0] == "section":
                out += [f"## {it[1]}", ""]
            elif it[0] == "text":
                out += [it[1], ""]
            else:
                out += ["$$", f"{it[2]} = {it[3]} \\tag{{{it[1]}}}", "$$", ""]
        return "\n".join(out).rstrip() + "\n"

    def latex(self, title, preamble):
        out = [r"\documentclass[10pt]{article}",
               r"\usepackage[a4paper,margin=18mm]{geometry}",
               r"\usepackage{amsmath}",
               r"\usepackage{breqn}",
               r"\allowdisplaybreaks",
               r"\setcounter{MaxMatrixCols}{12}",
               r"\begin{document}",
               r"\section*{" + _tex_escape(title) + "}"]
        out += [_tex_escape(p) for p in preamble]
        out += ["", r"\noindent Equations: "
                + _tex_escape(", ".join(f"({t})" for t in self.tags())) + "."]
        for it in self.items:
            if it[0] == "section":
                out += [r"\subsection*{" + _tex_escape(it[1]) + "}"]
            elif it[0] == "text":
                out += [_tex_escape(it[1]), ""]
            else:
                # breqn breaks long right-hand sides across lines by itself
                out += [f"\\begin{{dmath}}[number={{{it[1]}}}]", f"{it[2]} = {it[3]}",
                        r"\end{dmath}"]
        out += [r"\end{document}"]
        return "\n".join(out) + "\n"


def _tex_escape(s):
    return (s.replace("\\", r"\textbackslash{}").replace("_", r"\_").replace("&", r"\&")
            .replace("%", r"\%").replace("#", r"\#").replace("$", r"\$"))


def build(m, description):
    e = m.equations
    d = Doc()
    slip = m.assumptions["contact"] == "slip"
    d.section("Kinematics (Fig. 5, Table 1): z-x-z Euler angles")
    d.text("C_XY maps components in frame Y to components in frame X.")
    d.eq("K1", r"C_{NA}", e["C_NA"], simplify=False)
    d.eq("K2", r"C_{AB}", e["C_AB"], simplify=False)
    d.eq("K3", r"C_{BK}", e["C_BK"], simplify=False)
    d.eq("K4", r"\vec\omega^{K}", e["omega_K"])
    d.eq("K5", r"\vec\omega^{A}", e["omega_A"])
    d.eq("K6", r"\vec r_c^{\,A}", e["r_c_A"])
    d.eq("2.2a", r"R^*", e["R_star"])
    d.eq("2.3", r"Z", e["Z"])
    d.eq("K7", r"v_c = (\vec\omega\times\vec r_c)\cdot\vec e_{x_1}", e["v_c"])
    d.section("Rotor and contact (2.1)-(2.5)" + (", (5.1)-(5.2)" if slip else ""))
    d.eq("2.1", r"F_n", e["F_n"])
    if slip:
        d.eq("5.1", r"v_{rel}", e["v_rel"])
        d.eq("5.2", r"\mu(v_{rel})", e["friction"])
        d.eq("5.1b", r"F_t", r"\mu(v_{rel})\,F_n")
        d.eq("2.2", r"0", e["rotor_balance"])
        d.text("with w_R = -phidot_R, the rotor's speed in its driving direction.")
    else:
        d.eq("2.4", r"w_R = -\dot\varphi_R", e["w_R"])
        d.eq("2.2", r"F_t", e["F_t_generic"])
    d.section("Torques on the stator in frame A (2.7)-(2.11)")
    d.eq("2.8", r"\vec M_E^{A}", e["M_E_A"])
    d.eq("2.9", r"\vec M_R^{A}", e["M_R_A"])
    if e["extra_names"]:
        d.eq("T1", r"\dot\tau", e["extra_rates"][0])
    d.eq("2.10", r"\vec M_D^{A}", e["M_D_A"])
    d.eq("2.11", r"\vec M_C^{A} = \vec r_c\times\vec F_c", e["M_C_A"])
    d.eq("L1", r"\vec L^{A} = I^{A}\vec\omega^{A}", e["L_A"])
    d.section("Euler's equations (2.6), projected on frame A")
    d.text("E = dL/dt + omega_A x L - (M_E - M_R - M_D + M_C) = 0 in frame A (frame A turns "
           "with phidot about Z); these rows are C_AK times (2.6). They are linear in the "
           "accelerations: M_q qddot = f_q with M_q = dE/dqddot and f_q = -E at qddot = 0.")
    M_q = e["M_q"]
    if slip:
        # written with v_rel (5.1) rather than its expansion
        M_q = M_q.subs(e["v_rel"], e["v_sym"])
    M_q = prepare(M_q)
    n = M_q.shape[0]
    names = [s.name for s in e["qdd"]]
    for i in range(n):
        for j in range(n):
            if M_q[i, j] != 0:
                d.eq(f"M{i + 1}{j + 1}", f"m_{{{i + 1}{j + 1}}}", M_q[i, j], simplify=False)
    d.text("Acceleration order: " + ", ".join(names) + ". First-order form (4.6)/(5.3): "
           "x = [q, qdot" + (", tau" if e["extra_names"] else "") + "], "
           "M(x) = diag(1, M_q" + (", 1" if e["extra_names"] else "") + "), "
           "f = [qdot, f_q" + (", omega_Z" if e["extra_names"] else "") + "].")
    d.section("Stationary solution (3.1)-(3.6)")
    d.text("chi is the twist angle on the stationary solution, from the twisting balance "
           "(the Z row of Euler's equations); beta follows from phi + psi cos(theta) = chi.")
    ansatz_tags = {"phi": "3.1a", "theta": "3.1b", "psi": "3.1c", "phi_R": "S1"}
    for name, expr in e["ansatz"].items():
        d.eq(ansatz_tags[name], GREEK[name], expr)
    short = {}
    if slip:
        d.eq("S2", r"v_{rel}", e["v_rel_bar"])
        short = {e["v_rel_bar"]: e["v_sym"]}
    for i, r in enumerate(e["residual"]):
        label = ["3.5a", "3.5b", "5.4"][i] if not slip else ["5.4", "3.5a", "3.5b"][i]
        d.eq(label, "0", r.subs(short), simplify=False)
    d.eq("3.6", r"\chi", e["twist_display"])
    d.eq("3.6b", r"\beta", e["beta_generic"])
    if not slip:
        d.eq("3.7", r"\dot\varphi_R", e["rotor_speed_bar"])
    preamble = [f"Model {m.name}: {description}.",
                "Assumptions: " + ", ".join(f"{k}={v}" for k, v in m.assumptions.items()) + ".",
                "Generated by derive/generate.py from the same derivation as the C kernels; "
                "Omega = 2 pi f. Equation numbers in parentheses are the paper's where it has "
                "one (K, L, M, S, T mark equations the paper does not number)."]
    return d, preamble


def model_docs(m, description):
    d, preamble = build(m, description)
    title = f"Equations of the {m.name} model"
    return ({f"usm_{m.name}_equations.md": d.markdown(title, preamble),
             f"usm_{m.name}_equations.tex": d.latex(title, preamble)}, d.tags())


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
            "   (also generated/usm_<model>_equations.{md,tex}); lines end at NULL. */\n"
            "typedef struct usm_equation_doc {\n    const char *model;\n"
            "    const char *format; /* \"markdown\" or \"latex\" */\n"
            "    const char *const *lines;\n} usm_equation_doc;\n"
            f"#define USM_NEQUATION_DOCS {ndocs}\n"
            "extern const usm_equation_doc usm_equation_docs[USM_NEQUATION_DOCS];\n"
            '\n#ifdef __cplusplus\n}\n#endif\n\n#endif /* USM_EQUATIONS_H */\n')
