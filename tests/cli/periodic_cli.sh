#!/bin/bash
# `usm periodic`: the contract of its options, JSON keys, exit
# codes and --orbit file; its numbers are tested against independent truths in
# test_periodic.c.  Here: the --orbit samples against the JSON summary (the
# extremes and means the command derives from them), the contact check
# against the sign of F_n in the file, and the refusals.
#
# usage: periodic_cli.sh PATH/TO/usm
set -u

USM=${1:?usage: periodic_cli.sh PATH/TO/usm}
. "$(dirname "$0")/../cli_common.sh"

KEYS="['model','parameters','converged','rotor_speed_mean','rotor_speed_ripple','F_n_min','F_n_max',
'friction_needed_max','theta_mean','theta_min','theta_max','harmonic_2','floquet','contact_open',
'openings_per_period','newton_iterations','residual','valid','invalid_reason','squeal_frequency','squeal_multiplier',
'squeal_reason']"

# the paper's twist law has no periodic orbit in these coordinates: exit 2, the reason
expect_bad "model 3dof" "twist" periodic --variant paper
# the default variant of periodic is imperfect
if expect_rc 0 periodic --json; then
    grep -q '"model": "3dof_imperfect"' "$out" || fail "usm periodic: default variant is not imperfect"
fi
expect_bad "model 4dof_friction_tanh" "twist" periodic --model 4dof --variant friction_tanh
# imperfections only in the variant imperfect; the stationary solution only without them
expect_bad "amp_imbalance" "variant imperfect" periodic --variant twist_integrated --set amp_imbalance=0.1
expect_bad "phase_error" "ideal motor" steady --variant imperfect --set phase_error=0.1
# the sweep follows the periodic orbit instead (its events: test_periodic_sweep.c);
# the stationary sweep's own options are refused with it
expect_bad "--no-floquet" "stationary sweep only" sweep --variant imperfect --over phase_error --from 0 --to 0.1 --no-floquet
expect_bad "--periodic" "stationary sweep only" sweep --periodic --variant twist_integrated --over T --from 0 --to 1e-4 --extremum theta
expect_bad "mode_split" "\(-1, 1\)" sweep --variant imperfect --over mode_split --from 0 --to 1
expect_bad "model 3dof" "twist" sweep --periodic --over T --from 0 --to 1e-4 --points 3
if expect_rc 0 sweep --variant imperfect --over phase_error --from 0 --to 0.6 --points 7; then
    checks=$((checks + 1))
    head -1 "$out" | grep -q '^phase_error \[rad\],converged,rotor_speed_mean \[1/s\],rotor_speed_ripple \[1/s\],F_n_min \[N\],F_n_max \[N\],friction_needed_max \[1\],theta_mean \[rad\],theta_min \[rad\],theta_max \[rad\],theta_harmonic_2 \[rad\],F_n_harmonic_2 \[N\],max_modulus \[1\],stable,contact_open,error,valid,invalid_reason$' \
        || fail "periodic sweep: CSV header"
    checks=$((checks + 1))
    [ "$(grep -c '^[0-9]' "$out")" -eq 7 ] && grep -q '^# stick_loss at phase_error = 0\.2724' "$out" \
        && grep -q '^# contact_loss at phase_error = 0\.5013' "$out" \
        && grep -q '^0\.6,true,.*,,.*,true,true,,false,contact_open$' "$out" || fail "periodic sweep: rows and events"
    # the validity limits' own events carry no "model invalid" (their orbits
    # lie on that boundary, on either side by rounding)
    checks=$((checks + 1))
    ! grep -q '^# .*model invalid' "$out" || fail "periodic sweep: a limit event marked invalid"
    # valid: false exactly where the contact opens (F_n_min <= 0)
    # or the stick model needs more than mu0 = 0.3; invalid from past stick_loss on
    checks=$((checks + 1))
    "$PY" - "$out" <<'EOF' || fail "periodic sweep: valid and invalid_reason"
import csv, sys
lines = open(sys.argv[1]).read().splitlines()
rows = list(csv.DictReader([l for l in lines if not l.startswith("#")]))
loss = float([l for l in lines if l.startswith("# stick_loss")][0].split(" = ")[1].split(":")[0])
for r in rows:
    Fmin, fn = float(r["F_n_min [N]"]), r["friction_needed_max [1]"]
    want = "contact_open" if Fmin <= 0 else ("stick_not_admissible" if float(fn) > 0.3 else "")
    assert r["invalid_reason"] == want and r["valid"] == ("false" if want else "true"), r
    assert (r["valid"] == "true") == (float(r["phase_error [rad]"]) < loss), (r, loss)
