#!/usr/bin/env bash
# Values with units on the command line, JSON numbers in the shortest form,
# grid values as typed, and the usage lines (items 4 and 5).
# Usage: units_cli.sh PATH/TO/usm
USM=$1
# shellcheck source=../cli_common.sh
. "$(dirname "$0")/../cli_common.sh"

# ---- values with units: the issue's examples, exactly --------------------------
if expect_rc 0 steady --variant imperfect --set phase_error=10deg --set f=37.5kHz \
        --set T=0.5mNm --set F0=400mN --set phase_error=0 --json; then
    py "import math
p = o['parameters']
assert p['f'] == 37500.0 and p['T'] == 0.0005 and p['F0'] == 0.4, p"
fi
if expect_rc 0 periodic --set phase_error=10deg --json; then
    py "import math
assert o['parameters']['phase_error'] == 10 * math.pi / 180, o['parameters']['phase_error']"
fi
expect_rc 0 steady --set 'T=0.05 mNm' --set 'f=37 kHz' >/dev/null
# ranges in the unit of the swept parameter, known only after --over
if expect_rc 0 sweep --from 36kHz --to 37kHz --over f --points 3 --no-floquet --json; then
    py "assert [q['f'] for q in o['points']] == [36000.0, 36500.0, 37000.0], o['points']"
fi
if expect_rc 0 map --x-from 30kHz --x-to 46kHz --x-points 2 --y-to 8mNm --y-points 2 --json; then
    py "assert {(q['x'], q['y']) for q in o['points']} == {(30000.0, 0.0), (46000.0, 0.0), (30000.0, 0.008), (46000.0, 0.008)}, o['points']"
fi

# ---- bad units: exit 2, the accepted list ----------------------------------------
expect_bad '--set T' 'kHz is not a unit of a value in \[N m\] \(accepted: Nm, mNm, Nmm, uNm\)' steady --set T=5kHz
expect_bad '--set f' 'not a number, nor a number with a unit of \[Hz\] \(accepted: Hz, kHz, MHz\)' steady --set f=37furlongs
expect_bad '--set phase_error' 'accepted: rad, mrad, urad, deg' steady --set phase_error=10grad
expect_bad '--from' 'accepted: Hz, kHz, MHz' sweep --over f --from 36mN --to 37kHz
expect_bad '--x-to' 'accepted: Nm, mNm, Nmm, uNm' map --x T --x-from 0 --x-to 8kHz --y f --y-from 30kHz --y-to 40kHz
expect_bad '--vary' 'accepted: N, kN, mN, uN' optimize --objective rotor_speed --vary F0=300mN:500Hz
expect_bad '--t0' 'accepted: s, ms, us' steady --t0 5Hz
expect_bad '--vary F0' 'accepted: N, kN, mN, uN' tolerance --samples 10 --vary F0=uniform:350mN:450kHz
if expect_rc 0 tolerance --samples 20 --vary F0=uniform:350mN:450mN --vary T=normal:0.01mNm --json; then
    py "assert o['samples'] == 20, o"
fi

# ---- JSON: the shortest numbers; decimal grids as typed --------------------------
if expect_rc 0 steady --json; then
    grep -q '"m0": 0.005,' "$out" || fail "usm steady --json: m0 is not printed as 0.005"
fi
if expect_rc 0 sweep --over T --from 0.001 --to 0.005 --points 9 --no-floquet --json; then
    grep -q '"T": 0.0035,' "$out" || fail "sweep: the grid value 0.0035 is not printed as typed"
    py "want = [0.001, 0.0015, 0.002, 0.0025, 0.003, 0.0035, 0.004, 0.0045, 0.005]
got = [q['T'] for q in o['points']]
assert got == want, got"
fi

if expect_rc 0 map --x T --x-from 0.001 --x-to 0.005 --x-points 9 --y f --y-from 36.5kHz --y-to 37kHz --y-points 2 --json; then
    py "xs = sorted({q['x'] for q in o['points']})
assert xs == [0.001, 0.0015, 0.002, 0.0025, 0.003, 0.0035, 0.004, 0.0045, 0.005], xs"
fi
if expect_rc 0 sweep --variant imperfect --over phase_error --from 0.001 --to 0.005 --points 9 --json; then
    py "got = [q['phase_error'] for q in o['points']]
assert got == [0.001, 0.0015, 0.002, 0.0025, 0.003, 0.0035, 0.004, 0.0045, 0.005], got"
fi

# ---- help: the usage lines ----------------------------------------------------------
for cmd in steady sweep map simulate; do
    if expect_rc 0 "$cmd" --help; then
        sed -n '/^usage:/,/^$/p' "$out" | grep -q -- '--variant' || fail "usm $cmd --help: no --variant in the usage lines"
    fi
done
if expect_rc 0 tolerance --help; then
    sed -n '/^usage:/,/^$/p' "$out" | grep -q -- '--floquet-method NAME\] \[--rtol R' ||
        fail "usm tolerance --help: no --floquet-method/--rtol in the usage lines"
fi
if expect_rc 0 steady --help; then
    # the parameter table: every value column starts at one position
    cols=$(sed -n '/^parameters/,/^$/p' "$out" | awk 'NR > 1 && NF >= 3 {print index($0, $2)}' | sort -u | wc -l)
    [ "$cols" -eq 1 ] || fail "usm steady --help: the parameter table is not aligned"
    grep -q '^  Hz  *Hz, kHz, MHz$' "$out" || fail "usm steady --help: no units table"
