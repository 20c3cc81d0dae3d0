"""usm.Model: one generated model with one parameter set (docs/python.md)."""
import os
from collections.abc import Mapping
from typing import NamedTuple

from . import _core
from ._results import (SteadyResult, FloquetResult, SweepResult, SquealResult, SimulationResult,
                       PeriodicResult, SensitivityResult, FitResult, MapResult, OptimizeResult, ParetoResult,
                       EnvelopeResult,
                       ToleranceResult)


class Parameter(NamedTuple):
    """One parameter: its value in this model, and from the generated
    contracts (usm_param_table) its unit, the paper's default, what it
    means and its admissible sign ("positive", "nonnegative", "any")."""
    name: str
    value: float
    unit: str
    default: float
    description: str
    constraint: str


class Parameters(Mapping):
    """The parameters of a model, name -> Parameter, in the order of
    usm_params.  Read-only: Model.with_params makes a changed model."""

    def __init__(self, values):
        self._p = {name: Parameter(name, values[name], unit, default, desc, cons)
                   for name, unit, desc, cons, default in _core.parameter_table()}

    def __getitem__(self, name):
        try:
            return self._p[name]
        except KeyError:
            raise KeyError("%s: unknown parameter (known: %s)" % (name, ", ".join(self._p))) from None

    def __iter__(self):
        return iter(self._p)

    def __len__(self):
        return len(self._p)

    def values_dict(self):
        """{name: value} (SI units)."""
        return {k: p.value for k, p in self._p.items()}

    def __repr__(self):
        return "Parameters(%s)" % ", ".join("%s=%r" % (k, p.value) for k, p in self._p.items())


def _rebuild(name, params):
    """The model `name` (a generated model's full name) with these parameters."""
    return Model(name, **params)


def _raise(status, msg, result=None):
    raise _core._error(status, msg, result)


