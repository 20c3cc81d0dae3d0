"""The vectorised kernels equal the C kernels called one state at a time, bit
for bit: the reference calls the generated functions of libusm.so
(usm_<model>_rhs, ...) through ctypes, one state per call, for 10^4 random
states of every model; N = 0, non-contiguous, reversed, Fortran-ordered and
read-only arrays, and a time per state."""
import ctypes
import os

import numpy as np
import pytest

import usm

LIB = ctypes.CDLL(os.environ.get("USM_LIBRARY", "build/libusm.so"))
DP = ctypes.POINTER(ctypes.c_double)
N = 10_000


def ptr(a):
    return a.ctypes.data_as(DP)


def c_params(model):
    """usm_params: USM_NPARAMS doubles in the order of the contracts' table."""
    names = [row[0] for row in usm.parameter_table()]
    return np.array([model.params[k] for k in names], dtype=np.float64)


def random_states(model, n, rng):
    x = rng.uniform(-1.0, 1.0, size=(n, model.nx))
    if "theta" in model.state_names:
        th = model.state_names.index("theta")
        x[:, th] = rng.uniform(1e-3, 0.3, size=n)   # away from the Euler angles' singularity
    else:
        # the tilt vector (variant tilt): a = sin(theta) sin(al), b = -sin(theta) cos(al),
        # theta in the same range (its kernels are finite for theta > 0, docs/coordinates.md)
        th, al = rng.uniform(1e-3, 0.3, size=n), rng.uniform(0.0, 2 * np.pi, size=n)
        x[:, model.state_names.index("a")] = np.sin(th) * np.sin(al)
        x[:, model.state_names.index("b")] = -np.sin(th) * np.cos(al)
    for k, name in enumerate(model.state_names):
        if name.endswith("dot"):
            x[:, k] *= 2e5                            # rates of the order of Omega
    return x


def bits_equal(a, b):
    return a.shape == b.shape and np.array_equal(a.view(np.uint64), b.view(np.uint64))


@pytest.mark.parametrize("name", [m["name"] for m in usm.models()])
def test_kernels_one_state_at_a_time(name):
    info = next(m for m in usm.models() if m["name"] == name)
    model = usm.Model(info["base"], info["variant"]).with_params(F0=0.5, f=36500.0)
    rng = np.random.default_rng(27)
    nx, nu = model.nx, model.nu
    p = c_params(model)
    x = random_states(model, N, rng)
    t = rng.uniform(0.0, 1e-4, size=N)
    u = np.column_stack([rng.uniform(1e-6, 1e-3, N), rng.uniform(0, 2 * np.pi, N)]
                        + ([rng.uniform(-50, 0, N)] if nu == 3 else []))
    rhs = getattr(LIB, "usm_%s_rhs" % name)
    mass = getattr(LIB, "usm_%s_mass" % name)
    jac = getattr(LIB, "usm_%s_jac_rhs" % name)
    res = getattr(LIB, "usm_%s_steady_residual" % name)
    resj = getattr(LIB, "usm_%s_steady_jacobian" % name)
    rhs.argtypes = jac.argtypes = [DP, ctypes.c_double, DP, DP]
    mass.argtypes = res.argtypes = resj.argtypes = [DP, DP, DP]
    want = {k: np.empty(s) for k, s in (("rhs", (N, nx)), ("mass", (N, nx, nx)),
                                       ("jac", (N, nx, nx)), ("res", (N, nu)),
                                       ("resj", (N, nu, nu)))}
    for i in range(N):
        xi, ui = x[i], u[i]
        rhs(ptr(xi), t[i], ptr(p), ptr(want["rhs"][i]))
        mass(ptr(xi), ptr(p), ptr(want["mass"][i]))
        jac(ptr(xi), t[i], ptr(p), ptr(want["jac"][i]))
        res(ptr(ui), ptr(p), ptr(want["res"][i]))
        resj(ptr(ui), ptr(p), ptr(want["resj"][i]))
    assert bits_equal(model.rhs(x, t), want["rhs"])
    assert bits_equal(model.mass_matrix(x), want["mass"])
    assert bits_equal(model.jacobian(x, t), want["jac"])
    assert bits_equal(model.steady_residual(u), want["res"])
    assert bits_equal(model.steady_jacobian(u), want["resj"])
    # one state: shape (nx,) in, (nx,) / (nx, nx) out; a scalar t for all rows
    assert bits_equal(model.rhs(x[5], t[5]), want["rhs"][5])
    assert bits_equal(model.jacobian(x[7], t[7]), want["jac"][7])
    assert bits_equal(model.steady_jacobian(u[3]), want["resj"][3])
    out = np.empty((N, nx))
    assert model.rhs(x, t, out=out) is out and bits_equal(out, want["rhs"])
    assert bits_equal(model.rhs(x[9], np.array(t[9])), want["rhs"][9])   # a 0-d time
    one = np.empty(nx)
    rhs(ptr(x[9]), 2e-5, ptr(p), ptr(one))
    assert bits_equal(model.rhs(x, 2e-5)[9], one)