EOF
fi
if expect_rc 0 sweep --model 4dof --variant imperfect --over mode_split --from 0.08 --to 0.09 --points 3 --json; then
    py "assert sorted(o) == ['events', 'model', 'over', 'parameters', 'periodic', 'points'], sorted(o)
assert o['over'] == 'mode_split' and o['periodic'] is True and len(o['points']) == 3
pt = o['points'][0]
assert pt['converged'] and pt['mode_split'] == 0.08 and 'floquet' in pt and 'F_n_min' in pt
e = [e for e in o['events'] if e['type'] == 'stability_change']
assert len(e) == 1 and e[0]['kind'] == 'neimark_sacker' and abs(e[0]['mode_split'] - 0.0862) < 1e-4, e
assert abs(e[0]['orbit']['floquet']['max_modulus'] - 1) < 1e-8 and e[0]['multiplier'][1] > 0
# the bilateral orbit's contact is open there (F_n_min < 0): the event says so in its text too
assert e[0]['orbit']['F_n_min'] < 0 and not e[0]['orbit']['valid'], e[0]['orbit']['F_n_min']
assert e[0]['what'].endswith('; model invalid: contact_open'), e[0]['what']
assert o['points'][0]['floquet']['stable'] and not o['points'][2]['floquet']['stable']"
fi
# every event within a step, in order: one step of 0.02 holds the
# stick loss and the contact loss
if expect_rc 0 sweep --periodic --variant imperfect --over mode_split --from 0 --to 0.5 --points 26; then
    checks=$((checks + 1))
    grep '^#' "$out" | "$PY" -c "import sys, re
ev = [re.match(r'# (\w+) at mode_split = ([0-9.e+-]+):', l).groups() for l in sys.stdin]
assert [e[0] for e in ev] == ['stick_loss', 'contact_loss'], ev
assert abs(float(ev[0][1]) - 0.0089799) < 1e-7 and abs(float(ev[1][1]) - 0.0164256) < 1e-7, ev" \
        || fail "mode-split sweep: want stick_loss, then contact_loss: $(grep '^#' "$out")"
fi
# friction saturation is its own event, at the stationary sweep's load (1e-9), not a fold
if expect_rc 0 sweep --model 4dof --variant twist_integrated --over T --from 0 --to 0.002 --points 5; then
    cp "$out" "$tmp/stationary.csv"
    if expect_rc 0 sweep --periodic --model 4dof --variant twist_integrated --over T --from 0 --to 0.002 --points 5; then
        checks=$((checks + 1))
        a=$(sed -n 's/^# friction_saturation at T = \([0-9.e+-]*\):.*/\1/p' "$out")
        b=$(sed -n 's/^# friction_saturation at T = \([0-9.e+-]*\):.*/\1/p' "$tmp/stationary.csv")
        { [ -n "$a" ] && [ -n "$b" ] && ! grep -q '^# fold' "$out" && \
          "$PY" -c "import sys; a, b = float(sys.argv[1]), float(sys.argv[2]); assert abs(a / b - 1) <= 1e-9" "$a" "$b" && \
          grep -q '^0\.001,false,.*beyond friction_saturation' "$out"; } \
            || fail "4dof periodic load sweep: friction_saturation '$a', stationary '$b'; events: $(grep '^#' "$out")"
    fi
fi
expect_bad "amp_imbalance" "ideal motor" map --variant imperfect --x amp_imbalance --x-from 0 --x-to 0.1 --x-points 3 --y T --y-from 0 --y-to 1e-4 --y-points 3
expect_bad "mode_split" "\(-1, 1\)" periodic --variant imperfect --set mode_split=1
expect_bad "amp_imbalance" "\[-1, 1\]" periodic --variant imperfect --set amp_imbalance=-1.5
expect_bad "--force" "only with --orbit" periodic --variant imperfect --force
expect_bad "--bogus" "unknown option" periodic --variant imperfect --bogus

# a converged orbit, with the samples written
csv=$tmp/orbit.csv
if expect_rc 0 periodic --model 4dof --variant imperfect --set phase_error=0.2 --set mode_split=0.01 \
        --orbit "$csv" --json; then
    py "assert sorted(o) == sorted($KEYS), sorted(o)
