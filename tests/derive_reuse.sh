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
# Usage: derive_reuse.sh SOURCE_DIR PYTHON
set -euo pipefail
src=$1
py=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cp -r "$src/derive" "$src/generated" "$tmp/"
rm -rf "$tmp/derive/.cache"
cd "$tmp"
fail() { echo "derive_reuse: $*"; exit 1; }
nmodels=$(ls generated/usm_*_equations.json | wc -l)

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
