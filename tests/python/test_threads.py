"""Four Python threads computing steady states at once give the results of
one thread (the calls release the GIL; the library keeps no shared state:
each call has its own solver objects), and so do the kernels.
Models and results pickle, so a process pool gives the same results too."""
import pickle
from concurrent.futures import ProcessPoolExecutor, ThreadPoolExecutor

import numpy as np

import usm

POINTS = [("3dof", dict(f=f, F0=F0)) for f in (35000.0, 37000.0, 39000.0) for F0 in (0.3, 0.5)] \
    + [("4dof", dict(f=f)) for f in (36000.0, 38000.0)]


def steady(point):
    model, params = point
    return usm.Model(model, **params).steady().to_dict()


def test_four_threads_equal_one():
    serial = [steady(p) for p in POINTS]
    with ThreadPoolExecutor(max_workers=4) as pool:
        for _ in range(2):
            assert list(pool.map(steady, POINTS * 2)) == serial * 2


def test_kernels_in_threads():
    m = usm.Model("4dof")
    rng = np.random.default_rng(4)
    xs = [rng.uniform(0.01, 0.2, size=(20000, m.nx)) for _ in range(8)]
    serial = [m.rhs(x, 1e-5) for x in xs]
    with ThreadPoolExecutor(max_workers=4) as pool:
        for got, want in zip(pool.map(lambda x: m.rhs(x, 1e-5), xs), serial):
            assert np.array_equal(got.view(np.uint64), want.view(np.uint64))


def test_pickle_and_processes():
    m = usm.Model("4dof", "friction_tanh", F0=0.5)
    m2 = pickle.loads(pickle.dumps(m))
    assert m2.name == m.name and m2.params == m.params
    r = m.steady()
    assert pickle.loads(pickle.dumps(r)).to_dict() == r.to_dict()
    sim = usm.Model().simulate(2e-4)
    sim2 = pickle.loads(pickle.dumps(sim))
    assert sim2.to_dict() == sim.to_dict()
    assert np.array_equal(sim2.history_array, sim.history_array, equal_nan=True)
    serial = [steady(p) for p in POINTS[:4]]
    with ProcessPoolExecutor(max_workers=2) as pool:
        assert list(pool.map(steady, POINTS[:4])) == serial
