# cython: language_level=3, boundscheck=False, wraparound=False, initializedcheck=False, cdivision=True
# _core.pyx: the extension of the Python package usm (docs/python.md).
#
# Cython, not the raw numpy C API: typed memoryviews take any strided
# float64 array (non-contiguous input needs no copy), the loops over states
# compile to plain C with the GIL released (`with nogil`), and reference
# counting and error paths are written by Cython, not by hand.  No numpy C
# API call is made: numpy allocates the outputs, Cython indexes them.
#
# Everything is a call into libusm's public API: the kernels through the
# model descriptor (usm_model), the analyses through usm_run.h, the same
# library calls the command makes, written by the library's JSON writers.

import json as _json
import numpy as np

from libc.math cimport isfinite
from libc.stdlib cimport free
from libc.string cimport memcpy, strlen

gsl_set_error_handler_off()   # the library handles GSL's errors itself (usm.h)


class NoSolution(Exception):
    """No stationary solution (or no periodic orbit) for these parameters.
    .result is the command's JSON object where it prints one (converged =
    false), else None."""
    def __init__(self, message, result=None):
        super().__init__(message)
        self.result = result


class NumericalError(RuntimeError):
    """A numerical failure (integrator, Newton, eigen-solver).  .result is
    what was computed up to it, where the command prints that, else None."""
    def __init__(self, message, result=None):
        super().__init__(message)
        self.result = result


def version():
    """Version of libusm and of the generator of its kernels."""
    return usm_version().decode(), usm_generator_version().decode()


def variants():
    """The modelling variants: list of dicts name, models (the base models
    generated with it), description (as `usm variants`)."""
    out = []
    for v in range(USM_NVARIANTS):
        name = usm_variants[v].name.decode()
        models = [usm_models[k].base.decode() for k in range(USM_NMODELS)
                  if usm_models[k].variant.decode() == name]
        out.append({"name": name, "models": models,
                    "description": usm_variants[v].description.decode()})
    return out


def models():
    """Every generated model: list of dicts name, base, variant, nx, nu,
    slip, imperfect, description."""
    out = []
    for k in range(USM_NMODELS):
        m = usm_models[k]
        out.append({"name": m.name.decode(), "base": m.base.decode(),
                    "variant": m.variant.decode(), "nx": m.nx, "nu": m.nu,
                    "slip": bool(m.slip), "imperfect": bool(m.imperfect),
                    "description": m.description.decode()})
    return out


def parameter_table():
    """(name, unit, description, constraint, default) of every parameter,
    in the order of usm_params (the generated contracts)."""
    cdef usm_params d
    usm_params_default(&d)
    return [(usm_param_table[k].name.decode(), usm_param_table[k].unit.decode(),
             usm_param_table[k].description.decode(),
             usm_param_table[k].constraint.decode(),
             usm_params_get(&d, &usm_param_table[k]))
            for k in range(USM_NPARAMS)]


cdef object _status_error(int status, msg, result=None):
    if status == USM_EINPUT:
        return ValueError(msg)
    if status == USM_ENOSOLUTION:
        return NoSolution(msg, result)
    return NumericalError(msg, result)


# ---- kernels over arrays -------------------------------------------------------

cdef enum Kernel:
    K_MASS, K_RHS, K_JAC, K_RES, K_RESJAC


cdef enum Bad:
    BAD_INPUT, BAD_AXIS, BAD_SPHERE, BAD_OUTPUT


cdef Py_ssize_t _eval(Kernel kind, const usm_model *m, const usm_params *p,
                      const double[:, :] x, const double[:] t, int tscalar, double t1,
                      double *out, Py_ssize_t rowlen, Bad *why) nogil:
    """Evaluate kernel `kind` at every row of x into out (rowlen doubles a
    row).  Returns -1, or the first row where a value is not finite or the
    state lies outside the model's domain, *why saying which (nothing is
    evaluated after it).  The tilt vector's domain is 0 < a^2 + b^2 < 1: on
    the axis the contact point is undefined and the kernels have no limit
    (docs/coordinates.md), beyond it (a, b) is no unit vector's tilt."""
    cdef double buf[USM_MAX_NX]
    cdef const double *row
    cdef double *o
    cdef Py_ssize_t N = x.shape[0], n = x.shape[1], i, j
    cdef double ti, s2
    cdef int contiguous = x.strides[1] == sizeof(double)
    cdef int tilt = m.coordinates == 1 and (kind == K_MASS or kind == K_RHS or kind == K_JAC)
    why[0] = BAD_INPUT
    for i in range(N):
        if contiguous:
            row = &x[i, 0]
            for j in range(n):
                if not isfinite(row[j]):
                    return i
        else:
            for j in range(n):
                buf[j] = x[i, j]
                if not isfinite(buf[j]):
                    return i
            row = buf
        ti = t1 if tscalar else t[i]
        if not tscalar and not isfinite(ti):
            return i
        if tilt:
            s2 = row[m.x_a] * row[m.x_a] + row[m.x_b] * row[m.x_b]
            if not s2 > 0:
                why[0] = BAD_AXIS
                return i
            if not s2 < 1:
                why[0] = BAD_SPHERE
                return i
        o = out + i * rowlen
        if kind == K_RHS:
            m.rhs(row, ti, p, o)
        elif kind == K_MASS:
            m.mass(row, p, o)
        elif kind == K_JAC:
            m.jac_rhs(row, ti, p, o)
        elif kind == K_RES:
            m.steady_residual(row, p, o)
        else:
            m.steady_jacobian(row, p, o)
        for j in range(rowlen):
            if not isfinite(o[j]):
                why[0] = BAD_OUTPUT
                return i
    return -1


cdef object _checked_array(object a, str what):
    arr = a if isinstance(a, np.ndarray) else np.asarray(a)
    if arr.dtype != np.float64:
        raise TypeError("%s: dtype %s, expected float64" % (what, arr.dtype))
    return arr


