#!/bin/bash
# The usm command's input handling: every kind of bad input must exit with
# status 2 and ONE line on stderr naming the field and the reason, never a
# crash or a NaN; --json must print one parseable object; a case without a
# stationary solution must exit with 3.
#
# usage: cli_bad_input.sh PATH/TO/usm
set -u

USM=${1:?usage: cli_bad_input.sh PATH/TO/usm}
. "$(dirname "$0")/../cli_common.sh"

# ---- parameter files --------------------------------------------------------
printf '{\n  "m0": 0.006,\n  "T": ,\n}\n' >"$tmp/malformed.json"
printf '{"m0": 0.006, "T": 1e-5}\n' >"$tmp/good.json"
printf '{"m0": "5 kHz"}\n' >"$tmp/string.json"
printf '{"m0": true}\n' >"$tmp/bool.json"
printf '{"m0": null}\n' >"$tmp/null.json"
printf '{"m0": [1]}\n' >"$tmp/array_value.json"
printf '{"nosuch": 1}\n' >"$tmp/unknown.json"
printf '[1, 2]\n' >"$tmp/toplevel.json"
printf '{"m0": 1, "m0": 2}\n' >"$tmp/duplicate.json"
printf '{"m0": 1e999}\n' >"$tmp/overflow.json"
printf '{"m0": NaN}\n' >"$tmp/nan.json"
printf '{"I_xx": -1, "I_yy": -1}\n' >"$tmp/negative.json"
: >"$tmp/empty.json"
mkdir "$tmp/dir.json"

# ---- bad input: unknown parameter names -------------------------------------
expect_bad '--set nosuch' 'unknown parameter' steady --set nosuch=1
expect_bad 'nosuch' 'unknown parameter' steady --params "$tmp/unknown.json"
expect_bad 'unknown.json' 'unknown parameter' steady --params "$tmp/unknown.json"

# ---- bad input: values that are not numbers ---------------------------------
expect_bad '--set m0' 'not a number' steady --set m0=abc
expect_bad '--set m0' 'not a number' steady --set m0=
expect_bad '--set m0' 'not a number' steady --set m0=1e5x
expect_bad '--set m0' 'not a number' steady --set 'm0= 1'
expect_bad '--set m0' 'not a number' steady --set m0=0x
expect_bad '--set m0' 'expected NAME=VALUE' steady --set m0
expect_bad '--set' 'expected NAME=VALUE' steady --set =1
expect_bad 'm0' 'kHz is not a unit of a value in \[N m\] \(accepted: Nm, mNm, Nmm, uNm\)' steady --params "$tmp/string.json"
expect_bad 'm0' 'expected a number' steady --params "$tmp/bool.json"
expect_bad 'm0' 'expected a number' steady --params "$tmp/null.json"
expect_bad 'm0' 'expected a number' steady --params "$tmp/array_value.json"

# ---- bad input: NaN, infinity, overflow ---------------------------------------
for v in nan NaN -nan inf -inf +inf Infinity; do
    expect_bad '--set m0' 'not a finite number' steady --set "m0=$v"
done
expect_bad '--set T' 'out of range' steady --set T=1e999
expect_bad '--set T' 'out of range' steady --set T=-1e999
expect_bad 'overflow.json: m0' 'out of range.*overflow' steady --params "$tmp/overflow.json"
expect_bad 'nan.json:1:' 'malformed JSON' steady --params "$tmp/nan.json"

# ---- one number parser: --set and the parameter file agree -------------------
# a subnormal, an underflow to 0 and an overflow are rejected by
# both, naming the field; an integer beyond 2^63 is read by both as a double.
for v in 1e-310 -1e-310 1e-400 4.9e-324; do
    printf '{"T": %s}\n' "$v" >"$tmp/num.json"
    expect_bad '--set T' 'out of range.*underflow' steady --set "T=$v"
    expect_bad 'num.json: T' 'out of range.*underflow' steady --params "$tmp/num.json"
done
for v in 1e999 -1e400 1797693134862315807937289714053034150799341327710e260; do
    printf '{"T": %s}\n' "$v" >"$tmp/num.json"
    expect_bad '--set T' 'out of range.*overflow' steady --set "T=$v"
    expect_bad 'num.json: T' 'out of range.*overflow' steady --params "$tmp/num.json"
done
for v in 0 -0 0.0e-999 1e-300 2.2250738585072014e-308; do
    printf '{"T": %s}\n' "$v" >"$tmp/num.json"
    if expect_rc 0 steady --set "T=$v" --json; then cp "$out" "$tmp/set.out"; fi
    if expect_rc 0 steady --params "$tmp/num.json" --json; then
        py_file "$tmp/set.out" "assert o['parameters']['T'] == float('$v'), o['parameters']['T']"
        py "assert o['parameters']['T'] == float('$v'), o['parameters']['T']"
    fi