assert o['converged'] and o['model'] == '4dof_imperfect' and not o['contact_open']
assert o['valid'] is True and o['invalid_reason'] is None and o['F_n_min'] > 0
assert sorted(o['harmonic_2']) == ['F_n', 'theta']
assert len(o['floquet']['multipliers']) == 9 and o['floquet']['t0_dependent'] is False
import csv
rows = list(csv.DictReader(open('$csv')))
assert len(rows) == 200, len(rows)
assert list(rows[0])[:3] == ['t [s]', 'phi_R [rad]', 'phi [rad]'], list(rows[0])[:3]
Fn = [float(r['F_n [N]']) for r in rows]
th = [float(r['theta [rad]']) for r in rows]
w = [float(r['rotor_speed [1/s]']) for r in rows]
# sampled extremes bracket the refined ones from inside, within the ripple's 1e-3
for lo, hi, v in ((o['F_n_min'], o['F_n_max'], Fn), (o['theta_min'], o['theta_max'], th)):
    span = hi - lo
    assert lo <= min(v) + 1e-12 * abs(lo) and min(v) - lo <= 1e-3 * span, (lo, min(v))
    assert hi >= max(v) - 1e-12 * abs(hi) and hi - max(v) <= 1e-3 * span, (hi, max(v))
assert abs(sum(w) / len(w) - o['rotor_speed_mean']) <= 1e-12 * abs(o['rotor_speed_mean'])
assert abs(sum(th) / len(th) - o['theta_mean']) <= 1e-12 * o['theta_mean']
T = 1 / o['parameters']['f']
assert abs(float(rows[-1]['t [s]']) - T * 199 / 200) <= 1e-15"
    # never over an existing file without --force
    expect_bad "--orbit" "exists" periodic --model 4dof --variant imperfect --orbit "$csv"
    expect_rc 0 periodic --model 4dof --variant imperfect --orbit "$csv" --force
fi

# the contact opens at a large amplitude imbalance: said in the JSON and the table
if expect_rc 0 periodic --variant imperfect --set amp_imbalance=0.3 --orbit "$tmp/open.csv" --json; then
    py "import csv
Fn = [float(r['F_n [N]']) for r in csv.DictReader(open('$tmp/open.csv'))]
assert o['contact_open'] and o['F_n_min'] < 0 and min(Fn) < 0
assert o['friction_needed_max'] is None"
fi
expect_rc 0 periodic --variant imperfect --set amp_imbalance=0.3 && \
    { grep -q 'CONTACT OPENS' "$out" || fail "the table does not say that the contact opens"; }
# how often it opens is counted on the orbit, not stated: the --orbit file's
# stretches of F_n < 0 around the period (a mode split's 2 Omega wobble
# opens it twice), in the JSON, the table and the
# sweep's contact_loss event (which said "once a period" whatever the orbit)
if expect_rc 0 periodic --model 4dof --variant imperfect --set mode_split=0.02 --orbit "$tmp/ms.csv" --json; then
    py "import csv
Fn = [float(r['F_n [N]']) for r in csv.DictReader(open('$tmp/ms.csv'))]  # one period
n = sum(1 for i in range(len(Fn)) if Fn[i] < 0 and not Fn[i - 1] < 0)
assert n == 2, n
assert o['openings_per_period'] == n, (o['openings_per_period'], n)"
fi
expect_rc 0 periodic --model 4dof --variant imperfect --set mode_split=0.02 && \
    { grep -q 'CONTACT OPENS *2 times a period' "$out" || fail "the table does not count the openings: $(grep -i contact "$out")"; }
if expect_rc 0 sweep --periodic --model 4dof --variant imperfect --over mode_split --from 0 --to 0.02 --points 3 --json; then
    py "c = [e for e in o['events'] if e['type'] == 'contact_loss']
assert len(c) == 1 and 'opens twice a period' in c[0]['what'] and 'once' not in c[0]['what'], c
assert o['points'][-1]['openings_per_period'] == 2 and o['points'][0]['openings_per_period'] == 0"
fi
# an orbit with separation: its table says whether the model describes it
# (only --json did): stick_not_admissible at 35 deg (below), valid in 4-DOF
expect_rc 0 periodic --model 3dof --variant imperfect_unilateral --set phase_error=35deg && \
    { grep -q '^  valid  *no: stick_not_admissible' "$out" || fail "hybrid table: no validity line"; }
