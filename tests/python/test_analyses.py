"""Every wrapped analysis returns the command's JSON object, bit for bit
(json.loads of both texts: the writers print the shortest text that reads
back exactly, so equal objects are equal doubles), on the paper's parameters
and three other points: both models, a variant."""
import json
import os
import subprocess
import tempfile

import numpy as np
import pytest

import usm
from conftest import CLI, run_cli

# (model, variant, parameters): the paper's point, then three others
POINTS = [
    ("3dof", "paper", {}),
    ("4dof", "paper", {"f": 38000.0}),
    ("3dof", "twist_integrated", {"F0": 0.6}),
    ("4dof", "friction_tanh", {"T": 2e-4}),
]


def cli_args(model, variant, params):
    a = ["--model", model, "--variant", variant]
    for k, v in params.items():
        a += ["--set", "%s=%r" % (k, v)]
    return a


@pytest.mark.parametrize("model,variant,params", POINTS)
def test_steady(model, variant, params):
    want, _ = run_cli("steady", *cli_args(model, variant, params))
    got = usm.Model(model, variant, **params).steady()
    assert got.to_dict() == want
    # the attributes are the JSON's numbers
    assert got.rotor_speed == want["rotor_speed"]
    assert got.roots[0].floquet.max_modulus == want["roots"][0]["floquet"]["max_modulus"]
    mult = np.array([complex(*z) for z in want["floquet"]["multipliers"]])
    assert np.array_equal(got.floquet.multipliers, mult)


@pytest.mark.parametrize("model,variant,params", POINTS)
def test_floquet_options(model, variant, params):
    """floquet(method, rtol, t0) is roots[0].floquet of steady with the same options."""
    for method, rtol, t0 in (("variational", 1e-9, 0.0), ("exponential", None, 3e-6),
                             ("magnus", 1e-10, 1e-6)):
        extra = ["--floquet-method", method, "--t0", repr(t0)]
        if rtol is not None:
            extra += ["--rtol", repr(rtol)]
        want, _ = run_cli("steady", *cli_args(model, variant, params), *extra)
        got = usm.Model(model, variant, **params).floquet(method=method, rtol=rtol, t0=t0)
        assert got.to_dict() == want["roots"][0]["floquet"]


@pytest.mark.parametrize("model,variant,params", POINTS)
def test_sweep(model, variant, params):
    want, _ = run_cli("sweep", *cli_args(model, variant, params), "--over", "f", "--from",
                      "30000", "--to", "45000", "--points", "7")
    got = usm.Model(model, variant, **params).sweep("f", 30000, 45000, points=7)
    assert got.to_dict() == want
    # the columns are the points' values, in order
    assert np.array_equal(got.f, [p["f"] for p in want["points"]])
    rs = [np.nan if p.get("rotor_speed") is None else p["rotor_speed"] for p in want["points"]]
    assert np.array_equal(got.rotor_speed, rs, equal_nan=True)
    assert [e.to_dict() for e in got.events] == want["events"]


def test_sweep_units_and_floquet_off():
    want, _ = run_cli("sweep", "--over", "T", "--from", "0mNm", "--to", "0.2mNm", "--points",
                      "5", "--no-floquet")
    got = usm.Model().sweep("T", "0mNm", "0.2mNm", points=5, floquet=False)
    assert got.to_dict() == want


def test_sweep_monitors():
    want, _ = run_cli("sweep", "--model", "4dof", "--over", "f", "--from", "36kHz", "--to",
                      "39kHz", "--points", "31", "--extremum", "speed", "--extremum", "theta",
                      "--crossing", "F_n=0.4005", "--crossing", "F_n=0.401", "--crossing",
                      "speed=10")
    got = usm.Model("4dof").sweep("f", "36kHz", "39kHz", points=31, extremum=["speed", "theta"],
                                  crossing={"F_n": [0.4005, 0.401], "speed": 10})
    assert got.to_dict() == want
    assert {e.type for e in got.events} >= {"maximum", "crossing"}


