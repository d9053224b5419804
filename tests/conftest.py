"""Fixtures shared by the tests."""

import json
import signal

import pytest

import stability

from .helpers import once_per_run, run_gpu_script


def pytest_configure(config):
    """Give the suite a terminal's Ctrl-C. A suite started as a background job of a script
    (``.ci/run &``) inherits SIGINT ignored, and so would every ``stability run`` the fault
    tests start and then send a real SIGINT to, as from a terminal."""
    if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
        signal.signal(signal.SIGINT, signal.default_int_handler)


@pytest.fixture
def body123():
    """The test body of the literature notes, I = (1, 2, 3) kg m^2 (a mathematical body)."""
    return stability.RigidBody(1.0, 2.0, 3.0, physical=False)


@pytest.fixture(scope="module")
def simulated(tmp_path_factory):
    """The GPU kernels' results under the CUDA simulator (about 25 CPU s), made once in a run of
    the suite (``tests/gpu_simulated.py``; tests/engine/gpu/__init__.py says why a subprocess)."""
    folder = once_per_run(tmp_path_factory, "gpu_simulated", lambda folder: (
        folder / "results.json").write_text(json.dumps(run_gpu_script(True))))
    return json.loads((folder / "results.json").read_text())


def pytest_collection_modifyitems(config, items):
    """Run the documentation's build last: its examples and its work-precision run then load
    the member loops the other tests compiled from the disk cache instead of compiling them a
    second time beside those tests (on a clean clone the cache starts empty)."""
    last = [item for item in items if item.get_closest_marker("run_last")]
    items[:] = [item for item in items if not item.get_closest_marker("run_last")] + last
