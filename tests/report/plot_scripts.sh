#!/bin/bash
# The static gnuplot scripts of `usm sweep --plot` and `usm map --plot`
# (data/plots/sweep.gp, sweep_periodic.gp, map.gp) on the CSV files those
# commands write: each
# draws a PNG and an SVG, addresses the columns by name, and gnuplot reports
# no error or warning.  (The report's scripts are run by report_check.py and
# simulate.gp by simulate_cli.sh.)  Exit 77 without gnuplot.
#
# usage: plot_scripts.sh PATH/TO/usm
set -u

USM=${1:?usage: plot_scripts.sh PATH/TO/usm}
. "$(dirname "$0")/../cli_common.sh"
plots=$(cd "$(dirname "$0")/../../data/plots" && pwd)
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
checks=$((checks + 1))
if run map --x-points 5 --y-points 4; then
    cp "$out" "$tmp/grid.csv"
    draw grid map.gp "prefix='grid'; xcol='f [Hz]'; ycol='T [N m]'"
else
    fail "usm map exited $?"
fi

# ---- --plot PREFIX: the commands write PREFIX.csv/.gp and run gnuplot ---------
plotted() { # PREFIX: a non-empty PNG (by its signature) and SVG, the CSV and the script
    checks=$((checks + 1))
    [ -s "$tmp/$1.png" ] && [ "$(head -c 8 "$tmp/$1.png" | od -An -c | tr -d ' ')" = '211PNG\r\n032\n' ] ||
        { fail "--plot $1: no PNG"; return; }
    grep -q '<svg' "$tmp/$1.svg" 2>/dev/null || fail "--plot $1: no SVG"
    [ -s "$tmp/$1.csv" ] && [ -s "$tmp/$1.gp" ] || fail "--plot $1: no CSV or script"
    ! grep -qiE 'warning|error' "$tmp/$1.log" || fail "--plot $1: $(head -c 300 "$tmp/$1.log")"
}
sweep_plot=(sweep --over T --from 0 --to 0.008 --points 21 --no-floquet)
map_plot=(map --x-points 4 --y-points 3)
(cd "$tmp" && "$USM" "${sweep_plot[@]}" --plot tq >/dev/null 2>"$tmp/tq.err") ||
    fail "usm sweep --plot: exit $?: $(head -c 300 "$tmp/tq.err")"
plotted tq
# the CSV beside the plot is the one on stdout
checks=$((checks + 1))
(cd "$tmp" && "$USM" "${sweep_plot[@]}" >"$tmp/tq_stdout.csv") && cmp -s "$tmp/tq.csv" "$tmp/tq_stdout.csv" ||
    fail "usm sweep --plot: PREFIX.csv differs from the CSV on stdout"
(cd "$tmp" && "$USM" "${map_plot[@]}" --plot mp >/dev/null 2>"$tmp/mp.err") ||
    fail "usm map --plot: exit $?: $(head -c 300 "$tmp/mp.err")"
plotted mp
# the 4-DOF load sweep: speed in the driving direction, the events
# as labelled lines, the speed axis clipped before the divergence at the
# friction saturation (the speed reaches hundreds of 1/s there)
checks=$((checks + 1))
(cd "$tmp" && "$USM" sweep --model 4dof --over T --from 0 --to 0.001 --points 41 --plot s4 \
    >/dev/null 2>"$tmp/s4.err") || fail "usm sweep --model 4dof --plot: exit $?: $(head -c 300 "$tmp/s4.err")"
plotted s4
checks=$((checks + 1))
grep -qE "^events = 'stall friction_saturation ?'" "$tmp/s4.gp" &&
    grep -q 'friction_saturation: speed diverges' "$tmp/s4.svg" && grep -q '>stall<' "$tmp/s4.svg" ||
    fail "usm sweep --model 4dof --plot: the events are not drawn as labelled lines"
checks=$((checks + 1))
range=$(cd "$tmp" && gnuplot -e "set terminal unknown" -e "load 's4.gp'; set print '-'; print sprintf('%g %g %g %g', ymin, ymax, dlo, dhi)" 2>/dev/null | tail -1)
read -r ymin ymax dlo dhi <<<"$range"
awk -v a="$ymin" -v b="$ymax" -v lo="$dlo" -v hi="$dhi" \
    'BEGIN { exit !(a > -100 && b < 100 && b > 10 && lo < -200 && hi > 10) }' ||
    fail "usm sweep --model 4dof --plot: speed axis [$ymin, $ymax] for data [$dlo, $dhi]: not clipped, or not the driving direction"
