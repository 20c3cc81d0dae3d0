"""The analyses merged after the package was first written (item
1): usm pareto, the robust options of usm optimize, the orbit with
separation of usm periodic and the spectrum of usm simulate.  Each result's
.to_dict() equals the command's --json object bit for bit (json.loads of
both texts), on both models and a variant; wall-clock seconds, which differ
from run to run, are compared by key."""
import os
import tempfile

import numpy as np
import pytest

import usm
from conftest import run_cli


def cli_args(model, variant, params):
    a = ["--model", model, "--variant", variant]
    for k, v in params.items():
        a += ["--set", "%s=%r" % (k, v)]
    return a


def without_seconds(d):
    """d without its wall-clock "seconds" (asserted present and >= 0)."""
    d = dict(d)
    assert d.pop("seconds") >= 0
    return d


@pytest.mark.parametrize("model,variant,params,args,kw", [
    ("3dof", "paper", {}, ["--objectives", "speed,efficiency", "--vary", "F0=0.2:1.0",
                           "--points", "5", "--starts", "1"],
     dict(objectives="speed,efficiency", vary={"F0": (0.2, 1.0)}, points=5, starts=1)),
    ("4dof", "paper", {"T": 5e-5}, ["--objectives", "speed,min:F_n", "--vary", "F0=0.3:0.6",
                                    "--vary", "f=36.5kHz:38kHz", "--points", "4",
                                    "--starts", "1", "--constraint", "efficiency>=0.001"],
     dict(objectives=("speed", "min:F_n"), vary={"F0": (0.3, 0.6), "f": ("36.5kHz", "38kHz")},
          points=4, starts=1, constraints="efficiency>=0.001")),
    ("3dof", "twist_integrated", {}, ["--objectives", "power_out,margin", "--vary",
                                      "F0=0.3:0.8", "--points", "3", "--starts", "1"],
     dict(objectives=["power_out", "margin"], vary={"F0": (0.3, 0.8)}, points=3, starts=1)),
])
def test_pareto(model, variant, params, args, kw):
    want, _ = run_cli("pareto", *cli_args(model, variant, params), *args)
    got = usm.Model(model, variant, **params).pareto(**kw)
    assert without_seconds(got.to_dict()) == without_seconds(want)
    a, b = want["objectives"]
    assert np.array_equal(got.columns[a], [p[a] for p in want["points"]])
    assert np.array_equal(got.column(b), [p[b] for p in want["points"]])


@pytest.mark.parametrize("model,variant,params,args,kw", [
    # the yield constraint over a scatter, verified on fresh samples
    ("3dof", "paper", {}, ["--objective", "efficiency", "--vary", "F0=0.2:1.0", "--constraint",
                           "speed>=6", "--constraint", "yield>=0.9", "--scatter",
                           "c_r=normal:2%", "--samples", "200", "--verify-samples", "500",
                           "--max-evals", "6", "--starts", "1"],
     dict(objective="efficiency", vary={"F0": (0.2, 1.0)}, constraints=["speed>=6", "yield>=0.9"],
          scatter={"c_r": "normal:2%"}, samples=200, verify_samples=500, max_evals=6, starts=1)),
    # a quantile over the scatter, a unit in the scatter's number
    ("4dof", "paper", {}, ["--objective", "q05:speed", "--vary", "F0=0.3:0.6", "--scatter",
                           "f=normal:300", "--samples", "300", "--verify-samples", "300",
                           "--max-evals", "5", "--starts", "1", "--seed", "3"],
     dict(objective="q05:speed", vary={"F0": (0.3, 0.6)}, scatter=["f=normal:300Hz"],
          samples=300, verify_samples=300, max_evals=5, starts=1, seed=3)),
    # an output judged over an operating range
    ("3dof", "twist_integrated", {}, ["--objective", "speed", "--vary", "F0=0.3:0.6",
                                      "--over-range", "T=0:80e-6:5", "--range-stat", "mean",
                                      "--max-evals", "5", "--starts", "1"],
     dict(objective="speed", vary={"F0": (0.3, 0.6)}, over_range=("T", 0, 80e-6, 5),
          range_stat="mean", max_evals=5, starts=1)),
    # datasheet quantities: no_load_speed, and a constraint on stall_torque (slip model)
    ("4dof", "paper", {}, ["--objective", "no_load_speed", "--vary", "F0=0.3:0.6",
                           "--constraint", "stall_torque>=1e-4", "--max-evals", "4",
                           "--starts", "1"],
     dict(objective="no_load_speed", vary={"F0": (0.3, 0.6)},
          constraints=[("stall_torque", ">=", 1e-4)], max_evals=4, starts=1)),
])
def test_robust_optimize(model, variant, params, args, kw):
    want, _ = run_cli("optimize", *cli_args(model, variant, params), *args)
    got = usm.Model(model, variant, **params).optimize(**kw)
    assert without_seconds(got.to_dict()) == without_seconds(want)
    assert got.objective == want["objective"] and got.value == want["value"]