cdef class _Model:
    """The C side of usm.Model: one generated model and one parameter set
    (read-only once made; with_params makes another)."""
    cdef const usm_model *m
    cdef usm_params p

    def __cinit__(self):
        self.m = NULL

    # -- construction --------------------------------------------------------

    def _init(self, str base, str variant):
        cdef char known[512]
        b = base.encode()
        v = variant.encode()
        self.m = usm_model_variant(b, v)
        if self.m == NULL and variant == "paper":
            self.m = usm_model_find(b)      # a generated model's full name: "4dof_friction_tanh"
        if self.m == NULL:
            bases = sorted({x["base"] for x in models()})
            if base not in bases:
                raise ValueError('model: unknown model "%s" (known: %s)' % (base, ", ".join(bases)))
            if usm_variant_find(v) == NULL:
                raise ValueError('variant: unknown variant "%s" (known: %s)'
                                 % (variant, ", ".join(x["name"] for x in variants())))
            have = [x["name"] for x in variants() if base in x["models"]]
            raise ValueError('variant: variant "%s" is not generated for model %s (it has: %s)'
                             % (variant, base, ", ".join(have)))
        usm_params_default(&self.p)

    def _copy_set(self, dict values):
        """A new _Model with the same model and these parameters changed
        (numbers in SI, or text with a unit: "37.5 kHz"), checked as the
        command checks --set: usm_params_set, then usm_params_check."""
        cdef _Model new = type(self).__new__(type(self))
        cdef char msg[USM_IO_MSG_LEN]
        cdef double v
        cdef const usm_param_info *info
        new.m = self.m
        new.p = self.p
        for name, value in values.items():
            bname = str(name).encode()
            if b"\0" in bname:   # C would read the name up to it: another parameter
                raise ValueError("%r: unknown parameter (a name with a NUL character)" % (name,))
            info = usm_params_find(bname)
            if info == NULL:   # the library's message ("NAME: unknown parameter")
                usm_params_set(&new.p, bname, 0.0, msg)
                raise ValueError(msg.decode(errors="replace"))
            if isinstance(value, str):
                text = value.encode()
                if usm_parse_quantity(bname, info.unit, text, len(text), &v, msg) != USM_OK:
                    raise ValueError(msg.decode(errors="replace"))
            elif isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.integer, np.floating)):
                raise TypeError("%s: expected a number or a text with a unit, got %s"
                                % (name, type(value).__name__))
            else:
                try:
                    v = float(value)
                except OverflowError:
                    text = str(value)
                    raise ValueError("%s: %s is out of range for a double (overflow)"
                                     % (name, text if len(text) < 40 else text[:20] + "...")) from None
            if usm_params_set(&new.p, bname, v, msg) != USM_OK:
                raise ValueError(msg.decode(errors="replace"))
        if usm_params_check(&new.p, new.m, msg) != USM_OK:
            raise ValueError(msg.decode(errors="replace"))
        return new

    # -- description ---------------------------------------------------------

    @property
    def name(self):
        return self.m.name.decode()

    @property
    def base(self):
        return self.m.base.decode()

    @property
    def variant(self):
        return self.m.variant.decode()

    @property
    def description(self):
        return self.m.description.decode()

    @property
    def assumptions(self):
        return self.m.assumptions.decode()

    @property
    def nx(self):
        return self.m.nx

    @property
    def nu(self):
        return self.m.nu

    @property
    def slip(self):
        return bool(self.m.slip)

    @property
    def imperfect(self):
        return bool(self.m.imperfect)

    @property
    def state_names(self):
        return tuple(self.m.state_names[i].decode() for i in range(self.m.nx))

    @property
    def unknown_names(self):
        return tuple(self.m.unknown_names[i].decode() for i in range(self.m.nu))

    def _values(self):
        return {usm_param_table[k].name.decode(): usm_params_get(&self.p, &usm_param_table[k])
                for k in range(USM_NPARAMS)}

    # -- kernels ---------------------------------------------------------------

    cdef object _kernel(self, Kernel kind, x, t, int n, tuple outshape, str what, out=None):
        cdef const double[:, :] xv
        cdef const double[:] tv = None
        cdef double t1 = 0.0
        cdef int tscalar = 1
        cdef Py_ssize_t bad, rowlen, N
        cdef Bad why = BAD_INPUT
        cdef double[::1] ov
        arr = _checked_array(x, what)
        single = arr.ndim == 1
        if arr.ndim not in (1, 2) or arr.shape[arr.ndim - 1] != n:
            raise ValueError("%s: shape %s, expected (%d,) or (N, %d) for model %s"
                             % (what, arr.shape, n, n, self.name))
        x2 = arr.reshape(1, n) if single else arr
        N = x2.shape[0]
        if isinstance(t, np.ndarray) and t.ndim == 0:
            t = t[()]                          # a 0-d array is a number
        if t is not None and not np.isscalar(t):
            tarr = _checked_array(t, "t")
            if single or tarr.ndim != 1 or tarr.shape[0] != N:
                raise ValueError("t: shape %s, expected a number or (%d,) (one time per state)"
                                 % (tarr.shape, N))
            tv = tarr
            tscalar = 0
        elif t is not None:
            if isinstance(t, (bool, np.bool_)) or not isinstance(t, (int, float, np.integer, np.floating)):
                raise TypeError("t: expected a number, got %s" % type(t).__name__)
            t1 = float(t)
            if not isfinite(t1):
                raise ValueError("t: not finite (%r)" % t)
        rowlen = 1
        for d in outshape:
            rowlen *= d
        given = out
        if out is None:
            out = np.empty((N,) + outshape, dtype=np.float64)
        else:
            want = ((N,) if not single else ()) + outshape
            if not isinstance(out, np.ndarray) or out.dtype != np.float64 \
                    or out.shape != want or not out.flags.c_contiguous or not out.flags.writeable:
                raise ValueError("out: expected a writeable C-contiguous float64 array of shape %s"
                                 % (want,))
            out = out.reshape((N,) + outshape)
        ov = out.reshape(-1)
        xv = x2
        with nogil:
            bad = _eval(kind, self.m, &self.p, xv, tv, tscalar, t1,
                        &ov[0] if N > 0 else NULL, rowlen, &why)
        if bad >= 0:
            # one line, every digit: the row as the caller can find it
            row_text = "[%s]" % ", ".join(repr(float(v)) for v in x2[bad])
            state = row_text if tscalar else "x %s, t %r" % (row_text, tv[bad])
            if why == BAD_AXIS:
                raise ValueError("%s: row %d lies on the stator's axis, a^2 + b^2 = 0 (theta = 0; %s): "
                                 "the contact point of "
                                 "model %s is not defined on the stator's axis and its kernels "
                                 "have no limit there (docs/coordinates.md)"
                                 % (what, bad, state, self.name))
            if why == BAD_SPHERE:
                raise ValueError("%s: row %d has a^2 + b^2 >= 1 (%s): (a, b) is the tilt of the "
                                 "stator's unit axis, a^2 + b^2 = sin(theta)^2 < 1"
                                 % (what, bad, state))
            if why == BAD_OUTPUT:
                raise ValueError("%s: row %d gives a result that is not finite (%s) of model %s: "
                                 "a value too large for double precision, or a singular state "
                                 "(theta near 0 in the tilt vector, or near pi/2; "
                                 "docs/coordinates.md)" % (what, bad, state, self.name))
            raise ValueError("%s: row %d is not finite (%s)" % (what, bad, state))
        if given is not None:
            return given
        return out[0] if single else out

    def mass_matrix(self, x, t=None, out=None):
        return self._kernel(K_MASS, x, t, self.m.nx, (self.m.nx, self.m.nx), "x", out)

    def rhs(self, x, t=0.0, out=None):
        return self._kernel(K_RHS, x, t, self.m.nx, (self.m.nx,), "x", out)

    def jacobian(self, x, t=0.0, out=None):
        return self._kernel(K_JAC, x, t, self.m.nx, (self.m.nx, self.m.nx), "x", out)

    def steady_residual(self, u, out=None):
        return self._kernel(K_RES, u, None, self.m.nu, (self.m.nu,), "u", out)

    def steady_jacobian(self, u, out=None):
        return self._kernel(K_RESJAC, u, None, self.m.nu, (self.m.nu, self.m.nu), "u", out)

    # -- analyses (usm_run.h) ----------------------------------------------------------

    cdef object _finish(self, usm_run *r):
        """(status, message, parsed JSON or None, rows or None) of a run
        (usm_run.h); frees r."""
        cdef double[:, ::1] hv
        cdef char *text = NULL
        cdef size_t n = 0, nrows = 0, ncols = 0
        cdef const double *rows
        if r == NULL:
            raise MemoryError("out of memory")
        try:
            status = usm_run_status(r)
            msg = usm_run_message(r).decode(errors="replace")
            doc = None
            if usm_run_has_json(r):
                with nogil:
                    text = usm_run_json(r, &n)
                if text == NULL:
                    raise MemoryError("out of memory writing the JSON")
                try:
                    doc = _json.loads(text[:n].decode())
                finally:
                    free(text)
            rows = usm_run_rows(r, &nrows, &ncols)
            hist = None
            if rows != NULL:
                hist = np.empty((nrows, ncols), dtype=np.float64)
                if nrows > 0 and ncols > 0:
                    hv = hist
                    memcpy(&hv[0, 0], rows, nrows * ncols * sizeof(double))
            return status, msg, doc, hist
        finally:
            usm_run_free(r)

    def _steady(self, double t0, method, rtol, steps, int from_rest, from_rest_periods):
        cdef usm_floquet_options fo
        cdef usm_op_options op
        cdef usm_run *r
        usm_floquet_options_default(&fo)
        usm_op_options_default(&op)
        _floquet_options(&fo, method, rtol, steps)
        op.from_rest = from_rest
        if from_rest_periods is not None:
            op.periods = _number("from_rest_periods", from_rest_periods)
            if not (op.periods >= 1 and op.periods <= 1e7):
                raise ValueError("from_rest_periods: must be in [1, 1e7]")
        if not isfinite(t0):
            raise ValueError("t0: not finite")
        with nogil:
            r = usm_run_steady(self.m, &self.p, t0, &fo, &op)
        if r == NULL:
            raise MemoryError("out of memory")
        status = usm_run_status(r)
        msg = usm_run_message(r).decode(errors="replace")
        cdef _SteadyState state = None
        if usm_run_has_json(r):
            state = _SteadyState.__new__(_SteadyState)
            state.r = r
        else:
            usm_run_free(r)
        return status, msg, state

    def _sweep(self, str over, start, stop, int points, int floquet, double t0, method, rtol,
               steps, int threads, int from_rest, from_rest_periods, int periodic,
               list extremum, dict crossing):
        cdef usm_sweep_options so
        cdef usm_periodic_sweep_options po
        cdef usm_run *r
        cdef const usm_param_info *info
        cdef double a, b
        cdef const char *unit = NULL
        cdef usm_sweep_monitor mons[8]
        cdef usm_monitor_fn fn
        cdef int k
        bover = over.encode()
        info = usm_params_find(bover)
        if info != NULL:
            unit = info.unit
        a = _quantity("start", unit, start)
        b = _quantity("stop", unit, stop)
        if periodic:
            usm_periodic_sweep_options_default(&po)
            po.over = bover
            po.from_ = a
            po.to = b
            po.points = points
            with nogil:
                r = usm_run_periodic_sweep(self.m, &self.p, &po)
            return self._finish(r)
        usm_sweep_options_default(&so)
        so.over = bover
        so.from_ = a
        so.to = b
        so.points = points
        so.floquet = floquet
        _floquet_options(&so.floquet_options, method, rtol, steps)
        so.t0 = t0
        so.threads = threads
        so.op.from_rest = from_rest
        if from_rest_periods is not None:
            so.op.periods = _number("from_rest_periods", from_rest_periods)
            if not (so.op.periods >= 1 and so.op.periods <= 1e7):
                raise ValueError("from_rest_periods: must be in [1, 1e7]")
        # --extremum Q and --crossing Q=V: one monitor per quantity, in the
        # order first named (extrema first), as sweep_cmd.c builds them
        cdef const char *qname
        names = []
        for field, q in [("extremum", q) for q in extremum] + \
                        [("crossing", q) for q in crossing]:
            bq = str(q).encode()
            qname = usm_sweep_quantity(bq, len(bq), &fn)
            if qname == NULL:
                raise ValueError('%s: unknown quantity "%s" (%s)'
                                 % (field, q, USM_SWEEP_QUANTITIES.decode()))
            if q not in names:
                names.append(q)
                k = len(names) - 1
                mons[k].name = qname
                mons[k].fn = fn
                mons[k].ctx = NULL
                mons[k].extrema = 0
                mons[k].nlevels = 0
            k = names.index(q)
            if field == "extremum":
                mons[k].extrema = 1
            else:
                levels = crossing[q]
                levels = [levels] if np.isscalar(levels) else list(levels)
                for lv in levels:
                    if mons[k].nlevels == USM_SWEEP_MAX_LEVELS:
                        raise ValueError("crossing: at most %d levels per quantity"
                                         % USM_SWEEP_MAX_LEVELS)
                    mons[k].levels[mons[k].nlevels] = _number("crossing", lv)
                    mons[k].nlevels += 1
        so.monitors = mons if names else NULL
        so.nmonitors = len(names)
        with nogil:
            r = usm_run_sweep(self.m, &self.p, &so)
        return self._finish(r)

    def _squeal(self, over, start, stop, int points, long settle, long window,
                long lyapunov_periods, bint rest_check, double rtol, long power_periods,
                bint sensitivities):
        cdef usm_squeal_options so
        cdef usm_run *r
        cdef const usm_param_info *info
        cdef const char *unit = NULL
        bover = over.encode()
        info = usm_params_find(bover)
        if info != NULL:
            unit = info.unit
        usm_squeal_options_default(&so)
        so.over = bover
        so.from_ = _quantity("start", unit, start)
        so.to = _quantity("stop", unit, stop)
        so.points = points
        so.settle = settle
        so.window = window
        so.lyapunov_periods = lyapunov_periods
        so.check_rest = rest_check
        so.rtol = rtol
        so.power_periods = power_periods
        so.sensitivities = sensitivities
        with nogil:
            r = usm_run_squeal(self.m, &self.p, &so)
        return self._finish(r)

    def _simulate(self, dict opts):
        cdef usm_sim_options so
        cdef usm_run *r
        cdef const double[:] xv
        usm_sim_options_default(&so)
        so.rate = usm_sim_default_rate(&self.p)
        start = opts.pop("start", "rest")
        spectrum = opts.pop("spectrum", None)
        cdef long spectrum_periods = -1
        if spectrum is True:
            spectrum_periods = 0
        elif spectrum is not None and spectrum is not False:
            if isinstance(spectrum, bool) or not isinstance(spectrum, (int, np.integer)) \
                    or not 2 <= spectrum <= 10**9:
                raise ValueError("spectrum: True or a whole number of periods >= 2, got %r"
                                 % (spectrum,))
            spectrum_periods = int(spectrum)
        if isinstance(start, str):
            if start == "rest":
                so.start = USM_SIM_FROM_REST
            elif start == "stationary":
                so.start = USM_SIM_FROM_STATIONARY
            else:
                raise ValueError('start: "%s" is none of "rest", "stationary" or a state array'
                                 % start)
        else:
            x0 = _checked_array(start, "start")
            if x0.shape != (self.m.nx,):
                raise ValueError("start: shape %s, expected (%d,) (the state of model %s: %s)"
                                 % (x0.shape, self.m.nx, self.name, ", ".join(self.state_names)))
            xv = x0
            so.start = USM_SIM_FROM_STATE
            for i in range(self.m.nx):
                so.x0[i] = xv[i]
        units = {"duration": b"s", "rate": b"Hz", "tilt0": b"rad", "theta_limit": b"rad",
                 "speed_limit": b"1/s", "t0": b"s", "rotor_angle0": b"rad", "max_step": b"s"}
        known = ("duration", "rate", "tilt0", "rtol", "settle_tol", "theta_limit", "speed_limit",
                 "max_twist_growth", "t0", "rotor_angle0", "max_step", "rest_fraction",
                 "settle_periods", "max_steps")
        for key, value in opts.items():
            if key not in known:
                raise TypeError("simulate: unknown option %s (known: start, %s)"
                                % (key, ", ".join(known)))
            if value is None:
                continue
            if key in ("settle_periods", "max_steps"):
                v = _number(key, value)
                if v != int(v):
                    raise ValueError("%s: must be a whole number" % key)
                if key == "settle_periods":
                    if not 1 <= v <= 1e8:
                        raise ValueError("settle_periods: must be a whole number in [1, 100000000]")
                    so.settle_periods = int(v)
                else:
                    if not 1 <= v <= 1e15:
                        raise ValueError("max_steps: must be a whole number in [1, 1000000000000000]")
                    so.max_steps = int(v)
                continue
            ub = units.get(key)
            v = _quantity(key, <const char *>ub if ub is not None else NULL, value)
            if key == "duration": so.duration = v
            elif key == "rate": so.rate = v
            elif key == "tilt0": so.tilt0 = v
            elif key == "rtol": so.rtol = v
            elif key == "settle_tol": so.settle_tol = v
            elif key == "theta_limit": so.theta_limit = v
            elif key == "speed_limit": so.speed_limit = v
            elif key == "max_twist_growth": so.max_twist_growth = v
            elif key == "t0": so.t0 = v
            elif key == "rotor_angle0": so.rotor_angle0 = v
            elif key == "max_step": so.max_step = v
            elif key == "rest_fraction": so.rest_fraction = v
            else:
                raise TypeError("simulate: unknown option %s" % key)
        if so.rate * so.duration > 1e8:
            raise ValueError("rate: %g samples per second for %g s would give %.3g rows (at most 1e+08)"
                             % (so.rate, so.duration, so.rate * so.duration))
        with nogil:
            r = usm_run_simulate(self.m, &self.p, &so, NULL, spectrum_periods)
        spec = _spectrum(r)
        return self._finish(r) + (spec,)

    def _optimize(self, objective, dict vary, list constraints, int minimize, margin, starts,
                  t0, int allow_slip, int allow_driven, int no_flat, int from_rest,
                  from_rest_periods, dict robust):
        return _run_optimize(self, objective, vary, constraints, minimize, margin, starts, t0,
                             allow_slip, allow_driven, no_flat, from_rest, from_rest_periods,
                             robust)

    def _pareto(self, objectives, dict vary, list constraints, int points, margin, starts, t0,
                int allow_slip, int allow_driven, int from_rest, from_rest_periods):
        return _run_pareto(self, objectives, vary, constraints, points, margin, starts, t0,
                           allow_slip, allow_driven, from_rest, from_rest_periods)

    def _tolerance(self, list vary, list spec, samples, seed, threads, double t0, method, rtol,
                   steps, int from_rest, from_rest_periods, int allow_driven=0, progress=None):
        return _run_tolerance(self, vary, spec, samples, seed, threads, t0, method, rtol, steps,
                              from_rest, from_rest_periods, allow_driven, progress)

    def _periodic(self):
        cdef usm_run *r
        with nogil:
            r = usm_run_periodic(self.m, &self.p)
        return self._finish(r)

    def _sensitivity(self, of):
        cdef int want[64]
        cdef usm_run *r
        cdef int k
        usm_sensitivity_outputs_default(want)
        if of is not None:
            names = [of] if isinstance(of, str) else list(of)
            for k in range(USM_SENS_COUNT):
                want[k] = 0
            for name in names:
                k = usm_sensitivity_output_find(str(name).encode())
                if k < 0:
                    raise ValueError('of: unknown output "%s" (known: %s)' % (name, ", ".join(
                        usm_sensitivity_output_name(j).decode() for j in range(USM_SENS_COUNT))))
                want[k] = 1
        with nogil:
            r = usm_run_sensitivity(self.m, &self.p, want)
        return self._finish(r)

    def _fit(self, bytes path, text, bytes names, starts):
        cdef usm_fit_options fo
        cdef usm_run *r
        cdef const char *ctext = NULL
        cdef size_t n = 0
        cdef bytes btext
        cdef const char *cpath = path
        cdef const char *cnames = names
        usm_fit_options_default(&fo)
        if starts is not None:
            fo.starts = int(starts)
        if text is not None:
            btext = text.encode()
            ctext = btext
            n = len(btext)
        with nogil:
            r = usm_run_fit(self.m, &self.p, cpath, ctext, n, cnames, &fo)
        return self._finish(r)

    def _map(self, x, y, double t0, method, rtol, steps, int threads, int from_rest,
             from_rest_periods, progress=None):
        cdef usm_map_options mo
        cdef usm_run *r
        cdef const usm_param_info *info
        usm_map_options_default(&mo)
        keep = []
        for axis, spec, field in ((0, x, "x"), (1, y, "y")):
            if spec is None:
                continue
            name, lo, hi, n = _axis(field, spec)
            bname = name.encode()
            keep.append(bname)
            info = usm_params_find(bname)
            if axis == 0:
                default_name = mo.x.name.decode()
                mo.x.name = bname
                mo.x.points = n
                if lo is not None:
                    mo.x.from_ = _quantity(field + "_from", info.unit if info != NULL else NULL, lo)
                    mo.x.to = _quantity(field + "_to", info.unit if info != NULL else NULL, hi)
                elif name != default_name:
                    raise ValueError("x: give (name, from, to, points) when x is not %s" % default_name)
            else:
                default_name = mo.y.name.decode()
                mo.y.name = bname
                mo.y.points = n
                if lo is not None:
                    mo.y.from_ = _quantity(field + "_from", info.unit if info != NULL else NULL, lo)
                    mo.y.to = _quantity(field + "_to", info.unit if info != NULL else NULL, hi)
                elif name != default_name:
                    raise ValueError("y: give (name, from, to, points) when y is not %s" % default_name)
        mo.t0 = t0
        _floquet_options(&mo.floquet, method, rtol, steps)
        mo.threads = threads
        mo.op.from_rest = from_rest
        if from_rest_periods is not None:
            mo.op.periods = _number("from_rest_periods", from_rest_periods)
        state = _progress_state(progress)
        _progress_set(&mo.progress, state)
        with nogil:
            r = usm_run_map(self.m, &self.p, &mo)
        out = self._finish(r)
        _progress_raise(state)
        return out


    def _envelope(self, x, y, int lines, int nodes, int raster, int stability, double t0,
                  method, rtol, steps, int from_rest, from_rest_periods):
        cdef usm_envelope_options eo
        cdef usm_run *r
        cdef const usm_param_info *info
        usm_envelope_options_default(&eo)
        keep = []
        for axis, spec, field in ((0, x, "x"), (1, y, "y")):
            spec = tuple(spec)
            if len(spec) != 3:
                raise ValueError("%s: expected (name, lo, hi)" % field)
            bname = str(spec[0]).encode()
            keep.append(bname)
            info = usm_params_find(bname)
            unit = info.unit if info != NULL else NULL
            lo = _quantity(field, unit, spec[1])
            hi = _quantity(field, unit, spec[2])
            if axis == 0:
                eo.x.name = bname
                eo.x.lo = lo
                eo.x.hi = hi
            else:
                eo.y.name = bname
                eo.y.lo = lo
                eo.y.hi = hi
        eo.lines = lines
        eo.nodes = nodes
        eo.raster = raster
        eo.stability = stability
        eo.t0 = t0
        _floquet_options(&eo.floquet, method, rtol, steps)
        eo.op.from_rest = from_rest
        if from_rest_periods is not None:
            eo.op.periods = _number("from_rest_periods", from_rest_periods)
        with nogil:
            r = usm_run_envelope(self.m, &self.p, &eo)
        return self._finish(r)


