#!/usr/bin/env bash
# bench/build_times.sh: what a build costs (docs/changing-an-assumption.md,
# "What a build costs").  On a copy of the tree (the user's files are not
# touched), in order:
#   1. fresh configure + build at -j2 of the unchanged tree (derive/ as the
#      committed generated/ was generated from: no model derived);
#   2. one parameter default changed in derive/usm_derive/defaults.py, then
#      `cmake --build` (regenerate + rebuild): no model derived either, the
#      documents and usm_contracts.c rendered again; `usm steady --json` must
#      then report the new default;
#   3. with FULL=1, the full derivation from scratch (derive/generate.py
#      --no-cache --no-reuse; minutes of CPU).
# Each step prints its wall and CPU seconds (/usr/bin/time).  The compiler
# runs without a launcher (no ccache): the figures are a fresh clone's.
#
# usage: bench/build_times.sh SOURCE_DIR [PARAM VALUE]   (default: d_R 0.17)
#        JOBS=2 FULL=1 KEEP=1 (keep the copy) to change the run
set -euo pipefail
src=$(cd "${1:?usage: build_times.sh SOURCE_DIR [PARAM VALUE]}" && pwd)
param=${2:-d_R}
value=${3:-0.17}
jobs=${JOBS:-2}
tmp=$(mktemp -d)
if [ -z "${KEEP:-}" ]; then trap 'rm -rf "$tmp"' EXIT; else echo "copy kept in $tmp"; fi
timed() {  # label, command...
    local label=$1; shift
    /usr/bin/time -f "$label: %e s wall, %U s user + %S s system CPU" "$@"
}

(cd "$src" && git ls-files --cached --others --exclude-standard -z) |
    (cd "$src" && xargs -0 cp --parents -t "$tmp")
cd "$tmp"
# a fresh clone has no derivation cache
rm -rf derive/.cache

timed "1. fresh configure" cmake -S . -B build -DUSM_REGENERATE=ON > configure.log
timed "1. fresh build -j$jobs" cmake --build build -j"$jobs" > build1.log
grep -E "no model derived|derived in" build1.log || true

PARAM=$param VALUE=$value python3 - <<'PY'
import os, re
p = "derive/usm_derive/defaults.py"
s = open(p).read()
name, value = os.environ["PARAM"], os.environ["VALUE"]
s, n = re.subn(r'(\n    "%s": \()[^,]+,' % re.escape(name), r"\g<1>%s," % value, s, count=1)
if n != 1:
    raise SystemExit(f"build_times.sh: no default of {name} in {p}")
open(p, "w").write(s)
PY
timed "2. changed default $param=$value: regenerate + rebuild -j$jobs" \
    cmake --build build -j"$jobs" > build2.log
grep -E "unchanged|derived in|wrote" build2.log || true
got=$(build/usm steady --json | python3 -c "import json, sys; print(json.load(sys.stdin)['parameters']['$param'])")
python3 -c "import sys; sys.exit(0 if abs(float('$got') - float('$value')) <= 1e-12 * abs(float('$value')) else 1)" ||
    { echo "build_times.sh: usm steady --json reports $param = $got, not the new default $value"; exit 1; }
echo "2. usm steady --json: $param = $got (the new default)"

if [ -n "${FULL:-}" ]; then
    timed "3. full derivation from scratch" \
        /usr/bin/python3 derive/generate.py --no-cache --no-reuse --out "$tmp/full" --quiet
fi
