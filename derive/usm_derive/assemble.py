"""The files of generated/ made of every model's: the documents, the common
files and the manifest DIGESTS (pipeline.py makes the models' own files).

Not read while a model is derived: not in the models' digests
(digests.NOT_IN_MODELS), so a change here renders these files again and
derives no model.
"""
import json
import os
import platform

import sympy as sp

from . import GENERATOR_VERSION, digests, emit_contracts, emit_doc, emit_model
import variants

sha = digests.sha
# The manifest of generated/: the digest of all inputs, and per model the
# digest of its inputs and its kernels' hashes and owners.
MANIFEST = "DIGESTS"


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
    # JSON, one line per kernel
    head = {"generator": GENERATOR_VERSION, "sympy": sp.__version__,
            "python": platform.python_version(),
            "input_digest": digests.input_digest(sp.__version__)}
    lines = ["{" + ",\n ".join(f"{json.dumps(k)}: {json.dumps(v)}" for k, v in head.items())
             + ',\n "models": [']
    for i, m in enumerate(models):
        name = m[0]
        rows = [json.dumps([kind, h, owner[0]])
                for (kind, h), (_, owner) in zip(hashes[name], owners[name])]
        lines.append(f'  {{"name": {json.dumps(name)}, "digest": {json.dumps(keys[name])},'
                     ' "kernels": [\n   ' + ",\n   ".join(rows) + "]}"
                     + ("," if i + 1 < len(models) else ""))
    text = "\n".join(lines) + "\n ]}\n"
    json.loads(text)  # well formed
    return text


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
    # usm_contracts.c holds the defaults: its digest is of all inputs; not so
    # the header's, which usm_kernels.h and so every source includes (a
    # changed default recompiles usm_contracts.c alone)
    couplings = json.dumps(emit_contracts.couplings())
    contracts_h = dict(stamp, digest=sha(code, listing, couplings))
    contracts_c = dict(stamp, digest=sha(inputs, listing, couplings))
    out.update(emit_contracts.common_files(
        [(m[0], m[3]) for m in models], files,
        lambda title, extra: emit_model.banner(
            title, contracts_c if title.startswith("usm_contracts.c") else contracts_h, extra)))
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