cdef void _progress_call(void *ctx, long done, long total, const char *what) with gil:
    """The library's progress callback (usm_progress.h) into a Python
    callable: called one call at a time, from whichever thread of the study;
    the first exception it raises is kept (the study goes on: it cannot be
    stopped from here) and raised when the study returns."""
    state = <list>ctx
    if state[1] is not None:
        return
    try:
        state[0](done, total, what.decode())
    except BaseException as e:
        state[1] = e


cdef list _progress_state(progress):
    """[callable, first exception] for _progress_call, or None."""
    if progress is None:
        return None
    if not callable(progress):
        raise TypeError("progress: must be callable as progress(done, total, what)")
    return [progress, None]


cdef void _progress_set(usm_progress *p, list state):
    p.fn = NULL
    p.ctx = NULL
    if state is not None:
        p.fn = _progress_call
        p.ctx = <void *>state


cdef object _progress_raise(list state):
    if state is not None and state[1] is not None:
        raise state[1]


cdef object _problem(_Model self, usm_opt_problem *pb, usm_robust_problem *rp, objective,
                     dict vary, list constraints, int minimize, margin, starts, t0,
                     int allow_slip, int allow_driven, int no_flat, int from_rest,
                     from_rest_periods):
    """The options usm optimize and usm pareto share, as the command reads
    them into pb (and rp: the objective, yield and derived constraints)."""
    cdef char msg[USM_IO_MSG_LEN]
    cdef const usm_param_info *info
    cdef const char *unit
    cdef double lo, hi, v
    cdef int rc
    usm_opt_problem_init(pb)
    usm_robust_problem_init(rp)
    if objective is not None:
        if usm_robust_objective_parse(rp, str(objective).encode(), msg) != USM_OK:
            raise ValueError(msg.decode(errors="replace"))
    pb.minimize = minimize
    for name, bounds in vary.items():
        bname = str(name).encode()
        info = usm_params_find(bname)
        unit = info.unit if info != NULL else NULL
        try:
            blo, bhi = bounds
        except (TypeError, ValueError):
            raise ValueError("vary: %s: expected (lo, hi), got %r" % (name, bounds)) from None
        lo = _quantity("vary", unit, blo)
        hi = _quantity("vary", unit, bhi)
        if usm_opt_problem_add_vary(pb, bname, lo, hi, msg) != USM_OK:
            raise ValueError(msg.decode(errors="replace"))
    for c in constraints:
        if isinstance(c, str):
            text = c.replace(" ", "")
        else:
            try:
                out, rel, val = c
            except (TypeError, ValueError):
                raise ValueError("constraint: expected (output, \">=\"|\"<=\", value), got %r"
                                 % (c,)) from None
            if rel not in (">=", "<="):
                raise ValueError('constraint: the relation must be ">=" or "<=", got %r' % (rel,))
            text = "%s%s%r" % (out, rel, _number("constraint", val))
        # the yield's and the derived quantities' (library), else an output's
        rc = usm_robust_constraint_parse(rp, text.encode(), msg)
        if rc == USM_OK:
            continue
        if rc != 1:
            raise ValueError(msg.decode(errors="replace"))
        if ">=" in text:
            out, val = text.split(">=", 1)
            upper = 0
        elif "<=" in text:
            out, val = text.split("<=", 1)
            upper = 1
        else:
            raise ValueError('constraint: expected "OUTPUT>=X" or "OUTPUT<=X", got "%s"' % c)
        try:
            v = float(val)
        except ValueError:
            raise ValueError('constraint: "%s" is not a number' % val) from None
        if not isfinite(v):
            raise ValueError('constraint: %s: not finite' % out)
        if usm_opt_problem_add_constraint(pb, str(out).encode(), upper, v, msg) != USM_OK:
            raise ValueError(msg.decode(errors="replace"))
    if margin is not None:
        pb.margin = _number("stability_margin", margin)
    if starts is not None:
        if isinstance(starts, bool) or not isinstance(starts, (int, np.integer)):
            raise TypeError("starts: must be an integer")
        pb.starts = int(starts)
    if t0 is not None:
        pb.t0 = _quantity("t0", b"s", t0)
    pb.allow_slip = allow_slip
    pb.allow_driven = allow_driven
    pb.no_flat = no_flat
    pb.from_rest = from_rest
    if from_rest_periods is not None:
        pb.from_rest_periods = _number("from_rest_periods", from_rest_periods)
        if not (pb.from_rest_periods >= 1 and pb.from_rest_periods <= 1e7):
            raise ValueError("from_rest_periods: must be in [1, 1e7]")
    if usm_params_check_ideal(&self.p, msg) != USM_OK:
        raise ValueError(msg.decode(errors="replace"))


