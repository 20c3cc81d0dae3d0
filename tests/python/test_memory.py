"""The extension frees what the library allocates: hundreds of rounds of analyses,
results read and dropped, failures included, leave the C heap (glibc's
mallinfo2: bytes in use) where it was.  A leak of one solver, result or
JSON text per call would grow it by megabytes.  (Under the sanitizer build,
where ASan replaces malloc and mallinfo2 says nothing, the leaks of the
library's runs (usm_run.h) are the C test run_analyses's.)"""
import ctypes
import gc
import os

import numpy as np
import pytest

import usm

pytestmark = pytest.mark.skipif("asan" in os.environ.get("LD_PRELOAD", ""),
                                reason="ASan replaces malloc: mallinfo2 reports nothing")


class Mallinfo2(ctypes.Structure):
    _fields_ = [(n, ctypes.c_size_t) for n in ("arena", "ordblks", "smblks", "hblks", "hblkhd",
                                               "usmblks", "fsmblks", "uordblks", "fordblks",
                                               "keepcost")]


libc = ctypes.CDLL("libc.so.6")
libc.mallinfo2.restype = Mallinfo2


def in_use():
    gc.collect()
    m = libc.mallinfo2()
    return m.uordblks + m.hblkhd


def work(m, bad):
    m.steady()                              # the state freed unread
    m.steady().to_dict()                    # and after its JSON was written
    m.rhs(np.full((50, m.nx), 0.01))
    try:
        bad.steady()
    except usm.NoSolution as e:
        e.result.to_dict()
    try:
        m.with_params(F0=-1)
    except ValueError:
        pass
    m.sweep("f", 36000, 37000, points=3, floquet=False)
    m.simulate(2e-4, rate=1e5)


def test_no_growth():
    m, bad = usm.Model("4dof"), usm.Model("4dof", T=0.1)
    for _ in range(50):                     # warm up: pools, caches, interned objects
        work(m, bad)
    before = in_use()
    for _ in range(300):
        work(m, bad)
    grown = in_use() - before
    # measured: 0 bytes over 300 rounds; one steady state kept alive per call
    # grows the heap by 100 kB (its solver's workspace), 30 MB over 300 rounds
    assert grown < 256 * 1024, "C heap grew by %d bytes over 300 rounds" % grown
