#!/bin/bash
# usm sensitivity and the power fields of usm steady from the command line:
#  - --json has exactly the documented shape: {"model", "parameters",
#    "outputs": {NAME: {"value", "d": {PARAM}, "elasticity": {PARAM}}}} with all
#    23 parameters, the default outputs, and elasticity = (p / value) d;
#  - the values equal `usm steady --json` (theta, rotor_speed, F_n, F_t,
#    efficiency, mu0 F_n - F_t) and its max_modulus (1e-6: the Floquet methods);
#  - usm steady --json carries power_in, power_out, power_damping, power_slip and
#    efficiency = power_out / power_in;
#  - exit codes as usm steady: 2 for bad input naming the field, 3 when no
#    stationary solution exists.
#
# usage: sensitivity_cli.sh PATH/TO/usm
set -u

USM=${1:?usage: sensitivity_cli.sh PATH/TO/usm}
. "$(dirname "$0")/../cli_common.sh"

for model in 3dof 4dof; do
    expect_rc 0 steady --model $model --json && cp "$out" "$tmp/steady.json"
    py_file "$tmp/steady.json" "
for k in ('power_in', 'power_out', 'power_damping', 'power_slip', 'efficiency'):
    assert k in o, k
assert abs(o['efficiency'] - o['power_out'] / o['power_in']) <= 1e-15, o['efficiency']
bal = o['power_in'] - o['power_out'] - o['power_damping'] - o['power_slip']
assert abs(bal) <= 1e-9 * o['power_in'], bal"
    expect_rc 0 sensitivity --model $model --json
    py "
s = json.load(open('$tmp/steady.json'))
assert list(o) == ['model', 'parameters', 'outputs'], list(o)
assert o['model'] == '$model'
names = ['theta', 'rotor_speed', 'F_n', 'F_t', 'efficiency', 'stick_margin', 'max_modulus']
assert list(o['outputs']) == names, list(o['outputs'])
params = o['parameters']
assert len(params) == 23
want = {'theta': s['theta'], 'rotor_speed': s['rotor_speed'], 'F_n': s['F_n'], 'F_t': s['F_t'],
        'efficiency': s['efficiency'], 'stick_margin': params['mu0'] * s['F_n'] - s['F_t']}
for name, v in o['outputs'].items():
    assert list(v) == ['value', 'd', 'elasticity'], (name, list(v))
    assert list(v['d']) == list(params) and list(v['elasticity']) == list(params)
    if name in want:
        assert abs(v['value'] - want[name]) <= 1e-12 * abs(want[name]), (name, v['value'])
    for p, d in v['d'].items():
        e = v['elasticity'][p]
        assert abs(e - params[p] / v['value'] * d) <= 1e-12 * abs(e) + 1e-300, (name, p, e)
mm = o['outputs']['max_modulus']['value']
assert abs(mm - s['floquet']['max_modulus']) <= 1e-6, (mm, s['floquet']['max_modulus'])
assert o['outputs']['stick_margin']['d']['mu0'] != 0"
done

expect_rc 0 sensitivity --of rotor_speed,power_out --json
py "assert list(o['outputs']) == ['rotor_speed', 'power_out'], list(o['outputs'])"
expect_rc 0 sensitivity --of max_modulus
grep -q '^max_modulus = ' "$out" || fail "table lacks max_modulus"
expect_bad --of "unknown output" sensitivity --of bogus
expect_bad --of "comma-separated" sensitivity --of ''
expect_bad --frobnicate "unknown option" sensitivity --frobnicate
expect_bad f "" sensitivity --set f=-1
checks=$((checks + 1))
run sensitivity --set m0=1e-9
rc=$?
[ $rc -eq 3 ] || fail "sensitivity without a stationary solution: exit $rc, want 3"
[ "$(wc -l <"$err")" -eq 1 ] && grep -q '^usm: no stationary solution' "$err" ||
    fail "sensitivity without a stationary solution: stderr"

finish sensitivity_cli