cdef object _whole(str field, value, lo, hi):
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) \
            or not lo <= value <= hi:
        raise ValueError('%s: "%s" must be a whole number from %d to %d' % (field, value, lo, hi))
    return int(value)


cdef object _run_optimize(_Model self, objective, dict vary, list constraints, int minimize,
                          margin, starts, t0, int allow_slip, int allow_driven, int no_flat,
                          int from_rest, from_rest_periods, dict robust):
    """usm optimize: the problem as optimize_cmd.c builds it from its
    options, checked by the library, then run (usm_run_optimize, or
    usm_run_robust for a robust problem)."""
    cdef usm_opt_problem pb
    cdef usm_robust_problem rp
    cdef char msg[USM_IO_MSG_LEN]
    cdef const usm_param_info *info
    cdef usm_run *r
    _problem(self, &pb, &rp, objective, vary, constraints, minimize, margin, starts, t0,
             allow_slip, allow_driven, no_flat, from_rest, from_rest_periods)
    scatter = robust.get("scatter")
    if scatter is not None:
        if isinstance(scatter, dict):
            scatter = ["%s=%s" % kv for kv in scatter.items()]
        elif isinstance(scatter, str):
            scatter = [scatter]
        if len(scatter) > USM_ROBUST_MAX_SCATTER:
            raise ValueError("scatter: at most %d" % USM_ROBUST_MAX_SCATTER)
        for text in scatter:
            if usm_tolerance_vary_parse_units(b"scatter:", str(text).encode(),
                                              &rp.scatter[rp.nscatter], msg) != USM_OK:
                raise ValueError(msg.decode(errors="replace"))
            rp.nscatter += 1
    if robust.get("samples") is not None:
        rp.samples = _whole("samples", robust["samples"], USM_ROBUST_MIN_SAMPLES,
                            USM_ROBUST_MAX_SAMPLES)
    if robust.get("verify_samples") is not None:
        rp.verify_samples = _whole("verify_samples", robust["verify_samples"],
                                   USM_ROBUST_MIN_SAMPLES, USM_ROBUST_MAX_SAMPLES)
    if robust.get("seed") is not None:
        rp.seed = _whole("seed", robust["seed"], 0, USM_SEED_MAX)
    if robust.get("threads") is not None:
        rp.threads = _whole("threads", robust["threads"], 1, 64)
    if robust.get("max_evals") is not None:
        rp.max_evals = _whole("max_evals", robust["max_evals"], 4, 100000)
    rng = robust.get("over_range")
    if rng is not None:
        rng = tuple(rng)
        if len(rng) not in (3, 4):
            raise ValueError("over_range: expected (name, lo, hi) or (name, lo, hi, points)")
        info = usm_params_find(str(rng[0]).encode())
        if info == NULL:
            raise ValueError('over_range: unknown parameter "%s"' % rng[0])
        rp.qopt.range.lo = _quantity("over_range", info.unit, rng[1])
        rp.qopt.range.hi = _quantity("over_range", info.unit, rng[2])
        if len(rng) == 4:
            rp.qopt.range.points = _whole("over_range", rng[3], 2, 100000)
        if not rp.qopt.range.lo < rp.qopt.range.hi:
            raise ValueError("over_range: needs LO < HI and 2 <= N <= 100000")
        rp.qopt.range.param = usm_param_index(info)
    if robust.get("range_stat") is not None:
        k = usm_range_stat_find(str(robust["range_stat"]).encode())
        if k < 0:
            raise ValueError('range_stat: one of worst, mean, integral, got "%s"'
                             % robust["range_stat"])
        rp.qopt.range.stat = k
    if robust.get("band_threshold") is not None:
        rp.qopt.band_threshold = _number("band_threshold", robust["band_threshold"])
    if usm_robust_problem_is_robust(&rp):
        rp.nominal = pb
        if usm_robust_problem_check(&rp, self.m, &self.p, msg) != USM_OK:
            raise ValueError(msg.decode(errors="replace"))
        with nogil:
            r = usm_run_robust(self.m, &self.p, &rp)
        return self._finish(r)
    if rp.objective >= 0:
        pb.objective = rp.objective
    if usm_opt_problem_check(&pb, self.m, &self.p, msg) != USM_OK:
        raise ValueError(msg.decode(errors="replace"))
    with nogil:
        r = usm_run_optimize(self.m, &self.p, &pb)
    return self._finish(r)


