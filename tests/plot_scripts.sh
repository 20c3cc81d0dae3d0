#!/bin/bash
# The static gnuplot scripts of `usm sweep --plot` and `usm map --plot`
# (data/plots/sweep.gp, map.gp) on the CSV files those commands write: each
# draws a PNG and an SVG, addresses the columns by name, and gnuplot reports
# no error or warning.  (The report's scripts are run by report_check.py and
# simulate.gp by simulate_cli.sh.)  Exit 77 without gnuplot.
#
# usage: plot_scripts.sh PATH/TO/usm
set -u

USM=${1:?usage: plot_scripts.sh PATH/TO/usm}
. "$(dirname "$0")/cli_common.sh"
plots=$(cd "$(dirname "$0")/../data/plots" && pwd)
command -v gnuplot >/dev/null || { echo "SKIP: gnuplot not found"; exit 77; }

draw() { # NAME SCRIPT ASSIGNMENTS
    checks=$((checks + 1))
    (cd "$tmp" && gnuplot -e "$3" "$plots/$2" >"$tmp/$1.log" 2>&1) ||
        { fail "$2 on $1.csv: gnuplot failed: $(head -c 300 "$tmp/$1.log")"; return; }
    [ -s "$tmp/$1.png" ] && [ -s "$tmp/$1.svg" ] || fail "$2 on $1.csv: no PNG or SVG"
    ! grep -qiE 'warning|error' "$tmp/$1.log" || fail "$2 on $1.csv: $(head -c 300 "$tmp/$1.log")"
}

if expect_rc 0 sweep --over T --from 0 --to 0.008 --points 41; then
    cp "$out" "$tmp/torque.csv"
    draw torque sweep.gp "prefix='torque'; xcol='T [N m]'"
fi
if expect_rc 0 sweep --model 4dof --over f --from 35000 --to 39000 --points 9; then
    cp "$out" "$tmp/freq.csv"
    draw freq sweep.gp "prefix='freq'; xcol='f [Hz]'"
fi
# (the map's CSV may still hold "nan" for missing values: not checked here)
checks=$((checks + 1))
if run map --x-points 5 --y-points 4; then
    cp "$out" "$tmp/grid.csv"
    draw grid map.gp "prefix='grid'; xcol='f'; ycol='T'"
else
    fail "usm map exited $?"
fi

finish plot_scripts
