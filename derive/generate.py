#!/usr/bin/env python3
"""Regenerate the C kernels in generated/ from the variants in derive/variants.py.

    python3 derive/generate.py [--out DIR] [--check] [--only NAME ...] [--jobs N]
    python3 derive/generate.py --list     (the files it writes, ;-separated)

--check regenerates into a temporary directory and exits 1 (listing the files)
when the committed generated/ differs, 0 when it is up to date.
Output is byte-identical for the same inputs and sympy version: the hash seed
is pinned (the script re-executes itself with PYTHONHASHSEED=0).
"""
import argparse
import filecmp
import hashlib
import multiprocessing
import os
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
    files = ["usm_kernels.c", "usm_kernels.h", "usm_equations.c"]
    for n in names:
        files += [f"usm_{n}.c", f"usm_{n}.h", f"usm_{n}_equations.md", f"usm_{n}_equations.tex"]
    print(";".join(sorted(files)))
    sys.exit(0)

import sympy as sp  # noqa: E402

from usm_derive import GENERATOR_VERSION  # noqa: E402
from usm_derive.model import derive_model  # noqa: E402
from usm_derive import emit_doc, emit_model  # noqa: E402
import variants  # noqa: E402


def input_digest():
    """sha256 over every file of derive/ that can change the output."""
    h = hashlib.sha256()
    files = []
    for root, dirs, names in os.walk(HERE):
        dirs[:] = sorted(d for d in dirs if d != "__pycache__")
        files += [os.path.join(root, n) for n in names if n.endswith(".py")]
    for path in sorted(files):
        h.update(os.path.relpath(path, HERE).encode() + b"\0")
        with open(path, "rb") as fh:
            h.update(fh.read() + b"\0")
    return h.hexdigest()


def _model_files(job):
    name, base, variant, spec, description, stamp = job
    t0 = time.perf_counter()
    model = derive_model(name, spec)
    t1 = time.perf_counter()
    files = emit_model.model_files(model, description, stamp, base, variant)
    docs, _ = emit_doc.model_docs(model, description)
    files.update(docs)
    return name, files, t1 - t0, time.perf_counter() - t1


def write_all(out_dir, only=None, verbose=True, jobs=2):
    os.makedirs(out_dir, exist_ok=True)
    digest = input_digest()
    stamp = {"generator": GENERATOR_VERSION, "sympy": sp.__version__,
             "digest": digest}
    models = [m for m in variants.generated_models() if not only or m[0] in only]
    work = [m + (stamp,) for m in models]
    # The models are independent: derive them on both cores.  Each worker is a
    # fork of this process (PYTHONHASHSEED=0), so the output does not depend on
    # how the work is split.
    if jobs > 1 and len(work) > 1:
        with multiprocessing.get_context("fork").Pool(min(jobs, len(work))) as pool:
            results = pool.map(_model_files, work, chunksize=1)
    else:
        results = [_model_files(w) for w in work]
    files = {}
    for name, model_files, t_derive, t_emit in results:
        files.update(model_files)
        if verbose:
            print(f"  {name}: derived in {t_derive:.1f} s, emitted in {t_emit:.1f} s",
                  file=sys.stderr)
    if not only:
        files.update(emit_model.common_files(
            [(m[0], m[1], m[2]) for m in models],
            [(v, d[2]) for v, d in variants.VARIANTS.items()], stamp))
        docs = [(m[0], fmt, files[f"usm_{m[0]}_equations.{ext}"])
                for m in models for fmt, ext in (("markdown", "md"), ("latex", "tex"))]
        files["usm_equations.c"] = emit_doc.equations_c(docs, emit_model.banner(
            "usm_equations.c: the derived equations as documents, for `usm equations`.", stamp))
    for fname, text in files.items():
        with open(os.path.join(out_dir, fname), "w", encoding="utf-8", newline="\n") as fh:
            fh.write(text)
    return sorted(files)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=os.path.join(HERE, "..", "generated"))
    ap.add_argument("--check", action="store_true",
                    help="compare with --out instead of writing it")
    ap.add_argument("--only", nargs="*", help="variants to generate (default: all)")
    ap.add_argument("--quiet", action="store_true")
    ap.add_argument("--jobs", type=int, default=2, help="worker processes (default 2)")
    args = ap.parse_args()
    t0 = time.perf_counter()
    if args.check:
        with tempfile.TemporaryDirectory() as tmp:
            written = write_all(tmp, args.only, not args.quiet, args.jobs)
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
    written = write_all(args.out, args.only, not args.quiet, args.jobs)
    if not args.quiet:
        print(f"wrote {len(written)} files to {os.path.normpath(args.out)} in "
              f"{time.perf_counter() - t0:.1f} s", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
