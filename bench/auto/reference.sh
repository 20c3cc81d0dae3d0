#!/bin/bash
# AUTO-07p's two-parameter continuation of the 3-DOF model's fold in (f, m0)
# and of the Hopf point of twist_integrated in (f, T): the references that
# tests/envelope/test_envelope_auto.c compares usm's envelope curves with
# (tests/envelope/auto_reference/fold_f_m0.csv, stability_f_T.csv).
#
# AUTO-07p is NOT a dependency of usm: this script is not part of the build
# or of ctest; the CSV it writes is committed and is the reference.  It needs
# the Debian package auto-07p (/usr/bin/auto-07p, /usr/lib/auto-07p,
# /usr/include/auto_f2c.h), gfortran and a usm build (libusm.so, for the
# start point only).  Offline: nothing is downloaded.
#
# Usage: bench/auto/reference.sh [build-dir [out-dir]]
#   (defaults: build, tests/envelope/auto_reference)
# Each curve is two AUTO runs: run 1 follows a stationary branch in one
# parameter to its limit point (LP) or Hopf point (HB); run 2 continues that
# point in two parameters (ISW = 2) both ways.  Fold: the branch at
# m0 = 50 N m in f; its LP continued in (f, m0) up to m0 = 100 N m, and down
# through the cusp (CP) and up again to m0 = 100 N m at a tilt of 1.03 rad.
# Stability: the branch of twist_integrated at f = 37.5 kHz in T; its HB
# continued in (f, T) to f = 35 kHz and 40 kHz.  The user files and the
# constants files say why each constant is what it is.
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
build_exe() { # user-file kernels-file exe [more objects]
    gcc "${cc_flags[@]}" -c "$here/$1" -o "$work/$3.o"
    gcc -O2 -I"$top/generated" -c "$top/generated/$2" -o "$work/$3_kernels.o"
    gfortran -O2 -fopenmp "$work/$3.o" "$work/$3_kernels.o" ${4:-} "$AUTO_DIR"/lib/*.o \
        -L"$AUTO_DIR/lib" -lauto_c -L"$build" -lusm -Wl,-rpath,"$build" -lgsl -lgslcblas -lm \
        -o "$work/$3.exe"
}
build_exe usm3dof_fold.c usm_3dof.c fold
# the Hopf problem's linearisation in long double (usm3dof_hopf.c says why):
# the generated kernels with every double a long double, prefix ld_
sed -e 's/double/long double/g' -e 's/usm_3dof_twist_integrated_/ld_/g' \
    -e 's/#include "usm_3dof_twist_integrated.h"/#include "usm_kernels.h"\n#include <tgmath.h>/' \
    -e '/#include "usm_3dof.h"/d' -e '/^static const char \*const state_names/,$d' \
    "$top/generated/usm_3dof_twist_integrated.c" > "$work/ld_kernels.c"
gcc -O2 -w -I"$top/generated" -I"$top/runtime/include/usm" -c "$work/ld_kernels.c" -o "$work/ld_kernels.o"
build_exe usm3dof_hopf.c usm_3dof_twist_integrated.c hopf "$work/ld_kernels.o"

# two_runs EXE CONSTANTS TYPE: run 1, then run 2 both ways from the first
# point of type TYPE (AUTO's numeric type in the b-file: 2 LP, 3 HB); leaves
# b.EXE.fwd, b.EXE.bwd and their logs in $work
two_runs() {
    cp "$here/c.$2.1" "$work/c.in"
    (cd "$work" && rm -f fort.7 fort.8 fort.9 &&
        OMP_NUM_THREADS=1 ./$1.exe < c.in > $1.run1.log 2>&1)
    local lab
    lab=$(awk -v t="$3" '$1 != 0 && $3 == t { print $4; exit }' "$work/fort.7")
    [ -n "$lab" ] || { echo "reference.sh: $1: no point of type $3 in run 1" >&2; exit 1; }
    cp "$work/fort.8" "$work/s.$1"
    for dir in fwd bwd; do
        local sign=""; [ $dir = bwd ] && sign="-"
        sed -e "s/START_LABEL/$lab/" -e "s/DS_SIGN/$sign/" "$here/c.$2.2" > "$work/c.in"
        (cd "$work" && cp s.$1 fort.3 && rm -f fort.7 fort.8 fort.9 &&
            OMP_NUM_THREADS=1 ./$1.exe < c.in > $1.run2_$dir.log 2>&1)
        cp "$work/fort.7" "$work/b.$1.$dir"
    done
}
two_runs fold usm3dof_fold 2
two_runs hopf usm3dof_hopf 3

version=$(dpkg-query -W -f='${Version}' auto-07p 2>/dev/null || echo unknown)
# A b-file's rows after its header line (BR PT TY LAB PAR(1) L2-NORM U(1) ...
# PAR(2)); a labelled point's type is named as AUTO names it in its run log.
# The first point of run 2 ("start") is run 1's LP or HB as AUTO located it
# (to EPSS = 1e-6) and not corrected: no point of the curve (for the fold
# det r_u = -2.3 there, 1e-6 at its neighbours).  The backward run (DS < 0)
# is written in reverse, so the CSV runs along the curve from end to end.
rows() { # b-file run-log y-scale theta-scale -> "type x y theta alpha" per point
    awk -v ys="$3" -v ts="$4" '
        FNR == NR { if ($1 ~ /^[0-9]+$/ && $3 ~ /^[A-Z][A-Z]$/) name[$4] = $3; next }
        $1 == 0 && $3 == "TY" { for (i = 1; i <= NF; ++i) col[$i] = i; next }
        $1 != 0 && ("PAR(2)" in col) {
            x = $(col["PAR(1)"]); y = $(col["PAR(2)"])
            if (x == lx && y == ly) next
            t = ($4 != 0 && ($4 in name)) ? name[$4] : "-"
            if (!started++) t = "start"
            printf "%s,%.10e,%.10e,%.10e,%.10e\n", t, x, y * ys, $(col["U(1)"]) * ts, $(col["U(2)"])
            lx = x; ly = y }' "$2" "$1"
}
curve() { # exe -> the CSV rows along the curve
    rows "$work/b.$1.bwd" "$work/$1.run2_bwd.log" "$2" "$3" | tac
    rows "$work/b.$1.fwd" "$work/$1.run2_fwd.log" "$2" "$3" | tail -n +2
}
made="# Made by: bench/auto/reference.sh on $(date -u +%Y-%m-%d) with AUTO-07p $version (Debian package auto-07p)"
{
    echo "# AUTO-07p: the fold of the 3-DOF model (paper parameters) in (f, m0), continued"
    echo "# by AUTO (ISW = 2) from the limit point of the branch in f at m0 = 50 N m."
    echo "$made;"
    echo "# user file bench/auto/usm3dof_fold.c, constants c.usm3dof_fold.1, c.usm3dof_fold.2."
    echo "# EPSL = EPSU = 1e-12.  'type': AUTO's label (CP the cusp; UZ the ends at m0 = 100 N m;"
    echo "# BT: r_u has a double zero eigenvalue, no Bogdanov-Takens point of this residual,"
    echo "# which is no ODE; '-' none; 'start': run 1's LP located to EPSS = 1e-6, the start of"
    echo "# run 2, not a point of the curve)."
    echo "type,f [Hz],m0 [N m],theta [rad],alpha [rad]"
    curve fold 1 1
} > "$out/fold_f_m0.csv"
{
    echo "# AUTO-07p: the stability boundary of the 3-DOF model, variant twist_integrated"
    echo "# (paper parameters), in (f, T): AUTO's Hopf point of the stationary solution in the"
    echo "# frame turning with the excitation (the constant linearisation's eigenvalue pair on"
    echo "# the imaginary axis), continued by AUTO (ISW = 2) from the HB of the branch in T at"
    echo "# f = 37.5 kHz to f = 35 kHz and 40 kHz."
    echo "$made;"
    echo "# user file bench/auto/usm3dof_hopf.c, constants c.usm3dof_hopf.1, c.usm3dof_hopf.2."
    echo "# EPSL = EPSU = 1e-12.  'type': AUTO's label (UZ the ends; GH: AUTO's first Lyapunov"
    echo "# coefficient changes sign, noise here, the linearisation's part of the problem is"
    echo "# linear; '-' none; 'start': run 1's HB located to EPSS = 1e-6, not a point of the curve)."
    echo "type,f [Hz],T [N m],theta [rad],alpha [rad]"
    curve hopf 1e-3 1e-4
} > "$out/stability_f_T.csv"
for f in fold_f_m0 stability_f_T; do
    echo "wrote $out/$f.csv ($(grep -vc '^#' "$out/$f.csv") lines)"
done
grep -h -E '^(CP|UZ)' "$out/fold_f_m0.csv" "$out/stability_f_T.csv" || true
