"""``stability bench`` (stability.cli.bench): its NumPy baseline is the kernel's RK4, its tables,
and its work-precision measurements at known accuracy and order."""

import numpy as np
import pytest

from stability.cli import bench as bench_module
from stability.cli import main
from stability.free_body.propagate import propagate


def test_numpy_baseline_is_the_same_rk4_as_the_kernel():
    body, axis, w0 = bench_module.workload(40)
    m0 = w0 * body.moments
    m_numpy = bench_module.numpy_rk4(body.moments, m0, 2e-3, 50)
    m_numba = propagate("rk4", body.moments, m0, 2e-3, 50, progress=False).m_final
    np.testing.assert_allclose(m_numpy, m_numba, rtol=1e-13, atol=1e-16)


def test_bench_prints_its_table(capsys, monkeypatch):
    # the table's rows, not W1's timings: a small W1 in two rounds (the full one took 51 s here)
    monkeypatch.setitem(bench_module.W1, "members", 256)
    monkeypatch.setitem(bench_module.W1, "t_end", 1.0)
    monkeypatch.setattr(bench_module, "ENGINE_ROUNDS", 2)
    args = ["bench", "--members", "64", "--steps", "20", "--methods", "rk4", "--threads", "1",
            "--repeat", "1"]
    assert main(args) == 0
    lines = capsys.readouterr().out.splitlines()
    header = next(k for k, line in enumerate(lines) if line.startswith("solver"))
    for column in ("member-steps/s", "x NumPy RK4", "x SciPy DOP853", "max |w error|"):
        assert column in lines[header]
    body = [line for line in lines[header + 2:] if line.strip()]
    solvers = [line.split("  ")[0].strip() for line in body[:4]]
    assert [line.split("  ")[0].strip() for line in body[4:6]] == ["scipy DOP853", "numpy RK4"]
    assert solvers == ["rk4", "rk4, one event", "adaptive dopri5", "adaptive dopri5, one event"]
    assert "over rk4" in body[1]
    # then what the engine costs on W1, a row per loop
    engine = next(k for k, line in enumerate(lines) if "what the engine costs" in line)
    shown = "\n".join(lines[engine:])
    for row in ("plain RK4 loop", "engine rk4, uncompensated", "engine rk4",
                "run_ensemble rk4, summaries only"):
        assert row in shown
    assert main([*args, "--no-engine"]) == 0
    assert "what the engine costs" not in capsys.readouterr().out


def test_bench_measures_every_solver_at_known_accuracy():
    report = bench_module.bench(members=64, steps=20, threads=[1], methods=["rk4", "lp2"],
                                repeat=2)
    rows = {row.solver: row for row in report.rows}
    assert set(rows) == {"rk4", "lp2", "rk4, one event", "adaptive dopri5",
                         "adaptive dopri5, one event", "scipy DOP853", "numpy RK4"}
    # the event leaves the states as they are: RK4's own error, bitwise
    assert rows["rk4, one event"].error == rows["rk4"].error
    for row in rows.values():
        assert row.wall > 0 and row.rate == pytest.approx(64 * 20 / row.wall)
        # 20 steps of 2 ms near steady spin: every solver within 1e-6 rad/s of the exact w.
        assert row.error < 1e-6
    # The NumPy baseline runs the same RK4 as the kernel: the same error to round-off.
    assert rows["numpy RK4"].error == pytest.approx(rows["rk4"].error, rel=1e-3, abs=1e-13)


def test_bench_heavy_top_prints_every_method_and_its_order(capsys):
    args = ["bench", "--scene", "heavy_top", "--top-members", "4", "--threads", "1",
            "--repeat", "1"]
    assert main(args) == 0
    out = capsys.readouterr().out
    assert "solver" not in out  # the free-body table is not run
    lines = out.splitlines()
    header = next(k for k, line in enumerate(lines) if line.startswith("method  step angle"))
    n = len(bench_module.STEP_ANGLES)
    rows = [[cell.strip() for cell in line.split("  ") if cell.strip()]
            for line in lines[header + 2:header + 2 + 3 * n]]
    assert [row[0] for row in rows] == ["rk4"] * n + ["lp2"] * n + ["lp4"] * n
    for row in rows:
        error = row[-1]
        if error.startswith("unstable"):
            # RK4 turning with the spin is unstable above a step angle of 2 sqrt(2).
            assert row[0] == "rk4" and float(row[1]) > 2.8
        else:
            assert 0.0 < float(error) < 0.1
    orders = next(k for k, line in enumerate(lines) if line.startswith("method  declared order"))
    for line in lines[orders + 2:orders + 5]:
        name, declared, measured = line.split()[:3]
        assert abs(float(measured) - float(declared)) < 0.2, line


def test_heavy_top_errors_against_the_exact_motion_fall_at_each_methods_order():
    """Halving h in the asymptotic range divides lp4's error by ~2^4 and lp2's by ~2^2."""
    report = bench_module.top_work_precision(members=4, periods=1.25, step_angles=(0.8, 0.4),
                                             threads=1, repeat=1)
    rows = {(row.method, row.step_angle): row for row in report.rows}
    assert {name for name, _ in rows} == {"rk4", "lp2", "lp4"}
    for row in rows.values():
        assert row.failed == 0 and np.isfinite(row.error) and row.error > 0.0
        assert row.steps * row.h == pytest.approx(report.t_end, rel=1e-12)
    assert rows["lp4", 0.8].error / rows["lp4", 0.4].error > 2.0**3
    assert 2.0 < rows["lp2", 0.8].error / rows["lp2", 0.4].error < 2.0**3
    lp4 = [rows["lp4", a] for a in (0.8, 0.4)]
    slope, points = bench_module.measured_order([r.h for r in lp4], [r.error for r in lp4])
    assert points == 2 and slope == pytest.approx(4.0, abs=0.3)
