#!/bin/bash
# usm tolerance: bad input exits 2 with one stderr line naming the
# field; the --json object's keys and ranges; the result is byte-identical
# for any number of threads; a run stopped after one block
# (USM_TOLERANCE_STOP_AFTER_BLOCKS) and resumed from its --checkpoint prints
# and writes exactly what an uninterrupted run does; a checkpoint of another
# study is refused; --out files and the refusal to overwrite.
#
# usage: tolerance_cli.sh PATH/TO/usm
set -u
USM=${1:?usage: tolerance_cli.sh PATH/TO/usm}
. "$(dirname "$0")/../cli_common.sh"

T="tolerance --samples 300 --vary F0=normal:10% --vary T=uniform:0:0.009 --spec rotor_speed<=-5"

# ---- bad input ------------------------------------------------------------------
expect_bad '--vary nosuch' 'unknown parameter' tolerance --samples 10 --vary nosuch=normal:5%
expect_bad '--vary c_t' 'unknown distribution' tolerance --samples 10 --vary c_t=gauss:5%
expect_bad '--vary c_t' 'not a distribution' tolerance --samples 10 --vary c_t=normal:5%%
expect_bad '--vary c_t' 'LO < HI' tolerance --samples 10 --vary c_t=uniform:2:1
expect_bad '--vary c_t' 'positive' tolerance --samples 10 --vary c_t=normal:-1
# a width in the wrong unit (sigma 5 N on 0.4 N: 189 of 200 draws were redrawn), a range
# in the wrong unit, a scatter the model does not have
expect_bad 'F0: the standard deviation 5 N exceeds the value 0.4 N' 'did you mean 5%' \
    tolerance --samples 10 --vary F0=normal:5
expect_bad "f: uniform:37.5:38.5 lies outside the parameter's range" 'did you mean 38.5 kHz' \
    tolerance --samples 10 --vary f=uniform:37.5:38.5
expect_bad 'amp_imbalance' 'ideal motor' tolerance --samples 10 --vary amp_imbalance=normal:0.01
expect_bad '--vary F0' 'smallest normal' tolerance --samples 10 --vary 'F0=normal:0x1p-1074%'
expect_bad '--vary F0' 'smallest normal' tolerance --samples 10 --vary 'F0=uniform:1e-307%'
expect_bad '--vary' 'expected NAME=DIST' tolerance --samples 10 --vary c_t
expect_bad '--vary c_t' 'varied twice' tolerance --samples 10 --vary c_t=normal:1% --vary c_t=normal:2%
expect_bad '--spec speed' 'unknown output' tolerance --samples 10 --vary c_t=normal:1% --spec 'speed<=1'
expect_bad '--spec' 'expected OUTPUT>=X' tolerance --samples 10 --vary c_t=normal:1% --spec 'theta=1'
expect_bad '--spec theta' 'not a finite number' tolerance --samples 10 --vary c_t=normal:1% --spec 'theta<=x'
expect_bad '--samples' 'required' tolerance --vary c_t=normal:1%
expect_bad '--vary' 'required' tolerance --samples 10
expect_bad '--samples' 'whole number' tolerance --samples 0 --vary c_t=normal:1%
expect_bad '--samples' 'whole number' tolerance --samples 1.5 --vary c_t=normal:1%
expect_bad '--threads' 'whole number' tolerance --samples 10 --threads 0 --vary c_t=normal:1%
expect_bad '--seed' 'whole number' tolerance --samples 10 --seed -1 --vary c_t=normal:1%
expect_bad 'T' 'nominal value is 0' tolerance --samples 10 --set T=0 --vary T=normal:5%
expect_bad 'c_t' 'outside the physical range' tolerance --samples 10 --vary c_t=uniform:-2:-1
expect_bad '--bogus' 'unknown option' tolerance --samples 10 --vary c_t=normal:1% --bogus
mkdir "$tmp/exists" && echo keep >"$tmp/exists/keep" # an empty DIR is taken
expect_bad '--out' 'exists' tolerance --samples 10 --vary c_t=normal:1% --out "$tmp/exists"

# ---- the result -------------------------------------------------------------------
if expect_rc 0 $T --json --threads 1; then
    cp "$out" "$tmp/t1.json"
    py 'assert set(o) >= {"samples", "seed", "yield", "yield_ci", "quantiles", "influence", "failed"}, o.keys()
