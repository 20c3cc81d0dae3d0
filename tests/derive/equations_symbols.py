#!/usr/bin/python3
"""Every symbol of an equations document is defined, every parameter is in its table.

    equations_symbols.py USM GENERATED_DIR [--mutate]

For every generated/usm_<model>_equations.tex (the document as typeset) this reads
  * the parameter table and the notation table (a symbol in the first column is
    defined from there on),
  * every display equation in document order: a definition ("% line def:...")
    defines the first symbol of its left-hand side (all of it for a column of
    symbols), a line marked "% defines S" defines S;
(a comment "% defines S" just before "% line KEY"), and requires each symbol of
each equation to be defined at or before that line, under the conventions the document states in its notation section: a dot (time
derivative), a bar (value on the orbit), a superscript (0) (value at zero
accelerations) and Delta (deviation) apply to a defined symbol; X_{x_1} (or
X_{E,x_1}) is a component of a defined vector \\vec X (\\vec X_E); X_{5,7} or
X_{n_q + 1} an entry of a defined bold or calligraphic matrix or vector X.
The parameter table must list every parameter the runtime knows (`usm steady
--json`, key "parameters": names and default values, an independent source)
with a unit and the same default value (8 significant digits printed).
--mutate: removes the definition of R^* and the table row of c_R from a copy of
the 3dof document and requires both to be reported.
"""
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

ACCENTS = {"dot", "ddot", "bar", "vec", "hat", "tilde", "mathbf", "mathcal", "mathsf"}
GREEK = {"alpha", "beta", "gamma", "delta", "epsilon", "varepsilon", "zeta", "eta", "theta",
         "vartheta", "iota", "kappa", "lambda", "mu", "nu", "xi", "pi", "rho", "sigma", "tau",
         "upsilon", "phi", "varphi", "chi", "psi", "omega", "Gamma", "Theta", "Lambda", "Xi",
         "Pi", "Sigma", "Phi", "Psi", "Omega"}
# \Delta is the deviation operator here, not a symbol
WORDS = {"mathrm", "operatorname", "text", "begin", "end"}
DECOR = {"*": "*", "(0)": "(0)"}          # superscripts that are part of a name
DROP = {"A", "K", r"\mathsfT", "T"}      # frame of the components, transpose (as _label)


def _group(s, i):
    """(content, index after) of the {...} group at s[i] == '{'."""
    depth, j = 0, i
    while j < len(s):
        if s[j] == "{":
            depth += 1
        elif s[j] == "}":
            depth -= 1
            if depth == 0:
                return s[i + 1:j], j + 1
        elif s[j] == "\\":
            j += 1
        j += 1
    raise ValueError(f"unbalanced braces in {s[i:i + 60]!r}")


def _arg(s, i):
    """The argument of an accent, _ or ^ at s[i]: (text, index after)."""
    while i < len(s) and s[i] == " ":
        i += 1
    if i >= len(s):
        return "", i
    if s[i] == "{":
        return _group(s, i)
    if s[i] == "\\":
        m = re.match(r"\\([A-Za-z]+|.)", s[i:])
        return m.group(0), i + m.end()
    return s[i], i + 1


def _label(x):
    return re.sub(r"\\[,;! ]|\s|[{}]", "", x)


