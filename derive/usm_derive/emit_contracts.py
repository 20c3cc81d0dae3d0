"""The contracts between derive/ and the runtime: every parameter, output and
constraint by index, with names and units as tables, and the parameter
couplings that the assumptions imply (derive/variants.py, COUPLINGS).

Emitted as generated/usm_contracts.{h,c}; each model's descriptor carries its
couplings (param_coupling, through model_coupling_array below).  The runtime
reads these instead of spelling names: no parameter name is compared with a
string literal in runtime/.

Naming (also in the header's comment):
  USM_P_<name>       index of parameter <name> in usm_params order (the
                     usm_param_table row, the steady_jacobian_params column);
                     <name> is the field exactly as spelled, case kept: c_R
                     and c_r are two parameters
  USM_CONSTRAINT_<K> the admissible sign of a parameter, <K> its
                     usm_param_info.constraint word in capitals
  usm_<kernel>_outputs[USM_<KERNEL>_<NAME>]  name and unit of each output of
                     a kernel, indexed by usm_kernels.h's enums (USM_OUT_*,
                     USM_STEADY_*, USM_SEED_*, USM_POWER_*, USM_DESIGN_*)
"""
import re

from .defaults import defaults, ranges
from .model import IMPERFECTIONS, PARAMETERS
from .outputs import (DESIGN_NAMES, OUTPUT_NAMES, OUTPUT_UNITS, POWER_NAMES, SEED_NAMES,
                      STEADY_NAMES)

PARAM_NAMES = [name for name, *_ in PARAMETERS]

# The admissible signs a parameter can have (PARAMETERS' last column), in
# enum order; the words are usm_param_info.constraint.
CONSTRAINTS = [
    ("any", "every finite value"),
    ("positive", "> 0"),
    ("nonnegative", ">= 0"),
    ("unit_interval", "in [0, 1]"),
]



def _output_lists():
    return [("out", "USM_OUT", "the outputs of <model>_outputs (along a motion)", OUTPUT_NAMES),
            ("steady", "USM_STEADY", "the outputs of <model>_steady_outputs", STEADY_NAMES),
            ("seed", "USM_SEED", "the outputs of <model>_steady_seed", SEED_NAMES),
            ("power", "USM_POWER", "the outputs of <model>_steady_power", POWER_NAMES),
            ("design", "USM_DESIGN", "the rows of <model>_steady_design_jacobian", DESIGN_NAMES)]


def couplings():
    """[(assumption, choice, parameter, equals, because)] in derive/variants.py order."""
    import variants
    out = []
    for (assumption, choice), pairs in variants.COUPLINGS.items():
        for param, equals, because in pairs:
            out.append((assumption, choice, param, equals, because))
    for a, c, param, equals, _ in out:
        if param not in PARAM_NAMES or equals not in PARAM_NAMES or param == equals:
            raise ValueError(f"COUPLINGS {a}={c}: {param} = {equals} is not two parameters")
        if any(equals == other[2] for other in out):
            raise ValueError(f"COUPLINGS: {equals} is itself coupled (no chains)")
    if len({c[2] for c in out}) != len(out):
        raise ValueError("COUPLINGS: a parameter coupled twice")
    return out


def model_couplings(assumptions):
    """Index in usm_param_couplings of the coupling that fixes each parameter
    under these assumptions, -1 where the parameter is free."""
    out = [-1] * len(PARAM_NAMES)
    for i, (a, c, param, _, _) in enumerate(couplings()):
        if assumptions.get(a) == c:
            out[PARAM_NAMES.index(param)] = i
    return out


def model_coupling_array(assumptions):
    """The C array a model's descriptor points to (field param_coupling)."""
    items = ", ".join(str(i) for i in model_couplings(assumptions))
    return f"static const signed char param_coupling[USM_NPARAMS] = {{{items}}};\n"


DESCRIPTOR_MEMBER = (
    "    /* Per parameter k (USM_P_<name>, usm_contracts.h): index in usm_param_couplings\n"
    "       of the coupling that fixes it under this model's assumptions, -1 where k is\n"
    "       free (derive/variants.py, COUPLINGS; usm_param_coupled) */\n"
    "    const signed char *param_coupling;\n")


def check_models(models, files):
    """The derived kernels honour the couplings: a model whose assumptions
    tie a parameter to another never reads it."""
    for name, spec in models:
        for k, i in enumerate(model_couplings(spec)):
            if i >= 0 and re.search(rf"\bp->{PARAM_NAMES[k]}\b", files[f"usm_{name}.c"]):
                raise RuntimeError(f"usm_{name}.c reads {PARAM_NAMES[k]}, which its assumptions "
                                   f"tie to {couplings()[i][3]} (derive/variants.py, COUPLINGS)")


