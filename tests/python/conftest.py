"""Shared helpers of the Python package's tests (tests/python, run by ctest
with PYTHONPATH=build/python, USM_CLI=build/usm, USM_LIBRARY=build/libusm.so)."""
import json
import os
import subprocess

import pytest

CLI = os.environ.get("USM_CLI", "build/usm")


def run_cli(*args, expect=0):
    """`usm ARGS --json`: (the parsed JSON object or None, stderr)."""
    r = subprocess.run([CLI, *args, "--json"], capture_output=True, text=True)
    assert r.returncode == expect, (args, r.returncode, r.stderr)
    return (json.loads(r.stdout) if r.stdout.strip() else None), r.stderr


def cli_error(*args, expect):
    """The message `usm ARGS` prints on failure, without "usm: "."""
    r = subprocess.run([CLI, *args], capture_output=True, text=True)
    assert r.returncode == expect, (args, r.returncode, r.stderr)
    line = r.stderr.strip().splitlines()[-1]
    assert line.startswith("usm: "), line
    return line[len("usm: "):]


@pytest.fixture
def cli():
    return run_cli