cdef object _run_pareto(_Model self, objectives, dict vary, list constraints, int points,
                        margin, starts, t0, int allow_slip, int allow_driven, int from_rest,
                        from_rest_periods):
    """usm pareto --objectives A,B (max:NAME or min:NAME): the problem as
    pareto_cmd.c builds it, checked by the library, then run (usm_run_pareto)."""
    cdef usm_opt_problem pb
    cdef usm_robust_problem rp
    cdef char msg[USM_IO_MSG_LEN]
    cdef int obj[2]
    cdef int mini[2]
    cdef usm_run *r
    if isinstance(objectives, str):
        text = objectives
    else:
        text = ",".join(str(o).strip() for o in objectives)
    if usm_pareto_objectives_parse(text.encode(), obj, mini, msg) != USM_OK:
        raise ValueError(msg.decode(errors="replace"))
    if not 2 <= points <= USM_PARETO_MAX_POINTS:
        raise ValueError("points: must be 2 to %d" % USM_PARETO_MAX_POINTS)
    _problem(self, &pb, &rp, None, vary, constraints, 0, margin, starts, t0, allow_slip,
             allow_driven, 0, from_rest, from_rest_periods)
    pb.objective = obj[0]
    if usm_opt_problem_check(&pb, self.m, &self.p, msg) != USM_OK:
        raise ValueError(msg.decode(errors="replace"))
    with nogil:
        r = usm_run_pareto(self.m, &self.p, &pb, obj, mini, points)
    return self._finish(r)


