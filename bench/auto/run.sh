#!/bin/bash
# The 3-DOF load branch (T = 0 to theta = 0) followed by AUTO-07p, per-point
# CPU time, paired with bench_cont (usm) on the same machine.
#
# AUTO-07p is NOT a dependency of usm: this script is not part of the build
# or of ctest.  It needs the Debian package auto-07p (/usr/bin/auto-07p,
# /usr/lib/auto-07p, /usr/include/auto_f2c.h), gfortran, and a usm build
# (libusm.so, bench_cont).  Offline: nothing is downloaded.
#
# Usage: bench/auto/run.sh [build-dir [pairs]]   (defaults: build, 5)
# Prints, per run, AUTO's continuation points (the last PT of its b-file,
# fort.7) and its CPU per point (from the first to the last point, timed
# inside the user file's pvls, which AUTO calls twice a point: start-up and
# output files excluded), then bench_cont's lines; the runs alternate, AUTO
# then usm, `pairs` times, each side the best of 3 runs.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
top=$(cd "$here/../.." && pwd)
build=$(cd "${1:-$top/build}" && pwd)
pairs=${2:-5}
AUTO_DIR=${AUTO_DIR:-/usr/lib/auto-07p}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# The user file with the generated kernels, linked against libusm for the
# start at T = 0 (usm_steady_solve) only.
cc_flags=(-O2 -I/usr/include -I"$top/runtime/include/usm" -I"$top/generated" -I"$top/runtime")
gcc "${cc_flags[@]}" -c "$here/usm3dof.c" -o "$work/usm3dof.o"
gcc -O2 -I"$top/generated" -c "$top/generated/usm_3dof.c" -o "$work/usm_3dof.o"
gfortran -O2 -fopenmp "$work/usm3dof.o" "$work/usm_3dof.o" "$AUTO_DIR"/lib/*.o \
    -L"$AUTO_DIR/lib" -lauto_c -L"$build" -lusm -Wl,-rpath,"$build" -lm -o "$work/usm3dof.exe"

# AUTO's step: arclength in its own norm; a first run at DS0 counts the
# points, and DS is rescaled for 1,002.
run_auto() { # ds -> "points cpu_ms us_per_point"; leaves fort.7 in $work
    sed "s/DS_VALUE/$1/g" "$here/c.usm3dof" > "$work/c.in"
    local line
    line=$(cd "$work" && rm -f fort.7 fort.8 fort.9 &&
        OMP_NUM_THREADS=1 ./usm3dof.exe < c.in 2>&1 >/dev/null | grep '^auto-07p:')
    local pts
    pts=$(awk '$1 != 0 && $2 ~ /^-?[0-9]+$/ { n = $2 < 0 ? -$2 : $2 } END { print n }' "$work/fort.7")
    echo "$line" | awk -v n="$pts" '{ printf "%d %.3f %.2f\n", n, $4, $4 * 1e3 / (n - 1) }'
}
ds0=1e-5
n0=$(run_auto $ds0 | awk '{print $1}')
ds=$(awk -v d=$ds0 -v n=$n0 'BEGIN { printf "%.6e", d * (n - 1) / 1001 }')
echo "AUTO-07p: DS = $ds (from $n0 points at DS = $ds0); its last point:"
run_auto "$ds" >/dev/null
tail -1 "$work/fort.7"
echo
for ((k = 1; k <= pairs; ++k)); do
    echo "pair $k"
    # each side the best of 3 runs
    for r in 1 2 3; do run_auto "$ds"; done | sort -k2 -g | head -1 |
        awk '{ printf "%-48s %8d %12.3f %9.2f us\n", "AUTO-07p: continuation points", $1, $2, $3 }'
    "$build/bench/bench_cont" 3 | tail -4
done
