#!/bin/bash
# usm envelope from the command line:
#  - --json has curves (kind, points [[x, y], ...], ends), regions (class,
#    sample [x, y]) and codim2, the kinds named as the sweep's events; the
#    tilt_zero curve of the 3-DOF model in (f, F0) is the start threshold
#    F0 = sqrt(m0^2 - (H T / R)^2) / R at every point;
#  - the CSV (stdout and --out) has the header curve,kind,X [unit],Y [unit],
#    --units converts its columns, and an existing --out is kept without --force;
#  - --plot writes PREFIX.csv (curves, regions' cells, codimension-two points),
#    PREFIX.gp and, with gnuplot, the figures; existing files are kept;
#  - bad input (unknown name, LO >= HI, the same parameter twice, not
#    NAME:LO:HI, a missing axis) exits 2 with one line naming the field.
#
# usage: envelope_cli.sh PATH/TO/usm
set -u

USM=${1:?usage: envelope_cli.sh PATH/TO/usm}
. "$(dirname "$0")/../cli_common.sh"

box=(--x f:36kHz:40kHz --y F0:0.1:2 --no-stability --raster 40)

if expect_rc 0 envelope "${box[@]}" --json; then
    py "
kinds = [c['kind'] for c in o['curves']]
assert sorted(kinds) == ['fold', 'tilt_zero'], kinds
assert o['x']['name'] == 'f' and o['x']['lo'] == 36000 and o['x']['hi'] == 40000, o['x']
p = o['parameters']
F0s = (p['m0'] ** 2 - (p['H'] * p['T'] / p['R']) ** 2) ** 0.5 / p['R']
tz = [c for c in o['curves'] if c['kind'] == 'tilt_zero'][0]
assert len(tz['points']) >= 10
assert all(abs(y - F0s) <= 1e-12 * F0s for x, y in tz['points']), F0s
assert min(x for x, y in tz['points']) == 36000 and max(x for x, y in tz['points']) == 40000
assert tz['ends'] == ['box', 'box'], tz['ends']
classes = sorted(r['class'] for r in o['regions'])
assert classes == ['no_solution', 'operating_point', 'unknown'], classes
assert all(len(r['sample']) == 2 for r in o['regions'])
assert [c['type'] for c in o['codim2']] == ['tilt_zero/fold'], o['codim2']
"
fi

if expect_rc 0 envelope "${box[@]}"; then
    checks=$((checks + 1))
    [ "$(head -n 1 "$out")" = "curve,kind,f [Hz],F0 [N]" ] || fail "CSV header: $(head -n 1 "$out")"
    checks=$((checks + 1))
    grep -q '^# region 0 ' "$out" && grep -q '^# codim2 tilt_zero/fold at f = ' "$out" ||
        fail "CSV: no region or codim2 lines"
fi
if expect_rc 0 envelope "${box[@]}" --units kHz; then
    checks=$((checks + 1))
    [ "$(head -n 1 "$out")" = "curve,kind,f [kHz],F0 [N]" ] || fail "--units kHz: $(head -n 1 "$out")"
fi

csv=$tmp/env.csv
if expect_rc 0 envelope "${box[@]}" --out "$csv"; then
    checks=$((checks + 1))
    [ ! -s "$out" ] && [ "$(head -n 1 "$csv")" = "curve,kind,f [Hz],F0 [N]" ] ||
        fail "--out: stdout not empty or the file's header wrong"
fi
expect_bad "--out" "exists" envelope "${box[@]}" --out "$csv"

# --plot: the data file (curves, a blank line after each, the regions' cells)
# and, where gnuplot is installed, the figures
if expect_rc 0 envelope "${box[@]}" --plot "$tmp/fig"; then
    checks=$((checks + 1))
    grep -q '^-1,region:operating_point,' "$tmp/fig.csv" && grep -q '^-1,codim2:tilt_zero/fold,' "$tmp/fig.csv" &&
        [ -s "$tmp/fig.gp" ] || fail "--plot: PREFIX.csv or PREFIX.gp incomplete"
    if command -v gnuplot >/dev/null; then
        checks=$((checks + 1))
        [ -s "$tmp/fig.png" ] && [ -s "$tmp/fig.svg" ] || fail "--plot: no figure"
    fi
fi
expect_bad "--plot" "exists" envelope "${box[@]}" --plot "$tmp/fig"

expect_bad "--x" "unknown parameter 'nope'" envelope --x nope:1:2 --y F0:0.1:2
expect_bad "--x" "below HI" envelope --x f:40000:36000 --y F0:0.1:2
expect_bad "--y" "below HI" envelope --x f:36000:40000 --y F0:2:2
expect_bad "--y" "same parameter as --x" envelope --x f:36000:40000 --y f:1:2
expect_bad "--x" "not NAME:LO:HI" envelope --x f:36000 --y F0:0.1:2
expect_bad "--x" "required" envelope --y F0:0.1:2
expect_bad "--y" "kHz|unit|number" envelope --x f:36000:40000 --y F0:0.1:2kHz

finish envelope_cli
