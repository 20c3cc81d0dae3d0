#!/usr/bin/env bash
# The build derives only what changed (derive/generate.py;
# docs/changing-an-assumption.md, "What is derived"), on a copy of derive/ and
# generated/ without a derivation cache, as a fresh clone has them:
#  1. derive/ as generated/ was generated from: generated/ is copied, no
#     model derived and sympy not even imported;
#  2. one parameter default changed: still no model derived; the new default
#     in usm_contracts.c and in the documents' parameter tables; every model's
#     own files as committed, and usm_kernels.h and usm_contracts.h (which every
#     source includes) too, so that the rebuild compiles a few files only.
# With "sharing" (a minute of CPU), instead: generated/DIGESTS claims that
# 3dof_twist_integrated changed; it is derived, and so are the models that
# call its kernels (3dof_imperfect, 3dof_imperfect_unilateral), since their
# sources in generated/ may no longer hold; the files must come out as
# committed (nothing changed in fact), DIGESTS included.
# Usage: derive_reuse.sh SOURCE_DIR PYTHON [sharing]
set -euo pipefail
src=$1
py=$2
what=${3:-defaults}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cp -r "$src/derive" "$src/generated" "$tmp/"
rm -rf "$tmp/derive/.cache"
cd "$tmp"
fail() { echo "derive_reuse: $*"; exit 1; }
nmodels=$(ls generated/usm_*_equations.json | wc -l)

if [ "$what" = sharing ]; then
    "$py" - <<'PY'
import json
p = "generated/DIGESTS"
s = open(p).read()
m = json.loads(s)
# another digest of all inputs (no fast path) and of one model
s = s.replace(m["input_digest"], "1" * 64)
s = s.replace(next(e["digest"] for e in m["models"] if e["name"] == "3dof_twist_integrated"),
              "0" * 64)
open(p, "w").write(s)
PY
    "$py" derive/generate.py --out out3 --cache cache 2> log3 || { cat log3; fail "generate.py failed"; }
    cat log3
    derived=$(sed -n 's/^  \([a-z0-9_]*\): derived in .*/\1/p' log3 | sort | tr '\n' ' ')
    [ "$derived" = "3dof_imperfect 3dof_imperfect_unilateral 3dof_twist_integrated " ] ||
        fail "derived: $derived; wanted 3dof_twist_integrated and the two models calling its kernels"
    for f in "$src"/generated/*; do
        cmp -s "$f" "out3/$(basename "$f")" || fail "$(basename "$f") differs from the committed"
    done
    echo "derive_reuse: a changed model and the models calling its kernels derived; every file as committed"
    exit 0
fi

# 1. unchanged: a copy, no sympy
PYTHONPROFILEIMPORTTIME=1 "$py" derive/generate.py --out out1 --cache cache 2> log1 ||
    { cat log1; fail "generate.py failed on the unchanged tree"; }
grep -q "no model derived" log1 || { cat log1; fail "unchanged tree: not the fast path"; }
if grep -qE '\| +sympy$' log1; then fail "unchanged tree: sympy was imported"; fi
diff -r out1 generated > /dev/null || fail "unchanged tree: the copy differs from generated/"
echo "derive_reuse: unchanged derive/: generated/ copied, sympy not imported"

# 2. a changed default: nothing derived
sed -i 's/^    "d_R": (0\.1632, /    "d_R": (0.17, /' derive/usm_derive/defaults.py
grep -q '"d_R": (0.17, ' derive/usm_derive/defaults.py || fail "cannot change the default of d_R"
"$py" derive/generate.py --out out2 --cache cache 2> log2 || { cat log2; fail "generate.py failed"; }
cat log2
if grep -q "derived in" log2; then fail "a changed default derived a model"; fi
[ "$(grep -c ': unchanged (generated/' log2)" -eq "$nmodels" ] ||
    fail "not all $nmodels models taken from generated/"
grep -qE '^    0\.17, /\* d_R ' out2/usm_contracts.c || fail "usm_contracts.c lacks the new default of d_R"
grep -q '0\.17' out2/usm_3dof_equations.md || fail "the 3dof document lacks the new default"
for f in generated/usm_*.h generated/usm_*.c generated/usm_*_equations.json; do
    n=$(basename "$f")
    case $n in usm_contracts.c|usm_kernels.c|usm_equations.c) continue ;; esac
    cmp -s "$f" "out2/$n" || fail "$n changed with a parameter default"
done
echo "derive_reuse: changed default: no model derived; usm_contracts.c, usm_kernels.c, usm_equations.c and the documents rendered again"
