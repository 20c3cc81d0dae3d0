"""Four Python threads computing steady states at once give the results of
one thread (the calls release the GIL; the library keeps no shared state:
each call has its own solver objects), and so do the kernels (issue 27)."""
from concurrent.futures import ThreadPoolExecutor

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