cdef object _run_tolerance(_Model self, list vary, list spec, samples, seed, threads,
                           double t0, method, rtol, steps, int from_rest, from_rest_periods,
                           int allow_driven, progress=None):
    cdef usm_tolerance_options opt
    cdef usm_tolerance_vary v[64]
    cdef usm_tolerance_spec sp[64]
    cdef char msg[USM_IO_MSG_LEN]
    cdef usm_run *r
    cdef int nv = 0, ns = 0
    usm_tolerance_options_default(&opt)
    if len(vary) == 0:
        raise ValueError("vary: required (at least one NAME=DIST)")
    if len(vary) > USM_NPARAMS:
        raise ValueError("vary: too many")
    if len(spec) > 64:
        raise ValueError("spec: at most 64")
    for text in vary:
        if usm_tolerance_vary_parse_units(b"vary", str(text).encode(), &v[nv], msg) != USM_OK:
            raise ValueError(msg.decode(errors="replace"))
        nv += 1
    for text in spec:
        if usm_tolerance_spec_parse(str(text).replace(" ", "").encode(), &sp[ns], msg) != USM_OK:
            raise ValueError("spec " + msg.decode(errors="replace"))
        ns += 1
    for field, value, lo, hi in (("samples", samples, 1, USM_TOLERANCE_MAX_SAMPLES),
                                 ("seed", seed, 0, USM_SEED_MAX),
                                 ("threads", threads, 1, 64)):
        if value is None:
            continue
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)) \
                or not lo <= value <= hi:
            raise ValueError('%s: "%s" must be a whole number from %d to %d' % (field, value, lo, hi))
    opt.samples = samples
    if seed is not None:
        opt.seed = seed
    if threads is not None:
        opt.threads = threads
    opt.t0 = t0
    _floquet_options(&opt.floquet, method, rtol, steps)
    opt.op.from_rest = from_rest
    if from_rest_periods is not None:
        opt.op.periods = _number("from_rest_periods", from_rest_periods)
        if not (opt.op.periods >= 1 and opt.op.periods <= 1e7):
            raise ValueError("from_rest_periods: must be in [1, 1e7]")
    opt.allow_driven = allow_driven
    state = _progress_state(progress)
    _progress_set(&opt.progress, state)
    with nogil:
        r = usm_run_tolerance(self.m, &self.p, v, nv, sp, ns, &opt, NULL)
    out = self._finish(r)
    _progress_raise(state)
    return out