def atoms(s):
    """The symbols of a LaTeX expression: (accents, base, subscript, decoration)."""
    out, i, last = [], 0, None
    while i < len(s):
        c = s[i]
        if c == "\\":
            m = re.match(r"\\([A-Za-z]+|.)", s[i:])
            name, i = m.group(1), i + m.end()
            if name in WORDS:
                if i < len(s) and s[i] == "{":
                    _, i = _group(s, i)
                last = None
            elif name in ACCENTS:
                arg, i = _arg(s, i)
                inner = atoms(arg)
                if len(inner) == 1:
                    a = inner[0]
                    last = ((name,) + a[0], a[1], a[2], a[3])
                    out.append(last)
                else:          # \mathbf{1}: a constant; or several symbols
                    out.extend(inner)
                    last = None
            elif name in GREEK:
                last = ((), name, "", "")
                out.append(last)
            else:              # a function, operator or spacing
                last = None
            continue
        if c == "{":
            arg, i = _group(s, i)
            inner = atoms(arg)
            if len(inner) == 1 and i < len(s) and s[i] in "_^" and \
                    re.fullmatch(r"\s*(\\[a-z]+\s*)*(\{.*\}|\\?[A-Za-z]+)?\s*(_.*|\^.*)?",
                                 arg) is not None:
                last = inner[0]
                out.append(last)
            else:
                out.extend(inner)
                last = None
            continue
        if c in "_^":
            arg, i = _arg(s, i + 1)
            if last is None:
                if c == "^" and _label(arg) not in DROP:
                    out.extend(atoms(arg))
                continue       # a subscript of a bracket: a label
            acc, base, sub, dec = last
            if c == "_" and not sub:
                new = (acc, base, _label(arg), dec)
            elif c == "^" and _label(arg) in DECOR:
                new = (acc, base, sub, DECOR[_label(arg)])
            elif c == "^" and _label(arg) in DROP:
                new = last
            else:              # a power
                out.extend(atoms(arg))
                continue
            # replace the last occurrence (the atom being decorated)
            for k in range(len(out) - 1, -1, -1):
                if out[k] == last:
                    out[k] = new
                    break
            last = new
            continue
        if c.isalpha():
            last = ((), c, "", "")
            out.append(last)
            i += 1
            continue
        last = None
        i += 1
    return out


def show(a):
    acc, base, sub, dec = a
    s = base + (f"_{{{sub}}}" if sub else "") + (f"^{dec}" if dec else "")
    for x in reversed(acc):
        s = f"{x}({s})"
    return s


INDEX = re.compile(r"(\d+|k|l|n_q\+\d+|2n_q)(,(\d+|k|l|n_q\+\d+|2n_q))*")


def is_defined(a, known):
    if a in known:
        return True
    acc, base, sub, dec = a
    if dec == "(0)" and is_defined((acc, base, sub, ""), known):
        return True
    if acc and acc[0] in ("dot", "ddot", "bar") and is_defined((acc[1:], base, sub, dec), known):
        return True
    if sub:
        m = re.fullmatch(r"(?:(.*),)?([xyz]_?[12]?)", sub)
        if m and ("vec",) + acc == ("vec",) + acc and \
                is_defined((("vec",) + acc, base, m.group(1) or "", ""), known):
            return True
        if INDEX.fullmatch(sub) and acc and acc[-1] in ("mathbf", "mathcal") and \
                is_defined((acc, base, "", ""), known):
            return True
    return False


def read_doc(tex):
    """[(kind, key, atoms defined, atoms used)] in document order, and the
    parameter rows [(cells)]."""
    items, params = [], []
    lines = tex.split("\n")
    table, pending = None, None
    k = 0
    while k < len(lines):
        ln = lines[k]
        if ln.startswith("% table "):
            table = ln.split()[2]
        elif ln.startswith(r"\end{longtable}"):
            table = None
        elif table and ln.endswith(r"\\") and not ln.startswith(r"\textbf"):
            cells = [c.strip() for c in ln[:-2].split(" & ")]
            if table in ("parameters", "notation"):
                first = cells[0].strip("$")
                items.append(("table", f"{table}: {first}", atoms(first), []))
            if table == "parameters":
                params.append(cells)
        elif ln.startswith("% defines "):
            pending = ln[len("% defines "):]
        elif ln.startswith("% line "):
            key = ln.split()[2]
            defines, pending = pending, None
            k += 1
            m = re.match(r"\\begin\{equation\*\}(.*?)(?:\\tag\{[^}]*\})?\\end\{equation\*\}$",
                         lines[k])
            if not m:
                raise ValueError(f"{key}: no equation after its comment")
            body = m.group(1).replace(r"\begin{aligned}", "").replace(r"\end{aligned}", "") \
                .replace("&", "").replace(r"\\", " ")
            used = atoms(body)
            if defines is not None:
                new = atoms(defines)
            elif key.startswith("def:"):
                lhs = body.split(" = ")[0]
                new = atoms(lhs) if lhs.lstrip().startswith(r"\left(\begin{matrix}") \
                    else atoms(lhs)[:1]
            else:
                new = []
            items.append(("eq", key, new, used))
        k += 1
    return items, params


def check_symbols(items):
    known, errors = set(), []
    for kind, key, new, used in items:
        known.update(new)
        for a in used:
            if not is_defined(a, known):
                errors.append(f"{key}: {show(a)} is not defined before this line")
    return errors


