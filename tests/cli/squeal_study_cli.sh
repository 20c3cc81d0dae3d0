#!/bin/bash
# usm squeal (the motion over one parameter past the last periodic orbit):
#  - its audible lines against an independent FFT (numpy: Hann window, local
#    maxima between 20 Hz and 20 kHz) of `usm simulate --out` of the same run
#    (from rest, the same periods, rate and tolerance), the sound source
#    computed here from the CSV's theta and thetadot as (R cos theta - H sin
#    theta) thetadot: every line within one bin of a numpy maximum, numpy's
#    strongest within one bin of a line (the order may differ: usm ranks by
#    the interpolated amplitude, numpy here by the bin's);
#  - the change from period-1 to other motion lies where the stable branch of
#    `usm sweep --periodic` (the shooting's orbits with separation) ends, to
#    one grid step: 3-DOF phase error 0.90 to 0.93 rad, the two-impact orbit
#    ending between 0.912 and 0.914 rad;
#  - the origin at the end of that branch (usm squeal --json "origin"): the
#    last period-1 value's orbit, stable (max |lambda| that of the sweep's
#    orbit there, to 1e-6), its closed phase nearly gone: the kind
#    closed_phase_vanishing; the participation shares sum to 1;
#  - --plot writes the bifurcation diagram's CSV and gnuplot's figures;
#  - bad input: an unknown name, A == B, fewer than 2 points, a model whose
#    contact never opens, an --out file that exists: one line, exit 2.
#
# usage: squeal_study_cli.sh PATH/TO/usm
set -u

USM=${1:?usage: squeal_study_cli.sh PATH/TO/usm}
. "$(dirname "$0")/../cli_common.sh"

SETTLE=60
WINDOW=128
# 4-DOF at 5 % mode split: the rotor bounces irregularly (no orbit with a
# closed phase from 3.6 %), the spectrum has many audible lines
if expect_rc 0 squeal --model 4dof --over mode_split --from 0.05 --to 0.051 --points 2 \
    --settle $SETTLE --window $WINDOW --lyapunov-periods 20 --power-periods 20 --no-rest-check \
    --json --quiet; then
    cp "$out" "$tmp/squeal.json"
    py "
p = o['points'][0]
assert p['motion'] == 'chaotic', p['motion']
assert p['lyapunov'] > 0, p['lyapunov']
assert len(p['lines']) >= 3, p['lines']
# the power account reaches the JSON: its balance closes, the driver feeds
assert p['power']['periods'] == 20 and p['energy_balance_error'] < 1e-6, p['power']
assert p['power']['excitation'] > 0 and p['power']['impacts'] < 0, p['power']
assert o['onset'] is None, o['onset']
"
    if expect_rc 0 simulate --model 4dof --variant imperfect_unilateral --set mode_split=0.05 \
        --duration $(python3 -c "print(($SETTLE + $WINDOW) / 37000)") --rate 296000 \
        --out "$tmp/sim.csv" --quiet --json; then
        py_file "$tmp/squeal.json" "
import csv, numpy as np
rows = list(csv.reader(open('$tmp/sim.csv')))
head = [h.split(' ')[0] for h in rows[0]]
body = [r for r in rows[1:] if r and not r[0].startswith('#')]
th = np.array([float(r[head.index('theta')]) for r in body])
thd = np.array([float(r[head.index('thetadot')]) for r in body])
R, H, f, m = 0.005, 0.003, 37000.0, 8
n = $WINDOW * m
a = $SETTLE * m
assert len(th) >= a + n, (len(th), a + n)
v = ((R * np.cos(th) - H * np.sin(th)) * thd)[a:a + n]
v = v - v.mean()
w = 0.5 * (1 - np.cos(2 * np.pi * np.arange(n) / n))
amp = 4 * np.abs(np.fft.rfft(v * w)) / n
df = f / $WINDOW
k = np.arange(1, len(amp) - 1)
peaks = k[(amp[k] > amp[k - 1]) & (amp[k] >= amp[k + 1]) & (k * df >= 20) & (k * df <= 20000)]
peaks = peaks[np.argsort(-amp[peaks])]
lines = o['points'][0]['lines']
assert abs(o['points'][0]['bin'] - df) < 1e-9 * df
for l in lines:
    near = min(abs(p * df - l['frequency']) for p in peaks[:20])
    assert near <= df, (l, near / df)