assert o["samples"] == 300 and o["seed"] == 1
lo, hi = o["yield_ci"]
assert 0 <= lo <= o["yield"] <= hi <= 1, (lo, o["yield"], hi)
assert 0 < o["yield"] < 1, o["yield"]
q = o["quantiles"]["rotor_speed"]
assert q["p1"] <= q["p5"] <= q["p50"] <= q["p95"] <= q["p99"], q
assert set(o["influence"]["theta"]) == {"F0", "T"}
# the load slows the motor down: rotor_speed (negative when driving) rises with T
assert o["influence"]["rotor_speed"]["T"] > 0.5, o["influence"]'
fi
# "timings" (wall seconds, last, on a line of its own) differ between runs: compared without it
py_file "$tmp/t1.json" 't = o["timings"]
assert set(t) == {"compute", "reduce", "statistics", "output", "compute_cpu", "output_cpu"} and all(v >= 0 for v in t.values()), t
assert list(o)[-1] == "timings", list(o)'
notimings() { grep -v '^  "timings": ' "$1"; }
expect_rc 0 $T --json --threads 2 &&
    { cmp -s <(notimings "$out") <(notimings "$tmp/t1.json") || fail "threads 2 differs from threads 1"; }

# ---- --out --------------------------------------------------------------------------
if expect_rc 0 $T --out "$tmp/full"; then
    for f in samples.csv summary.md; do [ -s "$tmp/full/$f" ] || fail "--out: no $f"; done
    head -n 1 "$tmp/full/samples.csv" | grep -qx 'sample,F0 \[N\],T \[N m\],exists,stable,stick_admissible,theta \[rad\],rotor_speed \[1/s\],F_n \[N\],F_t \[N\],max_modulus \[1\],efficiency \[1\],good,redraws,operating_point,op_class,valid,invalid_reason' ||
        fail "samples.csv header: $(head -n 1 "$tmp/full/samples.csv")"
    [ "$(wc -l <"$tmp/full/samples.csv")" -eq 301 ] || fail "samples.csv rows"
    grep -qi 'nan\|inf' "$tmp/full/samples.csv" && fail "samples.csv has nan/inf"
    if command -v gnuplot >/dev/null; then
        [ -s "$tmp/full/histograms.png" ] && [ -s "$tmp/full/histograms.svg" ] || fail "no histograms"
        # the key names each bound as drawn (within one data span of the
        # samples) or as off the axis, judged here from samples.csv
        python3 - "$tmp/full" <<'PY' || fail "histogram key: bounds not named as drawn"
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1] + "/samples.csv")))
import html
svg = html.unescape(open(sys.argv[1] + "/histograms.svg").read())
def key(col, bound, what):
    v = [float(r[col]) for r in rows if r[col]]
    lo, hi = min(v), max(v)
    near = lo - (hi - lo) <= bound <= hi + (hi - lo)
    want = ("dashed: %s %g" % (what, bound) if near else
            "%s %g off the axis, %s every sample" % (what, bound, "above" if bound > hi else "below"))
    assert want in svg, (want, lo, hi)
key("rotor_speed [1/s]", -5, "spec <=")
key("max_modulus [1]", 1, "stability limit")
PY
    fi
    # the figure's counts (histograms.csv, binned by the library) against the
    # samples binned here: 40 bins of equal width over each output's range,
    # the maximum in the last bin
    python3 - "$tmp/full" <<'PY' || fail "histograms.csv: not the samples' counts"
import csv, math, sys
rows = list(csv.DictReader(open(sys.argv[1] + "/samples.csv")))
bins = list(csv.DictReader(open(sys.argv[1] + "/histograms.csv")))
assert len(bins) == 40, len(bins)
for name, unit in (("rotor_speed", "1/s"), ("max_modulus", "1")):
    v = [float(r["%s [%s]" % (name, unit)]) for r in rows if r["%s [%s]" % (name, unit)]]
    lo, hi = min(v), max(v)
    got_lo = float(bins[0]["%s_lo [%s]" % (name, unit)])
    got_hi = float(bins[-1]["%s_hi [%s]" % (name, unit)])
    assert got_lo == lo and got_hi == hi, (name, got_lo, lo, got_hi, hi)
    want = [0] * 40
    for x in v:
        want[min(39, int(math.floor((x - lo) / ((hi - lo) / 40))))] += 1
    got = [int(b["%s_count" % name]) for b in bins]
    assert got == want and sum(got) == len(v), (name, got, want)
