#!/usr/bin/env python3
"""`usm report --quick --no-plots` at parameters away from the paper's.

    report_params.py PATH/TO/usm

A valid parameter set must give a complete report (exit 0) even where a
limit the report quotes is not reached in the range it sweeps: the report
then says so ("over the whole load range swept", "none between ..."),
never an unknown placeholder, "n/a" or a number the computation did not
produce.  Each "not reached" or "ends at" statement checked here is tested
against independent `usm steady` runs: a stationary solution exists at the
end of the range swept (not reached), and does not exist just beyond a
located end (reached).
"""
import json
import os
import subprocess
import sys
import tempfile

USM = sys.argv[1]
fails = []


def check(cond, what):
    if not cond:
        fails.append(what)
        print("FAIL:", what)


def steady(model, sets):
    args = [USM, "steady", "--model", model, "--json"]
    for s in sets:
        args += ["--set", s]
    r = subprocess.run(args, capture_output=True, text=True)
    return r.returncode


def report(tmp, name, sets):
    out = os.path.join(tmp, name)
    args = [USM, "report", "--quick", "--no-plots", "--threads", "2", "--out", out]
    for s in sets:
        args += ["--set", s]
    r = subprocess.run(args, capture_output=True, text=True)
    check(r.returncode == 0, f"{name}: exit {r.returncode}: {r.stderr.strip()}")
    if r.returncode != 0:
        return None, None
    md = open(os.path.join(out, "report.md")).read()
    for bad in ("{{", "}}", "n/a", "unknown name"):
        check(bad not in md, f"{name}: report.md contains {bad!r}")
    data = json.load(open(os.path.join(out, "report.json")))
    return md, data["characteristics"]["located"]


with tempfile.TemporaryDirectory() as tmp:
    # F0 = 0.2 N: the 3-DOF load curve does not end below 8 N mm
    md, loc = report(tmp, "F0_0.2", ["F0=0.2"])
    if loc:
        e3, e4 = loc["existence_T_3dof"], loc["existence_T_4dof"]
        check(not e3["ok"] and "theta" not in e3, "F0=0.2: 3-DOF load limit must be absent")
        check("the 3-DOF stick solution exists over the whole load range swept (to 8 N mm)" in md,
              "F0=0.2: report.md does not say the 3-DOF branch outlasts the range")
        check(steady("3dof", ["F0=0.2", "T=8e-3"]) == 0,
              "F0=0.2: independent usm steady finds no 3-DOF solution at T = 8 N mm")
        check(e4["ok"] and e4["by"]["friction_saturation"] and not e4["has_solution"],
              "F0=0.2: the 4-DOF load curve must end at friction saturation, without a solution there")
        if e4["ok"]:
            t = e4["value"]
            check(steady("4dof", ["F0=0.2", f"T={t * 0.99}"]) == 0 and
                  steady("4dof", ["F0=0.2", f"T={t * 1.01}"]) == 3,
                  "F0=0.2: independent usm steady does not bracket the 4-DOF load limit")
        m3 = loc["existence_m0_3dof"]
        check(m3["ok"] and m3["by"]["tilt_zero"], "F0=0.2: the m0 curve must end where the tilt vanishes")
        if m3["ok"]:
            check(steady("3dof", ["F0=0.2", f"m0={m3['value'] * 1.01}"]) == 0 and
                  steady("3dof", ["F0=0.2", f"m0={m3['value'] * 0.99}"]) == 3,
                  "F0=0.2: independent usm steady does not bracket the smallest m0")
    # mu0 = 1: the 4-DOF load curve does not reach friction saturation by 1.2 N mm
    md, loc = report(tmp, "mu0_1", ["mu0=1"])
    if loc:
        check(not loc["existence_T_4dof"]["ok"], "mu0=1: 4-DOF load limit must be absent")
        check(steady("4dof", ["mu0=1", "T=1.2e-3"]) == 0,
              "mu0=1: independent usm steady finds no 4-DOF solution at T = 1.2 N mm")
    # c_r / 2: the tilt resonance (26 kHz) lies below the frequency range swept
    md, loc = report(tmp, "c_r_half", ["c_r=462.33385"])
    if loc:
        check(not loc["f_max_3dof"]["ok"] and "none between 30 and 46 kHz" in md,
              "c_r/2: no speed maximum between 30 and 46 kHz must be stated")

print("report_params: %d failure(s)" % len(fails))
sys.exit(1 if fails else 0)