# usm sweep --periodic --plot: its own script, the events labelled
checks=$((checks + 1))
(cd "$tmp" && "$USM" sweep --periodic --variant imperfect --over phase_error --from 0 --to 0.6 \
    --points 7 --plot pe >/dev/null 2>"$tmp/pe.err") ||
    fail "usm sweep --periodic --plot: exit $?: $(head -c 300 "$tmp/pe.err")"
plotted pe
checks=$((checks + 1))
grep -qE "^events = 'stick_loss contact_loss ?'" "$tmp/pe.gp" && grep -q '>contact_loss<' "$tmp/pe.svg" &&
    grep -q 'sweep_periodic.gp' "$tmp/pe.gp" ||
    fail "usm sweep --periodic --plot: not the periodic script, or the events not drawn"
# exactly one event: its value alone is still a word list (gnuplot's word()
# refused a bare number: "non-STRING argument", exit 1 after the sweep)
checks=$((checks + 1))
(cd "$tmp" && "$USM" sweep --periodic --model 4dof --variant imperfect --over mode_split \
    --from 0 --to 0.02 --points 3 --plot one >/dev/null 2>"$tmp/one.err") ||
    fail "usm sweep --periodic --plot with one event: exit $?: $(head -c 300 "$tmp/one.err")"
plotted one
checks=$((checks + 1))
grep -qE "^events = 'contact_loss ?'" "$tmp/one.gp" && grep -q '>contact_loss<' "$tmp/one.svg" ||
    fail "usm sweep --periodic --plot with one event: the event is not drawn"
# a channel zero throughout (usm simulate --spectrum): its panel says so, the
# others are drawn (a log scale of no positive value was gnuplot's error,
# exit 1 after a complete run)
checks=$((checks + 1))
if (cd "$tmp" && "$USM" simulate --from stationary --duration 0.0005 --spectrum sz >/dev/null 2>"$tmp/sz.err"); then
    awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) if ($i == "theta [rad]") c = i; print; next }
             { $c = 0; print }' OFS=, "$tmp/sz.csv" >"$tmp/zero.csv"
    draw zero spectrum.gp "prefix='zero'; csv='zero.csv'; title='one channel zero'; f=37000; nh_rotor_speed=0; nh_theta=0; nh_F_n=0; nh_rotor_speed_amp=0; nh_theta_amp=0; nh_F_n_amp=0; fmax=180000; peak_rotor_speed=1; peak_theta=0; peak_F_n=1"
    grep -q 'an empty spectrum' "$tmp/zero.svg" || fail "spectrum.gp: a zero channel's panel does not say so"
    grep -q '^peak_theta = ' "$tmp/sz.gp" || fail "usm simulate --spectrum: no peak_theta in sz.gp"
else
    fail "usm simulate --spectrum: exit $?: $(head -c 300 "$tmp/sz.err")"
fi
# a file of the user's is never overwritten without --force (exit 2, one line,
# checked before the computation), and is with --force
for cmd in sweep map; do
    for ext in csv png; do
        checks=$((checks + 1))
        echo "user's file" >"$tmp/own_$cmd.$ext"
        if [ $cmd = sweep ]; then args=("${sweep_plot[@]}"); else args=("${map_plot[@]}"); fi
        (cd "$tmp" && "$USM" "${args[@]}" --plot "own_$cmd" >/dev/null 2>"$tmp/own.err")
        rc=$?
        [ $rc = 2 ] && [ "$(wc -l <"$tmp/own.err")" = 1 ] && grep -q "^usm: --plot own_$cmd.*exists" "$tmp/own.err" ||
            fail "usm $cmd --plot over own_$cmd.$ext: exit $rc, $(cat "$tmp/own.err")"
        [ "$(cat "$tmp/own_$cmd.$ext")" = "user's file" ] || fail "usm $cmd --plot overwrote own_$cmd.$ext"
        [ ! -e "$tmp/own_$cmd.gp" ] || fail "usm $cmd --plot wrote own_$cmd.gp though it refused"
        rm -f "$tmp/own_$cmd.$ext"
    done
    checks=$((checks + 1))
    echo "user's file" >"$tmp/own_$cmd.svg"
    (cd "$tmp" && "$USM" "${args[@]}" --plot "own_$cmd" --force >/dev/null 2>"$tmp/own.err") ||
        fail "usm $cmd --plot --force: exit $?: $(cat "$tmp/own.err")"
    plotted "own_$cmd"
done

finish plot_scripts
