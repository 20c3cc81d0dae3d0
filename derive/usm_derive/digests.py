"""The digests that say whether a file of generated/ is current.

No sympy here: the build compares the committed generated/DIGESTS with
input_digest() before anything imports sympy, so that a tree whose derive/
matches its generated/ derives nothing (derive/generate.py, the build's
fast path).

What each digest covers, and why:

  model_code_digest  every file of usm_derive/ but NOT_IN_MODELS, the generator
                     version, the sympy and Python versions: the code a model's
                     own files (usm_<name>.{h,c}, usm_<name>_equations.json) are
                     computed by.  derive/generate.py is not in it: it only
                     chooses which models to derive and where to read and write
                     them; the output is computed in usm_derive/ (pipeline.py,
                     assemble.py).
  input_digest       model_code_digest's files, NOT_IN_MODELS and variants.py:
                     everything any file of generated/ depends on.
"""
import hashlib
import os
import platform

from . import GENERATOR_VERSION

PACKAGE = os.path.dirname(os.path.abspath(__file__))
DERIVE = os.path.dirname(PACKAGE)

# Never read while a model's own files are made: the defaults reach the
# documents' parameter tables and usm_contracts.c only, assemble.py makes the
# files of all models together.  Changing them renders those again and derives
# nothing.  (defaults.defaults() refuses to run while a model is derived, so
# that a use there fails instead of leaving a stale model.)
NOT_IN_MODELS = ("defaults.py", "assemble.py")


def sha(*parts):
    h = hashlib.sha256()
    for part in parts:
        h.update(part if isinstance(part, bytes) else part.encode())
        h.update(b"\0")
    return h.hexdigest()


def _file_digest(names):
    parts = []
    for name in names:
        with open(os.path.join(DERIVE, name), "rb") as fh:
            parts += [name, fh.read()]
    return sha(*parts)


def code_files():
    """usm_derive/*.py, relative to derive/, sorted."""
    return sorted(os.path.join("usm_derive", n) for n in os.listdir(PACKAGE) if n.endswith(".py"))


def sympy_version():
    """The installed sympy's version, without importing sympy (seconds)."""
    try:
        from importlib import metadata
        return metadata.version("sympy")
    except Exception:  # no metadata: ask the module itself
        try:
            import sympy
        except ImportError:
            return "none"
        return sympy.__version__


def _versions(sympy):
    return [GENERATOR_VERSION, sympy, platform.python_version()]


def model_code_digest(sympy):
    files = [f for f in code_files() if os.path.basename(f) not in NOT_IN_MODELS]
    return sha(_file_digest(files), *_versions(sympy))


def input_digest(sympy):
    return sha(_file_digest(code_files() + ["variants.py"]), *_versions(sympy))
