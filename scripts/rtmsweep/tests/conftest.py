"""Fixtures of the sweep tests: the rtm binary under test and running scripts/sweep.

The rtm binary is $RTM_BINARY (CMake's sweep_pytest test sets it), else build/rtm in the
checkout; without one, the tests that render are skipped and the unit tests still run. Importing
support here puts the rtmsweep package on the path for every test module.
"""

import os

import pytest

from support import ROOT, SWEEP, sh


@pytest.fixture(scope="session")
def rtm():
    """The rtm executable under test."""
    path = os.environ.get("RTM_BINARY") or os.path.join(ROOT, os.environ.get("RTM_BUILD_DIR", "build"), "rtm")
    if not (os.path.isfile(path) and os.access(path, os.X_OK)):
        pytest.skip(f"no rtm executable at {path} (set RTM_BINARY, or build: scripts/setup)")
    return os.path.abspath(path)


@pytest.fixture
def sweep(rtm, tmp_path):
    """scripts/sweep SPEC --out OUT --rtm RTM [args], run in the test's folder."""
    def run_sweep(spec, out, *args, timeout=120):
        return sh(SWEEP, spec, "--out", out, "--rtm", rtm, *args, cwd=tmp_path, timeout=timeout)
    return run_sweep
