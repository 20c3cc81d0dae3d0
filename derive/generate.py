#!/usr/bin/env python3
"""Regenerate the C kernels in generated/ from the variants in derive/variants.py.

    python3 derive/generate.py [--out DIR] [--check] [--only NAME ...] [--jobs N]
                               [--cache DIR | --no-cache] [--committed DIR | --no-reuse]
                               [--allow-other-sympy]
    python3 derive/generate.py --list     (the files it writes, ;-separated)

It refuses to run with a sympy other than the pinned one (PINNED_SYMPY below,
Debian's /usr/bin/python3 with python3-sympy) unless --allow-other-sympy.

Only what changed is derived (usm_derive/digests.py says what each digest covers):
  - the committed generated/DIGESTS holds the digest of all inputs it was
    generated from; when derive/ still has that digest the files of
    generated/ are copied to --out, and neither sympy nor a model is touched;
  - otherwise each model is derived only when one of its inputs changed: a
    model whose digest is the one in its cache entry (derive/.cache) or in
    generated/DIGESTS is taken from there, and the documents and the common
    files are rendered again (seconds).  A kernel identical in several models
    is emitted once, by the first (emit_model.share_kernels): a model taken
    from generated/ whose kernels' owners change is derived too.
--no-cache --no-reuse derive every model from scratch (what generated_in_sync
checks); with --only, the other models' kernels come from the cache or
generated/.  Each model derived prints one line with its time.  Files whose
content is unchanged are not rewritten.

--check regenerates into a temporary directory (never reusing the directory it
checks) and exits 1 (listing the files) when the committed generated/
differs, 0 when it is up to date.
Output is byte-identical for the same inputs and sympy version: the hash seed
is pinned (the script re-executes itself with PYTHONHASHSEED=0, and a larger
SYMPY_CACHE_SIZE unless one is set).
"""
import argparse
import filecmp
import json
import multiprocessing
import os
import sys
import tempfile
import time

# sympy's cache holds 1000 results by default; the Jacobians and directional
# derivatives of the large tilt-vector expressions evict what they reuse.  A
# larger one saves CPU (about 7 % on 3dof_tilt) and changes no output byte.
if os.environ.get("PYTHONHASHSEED") != "0" or "SYMPY_CACHE_SIZE" not in os.environ:
    os.environ["PYTHONHASHSEED"] = "0"
    os.environ.setdefault("SYMPY_CACHE_SIZE", "200000")
    os.execv(sys.executable, [sys.executable] + sys.argv)

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

from usm_derive import digests  # noqa: E402  (no sympy)

MANIFEST = "DIGESTS"   # usm_derive/assemble.py, MANIFEST


def file_list():
    """The files a regeneration writes; needs no sympy."""
    import variants
    names = [m[0] for m in variants.generated_models()]
    files = ["usm_kernels.c", "usm_kernels.h", "usm_equations.c", "usm_equations.h",
             "usm_contracts.c", "usm_contracts.h", MANIFEST]
    for n in names:
        files += [f"usm_{n}.c", f"usm_{n}.h", f"usm_{n}_equations.md", f"usm_{n}_equations.tex",
                  f"usm_{n}_equations.json"]
    return sorted(files)


if sys.argv[1:] == ["--list"]:
    # for the build system
    print(";".join(file_list()))
    sys.exit(0)


def _read_manifest(committed):
    if not committed:
        return {}
    try:
        with open(os.path.join(committed, MANIFEST), encoding="utf-8") as fh:
            return json.load(fh)
    except (OSError, ValueError):
        return {}


def _read(path):
    with open(path, encoding="utf-8", newline="") as fh:
        return fh.read()


def _write_if_changed(path, text):
    """Unchanged files keep their time stamp, so the build recompiles only
    the kernels of the models that changed."""
    try:
        if _read(path) == text:
            return False
    except OSError:
        pass
    with open(path, "w", encoding="utf-8", newline="\n") as fh:
        fh.write(text)
    return True


