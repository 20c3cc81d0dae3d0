#!/bin/bash
# usm simulate from the command line: a start-up that settles (table and
# JSON), an impossible load that must end quickly with a report and a
# non-zero status, --out never overwriting without --force, --from FILE
# continuing a run, bad input, and the plots.
#
# usage: simulate_cli.sh PATH/TO/usm
set -u

USM=${1:?usage: simulate_cli.sh PATH/TO/usm}
. "$(dirname "$0")/../cli_common.sh"

# expect RC ARGS...
expect() {
    local want=$1
    shift
    checks=$((checks + 1))
    run "$@"
    local rc=$?
    if [ $rc -ne "$want" ]; then fail "usm $*: exit $rc, want $want"; return 1; fi
    return 0
}

# ---- a start-up that settles: table on stdout with --out, CSV with units ------
if expect 0 simulate --model 3dof --duration 5e-3 --out "$tmp/a.csv"; then
    grep -q 'settled  *yes, at t = ' "$out" || fail "3dof: table does not report settling"
    head -n 1 "$tmp/a.csv" | grep -q '^t \[s\],phi \[rad\],theta \[rad\],psi \[rad\],phidot \[rad/s\]' ||
        fail "CSV header lacks names with units"
    # default rate 10 f: 1850 intervals + the first row + the header
    rows=$(wc -l <"$tmp/a.csv")
    [ "$rows" -eq 1852 ] || fail "CSV has $rows lines, want 1852"
    grep -q 'warning: |F_t| > mu0 F_n' "$err" || fail "3dof: no stick warning during start-up"
    grep -qiE 'nan|inf' "$tmp/a.csv" && fail "CSV contains NaN or inf"
fi

# ---- JSON summary; CSV on stdout puts the summary on stderr ---------------------
if expect 0 simulate --model 4dof --duration 5e-3 --rate 0 --json; then
    cp "$out" "$tmp/s.json"
    py_file "$tmp/s.json" "
assert o['model'] == '4dof' and o['completed'] and o['stop'] == 'completed'
assert o['settled'] is True and 1e-3 < o['t_settle'] < 2e-3, o['t_settle']
assert abs(o['theta_rel_end']) < 1e-6 and abs(o['rotor_speed_rel_end']) < 1e-6
assert abs(o['stationary']['rotor_speed'] + 10.34) < 0.01
assert o['contact_open']['count'] == 0 and 'stick_exceeded' not in o
assert len(o['final_state']['x']) == 8 and o['final_state']['names'][0] == 'phi_R'"
fi
if expect 0 simulate --model 4dof --duration 2e-4 --rate 1e5 --json; then
    head -n 1 "$out" | grep -q '^t \[s\],' || fail "CSV is not on stdout without --out"
    [ "$(wc -l <"$out")" -eq 22 ] || fail "CSV on stdout: $(wc -l <"$out") lines, want 22"
    py_file "$err" "assert o['samples'] == 21"
fi

# ---- an impossible load: clear report, exit 1, quickly -------------------------
for model in 3dof 4dof; do
    start=$(date +%s)
    if expect 1 simulate --model $model --set T=1 --duration 10 --rate 0; then
        grep -q 'runaway' "$out" || fail "$model T=1: summary does not say runaway"
        grep -q '^usm: stopped at t = .*runaway' "$err" || fail "$model T=1: no report on stderr"
        grep -q 'none (' "$out" || fail "$model T=1: no word about the missing stationary solution"
        [ "$(wc -l <"$err")" -eq 1 ] || fail "$model T=1: exit 1 printed $(wc -l <"$err") stderr lines, want 1"
    fi
    [ $(($(date +%s) - start)) -le 10 ] || fail "$model T=1: took more than 10 s"
done
# the step cap ends a run with a report too
if expect 1 simulate --duration 1e-3 --rate 0 --max-steps 50 --json; then
    py_file "$out" "assert o['stop'] == 'max_steps' and 'step cap' in o['reason'] and not o['completed'] and 'circles' not in o['reason']"
    [ "$(wc -l <"$err")" -eq 1 ] || fail "step cap: exit 1 printed $(wc -l <"$err") stderr lines, want 1"