def test_empty_and_strided():
    m = usm.Model("4dof")
    rng = np.random.default_rng(1)
    assert m.rhs(np.empty((0, m.nx))).shape == (0, m.nx)
    assert m.mass_matrix(np.empty((0, m.nx))).shape == (0, m.nx, m.nx)
    assert m.jacobian(np.empty((0, m.nx)), np.empty(0)).shape == (0, m.nx, m.nx)
    assert m.steady_residual(np.empty((0, m.nu))).shape == (0, m.nu)
    assert m.steady_jacobian(np.empty((0, m.nu))).shape == (0, m.nu, m.nu)
    big = random_states(m, 400, rng).repeat(2, axis=1)        # (400, 2 nx)
    x = big[:, ::2]                                            # a stride in both axes
    assert not x.flags.c_contiguous
    xc = np.ascontiguousarray(x)
    t = np.linspace(0, 1e-4, 400 * 3)[::3]
    assert bits_equal(m.rhs(x, t), m.rhs(xc, np.ascontiguousarray(t)))
    assert bits_equal(m.mass_matrix(x), m.mass_matrix(xc))
    assert bits_equal(m.jacobian(x[::-1]), m.jacobian(xc[::-1].copy()))
    assert bits_equal(m.rhs(np.asfortranarray(xc)), m.rhs(xc))
    ro = xc.copy()
    ro.setflags(write=False)
    assert bits_equal(m.rhs(ro), m.rhs(xc))
    assert bits_equal(m.rhs(list(xc[0])), m.rhs(xc[0]))       # a list of floats
    col = np.asfortranarray(np.array([[1e-4, 1.0, -10.0], [2e-4, 2.0, -12.0]]))
    assert not col.flags.c_contiguous
    assert bits_equal(m.steady_residual(col), m.steady_residual(np.ascontiguousarray(col)))


@pytest.mark.parametrize("base", ["3dof", "4dof"])
def test_tilt_vector_domain(base):
    """The tilt vector's kernels are not finite on the stator's axis (the
    contact point is undefined there and has no limit: docs/coordinates.md)
    nor beyond a^2 + b^2 = 1: each kernel of the state refuses such a row
    with a ValueError naming it and the reason, never a silent inf or NaN
    (before, mass_matrix, rhs and jacobian returned inf and NaN at
    a = b = 0)."""
    m = usm.Model(base, "tilt")
    ia, ib = m.state_names.index("a"), m.state_names.index("b")
    x = random_states(m, 4, np.random.default_rng(5))
    for kernel in (m.mass_matrix, m.rhs, m.jacobian):
        assert np.all(np.isfinite(kernel(x)))
        on_axis = x.copy()
        on_axis[2, ia] = on_axis[2, ib] = 0.0
        with pytest.raises(ValueError, match=r"x: row 2 lies on the stator's axis, "
                                             r"a\^2 \+ b\^2 = 0 .*not defined on the stator's axis"):
            kernel(on_axis)
        tiny = x[1].copy()
        tiny[ia], tiny[ib] = 1e-170, 0.0        # a^2 + b^2 is 0 in double: theta = 0
        with pytest.raises(ValueError, match=r"x: row 0 lies on the stator's axis"):
            kernel(tiny)
        out = x.copy()
        out[0, ia], out[0, ib] = 0.8, 0.6
        with pytest.raises(ValueError, match=r"x: row 0 has a\^2 \+ b\^2 >= 1"):
            kernel(out)
    # the stationary kernels take (theta, alpha): finite at theta = 0
    assert np.all(np.isfinite(m.steady_residual(np.zeros(m.nu))))
