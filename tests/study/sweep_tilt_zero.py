#!/usr/bin/env python3
"""The sweep's tilt_zero event against a closed form derived here, from the
mechanics of the paper's stator at theta = 0, independently of derive/ and the
generated kernels.

At theta = 0 the stator does not tilt: the gyroscopic and restoring moments
(proportional to tan(theta), theta) vanish, the contact point is R e_y + H e_z
in the frame turning with the tilt axis (R* = R, Z = H), the spring force is
its preload (F_n = F0, Z - H = 0) and the rotor balance I_R dw/dt = F_t R* - T
gives F_t = T / R.  The stator's moment balance about its centre, excitation
m0 (cos alpha, sin alpha) plus the contact moment r_c x F_c with the contact
force on the stator F_c = -F_t e_x - F_n e_z, then has two components and two
unknowns (alpha and the swept parameter).  Eliminating alpha gives the
parameter where the branch reaches theta = 0; the test solves it with sympy
and requires the event within 1e-10 relative.

usage: sweep_tilt_zero.py USM
"""
import json
import subprocess
import sys

import sympy as sp

USM = sys.argv[1]

R, H, m0, F0, T, a = sp.symbols("R H m0 F0 T alpha", real=True)
r_c = sp.Matrix([0, R, H])
F_t = T / R
F_c = sp.Matrix([-F_t, 0, -F0])
moment = r_c.cross(F_c) + sp.Matrix([m0 * sp.cos(a), m0 * sp.sin(a), 0])
# eliminate alpha: cos^2 + sin^2 = 1
cos_a = sp.solve(moment[0], sp.cos(a))[0]
sin_a = sp.solve(moment[1], sp.sin(a))[0]
limit = sp.Eq(cos_a**2 + sin_a**2, 1)
T_zero = [s for s in sp.solve(limit, T) if s.subs({R: 5e-3, H: 3e-3, m0: 5e-3, F0: 0.4}) > 0][0]
m0_zero = [s for s in sp.solve(limit, m0) if s.subs({R: 5e-3, H: 3e-3, F0: 0.4, T: 6.46e-5}) > 0][0]
print("closed form: T(theta = 0) =", sp.simplify(T_zero), "; m0(theta = 0) =", sp.simplify(m0_zero))

DEFAULT = {"R": 5e-3, "H": 3e-3, "m0": 5e-3, "F0": 0.4, "T": 6.46e-5}
failures = 0


def event(model, over, frm, to, values):
    args = [USM, "sweep", "--model", model, "--over", over, "--from", repr(frm), "--to", repr(to),
            "--points", "5", "--no-floquet", "--json"]
    for k, v in values.items():
        args += ["--set", f"{k}={v!r}"]
    out = subprocess.run(args, check=True, capture_output=True, text=True).stdout
    ev = json.loads(out)["events"]
    names = [e["type"] for e in ev]
    hits = [e[over] for e in ev if e["type"] == "tilt_zero"]
    if "fold" in names:
        raise AssertionError(f"{model} {over}: a fold reported at the tilt's end: {names}")
    if len(hits) != 1:
        raise AssertionError(f"{model} {over} {values}: want one tilt_zero event, got {names}")
    return hits[0]


def check(model, over, closed, values):
    global failures
    subs = {R: values["R"], H: values["H"], m0: values["m0"], F0: values["F0"], T: values["T"]}
    want = float(closed.subs(subs))
    # sweep from the working point towards the limit, ending beyond it
    start = values[over]
    got = event(model, over, start, start + 1.5 * (want - start), values)
    rel = abs(got - want) / abs(want)
    ok = rel <= 1e-10
    failures += not ok
    print(f"{'ok  ' if ok else 'FAIL'} {model} {over}: tilt_zero {got!r}, closed form {want!r}, "
          f"relative difference {rel:.2e} ({values})")


cases = [dict(DEFAULT),
         dict(DEFAULT, R=6e-3, H=2e-3),
         dict(DEFAULT, m0=8e-3, F0=0.9),
         dict(DEFAULT, R=4e-3, H=5e-3, m0=3e-3, F0=0.5)]
for values in cases:
    check("3dof", "T", T_zero, dict(values, T=0.0))
    for model in ("3dof", "4dof"):
        check(model, "m0", m0_zero, values)
sys.exit(1 if failures else 0)