done
# (read as the double 9.87654e+28 by both, and refused by both for lying
# outside kappa's physical range)
big=98765432109876543210987654321
printf '{"kappa": %s}\n' "$big" >"$tmp/num.json"
expect_bad 'kappa = 9.87654e+28 s/m' 'outside' steady --params "$tmp/num.json" --json
expect_bad 'kappa = 9.87654e+28 s/m' 'outside' steady --set "kappa=$big" --json
# the file's syntax is JSON's: no hex, no leading '+', no blanks inside
for v in 0x10 +1 '1 0' .5 01; do
    printf '{"T": %s}\n' "$v" >"$tmp/num.json"
    expect_bad 'num.json:1:' 'malformed JSON' steady --params "$tmp/num.json"
done

# ---- bad input: non-physical values (usm_params_check) ------------------------
expect_bad 'I_xx' 'must be positive' steady --set I_xx=-1e-8 --set I_yy=-1e-8
expect_bad 'I_zz' 'must be positive' steady --set I_zz=-1e-8
expect_bad 'I_R' 'must be positive' steady --set I_R=0
expect_bad 'c_R' 'must not be negative' steady --set c_R=-1
expect_bad 'c_r' 'must not be negative' steady --set c_r=-1
expect_bad 'c_t' 'must not be negative' steady --set c_t=-1
expect_bad 'usm: R:' 'must be positive' steady --set R=-0.005
expect_bad 'usm: H:' 'must be positive' steady --set H=-0.003
expect_bad 'usm: f:' 'must be positive' steady --set f=0
expect_bad 'usm: f:' 'must be positive' steady --model 4dof --set f=-37000
expect_bad 'I_yy' 'must equal I_xx' steady --set I_yy=2e-8
expect_bad 'I_xx' 'must be positive' steady --params "$tmp/negative.json"
# --set is applied after the file, whatever the order on the command line
expect_bad 'I_xx' 'must be positive' steady --set I_xx=-1 --params "$tmp/good.json"

# ---- bad input: a value in the wrong unit (the parameter ranges of
# derive/usm_derive/defaults.py, usm_param_check_value) -------------------------
# f = 38 was solved at 38 Hz and called valid; phase_error = 35 was 35 rad
expect_bad 'f = 38 Hz is outside 1 kHz..1 MHz' 'did you mean 38 kHz\?' steady --set f=38
expect_bad 'phase_error = 35 rad is outside' 'did you mean 35 deg\?' \
    periodic --variant imperfect --set phase_error=35
expect_bad 'F0 = 400 N is outside' 'did you mean 400 mN\?' steady --set F0=400
expect_bad 'R = 5 m is outside 100 um..10 cm' 'did you mean 5 mm\?' steady --set R=5
printf '{"f": 38}\n' >"$tmp/hz.json"
expect_bad 'f = 38 Hz is outside' 'did you mean 38 kHz' steady --params "$tmp/hz.json"
# with its unit the same number is inside, and an angle in degrees is taken
expect_rc 0 steady --set f=38kHz >/dev/null
expect_rc 0 periodic --variant imperfect --set phase_error=35deg >/dev/null

# ---- bad input: files ---------------------------------------------------------
expect_bad 'malformed.json:3:' 'malformed JSON' steady --params "$tmp/malformed.json"
checks=$((checks + 1))
grep -qE 'malformed\.json:[0-9]+:[0-9]+: malformed JSON: ' "$err" ||
    fail "malformed JSON: no FILE:LINE:COLUMN in the message"
expect_bad 'duplicate.json' 'duplicate' steady --params "$tmp/duplicate.json"
expect_bad 'toplevel.json' 'expected a JSON object' steady --params "$tmp/toplevel.json"
expect_bad 'empty.json' 'malformed JSON' steady --params "$tmp/empty.json"
expect_bad 'missing.json' 'cannot open' steady --params "$tmp/missing.json"
expect_bad 'dir.json' 'cannot read' steady --params "$tmp/dir.json"
expect_bad '--params' 'empty file name' steady --params=

# ---- bad input: options, models, commands -------------------------------------
expect_bad '--frobnicate' 'unknown option' steady --frobnicate
expect_bad '--json=1' 'unknown option' steady --json=1
expect_bad '--frobnicate' 'unknown option' --frobnicate
expect_bad 'frobnicate' 'unknown command' frobnicate
expect_bad 'frobnicate' 'unknown command' help frobnicate
expect_bad 'stray' 'unexpected argument' steady stray
expect_bad '--model' 'unknown model' steady --model 5dof
expect_bad '--model' 'unknown model' steady --model=
expect_bad '--t0' 'not a number' steady --t0 abc
expect_bad '--t0' 'not a number' steady --t0=
expect_bad '--t0' 'not a finite number' steady --t0 nan
expect_bad '--t0' 'not a finite number' steady --t0 inf
expect_bad '--t0' 'out of range' steady --t0 1e400
for opt in --params --set --model --t0; do
    expect_bad "$opt" 'missing argument' steady "$opt"
done
# bad input in --json mode is still a one-line error, not a JSON object
expect_bad '--set m0' 'not a number' steady --json --set m0=abc

