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

finish units_cli
