#!/bin/bash
# Robust design from the command line:
#  - usm optimize --constraint yield>=0.99 --scatter ...: --json has yield,
#    yield_ci, samples, verified (and crn, nominal_optimum); the verified yield
#    meets the constraint, the nominal optimum's is reported and lower; the
#    yield of the chosen design agrees with `usm tolerance` (its own sampler,
#    another generator) within 4 standard errors;
#  - common random numbers: the same answer, bit for bit, with 1 and 2 threads
#    and on a second run;
#  - stall_torque equals the stall event of `usm sweep` at the chosen design to
#    1e-9; band_width equals the distance between the two crossing events of
#    `usm sweep --crossing speed=X`; --over-range's mean and integral equal the
#    trapezoid rule on `usm sweep`'s points (1e-12); worst their minimum;
#  - usm pareto: CSV and JSON (every point with its design and active
#    constraints), no point dominated by another, the figure with --plot;
#  - bad input: exit 2 naming the field.
# (Against independent truths in the library: test_robust.c.)
#
# usage: robust_cli.sh PATH/TO/usm
set -u

USM=${1:?usage: robust_cli.sh PATH/TO/usm}
. "$(dirname "$0")/../cli_common.sh"

SCATTER=(--scatter c_r=normal:2% --scatter f=normal:1%)
BOX=(--vary f=34000:42000 --vary F0=0.2:1.0)

# ---- the robust optimum, verified ------------------------------------------------
# (small sets to stay fast under the sanitizers: the search asks the 1000 CRN
# samples 0.99 + 2 sqrt(0.99 0.01 / 1000) = 0.9963; the 5000 fresh ones estimate
# the yield to 1.1e-3.  Deterministic: the same numbers at every run)
if expect_rc 0 optimize --objective efficiency "${BOX[@]}" --constraint speed\>=6 \
    --constraint yield\>=0.99 "${SCATTER[@]}" --samples 1000 --verify-samples 5000 \
    --max-evals 12 --starts 2 --json; then
    cp "$out" "$tmp/robust.json"
    py 'assert o["feasible"] is True and o["verified"] is True, o.get("verified")
for k in ("yield", "yield_ci", "samples", "verified", "crn", "nominal_optimum"):
    assert k in o, k
assert o["samples"] == 5000 and o["crn"]["samples"] == 1000, (o["samples"], o["crn"])
lo, hi = o["yield_ci"]
assert lo <= o["yield"] <= hi and o["yield"] >= 0.99, (o["yield"], lo, hi)
n = o["nominal_optimum"]
assert n["yield"] < 0.99 and n["yield"] < o["yield"], (n["yield"], o["yield"])
assert n["value"] >= o["value"], (n["value"], o["value"])
assert o["nominal_operating_point"]["speed"] >= 6'
    F=$("$PY" -c 'import json,sys; print(repr(json.load(open(sys.argv[1]))["varied"]["f"]))' "$tmp/robust.json")
    F0=$("$PY" -c 'import json,sys; print(repr(json.load(open(sys.argv[1]))["varied"]["F0"]))' "$tmp/robust.json")
    # usm tolerance's sampler at the same design: the same probability
    if expect_rc 0 tolerance --samples 4000 --vary c_r=normal:2% --vary f=normal:1% \
        --spec rotor_speed\<=-6 --set f="$F" --set F0="$F0" --json; then
        py_file "$out" "
import math
r = json.load(open('$tmp/robust.json'))
y1, n1 = o['yield'], o['samples']
y2, n2 = r['yield'], r['samples']
se = math.sqrt(y1 * (1 - y1) / n1 + y2 * (1 - y2) / n2 + 1 / (n1 * n2))
assert abs(y1 - y2) <= 4 * se, (y1, y2, se)"
    fi
fi

# ---- common random numbers: bit for bit across threads and runs ------------------
Q=(optimize --objective q05:speed --vary F0=0.2:1.0 --scatter f=normal:1% --samples 600
   --verify-samples 600 --max-evals 10 --json)
if expect_rc 0 "${Q[@]}" --threads 1; then
    grep -v '"seconds"' "$out" >"$tmp/q1"
    cp "$out" "$tmp/q1.json"
    expect_rc 0 "${Q[@]}" --threads 2 && grep -v '"seconds"' "$out" >"$tmp/q2"
    expect_rc 0 "${Q[@]}" --threads 2 && grep -v '"seconds"' "$out" >"$tmp/q3"
    checks=$((checks + 1))
    cmp -s "$tmp/q1" "$tmp/q2" || fail "q05 objective differs between 1 and 2 threads"
    checks=$((checks + 1))
    cmp -s "$tmp/q2" "$tmp/q3" || fail "q05 objective differs between two runs"
    py_file "$tmp/q1.json" 'assert o["statistic"] == "q05" and o["crn"]["seed"] == 1'
fi

