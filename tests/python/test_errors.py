"""Bad inputs raise the documented exceptions with the library's message
(the text the command prints after "usm: ", where the command has the
same input); no crash, no silent NaN."""
import numpy as np
import pytest

import usm
from conftest import cli_error, run_cli


def test_bad_parameters_value_error_with_library_message():
    m = usm.Model()
    with pytest.raises(ValueError) as e:
        m.with_params(Q=1.0)
    assert str(e.value) == "Q: unknown parameter"
    with pytest.raises(ValueError) as e:
        m.with_params(F0=float("nan"))
    assert str(e.value) == "F0: value must be a finite number"
    with pytest.raises(ValueError) as e:
        m.with_params(F0=-1)
    assert str(e.value) == cli_error("steady", "--set", "F0=-1", expect=2)
    with pytest.raises(ValueError) as e:
        usm.Model("3dof", amp_imbalance=0.05)
    assert str(e.value) == cli_error("steady", "--set", "amp_imbalance=0.05", expect=2)
    with pytest.raises(ValueError) as e:
        m.with_params(f="37 parsecs")
    assert str(e.value).startswith('f: "37 parsecs" is not a number, nor a number with a unit')
    with pytest.raises(TypeError):
        m.with_params(f=None)
    assert m.with_params(f="37.5kHz").params["f"] == 37500.0
    assert m.params["f"] == 37000.0                       # the model itself is unchanged


def test_unknown_model_and_variant():
    with pytest.raises(ValueError, match='variant: unknown variant "nonsense"'):
        usm.Model("3dof", variant="nonsense")
    with pytest.raises(ValueError, match=r'variant "friction_tanh" is not generated for model 3dof \(it has: paper'):
        usm.Model("3dof", variant="friction_tanh")
    with pytest.raises(ValueError, match='model: unknown model "5dof"'):
        usm.Model("5dof")
    # a generated model by its full name is the base under that variant
    assert usm.Model("4dof_friction_tanh").name == usm.Model("4dof", "friction_tanh").name


def test_kernel_shapes_and_dtypes():
    m = usm.Model()
    with pytest.raises(ValueError, match=r"x: shape \(5,\), expected \(6,\) or \(N, 6\) for model 3dof"):
        m.rhs(np.zeros(5))
    with pytest.raises(ValueError, match=r"x: shape \(2, 3, 6\)"):
        m.rhs(np.zeros((2, 3, 6)))
    with pytest.raises(ValueError, match=r"u: shape \(3,\), expected \(2,\)"):
        m.steady_residual(np.zeros(3))
    with pytest.raises(TypeError, match="x: dtype int64, expected float64"):
        m.rhs(np.zeros(6, dtype=np.int64))
    with pytest.raises(TypeError, match="x: dtype float32, expected float64"):
        m.mass_matrix(np.zeros((4, 6), dtype=np.float32))
    x = np.full((3, 6), 0.01)
    x[1, 2] = np.nan
    with pytest.raises(ValueError, match="x: row 1 is not finite"):
        m.rhs(x)
    with pytest.raises(ValueError, match=r"t: shape \(2,\), expected a number or \(3,\)"):
        m.rhs(np.full((3, 6), 0.01), np.zeros(2))
    with pytest.raises(ValueError, match=r"out: expected a writeable C-contiguous float64 array of shape \(3, 6\)"):
        m.rhs(np.full((3, 6), 0.01), out=np.empty((3, 5)))
    with pytest.raises(ValueError, match="t: not finite"):
        m.rhs(np.full(6, 0.01), float("inf"))


def test_no_solution():
    want, _ = run_cli("steady", "--set", "T=0.1", expect=3)
    with pytest.raises(usm.NoSolution) as e:
        usm.Model(T=0.1).steady()
    assert str(e.value) == cli_error("steady", "--set", "T=0.1", expect=3)
    assert e.value.result.to_dict() == want                # converged: false, as --json
    assert e.value.result.converged is False
    with pytest.raises(usm.NoSolution):
        usm.Model(T=0.1).sensitivity()