PY
    # the figure reads the 40 counts only: re-plotted with samples.csv
    # gone it is the same (gnuplot read every sample: 3.5 of 4.8 s at 10^5
    # samples, hours at 10^8)
    if command -v gnuplot >/dev/null; then
        checks=$((checks + 1))
        mkdir "$tmp/replot" && cp "$tmp/full/histograms.gp" "$tmp/full/histograms.csv" "$tmp/replot/"
        (cd "$tmp/replot" && sed -e "s|^csv = .*|csv = 'full/samples.csv'|" \
            -e "s|^bins = .*|bins = 'histograms.csv'|" -e "s|^prefix = .*|prefix = 'again'|" histograms.gp >again.gp &&
            gnuplot again.gp >again.log 2>&1) && [ -s "$tmp/replot/again.svg" ] &&
            ! grep -qiE 'warning|error' "$tmp/replot/again.log" &&
            cmp -s <(grep -v 'full/samples.csv' "$tmp/replot/again.svg") <(grep -v 'full/samples.csv' "$tmp/full/histograms.svg") ||
            fail "the histograms need samples.csv: $(head -c 300 "$tmp/replot/again.log")"
    fi
    cp "$out" "$tmp/full.stdout"
fi

# no sample has a solution: yield 0 with the interval [0, hi], histograms all the same
if expect_rc 0 tolerance --samples 20 --vary T=uniform:0.01:0.02 --json --out "$tmp/none"; then
    py 'assert o["yield"] == 0 and o["yield_ci"][0] == 0 and 0 < o["yield_ci"][1] < 0.2, o
assert o["exists"] == 0 and o["quantiles"]["theta"]["p50"] is None and o["quantiles"]["theta"]["count"] == 0'
fi
if command -v gnuplot >/dev/null; then
    for d in full none; do
        [ -s "$tmp/$d/histograms.png" ] && ! grep -qiE 'warning|error' "$tmp/$d/histograms.log" ||
            fail "$d: tolerance.gp: $(head -c 300 "$tmp/$d/histograms.log")"
    done
fi

# ---- checkpoint: stop after one block, resume, compare byte for byte -----------------------
checks=$((checks + 1))
USM_TOLERANCE_STOP_AFTER_BLOCKS=1 timeout 60 "$USM" $T --checkpoint "$tmp/ck" --out "$tmp/resumed" >"$out" 2>"$err"
rc=$?
if [ $rc -ne 1 ] || ! grep -q 'stopped after 1 block' "$err" || [ "$(wc -l <"$err")" -ne 1 ] || [ ! -s "$tmp/ck" ]; then
    fail "stop after one block: exit $rc"
fi
if expect_rc 0 $T --checkpoint "$tmp/ck" --out "$tmp/resumed" --force; then
    cmp -s "$out" "$tmp/full.stdout" || fail "resumed summary differs"
    cmp -s "$tmp/resumed/samples.csv" "$tmp/full/samples.csv" || fail "resumed samples.csv differs"
fi
expect_bad 'checkpoint' 'another study.*seed' $T --seed 2 --checkpoint "$tmp/ck"

# ---- checkpoints that cannot lie: each refused with one line, exit 2 ------------
# a checkpoint of 3 of the 5 blocks (the last in-place run left all of them): damaged copies
USM_TOLERANCE_STOP_AFTER_BLOCKS=3 timeout 60 "$USM" $T --checkpoint "$tmp/ck3" >"$out" 2>"$err"
size=$(stat -c %s "$tmp/ck3")
cp "$tmp/ck3" "$tmp/ck3.orig"
flip() { # FILE OFFSET: one byte inverted
    "$PY" -c 'import sys; p, k = sys.argv[1], int(sys.argv[2]); b = bytearray(open(p, "rb").read()); b[k] ^= 0xff; open(p, "wb").write(b)' "$1" "$2"
}
for at in 120 $((size / 2)) $((size - 20)) $((size - 100)); do # the configuration, a row, the checksum, the last rows
    cp "$tmp/ck3.orig" "$tmp/ck3"; flip "$tmp/ck3" $at
    expect_bad 'checkpoint' 'damaged' $T --checkpoint "$tmp/ck3"
