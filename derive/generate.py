#!/usr/bin/env python3
"""Regenerate the C kernels in generated/ from the variants in derive/variants.py.

    python3 derive/generate.py [--out DIR] [--check] [--only NAME ...] [--jobs N]
                               [--cache DIR | --no-cache] [--allow-other-sympy]
    python3 derive/generate.py --list     (the files it writes, ;-separated)

It refuses to run with a sympy other than the pinned one (PINNED_SYMPY below,
Debian's /usr/bin/python3 with python3-sympy) unless --allow-other-sympy.
Each model is derived only when one of its inputs changed: its outputs are
cached (derive/.cache) under a digest of its assumptions, the generator's code
(derive/generate.py, derive/usm_derive/*.py) and the sympy and Python versions.
A kernel identical in several models is emitted once (emit_model.share_kernels,
after every model is known; with --only, the other models' kernels come from
the cache).  Files whose content is unchanged are not rewritten.

--check regenerates into a temporary directory and exits 1 (listing the files)
when the committed generated/ differs, 0 when it is up to date.
Output is byte-identical for the same inputs and sympy version: the hash seed
is pinned (the script re-executes itself with PYTHONHASHSEED=0).
"""
import argparse
import filecmp
import hashlib
import json
import multiprocessing
import os
import platform
import sys
import tempfile
import time

if os.environ.get("PYTHONHASHSEED") != "0":
    os.environ["PYTHONHASHSEED"] = "0"
    os.execv(sys.executable, [sys.executable] + sys.argv)

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

if sys.argv[1:] == ["--list"]:
    # The files a regeneration writes, for the build system; needs no sympy.
    import variants
    names = [m[0] for m in variants.generated_models()]
    files = ["usm_kernels.c", "usm_kernels.h", "usm_equations.c", "usm_equations.h",
             "usm_contracts.c", "usm_contracts.h"]
    for n in names:
        files += [f"usm_{n}.c", f"usm_{n}.h", f"usm_{n}_equations.md", f"usm_{n}_equations.tex",
                  f"usm_{n}_equations.json"]
    print(";".join(sorted(files)))
    sys.exit(0)

import sympy as sp  # noqa: E402

from usm_derive import GENERATOR_VERSION  # noqa: E402
from usm_derive.model import derive_model  # noqa: E402
from usm_derive import emit_contracts, emit_doc, emit_model  # noqa: E402
import variants  # noqa: E402


PINNED_PYTHON = "/usr/bin/python3"
PINNED_SYMPY = "1.11.1"
CODE_FILES = ["generate.py"] + sorted(
    os.path.join("usm_derive", n) for n in os.listdir(os.path.join(HERE, "usm_derive"))
    if n.endswith(".py"))


def _sha(*parts):
    h = hashlib.sha256()
    for part in parts:
        h.update(part if isinstance(part, bytes) else part.encode())
        h.update(b"\0")
    return h.hexdigest()


def _file_digest(names):
    parts = []
    for name in names:
        with open(os.path.join(HERE, name), "rb") as fh:
            parts += [name, fh.read()]
    return _sha(*parts)


def input_digest():
    """sha256 over every file of derive/ that can change the output."""
    return _file_digest(CODE_FILES + ["variants.py"])


def code_digest():
    """sha256 over the generator's code (not variants.py) and the sympy and
    Python versions: everything a model's output depends on besides its spec."""
    return _sha(_file_digest(CODE_FILES), GENERATOR_VERSION, sp.__version__,
                platform.python_version())


def model_digest(model, code):
    """The cache key of one model: exactly the inputs its files depend on."""
    name, base, variant, spec, description = model
    return _sha(code, json.dumps([name, base, variant, spec, description,
                                  emit_contracts.model_couplings(spec)], sort_keys=True))


class Refused(Exception):
    """The derivation refuses a model's assumptions: one line for the user,
    naming the model and the assumptions (no traceback)."""


def _model_files(job):
    name, base, variant, spec, description, stamp = job
    t0 = time.perf_counter()
    try:
        model = derive_model(name, spec)
    except (ValueError, RuntimeError, KeyError) as e:
        changes = variants.VARIANTS.get(variant, ({},))[0]
        said = ", ".join(f"{k}={v}" for k, v in changes.items()) or "the paper's"
        raise Refused(f"model {name} (variant {variant}: {said}): {e}") from None
    t1 = time.perf_counter()
    files = emit_model.model_files(model, description, stamp, base, variant)
    # the document as data; rendered by render_docs() once every model is known
    files[f"usm_{name}_equations.json"] = json.dumps(
        emit_doc.model_data(model), indent=0, sort_keys=True) + "\n"
    return name, files, t1 - t0, time.perf_counter() - t1


