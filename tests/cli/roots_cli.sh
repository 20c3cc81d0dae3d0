#!/bin/bash
# Every root with its stability, and where a start-up ends, from
# the command line: `usm steady --json` gives each root its own "floquet"
# with the top level's keys (root 0's equal to the top level's), the table
# one line per root with its stability; `usm simulate` names the root it
# settled on (settled_on), checked against `usm steady`'s roots.
#
# usage: roots_cli.sh PATH/TO/usm
set -u

USM=${1:?usage: roots_cli.sh PATH/TO/usm}
. "$(dirname "$0")/../cli_common.sh"

# ---- steady: every root's multipliers ------------------------------------------
if expect_rc 0 steady --set F0=1.2 --set f=38000 --no-from-rest --json; then
    cp "$out" "$tmp/steady12.json"
    py "
r = o['roots']
assert len(r) == 2, len(r)
for k, root in enumerate(r):
    assert set(root['floquet']) == set(o['floquet']), (k, sorted(root['floquet']))
assert r[0]['floquet'] == o['floquet'], 'root 0 differs from the top level'
assert not r[0]['floquet']['stable'] and abs(r[0]['floquet']['max_modulus'] - 1.1383964) < 1e-6
assert r[1]['floquet']['stable'] and abs(r[1]['theta'] - 8.0137e-5) < 1e-8
assert o['theta'] == r[0]['theta'] and not o['floquet']['stable']"
fi
if expect_rc 0 steady --set F0=1.2 --set f=38000; then
    grep -qE '^ +1 +2\.365459127e-05 .* unstable$' "$out" || fail "table: root #1 not unstable"
    grep -qE '^ +2 +8\.013712534e-05 .* stable$' "$out" || fail "table: root #2 not stable"
fi
if expect_rc 0 steady --json; then
    py "
assert len(o['roots']) == 1 and o['roots'][0]['floquet'] == o['floquet']"
fi

# ---- steady: the operating point ------------------------------------------------
if expect_rc 0 steady --json; then
    py "
assert o['operating_point'] == 0 and o['operating_point_reason'] == 'only_stable_root'
assert o['starts_from_rest'] is None and 'from_rest' not in o"
fi
py_file "$tmp/steady12.json" "
assert o['operating_point'] is None and o['operating_point_reason'] is None
assert o['starts_from_rest'] is None and 'start-up from rest' in o['operating_point_message']"
# F0 = 1.001 N is above the start threshold (0.99997 N): from rest, below root #1,
# the motor does not start (docs/operating-point.md)
if expect_rc 0 steady --set F0=1.001 --set f=38000 --from-rest --json; then
    py "
assert o['operating_point'] is None and o['operating_point_reason'] == 'does_not_start'
assert o['starts_from_rest'] is False and o['from_rest']['settled_on'] == 'rest'
assert o['from_rest']['tilt_start'] <= 1e-2 * o['roots'][0]['theta'] and o['start_margin'] < 0"
fi
if expect_rc 0 steady --set F0=1.2 --set f=38000 --from-rest --json; then
    py "
assert o['operating_point'] is None and o['operating_point_reason'] == 'does_not_start'
assert o['starts_from_rest'] is False and o['from_rest']['stop'] == 'rest'
assert o['theta'] == o['roots'][0]['theta']"
fi
if expect_rc 0 steady --set F0=1.2 --set f=38000 --from-rest; then
    grep -q '^operating point  *none (does_not_start)' "$out" || fail "table: no does_not_start"
    grep -q 'starts from rest:  no: the wobble decays' "$out" || fail "table: starts from rest"
fi
if expect_rc 0 steady --set f=32000 --set T=0.004 --json; then
    py "assert o['operating_point'] is None and o['operating_point_reason'] == 'no_stable_root'"
fi
expect_bad --from-rest-periods 'must be in' steady --from-rest --from-rest-periods 0

# ---- simulate: which root a start-up from rest ends on --------------------------
if expect_rc 0 steady --set F0=1.001 --set f=38000 --json; then
    cp "$out" "$tmp/steady1001.json"
fi
# from 1e-6 rad, above root #1 (not a start at rest): root #2
if expect_rc 0 simulate --set F0=1.001 --set f=38000 --tilt0 1e-6 --duration 6e-3 --rate 0 --json; then
    py "
s = json.load(open('$tmp/steady1001.json'))
assert o['settled_on'] == 1 and o['roots'] == 2, (o['settled_on'], o['roots'])
assert not o['settled'], 'settled refers to root 0'
r = s['roots'][1]
assert abs(r['theta'] - 8.635e-5) < 1e-8 and abs(r['rotor_speed'] + 12.37) < 5e-3
assert abs(o['settled_root']['theta'] - r['theta']) <= 1e-15 * r['theta']
assert abs(o['theta_avg_end'] / r['theta'] - 1) < 1e-3
assert abs(o['rotor_speed_avg_end'] / r['rotor_speed'] - 1) < 1e-3
assert not s['roots'][0]['floquet']['stable'] and s['roots'][1]['floquet']['stable']"
fi
if expect_rc 0 simulate --set F0=1.001 --set f=38000 --tilt0 1e-6 --duration 6e-3 --rate 0; then
    grep -q 'settled on  *root #2 of 2 (theta = 8.635042134e-05 rad' "$out" ||
        fail "table: does not say it settled on root #2"
fi
if expect_rc 0 simulate --duration 5e-3 --rate 0 --json; then
    py "assert o['settled_on'] == 0 and o['settled'] and o['roots'] == 1"
fi
# the wobble decays at F0 = 1.2 N: rest, the run stops there (exit 0)
if expect_rc 0 simulate --set F0=1.2 --set f=38000 --duration 2e-3 --rate 0 --json; then
    py "
assert o['settled_on'] == 'rest' and o['stop'] == 'rest' and not o['completed'], o['stop']
assert o['theta_avg_end'] < o['rest_fraction'] * o['rest_theta_ref'] and o['t_rest'] == o['t_reached']"
fi
if expect_rc 0 simulate --set F0=1.2 --set f=38000 --duration 2e-3 --rate 0; then
    grep -q 'settled on  *rest: the wobble decayed' "$out" || fail "table: does not say rest"
fi
# too short to settle: null
if expect_rc 0 simulate --duration 1e-3 --rate 0 --json; then
    py "assert o['settled_on'] is None"
fi

finish roots_cli