done
cp "$tmp/ck3.orig" "$tmp/ck3"; head -c $((size - 9)) "$tmp/ck3.orig" >"$tmp/ck3"
expect_bad 'checkpoint' 'truncated' $T --checkpoint "$tmp/ck3"
head -c $((size / 3)) "$tmp/ck3.orig" >"$tmp/ck3"
expect_bad 'checkpoint' 'truncated' $T --checkpoint "$tmp/ck3"
cp "$tmp/ck3.orig" "$tmp/ck3"
expect_bad 'checkpoint' 'another study.*seed 1.*seed 3' $T --seed 3 --checkpoint "$tmp/ck3"
sed '2s/^usm .*/usm 0.0.1/' "$tmp/ck3.orig" >"$tmp/ck3"
expect_bad 'checkpoint' 'written by usm 0.0.1, this is usm' $T --checkpoint "$tmp/ck3"
sed '1s/checkpoint 3/checkpoint 2/' "$tmp/ck3.orig" >"$tmp/ck3"
cp "$tmp/ck3" "$tmp/ck3.bad"
expect_bad 'checkpoint' 'another format' $T --checkpoint "$tmp/ck3"
cmp -s "$tmp/ck3" "$tmp/ck3.bad" || fail "a refused checkpoint was rewritten"
# the intact one resumes to the uninterrupted result
cp "$tmp/ck3.orig" "$tmp/ck3"
expect_rc 0 $T --checkpoint "$tmp/ck3" && { cmp -s "$out" "$tmp/full.stdout" || fail "resumed from 3 blocks differs"; }
printf 'my notes\n' >"$tmp/notes"
expect_bad 'checkpoint' 'not a usm tolerance checkpoint' $T --checkpoint "$tmp/notes"
grep -qx 'my notes' "$tmp/notes" || fail "a foreign file was overwritten"

# ---- validity: each sample's valid flag is what the model says there -----
# A 3-DOF (stick) study across the stick limit (the load T and the friction scale mu0
# varied): every row's valid/invalid_reason recomputed from its own F_n, F_t and mu0
# (steady.c's definition: contact closed, |F_t| <= mu0 F_n); good only when the operating
# point exists, is stable, meets the spec and is valid; the JSON's invalid counts are the
# CSV's; and three samples (a valid one, an invalid one, the one nearest the limit) against
# `usm steady` at the sample's parameters.
V="tolerance --samples 40 --seed 5 --vary T=uniform:0:0.001 --vary mu0=uniform:0.1:0.4 --vary F0=normal:10% --spec rotor_speed<=-5"
if expect_rc 0 $V --json --out "$tmp/valid"; then
    cp "$out" "$tmp/valid.json"
    checks=$((checks + 1))
    "$PY" - "$USM" "$tmp/valid/samples.csv" "$tmp/valid.json" >"$tmp/valid.out" 2>&1 <<'PYEOF' || {
import csv, json, subprocess, sys
usm, rows, summary = sys.argv[1], list(csv.DictReader(open(sys.argv[2]))), json.load(open(sys.argv[3]))
invalid = {"contact_open": 0, "stick_not_admissible": 0}
for r in rows:
    if r["exists"] != "true":
        assert r["valid"] == "" and r["invalid_reason"] == "", r
        continue
    F_n, F_t, mu0 = float(r["F_n [N]"]), float(r["F_t [N]"]), float(r["mu0 [1]"])
    want = "" if F_n > 0 and abs(F_t) <= mu0 * F_n else \
        "contact_open" if not F_n > 0 else "stick_not_admissible"
    assert r["valid"] == ("true" if want == "" else "false"), (r, want)
    assert r["invalid_reason"] == want, (r, want)
    if want:
        invalid[want] += 1
    good = (r["op_class"] == "operating_point" and r["stable"] == "true" and
            float(r["rotor_speed [1/s]"]) <= -5 and want == "")
    assert (r["good"] == "true") == good, (r, good)
assert summary["invalid"] == sum(invalid.values()), (summary["invalid"], invalid)
assert summary["invalid_reasons"] == invalid, (summary["invalid_reasons"], invalid)
assert summary["good"] == sum(r["good"] == "true" for r in rows)
nvalid = sum(r["valid"] == "true" for r in rows)
assert nvalid >= 3 and invalid["stick_not_admissible"] >= 3, (nvalid, invalid)
# some samples are good only because they are valid: an invalid one meets the rest
assert any(r["valid"] == "false" and r["op_class"] == "operating_point" and
           float(r["rotor_speed [1/s]"]) <= -5 for r in rows)
def margin(r):
    return abs(abs(float(r["F_t [N]"])) - float(r["mu0 [1]"]) * float(r["F_n [N]"]))
pick = [next(r for r in rows if r["valid"] == "true"),
        next(r for r in rows if r["valid"] == "false"), min(rows, key=margin)]
for r in pick:
    args = [usm, "steady", "--json"]
    for n in ("T [N m]", "mu0 [1]", "F0 [N]"):
        args += ["--set", "%s=%r" % (n.split()[0], float(r[n]))]
    o = json.loads(subprocess.run(args, capture_output=True, text=True, check=True).stdout)
    assert o["rotor_speed"] == float(r["rotor_speed [1/s]"]), (o["rotor_speed"], r)
    assert o["valid"] == (r["valid"] == "true"), (o["valid"], r)
    assert (o["invalid_reason"] or "") == r["invalid_reason"], (o["invalid_reason"], r)
print("validity: %d rows, %d valid, invalid %s" % (len(rows), nvalid, invalid))
PYEOF
        failures=$((failures + 1))
        echo "FAIL: tolerance validity: $(tail -n 3 "$tmp/valid.out")"
    } && cat "$tmp/valid.out"
