#!/bin/bash
# The studies judge a design by its operating point,
# each checked against `usm steady` (the operating point's definition, with
# --from-rest: a simulation from rest) at the same parameters:
#  - map: every cell's operating-point class and index equal steady's;
#    without --from-rest the cells with several roots are "unknown";
#  - sweep: every point's operating point equals steady's, and each
#    operating_point_jump event lies between two grid values whose steady
#    operating points differ (and no jump where they agree on one branch);
#  - tolerance: a sample counts (good) exactly when steady finds an
#    operating point at its parameters and calls it valid; its valid and
#    invalid_reason are steady's; unknown samples are counted;
#  - optimize: without --from-rest a design with several roots is refused,
#    so the optimum has one root, its operating point.
#
# usage: judge_cli.sh PATH/TO/usm
set -u

USM=${1:?usage: judge_cli.sh PATH/TO/usm}
. "$(dirname "$0")/../cli_common.sh"

# the classes of steady's reasons
cat >"$tmp/judge.py" <<'EOF'
import csv, json, subprocess, sys

USM = sys.argv[1]
CLASS = {"only_stable_root": "operating_point", "reached_from_rest": "operating_point",
         "no_stable_root": "no_stable_root", "does_not_start": "does_not_start", None: "unknown"}

last = [None]  # steady's last JSON

def steady(sets, from_rest=True):
    args = [USM, "steady", "--json"] + (["--from-rest"] if from_rest else ["--no-from-rest"])
    for k, v in sets.items():
        args += ["--set", "%s=%r" % (k, v)]
    r = subprocess.run(args, capture_output=True, text=True, timeout=120)
    if r.returncode == 3:
        return None, "no_solution"
    assert r.returncode == 0, (args, r.stderr)
    o = json.loads(r.stdout)
    last[0] = o
    return o["operating_point"], CLASS[o["operating_point_reason"]]

def check_map(path, from_rest):
    o = json.load(open(path))
    xn, yn = o["x"]["name"], o["y"]["name"]
    seen = set()
    for p in o["points"]:
        want = steady({xn: p["x"], yn: p["y"]}, from_rest)
        got = (p["operating_point"], p["operating_point_class"])
        assert got == want, ("map cell", xn, p["x"], yn, p["y"], got, want)
        seen.add(got[1])
    return seen

def check_sweep(path, over, fixed):
    o = json.load(open(path))
    pts = o["points"]
    truth = []
    for p in pts:
        want = steady(dict(fixed, **{over: p[over]}))
        got = (p["operating_point"], p["operating_point_class"])
        assert got == want, ("sweep point", p[over], got, want)
        truth.append(want)
    jumps = [e for e in o["events"] if e["type"] == "operating_point_jump"]
    for e in jumps:
        v = e[over]
        k = [i for i in range(len(pts) - 1) if min(pts[i][over], pts[i + 1][over]) < v <
             max(pts[i][over], pts[i + 1][over])]
        assert len(k) == 1, ("jump not between grid values", v)
        a, b = truth[k[0]], truth[k[0] + 1]
        assert a != b, ("jump where steady's operating points agree", v, a, b)
    return len(jumps)

def check_tolerance(path, fixed, names):
    rows = list(csv.DictReader(open(path)))
    unknown = 0
    for r in rows:
        sets = dict(fixed)
        for n in names:
            sets[n] = float(r["%s [N]" % n] if "%s [N]" % n in r else r[n])
        idx, cls = steady(sets)
        assert r["op_class"] == cls, (r, cls)
        # the top level of steady describes the operating point, as the sample does
        valid = last[0]["valid"] if cls != "no_solution" else None
        assert r["valid"] == {True: "true", False: "false", None: ""}[valid], (r, valid)
        if cls != "no_solution":
            assert r["invalid_reason"] == (last[0]["invalid_reason"] or ""), (r, last[0])
        assert (r["good"] == "true") == (cls == "operating_point" and valid), (r, cls)
        unknown += cls == "unknown"
    return len(rows), unknown

what = sys.argv[2]
if what == "map":
    seen = check_map(sys.argv[3], sys.argv[4] == "1")
    want = set(sys.argv[5].split(","))
    assert want <= seen, (seen, want)
elif what == "sweep":
    n = check_sweep(sys.argv[3], sys.argv[4], {"f": 38000.0})
    assert n >= int(sys.argv[5]), ("jumps", n)
