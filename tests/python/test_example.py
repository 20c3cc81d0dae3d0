"""examples/fig9.py (docs/python.md) runs and writes its figure; its speed
maximum is the sweep's, near the 37.45 kHz of README's comparison table."""
import os
import re
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
EXAMPLE = os.path.join(HERE, "..", "..", "examples", "fig9.py")


def test_fig9_example_runs():
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, "fig9.png")
        env = dict(os.environ, MPLBACKEND="Agg", MPLCONFIGDIR=d)
        r = subprocess.run([sys.executable, EXAMPLE, out], capture_output=True, text=True,
                           env=env, cwd=d)
        assert r.returncode == 0, r.stderr
        with open(out, "rb") as f:
            assert f.read(8) == b"\x89PNG\r\n\x1a\n"
    found = dict(re.findall(r"^(\w+): speed maximum \S+ 1/s at (\S+) kHz", r.stdout, re.M))
    # a 100 Hz grid: the maximum within one step of README's 37.452 kHz (both models)
    assert abs(float(found["3dof"]) - 37.452) <= 0.1
    assert abs(float(found["4dof"]) - 37.452) <= 0.1
