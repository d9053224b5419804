"""Fixtures shared by the tests."""

import signal

import pytest

import stability


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


def pytest_collection_modifyitems(config, items):
    """Run the documentation's build last: its examples and its work-precision run then load
    the member loops the other tests compiled from the disk cache instead of compiling them a
    second time beside those tests (on a clean clone the cache starts empty)."""
    last = [item for item in items if item.get_closest_marker("run_last")]
    items[:] = [item for item in items if not item.get_closest_marker("run_last")] + last