def test_band_width():
    args = ["--objective", "band_width", "--vary", "F0=0.3:0.6", "--over-range",
            "f=36kHz:39kHz:7", "--band-threshold", "5", "--max-evals", "4", "--starts", "1"]
    want, _ = run_cli("optimize", *args)
    got = usm.Model().optimize("band_width", {"F0": (0.3, 0.6)}, over_range=("f", "36kHz",
                               "39kHz", 7), band_threshold=5, max_evals=4, starts=1)
    assert without_seconds(got.to_dict()) == without_seconds(want)


def test_robust_errors():
    m = usm.Model()
    with pytest.raises(ValueError, match="objective: .*q0x:speed.*quantile"):
        m.optimize("q0x:speed", {"F0": (0.3, 0.6)}, scatter={"f": "normal:1%"})
    with pytest.raises(ValueError, match="constraint: yield>=Y with 0 < Y < 1"):
        m.optimize("speed", {"F0": (0.3, 0.6)}, "yield>=1.5", scatter={"f": "normal:1%"})
    with pytest.raises(ValueError, match="scatter: "):
        m.optimize("yield", {"F0": (0.3, 0.6)}, "speed>=5", scatter={"c_x": "normal:2%"})
    with pytest.raises(ValueError, match="range_stat: one of worst, mean, integral"):
        m.optimize("speed", {"F0": (0.3, 0.6)}, over_range=("T", 0, 1e-4), range_stat="best")
    with pytest.raises(ValueError, match="objectives: \"nope\": unknown output"):
        m.pareto("speed,nope", {"F0": (0.3, 0.6)})
    with pytest.raises(ValueError, match="objectives: two different outputs"):
        m.pareto("speed,speed", {"F0": (0.3, 0.6)})


@pytest.mark.parametrize("model,phase", [("3dof", "35deg"), ("4dof", "30deg")])
def test_periodic_with_separation(model, phase):
    """A unilateral model whose orbit opens the contact: the orbit with
    separation (usm_hybrid_solve), as usm periodic chooses it."""
    want, _ = run_cli("periodic", "--model", model, "--variant", "imperfect_unilateral",
                      "--set", "phase_error=" + phase)
    got = usm.Model(model, "imperfect_unilateral", phase_error=phase).periodic()
    assert got.to_dict() == want
    assert 0 < got.separation_fraction < 1 and "o" in got.mode_sequence
    assert got.separations_per_period >= 1


def test_simulate_unilateral():
    """The event-driven simulation's separations, impacts and open fraction."""
    args = ["--model", "3dof", "--variant", "imperfect_unilateral", "--set",
            "phase_error=35deg", "--duration", "0.002", "--rate", "0"]
    want, _ = run_cli("simulate", *args)
    got = usm.Model("3dof", "imperfect_unilateral", phase_error="35deg").simulate(0.002, rate=0)
    d = got.to_dict()
    assert d.pop("wall_time") > 0 and want.pop("wall_time") > 0
    assert d == want
    assert got.separations > 0 and got.impacts > 0 and 0 < got.open_fraction < 1


def test_simulate_spectrum():
    """--spectrum: the summary's spectrum object (its csv null here) and the
    amplitudes as arrays, equal to the command's PREFIX.csv."""
    args = ["--model", "4dof", "--variant", "imperfect", "--set", "mode_split=0.088",
            "--duration", "0.006"]
    with tempfile.TemporaryDirectory() as d:
        want, _ = run_cli("simulate", *args, "--spectrum", os.path.join(d, "sp"),
                          "--spectrum-periods", "100")
        csv = np.genfromtxt(os.path.join(d, "sp.csv"), delimiter=",", skip_header=1,
                            comments="#")
    got = usm.Model("4dof", "imperfect", mode_split=0.088).simulate(0.006, spectrum=100)
    have = got.to_dict()
    for o in (have, want):
        assert o.pop("wall_time") > 0 and o["spectrum"].pop("seconds") >= 0
    assert want["spectrum"].pop("csv").endswith("sp.csv") and have["spectrum"].pop("csv") is None
    assert have == want
    s = got.spectrum_arrays
    n = want["spectrum"]["samples"] // 2 + 1           # bins of n grid points
    assert all(v.shape == (n,) for v in s.values())
    assert np.array_equal(s["frequency"], np.arange(n) * want["spectrum"]["resolution"])
    # the CSV: frequency, order, rotor_speed, theta, F_n from bin 1, printed shortest
    assert np.array_equal(s["frequency"][1:], csv[:, 0])
    for c, name in enumerate(("rotor_speed", "theta", "F_n")):
        assert np.array_equal(s[name][1:], csv[:, 2 + c])


def test_periodic_sweep_with_separation():
    """usm sweep --periodic on the unilateral model past contact loss: the
    separating rows' fraction, impacts and mode sequence as columns."""
    want, _ = run_cli("sweep", "--periodic", "--model", "3dof", "--variant",
                      "imperfect_unilateral", "--over", "phase_error", "--from", "30deg", "--to",
                      "36deg", "--points", "3")
    got = usm.Model("3dof", "imperfect_unilateral").sweep("phase_error", "30deg", "36deg",
                                                          points=3)
    assert got.to_dict() == want
    assert got.columns["separation_fraction"].shape == (3,)
    assert np.array_equal(got.separating, [p["separating"] for p in want["points"]])
