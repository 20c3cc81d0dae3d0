"""From the variants to the text of every file of generated/: the models.

Everything that decides a file's text is here, in assemble.py or below, in
usm_derive/, and so in the digests (digests.py); derive/generate.py only
chooses which models to derive, which to take from its cache or from the
committed generated/, and writes the files.  Each step's inputs:

  model_files     one model: its assumptions (derive/variants.py), the code
                  (model_digest)  -> usm_<name>.h, the source in parts,
                  usm_<name>_equations.json
  share_kernels   every model's kernel_hashes  -> usm_<name>.c (emit_model)
  assemble.render_docs   every model's equations data
                  -> usm_<name>_equations.{md,tex}
  assemble.common_files  the list of models, the documents, the defaults
                  -> usm_kernels.*, usm_contracts.*, usm_equations.*
  assemble.manifest      the digests, the kernels' hashes and owners -> DIGESTS
"""
import json
import time

import sympy as sp

from . import GENERATOR_VERSION, defaults, digests, emit_contracts, emit_doc, emit_model
from .model import _euler_name, derive_model
import variants

sha = digests.sha


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
    """(name, files, derivation s, emission s, CPU s) of one model; job from job()."""
    name, base, variant, spec, description, stamp = job
    t0, cpu0 = time.perf_counter(), time.process_time()
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
    return name, files, t1 - t0, time.perf_counter() - t1, time.process_time() - cpu0


def chain_files(jobs):
    """model_files of each job in order, in this process, so that the later
    models take what they share with the earlier ones (model._SHARED,
    emit_c._EMITTED)."""
    return [model_files(j) for j in jobs]