fi
# ... and says why where the preload holds the wobble at the axis: at F0 =
# 1.1 N > m0/R the tilt shrinks to ~1e-10 rad and circles the axis ever faster
# (docs/coordinates.md); the tilt named is the run's own, far below the
# stationary 2.4e-5.  The cap at the paper's preload (above) carries no such word.
# (the decay rule decides on the tilt alone, so the run now ends there: rest, exit 0)
if expect 0 simulate --model 4dof --variant tilt --set F0=1.1 --set f=38800 --duration 2e-3 --rate 0 --json; then
    py_file "$out" "assert o['stop'] == 'rest' and o['settled_on'] == 'rest', o['reason']"
fi

# ---- validity per row: the stick model describes the motor only where
# |F_t| <= mu0 F_n (mu0 = 0.3) and the contact is closed, recomputed from each
# row's own forces; at T = 1 N mm (past the stick limit, 0.602 N mm) no row is
if expect 0 simulate --model 3dof --set T=0.001 --from stationary --duration 2e-4 --out "$tmp/v.csv"; then
    checks=$((checks + 1))
    "$PY" - "$tmp/v.csv" <<'PYEOF' || fail "simulate rows: valid, invalid_reason"
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
assert rows
for r in rows:
    fn, ft = float(r["F_n [N]"]), float(r["F_t [N]"])
    want = ("false", "contact_open") if not fn > 0 else \
           ("false", "stick_not_admissible") if abs(ft) > 0.3 * fn else ("true", "")
    assert (r["valid"], r["invalid_reason"]) == want, r
assert all(r["valid"] == "false" for r in rows)
PYEOF
fi
if expect 0 simulate --model 3dof --from stationary --duration 2e-4 --out "$tmp/v0.csv"; then
    checks=$((checks + 1))
    "$PY" -c "import csv,sys; rows=list(csv.DictReader(open(sys.argv[1]))); assert rows and all(r['valid'] == 'true' for r in rows)" "$tmp/v0.csv" ||
        fail "simulate rows at the paper's load are not all valid"
fi

# ---- --out never overwrites without --force -------------------------------------
echo "precious" >"$tmp/keep.csv"
if expect 2 simulate --duration 1e-4 --out "$tmp/keep.csv"; then
    grep -q 'keep.csv: exists; refusing to overwrite it (use --force)' "$err" ||
        fail "refusal message"
    [ "$(cat "$tmp/keep.csv")" = "precious" ] || fail "--out changed an existing file"
    [ -s "$out" ] && fail "output on stdout although the run was refused"
fi
if expect 0 simulate --duration 1e-4 --out "$tmp/keep.csv" --force; then
    head -n 1 "$tmp/keep.csv" | grep -q '^t \[s\]' || fail "--force did not overwrite"
fi

# ---- --from FILE: continue from the last CSV row / the JSON summary -------------
if expect 0 simulate --model 4dof --duration 1e-3 --rate 1e5 --out "$tmp/b.csv" --json; then
    cp "$out" "$tmp/b.json"
    if expect 0 simulate --model 4dof --from "$tmp/b.csv" --duration 4e-3 --rate 0 --json; then
        py_file "$out" "
assert o['start'] == 'file' and abs(o['t0'] - 1e-3) < 1e-15, o['t0']
assert o['settled'] and o['t_settle'] > 1e-3"
    fi
    if expect 0 simulate --model 4dof --from "$tmp/b.json" --duration 1e-4 --rate 0 --json; then
        py_file "$out" "assert abs(o['t0'] - 1e-3) < 1e-15"
    fi
fi
printf '{"t": 0, "x": [0.1, 8e-5, -0.1, 2.3e5, 0, -2.3e5]}\n' >"$tmp/x.json"
expect 0 simulate --from "$tmp/x.json" --duration 1e-4 --rate 0 || true
expect 2 simulate --model 4dof --from "$tmp/x.json" --duration 1e-4 --rate 0 &&
    { grep -q '"x" must be a list of 8 numbers' "$err" || fail "wrong-length x message"; }
printf 't,phi,theta\n0,1,1e-4\n' >"$tmp/short.csv"
expect 2 simulate --from "$tmp/short.csv" --duration 1e-4 --rate 0 &&
    { grep -q 'no value for psi' "$err" || fail "missing state variable message"; }
printf '{"x": [0, 0, 0, 0, 0, 0]}\n' >"$tmp/zero.json"
expect 2 simulate --from "$tmp/zero.json" --duration 1e-4 --rate 0 &&
    { grep -q 'theta must be > 0' "$err" || fail "theta = 0 start message"; }