def tolerance_output_names():
    """The outputs recorded per sample (usm_tolerance_output_name)."""
    return [usm_tolerance_output_name(k).decode() for k in range(USM_TOL_NOUTPUTS)]


cdef object _spectrum(const usm_run *r):
    """The amplitude spectrum of a simulate run: {"frequency": (bins,) [Hz],
    CHANNEL: (bins,) amplitudes}, or None."""
    cdef const usm_sim_spectrum_result *sr = usm_run_spectrum(r)
    cdef const double *amp
    cdef double[::1] v
    if sr == NULL:
        return None
    out = {"frequency": np.arange(sr.bins, dtype=np.float64) * sr.df}
    for c in range(USM_SPECTRUM_NCHANNELS):
        amp = usm_run_spectrum_amplitudes(r, c)
        a = np.empty(sr.bins, dtype=np.float64)
        if amp != NULL and sr.bins > 0:
            v = a
            memcpy(&v[0], amp, sr.bins * sizeof(double))
        out[usm_spectrum_channel_name(c).decode()] = a
    return out


cdef class _SteadyState:
    """The run of one steady analysis (usm_run.h), kept so that the JSON
    text is written only when a result is read: .json() writes it once (the
    library's writer, the GIL released) and keeps it."""
    cdef usm_run *r
    cdef object text

    def __cinit__(self):
        self.r = NULL
        self.text = None

    def __dealloc__(self):
        usm_run_free(self.r)

    def json(self):
        cdef char *buf = NULL
        cdef size_t n = 0
        if self.text is None:
            with nogil:
                buf = usm_run_json(self.r, &n)
            if buf == NULL:
                raise NumericalError("out of memory or write error")
            try:
                text = buf[:n].decode()
            finally:
                free(buf)
            if self.text is None:
                self.text = text
        return self.text


