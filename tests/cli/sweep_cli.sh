#!/bin/bash
# usm sweep from the command line:
#  - every converged grid point equals a single `usm steady --json` run at the
#    same parameters (theta, alpha, rotor_speed and the multipliers, 1e-9 relative);
#  - the CSV has the documented header, one row per point (empty fields where
#    no solution exists) and the events as '#' lines at the end;
#  - bad input exits with 2 and one line "usm: FIELD: reason".
#
# usage: sweep_cli.sh PATH/TO/usm
set -u

USM=${1:?usage: sweep_cli.sh PATH/TO/usm}
. "$(dirname "$0")/../cli_common.sh"

# ---- grid points equal single stationary solves -----------------------------------
# compare MODEL ARGS...: run the sweep with --json, then usm steady at each point.
compare() {
    local model=$1
    shift
    checks=$((checks + 1))
    if ! "$USM" sweep --json --model "$model" "$@" >"$out" 2>"$err"; then
        fail "usm sweep --model $model $*: exit $?"
        return
    fi
    cat >"$tmp/compare.py" <<'EOF'
import json, subprocess, sys
usm, model = sys.argv[1], sys.argv[2]
with open(sys.argv[3]) as f:
    sweep = json.load(f)
sweep_args = sys.argv[4:]
fixed = []  # the sweep's --set options, for usm steady too
for k, a in enumerate(sweep_args):
    if a == "--set":
        fixed += ["--set", sweep_args[k + 1]]
over = sweep["over"]
worst, compared = 0.0, 0
for pt in sweep["points"]:
    if not pt["converged"]:
        continue
    run = subprocess.run([usm, "steady", "--json", "--model", model,
                          *fixed, "--set", f"{over}={pt[over]!r}"],
                         capture_output=True, text=True)
    if run.returncode == 3:
        continue  # no solution found by the full search: nothing to compare
    assert run.returncode == 0, run.stderr
    st = json.loads(run.stdout)
    for k in ("theta", "alpha", "rotor_speed"):
        worst = max(worst, abs(pt[k] - st[k]) / abs(st[k]))
    a, b = pt["floquet"]["multipliers"], st["floquet"]["multipliers"]
    assert len(a) == len(b)
    for x, y in zip(a, b):
        worst = max(worst, abs(complex(*x) - complex(*y)) / abs(complex(*y)))
    compared += 1
assert compared >= 3, f"only {compared} points compared"
print(f"{model} over {over}: {compared} points, largest relative difference {worst:.2e}")
assert worst <= 1e-9, f"largest relative difference {worst:.3e}"
EOF
    if ! "$PY" "$tmp/compare.py" "$USM" "$model" "$out" "$@" >"$tmp/py" 2>&1; then
        fail "usm sweep --model $model $*: $(tail -n 1 "$tmp/py")"
        return
    fi
    cat "$tmp/py"
}
compare 3dof --over f --from 36000 --to 39000 --points 7
compare 3dof --over T --from 0 --to 0.0076 --points 6
compare 4dof --over T --from 0 --to 0.0012 --points 7
compare 4dof --over m0 --from 0.004 --to 0.006 --points 5 --set T=3e-4

# ---- CSV ----------------------------------------------------------------------
checks=$((checks + 1))
if "$USM" sweep --over T --from 0 --to 0.01 --points 11 >"$out" 2>"$err"; then
    cat >"$tmp/csv_check.py" <<'EOF'
import csv
import sys
with open(sys.argv[1]) as f:
    lines = f.read().splitlines()
assert lines[0] == ("T [N m],theta [rad],alpha [rad],rotor_speed [1/s],F_n [N],F_t [N],"
                    "mu_needed [1],max_modulus [1],stable,converged,roots,error,"
                    "power_in [W],power_out [W],power_damping [W],power_slip [W],"
                    "efficiency [1],valid,invalid_reason,operating_point,op_class,"
                    "op_theta [rad],op_rotor_speed [1/s],op_max_modulus [1]"), lines[0]