# ---- stall_torque against usm sweep's stall event ---------------------------------
if expect_rc 0 optimize --model 4dof --objective stall_torque --vary F0=0.3:0.5 \
    --over-range T=0:0.002 --max-evals 8 --json; then
    cp "$out" "$tmp/stall.json"
    F0=$("$PY" -c 'import json,sys; print(repr(json.load(open(sys.argv[1]))["varied"]["F0"]))' "$tmp/stall.json")
    if expect_rc 0 sweep --model 4dof --over T --from 0 --to 0.001 --points 51 --no-floquet \
        --set F0="$F0" --json; then
        py "
s = json.load(open('$tmp/stall.json'))['value']
ev = [e['T'] for e in o['events'] if e['type'] == 'stall']
assert ev and abs(ev[0] - s) <= 1e-9 * abs(ev[0]), (ev, s)"
    fi
fi

# ---- band_width against the crossing events -----------------------------------------
if expect_rc 0 optimize --model 4dof --objective band_width --vary F0=0.3:0.5 \
    --over-range f=34000:42000:41 --band-threshold 6 --max-evals 8 --json; then
    cp "$out" "$tmp/band.json"
    F0=$("$PY" -c 'import json,sys; print(repr(json.load(open(sys.argv[1]))["varied"]["F0"]))' "$tmp/band.json")
    if expect_rc 0 sweep --model 4dof --over f --from 34000 --to 42000 --points 41 --no-floquet \
        --crossing speed=6 --set F0="$F0" --json; then
        py "
b = json.load(open('$tmp/band.json'))['value']
x = sorted(e['f'] for e in o['events'] if e['type'] == 'crossing')
assert len(x) == 2, x
assert abs((x[1] - x[0]) - b) <= 1e-6 * b, (x, b)"
    fi
fi

# ---- --over-range: worst, mean, integral against the sweep's points ------------------
for stat in worst mean integral; do
    if expect_rc 0 optimize --model 4dof --objective speed --vary F0=0.4:0.400001 \
        --over-range T=0:0.0003:31 --range-stat $stat --max-evals 4 --json; then
        cp "$out" "$tmp/range.json"
        F0=$("$PY" -c 'import json,sys; print(repr(json.load(open(sys.argv[1]))["varied"]["F0"]))' "$tmp/range.json")
        if expect_rc 0 sweep --model 4dof --over T --from 0 --to 0.0003 --points 31 --no-floquet \
            --set F0="$F0" --json; then
            py "
r = json.load(open('$tmp/range.json'))
x = [p['T'] for p in o['points']]
y = [-p['rotor_speed'] for p in o['points']]
integral = sum(0.5 * (y[i] + y[i - 1]) * (x[i] - x[i - 1]) for i in range(1, len(x)))
want = {'worst': min(y), 'mean': integral / 0.0003, 'integral': integral}['$stat']
assert r['over_range']['statistic'] == '$stat'
assert abs(r['value'] - want) <= 1e-12 * abs(want), (r['value'], want)"
        fi
    fi
done

# ---- usm pareto ------------------------------------------------------------------------
P=(pareto --objectives speed,efficiency "${BOX[@]}" --points 10)
if expect_rc 0 "${P[@]}" --json; then
    py 'pts = o["points"]
assert o["objectives"] == ["speed", "efficiency"] and len(pts) >= 6, len(pts)
for p in pts:
    assert set(p["design"]) == {"f", "F0"} and isinstance(p["active_constraints"], list), p
    for q in pts:
        assert not (q["speed"] >= p["speed"] and q["efficiency"] >= p["efficiency"] and
                    (q["speed"] > p["speed"] or q["efficiency"] > p["efficiency"])), (p, q)'
fi
if expect_rc 0 "${P[@]}" --plot "$tmp/front"; then
    checks=$((checks + 1))
    head -n 1 "$out" | grep -q '^point,speed \[1/s\],efficiency \[1\],f \[Hz\],F0 \[N\],active$' ||
        fail "pareto CSV header"
    checks=$((checks + 1))
    cmp -s "$out" "$tmp/front.csv" || fail "pareto --plot CSV differs from stdout"
    if command -v gnuplot >/dev/null; then
        checks=$((checks + 1))
        [ -s "$tmp/front.png" ] && [ -s "$tmp/front.svg" ] || fail "pareto --plot: no figure"
    fi
fi

# --scatter takes units as --vary and Python's scatter do (usm_tolerance_vary_parse_units):
# (an absolute uniform range of a parameter that is not designed: one of f would be refused)
# the same problem written in SI gives the same JSON, bit for bit but the timings
U=(optimize --objective yield --vary f=34000:42000 --samples 200 --verify-samples 400 --max-evals 4 --json)
if expect_rc 0 "${U[@]}" --scatter F0=normal:20mN --scatter T=uniform:0.05mNm:0.07mNm; then
    cp "$out" "$tmp/units.json"
    if expect_rc 0 "${U[@]}" --scatter F0=normal:0.02 --scatter T=uniform:5e-05:7e-05; then
        checks=$((checks + 1))
        "$PY" - "$tmp/units.json" "$out" <<'PYEOF' || fail "--scatter with units differs from SI"