def test_numerical_error_carries_the_result():
    want, _ = run_cli("simulate", "--duration", "0.001", "--max-steps", "10", "--rate", "0",
                      expect=1)
    with pytest.raises(usm.NumericalError) as e:
        usm.Model().simulate(0.001, max_steps=10, rate=0)
    d = e.value.result.to_dict()
    for k in ("wall_time", "out"):
        d.pop(k), want.pop(k)
    assert d == want
    assert "max_steps" in str(e.value)


def test_bad_options():
    m = usm.Model()
    with pytest.raises(ValueError) as e:
        m.sweep("Q", 1, 2)
    assert str(e.value) == 'over: unknown parameter "Q"'
    with pytest.raises(ValueError) as e:
        m.sweep("f", 1, 2, points=1)
    assert str(e.value) == cli_error("sweep", "--over", "f", "--from", "1", "--to", "2",
                                     "--points", "1", expect=2)
    with pytest.raises(ValueError, match='extremum: unknown quantity "speeed"'):
        m.sweep("f", 36000, 37000, points=3, extremum="speeed")
    with pytest.raises(ValueError, match="crossing: at most 4 levels"):
        m.sweep("f", 36000, 37000, points=3, crossing={"theta": [1, 2, 3, 4, 5]})
    with pytest.raises(ValueError, match="method: foo: unknown Floquet method"):
        m.steady(method="foo")
    with pytest.raises(ValueError, match=r"rtol: must be in \[1e-14, 1e-3\]"):
        m.floquet(rtol=0.1)
    with pytest.raises(ValueError, match='of: unknown output "foo"'):
        m.sensitivity(of="foo")
    with pytest.raises(ValueError, match='start: "sideways"'):
        m.simulate(0.001, start="sideways")
    with pytest.raises(ValueError, match=r"start: shape \(3,\)"):
        m.simulate(0.001, start=np.zeros(3))
    with pytest.raises(ValueError, match="duration"):
        m.simulate(-1.0)
    with pytest.raises(TypeError, match="simulate: unknown option"):
        m.simulate(0.001, colour="red")
    with pytest.raises(ValueError, match="x"):
        m.stability_map(x=("Q", 1, 2, 3))
    with pytest.raises(ValueError, match="root: 3 is out of range"):
        m.floquet(root=3)


def test_optimize_errors():
    m = usm.Model()
    want, _ = run_cli("optimize", "--objective", "speed", "--vary", "F0=0.3:0.6", "--constraint",
                      "F_n>=5", "--starts", "2", expect=3)
    with pytest.raises(usm.NoSolution) as e:
        m.optimize("speed", {"F0": (0.3, 0.6)}, "F_n>=5", starts=2)
    assert str(e.value) == cli_error("optimize", "--objective", "speed", "--vary", "F0=0.3:0.6",
                                     "--constraint", "F_n>=5", "--starts", "2", expect=3)
    assert e.value.result.to_dict() == want and e.value.result.feasible is False
    # the library's "vary: ..." (the command prefixes it with "--")
    with pytest.raises(ValueError) as e:
        m.optimize("speed", {"F0": (0.6, 0.3)})
    assert "--" + str(e.value) == cli_error("optimize", "--objective", "speed", "--vary",
                                            "F0=0.6:0.3", expect=2)
    with pytest.raises(ValueError, match='objective: unknown output "spd"'):
        m.optimize("spd", {"F0": (0.3, 0.6)})
    with pytest.raises(ValueError, match="vary"):
        m.optimize("speed", {"Q": (0.3, 0.6)})
    with pytest.raises(ValueError, match="constraint"):
        m.optimize("speed", {"F0": (0.3, 0.6)}, "F_n=5")


def test_tolerance_errors():
    m = usm.Model()
    with pytest.raises(ValueError) as e:
        m.tolerance(10, {"Q": "normal:5%"})
    assert "--" + str(e.value) == cli_error("tolerance", "--samples", "10", "--vary",
                                            "Q=normal:5%", expect=2)
    with pytest.raises(ValueError) as e:
        m.tolerance(10, {"F0": "normal:5%"}, "thetaa<=1")
    assert "--" + str(e.value) == cli_error("tolerance", "--samples", "10", "--vary",
                                            "F0=normal:5%", "--spec", "thetaa<=1", expect=2)
    with pytest.raises(ValueError, match="samples"):
        m.tolerance(0, {"F0": "normal:5%"})
    with pytest.raises(ValueError, match="vary: required"):
        m.tolerance(10, {})