rows = [l for l in lines[1:] if not l.startswith("#")]
assert len(rows) == 11, len(rows)
assert lines[1:12] == rows, "event lines must follow the rows"
# the stability change (tests/study/test_sweep.c checks it against Floquet on either
# side): stable below it, unstable above, and stable means max |lambda| < 1
t_stab = [float(l.split(" at T = ")[1].split(":")[0]) for l in lines[12:]
          if l.startswith("# stability_change ")]
assert len(t_stab) == 1, lines[12:]
for f in csv.reader(rows):
    assert len(f) == 24, f
    if f[9] == "true":
        assert all(f[:8]) and f[10] == "1" and not f[11], f
        assert f[8] == ("true" if float(f[0]) < t_stab[0] else "false"), (f, t_stab)
        assert (f[8] == "true") == (float(f[7]) < 1), f
        # the power balance of a stick solution (independent of how the
        # columns are written): in = out + damping, slip 0; efficiency = out / in
        pin, pout, pdamp, pslip, eff = (float(v) for v in f[12:17])
        assert pslip == 0 and abs(pin - pout - pdamp) <= 1e-9 * pin, f
        assert abs(eff - pout / pin) <= 1e-12 * abs(eff) + 1e-15, f
        # T * |rotor speed| is the output power (the load is driven)
        assert abs(pout - float(f[0]) * -float(f[3])) <= 1e-9 * (abs(pout) + 1e-12), f
        # valid: the stick model holds where F_t <= mu0 F_n (mu0 = 0.3), from the
        # row's own forces, and the contact is closed
        stick = abs(float(f[5])) <= 0.3 * float(f[4]) and float(f[4]) > 0
        assert f[17:19] == (["true", ""] if stick else ["false", "stick_not_admissible"]), f
    else:
        # beyond the tilt's end: no root at all, and the reason
        assert f[9] == "false" and not any(f[1:9]) and f[10] == "0" and "tilt_zero" in f[11], f
        assert not any(f[12:19]), f  # no solution: valid and invalid_reason empty too
        assert not f[19] and f[20] == "no_solution" and not any(f[21:]), f
        continue
    # the operating point: the only root, stable (only_stable_root), or none
    # where that root is unstable (no_stable_root)
    if f[8] == "true":
        assert f[19] == "0" and f[20] == "operating_point", f
        assert all(abs(float(f[i]) - float(f[j])) <= 1e-11 * abs(float(f[j]))
                   for i, j in ((21, 1), (22, 3), (23, 7))), f
    else:
        assert f[19] == "" and f[20] == "no_stable_root", f
events = lines[12:-1]
# the last line states the operating point's rule (usm_op_rule_text)
assert lines[-1].startswith("# operating point rule: ambiguous points"), lines[-1]
assert [e.split()[1] for e in events] == ["stick_limit", "stability_change", "tilt_zero"], events
assert all(e.startswith("# ") and " at T = " in e for e in events), events
EOF
    if ! "$PY" "$tmp/csv_check.py" "$out" >"$tmp/py" 2>&1; then
        fail "CSV: $(tail -n 1 "$tmp/py")"
    fi
    [ -s "$err" ] && fail "CSV: stderr not empty (no progress bar when stderr is not a terminal)"
else
    fail "usm sweep --over T --from 0 --to 0.01: exit $?, want 0 (points without solution are not an error)"
fi

# ---- validity ------------------------------------------------------
# 3dof over T: valid is exactly stick_admissible (independent: F_t <= mu0 F_n from
# the point's own forces), the reason names the stick, and the first invalid
# point lies past the stick_limit event, the last valid one before it.
if expect_rc 0 sweep --model 3dof --over T --from 0 --to 0.002 --points 21 --no-floquet --json; then
    py "pts = [p for p in o['points'] if p['converged']]
assert len(pts) == 21
mu0 = o['parameters']['mu0']
for p in pts:
    stick = p['F_n'] > 0 and abs(p['F_t']) <= mu0 * p['F_n']
    assert p['valid'] == p['stick_admissible'] == stick, p
    assert p['invalid_reason'] == (None if stick else 'stick_not_admissible'), p