def up_to_date(committed, out_dir, verbose):
    """The build's fast path: when derive/ has the digest of all inputs that
    generated/DIGESTS records, the committed files are the derivation's output
    (generated_in_sync proves it for the committed tree); copy them to out_dir.
    Imports no sympy.  Returns (files, changed) or None."""
    manifest = _read_manifest(committed)
    if not manifest or manifest.get("input_digest") != digests.input_digest(
            digests.sympy_version()):
        return None
    names = file_list()
    if not all(os.path.isfile(os.path.join(committed, f)) for f in names):
        return None
    os.makedirs(out_dir, exist_ok=True)
    same = os.path.realpath(committed) == os.path.realpath(out_dir)
    changed = [] if same else [f for f in names if _write_if_changed(
        os.path.join(out_dir, f), _read(os.path.join(committed, f)))]
    if verbose:
        print(f"derive/ is unchanged since {os.path.normpath(committed)} was generated "
              f"(input digest {manifest['input_digest'][:12]}): no model derived",
              file=sys.stderr)
    return names, changed


PINNED_PYTHON = "/usr/bin/python3"
PINNED_SYMPY = "1.11.1"
sp = assemble = emit_model = pipeline = variants = None


def _import_derivation():
    """sympy and the derivation: only once something is to be derived or
    rendered (seconds to import; the fast path needs none of it)."""
    global sp, assemble, emit_model, pipeline, variants
    import sympy as sp
    from usm_derive import assemble, emit_model, pipeline
    import variants


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


def _chain(task):
    """Derive the models of one chain in this process (pipeline.chain_files),
    then cache and log each (one line per model, when its chain is done)."""
    jobs, keys, cache, verbose = task
    out = {}
    for name, files, *times in pipeline.chain_files(jobs):
        _cache_write(cache, keys[name], files)
        _said(name, times, verbose)
        out[name] = files
    return out


def _derive(work, keys, jobs, cache, verbose):
    """Derive the models of ``work`` (on ``jobs`` cores); {name: files}."""
    # The models of one base model share much of their derivation and many
    # kernels (the bilateral model of a unilateral one, the Euler angles'
    # stationary problem of a tilt model, the stationary kernels of every
    # variant): one process derives them in derive/variants.py order, and
    # keeps what the later ones take (model.py, _SHARED; emit_c.py,
    # _EMITTED).  The bases run on both cores, each worker a fork of this
    # process (PYTHONHASHSEED=0): the output does not depend on the split.
    chains = {}
    for m in work:
        chains.setdefault(m[1], []).append(pipeline.job(m, keys[m[0]]))
    tasks = [(c, keys, cache, verbose)
             for c in sorted(chains.values(), key=len, reverse=True)]   # the longest first
    out = {}
    if jobs > 1 and len(tasks) > 1:
        with multiprocessing.get_context("fork").Pool(min(jobs, len(tasks))) as pool:
            for files in pool.imap_unordered(_chain, tasks, chunksize=1):
                out.update(files)
        return out
    for task in tasks:
        out.update(_chain(task))
    return out


def _said(name, times, verbose):
    """The build log's line of one derived model."""
    if verbose:
        t_derive, t_emit, cpu = times
        print(f"  {name}: derived in {t_derive:.1f} s, emitted in {t_emit:.1f} s "
              f"(CPU {cpu:.1f} s)", file=sys.stderr, flush=True)


def _same_sharing(name, owners, old, keys):
    """Whether a model taken from generated/ keeps its source there: each of
    its kernels has the owner it had, and that owner is unchanged (a changed
    owner's assumptions would change the note of the calling kernel)."""
    now = [(kind, owner[0]) for kind, owner in owners[name]]
    was = [(kind, owner) for kind, _, owner in old[name]["kernels"]]
    return now == was and all(o == name or (o in old and old[o]["digest"] == keys[o])
                              for _, o in now)