elif what == "tolerance":
    n, unknown = check_tolerance(sys.argv[3], {"f": 38000.0}, ["F0"])
    s = json.load(open(sys.argv[4]))
    assert s["operating_point"]["unknown"] == unknown, (s["operating_point"], unknown)
EOF

judge() {
    checks=$((checks + 1))
    "$PY" "$tmp/judge.py" "$USM" "$@" >"$tmp/judge.out" 2>&1 || {
        failures=$((failures + 1))
        echo "FAIL: judge $*"
        tail -n 5 "$tmp/judge.out"
    }
}

# ---- map: 3 x 3 over f x F0 across the region of several roots -------------------
MAP="map --x f --x-from 37500 --x-to 39500 --x-points 3 --y F0 --y-from 0.9 --y-to 1.3 --y-points 3 --json"
if expect_rc 0 $MAP --from-rest; then
    cp "$out" "$tmp/map_fr.json"
    judge map "$tmp/map_fr.json" 1 operating_point,does_not_start
fi
if expect_rc 0 $MAP; then
    cp "$out" "$tmp/map.json"
    judge map "$tmp/map.json" 0 operating_point,unknown
fi
# CSV: the class columns are the last ones
if expect_rc 0 map --x-points 2 --y-points 2; then
    head -n 1 "$out" | grep -q ',operating_point,op_class,op_reason,starts_from_rest,op_theta \[rad\],op_rotor_speed \[1/s\],op_max_modulus \[1\]$' ||
        fail "map CSV: the operating point's columns"
fi

# ---- sweep: F0 across the start-up limit at 38 kHz ---------------------------------
if expect_rc 0 sweep --over F0 --from 0.9 --to 1.3 --points 9 --set f=38000 --from-rest --json; then
    cp "$out" "$tmp/sweep.json"
    judge sweep "$tmp/sweep.json" F0 1
fi
expect_bad "--from-rest-periods" "1e7" sweep --over F0 --from 0.9 --to 1.3 --from-rest-periods 0

# ---- tolerance: goodness is steady's verdict -----------------------------------------
TOL="tolerance --samples 8 --seed 3 --vary F0=uniform:0.9:1.1 --set f=38000 --threads 2"
if expect_rc 0 $TOL --from-rest --out "$tmp/tol_fr"; then
    expect_rc 0 $TOL --from-rest --json && cp "$out" "$tmp/tol_fr.json"
    judge tolerance "$tmp/tol_fr/samples.csv" "$tmp/tol_fr.json"
fi
if expect_rc 0 $TOL --out "$tmp/tol"; then
    expect_rc 0 $TOL --json && cp "$out" "$tmp/tol.json"
    py_file "$tmp/tol.json" "
u = o['operating_point']['unknown']
assert u > 0 and o['good'] + u <= o['samples'], o['operating_point']"
fi

# ---- optimize: several roots refused without --from-rest ------------------------------
if expect_rc 0 optimize --objective speed --vary F0=0.9:1.3 --set f=38000 --starts 3 --no-flat --json; then
    py "
s = o['solution']
assert len(s['roots']) == 1 and s['operating_point'] == 0, (len(s['roots']), s['operating_point'])
assert s['operating_point_reason'] == 'only_stable_root'"
fi

# with --from-rest a design with several roots is judged by its start-up from rest:
# at F0 in [1, 1.03] N (above the start threshold 0.99997 N, where root #1 is born
# at theta = 0) the motor does not start, so the optimum lies below, on one root
if expect_rc 0 optimize --objective speed --vary F0=0.95:1.03 --set f=38000 --starts 2 --no-flat --from-rest --json; then
    cp "$out" "$tmp/opt_fr.json"
    py "
s = o['solution']
assert o['parameters']['F0'] < 0.99997, o['parameters']['F0']
assert len(s['roots']) == 1 and s['operating_point'] == 0, (len(s['roots']), s['operating_point'])
assert s['floquet']['stable'] and abs(o['value'] + s['rotor_speed']) <= 1e-9 * abs(o['value'])"
fi
if expect_rc 0 steady --set f=38000 --set F0=1.001 --json; then
    py "assert o['operating_point'] is None and o['operating_point_reason'] == 'does_not_start'"
fi

finish judge_cli