ev = [e['T'] for e in o['events'] if e['type'] == 'stick_limit']
assert len(ev) == 1, o['events']
bad = [p['T'] for p in pts if not p['valid']]
good = [p['T'] for p in pts if p['valid']]
assert bad and good and min(bad) > ev[0] and max(good) <= ev[0], (ev, bad[:1], good[-1:])"
fi
# 4dof: slip is the model, so every point with the contact closed is valid
if expect_rc 0 sweep --model 4dof --over T --from 0 --to 0.002 --points 5 --no-floquet --json; then
    py "pts = [p for p in o['points'] if p['converged']]
assert pts and all(p['valid'] == (p['F_n'] > 0) for p in pts), pts
assert all(p['invalid_reason'] in (None, 'contact_open') for p in pts)"
fi
# usm steady: every root and the top level carry valid, invalid_reason
if expect_rc 0 steady --set T=0.001 --json; then
    py "assert o['valid'] is False and o['invalid_reason'] == 'stick_not_admissible', o
assert all(r['valid'] == r['stick_admissible'] for r in o['roots'])"
fi

# usm map: valid and invalid_reason after efficiency (the operating point's columns
# follow); valid exactly where stick is admissible
# (3dof, the contact closed), from the cell's own mu_used (independent of the flag)
if expect_rc 0 map --x-points 3 --y-points 6; then
    checks=$((checks + 1))
    "$PY" - "$out" <<'EOF' || fail "usm map: valid, invalid_reason"
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
cols = list(rows[0])
assert cols[cols.index("efficiency [1]") + 1:][:2] == ["valid", "invalid_reason"], cols
n = 0
for r in rows:
    if r["exists"] != "true":
        assert r["valid"] == r["invalid_reason"] == "", r
        continue
    stick = abs(float(r["mu_used [1]"])) <= 0.3
    assert r["valid"] == ("true" if stick else "false") == r["stick_admissible"], r
    assert r["invalid_reason"] == ("" if stick else "stick_not_admissible"), r
    n += not stick
assert n > 0, "no invalid cell on the default T range"
EOF
fi

# ---- sweeps that must not give up ----------------------------------------------------
# over decades of a parameter: every grid point solved, exit 0
for args in "--over c_r --from 924.7 --to 924668" "--over mu0 --from 0.3 --to 300" \
            "--model 4dof --over kappa --from 20 --to 20000" "--over d_r --from 2.3865e-4 --to 2.3865"; do
    checks=$((checks + 1))
    # shellcheck disable=SC2086
    if "$USM" sweep $args --points 11 --no-floquet >"$out" 2>"$err"; then
        n=$(grep -c ',true,1,,' "$out" || true)
        [ "$n" = 11 ] || fail "usm sweep $args: $n of 11 points solved"
    else
        fail "usm sweep $args: exit $?, want 0: $(cat "$err")"
    fi
done
# a point whose multipliers fail is marked; the others keep theirs
checks=$((checks + 1))
if "$USM" sweep --over d_R --from 0.1632 --to 1e12 --points 3 --floquet-method variational >"$out" 2>"$err"; then
    grep -q '^0.1632,.*,true,true,1,,' "$out" || fail "d_R sweep: the first point lost its multipliers"
    grep -q '^1e+12,.*,,,true,1,"floquet: ' "$out" || fail "d_R sweep: no marked Floquet failure at 1e12"
else
    fail "usm sweep --over d_R --to 1e12: exit $?, want 0 (one failed Floquet point is marked)"
fi

R0=(--from 36000 --to 39000 --points 5)
# ---- monitors -----------------------------------------------------------------------
checks=$((checks + 1))
if "$USM" sweep --over f --from 36000 --to 39000 --points 7 --no-floquet --extremum speed \
        --crossing theta=8.5e-5 >"$out" 2>"$err"; then
    [ "$(grep -c '^# maximum at f = 3745[0-9.]*: speed has a maximum' "$out")" = 1 ] ||
        fail "--extremum speed: want one maximum near 37.45 kHz: $(grep '^#' "$out")"
    [ "$(grep -c '^# crossing at f = .*: theta crosses 8.5e-05' "$out")" = 2 ] ||
        fail "--crossing theta=8.5e-5: want two crossings: $(grep '^#' "$out")"