def test_periodic_sweep():
    want, _ = run_cli("sweep", "--variant", "imperfect", "--set", "amp_imbalance=0.05", "--over",
                      "f", "--from", "36500", "--to", "37500", "--points", "3")
    got = usm.Model("3dof", "imperfect", amp_imbalance=0.05).sweep("f", 36500, 37500, points=3)
    assert got.to_dict() == want


@pytest.mark.parametrize("model,variant,params", POINTS)
def test_sensitivity(model, variant, params):
    want, _ = run_cli("sensitivity", *cli_args(model, variant, params))
    assert usm.Model(model, variant, **params).sensitivity().to_dict() == want
    want, _ = run_cli("sensitivity", *cli_args(model, variant, params), "--of",
                      "rotor_speed,max_modulus")
    got = usm.Model(model, variant, **params).sensitivity(of=["rotor_speed", "max_modulus"])
    assert got.to_dict() == want


@pytest.mark.parametrize("model,params", [("3dof", {}), ("4dof", {"amp_imbalance": 0.05}),
                                          ("3dof", {"phase_error": 0.1, "F0": 0.5})])
def test_periodic(model, params):
    want, _ = run_cli("periodic", "--model", model, "--variant", "imperfect",
                      *sum([["--set", "%s=%r" % kv] for kv in params.items()], []))
    got = usm.Model(model, "imperfect", **params).periodic()
    assert got.to_dict() == want


def test_periodic_invalid_flagged():
    """An orbit the model does not describe (8.62 % mode split, past contact
    loss at 1.33 %): the command's JSON says valid false, and the result's
    repr, what an interactive user sees, names it before any value (its
    squeal frequency is a prediction only with that flag)."""
    got = usm.Model("4dof", "imperfect", mode_split=0.0862).periodic()
    assert got.valid is False and got.invalid_reason == "contact_open" and got.F_n_min < 0
    assert repr(got).startswith("<PeriodicResult MODEL_INVALID='contact_open' "), repr(got)
    ok = usm.Model("4dof", "imperfect", mode_split=0.01).periodic()
    assert ok.valid is True and "MODEL_INVALID" not in repr(ok)


def simulate_cli(args):
    """The command's summary (its "out" and wall time set aside) and its CSV."""
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "h.csv")
        want, _ = run_cli("simulate", *args, "--out", path)
        csv = np.genfromtxt(path, delimiter=",", skip_header=1, usecols=range(14))
    return want, csv.reshape(-1, 14)


@pytest.mark.parametrize("model,variant,params", POINTS)
def test_simulate(model, variant, params):
    want, csv = simulate_cli([*cli_args(model, variant, params), "--duration", "0.0015"])
    got = usm.Model(model, variant, **params).simulate(0.0015)
    d = got.to_dict()
    assert d.pop("out") is None and want.pop("out").endswith("h.csv")
    assert d.pop("wall_time") > 0 and want.pop("wall_time") > 0  # seconds of computing
    assert d == want
    assert np.array_equal(got.history_array[:, :14], csv, equal_nan=True)
    assert np.array_equal(got.history["t"], csv[:, 0])


def test_simulate_options():
    want, csv = simulate_cli(["--duration", "0.001", "--from", "stationary", "--rate", "100kHz",
                              "--rtol", "1e-9", "--settle-periods", "5"])
    got = usm.Model().simulate(0.001, start="stationary", rate="100kHz", rtol=1e-9,
                               settle_periods=5)
    d = got.to_dict()
    for k in ("out", "wall_time"):
        d.pop(k), want.pop(k)
    assert d == want
    assert np.array_equal(got.history_array[:, :14], csv, equal_nan=True)


@pytest.mark.parametrize("model,variant,params", POINTS)
def test_stability_map(model, variant, params):
    want, _ = run_cli("map", *cli_args(model, variant, params), "--x-points", "4", "--y",
                      "F0", "--y-from", "0.3", "--y-to", "0.5", "--y-points", "3")
    got = usm.Model(model, variant, **params).stability_map(x=("f", 4), y=("F0", 0.3, 0.5, 3))
    assert got.to_dict() == want
    assert got.grid("max_modulus").shape == (3, 4)