expect_rc 0 periodic --model 4dof --variant imperfect_unilateral --set phase_error=30deg && \
    { grep -q '^  valid  *yes' "$out" || fail "hybrid table (4-DOF): no validity line"; }

# a contact that may open (docs/unilateral.md): the orbit with separation past
# contact loss (28.73 deg), the bilateral orbit with the keys at 0 before it
if expect_rc 0 periodic --model 3dof --variant imperfect_unilateral --set phase_error=35deg --json; then
    py "assert o['converged'] and o['contact_open'] and o['mode_sequence'] == 'cococ'
assert 0.40 < o['separation_fraction'] < 0.41 and o['impacts_per_period'] == 2
assert 1e-3 < o['impact_velocity_max'] < 1e-2 and o['floquet']['max_modulus'] < 1
assert abs(o['rotor_speed_mean'] + 10.7523) < 1e-3
assert o['valid'] is False and o['invalid_reason'] == 'stick_not_admissible'"
fi
if expect_rc 0 periodic --model 3dof --variant imperfect_unilateral --set phase_error=10deg --json; then
    py "assert o['converged'] and not o['contact_open'] and o['mode_sequence'] == 'c'
assert o['separation_fraction'] == 0 and o['impacts_per_period'] == 0"
fi
expect_rc 0 periodic --model 4dof --variant imperfect_unilateral --set phase_error=30deg && \
    { grep -q 'mode sequence  *cococ' "$out" || fail "the table has no mode sequence"; }
# --orbit of an orbit with separation: a second run of the period map,
# sampled; its rows alone give the JSON's mode sequence, time open, mean
# speed and the orbit's closing
hcsv=$tmp/hybrid_orbit.csv
if expect_rc 0 periodic --model 4dof --variant imperfect_unilateral --set phase_error=30deg \
        --orbit "$hcsv" --json; then
    py "import csv
rows = list(csv.reader(open('$hcsv')))
head, d = rows[0], [[float(v) for v in r] for r in rows[1:]]
assert head[:2] == ['t [s]', 'open [1]'] and head[-4:] == ['gap [m]', 'F_n [N]', 'F_t [N]', 'rotor_speed [1/s]'], head
assert len(head) == 9 + 6 and head[2] == 'phi_R [rad]' and head[8] == 'thetadot [rad/s]', head
t, op, T = [r[0] for r in d], [int(r[1]) for r in d], 1 / o['parameters']['f']
assert t[0] == o['section_t'] and abs(t[-1] - t[0] - T) < 1e-15 * t[-1] * 8, (t[0], t[-1])
assert all(b >= a for a, b in zip(t, t[1:])) and len(d) >= 201 + 2 * 4, len(d)
seq = ''.join('o' if m else 'c' for i, m in enumerate(op) if i == 0 or m != op[i - 1])
assert seq == o['mode_sequence'], (seq, o['mode_sequence'])
opent = sum(t[i + 1] - t[i] for i in range(len(d) - 1) if op[i] and op[i + 1])
# measured 5.7e-10 (two runs of the map at rtol 1e-11)
assert abs(opent / T - o['separation_fraction']) < 1e-8, (opent / T, o['separation_fraction'])
# no contact force while open, no gap while closed, never a negative gap
assert all(r[12] == 0 and r[13] == 0 and r[11] >= -1e-15 for r in d if r[1] == 1)
assert all(r[11] == 0 and r[12] >= -1e-9 for r in d if r[1] == 0)
# the orbit closes: theta, its rate, the spin rates and tau come back
# (measured 1.3e-12 to 4.1e-10 of their largest values, tau 2.2e-8)
for k in (4, 6, 7, 8, 9, 10):
    sc = max(abs(r[k]) for r in d)
    assert abs(d[-1][k] - d[0][k]) < 1e-7 * sc, (head[k], d[0][k], d[-1][k])
# the mean rotor speed by the trapezoidal rule over the rows (both sides of
# every switch: exact where the speed jumps) against the orbit's quadrature
w = sum((t[i + 1] - t[i]) * (d[i][14] + d[i + 1][14]) / 2 for i in range(len(d) - 1)) / T
# measured 2.2e-10
assert abs(w / o['rotor_speed_mean'] - 1) < 1e-6, (w, o['rotor_speed_mean'])"
fi