def write_all(out_dir, only=None, verbose=True, jobs=2, cache=None, committed=None):
    os.makedirs(out_dir, exist_ok=True)
    code = pipeline.code_digest()
    every = variants.generated_models()
    models = [m for m in every if not only or m[0] in only]
    keys = {m[0]: pipeline.model_digest(m, code) for m in every}
    old = {e["name"]: e for e in _read_manifest(committed).get("models", [])}
    own = ["usm_{}.h", "usm_{}.c", "usm_{}_equations.json"]

    def committed_files(name):
        try:
            return {f.format(name): _read(os.path.join(committed, f.format(name))) for f in own}
        except OSError:
            return None
    # where each model comes from: (source, files, kernel hashes); files are
    # model_files' (the source in parts) or, from generated/, the final texts
    src = {}
    for m in every:
        name, key = m[0], keys[m[0]]
        cached = _cache_read(cache, key)
        if cached is not None:
            src[name] = ("cache", cached, emit_model.kernel_hashes(name, cached[f"usm_{name}.c"]))
        elif name in old and old[name]["digest"] == key:
            texts = committed_files(name) if m in models else {}
            if texts is not None:
                src[name] = ("generated/", texts, [k[:2] for k in old[name]["kernels"]])
    if verbose:
        for m in models:
            if m[0] in src:
                print(f"  {m[0]}: unchanged ({src[m[0]][0]}, digest {keys[m[0]][:12]})",
                      file=sys.stderr)
    work = [m for m in models if m[0] not in src]
    while True:
        for name, files in _derive(work, keys, jobs, cache, verbose).items():
            src[name] = ("derived", files, emit_model.kernel_hashes(name, files[f"usm_{name}.c"]))
        owners = emit_model.kernel_owners([(m, src[m[0]][2]) for m in every if m[0] in src])
        work = [m for m in models if src[m[0]][0] == "generated/"
                and not _same_sharing(m[0], owners, old, keys)]
        if not work:
            break
        for m in work:
            del src[m[0]]
            if verbose:
                print(f"  {m[0]}: calls a kernel of a model that changed: derived again",
                      file=sys.stderr)
    for m in every:
        if m[0] not in src:
            print(f"  {m[0]}: neither in the cache nor in generated/; its kernels are not "
                  "shared (run without --only for the files of a full regeneration)",
                  file=sys.stderr)
    files = {}
    for m in models:
        files.update(src[m[0]][1])
    entries = [(m, src[m[0]][2], src[m[0]][1][f"usm_{m[0]}.c"]
                if m in models and src[m[0]][0] != "generated/" else None)
               for m in every if m[0] in src]
    owners = emit_model.share_kernels(entries, files)
    diffs = assemble.render_docs(models, files, out_dir)
    if not only:
        files.update(assemble.common_files(models, files, code, diffs))
        files[MANIFEST] = assemble.manifest(models, keys, owners,
                                            {m[0]: src[m[0]][2] for m in models})
    changed = [f for f, text in files.items()
               if _write_if_changed(os.path.join(out_dir, f), text)]
    return sorted(files), changed


def check_sympy(allow_other):
    """The committed generated/ is byte-identical only with the pinned sympy."""
    _import_derivation()
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
    except Exception as e:
        if pipeline is None or not isinstance(e, pipeline.Refused):
            raise
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
    ap.add_argument("--no-cache", action="store_true", help="do not use the cache")
    ap.add_argument("--committed", default=os.path.join(HERE, "..", "generated"),
                    help="the generated/ whose files are taken where derive/ has not changed "
                         "since (its DIGESTS; default the committed generated/)")
    ap.add_argument("--no-reuse", action="store_true",
                    help="take nothing from --committed (with --no-cache: derive every model)")
    ap.add_argument("--stamp", help="file to touch after writing (for the build)")
    ap.add_argument("--allow-other-sympy", action="store_true",
                    help=f"generate with a sympy other than the pinned {PINNED_SYMPY} (warns)")
    args = ap.parse_args()
    t0 = time.perf_counter()
    committed = None if args.no_reuse else args.committed
    if committed and not args.check and not args.only:
        fast = up_to_date(committed, args.out, not args.quiet)
        if fast is not None:
            _finish(args, *fast, t0)
            return 0
    if not check_sympy(args.allow_other_sympy):
        return 2
    cache = None if args.no_cache else args.cache
    if args.check:
        # the directory checked is never a source of the files it is checked against
        same = committed and os.path.realpath(committed) == os.path.realpath(args.out)
        with tempfile.TemporaryDirectory() as tmp:
            written, _ = write_all(tmp, args.only, not args.quiet, args.jobs, cache,
                                   None if same else committed)
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
    written, changed = write_all(args.out, args.only, not args.quiet, args.jobs, cache,
                                 committed)
    _finish(args, written, changed, t0)
    return 0


def _finish(args, written, changed, t0):
    if args.stamp:
        with open(args.stamp, "w", encoding="utf-8") as fh:
            fh.write("\n".join(written) + "\n")
    if not args.quiet:
        print(f"wrote {len(changed)} of {len(written)} files (the others unchanged) to "
              f"{os.path.normpath(args.out)} in {time.perf_counter() - t0:.1f} s",
              file=sys.stderr)


if __name__ == "__main__":
    sys.exit(main())