import json, sys
def strip(o):
    if isinstance(o, dict):
        return {k: strip(v) for k, v in o.items() if 'seconds' not in k and k != 'timings'}
    if isinstance(o, list):
        return [strip(v) for v in o]
    return o
a, b = (strip(json.load(open(f))) for f in sys.argv[1:3])
assert a == b, (a, b)
PYEOF
    fi
fi
expect_bad "--scatter: F0" "unit" optimize --objective yield "${BOX[@]}" --scatter F0=normal:20parsec

# ---- bad input ---------------------------------------------------------------------------
expect_bad "--scatter" "neither" optimize --objective speed "${BOX[@]}" "${SCATTER[@]}"
expect_bad "--scatter" "needs" optimize --objective yield "${BOX[@]}"
expect_bad "--constraint" "0 < Y < 1" optimize --objective speed "${BOX[@]}" "${SCATTER[@]}" \
    --constraint yield\>=1.5
expect_bad "--scatter" "unknown" optimize --objective yield "${BOX[@]}" --scatter c_x=normal:2%
expect_bad "--objective" "quantile" optimize --objective q0x:speed "${BOX[@]}" "${SCATTER[@]}"
expect_bad "--objective" "stall_torque" optimize --objective stall_torque --vary F0=0.3:0.5
expect_bad "--over-range" "band_width" optimize --model 4dof --objective band_width \
    --vary F0=0.3:0.5
expect_bad "--over-range" "NAME=LO:HI" optimize --objective speed --vary F0=0.3:0.5 \
    --over-range T=1
expect_bad "--samples" "whole number" optimize --objective yield "${BOX[@]}" "${SCATTER[@]}" \
    --samples 0.5
# an absolute uniform scatter of a designed parameter ignores the design (it gave yield 1.0
# at f = 36.6 kHz); a scatter the model does not have, or a width in the wrong unit
expect_bad "--scatter: f: uniform:37550:37650 is absolute, but f is designed" "about the design" \
    optimize --objective yield --vary f=34000:42000 --scatter f=uniform:37.55kHz:37.65kHz
expect_bad "--scatter: amp_imbalance" "ideal motor" optimize --objective yield "${BOX[@]}" \
    --scatter amp_imbalance=normal:0.01
expect_bad "--scatter: mode_split" "ideal motor" optimize --objective yield "${BOX[@]}" \
    --scatter mode_split=normal:1%
expect_bad "--scatter: F0: the standard deviation 5 N exceeds the value 0.4 N" "did you mean 5%" \
    optimize --objective yield "${BOX[@]}" --scatter F0=normal:5
expect_bad "--minimize" "yield is maximized" optimize --objective yield --minimize "${BOX[@]}" \
    "${SCATTER[@]}"
# each limit named as itself, and one sample and one seed limit everywhere
expect_bad "--max-evals" "4 to 100000" optimize --objective yield "${BOX[@]}" "${SCATTER[@]}" \
    --max-evals 3
expect_bad "--samples" "100 to 10000000" optimize --objective yield "${BOX[@]}" "${SCATTER[@]}" \
    --samples 50
expect_bad "--seed" "0 to 9007199254740991" optimize --objective yield "${BOX[@]}" \
    "${SCATTER[@]}" --seed 9007199254740992
expect_bad "--seed" "0 to 9007199254740991" tolerance --samples 3 --vary F0=normal:5% \
    --seed 9007199254740992
checks=$((checks + 1))
"$USM" optimize --help | grep -q -- "--samples N .*100 to 10000000" ||
    "$USM" optimize --help | grep -A1 -- "--samples N" | grep -q "100 to 10000000" ||
    fail "optimize --help does not state the sample limit"
# exit 3 says why in a sentence (it said "... an operating point exists cannot be met")
if expect_rc 3 optimize --objective speed --vary F0=0.2:1.0 --constraint 'yield>=0.9' \
        --scatter c_r=normal:2% --set T=0.1 --samples 100 --verify-samples 100 --max-evals 4; then
    checks=$((checks + 1))
    grep -q '^usm: constraint: no feasible design found: no design tried has a stationary solution with an operating point$' "$err" &&
        ! grep -q 'exists cannot be met' "$err" || fail "exit 3 message: $(cat "$err")"
fi
expect_bad "--objectives" "A,B" pareto --objectives speed "${BOX[@]}"
expect_bad "--objectives" "unknown output" pareto --objectives speed,nope "${BOX[@]}"
expect_bad "--objectives" "two different" pareto --objectives speed,speed "${BOX[@]}"
expect_bad "--points" "2 to" pareto --objectives speed,efficiency "${BOX[@]}" --points 1

finish robust_cli
