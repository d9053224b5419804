"""Fixtures shared by the tests."""

import json
import signal
import threading

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


def _simulate(folder):
    (folder / "results.json").write_text(json.dumps(run_gpu_script(True)))


@pytest.fixture(scope="module")
def simulated(tmp_path_factory):
    """The GPU kernels' results under the CUDA simulator (about 25 CPU s warm, minutes on a
    clean clone), made once in a run of the suite (``tests/gpu_simulated.py``;
    tests/engine/gpu/__init__.py says why a subprocess)."""
    folder = once_per_run(tmp_path_factory, "gpu_simulated", _simulate)
    return json.loads((folder / "results.json").read_text())


@pytest.fixture(scope="session", autouse=True)
def simulate_in_the_background(request, tmp_path_factory):
    """Where a test of the run reads :func:`simulated`, its results start being made at the
    run's first test, in a thread that waits on the simulator's process: a worker that reaches
    those tests then waits for what is left of it, not for all of it, while the tests before
    them ran beside it (on a clean clone the wait had idled one of two workers for minutes)."""
    if any("simulated" in getattr(item, "fixturenames", ()) for item in request.session.items):
        tmp_path_factory.getbasetemp()  # made here: made in the thread, it raced the tests'
        threading.Thread(target=once_per_run, args=(tmp_path_factory, "gpu_simulated", _simulate),
                         daemon=True).start()


def pytest_collection_modifyitems(config, items):
    """Run the tests that read the simulator's results late, and the documentation's build
    last. The simulator's results are made beside the other tests from the run's start
    (:func:`simulate_in_the_background`): reached late, they are done (on a clean clone the
    workers had waited 105 and 44 s for them). The docs' examples and work-precision run then
    load the member loops the other tests compiled from the disk cache instead of compiling
    them a second time beside those tests (on a clean clone the cache starts empty)."""
    def rank(item):
        if item.get_closest_marker("run_last"):
            return 2
        return 1 if "simulated" in getattr(item, "fixturenames", ()) else 0

    items.sort(key=rank)  # stable: the order within each rank is kept