def render_docs(models, files, out_dir):
    """usm_<name>_equations.{md,tex} of every model from its data, with the lines
    that differ from the paper's model of the same base highlighted; and the
    documents of those lines only (for `usm equations --diff`)."""
    diffs = {}
    for name, base, variant, spec, description in models:
        data = json.loads(files[f"usm_{name}_equations.json"])
        paper, changes = None, []
        if variant != "paper":
            key = f"usm_{base}_equations.json"
            text = files.get(key)
            if text is None and os.path.exists(os.path.join(out_dir, key)):
                with open(os.path.join(out_dir, key), encoding="utf-8") as fh:
                    text = fh.read()
            paper = json.loads(text) if text is not None else None
            changes = [(k, v, variants.PAPER.get(k, variants.UNSTATED.get(k)))
                       for k, v in sorted(variants.VARIANTS[variant][0].items())]
        md, tex = emit_doc.render(data, description, paper, changes)
        files[f"usm_{name}_equations.md"] = md
        files[f"usm_{name}_equations.tex"] = tex
        diffs[name] = emit_doc.render(data, description, paper, changes, diff=True)
    return diffs


def _cache_read(cache, key):
    if not cache:
        return None
    try:
        with open(os.path.join(cache, key + ".json"), encoding="utf-8") as fh:
            return json.load(fh)
    except (OSError, ValueError):
        return None


def _cache_write(cache, key, files):
    if not cache:
        return
    os.makedirs(cache, exist_ok=True)
    # atomic: a build and a manual run may write the same entry at once
    fd, tmp = tempfile.mkstemp(dir=cache, suffix=".tmp")
    with os.fdopen(fd, "w", encoding="utf-8") as fh:
        json.dump(files, fh, sort_keys=True)
    os.replace(tmp, os.path.join(cache, key + ".json"))


def _kernel_parts(models, files, code, cache):
    """(model, its source in parts, whether it is written) of every model in
    derive/variants.py order: a kernel is emitted once, by the first model
    that has it (emit_model.share_kernels), so the files of one model depend
    on the others' kernels; with --only, those of the models not written come
    from the cache."""
    out = []
    for m in variants.generated_models():
        if m in models:
            out.append((m, files[f"usm_{m[0]}.c"], True))
            continue
        cached = _cache_read(cache, model_digest(m, code))
        if cached is None:
            print(f"  {m[0]}: not in the cache; its kernels are not shared (run "
                  "without --only for the files of a full regeneration)", file=sys.stderr)
        else:
            out.append((m, cached[f"usm_{m[0]}.c"], False))
    return out


def _write_if_changed(path, text):
    """Unchanged files keep their time stamp, so the build recompiles only
    the kernels of the models that changed."""
    try:
        with open(path, encoding="utf-8", newline="") as fh:
            if fh.read() == text:
                return False
    except OSError:
        pass
    with open(path, "w", encoding="utf-8", newline="\n") as fh:
        fh.write(text)
    return True


def write_all(out_dir, only=None, verbose=True, jobs=2, cache=None):
    os.makedirs(out_dir, exist_ok=True)
    code = code_digest()
    models = [m for m in variants.generated_models() if not only or m[0] in only]
    files, work = {}, []
    for m in models:
        key = model_digest(m, code)
        cached = _cache_read(cache, key)
        if cached is not None:
            files.update(cached)
            if verbose:
                print(f"  {m[0]}: unchanged (cache {key[:12]})", file=sys.stderr)
        else:
            work.append(m + ({"generator": GENERATOR_VERSION, "sympy": sp.__version__,
                              "digest": key},))
    # The models are independent: derive them on both cores.  Each worker is a
    # fork of this process (PYTHONHASHSEED=0), so the output does not depend on
    # how the work is split.
    if jobs > 1 and len(work) > 1:
        # the longest derivations first (those in coordinates other than the
        # Euler angles also derive the Euler angles' stationary problem), so
        # that the cores finish together; the results keep the order of work
        cost = [0 if w[3].get("coordinates", "euler_zxz") == "euler_zxz" else -1 for w in work]
        order = sorted(range(len(work)), key=lambda i: cost[i])
        with multiprocessing.get_context("fork").Pool(min(jobs, len(work))) as pool:
            done = pool.map(_model_files, [work[i] for i in order], chunksize=1)
        results = [None] * len(work)
        for i, r in zip(order, done):
            results[i] = r
    else:
        results = [_model_files(w) for w in work]
    for (name, model_files, t_derive, t_emit), job in zip(results, work):
        files.update(model_files)
        _cache_write(cache, job[-1]["digest"], model_files)
        if verbose:
            print(f"  {name}: derived in {t_derive:.1f} s, emitted in {t_emit:.1f} s",
                  file=sys.stderr)
    emit_model.share_kernels(_kernel_parts(models, files, code, cache), files)
    diffs = render_docs(models, files, out_dir)
    if not only:
        # usm_kernels.h depends on the code and the list of models and
        # variants only; usm_kernels.c also holds the digest of all inputs.
        variant_list = [(v, d[2]) for v, d in variants.VARIANTS.items()]
        listing = json.dumps([[m[0], m[1], m[2]] for m in models] + variant_list)
        stamp = {"generator": GENERATOR_VERSION, "sympy": sp.__version__,
                 "digest": _sha(code, listing), "input_digest": input_digest()}
        files.update(emit_model.common_files(
            [(m[0], m[1], m[2]) for m in models], variant_list, stamp))
        contracts_stamp = dict(stamp, digest=_sha(code, listing,
                                                  json.dumps(emit_contracts.couplings())))
        files.update(emit_contracts.common_files(
            [(m[0], m[3]) for m in models], files,
            lambda title, extra: emit_model.banner(title, contracts_stamp, extra)))
        docs = [(m[0], fmt, files[f"usm_{m[0]}_equations.{ext}"])
                for m in models for fmt, ext in (("markdown", "md"), ("latex", "tex"))]
        docs += [(m[0], fmt, diffs[m[0]][k]) for m in models
                 for k, fmt in enumerate(("markdown-diff", "latex-diff"))]
        doc_stamp = dict(stamp, digest=_sha(code, *(d[2] for d in docs)))
        files["usm_equations.c"] = emit_doc.equations_c(docs, emit_model.banner(
            "usm_equations.c: the derived equations as documents, for `usm equations`.",
            doc_stamp))
        files["usm_equations.h"] = emit_doc.equations_h(len(docs), emit_model.banner(
            "usm_equations.h: the derived equations as documents, for `usm equations`\n"
            " * (linked into the command only, not into libusm).", stamp))
    changed = [f for f, text in files.items()
               if _write_if_changed(os.path.join(out_dir, f), text)]
    return sorted(files), changed