else
    fail "usm sweep --extremum speed: exit $?"
fi
expect_bad '--extremum' 'unknown quantity' sweep --over f "${R0[@]}" --extremum nope
expect_bad '--crossing' 'QUANTITY=VALUE' sweep --over f "${R0[@]}" --crossing theta

# ---- bad input ------------------------------------------------------------------
R=(--from 36000 --to 39000 --points 5)
expect_bad 'over:' 'unknown parameter' sweep --over nosuch "${R[@]}"
expect_bad '--over' 'required' sweep "${R[@]}"
expect_bad 'points:' 'at least 2' sweep --over f --from 36000 --to 39000 --points 1
expect_bad '--points' 'must be an integer' sweep --over f --from 36000 --to 39000 --points 2.5
expect_bad '--points' 'not a number' sweep --over f --from 36000 --to 39000 --points x
expect_bad '--from' 'not a number' sweep --over f --from abc --to 39000
expect_bad '--from' 'not a finite number' sweep --over f --from nan --to 39000
expect_bad '--to' 'required' sweep --over f --from 36000
expect_bad 'to:' 'must differ' sweep --over f --from 36000 --to 36000
expect_bad 'threads:' 'between 1 and' sweep --over f "${R[@]}" --threads 0
expect_bad 'usm: f:' 'must be positive' sweep --over f --from -1000 --to 1000 --points 3
# a range in the wrong unit is refused before the first point, naming the end
# and the unit it was likely meant in (a sweep of f from 36 to 38 ran in Hz;
# --periodic --over phase_error --to 36 ran to 36 rad)
expect_bad 'f = 36 Hz is outside 1 kHz..1 MHz' "did you mean 36 kHz\\? \\(the sweep's from\\)" \
    sweep --over f --from 36 --to 38 --points 3
expect_bad 'phase_error = 36 rad is outside' "did you mean 36 deg\\? \\(the sweep's to\\)" \
    sweep --periodic --over phase_error --from 0 --to 36 --points 3
expect_bad 'f = 1e+300 Hz' "outside.*the sweep's to" sweep --over f --from 36000 --to 1e300 --points 3
# --from and --to are read in --over's unit: an unknown --over is the fault
expect_bad '--over: unknown parameter "freq"' '' sweep --over freq --from 36kHz --to 38kHz
expect_bad '--frobnicate' 'unknown option' sweep --over f "${R[@]}" --frobnicate
expect_bad '--set m0' 'not a number' sweep --over f "${R[@]}" --set m0=abc
expect_bad '--from' 'missing argument' sweep --over f --from

# An event on a root the model does not describe carries the flag: the 3-DOF
# stick model loses stability at 3.577 N mm, past its stick limit (0.602 N mm),
# where |F_t| > mu0 F_n (judged here from the event's own root); the stick
# limit itself, the boundary, carries none
if expect_rc 0 sweep --over T --from 0 --to 0.005 --points 11 --json; then
    py "s = [e for e in o['events'] if e['type'] == 'stability_change']
assert len(s) == 1, o['events']
e, r = s[0], s[0]['solution']
assert abs(r['F_t']) > o['parameters']['mu0'] * r['F_n'], r
assert e['valid'] is False and e['invalid_reason'] == 'stick_not_admissible', e
assert e['what'].endswith('; model invalid: stick_not_admissible'), e['what']
k = [e for e in o['events'] if e['type'] == 'stick_limit'][0]
assert 'valid' not in k and 'model invalid' not in k['what'], k"
fi
if expect_rc 0 sweep --over T --from 0 --to 0.005 --points 11; then
    grep -q '^# stability_change at .*; model invalid: stick_not_admissible$' "$out" ||
        fail "sweep CSV: the invalid root's event has no flag: $(grep '^#' "$out")"
fi

finish sweep_cli
