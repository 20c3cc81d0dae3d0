"""usm: the ultrasonic-motor library and its generated kernels from Python.

    import usm
    m = usm.Model("3dof", variant="paper")          # the paper's motor
    m.parameters["F0"]                              # value, unit, default, description
    s = m.with_params(f=37500).steady()             # every stationary solution
    s.rotor_speed, s.roots[0].floquet.max_modulus
    sw = m.sweep("f", 30e3, 45e3, points=61)        # numpy columns: sw.f, sw.rotor_speed
    m.rhs(x, t)                                     # the kernels over (N, nx) arrays

Every number comes from libusm (C): the kernels run over whole arrays with
the GIL released, and each analysis makes the library calls the `usm`
command makes, so a result's .to_dict() is the command's --json object bit
for bit.  Reference: docs/python.md.
"""
from . import _core
from ._core import NoSolution, NumericalError, variants, models, parameter_table
from ._results import (Result, SteadyResult, FloquetResult, SweepResult, SimulationResult,
                       PeriodicResult, SensitivityResult, MapResult, EnvelopeResult, OptimizeResult, ToleranceResult,
                       ParetoResult, SquealResult, FitResult,
                       SIM_COLUMNS, SIM_UNITS,
                       VALIDITY_NAMES)
from ._model import Model, Parameter, Parameters

__version__, generator_version = _core.version()

__all__ = ["Model", "Parameter", "Parameters", "NoSolution", "NumericalError", "variants",
           "models", "parameter_table", "Result", "SteadyResult", "FloquetResult", "SweepResult",
           "SimulationResult", "PeriodicResult", "SensitivityResult", "MapResult", "EnvelopeResult", "OptimizeResult", "ToleranceResult", "ParetoResult",
           "SquealResult", "FitResult",
           "SIM_COLUMNS", "SIM_UNITS", "VALIDITY_NAMES", "__version__", "generator_version"]