assert min(abs(peaks[0] * df - l['frequency']) for l in lines) <= df, (peaks[0] * df, lines)
"
    fi
fi

# ---- the onset against the periodic sweep's stable branch -------------------------
ONSET="--over phase_error --from 0.90 --to 0.93 --points 4"
if expect_rc 0 squeal $ONSET --settle 200 --window 64 --lyapunov-periods 50 --no-rest-check \
    --power-periods 0 --json --quiet --plot "$tmp/onset"; then
    cp "$out" "$tmp/onset.json"
    # --plot: the diagram's data and gnuplot's figures, without a complaint
    if command -v gnuplot >/dev/null; then
        checks=$((checks + 1))
        [ -s "$tmp/onset.csv" ] && [ -s "$tmp/onset.png" ] && [ -s "$tmp/onset.svg" ] ||
            fail "--plot: no CSV, PNG or SVG"
        ! grep -qiE 'warning|error' "$tmp/onset.log" 2>/dev/null ||
            fail "--plot: gnuplot said $(head -c 300 "$tmp/onset.log")"
    fi
    if expect_rc 0 sweep --periodic --variant imperfect_unilateral $ONSET --json --quiet; then
        py_file "$tmp/onset.json" "
sw = json.load(open('$out'))
vals = [p['value'] for p in o['points']]
step = vals[1] - vals[0]
p1 = [p['value'] for p in o['points'] if p['motion'] == 'periodic' and p['period'] == 1]
assert p1 and p1[0] == vals[0], [(p['value'], p['motion']) for p in o['points']]
# the last value of the leading run of period-1 motion
last = vals[0]
for p in o['points']:
    if p['motion'] != 'periodic' or p['period'] != 1:
        break
    last = p['value']
stable = [p['phase_error'] for p in sw['points'] if p.get('separating') and p['valid']
          and p['floquet']['stable']]
end = vals[0]
for v in vals:
    if v not in stable:
        break
    end = v
assert last < vals[-1], 'no change of motion in the range'
assert abs(last - end) <= step * (1 + 1e-9), (last, end)
# the origin at the branch's end: the orbit at the last period-1 value, its
# largest multiplier that of the sweep's own orbit there (a second solve:
# the continuation's, not the study's), stable, the closed phase nearly gone;
# the participation shares sum to 1
g = o['origin']
assert g['found'] and g['value'] == last, g
assert g['kind'] == 'closed_phase_vanishing', g
at = [p for p in sw['points'] if abs(p['phase_error'] - last) < 1e-12 and p.get('separating')]
assert at, 'the sweep has no orbit at %g' % last
ref = at[0]['floquet']['max_modulus']
assert abs(g['max_modulus'] - ref) <= 1e-6 * ref, (g['max_modulus'], ref)
assert g['max_modulus'] < 1 and g['separation_fraction'] > 0.8, g
assert abs(sum(g['participation'].values()) - 1) < 1e-12, g['participation']
"
    fi
fi

# ---- bad input ------------------------------------------------------------------
expect_bad '--over' 'unknown parameter' squeal --over nosuch --from 0 --to 1
expect_bad 'from, to' 'different' squeal --over mode_split --from 0.02 --to 0.02
expect_bad 'points' 'must be 2' squeal --over mode_split --from 0.02 --to 0.03 --points 1
expect_bad 'model' 'never opens' squeal --variant imperfect --over mode_split --from 0.02 --to 0.03
# a file a user has is refused before the (long) study, not after it
echo keep >"$tmp/kept.csv"
expect_bad '--out' 'exists' squeal --over mode_split --from 0.02 --to 0.03 --out "$tmp/kept.csv"
checks=$((checks + 1))
[ "$(cat "$tmp/kept.csv")" = keep ] || fail "--out: the user's file was changed"

finish squeal_study_cli