# sweep --periodic on a unilateral model continues past contact loss: the
# points carry the orbit with separation (the same as usm periodic's, started
# independently from a simulation), contact_regained sweeping back, grazing
# where the mode sequence changes (cococ -> coc near 53 deg, 3-DOF)
if expect_rc 0 periodic --model 3dof --variant imperfect_unilateral --set phase_error=0.6 --json; then
    cp "$out" "$tmp/p06.json"
fi
if expect_rc 0 sweep --periodic --model 3dof --variant imperfect_unilateral --over phase_error \
    --from 0.45 --to 0.7 --points 6 --json; then
    py "p06 = json.load(open('$tmp/p06.json'))
pts = o['points']
assert [p['separating'] for p in pts] == [False, False, True, True, True, True], pts
for p in pts:
    assert p['mode_sequence'] == ('cococ' if p['separating'] else 'c'), p
assert pts[0]['contact_open'] is False and pts[3]['contact_open'] is True
# Newton's tol 1e-9 of the scales, two starts: measured 2e-10
assert abs(pts[3]['rotor_speed_mean'] / p06['rotor_speed_mean'] - 1) < 1e-7, (pts[3], p06)
assert abs(pts[3]['separation_fraction'] - p06['separation_fraction']) < 1e-6
e = o['events']
assert [x['type'] for x in e].count('contact_loss') == 1, e
cl = [x for x in e if x['type'] == 'contact_loss'][0]
assert abs(cl['phase_error'] - 0.50136329) < 1e-8, cl"
fi
if expect_rc 0 sweep --periodic --model 3dof --variant imperfect_unilateral --over phase_error \
    --from 0.6 --to 0.45 --points 4 --json; then
    py "e = [x for x in o['events'] if x['type'].startswith('contact')]
assert len(e) == 1 and e[0]['type'] == 'contact_regained' and abs(e[0]['phase_error'] - 0.50136329) < 1e-8, e"
fi
# the two-impact orbit (cococ) ends between 0.912 and 0.914 rad (its closed
# phases shrink; a sweep with steps of 0.002 rad finds it up to 0.912 with
# open 0.944, and from 0.918 a one-impact orbit (coc) open 0.888, unstable):
# not a grazing within one branch but a branch that ends, and another orbit
# found from rest (branch_switch with branch_lost; at 0.92, or at 0.94 when
# no orbit is found at 0.92)
if expect_rc 0 sweep --periodic --model 3dof --variant imperfect_unilateral --over phase_error \
    --from 0.88 --to 0.98 --points 6 --json; then
    py "e = o['events']
assert not [x for x in e if x['type'] == 'grazing'], e
b = [x for x in e if x['type'] == 'branch_switch']
assert len(b) == 1 and b[0]['branch_lost'] is True and 0.919 < b[0]['phase_error'] < 0.941, b
assert abs(b[0]['last_value'] - 0.9) < 1e-12 and b[0]['last_orbit']['mode_sequence'] == 'cococ'
assert b[0]['orbit']['mode_sequence'] == 'coc' and b[0]['orbit']['floquet']['max_modulus'] > 1
pts = o['points']
assert [p['mode_sequence'] for p in pts[:2]] == ['cococ', 'cococ'], pts
assert all(p['mode_sequence'] == 'coc' for p in pts[3:]), pts"
fi
# the followed orbit with separation becomes stable (4-DOF, one-impact orbit
# coc, mode split 3.373 %, a real multiplier through -1): a stability_change
# with the bilateral ones' keys and the located orbit with separation under
# `orbit` (numbers: test_periodic_sweep_hybrid_stability.c)
if expect_rc 0 sweep --periodic --model 4dof --variant imperfect_unilateral --over mode_split \
    --from 0.032 --to 0.034 --points 3 --json; then
    py "s = [x for x in o['events'] if x['type'] == 'stability_change']
assert len(s) == 1, o['events']
s = s[0]
assert sorted(s) == ['invalid_reason', 'kind', 'mode_split', 'multiplier', 'orbit', 'type', 'valid',
                     'what'], s
assert s['valid'] is s['orbit']['valid'], s
assert s['kind'] == 'period_doubling' and 0.033 < s['mode_split'] < 0.034, s
assert abs(s['multiplier'][0] + 1) < 1e-3 and 'becomes stable' in s['what'], s
assert s['orbit']['mode_sequence'] == 'coc' and abs(s['orbit']['floquet']['max_modulus'] - 1) < 1e-6"
fi

