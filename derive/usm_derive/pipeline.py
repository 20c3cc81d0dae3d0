"""From the variants to the text of every file of generated/.

Everything that decides a file's text is here (or below, in usm_derive/), and
so in the digests (digests.py); derive/generate.py only chooses which models
to derive, which to take from its cache or from the committed generated/, and
writes the files.  Each step's inputs:

  model_files     one model: its assumptions (derive/variants.py), the code
                  (model_digest)  -> usm_<name>.h, the source in parts,
                  usm_<name>_equations.json
  share_kernels   every model's kernel_hashes  -> usm_<name>.c (emit_model)
  render_docs     every model's equations data -> usm_<name>_equations.{md,tex}
  common_files    the list of models, the documents, the defaults
                  -> usm_kernels.*, usm_contracts.*, usm_equations.*, DIGESTS
"""
import json
import os
import time

import sympy as sp

from . import GENERATOR_VERSION, defaults, digests, emit_contracts, emit_doc, emit_model
from .model import _euler_name, derive_model
import variants

sha = digests.sha
# The manifest of generated/: the digest of all inputs, and per model the
# digest of its inputs and its kernels' hashes and owners.
MANIFEST = "DIGESTS"


class Refused(Exception):
    """The derivation refuses a model's assumptions: one line for the user,
    naming the model and the assumptions (no traceback)."""


def code_digest():
    return digests.model_code_digest(sp.__version__)


def model_digest(model, code):
    """The digest of one model's own files: exactly the inputs they depend on
    (its assumptions, the models of the same assumptions in the other
    coordinates that its descriptor and document name, the couplings, the code)."""
    name, base, variant, spec, description = model
    return sha(code, json.dumps([name, base, variant, spec, description,
                                 emit_contracts.model_couplings(spec),
                                 _euler_name(name), emit_model._other_coordinates(name)],
                                sort_keys=True))


def job(model, key):
    """model_files' argument: the model and what its banners say."""
    return model + ({"generator": GENERATOR_VERSION, "sympy": sp.__version__, "digest": key},)


def model_files(job):
    """(name, files, derivation s, emission s) of one model; job from job()."""
    name, base, variant, spec, description, stamp = job
    t0 = time.perf_counter()
    defaults.IN_MODEL = True
    try:
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
    finally:
        defaults.IN_MODEL = False
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


def manifest(models, keys, owners, hashes):
    """generated/DIGESTS: what derive/generate.py needs to take a model's files
    from generated/ instead of deriving it (its digest, its kernels' hashes and
    owners, for emit_model.share_kernels), and the digest of all inputs."""
    entries = []
    for m in models:
        name = m[0]
        entries.append({"name": name, "digest": keys[name],
                        "kernels": [[kind, h, owner[0]]
                                    for (kind, h), (_, owner) in zip(hashes[name], owners[name])]})
    return json.dumps({"generator": GENERATOR_VERSION, "sympy": sp.__version__,
                       "input_digest": digests.input_digest(sp.__version__),
                       "models": entries}, indent=1, sort_keys=True) + "\n"


def common_files(models, files, code, diffs):
    """usm_kernels.{h,c}, usm_contracts.{h,c}, usm_equations.{h,c} from every
    model's files (with the documents rendered)."""
    out = {}
    # usm_kernels.h depends on the code and the list of models and variants
    # only; usm_kernels.c also holds the digest of all inputs.
    variant_list = [(v, d[2]) for v, d in variants.VARIANTS.items()]
    listing = json.dumps([[m[0], m[1], m[2]] for m in models] + variant_list)
    inputs = digests.input_digest(sp.__version__)
    stamp = {"generator": GENERATOR_VERSION, "sympy": sp.__version__,
             "digest": sha(code, listing), "input_digest": inputs}
    out.update(emit_model.common_files(
        [(m[0], m[1], m[2]) for m in models], variant_list, stamp))
    # usm_contracts.c holds the defaults: its digest is of all inputs
    contracts_stamp = dict(stamp, digest=sha(inputs, listing,
                                             json.dumps(emit_contracts.couplings())))
    out.update(emit_contracts.common_files(
        [(m[0], m[3]) for m in models], files,
        lambda title, extra: emit_model.banner(title, contracts_stamp, extra)))
    docs = [(m[0], fmt, files[f"usm_{m[0]}_equations.{ext}"])
            for m in models for fmt, ext in (("markdown", "md"), ("latex", "tex"))]
    docs += [(m[0], fmt, diffs[m[0]][k]) for m in models
             for k, fmt in enumerate(("markdown-diff", "latex-diff"))]
    doc_stamp = dict(stamp, digest=sha(code, *(d[2] for d in docs)))
    out["usm_equations.c"] = emit_doc.equations_c(docs, emit_model.banner(
        "usm_equations.c: the derived equations as documents, for `usm equations`.",
        doc_stamp))
    out["usm_equations.h"] = emit_doc.equations_h(len(docs), emit_model.banner(
        "usm_equations.h: the derived equations as documents, for `usm equations`\n"
        " * (linked into the command only, not into libusm).", stamp))
    return out
