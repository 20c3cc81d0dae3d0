"""Results of the analyses: the command's JSON object, with its keys as
attributes (docs/python.md).

A result keeps the object the library's writer produced (the `usm NAME
--json` text, parsed); .to_dict() returns a copy of it, so keys that the
writers gain appear without a change here.  Attribute access converts:
nested objects become results, lists of numbers numpy arrays (null -> nan),
"multipliers" ([re, im] pairs) a complex array.
"""
import copy
import json
import math

import numpy as np

__all__ = ["Result", "SteadyResult", "FloquetResult", "SweepResult", "SquealResult",
           "SimulationResult",
           "PeriodicResult", "SensitivityResult", "MapResult", "OptimizeResult", "ToleranceResult",
           "ParetoResult"]


def _is_number(v):
    return v is None or (isinstance(v, (int, float)) and not isinstance(v, bool))


def _convert(key, v):
    if isinstance(v, dict):
        return Result(v)
    if isinstance(v, list):
        if key == "multipliers" and all(isinstance(z, list) and len(z) == 2 for z in v):
            return np.array([complex(*(math.nan if c is None else c for c in z)) for z in v],
                            dtype=np.complex128)
        if v and all(isinstance(z, dict) for z in v):
            return [Result(z) for z in v]
        if all(isinstance(z, bool) for z in v):
            return np.array(v, dtype=bool)
        if all(_is_number(z) for z in v):
            return np.array([math.nan if z is None else z for z in v], dtype=np.float64)
        if v and all(isinstance(z, list) and all(_is_number(c) for c in z) for z in v) \
                and len({len(z) for z in v}) == 1:
            return np.array([[math.nan if c is None else c for c in z] for z in v],
                            dtype=np.float64)
    return v


class Result:
    """One JSON object of the command as attributes.  r.KEY and r["KEY"]
    give the value of KEY (converted, see the module's text); r.to_dict()
    is the object itself, equal to the command's --json output."""

    def __init__(self, d=None, source=None):
        # d: the parsed object; or source: a function returning its JSON
        # text, called (and parsed) when the result is first read
        object.__setattr__(self, "_dd", d)
        object.__setattr__(self, "_source", source)

    @property
    def _d(self):
        if self._dd is None:
            object.__setattr__(self, "_dd", json.loads(self._source()))
            object.__setattr__(self, "_source", None)
        return self._dd

    def to_dict(self):
        """A deep copy of the JSON object (plain dicts, lists, floats)."""
        return copy.deepcopy(self._d)

    def __reduce__(self):
        return (type(self), (self._d,))

    def keys(self):
        return self._d.keys()

    def __contains__(self, key):
        return key in self._d

    def __getitem__(self, key):
        return _convert(key, self._d[key])

    def __getattr__(self, key):
        if key.startswith("_"):
            raise AttributeError(key)
        try:
            return _convert(key, self._d[key])
        except KeyError:
            raise AttributeError("%s has no %r (keys: %s)"
                                 % (type(self).__name__, key, ", ".join(self._d))) from None

    def __setattr__(self, key, value):
        raise AttributeError("results are read-only")

    def __dir__(self):
        return sorted(set(super().__dir__()) | set(self._d))

    def __eq__(self, other):
        return isinstance(other, Result) and self._d == other._d

    def __repr__(self):
        shown = []
        # a result the model does not describe says so first: its values (a
        # squeal frequency too) are predictions only with this flag
        if self._d.get("valid") is False:
            shown.append("MODEL_INVALID=%r" % (self._d.get("invalid_reason"),))
        for k, v in self._d.items():
            if isinstance(v, (dict, list)):
                continue
            shown.append("%s=%r" % (k, v))
            if len(shown) == 6 + (self._d.get("valid") is False):
                break
        return "<%s %s%s>" % (type(self).__name__, " ".join(shown),
                              " ..." if len(self._d) > len(shown) else "")


class SteadyResult(Result):
    """`usm steady --json`: the top level describes the primary root (or the
    operating point's root), .roots every stationary solution with its
    .floquet multipliers."""


class FloquetResult(Result):
    """The "floquet" object of one root: t0, t0_dependent, multipliers
    (complex array), cyclic, max_modulus, stable."""


class PeriodicResult(Result):
    """`usm periodic --json` (docs/periodic.md)."""


class OptimizeResult(Result):
    """`usm optimize --json`: feasible, objective, sense, value, varied (the
    optimal parameters), parameters, the active constraints with their
    multipliers, the stationary solution and stability at the optimum."""


class ToleranceResult(Result):
    """`usm tolerance --json` (yield, yield_ci, quantiles, influence, ...)
    and .table: per sample (a dict of arrays of length `samples`; the
    JSON's "samples" stays its count) the
    varied parameters' values under their names, the outputs (theta,
    rotor_speed, F_n, F_t, max_modulus, efficiency, stable,
    stick_admissible, exists, operating_point, op_class, validity; NaN
    where one does not exist), good (counts for the yield) and redraws:
    the numbers of the command's --out DIR/samples.csv."""

    def __reduce__(self):
        return (type(self), (self._d, self.table_array, list(self.table)))

    def __init__(self, d, table, names):
        super().__init__(d)
        if table is None:
            table = np.empty((0, len(names)))
        object.__setattr__(self, "table_array", table)
        object.__setattr__(self, "table", {k: table[:, i] for i, k in enumerate(names)})


class SensitivityResult(Result):
    """`usm sensitivity --json`: per output its value, derivatives d and
    elasticities in every parameter."""


class FitResult(Result):
    """`usm fit --json`: estimates with standard errors and 95 % intervals,
    correlation, chi2, p_value, identifiable, unidentifiable, points."""