def _value(cell):
    c = cell.strip().strip("$").strip()
    m = re.fullmatch(r"(-?[\d.]+)(?:\s*\\cdot\s*10\^\{(-?\d+)\})?", c)
    if not m:
        return None
    return float(m.group(1)) * (10.0 ** int(m.group(2)) if m.group(2) else 1.0)


def check_parameters(params, runtime):
    """Every runtime parameter: a row with its name, a unit, the runtime's default."""
    errors = []
    rows = {}
    for cells in params:
        m = re.search(r"\\texttt\{([^}]*)\}", cells[1]) if len(cells) > 1 else None
        if m:
            rows[m.group(1).replace(r"\_", "_")] = cells
    for name, value in runtime.items():
        cells = rows.get(name)
        if cells is None:
            errors.append(f"parameter {name}: not in the parameter table")
            continue
        if len(cells) < 6 or not cells[3].strip():
            errors.append(f"parameter {name}: no unit")
            continue
        shown = cells[4].strip().strip("$").strip()
        if shown.startswith("="):
            sym = shown[1:].strip()
            other = [n for n, c in rows.items() if c[0].strip("$") == sym]
            if not other or runtime.get(other[0]) != value:
                errors.append(f"parameter {name}: shown {shown}, runtime default {value!r}")
            continue
        v = _value(shown)
        # 8 significant digits printed
        if v is None or abs(v - value) > 1e-7 * abs(value):
            errors.append(f"parameter {name}: table {shown!r}, runtime default {value!r}")
    return errors


def check_file(path, runtime):
    with open(path, encoding="utf-8") as fh:
        tex = fh.read()
    items, params = read_doc(tex)
    return check_symbols(items) + check_parameters(params, runtime), items


def runtime_parameters(usm):
    out = subprocess.run([usm, "steady", "--json"], capture_output=True, text=True)
    return json.loads(out.stdout)["parameters"]


def mutate(usm, gen, runtime):
    ok = True
    src = os.path.join(gen, "usm_3dof_equations.tex")
    with open(src, encoding="utf-8") as fh:
        tex = fh.read()
    with tempfile.TemporaryDirectory() as tmp:
        cut = re.sub(r"% line def:R_star\n\\begin\{equation\*\}[^\n]*\n", "", tex, count=1)
        cut2 = re.sub(r"\n\$c_R\$ & [^\n]*", "", tex, count=1)
        for what, text, want in (("definition of R^* removed", cut, "R_{*}"),
                                 ("table row of c_R removed", cut2, "c_R")):
            if text == tex:
                print(f"FAIL mutate: could not apply: {what}")
                ok = False
                continue
            path = os.path.join(tmp, "usm_3dof_equations.tex")
            with open(path, "w", encoding="utf-8") as fh:
                fh.write(text)
            errors, _ = check_file(path, runtime)
            hit = [e for e in errors if want.replace("_{*}", "") in e]
            print(("ok   " if hit else "FAIL ") + f"mutate: {what}: {len(errors)} error(s)"
                  + (f", first: {hit[0]}" if hit else ""))
            ok &= bool(hit)
    return ok


def main():
    if len(sys.argv) < 3:
        print(__doc__, file=sys.stderr)
        return 2
    usm, gen = sys.argv[1], sys.argv[2]
    runtime = runtime_parameters(usm)
    if "--mutate" in sys.argv[3:]:
        return 0 if mutate(usm, gen, runtime) else 1
    docs = sorted(f for f in os.listdir(gen) if re.fullmatch(r"usm_.+_equations\.tex", f))
    if not docs:
        print(f"FAIL: no equations documents in {gen}")
        return 1
    bad = 0
    for f in docs:
        errors, items = check_file(os.path.join(gen, f), runtime)
        neq = sum(1 for it in items if it[0] == "eq")
        nsym = len({a for it in items for a in it[3]})
        if errors:
            bad += 1
            print(f"FAIL {f}: {len(errors)} error(s)")
            for e in errors[:20]:
                print("     " + e)
        else:
            print(f"ok   {f}: {neq} equations, {nsym} distinct symbols, each defined before "
                  f"use; {len(runtime)} parameters in the table with unit and default")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