def _check_names():
    for nm in PARAM_NAMES:
        if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", nm):
            raise ValueError(f"parameter {nm!r}: not a C identifier")
    if len(set(PARAM_NAMES)) != len(PARAM_NAMES):
        raise ValueError("two parameters of the same name")
    words = [w for w, _ in CONSTRAINTS]
    for name, _, _, cons in PARAMETERS:
        if cons not in words:
            raise ValueError(f"parameter {name}: constraint {cons!r} not in {words}")
    for _, _, _, names in _output_lists():
        for nm in names:
            if nm not in OUTPUT_UNITS:
                raise ValueError(f"output {nm}: no unit in outputs.OUTPUT_UNITS")


def _lines(items):
    """Aligned C enumerator lines with trailing comments."""
    width = max(len(code) for code, _ in items)
    return "".join(f"    {code.ljust(width)} /* {comment} */\n" for code, comment in items)


def contracts_h(banner):
    _check_names()
    cs = couplings()
    h = banner
    h += "#ifndef USM_CONTRACTS_H\n#define USM_CONTRACTS_H\n\n#include \"usm_kernels.h\"\n\n"
    h += '#ifdef __cplusplus\nextern "C" {\n#endif\n\n'
    h += ("/* Index of each parameter: usm_param_table[USM_P_<name>] describes the field\n"
          "   <name> of usm_params, column USM_P_<name> of steady_jacobian_params is the\n"
          "   derivative in it.  <name> is spelled as the field, case kept. */\n"
          "enum usm_param_index {\n")
    h += _lines([(f"USM_P_{name} = {k},", f"[{unit}] {desc}")
                 for k, (name, unit, desc, _) in enumerate(PARAMETERS)])
    h += f"    USM_P_COUNT = {len(PARAMETERS)}\n}};\n\n"
    h += ("/* The admissible sign of a parameter; usm_constraint_names[c] is the word in\n"
          "   usm_param_info.constraint. */\n"
          "typedef enum usm_constraint {\n")
    h += _lines([(f"USM_CONSTRAINT_{w.upper()} = {i},", f'"{w}": {what}')
                 for i, (w, what) in enumerate(CONSTRAINTS)])
    h += f"    USM_CONSTRAINT_COUNT = {len(CONSTRAINTS)}\n}} usm_constraint;\n\n"
    h += ("extern const char *const usm_constraint_names[USM_CONSTRAINT_COUNT];\n"
          "/* The constraint of each parameter, by USM_P_<name>. */\n"
          "extern const usm_constraint usm_param_constraints[USM_NPARAMS];\n\n")
    h += ("/* The row of usm_param_table that info points to: its USM_P_<name>. */\n"
          "static inline int usm_param_index(const usm_param_info *info)\n"
          "{\n    return (int)(info - usm_param_table);\n}\n\n")
    h += ("/* The default value of each parameter, by USM_P_<name>, in its SI unit\n"
          "   (derive/usm_derive/defaults.py: the paper's Appendix A and the values it\n"
          "   leaves out; usm_params_default copies them). */\n"
          "extern const double usm_param_defaults[USM_NPARAMS];\n\n")
    h += ("/* The physical range of a parameter in its SI unit, both ends included. */\n"
          "typedef struct usm_param_range {\n    double lo;\n    double hi;\n} usm_param_range;\n\n"
          "/* The range of each parameter, by USM_P_<name> (derive/usm_derive/defaults.py,\n"
          "   RANGES: generous for this motor class, so that a value outside is one typed\n"
          "   in the wrong unit; usm_params_set and usm_params_check refuse it). */\n"
          "extern const usm_param_range usm_param_ranges[USM_NPARAMS];\n\n")
    h += ("/* The imperfections of a real motor (0 in every ideal model), in table order. */\n"
          f"#define USM_NIMPERFECTIONS {len(IMPERFECTIONS)}\n"
          "extern const int usm_param_imperfections[USM_NIMPERFECTIONS];\n\n")
    h += ("/* A parameter an assumption ties to another (derive/variants.py, COUPLINGS):\n"
          "   under it, parameter param equals parameter equals. */\n"
          "typedef struct usm_param_coupling {\n"
          "    int param;              /* USM_P_<name> of the parameter that is not free */\n"
          "    int equals;             /* USM_P_<name> of the parameter it equals (free) */\n"
          "    const char *assumption; /* e.g. \"stator_inertia=axisymmetric\" */\n"
          "    const char *because;    /* the assumption in words, e.g. \"an axisymmetric stator\" */\n"
          "} usm_param_coupling;\n\n")
    h += "/* Every coupling: " + "; ".join(f"{p} = {e} ({a}={c})" for a, c, p, e, _ in cs) + ". */\n"
    h += (f"#define USM_NCOUPLINGS {len(cs)}\n"
          f"extern const usm_param_coupling usm_param_couplings[{max(len(cs), 1)}];\n\n"
          "/* The coupling that fixes parameter k (USM_P_<name>) in model m; NULL where k\n"
          "   is free there (or k is not a parameter). */\n"
          "const usm_param_coupling *usm_param_coupled(const usm_model *m, int k);\n\n"
          "/* Applies model m's couplings to p: every parameter that m ties to parameter k\n"
          "   is set equal to it; k = -1: every coupling of m. */\n"
          "void usm_params_couple(const usm_model *m, usm_params *p, int k);\n\n")
    h += ("/* Name and unit of one output of a kernel. */\n"
          "typedef struct usm_output_info {\n    const char *name;\n    const char *unit;\n"
          "} usm_output_info;\n\n")
    for short, enum, what, names in _output_lists():
        h += (f"/* Name and unit of {what}, by {enum}_<NAME>. */\n"
              f"extern const usm_output_info usm_{short}_outputs[{enum}_COUNT];\n")
    h += '\n#ifdef __cplusplus\n}\n#endif\n\n#endif /* USM_CONTRACTS_H */\n'
    return h