def _columns(points):
    """Per key of the point objects an array over the points: numbers float64
    (null -> nan), booleans bool (float with nan where one is null), text an
    object array; nested objects give "KEY.SUB" columns of their scalars."""
    keys = []
    seen = set()

    def add(k):
        if k not in seen:
            seen.add(k)
            keys.append(k)

    for p in points:
        for k, v in p.items():
            if isinstance(v, dict):
                for s, w in v.items():
                    if not isinstance(w, (dict, list)):
                        add(k + "." + s)
            elif not isinstance(v, list):
                add(k)
    cols = {}
    for k in keys:
        vals = []
        for p in points:
            if "." in k and k.split(".", 1)[0] in p and isinstance(p[k.split(".", 1)[0]], dict):
                a, b = k.split(".", 1)
                vals.append(p[a].get(b))
            else:
                vals.append(p.get(k))
        present = [v for v in vals if v is not None]
        if present and all(isinstance(v, bool) for v in present):
            if len(present) == len(vals):
                cols[k] = np.array(vals, dtype=bool)
            else:
                cols[k] = np.array([math.nan if v is None else float(v) for v in vals])
        elif all(_is_number(v) for v in vals):
            cols[k] = np.array([math.nan if v is None else v for v in vals], dtype=np.float64)
        else:
            cols[k] = np.array(vals, dtype=object)
    return cols


class _Table(Result):
    """A result with a list of point objects: .columns is a dict of numpy
    arrays, one per key of the points; r.KEY falls back to the column."""

    _points_key = "points"

    def __init__(self, d=None, source=None):
        super().__init__(d, source)
        object.__setattr__(self, "_cols", None)

    @property
    def columns(self):
        if self._cols is None:
            object.__setattr__(self, "_cols", _columns(self._d.get(self._points_key) or []))
        return self._cols

    def column(self, name):
        """The column `name` ("theta", "floquet.max_modulus", ...)."""
        try:
            return self.columns[name]
        except KeyError:
            raise KeyError("%s: no column %r (columns: %s)"
                           % (type(self).__name__, name, ", ".join(self.columns))) from None

    def __getattr__(self, key):
        if key.startswith("_"):
            raise AttributeError(key)
        if key in self._d:
            return _convert(key, self._d[key])
        if key in self.columns:
            return self.columns[key]
        raise AttributeError("%s has no %r (keys: %s; columns: %s)"
                             % (type(self).__name__, key, ", ".join(self._d),
                                ", ".join(self.columns)))


class SweepResult(_Table):
    """`usm sweep --json`: .points (results), .columns (arrays per key:
    the swept parameter under its name, theta, rotor_speed,
    floquet.max_modulus, ...) and .events."""


class SquealResult(_Table):
    """`usm squeal --json`: .points (results: value, motion, period,
    lyapunov, lines, power, energy_balance_error, ...), .columns (arrays
    per key), and the keys "origin" and "onset" (null without
    sensitivities)."""


class ParetoResult(_Table):
    """`usm pareto --json`: objectives [A, B], senses, .points (each A, B,
    design {NAME: value}, active_constraints) sorted by B increasing,
    .columns (A, B, design.NAME arrays), computed, seconds."""


class MapResult(_Table):
    """`usm map --json`: .points (x fastest), .columns, .grid(name) as a
    (y points, x points) array, .boundaries."""

    def grid(self, name):
        c = self.column(name)
        nx = self._d["x"]["points"]
        ny = self._d["y"]["points"]
        return c.reshape(ny, nx)


class EnvelopeResult(Result):
    """`usm envelope --json`: .curves, .regions, .codim2, .x, .y."""


SIM_COLUMNS = ("t", "phi", "theta", "psi", "phidot", "thetadot", "psidot", "phi_R", "phi_Rdot",
               "F_n", "F_t", "v_rel", "theta_avg", "phi_Rdot_avg", "validity")
SIM_UNITS = ("s", "rad", "rad", "rad", "rad/s", "rad/s", "rad/s", "rad", "rad/s", "N", "N", "m/s",
             "rad", "rad/s", "1")
VALIDITY_NAMES = ("", "contact_open", "stick_not_admissible")


class SimulationResult(Result):
    """`usm simulate --json` (the summary) and .history, the time history
    as a dict of arrays (the CSV's columns: t [s], phi, theta, psi [rad],
    phidot, thetadot, psidot [rad/s], phi_R [rad], phi_Rdot [rad/s],
    F_n, F_t [N], v_rel [m/s], theta_avg [rad], phi_Rdot_avg [rad/s];
    the means nan before the first complete period; validity 0 where the
    model describes the motor, 1 contact open, 2 stick not admissible:
    the CSV's invalid_reason), and history["valid"] (bool).  .to_dict() is
    the summary only, as the command prints it (its "out" is null).
    With spectrum=...: .spectrum_arrays, the amplitude spectrum as arrays
    of length bins: "frequency" [Hz] (k df), "rotor_speed" [1/s], "theta"
    [rad], "F_n" [N] (the --spectrum CSV's columns, bin 0 included); None
    without a spectrum."""

    def __reduce__(self):
        return (type(self), (self._d, self._hist, self.spectrum_arrays))

    def __init__(self, d, history, spectrum=None):
        super().__init__(d)
        object.__setattr__(self, "spectrum_arrays", spectrum)
        if history is None:
            history = np.empty((0, len(SIM_COLUMNS)))
        object.__setattr__(self, "_hist", history)
        h = {k: history[:, i] for i, k in enumerate(SIM_COLUMNS)}
        h["valid"] = h["validity"] == 0
        object.__setattr__(self, "history", h)

    @property
    def history_array(self):
        """The time history as one (rows, 15) array, columns SIM_COLUMNS."""
        return self._hist
