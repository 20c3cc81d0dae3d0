#!/usr/bin/env bash
# Do the tests notice when the physics is wrong?
#   mutation.sh SOURCE_DIR C_COMPILER
# Copies the tree, builds the kernel and solver tests once (committed
# generated/, REGENERATE=OFF), checks that they pass, then injects one error at
# a time into a paper model's generated kernels, rebuilds and requires at
# least two of the tests to fail:
#   rhs:  f_i += 1e-3 m0 in the tilt row (i = <MODEL>_X_THETADOT), a torque
#         error of 1e-3 of the paper's excitation amplitude m0 = 5e-3 N m;
#   mass: M_ij += 1e-3 m0 / Omega in the tilt row and the column of phi
#         (j = <MODEL>_X_PHI): on the stationary orbit, where phi' = Omega,
#         again a torque error of 1e-3 m0 (the paper's m0 and Omega = 2 pi
#         37 kHz), now made by the mass-matrix kernel;
# for the 3dof and 4dof models.  The error is a constant, so it is present
# whatever parameters a test uses.
set -euo pipefail
src=$(cd "$1" && pwd)
cc=${2:-cc}
tmp=$(mktemp -d "${TMPDIR:-/tmp}/usm-mutation.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

mkdir "$tmp/src"
tar -C "$src" --exclude='./build*' --exclude=./.git --exclude=./derive/.cache \
    --exclude=./report --exclude=./out -cf - . | tar -C "$tmp/src" -xf -
build=$tmp/build
targets=(test_steady_floquet test_kernels_energy test_simulate)
tests='^(steady_floquet|kernel_energy|kernel_momentum|simulate_transient)$'
ntests=4

# Ninja where it is installed: the same objects as with Makefiles, without
# their per-target dependency scanning and recursive make (the walkthrough's
# build of the whole tree: 111 -> 67 CPU-seconds, measured side by side)
generator=()
if command -v ninja >/dev/null; then generator=(-G Ninja); fi

echo "== configure and build ${targets[*]} (REGENERATE=OFF${generator[*]:+, ${generator[*]}})"
# Debug (-O0): the library compiles in less CPU than at -O2 and the four tests
# are short, so the whole check takes 106 instead of 128 CPU-seconds (measured
# side by side); the error the tests must notice does not depend on it.  No -g
# either: debug information is a third of the compile's CPU.  The kernels too
# at -O0 (USM_KERNEL_FLAGS empty): the first build 32 -> 18 CPU-seconds, each
# mutant's 1.8 -> 1.1, and the four tests no slower (3.6 s a round)
cmake -S "$tmp/src" -B "$build" "${generator[@]}" -DUSM_REGENERATE=OFF -DUSM_KERNEL_FLAGS= \
      -DCMAKE_BUILD_TYPE=Debug -DCMAKE_C_FLAGS_DEBUG=-O0 \
      -DCMAKE_C_COMPILER="$cc" \
      > "$tmp/configure.log" 2>&1 || { cat "$tmp/configure.log"; fail "configure"; }
rebuild() {
    cmake --build "$build" -j2 --target "${targets[@]}" > "$tmp/build.log" 2>&1 ||
        { tail -n 30 "$tmp/build.log"; fail "build ($1)"; }
}
run_tests() {  # prints the number of failed tests
    local out
    out=$(ctest --test-dir "$build" -R "$tests" 2>&1 || true)
    local ran
    ran=$(printf '%s\n' "$out" | grep -c 'Test *#' || true)
    [ "$ran" -eq "$ntests" ] || { printf '%s\n' "$out" >&2; fail "expected $ntests tests, ran $ran"; }
    printf '%s\n' "$out" | grep -c '\*\*\*Failed\|\*\*\*Exception\|\*\*\*Timeout' || true
}
rebuild original
nfail=$(run_tests)
[ "$nfail" -eq 0 ] || fail "the unmodified tree fails $nfail of the tests"
echo "unmodified: all $ntests tests pass"

# inject FILE FUNCTION INDEX DELTA: out[INDEX] of FUNCTION gets + DELTA.
inject() {
    /usr/bin/env python3 - "$@" <<'EOF'
import re, sys
path, func, index, delta = sys.argv[1:]
text = open(path).read()
start = text.index(f"\nvoid {func}(")
end = text.index("\n}\n", start)
body = text[start:end]
pattern = re.compile(rf"^    out\[{index}\] = (.*);$", re.M)
if len(pattern.findall(body)) != 1:
    sys.exit(f"mutation.sh: no single out[{index}] in {func}")
body = pattern.sub(lambda m: f"    out[{index}] = ({m.group(1)}) + ({delta});", body)
open(path, "w").write(text[:start] + body + text[end:])
EOF
}

define() {  # define HEADER NAME: the value of #define NAME in HEADER
    sed -n "s/^#define $2 \([0-9]*\)$/\1/p" "$1"
}

m0=5e-3
omega=$(/usr/bin/env python3 -c 'import math; print(repr(2 * math.pi * 37e3))')
bad=0
for model in 3dof 4dof; do
    c=$tmp/src/generated/usm_$model.c
    h=$tmp/src/generated/usm_$model.h
    P=USM_$(echo "$model" | tr '[:lower:]' '[:upper:]')
    n=$(define "$h" "${P}_NX")
    row=$(define "$h" "${P}_X_THETADOT")
    col=$(define "$h" "${P}_X_PHI")
    [ -n "$n" ] && [ -n "$row" ] && [ -n "$col" ] || fail "$h: no ${P}_NX, _X_THETADOT or _X_PHI"
    cp "$c" "$tmp/original.c"
    for kind in rhs mass; do
        if [ "$kind" = rhs ]; then
            inject "$c" "usm_${model}_rhs" "$row" "1e-3 * $m0"
        else
            inject "$c" "usm_${model}_mass" "$((row * n + col))" "1e-3 * $m0 / $omega"
        fi
        rebuild "$model $kind"
        nfail=$(run_tests)
        echo "$model, error of 1e-3 m0 in the $kind kernel (row $row): $nfail of $ntests tests fail"
        if [ "$nfail" -lt 2 ]; then
            echo "FAIL: $model $kind: only $nfail test(s) notice the error" >&2
            bad=1
        fi
        cp "$tmp/original.c" "$c"
    done
done
[ "$bad" -eq 0 ] || exit 1
echo "mutation: every injected error fails at least two tests"
