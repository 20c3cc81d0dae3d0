#!/usr/bin/python3
"""The equations documents are the model the kernels compute.

    equations_proof.py KERNELS GENERATED_DIR [--mutate]

For every generated/usm_<model>_equations.json (the machine-readable form of
each typeset line, sympy srepr) this parses every line back and checks:
  * the typeset text: each line of usm_<model>_equations.tex is the LaTeX of
    the parsed expression (so the check below is about the printed document);
  * the numbers: with the definitions substituted in document order at random
    states, accelerations, times, parameters and stationary unknowns, the
    matrix M(x) and the vector f(x, t) equal the compiled `mass` and `rhs`
    kernels (KERNELS, tests/derive/equations_kernels.c: an independent route, the C
    that derive/ emitted and the compiler built), Euler's equations and the
    rotor law as printed equal the kernels' rows M x' - f, the residuals
    (3.5) equal `steady_residual`, and beta, the twist angle and the rotor
    speed (3.7) equal `steady_outputs`, the ansatz (3.1) equals `steady_state`;
    identities (3.3) hold.  The parameters include the imperfections (e, delta,
    s, nonzero at the points): the stationary lines of an imperfect model are
    stated at e = delta = s = 0 and so must equal kernels that ignore them.
    The lengths come from the compiled model (KERNELS MODEL --sizes), and the
    document must state as many states, parameters, stationary unknowns and
    residuals as the kernels have.
--mutate: flips one sign in a copy of a document (once in the LaTeX, once in
the srepr of a mass-matrix entry) and requires the check to fail each time.
"""
import json
import math
import os
import random
import re
import shutil
import subprocess
import sys
import tempfile

import sympy as sp

NS = {k: getattr(sp, k) for k in dir(sp) if not k.startswith("_")}
NS.update({"Integer": sp.Integer, "Rational": sp.Rational, "Float": sp.Float})
STEADY = ["beta", "rotor_speed", "F_n", "F_t", "v_c", "v_rel", "R_star", "Z", "twist"]
POINTS = 4


def parse(s):
    return eval(s, dict(NS))  # the srepr of the emitter's own output


def unbreak(body):
    if not body.startswith(r"\begin{aligned}"):
        return body
    body = body[len(r"\begin{aligned}"):-len(r"\end{aligned}")]
    return body.replace(r"\\ &\quad ", " ").replace(" &= ", " = ", 1)


def check_text(data, tex_path, fail):
    """Every parsed line prints as the LaTeX in the .tex document."""
    names = {sp.Symbol(n, real=True): tex for n, tex in data["symbols"].items()}
    with open(tex_path, encoding="utf-8") as fh:
        tex = fh.read()
    bodies = dict(re.findall(r"% line (\S+)\n\\begin\{equation\*\}(.*?)(?:\\tag\{[^}]*\})?"
                             r"\\end\{equation\*\}", tex))
    for ln in data["lines"]:
        if ln["kind"] in ("section", "text"):
            continue
        body = bodies.get(ln["key"])
        if body is None:
            fail(f"{ln['key']}: not in {os.path.basename(tex_path)}")
            continue
        # a display may state a relation other than '=' (F_n > 0)
        if unbreak(body) != f"{ln['lhs_tex']} {ln.get('rel', '=')} {ln['rhs_tex']}":
            fail(f"{ln['key']}: the .tex line differs from the data: {unbreak(body)[:120]}")
        if ln["kind"] == "display":
            continue
        printed = sp.latex(parse(ln["rhs"]), symbol_names=names, mat_delim="(",
                           inv_trig_style="full")
        if printed != ln["rhs_tex"]:
            fail(f"{ln['key']}: typeset {ln['rhs_tex'][:80]!r} is not its expression "
                 f"{printed[:80]!r}")


def evaluate(expr, env, fail, key):
    missing = [s.name for s in expr.free_symbols if s.name not in env]
    if missing:
        fail(f"{key}: undefined symbols {missing}")
        return None
    vals = {s: env[s.name] for s in expr.free_symbols}
    if isinstance(expr, sp.MatrixBase):
        return [[complex(sp.N(x.xreplace(vals), 30)) for x in expr.row(i)]
                for i in range(expr.rows)]
    return complex(sp.N(expr.xreplace(vals), 30))


def in_dependency_order(parsed, known, fail):
    """The lines, each after the definitions it uses (a line may use a symbol
    defined further down, e.g. the ansatz (3.1c) uses beta of (3.6))."""
    known, todo, out = set(known), list(parsed), []
    while todo:
        def uses(item):
            ln, lhs, rhs = item
            return rhs.free_symbols | (set() if ln["kind"] == "def" else lhs.free_symbols)
        ready = [item for item in todo if all(s.name in known for s in uses(item))]
        if not ready:
            fail("undefined symbols in " + ", ".join(item[0]["key"] for item in todo))
            return out
        for item in ready:
            todo.remove(item)
            out.append(item)
            if item[0]["kind"] == "def":
                d = item[0]["defines"]
                known.update([d] if isinstance(d, str) else d)
    return out