fi

# ---- the motor drives its load: power_out >= 0 (rule, condition 5) ----------------------
# A 4-DOF (slip) study whose load torque scatters across the stall torque (4.95e-4 N m,
# `usm sweep --model 4dof --over T`; past it the rotor turns backwards, stable and valid up
# to the friction saturation at 9.46e-4 N m): from samples.csv alone, with power_out =
# -T rotor_speed computed here (the paper's sign), good is the rule -- 0 wherever
# power_out < 0 -- and the JSON's driven counts the samples good but for that sign; with
# --allow-driven good is the old rule and driven 0; at T = 0 (power_out 0) nothing is
# driven.
D="tolerance --model 4dof --samples 200 --seed 9 --vary T=uniform:0.0002:0.0008 --vary F0=normal:5% --spec max_modulus<=0.95"
for allow in "" --allow-driven; do
    expect_rc 0 $D $allow --json --out "$tmp/drv$allow" || continue
    cp "$out" "$tmp/drv$allow.json"
    checks=$((checks + 1))
    "$PY" - "$tmp/drv$allow/samples.csv" "$tmp/drv$allow.json" "$allow" >"$tmp/drv.out" 2>&1 <<'PYEOF' || {
import csv, json, sys
rows, summary, allow = list(csv.DictReader(open(sys.argv[1]))), json.load(open(sys.argv[2])), sys.argv[3] != ""
driven = negative = 0
for r in rows:
    rest = (r["op_class"] == "operating_point" and r["stable"] == "true" and r["valid"] == "true"
            and float(r["max_modulus [1]"]) <= 0.95)
    power_out = -float(r["T [N m]"]) * float(r["rotor_speed [1/s]"]) if r["exists"] == "true" else None
    negative += power_out is not None and power_out < 0
    good = rest and (allow or power_out >= 0)
    assert (r["good"] == "true") == good, (r, power_out)
    driven += rest and not good
assert summary["driven"] == driven, (summary["driven"], driven)
assert summary["good"] == sum(r["good"] == "true" for r in rows)
assert 50 < negative < 150 and (allow or 0 < driven < negative), (negative, driven)
print("drives%s: %d rows, power_out < 0 in %d, driven %d, good %d" % (
    " (--allow-driven)" if allow else "", len(rows), negative, driven, summary["good"]))
PYEOF
        failures=$((failures + 1))
        echo "FAIL: tolerance drives$allow: $(tail -n 3 "$tmp/drv.out")"
    } && cat "$tmp/drv.out"
done
py_file "$tmp/drv.json" 'assert o["driven"] > 0, o["driven"]'
py_file "$tmp/drv--allow-driven.json" 'assert o["driven"] == 0, o["driven"]'
# the summary says why they do not count
expect_rc 0 $D && { grep -q '^Driven backwards by the load.*: [1-9][0-9]*\.$' "$out" || fail "summary: no driven count"; }
expect_rc 0 tolerance --model 4dof --samples 64 --set T=0 --vary F0=normal:5% --json &&
    py 'assert o["driven"] == 0 and o["good"] == o["operating_point"]["exists"] == 64, o'
# a checkpoint of one rule is another study for the other
USM_TOLERANCE_STOP_AFTER_BLOCKS=1 timeout 60 "$USM" $D --checkpoint "$tmp/ckd" >"$out" 2>"$err"
expect_bad 'checkpoint' 'another study.*allow_driven 0.*allow_driven 1' $D --allow-driven --checkpoint "$tmp/ckd"

finish tolerance_cli
