"""C emission: common subexpressions eliminated, const temporaries, op counts."""
import sympy as sp
from sympy.printing.c import C99CodePrinter

from .model import PARAMETERS, P

PI_LITERAL = "3.141592653589793238462643383279502884"


class KernelPrinter(C99CodePrinter):
    """C99 printer without pow() for small integer powers and without M_PI."""

    def __init__(self, names):
        super().__init__()
        self._names = names

    def _print_Symbol(self, expr):
        if expr in self._names:
            return self._names[expr]
        return super()._print_Symbol(expr)

    def _print_Pi(self, expr):
        return PI_LITERAL

    def _print_Pow(self, expr):
        base, e = expr.base, expr.exp
        if e.is_Integer and 2 <= abs(int(e)) <= 4:
            b = self.parenthesize(base, sp.printing.precedence.PRECEDENCE["Mul"] + 1)
            # parenthesised: the product must bind as tightly as the power it replaces
            prod = "(" + "*".join([b] * abs(int(e))) + ")"
            return prod if e > 0 else f"1.0/{prod}"
        if e == -1:
            return f"1.0/{self.parenthesize(base, sp.printing.precedence.PRECEDENCE['Mul'] + 1)}"
        if e == sp.Rational(1, 2):
            return f"sqrt({self._print(base)})"
        if e == sp.Rational(-1, 2):
            return f"1.0/sqrt({self._print(base)})"
        return super()._print_Pow(expr)

    def _print_Rational(self, expr):
        return f"{float(expr.p)!r}/{float(expr.q)!r}".replace("e+", "e")

    def _print_Integer(self, expr):
        return f"{int(expr)}.0" if abs(int(expr)) < 10**15 else super()._print_Integer(expr)


def _drop_unused(repl, reduced):
    """cse can leave a temporary that no output needs (its uses cancelled)."""
    needed = set().union(*(sp.sympify(e).free_symbols for e in reduced))
    kept = []
    for sym, e in reversed(repl):
        if sym in needed:
            kept.append((sym, e))
            needed |= e.free_symbols
    return kept[::-1]


def _square_of_trig(f):
    """('sin' or 'cos', argument) if f is sin(a)**2 or cos(a)**2, else None."""
    if f.is_Pow and f.exp == 2 and isinstance(f.base, (sp.sin, sp.cos)):
        return ("sin" if isinstance(f.base, sp.sin) else "cos", f.base.args[0])
    return None


def _pythagoras_add(add):
    """In one sum: c r sin^2(a) + c r cos^2(a) -> c r, and
    c r sin^2(a) - c r -> -c r cos^2(a) (likewise with sin and cos swapped)."""
    terms = list(add.args)
    squares = {}                     # (kind, a, c, rest) -> index of the term
    plain = {}                       # term -> index, for c r without a square
    for i, term in enumerate(terms):
        c, factors = term.as_coeff_mul()
        plain.setdefault(term, i)
        for k, f in enumerate(factors):
            sq = _square_of_trig(f)
            if sq is not None:
                squares.setdefault((sq[0], sq[1], c, factors[:k] + factors[k + 1:]), i)
    used, extra = set(), []
    other = {"sin": "cos", "cos": "sin"}
    for (kind, arg, c, rest), i in squares.items():
        if i in used:
            continue
        j = squares.get((other[kind], arg, c, rest))
        if j is not None and j not in used and j != i:
            used |= {i, j}
            extra.append(c * sp.Mul(*rest))
            continue
        base = c * sp.Mul(*rest)
        j = plain.get(-base)
        if j is not None and j not in used and j != i:
            used |= {i, j}
            fn = sp.cos if kind == "sin" else sp.sin
            extra.append(-c * sp.Mul(*rest) * fn(arg) ** 2)
    if not used:
        return add
    return sp.Add(*([t for i, t in enumerate(terms) if i not in used] + extra))


def pythagoras(expr, memo=None):
    """sin^2 + cos^2 = 1 applied wherever a sum shows it, bottom up: cheap
    (one pass, no trigsimp), so it runs on every emitted expression."""
    memo = {} if memo is None else memo
    if expr in memo:
        return memo[expr]
    if not expr.args or expr.is_Atom:
        return expr
    args = [pythagoras(a, memo) for a in expr.args]
    new = expr.func(*args) if any(a is not b for a, b in zip(args, expr.args)) else expr
    if new.is_Add:
        new = _pythagoras_add(new)
    memo[expr] = new
    return new


def _count_node(a):
    """sympy's count_ops (sympy/core/function.py, 1.11) for one node of its
    work list: (the operations it counts there, the nodes it goes on with)."""
    from sympy.core.function import _coeff_isneg
    from sympy.simplify.radsimp import fraction
    ops = 0
    if a.is_Rational:
        if a is not sp.S.One:
            return (a.p < 0) + (a.q != 1), ()
    elif a.is_Mul:
        if _coeff_isneg(a):
            ops += 1
            a = a.as_two_terms()[1] if a.args[0] is sp.S.NegativeOne else -a
        n, d = fraction(a)
        if n.is_Integer:
            return ops + 1 + (1 if n.is_negative else 0), (d,)
        if d is not sp.S.One:
            return ops + 1, ((d, n) if not d.is_Integer else (n,))
    elif a.is_Add:
        terms = []
        negs = 0
        for i, ai in enumerate(a.args):
            if _coeff_isneg(ai):
                negs += 1
                terms.append(-ai)
            else:
                terms.append(ai)
            ops += i > 0                # ADD or SUB
        if negs == len(a.args):
            ops += 1                    # NEG
        return ops, tuple(terms)        # (SUB - ADD counts 0)
    if a.is_Pow and a.exp is sp.S.NegativeOne:
        return ops + 1, (a.base,)
    if a == sp.S.Exp1:
        return ops + 1, ()
    if a.is_Pow and a.base == sp.S.Exp1:
        return ops + 1, (a.exp,)
    if a.is_Mul:
        ops += len(a.args) - 1
    elif a.args and (a.is_Pow or a.is_Function):
        ops += 1
    return ops, (() if a.is_Symbol else a.args)


