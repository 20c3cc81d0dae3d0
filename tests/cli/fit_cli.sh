#!/bin/bash
# usm fit: a fit from a data file with units (JSON read back), the residuals'
# CSV, and bad data refused with one line naming the column or row and the
# reason, exit 2; a point where the motor does not run is a flagged residual.
set -u
USM=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
DIR=$(cd "$(dirname "$0")" && pwd)
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
fail=0
bad() { echo "FAIL: $*"; fail=1; }

# a fit of the committed speed curves (1 % noise from the paper's parameters)
"$USM" fit --model 4dof --data "$DIR/fit/speed.csv" --fit c_r,kappa --starts 1 --json \
    --out "$T/res.csv" > "$T/fit.json" || bad "fit exit $?"
python3 - "$T/fit.json" "$T/res.csv" <<'PY' || fail=1
import csv, json, sys
d = json.load(open(sys.argv[1]))
rows = list(csv.DictReader(open(sys.argv[2])))
e = d["estimates"]
ok = True
def check(c, what):
    global ok
    if not c:
        print("FAIL:", what); ok = False
# truth c_r = 924.6677, kappa = 20 inside the 95 % intervals
check(e["c_r"]["ci95"][0] < 924.6677 < e["c_r"]["ci95"][1], "c_r interval %s" % e["c_r"])
check(e["kappa"]["ci95"][0] < 20 < e["kappa"]["ci95"][1], "kappa interval %s" % e["kappa"])
check(d["identifiable"] is True and d["unidentifiable"] == [], "identifiable")
check(d["sigma_estimated"] is False and 0 < d["p_value"] <= 1, "p-value")
check(len(rows) == len(d["points"]) == 22, "points")
check(all(abs(float(r["residual"]) - p["residual"]) <= 1e-12 * max(1, abs(p["residual"]))
          for r, p in zip(rows, d["points"])), "CSV residuals = JSON residuals")
# speed [rpm] read in SI (1/s): the model value of row 1 is about 110 rpm
check(abs(d["points"][0]["model"] * 60 / 6.283185307179586 - 110) < 2, "rpm converted")
sys.exit(0 if ok else 1)
PY

# mu0 and kappa from the speed-frequency curves alone: not identifiable
head -18 "$DIR/fit/speed.csv" > "$T/curves.csv"
"$USM" fit --model 4dof --data "$T/curves.csv" --fit mu0,kappa --starts 1 --json > "$T/mk.json" ||
    bad "mu0,kappa exit $?"
python3 -c '
import json, sys
d = json.load(open(sys.argv[1]))
u = d["unidentifiable"]
ok = d["identifiable"] is False and len(u) == 1 and set(u[0]["combination"]) == {"mu0", "kappa"} \
    and u[0]["advice"] is not None
ok or print("FAIL: mu0,kappa %s" % u)
sys.exit(0 if ok else 1)' "$T/mk.json" || fail=1

# a point where the motor has no operating point (a load past the friction
# limit): a flagged residual, not a refusal
printf 'T [N m],speed [1/s],sigma_speed [1/s]\n0,11.5,0.1\n6.46e-5,10.3,0.1\n1e-4,9.7,0.1\n0.002,0,0.1\n' > "$T/stall.csv"
"$USM" fit --model 4dof --data "$T/stall.csv" --fit c_r --starts 1 --json > "$T/stall.json" ||
    bad "stall: exit $?"
python3 -c '
import json, sys
d = json.load(open(sys.argv[1]))
p = d["points"][3]
ok = d["flagged"] == 1 and p["flagged"] and p["reason"] == "no_solution" and p["model"] == 0
ok or print("FAIL: flagged point %s" % p)
sys.exit(0 if ok else 1)' "$T/stall.json" || fail=1

# a datasheet quantity measured: stall_torque in mN m (converted to N m), its
# model value the datasheet's; the JSON says how many starts reached the best
printf 'f [kHz],T [mNm],speed [rpm],stall_torque [mNm]\n37,0,108.6,\n38,0,120,\n39,0,110,\n38.8,0,,0.43\n' \
    > "$T/ds.csv"
"$USM" fit --model 4dof --data "$T/ds.csv" --fit mu0 --starts 2 --json > "$T/ds.json" ||
    bad "stall_torque: exit $?"
python3 -c '
import json, sys
d = json.load(open(sys.argv[1]))
p = d["points"][3]
ok = p["output"] == "stall_torque" and abs(p["measured"] - 4.3e-4) < 1e-12 \
    and 3e-4 < p["model"] < 6e-4 and not p["flagged"] and 1 <= d["starts_at_best"] <= d["starts"] == 2
