#!/bin/bash
# usm optimize from the command line:
#  - --json has the keys of issue 13 (objective, sense, value, varied, parameters,
#    active_constraints, kkt_residual, evaluations, solution = a usm steady object);
#  - the optimum meets every constraint (a user constraint, the stability margin)
#    and its value is the solution's;
#  - no feasible point: exit 3 naming the constraint; bad specification: exit 2
#    naming the field.
# (The optimum against a grid search: test_optimize.c.)
#
# usage: optimize_cli.sh PATH/TO/usm
set -u

USM=${1:?usage: optimize_cli.sh PATH/TO/usm}
. "$(dirname "$0")/cli_common.sh"

expect_rc 0 optimize --objective efficiency --vary F0=0.2:0.8 --vary f=36000:38000 --set T=3e-4 \
    --stability-margin 0.02 --constraint 'rotor_speed>=8' --starts 4 --json
py "
assert list(o) == ['objective', 'sense', 'value', 'varied', 'parameters', 'active_constraints',
                   'kkt_residual', 'evaluations', 'solution'], list(o)
assert o['objective'] == 'efficiency' and o['sense'] == 'max'
assert list(o['varied']) == ['F0', 'f'] and len(o['parameters']) == 22
assert 0.2 <= o['varied']['F0'] <= 0.8 and 36000 <= o['varied']['f'] <= 38000
for k, v in o['varied'].items():
    assert o['parameters'][k] == v and o['solution']['parameters'][k] == v
s = o['solution']
assert abs(s['efficiency'] - o['value']) <= 1e-12 * o['value']
assert -s['rotor_speed'] >= 8 * (1 - 1e-6), s['rotor_speed']
assert s['floquet']['max_modulus'] <= 0.98 + 1e-6
assert s['stick_admissible']
assert 'rotor_speed >= 8' in o['active_constraints'], o['active_constraints']
assert isinstance(o['evaluations'], int) and o['evaluations'] > 0
assert o['kkt_residual'] <= 1e-6"

# the speed grows with m0, so the optimum is the upper bound, exactly: 0.001 + (0.01 - 0.001)
# rounds to 0.010000000000000002 (issue 22)
expect_rc 0 optimize --objective rotor_speed --vary m0=0.001:0.01 --starts 2 --json
py "
assert o['varied']['m0'] == 0.01, repr(o['varied']['m0'])
assert o['parameters']['m0'] == 0.01 and o['solution']['parameters']['m0'] == 0.01"

expect_rc 0 optimize --objective rotor_speed --minimize --vary m0=0.004:0.006 --starts 2
grep -q '^minimum of rotor_speed' "$out" || fail "table lacks the minimum line"

checks=$((checks + 1))
run optimize --objective efficiency --vary F0=0.2:0.8 --constraint 'power_out>=1' --starts 2
rc=$?
[ $rc -eq 3 ] || fail "infeasible: exit $rc, want 3"
grep -q '^usm: constraint: .*power_out >= 1' "$err" || fail "infeasible: stderr does not name the constraint"

expect_bad --objective "unknown output" optimize --objective bogus --vary F0=0.2:0.8
expect_bad --objective "required" optimize --vary F0=0.2:0.8
expect_bad --vary "required" optimize --objective efficiency
expect_bad --vary "unknown parameter" optimize --objective efficiency --vary Q=0:1
expect_bad --vary "less than" optimize --objective efficiency --vary F0=0.8:0.2
expect_bad --vary "NAME=LO:HI" optimize --objective efficiency --vary F0=0.8
expect_bad --vary "twice" optimize --objective efficiency --vary F0=0.2:0.8 --vary F0=0.3:0.4
expect_bad --vary "I_xx" optimize --objective efficiency --vary I_yy=1e-8:2e-8
expect_bad --constraint "OUTPUT>=X" optimize --objective efficiency --vary F0=0.2:0.8 --constraint F_n=3
expect_bad --constraint "unknown output" optimize --objective efficiency --vary F0=0.2:0.8 --constraint 'x>=3'
expect_bad --stability-margin "0, 1" optimize --objective efficiency --vary F0=0.2:0.8 --stability-margin 1.5
expect_bad --starts "integer" optimize --objective efficiency --vary F0=0.2:0.8 --starts 0

finish optimize_cli