def test_envelope():
    # the same library call as `usm envelope --json`, so the same object
    want, _ = run_cli("envelope", "--x", "f:36kHz:40kHz", "--y", "F0:0.1:2", "--no-stability",
                      "--raster", "40")
    got = usm.Model().envelope(("f", "36kHz", "40kHz"), ("F0", 0.1, 2), stability=False, raster=40)
    assert got.to_dict() == want
    assert sorted(c["kind"] for c in got.curves) == ["fold", "tilt_zero"]
    with pytest.raises(ValueError, match="y: the same parameter as x"):
        usm.Model().envelope(("f", 36000, 40000), ("f", 1, 2))


@pytest.mark.parametrize("model,variant,params,args,kw", [
    ("3dof", "paper", {}, ["--objective", "speed", "--vary", "f=36kHz:39kHz", "--vary",
                           "F0=0.3:0.6", "--constraint", "F_n>=0.35", "--starts", "2"],
     dict(objective="speed", vary={"f": ("36kHz", "39kHz"), "F0": (0.3, 0.6)},
          constraints=["F_n>=0.35"], starts=2)),
    ("4dof", "paper", {"T": 5e-5}, ["--objective", "efficiency", "--vary", "F0=0.3:0.6",
                                    "--constraint", "speed>=5", "--starts", "2", "--no-flat"],
     dict(objective="efficiency", vary={"F0": (0.3, 0.6)}, constraints=[("speed", ">=", 5)],
          starts=2, no_flat=True)),
    ("3dof", "twist_integrated", {}, ["--objective", "theta", "--minimize", "--vary",
                                      "F0=0.3:0.6", "--starts", "2", "--stability-margin",
                                      "0.05"],
     dict(objective="theta", minimize=True, vary={"F0": (0.3, 0.6)}, starts=2,
          stability_margin=0.05)),
])
def test_optimize(model, variant, params, args, kw):
    want, _ = run_cli("optimize", *cli_args(model, variant, params), *args)
    got = usm.Model(model, variant, **params).optimize(**kw)
    assert got.to_dict() == want
    assert got.feasible is True and got.value == want["value"]


@pytest.mark.parametrize("allow", [False, True])
def test_tolerance_allow_driven(allow):
    # a 4-DOF study across the stall torque: samples the load drives backwards
    vary = ["T=uniform:0.0002:0.0008", "F0=normal:5%"]
    want, _ = run_cli("tolerance", "--model", "4dof", "--samples", "128", "--seed", "3",
                      *sum([["--vary", v] for v in vary], []),
                      *(["--allow-driven"] if allow else []))
    got = usm.Model("4dof").tolerance(128, vary, seed=3, allow_driven=allow).to_dict()
    got.pop("timings")
    want.pop("timings")
    assert got == want
    assert (want["driven"] == 0) == allow, want["driven"]


@pytest.mark.parametrize("model,variant,params,vary,spec", [
    ("3dof", "paper", {}, {"F0": "normal:5%", "f": "uniform:36.9kHz:37.1kHz"}, ["theta<=1e-4"]),
    ("4dof", "paper", {"T": 5e-5}, {"F0": "uniform:350mN:450mN", "c_r": "normal:2%"},
     ["rotor_speed<=-5", "max_modulus<=0.99"]),
    ("3dof", "twist_integrated", {"F0": 0.6}, {"m0": "normal:0.0002"}, []),
])
def test_tolerance(model, variant, params, vary, spec):
    import csv
    args = sum([["--vary", "%s=%s" % kv] for kv in vary.items()], []) \
        + sum([["--spec", s] for s in spec], [])
    with tempfile.TemporaryDirectory() as d:
        want, _ = run_cli("tolerance", *cli_args(model, variant, params), "--samples", "70",
                          "--seed", "5", *args, "--out", os.path.join(d, "out"))
        with open(os.path.join(d, "out", "samples.csv")) as f:
            rows = list(csv.DictReader(f))
    got = usm.Model(model, variant, **params).tolerance(70, vary, spec, seed=5)
    # wall-clock seconds per phase differ from run to run: the
    # keys are compared, the values are not
    have = got.to_dict()
    assert set(have.pop("timings")) == set(want.pop("timings")) == \
        {"compute", "reduce", "statistics", "output", "compute_cpu", "output_cpu"}
    assert have == want and got.samples == 70
    # the samples are the command's samples.csv, number for number
    for col in ["theta [rad]", "rotor_speed [1/s]", "F_n [N]", "F_t [N]", "max_modulus [1]",
                "efficiency [1]", "redraws"] + ["%s [%s]" % (k, usm.Model().parameters[k].unit)
                                                for k in vary]:
        name = col.split(" [")[0]
        want_col = [float(r[col]) if r[col] != "" else np.nan for r in rows]
        assert np.array_equal(got.table[name], want_col, equal_nan=True), col
    assert np.array_equal(got.table["good"], [r["good"] == "true" for r in rows])