def close(a, b, scale):
    return abs(a - b) <= 1e-9 * (1.0 + scale)


def kernel_sizes(kernels, model):
    """nx, nu, the number of parameters and of stationary outputs of the
    compiled model (its usm_model fields and the generated constants)."""
    out = subprocess.run([kernels, model, "--sizes"], text=True, capture_output=True, check=True)
    return [int(v) for v in out.stdout.split()]


def check_numbers(data, kernels, rng, fail):
    model = data["model"]
    nx, nu, npar, nsteady = kernel_sizes(kernels, model)
    nq = len(data["accelerations"])
    # the document states every quantity the kernels compute: the same state,
    # parameters, stationary unknowns and residuals (none may be left out)
    for what, doc, want in (("states", len(data["states"]), nx),
                            ("parameters", len(data["parameters"]), npar),
                            ("stationary unknowns", len(data["unknowns"]), nu),
                            ("stationary residuals", len(data["residual"]), nu)):
        if doc != want:
            fail(f"the document has {doc} {what}, the kernels {want}")
            return
    if nsteady != len(STEADY):
        fail(f"the kernels have {nsteady} stationary outputs, the proof knows {len(STEADY)}")
        return
    lines = [ln for ln in data["lines"] if ln["kind"] in ("def", "eq", "identity")]
    parsed = [(ln, parse(ln["lhs"]), parse(ln["rhs"])) for ln in lines]
    points, inputs = [], []
    for _ in range(POINTS):
        x = [rng.uniform(-1, 1) for _ in range(nx)]
        if "theta" in data["states"]:
            x[data["states"].index("theta")] = rng.uniform(-0.2, 0.2)
        else:  # the tilt vector (a, b): |(a, b)| = sin(theta) < 1
            for c in ("a", "b"):
                x[data["states"].index(c)] = rng.uniform(-0.15, 0.15)
        p = [rng.uniform(0.5, 2.0) for _ in data["parameters"]]
        u = [rng.uniform(-0.2, 0.2), rng.uniform(0, 2 * math.pi)] + \
            [rng.uniform(-2, 2) for _ in range(nu - 2)]
        tt = rng.uniform(0, 1)
        acc = [rng.uniform(-1, 1) for _ in range(nq)]
        points.append((x, tt, p, u, acc))
        inputs.append(" ".join(repr(v) for v in x + [tt] + p + u))
    out = subprocess.run([kernels, model], input="\n".join(inputs) + "\n", text=True,
                         capture_output=True, check=True).stdout.strip().split("\n")
    for (x, tt, p, u, acc), row in zip(points, out):
        blocks = [[float(v) for v in b.split()] for b in row.split("|")]
        if [len(b) for b in blocks] != [nx * nx, nx, nu, nsteady, nx]:
            fail(f"kernel output of lengths {[len(b) for b in blocks]}")
            return
        M = [blocks[0][i * nx:(i + 1) * nx] for i in range(nx)]
        f, res, steady, xbar = blocks[1], blocks[2], blocks[3], blocks[4]
        env = dict(zip(data["states"], x))
        env.update(zip(data["accelerations"], acc))
        env.update(zip(data["parameters"], p))
        env.update(zip(data["unknowns"], u))
        env["t"] = tt
        xdot = x[nq:2 * nq] + acc + [0.0] * (nx - 2 * nq)
        for ln, lhs, rhs in in_dependency_order(parsed, set(env), fail):
            key = ln["key"]
            value = evaluate(rhs, env, fail, key)
            if value is None:
                continue
            if ln["kind"] == "def":
                if isinstance(ln["defines"], str):
                    env[ln["defines"]] = ([[v.real for v in r] for r in value]
                                          if isinstance(value, list) else value.real)
                else:
                    flat = [v for r in value for v in r] if isinstance(value, list) else [value]
                    for name, v in zip(ln["defines"], flat):
                        if abs(v.imag) > 1e-12 * (1 + abs(v.real)):
                            fail(f"{key}: {name} is not real")
                        env[name] = v.real
            elif ln["kind"] == "identity":
                left = evaluate(lhs, env, fail, key)
                if left is not None and not close(left, value, abs(value)):
                    fail(f"{key}: identity fails: {left} != {value}")
            else:  # an equation of motion as printed: lhs - rhs = rows of M x' - f
                left = evaluate(lhs, env, fail, key)
                if left is None:
                    continue
                lv = [r[0] for r in left] if isinstance(left, list) else [left]
                rv = [r[0] for r in value] if isinstance(value, list) else [value]
                for k, (a, b) in enumerate(zip(lv, rv)):
                    i = ln["row"] + k
                    terms = [M[i][j] * xdot[j] for j in range(nx)] + [f[i]]
                    want = sum(terms[:-1]) - f[i]
                    if not close((a - b).real, want, max(abs(v) for v in terms)):
                        fail(f"{key}: row {i + 1} of M x' - f: printed {(a - b).real!r}, "
                             f"kernels {want!r}")
        Md, fd = env.get(data["mass"]), env.get(data["rhs"])
        if Md is None or fd is None:
            fail("M or f not defined")
            return
        scale = max(abs(v) for r in M for v in r)
        for i in range(nx):
            for j in range(nx):
                if not close(Md[i][j], M[i][j], scale):
                    fail(f"m_{i + 1},{j + 1}: document {Md[i][j]!r}, kernel {M[i][j]!r}")
            if not close(fd[i][0], f[i], max(abs(v) for v in f)):
                fail(f"f_{i + 1}: document {fd[i][0]!r}, kernel {f[i]!r}")
        for k, name in enumerate(data["residual"]):
            if not close(env[name], res[k], max(abs(v) for v in res)):
                fail(f"residual {name}: document {env[name]!r}, kernel {res[k]!r}")
        for name, sym in data["steady"].items():
            want = steady[STEADY.index(name)]
            if not close(env[sym], want, abs(want)):
                fail(f"stationary {name}: document {env[sym]!r}, kernel {want!r}")
        for state, sym in data.get("ansatz", {}).items():
            want = xbar[data["states"].index(state)]
            if not close(env[sym], want, abs(want)):
                fail(f"ansatz (3.1) for {state}: document {env[sym]!r}, kernel {want!r}")