# The variant tilt is twist_integrated in the tilt vector (docs/coordinates.md):
# one motor, one orbit.  Before the shooting handled those coordinates it wrote
# its tilt scale into scale[-1], the period, and failed after 100,000 steps
# ("CVODES failed at t = 0.054 s of the period").  Its orbit here equals
# twist_integrated's: the mean rotor speed and theta to 1e-9 relative (the
# Newton tolerance, of the state scales), the multipliers as sets to 2e-8
# (each orbit's are 1e-9 .. 8e-9 from usm_floquet's at the default rtol 1e-11;
# test_periodic_tilt.c).  Paper's point and T = 0, f = 38.5 kHz.
for base in 3dof 4dof; do
    for point in "" "--set T=0 --set f=38500"; do
        # shellcheck disable=SC2086
        if expect_rc 0 periodic --model $base --variant twist_integrated $point --json; then
            cp "$out" "$tmp/euler.json"
            # shellcheck disable=SC2086
            if expect_rc 0 periodic --model $base --variant tilt $point --json \
                    --orbit "$tmp/tilt-$base.csv" --force; then
                py "e = json.load(open('$tmp/euler.json'))
assert o['converged'] and o['model'] == '${base}_tilt', o['model']
for k in ('rotor_speed_mean', 'theta_mean', 'theta_min', 'theta_max', 'F_n_min', 'F_n_max'):
    assert abs(o[k] / e[k] - 1) <= 1e-9, (k, o[k], e[k])
a = [complex(*z) for z in o['floquet']['multipliers']]
b = [complex(*z) for z in e['floquet']['multipliers']]
assert len(a) == len(b)
worst = 0
while a:
    i, j = min(((i, j) for i in range(len(a)) for j in range(len(b))), key=lambda ij: abs(a[ij[0]] - b[ij[1]]))
    worst = max(worst, abs(a.pop(i) - b.pop(j)))
assert worst <= 2e-8, worst
assert o['valid'] == e['valid'] and abs(o['squeal_frequency'] / e['squeal_frequency'] - 1) <= 1e-8
import csv, math
rows = list(csv.DictReader(open('$tmp/tilt-$base.csv')))
assert len(rows) == 200 and 'a [1]' in rows[0] and 'adot [1/s]' in rows[0], list(rows[0])
th = [math.asin(math.hypot(float(r['a [1]']), float(r['b [1]']))) for r in rows]
assert abs(sum(th) / len(th) / o['theta_mean'] - 1) <= 1e-12, (sum(th) / len(th), o['theta_mean'])"
            fi
        fi
    done
done
# the sweep follows it too, to the 4-DOF friction saturation (against twist_integrated's)
if expect_rc 0 sweep --periodic --model 4dof --variant twist_integrated --over T --from 0 --to 0.002 --points 5; then
    cp "$out" "$tmp/euler.csv"
    if expect_rc 0 sweep --periodic --model 4dof --variant tilt --over T --from 0 --to 0.002 --points 5; then
        checks=$((checks + 1))
        a=$(sed -n 's/^# friction_saturation at T = \([0-9.e+-]*\):.*/\1/p' "$out")
        b=$(sed -n 's/^# friction_saturation at T = \([0-9.e+-]*\):.*/\1/p' "$tmp/euler.csv")
        { [ -n "$a" ] && [ -n "$b" ] && [ "$(grep -c '^[0-9.e-]*,true,' "$out")" -eq 2 ] && \
          "$PY" -c "import sys; a, b = float(sys.argv[1]), float(sys.argv[2]); assert abs(a / b - 1) <= 1e-9" "$a" "$b"; } \
            || fail "4dof tilt periodic load sweep: friction_saturation '$a', twist_integrated '$b'"
    fi
fi
# periodic's help states its default variant once, and it is the one it uses
if expect_rc 0 periodic --help; then
    checks=$((checks + 1))
    [ "$(grep -ciE 'default (variant|paper|imperfect)|variant is imperfect unless' "$out")" -eq 1 ] && \
        grep -q -- '--variant NAME .*(default imperfect;' "$out" || fail "periodic --help: the variant's default"
fi
# a simulation from a tilt-vector state on the axis: refused, named
echo '{"a": 0, "b": 0, "chi": 0, "adot": 0, "bdot": 0, "chidot": 0, "tau": 0}' > "$tmp/axis.json"
expect_bad "a^2 + b^2" "theta = 0" simulate --variant tilt --duration 1e-4 --from "$tmp/axis.json" --out "$tmp/axis.csv"

finish periodic_cli