def count_ops(expr, memo):
    """sp.count_ops(expr) (visual=False) of an expression of the kernels'
    kinds (no Derivative, Integral, Sum, lattice or relational nodes), the
    same number, with the count of every distinct subexpression remembered in
    memo: sympy walks the tree, which costs minutes on the large
    tilt-vector expressions whose subtrees repeat."""
    expr = sp.sympify(expr)
    stack = [(expr, False)]
    while stack:
        node, expanded = stack.pop()
        if node in memo:
            continue
        if not expanded:
            ops, children = _count_node(node)
            pending = [c for c in children if c not in memo]
            if pending:
                stack.append((node, True))
                stack.extend((c, False) for c in pending)
                continue
            memo[node] = ops + sum(memo[c] for c in children)
        else:
            ops, children = _count_node(node)
            memo[node] = ops + sum(memo[c] for c in children)
    return memo[expr]


def param_names():
    return {P[name]: f"p->{name}" for name, *_ in PARAMETERS}


# Kernel.emit's results in this process: (documentation, arguments,
# bindings, outputs) -> (text with the name replaced by "@", operations).
_EMITTED = {}


class Kernel:
    """One C function: named inputs bound to array entries, a list of outputs.

    ``args`` is a list of (C declaration, symbols it provides); an argument none
    of whose symbols occurs in the outputs is marked unused with a (void) cast.
    """

    def __init__(self, name, doc, args, bindings, outputs, out_doc, arrays=(), blocks=None):
        self.name, self.doc, self.args = name, doc, args
        self.bindings = bindings      # list of (symbol, C expression, comment)
        self.outputs = outputs        # list of sympy expressions (out[i])
        self.out_doc = out_doc        # comment describing the out layout
        self.arrays = list(arrays)    # (argument name, length) of each array input
        # (name, length) of each block of a packed out, in order; None: one block
        self.blocks = blocks
        if blocks is not None and sum(ln for _, ln in blocks) != len(outputs):
            raise RuntimeError(f"{name}: the blocks {blocks} do not cover its "
                               f"{len(outputs)} outputs")

    def lengths(self):
        """(argument name, length) of every array argument, inputs first, out last."""
        return self.arrays + [("out", len(self.outputs))]

    def offsets(self):
        """(block name, offset in out) of each block of a packed out: the
        runtime reads the blocks by these, never by offsets it computes."""
        at, out = 0, []
        for block, ln in self.blocks or ():
            out.append((block, at))
            at += ln
        return out

    def signature(self):
        return f"void {self.name}({', '.join(d for d, _ in self.args)})"

    def emit(self):
        """(C text, operations after CSE).  A kernel the same as one emitted
        earlier in this process but for its name (the same documentation,
        arguments, bindings and outputs: the models share many, see
        emit_model.share_kernels) is not emitted again: its text is that one's
        with this name."""
        key = (tuple(self.doc), self.out_doc,
               tuple((decl, None if provided is None else tuple(provided))
                     for decl, provided in self.args),
               tuple(self.bindings), tuple(sp.sympify(e) for e in self.outputs))
        sig = f"void {self.name}("
        done = _EMITTED.get(key)
        if done is None:
            text, ops = self._emit()
            if text.count(sig) != 1:
                raise RuntimeError(f"{self.name}: its name is not once in its text")
            done = _EMITTED[key] = (text.replace(sig, "void @(", 1), ops)
        return done[0].replace("void @(", sig, 1), done[1]

    def _emit(self):
        names = param_names()
        memo = {}
        exprs = [pythagoras(sp.sympify(e), memo) for e in self.outputs]
        used = set().union(*(e.free_symbols for e in exprs))
        bind = [f"    const double {sym.name} = {c_expr};  /* {comment} */"
                for sym, c_expr, comment in self.bindings if sym in used]
        unused = [f"    (void){decl.split()[-1].lstrip('*')};"
                  for decl, provided in self.args
                  if provided is not None and not (set(provided) & used)]
        repl, reduced = sp.cse(exprs, symbols=sp.numbered_symbols("w"),
                               order="canonical")
        repl = _drop_unused(repl, reduced)
        printer = KernelPrinter(names)
        counted = {}
        ops_before = sum(count_ops(e, counted) for e in exprs)
        ops_after = (sum(count_ops(e, counted) for _, e in repl)
                     + sum(count_ops(e, counted) for e in reduced))
        temps = [f"    const double {sym.name} = {printer.doprint(e)};"
                 for sym, e in repl]
        outs = [f"    out[{i}] = {printer.doprint(e)};"
                for i, e in enumerate(reduced)]
        head = ["/* " + self.doc[0]] + [" * " + line for line in self.doc[1:]]
        head += [f" * {self.out_doc}",
                 f" * Operations: {ops_after} after CSE ({ops_before} before), "
                 f"{len(repl)} temporaries.",
                 " */"]
        parts = ["\n".join(head), self.signature(), "{"]
        if unused:
            parts += unused
        if bind:
            parts += ["    /* inputs */"] + bind
        if temps:
            parts += ["    /* common subexpressions */"] + temps
        parts += ["    /* outputs */"] + outs + ["}", ""]
        return "\n".join(parts), ops_after
