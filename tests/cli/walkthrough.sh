#!/usr/bin/env bash
# Performs docs/changing-an-assumption.md on a copy of the tree: the two lines
# the document tells the user to add are read from the document itself.
# Usage: walkthrough.sh SOURCE_DIR
set -euo pipefail
src=$1
doc=$src/docs/changing-an-assumption.md
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# the first ```python block after each step heading
block() { awk -v step="$1" '$0 ~ "^## " step {f=1} f && /^```python/ {p=1; next} p && /^```/ {exit} p {print}' "$doc"; }
law=$(block "Step 1")
variant=$(block "Step 2")
[ -n "$law" ] && [ -n "$variant" ] || { echo "walkthrough: cannot find the code blocks in $doc"; exit 1; }

# a copy of the tree as a user has it: the tracked and new files, no build dirs
(cd "$src" && git ls-files --cached --others --exclude-standard -z) |
    (cd "$src" && xargs -0 cp --parents -t "$tmp" 2>/dev/null || true)
# and the derivation cache of earlier builds, as a user's tree has it
# (derive/.cache: each model's output under the digest of its inputs; only the
# new variant is derived then)
if [ -d "$src/derive/.cache" ]; then cp -r "$src/derive/.cache" "$tmp/derive/"; fi
cd "$tmp"
LAW="$law" VARIANT="$variant" python3 - <<'PY'
import os, re
p = "derive/variants.py"
s = open(p).read()
s = s.replace("FRICTION_LAWS = {\n", "FRICTION_LAWS = {\n" + os.environ["LAW"] + "\n", 1)
# at the end of VARIANTS, after "imperfect", as the document says
at = s.index("\n}\n", s.index("VARIANTS = {\n")) + 1
s = s[:at] + os.environ["VARIANT"] + "\n" + s[at:]
open(p, "w").write(s)
PY
# Ninja where it is installed (the document's steps are cmake --build, the same
# with either generator): the whole tree's build took 67 instead of 111
# CPU-seconds, the Makefiles' dependency scanning and recursive make gone
# (measured side by side; the compiler's own CPU, 45 s, is the same)
generator=()
if command -v ninja >/dev/null; then generator=(-G Ninja); fi
# Debug: the steps are the document's whatever the build type, and the whole
# tree (library, command, every test, the Python module) compiles at -O0 in
# 2.4 times less CPU than at the default's -O2; with the tests below slower,
# the walkthrough took 156 CPU-seconds instead of 181 (measured side by side).
# Without -g: nobody debugs this copy, and debug information is a third of the
# compile's CPU (the library and command: 55 -> 38 CPU-seconds)
# The kernels at -O0 as well (USM_KERNEL_FLAGS empty): 3 instead of 18 CPU-seconds
# of compiling them, the tests below no slower for it
cmake -S . -B build "${generator[@]}" -DUSM_REGENERATE=ON -DUSM_KERNEL_FLAGS= -DUSM_BUILD_TESTS=ON -DCMAKE_BUILD_TYPE=Debug \
      -DCMAKE_C_FLAGS_DEBUG=-O0 > cmake.log
# step 3, as documented
start=$(date +%s)
cmake --build build --target generate && cmake --build build -j2 > build.log
echo "walkthrough: regenerated and rebuilt in $(( $(date +%s) - start )) s"
test -f generated/usm_4dof_friction_rational.c
grep -q '^friction_rational ' <<< "$(build/usm variants)"
out=$(build/usm steady --model 4dof --variant friction_rational --json)
paper=$(build/usm steady --model 4dof --json)
OUT="$out" PAPER="$paper" python3 -c '
import json, os
r, a = json.loads(os.environ["OUT"]), json.loads(os.environ["PAPER"])
assert r["converged"], r
assert r["model"] == "4dof_friction_rational", r["model"]
assert r["residual_norm"] < 1e-12, r["residual_norm"]
# Stable, for a reason independent of the new code: the paper finds its 4dof
# stationary solution stable at these parameters (tests/solve/steady_paper_check.py; usm
# gives max |lambda| 0.865), and at the operating point, x = kappa |v_rel| ~ 0.11,
# the new law mu0 x/sqrt(1 + x^2) and the paper s mu0 atan(x) have the slopes
# mu0 (1 + x^2)^(-3/2) and mu0/(1 + x^2): 0.6 % apart, so the stationary
# solution and its multipliers are nearly the paper s.
x = r["parameters"]["kappa"] * abs(r["v_rel"])
assert x < 0.2, "kappa |v_rel| = %g: the two laws are no longer alike there" % x
assert a["floquet"]["stable"] is True, a["floquet"]   # the paper: stable
assert r["floquet"]["stable"] is True, r["floquet"]
# (the variant friction_tanh, as close to atan there, moves max |lambda| by 2e-6): 1e-3
assert abs(r["floquet"]["max_modulus"] - a["floquet"]["max_modulus"]) < 1e-3, \
    (r["floquet"]["max_modulus"], a["floquet"]["max_modulus"])
print("friction_rational: theta %.6e, rotor speed %.6f 1/s, max |lambda| %.6f (paper law %.6f), "
      "kappa |v_rel| %.3f: stable, as the paper s model"
      % (r["theta"], r["rotor_speed"], r["floquet"]["max_modulus"], a["floquet"]["max_modulus"], x))'
# every kernel test, on every model including the new one (its friction law
# taken from its generated friction kernel)
ctest --test-dir build -R '^(kernel_jacobians|kernel_energy|kernel_momentum|steady_floquet|generated_current|equations_proof)$' \
      --output-on-failure
grep -q 'friction_rational' <<< "$(build/tests/test_kernels_energy energy)"
# its equations: the changed friction law (5.2) is what differs from the paper's model
grep -qF '\tag{5.2}' <<< "$(build/usm equations --model 4dof --variant friction_rational --diff)"
echo "walkthrough: the documented steps build and solve the new variant"