def test_values_in_the_wrong_unit_are_refused_by_the_library():
    """A parameter outside its physical range (derive/usm_derive/defaults.py)
    is refused with the command's message, naming the unit it was likely
    meant in: f = 38 was solved at 38 Hz, phase_error = 35 was 35 rad."""
    m = usm.Model()
    with pytest.raises(ValueError) as e:
        m.with_params(f=38)
    assert str(e.value) == "f = 38 Hz is outside 1 kHz..1 MHz; did you mean 38 kHz?"
    assert str(e.value) == cli_error("steady", "--set", "f=38", expect=2)
    with pytest.raises(ValueError, match=r"phase_error = 35 rad is outside .*did you mean 35 deg\?"):
        usm.Model("3dof", "imperfect", phase_error=35)
    assert usm.Model("3dof", "imperfect", phase_error="35deg").params["phase_error"] > 0.6
    with pytest.raises(ValueError, match=r"F0: the standard deviation 5 N exceeds the value 0.4 N"):
        m.tolerance(10, {"F0": "normal:5"})
    with pytest.raises(ValueError, match=r"f: uniform:37\.5:38\.5 lies outside the parameter's range"):
        m.tolerance(10, {"f": "uniform:37.5:38.5"})


def test_scatter_rules_of_robust_optimize():
    m = usm.Model()
    box = {"f": (34000, 42000)}
    with pytest.raises(ValueError, match="f: uniform:37550:37650 is absolute, but f is designed"):
        m.optimize("yield", box, scatter={"f": "uniform:37.55kHz:37.65kHz"}, samples=100,
                   verify_samples=100)
    with pytest.raises(ValueError, match="amp_imbalance: model 3dof is an ideal motor"):
        m.optimize("yield", box, scatter={"amp_imbalance": "normal:0.01"}, samples=100,
                   verify_samples=100)
    with pytest.raises(ValueError, match="minimize: the objective yield is maximized"):
        m.optimize("yield", box, minimize=True, scatter={"F0": "normal:5%"}, samples=100,
                   verify_samples=100)
    # one sample limit, one seed limit: the library's, as the command states them
    with pytest.raises(ValueError, match="samples: \"50\" must be a whole number from 100 to 10000000"):
        m.optimize("yield", box, scatter={"F0": "normal:5%"}, samples=50)
    with pytest.raises(ValueError, match="max_evals: \"3\" must be a whole number from 4"):
        m.optimize("yield", box, scatter={"F0": "normal:5%"}, samples=100, max_evals=3)
    for call in (lambda s: m.tolerance(3, {"F0": "normal:5%"}, seed=s),
                 lambda s: m.optimize("yield", box, scatter={"F0": "normal:5%"}, samples=100,
                                      seed=s)):
        with pytest.raises(ValueError, match="seed: .* from 0 to 9007199254740991"):
            call(2**53)


def test_python_inputs_raise_value_or_type_error():
    m = usm.Model()
    with pytest.raises(ValueError, match="unknown parameter"):
        m.with_params(**{"f\0oo": 37000.0})        # C would read "f"
    with pytest.raises(ValueError, match="f: .* out of range for a double"):
        m.with_params(f=10**400)                    # not OverflowError
    for v in (1e-310, 5e-324, -1e-310):
        with pytest.raises(ValueError, match="underflow"):
            m.with_params(T=v)                      # as --set T=1e-310
    for steps in (0, -1, 10**30):
        with pytest.raises(ValueError, match="steps: must be 1 to 1000000"):
            m.steady(steps=steps)                   # not NumericalError nor OverflowError


def test_kernels_never_return_inf_or_nan_for_finite_input():
    m = usm.Model()
    with pytest.raises(ValueError, match="x: row 0 gives a result that is not finite"):
        m.rhs(np.full(6, 1e300))
    x = np.full((3, 6), 0.01)
    x[2] = 1e300
    with pytest.raises(ValueError, match="x: row 2 gives a result that is not finite"):
        m.jacobian(x)
    assert np.all(np.isfinite(m.rhs(np.full(6, 0.01))))