def check_sympy(allow_other):
    """The committed generated/ is byte-identical only with the pinned sympy."""
    if sp.__version__ == PINNED_SYMPY:
        return True
    what = (f"sympy {sp.__version__} (python {sys.executable}) is not the pinned sympy "
            f"{PINNED_SYMPY} (python {PINNED_PYTHON}, Debian's python3-sympy)")
    if not allow_other:
        print(f"derive/generate.py: {what}: its output would differ from the committed "
              f"generated/; run {PINNED_PYTHON} derive/generate.py, or pass "
              "--allow-other-sympy to generate anyway", file=sys.stderr)
        return False
    print(f"derive/generate.py: warning: {what}; generating anyway (--allow-other-sympy): "
          "the output may differ from the committed generated/ and fail generated_in_sync",
          file=sys.stderr)
    return True


def main():
    try:
        return _main()
    except Refused as e:
        print(f"derive/generate.py: refused: {e}", file=sys.stderr)
        return 2


def _main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=os.path.join(HERE, "..", "generated"))
    ap.add_argument("--check", action="store_true",
                    help="compare with --out instead of writing it")
    ap.add_argument("--only", nargs="*", help="variants to generate (default: all)")
    ap.add_argument("--quiet", action="store_true")
    ap.add_argument("--jobs", type=int, default=2, help="worker processes (default 2)")
    ap.add_argument("--cache", default=os.path.join(HERE, ".cache"),
                    help="directory of derived models, keyed by the digest of their "
                         "inputs (default derive/.cache)")
    ap.add_argument("--no-cache", action="store_true", help="derive every model again")
    ap.add_argument("--stamp", help="file to touch after writing (for the build)")
    ap.add_argument("--allow-other-sympy", action="store_true",
                    help=f"generate with a sympy other than the pinned {PINNED_SYMPY} (warns)")
    args = ap.parse_args()
    if not check_sympy(args.allow_other_sympy):
        return 2
    cache = None if args.no_cache else args.cache
    t0 = time.perf_counter()
    if args.check:
        with tempfile.TemporaryDirectory() as tmp:
            written, _ = write_all(tmp, args.only, not args.quiet, args.jobs, cache)
            stale = [f for f in written
                     if not os.path.exists(os.path.join(args.out, f))
                     or not filecmp.cmp(os.path.join(tmp, f),
                                        os.path.join(args.out, f), shallow=False)]
        if stale:
            print("generated/ is out of date with derive/ (sympy "
                  f"{sp.__version__}): " + ", ".join(stale)
                  + "\nrun: python3 derive/generate.py", file=sys.stderr)
            return 1
        print(f"generated/ is up to date ({len(written)} files)")
        return 0
    written, changed = write_all(args.out, args.only, not args.quiet, args.jobs, cache)
    if args.stamp:
        with open(args.stamp, "w", encoding="utf-8") as fh:
            fh.write("\n".join(written) + "\n")
    if not args.quiet:
        print(f"wrote {len(changed)} of {len(written)} files (the others unchanged) to "
              f"{os.path.normpath(args.out)} in {time.perf_counter() - t0:.1f} s",
              file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