# ---- bad input --------------------------------------------------------------------
expect 2 simulate --rate 0 && { grep -q -- '--duration: missing' "$err" || fail "missing --duration"; }
expect 2 simulate --duration -1 && { grep -q -- '--duration: must be positive' "$err" || fail "--duration -1"; }
expect 2 simulate --duration 1e-3 --tilt0 0 && { grep -q -- '--tilt0' "$err" || fail "--tilt0 0"; }
expect 2 simulate --duration 1e-3 --rtol 1 && { grep -q -- '--rtol' "$err" || fail "--rtol 1"; }
expect 2 simulate --duration 1e-3 --rate nan && { grep -q -- '--rate' "$err" || fail "--rate nan"; }
expect 2 simulate --duration 1e-3 --plot "$tmp/p" && { grep -q -- '--plot: needs --out' "$err" || fail "--plot without --out"; }
expect 2 simulate --duration 1e3 --rate 1e6 && { grep -q -- 'rows' "$err" || fail "too many rows"; }
expect 2 simulate --duration 1e-3 --from "$tmp/nosuch.csv" && { grep -q 'nosuch.csv' "$err" || fail "missing --from file"; }
expect 3 simulate --duration 1e-3 --from stationary --set m0=1e-6 --rate 0 &&
    { grep -q 'no stationary solution' "$err" || fail "--from stationary without a solution"; }

# ---- a contact that may open (docs/unilateral.md) -----------------------------------
if expect 0 simulate --model 4dof --variant imperfect_unilateral --set phase_error=30deg \
    --duration 2e-3 --rate 0 --json; then
    py_file "$out" "
assert o['model'] == '4dof_imperfect_unilateral' and o['completed']
# twice per period past contact loss (23.17 deg): 74 periods in 2 ms
assert o['separations'] >= 100 and o['impacts'] >= o['separations'] - 1, (o['separations'], o['impacts'])
assert 0.3 < o['open_fraction'] < 0.5 and 1e-3 < o['impact_velocity_max'] < 0.1
assert o['contact_open']['count'] == o['separations'] and o['contact_open']['min_F_n'] == 0"
    grep -q 'F_n < 0' "$err" && fail "unilateral: the bilateral contact warning"
fi
# restitution: the rotor bounces (several impacts per landing) and lands below v_land
if expect 0 simulate --model 4dof --variant imperfect_unilateral --set phase_error=35deg \
    --set e_impact=0.5 --duration 1e-3 --rate 0 --json; then
    py_file "$out" "
assert o['completed'] and o['separations'] >= 30, o['separations']
assert o['impacts'] >= 3 * o['separations'], (o['impacts'], o['separations'])"
fi
if expect 0 simulate --model 3dof --variant imperfect --duration 1e-3 --rate 0 --json; then
    py_file "$out" "assert 'separations' not in o and 'open_fraction' not in o"
fi
expect 2 simulate --variant imperfect_unilateral --set M=0 --duration 1e-3 &&
    { grep -q 'M: must be positive for a contact that may open' "$err" || fail "M=0 accepted"; }
expect 2 simulate --variant imperfect_unilateral --set e_impact=1.5 --duration 1e-3 &&
    { grep -q 'e_impact: must lie in \[0, 1\]' "$err" || fail "e_impact=1.5 accepted"; }

# ---- plots -------------------------------------------------------------------------
if command -v gnuplot >/dev/null; then
    if expect 0 simulate --duration 2e-3 --rate 2e5 --out "$tmp/p.csv" --plot "$tmp/p"; then
        for f in p.gp p.png p.svg; do [ -s "$tmp/$f" ] || fail "--plot did not write $f"; done
        head -c 8 "$tmp/p.png" | grep -q 'PNG' || fail "p.png is not a PNG"
        grep -q '<svg' "$tmp/p.svg" || fail "p.svg is not an SVG"
    fi
    expect 2 simulate --duration 2e-3 --out "$tmp/q.csv" --plot "$tmp/p" &&
        { grep -q 'p.gp: exists' "$err" || fail "--plot overwrote without --force"; }
    [ -e "$tmp/q.csv" ] && fail "--out written although --plot was refused"
fi

finish simulate_cli