def contracts_c(banner):
    cs = couplings()
    c = banner + '#include <stddef.h>\n\n#include "usm_contracts.h"\n\n'
    c += "const char *const usm_constraint_names[USM_CONSTRAINT_COUNT] = {"
    c += ", ".join(f'"{w}"' for w, _ in CONSTRAINTS) + "};\n\n"
    c += "const usm_constraint usm_param_constraints[USM_NPARAMS] = {\n"
    c += "".join(f"    USM_CONSTRAINT_{cons.upper()}, /* {name} */\n"
                 for name, _, _, cons in PARAMETERS) + "};\n\n"
    c += "const double usm_param_defaults[USM_NPARAMS] = {\n"
    c += "".join(f"    {value!r}, /* {name} [{unit}]: {source} */\n"
                 for name, unit, _, value, source, _ in defaults()) + "};\n\n"
    c += "const usm_param_range usm_param_ranges[USM_NPARAMS] = {\n"
    c += "".join(f"    {{{lo!r}, {hi!r}}}, /* {name} [{unit}] */\n"
                 for name, unit, lo, hi in ranges()) + "};\n\n"
    c += ("const int usm_param_imperfections[USM_NIMPERFECTIONS] = {"
          + ", ".join(f"USM_P_{nm}" for nm in IMPERFECTIONS) + "};\n\n")
    c += f"const usm_param_coupling usm_param_couplings[{max(len(cs), 1)}] = {{\n"
    c += "".join(f'    {{USM_P_{p}, USM_P_{e}, "{a}={ch}", "{b}"}},\n' for a, ch, p, e, b in cs)
    if not cs:
        c += "    {-1, -1, \"\", \"\"},\n"
    c += "};\n\n"
    c += ("const usm_param_coupling *usm_param_coupled(const usm_model *m, int k)\n"
          "{\n"
          "    if (k < 0 || k >= USM_NPARAMS || !m->param_coupling || m->param_coupling[k] < 0)\n"
          "        return NULL;\n"
          "    return &usm_param_couplings[m->param_coupling[k]];\n"
          "}\n\n"
          "void usm_params_couple(const usm_model *m, usm_params *p, int k)\n"
          "{\n"
          "    for (int j = 0; j < USM_NPARAMS; ++j) {\n"
          "        const usm_param_coupling *c = usm_param_coupled(m, j);\n"
          "        if (c && (k < 0 || c->equals == k))\n"
          "            *(double *)((char *)p + usm_param_table[j].offset) =\n"
          "                *(const double *)((const char *)p + usm_param_table[c->equals].offset);\n"
          "    }\n"
          "}\n")
    for short, enum, _, names in _output_lists():
        c += f"\nconst usm_output_info usm_{short}_outputs[{enum}_COUNT] = {{\n"
        c += "".join(f'    {{"{nm}", "{OUTPUT_UNITS[nm]}"}},\n' for nm in names) + "};\n"
    return c


def common_files(models, files, banner_of):
    """usm_contracts.{h,c}; models: (name, assumptions) of every generated model,
    files: the emitted files (checked against the couplings)."""
    check_models(models, files)
    naming = ["The parameters, outputs and constraints the runtime knows, by index,",
              "with their names and units as tables, and the parameter couplings the",
              "assumptions imply.  Naming:",
              "  USM_P_<name>          parameter <name> (the usm_params field as spelled,",
              "                        case kept: c_R and c_r are two parameters)",
              "  USM_CONSTRAINT_<WORD> admissible sign (usm_param_info.constraint)",
              "  usm_<kernel>_outputs  name and unit of each output, indexed by the",
              "                        USM_OUT_, USM_STEADY_, USM_SEED_, USM_POWER_ and",
              "                        USM_DESIGN_ enums of usm_kernels.h",
              "Thread safety: read-only data and pure functions."]
    return {"usm_contracts.h": contracts_h(banner_of(
                "usm_contracts.h: parameters, outputs, constraints and couplings by index.",
                naming)),
            "usm_contracts.c": contracts_c(banner_of(
                "usm_contracts.c: the tables of usm_contracts.h.", []))}
