#!/usr/bin/env python3
"""The Python module's measures, beside the same work in C
(build/bench/bench_python):
  - usm.Model.rhs over N = 10^6 states (best of 5) vs the C loop;
  - steady() per call vs the C call (usm_run_steady, usm_run.h):
    the time Python adds;
  - the README example (examples/fig9.py), wall time.
CPU time of this process for the first two (the machine is shared; the C
program measures its CPU time too), wall time for the example.
Run from the repository root:
  PYTHONPATH=build/python /usr/bin/python3 bench/bench_python.py [build]"""
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

import usm

build = sys.argv[1] if len(sys.argv) > 1 else "build"
N = 1_000_000
c = dict(line.split(None, 1) for line in
         subprocess.run([os.path.join(build, "bench", "bench_python"), str(N)],
                        capture_output=True, text=True, check=True).stdout.splitlines())
c_rhs = float(c["rhs_loop_s"].split()[1])
c_steady = float(c["steady_call_us"])
c_nojson = float(c["steady_nojson_us"])

m = usm.Model("3dof")
x = np.random.default_rng(27).uniform(0.01, 0.2, size=(N, m.nx))
best = 1e300
for _ in range(10):
    t0 = time.process_time()
    m.rhs(x, 1e-5)
    best = min(best, time.process_time() - t0)
out = np.empty_like(x)
best_out = 1e300
for _ in range(10):
    t0 = time.process_time()
    m.rhs(x, 1e-5, out=out)
    best_out = min(best_out, time.process_time() - t0)
print("rhs, N = %d: Python %.4f s (with out=: %.4f s), C loop %.4f s, ratio %.3f (%.3f)"
      % (N, best, best_out, c_rhs, best / c_rhs, best_out / c_rhs))

# per call: the best mean of 10 batches of 50 calls (the machine is shared)
def per_call(f):
    best = 1e300
    for _ in range(10):
        t0 = time.process_time()
        for _ in range(50):
            f()
        best = min(best, (time.process_time() - t0) / 50)
    return 1e6 * best


py = per_call(m.steady)
py_dict = per_call(lambda: m.steady().to_dict())
print("steady(): Python %.1f us per call, the C calls %.1f us: added %.1f us" % (py, c_nojson, py - c_nojson))
print("steady().to_dict(): %.1f us (the library's JSON writer %.1f us in C, json.loads the rest)"
      % (py_dict, c_steady - c_nojson))

with tempfile.TemporaryDirectory() as d:
    t0 = time.perf_counter()
    subprocess.run([sys.executable, os.path.join(os.path.dirname(__file__), "..", "examples",
                                                 "fig9.py"), os.path.join(d, "fig9.png")],
                   check=True, capture_output=True, env=dict(os.environ, MPLBACKEND="Agg"))
    print("README example (examples/fig9.py): %.2f s wall" % (time.perf_counter() - t0))