fi
if expect_rc 0 variants --help; then
    for cmd in steady sweep map simulate periodic sensitivity optimize tolerance equations; do
        grep -q "$cmd" "$out" || fail "usm variants --help does not name $cmd"
    done
fi

# ---- units out (--units): values shown in rpm, deg, mNm; JSON stays SI ------------
# Truth: the units' definitions (1 rpm = 2 pi/60 1/s, 1 deg = pi/180 rad) applied
# to the SI output of the same run.
if expect_rc 0 steady --json; then cp "$out" "$tmp/steady_si.json"; fi
if expect_rc 0 steady --json --units rpm,deg; then
    cmp -s "$out" "$tmp/steady_si.json" || fail "steady --json --units: the JSON is not the SI one"
fi
if expect_rc 0 steady --units rpm,deg; then
    py_si() { "$PY" - "$tmp/steady_si.json" "$out" <<'PYEOF'
import json, math, sys
o = json.load(open(sys.argv[1]))
rows = {l.split()[0]: l.split() for l in open(sys.argv[2]) if l.startswith('  ') and len(l.split()) > 2}
w, th = rows['rotor_speed'], rows['theta']
assert w[2] == 'rpm' and th[2] == 'deg', (w, th)
assert abs(float(w[1]) - o['rotor_speed'] * 60 / (2 * math.pi)) <= 1e-9 * abs(float(w[1])), w
assert abs(float(th[1]) - o['theta'] * 180 / math.pi) <= 1e-9 * abs(float(th[1])), th
PYEOF
    }
    checks=$((checks + 1)); py_si || fail "steady --units rpm,deg: the table is not the SI values converted"
fi
if expect_rc 0 sweep --over T --from 0 --to 2mNm --points 5 --no-floquet; then cp "$out" "$tmp/sweep_si.csv"; fi
if expect_rc 0 sweep --over T --from 0 --to 2mNm --points 5 --no-floquet --units rpm,deg,mNm; then
    checks=$((checks + 1))
    "$PY" - "$tmp/sweep_si.csv" "$out" <<'PYEOF' || fail "sweep --units: the CSV is not the SI one converted"
import csv, math, sys
def read(path):
    lines = open(path).read().splitlines()
    rows = list(csv.DictReader([l for l in lines if not l.startswith('#')]))
    return rows, [l for l in lines if l.startswith('# stick_limit')]
si, ev_si = read(sys.argv[1])
sh, ev_sh = read(sys.argv[2])
scale = {'T': ('T [N m]', 'T [mNm]', 1e-3), 'theta': ('theta [rad]', 'theta [deg]', math.pi / 180),
         'rotor_speed': ('rotor_speed [1/s]', 'rotor_speed [rpm]', 2 * math.pi / 60),
         'op_theta': ('op_theta [rad]', 'op_theta [deg]', math.pi / 180)}
for a, b in zip(si, sh):
    for k, (ca, cb, f) in scale.items():
        if a[ca] == '':
            assert b[cb] == '', (k, b[cb])
            continue
        assert abs(float(b[cb]) * f - float(a[ca])) <= 1e-14 * abs(float(a[ca])) + 1e-300, (k, a[ca], b[cb])
    assert a['F_n [N]'] == b['F_n [N]'] and a['valid'] == b['valid'], 'other columns changed'
x_si = float(ev_si[0].split(' = ')[1].split(':')[0])
x_sh = float(ev_sh[0].split(' = ')[1].split(':')[0])
assert abs(x_sh * 1e-3 - x_si) <= 1e-14 * x_si, (x_si, x_sh)
PYEOF
fi
# a time history written in rpm and deg continues a run as the SI one does
if expect_rc 0 simulate --duration 0.0002 --out "$tmp/h_si.csv" &&
   expect_rc 0 simulate --duration 0.0002 --units rpm,deg --out "$tmp/h_rpm.csv"; then
    head -1 "$tmp/h_rpm.csv" | grep -q 'phi_Rdot \[rpm\].*theta_avg \[deg\]' ||
        fail "simulate --units: the header does not name rpm and deg"
    if expect_rc 0 simulate --duration 0.0001 --rate 0 --from "$tmp/h_si.csv" --json; then cp "$out" "$tmp/c_si.json"; fi
    if expect_rc 0 simulate --duration 0.0001 --rate 0 --from "$tmp/h_rpm.csv" --json; then
        checks=$((checks + 1))
        "$PY" - "$tmp/c_si.json" "$out" <<'PYEOF' || fail "simulate --from a file in rpm/deg: not the run from the SI file"
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:3])
xa, xb = a['final_state']['x'], b['final_state']['x']
assert all(abs(p - q) <= 1e-9 * max(1.0, abs(p)) for p, q in zip(xa, xb)), (xa, xb)
PYEOF
    fi
fi
if expect_rc 0 map --x-points 2 --y-points 2 --units kHz,mNm --quiet; then
    head -1 "$out" | grep -q '^f \[kHz\],T \[mNm\],' || fail "map --units kHz,mNm: header $(head -1 "$out")"
fi
expect_bad '--units' '"furlong" is not a unit usm knows' steady --units furlong
expect_bad '--units' 'rpm and rad/s are both units of \[1/s\]' sweep --over T --units rpm,rad/s
expect_bad '--units' 'a ratio' simulate --duration 1e-4 --units %
expect_bad '--units' 'unknown option' optimize --units rpm

finish units_cli
