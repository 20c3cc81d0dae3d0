#!/bin/bash
# AUTO-07p's two-parameter continuation of the 3-DOF model's fold in (f, m0):
# the reference that tests/envelope/test_envelope_auto.c compares usm's
# envelope fold curve with (tests/envelope/auto_reference/fold_f_m0.csv).
#
# AUTO-07p is NOT a dependency of usm: this script is not part of the build
# or of ctest; the CSV it writes is committed and is the reference.  It needs
# the Debian package auto-07p (/usr/bin/auto-07p, /usr/lib/auto-07p,
# /usr/include/auto_f2c.h), gfortran and a usm build (libusm.so, for the
# start point only).  Offline: nothing is downloaded.
#
# Usage: bench/auto/reference.sh [build-dir [out-dir]]
#   (defaults: build, tests/envelope/auto_reference)
# Run 1 follows the stationary branch at m0 = 50 N m in f to its limit point
# (LP); run 2 continues that LP in (f, m0) both ways (ISW = 2): up to
# m0 = 100 N m, and down through the cusp (CP) to a tilt of 1 rad.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
top=$(cd "$here/../.." && pwd)
build=$(cd "${1:-$top/build}" && pwd)
out=${2:-$top/tests/envelope/auto_reference}
AUTO_DIR=${AUTO_DIR:-/usr/lib/auto-07p}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$out"

cc_flags=(-O2 -I/usr/include -I"$top/runtime/include/usm" -I"$top/generated" -I"$top/runtime")
gcc "${cc_flags[@]}" -c "$here/usm3dof_fold.c" -o "$work/fold.o"
gcc -O2 -I"$top/generated" -c "$top/generated/usm_3dof.c" -o "$work/usm_3dof.o"
gfortran -O2 -fopenmp "$work/fold.o" "$work/usm_3dof.o" "$AUTO_DIR"/lib/*.o \
    -L"$AUTO_DIR/lib" -lauto_c -L"$build" -lusm -Wl,-rpath,"$build" -lm -o "$work/fold.exe"

# run 1: the branch in f to its LP; fort.8 holds the LP's solution
cp "$here/c.usm3dof_fold.1" "$work/c.in"
(cd "$work" && OMP_NUM_THREADS=1 ./fold.exe < c.in > run1.log 2>&1)
cp "$work/fort.7" "$work/b.1"
cp "$work/fort.8" "$work/s.1"
lp=$(awk '$1 != 0 && $3 == 2 { print $4; exit }' "$work/b.1")
[ -n "$lp" ] || { echo "reference.sh: no limit point in run 1" >&2; exit 1; }

# run 2, both ways from the LP: AUTO reads the start from fort.3
for dir in fwd bwd; do
    sign=""; [ $dir = bwd ] && sign="-"
    sed -e "s/LP_LABEL/$lp/" -e "s/DS_SIGN/$sign/" "$here/c.usm3dof_fold.2" > "$work/c.in"
    (cd "$work" && cp s.1 fort.3 && rm -f fort.7 fort.8 fort.9 &&
        OMP_NUM_THREADS=1 ./fold.exe < c.in > run2_$dir.log 2>&1)
    cp "$work/fort.7" "$work/b.2$dir"
done

version=$(dpkg-query -W -f='${Version}' auto-07p 2>/dev/null || echo unknown)
# The b-file's rows: BR PT TY LAB PAR(1) L2-NORM U(1) U(2) PAR(2); a
# labelled point's type is named as AUTO names it in its run log (LP, BT, CP,
# UZ, EP; BT: r_u has a double zero eigenvalue, which for this residual,
# not an ODE, is no Bogdanov-Takens point).  The backward run (DS < 0) is
# written in reverse, so the CSV runs along the curve from m0 = 100 N m on
# one side to m0 = 100 N m on the other.  Its first point ("start") is run
# 1's LP as AUTO located it (to EPSS = 1e-6) and not corrected: no point of
# the fold curve (det r_u = -2.3 there, 1e-6 at its neighbours).
rows() { # b-file run-log -> "type f m0 theta alpha" per point
    awk 'FNR == NR { if ($1 ~ /^[0-9]+$/ && $3 ~ /^[A-Z][A-Z]$/) name[$4] = $3; next }
         $1 != 0 && NF == 9 && !($5 == lf && $9 == lm) {
             t = ($4 != 0 && ($4 in name)) ? name[$4] : "-"
             if (!started++) t = "start"
             print t, $5, $9, $7, $8; lf = $5; lm = $9 }' "$2" "$1"
}
{
    echo "# AUTO-07p $version: the fold of the 3-DOF model (paper parameters) in (f, m0),"
    echo "# continued by AUTO (ISW = 2) from the limit point of the branch in f at m0 = 50 N m."
    echo "# Made by: bench/auto/reference.sh (user file bench/auto/usm3dof_fold.c,"
    echo "# constants bench/auto/c.usm3dof_fold.1, c.usm3dof_fold.2) on $(date -u +%Y-%m-%d)."
    echo "# EPSL = EPSU = 1e-12; AUTO's labels in 'type' (CP the cusp; UZ the ends at m0 = 100 N m; '-' none;"
    echo "# 'start': run 1's LP located to EPSS = 1e-6, the start of run 2, not a point of the curve)."
    echo "type,f [Hz],m0 [N m],theta [rad],alpha [rad]"
    { rows "$work/b.2bwd" "$work/run2_bwd.log" | tac; rows "$work/b.2fwd" "$work/run2_fwd.log" | tail -n +2; } |
        awk '{ printf "%s,%.10e,%.10e,%.10e,%.10e\n", $1, $2, $3, $4, $5 }'
} > "$out/fold_f_m0.csv"
echo "wrote $out/fold_f_m0.csv ($(grep -vc '^#' "$out/fold_f_m0.csv") lines)"
grep -E '^(CP|LP|BT|ZH)' "$out/fold_f_m0.csv" || true