def test_progress():
    # progress=: done never decreases, ends at total, the unit is the
    # study's; the result is the one without a callback; the callable's
    # exception is raised when the study returns
    m = usm.Model("3dof")
    for study, total, unit in (
            (lambda **kw: m.tolerance(3000, {"F0": "normal:5%"}, seed=2, **kw), 3000,
             "samples"),
            (lambda **kw: m.stability_map(x=("f", 6), y=("T", 5), **kw), 30, "points")):
        calls = []
        got = study(progress=lambda d, t, w: calls.append((d, t, w)))
        done = [c[0] for c in calls]
        assert calls and done == sorted(done) and done[-1] == total, calls
        assert {(c[1], c[2]) for c in calls} == {(total, unit)}
        have, want = got.to_dict(), study().to_dict()
        have.pop("timings", None)
        want.pop("timings", None)
        assert have == want

    def stop(done, total, what):
        raise KeyboardInterrupt("stop")
    with pytest.raises(KeyboardInterrupt):
        m.tolerance(200, {"F0": "normal:5%"}, progress=stop)
    with pytest.raises(TypeError, match="progress"):
        m.tolerance(200, {"F0": "normal:5%"}, progress=3)


@pytest.mark.parametrize("model", ["3dof", "4dof"])
def test_periodic_tilt(model):
    """The variant tilt's periodic orbit (the tilt vector) is twist_integrated's
    (the Euler angles): the same motor, one orbit; before, the shooting wrote
    its tilt scale outside its array in the tilt vector and failed."""
    got = usm.Model(model, "tilt").periodic()
    want = usm.Model(model, "twist_integrated").periodic()
    assert got.converged and got.to_dict() == run_cli("periodic", "--model", model, "--variant",
                                                      "tilt")[0]
    assert abs(got.rotor_speed_mean / want.rotor_speed_mean - 1) < 1e-9
    assert abs(got.theta_mean / want.theta_mean - 1) < 1e-9
    # the multipliers as sets, nearest pairs first (tests/check.h's distance)
    a, b = list(got.floquet.multipliers), list(want.floquet.multipliers)
    assert len(a) == len(b)
    worst = 0.0
    while a:
        i, j = min(((i, j) for i in range(len(a)) for j in range(len(b))),
                   key=lambda ij: abs(a[ij[0]] - b[ij[1]]))
        worst = max(worst, abs(a.pop(i) - b.pop(j)))
    assert worst < 2e-8, worst


def test_squeal():
    """squeal() is `usm squeal --json` (but the CPU seconds): 3-DOF phase
    error 0.90 and 0.93 rad, periodic then chaotic, short runs."""
    args = ["--over", "phase_error", "--from", "0.90", "--to", "0.93", "--points", "2",
            "--settle", "100", "--window", "32", "--lyapunov-periods", "10", "--no-rest-check"]
    want, _ = run_cli("squeal", *args)
    got = usm.Model("3dof", "imperfect_unilateral").squeal(
        "phase_error", 0.90, 0.93, points=2, settle=100, window=32, lyapunov_periods=10,
        rest_check=False).to_dict()
    for d in (want, got):
        for p in d["points"]:
            p.pop("seconds")
    assert got == want
    assert [p["motion"] for p in want["points"]] == ["periodic", "chaotic"]
