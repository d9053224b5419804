"""The work-precision Dataset read back: time to reach an accuracy, the fastest method."""

import math

import numpy as np
import pytest
import xarray as xr

from stability.free_body.work_precision import measure as wp
from stability.free_body.accuracy import METRICS


def synthetic(errors, walls, failed=None, methods=("m",)):
    """A one-workload Dataset: per method (row), a sweep of p99 errors and wall times."""
    errors, walls = np.array(errors, float), np.array(walls, float)
    w_error = np.full((1,) + errors.shape + (len(METRICS),), np.nan)
    w_error[0, :, :, METRICS.index("p99")] = errors
    failed = np.zeros(errors.shape) if failed is None else np.array(failed, float)
    dims = ("workload", "method", "sweep")
    return xr.Dataset(
        {"w_error": (dims + ("metric",), w_error), "wall_time": (dims, walls[None]),
         "failed": (dims, failed[None])},
        coords={"workload": ["w"], "method": list(methods), "metric": list(METRICS)},
    )


def test_time_to_reach_interpolates_in_log_log():
    ds = synthetic([[1e-2, 1e-4, 1e-6]], [[1.0, 10.0, 100.0]])
    assert wp.time_to_reach(ds, "w", "m", 1e-4) == pytest.approx(10.0)
    assert wp.time_to_reach(ds, "w", "m", 1e-3) == pytest.approx(math.sqrt(10.0))
    assert wp.time_to_reach(ds, "w", "m", 1e-1) == pytest.approx(1.0)
    assert math.isnan(wp.time_to_reach(ds, "w", "m", 1e-7))


def test_time_to_reach_ignores_points_with_failed_members():
    ds = synthetic([[1e-2, 1e-6, 1e-8]], [[1.0, 10.0, 100.0]], failed=[[0, 3, 0]])
    # the failed point at 10 s is skipped: 1e-6 lies 2/3 of the way (in log) from 1 s to 100 s
    assert wp.time_to_reach(ds, "w", "m", 1e-6) == pytest.approx(100.0 ** (2 / 3))


def test_fastest_ranks_the_methods_that_reach_the_target_and_sets_the_exact_flow_aside():
    ds = synthetic([[1e-2, 1e-8], [1e-15, np.nan], [1e-3, 1e-5]],
                   [[1.0, 2.0], [5.0, np.nan], [0.5, 8.0]], methods=("rk4", "exact", "lp2"))
    times, ranked, stepping = wp.fastest(ds, "w", 1e-8)
    assert set(times) == {"rk4", "exact", "lp2"} and math.isnan(times["lp2"])
    assert [m for _, m in ranked] == ["rk4", "exact"]
    assert [m for _, m in stepping] == ["rk4"]
    _, ranked, stepping = wp.fastest(ds, "w", 1e-12)
    assert [m for _, m in ranked] == ["exact"] and stepping == []


def test_format_time_picks_the_unit():
    assert wp.format_time(2.5e-4) == "250 µs"
    assert wp.format_time(0.0123) == "12.3 ms"
    assert wp.format_time(4.56) == "4.56 s"
    assert wp.format_time(math.nan) == "–"