# ---- help and version ---------------------------------------------------------
if expect_rc 0 --help; then
    checks=$((checks + 1)); grep -q '^usage: usm' "$out" || fail "usm --help: no usage"
fi
if expect_rc 0 steady --help; then
    checks=$((checks + 1)); grep -q '^usage: usm steady' "$out" || fail "usm steady --help: no usage"
fi
if expect_rc 0 help steady; then
    checks=$((checks + 1)); grep -q '^usage: usm steady' "$out" || fail "usm help steady: no usage"
fi
if expect_rc 0 --version; then
    checks=$((checks + 1))
    head -n 1 "$out" | grep -qE '^usm [0-9]+\.[0-9]+\.[0-9]+' || fail "usm --version: first line"
    grep -qE 'generator [0-9]+\.[0-9]+\.[0-9]+' "$out" || fail "usm --version: no generator version"
fi
if expect_rc 2; then
    checks=$((checks + 1))
    [ ! -s "$out" ] && grep -q '^usage: usm' "$err" || fail "usm without arguments: usage on stderr"
fi

# ---- solved cases ---------------------------------------------------------------
ROOT_KEYS="'theta','alpha','beta','rotor_speed','F_n','F_t','v_rel','stick_admissible'"
TOP_KEYS="'model','parameters','converged','floquet','roots','mu_used','v_c','R_star','Z',$ROOT_KEYS"
PARAMS="'m0','T','F0','c_R','d_R','c_t','c_r','d_t','d_r','R','H','I_R','I_xx','I_yy','I_zz','M','f','mu0','kappa','amp_imbalance','phase_error','mode_split','e_impact'"
CHECK_SOLVED="
import math
for k in [$TOP_KEYS]: assert k in o, 'missing key ' + k
assert 'error' not in o, 'error key although converged'
assert o['converged'] is True
assert sorted(o['parameters']) == sorted([$PARAMS]), 'parameters: ' + str(sorted(o['parameters']))
assert len(o['roots']) >= 1
for r in o['roots']:
    for k in [$ROOT_KEYS]: assert k in r, 'root lacks ' + k
    assert isinstance(r['stick_admissible'], bool)
assert o['roots'][0]['theta'] == o['theta']
fl = o['floquet']
for k in ['t0','multipliers','stable','max_modulus','cyclic']: assert k in fl, 'floquet lacks ' + k
assert len(fl['multipliers']) >= 6 and all(len(z) == 2 for z in fl['multipliers'])
assert len(fl['cyclic']) == len(fl['multipliers'])
assert isinstance(fl['stable'], bool)
def finite(x):
    if isinstance(x, dict): return all(finite(v) for v in x.values())
    if isinstance(x, list): return all(finite(v) for v in x)
    if isinstance(x, float): return math.isfinite(x)
    return True
assert finite(o), 'non-finite number'
"

if expect_rc 0 steady; then
    checks=$((checks + 1)); grep -q 'theta' "$out" || fail "usm steady: no table"
fi
if expect_rc 0 steady --json; then
    py "$CHECK_SOLVED
assert o['model'] == '3dof'
assert o['floquet']['t0'] == 0.0
assert o['stick_admissible'] is True and o['rotor_speed'] < 0
assert o['parameters']['m0'] == 0.005"
fi
if expect_rc 0 steady --model 4dof --json --t0 1e-6; then
    py "$CHECK_SOLVED
assert o['model'] == '4dof'
assert o['floquet']['t0'] == 1e-6
assert o['v_rel'] > 0"
fi
# --set wins over the file even when given first; the file wins over defaults
if expect_rc 0 steady --set m0=0.007 --params "$tmp/good.json" --json; then
    py "$CHECK_SOLVED
assert o['parameters']['m0'] == 0.007, o['parameters']['m0']
assert o['parameters']['T'] == 1e-5, o['parameters']['T']"
fi
if expect_rc 0 steady --set m0=0.006 --set m0=0.008 --json; then
    py "assert o['parameters']['m0'] == 0.008"
fi

# ---- no stationary solution: exit 3 --------------------------------------------
# m0 = 1e-6 N m cannot tilt the stator at all; T = 2 mN m is beyond what
# friction can carry in the slip model.
for args in "--set m0=1e-6" "--model 4dof --set T=0.002"; do
    # shellcheck disable=SC2086 # word splitting of $args is intended
    if expect_rc 3 steady $args; then
        checks=$((checks + 1))
        [ ! -s "$out" ] && [ "$(wc -l <"$err")" -eq 1 ] &&
            grep -q '^usm: no stationary solution: ' "$err" ||
            fail "usm steady $args: want one line 'usm: no stationary solution: ...'"
    fi
    # shellcheck disable=SC2086
    if expect_rc 3 steady $args --json; then
        py "assert o['converged'] is False
assert isinstance(o['error'], str) and o['error'], 'no error string'
assert o['roots'] == []
assert 'model' in o and len(o['parameters']) == 23"
    fi
done

finish cli_bad_input