def check_model(kernels, gen, model, rng):
    errors = []

    def fail(msg):
        errors.append(msg)
    with open(os.path.join(gen, f"usm_{model}_equations.json"), encoding="utf-8") as fh:
        data = json.load(fh)
    check_text(data, os.path.join(gen, f"usm_{model}_equations.tex"), fail)
    check_numbers(data, kernels, rng, fail)
    return data, errors


def models_in(gen):
    return sorted(m.group(1) for m in (re.match(r"usm_(.+)_equations\.json$", f)
                                       for f in os.listdir(gen)) if m)


def mutate(kernels, gen, rng):
    """One sign flipped in a copy of the document: the check must fail."""
    ok = True
    for model in ("3dof", "4dof"):
        with tempfile.TemporaryDirectory() as tmp:
            for ext in ("json", "tex"):
                shutil.copy(os.path.join(gen, f"usm_{model}_equations.{ext}"), tmp)
            tex_path = os.path.join(tmp, f"usm_{model}_equations.tex")
            with open(tex_path, encoding="utf-8") as fh:
                tex = fh.read()
            # the LaTeX of the first right-hand side row f_i with a ' - ' in it
            m = re.search(r"(% line def:f_\d+\n\\begin\{equation\*\}[^\n]*?[^=]) - ", tex)
            if not m:
                print(f"FAIL {model}: no sign to flip in the LaTeX")
                return False
            with open(tex_path, "w", encoding="utf-8") as fh:
                fh.write(tex[:m.end(1)] + " + " + tex[m.end():])
            _, errors = check_model(kernels, tmp, model, rng)
            print(("ok   " if errors else "FAIL ") + f"{model}: LaTeX sign flipped in "
                  f"{m.group(1).split()[2]}: {len(errors)} error(s)"
                  + (f", first: {errors[0]}" if errors else ""))
            ok &= bool(errors)
            # the srepr of the first mass-matrix entry, negated (data and .tex agree)
            shutil.copy(os.path.join(gen, f"usm_{model}_equations.tex"), tmp)
            json_path = os.path.join(tmp, f"usm_{model}_equations.json")
            with open(json_path, encoding="utf-8") as fh:
                data = json.load(fh)
            ln = next(x for x in data["lines"] if x["key"].startswith("def:m_"))
            ln["rhs"] = f"Mul(Integer(-1), {ln['rhs']})"
            with open(json_path, "w", encoding="utf-8") as fh:
                json.dump(data, fh)
            errors = [e for e in check_model(kernels, tmp, model, rng)[1]
                      if "typeset" not in e]
            print(("ok   " if errors else "FAIL ") + f"{model}: {ln['key']} negated: "
                  f"{len(errors)} numeric error(s)" + (f", first: {errors[0]}" if errors else ""))
            ok &= bool(errors)
    return ok


def main():
    if len(sys.argv) < 3:
        print(__doc__, file=sys.stderr)
        return 2
    kernels, gen = sys.argv[1], sys.argv[2]
    rng = random.Random(20261123)
    if "--mutate" in sys.argv[3:]:
        return 0 if mutate(kernels, gen, rng) else 1
    bad = 0
    models = models_in(gen)
    if not models:
        print(f"FAIL: no usm_*_equations.json in {gen}")
        return 1
    for model in models:
        data, errors = check_model(kernels, gen, model, rng)
        n = sum(1 for ln in data["lines"] if ln["kind"] in ("def", "eq", "identity"))
        if errors:
            bad += 1
            print(f"FAIL {model}: {len(errors)} error(s)")
            for e in errors[:15]:
                print("     " + e)
        else:
            print(f"ok   {model}: {n} lines parsed; M, f, Euler's rows, residuals, beta, ansatz "
                  f"equal the kernels at {POINTS} random points")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