cdef object _axis(str field, spec):
    """(name, from|None, to|None, points) of a map axis given as
    (name, from, to, points) or (name, points)."""
    spec = tuple(spec)
    if len(spec) == 4:
        name, lo, hi, n = spec
    elif len(spec) == 2:
        name, n = spec
        lo = hi = None
    else:
        raise ValueError("%s: expected (name, from, to, points) or (name, points)" % field)
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)):
        raise TypeError("%s: points must be an integer" % field)
    return str(name), lo, hi, int(n)


cdef double _number(str field, value) except? -1.0:
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise TypeError("%s: expected a number, got %s" % (field, type(value).__name__))
    v = float(value)
    if not isfinite(v):
        raise ValueError("%s: not finite (%r)" % (field, value))
    return v


cdef double _quantity(str field, const char *unit, value) except? -1.0:
    """A number in SI, or a text with a unit (usm_parse_quantity)."""
    cdef char msg[USM_IO_MSG_LEN]
    cdef double v
    if isinstance(value, str):
        text = value.encode()
        bfield = field.encode()
        if usm_parse_quantity(bfield, unit, text, len(text), &v, msg) != USM_OK:
            raise ValueError(msg.decode(errors="replace"))
        return v
    return _number(field, value)


cdef int _floquet_options(usm_floquet_options *fo, method, rtol, steps) except -1:
    """The command's --floquet-method and --rtol (atol = 1e-4 rtol), and steps."""
    cdef char msg[USM_MSG_LEN]
    cdef double r
    if method is not None:
        if usm_floquet_method_from_name(str(method).encode(), &fo.method, msg) != USM_OK:
            raise ValueError("method: " + msg.decode(errors="replace"))
    if rtol is not None:
        r = _number("rtol", rtol)
        if not (r >= 1e-14 and r <= 1e-3):
            raise ValueError("rtol: must be in [1e-14, 1e-3], got %g" % r)
        fo.rtol = r
        fo.atol = 1e-4 * r
    if steps is not None:
        if isinstance(steps, bool) or not isinstance(steps, (int, np.integer)):
            raise TypeError("steps: must be an integer")
        if not 1 <= steps <= USM_FLOQUET_MAX_STEPS:
            raise ValueError("steps: must be 1 to %d, got %d" % (USM_FLOQUET_MAX_STEPS, steps))
        fo.steps = int(steps)
    return 0


def _error(status, msg, result=None):
    return _status_error(status, msg, result)