class Model:
    """A generated model ("3dof", "4dof") under a variant ("paper",
    "twist_integrated", ...: usm.variants()), or by its full name
    ("4dof_friction_tanh", usm.models()), with a parameter set (the paper's,
    Appendix A, changed by keyword: Model("3dof", F0=0.6)).
    Immutable; thread-safe (each call has its own workspace)."""

    def __init__(self, model="3dof", variant="paper", **params):
        c = _core._Model()
        c._init(str(model), str(variant))
        if params:
            c = c._copy_set(params)
        self._c = c

    @classmethod
    def _from(cls, c):
        m = cls.__new__(cls)
        m._c = c
        return m

    # ---- description and parameters ------------------------------------------

    name = property(lambda self: self._c.name, doc="the generated model (\"3dof\", \"4dof_twist_integrated\", ...)")
    base = property(lambda self: self._c.base, doc="\"3dof\" or \"4dof\"")
    variant = property(lambda self: self._c.variant, doc="the variant's name")
    description = property(lambda self: self._c.description)
    assumptions = property(lambda self: self._c.assumptions)
    nx = property(lambda self: self._c.nx, doc="length of the state x")
    nu = property(lambda self: self._c.nu, doc="number of stationary unknowns u")
    slip = property(lambda self: self._c.slip, doc="True: rotor angle free, F_t = mu(v_rel) F_n")
    imperfect = property(lambda self: self._c.imperfect,
                         doc="True: amp_imbalance, phase_error, mode_split enter the equations")
    state_names = property(lambda self: self._c.state_names, doc="names of x's components")
    unknown_names = property(lambda self: self._c.unknown_names, doc="names of u's components")

    @property
    def parameters(self):
        """Parameters: name -> Parameter(name, value, unit, default, description, constraint)."""
        return Parameters(self._c._values())

    @property
    def params(self):
        """{name: value} in SI units."""
        return self._c._values()

    def with_params(self, **values):
        """A model with these parameters changed: numbers in SI units, or
        text with a unit ("37.5 kHz", "0.5 mNm").  ValueError with the
        library's message ("NAME: reason") for an unknown name, a value
        that is not finite or not physical for the model."""
        return Model._from(self._c._copy_set(values))

    def __reduce__(self):
        # pickled as its generated model's name and its parameters (multiprocessing)
        return (_rebuild, (self.name, self.params))

    def __repr__(self):
        changed = {k: p.value for k, p in self.parameters.items() if p.value != p.default}
        return "usm.Model(%r, variant=%r%s)" % (self.base, self.variant, "".join(
            ", %s=%r" % kv for kv in changed.items()))

    # ---- kernels -------------------------------------------------------------------

    def mass_matrix(self, x, t=None, out=None):
        """M(x): x (nx,) -> (nx, nx); (N, nx) -> (N, nx, nx).  t is accepted
        and ignored (M does not depend on time)."""
        return self._c.mass_matrix(x, t, out)

    def rhs(self, x, t=0.0, out=None):
        """f(x, t) of M(x) x' = f(x, t): x (nx,) -> (nx,), (N, nx) -> (N, nx);
        t [s] a number or (N,) array.  out: an array of the result's shape
        (C-contiguous float64) to write into instead of a new one."""
        return self._c.rhs(x, t, out)

    def jacobian(self, x, t=0.0, out=None):
        """df/dx: x (nx,) -> (nx, nx), (N, nx) -> (N, nx, nx), row i = f_i."""
        return self._c.jacobian(x, t, out)

    def steady_residual(self, u, out=None):
        """r(u) of the stationary ansatz, u = (theta, alpha[, phidot_R]):
        (nu,) -> (nu,), (N, nu) -> (N, nu) [N m]."""
        return self._c.steady_residual(u, out)

    def steady_jacobian(self, u, out=None):
        """dr/du: (nu,) -> (nu, nu), (N, nu) -> (N, nu, nu)."""
        return self._c.steady_jacobian(u, out)

    # ---- analyses ------------------------------------------------------------------

    def steady(self, t0=0.0, method=None, rtol=None, steps=None, from_rest=True,
               from_rest_periods=None):
        """Every stationary solution, the Floquet multipliers of each and the
        operating point (`usm steady --json`).  NoSolution when none exists
        (its .result is the converged = false object)."""
        st, msg, state = self._c._steady(float(t0), method, rtol, steps, bool(from_rest),
                                         from_rest_periods)
        # the JSON is written and parsed when the result is first read
        res = SteadyResult(source=state.json) if state is not None else None
        if st != 0:
            _raise(st, msg, res)
        return res

    def floquet(self, method=None, rtol=None, t0=0.0, steps=None, root=0):
        """The Floquet multipliers of stationary root `root` (0: the
        primary), computed by `method` ("auto", "magnus", "exponential",
        "variational") to `rtol`, over [t0, t0 + T]: the "floquet" object of
        roots[root] in `usm steady --json --floquet-method M --rtol R --t0 S`."""
        s = self.steady(t0=t0, method=method, rtol=rtol, steps=steps)
        roots = s.to_dict()["roots"]
        if not 0 <= root < len(roots):
            raise ValueError("root: %d is out of range (%d roots)" % (root, len(roots)))
        return FloquetResult(roots[root]["floquet"])

    def sweep(self, over, start, stop, points=101, floquet=True, t0=0.0, method=None, rtol=None,
              steps=None, threads=2, from_rest=False, from_rest_periods=None, periodic=None,
              extremum=(), crossing=None):
        """Continuation of the stationary solution over parameter `over` from
        `start` to `stop` (SI or text with a unit) at `points` values
        (`usm sweep --json`).  extremum: quantities whose maxima and minima
        are events (--extremum Q); crossing: {quantity: value or values}
        (--crossing Q=V).  periodic=True (default for an imperfect model):
        the periodic orbit's sweep (`usm sweep --periodic`)."""
        if isinstance(extremum, str):
            extremum = [extremum]
        crossing = dict(crossing or {})
        if periodic is None:
            periodic = self.imperfect
        if isinstance(points, bool) or not isinstance(points, int):
            raise TypeError("points: must be an integer")
        if isinstance(threads, bool) or not isinstance(threads, int):
            raise TypeError("threads: must be an integer")
        if periodic and (not floquet or t0 != 0.0 or method is not None or rtol is not None
                         or steps is not None or from_rest or from_rest_periods is not None
                         or extremum or crossing):
            raise ValueError("periodic: the periodic sweep takes only over, start, stop, points")
        st, msg, doc, _ = self._c._sweep(str(over), start, stop, points, bool(floquet), float(t0),
                                         method, rtol, steps, threads, bool(from_rest),
                                         from_rest_periods, bool(periodic), list(extremum),
                                         crossing)
        if st != 0:
            _raise(st, msg)
        return SweepResult(doc)

    def squeal(self, over, start, stop, points=11, settle=400, window=1024,
               lyapunov_periods=200, rest_check=True, rtol=1e-8, power_periods=200,
               sensitivities=False):
        """The motion past the last periodic orbit over parameter `over` from
        `start` to `stop` (SI or text with a unit) at `points` values (`usm
        squeal --json`, docs/squeal.md): each point's motion ("periodic",
        "quasi_periodic", "chaotic", ...), period, Lyapunov exponent, mean
        speed, impacts and audible lines, the power of each force and the
        energy balance over `power_periods` periods (0: none); with
        `sensitivities` the onset located past the origin and its derivatives
        in F0, mu0, f, T, m0 (.onset; about 10 s of CPU).  A model
        whose contact may open (variant "imperfect_unilateral")."""
        for name, v in (("points", points), ("settle", settle), ("window", window),
                        ("lyapunov_periods", lyapunov_periods),
                        ("power_periods", power_periods)):
            if isinstance(v, bool) or not isinstance(v, int):
                raise TypeError("%s: must be an integer" % name)
        st, msg, doc, _ = self._c._squeal(str(over), start, stop, points, settle, window,
                                          lyapunov_periods, bool(rest_check), float(rtol),
                                          power_periods, bool(sensitivities))
        if st != 0:
            _raise(st, msg)
        return SquealResult(doc)

    def simulate(self, duration, start="rest", **options):
        """Integrate M(x) x' = f(x, t) for `duration` seconds (`usm
        simulate --json` and its time history).  start: "rest",
        "stationary" or a state (nx,).  Options as the command's, by their
        library names: rate (default 10 f), t0, tilt0, rotor_angle0, rtol,
        settle_tol, settle_periods, theta_limit, speed_limit, max_steps,
        max_step, max_twist_growth, rest_fraction; spectrum=True (or a
        number of periods: --spectrum-periods) for the amplitude spectrum of
        the samples (`--spectrum`: the summary's "spectrum" object, its
        "csv" null, and .spectrum_arrays).  A run that stops early raises
        NumericalError with the result in .result."""
        opts = dict(options)
        opts["duration"] = duration
        opts["start"] = start
        st, msg, doc, hist, spec = self._c._simulate(opts)
        res = SimulationResult(doc, hist, spec) if doc is not None else None
        if st != 0:
            _raise(st, msg, res)
        return res

    def periodic(self):
        """The periodic orbit by shooting (`usm periodic --json`): of an
        imperfect model (variant "imperfect"), or the stationary orbit of an
        ideal one; of a unilateral model ("imperfect_unilateral") whose
        orbit opens the contact, the orbit with separation (separation_fraction,
        mode_sequence, impacts_per_period, ...), as the command chooses."""
        st, msg, doc, _ = self._c._periodic()
        res = PeriodicResult(doc) if doc is not None else None
        if st != 0:
            _raise(st, msg, res)
        return res

    def sensitivity(self, of=None):
        """Derivatives and elasticities of outputs (`usm sensitivity --json
        --of ...`; default the command's outputs) in every parameter."""
        st, msg, doc, _ = self._c._sensitivity(of)
        if st != 0:
            _raise(st, msg)
        return SensitivityResult(doc)

    def fit(self, data, fit, starts=None):
        """The parameters `fit` (names, or "a,b") identified from measured
        characteristics (`usm fit --json`, docs/fit.md), starting from this
        model's values.  data: the path of a CSV file, or a mapping of column
        headers ("f [kHz]", "speed [rpm]", "sigma_speed [rpm]") to sequences
        of equal length (None or nan in an output column: not measured).
        starts: the starts of the local search (default the library's)."""
        names = fit if isinstance(fit, str) else ",".join(fit)
        if isinstance(data, Mapping):
            cols = list(data)
            rows = [list(data[c]) for c in cols]
            if not cols or any(len(r) != len(rows[0]) for r in rows):
                raise ValueError("data: columns of equal length expected")
            lines = [",".join(cols)]
            for i in range(len(rows[0])):
                lines.append(",".join("" if v is None or v != v else repr(float(v))
                                      for v in (r[i] for r in rows)))
            st, msg, doc, _ = self._c._fit(b"data", "\n".join(lines) + "\n", names.encode(),
                                           starts)
        else:
            st, msg, doc, _ = self._c._fit(os.fsencode(data), None, names.encode(), starts)
        if st != 0:
            _raise(st, msg)
        return FitResult(doc)

    def stability_map(self, x=None, y=None, t0=0.0, method=None, rtol=None, steps=None,
                      threads=2, from_rest=False, from_rest_periods=None, progress=None):
        """The stability map over two parameters (`usm map --json`).  x, y:
        (name, from, to, points), or (name, points) for the default axis'
        range; default f 30-46 kHz x T 0-8 mN m, 33 x 33.  progress: None
        or a callable progress(done, total, "points"), called about ten
        times a second and at the end (one call at a time; the first
        exception it raises is raised when the map is done)."""
        if isinstance(threads, bool) or not isinstance(threads, int):
            raise TypeError("threads: must be an integer")
        st, msg, doc, _ = self._c._map(x, y, float(t0), method, rtol, steps, threads,
                                       bool(from_rest), from_rest_periods, progress)
        if st != 0:
            _raise(st, msg)
        return MapResult(doc)

    def envelope(self, x, y, lines=3, nodes=9, raster=120, stability=True, t0=0.0, method=None,
                 rtol=None, steps=None, from_rest=False, from_rest_periods=None):
        """The operating envelope over two parameters (`usm envelope --json`,
        docs/envelope.md).  x, y: (name, lo, hi), lo < hi (numbers in SI or
        texts with a unit, "36kHz").  The result's .curves (kind, points
        [[x, y], ...], ends), .regions (class, root, sample [x, y], ...) and
        .codim2 (type, point)."""
        for name, v in (("lines", lines), ("nodes", nodes), ("raster", raster)):
            if isinstance(v, bool) or not isinstance(v, int):
                raise TypeError("%s: must be an integer" % name)
        st, msg, doc, _ = self._c._envelope(x, y, lines, nodes, raster, bool(stability), float(t0),
                                            method, rtol, steps, bool(from_rest),
                                            from_rest_periods)
        if st != 0:
            _raise(st, msg)
        return EnvelopeResult(doc)

    def optimize(self, objective, vary, constraints=(), minimize=False, stability_margin=None,
                 starts=None, t0=None, allow_slip=False, allow_driven=False, no_flat=False,
                 from_rest=False, from_rest_periods=None, scatter=None, samples=None,
                 verify_samples=None, seed=None, threads=None, max_evals=None, over_range=None,
                 range_stat=None, band_threshold=None):
        """Design optimisation (`usm optimize --json`): maximise (minimize=True:
        minimise) `objective` over the parameters of `vary`, {name: (lo, hi)}
        (SI, or texts with a unit), subject to `constraints`: "OUTPUT>=X",
        "OUTPUT<=X", "rootR.OUTPUT<=X", "roots<=1", "yield>=Y", a derived
        quantity's "stall_torque>=X", or (output, ">=" | "<=", X).  objective:
        an output ("speed", "efficiency", "power_out", ...), a datasheet
        quantity ("stall_torque", "no_load_speed", "max_power",
        "band_width"), "yield", "mean:NAME" or "qNN:NAME" (a statistic over
        the scatter).  The other options as the command's (--stability-margin,
        --starts, --t0, --allow-slip, --allow-driven, --no-flat, --from-rest,
        --scatter (as tolerance's vary), --samples, --verify-samples, --seed,
        --threads, --max-evals, --over-range (name, lo, hi[, points]),
        --range-stat, --band-threshold).  A yield, a statistic, a range or a
        datasheet quantity makes it the robust problem (docs/design.md).  No
        feasible point raises NoSolution, its .result the {"feasible":
        false, ...} object."""
        constraints = _constraint_list(constraints)
        robust = {"scatter": scatter, "samples": samples, "verify_samples": verify_samples,
                  "seed": seed, "threads": threads, "max_evals": max_evals,
                  "over_range": over_range, "range_stat": range_stat,
                  "band_threshold": band_threshold}
        st, msg, doc, _ = self._c._optimize(str(objective), dict(vary), constraints,
                                            bool(minimize), stability_margin, starts, t0,
                                            bool(allow_slip), bool(allow_driven), bool(no_flat),
                                            bool(from_rest), from_rest_periods, robust)
        res = OptimizeResult(doc) if doc is not None else None
        if st != 0:
            _raise(st, msg, res)
        return res

    def pareto(self, objectives, vary, constraints=(), points=30, stability_margin=None,
               starts=None, t0=None, allow_slip=False, allow_driven=False, from_rest=False,
               from_rest_periods=None):
        """The Pareto front of two outputs (`usm pareto --json`):
        objectives "A,B" or (A, B), each maximised, "min:NAME" minimised
        (outputs with analytic gradients: speed, theta, F_n, F_t,
        efficiency, stick_margin, max_modulus, power_in, power_out, margin);
        vary, constraints and the options as optimize's; points: epsilon
        levels including the two ends (2 .. 1000).  .columns(): per key of
        the points an array (A, B, design.NAME, ...)."""
        if isinstance(points, bool) or not isinstance(points, int):
            raise TypeError("points: must be an integer")
        st, msg, doc, _ = self._c._pareto(objectives, dict(vary), _constraint_list(constraints),
                                          points, stability_margin, starts, t0,
                                          bool(allow_slip), bool(allow_driven), bool(from_rest),
                                          from_rest_periods)
        if st != 0:
            _raise(st, msg)
        return ParetoResult(doc)

    def tolerance(self, samples, vary, spec=(), seed=None, threads=None, t0=0.0, method=None,
                  rtol=None, steps=None, from_rest=False, from_rest_periods=None,
                  allow_driven=False, progress=None):
        """Monte Carlo tolerance study (`usm tolerance --json --samples N
        --vary ... --spec ...`): `samples` draws of the parameters of
        `vary` ({name: dist} or ["NAME=DIST", ...]; dist "normal:5%",
        "normal:0.01", "uniform:2%", "uniform:LO:HI", numbers in SI or with
        a unit), the yield against `spec` (["theta<=1e-4", ...]); seed
        (default 1), threads (default 2: the results do not depend on it);
        allow_driven (--allow-driven): a sample the load drives backwards
        (power_out < 0) may count.  progress: None or a callable
        progress(done, total, "samples"), as stability_map's."""
        if isinstance(vary, dict):
            vary = ["%s=%s" % kv for kv in vary.items()]
        elif isinstance(vary, str):
            vary = [vary]
        if isinstance(spec, str):
            spec = [spec]
        st, msg, doc, table = self._c._tolerance(list(vary), list(spec), samples, seed, threads,
                                                 float(t0), method, rtol, steps, bool(from_rest),
                                                 from_rest_periods, bool(allow_driven),
                                                 progress)
        if st != 0:
            _raise(st, msg)
        names = [v.split("=", 1)[0] for v in vary] + _core.tolerance_output_names() \
            + ["good", "redraws"]
        return ToleranceResult(doc, table, names)


def _constraint_list(constraints):
    """One constraint (a text or a (output, rel, value) tuple) or several, as a list."""
    if isinstance(constraints, str) or (isinstance(constraints, tuple) and len(constraints) == 3
                                        and constraints[1] in (">=", "<=")):
        return [constraints]
    return list(constraints)