ok or print("FAIL: stall_torque %s, starts %s at best %s" % (p, d["starts"], d["starts_at_best"]))
sys.exit(0 if ok else 1)' "$T/ds.json" || fail=1
# the table for people in the --units display (JSON stays SI): the speeds in
# rpm as the data gave them, the stall torque and the fitted torque m0 in mN m
"$USM" fit --model 4dof --data "$T/ds.csv" --fit m0 --starts 1 --units rpm,mNm > "$T/ds.txt" ||
    bad "--units: exit $?"
grep -Eq '^ +1 speed +108\.6 ' "$T/ds.txt" && grep -Eq '^ +4 stall_torque +0\.43 ' "$T/ds.txt" &&
    grep -Eq '^  m0 .* mN ?m' "$T/ds.txt" || { echo "FAIL: --units rpm,mNm table:"; cat "$T/ds.txt"; fail=1; }
"$USM" fit --model 4dof --data "$T/ds.csv" --fit mu0 --spread 0.5 2> "$T/err" > /dev/null
[ $? -eq 2 ] && [ "$(wc -l < "$T/err")" -eq 1 ] && grep -q -- "--spread: 0.5 is not in 1..1e6" "$T/err" ||
    bad "--spread 0.5: $(cat "$T/err")"

# --plot: the residuals' CSV and the figure (when gnuplot is installed); the
# stall file's flagged point drawn apart; --out and --plot's CSV the same file
# refused before the fit
if command -v gnuplot >/dev/null; then
    (cd "$T" && "$USM" fit --model 4dof --data stall.csv --fit c_r --starts 1 --plot fp \
        > /dev/null) || bad "--plot exit $?"
    for e in csv gp png svg; do [ -s "$T/fp.$e" ] || bad "--plot: no fp.$e"; done
    grep -q "^xcol = 'T \[N m\]'" "$T/fp.gp" || bad "--plot: x axis not T: $(grep xcol "$T/fp.gp")"
    [ "$(cut -d, -f10 "$T/fp.csv" | tail -1)" = 1 ] || bad "--plot: the flagged point's flagged column"
fi
"$USM" fit --model 4dof --data "$DIR/fit/speed.csv" --fit c_r --out "$T/same.csv" \
    --plot "$T/same" 2> "$T/err" > /dev/null
[ $? -eq 2 ] && grep -q "are the same file" "$T/err" || bad "--out = --plot's CSV: $(cat "$T/err")"

# bad data: one line, exit 2, naming the column or row
expect_bad() { # NAME PATTERN CSV-TEXT [fit]
    printf '%b' "$3" > "$T/$1.csv"
    "$USM" fit --model 4dof --data "$T/$1.csv" --fit "${4:-c_r,kappa}" > "$T/out" 2> "$T/err"
    local rc=$?
    [ $rc -eq 2 ] || bad "$1: exit $rc"
    [ "$(wc -l < "$T/err")" -eq 1 ] || bad "$1: not one line: $(cat "$T/err")"
    grep -q -- "$2" "$T/err" || bad "$1: message lacks '$2': $(cat "$T/err")"
}
expect_bad missing_output "column sigma_power_in: its output column power_in is missing" \
    'f [Hz],speed [1/s],sigma_speed [1/s],sigma_power_in [W]\n37000,11,0.1,0.01\n38000,11,0.1,0.01\n39000,9,0.1,0.01\n'
expect_bad unit "column speed: the unit \[N\] does not convert to 1/s" \
    'f [Hz],speed [N]\n37000,11\n38000,11\n39000,9\n'
expect_bad nan ':3: column speed: "nan" is not a finite number' \
    'f [Hz],speed [1/s]\n37000,11\n38000,nan\n39000,9\n'
expect_bad negative_sigma ':2: column sigma_speed: "-0.1" is not a standard deviation' \
    'f [Hz],speed [1/s],sigma_speed [1/s]\n37000,11,-0.1\n38000,11,0.1\n'
expect_bad fewer "fewer points than parameters" \
    'f [Hz],speed [1/s],sigma_speed [1/s]\n37000,11,0.1\n' c_r,kappa
expect_bad unknown "column spede: neither a parameter nor a measured output" \
    'f [Hz],spede [1/s]\n37000,11\n'
expect_bad fields ":3: 1 fields, the header has 2" 'f [Hz],speed [1/s]\n37000,11\n38000\n'
expect_bad range ":2: f = 37 Hz is outside" 'f [Hz],speed [1/s]\n37,11\n38,11\n39,11\n'

[ $fail -eq 0 ] && echo "fit_cli: ok"
exit $fail
